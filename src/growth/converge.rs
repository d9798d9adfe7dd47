//! Error against run time: how fast each sampler pins down a scene's observable.
//!
//! [`converge`] runs a scene for `1, 2, ..., m` independent seeds and records, after each
//! seed, the standard error of the observable's mean over the seeds so far against the
//! cumulative run time: a [`ConvergeCurve`]. Two samplers of the same process estimate the
//! same mean; the one whose curve lies lower reaches a given error sooner.
//!
//! The growth study splits over independent processes: its runs (case, sampler, seed) in a
//! fixed order are shared out by [`Part`] ([`growth_runs`]), each part records its
//! [`RunRecord`]s, and [`gather_growth`] builds the curves from all parts' records, the same
//! curves as one process (run times aside).

use serde::Serialize;

use crate::engine::part::Part;
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

/// One run of the growth study: its curve (index in [`growth_cases`]), seed number and result.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct RunRecord {
    /// The curve, an index into [`growth_cases`].
    pub curve: usize,
    /// The seed's place in the curve, `0 .. seeds`.
    pub k: usize,
    /// The observable (NaN when undefined).
    pub value: f64,
    /// Set-up and run time, s.
    pub seconds: f64,
}

/// The curves of the growth study: label, configuration and first seed.
pub fn growth_cases() -> Vec<(&'static str, SceneConfig, u64)> {
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
            out.push((label, c, first));
        }
    }
    out
}

/// Runs the share of `part` of the growth study's runs (every curve's `seeds` seeds, curve
/// by curve), in order.
pub fn growth_runs(seeds: usize, part: Part) -> Result<Vec<RunRecord>, SceneError> {
    let cases = growth_cases();
    let mut out = Vec::new();
    for r in part.range(cases.len() * seeds) {
        let (curve, k) = (r / seeds, r % seeds);
        let (_, cfg, first) = &cases[curve];
        let mut c = cfg.clone();
        c.seed = first + k as u64;
        c.snapshots.clear();
        c.series = 1;
        let (_, get) = scene_observable(c.scene);
        let res = scene::run(&c, &mut NoHooks)?;
        out.push(RunRecord {
            curve,
            k,
            value: get(&res.last.values).unwrap_or(f64::NAN),
            seconds: res.setup_s + res.elapsed_s,
        });
    }
    Ok(out)
}

/// The growth study's curves from the records of every run (from any number of parts, in any
/// order). Errors: a run missing or recorded twice.
pub fn gather_growth(seeds: usize, records: &[RunRecord]) -> Result<Vec<ConvergeCurve>, String> {
    let cases = growth_cases();
    let mut slots: Vec<Option<(f64, f64)>> = vec![None; cases.len() * seeds];
    for r in records {
        if r.curve >= cases.len() || r.k >= seeds {
            return Err(format!(
                "run (curve {}, seed {}) outside the study ({} curves of {seeds} seeds)",
                r.curve,
                r.k,
                cases.len()
            ));
        }
        let slot = &mut slots[r.curve * seeds + r.k];
        if slot.is_some() {
            return Err(format!(
                "run (curve {}, seed {}) recorded twice",
                r.curve, r.k
            ));
        }
        *slot = Some((r.value, r.seconds));
    }
    if let Some(i) = slots.iter().position(Option::is_none) {
        let missing = slots.iter().filter(|s| s.is_none()).count();
        return Err(format!(
            "{missing} of {} runs missing (the first: curve {}, seed {}): run the parts that own them",
            slots.len(),
            i / seeds,
            i % seeds
        ));
    }
    Ok(cases
        .iter()
        .enumerate()
        .map(|(c, (label, cfg, _))| {
            let runs: Vec<(f64, f64)> = slots[c * seeds..(c + 1) * seeds]
                .iter()
                .map(|s| s.unwrap_or((f64::NAN, 0.0)))
                .collect();
            ConvergeCurve {
                label: label.to_string(),
                scene: cfg.scene,
                sampler: cfg.sampler,
                observable: scene_observable(cfg.scene).0,
                points: error_curve(&runs),
            }
        })
        .collect())
}

/// The growth study: the flame (n = 2 and the stiffer n = 8), the deposition and the crystal,
/// each with both stochastic samplers, `seeds` seeds each.
pub fn converge_growth(seeds: usize) -> Result<Vec<ConvergeCurve>, SceneError> {
    let records = growth_runs(seeds, Part::WHOLE)?;
    // one process records every run once: the gathering cannot fail
    Ok(gather_growth(seeds, &records).unwrap_or_default())
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

    #[test]
    fn parts_gathered_give_the_curves_of_one_process() {
        // the records of 3 parts, gathered in any order, equal those of one process
        let seeds = 3;
        let n = growth_cases().len() * seeds;
        // timing aside: fake records with the one-process order, split as the parts split
        let all: Vec<RunRecord> = (0..n)
            .map(|r| RunRecord {
                curve: r / seeds,
                k: r % seeds,
                value: (r as f64).sin(),
                seconds: 1.0 + r as f64,
            })
            .collect();
        let one = gather_growth(seeds, &all).unwrap();
        let mut parts: Vec<RunRecord> = (0..3)
            .rev()
            .flat_map(|i| all[Part { index: i, count: 3 }.range(n)].to_vec())
            .collect();
        assert_eq!(gather_growth(seeds, &parts).unwrap(), one);
        assert_eq!(one.len(), 8);
        assert_eq!(one[0].points.len(), seeds - 1);
        parts.pop();
        assert!(
            gather_growth(seeds, &parts)
                .unwrap_err()
                .contains("1 of 24 runs missing")
        );
        parts.push(parts[0].clone());
        assert!(gather_growth(seeds, &parts).unwrap_err().contains("twice"));
    }
}
