//! Stiff and extreme cases (the users' "stiff and extreme cases"): very small and very large n,
//! the lattice filling up, a seed that touches itself across the torus, the smallest legal
//! lattices, direction weights that vanish on some sites, and invalid parameters. Nothing may
//! panic, hang or return NaN; the exact sampler's clock is finite or reported as overflowed.

use std::sync::Arc;

use cellsurf::engine::lattice::{Boundary, Lattice, Neighbourhood};
use cellsurf::engine::rng::stream;
use cellsurf::growth::Growth;
use cellsurf::growth::rule::{Sticking, Weight};
use cellsurf::growth::sampler::{Outcome, SamplerKind};
use cellsurf::growth::scene::{self, NoHooks, SceneConfig, SceneKind, Shape, StopReason};

/// `ln(1e300)`: a class whose weight relative to the top class is below `1e-300` has
/// `n ln(top / b)` above this.
const LN_1E300: f64 = 690.775_527_898_213_7;

fn hex_torus(w: usize, h: usize) -> Lattice {
    Lattice::new(Neighbourhood::Hex, w, h, Boundary::TORUS).unwrap()
}

fn growth(l: Lattice, n: f64) -> Growth {
    let z = l.z();
    Growth::new(l, Sticking::new(n, z).unwrap(), Weight::Isotropic, false).unwrap()
}

/// A 24 x 24 hexagonal torus with a square of side 6 occupied at its centre.
fn square_start(n: f64) -> Growth {
    let l = hex_torus(24, 24);
    let (pw, ph) = l.physical_size();
    let (cx, cy) = (pw / 2.0, ph / 2.0);
    let mut g = growth(l, n);
    g.occupy_where(|x, y| (x - cx).abs() < 3.0 && (y - cy).abs() < 3.0);
    g
}

/// A 24 x 24 hexagonal torus whose rows 0..16 are filled at random with density 3/4 (a fixed
/// pseudo-random pattern), rows 16..24 empty: holes with every b from 1 to 6, so that large n
/// has classes to choose between and finite waits (holes with b = 6 have p = 1).
fn porous_start(n: f64) -> Growth {
    let l = hex_torus(24, 24);
    let mut g = growth(l, n);
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    for c in 0..16 * 24 {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        if !x.is_multiple_of(4) {
            g.occupy(c).unwrap();
        }
    }
    g
}

/// Occupied neighbours of `cell`, counted from scratch.
fn count_b(g: &Growth, cell: usize) -> usize {
    g.lattice()
        .neighbours(cell)
        .filter(|&m| g.is_occupied(m))
        .count()
}

/// The largest b over the surface sites.
fn top_class(g: &Growth) -> usize {
    g.surface()
        .sites()
        .iter()
        .map(|&c| g.occupied_neighbours(c as usize).unwrap())
        .max()
        .unwrap_or(0)
}

/// Every cell's stored neighbour count agrees with a recount, and the library's own check.
fn assert_consistent(g: &Growth) {
    g.check_invariants().unwrap();
    let mut surface = 0;
    for c in 0..g.lattice().len() {
        if let Some(b) = g.occupied_neighbours(c) {
            assert_eq!(b, count_b(g, c), "cell {c}");
            surface += (b >= 1) as usize;
        }
    }
    assert_eq!(surface, g.surface().len());
}

/// Steps the exact sampler (limit `f64::MAX`) for up to `events` acceptances, checking after
/// each call: the clock is never NaN and never goes back; it never overflows (an acceptance
/// past the largest `f64` lies after the limit: the run stops there, with `Limit`); the
/// accepted site's class is not negligible next to the top class (`(b / top)^n >= 1e-300`).
/// Returns the accepted `(b, top)` pairs and the last outcome.
fn exact_events(g: &mut Growth, seed: u64, events: usize) -> (Vec<(usize, usize)>, Outcome) {
    let mut rng = stream(seed);
    let n = g.rule().n();
    let mut seen = Vec::new();
    let mut last = Outcome::Limit;
    for k in 0..events {
        let top = top_class(g);
        let before = g.time();
        let o = g.step_exact(&mut rng, f64::MAX);
        let t = g.time();
        assert!(!t.is_nan(), "n = {n}: clock is NaN after {o:?}");
        assert!(t >= before, "n = {n}: clock went back from {before} to {t}");
        assert!(t.is_finite(), "n = {n}: clock {t} with outcome {o:?}");
        last = o;
        match o {
            Outcome::Accepted(c) => {
                assert!(g.is_occupied(c));
                // Occupying c does not change its neighbours' occupancy: this is c's b just
                // before it was accepted.
                let b = count_b(g, c);
                assert!(b >= 1 && b <= top, "b = {b}, top = {top}");
                assert!(
                    n * (top as f64 / b as f64).ln() <= LN_1E300,
                    "n = {n}: accepted b = {b} although the top class is {top}"
                );
                seen.push((b, top));
            }
            Outcome::Exhausted => {
                assert!(g.surface().is_empty());
                assert_eq!(g.occupied(), g.lattice().len());
                break;
            }
            Outcome::Limit => {
                assert_eq!(t, f64::MAX, "n = {n}");
                break;
            }
            o => panic!("n = {n}: unexpected {o:?}"),
        }
        if k % 200 == 0 {
            g.check_invariants().unwrap();
        }
    }
    assert_consistent(g);
    (seen, last)
}

