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
//!
//! # A first run of each model
//!
//! Every model is a configuration checked by its constructor (a typed error names the
//! parameter, its value and the valid range) and a run seeded from a `u64`: the same seed
//! gives the same result. Each module's page has a fuller example.
//!
//! ```
//! use cellsurf::{cursor, dunes, engine, growth, windripples};
//!
//! // The engine: a 64 x 64 square 8-neighbour torus.
//! use engine::lattice::{Boundary, Lattice, Neighbourhood};
//! let lattice = Lattice::new(Neighbourhood::Square8, 64, 64, Boundary::TORUS).unwrap();
//! assert_eq!(lattice.neighbours(0).count(), 8);
//!
//! // Growth: the crystal of Fig. 7, 500 events on a small lattice.
//! use growth::scene::{NoHooks, SceneConfig, SceneKind};
//! let mut cfg = SceneConfig::defaults(SceneKind::Crystal);
//! (cfg.width, cfg.height, cfg.start, cfg.steps, cfg.events) = (48, 56, 10.0, 0, Some(500));
//! cfg.snapshots.clear();
//! assert_eq!(growth::scene::run(&cfg, &mut NoHooks).unwrap().last.accepted, 500);
//!
//! // Werner-model dunes, wind ripples and the cursor walk.
//! let mut d = dunes::DuneModel::new(&dunes::DuneConfig { grid: 24, ..Default::default() }).unwrap();
//! d.step();
//! let w = windripples::WindParams { bins: 16, particles: 4096, steps: 4, ..Default::default() };
//! assert_eq!(windripples::run(&w, |_| {}).unwrap().height.len(), 256);
//! let field = cursor::WindSpec::article("calm").unwrap().field(16, 16).unwrap();
//! let tr = cursor::Transitions::new(&field, 0.95).unwrap();
//! let mut walk = cursor::CursorWalk::new(&tr, 1);
//! walk.run(1000);
//! assert_eq!(walk.height_total(), 1000);
//! ```
// The library reports through its return values and callbacks, never on the terminal.
#![deny(clippy::print_stderr, clippy::print_stdout)]

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
