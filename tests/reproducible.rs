//! Reproducibility: a run is a function of its configuration and seed alone.
//!
//! - The same seed gives the same snapshots (byte for byte) and the same observation series,
//!   for every sampler; different seeds give different runs (the CA ignores the seed).
//! - Where a run pauses does not change it: advancing to the final limit through many
//!   intermediate limits gives exactly the state, clock and random stream of a single call
//!   (the exact sampler keeps its next acceptance time across a pause). The scene runner's
//!   extra checkpoints (animation frames) therefore do not change its results either.

use cellsurf::engine::lattice::{Boundary, Lattice, Neighbourhood};
use cellsurf::engine::rng::{Stream, stream};
use cellsurf::growth::Growth;
use cellsurf::growth::rule::{Sticking, Weight};
use cellsurf::growth::sampler::{Outcome, SamplerKind};
use cellsurf::growth::scene::{
    self, NoHooks, Observation, RunHooks, RunResult, SceneConfig, SceneKind,
};
use rand::RngExt;

/// A small flame: hexagonal 32 x 36 torus, square start of side 6, n = 2, 3000 timesteps.
fn small_flame(sampler: SamplerKind, seed: u64) -> SceneConfig {
    let mut cfg = SceneConfig::defaults(SceneKind::Flame);
    cfg.width = 32;
    cfg.height = 36;
    cfg.start = 6.0;
    cfg.steps = 3000;
    cfg.snapshots = vec![1, 300, 1500, 3000];
    cfg.series = 30;
    cfg.sampler = sampler;
    cfg.seed = seed;
    if sampler == SamplerKind::Ca {
        cfg.steps = 12;
        cfg.snapshots = vec![1, 6, 12];
        cfg.series = 12;
    }
    cfg
}

/// The bytes of everything a run produced that must be reproducible: snapshot times and
/// states, the observation series and the final observation, the stop reason.
fn run_bytes(r: &RunResult) -> Vec<u8> {
    let mut b = Vec::new();
    for s in &r.snapshots {
        b.extend(s.time.to_bits().to_le_bytes());
        b.extend(&s.states);
    }
    let mut obs = |o: &Observation| {
        b.extend(o.time.to_bits().to_le_bytes());
        b.extend(o.accepted.to_le_bytes());
        b.extend((o.occupied as u64).to_le_bytes());
        b.extend((o.surface as u64).to_le_bytes());
        let v = &o.values;
        for x in [
            v.front_radius_cv,
            v.axis_diagonal_ratio,
            v.mode1_amplitude,
            v.mean_elevation,
        ] {
            b.extend(x.map_or(u64::MAX, f64::to_bits).to_le_bytes());
        }
    };
    for o in &r.series {
        obs(o);
    }
    obs(&r.last);
    b.extend(format!("{:?}", r.stop).bytes());
    b
}

#[test]
fn same_seed_same_bytes_for_every_sampler() {
    for sampler in [SamplerKind::Exact, SamplerKind::Rejection, SamplerKind::Ca] {
        let cfg = small_flame(sampler, 11);
        let a = scene::run(&cfg, &mut NoHooks).unwrap();
        let b = scene::run(&cfg, &mut NoHooks).unwrap();
        assert_eq!(a.snapshots, b.snapshots, "{sampler}");
        assert_eq!(a.series, b.series, "{sampler}");
        assert_eq!(run_bytes(&a), run_bytes(&b), "{sampler}");
        // Not trivially equal: the run grew.
        assert!(a.last.accepted > 50, "{sampler}: {}", a.last.accepted);
    }
}

#[test]
fn eq5_weight_runs_are_reproducible_too() {
    for sampler in [SamplerKind::Exact, SamplerKind::Rejection] {
        let mut cfg = SceneConfig::defaults(SceneKind::Crystal);
        cfg.width = 32;
        cfg.height = 36;
        cfg.start = 6.0;
        cfg.steps = 3000;
        cfg.snapshots = vec![1000, 3000];
        cfg.series = 10;
        cfg.sampler = sampler;
        let a = scene::run(&cfg, &mut NoHooks).unwrap();
        let b = scene::run(&cfg, &mut NoHooks).unwrap();
        assert_eq!(run_bytes(&a), run_bytes(&b), "{sampler}");
    }
}

