//! Statistics of a height field: [`WindStats`] (mean, standard deviation, wavelengths) and the
//! power spectrum along the wind.

use rayon::prelude::*;
use serde::Serialize;

/// Summary statistics of a height field.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct WindStats {
    /// Mean height (1 up to rounding: density normalisation).
    pub height_mean: f64,
    /// Standard deviation of the height over the cells (population, numpy's `height.std()`).
    pub height_std: f64,
    /// Dominant ripple wavelength along the wind, in bins: the peak of the smoothed spectrum
    /// ([`wavelength_bins`]). `None` for a field with no variation along `y` (or `bins < 2`).
    pub wavelength_bins: Option<f64>,
    /// Spectrum-weighted mean wavelength along the wind, in bins ([`mean_wavelength_bins`]):
    /// steadier than the peak when the spectrum is broad. `None` as for `wavelength_bins`.
    pub mean_wavelength_bins: Option<f64>,
}

/// Mean, standard deviation and wavelengths of a `bins x bins` height field laid out as
/// [`WindRipples::counts`](super::WindRipples::counts). Sums run in cell order, so the result is reproducible.
pub fn height_stats(height: &[f64], bins: usize) -> WindStats {
    let m = height.len().max(1) as f64;
    let mean = compensated_sum(height.iter().copied()) / m;
    let var = compensated_sum(height.iter().map(|h| (h - mean) * (h - mean))) / m;
    let p = power_spectrum_y(height, bins);
    WindStats {
        height_mean: mean,
        height_std: var.sqrt(),
        wavelength_bins: peak_wavelength(&p, bins),
        mean_wavelength_bins: mean_wavelength(&p, bins),
    }
}

/// The sum of `v` in order, with Neumaier's compensation (error of order one rounding,
/// whatever the length).
fn compensated_sum(v: impl Iterator<Item = f64>) -> f64 {
    let (mut sum, mut c) = (0.0f64, 0.0f64);
    for x in v {
        let t = sum + x;
        if sum.abs() >= x.abs() {
            c += (sum - t) + x;
        } else {
            c += (x - t) + sum;
        }
        sum = t;
    }
    sum + c
}

/// Columns per unit of parallel work in [`power_spectrum_y`].
const SPECTRUM_GROUP: usize = 16;

/// The power spectrum of the height along the wind, summed over the columns:
/// `P(k) = sum_ix |sum_iy (h[ix, iy] - 1) exp(-2 pi i k iy / bins)|^2` for `k = 0..=bins/2`
/// (element `k`; `P(0)` is included for indexing but carries only the column means).
///
/// This is the 2-D power spectrum of the field summed over the wavenumber across the wind, so
/// crests need not be straight or aligned. Each column's DFT is a rustfft FFT with the scalar
/// planner (the same arithmetic on every machine, unlike its SIMD planners); the columns are
/// summed in fixed groups and the groups in order, so the result does not depend on the number
/// of threads. Empty for `bins = 0` or a `height` of the wrong length.
pub fn power_spectrum_y(height: &[f64], bins: usize) -> Vec<f64> {
    use rustfft::num_complex::Complex;
    let n = bins;
    if n == 0 || height.len() != n * n {
        return Vec::new();
    }
    let half = n / 2;
    let fft = rustfft::FftPlannerScalar::<f64>::new().plan_fft_forward(n);
    let groups: Vec<Vec<f64>> = height
        .par_chunks(n * SPECTRUM_GROUP)
        .map(|block| {
            let mut p = vec![0.0; half + 1];
            let mut buf = vec![Complex::new(0.0, 0.0); n];
            let mut scratch = vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()];
            for col in block.chunks_exact(n) {
                for (b, &h) in buf.iter_mut().zip(col) {
                    *b = Complex::new(h - 1.0, 0.0);
                }
                fft.process_with_scratch(&mut buf, &mut scratch);
                for (pk, b) in p.iter_mut().zip(&buf) {
                    *pk += b.norm_sqr();
                }
            }
            p
        })
        .collect();
    let mut p = vec![0.0; half + 1];
    for g in &groups {
        for (a, b) in p.iter_mut().zip(g) {
            *a += b;
        }
    }
    p
}

