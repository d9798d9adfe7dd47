//! Checks of the walk against exact results: density error, its expected value, drift, and
//! the error-against-steps slope.
//!
//! - [`density_error`]: the relative RMS deviation of the visit density from uniform,
//!   `eps = sqrt( (1/n) sum_c (h_c n / N - 1)^2 )` for `N` steps on `n` cells.
//! - [`NoiseModel`]: for a uniform wind (calm included) the walk's increments are independent
//!   and identically distributed, so each Fourier mode `chi` of the height field has
//!   `E |sum_t chi(X_t)|^2 = 2 Re G - N` with `G = sum_{tau=0}^{N-1} (N - tau) phi^tau` and `phi` the
//!   characteristic function of one step at that mode, exactly, for any start. By Parseval,
//!   `E[eps^2] = (1/N^2) sum_{chi != 0} (2 Re G_chi - N)`, which for large `N` is
//!   `S / N` with `S = sum_{chi != 0} (1 + phi) / (1 - phi)` (real part): the error falls like
//!   `1/sqrt(N)`, with a prefactor fixed by the wind, `k` and the grid. The spread of `eps^2` over
//!   seeds follows from the same modes (Gaussian limit).
//! - [`mean_step`] and [`step_covariance`]: the drift per step `sum_i P_i d_i` (displacement
//!   `d_i`, diagonals of length `sqrt 2`) and its covariance; [`mean_direction`]: the mean unit
//!   vector `sum_i P_i u_i`. With the article's Eq. (2) these are `k W (1 + sqrt 2) / 880` and
//!   `k W / 440` (article units in, cells per step out).
//! - [`error_curve`] and [`loglog_slope`](crate::engine::stats::loglog_slope): the density error at increasing step counts and the
//!   least-squares slope of `ln eps` against `ln N` (-1/2 expected).

use serde::Serialize;

use super::walk::{CursorWalk, DIRECTIONS, Transitions, UNIT, probabilities};
use super::wind::Wind;

/// Relative RMS deviation of the visit density from uniform (see the module documentation);
/// `None` when the heights are empty or all 0.
pub fn density_error(heights: &[u64]) -> Option<f64> {
    let n = heights.len();
    let total: u64 = heights.iter().sum();
    if n == 0 || total == 0 {
        return None;
    }
    let mean = total as f64 / n as f64;
    let ss: f64 = heights
        .iter()
        .map(|&h| {
            let d = h as f64 / mean - 1.0;
            d * d
        })
        .sum();
    Some((ss / n as f64).sqrt())
}

/// Mean displacement per step, cells: `sum_i P_i d_i`.
pub fn mean_step(p: &[f64; 8]) -> (f64, f64) {
    let mut m = (0.0, 0.0);
    for (pi, &(dx, dy)) in p.iter().zip(DIRECTIONS.iter()) {
        m.0 += pi * f64::from(dx);
        m.1 += pi * f64::from(dy);
    }
    m
}

/// Mean unit direction per step: `sum_i P_i u_i`.
pub fn mean_direction(p: &[f64; 8]) -> (f64, f64) {
    let mut m = (0.0, 0.0);
    for (pi, &(ux, uy)) in p.iter().zip(UNIT.iter()) {
        m.0 += pi * ux;
        m.1 += pi * uy;
    }
    m
}

/// Covariance `[[xx, xy], [xy, yy]]` of one step's displacement, cells squared.
pub fn step_covariance(p: &[f64; 8]) -> [[f64; 2]; 2] {
    let (mx, my) = mean_step(p);
    let mut c = [[0.0; 2]; 2];
    for (pi, &(dx, dy)) in p.iter().zip(DIRECTIONS.iter()) {
        let (x, y) = (f64::from(dx) - mx, f64::from(dy) - my);
        c[0][0] += pi * x * x;
        c[0][1] += pi * x * y;
        c[1][1] += pi * y * y;
    }
    c[1][0] = c[0][1];
    c
}

/// The drift of Eq. (2) in closed form, cells per step: `k W (1 + sqrt 2) / 880` for a wind in
/// article units (the axis directions contribute `2 k W / s`, the diagonals `2 sqrt 2 k W / s`).
pub fn drift_formula(wind: Wind, k: f64) -> (f64, f64) {
    let f = k * (1.0 + std::f64::consts::SQRT_2) / 880.0;
    (wind.x * f, wind.y * f)
}

/// A complex number, for the Fourier modes.
#[derive(Clone, Copy, Debug)]
struct C(f64, f64);

impl C {
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn sub(self, o: C) -> C {
        C(self.0 - o.0, self.1 - o.1)
    }
    fn div(self, o: C) -> C {
        let d = o.0 * o.0 + o.1 * o.1;
        C(
            (self.0 * o.0 + self.1 * o.1) / d,
            (self.1 * o.0 - self.0 * o.1) / d,
        )
    }
    fn powu(self, n: u64) -> C {
        let r = self.0.hypot(self.1);
        if r == 0.0 {
            return C(0.0, 0.0);
        }
        let a = self.1.atan2(self.0) * n as f64;
        let m = (n as f64 * r.ln()).exp();
        C(m * a.cos(), m * a.sin())
    }
}

/// The exact expected squared density error of a walk in a uniform wind (see the module
/// documentation): the characteristic function of one step at every nonzero Fourier mode of
/// the torus.
#[derive(Clone, Debug)]
pub struct NoiseModel {
    phis: Vec<C>,
}

