//! Dune-scale relief by spectral synthesis ([`DuneField`], [`FbmParams`], [`Relief`]) and its
//! radially averaged power spectrum ([`radial_spectrum`], [`spectrum_slope`]).
//!
//! **Fractional Brownian surface** (Saupe 1988, "Algorithms for random fractals", in The
//! Science of Fractal Images, Springer, `SpectralSynthesisFM2D`): on a periodic `nx x ny` grid with
//! spacings `dx, dy` (m), every wave vector `k = (i / (nx dx), j / (ny dy))` (cycles per metre,
//! FFT frequencies) gets the coefficient `A(K) g e^{i phi}`: a Gaussian amplitude `g`, a
//! uniform phase `phi`, and `A(K) = K^-(H + 1)` (`A(0) = 0`, zero mean), so that the power
//! spectrum is `K^-(2H + 2)` (fractal dimension `3 - H`; seafloor roughness near `H = 0.6`,
//! 2-D exponent about 3.2). Coefficients of `-k` are the complex conjugates (Hermitian
//! symmetry; the self-conjugate frequencies are real), so the inverse FFT (rustfft, rows then
//! columns, [`crate::ripple::spectrum::fft2`]) is real. Being a finite Fourier series the
//! surface is periodic, so it tiles too. The strength is the rms height: the surface is scaled
//! to it exactly.
//!
//! **Dune wavelength** (the alternative): the power is a Gaussian ring in `K` around
//! `1 / wavelength` (relative width 1/4) times `cos^2` of the angle between `k` and the current,
//! so the dunes are mostly transverse to the current, with the same random phases and
//! amplitudes.
//!
//! Between nodes the height is bicubic (Catmull-Rom) and the slope bilinear in the node
//! slopes (central differences), both periodic.

use std::f64::consts::PI;

use rand::RngExt;
use rand_distr::{Distribution, StandardNormal};
use rustfft::num_complex::Complex;

use super::TileError;
use super::seam::{SlopeAcc, SlopeStats};
use crate::engine::rng;
use crate::engine::wrap::{floor, floor_by, wrap};
use crate::ripple::spectrum::fft2;

/// The shape of the dune spectrum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Relief {
    /// Fractional Brownian surface of Hurst exponent `hurst` in (0, 1): power `K^-(2H+2)`.
    Fbm {
        /// Hurst exponent H.
        hurst: f64,
    },
    /// A band around one dune wavelength (m), crests across the current (degrees
    /// counter-clockwise from +x).
    Wavelength {
        /// Dune wavelength, m.
        wavelength: f64,
        /// Current direction, degrees.
        current_angle: f64,
    },
}

/// Parameters of a dune field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FbmParams {
    /// Nodes along x (>= 2).
    pub nx: usize,
    /// Nodes along y (>= 2).
    pub ny: usize,
    /// Node spacing along x, m (> 0).
    pub dx: f64,
    /// Node spacing along y, m (> 0).
    pub dy: f64,
    /// The spectrum.
    pub relief: Relief,
    /// Rms height, m (0 to [`MAX_RMS`]; 0 gives a flat field).
    pub rms: f64,
    /// Seed of the random stream.
    pub seed: u64,
}

/// The largest rms height of a dune field, m: far above any sea floor's dunes and sand waves
/// (tens of metres), and far below heights whose largest values no longer fit the volumes'
/// 32-bit floats.
pub const MAX_RMS: f64 = 1000.0;

/// The ranges of the relief's strength that depend on nothing else: the rms height `rms`, m
/// (0 to [`MAX_RMS`]), and the Hurst exponent of an fBm relief, in (0, 1) (`None` for a
/// relief of one wavelength). [`FbmParams::validate`] checks them, and `cellsurf tile` before
/// it makes any tile.
pub fn check_strength(rms: f64, hurst: Option<f64>) -> Result<(), TileError> {
    if !(rms.is_finite() && (0.0..=MAX_RMS).contains(&rms)) {
        let shown = crate::ripple::params::shown(rms);
        return Err(TileError::range("dune_rms", shown, "0 to 1000 m"));
    }
    if let Some(h) = hurst
        && !(h.is_finite() && h > 0.0 && h < 1.0)
    {
        return Err(TileError::range("hurst", h, "0 < H < 1"));
    }
    Ok(())
}