#[test]
fn different_seeds_give_different_runs() {
    for sampler in [SamplerKind::Exact, SamplerKind::Rejection] {
        let runs: Vec<Vec<u8>> = (1..=6)
            .map(|seed| {
                let r = scene::run(&small_flame(sampler, seed), &mut NoHooks).unwrap();
                r.snapshots.last().unwrap().states.clone()
            })
            .collect();
        for i in 0..runs.len() {
            for j in i + 1..runs.len() {
                assert_ne!(runs[i], runs[j], "{sampler}: seeds {} and {}", i + 1, j + 1);
            }
        }
    }
    // The CA is deterministic: the seed does not matter.
    let a = scene::run(&small_flame(SamplerKind::Ca, 1), &mut NoHooks).unwrap();
    let b = scene::run(&small_flame(SamplerKind::Ca, 2), &mut NoHooks).unwrap();
    assert_eq!(a.snapshots, b.snapshots);
}

/// A 32 x 32 hexagonal torus with a square of side 6 at its centre.
fn start(n: f64, weight: Weight, per_site: bool) -> Growth {
    let l = Lattice::new(Neighbourhood::Hex, 32, 32, Boundary::TORUS).unwrap();
    let (pw, ph) = l.physical_size();
    let (cx, cy) = (pw / 2.0, ph / 2.0);
    let mut g = Growth::new(l, Sticking::new(n, 6).unwrap(), weight, per_site).unwrap();
    g.occupy_where(|x, y| (x - cx).abs() < 3.0 && (y - cy).abs() < 3.0);
    g
}

/// Everything observable about a run's state, and the next number of its random stream (so
/// that the two runs also consumed the stream identically).
fn fingerprint(g: &Growth, rng: &mut Stream) -> (Vec<u8>, Vec<u32>, u64, u64, usize, u64) {
    (
        g.field_states(),
        g.surface().sites().to_vec(),
        g.time().to_bits(),
        g.accepted(),
        g.occupied(),
        rng.random(),
    )
}

fn advance(g: &mut Growth, rng: &mut Stream, exact: bool, limit: f64) -> Outcome {
    if exact {
        g.run_exact(rng, limit)
    } else {
        g.run_rejection(rng, limit)
    }
}

/// Runs to `last` in one call and through `limits` (increasing, ending at `last`), and
/// checks the two agree exactly; then runs both on to `last + 1000` and checks again (the
/// pending acceptance of a paused exact run must be the one the single call would make).
fn assert_pauses_change_nothing(make: &dyn Fn() -> Growth, exact: bool, limits: &[f64]) {
    let last = *limits.last().unwrap();
    let mut one = make();
    let mut rng_one = stream(2024);
    assert_eq!(advance(&mut one, &mut rng_one, exact, last), Outcome::Limit);
    let mut many = make();
    let mut rng_many = stream(2024);
    for &t in limits {
        assert_eq!(advance(&mut many, &mut rng_many, exact, t), Outcome::Limit);
        assert_eq!(many.time(), t);
    }
    assert!(one.accepted() > 100, "the run barely grew");
    // Compare on clones, so that drawing from the streams does not disturb the runs.
    assert_eq!(
        fingerprint(&one, &mut rng_one.clone()),
        fingerprint(&many, &mut rng_many.clone()),
        "exact = {exact}: paused run differs at {last}"
    );
    advance(&mut one, &mut rng_one, exact, last + 1000.0);
    advance(&mut many, &mut rng_many, exact, last + 1000.0);
    assert_eq!(
        fingerprint(&one, &mut rng_one),
        fingerprint(&many, &mut rng_many),
        "exact = {exact}: paused run differs after resuming"
    );
    many.check_invariants().unwrap();
}

