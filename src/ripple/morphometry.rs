//! [`Faces`]: ripple height and lee and stoss slopes measured ripple by ripple, on profiles
//! along the current, the way bedform morphometry measures them in the field and the flume.
//!
//! - **Profiles** ([`flow_profiles`]): lines through the periodic bed along the current
//!   direction, one per row (or column, for a current closer to y), sampled with linear
//!   interpolation, ordered downstream.
//! - **Crests and troughs** ([`extrema`]): alternating maxima and minima with a hysteresis
//!   `delta`: a maximum counts once the profile has fallen `delta` below it, a minimum once it
//!   has risen `delta` above it. `delta` is two automata (the resolution of the bed is one) or
//!   half the bed's standard deviation, whichever is larger, so that roughness on a ripple is
//!   not counted as a ripple.
//! - **Faces**: from a crest down to the next trough downstream is a lee face; from a trough up
//!   to the next crest a stoss face. A face's height is its drop; its slope is measured over
//!   the middle half of the drop (between 25 % and 75 % of it below the crest), the straight
//!   part of the face: this is the slip-face angle of a lee face, without the rounded crest
//!   and the flat trough that a mean over the whole face would include.
//! - **One bedform per domain length**: where a profile holds no lee face and stoss face in
//!   one period (its crest or trough on the period's ends), the profiles run on around the torus
//!   and the faces starting in one period are measured ([`Faces::around`]).
//! - **Height** is the mean face height (crest to trough), the ripple index the spectral
//!   wavelength over it ([`super::Analysis`]).

/// Lee and stoss faces measured on a bed.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Faces {
    /// Lee faces measured.
    pub lee_faces: usize,
    /// Stoss faces measured.
    pub stoss_faces: usize,
    /// Mean crest-to-trough height of the faces (lee and stoss), m.
    pub height_m: f64,
    /// Mean slope of the middle half of the lee faces, degrees.
    pub lee_slope_deg: f64,
    /// Mean slope of the middle half of the stoss faces, degrees.
    pub stoss_slope_deg: f64,
    /// Mean horizontal length of the lee faces (crest to trough), m.
    pub lee_length_m: f64,
    /// Mean horizontal length of the stoss faces (trough to crest), m.
    pub stoss_length_m: f64,
    /// Whether the faces were measured around the torus: at most one bedform per domain length
    /// along the flow (one crest and one trough per profile), whose wavelength is then the
    /// domain's length.
    pub around: bool,
}

impl Faces {
    /// Stoss length over lee length, the ripple symmetry index: about 1 for symmetric (wave)
    /// ripples, larger for current ripples. NaN when no face was found.
    pub fn symmetry_index(&self) -> f64 {
        self.stoss_length_m / self.lee_length_m
    }
}

/// Profiles of the row-major `nx x ny` periodic field `z` (bins `dx` m) along the direction
/// `angle` (radians from +x): (samples, spacing m). Each profile runs downstream over one
/// period of the dominant axis.
pub fn flow_profiles(z: &[f64], nx: usize, ny: usize, dx: f64, angle: f64) -> (Vec<Vec<f64>>, f64) {
    flow_profiles_over(z, nx, ny, dx, angle, 1)
}

/// [`flow_profiles`] running on around the torus for `periods` periods of the dominant axis.
pub fn flow_profiles_over(
    z: &[f64],
    nx: usize,
    ny: usize,
    dx: f64,
    angle: f64,
    periods: usize,
) -> (Vec<Vec<f64>>, f64) {
    let (c, s) = (angle.cos(), angle.sin());
    if ny == 1 {
        let p = (0..periods * nx)
            .map(|j| {
                if c >= 0.0 {
                    z[j % nx]
                } else {
                    z[(nx - j % nx) % nx]
                }
            })
            .collect();
        return (vec![p], dx);
    }
    if c.abs() >= s.abs() {
        along_x(z, nx, ny, dx, c, s, periods)
    } else {
        // A current closer to y: the same march on the transposed field, x and y swapped.
        let zt: Vec<f64> = (0..nx * ny).map(|i| z[(i % ny) * nx + i / ny]).collect();
        along_x(&zt, ny, nx, dx, s, c, periods)
    }
}