impl FbmParams {
    /// Checks every range.
    pub fn validate(&self) -> Result<(), TileError> {
        for (name, n) in [("dune grid nx", self.nx), ("dune grid ny", self.ny)] {
            if !(2..=1 << 14).contains(&n) {
                return Err(TileError::range(name, n, "2 ..= 16384 nodes"));
            }
        }
        for (name, d) in [("dune grid dx", self.dx), ("dune grid dy", self.dy)] {
            if !(d.is_finite() && d > 0.0) {
                return Err(TileError::range(name, d, "> 0 m"));
            }
        }
        let hurst = match self.relief {
            Relief::Fbm { hurst } => Some(hurst),
            Relief::Wavelength { .. } => None,
        };
        check_strength(self.rms, hurst)?;
        match self.relief {
            Relief::Fbm { .. } => {}
            Relief::Wavelength {
                wavelength,
                current_angle,
            } => {
                let lo = 4.0 * self.dx.max(self.dy);
                let hi = (self.nx as f64 * self.dx).min(self.ny as f64 * self.dy);
                if !(wavelength.is_finite() && wavelength >= lo && wavelength <= hi) {
                    return Err(TileError::range(
                        "dune_wavelength",
                        wavelength,
                        format!(
                            "{lo} ..= {hi} m (4 dune-grid spacings to the smaller side of the surface)"
                        ),
                    ));
                }
                if !current_angle.is_finite() {
                    return Err(TileError::range(
                        "current_angle",
                        current_angle,
                        "a finite angle in degrees",
                    ));
                }
            }
        }
        Ok(())
    }
}

/// The signed FFT frequency index of `i` on `n` points.
#[inline]
fn freq(i: usize, n: usize) -> f64 {
    if i <= n / 2 {
        i as f64
    } else {
        i as f64 - n as f64
    }
}

/// The spectral amplitude `A(k)` (square root of the power) at wave vector `(kx, ky)`, cycles
/// per metre.
fn amplitude(relief: Relief, kx: f64, ky: f64) -> f64 {
    let k = (kx * kx + ky * ky).sqrt();
    if k == 0.0 {
        return 0.0;
    }
    match relief {
        Relief::Fbm { hurst } => k.powf(-(hurst + 1.0)),
        Relief::Wavelength {
            wavelength,
            current_angle,
        } => {
            let k0 = 1.0 / wavelength;
            let s = 0.25 * k0;
            let a = current_angle.to_radians();
            let c = (kx * a.cos() + ky * a.sin()) / k;
            let p = (-0.5 * ((k - k0) / s).powi(2)).exp() * c * c;
            p.sqrt()
        }
    }
}

/// The complex field of the synthesis before taking the real part (its imaginary part is
/// rounding noise when the Hermitian symmetry holds), unscaled.
pub(crate) fn synthesize_complex(p: &FbmParams) -> Vec<Complex<f64>> {
    let (nx, ny) = (p.nx, p.ny);
    let mut rng = rng::stream(p.seed);
    let mut buf = vec![Complex::new(0.0, 0.0); nx * ny];
    let (lx, ly) = (nx as f64 * p.dx, ny as f64 * p.dy);
    for j in 0..ny {
        for i in 0..nx {
            let idx = j * nx + i;
            let (mi, mj) = ((nx - i) % nx, (ny - j) % ny);
            let mirror = mj * nx + mi;
            if mirror < idx {
                continue; // set as the conjugate of its mirror
            }
            let a = amplitude(p.relief, freq(i, nx) / lx, freq(j, ny) / ly);
            let g: f64 = StandardNormal.sample(&mut rng);
            if mirror == idx {
                // self-conjugate (k = -k modulo the grid): a real coefficient
                buf[idx] = Complex::new(a * g, 0.0);
            } else {
                let phi = 2.0 * PI * rng.random::<f64>();
                let c = Complex::from_polar(a * g, phi);
                buf[idx] = c;
                buf[mirror] = c.conj();
            }
        }
    }
    fft2(&mut buf, nx, ny, true);
    buf
}

