//! Stop conditions of the growth scenes: `events` (accepted events) and `until_occupied` (an
//! occupied fraction) alongside `steps`, for every sampler; the log clock that lets stiff runs
//! (large n) go past the largest `f64`; the CLI's counts (`--steps 1e7`) and their errors.

mod common;

use cellsurf::engine::rng::stream;
use cellsurf::growth::sampler::{Outcome, SamplerKind, ln_rejected_picks, rejected_picks};
use cellsurf::growth::scene::{self, NoHooks, SceneConfig, SceneKind, StopReason};

fn flame(n: f64, sampler: SamplerKind) -> SceneConfig {
    let mut c = SceneConfig::defaults(SceneKind::Flame);
    c.width = 96;
    c.height = 110;
    c.start = 12.0;
    c.n = n;
    c.sampler = sampler;
    c.snapshots.clear();
    c.series = 5;
    c
}

#[test]
fn events_stop_after_exactly_that_many_acceptances() {
    for sampler in [SamplerKind::Exact, SamplerKind::Rejection] {
        let mut c = flame(2.0, sampler);
        c.steps = 1 << 40;
        c.events = Some(1234);
        let r = scene::run(&c, &mut NoHooks).unwrap();
        assert_eq!(r.last.accepted, 1234, "{sampler}");
        assert_eq!(r.stop, StopReason::Events);
        assert!(r.clock_exact && r.last.time.is_finite());
        assert_eq!(r.series.len(), 6, "the start and 5 points");
        assert!(r.series.windows(2).all(|w| w[1].accepted >= w[0].accepted));
    }
    // The CA adds whole rings: it stops at the first update that reaches the count.
    let mut c = SceneConfig::defaults(SceneKind::Ca);
    c.width = 41;
    c.height = 41;
    c.steps = 0;
    c.events = Some(100);
    c.snapshots.clear();
    let r = scene::run(&c, &mut NoHooks).unwrap();
    assert!(r.last.accepted >= 100 && r.stop == StopReason::Events);
    c.events = Some(r.last.accepted - 1);
    let fewer = scene::run(&c, &mut NoHooks).unwrap();
    assert_eq!(
        fewer.last.time, r.last.time,
        "the same update crosses both counts"
    );
}

#[test]
fn an_events_stop_and_a_clock_stop_at_its_time_agree() {
    // The run depends only on the configuration: stopping after N events at time T, or at
    // time T by the clock, gives the same state.
    let mut c = flame(3.0, SamplerKind::Exact);
    c.steps = 0;
    c.events = Some(2000);
    let by_events = scene::run(&c, &mut NoHooks).unwrap();
    let mut d = flame(3.0, SamplerKind::Exact);
    d.steps = by_events.last.time as u64;
    let by_clock = scene::run(&d, &mut NoHooks).unwrap();
    assert_eq!(by_clock.last.accepted, 2000);
    assert_eq!(by_clock.last.occupied, by_events.last.occupied);
    assert_eq!(by_clock.last.values, by_events.last.values);
}

#[test]
fn until_occupied_stops_at_the_first_event_that_reaches_the_fraction() {
    let mut c = flame(2.0, SamplerKind::Exact);
    c.steps = 0;
    c.until_occupied = Some(0.25);
    let r = scene::run(&c, &mut NoHooks).unwrap();
    let cells = c.width * c.height;
    assert_eq!(r.last.occupied, (0.25 * cells as f64).ceil() as usize);
    assert_eq!(r.stop, StopReason::Occupied);
    // With both, the first reached wins.
    c.events = Some(10);
    let r = scene::run(&c, &mut NoHooks).unwrap();
    assert_eq!((r.last.accepted, r.stop), (10, StopReason::Events));
    // A fraction already reached by the initial shape is refused, naming the parameter.
    c.events = None;
    c.until_occupied = Some(1e-4);
    let e = scene::run(&c, &mut NoHooks).unwrap_err().to_string();
    assert!(
        e.contains("until_occupied") && e.contains("initial occupied fraction"),
        "{e}"
    );
}

#[test]
fn the_ca_stops_after_the_update_that_reaches_the_count_and_a_full_lattice_says_so() {
    // The CA adds whole updates: --events 10 stops after the second (4 + 8 = 12 cells on the
    // hex torus from a point), named by the count; an event count reached by the update that
    // fills the lattice is named by the full lattice, with every sampler.
    let mut c = SceneConfig::defaults(SceneKind::Ca);
    c.steps = 0;
    c.events = Some(10);
    c.sampler = SamplerKind::Ca;
    let r = scene::run(&c, &mut NoHooks).unwrap();
    assert_eq!((r.last.accepted, r.stop), (12, StopReason::Events));
    use cellsurf::engine::lattice::Neighbourhood;
    for sampler in [SamplerKind::Ca, SamplerKind::Exact, SamplerKind::Rejection] {
        let mut c = SceneConfig::defaults(SceneKind::Grow);
        c.lattice = Neighbourhood::Square4;
        c.width = 4;
        c.height = 4;
        c.sampler = sampler;
        c.steps = if sampler == SamplerKind::Rejection {
            1_000_000
        } else {
            0
        };
        c.events = Some(15);
        let r = scene::run(&c, &mut NoHooks).unwrap();
        assert_eq!(r.last.occupied, 16, "{sampler:?}");
        assert_eq!(r.stop, StopReason::LatticeFull, "{sampler:?}");
    }
}

