//! The subcommands, one file per family: the growth scenes (and their convergence study),
//! the figures, and each related model.
pub mod conv;
pub mod cursor;
pub mod dunes;
pub mod figures;
pub mod growth;
pub mod raytrace;
pub mod ripple;
pub mod serve;
pub mod tile;
pub mod windripples;