#[test]
fn exact_sampler_is_sound_at_every_n() {
    for n in [0.0, 1e-9, 2.0, 50.0, 1000.0, 1e4] {
        for (name, start) in [
            ("square", square_start as fn(f64) -> Growth),
            ("porous", porous_start),
        ] {
            let mut g = start(n);
            let (seen, last) = exact_events(&mut g, 17, 1500);
            eprintln!(
                "n = {n}, {name}: {} events, last {last:?}, clock {}",
                seen.len(),
                g.time()
            );
            if n == 0.0 {
                // Every pick is accepted: one timestep per event.
                assert_eq!(g.time(), g.accepted() as f64);
            }
            if n <= 50.0 {
                // (1/6)^50 = 1e-39: the wait stays far below f64::MAX; the limit is never
                // reached.
                assert_ne!(last, Outcome::Limit, "n = {n}, {name}");
                assert!(g.time() < 1e100);
            }
        }
    }
}

#[test]
fn n_1e4_accepts_only_the_maximal_class() {
    // n = 1e4: (5/6)^n = e^-1823 underflows f64, so the classes differ by far more than
    // 1e-300 and only b = top may be accepted. From the porous start the top class is 6
    // (p = 1, finite waits) until every fully enclosed hole is filled (filling one can raise a
    // neighbour to b = 6); then the next wait is about e^1823 picks, past the largest f64:
    // the run reaches its limit of f64::MAX timesteps.
    let mut g = porous_start(1e4);
    let initial_full = g
        .surface()
        .sites()
        .iter()
        .filter(|&&c| g.occupied_neighbours(c as usize) == Some(6))
        .count();
    assert!(initial_full >= 10, "the fixture has {initial_full} holes");
    let (seen, last) = exact_events(&mut g, 3, 5000);
    assert!(seen.len() >= initial_full);
    for &(b, top) in &seen {
        assert_eq!(b, top);
        assert_eq!(b, 6);
    }
    assert_eq!(last, Outcome::Limit);
    assert_eq!(g.time(), f64::MAX);
    assert!(top_class(&g) < 6);
    // Nothing more is accepted before that limit.
    let occ = g.occupied();
    let o = g.step_exact(&mut stream(4), f64::MAX);
    assert!(!matches!(o, Outcome::Accepted(_)), "{o:?}");
    assert_eq!(g.occupied(), occ);
    assert_consistent(&g);
}

#[test]
fn n_1000_picks_the_top_classes_and_keeps_a_finite_clock_while_it_can() {
    // n = 1000: (5/6)^n = 1e-79 and (4/6)^n = 1e-176 are representable relative weights, but
    // (3/6)^n = 1e-301 relative to b = 6 is not; the clock uses log weights and stays finite
    // while the top class has (top/6)^n above about 1e-300.
    let mut g = porous_start(1000.0);
    let (seen, _last) = exact_events(&mut g, 5, 3000);
    assert!(seen.len() > 20);
    // Classes below the top were accepted too (where the top was 5 or 4), never class 1 or 2
    // next to a top of 6.
    assert!(seen.iter().any(|&(b, _)| b == 5));
    assert!(seen.iter().all(|&(b, top)| !(top == 6 && b <= 2)));
}

