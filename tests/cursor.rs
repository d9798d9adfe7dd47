//! The wind-field cursor walk ("A model for sedimentation of airborne particles"): exact properties of Eq. (2), the walk's long-run
//! statistics against exact results, reproducibility, input checks and the command line.
//!
//! Statistical tests use fixed seeds (so they are deterministic) and tolerances derived from
//! the standard error of the quantity tested, stated at each test. The fixtures
//! `tests/fixtures/cursor_*.png` are written by the ignored test `make_fixtures`.

use std::path::{Path, PathBuf};

use cellsurf::cursor::display::{SeaLevel, flooded_fraction, quantile, quantile_level};
use cellsurf::cursor::stats::{
    self, NoiseModel, density_error, drift_formula, mean_direction, mean_step, step_covariance,
};
use cellsurf::cursor::{
    CursorError, CursorWalk, DIRECTIONS, MAX_WIND, Transitions, UNIT, Wind, WindField, WindSpec,
    probabilities,
};
use cellsurf::engine::stats::loglog_slope;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("fixtures")
        .join(name)
}

fn uniform(angle: f64, speed: f64, w: usize, h: usize) -> WindField {
    WindSpec::Uniform {
        angle_deg: angle,
        speed,
    }
    .field(w, h)
    .unwrap()
}

// ---------------------------------------------------------------------------------------------
// Eq. (2): probabilities.

#[test]
fn probabilities_lie_in_range_and_sum_to_one() {
    for k in [0.0, 0.3, 0.95, 1.0] {
        for speed in [0.0, 50.0, 219.9, MAX_WIND] {
            for a in 0..36 {
                let w = Wind::from_angle(a as f64 * 10.0, speed);
                let p = probabilities(w, k);
                let sum: f64 = p.iter().sum();
                assert!((sum - 1.0).abs() < 1e-15, "sum {sum} at k {k}, {w:?}");
                for &pi in &p {
                    assert!(
                        (0.0..=0.25 + 1e-15).contains(&pi),
                        "P = {pi} at k {k}, {w:?}"
                    );
                }
            }
        }
    }
    // At k = 1 and |W| = 220 the move against the wind has probability 0, the move with it 1/4.
    let p = probabilities(Wind { x: 220.0, y: 0.0 }, 1.0);
    assert_eq!(p[4], 0.0);
    assert_eq!(p[0], 0.25);
    // Calm: 1/8 each.
    assert_eq!(probabilities(Wind::CALM, 0.95), [0.125; 8]);
}

#[test]
fn unit_vectors_match_the_lattice_directions() {
    for (&(dx, dy), &(ux, uy)) in DIRECTIONS.iter().zip(UNIT.iter()) {
        let n = f64::from(dx).hypot(f64::from(dy));
        assert!((f64::from(dx) / n - ux).abs() < 1e-15);
        assert!((f64::from(dy) / n - uy).abs() < 1e-15);
    }
    // The Moore offsets of the lattice engine, in the same order.
    use cellsurf::engine::lattice::Neighbourhood;
    assert_eq!(Neighbourhood::Square8.offsets(0), &DIRECTIONS);
}

#[test]
fn walk_uses_rounded_probabilities_that_sum_to_exactly_one() {
    let field = WindSpec::article("rotating")
        .unwrap()
        .field(30, 30)
        .unwrap();
    let tr = Transitions::new(&field, 0.7).unwrap();
    for cell in [0, 17, 455, 899] {
        let q = tr.cell_probabilities(cell);
        let exact = probabilities(field.winds()[cell], 0.7);
        assert_eq!(q.iter().sum::<f64>(), 1.0);
        for (a, b) in q.iter().zip(exact.iter()) {
            // Rounded to multiples of 2^-31: within a few units of 2^-31 of Eq. (2).
            assert!((a - b).abs() < 4.0 / (1u64 << 31) as f64, "{a} vs {b}");
        }
    }
}

#[test]
fn zero_probability_direction_is_never_taken() {
    let field = WindField::uniform(9, 9, Wind { x: 220.0, y: 0.0 }).unwrap();
    let tr = Transitions::new(&field, 1.0).unwrap();
    assert_eq!(tr.cell_probabilities(0)[4], 0.0);
    let mut walk = CursorWalk::new(&tr, 3);
    let mut counts = [0u64; 8];
    walk.run_with(200_000, |_, d, _| counts[d] += 1);
    assert_eq!(counts[4], 0, "moved against the wind: {counts:?}");
    assert!(counts.iter().enumerate().all(|(i, &c)| i == 4 || c > 0));
}

// ---------------------------------------------------------------------------------------------
// Heights.

#[test]
fn height_total_equals_steps_and_the_start_is_not_counted() {
    let field = WindSpec::article("bimodal").unwrap().field(40, 30).unwrap();
    let tr = Transitions::new(&field, 0.95).unwrap();
    let mut walk = CursorWalk::new(&tr, 5);
    assert_eq!(walk.height_total(), 0);
    assert_eq!(walk.position(), (20, 15));
    walk.run(1);
    // One visit, in a neighbour of the start (the start cell itself is not counted).
    assert_eq!(walk.height_total(), 1);
    let start = 15 * 40 + 20;
    let visited: Vec<usize> = (0..walk.heights().len())
        .filter(|&c| walk.heights()[c] > 0)
        .collect();
    assert_eq!(visited.len(), 1);
    assert!(tr.neighbours(start).contains(&(visited[0] as u32)));
    for n in [0, 1, 999, 12_345] {
        walk.run(n);
    }
    assert_eq!(walk.steps(), 1 + 999 + 12_345 + 1);
    assert_eq!(walk.height_total(), walk.steps());
}

