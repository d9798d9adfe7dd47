//! Wind-field cursor walk: sand landscapes drawn by one random walker under a fixed wind field.
//!
//! The model of "A model for sedimentation of airborne particles" (article;
//! its ambiguous passages read as stated below). One cursor walks an 8-neighbour torus; each cell it
//! arrives in gains one unit of height ("100% binding rule": the height is the number of hits).
//! In calm air each of the eight moves has probability `P0 = 1/8`; under a wind `W` the
//! probability of direction `i` is (article Eqs. 1-2, Hooke's-law redistribution)
//!
//! ```text
//! P_i = 1/8 + k (W . u_i) / s,      s = 8 * 220 = 1760,
//! ```
//!
//! with `u_i` the unit vector of direction `i` (diagonals normalised), `k` the force constant
//! (`0 <= k <= 1`, default 0.95) and `W` in the article's units (colour levels, `|W| <= 220`).
//! Choice of `s`: `|W . u_i| <= |W| <= 220`, so `|P_i - 1/8| <= k/8 <= 1/8` and every `P_i` lies in
//! `[0, 1/4]`; at `k = 1` and `|W| = 220` the move straight against the wind has probability 0
//! and the move with it 1/4. The eight `P_i` sum to 1 exactly (in exact arithmetic), because
//! `u_{i+4} = -u_i`: the corrections cancel in opposite pairs. Inputs outside this domain
//! (`k` outside `[0, 1]`, a wind faster than 220) are rejected with [`CursorError`].
//!
//! The principal types:
//!
//! - [`Wind`] and [`WindField`] (module [`wind`]): wind vectors, the article's RGB encoding
//!   (three colour vectors at 120 degrees; red toward +x, green toward 120 degrees, blue toward
//!   240 degrees), PNG input and output;
//! - [`WindSpec`]: the built-in generators (calm, uniform, bimodal, converging, rotating);
//! - [`Transitions`] and [`CursorWalk`] (module [`walk`]): the per-cell cumulative tables of
//!   the eight probabilities (one random number and seven comparisons per step) and the walker
//!   with its heights;
//!
//! ```
//! use cellsurf::cursor::{CursorWalk, Transitions, WindSpec};
//!
//! // A uniform wind (the article's Fig. 4 settings) on a 60 x 60 torus.
//! let field = WindSpec::article("uniform").unwrap().field(60, 60).unwrap();
//! let tr = Transitions::new(&field, 0.95).unwrap();
//! let mut walk = CursorWalk::new(&tr, 7);
//! walk.run(100_000);
//! // Each step adds one unit of height where the cursor arrives.
//! assert_eq!(walk.height_total(), 100_000);
//! // k outside [0, 1] would make a probability negative: refused.
//! assert!(Transitions::new(&field, 1.5).is_err());
//! ```
//! - [`SeaLevel`] (module [`display`]): the article's "sea level" flooding and the colour map;
//! - [`stats`]: density error, its exact expectation for uniform winds ([`stats::NoiseModel`]),
//!   drift, error-against-steps slope;
//! - [`CursorError`]: every rejected input, naming the parameter, its value and the valid range.
//!
//! Counting rule: the walk starts in the centre cell (article: "Simulation begins with the
//! cursor placed in the center of grid") with all heights 0, and each step adds 1 to the cell
//! it arrives in; the start is not a visit, so the heights always sum to the number of steps.
//! The article's runs use 11,520,000 steps ([`ARTICLE_STEPS`]); its grid size is not given, the
//! default here is 240 x 240 ([`DEFAULT_SIZE`]: a mean height of 200, so that the article's
//! default sea level of 100 is half the mean height).
//!
//! Figures (feature `plot`): [`FIGURES`], the runs of their scenario files read by
//! [`CursorScenario`].

pub mod display;
#[cfg(feature = "plot")]
mod figures;
mod scenario;
pub mod stats;
pub mod walk;
pub mod wind;

use thiserror::Error;

use crate::engine::count::CountRange;
use crate::engine::lattice::LatticeError;

pub use display::SeaLevel;
pub use scenario::CursorScenario;
pub use walk::{CursorWalk, DIRECTIONS, Transitions, UNIT, probabilities};
pub use wind::{Wind, WindField, WindSpec};

