//! Subcommands of the related models, one file each.
pub mod cursor;
pub mod dunes;
pub mod raytrace;
pub mod ripple;
pub mod tile;
pub mod windripples;