#[test]
fn moves_go_to_the_neighbour_in_the_drawn_direction_with_wrapping() {
    let field = uniform(45.0, 150.0, 5, 4);
    let tr = Transitions::new(&field, 0.9).unwrap();
    let mut walk = CursorWalk::from_cell(&tr, 11, 0);
    let mut checked = 0;
    walk.run_with(5_000, |from, dir, to| {
        assert_eq!(tr.neighbours(from)[dir] as usize, to);
        checked += 1;
    });
    assert_eq!(checked, 5_000);
}

// ---------------------------------------------------------------------------------------------
// Long-run density: uniform for calm air and any uniform wind (doubly stochastic transition
// matrix), checked against the exact expectation of the squared density error.

/// Mean over `seeds` seeds of `eps^2 / E[eps^2]` after `steps` steps, and its standard error
/// from the Gaussian-limit spread of `eps^2` ([`NoiseModel::relative_spread_sq_error`]).
fn density_ratio(field: &WindField, k: f64, steps: u64, seeds: u64) -> (f64, f64) {
    let tr = Transitions::new(field, k).unwrap();
    let model = NoiseModel::for_transitions(&tr).unwrap();
    let expected = model.expected_sq_error(steps);
    let mut sum = 0.0;
    for s in 0..seeds {
        let mut walk = CursorWalk::new(&tr, 1000 + s);
        walk.run(steps);
        sum += density_error(walk.heights()).unwrap().powi(2) / expected;
    }
    let se = model.relative_spread_sq_error(steps) / (seeds as f64).sqrt();
    (sum / seeds as f64, se)
}

#[test]
fn calm_air_gives_a_uniform_long_run_density() {
    // 12 x 10 torus, 150,000 steps (1,250 visits per cell), 6 seeds. A non-uniform stationary
    // law would leave a density error that does not fall with N: the ratio would grow like N.
    // Tolerance: 4 standard errors of the mean ratio.
    let field = WindField::calm(12, 10).unwrap();
    let (ratio, se) = density_ratio(&field, 0.95, 150_000, 6);
    assert!((ratio - 1.0).abs() < 4.0 * se, "ratio {ratio}, se {se}");
    assert!(se < 0.2, "the test must resolve the ratio: se {se}");
}

#[test]
fn uniform_winds_give_a_uniform_long_run_density() {
    for (angle, speed, k) in [(0.0, 220.0, 0.95), (30.0, 180.0, 1.0), (135.0, 100.0, 0.5)] {
        let field = uniform(angle, speed, 12, 10);
        let tr = Transitions::new(&field, k).unwrap();
        assert!(tr.is_doubly_stochastic());
        let (ratio, se) = density_ratio(&field, k, 150_000, 6);
        assert!(
            (ratio - 1.0).abs() < 4.0 * se,
            "wind {angle} deg {speed}, k {k}: ratio {ratio}, se {se}"
        );
    }
}

#[test]
fn a_converging_field_is_detected_as_non_uniform() {
    // Negative control: the same statistic is far above 1 when the density is not uniform.
    let field = WindSpec::Rotating {
        angle_deg: 0.0,
        speed: 200.0,
        wavelength: 12.0,
        arms: 4,
    }
    .field(12, 12)
    .unwrap();
    let tr = Transitions::new(&field, 0.95).unwrap();
    assert!(!tr.is_doubly_stochastic());
    assert!(tr.arrival_deviation() > 0.01);
    let calm = NoiseModel::for_wind(Wind::CALM, 0.95, 12, 12);
    let mut walk = CursorWalk::new(&tr, 1);
    walk.run(200_000);
    let ratio = density_error(walk.heights()).unwrap().powi(2) / calm.expected_sq_error(200_000);
    assert!(ratio > 10.0, "ratio {ratio}");
}

#[test]
fn generators_other_than_calm_and_uniform_are_not_doubly_stochastic() {
    for name in ["bimodal", "converging", "rotating"] {
        let field = WindSpec::article(name).unwrap().field(240, 240).unwrap();
        let tr = Transitions::new(&field, 0.95).unwrap();
        assert!(!tr.is_doubly_stochastic(), "{name}");
        assert!(NoiseModel::for_transitions(&tr).is_none());
    }
    for name in ["calm", "uniform"] {
        let field = WindSpec::article(name).unwrap().field(20, 20).unwrap();
        let tr = Transitions::new(&field, 0.95).unwrap();
        assert!(tr.is_doubly_stochastic(), "{name}");
        assert!(tr.is_translation_invariant(), "{name}");
    }
    // At k = 0 every field is calm air.
    let field = WindSpec::article("rotating")
        .unwrap()
        .field(60, 60)
        .unwrap();
    let tr = Transitions::new(&field, 0.0).unwrap();
    assert!(tr.is_translation_invariant() && tr.is_doubly_stochastic());
    assert_eq!(tr.cell_probabilities(1234), [0.125; 8]);
}

