//! Simulation-level tests: each published figure's scenario reproduces what the growth paper
//! says it shows. The tests use the same scenario files as `cellsurf figures`.

use cellsurf::growth::figures::scenario;
use cellsurf::growth::sampler::SamplerKind;
use cellsurf::growth::scene::{self, NoHooks, Observation, RunResult, SceneConfig};

fn run(cfg: &SceneConfig) -> RunResult {
    scene::run(cfg, &mut NoHooks).unwrap()
}

/// Mean and standard error of a value over `seeds` runs.
fn over_seeds(
    cfg: &SceneConfig,
    seeds: std::ops::Range<u64>,
    get: impl Fn(&Observation) -> f64,
) -> (f64, f64, f64, f64) {
    let mut first = Vec::new();
    let mut last = Vec::new();
    for s in seeds {
        let mut c = cfg.clone();
        c.seed = s;
        c.snapshots.clear();
        let r = run(&c);
        first.push(get(&r.series[0]));
        last.push(get(&r.last));
    }
    let stats = |v: &[f64]| {
        let m = v.iter().sum::<f64>() / v.len() as f64;
        let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64;
        (m, (var / v.len() as f64).sqrt())
    };
    let (m0, s0) = stats(&first);
    let (m1, s1) = stats(&last);
    (m0, s0, m1, s1)
}

#[test]
fn growth_fig3_ca_grows_a_diamond() {
    // Growth on all free edges from one cell: after t steps the L1 ball of radius t,
    // 2t^2 + 2t + 1 cells: 41 after 4 steps; its corners on the axes.
    let r = run(&scenario("growth_fig3_ca").unwrap());
    let counts: Vec<usize> = r
        .snapshots
        .iter()
        .map(|s| s.states.iter().filter(|&&v| v == 2).count())
        .collect();
    assert_eq!(counts, vec![5, 13, 25, 41]);
    let ratio = r.last.values.axis_diagonal_ratio.unwrap();
    // Measured on the surface sites of a radius-4 diamond: 1.27 (sqrt 2 in the large limit).
    assert!(ratio > 1.2, "diamond: axis/diagonal {ratio}");
}

#[test]
fn growth_fig4_ca_axes_grows_squares() {
    // Alternating b >= 1 and b >= 2: plus, 3x3 square, plus-extended square, 5x5 square.
    let r = run(&scenario("growth_fig4_ca_axes").unwrap());
    let counts: Vec<usize> = r
        .snapshots
        .iter()
        .map(|s| s.states.iter().filter(|&&v| v == 2).count())
        .collect();
    assert_eq!(counts, vec![5, 9, 21, 25]);
    let ratio = r.last.values.axis_diagonal_ratio.unwrap();
    // Surface sites of a 5x5 square: 0.85 (1/sqrt 2 in the large limit).
    assert!(ratio < 0.9, "axis-aligned square: axis/diagonal {ratio}");
}

#[test]
fn growth_fig5_flame_becomes_round() {
    // The square front (CV of radius over angle about 0.10) becomes round: the CV falls.
    // Tolerance: the drop must exceed 5 standard errors of the final mean.
    let cfg = scenario("growth_fig5_flame").unwrap();
    let (m0, _, m1, s1) = over_seeds(&cfg, 1..9, |o| o.values.front_radius_cv.unwrap());
    assert!((m0 - 0.1).abs() < 0.01, "initial square CV {m0}");
    assert!(m0 - m1 > 5.0 * s1, "CV {m0} -> {m1} +- {s1}");
    assert!(m1 < 0.07, "final CV {m1}");
}

#[test]
fn growth_fig6_deposit_fills_the_trough() {
    // The cosine's first mode (amplitude 12) decays to the noise floor; the surface rises.
    let cfg = scenario("growth_fig6_deposit").unwrap();
    let (a0, _, a1, s1) = over_seeds(&cfg, 1..7, |o| o.values.mode1_amplitude.unwrap());
    assert!((a0 - 12.0).abs() < 0.5, "initial amplitude {a0}");
    assert!(
        a1 < 0.25 * a0 && a1 + 3.0 * s1 < 0.3 * a0,
        "final amplitude {a1} +- {s1}"
    );
    let (e0, _, e1, _) = over_seeds(&cfg, 1..3, |o| o.values.mean_elevation.unwrap());
    assert!(e1 > e0 + 50.0, "mean elevation {e0} -> {e1}");
}

#[test]
fn growth_fig7_crystal_becomes_a_diamond() {
    // Eq. (5) makes growth fastest along the axes: the axis/diagonal extent ratio rises from
    // about 1 (disc) towards sqrt 2 (diamond).
    let cfg = scenario("growth_fig7_crystal").unwrap();
    let (r0, _, r1, s1) = over_seeds(&cfg, 1..5, |o| o.values.axis_diagonal_ratio.unwrap());
    assert!((r0 - 1.0).abs() < 0.05, "disc {r0}");
    assert!(
        r1 - 1.0 > 0.08 && r1 - 3.0 * s1 > 1.05,
        "final ratio {r1} +- {s1}"
    );
    // Without the weight the crystal stays round.
    let mut iso = cfg.clone();
    iso.weight = cellsurf::growth::scene::WeightKind::None;
    let (_, _, q1, t1) = over_seeds(&iso, 1..5, |o| o.values.axis_diagonal_ratio.unwrap());
    assert!(
        r1 - q1 > 5.0 * (s1 * s1 + t1 * t1).sqrt(),
        "weighted {r1} vs isotropic {q1}"
    );
}

#[test]
fn figure_scenarios_agree_between_samplers() {
    // Same process: the flame's accepted count at t = 50000 agrees between the samplers within
    // 4 standard errors of the difference.
    let cfg = scenario("growth_fig5_flame").unwrap();
    let mut means = Vec::new();
    for (sampler, seeds) in [
        (SamplerKind::Exact, 1..13),
        (SamplerKind::Rejection, 101..113),
    ] {
        let mut c = cfg.clone();
        c.sampler = sampler;
        let v: Vec<f64> = seeds
            .map(|s| {
                let mut c = c.clone();
                c.seed = s;
                c.snapshots.clear();
                c.series = 1;
                run(&c).last.accepted as f64
            })
            .collect();
        let m = v.iter().sum::<f64>() / v.len() as f64;
        let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64;
        means.push((m, var / v.len() as f64));
    }
    let d = (means[0].0 - means[1].0).abs();
    let se = (means[0].1 + means[1].1).sqrt();
    assert!(
        d < 4.0 * se,
        "exact {} vs rejection {}: diff {d}, se {se}",
        means[0].0,
        means[1].0
    );
}
