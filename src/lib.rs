//! cellsurf: cellular Monte Carlo surface models.
//!
//! The lattice engine ([`lattice::Lattice`]: square 4- and 8-neighbour, hexagonal 6-neighbour;
//! torus or walls) carries every model. The growth models of "Simple Monte Carlo cellular
//! models for surface growth" are built from a sticking rule ([`rule::Sticking`],
//! [`rule::Weight`]), a growth state ([`growth::Growth`]) and interchangeable samplers
//! ([`sampler::SamplerKind`]: the paper's rejection algorithm, an exact rejection-free
//! equivalent, and the deterministic CA). [`scene`] runs the paper's scenes; [`figures`]
//! (feature `plot`) draws them.
//!
//! Features: `plot` (figures and animations, plotters with a bundled font) and `cli` (the
//! `cellsurf` program); both on by default. `--no-default-features` builds the engine alone.
pub mod converge;
pub mod cursor;
pub mod dunes;
#[cfg(feature = "plot")]
pub mod figures;
pub mod growth;
pub mod io;
pub mod lattice;
pub mod observe;
#[cfg(feature = "plot")]
pub mod plot;
pub mod raytrace;
pub mod ripple;
pub mod rule;
pub mod sampler;
pub mod scene;
pub mod sumtree;
pub mod surface;
pub mod tile;
pub mod windripples;
