//! Wind ripples: the particle model of Laurent Perrinet's notebook "Modelling wind ripples"
//! (`../shared/seeds/001_*.txt`, read with `../shared/READING.md`, section 001).
//!
//! The principal types are:
//!
//! - [`WindParams`]: the parameters (notebook defaults: 256 x 256 bins, 524,288 particles, 1024
//!   steps, hop `L = 1/64`, `kappa = 4.5`, `D = 8e-4`, seed 1998) and the diffusion
//!   [`Schedule`];
//! - [`WindRipples`]: the particles and the last height histogram, advanced by
//!   [`WindRipples::step`];
//! - [`WindStats`]: the summary of a height field ([`height_stats`]): mean (1 by construction),
//!   standard deviation, dominant ripple wavelength ([`wavelength_bins`]) and spectrum-weighted
//!   mean wavelength ([`mean_wavelength_bins`]), both from [`power_spectrum_y`];
//! - [`WindRun`]: a whole run ([`run`]) with its timing;
//! - [`WindError`]: a parameter out of range, naming the parameter, its value and the range;
//! - [`npy_bytes`], the `.npy` writer. Normal deviates come from `rand_distr::StandardNormal`.
//!
//! Figures (feature `plot`): [`FIGURES`] (`windripples_height`, `windripples_error_vs_time`),
//! drawn by the `figures` module.
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
//! As in the notebook (and the peer `../shared/peers/wind_ripples_numpy.py`), the saltation is
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

use std::fmt;
use std::str::FromStr;
use std::time::Instant;

use rand::RngExt;
use rand_distr::StandardNormal;
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Particles per random stream (and per unit of parallel work).
pub const CHUNK: usize = 4096;
/// Largest number of bins per side (`bins^2` = 16,777,216 cells, 64 MiB of counts).
pub const MAX_BINS: usize = 4096;
/// Largest number of particles (24 bytes each, 48 while they are sorted: 48 GiB at this
/// limit).
pub const MAX_PARTICLES: usize = 1 << 30;
/// Largest hop `L` and diffusion `D` accepted (the torus has size 1: far larger values only
/// lose the position's precision).
pub const MAX_LENGTH: f64 = 1e6;

/// Counts below this have their hop precomputed (larger counts are computed on the fly, with
/// the same function, so the result is the same).
const HOP_TABLE_LEN: usize = 1024;
/// Steps between two sorts of the particles by cell ([`WindRipples::step`]).
pub const SORT_EVERY: u64 = 64;
/// Particles per batch of normals drawn ahead of the moves.
const BATCH: usize = 256;
/// Budget of `u32` histogram cells held at once by the parallel partial histograms.
const PARTIAL_CELLS_BUDGET: usize = 1 << 24;

/// How the diffusion step size changes with the step number.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Schedule {
    /// `sigma = D / sqrt(step + 1)`, `step` counted from 0: the notebook's numpy code (default).
    #[default]
    Annealed,
    /// `sigma = D` at every step: the notebook's torch code.
    Constant,
}

impl Schedule {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Schedule::Annealed => "annealed",
            Schedule::Constant => "constant",
        }
    }

    /// The diffusion step size of step `step` (counted from 0) for diffusion constant `d`.
    pub fn sigma(self, d: f64, step: u64) -> f64 {
        match self {
            Schedule::Annealed => d / ((step + 1) as f64).sqrt(),
            Schedule::Constant => d,
        }
    }
}

impl fmt::Display for Schedule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Schedule {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "annealed" => Ok(Schedule::Annealed),
            "constant" => Ok(Schedule::Constant),
            _ => Err(format!(
                "unknown schedule '{s}': expected annealed (D/sqrt(step+1), numpy) or constant (D, torch)"
            )),
        }
    }
}

/// A parameter out of its valid range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum WindError {
    /// `name = value` is outside `range`.
    #[error("{name} = {value} is out of range: {range}")]
    OutOfRange {
        /// The parameter (as on the command line: `particles`, `bins`, `steps`, `kappa`, `hop`,
        /// `diffusion`).
        name: &'static str,
        /// Its value, as given.
        value: String,
        /// The valid range, in words.
        range: &'static str,
    },
}

impl WindError {
    fn out_of_range(name: &'static str, value: impl fmt::Display, range: &'static str) -> Self {
        WindError::OutOfRange {
            name,
            value: value.to_string(),
            range,
        }
    }
}

/// The parameters of a run. Lengths are in units of the torus side (the torus is `[0, 1)^2`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WindParams {
    /// Histogram cells per side (`bins x bins` cells); default 256 (notebook `bins = 2**8`).
    pub bins: usize,
    /// Number of particles `N`; default 524,288 (notebook `N_particles = 2**16 * 8`).
    pub particles: usize,
    /// Number of steps of [`run`]; default 1024 (notebook `N_step = 2**10`).
    pub steps: u64,
    /// Saltation hop `L` along `y`, torus units; default `1/64` (notebook `L = 1 / 2**6`).
    pub hop: f64,
    /// Saltation sensitivity to the height `kappa` (dimensionless; the height is 1 on average);
    /// default 4.5.
    pub kappa: f64,
    /// Diffusion `D`, torus units per step (standard deviation of one step's displacement per
    /// axis, before the schedule's factor); default `8e-4`.
    pub diffusion: f64,
    /// Diffusion schedule; default [`Schedule::Annealed`] (the notebook's numpy code).
    pub schedule: Schedule,
    /// Seed of the random streams; default 1998.
    pub seed: u64,
}

impl Default for WindParams {
    /// The notebook's `Params()`.
    fn default() -> Self {
        WindParams {
            bins: 256,
            particles: 524_288,
            steps: 1024,
            hop: 1.0 / 64.0,
            kappa: 4.5,
            diffusion: 8e-4,
            schedule: Schedule::Annealed,
            seed: 1998,
        }
    }
}

impl WindParams {
    /// The parameters as `key = value` lines (TOML), with the model's name and the cellsurf
    /// version: recorded in the PNG files and the `.npy` sidecar.
    pub fn describe_toml(&self) -> String {
        format!(
            "model = \"wind-ripples\"\nversion = \"{}\"\nsteps = {}\nparticles = {}\nbins = {}\n\
             hop = {:?}\nkappa = {:?}\ndiffusion = {:?}\nschedule = \"{}\"\nseed = {}\n",
            crate::engine::VERSION,
            self.steps,
            self.particles,
            self.bins,
            self.hop,
            self.kappa,
            self.diffusion,
            self.schedule,
            self.seed
        )
    }