#[test]
fn a_wait_past_the_largest_f64_reaches_every_finite_limit() {
    // Square start on the hexagonal lattice at n = 1e4: the top class has b <= 3, and
    // p = (1/2)^1e4 = e^-6931 at best: the first acceptance lies past the largest f64, so
    // after every finite limit. The run reaches its limit with nothing accepted, as the
    // rejection sampler does (below); only a run without a limit reports the overflow.
    let mut g = square_start(1e4);
    let occ = g.occupied();
    let o = g.step_exact(&mut stream(1), f64::MAX);
    assert_eq!(o, Outcome::Limit);
    assert_eq!(g.time(), f64::MAX);
    assert_eq!(g.accepted(), 0);
    assert_eq!(g.occupied(), occ);
    assert_consistent(&g);
    // Continued: still nothing before the limit; then without one, the overflow.
    assert_eq!(g.step_exact(&mut stream(1), f64::MAX), Outcome::Limit);
    assert_eq!(
        g.step_exact(&mut stream(1), f64::INFINITY),
        Outcome::ClockOverflow
    );
    assert_eq!(g.time(), f64::INFINITY);
    // Once overflowed, nothing more is accepted.
    assert!(!matches!(
        g.step_exact(&mut stream(1), f64::MAX),
        Outcome::Accepted(_)
    ));
    assert_eq!(g.occupied(), occ);
    assert_consistent(&g);
    // n = 1000: sites with b = 3 give waits of about 2^1000 = 1e301 picks (finite); once
    // only b <= 2 is left, (1/3)^1000 = e^-1099 overflows. run_exact accepts while the
    // waits are finite, then stops at its limit, never looping or returning NaN.
    let mut g = square_start(1000.0);
    assert_eq!(g.run_exact(&mut stream(2), f64::MAX), Outcome::Limit);
    assert_eq!(g.time(), f64::MAX);
    assert!(g.accepted() > 0);
    assert_consistent(&g);
    // A wait beyond the limit is a pause, finite or not.
    for n in [1e4, 1000.0] {
        let mut g = square_start(n);
        assert_eq!(g.run_exact(&mut stream(3), 1e12), Outcome::Limit, "n = {n}");
        assert_eq!(g.time(), 1e12);
    }
    // The rejection sampler cannot overflow: p underflows to 0 in f64 and it simply runs to
    // the limit without acceptance (and without hanging).
    for n in [1000.0, 1e4] {
        let mut g = square_start(n);
        assert_eq!(g.run_rejection(&mut stream(3), 20_000.0), Outcome::Limit);
        assert_eq!(g.time(), 20_000.0);
        assert_eq!(g.accepted(), 0, "n = {n}");
    }
}

#[test]
fn a_pause_before_a_wait_past_the_largest_f64_changes_nothing() {
    // With the log clock allowed, an unbounded run goes on past the largest f64. A run first
    // paused at finite limits (where that acceptance comes after them) and then continued
    // without one accepts the same cells at the same log clock as a run that never paused.
    let mut once = square_start(1e4);
    once.allow_log_clock(true);
    let mut r1 = stream(5);
    assert_eq!(
        once.run_exact_until(&mut r1, f64::INFINITY, 3),
        Outcome::Limit
    );
    assert_eq!(once.accepted(), 3);
    let mut paused = square_start(1e4);
    paused.allow_log_clock(true);
    let mut r2 = stream(5);
    assert_eq!(paused.run_exact(&mut r2, 1e300), Outcome::Limit);
    assert_eq!(paused.run_exact(&mut r2, f64::MAX), Outcome::Limit);
    assert_eq!(paused.accepted(), 0);
    assert_eq!(
        paused.run_exact_until(&mut r2, f64::INFINITY, 3),
        Outcome::Limit
    );
    assert_eq!(paused.log10_time(), once.log10_time());
    assert!(once.log10_time() > 3000.0, "{}", once.log10_time());
    for c in 0..once.lattice().len() {
        assert_eq!(once.is_occupied(c), paused.is_occupied(c), "cell {c}");
    }
}

#[test]
fn clock_overflow_is_reported_with_an_infinite_limit() {
    // Same as above with limit = f64::INFINITY ("run for ever"): the next acceptance lies
    // beyond the largest f64, so the clock is +inf and ClockOverflow must be reported; the
    // sampler must not accept a cell "at infinity" and report Accepted.
    let mut g = square_start(1e4);
    let o = g.step_exact(&mut stream(1), f64::INFINITY);
    assert_eq!(o, Outcome::ClockOverflow, "clock {}", g.time());
    assert_eq!(g.accepted(), 0);
    let mut g = square_start(1e4);
    assert_eq!(
        g.run_exact(&mut stream(1), f64::INFINITY),
        Outcome::ClockOverflow
    );
}

