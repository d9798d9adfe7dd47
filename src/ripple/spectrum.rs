//! [`Analysis`]: ripple wavelength and orientation from the 2-D spectrum of the elevation
//! (rustfft), height, ripple index, lee and stoss slopes, and the grain size at crests and
//! troughs.
//!
//! - **Wavelength and orientation**: the elevation minus its mean is transformed with a 2-D FFT
//!   (rows then columns); the dominant wave vector is the power-weighted mean over the bins
//!   holding at least half the largest power (one of each pair k, -k). The wavelength is
//!   `1 / |k|` (k in cycles per metre, |k| power-averaged) and `crest_normal_deg` the
//!   power-weighted direction of k in degrees, in [0, 180), over the peak and its side bands
//!   (bins above a tenth of the largest power, [`ORIENTATION_POWER_FRACTION`]; averaged as a
//!   doubled angle: a wave vector and its opposite are the same ripples), comparable with
//!   `current_angle` modulo 180.
//! - **Height, slopes, symmetry**: measured ripple by ripple on profiles along the current
//!   ([`super::morphometry`]): the mean crest-to-trough height, the slope of the middle half of
//!   the lee faces (the slip face) and of the stoss faces, and the symmetry index (stoss
//!   length over lee length).
//! - **Crest and trough grain size**: the median diameter of the top automata of the columns
//!   whose smoothed height is above mean + sigma/2 (crests) or below mean - sigma/2 (troughs).

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;
use serde::Serialize;

use super::grain::median_d_mm;
use super::model::Ripple;
use super::morphometry::faces;

/// Measures of a ripple field.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Analysis {
    /// Dominant wavelength, m.
    pub wavelength_m: f64,
    /// Direction of the dominant wave vector, degrees counter-clockwise from east in [0, 180)
    /// (measured on the lattice, plus [`RippleParams::frame_angle`](super::RippleParams::frame_angle)).
    pub crest_normal_deg: f64,
    /// Ripple height, m.
    pub height_m: f64,
    /// Wavelength / height.
    pub ripple_index: f64,
    /// Mean lee slope, degrees.
    pub lee_slope_deg: f64,
    /// Mean stoss slope, degrees.
    pub stoss_slope_deg: f64,
    /// Stoss length over lee length (1: symmetric).
    pub symmetry_index: f64,
    /// Lee and stoss faces measured.
    pub faces: usize,
    /// At most one bedform per domain length along the flow: its faces were measured around
    /// the torus ([`super::morphometry::Faces::around`]) and its wavelength is the domain's
    /// length.
    pub single_bedform: bool,
    /// Median grain size of the surface automata on crests, mm.
    pub d50_crest_mm: f64,
    /// Median grain size of the surface automata in troughs, mm.
    pub d50_trough_mm: f64,
}

/// The share of the largest power above which a spectral bin counts for the orientation. On a
/// torus a few wavelengths across the wave vectors are the discrete modes `(n/Lx, m/Ly)`: a
/// field whose crests wind once across a 64 cm domain has its largest bin at 18 deg although
/// most of its crests run square to the flow, and the half-maximum cut of the wavelength would
/// read the orientation from that one mode. The orientation weighs the peak with its side
/// bands instead (the bins above a tenth of the largest power).
pub const ORIENTATION_POWER_FRACTION: f64 = 0.1;