    /// Checks every parameter; the error names the first one out of range.
    pub fn validate(&self) -> Result<(), WindError> {
        if self.particles == 0 || self.particles > MAX_PARTICLES {
            return Err(WindError::out_of_range(
                "particles",
                self.particles,
                "1 to 1073741824 (2^30)",
            ));
        }
        if self.bins == 0 || self.bins > MAX_BINS {
            return Err(WindError::out_of_range(
                "bins",
                self.bins,
                "1 to 4096 (bins^2 histogram cells)",
            ));
        }
        if self.steps == 0 {
            return Err(WindError::out_of_range("steps", self.steps, "at least 1"));
        }
        if !(self.kappa.is_finite() && self.kappa >= 0.0) {
            return Err(WindError::out_of_range(
                "kappa",
                self.kappa,
                "finite and >= 0",
            ));
        }
        if !(self.hop.is_finite() && (0.0..=MAX_LENGTH).contains(&self.hop)) {
            return Err(WindError::out_of_range(
                "hop",
                self.hop,
                "0 to 1e6 torus sides (L >= 1 wraps around)",
            ));
        }
        if !(self.diffusion.is_finite() && (0.0..=MAX_LENGTH).contains(&self.diffusion)) {
            return Err(WindError::out_of_range(
                "diffusion",
                self.diffusion,
                "0 to 1e6 torus sides per step",
            ));
        }
        Ok(())
    }
}

/// `1 / (1 + exp(-z))`, without overflow for any `z` (it is `exp(z) / (1 + exp(z))` for
/// `z < 0`): exactly 1/2 at 0, 0 at `-inf`, 1 at `+inf`, never NaN for a non-NaN `z`.
#[inline]
pub fn sigmoid(z: f64) -> f64 {
    if z >= 0.0 {
        1.0 / (1.0 + (-z).exp())
    } else {
        let e = z.exp();
        e / (1.0 + e)
    }
}

/// `v mod 1` in `[0, 1)`: `v - floor(v)` (numpy's `v % 1`), except that a result that rounds up
/// to 1 (a tiny negative `v`, e.g. `-1e-17`) is mapped to 0, the same point of the torus, where
/// numpy would return 1.0 (and the notebook's `(x*bins).astype(int)` would index past the last
/// bin). Exact for `v` in `[0, 2)`.
#[inline]
pub fn wrap_unit(v: f64) -> f64 {
    // The common cases first: bit for bit `v - floor(v)` (floor is a libm call on baseline
    // x86-64). `v + 1.0` may round up to 1 for a tiny negative `v`.
    let r = if (0.0..1.0).contains(&v) {
        v
    } else if (1.0..2.0).contains(&v) {
        v - 1.0
    } else if (-1.0..0.0).contains(&v) {
        v + 1.0
    } else {
        v - v.floor()
    };
    if r < 1.0 { r } else { 0.0 }
}

/// The hop of a particle in a cell holding `count` particles:
/// `L * sigmoid(-kappa * count * scale)` with `scale = bins^2 / N`.
#[inline]
fn hop_of_count(count: u32, scale: f64, kappa: f64, hop: f64) -> f64 {
    hop * sigmoid(-kappa * (f64::from(count) * scale))
}

/// The cell `ix * bins + iy` of a position in `[0, 1)^2` (`fb = bins as f64`).
#[inline(always)]
fn cell_of(x: f64, y: f64, fb: f64, bins: u32) -> u32 {
    // `as u32` saturates; `min` guards against a product rounding up to `bins`.
    let ix = ((x * fb) as u32).min(bins - 1);
    let iy = ((y * fb) as u32).min(bins - 1);
    ix * bins + iy
}

/// The particles and the last height histogram of a run (see the module documentation).
#[derive(Clone, Debug)]
pub struct WindRipples {
    params: WindParams,
    x: Vec<f64>,
    y: Vec<f64>,
    /// Cell of each particle at the last histogram.
    cell: Vec<u32>,
    /// The last histogram, `bins * bins` counts.
    counts: Vec<u32>,
    /// One random stream per chunk of [`CHUNK`] particles.
    rngs: Vec<Xoshiro256PlusPlus>,
    /// `bins^2 / N`: height of one particle.
    scale: f64,
    /// Hop for counts below its length.
    hop_table: Vec<f64>,
    /// The last step's saltation is not yet added to `y` (it is fused into the next step's
    /// pass over the particles, or applied by [`WindRipples::positions`]).
    pending: bool,
    /// Identity of each particle: its index when the particles were placed.
    id: Vec<u32>,
    steps_done: u64,
}

impl WindRipples {
    /// Places the particles uniformly on the torus (chunk `c`'s stream gives `x_i, y_i` in turn
    /// for its particles) and histograms them. `params.steps` is not used here (see [`run`]).
    pub fn new(params: WindParams) -> Result<Self, WindError> {
        params.validate()?;
        let n = params.particles;
        let bins = params.bins;
        let n_chunks = n.div_ceil(CHUNK);
        let mut base = crate::engine::rng::stream(params.seed);
        let mut rngs = Vec::with_capacity(n_chunks);
        for _ in 0..n_chunks {
            rngs.push(base.clone());
            base.jump();
        }
        let scale = (bins * bins) as f64 / n as f64;
        let hop_table = (0..HOP_TABLE_LEN.min(n + 1))
            .map(|c| hop_of_count(c as u32, scale, params.kappa, params.hop))
            .collect();
        let mut w = WindRipples {
            x: vec![0.0; n],
            y: vec![0.0; n],
            cell: vec![0; n],
            counts: Vec::new(),
            params,
            rngs,
            scale,
            hop_table,
            pending: false,
            id: (0..n as u32).collect(),
            steps_done: 0,
        };
        w.counts = w.pass(None);
        w.sort_by_cell();
        Ok(w)
    }

    /// The parameters.
    pub fn params(&self) -> &WindParams {
        &self.params
    }

    /// Steps done so far.
    pub fn steps_done(&self) -> u64 {
        self.steps_done
    }

    /// The positions `(x, y)` after the last step's saltation: `x` in `[0, 1)`, `y` in `[0, 1)`
    /// before the first step and in `[0, 1 + L)` after a step (the saltation is wrapped by the
    /// next step, as in the notebook). Applies the pending saltation first (see
    /// [`WindRipples::step`]); this changes no result.
    pub fn positions(&mut self) -> (&[f64], &[f64]) {
        self.settle();
        (&self.x, &self.y)
    }

    /// The identity of each particle (its index when the particles were placed), in the
    /// order of [`Self::positions`]: the particles are kept sorted by cell (see
    /// [`WindRipples::step`]), so a particle's index changes, its identity does not.
    pub fn ids(&self) -> &[u32] {
        &self.id
    }

    /// The cell index `ix * bins + iy` of each particle at the last histogram.
    pub fn cells(&self) -> &[u32] {
        &self.cell
    }