#[test]
fn noise_model_closed_form_matches_direct_sum() {
    // The closed form (N > 256) continues the direct sum (N <= 256) smoothly: E[eps^2] N is
    // nearly the same at N = 256 and 257, and both match a brute-force double sum for one mode.
    let p = probabilities(Wind::from_angle(20.0, 150.0), 0.8);
    let m = NoiseModel::new(&p, 7, 5);
    let (a, b) = (
        m.expected_sq_error(256) * 256.0,
        m.expected_sq_error(257) * 257.0,
    );
    assert!((a - b).abs() / a < 0.01, "{a} vs {b}");
    // Large N: E[eps^2] N tends to the asymptotic constant S.
    let s = m.asymptotic_constant();
    let big = m.expected_sq_error(10_000_000) * 1e7;
    assert!((big - s).abs() / s < 1e-4, "{big} vs {s}");
    // Calm 3 x 3 torus: every step leaves the cell, the closed forms agree with a direct
    // simulation-free evaluation at N = 1 (eps^2 = n - 1 = 8 for one visit).
    let calm = NoiseModel::new(&[0.125; 8], 3, 3);
    assert!((calm.expected_sq_error(1) - 8.0).abs() < 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Drift.

#[test]
fn drift_per_step_equals_sum_of_p_i_d_i() {
    // Uniform winds: the steps are independent with mean sum_i P_i d_i; tolerance 4 standard
    // errors (from the step covariance) over 400,000 steps.
    let n = 400_000u64;
    for (angle, speed, k) in [(0.0, 220.0, 0.95), (30.0, 220.0, 0.95), (250.0, 90.0, 0.4)] {
        let field = uniform(angle, speed, 31, 17);
        let tr = Transitions::new(&field, k).unwrap();
        let p = tr.cell_probabilities(0);
        let m = mean_step(&p);
        let c = step_covariance(&p);
        // The closed form k W (1 + sqrt 2) / 880.
        let f = drift_formula(field.winds()[0], k);
        assert!((m.0 - f.0).abs() < 1e-8 && (m.1 - f.1).abs() < 1e-8);
        let mut walk = CursorWalk::new(&tr, 77);
        let mut unit = (0.0, 0.0);
        walk.run_with(n, |_, d, _| {
            unit.0 += UNIT[d].0;
            unit.1 += UNIT[d].1;
        });
        let (dx, dy) = walk.displacement();
        let got = (dx as f64 / n as f64, dy as f64 / n as f64);
        let se = ((c[0][0] / n as f64).sqrt(), (c[1][1] / n as f64).sqrt());
        assert!((got.0 - m.0).abs() < 4.0 * se.0, "x: {got:?} vs {m:?}");
        assert!((got.1 - m.1).abs() < 4.0 * se.1, "y: {got:?} vs {m:?}");
        // The mean unit direction, sum_i P_i u_i = k W / 440 (each |u_i| = 1: se <= 1/sqrt N).
        let u = mean_direction(&p);
        let w = field.winds()[0];
        assert!((u.0 - k * w.x / 440.0).abs() < 1e-8 && (u.1 - k * w.y / 440.0).abs() < 1e-8);
        let se_u = 1.0 / (n as f64).sqrt();
        assert!((unit.0 / n as f64 - u.0).abs() < 4.0 * se_u);
        assert!((unit.1 / n as f64 - u.1).abs() < 4.0 * se_u);
    }
}

#[test]
fn drift_in_a_varying_field_follows_the_local_formula() {
    // Martingale check: sum_t (d_t - m(c_t)) has mean 0 and variance sum_t Var(c_t), with m and
    // Var the local mean and covariance of the cell the step leaves. Tolerance 4 standard
    // deviations.
    let field = WindSpec::article("bimodal").unwrap().field(40, 40).unwrap();
    let tr = Transitions::new(&field, 0.95).unwrap();
    let mut walk = CursorWalk::new(&tr, 9);
    let (mut mx, mut my, mut vx, mut vy) = (0.0, 0.0, 0.0, 0.0);
    walk.run_with(300_000, |from, _, _| {
        let p = tr.cell_probabilities(from);
        let m = mean_step(&p);
        let c = step_covariance(&p);
        mx += m.0;
        my += m.1;
        vx += c[0][0];
        vy += c[1][1];
    });
    let (dx, dy) = walk.displacement();
    assert!((dx as f64 - mx).abs() < 4.0 * vx.sqrt(), "{dx} vs {mx}");
    assert!((dy as f64 - my).abs() < 4.0 * vy.sqrt(), "{dy} vs {my}");
    // The drift is real: it is many standard deviations from zero.
    assert!(mx.hypot(my) > 20.0 * vx.max(vy).sqrt());
}

// ---------------------------------------------------------------------------------------------
// Error against steps.

#[test]
fn density_error_falls_like_one_over_sqrt_steps() {
    // 12 x 12 torus, 10,000 to 500,000 steps (well past the slowest mode's relaxation, about
    // 50 steps), RMS over 4 seeds; least-squares slope of ln eps against ln N. Expected -1/2.
    // Tolerance 0.1: 4 standard deviations of this fitted slope, measured over 40 groups of 4
    // seeds (sd 0.025 in calm air, 0.019 in the uniform wind; means -0.494 and -0.499).
    let checkpoints = stats::log_spaced(10_000, 500_000, 12);
    for field in [
        WindField::calm(12, 12).unwrap(),
        uniform(30.0, 220.0, 12, 12),
    ] {
        let tr = Transitions::new(&field, 0.95).unwrap();
        let mut ms = vec![0.0; checkpoints.len()];
        for s in 0..4 {
            for (i, p) in stats::error_curve(&tr, 500 + s, &checkpoints)
                .iter()
                .enumerate()
            {
                assert_eq!(p.steps, checkpoints[i]);
                ms[i] += p.density_error.powi(2) / 4.0;
            }
        }
        let pts: Vec<(f64, f64)> = checkpoints
            .iter()
            .zip(&ms)
            .map(|(&n, &e)| (n as f64, e.sqrt()))
            .collect();
        let (slope, _) = loglog_slope(&pts).unwrap();
        assert!((slope + 0.5).abs() < 0.1, "slope {slope}");
    }
}

#[test]
fn loglog_slope_recovers_a_power_law() {
    let pts: Vec<(f64, f64)> = (1..20)
        .map(|i| (i as f64 * 10.0, 3.0 * (i as f64 * 10.0).powf(-0.5)))
        .collect();
    let (s, c) = loglog_slope(&pts).unwrap();
    assert!((s + 0.5).abs() < 1e-12);
    assert!((c - 3f64.ln()).abs() < 1e-12);
    assert!(loglog_slope(&[(1.0, 1.0)]).is_none());
    assert_eq!(density_error(&[]), None);
    assert_eq!(density_error(&[0, 0]), None);
    assert_eq!(density_error(&[5, 5, 5]), Some(0.0));
}

// ---------------------------------------------------------------------------------------------
// Reproducibility.

#[test]
fn same_seed_same_heights_and_chunking_does_not_matter() {
    let field = WindSpec::article("converging")
        .unwrap()
        .field(80, 60)
        .unwrap();
    let tr = Transitions::new(&field, 0.95).unwrap();
    let mut a = CursorWalk::new(&tr, 123);
    a.run(50_000);
    let mut b = CursorWalk::new(&tr, 123);
    for _ in 0..10 {
        b.run(5_000);
    }
    assert_eq!(a.heights(), b.heights());
    assert_eq!(a.position(), b.position());
    assert_eq!(a.displacement(), b.displacement());
    let mut c = CursorWalk::new(&tr, 124);
    c.run(50_000);
    assert_ne!(a.heights(), c.heights());
}

#[test]
fn first_positions_are_pinned_for_a_seed() {
    // Value stability: the stream (Xoshiro256++ from seed 42), the thresholds and the direction
    // order fix these positions; a change here changes every published run.
    let tr = Transitions::new(&WindField::calm(16, 16).unwrap(), 0.95).unwrap();
    let mut walk = CursorWalk::new(&tr, 42);
    let mut calm = Vec::new();
    for _ in 0..12 {
        walk.run(1);
        calm.push(walk.position());
    }
    let tr = Transitions::new(&uniform(0.0, 220.0, 16, 16), 0.95).unwrap();
    let mut walk = CursorWalk::new(&tr, 42);
    let mut windy = Vec::new();
    for _ in 0..12 {
        walk.run(1);
        windy.push(walk.position());
    }
    assert_eq!(calm, CALM_42);
    assert_eq!(windy, WINDY_42);
}

/// First 12 positions of the calm walk on 16 x 16 from seed 42.
const CALM_42: [(usize, usize); 12] = [
    (8, 7),
    (8, 8),
    (9, 7),
    (8, 6),
    (8, 5),
    (7, 5),
    (8, 6),
    (7, 6),
    (8, 7),
    (9, 6),
    (8, 6),
    (8, 5),
];
/// First 12 positions in a uniform wind toward +x at 220 (k = 0.95), 16 x 16, seed 42.
const WINDY_42: [(usize, usize); 12] = [
    (9, 7),
    (10, 8),
    (11, 7),
    (11, 6),
    (12, 5),
    (11, 6),
    (12, 6),
    (11, 7),
    (12, 7),
    (13, 6),
    (13, 7),
    (14, 6),
];

// ---------------------------------------------------------------------------------------------
// Input checks.

#[test]
fn force_constant_outside_zero_one_is_rejected() {
    let field = WindField::calm(5, 5).unwrap();
    for k in [-0.01, 1.01, f64::NAN, f64::INFINITY] {
        let e = Transitions::new(&field, k).unwrap_err();
        assert!(matches!(e, CursorError::ForceConstant(_)));
        let m = e.to_string();
        assert!(m.contains("k = ") && m.contains("expected 0 to 1"), "{m}");
    }
    assert!(Transitions::new(&field, 0.0).is_ok());
    assert!(Transitions::new(&field, 1.0).is_ok());
}

#[test]
fn winds_faster_than_220_are_rejected() {
    let e = WindField::from_fn(5, 5, |x, _| Wind {
        x: if x == 3 { 221.0 } else { 0.0 },
        y: 0.0,
    })
    .unwrap_err();
    let m = e.to_string();
    assert!(
        m.contains("221.00") && m.contains("220") && m.contains("x 3"),
        "{m}"
    );
    assert!(
        WindField::uniform(
            5,
            5,
            Wind {
                x: f64::NAN,
                y: 0.0
            }
        )
        .is_err()
    );
    // Exactly 220 in any direction is accepted.
    for a in 0..24 {
        assert!(WindField::uniform(5, 5, Wind::from_angle(a as f64 * 15.0, 220.0)).is_ok());
    }
}

#[test]
fn generator_parameters_are_checked_by_name() {
    let cases: [(WindSpec, &str); 7] = [
        (
            WindSpec::Uniform {
                angle_deg: 0.0,
                speed: 221.0,
            },
            "wind speed = 221",
        ),
        (
            WindSpec::Uniform {
                angle_deg: f64::NAN,
                speed: 10.0,
            },
            "wind angle",
        ),
        (
            WindSpec::Bimodal {
                angle_deg: 0.0,
                speed: 100.0,
                spread_deg: 190.0,
                wavelength: 20.0,
            },
            "wind spread = 190",
        ),
        (
            WindSpec::Bimodal {
                angle_deg: 0.0,
                speed: 100.0,
                spread_deg: 90.0,
                wavelength: 2.0,
            },
            "wind wavelength = 2",
        ),
        (
            WindSpec::Converging {
                angle_deg: 0.0,
                speed: 100.0,
                radial: 150.0,
                wavelength: 60.0,
                spacing: 60.0,
                radius: 20.0,
            },
            "wind radial = 150",
        ),
        (
            WindSpec::Converging {
                angle_deg: 0.0,
                speed: 50.0,
                radial: -150.0,
                wavelength: 60.0,
                spacing: 30.0,
                radius: 20.0,
            },
            "wind radius = 20",
        ),
        (
            WindSpec::Rotating {
                angle_deg: 0.0,
                speed: 60.0,
                wavelength: 60.0,
                arms: 13,
            },
            "wind arms = 13",
        ),
    ];
    for (spec, text) in cases {
        let m = spec.field(60, 60).unwrap_err().to_string();
        assert!(m.contains(text) && m.contains("out of range"), "{m}");
    }
}

#[test]
fn grid_sizes_are_checked() {
    for (w, h) in [(2, 10), (10, 0), (5000, 5000)] {
        let m = WindField::calm(w, h).unwrap_err().to_string();
        assert!(m.contains(&format!("{w}x{h}")), "{m}");
    }
}

#[test]
fn generators_stay_within_their_speed_and_are_periodic() {
    for name in ["calm", "uniform", "bimodal", "converging", "rotating"] {
        let spec = WindSpec::article(name).unwrap();
        let f = spec.field(240, 240).unwrap();
        assert!(f.max_speed() <= MAX_WIND * (1.0 + 1e-12), "{name}");
        assert!(spec.is_uniform() == (f.uniform_wind().is_some()), "{name}");
    }
    // An array of nodes 60 cells apart on 240 cells repeats every 60 cells.
    let f = WindSpec::article("rotating")
        .unwrap()
        .field(240, 240)
        .unwrap();
    for (x, y) in [(3, 7), (100, 50), (17, 200)] {
        assert_eq!(f.at(x, y), f.at((x + 60) % 240, y));
        assert_eq!(f.at(x, y), f.at(x, (y + 60) % 240));
    }
}

// ---------------------------------------------------------------------------------------------
// Colour encoding and PNG input.

#[test]
fn colour_vectors_point_at_0_120_240_degrees() {
    let r = Wind::from_rgb([200, 0, 0]);
    let g = Wind::from_rgb([0, 200, 0]);
    let b = Wind::from_rgb([0, 0, 200]);
    for (w, a) in [(r, 0.0), (g, 120.0), (b, -120.0)] {
        assert!((w.speed() - 200.0).abs() < 1e-9);
        assert!((w.angle_deg() - a).abs() < 1e-9, "{w:?}");
    }
    assert_eq!(Wind::from_rgb([77, 77, 77]).speed(), 0.0);
}

#[test]
fn rgb_encoding_round_trips_within_one_unit_and_220() {
    for a in 0..72 {
        for speed in [0.0, 1.0, 37.5, 110.0, 200.0, 219.5, 220.0] {
            let w = Wind::from_angle(a as f64 * 5.0, speed);
            let rgb = w.to_rgb().unwrap();
            let back = Wind::from_rgb(rgb);
            assert!(
                (back.x - w.x).hypot(back.y - w.y) <= 1.0,
                "{w:?} -> {rgb:?}"
            );
            assert!(
                back.speed() <= MAX_WIND,
                "{w:?} -> {rgb:?} -> {}",
                back.speed()
            );
            assert!(rgb.contains(&0) || speed == 0.0, "{rgb:?}: smallest levels");
        }
    }
    // Outside the hexagon reachable with levels 0..=255.
    assert!(Wind { x: 300.0, y: 0.0 }.to_rgb().is_none());
}

#[test]
fn png_fixture_decodes_with_image_rows_top_first() {
    let f = WindField::from_png(&fixture("cursor_wind_4x3.png"), Some((4, 3)), 1.0).unwrap();
    assert_eq!((f.width(), f.height()), (4, 3));
    // Image row 0 (top) is lattice row 2.
    assert_eq!(f.at(0, 2), Wind::from_rgb([200, 0, 0]));
    assert_eq!(f.at(1, 2), Wind::from_rgb([0, 200, 0]));
    assert_eq!(f.at(2, 2), Wind::from_rgb([0, 0, 200]));
    assert_eq!(f.at(3, 2), Wind::CALM);
    assert_eq!(f.at(0, 0), Wind::from_rgb([0, 110, 110]));
    // Its own size when no size is expected; scaling.
    let g = WindField::from_png(&fixture("cursor_wind_4x3.png"), None, 0.5).unwrap();
    assert_eq!(g.at(0, 2), Wind { x: 100.0, y: 0.0 });
    // A grey image is calm air.
    let grey = WindField::from_png(&fixture("cursor_grey_5x5.png"), Some((5, 5)), 1.0).unwrap();
    assert_eq!(grey.max_speed(), 0.0);
}

#[test]
fn png_fixture_round_trips_a_generator_field() {
    let f = WindSpec::article("bimodal").unwrap().field(24, 18).unwrap();
    let bytes = f.to_png_bytes().unwrap();
    let g = WindField::from_png_bytes(&bytes, "memory", Some((24, 18)), 1.0).unwrap();
    for (a, b) in f.winds().iter().zip(g.winds()) {
        assert!((a.x - b.x).hypot(a.y - b.y) <= 1.0);
    }
}

#[test]
fn bad_png_files_get_clear_errors() {
    let trunc = fixture("cursor_truncated.png");
    let m = WindField::from_png(&trunc, Some((4, 3)), 1.0)
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("cursor_truncated.png") && m.contains("cannot read wind image"),
        "{m}"
    );

    let wrong = fixture("cursor_wrong_size.png");
    let e = WindField::from_png(&wrong, Some((240, 240)), 1.0).unwrap_err();
    assert!(matches!(
        e,
        CursorError::PngSize {
            width: 7,
            height: 5,
            ..
        }
    ));
    let m = e.to_string();
    assert!(
        m.contains("cursor_wrong_size.png") && m.contains("7x5") && m.contains("240x240"),
        "{m}"
    );

    let strong = fixture("cursor_too_strong.png");
    let m = WindField::from_png(&strong, None, 1.0)
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("cursor_too_strong.png") && m.contains("[255, 0, 0]") && m.contains("255.00"),
        "{m}"
    );
    // Scaled by 220/255 it is accepted.
    assert!(WindField::from_png(&strong, None, 220.0 / 255.0).is_ok());

    let missing = fixture("cursor_does_not_exist.png");
    let m = WindField::from_png(&missing, None, 1.0)
        .unwrap_err()
        .to_string();
    assert!(m.contains("cursor_does_not_exist.png"), "{m}");

    let not_png = Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml");
    let m = WindField::from_png(&not_png, None, 1.0)
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("Cargo.toml") && m.contains("not a readable PNG"),
        "{m}"
    );
    assert!(WindField::from_png(&strong, None, -1.0).is_err());
}