/// The Catmull-Rom cubic through `p[1]` (`t = 0`) and `p[2]` (`t = 1`) with the end slopes
/// `(p[2] - p[0]) / 2` and `(p[3] - p[1]) / 2` (Catmull & Rom 1974, "A class of local
/// interpolating splines", in Computer Aided Geometric Design, Academic Press), in Horner form.
#[inline(always)]
fn catmull_rom(p: [f64; 4], t: f64) -> f64 {
    p[1] + 0.5
        * t
        * (p[2] - p[0]
            + t * (2.0 * p[0] - 5.0 * p[1] + 4.0 * p[2] - p[3]
                + t * (3.0 * (p[1] - p[2]) + p[3] - p[0])))
}

/// A periodic dune relief on a grid of nodes (node `(i, j)` at `(i dx, j dy)` m).
#[derive(Clone, Debug, PartialEq)]
pub struct DuneField {
    /// Nodes along x.
    pub nx: usize,
    /// Nodes along y.
    pub ny: usize,
    /// Spacing along x, m.
    pub dx: f64,
    /// Spacing along y, m.
    pub dy: f64,
    /// Heights, m, row-major; zero mean.
    pub h: Vec<f64>,
    gx: Vec<f64>,
    gy: Vec<f64>,
}

impl DuneField {
    /// Synthesises the relief of `p` (see the module documentation).
    pub fn synthesize(p: &FbmParams) -> Result<DuneField, TileError> {
        p.validate()?;
        let c = synthesize_complex(p);
        let mut h: Vec<f64> = c.iter().map(|v| v.re).collect();
        let n = h.len() as f64;
        let mean = h.iter().sum::<f64>() / n;
        let rms = (h.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
        let scale = if rms > 0.0 { p.rms / rms } else { 0.0 };
        for v in &mut h {
            *v = (*v - mean) * scale;
        }
        Self::from_grid(p.nx, p.ny, p.dx, p.dy, h)
    }

    /// A field from given heights (row-major `nx x ny`, m).
    pub fn from_grid(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        h: Vec<f64>,
    ) -> Result<DuneField, TileError> {
        if nx < 2 || ny < 2 || h.len() != nx * ny {
            return Err(TileError::range(
                "dune grid",
                format!("{nx}x{ny} with {} values", h.len()),
                "at least 2x2 nodes and nx x ny values",
            ));
        }
        if let Some(v) = h.iter().find(|v| !v.is_finite()) {
            return Err(TileError::range("dune height", v, "finite heights"));
        }
        let at = |i: usize, j: usize| h[(j % ny) * nx + i % nx];
        let mut gx = vec![0.0; nx * ny];
        let mut gy = vec![0.0; nx * ny];
        for j in 0..ny {
            for i in 0..nx {
                gx[j * nx + i] = (at(i + 1, j) - at(i + nx - 1, j)) / (2.0 * dx);
                gy[j * nx + i] = (at(i, j + 1) - at(i, j + ny - 1)) / (2.0 * dy);
            }
        }
        Ok(DuneField {
            nx,
            ny,
            dx,
            dy,
            h,
            gx,
            gy,
        })
    }

    /// Period along x and y, m.
    pub fn period(&self) -> (f64, f64) {
        (self.nx as f64 * self.dx, self.ny as f64 * self.dy)
    }

    fn bilinear(&self, v: &[f64], x: f64, y: f64) -> f64 {
        let (fx, fy) = (x / self.dx, y / self.dy);
        let (x0, y0) = (fx.floor(), fy.floor());
        let (ax, ay) = (fx - x0, fy - y0);
        let i0 = (x0 as i64).rem_euclid(self.nx as i64) as usize;
        let j0 = (y0 as i64).rem_euclid(self.ny as i64) as usize;
        let (i1, j1) = ((i0 + 1) % self.nx, (j0 + 1) % self.ny);
        let at = |i: usize, j: usize| v[j * self.nx + i];
        (1.0 - ay) * ((1.0 - ax) * at(i0, j0) + ax * at(i1, j0))
            + ay * ((1.0 - ax) * at(i0, j1) + ax * at(i1, j1))
    }

    /// Height at `(x, y)` m, periodic: bicubic (Catmull-Rom) between nodes, so that it passes
    /// through the nodes and its slope is continuous (bilinear facets would show in shaded
    /// relief and in the acoustic normals).
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let (fx, fy) = (x / self.dx, y / self.dy);
        let (x0, y0) = (floor(fx), floor(fy));
        let (tx, ty) = (fx - x0, fy - y0);
        let (nx, ny) = (self.nx, self.ny);
        let i: [usize; 4] = std::array::from_fn(|d| wrap(x0 as i64 + d as i64 - 1, nx));
        let mut col = [0.0; 4];
        for (k, c) in col.iter_mut().enumerate() {
            let j = wrap(y0 as i64 + k as i64 - 1, ny);
            let row = &self.h[j * self.nx..(j + 1) * self.nx];
            *c = catmull_rom([row[i[0]], row[i[1]], row[i[2]], row[i[3]]], tx);
        }
        catmull_rom(col, ty)
    }

