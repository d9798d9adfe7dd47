//! Kinetic roughening on a flat substrate: a lesson beyond the growth paper.
//!
//! The paper's rule `p = (b/z)^n` grown from a flat layer (shape `flat`, periodic in x) makes
//! a rough front; with `n = 0` every pick sticks and the process is the Eden model (M. Eden,
//! "A two-dimensional growth process", Proc. 4th Berkeley Symp. Math. Stat. Prob. 4, 223
//! (1961)). The interface width `w(L, t)` ([`observe::interface_width`]) grows as `t^beta`
//! and saturates at `w_sat ~ L^alpha` after a crossover time `~ L^(3/2)`; in 1+1 dimensions
//! the Kardar-Parisi-Zhang class has `beta = 1/3`, `alpha = 1/2` (M. Kardar, G. Parisi and
//! Y.-C. Zhang, "Dynamic scaling of growing interfaces", Phys. Rev. Lett. 56, 889 (1986)).
//!
//! - [`RoughnessRun`]: one flat-substrate configuration ([`RoughnessRun::scene`]) and its
//!   width curve ([`width_curve`]) at log-spaced times ([`log_times`]).
//! - The exponents: [`growth_exponent`] gives `beta` from the log-log slope of `w(t)` over a time window, mean and
//!   standard error over seeds; [`roughness_exponent`] gives `alpha` from the saturated widths
//!   of several lattice widths.
//!
//! Time is the paper's clock (picks); `t / L` is in monolayers.

use rayon::prelude::*;

use crate::engine::lattice::{Boundary, Neighbourhood};
use crate::engine::stats::{loglog_slope, mean_and_se};
use crate::growth::observe;
use crate::growth::sampler::SamplerKind;
use crate::growth::scene::{SceneConfig, SceneError, SceneKind, Shape, WeightKind};

/// One flat-substrate run: lattice, width, exponent, length in monolayers, seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughnessRun {
    /// Neighbourhood (the paper's is hexagonal).
    pub lattice: Neighbourhood,
    /// Substrate width `L`, columns (periodic).
    pub width: usize,
    /// Power-law exponent `n >= 0` (0: Eden).
    pub n: f64,
    /// Length of the run, monolayers (`L` timesteps each).
    pub monolayers: f64,
    /// Seed of the random stream.
    pub seed: u64,
}

impl RoughnessRun {
    /// The scene: a `grow` scene on a channel (periodic x, walls y) tall enough for the run
    /// (rows = monolayers + 40 + 10 %), a flat layer of thickness 1, the exact sampler.
    pub fn scene(&self) -> SceneConfig {
        let rows = (self.monolayers * 1.1) as usize + 40;
        let rows = rows + rows % 2;
        SceneConfig {
            scene: SceneKind::Grow,
            lattice: self.lattice,
            width: self.width,
            height: rows,
            boundary: Boundary::CHANNEL,
            n: self.n,
            weight: WeightKind::None,
            shape: Shape::Flat,
            start: 1.0,
            steps: ((self.monolayers * self.width as f64) as u64).max(1),
            events: None,
            until_occupied: None,
            snapshots: vec![],
            sampler: SamplerKind::Exact,
            ca_rule: vec![1],
            seed: self.seed,
            series: 1,
        }
    }
}

/// `points` times from `t0` to `t1` (timesteps), evenly spaced in `ln t`, rounded to whole
/// timesteps and deduplicated.
pub fn log_times(t0: f64, t1: f64, points: usize) -> Vec<f64> {
    let (a, b) = (t0.max(1.0).ln(), t1.max(1.0).ln());
    let k = points.max(2) - 1;
    let mut v: Vec<f64> = (0..=k)
        .map(|i| (a + (b - a) * i as f64 / k as f64).exp().round())
        .collect();
    v.dedup();
    v
}

/// The interface width at each of `times` (timesteps, increasing) of one run.
pub fn width_curve(run: &RoughnessRun, times: &[f64]) -> Result<Vec<f64>, SceneError> {
    let cfg = run.scene();
    let mut g = cfg.build()?;
    let mut rng = crate::engine::rng::stream(cfg.seed);
    Ok(times
        .iter()
        .map(|&t| {
            g.run_exact(&mut rng, t);
            observe::interface_width(&g)
        })
        .collect())
}