// ---------------------------------------------------------------------------------------------
// Sea level.

#[test]
fn sea_level_rules() {
    let h = [0u64, 10, 20, 30, 40, 50, 60, 70, 80, 90];
    assert_eq!(SeaLevel::default().resolve(&h), 22.5);
    assert_eq!(SeaLevel::Height(33.0).resolve(&h), 33.0);
    assert_eq!(SeaLevel::Quantile(0.3).resolve(&h), 30.0);
    assert_eq!(quantile(&h, 1.0), 90.0);
    assert_eq!(flooded_fraction(&h, 22.5), 0.3);
    // each refusal names the scenario key that sets the level (the command line shows its flag)
    for (sea, key) in [
        (SeaLevel::Quantile(1.5), "sea_quantile = 1.5"),
        (SeaLevel::Height(-1.0), "sea_level = -1"),
        (SeaLevel::MeanFraction(f64::NAN), "sea_fraction = NaN"),
    ] {
        let e = sea.validate().unwrap_err().to_string();
        assert!(e.starts_with(key), "{e}");
    }
}

#[test]
fn sea_quantile_floods_that_fraction_of_the_cells() {
    // distinct heights: round(Q n) cells exactly, for every Q, Q = 1 included
    let h: Vec<u64> = (0..100u64).map(|i| (i * 37) % 100 * 3 + 5).collect();
    for q in [0.0, 0.01, 0.25, 0.5, 0.87, 0.99, 1.0] {
        let level = SeaLevel::Quantile(q).resolve(&h);
        let f = flooded_fraction(&h, level);
        assert_eq!(f, (q * 100.0).round() / 100.0, "Q = {q}: level {level}");
    }
    assert_eq!(SeaLevel::Quantile(1.0).resolve(&h), 303.0);
    assert_eq!(SeaLevel::Quantile(0.0).resolve(&h), 5.0);
    // 4 cells, Q = 0.5: two of them (the nearest rank round(Q (n - 1)) flooded one)
    assert_eq!(
        flooded_fraction(&[7, 1, 9, 4], quantile_level(&[7, 1, 9, 4], 0.5)),
        0.5
    );
    // ties are flooded together, to the count nearer round(Q n) (the lower one on a tie)
    let t = [1u64, 2, 2, 2, 2, 3, 4, 5, 6, 7];
    let frac = |q: f64| flooded_fraction(&t, quantile_level(&t, q));
    assert_eq!(frac(0.1), 0.1);
    assert_eq!(frac(0.2), 0.1); // the run 2,2,2,2 (cells 2-5): 1 cell or 5, 1 is nearer 2
    assert_eq!(frac(0.3), 0.1); // 1 or 5: a tie, the lower
    assert_eq!(frac(0.4), 0.5);
    assert_eq!(frac(0.5), 0.5);
    assert_eq!(frac(1.0), 1.0);
}

