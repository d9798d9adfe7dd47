//! Error against run time: how fast each sampler pins down a scene's observable.
//!
//! [`converge`] runs a scene for `1, 2, ..., m` independent seeds and records, after each
//! seed, the standard error of the observable's mean over the seeds so far against the
//! cumulative run time: a [`ConvergeCurve`]. Two samplers of the same process estimate the
//! same mean; the one whose curve lies lower reaches a given error sooner.

use serde::Serialize;

use crate::engine::stats::{ConvergePoint, error_curve};

use crate::growth::sampler::SamplerKind;
use crate::growth::scene::{self, NoHooks, Observables, SceneConfig, SceneError, SceneKind};

/// Standard error against run time for one scene, sampler and observable.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConvergeCurve {
    /// A label for the run, e.g. `flame n=2`.
    pub label: String,
    /// The scene.
    pub scene: SceneKind,
    /// The sampler.
    pub sampler: SamplerKind,
    /// The observable's name.
    pub observable: &'static str,
    /// Points for 2, 3, ..., m seeds.
    pub points: Vec<ConvergePoint>,
}

/// The observable a scene's claim rests on, with its name.
pub fn scene_observable(scene: SceneKind) -> (&'static str, fn(&Observables) -> Option<f64>) {
    match scene {
        SceneKind::Flame => ("front_radius_cv", |o| o.front_radius_cv),
        SceneKind::Deposit => ("mode1_amplitude", |o| o.mode1_amplitude),
        SceneKind::Crystal | SceneKind::Ca => ("axis_diagonal_ratio", |o| o.axis_diagonal_ratio),
        SceneKind::Grow => ("front_radius_cv", |o| o.front_radius_cv),
    }
}

/// Runs `cfg` with seeds `first_seed..first_seed + seeds` and returns the curve.
pub fn converge(
    label: &str,
    cfg: &SceneConfig,
    first_seed: u64,
    seeds: usize,
) -> Result<ConvergeCurve, SceneError> {
    let (name, get) = scene_observable(cfg.scene);
    let mut runs = Vec::with_capacity(seeds);
    for k in 0..seeds as u64 {
        let mut c = cfg.clone();
        c.seed = first_seed + k;
        c.snapshots.clear();
        c.series = 1;
        let r = scene::run(&c, &mut NoHooks)?;
        runs.push((
            get(&r.last.values).unwrap_or(f64::NAN),
            r.setup_s + r.elapsed_s,
        ));
    }
    let points = error_curve(&runs);
    Ok(ConvergeCurve {
        label: label.to_string(),
        scene: cfg.scene,
        sampler: cfg.sampler,
        observable: name,
        points,
    })
}

/// The growth study: the flame (n = 2 and the stiffer n = 8), the deposition and the crystal,
/// each with both stochastic samplers, `seeds` seeds each.
pub fn converge_growth(seeds: usize) -> Result<Vec<ConvergeCurve>, SceneError> {
    let mut out = Vec::new();
    let mut flame8 = SceneConfig::defaults(SceneKind::Flame);
    flame8.n = 8.0;
    let cases = [
        ("flame n=2", SceneConfig::defaults(SceneKind::Flame)),
        ("flame n=8", flame8),
        ("deposit n=2", SceneConfig::defaults(SceneKind::Deposit)),
        ("crystal n=2", SceneConfig::defaults(SceneKind::Crystal)),
    ];
    for (label, cfg) in cases {
        for sampler in [SamplerKind::Rejection, SamplerKind::Exact] {
            let mut c = cfg.clone();
            c.sampler = sampler;
            // Disjoint seed ranges per sampler: independent estimates.
            let first = if sampler == SamplerKind::Exact {
                1_000
            } else {
                1
            };
            out.push(converge(label, &c, first, seeds)?);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curve_has_a_point_per_seed_and_growing_time() {
        let mut c = SceneConfig::defaults(SceneKind::Flame);
        c.width = 40;
        c.height = 46;
        c.start = 8.0;
        c.steps = 2000;
        c.snapshots = vec![];
        let curve = converge("t", &c, 1, 5).unwrap();
        assert_eq!(curve.points.len(), 4);
        assert!(curve.points.windows(2).all(|w| w[1].cpu_s >= w[0].cpu_s));
        assert!(curve.points.iter().all(|p| p.std_error.is_finite()));
    }
}