    /// The last histogram: particle counts of the `bins * bins` cells, cell `(ix, iy)` at
    /// `ix * bins + iy`. Before the first step, the histogram of the initial positions.
    pub fn counts(&self) -> &[u32] {
        &self.counts
    }

    /// The last height field, `h = count * bins^2 / N` (mean 1), laid out as [`Self::counts`]:
    /// what the notebook's `wind_ripples(p)` returns after `steps_done` steps.
    pub fn height(&self) -> Vec<f64> {
        let s = self.scale;
        self.counts.iter().map(|&c| f64::from(c) * s).collect()
    }

    /// The summary statistics of [`Self::height`].
    pub fn stats(&self) -> WindStats {
        height_stats(&self.height(), self.params.bins)
    }

    /// The diffusion step size of the next step.
    pub fn next_sigma(&self) -> f64 {
        self.params
            .schedule
            .sigma(self.params.diffusion, self.steps_done)
    }

    /// The hop of a particle in a cell of `count` particles.
    #[inline(always)]
    fn hop_for(table: &[f64], count: u32, scale: f64, kappa: f64, hop: f64) -> f64 {
        match table.get(count as usize) {
            Some(&h) => h,
            None => hop_of_count(count, scale, kappa, hop),
        }
    }

    /// Reorders the particles by their cell at the last histogram (a stable counting sort;
    /// positions, cells, identities and the pending saltation move together), so that the
    /// particles of a chunk touch few cells of the histogram: its updates then hit the cache.
    /// Deterministic, so results still do not depend on the thread count.
    fn sort_by_cell(&mut self) {
        let n = self.x.len();
        let mut next = Vec::with_capacity(self.counts.len());
        let mut at = 0u32;
        for &c in &self.counts {
            next.push(at);
            at += c;
        }
        let mut x = vec![0.0; n];
        let mut y = vec![0.0; n];
        let mut cell = vec![0u32; n];
        let mut id = vec![0u32; n];
        for i in 0..n {
            let c = self.cell[i];
            let d = next[c as usize] as usize;
            next[c as usize] += 1;
            x[d] = self.x[i];
            y[d] = self.y[i];
            cell[d] = c;
            id[d] = self.id[i];
        }
        self.x = x;
        self.y = y;
        self.cell = cell;
        self.id = id;
    }

    /// Adds the pending saltation to `y`.
    fn settle(&mut self) {
        if !self.pending {
            return;
        }
        let (counts, table) = (&self.counts, &self.hop_table);
        let (scale, kappa, hop) = (self.scale, self.params.kappa, self.params.hop);
        self.y
            .par_chunks_mut(CHUNK)
            .zip(self.cell.par_chunks(CHUNK))
            .for_each(|(ys, cs)| {
                for (yi, &c) in ys.iter_mut().zip(cs) {
                    *yi += Self::hop_for(table, counts[c as usize], scale, kappa, hop);
                }
            });
        self.pending = false;
    }

    /// One parallel pass over the chunks: with `sigma = None`, draws the initial positions;
    /// with `Some(sigma)`, adds the pending saltation (if any), then the diffusion, and wraps.
    /// Then records each particle's cell and returns the histogram (integer counts).
    fn pass(&mut self, sigma: Option<f64>) -> Vec<u32> {
        let bins = self.params.bins;
        let cells = bins * bins;
        let n_chunks = self.rngs.len();
        let threads = rayon::current_num_threads().max(1);
        // A few partial histograms per thread (for balance), within a memory budget; the integer
        // sum does not depend on how many there are.
        let pieces = (4 * threads)
            .min(n_chunks)
            .min((PARTIAL_CELLS_BUDGET / cells).max(1))
            .max(1);
        let min_len = n_chunks.div_ceil(pieces);
        let fb = bins as f64;
        let b32 = bins as u32;
        let salt = self.pending.then_some((&self.counts, &self.hop_table));
        let (scale, kappa, hop) = (self.scale, self.params.kappa, self.params.hop);
        let counts = self
            .x
            .par_chunks_mut(CHUNK)
            .zip(self.y.par_chunks_mut(CHUNK))
            .zip(self.cell.par_chunks_mut(CHUNK))
            .zip(self.rngs.par_iter_mut())
            .with_min_len(min_len)
            .fold(
                || vec![0u32; cells],
                |mut acc, (((xs, ys), cs), rng)| {
                    let mut r = rng.clone();
                    match (sigma, salt) {
                        (None, _) => {
                            let it = xs.iter_mut().zip(ys.iter_mut()).zip(cs.iter_mut());
                            for ((xi, yi), c) in it {
                                *xi = r.random::<f64>();
                                *yi = r.random::<f64>();
                                *c = cell_of(*xi, *yi, fb, b32);
                                acc[*c as usize] += 1;
                            }
                        }
                        (Some(s), salt) => {
                            // In batches: first the normals (nu, nu' per particle, in order),
                            // then the moves; the same draws and arithmetic as one loop over
                            // the particles, in tighter loops (measured 20 % faster).
                            let mut nu = [0.0f64; 2 * BATCH];
                            for ((xb, yb), cb) in xs
                                .chunks_mut(BATCH)
                                .zip(ys.chunks_mut(BATCH))
                                .zip(cs.chunks_mut(BATCH))
                            {
                                let nu = &mut nu[..2 * xb.len()];
                                for v in nu.iter_mut() {
                                    *v = r.sample(StandardNormal);
                                }
                                let it = xb.iter_mut().zip(yb.iter_mut()).zip(cb.iter());
                                for (((xi, yi), c), pair) in it.zip(nu.chunks_exact(2)) {
                                    // The previous step's saltation, then this step's diffusion.
                                    let y = match salt {
                                        Some((prev, table)) => {
                                            let n = prev[*c as usize];
                                            *yi + Self::hop_for(table, n, scale, kappa, hop)
                                        }
                                        None => *yi,
                                    };
                                    *xi = wrap_unit(*xi + s * pair[0]);
                                    *yi = wrap_unit(y + s * pair[1]);
                                }
                                // Then the cells and the histogram, in loops of their own.
                                for ((xi, yi), c) in xb.iter().zip(yb.iter()).zip(cb.iter_mut()) {
                                    *c = cell_of(*xi, *yi, fb, b32);
                                }
                                for &c in cb.iter() {
                                    acc[c as usize] += 1;
                                }
                            }
                        }
                    }
                    *rng = r;
                    acc
                },
            )
            .reduce_with(|mut a, b| {
                for (u, v) in a.iter_mut().zip(&b) {
                    *u += *v;
                }
                a
            })
            .unwrap_or_else(|| vec![0; cells]);
        self.pending = false;
        counts
    }