    /// The x node cell of the bins of a row for [`DuneField::height_row`]: for bin `k` at
    /// `k step` m (`k < n`), the node column `i` at or left of it and its offset `tx` in `[0, 1)`
    /// from there, as [`DuneField::height`] computes them.
    pub(crate) fn row_cells(&self, step: f64, n: usize) -> Vec<(u32, f64)> {
        (0..n)
            .map(|k| {
                let fx = (k as f64 * step) / self.dx;
                let x0 = floor(fx);
                (wrap(x0 as i64, self.nx) as u32, fx - x0)
            })
            .collect()
    }

    /// [`DuneField::height`] along a row: `out[k] = height(k step, y)`, bit for bit, with
    /// `cells` from [`DuneField::row_cells`] for the same `step`. The four node rows round `y`
    /// get their Catmull-Rom coefficients along x once per node column (the same operations in
    /// the same order as `height`), so a bin costs four cubics in x and one in y.
    #[inline(always)]
    pub(crate) fn height_row<const LIB: bool>(
        &self,
        y: f64,
        cells: &[(u32, f64)],
        out: &mut [f64],
    ) {
        let fy = y / self.dy;
        let y0 = floor_by::<LIB>(fy);
        let ty = fy - y0;
        let nx = self.nx;
        let rows: [&[f64]; 4] = std::array::from_fn(|k| {
            let j = wrap(y0 as i64 + k as i64 - 1, self.ny);
            &self.h[j * nx..(j + 1) * nx]
        });
        // per node column i, per row: (p1, p2 - p0, 2 p0 - 5 p1 + 4 p2 - p3, 3 (p1 - p2) + p3 - p0)
        let mut coef = vec![[[0.0; 4]; 4]; nx];
        for (i, c) in coef.iter_mut().enumerate() {
            let (im, ip, ip2) = ((i + nx - 1) % nx, (i + 1) % nx, (i + 2) % nx);
            for (c, r) in c.iter_mut().zip(rows) {
                let p = [r[im], r[i], r[ip], r[ip2]];
                *c = [
                    p[1],
                    p[2] - p[0],
                    2.0 * p[0] - 5.0 * p[1] + 4.0 * p[2] - p[3],
                    3.0 * (p[1] - p[2]) + p[3] - p[0],
                ];
            }
        }
        for (o, &(i, tx)) in out.iter_mut().zip(cells) {
            let c = &coef[i as usize];
            let col = c.map(|[p1, a, b, d]| p1 + 0.5 * tx * (a + tx * (b + tx * d)));
            *o = catmull_rom(col, ty);
        }
    }

