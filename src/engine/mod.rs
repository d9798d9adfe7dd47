//! The engine every model is built on: lattices, the surface partition, the sum tree, the
//! random stream, shared statistics and atomic output.
//!
//! - [`lattice`]: [`Lattice`](lattice::Lattice), a `width x height` grid with a
//!   [`Neighbourhood`](lattice::Neighbourhood) (square 4-neighbour, Eq. (2) of the growth
//!   paper; square 8-neighbour Moore; hexagonal 6-neighbour, Eq. (3)) and a
//!   [`Boundary`](lattice::Boundary) per axis (torus or walls). Models take their neighbour
//!   offsets from here ([`lattice::MOORE`] for the 8-neighbour models).
//! - [`surface`]: [`Surface`](surface::Surface), the surface sites partitioned by their count
//!   of occupied neighbours (the growth samplers' `O(1)` picks).
//! - [`count`]: [`CountRange`](count::CountRange), the range of a whole-number parameter,
//!   shared by its model's check, its scenario reader and its command-line option.
//! - [`sumtree`]: [`SumTree`](sumtree::SumTree), partial sums for weighted selection.
//! - [`part`]: [`Part`](part::Part), one share of a job split over independent processes
//!   (`--part i/N`).
//! - [`study`]: [`Study`](study::Study), an error-against-time study as independent runs, run
//!   whole or in parts and gathered.
//! - [`rng`]: [`Stream`](rng::Stream), the Xoshiro256++ stream every model draws from.
//! - [`stats`]: mean and standard error over seeds, error-against-run-time points, power-law
//!   slopes.
//! - [`wrap`]: periodic indices and a floor without a library call, for hot loops.
//! - [`io`]: [`write_atomic`](io::write_atomic) and the output checks: no reader ever sees a
//!   partial file.
//! - [`scenario`]: [`read`](scenario::read), a subcommand's scenario file (`model = "..."` and
//!   its options) as the library reads it back for the published figures.
//! - `zarr` (feature `zarr`): Zarr v3 stores written chunk by chunk by independent processes
//!   (atomic chunks, metadata written by whichever writer comes first, checked by the others).
//!
//! The engine imports nothing else of the crate; everything else imports it.
//!
//! Equations (2) and (3) are those of "Simple Monte Carlo cellular models for surface growth"
//! (the growth paper).
//!
//! ```
//! use cellsurf::engine::lattice::{Boundary, Lattice, Neighbourhood};
//!
//! // A 6 x 4 hexagonal torus: every cell has 6 neighbours, and neighbourhood is symmetric.
//! let l = Lattice::new(Neighbourhood::Hex, 6, 4, Boundary::TORUS).unwrap();
//! assert_eq!(l.len(), 24);
//! for c in 0..l.len() {
//!     assert_eq!(l.neighbours(c).count(), 6);
//!     assert!(l.neighbours(c).all(|d| l.neighbours(d).any(|e| e == c)));
//! }
//! // An odd row count cannot close a hexagonal torus: a typed error names the axis.
//! assert!(Lattice::new(Neighbourhood::Hex, 6, 5, Boundary::TORUS).is_err());
//! ```

pub mod count;
pub mod io;
pub mod lattice;
pub mod part;
pub mod rng;
pub mod scenario;
pub mod stats;
pub mod study;
pub mod sumtree;
pub mod surface;
pub mod wrap;
#[cfg(feature = "zarr")]
pub mod zarr;

/// The crate version, recorded in every output file.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// A number as an error message shows it: in scientific notation when very large or very
/// small (`1e300`, not three hundred digits), as written otherwise.
pub fn shown(v: f64) -> String {
    if v.is_finite() && v != 0.0 && !(1e-6..1e9).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}