    /// One step of the notebook's loop: diffusion, wrap, histogram, saltation (see the module
    /// documentation). Afterwards [`Self::counts`] and [`Self::height`] hold this step's
    /// histogram.
    ///
    /// The saltation is computed from this histogram but added to `y` at the start of the next
    /// step's pass over the particles (or by [`Self::positions`]): the same arithmetic in the
    /// same order as the notebook, one pass over memory fewer. Every [`SORT_EVERY`] steps (and
    /// once when the particles are placed) the particles are reordered by cell, which changes
    /// which stream serves which particle but not the model (the particles are exchangeable);
    /// [`Self::ids`] keeps their identities.
    pub fn step(&mut self) {
        if self.steps_done % SORT_EVERY == 0 && self.steps_done > 0 {
            self.sort_by_cell();
        }
        let sigma = self.next_sigma();
        self.counts = self.pass(Some(sigma));
        self.pending = true;
        self.steps_done += 1;
    }
}

/// Summary statistics of a height field.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct WindStats {
    /// Mean height (1 up to rounding: density normalisation).
    pub height_mean: f64,
    /// Standard deviation of the height over the cells (population, numpy's `height.std()`).
    pub height_std: f64,
    /// Dominant ripple wavelength along the wind, in bins: the peak of the smoothed spectrum
    /// ([`wavelength_bins`]). `None` for a field with no variation along `y` (or `bins < 2`).
    pub wavelength_bins: Option<f64>,
    /// Spectrum-weighted mean wavelength along the wind, in bins ([`mean_wavelength_bins`]):
    /// steadier than the peak when the spectrum is broad. `None` as for `wavelength_bins`.
    pub mean_wavelength_bins: Option<f64>,
}

/// Mean, standard deviation and wavelengths of a `bins x bins` height field laid out as
/// [`WindRipples::counts`]. Sums run in cell order, so the result is reproducible.
pub fn height_stats(height: &[f64], bins: usize) -> WindStats {
    let m = height.len().max(1) as f64;
    let mean = compensated_sum(height.iter().copied()) / m;
    let var = compensated_sum(height.iter().map(|h| (h - mean) * (h - mean))) / m;
    let p = power_spectrum_y(height, bins);
    WindStats {
        height_mean: mean,
        height_std: var.sqrt(),
        wavelength_bins: peak_wavelength(&p, bins),
        mean_wavelength_bins: mean_wavelength(&p, bins),
    }
}

/// The sum of `v` in order, with Neumaier's compensation (error of order one rounding,
/// whatever the length).
fn compensated_sum(v: impl Iterator<Item = f64>) -> f64 {
    let (mut sum, mut c) = (0.0f64, 0.0f64);
    for x in v {
        let t = sum + x;
        if sum.abs() >= x.abs() {
            c += (sum - t) + x;
        } else {
            c += (x - t) + sum;
        }
        sum = t;
    }
    sum + c
}

/// Columns per unit of parallel work in [`power_spectrum_y`].
const SPECTRUM_GROUP: usize = 16;

/// The power spectrum of the height along the wind, summed over the columns:
/// `P(k) = sum_ix |sum_iy (h[ix, iy] - 1) exp(-2 pi i k iy / bins)|^2` for `k = 0..=bins/2`
/// (element `k`; `P(0)` is included for indexing but carries only the column means).
///
/// This is the 2-D power spectrum of the field summed over the wavenumber across the wind, so
/// crests need not be straight or aligned. Each column's DFT is a rustfft FFT with the scalar
/// planner (the same arithmetic on every machine, unlike its SIMD planners); the columns are
/// summed in fixed groups and the groups in order, so the result does not depend on the number
/// of threads. Empty for `bins = 0` or a `height` of the wrong length.
pub fn power_spectrum_y(height: &[f64], bins: usize) -> Vec<f64> {
    use rustfft::num_complex::Complex;
    let n = bins;
    if n == 0 || height.len() != n * n {
        return Vec::new();
    }
    let half = n / 2;
    let fft = rustfft::FftPlannerScalar::<f64>::new().plan_fft_forward(n);
    let groups: Vec<Vec<f64>> = height
        .par_chunks(n * SPECTRUM_GROUP)
        .map(|block| {
            let mut p = vec![0.0; half + 1];
            let mut buf = vec![Complex::new(0.0, 0.0); n];
            let mut scratch = vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()];
            for col in block.chunks_exact(n) {
                for (b, &h) in buf.iter_mut().zip(col) {
                    *b = Complex::new(h - 1.0, 0.0);
                }
                fft.process_with_scratch(&mut buf, &mut scratch);
                for (pk, b) in p.iter_mut().zip(&buf) {
                    *pk += b.norm_sqr();
                }
            }
            p
        })
        .collect();
    let mut p = vec![0.0; half + 1];
    for g in &groups {
        for (a, b) in p.iter_mut().zip(g) {
            *a += b;
        }
    }
    p
}

/// The dominant ripple wavelength along the wind (`y`), in bins, of a `bins x bins` height
/// field: the peak of [`power_spectrum_y`] smoothed over `2w + 1` wavenumbers, `w = max(1,
/// bins / 64)`, refined to the power-weighted mean wavenumber `k_hat` within that window;
/// `bins / k_hat`. Exact for a sinusoid of integer wavenumber, within about 1 % otherwise.
///
/// When the spectrum is broad with several humps of similar power (the notebook's model at 128
/// steps has nearly equal power from 2 to 6 bins), the peak can jump between them from seed to
/// seed; [`mean_wavelength_bins`] is then the steadier statistic. `None` when `bins < 2` or
/// the field does not vary along `y` (power at `k >= 1` below `1e-20` of the total: rounding).
pub fn wavelength_bins(height: &[f64], bins: usize) -> Option<f64> {
    peak_wavelength(&power_spectrum_y(height, bins), bins)
}

/// The spectrum-weighted mean wavelength along the wind, in bins:
/// `sum_k (bins / k) P(k) / sum_k P(k)` over `k = 1..=bins/2` ([`power_spectrum_y`]). Exact for
/// a sinusoid of integer wavenumber; spectral leakage biases it up by a few per cent otherwise.
/// `None` as for [`wavelength_bins`].
pub fn mean_wavelength_bins(height: &[f64], bins: usize) -> Option<f64> {
    mean_wavelength(&power_spectrum_y(height, bins), bins)
}

/// Whether the spectrum has power along the wind: `sum_{k>=1} P(k)` above rounding, i.e. above
/// `1e-20` of the total including `P(0)` (a DFT of a constant column is zero only to rounding).
fn has_power_along_y(p: &[f64]) -> bool {
    if p.len() < 2 {
        return false;
    }
    let along: f64 = p[1..].iter().sum();
    along > 0.0 && along > 1e-20 * (along + p[0])
}

