//! Statistics shared by every model's studies: the mean and its standard error over seeds
//! ([`mean_and_se`]), error-against-run-time curves ([`error_curve`] of [`ConvergePoint`]s) and
//! the least-squares slope of a power law ([`loglog_slope`]).

use serde::Serialize;

/// One point of an error-against-run-time curve: the mean of an observable over the seeds
/// run so far and its standard error, against the cumulative run time.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConvergePoint {
    /// Seeds run so far.
    pub seeds: usize,
    /// Cumulative run time, seconds (single thread: wall time of the runs, set-up included).
    pub cpu_s: f64,
    /// Mean of the observable over the seeds.
    pub mean: f64,
    /// Standard error of that mean: sample standard deviation / sqrt(seeds).
    pub std_error: f64,
}

/// The error-against-run-time curve of seeds run one after another, from `(value, run time
/// in seconds)` per seed: after each seed from the second on, the mean of the values so far,
/// its standard error and the cumulative run time.
pub fn error_curve(runs: &[(f64, f64)]) -> Vec<ConvergePoint> {
    let mut values = Vec::with_capacity(runs.len());
    let mut cpu = 0.0;
    let mut points = Vec::new();
    for &(v, t) in runs {
        cpu += t;
        values.push(v);
        if values.len() >= 2 {
            let (mean, se) = mean_and_se(&values);
            points.push(ConvergePoint {
                seeds: values.len(),
                cpu_s: cpu,
                mean,
                std_error: se,
            });
        }
    }
    points
}

/// Mean and standard error of the mean (sample standard deviation / sqrt(m)).
pub fn mean_and_se(v: &[f64]) -> (f64, f64) {
    let m = v.len() as f64;
    let mean = v.iter().sum::<f64>() / m;
    if v.len() < 2 {
        return (mean, f64::NAN);
    }
    let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (m - 1.0);
    (mean, (var / m).sqrt())
}

/// Least-squares slope and intercept of `ln y` against `ln x` over the points with both
/// coordinates positive and finite; `None` with fewer than two such points.
pub fn loglog_slope(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx == 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    Some((slope, my - slope * mx))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_error_of_the_mean() {
        let (m, se) = mean_and_se(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(m, 2.5);
        // sample variance 5/3, se = sqrt(5/12)
        assert!((se - (5.0f64 / 12.0).sqrt()).abs() < 1e-15);
        assert!(mean_and_se(&[7.0]).1.is_nan());
    }

    #[test]
    fn error_curve_has_a_point_per_seed_from_the_second() {
        let c = error_curve(&[(1.0, 0.5), (3.0, 0.25), (2.0, 1.0)]);
        assert_eq!(c.len(), 2);
        assert_eq!((c[0].seeds, c[0].cpu_s, c[0].mean), (2, 0.75, 2.0));
        assert_eq!((c[1].seeds, c[1].cpu_s, c[1].mean), (3, 1.75, 2.0));
        assert!((c[1].std_error - (1.0f64 / 3.0).sqrt()).abs() < 1e-15);
    }
}