    /// Slope `(dh/dx, dh/dy)` at `(x, y)` m: central differences at the nodes, bilinear between.
    pub fn gradient(&self, x: f64, y: f64) -> (f64, f64) {
        (self.bilinear(&self.gx, x, y), self.bilinear(&self.gy, x, y))
    }

    /// Slopes of the relief at its nodes (central differences), against the angle of repose.
    pub fn slope_stats(&self) -> SlopeStats {
        let mut acc = SlopeAcc::default();
        for (&gx, &gy) in self.gx.iter().zip(&self.gy) {
            acc.push(gx, gy);
        }
        acc.stats()
    }

    /// Rms height, m.
    pub fn rms(&self) -> f64 {
        let n = self.h.len() as f64;
        let m = self.h.iter().sum::<f64>() / n;
        (self.h.iter().map(|v| (v - m).powi(2)).sum::<f64>() / n).sqrt()
    }
}

/// The radially averaged power spectrum of a periodic row-major `nx x ny` field with spacings
/// `dx, dy` (m): `(K, P)` pairs, `K` the mean wavenumber (cycles/m) of a ring of width
/// `dk = max(1 / (nx dx), 1 / (ny dy))` and `P` the mean `|F(k)|^2` over the ring, for the rings
/// from `dk` up to the smaller Nyquist frequency. The mean is removed first.
pub fn radial_spectrum(field: &[f64], nx: usize, ny: usize, dx: f64, dy: f64) -> Vec<(f64, f64)> {
    if nx == 0 || ny == 0 || field.len() != nx * ny {
        return Vec::new();
    }
    let mean = field.iter().sum::<f64>() / field.len() as f64;
    let mut buf: Vec<Complex<f64>> = field.iter().map(|&v| Complex::new(v - mean, 0.0)).collect();
    fft2(&mut buf, nx, ny, false);
    let (lx, ly) = (nx as f64 * dx, ny as f64 * dy);
    let dk = (1.0 / lx).max(1.0 / ly);
    let kmax = (0.5 / dx).min(0.5 / dy);
    let rings = (kmax / dk).floor() as usize + 1;
    let mut sk = vec![0.0; rings];
    let mut sp = vec![0.0; rings];
    let mut n = vec![0usize; rings];
    for j in 0..ny {
        for i in 0..nx {
            let (kx, ky) = (freq(i, nx) / lx, freq(j, ny) / ly);
            let k = (kx * kx + ky * ky).sqrt();
            let r = (k / dk).round() as usize;
            if r == 0 || r >= rings || k > kmax {
                continue;
            }
            sk[r] += k;
            sp[r] += buf[j * nx + i].norm_sqr();
            n[r] += 1;
        }
    }
    (1..rings)
        .filter(|&r| n[r] > 0)
        .map(|r| (sk[r] / n[r] as f64, sp[r] / n[r] as f64))
        .collect()
}

/// The least-squares slope of `ln P` against `ln K` over the pairs with `kmin <= K <= kmax`
/// and `P > 0`; `None` with fewer than 3 of them.
pub fn spectrum_slope(spec: &[(f64, f64)], kmin: f64, kmax: f64) -> Option<f64> {
    let pts: Vec<(f64, f64)> = spec
        .iter()
        .copied()
        .filter(|(k, p)| *k >= kmin && *k <= kmax && *p > 0.0)
        .collect();
    if pts.len() < 3 {
        return None;
    }
    crate::engine::stats::loglog_slope(&pts).map(|(slope, _)| slope)
}