#[test]
fn n_1e9_behaves_like_n_0() {
    // n = 1e-9: p = (b/6)^1e-9 >= 1 - 1.8e-9, so a pick is rejected with probability below
    // 2e-9. Over 200 runs of T = 400 picks the chance of a single rejection is below 2e-4:
    // every run adds exactly T cells, as at n = 0. The shapes (surface sizes) must have one
    // law: means within 4 standard errors of the difference (see samplers_agree.rs).
    let t = 400.0;
    let mut surf = [Vec::new(), Vec::new()];
    for (k, n) in [0.0, 1e-9].into_iter().enumerate() {
        for s in 0..200u64 {
            let mut g = square_start(n);
            let occ = g.occupied();
            let seed = 1000 * k as u64 + s;
            assert_eq!(g.run_exact(&mut stream(seed), t), Outcome::Limit);
            assert_eq!(g.occupied(), occ + 400, "n = {n}, seed {seed}");
            assert_eq!(g.time(), t);
            surf[k].push(g.surface().len() as f64);
        }
    }
    let stats = |v: &[f64]| {
        let m = v.len() as f64;
        let mean = v.iter().sum::<f64>() / m;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (m - 1.0);
        (mean, var / m)
    };
    let ((ma, sa), (mb, sb)) = (stats(&surf[0]), stats(&surf[1]));
    assert!(
        (ma - mb).abs() < 4.0 * (sa + sb).sqrt(),
        "surface at n = 0: {ma}, at n = 1e-9: {mb}"
    );
    // The rejection sampler at n = 1e-9 also accepts every pick (over these 50 seeds).
    for s in 0..50u64 {
        let mut g = square_start(1e-9);
        let occ = g.occupied();
        g.run_rejection(&mut stream(5000 + s), t);
        assert_eq!(g.occupied(), occ + 400);
    }
}

#[test]
fn rejection_sampler_at_large_n_accepts_only_full_holes_and_terminates() {
    // At n = 1e4 the paper's algorithm can only accept b = 6 sites (p = 1; every other p is 0
    // in f64, truly below 1e-790); it must run to its limit without hanging.
    let mut g = porous_start(1e4);
    let mut rng = stream(8);
    loop {
        match g.step_rejection(&mut rng, 200_000.0) {
            Outcome::Accepted(c) => assert_eq!(count_b(&g, c), 6),
            Outcome::Limit => break,
            o => panic!("{o:?}"),
        }
    }
    assert_eq!(g.time(), 200_000.0);
    assert!(g.accepted() > 0);
    assert_consistent(&g);
}

#[test]
fn lattice_fills_up_and_samplers_stop_cleanly() {
    for n in [0.0, 2.0, 50.0] {
        for sampler in [SamplerKind::Exact, SamplerKind::Rejection] {
            if sampler == SamplerKind::Rejection && n > 2.0 {
                continue; // (1/6)^50 per pick: the paper's algorithm would take ~1e39 picks.
            }
            let mut g = growth(hex_torus(6, 6), n);
            g.occupy(14).unwrap();
            let mut rng = stream(9);
            let o = match sampler {
                SamplerKind::Exact => g.run_exact(&mut rng, f64::MAX),
                _ => g.run_rejection(&mut rng, 1e9),
            };
            assert_eq!(
                o,
                Outcome::Exhausted,
                "{sampler:?}, n = {n}, clock {}, occupied {}",
                g.time(),
                g.occupied()
            );
            assert_eq!(g.occupied(), 36);
            assert_eq!(g.accepted(), 35);
            assert!(g.surface().is_empty());
            assert!(g.time().is_finite() && g.time() >= 35.0);
            assert_consistent(&g);
            // Asking again is harmless and says the same.
            let t = g.time();
            assert_eq!(g.step_exact(&mut rng, f64::MAX), Outcome::Exhausted);
            assert_eq!(g.step_rejection(&mut rng, f64::MAX), Outcome::Exhausted);
            assert_eq!(g.time(), t);
        }
    }
}

#[test]
fn scene_on_a_tiny_lattice_reports_lattice_full() {
    for sampler in [SamplerKind::Exact, SamplerKind::Rejection, SamplerKind::Ca] {
        let mut cfg = SceneConfig::defaults(SceneKind::Grow);
        cfg.width = 6;
        cfg.height = 6;
        cfg.boundary = Boundary::TORUS;
        cfg.lattice = Neighbourhood::Hex;
        cfg.shape = Shape::Point;
        cfg.sampler = sampler;
        cfg.steps = 100_000;
        cfg.snapshots = vec![5, 100_000];
        cfg.series = 10;
        let r = scene::run(&cfg, &mut NoHooks).unwrap();
        assert_eq!(r.stop, StopReason::LatticeFull, "{sampler:?}");
        assert_eq!(r.last.occupied, 36);
        assert_eq!(r.last.surface, 0);
        // A panel per requested time before the lattice filled, then the final state once
        // in place of the times it did not reach (all of them for the CA, full at t = 3).
        let last = r.snapshots.last().unwrap();
        assert!(last.states.iter().all(|&s| s == 2));
        assert_eq!(last.time, r.last.time);
        let before = cfg.snapshots.iter().filter(|&&t| (t as f64) < r.last.time);
        assert_eq!(r.snapshots.len(), before.count() + 1, "{sampler:?}");
        let after: Vec<u64> = cfg
            .snapshots
            .iter()
            .copied()
            .filter(|&t| t as f64 > r.last.time)
            .collect();
        assert_eq!(last.unreached, after);
        assert!(r.snapshots.iter().all(|s| s.time.is_finite()));
        assert!(r.series.iter().all(|o| o.time.is_finite()));
    }
}

