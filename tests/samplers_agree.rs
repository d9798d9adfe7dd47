//! The rejection sampler (the paper's algorithm) and the exact rejection-free sampler run the
//! same stochastic process on the same clock (our reading of the paper's clock: one timestep is one pick), so the distribution of
//! any observable at a fixed timestep must be the same for both.
//!
//! Each test runs many independent seeds of each sampler (the seeds of the two samplers are
//! disjoint, so the two samples are independent) to a fixed time `T`, and compares the two
//! samples of each observable with three two-sample tests:
//!
//! - means: `|mean_a - mean_b| < 4 sqrt(se_a^2 + se_b^2)`, `se = s / sqrt(m)`. Under the null
//!   hypothesis the difference is approximately normal (central limit theorem, m >= 200), so a
//!   false alarm has probability about 6e-5 per comparison.
//! - variances: `|s2_a - s2_b| < 4 sqrt(se(s2_a)^2 + se(s2_b)^2)`, with the standard error of
//!   the sample variance from the fourth central moment, `se(s2)^2 = (m4 - s2^2 (m-3)/(m-1)) / m`.
//!   That form does not assume normal data (the F test does, and occupied counts are skewed);
//!   the same 4-sigma bound as for the means.
//! - whole distributions: two-sample Kolmogorov-Smirnov, `D < 1.95 sqrt((m + n) / (m n))`, the
//!   asymptotic critical value at alpha = 0.001 (`sqrt(-ln(alpha / 2) / 2) = 1.95`). The
//!   observables are integers, so the data have ties; the test is then conservative.
//!
//! A negative control (`the_comparison_detects_a_ten_percent_clock_error`) checks that these
//! tests have the power to see a real difference at these sample sizes.
//!
//! All seeds are fixed, so every run of this file is the same; the false-alarm rates above are
//! the chance that a correct implementation would have been unlucky with these seeds.

use cellsurf::engine::lattice::{Boundary, Lattice, Neighbourhood};
use cellsurf::engine::rng::stream;
use cellsurf::growth::Growth;
use cellsurf::growth::observe;
use cellsurf::growth::rule::{Sticking, Weight};
use cellsurf::growth::sampler::Outcome;
use std::sync::Arc;

/// Which sampler advances a run.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Sampler {
    Rejection,
    Exact,
}

/// Seeds of the rejection runs; the exact runs use `EXACT_SEED_BASE + k`, never overlapping.
const REJECTION_SEED_BASE: u64 = 1;
const EXACT_SEED_BASE: u64 = 1_000_001;

/// Summary statistics of one sample.
#[derive(Debug)]
struct Summary {
    m: usize,
    mean: f64,
    /// Unbiased sample variance.
    var: f64,
    /// Standard error of the mean.
    se_mean: f64,
    /// Standard error of the sample variance (from the fourth central moment).
    se_var: f64,
}

fn summary(x: &[f64]) -> Summary {
    let m = x.len();
    let mf = m as f64;
    let mean = x.iter().sum::<f64>() / mf;
    let m2 = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / mf;
    let m4 = x.iter().map(|v| (v - mean).powi(4)).sum::<f64>() / mf;
    let var = m2 * mf / (mf - 1.0);
    let se_var = ((m4 - var * var * (mf - 3.0) / (mf - 1.0)).max(0.0) / mf).sqrt();
    Summary {
        m,
        mean,
        var,
        se_mean: (var / mf).sqrt(),
        se_var,
    }
}

/// Two-sample Kolmogorov-Smirnov statistic `sup |F_a - F_b|` (ties handled by evaluating both
/// empirical distribution functions after every distinct value).
fn ks_statistic(a: &[f64], b: &[f64]) -> f64 {
    let mut a = a.to_vec();
    let mut b = b.to_vec();
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    let (mut i, mut j, mut d) = (0usize, 0usize, 0.0f64);
    while i < a.len() || j < b.len() {
        let v = match (a.get(i), b.get(j)) {
            (Some(&x), Some(&y)) => x.min(y),
            (Some(&x), None) => x,
            (None, Some(&y)) => y,
            (None, None) => unreachable!(),
        };
        while i < a.len() && a[i] <= v {
            i += 1;
        }
        while j < b.len() && b[j] <= v {
            j += 1;
        }
        d = d.max((i as f64 / a.len() as f64 - j as f64 / b.len() as f64).abs());
    }
    d
}