impl NoiseModel {
    /// The model for the step probabilities `p` (in the order of [`DIRECTIONS`]) on a
    /// `width x height` torus.
    pub fn new(p: &[f64; 8], width: usize, height: usize) -> NoiseModel {
        let mut phis = Vec::with_capacity(width * height);
        for b in 0..height {
            for a in 0..width {
                if a == 0 && b == 0 {
                    continue;
                }
                let mut phi = C(0.0, 0.0);
                for (pi, &(dx, dy)) in p.iter().zip(DIRECTIONS.iter()) {
                    let t = std::f64::consts::TAU
                        * (a as f64 * f64::from(dx) / width as f64
                            + b as f64 * f64::from(dy) / height as f64);
                    phi.0 += pi * t.cos();
                    phi.1 += pi * t.sin();
                }
                phis.push(phi);
            }
        }
        NoiseModel { phis }
    }

    /// The model of a uniform wind `wind` with force constant `k` (the real `P_i`).
    pub fn for_wind(wind: Wind, k: f64, width: usize, height: usize) -> NoiseModel {
        NoiseModel::new(&probabilities(wind, k), width, height)
    }

    /// The model of a translation-invariant [`Transitions`] (uniform wind, or `k = 0`), with
    /// the rounded `P_i` it walks with; `None` when the probabilities vary between cells.
    pub fn for_transitions(tr: &Transitions) -> Option<NoiseModel> {
        if !tr.is_translation_invariant() {
            return None;
        }
        Some(NoiseModel::new(
            &tr.cell_probabilities(0),
            tr.width(),
            tr.height(),
        ))
    }

    /// `E |sum_{t=1}^N chi(X_t)|^2` for each mode.
    fn mode_moments(&self, steps: u64) -> impl Iterator<Item = f64> + '_ {
        let n = steps as f64;
        self.phis.iter().map(move |&phi| {
            let g = if steps <= 256 {
                // Direct sum: G = sum_{tau=0}^{N-1} (N - tau) phi^tau.
                let mut g = C(0.0, 0.0);
                let mut pw = C(1.0, 0.0);
                for tau in 0..steps {
                    let w = (steps - tau) as f64;
                    g.0 += w * pw.0;
                    g.1 += w * pw.1;
                    pw = pw.mul(phi);
                }
                g
            } else {
                // G = (N - phi (1 - phi^N) / (1 - phi)) / (1 - phi).
                let one = C(1.0, 0.0);
                let om = one.sub(phi);
                let inner = phi.mul(one.sub(phi.powu(steps))).div(om);
                C(n, 0.0).sub(inner).div(om)
            };
            (2.0 * g.0 - n).max(0.0)
        })
    }

    /// `E[eps^2]` after `steps` steps (exact for independent increments).
    pub fn expected_sq_error(&self, steps: u64) -> f64 {
        if steps == 0 {
            return f64::NAN;
        }
        let n = steps as f64;
        self.mode_moments(steps).sum::<f64>() / (n * n)
    }

    /// `sqrt(E[eps^2])`: the density error expected from noise alone.
    pub fn expected_error(&self, steps: u64) -> f64 {
        self.expected_sq_error(steps).sqrt()
    }

    /// The large-`N` constant `S` of `E[eps^2] ~ S / N`.
    pub fn asymptotic_constant(&self) -> f64 {
        self.phis
            .iter()
            .map(|&phi| {
                let one = C(1.0, 0.0);
                C(1.0 + phi.0, phi.1).div(one.sub(phi)).0
            })
            .sum()
    }

    /// Standard deviation of `eps^2` over seeds relative to its mean, in the Gaussian limit
    /// (each mode's sum is asymptotically complex Gaussian: `Var = 2 sum m^2 / (sum m)^2`).
    pub fn relative_spread_sq_error(&self, steps: u64) -> f64 {
        let (mut s1, mut s2) = (0.0, 0.0);
        for m in self.mode_moments(steps) {
            s1 += m;
            s2 += m * m;
        }
        (2.0 * s2).sqrt() / s1
    }
}

/// One point of an error-against-steps curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ErrorPoint {
    /// Steps made.
    pub steps: u64,
    /// [`density_error`] after those steps.
    pub density_error: f64,
}

/// The density error of one walk (from the centre, stream `seed`) after each of `checkpoints`
/// steps (increasing; one walk, continued between checkpoints).
pub fn error_curve(tr: &Transitions, seed: u64, checkpoints: &[u64]) -> Vec<ErrorPoint> {
    let mut walk = CursorWalk::new(tr, seed);
    let mut out = Vec::with_capacity(checkpoints.len());
    for &c in checkpoints {
        if c > walk.steps() {
            walk.run(c - walk.steps());
        }
        out.push(ErrorPoint {
            steps: walk.steps(),
            density_error: density_error(walk.heights()).unwrap_or(f64::NAN),
        });
    }
    out
}

/// About `count` step counts spaced evenly in logarithm from `first` to `last` (both
/// included), rounded and deduplicated.
pub fn log_spaced(first: u64, last: u64, count: usize) -> Vec<u64> {
    let (a, b) = ((first.max(1) as f64).ln(), (last.max(1) as f64).ln());
    let mut v: Vec<u64> = (0..count.max(2))
        .map(|i| {
            (a + (b - a) * i as f64 / (count.max(2) - 1) as f64)
                .exp()
                .round() as u64
        })
        .collect();
    v.dedup();
    v
}
