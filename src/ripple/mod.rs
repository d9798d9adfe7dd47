//! The sand-ripple volume generator of Staelens, Dupont & Henriet ("Sand ripple volume
//! generator for underwater acoustic models, a cellular automaton Monte-Carlo approach"),
//! on the engine's square 8-neighbour torus.
//!
//! Principal types:
//! - [`RippleParams`] ([`params`]): every parameter, unit and default; TOML scenes.
//! - [`Ripple`] ([`model`]): the run: a [`SandVolume`] ([`volume`]) of columns of automata,
//!   each with a grain-size class ([`GrainClasses`], [`grain`]) and a porosity code
//!   ([`Compaction`], [`compaction`]); the water volume ([`WaterVolume`], [`Flow`],
//!   [`water`], Sect. 2.3) or the shadow rule of Eq. (3); the rules ([`rules`]: roll/saltation
//!   Eqs. 1-5 and 7-8, avalanche Eq. 6, creep Eqs. 9-10).
//! - [`Analysis`] ([`spectrum`]): wavelength and crest orientation from the 2-D spectrum,
//!   height, ripple index, slopes, crest/trough grain size.
//! - [`acoustics`]: bulk density, sound speed and impedance per automaton.
//! - [`clock`]: the physical duration of a step from the Meyer-Peter & Mueller bedload
//!   ([`clock::StepClock`]).
//! - [`travel`]: the median grain's flat-bed travel, and the bin of `bin_travels`
//!   ([`travel::median_travel`]).
//! - [`equilibrium`]: running until the field is mature ([`equilibrium::run_until_mature`]).
//! - [`predictors`]: the ripple that Soulsby & Whitehouse (2005) or Wiberg & Harris (1994)
//!   expect for a run, as a check ([`predictors::Prediction`]).
//! - [`recipe`]: built-in scenario files of opt-in rules ([`recipe::Recipe`]: current
//!   ripples that stop growing).
//! - [`waves`]: near-bed orbital velocity of surface waves by linear wave theory
//!   ([`waves::SurfaceWave`]).
//! - [`regime`]: the flow regime of a run (no motion, ripples, sheet flow) from the Shields
//!   number of the median grain ([`regime::RegimeReport`]).
//! - [`output`]: NetCDF-3 (64-bit offset, CF-style) and `.npy` volumes, written atomically;
//!   `zarr` (feature `zarr`) the same variables as a chunked Zarr v3 store; [`input`] reads
//!   the NetCDF files back ([`input::RippleFile`]).
//! - `figures` (feature `plot`): the paper's Figs. 2, 3, 4, 7, 8 and an error-versus-time
//!   chart, listed in [`FIGURES`].
//!
//! Automata are moved, never created or destroyed: the number of automata and the mass of
//! every grain-size class are conserved exactly ([`Ripple::mass_change`]). After every step no
//! slope between Moore neighbours exceeds the avalanche angle ([`Ripple::steep_pair`]).
//!
//! ```
//! use cellsurf::ripple::{Ripple, RippleParams};
//!
//! // A small 3-D run: 24 x 12 columns of 10 automata, 200 steps of the current.
//! let p = RippleParams { nx: 24, ny: 12, layers: 10, steps: 200, ..RippleParams::default() };
//! let mut r = Ripple::new(&p).unwrap();
//! let automata = r.automata();
//! r.run(p.steps, |_| {});
//! // Automata move but are never created or destroyed, and no slope exceeds the avalanche
//! // angle after a step.
//! assert_eq!(r.automata(), automata);
//! assert_eq!(r.mass_change(), 0);
//! assert!(r.steep_pair().is_none());
//! ```

pub mod acoustics;
pub mod clock;
pub mod compaction;
pub mod equilibrium;
#[cfg(feature = "plot")]
pub mod figures;
pub mod grain;
pub mod input;
pub mod model;
pub mod morphometry;
pub mod orbit;
pub mod output;
pub mod params;
pub mod predictors;
pub mod recipe;
pub mod regime;
pub mod rules;
pub mod spectrum;
pub mod travel;
pub mod volume;
pub mod water;
pub mod waves;
#[cfg(feature = "zarr")]
pub mod zarr;

pub use compaction::Compaction;
pub use grain::GrainClasses;
pub use model::{Ripple, RippleStats};
pub use output::{Field, Format, OutputSpec};
pub use params::{Abstraction, AcousticModel, Frame, Mode, RippleParams};
pub use spectrum::Analysis;
pub use volume::{Automaton, SandVolume};
pub use water::{Flow, WaterVolume};

/// The crate version, recorded in every output (the engine's).
pub use crate::engine::VERSION;

/// The figures of this model, made by `cellsurf figures`.
#[cfg(feature = "plot")]
pub const FIGURES: &[crate::plot::Figure] = figures::FIGURES;

/// Errors of the ripple model.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum RippleError {
    /// A parameter is out of range.
    #[error("{parameter} = {value} is out of range: expected {expected}")]
    Range {
        /// The parameter's name.
        parameter: &'static str,
        /// The value given.
        value: String,
        /// The valid range.
        expected: String,
    },
    /// A name is not known.
    #[error("unknown {parameter} '{value}': expected {expected}")]
    Unknown {
        /// The parameter's name.
        parameter: &'static str,
        /// The value given.
        value: String,
        /// The valid names.
        expected: &'static str,
    },
    /// The lattice could not be built.
    #[error("lattice: {0}")]
    Lattice(String),
    /// A scene file could not be parsed.
    #[error("scene file: {0}")]
    Toml(String),
    /// Reading an input file failed.
    #[error("reading {path}: {reason}")]
    Input {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// Writing an output failed.
    #[error("writing {path}: {reason}")]
    Output {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
}