/// The result of the three comparisons (true = consistent with one law).
#[derive(Debug)]
struct Verdict {
    means: bool,
    variances: bool,
    ks: bool,
    report: String,
}

fn compare(name: &str, a: &[f64], b: &[f64]) -> Verdict {
    let (sa, sb) = (summary(a), summary(b));
    let mean_tol = 4.0 * (sa.se_mean.powi(2) + sb.se_mean.powi(2)).sqrt();
    let var_tol = 4.0 * (sa.se_var.powi(2) + sb.se_var.powi(2)).sqrt();
    let d = ks_statistic(a, b);
    let (m, n) = (sa.m as f64, sb.m as f64);
    let d_crit = 1.95 * ((m + n) / (m * n)).sqrt();
    Verdict {
        means: (sa.mean - sb.mean).abs() < mean_tol,
        variances: (sa.var - sb.var).abs() < var_tol,
        ks: d < d_crit,
        report: format!(
            "{name}: mean {:.3} vs {:.3} (tol {mean_tol:.3}), var {:.3} vs {:.3} (tol {var_tol:.3}), \
             KS D = {d:.4} (crit {d_crit:.4})",
            sa.mean, sb.mean, sa.var, sb.var
        ),
    }
}

/// Asserts that two samples are consistent with one law by all three tests.
fn assert_same_law(name: &str, a: &[f64], b: &[f64]) {
    let v = compare(name, a, b);
    assert!(
        v.means && v.variances && v.ks,
        "samplers disagree: {}",
        v.report
    );
    // Shown with --nocapture: how close the two samples were.
    eprintln!("{}", v.report);
}

/// Runs `runs` seeds of `sampler` to time `t` from the state `make()` and returns, per run, the
/// observables `observe(g)`. Checks that each run ends at the limit with the clock exactly `t`.
fn sample(
    make: &dyn Fn(Sampler) -> Growth,
    sampler: Sampler,
    runs: u64,
    t: f64,
    observe: &dyn Fn(&Growth) -> Vec<f64>,
) -> Vec<Vec<f64>> {
    let base = match sampler {
        Sampler::Rejection => REJECTION_SEED_BASE,
        Sampler::Exact => EXACT_SEED_BASE,
    };
    (0..runs)
        .map(|k| {
            let mut g = make(sampler);
            let mut rng = stream(base + k);
            let o = match sampler {
                Sampler::Rejection => g.run_rejection(&mut rng, t),
                Sampler::Exact => g.run_exact(&mut rng, t),
            };
            assert_eq!(o, Outcome::Limit, "{sampler:?} seed {}", base + k);
            assert_eq!(g.time(), t, "{sampler:?} clock");
            observe(&g)
        })
        .collect()
}

fn column(rows: &[Vec<f64>], k: usize) -> Vec<f64> {
    rows.iter().map(|r| r[k]).collect()
}

/// A 32 x 32 hexagonal torus with an axis-aligned square of side 6 occupied at its centre.
fn hex_square_start(n: f64, weight: Weight, per_site_weights: bool) -> Growth {
    let l = Lattice::new(Neighbourhood::Hex, 32, 32, Boundary::TORUS).unwrap();
    let (cx, cy) = hex_centre(&l);
    let mut g = Growth::new(l, Sticking::new(n, 6).unwrap(), weight, per_site_weights).unwrap();
    g.occupy_where(|x, y| (x - cx).abs() < 3.0 && (y - cy).abs() < 3.0);
    g
}

/// The physical centre of a lattice.
fn hex_centre(l: &Lattice) -> (f64, f64) {
    let (pw, ph) = l.physical_size();
    (pw / 2.0, ph / 2.0)
}

