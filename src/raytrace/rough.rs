//! Periodic Gaussian random surfaces ([`gaussian_surface`]) and Smith's (1967) shadowing
//! function ([`smith_illuminated_fraction`]), the check of the shadow computation.
//!
//! The surface is made by spectral synthesis: complex normal deviates (`rand_distr`) on the
//! 2-D wavenumber grid, weighted by the square root of the Gaussian spectrum
//! S(k) ~ exp(-k^2 l^2 / 4) of the correlation function exp(-r^2 / l^2), transformed back with
//! `rustfft`; the real part is a stationary Gaussian field, periodic in x and y (so it tiles).
//! Its mean is removed and it is scaled so that the rms of its x-slopes (finite differences
//! between neighbouring samples) is exactly the asked `rms_slope`.

use rand::RngExt;
use rand_distr::StandardNormal;
use rustfft::num_complex::Complex;

use super::{RaytraceError, check_range, range_err};

/// Smith's (1967) illuminated fraction of a Gaussian rough surface of rms slope `s` under a
/// plane wave at grazing angle `theta` (radians) (Smith 1967, IEEE Trans. Antennas Propag. 15, 668-671):
/// mu = tan(theta) / (sqrt(2) s), Lambda = exp(-mu^2) / (2 sqrt(pi) mu) - erfc(mu) / 2,
/// fraction = (1 - erfc(mu) / 2) / (1 + Lambda). (s = 0.1: 5 deg -> 0.722, 10 deg -> 0.953.)
pub fn smith_illuminated_fraction(theta: f64, s: f64) -> f64 {
    let mu = theta.tan() / (std::f64::consts::SQRT_2 * s);
    if mu <= 0.0 {
        return 0.0;
    }
    let erfc = libm::erfc(mu);
    let lambda = (-mu * mu).exp() / (2.0 * std::f64::consts::PI.sqrt() * mu) - erfc / 2.0;
    (1.0 - erfc / 2.0) / (1.0 + lambda)
}

/// A periodic Gaussian random surface, `nx x ny` heights (y-major rows of x, m) at spacing
/// `dx`, correlation length `corr_len` (m) and rms x-slope `rms_slope` (module docs).
pub fn gaussian_surface(
    nx: usize,
    ny: usize,
    dx: f64,
    corr_len: f64,
    rms_slope: f64,
    seed: u64,
) -> Result<Vec<f64>, RaytraceError> {
    if !(4..=1 << 14).contains(&nx) || !(1..=1 << 14).contains(&ny) || nx * ny > 1 << 24 {
        return Err(range_err(
            "surface size",
            format!("{nx} x {ny}"),
            "nx in [4, 16384], ny in [1, 16384], at most 2^24 samples",
        ));
    }
    check_range("dx", dx, 1e-9, 1e6, "m")?;
    check_range(
        "correlation length",
        corr_len,
        2.0 * dx,
        nx as f64 * dx / 4.0,
        "m (2 dx to nx dx / 4)",
    )?;
    check_range("rms slope", rms_slope, 1e-6, 10.0, "")?;
    let mut rng = crate::engine::rng::stream(seed);
    let tau = std::f64::consts::TAU;
    let kx = |i: usize, n: usize| {
        let m = if i <= n / 2 {
            i as f64
        } else {
            i as f64 - n as f64
        };
        tau * m / (n as f64 * dx)
    };
    let mut a: Vec<Complex<f64>> = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let k2 = kx(i, nx).powi(2) + kx(j, ny).powi(2);
            let w = (-k2 * corr_len * corr_len / 8.0).exp();
            let re: f64 = rng.sample(StandardNormal);
            let im: f64 = rng.sample(StandardNormal);
            a.push(Complex::new(re * w, im * w));
        }
    }
    crate::ripple::spectrum::fft2(&mut a, nx, ny, true);
    let mut h: Vec<f64> = a.iter().map(|c| c.re).collect();
    let mean = h.iter().sum::<f64>() / h.len() as f64;
    let mut ss = 0.0;
    for j in 0..ny {
        for i in 0..nx {
            let d = (h[j * nx + (i + 1) % nx] - h[j * nx + i]) / dx;
            ss += d * d;
        }
    }
    let slope = (ss / (nx * ny) as f64).sqrt();
    if !(slope > 0.0 && slope.is_finite()) {
        return Err(range_err(
            "surface",
            slope,
            "a surface with non-zero slopes",
        ));
    }
    let k = rms_slope / slope;
    for v in &mut h {
        *v = (*v - mean) * k;
    }
    Ok(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smith_check_values() {
        let s = 0.1;
        let f5 = smith_illuminated_fraction(5f64.to_radians(), s);
        let f10 = smith_illuminated_fraction(10f64.to_radians(), s);
        assert!((f5 - 0.722).abs() < 5e-4, "{f5}");
        assert!((f10 - 0.953).abs() < 5e-4, "{f10}");
        assert!(smith_illuminated_fraction(80f64.to_radians(), s) > 0.9999);
    }

    #[test]
    fn surface_is_periodic_gaussian_with_the_asked_slope() {
        let (nx, ny, dx) = (512, 64, 0.01);
        let h = gaussian_surface(nx, ny, dx, 0.08, 0.1, 7).unwrap();
        assert!(h.iter().all(|v| v.is_finite()));
        let n = h.len() as f64;
        let mean = h.iter().sum::<f64>() / n;
        assert!(mean.abs() < 1e-12);
        let var = h.iter().map(|v| v * v).sum::<f64>() / n;
        let kurt = h.iter().map(|v| v.powi(4)).sum::<f64>() / n / (var * var);
        assert!((kurt - 3.0).abs() < 0.3, "kurtosis {kurt}");
        // rms height of exp(-r^2/l^2) with rms slope s: sigma = s l / sqrt(2)
        let sigma = 0.1 * 0.08 / 2f64.sqrt();
        assert!(
            (var.sqrt() / sigma - 1.0).abs() < 0.15,
            "{} vs {sigma}",
            var.sqrt()
        );
        assert!(gaussian_surface(512, 1, 0.01, 0.001, 0.1, 1).is_err());
    }
}