/// The dominant ripple wavelength along the wind (`y`), in bins, of a `bins x bins` height
/// field: the peak of [`power_spectrum_y`] smoothed over `2w + 1` wavenumbers, `w = max(1,
/// bins / 64)`, refined to the power-weighted mean wavenumber `k_hat` within that window;
/// `bins / k_hat`. Exact for a sinusoid of integer wavenumber, within about 1 % otherwise.
///
/// When the spectrum is broad with several humps of similar power (the notebook's model at 128
/// steps has nearly equal power from 2 to 6 bins), the peak can jump between them from seed to
/// seed; [`mean_wavelength_bins`] is then the steadier statistic. `None` when `bins < 2` or
/// the field does not vary along `y` (power at `k >= 1` below `1e-20` of the total: rounding).
pub fn wavelength_bins(height: &[f64], bins: usize) -> Option<f64> {
    peak_wavelength(&power_spectrum_y(height, bins), bins)
}

/// The spectrum-weighted mean wavelength along the wind, in bins:
/// `sum_k (bins / k) P(k) / sum_k P(k)` over `k = 1..=bins/2` ([`power_spectrum_y`]). Exact for
/// a sinusoid of integer wavenumber; spectral leakage biases it up by a few per cent otherwise.
/// `None` as for [`wavelength_bins`].
pub fn mean_wavelength_bins(height: &[f64], bins: usize) -> Option<f64> {
    mean_wavelength(&power_spectrum_y(height, bins), bins)
}

/// Whether the spectrum has power along the wind: `sum_{k>=1} P(k)` above rounding, i.e. above
/// `1e-20` of the total including `P(0)` (a DFT of a constant column is zero only to rounding).
fn has_power_along_y(p: &[f64]) -> bool {
    if p.len() < 2 {
        return false;
    }
    let along: f64 = p[1..].iter().sum();
    along > 0.0 && along > 1e-20 * (along + p[0])
}

fn peak_wavelength(p: &[f64], bins: usize) -> Option<f64> {
    if !has_power_along_y(p) {
        return None;
    }
    let top = p.len() - 1;
    let w = (bins / 64).max(1);
    let window = |j: usize| (j.saturating_sub(w).max(1), (j + w).min(top));
    let mut best: Option<(usize, f64)> = None;
    for j in 1..=top {
        let (lo, hi) = window(j);
        let s = p[lo..=hi].iter().sum::<f64>() / (hi - lo + 1) as f64;
        if best.is_none_or(|(_, b)| s > b) {
            best = Some((j, s));
        }
    }
    let (j, _) = best?;
    let (lo, hi) = window(j);
    let (mut num, mut den) = (0.0, 0.0);
    for (k, &pk) in p.iter().enumerate().take(hi + 1).skip(lo) {
        num += k as f64 * pk;
        den += pk;
    }
    (den > 0.0).then(|| bins as f64 / (num / den))
}

fn mean_wavelength(p: &[f64], bins: usize) -> Option<f64> {
    if !has_power_along_y(p) {
        return None;
    }
    let (mut num, mut den) = (0.0, 0.0);
    for (k, &pk) in p.iter().enumerate().skip(1) {
        num += bins as f64 / k as f64 * pk;
        den += pk;
    }
    (den > 0.0).then(|| num / den)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compensated_sum_is_exact_where_naive_summation_drifts() {
        let v = vec![0.1; 1_000_000];
        let naive: f64 = v.iter().sum();
        let good = compensated_sum(v.iter().copied());
        assert!((good - 100_000.0).abs() < 1e-9, "{good}");
        assert!((naive - 100_000.0).abs() > (good - 100_000.0).abs());
    }
}