fn peak_wavelength(p: &[f64], bins: usize) -> Option<f64> {
    if !has_power_along_y(p) {
        return None;
    }
    let top = p.len() - 1;
    let w = (bins / 64).max(1);
    let window = |j: usize| (j.saturating_sub(w).max(1), (j + w).min(top));
    let mut best: Option<(usize, f64)> = None;
    for j in 1..=top {
        let (lo, hi) = window(j);
        let s = p[lo..=hi].iter().sum::<f64>() / (hi - lo + 1) as f64;
        if best.is_none_or(|(_, b)| s > b) {
            best = Some((j, s));
        }
    }
    let (j, _) = best?;
    let (lo, hi) = window(j);
    let (mut num, mut den) = (0.0, 0.0);
    for (k, &pk) in p.iter().enumerate().take(hi + 1).skip(lo) {
        num += k as f64 * pk;
        den += pk;
    }
    (den > 0.0).then(|| bins as f64 / (num / den))
}

fn mean_wavelength(p: &[f64], bins: usize) -> Option<f64> {
    if !has_power_along_y(p) {
        return None;
    }
    let (mut num, mut den) = (0.0, 0.0);
    for (k, &pk) in p.iter().enumerate().skip(1) {
        num += bins as f64 / k as f64 * pk;
        den += pk;
    }
    (den > 0.0).then(|| num / den)
}

/// The result of [`run`].
#[derive(Clone, Debug)]
pub struct WindRun {
    /// The parameters.
    pub params: WindParams,
    /// The final height field (`bins * bins`, layout of [`WindRipples::counts`]).
    pub height: Vec<f64>,
    /// Its statistics.
    pub stats: WindStats,
    /// Wall time of the steps (set-up excluded), seconds.
    pub elapsed_s: f64,
    /// Wall time of placing the particles, seconds.
    pub setup_s: f64,
}

/// Runs `params.steps` steps from a fresh start, calling `progress(steps_done)` after each step.
pub fn run<F: FnMut(u64)>(params: &WindParams, mut progress: F) -> Result<WindRun, WindError> {
    let t0 = Instant::now();
    let mut w = WindRipples::new(params.clone())?;
    let setup_s = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    for _ in 0..params.steps {
        w.step();
        progress(w.steps_done());
    }
    let elapsed_s = t1.elapsed().as_secs_f64();
    let height = w.height();
    let stats = height_stats(&height, params.bins);
    Ok(WindRun {
        params: params.clone(),
        height,
        stats,
        elapsed_s,
        setup_s,
    })
}