/// The largest wind the model accepts, article units ("0-220 whatever units").
pub const MAX_WIND: f64 = 220.0;
/// The spring scale `s` of Eq. (2): `8 * 220`, so that every `P_i` stays in `[0, 1]` (see the
/// module documentation).
pub const SPRING_SCALE: f64 = 8.0 * MAX_WIND;
/// The calm-air probability of each direction, `P0 = 1/8`.
pub const P0: f64 = 0.125;
/// The article's default force constant.
pub const DEFAULT_K: f64 = 0.95;
/// The article's number of particles (steps) per landscape.
pub const ARTICLE_STEPS: u64 = 11_520_000;
/// The default grid, cells (the article does not state its grid).
pub const DEFAULT_SIZE: (usize, usize) = (240, 240);
/// The largest grid, cells (`4096 x 4096`; the walk needs 40 bytes per cell, 32 for its
/// table and 8 for the height, plus 16 for the wind field while the table is built).
pub const MAX_CELLS: usize = 1 << 24;
/// `steps`: steps of the walk.
pub const STEPS: CountRange = CountRange::new(1, 1_000_000_000_000, "1 to 10^12");
/// `--size`, as [`wind::check_size`] holds it.
pub const SIZE_SIDES: &str = "sides of at least 3 cells, at most 2^24 = 16777216 cells in all";

/// Errors of the cursor model: every one names the parameter or file at fault.
#[derive(Debug, Error)]
pub enum CursorError {
    /// The force constant is outside `[0, 1]`.
    #[error(
        "force constant k = {0} is out of range: expected 0 to 1, so that every probability P_i = 1/8 + k (W . u_i) / 1760 stays between 0 and 1"
    )]
    ForceConstant(f64),
    /// A wind is faster than 220 (or not finite).
    #[error(
        "wind too strong in {place}: |W| = {speed:.2}, but the model accepts at most 220 (article units): a faster wind makes the probability against the wind negative for k near 1 (scale the winds down; for a wind image, --wind-scale 0.86 = 220/255 admits every colour)"
    )]
    WindTooStrong {
        /// Where: the file and pixel, or the field and cell.
        place: String,
        /// The wind's speed.
        speed: f64,
    },
    /// A parameter is out of its range.
    #[error("{name} = {} is out of range: {range}", crate::engine::shown(*value))]
    Parameter {
        /// The parameter.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The valid range, in words.
        range: String,
    },
    /// A wind image cannot be read or decoded.
    #[error("cannot read wind image {path}: {reason}")]
    Png {
        /// The file.
        path: String,
        /// Why.
        reason: String,
    },
    /// A wind image does not have one pixel per cell.
    #[error(
        "wind image {path} is {width}x{height} pixels, but the grid is {expected_width}x{expected_height} cells: the image must have exactly one pixel per cell (no resampling is done; use --size {width}x{height} to match the image)"
    )]
    PngSize {
        /// The file.
        path: String,
        /// Its width, pixels.
        width: usize,
        /// Its height, pixels.
        height: usize,
        /// The grid's width, cells.
        expected_width: usize,
        /// The grid's height, cells.
        expected_height: usize,
    },
    /// A grid size is unusable.
    #[error("grid size {0}")]
    GridSize(String),
    /// The lattice cannot be built.
    #[error(transparent)]
    Lattice(#[from] LatticeError),
}

/// The figures of this model, made by `cellsurf figures`.
#[cfg(feature = "plot")]
pub const FIGURES: &[crate::plot::Figure] = figures::FIGURES;

/// The scenario files of the figures' runs (`scenarios/NAME.toml`), as `(NAME, text)`.
#[cfg(feature = "plot")]
pub const SCENARIOS: &[(&str, &str)] = figures::SCENARIOS;

/// Draws a landscape next to its wind field into a PNG (written atomically): the wind as the
/// article's input image with arrows, the heights flooded below `sea` (visits) with the
/// colour map of [`display::terrain_rgb`], `title` above and `caption` (lines) below. Cells
/// are drawn `max(1, 480 / max(width, height))` pixels wide.
///
/// # Errors
///
/// [`crate::plot::PlotError`] when the heights do not match the field, the picture would be
/// too large, or drawing or writing fails.
#[cfg(feature = "plot")]
pub fn draw_landscape(
    path: &std::path::Path,
    title: &str,
    caption: &str,
    field: &WindField,
    heights: &[u64],
    sea: f64,
) -> Result<(), crate::plot::PlotError> {
    let (w, h) = (field.width(), field.height());
    if heights.len() != w * h {
        return Err(crate::plot::PlotError::InvalidInput {
            name: "heights".into(),
            reason: format!("has {} entries for a {w}x{h} field", heights.len()),
        });
    }
    let px = (480 / w.max(h)).max(1);
    let pics = [
        figures::wind_picture("wind field (RGB encoding, arrows)".into(), field, px),
        figures::landscape_picture(
            format!(
                "heights (sea level {sea:.0}, {:.0}% flooded)",
                100.0 * display::flooded_fraction(heights, sea)
            ),
            heights,
            w,
            h,
            sea,
            px,
        ),
    ];
    figures::draw_pictures(path, title, caption, &pics, 2)
}