/// Profiles marching along x (one per row, `|cos| >= |sin|`) over `periods` periods, y
/// drifting by `tan` per bin, with linear interpolation between rows.
fn along_x(
    z: &[f64],
    nx: usize,
    ny: usize,
    dx: f64,
    c: f64,
    s: f64,
    periods: usize,
) -> (Vec<Vec<f64>>, f64) {
    let at = |x: isize, y: isize| {
        let x = x.rem_euclid(nx as isize) as usize;
        let y = y.rem_euclid(ny as isize) as usize;
        z[y * nx + x]
    };
    let t = s / c;
    let sign = if c >= 0.0 { 1 } else { -1 };
    let profiles = (0..ny)
        .map(|y0| {
            (0..(periods * nx) as isize)
                .map(|j| {
                    let i = sign * j;
                    let yf = y0 as f64 + t * i as f64;
                    let y = yf.floor();
                    let w = yf - y;
                    (1.0 - w) * at(i, y as isize) + w * at(i, y as isize + 1)
                })
                .collect()
        })
        .collect();
    (profiles, dx / c.abs())
}

/// Alternating extrema of `p` with hysteresis `delta`: (index, is_crest), in order. Extrema
/// on the first or last sample are left out: the profile may have cut a face there.
pub fn extrema(p: &[f64], delta: f64) -> Vec<(usize, bool)> {
    let mut out = Vec::new();
    if p.is_empty() {
        return out;
    }
    let (mut hi, mut lo) = (0usize, 0usize);
    // None: direction not known yet; Some(true): looking for a crest.
    let mut seeking: Option<bool> = None;
    for i in 1..p.len() {
        match seeking {
            None => {
                if p[i] > p[hi] {
                    hi = i;
                }
                if p[i] < p[lo] {
                    lo = i;
                }
                if p[hi] - p[i] >= delta && hi < i {
                    out.push((hi, true));
                    lo = i;
                    seeking = Some(false);
                } else if p[i] - p[lo] >= delta && lo < i {
                    out.push((lo, false));
                    hi = i;
                    seeking = Some(true);
                }
            }
            Some(true) => {
                if p[i] > p[hi] {
                    hi = i;
                } else if p[hi] - p[i] >= delta {
                    out.push((hi, true));
                    lo = i;
                    seeking = Some(false);
                }
            }
            Some(false) => {
                if p[i] < p[lo] {
                    lo = i;
                } else if p[i] - p[lo] >= delta {
                    out.push((lo, false));
                    hi = i;
                    seeking = Some(true);
                }
            }
        }
    }
    out.retain(|&(i, _)| i != 0 && i + 1 != p.len());
    out
}

/// Where, from `a` towards `b` (indices), the profile first reaches `level`, as a fractional
/// index (linear interpolation between samples).
fn crossing(p: &[f64], a: usize, b: usize, level: f64) -> f64 {
    let down = p[a] > p[b];
    let reached = |v: f64| if down { v <= level } else { v >= level };
    let mut i = a;
    while i != b {
        let j = if b > a { i + 1 } else { i - 1 };
        if reached(p[j]) {
            let d = p[j] - p[i];
            let w = if d == 0.0 { 0.0 } else { (level - p[i]) / d };
            return i as f64 + w.clamp(0.0, 1.0) * (j as f64 - i as f64);
        }
        i = j;
    }
    b as f64
}

/// Measures the faces of the row-major `nx x ny` periodic bed `z` (m, bins `dx` m) along the
/// current direction `angle` (radians), with the resolution `gd` (m, one automaton).
pub fn faces(z: &[f64], nx: usize, ny: usize, dx: f64, gd: f64, angle: f64) -> Faces {
    let n = z.len().max(1) as f64;
    let mean = z.iter().sum::<f64>() / n;
    let sd = (z.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n).sqrt();
    let delta = (2.0 * gd).max(HYSTERESIS_SD * sd) * (1.0 - 1e-9);
    faces_with(z, nx, ny, dx, angle, delta)
}

