//! Wind ripples: the particle model of Laurent Perrinet's notebook "Modelling wind ripples"
//! (numpy and PyTorch). Our readings of its ambiguous passages are stated below.
//!
//! The principal types, one concept per file:
//!
//! - [`WindParams`] ([`params`]): the parameters (notebook defaults: 256 x 256 bins, 524,288
//!   particles, 1024 steps, hop `L = 1/64`, `kappa = 4.5`, `D = 8e-4`, seed 1998), the
//!   diffusion [`Schedule`] and [`WindError`] (a parameter out of range, naming the parameter,
//!   its value and the range);
//! - [`WindRipples`] ([`model`]): the particles and the last height histogram, advanced by
//!   [`WindRipples::step`]; [`WindRun`], a whole run ([`run`]) with its timing;
//! - [`WindStats`] ([`stats`]): the summary of a height field ([`height_stats`]): mean (1 by
//!   construction), standard deviation, dominant ripple wavelength ([`wavelength_bins`]) and
//!   spectrum-weighted mean wavelength ([`mean_wavelength_bins`]), both from
//!   [`power_spectrum_y`];
//! - [`npy_bytes`] ([`output`]): the `.npy` writer.
//!
//! Normal deviates come from `rand_distr::StandardNormal`, on the engine's random streams.
//! Figures (feature `plot`): [`FIGURES`] (`windripples_height`, `windripples_error_vs_time`),
//! drawn by the `figures` module.
//!
//! ```
//! use cellsurf::windripples::{self, WindParams};
//!
//! // 20 steps of 20,000 particles on 32 x 32 bins.
//! let p = WindParams { bins: 32, particles: 20_000, steps: 20, ..WindParams::default() };
//! let run = windripples::run(&p, |_| {}).unwrap();
//! // The height is a density histogram: its mean is 1 by construction.
//! assert!((run.stats.height_mean - 1.0).abs() < 1e-12);
//! assert_eq!(run.height.len(), 32 * 32);
//! // The same seed gives the same field, whatever the thread count.
//! assert_eq!(windripples::run(&p, |_| {}).unwrap().height, run.height);
//! ```
//!
//! # The model (the notebook's loop, exactly)
//!
//! `N` particles at `(x_i, y_i)` on the unit torus, initially uniform. Each step `s = 0, 1, ...`:
//!
//! 1. diffusion: `x_i += sigma_s nu`, `y_i += sigma_s nu'` with `nu, nu'` standard normal and
//!    `sigma_s = D / sqrt(s + 1)` ([`Schedule::Annealed`], the notebook's numpy code, default)
//!    or `sigma_s = D` ([`Schedule::Constant`], its torch code);
//! 2. wrap: `x_i <- x_i mod 1`, `y_i <- y_i mod 1` ([`wrap_unit`]);
//! 3. height: the 2-D histogram of the positions on `bins x bins` cells with density
//!    normalisation, `h = count * bins^2 / N` (numpy's `histogram2d(..., density=True)`), so the
//!    mean height is 1;
//! 4. saltation in the wind direction `y`: `y_i += L * sigmoid(-kappa * h(cell of particle i))`
//!    with `sigmoid(z) = 1 / (1 + exp(-z))` ([`sigmoid`]).
//!
//! As in the notebook (and its numpy code, the benchmarks' peer), the saltation is
//! *not* wrapped at once: between steps `y_i` lies in `[0, 1 + L)`, and the next step's wrap
//! (after its diffusion) brings it back. [`WindRipples::height`] is the histogram of the last
//! step, taken before that step's saltation, which is what the notebook's function returns.
//!
//! Cell `(ix, iy)` is `(floor(x bins), floor(y bins))`, stored at `ix * bins + iy` (numpy's
//! `height[ind_x, ind_y]`); the notebook draws `height.T`, so `x` runs across and `y` (the wind)
//! down the picture, and ripple crests run along `x`.
//!
//! # Parallelism and reproducibility
//!
//! Particles are split into fixed chunks of [`CHUNK`] (by their index in memory); chunk `c`
//! draws from its own Xoshiro256++ stream, [`crate::engine::rng::stream`]`(seed)` advanced by `c`
//! calls of `jump()` (2^128 draws each), for its initial positions and then, step after step,
//! for its normals (`nu` then `nu'` per particle, in index order). The histogram is made of
//! integer counts, whose sum does not depend on how the chunks are grouped. Every particle
//! therefore follows the same arithmetic whatever the number of threads, and the results are
//! bit-identical for any rayon pool. The random numbers differ from numpy's (a different
//! generator), so a run agrees with the notebook in distribution, not draw for draw.
//!
//! # Speed
//!
//! One pass over the particles per step: the previous step's saltation, this step's diffusion,
//! the wrap, the cell and the histogram (per-thread partial histograms of integer counts). The
//! particles are kept sorted by cell (a stable counting sort when they are placed and every
//! [`SORT_EVERY`] steps; they move less than a few cells per step), so that the histogram
//! updates of a chunk stay within a few columns of cells, in the L1 cache. The particles are
//! exchangeable, so which stream serves which particle does not change the model;
//! [`WindRipples::ids`] follows each particle through the sorts. The hop is tabulated by count.

#[cfg(feature = "plot")]
pub mod figures;
pub mod model;
pub mod output;
pub mod params;
pub mod stats;

pub use model::{CHUNK, SORT_EVERY, WindRipples, WindRun, run, sigmoid, wrap_unit};
pub use output::npy_bytes;
pub use params::{MAX_BINS, MAX_LENGTH, MAX_PARTICLES, Schedule, WindError, WindParams};
pub use stats::{WindStats, height_stats, mean_wavelength_bins, power_spectrum_y, wavelength_bins};

/// The figures of this model, made by `cellsurf figures`.
#[cfg(feature = "plot")]
pub const FIGURES: &[crate::plot::Figure] = &[
    crate::plot::Figure {
        name: "windripples_height",
        about: "Wind ripples: the notebook's height field (default parameters, 256 steps), with its spectrum",
        make: figures::height_figure,
    },
    crate::plot::Figure {
        name: "windripples_error_vs_time",
        about: "Wind ripples: seed-to-seed standard error of height_std and wavelength against run time",
        make: figures::error_figure,
    },
];