fn occupied_and_surface(g: &Growth) -> Vec<f64> {
    vec![g.occupied() as f64, g.surface().len() as f64]
}

#[test]
fn hex_torus_n2_occupied_and_surface_agree() {
    // n = 2 (the paper's flame), T = 3000 picks: about 250 acceptances per run.
    let make = |_: Sampler| hex_square_start(2.0, Weight::Isotropic, false);
    let a = sample(
        &make,
        Sampler::Rejection,
        300,
        3000.0,
        &occupied_and_surface,
    );
    let b = sample(&make, Sampler::Exact, 300, 3000.0, &occupied_and_surface);
    let initial = make(Sampler::Exact).occupied() as f64;
    // The runs did grow (otherwise the comparison would be vacuous).
    assert!(summary(&column(&a, 0)).mean > initial + 100.0);
    assert_same_law("occupied", &column(&a, 0), &column(&b, 0));
    assert_same_law("surface", &column(&a, 1), &column(&b, 1));
}

#[test]
fn n0_every_pick_is_accepted_by_both_samplers() {
    // With n = 0 every surface site has p = 1: every timestep adds exactly one cell, so the
    // occupied count at T is initial + T for both samplers, with no randomness at all. The
    // shape (hence the surface size) is random and must have one law. T = 500 keeps the
    // 32 x 32 torus (1024 cells) from filling.
    let t = 500.0;
    let make = |_: Sampler| hex_square_start(0.0, Weight::Isotropic, false);
    let initial = make(Sampler::Exact).occupied();
    let observe = |g: &Growth| {
        vec![
            g.occupied() as f64,
            g.surface().len() as f64,
            g.accepted() as f64,
        ]
    };
    let a = sample(&make, Sampler::Rejection, 300, t, &observe);
    let b = sample(&make, Sampler::Exact, 300, t, &observe);
    for (who, rows) in [("rejection", &a), ("exact", &b)] {
        for r in rows.iter() {
            assert_eq!(r[0], (initial + 500) as f64, "{who}: occupied");
            assert_eq!(r[2], 500.0, "{who}: accepted");
        }
    }
    assert_same_law("surface (n = 0)", &column(&a, 1), &column(&b, 1));
}

#[test]
fn square4_walls_n6_agree() {
    // n = 6 on a square4 lattice with walls: p = (b/4)^6 is 1/4096 for b = 1 and 1/64 for
    // b = 2, so growth is slow and dominated by filling in corners (the stiff regime the
    // rejection sampler is slow in). T = 30000 picks gives a few dozen acceptances.
    let t = 30_000.0;
    let make = |_: Sampler| {
        let l = Lattice::new(Neighbourhood::Square4, 32, 32, Boundary::WALLS).unwrap();
        let mut g =
            Growth::new(l, Sticking::new(6.0, 4).unwrap(), Weight::Isotropic, false).unwrap();
        g.occupy_where(|x, y| (x - 15.5).abs() < 3.0 && (y - 15.5).abs() < 3.0);
        assert_eq!(g.occupied(), 36);
        g
    };
    let a = sample(&make, Sampler::Rejection, 300, t, &occupied_and_surface);
    let b = sample(&make, Sampler::Exact, 300, t, &occupied_and_surface);
    assert!(summary(&column(&a, 0)).mean > 36.0 + 10.0);
    assert_same_law("occupied (square4, n = 6)", &column(&a, 0), &column(&b, 0));
    assert_same_law("surface (square4, n = 6)", &column(&a, 1), &column(&b, 1));
}

