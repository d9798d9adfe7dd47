//! Tiling toroidal ripple volumes into large surfaces, and fractal rippled dunes.
//!
//! Staelens, Dupont & Henriet (Sect. 3.4, "Generating an infinite surface", Fig. 6): the ripple
//! generator is a closed toroidal system, so its volumes tile into continuous infinite surfaces
//! "without holes or gaps"; neighbouring tiles can come from the same step or from different but
//! close steps ("ripple patches"), and "fractal properties of dunes can be used to generate
//! rippled dunes" (Fig. 9).
//!
//! Principal types:
//! - [`Tile`] ([`tileset`]): one toroidal ripple tile (elevation, optionally a volume field),
//!   from an in-process [`crate::ripple::Ripple`] run or from a ripple NetCDF file.
//! - [`Mosaic`] ([`mosaic`]): `mx x my` mosaic cells, each showing one tile ([`Choose`]: the
//!   same tile everywhere, or seeded random "patches" from a pool), optionally cross-faded over
//!   a band of bins at the tile edges ([`seam::edge_weights`]).
//! - [`SeamStats`] / [`SeamMeter`] ([`seam`]): the seam statistic, mean |height jump| across
//!   tile edges against the jump between neighbouring bins inside the tiles, per direction,
//!   measured row by row.
//! - [`FbmParams`], [`DuneField`] ([`fractal`]): periodic fractional Brownian relief by spectral
//!   synthesis (Saupe 1988), or a band-limited relief around a dune wavelength; the radially
//!   averaged spectrum and its slope.
//! - [`RippledDunes`] ([`dunes`]): ripples riding on dunes, the mosaic re-oriented so that crests
//!   stay perpendicular to the local current.
//! - [`RowSource`] and the streaming writers ([`stream`]): a surface of any size written row by
//!   row (NetCDF-3 64-bit offset with `y` as the record dimension, or `.npy`), memory
//!   independent of the number of rows.
//! - [`ZarrLayout`](zarr::ZarrLayout), [`Part`](zarr::Part) and the Zarr writer and checker
//!   (`zarr`, feature `zarr`): a surface as a chunked Zarr v3 store written by one process or
//!   by `N` independent parts, chunks of whole tiles.
//! - [`TileScenario`] ([`scenario`]): a `cellsurf tile` scenario file read back (the published
//!   figures' runs).
//! - `figures` (feature `plot`): `ripple_fig6_tiles` and `ripple_fig9_fractal_dunes`, listed in
//!   [`FIGURES`].
//!
//! ```
//! use cellsurf::ripple::RippleParams;
//! use cellsurf::tile::{Choose, Mosaic, tileset::tiles_from_run};
//!
//! // One small ripple run gives one toroidal tile; a 3 x 2 mosaic of it.
//! let p = RippleParams { nx: 24, ny: 12, layers: 10, steps: 20, ..RippleParams::default() };
//! let tiles = tiles_from_run(&p, &[1], &[20], None, |_| {}).unwrap();
//! let m = Mosaic::new(tiles, 3, 2, Choose::Same, 1, 0).unwrap();
//! assert_eq!(m.size(), (72, 24));
//! // The tile is a torus: the mosaic repeats it exactly, with no seam.
//! for y in 0..24 {
//!     for x in 0..24 {
//!         assert_eq!(m.value(x, y), m.value(x + 24, y));
//!         assert_eq!(m.value(x, y), m.value(x + 48, y));
//!     }
//! }
//! ```

pub mod dunes;
#[cfg(feature = "plot")]
pub mod figures;
pub mod fractal;
pub mod mosaic;
pub mod scenario;
pub mod seam;
pub mod stream;
pub mod tileset;
#[cfg(feature = "zarr")]
pub mod zarr;

pub use dunes::{DuneParams, RippledDunes};
pub use fractal::{DuneField, FbmParams, Relief};
pub use mosaic::{Choose, Mosaic};
pub use scenario::{GenerateOptions, TileScenario};
pub use seam::{ANGLE_OF_REPOSE_DEG, SeamMeter, SeamStats, SlopeStats};
pub use stream::{RowSource, StreamFormat, StreamReport, StreamSpec};
pub use tileset::Tile;

/// The figures of the tiling and the fractal dunes, made by `cellsurf figures`.
#[cfg(feature = "plot")]
pub const FIGURES: &[crate::plot::Figure] = figures::FIGURES;

/// Errors of tiling, fractal relief and streaming.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum TileError {
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
    /// Tiles that cannot share a mosaic (different sizes, bins or layers).
    #[error("tile {index} ({label}) does not match the first tile: {reason}")]
    Mismatch {
        /// Index of the tile in the pool.
        index: usize,
        /// Its label (file and step, or seed and step).
        label: String,
        /// What differs.
        reason: String,
    },
    /// The ripple model or a ripple file failed.
    #[error("ripple: {0}")]
    Ripple(#[from] crate::ripple::RippleError),
    /// A store checked, not written, is not what the run would write (what differs) or cannot
    /// be read.
    #[error("{0}")]
    Store(String),
    /// Writing an output failed.
    #[error("writing {path}: {reason}")]
    Output {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
}

impl TileError {
    /// A [`TileError::Range`].
    pub(crate) fn range(
        parameter: &'static str,
        value: impl std::fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        TileError::Range {
            parameter,
            value: value.to_string(),
            expected: expected.into(),
        }
    }
}