#[test]
fn until_occupied_stops_at_the_fraction_even_where_its_product_rounds_up() {
    // 0.07 x 100 = 7.000000000000001 and 0.28 x 10000 = 2800.0000000000005 in f64: the run
    // stops at 7 and 2800 cells (7 % and 28 %), not one cell later; 0.071 still asks for 8.
    use cellsurf::engine::lattice::Neighbourhood;
    for (size, f, want) in [
        (10, 0.07, 7),
        (10, 0.071, 8),
        (100, 0.28, 2800),
        (100, 0.56, 5600),
        (100, 0.81, 8100),
    ] {
        let mut c = SceneConfig::defaults(SceneKind::Grow);
        c.lattice = Neighbourhood::Square4;
        c.width = size;
        c.height = size;
        c.steps = 0;
        c.until_occupied = Some(f);
        let r = scene::run(&c, &mut NoHooks).unwrap();
        assert_eq!(
            (r.last.occupied, r.stop),
            (want, StopReason::Occupied),
            "{f}"
        );
    }
}

#[test]
fn stiff_runs_go_past_the_largest_f64_on_a_log_clock() {
    // n = 1e4: a pick on a site with b = 3 of 6 succeeds with probability 2^-10000, so the
    // waits are about 10^3010 picks; the clock leaves f64 but stays finite in log10.
    let mut c = flame(1e4, SamplerKind::Exact);
    c.steps = 0;
    c.events = Some(300);
    let r = scene::run(&c, &mut NoHooks).unwrap();
    assert_eq!(r.last.accepted, 300);
    assert_eq!(r.stop, StopReason::Events);
    assert!(r.last.time.is_infinite() && !r.clock_exact);
    assert!(
        r.log10_clock.is_finite() && r.log10_clock > 3000.0,
        "{}",
        r.log10_clock
    );
    // A bounded run reaches its bound first: every acceptance lies past 2^50 timesteps.
    let mut d = flame(1e4, SamplerKind::Exact);
    d.steps = 1 << 50;
    let r = scene::run(&d, &mut NoHooks).unwrap();
    assert_eq!(r.stop, StopReason::Completed);
    assert_eq!((r.last.accepted, r.last.time), (0, (1u64 << 50) as f64));
    // The same stream and events give the same log clock.
    let again = scene::run(&c, &mut NoHooks).unwrap();
    assert_eq!(
        again.log10_clock,
        scene::run(&c, &mut NoHooks).unwrap().log10_clock
    );
}

#[test]
fn ln_rejected_picks_is_the_log_of_the_count() {
    let mut rng = stream(4);
    use rand::RngExt;
    for ln_p in [-30.0, -100.0, -600.0] {
        for _ in 0..50 {
            let e: f64 = -(1.0 - rng.random::<f64>()).ln();
            let k = rejected_picks(ln_p, e);
            let lk = ln_rejected_picks(ln_p, e);
            // The count is rounded down: its log is within 1/k of the unrounded one.
            assert!(
                (k.ln() - lk).abs() < 1e-9 + 1.0 / k,
                "ln_p {ln_p}: {k} vs {lk}"
            );
        }
    }
    // Where the count leaves f64 its log is still finite.
    assert!(rejected_picks(-1e4, 1.0).is_infinite());
    assert!((ln_rejected_picks(-1e4, 1.0) - 1e4).abs() < 1e-6);
}

#[test]
fn step_exact_without_the_log_clock_still_reports_the_overflow() {
    let mut c = flame(1e4, SamplerKind::Exact);
    c.steps = 10;
    let mut g = c.build().unwrap();
    assert_eq!(
        g.run_exact(&mut stream(1), f64::INFINITY),
        Outcome::ClockOverflow
    );
}

#[test]
fn the_cli_takes_counts_in_scientific_notation_and_names_bad_ones() {
    let out = common::cellsurf(&["flame", "--steps", "2e3", "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["steps"], 2000.0);
    assert_eq!(v["clock_exact"], true);
    let out = common::cellsurf(&["flame", "--n", "1e4", "--events", "1e3", "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["accepted"], 1000);
    assert_eq!(v["stop_reason"], "events");
    assert_eq!(v["clock_exact"], false);
    assert!(v["log10_clock"].as_f64().unwrap() > 308.0);
    // Snapshots are timesteps too.
    let out = common::cellsurf(&[
        "grow",
        "--steps",
        "2e4",
        "--snapshots",
        "5e3,1e4,2e4",
        "--print-scenario",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("snapshots = [5000, 10000, 20000]"), "{text}");
    for (args, flag) in [
        (vec!["flame", "--steps", "1.5"], "--steps"),
        (vec!["flame", "--snapshots", "1e3,2.5e0"], "--snapshots"),
        (vec!["flame", "--events", "-1"], "--events"),
        (
            vec!["flame", "--until-occupied", "2"],
            "--until-occupied = 2",
        ),
        (
            vec!["flame", "--events", "10", "--sampler", "rejection"],
            "--steps",
        ),
    ] {
        let out = common::cellsurf(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert!(err.contains(flag), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}
