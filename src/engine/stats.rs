//! Statistics shared by every model's studies: the mean and its standard error over seeds
//! ([`mean_and_se`]), one point of an error-against-run-time curve ([`ConvergePoint`]) and
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
}