/// The hysteresis of [`faces`], in standard deviations of the bed.
pub const HYSTERESIS_SD: f64 = 0.5;

/// [`faces`] with the hysteresis `delta` (m) given. Faces are found on each profile over one
/// period; where that finds no pair of a lee and a stoss face (at most one bedform per domain
/// length: the crest or the trough falls on the profile's ends, which a face cannot cross),
/// they are found on the profiles run on around the torus, counting the faces that start in
/// one period, so that a domain-long bedform is measured too ([`Faces::around`]).
pub fn faces_with(z: &[f64], nx: usize, ny: usize, dx: f64, angle: f64, delta: f64) -> Faces {
    let (profiles, step) = flow_profiles(z, nx, ny, dx, angle);
    let f = measure(&profiles, step, delta, None);
    if f.lee_faces > 0 && f.stoss_faces > 0 {
        return f;
    }
    let (long, step) = flow_profiles_over(z, nx, ny, dx, angle, 3);
    let n = long.first().map_or(0, |p| p.len() / 3);
    let g = measure(&long, step, delta, Some(n..2 * n));
    if g.lee_faces > 0 && g.stoss_faces > 0 {
        Faces { around: true, ..g }
    } else {
        f
    }
}

/// The faces of `profiles` (samples `step` m apart) with hysteresis `delta`, those starting in
/// `starts` only when given.
fn measure(
    profiles: &[Vec<f64>],
    step: f64,
    delta: f64,
    starts: Option<std::ops::Range<usize>>,
) -> Faces {
    let mut f = Faces::default();
    let (mut h, mut tl, mut ts, mut ll, mut ls) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for p in profiles {
        let ex = extrema(p, delta);
        for w in ex.windows(2) {
            let ((a, crest_a), (b, _)) = (w[0], w[1]);
            if starts.as_ref().is_some_and(|r| !r.contains(&a)) {
                continue;
            }
            let drop = (p[a] - p[b]).abs();
            let top = p[a].max(p[b]);
            let (up, lo) = (
                crossing(p, a, b, top - 0.25 * drop),
                crossing(p, a, b, top - 0.75 * drop),
            );
            let run = ((lo - up).abs() * step).max(f64::MIN_POSITIVE);
            let slope = 0.5 * drop / run;
            let length = (b - a) as f64 * step;
            h += drop;
            if crest_a {
                f.lee_faces += 1;
                tl += slope;
                ll += length;
            } else {
                f.stoss_faces += 1;
                ts += slope;
                ls += length;
            }
        }
    }
    let nf = (f.lee_faces + f.stoss_faces) as f64;
    f.height_m = h / nf;
    f.lee_slope_deg = (tl / f.lee_faces as f64).atan().to_degrees();
    f.stoss_slope_deg = (ts / f.stoss_faces as f64).atan().to_degrees();
    f.lee_length_m = ll / f.lee_faces as f64;
    f.stoss_length_m = ls / f.stoss_faces as f64;
    if f.lee_faces == 0 || f.stoss_faces == 0 {
        f.height_m = 0.0;
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sawtooth along x: stoss rising `h` over `ls` bins, lee falling `h` over `ll` bins.
    fn sawtooth(nx: usize, ny: usize, ls: usize, ll: usize, h: f64) -> Vec<f64> {
        let period = ls + ll;
        (0..nx * ny)
            .map(|i| {
                let x = (i % nx) % period;
                if x <= ls {
                    h * x as f64 / ls as f64
                } else {
                    h * (period - x) as f64 / ll as f64
                }
            })
            .collect()
    }

    #[test]
    fn sawtooth_faces_give_their_slopes_lengths_and_height() {
        let (dx, gd) = (0.005, 0.0005);
        // 24-bin period, stoss 18 bins, lee 6 bins, 12 mm high
        let z = sawtooth(96, 4, 18, 6, 0.012);
        let f = faces(&z, 96, 4, dx, gd, 0.0);
        assert!((f.height_m - 0.012).abs() < 1e-9, "{f:?}");
        let lee = (0.012f64 / (6.0 * dx)).atan().to_degrees();
        let stoss = (0.012f64 / (18.0 * dx)).atan().to_degrees();
        assert!((f.lee_slope_deg - lee).abs() < 1e-6, "{f:?} {lee}");
        assert!((f.stoss_slope_deg - stoss).abs() < 1e-6, "{f:?} {stoss}");
        assert!((f.symmetry_index() - 3.0).abs() < 1e-9, "{f:?}");
        // the same bed with the current the other way: lee and stoss swap
        let b = faces(&z, 96, 4, dx, gd, std::f64::consts::PI);
        assert!((b.lee_slope_deg - stoss).abs() < 1e-6, "{b:?}");
    }

    #[test]
    fn profiles_follow_a_current_along_y_and_a_diagonal() {
        // the sawtooth rotated to run along y: measured with a current along +y
        let (nx, ny) = (4, 96);
        let zx = sawtooth(96, 4, 18, 6, 0.012);
        let mut z = vec![0.0; nx * ny];
        for y in 0..ny {
            for x in 0..nx {
                z[y * nx + x] = zx[y];
            }
        }
        let f = faces(&z, nx, ny, 0.005, 0.0005, std::f64::consts::FRAC_PI_2);
        assert!((f.symmetry_index() - 3.0).abs() < 1e-9, "{f:?}");
        // a 45-degree profile of a field constant along the diagonal's normal is a sawtooth
        let (p, step) = flow_profiles(&vec![1.0; 64], 8, 8, 0.005, std::f64::consts::FRAC_PI_4);
        assert_eq!(p.len(), 8);
        assert!((step - 0.005 * std::f64::consts::SQRT_2).abs() < 1e-15);
    }

    #[test]
    fn roughness_below_the_hysteresis_is_not_a_ripple() {
        // one-automaton jitter on a flat bed: no faces, height 0
        let z: Vec<f64> = (0..256).map(|i| 0.0005 * ((i * 7919) % 2) as f64).collect();
        let f = faces(&z, 64, 4, 0.005, 0.0005, 0.0);
        assert_eq!((f.lee_faces, f.stoss_faces), (0, 0));
        assert_eq!(f.height_m, 0.0);
    }

    #[test]
    fn extrema_alternate() {
        let p = [0.0, 1.0, 3.0, 2.9, 1.0, 0.0, 0.2, 2.0, 0.5];
        assert_eq!(extrema(&p, 1.0), vec![(2, true), (5, false), (7, true)]);
    }

    #[test]
    fn a_domain_long_bedform_is_measured_around_the_torus() {
        // one sawtooth over the whole domain, its crest and trough away from the ends
        for shift in [0, 5, 17] {
            let base = sawtooth(24, 4, 18, 6, 0.012);
            let z: Vec<f64> = (0..24 * 4)
                .map(|i| base[(i / 24) * 24 + (i % 24 + shift) % 24])
                .collect();
            let f = faces(&z, 24, 4, 0.005, 0.0005, 0.0);
            assert!((f.height_m - 0.012).abs() < 1e-9, "{shift}: {f:?}");
            assert!(f.around, "{shift}");
            assert_eq!((f.lee_faces, f.stoss_faces), (4, 4), "{shift}");
            assert!((f.symmetry_index() - 3.0).abs() < 1e-9, "{f:?}");
            // and in 2-D, against the current
            let row = &z[..24];
            let g = faces(row, 24, 1, 0.005, 0.0005, std::f64::consts::PI);
            assert!((g.height_m - 0.012).abs() < 1e-9, "{g:?}");
            assert!((g.symmetry_index() - 1.0 / 3.0).abs() < 1e-9, "{g:?}");
        }
        // two bedforms: measured in one period, as before
        let f = faces(&sawtooth(48, 4, 18, 6, 0.012), 48, 4, 0.005, 0.0005, 0.0);
        assert!(!f.around && f.height_m > 0.0, "{f:?}");
    }
}