#[test]
fn exact_sampler_pauses_change_nothing() {
    let make = || start(2.0, Weight::Isotropic, false);
    let hundreds: Vec<f64> = (1..=30).map(|k| 100.0 * k as f64).collect();
    assert_pauses_change_nothing(&make, true, &hundreds);
    // Every single timestep a pause: most calls end at their limit with an acceptance pending.
    let every: Vec<f64> = (1..=3000).map(|k| k as f64).collect();
    assert_pauses_change_nothing(&make, true, &every);
    // Irregular limits, some very close together.
    let irregular = [
        1.0, 2.0, 3.0, 7.0, 64.0, 65.0, 999.0, 1000.0, 1001.0, 2500.0, 3000.0,
    ];
    assert_pauses_change_nothing(&make, true, &irregular);
}

#[test]
fn exact_sampler_with_per_site_weights_pauses_change_nothing() {
    let make = || {
        let l = Lattice::new(Neighbourhood::Hex, 32, 32, Boundary::TORUS).unwrap();
        let (pw, ph) = l.physical_size();
        start(
            2.0,
            Weight::Axes {
                centre: (pw / 2.0, ph / 2.0),
            },
            true,
        )
    };
    let limits: Vec<f64> = (1..=60).map(|k| 50.0 * k as f64).collect();
    assert_pauses_change_nothing(&make, true, &limits);
}

#[test]
fn exact_sampler_pauses_at_large_n() {
    // n = 50: waits of 1e20 picks and more; pausing inside one of them must not redraw it.
    let make = || start(50.0, Weight::Isotropic, false);
    let mut g = make();
    let mut rng = stream(2024);
    let mut times = Vec::new();
    for _ in 0..150 {
        match g.step_exact(&mut rng, f64::MAX) {
            Outcome::Accepted(_) => times.push(g.time()),
            o => panic!("{o:?}"),
        }
    }
    // Pause at the midpoints between consecutive acceptances, then at the last acceptance.
    let mut limits: Vec<f64> = times
        .windows(2)
        .map(|w| w[0] + (w[1] - w[0]) / 2.0)
        .collect();
    limits.retain(|&t| t > 0.0);
    limits.dedup();
    limits.push(*times.last().unwrap());
    let mut one = make();
    let mut rng_one = stream(2024);
    one.run_exact(&mut rng_one, *limits.last().unwrap());
    let mut many = make();
    let mut rng_many = stream(2024);
    for &t in &limits {
        many.run_exact(&mut rng_many, t);
    }
    assert_eq!(one.accepted(), 150);
    assert_eq!(
        fingerprint(&one, &mut rng_one),
        fingerprint(&many, &mut rng_many)
    );
}

#[test]
fn rejection_sampler_pauses_change_nothing() {
    let make = || start(2.0, Weight::Isotropic, false);
    let hundreds: Vec<f64> = (1..=30).map(|k| 100.0 * k as f64).collect();
    assert_pauses_change_nothing(&make, false, &hundreds);
    let every: Vec<f64> = (1..=3000).map(|k| k as f64).collect();
    assert_pauses_change_nothing(&make, false, &every);
}

#[test]
fn step_by_step_equals_run() {
    // Calling step_* event by event is the same as run_* to the same limit.
    for exact in [true, false] {
        let mut a = start(2.0, Weight::Isotropic, false);
        let mut ra = stream(5);
        advance(&mut a, &mut ra, exact, 2000.0);
        let mut b = start(2.0, Weight::Isotropic, false);
        let mut rb = stream(5);
        loop {
            let o = if exact {
                b.step_exact(&mut rb, 2000.0)
            } else {
                b.step_rejection(&mut rb, 2000.0)
            };
            if o == Outcome::Limit {
                break;
            }
        }
        assert_eq!(fingerprint(&a, &mut ra), fingerprint(&b, &mut rb));
    }
}

/// Hooks that ask for a frame every 37 timesteps and record nothing.
struct ManyFrames;
impl RunHooks for ManyFrames {
    fn frame_times(&self) -> Vec<f64> {
        (1..=100).map(|k| 37.0 * k as f64).collect()
    }
}

#[test]
fn scene_results_do_not_depend_on_frames() {
    for sampler in [SamplerKind::Exact, SamplerKind::Rejection] {
        let cfg = small_flame(sampler, 7);
        let a = scene::run(&cfg, &mut NoHooks).unwrap();
        let b = scene::run(&cfg, &mut ManyFrames).unwrap();
        assert_eq!(run_bytes(&a), run_bytes(&b), "{sampler}");
    }
}
