//! The particle model: [`WindRipples`] (the particles and their height histogram), one step
//! of diffusion and saltation, and [`run`].

use std::time::Instant;

use crate::engine::rng::Stream;
use rand::RngExt;
use rand_distr::StandardNormal;
use rayon::prelude::*;

use super::params::{WindError, WindParams};
use super::stats::{WindStats, height_stats};

/// Particles per random stream (and per unit of parallel work).
pub const CHUNK: usize = 4096;
/// Counts below this have their hop precomputed (larger counts are computed on the fly, with
/// the same function, so the result is the same).
const HOP_TABLE_LEN: usize = 1024;
/// Steps between two sorts of the particles by cell ([`WindRipples::step`]).
pub const SORT_EVERY: u64 = 64;
/// Particles per batch of normals drawn ahead of the moves.
const BATCH: usize = 256;
/// Budget of `u32` histogram cells held at once by the parallel partial histograms.
const PARTIAL_CELLS_BUDGET: usize = 1 << 24;

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
    rngs: Vec<Stream>,
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
        if self.steps_done.is_multiple_of(SORT_EVERY) && self.steps_done > 0 {
            self.sort_by_cell();
        }
        let sigma = self.next_sigma();
        self.counts = self.pass(Some(sigma));
        self.pending = true;
        self.steps_done += 1;
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::windripples::params::{MAX_BINS, MAX_PARTICLES};

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