/// Mean width curves over `seeds` seeds (1, 2, ...) and the growth exponent fitted per seed
/// over the times in `[fit_from, fit_to]`: `(mean curve, beta mean, beta standard error,
/// per-seed betas)`. Seeds run in parallel.
pub fn growth_exponent(
    base: &RoughnessRun,
    times: &[f64],
    seeds: u64,
    fit_from: f64,
    fit_to: f64,
) -> Result<(Vec<f64>, f64, f64, Vec<f64>), SceneError> {
    let curves: Vec<Vec<f64>> = (1..=seeds)
        .into_par_iter()
        .map(|s| width_curve(&RoughnessRun { seed: s, ..*base }, times))
        .collect::<Result<_, _>>()?;
    let betas: Vec<f64> = curves
        .iter()
        .filter_map(|c| {
            let pts: Vec<(f64, f64)> = times
                .iter()
                .zip(c)
                .filter(|(t, _)| **t >= fit_from && **t <= fit_to)
                .map(|(&t, &w)| (t, w))
                .collect();
            loglog_slope(&pts).map(|(s, _)| s)
        })
        .collect();
    let mean: Vec<f64> = (0..times.len())
        .map(|i| curves.iter().map(|c| c[i]).sum::<f64>() / curves.len().max(1) as f64)
        .collect();
    let (b, se) = mean_and_se(&betas);
    Ok((mean, b, se, betas))
}

/// Saturated width of a substrate of `width` columns: the mean width over the last half (in
/// `ln t`) of a run of `monolayers`, averaged over `seeds` seeds: `(mean, standard error)`.
pub fn saturated_width(
    base: &RoughnessRun,
    width: usize,
    monolayers: f64,
    seeds: u64,
) -> Result<(f64, f64), SceneError> {
    let run = RoughnessRun {
        width,
        monolayers,
        ..*base
    };
    let t1 = monolayers * width as f64;
    let times = log_times(t1 / 4.0, t1, 12);
    let per_seed: Vec<f64> = (1..=seeds)
        .into_par_iter()
        .map(|s| {
            width_curve(&RoughnessRun { seed: s, ..run }, &times)
                .map(|c| c.iter().sum::<f64>() / c.len() as f64)
        })
        .collect::<Result<_, _>>()?;
    Ok(mean_and_se(&per_seed))
}

/// One saturated-width measurement: substrate width `L` (columns), mean saturated width and
/// its standard error over seeds (cell widths).
pub type SaturationPoint = (usize, f64, f64);

/// The roughness exponent: the log-log slope of saturated width against substrate width,
/// `(alpha, points (L, w_sat, se))`. Each width runs `saturation x L^(3/2)` monolayers.
pub fn roughness_exponent(
    base: &RoughnessRun,
    widths: &[usize],
    saturation: f64,
    seeds: u64,
) -> Result<(Option<f64>, Vec<SaturationPoint>), SceneError> {
    let pts: Vec<(usize, f64, f64)> = widths
        .iter()
        .map(|&l| {
            saturated_width(base, l, saturation * (l as f64).powf(1.5), seeds)
                .map(|(m, se)| (l, m, se))
        })
        .collect::<Result<_, _>>()?;
    let xy: Vec<(f64, f64)> = pts.iter().map(|&(l, w, _)| (l as f64, w)).collect();
    Ok((loglog_slope(&xy).map(|(s, _)| s), pts))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn width_grows_from_zero_and_runs_are_reproducible() {
        let run = RoughnessRun {
            lattice: Neighbourhood::Hex,
            width: 64,
            n: 0.0,
            monolayers: 50.0,
            seed: 3,
        };
        let times = log_times(64.0, 3200.0, 8);
        let a = width_curve(&run, &times).unwrap();
        let b = width_curve(&run, &times).unwrap();
        assert_eq!(a, b);
        assert!(a[0] > 0.0 && a[a.len() - 1] > 2.0 * a[0], "{a:?}");
    }

    #[test]
    fn log_times_are_increasing_and_span_the_range() {
        let t = log_times(10.0, 1e4, 20);
        assert_eq!(t[0], 10.0);
        assert_eq!(*t.last().unwrap(), 1e4);
        assert!(t.windows(2).all(|w| w[1] > w[0]));
    }
}