#[test]
fn eq5_axes_weight_agrees() {
    // Eq. (5) weight: the exact sampler keeps per-site weights (per_site_weights = true), the
    // rejection sampler evaluates v at each pick. Observables: occupied, surface and the
    // crystal's axis/diagonal extent ratio (a shape observable that v acts on).
    let make = |s: Sampler| {
        let l = Lattice::new(Neighbourhood::Hex, 32, 32, Boundary::TORUS).unwrap();
        let centre = hex_centre(&l);
        hex_square_start(2.0, Weight::Axes { centre }, s == Sampler::Exact)
    };
    let observe = |g: &Growth| {
        let centre = hex_centre(g.lattice());
        vec![
            g.occupied() as f64,
            g.surface().len() as f64,
            observe::axis_diagonal_ratio(g, centre).unwrap(),
        ]
    };
    let a = sample(&make, Sampler::Rejection, 300, 3000.0, &observe);
    let b = sample(&make, Sampler::Exact, 300, 3000.0, &observe);
    assert_same_law("occupied (axes)", &column(&a, 0), &column(&b, 0));
    assert_same_law("surface (axes)", &column(&a, 1), &column(&b, 1));
    assert_same_law("axis/diagonal ratio (axes)", &column(&a, 2), &column(&b, 2));
}

#[test]
fn strongly_anisotropic_custom_weight_agrees() {
    // A strongly non-uniform weight: v = 0.25 left of the centre, 1 elsewhere. The number of
    // cells added on the left is sensitive to any error in the per-site weights.
    let make = |s: Sampler| {
        let l = Lattice::new(Neighbourhood::Hex, 32, 32, Boundary::TORUS).unwrap();
        let centre = hex_centre(&l);
        let w = Weight::Custom {
            centre,
            f: Arc::new(|dx, _| if dx < 0.0 { 0.25 } else { 1.0 }),
        };
        hex_square_start(2.0, w, s == Sampler::Exact)
    };
    let observe = |g: &Growth| {
        let l = g.lattice();
        let centre = hex_centre(l);
        let left = (0..l.len())
            .filter(|&c| g.is_occupied(c) && l.displacement(centre, l.position(c)).0 < 0.0)
            .count();
        vec![g.occupied() as f64, left as f64]
    };
    let a = sample(&make, Sampler::Rejection, 300, 3000.0, &observe);
    let b = sample(&make, Sampler::Exact, 300, 3000.0, &observe);
    // The weight does act: fewer cells on the left than on the right.
    let s = summary(&column(&a, 1));
    assert!(s.mean < 0.45 * summary(&column(&a, 0)).mean, "{s:?}");
    assert_same_law("occupied (custom)", &column(&a, 0), &column(&b, 0));
    assert_same_law("left half (custom)", &column(&a, 1), &column(&b, 1));
}

#[test]
fn the_comparison_detects_a_ten_percent_clock_error() {
    // Negative control: exact runs to T = 3000 against exact runs to T = 3300 (a sampler whose
    // clock ran 10 % fast would look like this). The mean test must reject it, so the tests
    // above are not vacuous at these sample sizes.
    let make = |_: Sampler| hex_square_start(2.0, Weight::Isotropic, false);
    let a = sample(&make, Sampler::Exact, 200, 3000.0, &occupied_and_surface);
    let b: Vec<Vec<f64>> = (0..200u64)
        .map(|k| {
            let mut g = make(Sampler::Exact);
            g.run_exact(&mut stream(5_000_001 + k), 3300.0);
            occupied_and_surface(&g)
        })
        .collect();
    let v = compare("occupied, T vs 1.1 T", &column(&a, 0), &column(&b, 0));
    assert!(!v.means, "a 10 % clock error went unnoticed: {}", v.report);
    assert!(!v.ks, "a 10 % clock error went unnoticed: {}", v.report);
}

#[test]
fn statistics_helpers_are_right() {
    // The test machinery itself: KS statistic of disjoint samples is 1, of equal samples 0;
    // summary of a known sample.
    assert_eq!(ks_statistic(&[1.0, 2.0], &[3.0, 4.0]), 1.0);
    assert_eq!(ks_statistic(&[1.0, 2.0, 2.0], &[2.0, 1.0, 2.0]), 0.0);
    assert!((ks_statistic(&[1.0, 2.0, 3.0, 4.0], &[3.0, 4.0, 5.0, 6.0]) - 0.5).abs() < 1e-12);
    let s = summary(&[1.0, 2.0, 3.0, 4.0]);
    assert_eq!(s.mean, 2.5);
    assert!((s.var - 5.0 / 3.0).abs() < 1e-12);
}