/// The dominant wave vector of a row-major `nx x ny` field with bins `dx` m:
/// (wavelength m, direction degrees in [0, 180)). NaN for a flat field.
pub fn dominant_wave(field: &[f64], nx: usize, ny: usize, dx: f64) -> (f64, f64) {
    let mean = field.iter().sum::<f64>() / field.len() as f64;
    let mut buf: Vec<Complex<f64>> = field.iter().map(|&v| Complex::new(v - mean, 0.0)).collect();
    fft2(&mut buf, nx, ny, false);
    let freq = |i: usize, n: usize| -> f64 {
        if i <= n / 2 {
            i as f64
        } else {
            i as f64 - n as f64
        }
    };
    // The dominant peak: power-weighted mean over the bins holding at least half the largest
    // power (a wave vector and its opposite counted once, on the half plane kx > 0 or
    // kx = 0, ky > 0); the direction over the peak and its side bands, averaged as a doubled
    // angle (axial data).
    let mut bins = Vec::new();
    let mut pmax = 0.0f64;
    for y in 0..ny {
        for x in 0..nx {
            let (kx, ky) = (freq(x, nx), freq(y, ny));
            if kx < 0.0 || (kx == 0.0 && ky <= 0.0) {
                continue;
            }
            let p = buf[y * nx + x].norm_sqr();
            pmax = pmax.max(p);
            bins.push((p, kx / (nx as f64 * dx), ky / (ny as f64 * dx)));
        }
    }
    if pmax <= 1e-30 {
        return (f64::NAN, f64::NAN);
    }
    let (mut w, mut kk, mut c2, mut s2) = (0.0, 0.0, 0.0, 0.0);
    for &(p, kx, ky) in &bins {
        if p >= 0.5 * pmax {
            w += p;
            kk += p * (kx * kx + ky * ky).sqrt();
        }
        if p >= ORIENTATION_POWER_FRACTION * pmax {
            let a = ky.atan2(kx);
            c2 += p * (2.0 * a).cos();
            s2 += p * (2.0 * a).sin();
        }
    }
    let wl = w / kk;
    let ang = (0.5 * s2.atan2(c2)).to_degrees().rem_euclid(180.0);
    (wl, if ang >= 180.0 - 1e-9 { 0.0 } else { ang })
}

/// In-place 2-D FFT of a row-major `nx x ny` complex field (rows, then columns; rustfft),
/// forward or inverse (unnormalised: a forward and an inverse transform multiply by `nx ny`).
pub fn fft2(buf: &mut [Complex<f64>], nx: usize, ny: usize, inverse: bool) {
    if nx == 0 || ny == 0 || buf.len() != nx * ny {
        return;
    }
    let mut planner = FftPlanner::<f64>::new();
    let plan = |planner: &mut FftPlanner<f64>, n: usize| {
        if inverse {
            planner.plan_fft_inverse(n)
        } else {
            planner.plan_fft_forward(n)
        }
    };
    let fx = plan(&mut planner, nx);
    for row in buf.chunks_exact_mut(nx) {
        fx.process(row);
    }
    if ny > 1 {
        let fy = plan(&mut planner, ny);
        let mut col = vec![Complex::new(0.0, 0.0); ny];
        for x in 0..nx {
            for y in 0..ny {
                col[y] = buf[y * nx + x];
            }
            fy.process(&mut col);
            for y in 0..ny {
                buf[y * nx + x] = col[y];
            }
        }
    }
}

/// The 8-cell Moore average (with the cell itself) of a field on the run's lattice.
pub fn moore_average(r: &Ripple, field: &[f64]) -> Vec<f64> {
    let l = r.lattice();
    (0..field.len())
        .map(|c| {
            let mut s = field[c];
            let mut n = 1.0;
            l.for_each_neighbour(c, |m| {
                s += field[m];
                n += 1.0;
            });
            s / n
        })
        .collect()
}

/// The mean and standard deviation of a slice.
pub fn mean_std(v: &[f64]) -> (f64, f64) {
    let n = v.len().max(1) as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n;
    (m, var.sqrt())
}

