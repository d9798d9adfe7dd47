//! cellsurf: cellular Monte Carlo surface models.
//!
//! The [`engine`] (lattices: square 4- and 8-neighbour, hexagonal 6-neighbour, torus or
//! walls; the surface partition; the sum tree; the random stream; atomic output) carries
//! every model. [`plot`] (feature `plot`) draws lattice panels, continuous fields, charts and
//! animations. The models, one folder each:
//!
//! - [`growth`]: "Simple Monte Carlo cellular models for surface growth": sticking rule,
//!   growth state, samplers, scenes, observables, convergence, figures;
//! - [`ripple`]: the sand-ripple volume generator of Staelens, Dupont and Henriet;
//! - [`tile`]: large surfaces tiled from ripple tiles, on fractal dunes;
//! - [`raytrace`]: acoustic ray tracing over generated or read seafloors;
//! - [`windripples`]: the wind-ripple particle model;
//! - [`dunes`]: Werner-model dunes;
//! - [`cursor`]: the wind-field cursor walk.
//!
//! [`figures`] (feature `plot`) is the registry of every model's figures.
//!
//! Imports run downward only: engine <- plot <- growth and the models <- figures registry
//! <- the `cellsurf` program (`src/cmd/`, `src/main.rs`). A test checks it.
//!
//! Features: `plot` (figures and animations, plotters with a bundled font) and `cli` (the
//! `cellsurf` program); both on by default. `--no-default-features` builds the engine and the
//! models alone.
pub mod cursor;
pub mod dunes;
pub mod engine;
#[cfg(feature = "plot")]
pub mod figures;
pub mod growth;
#[cfg(feature = "plot")]
pub mod plot;
pub mod raytrace;
pub mod ripple;
#[cfg(feature = "serve")]
pub mod serve;
pub mod tile;
pub mod windripples;