#[test]
fn seed_touching_itself_across_the_torus() {
    // A band that spans the whole width of the torus (square start as wide as the lattice):
    // the band touches itself across the x seam. Every surface cell has the same b, the
    // surface is two full rows, and the counts agree with a recount.
    let mut cfg = SceneConfig::defaults(SceneKind::Grow);
    cfg.lattice = Neighbourhood::Square4;
    cfg.width = 10;
    cfg.height = 20;
    cfg.boundary = Boundary::TORUS;
    cfg.shape = Shape::Square;
    cfg.start = 10.0;
    let g = cfg.build().unwrap();
    assert_eq!(g.occupied(), 100);
    assert_eq!(g.surface().len(), 20);
    for &c in g.surface().sites() {
        assert_eq!(g.occupied_neighbours(c as usize), Some(1));
    }
    assert_consistent(&g);

    // The same on the hexagonal torus, built by hand: rows 4..8 full. Rows 3 and 8 are the
    // surface, each site with b = 2.
    let mut g = growth(hex_torus(12, 16), 2.0);
    let l = g.lattice().clone();
    g.occupy_where(|_, y| (4.0 * 0.866..7.5 * 0.866).contains(&y));
    assert_eq!(g.occupied(), 48);
    assert_eq!(g.surface().len(), 24);
    for &c in g.surface().sites() {
        assert_eq!(g.occupied_neighbours(c as usize), Some(2));
    }
    assert_consistent(&g);
    // Grow until the band wraps round in y and meets itself: the lattice fills.
    let mut rng = stream(10);
    let mut k = 0;
    loop {
        match g.step_exact(&mut rng, f64::MAX) {
            Outcome::Accepted(_) => {}
            Outcome::Exhausted => break,
            o => panic!("{o:?}"),
        }
        k += 1;
        if k % 25 == 0 {
            assert_consistent(&g);
        }
    }
    assert_eq!(g.occupied(), l.len());
    assert_consistent(&g);

    // A disc centred on the corner of the torus: it lies across both seams at once.
    let mut g = growth(hex_torus(16, 16), 2.0);
    let l = g.lattice().clone();
    let inside = |c: usize| {
        let (dx, dy) = l.displacement((0.0, 0.0), l.position(c));
        dx.hypot(dy) < 4.5
    };
    for c in 0..l.len() {
        if inside(c) {
            g.occupy(c).unwrap();
        }
    }
    let expect = (0..l.len()).filter(|&c| inside(c)).count();
    assert_eq!(g.occupied(), expect);
    // All four corners of the index grid are in the disc.
    for (x, y) in [(0, 0), (15, 0), (0, 15), (15, 15)] {
        assert!(g.is_occupied(l.index(x, y)), "({x}, {y})");
    }
    assert_consistent(&g);
    // 500 picks at n = 2 add about a hundred cells, far from filling the 256-cell torus.
    assert_eq!(g.run_rejection(&mut stream(11), 500.0), Outcome::Limit);
    assert_consistent(&g);
}