impl Analysis {
    /// Measures the run's current bed.
    pub fn of(r: &Ripple) -> Analysis {
        let (nx, ny) = r.size();
        let p = r.params();
        let dx = p.bin_size;
        let elev = r.elevation();
        let (wavelength_m, lattice_normal) = dominant_wave(&elev, nx, ny, dx);
        // from the lattice's frame to east-based degrees
        // (+ 0.0: a normal of -0 deg is 0 deg)
        let crest_normal_deg = (lattice_normal + p.frame_angle()).rem_euclid(180.0) + 0.0;
        let smooth = moore_average(r, &elev);
        let (mean, sd) = mean_std(&smooth);
        // profiles along the dominant flow on the lattice (towards -x for a 2-D section run at
        // 180 deg, so that lee and stoss keep their sides; in the current's sense where waves
        // dominate it)
        let theta = p.lattice_face_angle().to_radians();
        let f = faces(&elev, nx, ny, dx, p.layer_thickness, theta);
        let vol = r.volume();
        let k = r.classes().len();
        let (mut crest, mut trough) = (vec![0u64; k], vec![0u64; k]);
        for (c, &h) in smooth.iter().enumerate() {
            if let Some(a) = vol.top(c) {
                if h >= mean + 0.5 * sd {
                    crest[a.class() as usize] += 1;
                } else if h <= mean - 0.5 * sd {
                    trough[a.class() as usize] += 1;
                }
            }
        }
        Analysis {
            wavelength_m,
            crest_normal_deg,
            height_m: f.height_m,
            ripple_index: wavelength_m / f.height_m,
            lee_slope_deg: f.lee_slope_deg,
            stoss_slope_deg: f.stoss_slope_deg,
            symmetry_index: f.symmetry_index(),
            faces: f.lee_faces + f.stoss_faces,
            single_bedform: f.around,
            d50_crest_mm: median_d_mm(r.classes(), &crest),
            d50_trough_mm: median_d_mm(r.classes(), &trough),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spectrum_finds_a_plane_wave_and_its_direction() {
        let (nx, ny, dx) = (64, 32, 0.01);
        // wave vector (4 cycles along x, 2 along y): direction atan2(2/0.32, 4/0.64) = 45 deg.
        let f: Vec<f64> = (0..nx * ny)
            .map(|i| {
                let (x, y) = ((i % nx) as f64, (i / nx) as f64);
                (2.0 * std::f64::consts::PI * (4.0 * x / nx as f64 + 2.0 * y / ny as f64)).cos()
            })
            .collect();
        let (wl, ang) = dominant_wave(&f, nx, ny, dx);
        let k = ((4.0f64 / 0.64).powi(2) + (2.0f64 / 0.32).powi(2)).sqrt();
        assert!((wl - 1.0 / k).abs() < 1e-9, "{wl}");
        assert!((ang - 45.0).abs() < 1e-6, "{ang}");
    }

    #[test]
    fn orientation_weighs_the_side_bands() {
        // A wound crest, mode (4, 1) at 14.0 deg, over straight crests, mode (4, 0), with 0.36
        // of its power: the wavelength is the half-maximum peak's, the orientation the
        // power-weighted doubled angle of both (above a tenth of the largest power), and a
        // mode below that tenth is left out.
        let (n, dx) = (64, 0.01);
        let tau = 2.0 * std::f64::consts::PI;
        let f: Vec<f64> = (0..n * n)
            .map(|i| {
                let (x, y) = ((i % n) as f64 / n as f64, (i / n) as f64 / n as f64);
                (tau * (4.0 * x + y)).cos()
                    + 0.6 * (tau * 4.0 * x).cos()
                    + 0.3 * (tau * 2.0 * y).cos()
            })
            .collect();
        let (wl, ang) = dominant_wave(&f, n, n, dx);
        let l = n as f64 * dx;
        assert!((wl - l / 17f64.sqrt()).abs() < 1e-9, "{wl}");
        let t1 = 0.25f64.atan();
        let want = (0.5 * (2.0 * t1).sin().atan2((2.0 * t1).cos() + 0.36)).to_degrees();
        assert!((ang - want).abs() < 1e-6, "{ang} against {want}");
        assert!(want > 4.0 && want < 14.0 * 0.75, "{want}");
    }
}