// ---------------------------------------------------------------------------------------------
// Drawing.

#[cfg(feature = "plot")]
#[test]
fn landscape_picture_is_written() {
    let field = WindSpec::article("rotating")
        .unwrap()
        .field(30, 20)
        .unwrap();
    let tr = Transitions::new(&field, 0.95).unwrap();
    let mut walk = CursorWalk::new(&tr, 1);
    walk.run(20_000);
    let dir = std::env::temp_dir().join(format!("cellsurf-cursor-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("land.png");
    let sea = SeaLevel::default().resolve(walk.heights());
    cellsurf::cursor::draw_landscape(&p, "t", "c", &field, walk.heights(), sea).unwrap();
    let bytes = std::fs::read(&p).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    assert!(cellsurf::cursor::draw_landscape(&p, "t", "c", &field, &[1, 2], sea).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------------------------------------
// Command line.

#[cfg(feature = "cli")]
mod cli {
    use super::fixture;
    use std::process::Command;

    fn cellsurf(args: &[&str]) -> std::process::Output {
        Command::new(env!("CARGO_BIN_EXE_cellsurf"))
            .arg("cursor")
            .args(args)
            .output()
            .unwrap()
    }

    /// A fitted pattern is said in one warning, whatever --quiet says, naming each value as it
    /// was given (flag or scenario key); a value a scenario gave that the run refuses is named
    /// by its key; the default radius refused on a small torus says it is the default.
    #[test]
    fn fitted_patterns_and_scenario_values_are_said_as_given() {
        let o = cellsurf(&[
            "--wind-field",
            "bimodal",
            "--wind-wavelength",
            "40",
            "--wind-angle",
            "60",
            "--size",
            "50x50",
            "--steps",
            "10",
            "--quiet",
        ]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{e}");
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(
            e.contains("35.3553 cells apart (--wind-wavelength = 40)")
                && e.contains("its bands run at 45.0000 deg (--wind-angle = 60; the winds' resultant stays at 60 deg)"),
            "{e}"
        );
        // whole periods: nothing said
        let o = cellsurf(&[
            "--wind-field",
            "bimodal",
            "--wind-wavelength",
            "40",
            "--wind-angle",
            "90",
            "--size",
            "120x50",
            "--steps",
            "10",
            "--quiet",
        ]);
        assert!(
            o.stderr.is_empty(),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        let o = cellsurf(&[
            "--wind-field",
            "converging",
            "--size",
            "40",
            "--steps",
            "10",
        ]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(
            e.starts_with("error: in --wind-field converging: --wind-radius = 25 (the default) is out of range: expected 1 to 20 cells"),
            "{e}"
        );
        let dir = std::env::temp_dir().join(format!("cellsurf-cursor-keys-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (name, text, want) in [
            (
                "scale.toml",
                "model = \"cursor\"\nwind_scale = 2.0\n",
                "error: wind_scale (the scenario's) = 2 applies to a --wind-image only",
            ),
            (
                "seas.toml",
                "model = \"cursor\"\nsea_level = 5.0\nsea_fraction = 0.2\n",
                "error: sea_level (the scenario's), sea_fraction (the scenario's) are given together",
            ),
            (
                "spread.toml",
                "model = \"cursor\"\nwind_field = \"uniform\"\nwind_spread = 100.0\n",
                "error: wind_spread (the scenario's) does not apply to --wind-field uniform",
            ),
        ] {
            let p = dir.join(name);
            std::fs::write(&p, text).unwrap();
            let o = cellsurf(&["--scenario", p.to_str().unwrap(), "--steps", "10"]);
            let e = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(1), "{e}");
            assert!(e.starts_with(want), "{name}: {e}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The JSON summary of a run that must succeed.
    fn json(args: &[&str]) -> serde_json::Value {
        let out = cellsurf(args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap()
    }

    #[test]
    fn json_summary_has_steps_equal_to_height_total() {
        let v = json(&[
            "--steps",
            "30000",
            "--size",
            "30x20",
            "--wind-field",
            "uniform",
            "--json",
        ]);
        assert_eq!(v["steps"], 30000);
        assert_eq!(v["height_total"], 30000);
        assert!(v["density_error"].as_f64().unwrap() > 0.0);
        assert!(v["density_error_expected"].as_f64().unwrap() > 0.0);
        assert!(v["elapsed_s"].as_f64().is_some());
        assert_eq!(v["parameters"]["wind_field"], "uniform");
        assert_eq!(v["run"]["wind"]["field"], "uniform");
        assert_eq!(v["model"], "cursor");
        assert!(v["version"].is_string());
        // Not known for a converging field.
        let out = cellsurf(&[
            "--steps",
            "3000",
            "--size",
            "60x60",
            "--wind-field",
            "rotating",
            "--json",
        ]);
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert!(v["density_error"].is_null());
        assert_eq!(v["height_total"], 3000);
    }

    #[test]
    fn sea_quantile_floods_that_fraction() {
        // 10 x 10 cells of about 1000 visits: Q = 1 floods every cell (it flooded 99 of them),
        // Q = 0 none; Q = 0.5 half of them up to a run of equal heights at the 50th cell
        // (here two cells of 994 visits: 49 flooded, the lower count on a tie)
        for (q, want) in [
            ("1", 1.0),
            ("0.75", 0.75),
            ("0.5", 0.49),
            ("0.25", 0.25),
            ("0", 0.0),
        ] {
            let v = json(&[
                "--steps",
                "100000",
                "--size",
                "10",
                "--sea-quantile",
                q,
                "--json",
            ]);
            assert_eq!(v["flooded_fraction"], want, "Q = {q}: {v}");
        }
    }

    #[test]
    fn same_seed_same_picture_bytes() {
        let dir = std::env::temp_dir().join(format!("cellsurf-cursor-cli-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut bytes = Vec::new();
        for name in ["a.png", "b.png"] {
            let p = dir.join(name);
            let out = cellsurf(&[
                "--steps",
                "20000",
                "--size",
                "40x30",
                "--wind-field",
                "bimodal",
                "--seed",
                "7",
                "--quiet",
                "--out",
                p.to_str().unwrap(),
            ]);
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            bytes.push(std::fs::read(&p).unwrap());
        }
        assert_eq!(bytes[0], bytes[1]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_input_fails_with_a_clear_message_and_no_panic() {
        let wrong = fixture("cursor_wrong_size.png");
        let cases: [(Vec<&str>, &str); 5] = [
            (vec!["--k", "1.5"], "--k = 1.5"),
            (
                vec!["--wind-field", "uniform", "--wind-speed", "300"],
                "--wind-speed = 300",
            ),
            (
                vec!["--wind-field", "calm", "--wind-arms", "3"],
                "--wind-arms",
            ),
            (
                vec!["--wind", wrong.to_str().unwrap(), "--size", "30x30"],
                "7x5",
            ),
            (vec!["--steps", "0"], "--steps = 0"),
        ];
        for (args, text) in cases {
            let out = cellsurf(&args);
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
            assert!(
                err.contains(text) && !err.contains("panicked"),
                "{args:?}: {err}"
            );
        }
    }
}

/// A palette image whose pixels name entries the palette lacks is damaged (the decoder would
/// expand them to black, calm air): refused, naming the pixel; the same image with indices in
/// the palette reads, at 8 and at 4 bits a pixel.
#[test]
fn palette_indices_beyond_the_palette_are_refused() {
    let image = |depth: png::BitDepth, row: &[u8]| {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, 4, 3);
            enc.set_color(png::ColorType::Indexed);
            enc.set_depth(depth);
            enc.set_palette(vec![200u8, 0, 0, 0, 0, 200]);
            let mut wr = enc.write_header().unwrap();
            wr.write_image_data(&[row, row, row].concat()).unwrap();
            wr.finish().unwrap();
        }
        out
    };
    let read = |b: &[u8]| WindField::from_png_bytes(b, "pal.png", None, 1.0);
    let ok = read(&image(png::BitDepth::Eight, &[0, 1, 0, 1])).unwrap();
    assert_eq!(ok.at(1, 0), Wind::from_rgb([0, 0, 200]));
    let e = read(&image(png::BitDepth::Eight, &[0, 1, 5, 1]))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("pal.png")
            && e.contains("column 2, row 0")
            && e.contains("palette index 5")
            && e.contains("2 entries"),
        "{e}"
    );
    // 4 bits a pixel: 0x01 0x10 is 0, 1, 1, 0; 0x12 puts index 2 in column 2
    assert!(read(&image(png::BitDepth::Four, &[0x01, 0x10])).is_ok());
    let e = read(&image(png::BitDepth::Four, &[0x01, 0x20]))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("column 2, row 0") && e.contains("palette index 2"),
        "{e}"
    );
}

/// The generators fit their patterns to the torus: `fitted` names every distance or direction
/// that changes (none where the size holds whole periods), and a converging radius is checked
/// against the distances the torus takes, so that no centre's radial wind is cut off.
#[test]
fn generator_patterns_say_what_fitting_the_torus_changes() {
    let bimodal = WindSpec::Bimodal {
        angle_deg: 60.0,
        speed: 100.0,
        spread_deg: 150.0,
        wavelength: 40.0,
    };
    let f = bimodal.fitted(50, 50);
    let get = |f: &[(&str, f64, f64)], n: &str| f.iter().find(|x| x.0 == n).map(|x| x.2);
    // on 50 x 50 the nearest whole wave vector is (1, 1): bands at 45 deg, 50 / sqrt 2 apart
    assert!((get(&f, "wind_wavelength").unwrap() - 50.0 / 2f64.sqrt()).abs() < 1e-9);
    assert!(
        (get(&f, "wind_angle").unwrap() - 45.0).abs() < 1e-9,
        "{f:?}"
    );
    // along x on a width of whole wavelengths: nothing changes
    let along = WindSpec::Bimodal {
        angle_deg: 90.0,
        speed: 100.0,
        spread_deg: 150.0,
        wavelength: 40.0,
    };
    assert!(
        along.fitted(120, 50).is_empty(),
        "{:?}",
        along.fitted(120, 50)
    );
    let converging = |radius: f64| WindSpec::Converging {
        angle_deg: 0.0,
        speed: 50.0,
        radial: 100.0,
        wavelength: 80.0,
        spacing: 120.0,
        radius,
    };
    // 120 cells hold 1.5 wavelengths of 80: the centres sit 60 apart, so 40 is too wide
    let f = converging(40.0).fitted(120, 120);
    assert_eq!(get(&f, "wind_wavelength"), Some(60.0));
    assert_eq!(get(&f, "wind_spacing"), None);
    let e = converging(40.0).field(120, 120).unwrap_err().to_string();
    assert!(
        e.contains("expected 1 to 30") && e.contains("60 x 120 cells"),
        "{e}"
    );
    assert!(converging(30.0).field(120, 120).is_ok());
}

// ---------------------------------------------------------------------------------------------
// Fixtures and timing (ignored).

/// Writes the PNG fixtures (run once: `cargo test --test cursor -- --ignored make_fixtures`).
#[test]
#[ignore]
fn make_fixtures() {
    fn write(name: &str, w: u32, h: u32, color: png::ColorType, data: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, w, h);
            enc.set_color(color);
            enc.set_depth(png::BitDepth::Eight);
            let mut wr = enc.write_header().unwrap();
            wr.write_image_data(data).unwrap();
            wr.finish().unwrap();
        }
        std::fs::write(fixture(name), &out).unwrap();
        out
    }
    #[rustfmt::skip]
    let wind: [u8; 36] = [
        200, 0, 0,    0, 200, 0,   0, 0, 200,   100, 100, 100,
        0, 0, 0,      255, 255, 255, 10, 0, 0,  0, 10, 0,
        0, 110, 110,  50, 0, 50,   0, 0, 0,     0, 0, 0,
    ];
    let valid = write("cursor_wind_4x3.png", 4, 3, png::ColorType::Rgb, &wind);
    write(
        "cursor_grey_5x5.png",
        5,
        5,
        png::ColorType::Grayscale,
        &[90u8; 25],
    );
    write(
        "cursor_wrong_size.png",
        7,
        5,
        png::ColorType::Rgb,
        &[0u8; 105],
    );
    let mut strong = [0u8; 27];
    strong[12] = 255;
    write("cursor_too_strong.png", 3, 3, png::ColorType::Rgb, &strong);
    std::fs::write(fixture("cursor_truncated.png"), &valid[..valid.len() / 2]).unwrap();
}

/// Times the article's 11,520,000 steps (run with `--release --ignored --nocapture`).
#[test]
#[ignore]
fn time_article_steps() {
    for name in ["calm", "uniform", "bimodal", "converging", "rotating"] {
        let field = WindSpec::article(name).unwrap().field(240, 240).unwrap();
        let tr = Transitions::new(&field, 0.95).unwrap();
        let mut walk = CursorWalk::new(&tr, 1);
        let t = std::time::Instant::now();
        walk.run(cellsurf::cursor::ARTICLE_STEPS);
        eprintln!(
            "{name:11} {:.3} s for {} steps",
            t.elapsed().as_secs_f64(),
            walk.steps()
        );
    }
}