#[test]
fn smallest_legal_lattices_run() {
    let lattices = [
        Lattice::new(Neighbourhood::Hex, 3, 4, Boundary::TORUS).unwrap(),
        Lattice::new(Neighbourhood::Square8, 3, 3, Boundary::TORUS).unwrap(),
        Lattice::new(Neighbourhood::Square4, 3, 3, Boundary::TORUS).unwrap(),
        Lattice::new(Neighbourhood::Square4, 1, 1, Boundary::WALLS).unwrap(),
        Lattice::new(Neighbourhood::Hex, 1, 1, Boundary::WALLS).unwrap(),
        Lattice::new(Neighbourhood::Square8, 1, 1, Boundary::WALLS).unwrap(),
        Lattice::new(Neighbourhood::Hex, 1, 2, Boundary::WALLS).unwrap(),
    ];
    for l in lattices {
        let name = format!(
            "{} {}x{} {}",
            l.neighbourhood(),
            l.width(),
            l.height(),
            l.boundary()
        );
        // Nothing occupied: no surface, both samplers say so and leave the clock alone.
        let mut g = growth(l.clone(), 2.0);
        assert_eq!(
            g.step_exact(&mut stream(1), 100.0),
            Outcome::Exhausted,
            "{name}"
        );
        assert_eq!(
            g.step_rejection(&mut stream(1), 100.0),
            Outcome::Exhausted,
            "{name}"
        );
        assert_eq!(g.time(), 0.0);
        for (sampler, n) in [
            (SamplerKind::Exact, 0.0),
            (SamplerKind::Exact, 2.0),
            (SamplerKind::Exact, 50.0),
            (SamplerKind::Rejection, 0.0),
            (SamplerKind::Rejection, 2.0),
        ] {
            let mut g = growth(l.clone(), n);
            g.occupy(0).unwrap();
            let mut rng = stream(2);
            let o = match sampler {
                SamplerKind::Exact => g.run_exact(&mut rng, f64::MAX),
                _ => g.run_rejection(&mut rng, 1e7),
            };
            // Every legal lattice is connected: the growth fills it.
            assert_eq!(o, Outcome::Exhausted, "{name}, {sampler:?}, n = {n}");
            assert_eq!(g.occupied(), l.len(), "{name}");
            assert_consistent(&g);
        }
        // The deterministic CA fills it too.
        let mut g = growth(l.clone(), 2.0);
        g.occupy(0).unwrap();
        for _ in 0..l.len() {
            g.step_ca(1);
        }
        assert_eq!(g.occupied(), l.len(), "{name} (CA)");
        assert_consistent(&g);
        // And the scene runner accepts it.
        let mut cfg = SceneConfig::defaults(SceneKind::Grow);
        cfg.lattice = l.neighbourhood();
        cfg.width = l.width();
        cfg.height = l.height();
        cfg.boundary = l.boundary();
        cfg.shape = Shape::Point;
        cfg.steps = 1000;
        cfg.snapshots = vec![1000];
        let r = scene::run(&cfg, &mut NoHooks).unwrap();
        assert_eq!(r.stop, StopReason::LatticeFull, "{name}");
        assert_eq!(r.last.occupied, l.len());
    }
}

/// A weight that is 0 left of the centre (`dx < 0`) and 1 elsewhere.
fn right_half_plane(centre: (f64, f64)) -> Weight {
    Weight::Custom {
        centre,
        f: Arc::new(|dx, _| if dx < 0.0 { 0.0 } else { 1.0 }),
    }
}

/// A 24 x 24 hexagonal lattice with walls, a square of side 6 at its centre, and the weight
/// `right_half_plane`.
fn half_plane_growth(per_site_weights: bool) -> (Growth, (f64, f64)) {
    let l = Lattice::new(Neighbourhood::Hex, 24, 24, Boundary::WALLS).unwrap();
    let (pw, ph) = l.physical_size();
    let centre = (pw / 2.0, ph / 2.0);
    let mut g = Growth::new(
        l,
        Sticking::new(2.0, 6).unwrap(),
        right_half_plane(centre),
        per_site_weights,
    )
    .unwrap();
    g.occupy_where(|x, y| (x - centre.0).abs() < 3.0 && (y - centre.1).abs() < 3.0);
    (g, centre)
}

/// Runs a sampler to `limit` event by event and returns the accepted cells.
fn accepted_cells(g: &mut Growth, exact: bool, seed: u64, limit: f64) -> Vec<usize> {
    let mut rng = stream(seed);
    let mut cells = Vec::new();
    loop {
        let o = if exact {
            g.step_exact(&mut rng, limit)
        } else {
            g.step_rejection(&mut rng, limit)
        };
        match o {
            Outcome::Accepted(c) => cells.push(c),
            // Stalled: every surface site left has v = 0 (the right half is full).
            Outcome::Limit | Outcome::Stalled | Outcome::Exhausted => return cells,
            o => panic!("{o:?}"),
        }
    }
}

#[test]
fn zero_weight_sites_are_never_accepted() {
    for exact in [true, false] {
        let mut total = 0;
        for seed in 0..5 {
            let (mut g, centre) = half_plane_growth(exact);
            let cells = accepted_cells(&mut g, exact, seed, 4000.0);
            let l = g.lattice();
            for &c in &cells {
                let (dx, _) = l.displacement(centre, l.position(c));
                assert!(dx >= 0.0, "exact = {exact}: accepted cell {c} at dx = {dx}");
            }
            total += cells.len();
            g.check_invariants().unwrap();
        }
        // Not vacuous: the right half grew.
        assert!(total > 200, "exact = {exact}: only {total} events");
    }
}