/// The measured spectral slope of a dune field over the rings from 2 fundamental ring widths to
/// half the Nyquist frequency (the range used throughout: it avoids the few lowest rings and
/// the corners of the grid).
pub fn measured_slope(f: &DuneField) -> Option<f64> {
    let spec = radial_spectrum(&f.h, f.nx, f.ny, f.dx, f.dy);
    let (lx, ly) = f.period();
    let dk = (1.0 / lx).max(1.0 / ly);
    let kmax = 0.25 / f.dx.max(f.dy);
    spectrum_slope(&spec, 2.0 * dk, kmax)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fbm(n: usize, hurst: f64, seed: u64) -> FbmParams {
        FbmParams {
            nx: n,
            ny: n,
            dx: 1.0,
            dy: 1.0,
            relief: Relief::Fbm { hurst },
            rms: 0.5,
            seed,
        }
    }

    #[test]
    fn hermitian_symmetry_makes_the_synthesis_real() {
        for (nx, ny) in [(64, 64), (33, 20), (2, 2)] {
            let p = FbmParams {
                nx,
                ny,
                ..fbm(64, 0.6, 3)
            };
            let c = synthesize_complex(&p);
            let re = c.iter().map(|v| v.re.abs()).fold(0.0, f64::max);
            let im = c.iter().map(|v| v.im.abs()).fold(0.0, f64::max);
            assert!(re > 0.0);
            assert!(im <= 1e-12 * re, "{nx}x{ny}: imaginary {im} vs real {re}");
        }
    }

    #[test]
    fn strength_is_the_rms_height() {
        let f = DuneField::synthesize(&fbm(64, 0.6, 1)).unwrap();
        assert!((f.rms() - 0.5).abs() < 1e-9);
        assert!(f.h.iter().sum::<f64>().abs() < 1e-9);
        let flat = DuneField::synthesize(&FbmParams {
            rms: 0.0,
            ..fbm(16, 0.6, 1)
        })
        .unwrap();
        assert!(flat.h.iter().all(|&v| v == 0.0));
    }

    #[test]
    fn cubic_height_hits_the_nodes_and_wraps() {
        let f = DuneField::synthesize(&FbmParams {
            dx: 0.5,
            dy: 0.25,
            ..fbm(16, 0.6, 2)
        })
        .unwrap();
        for (i, j) in [(0, 0), (3, 7), (15, 15)] {
            let h = f.height(i as f64 * 0.5, j as f64 * 0.25);
            assert!((h - f.h[j * 16 + i]).abs() < 1e-12);
        }
        let (lx, ly) = f.period();
        assert!((f.height(1.3, 0.7) - f.height(1.3 - lx, 0.7 + 2.0 * ly)).abs() < 1e-12);
        // a linear ramp along x (inside one period) is reproduced between nodes
        let ramp: Vec<f64> = (0..64).map(|c| (c % 8) as f64).collect();
        let r = DuneField::from_grid(8, 8, 1.0, 1.0, ramp).unwrap();
        assert!((r.height(3.25, 2.5) - 3.25).abs() < 1e-12);
    }

    #[test]
    fn slope_of_an_exact_power_law() {
        let spec: Vec<(f64, f64)> = (1..50).map(|k| (k as f64, (k as f64).powf(-3.2))).collect();
        let s = spectrum_slope(&spec, 1.0, 50.0).unwrap();
        assert!((s + 3.2).abs() < 1e-12, "{s}");
        assert_eq!(spectrum_slope(&spec[..2], 0.0, 100.0), None);
    }

    #[test]
    fn out_of_range_parameters_are_named() {
        let e = DuneField::synthesize(&fbm(64, 1.5, 1)).unwrap_err();
        assert!(e.to_string().starts_with("hurst = 1.5"), "{e}");
        let e = DuneField::synthesize(&fbm(1, 0.5, 1)).unwrap_err();
        assert!(e.to_string().contains("dune grid nx = 1"), "{e}");
        let e = DuneField::synthesize(&FbmParams {
            relief: Relief::Wavelength {
                wavelength: 1000.0,
                current_angle: 0.0,
            },
            ..fbm(64, 0.5, 1)
        })
        .unwrap_err();
        assert!(e.to_string().starts_with("dune_wavelength = 1000"), "{e}");
    }
}