/// A `.npy` file (format version 1.0) holding `data` as a C-order float64 array of `shape`:
/// the magic string, a header dictionary padded with spaces to a multiple of 64 bytes, then the
/// little-endian values. `data.len()` must equal the product of `shape`.
pub fn npy_bytes(data: &[f64], shape: &[usize]) -> Vec<u8> {
    debug_assert_eq!(data.len(), shape.iter().product::<usize>());
    let dims = match shape {
        [d] => format!("({d},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {dims}, }}");
    // magic (6) + version (2) + header length (2) + header, ending in '\n', to a multiple of 64.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + 8 * data.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for v in data {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

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

/// Drawing the height field and the figures (feature `plot`).
#[cfg(feature = "plot")]
pub mod figures {
    use std::path::{Path, PathBuf};
    use std::time::Instant;

    use plotters::prelude::*;
    use plotters::style::text_anchor::{HPos, Pos, VPos};

    use super::{WindParams, WindRun, WindStats, power_spectrum_y, run};
    use crate::plot::FigureError;
    use crate::plot::{self, Chart, PlotError, Series};

    use crate::engine::VERSION;

    /// Steps of the `windripples_height` figure: a quarter of the notebook's 1024, so that
    /// `cellsurf figures` stays quick (`cellsurf wind-ripples --out` draws the full run).
    pub const FIGURE_STEPS: u64 = 256;
    /// Seeds of the `windripples_error_vs_time` figure.
    pub const ERROR_SEEDS: u64 = 8;
    /// Steps of each run of the `windripples_error_vs_time` figure.
    pub const ERROR_STEPS: u64 = 32;

    /// A one-line description of the parameters, for titles.
    pub fn describe(p: &WindParams) -> String {
        format!(
            "N={}, {}x{} bins, L={}, kappa={}, D={} {}, seed {}, cellsurf {VERSION}",
            p.particles, p.bins, p.bins, p.hop, p.kappa, p.diffusion, p.schedule, p.seed
        )
    }

    /// 256 colours of the viridis colormap (dark violet, blue, green, yellow), index 0 for
    /// height 0.
    fn lut() -> Vec<RGBColor> {
        (0..256)
            .map(|i| ViridisRGB::get_color_normalized(i as f64, 0.0, 255.0))
            .collect()
    }

    /// The colour index of height `h` on a scale `0..=vmax`.
    fn level(h: f64, vmax: f64) -> usize {
        if vmax > 0.0 {
            ((h / vmax).clamp(0.0, 1.0) * 255.0).round() as usize
        } else {
            0
        }
    }

    /// RGB8 pixels (row 0 at the top) of the `bins x bins` field `h` (layout `ix * bins + iy`)
    /// drawn as in the notebook's `imshow(height.T)`: `x` across, `y` (the wind) down, colour
    /// scale `0..=vmax`. `smooth`: bilinear interpolation between cell centres, periodic (the
    /// notebook draws with `interpolation='lanczos'`); otherwise each cell is a square.
    pub fn render(h: &[f64], bins: usize, px: u32, vmax: f64, smooth: bool) -> Vec<u8> {
        let lut = lut();
        let n = bins as f64;
        let px_us = px as usize;
        let mut out = vec![0u8; px_us * px_us * 3];
        let at = |ix: usize, iy: usize| h[(ix % bins) * bins + iy % bins];
        for row in 0..px_us {
            // Position in cell units, cell centres at integer + 0.5.
            let fy = (row as f64 + 0.5) / f64::from(px) * n;
            for col in 0..px_us {
                let fx = (col as f64 + 0.5) / f64::from(px) * n;
                let v = if smooth {
                    let (gx, gy) = (fx - 0.5 + n, fy - 0.5 + n);
                    let (x0, y0) = (gx.floor(), gy.floor());
                    let (tx, ty) = (gx - x0, gy - y0);
                    let (x0, y0) = (x0 as usize, y0 as usize);
                    let a = at(x0, y0) * (1.0 - tx) + at(x0 + 1, y0) * tx;
                    let b = at(x0, y0 + 1) * (1.0 - tx) + at(x0 + 1, y0 + 1) * tx;
                    a * (1.0 - ty) + b * ty
                } else {
                    at(fx as usize, fy as usize)
                };
                let c = lut[level(v, vmax)];
                let k = (row * px_us + col) * 3;
                out[k..k + 3].copy_from_slice(&[c.0, c.1, c.2]);
            }
        }
        out
    }

    /// Draws the height field of `r` into `path` (PNG): the whole field smoothed as in the
    /// notebook, a 64 x 64-bin corner cell by cell, a colour bar and the statistics.
    pub fn draw_height(path: &Path, r: &WindRun) -> Result<(), PlotError> {
        let p = &r.params;
        let bins = p.bins;
        let main_px: u32 = 768;
        let zoom_bins = bins.min(64);
        let zoom_px: u32 = 384;
        let (gap, title_h, label_h) = (16u32, 64u32, 28u32);
        let width = gap * 3 + main_px + zoom_px;
        let height = title_h + label_h + main_px + gap;
        let vmax = r.height.iter().cloned().fold(0.0, f64::max);
        plot::ensure_fonts();
        let mut buf = vec![255u8; width as usize * height as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
            root.fill(&WHITE).map_err(PlotError::drawing)?;
            let centre = Pos::new(HPos::Center, VPos::Center);
            let left = Pos::new(HPos::Left, VPos::Center);
            let t1 = ("sans-serif", 24.0, FontStyle::Bold)
                .into_font()
                .color(&BLACK)
                .pos(centre);
            let t2 = ("sans-serif", 16.0).into_font().color(&BLACK).pos(centre);
            let t3 = ("sans-serif", 16.0).into_font().color(&BLACK).pos(left);
            let draw = |s: String, at: (u32, u32), st: &TextStyle| {
                root.draw(&Text::new(s, (at.0 as i32, at.1 as i32), st.clone()))
                    .map_err(PlotError::drawing)
            };
            draw(
                format!(
                    "Wind ripples (the notebook's model): height after {} steps",
                    p.steps
                ),
                (width / 2, 20),
                &t1,
            )?;
            draw(describe(p), (width / 2, 48), &t2)?;
            let y0 = title_h + label_h;
            draw(
                "height field (bilinear, as the notebook's lanczos); x across, wind y down".into(),
                (gap + main_px / 2, title_h + label_h / 2),
                &t2,
            )?;
            let zx = 2 * gap + main_px;
            draw(
                format!("corner {zoom_bins} x {zoom_bins} bins, cell by cell"),
                (zx + zoom_px / 2, title_h + label_h / 2),
                &t2,
            )?;
            let field = render(&r.height, bins, main_px, vmax, true);
            let bm = BitMapElement::with_owned_buffer(
                (gap as i32, y0 as i32),
                (main_px, main_px),
                field,
            )
            .ok_or_else(|| PlotError::Drawing("height bitmap size mismatch".into()))?;
            root.draw(&bm).map_err(PlotError::drawing)?;
            // The corner: the first zoom_bins columns and rows.
            let mut corner = Vec::with_capacity(zoom_bins * zoom_bins);
            for ix in 0..zoom_bins {
                for iy in 0..zoom_bins {
                    corner.push(r.height[ix * bins + iy]);
                }
            }
            let zoom = render(&corner, zoom_bins, zoom_px, vmax, false);
            let bm =
                BitMapElement::with_owned_buffer((zx as i32, y0 as i32), (zoom_px, zoom_px), zoom)
                    .ok_or_else(|| PlotError::Drawing("zoom bitmap size mismatch".into()))?;
            root.draw(&bm).map_err(PlotError::drawing)?;
            // Colour bar under the corner.
            let cb_y = y0 + zoom_px + 40;
            let lut = lut();
            for i in 0..zoom_px {
                let c = lut[(i as usize * 255) / (zoom_px as usize - 1)];
                root.draw(&Rectangle::new(
                    [
                        (zx as i32 + i as i32, cb_y as i32),
                        (zx as i32 + i as i32 + 1, cb_y as i32 + 22),
                    ],
                    c.filled(),
                ))
                .map_err(PlotError::drawing)?;
            }
            for (frac, name) in [(0.0, "0"), (0.5, ""), (1.0, "")] {
                let x = zx + (frac * f64::from(zoom_px - 1)) as u32;
                let label = if name.is_empty() {
                    format!("{:.1}", frac * vmax)
                } else {
                    name.to_string()
                };
                draw(label, (x, cb_y + 36), &t2)?;
            }
            draw(
                "height (mean 1; scale 0 to the maximum, as the notebook)".into(),
                (zx + zoom_px / 2, cb_y - 12),
                &t2,
            )?;
            let s: &WindStats = &r.stats;
            let f = |v: Option<f64>| v.map_or("n/a".to_string(), |v| format!("{v:.2} bins"));
            let lines = [
                format!("height mean {:.6}, std {:.4}", s.height_mean, s.height_std),
                format!("dominant wavelength {}", f(s.wavelength_bins)),
                format!("mean wavelength {}", f(s.mean_wavelength_bins)),
                format!("hop L = {:.2} bins", p.hop * bins as f64),
            ];
            for (k, l) in lines.into_iter().enumerate() {
                draw(l, (zx, cb_y + 80 + 26 * k as u32), &t3)?;
            }
            root.present().map_err(PlotError::drawing)?;
        }
        let png = plot::encode_png(&buf, width, height)?;
        crate::engine::io::write_atomic(path, &png)?;
        Ok(())
    }

    /// Draws the spectrum `P(k)` of `r`'s height along the wind against the wavelength, with the
    /// two wavelength statistics marked.
    pub fn draw_spectrum(path: &Path, r: &WindRun) -> Result<(), PlotError> {
        let bins = r.params.bins;
        let p = power_spectrum_y(&r.height, bins);
        let total: f64 = p.iter().skip(1).sum();
        let lam: Vec<f64> = (1..p.len()).map(|k| bins as f64 / k as f64).collect();
        let rel: Vec<f64> = p
            .iter()
            .skip(1)
            .map(|v| v / total.max(f64::MIN_POSITIVE))
            .collect();
        let top = rel.iter().cloned().fold(0.0, f64::max);
        let mut series = vec![Series {
            label: "P(k) / sum P, k = 1..bins/2".into(),
            x: lam,
            y: rel,
            points: true,
        }];
        if let Some(w) = r.stats.wavelength_bins {
            series.push(Series {
                label: format!("dominant (smoothed peak) {w:.2} bins"),
                x: vec![w, w],
                y: vec![0.0, top],
                points: false,
            });
        }
        if let Some(w) = r.stats.mean_wavelength_bins {
            series.push(Series {
                label: format!("spectrum-weighted mean {w:.2} bins"),
                x: vec![w, w],
                y: vec![0.0, top],
                points: false,
            });
        }
        let chart = Chart {
            title: format!(
                "after {} steps; N={}, {} bins, seed {}",
                r.params.steps, r.params.particles, r.params.bins, r.params.seed
            ),
            x_label: "wavelength along the wind (bins)".into(),
            y_label: "share of the power".into(),
            series,
            log_x: true,
            log_y: false,
        };
        plot::line_charts(
            path,
            &format!("Wind ripples: height spectrum along the wind (cellsurf {VERSION})"),
            &[chart],
            1,
            (1000, 520),
        )
    }

    /// `windripples_height.png` (the notebook's figure, default parameters, [`FIGURE_STEPS`]
    /// steps) and `windripples_height_spectrum.png`.
    pub fn height_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
        let params = WindParams {
            steps: FIGURE_STEPS,
            ..WindParams::default()
        };
        let r = run(&params, |_| {}).map_err(|e| FigureError::Model(e.to_string()))?;
        // The run's parameters in the PNG files (`Figure::make` records only the name).
        plot::set_png_parameters(Some(params.describe_toml()));
        let p1 = dir.join("windripples_height.png");
        let p2 = dir.join("windripples_height_spectrum.png");
        let drawn = draw_height(&p1, &r).and_then(|()| draw_spectrum(&p2, &r));
        plot::set_png_parameters(None);
        drawn?;
        Ok(vec![p1, p2])
    }

    /// `windripples_error_vs_time.png`: [`ERROR_SEEDS`] runs (seeds 1, 2, ...) of
    /// [`ERROR_STEPS`] steps at the default parameters; after each, the standard error of the
    /// mean over the seeds so far of `height_std` and of both wavelengths, against the
    /// cumulative run time, with the `1/sqrt(time)` law through the sd of all the seeds.
    pub fn error_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
        let mut values: [Vec<f64>; 3] = Default::default();
        let mut time = 0.0;
        let mut xs = Vec::new();
        let mut se: [Vec<f64>; 3] = Default::default();
        let base = WindParams {
            steps: ERROR_STEPS,
            ..WindParams::default()
        };
        for k in 0..ERROR_SEEDS {
            let params = WindParams {
                seed: 1 + k,
                ..base.clone()
            };
            let t = Instant::now();
            let r = run(&params, |_| {}).map_err(|e| FigureError::Model(e.to_string()))?;
            time += t.elapsed().as_secs_f64();
            let s = r.stats;
            for (v, x) in values.iter_mut().zip([
                Some(s.height_std),
                s.wavelength_bins,
                s.mean_wavelength_bins,
            ]) {
                v.push(x.unwrap_or(f64::NAN));
            }
            if k >= 1 {
                xs.push(time);
                for (e, v) in se.iter_mut().zip(&values) {
                    e.push(crate::engine::stats::mean_and_se(v).1);
                }
            }
        }
        // sd / sqrt(seeds), with the sd of all the seeds: the 1/sqrt(time) law.
        let guide = |v: &[f64]| {
            let sd = crate::engine::stats::mean_and_se(v).1 * (v.len() as f64).sqrt();
            let per_seed = time / v.len() as f64;
            Series {
                label: "sd of all seeds / sqrt(seeds): 1/sqrt(time)".into(),
                x: xs.clone(),
                y: xs.iter().map(|t| sd * (per_seed / t).sqrt()).collect(),
                points: false,
            }
        };
        let [se_std, se_peak, se_mean] = se;
        let mean_of = |v: &[f64]| crate::engine::stats::mean_and_se(v).0;
        let charts = [
            Chart {
                title: format!("height_std = {:.4}", mean_of(&values[0])),
                x_label: "cumulative run time (s, wall, all threads)".into(),
                y_label: "standard error of the mean over seeds".into(),
                series: vec![
                    Series {
                        label: "height_std".into(),
                        x: xs.clone(),
                        y: se_std.clone(),
                        points: true,
                    },
                    guide(&values[0]),
                ],
                log_x: true,
                log_y: true,
            },
            Chart {
                title: format!(
                    "wavelengths: dominant {:.2}, mean {:.3} bins",
                    mean_of(&values[1]),
                    mean_of(&values[2])
                ),
                x_label: "cumulative run time (s, wall, all threads)".into(),
                y_label: "standard error of the mean over seeds (bins)".into(),
                series: vec![
                    Series {
                        label: "dominant (smoothed peak)".into(),
                        x: xs.clone(),
                        y: se_peak,
                        points: true,
                    },
                    Series {
                        label: "mean (spectrum-weighted)".into(),
                        x: xs.clone(),
                        y: se_mean.clone(),
                        points: true,
                    },
                    guide(&values[2]),
                ],
                log_x: true,
                log_y: true,
            },
        ];
        let path = dir.join("windripples_error_vs_time.png");
        plot::set_png_parameters(Some(format!(
            "{}seeds = \"1..={ERROR_SEEDS}\"\n",
            base.describe_toml()
        )));
        let drawn = plot::line_charts(
            &path,
            &format!(
                "Wind ripples: error against run time, seeds 1..{ERROR_SEEDS} of the {ERROR_STEPS}-step default run (cellsurf {VERSION})"
            ),
            &charts,
            2,
            (660, 460),
        );
        plot::set_png_parameters(None);
        drawn?;
        Ok(vec![path])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sigmoid_is_exact_at_zero_and_safe_at_the_extremes() {
        assert_eq!(sigmoid(0.0), 0.5);
        assert_eq!(sigmoid(-0.0), 0.5);
        assert_eq!(sigmoid(f64::INFINITY), 1.0);
        assert_eq!(sigmoid(f64::NEG_INFINITY), 0.0);
        // kappa = 1e6 on the largest possible height (all particles in one of 4096^2 cells).
        let z = -1e6 * (MAX_BINS * MAX_BINS) as f64;
        assert_eq!(sigmoid(z), 0.0);
        assert_eq!(sigmoid(-z), 1.0);
        for z in [-800.0, -745.2, -40.0, -1.0, 1e-300, 1.0, 40.0, 710.0, 800.0] {
            let s = sigmoid(z);
            assert!((0.0..=1.0).contains(&s), "{z}: {s}");
            // Symmetry s(z) + s(-z) = 1, to rounding.
            assert!((s + sigmoid(-z) - 1.0).abs() < 1e-15, "{z}");
        }
        // Agrees with the textbook formula where that does not overflow.
        for z in [-30.0, -4.5, -0.1, 0.3, 2.0, 30.0] {
            let naive = 1.0 / (1.0 + f64::exp(-z));
            assert!(
                (sigmoid(z) - naive).abs() <= 1e-15 * naive.max(1e-300),
                "{z}"
            );
        }
        // Tiny but representable tails are kept (not flushed to 0): e^-700.
        assert!(sigmoid(-700.0) > 0.0);
    }

    #[test]
    fn wrap_unit_lands_in_the_unit_interval_and_agrees_with_floor() {
        let cases = [
            0.0,
            0.5,
            1.0 - f64::EPSILON / 2.0,
            1.0,
            1.5,
            2.0,
            2.75,
            -0.25,
            -1.0,
            -1.5,
            -1e-17,
            -1e-300,
            -f64::MIN_POSITIVE,
            1e6 + 0.25,
            -1e6 - 0.25,
            1e300,
            -1e300,
            3.999_999_999_999_999_6,
        ];
        for v in cases {
            let w = wrap_unit(v);
            assert!((0.0..1.0).contains(&w), "{v} -> {w}");
            let floor_form = v - v.floor();
            if floor_form < 1.0 {
                assert_eq!(w.to_bits(), floor_form.to_bits(), "{v}");
            } else {
                // -1e-17 + 1 rounds to 1: the same point as 0 on the torus.
                assert_eq!(w, 0.0, "{v}");
            }
        }
        assert_eq!(wrap_unit(0.25), 0.25);
        assert_eq!(wrap_unit(1.25), 0.25);
        assert_eq!(wrap_unit(-0.75), 0.25);
        assert_eq!(wrap_unit(7.25), 0.25);
    }

    #[test]
    fn validate_names_the_parameter_its_value_and_the_range() {
        let ok = WindParams::default();
        assert_eq!(ok.validate(), Ok(()));
        let cases: Vec<(WindParams, &str)> = vec![
            (
                WindParams {
                    particles: 0,
                    ..ok.clone()
                },
                "particles",
            ),
            (
                WindParams {
                    particles: MAX_PARTICLES + 1,
                    ..ok.clone()
                },
                "particles",
            ),
            (
                WindParams {
                    bins: 0,
                    ..ok.clone()
                },
                "bins",
            ),
            (
                WindParams {
                    bins: MAX_BINS + 1,
                    ..ok.clone()
                },
                "bins",
            ),
            (
                WindParams {
                    steps: 0,
                    ..ok.clone()
                },
                "steps",
            ),
            (
                WindParams {
                    kappa: -1.0,
                    ..ok.clone()
                },
                "kappa",
            ),
            (
                WindParams {
                    kappa: f64::NAN,
                    ..ok.clone()
                },
                "kappa",
            ),
            (
                WindParams {
                    kappa: f64::INFINITY,
                    ..ok.clone()
                },
                "kappa",
            ),
            (
                WindParams {
                    hop: -0.1,
                    ..ok.clone()
                },
                "hop",
            ),
            (
                WindParams {
                    hop: f64::NAN,
                    ..ok.clone()
                },
                "hop",
            ),
            (
                WindParams {
                    hop: 2e6,
                    ..ok.clone()
                },
                "hop",
            ),
            (
                WindParams {
                    diffusion: -1e-9,
                    ..ok.clone()
                },
                "diffusion",
            ),
            (
                WindParams {
                    diffusion: f64::INFINITY,
                    ..ok.clone()
                },
                "diffusion",
            ),
        ];
        for (p, name) in cases {
            let e = p.validate().unwrap_err();
            let WindError::OutOfRange { name: got, .. } = &e;
            assert_eq!(*got, name);
            let msg = e.to_string();
            assert!(msg.starts_with(&format!("{name} = ")), "{msg}");
            assert!(msg.contains("out of range"), "{msg}");
            assert!(WindRipples::new(p).is_err());
        }
        // The edges of the ranges are accepted.
        for p in [
            WindParams {
                particles: 1,
                bins: 1,
                steps: 1,
                ..ok.clone()
            },
            WindParams {
                kappa: 0.0,
                hop: 0.0,
                diffusion: 0.0,
                ..ok.clone()
            },
            WindParams {
                kappa: 1e6,
                hop: 3.0,
                diffusion: 1.0,
                ..ok.clone()
            },
            WindParams {
                bins: MAX_BINS,
                ..ok.clone()
            },
        ] {
            assert_eq!(p.validate(), Ok(()), "{p:?}");
        }
    }

    #[test]
    fn schedules_parse_and_give_the_notebook_step_sizes() {
        assert_eq!("annealed".parse::<Schedule>(), Ok(Schedule::Annealed));
        assert_eq!("constant".parse::<Schedule>(), Ok(Schedule::Constant));
        assert!(
            "numpy"
                .parse::<Schedule>()
                .unwrap_err()
                .contains("annealed")
        );
        assert_eq!(Schedule::default(), Schedule::Annealed);
        assert_eq!(Schedule::Annealed.sigma(8e-4, 0), 8e-4);
        assert_eq!(Schedule::Annealed.sigma(8e-4, 3), 4e-4);
        assert_eq!(Schedule::Constant.sigma(8e-4, 1000), 8e-4);
        assert_eq!(Schedule::Constant.to_string(), "constant");
    }

    #[test]
    fn npy_bytes_have_a_valid_header_and_the_values() {
        let data: Vec<f64> = (0..6).map(|i| i as f64 * 0.5 - 1.0).collect();
        let b = npy_bytes(&data, &[3, 2]);
        assert_eq!(&b[..8], b"\x93NUMPY\x01\x00");
        let hl = u16::from_le_bytes([b[8], b[9]]) as usize;
        assert_eq!((10 + hl) % 64, 0);
        let header = std::str::from_utf8(&b[10..10 + hl]).unwrap();
        assert!(header.starts_with("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 2), }"));
        assert!(header.ends_with('\n'));
        assert_eq!(b.len(), 10 + hl + 48);
        for (k, v) in data.iter().enumerate() {
            let at = 10 + hl + 8 * k;
            assert_eq!(f64::from_le_bytes(b[at..at + 8].try_into().unwrap()), *v);
        }
        let b1 = npy_bytes(&[1.0; 5], &[5]);
        let hl = u16::from_le_bytes([b1[8], b1[9]]) as usize;
        assert!(
            std::str::from_utf8(&b1[10..10 + hl])
                .unwrap()
                .contains("'shape': (5,)")
        );
    }

    #[test]
    fn compensated_sum_is_exact_where_naive_summation_drifts() {
        let v = vec![0.1; 1_000_000];
        let naive: f64 = v.iter().sum();
        let good = compensated_sum(v.iter().copied());
        assert!((good - 100_000.0).abs() < 1e-9, "{good}");
        assert!((naive - 100_000.0).abs() > (good - 100_000.0).abs());
    }

    #[test]
    fn cell_of_stays_in_range_at_the_top_edge() {
        let top = 1.0 - f64::EPSILON / 2.0;
        for bins in [1u32, 3, 7, 256, 4095, 4096] {
            let fb = f64::from(bins);
            let c = cell_of(top, top, fb, bins);
            assert_eq!(c, (bins - 1) * bins + bins - 1, "bins {bins}");
            assert_eq!(cell_of(0.0, 0.0, fb, bins), 0);
        }
        // numpy's (x * bins).astype(int) on an interior point.
        assert_eq!(cell_of(0.5, 0.25, 256.0, 256), 128 * 256 + 64);
    }
}