#[test]
fn zero_weight_sites_are_never_accepted_by_exact_without_per_site_weights() {
    // The same with the exact sampler on a Growth built without per-site weights. Either the
    // weight is honoured or the sampler refuses to run; silently treating v as 1 gives the
    // wrong process.
    let (mut g, centre) = half_plane_growth(false);
    let cells = accepted_cells(&mut g, true, 0, 4000.0);
    let l = g.lattice();
    for &c in &cells {
        let (dx, _) = l.displacement(centre, l.position(c));
        assert!(dx >= 0.0, "accepted cell {c} at dx = {dx} where v = 0");
    }
}

#[test]
fn zero_weight_on_the_whole_surface_stalls() {
    // v = 0 everywhere, and v = 0 only outside a disc that the start covers (so v > 0 on some
    // cells but on no surface site).
    let weights: [Arc<dyn Fn(f64, f64) -> f64 + Send + Sync>; 2] = [
        Arc::new(|_, _| 0.0),
        Arc::new(|dx: f64, dy: f64| if dx.hypot(dy) < 4.0 { 1.0 } else { 0.0 }),
    ];
    for f in weights {
        let make = |per_site| {
            let l = hex_torus(24, 24);
            let (pw, ph) = l.physical_size();
            let centre = (pw / 2.0, ph / 2.0);
            let w = Weight::Custom {
                centre,
                f: f.clone(),
            };
            let mut g = Growth::new(l, Sticking::new(2.0, 6).unwrap(), w, per_site).unwrap();
            g.occupy_where(|x, y| (x - centre.0).hypot(y - centre.1) < 5.0);
            assert!(
                g.surface()
                    .sites()
                    .iter()
                    .all(|&c| g.probability(c as usize) == 0.0)
            );
            g
        };
        let mut g = make(true);
        let occ = g.occupied();
        let mut rng = stream(12);
        assert_eq!(g.step_exact(&mut rng, 5000.0), Outcome::Stalled);
        assert_eq!(g.time(), 5000.0);
        assert_eq!(g.run_exact(&mut rng, 1e15), Outcome::Stalled);
        assert_eq!(g.time(), 1e15);
        assert_eq!(g.occupied(), occ);
        g.check_invariants().unwrap();
        // The rejection sampler reaches its limit without hanging and without growth.
        let mut g = make(false);
        assert_eq!(g.run_rejection(&mut rng, 20_000.0), Outcome::Limit);
        assert_eq!(g.time(), 20_000.0);
        assert_eq!(g.occupied(), occ);
    }
}

#[test]
fn invalid_parameters_name_the_parameter() {
    // n < 0, NaN, infinite.
    for (n, needle) in [
        (-1.0, "n = -1"),
        (f64::NAN, "n = NaN"),
        (f64::INFINITY, "n = inf"),
    ] {
        let e = Sticking::new(n, 6).unwrap_err().to_string();
        assert!(e.contains(needle), "{e}");
    }
    // Size 0 and an odd row count on a hexagonal torus.
    let e = Lattice::new(Neighbourhood::Hex, 0, 8, Boundary::TORUS)
        .unwrap_err()
        .to_string();
    assert!(e.contains("width = 0"), "{e}");
    let e = Lattice::new(Neighbourhood::Square4, 8, 0, Boundary::WALLS)
        .unwrap_err()
        .to_string();
    assert!(e.contains("height = 0"), "{e}");
    let e = Lattice::new(Neighbourhood::Hex, 8, 7, Boundary::TORUS)
        .unwrap_err()
        .to_string();
    assert!(e.contains("height = 7") && e.contains("even"), "{e}");
    let e = Lattice::new(Neighbourhood::Square4, 2, 8, Boundary::TORUS)
        .unwrap_err()
        .to_string();
    assert!(e.contains("width = 2"), "{e}");
    // A weight above 1 (or NaN) is reported when the run is set up, naming v.
    for (v, needle) in [(1.5, "v = 1.5"), (f64::NAN, "v = NaN"), (-0.1, "v = -0.1")] {
        let l = hex_torus(8, 8);
        let w = Weight::Custom {
            centre: (4.0, 3.0),
            f: Arc::new(move |_, _| v),
        };
        let e = Growth::new(l, Sticking::new(2.0, 6).unwrap(), w, true)
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle) && e.contains("weight"), "{e}");
    }
    // A rule for another neighbourhood.
    let e = Growth::new(
        hex_torus(8, 8),
        Sticking::new(2.0, 4).unwrap(),
        Weight::Isotropic,
        false,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("z = 4"), "{e}");
    // The scene configuration: each field.
    let base = SceneConfig::defaults(SceneKind::Flame);
    let cases: Vec<(SceneConfig, &str)> = vec![
        (
            SceneConfig {
                n: -2.0,
                ..base.clone()
            },
            "n = -2",
        ),
        (
            SceneConfig {
                n: f64::NAN,
                ..base.clone()
            },
            "n = NaN",
        ),
        (
            SceneConfig {
                width: 0,
                ..base.clone()
            },
            "width = 0",
        ),
        (
            SceneConfig {
                height: 0,
                ..base.clone()
            },
            "height = 0",
        ),
        (
            SceneConfig {
                height: 231,
                ..base.clone()
            },
            "height = 231",
        ),
        (
            SceneConfig {
                snapshots: vec![8000, 1000],
                ..base.clone()
            },
            "snapshots",
        ),
        (
            SceneConfig {
                snapshots: vec![1000, 1000],
                ..base.clone()
            },
            "snapshots",
        ),
        (
            SceneConfig {
                steps: 0,
                ..base.clone()
            },
            "steps = 0",
        ),
        (
            SceneConfig {
                start: -1.0,
                ..base.clone()
            },
            "start = -1",
        ),
        (
            SceneConfig {
                start: f64::NAN,
                ..base.clone()
            },
            "start = NaN",
        ),
        (
            SceneConfig {
                series: 0,
                ..base.clone()
            },
            "series = 0",
        ),
    ];
    for (cfg, needle) in cases {
        let e = cfg.validate().unwrap_err().to_string();
        assert!(e.contains(needle), "expected '{needle}' in: {e}");
        // run refuses it too, with the same message, and does not panic.
        let e2 = scene::run(&cfg, &mut NoHooks).unwrap_err().to_string();
        assert_eq!(e, e2);
    }
}

#[test]
fn scene_at_n_1e4_completes_its_steps_with_either_sampler() {
    // The flame scene on a small torus at n = 1e4: the exact sampler's first acceptance lies
    // past the largest f64, so after the run's 5000 steps: the run completes with nothing
    // accepted, as the rejection sampler's does ((b/6)^1e4 is 0 in f64 for b < 6), without
    // panicking or returning NaN.
    let mut cfg = SceneConfig::defaults(SceneKind::Flame);
    cfg.width = 24;
    cfg.height = 24;
    cfg.start = 6.0;
    cfg.n = 1e4;
    cfg.steps = 5000;
    cfg.snapshots = vec![10, 5000];
    cfg.series = 5;
    for sampler in [SamplerKind::Exact, SamplerKind::Rejection] {
        cfg.sampler = sampler;
        let r = scene::run(&cfg, &mut NoHooks).unwrap();
        assert_eq!(r.stop, StopReason::Completed, "{sampler:?}");
        assert_eq!(r.last.accepted, 0);
        assert_eq!(r.last.time, 5000.0);
        assert!(r.series.iter().all(|o| !o.time.is_nan()));
        // Both requested panels, at their times.
        let times: Vec<f64> = r.snapshots.iter().map(|s| s.time).collect();
        assert_eq!(times, vec![10.0, 5000.0], "{sampler:?}");
    }
    // Without a step limit the exact run goes on past the largest f64, on its log clock.
    cfg.sampler = SamplerKind::Exact;
    cfg.steps = 0;
    cfg.events = Some(10);
    cfg.snapshots = vec![];
    let r = scene::run(&cfg, &mut NoHooks).unwrap();
    assert_eq!(r.stop, StopReason::Events);
    assert_eq!(r.last.accepted, 10);
    assert!(r.log10_clock > 3000.0, "{}", r.log10_clock);
}

/// An unbounded run at n = 2000 takes its clock past the largest `f64` on a log clock: its
/// observations and snapshots carry a finite base-10 log of it, where the time itself is `inf`.
#[test]
fn a_clock_past_the_largest_f64_keeps_a_finite_log() {
    let mut c = SceneConfig::defaults(SceneKind::Grow);
    c.width = 32;
    c.height = 32;
    c.n = 2000.0;
    c.steps = 0;
    c.events = Some(400);
    c.snapshots.clear();
    let r = scene::run(&c, &mut NoHooks).unwrap();
    assert_eq!(r.stop, StopReason::Events);
    let last = r.series.last().unwrap();
    assert!(last.time.is_infinite(), "{}", last.time);
    assert!(
        last.log10_time.is_finite() && last.log10_time > 308.0,
        "{}",
        last.log10_time
    );
    assert!((last.log10_time - r.log10_clock).abs() < 1e-9);
    // the logs never decrease along the series
    for w in r.series.windows(2) {
        assert!(w[1].log10_time >= w[0].log10_time);
    }
}
