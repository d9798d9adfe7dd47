//! Observables that test the growth paper's claims on a [`Growth`] state.
//!
//! - [`front_radius_cv`]: the flame front becomes round (Fig. 5): coefficient of variation of
//!   the front radius over angle.
//! - [`axis_diagonal_ratio`]: the crystal becomes a diamond (Fig. 7): extent along the axes
//!   over extent along the diagonals (support function), 1 for a disc, `sqrt(2)` for a
//!   diamond with its corners on the axes, `1/sqrt(2)` for an axis-aligned square.
//! - [`ColumnProfile`]: the deposition surface fills its trough (Fig. 6): mean elevation and
//!   the amplitude of the first Fourier mode of the surface height.
//! - [`interface_width`]: kinetic roughening on a flat substrate (a lesson beyond the paper):
//!   the interface width `w(L, t)`, the standard deviation of the column heights, which grows
//!   as `t^beta` and saturates at `L^alpha`; for the Kardar-Parisi-Zhang class in 1+1
//!   dimensions `beta = 1/3`, `alpha = 1/2` (M. Kardar, G. Parisi and Y.-C. Zhang, "Dynamic
//!   scaling of growing interfaces", Phys. Rev. Lett. 56, 889 (1986); the Eden cluster:
//!   M. Eden, "A two-dimensional growth process", Proc. 4th Berkeley Symp. Math. Stat. Prob.
//!   4, 223 (1961)).

use std::f64::consts::PI;

use crate::growth::Growth;

/// Coefficient of variation (std / mean) over `bins` angular sectors of the mean distance of
/// the surface (interface) sites from `centre` (physical coordinates; shortest way round a
/// torus). Sectors with no site are skipped. `None` when fewer than 3 sectors hold sites.
pub fn front_radius_cv(g: &Growth, centre: (f64, f64), bins: usize) -> Option<f64> {
    let bins = bins.max(3);
    let l = g.lattice();
    let mut sum = vec![0.0; bins];
    let mut cnt = vec![0usize; bins];
    for &c in g.surface().sites() {
        let (dx, dy) = l.displacement(centre, l.position(c as usize));
        let r = dx.hypot(dy);
        let a = dy.atan2(dx) + PI; // 0..2 pi
        let k = ((a / (2.0 * PI) * bins as f64) as usize).min(bins - 1);
        sum[k] += r;
        cnt[k] += 1;
    }
    let radii: Vec<f64> = sum
        .iter()
        .zip(&cnt)
        .filter(|&(_, &c)| c > 0)
        .map(|(s, &c)| s / c as f64)
        .collect();
    cv(&radii)
}

/// Coefficient of variation of a sample (population standard deviation over the mean).
pub fn cv(v: &[f64]) -> Option<f64> {
    if v.len() < 3 {
        return None;
    }
    let m = v.iter().sum::<f64>() / v.len() as f64;
    if m <= 0.0 {
        return None;
    }
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / v.len() as f64;
    Some(var.sqrt() / m)
}

/// Mean support function along the four axis directions over the mean along the four
/// diagonals, measured on the surface sites from `centre`. `None` without surface sites.
pub fn axis_diagonal_ratio(g: &Growth, centre: (f64, f64)) -> Option<f64> {
    let l = g.lattice();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let dirs = [
        (1.0, 0.0),
        (0.0, 1.0),
        (-1.0, 0.0),
        (0.0, -1.0),
        (s, s),
        (-s, s),
        (-s, -s),
        (s, -s),
    ];
    let mut h = [f64::NEG_INFINITY; 8];
    for &c in g.surface().sites() {
        let (dx, dy) = l.displacement(centre, l.position(c as usize));
        for (k, d) in dirs.iter().enumerate() {
            h[k] = h[k].max(dx * d.0 + dy * d.1);
        }
    }
    if h[0] == f64::NEG_INFINITY {
        return None;
    }
    let axes = h[..4].iter().sum::<f64>() / 4.0;
    let diag = h[4..].iter().sum::<f64>() / 4.0;
    (diag > 0.0).then_some(axes / diag)
}

/// The height of the occupied region in each column of a vertical section.
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnProfile {
    /// Physical height of the top of the highest occupied cell per column (0 if none).
    pub heights: Vec<f64>,
}

impl ColumnProfile {
    /// Scans each column from the top down to its highest occupied cell.
    pub fn of(g: &Growth) -> Self {
        let l = g.lattice();
        let (w, h) = (l.width(), l.height());
        let heights = (0..w)
            .map(|x| {
                (0..h)
                    .rev()
                    .find(|&y| g.is_occupied(l.index(x, y)))
                    .map_or(0.0, |y| l.position_xy(x, y).1 + 0.5)
            })
            .collect();
        ColumnProfile { heights }
    }

    /// Mean elevation (physical units, cell widths).
    pub fn mean(&self) -> f64 {
        self.heights.iter().sum::<f64>() / self.heights.len().max(1) as f64
    }

    /// Amplitude of the first Fourier mode of the profile over the section's width:
    /// `(2/W) |sum_x h(x) exp(-2 pi i x / W)|`, the amplitude `A` of a profile
    /// `h0 + A cos(2 pi x / W + phase)`. A single coefficient, by projection.
    pub fn mode1_amplitude(&self) -> f64 {
        let w = self.heights.len();
        if w < 2 {
            return 0.0;
        }
        let (mut re, mut im) = (0.0, 0.0);
        for (x, &h) in self.heights.iter().enumerate() {
            let a = 2.0 * PI * x as f64 / w as f64;
            re += h * a.cos();
            im -= h * a.sin();
        }
        2.0 / w as f64 * re.hypot(im)
    }
}

/// The interface width `w`: the population standard deviation of the column heights
/// ([`ColumnProfile::of`]: the top of the highest occupied cell in each column, cell widths)
/// of a vertical section grown from a flat substrate. 0 for a flat layer.
pub fn interface_width(g: &Growth) -> f64 {
    ColumnProfile::of(g).width()
}

impl ColumnProfile {
    /// Population standard deviation of the heights (cell widths): the interface width.
    pub fn width(&self) -> f64 {
        let n = self.heights.len();
        if n == 0 {
            return 0.0;
        }
        let m = self.mean();
        (self.heights.iter().map(|h| (h - m) * (h - m)).sum::<f64>() / n as f64).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::lattice::{Boundary, Lattice, Neighbourhood};
    use crate::growth::rule::{Sticking, Weight};

    fn empty(hood: Neighbourhood, w: usize, h: usize, b: Boundary) -> Growth {
        let l = Lattice::new(hood, w, h, b).unwrap();
        Growth::new(
            l,
            Sticking::new(2.0, hood.z()).unwrap(),
            Weight::Isotropic,
            false,
        )
        .unwrap()
    }

    #[test]
    fn disc_is_round_and_square_is_not() {
        let mut g = empty(Neighbourhood::Hex, 120, 140, Boundary::TORUS);
        let c = (60.0, 70.0 * 0.866);
        g.occupy_where(|x, y| (x - c.0).hypot(y - c.1) < 30.0);
        let disc_cv = front_radius_cv(&g, c, 36).unwrap();
        let disc_ratio = axis_diagonal_ratio(&g, c).unwrap();
        assert!(disc_cv < 0.02, "{disc_cv}");
        assert!((disc_ratio - 1.0).abs() < 0.03, "{disc_ratio}");
        let mut g = empty(Neighbourhood::Hex, 120, 140, Boundary::TORUS);
        g.occupy_where(|x, y| (x - c.0).abs() < 30.0 && (y - c.1).abs() < 30.0);
        let sq_cv = front_radius_cv(&g, c, 36).unwrap();
        // Square: r = a / cos(theta) over a side; CV about 0.09.
        assert!(sq_cv > 0.07 && sq_cv < 0.11, "{sq_cv}");
        let sq_ratio = axis_diagonal_ratio(&g, c).unwrap();
        assert!(
            (sq_ratio - std::f64::consts::FRAC_1_SQRT_2).abs() < 0.03,
            "{sq_ratio}"
        );
        // Diamond |x| + |y| < 30: ratio sqrt 2.
        let mut g = empty(Neighbourhood::Hex, 120, 140, Boundary::TORUS);
        g.occupy_where(|x, y| (x - c.0).abs() + (y - c.1).abs() < 30.0);
        let d = axis_diagonal_ratio(&g, c).unwrap();
        // Measured on the surface sites just outside the body: about 1.36 at this size.
        assert!((d - 2f64.sqrt()).abs() < 0.08, "{d}");
    }

    #[test]
    fn mode1_of_a_cosine_profile() {
        let mut g = empty(Neighbourhood::Square4, 64, 60, Boundary::CHANNEL);
        g.occupy_where(|x, y| y < 30.0 + 12.0 * (2.0 * PI * x / 64.0).cos());
        let p = ColumnProfile::of(&g);
        assert!(
            (p.mode1_amplitude() - 12.0).abs() < 0.6,
            "{}",
            p.mode1_amplitude()
        );
        assert!((p.mean() - 29.5).abs() < 0.6, "{}", p.mean());
        let mut g = empty(Neighbourhood::Square4, 64, 60, Boundary::CHANNEL);
        g.occupy_where(|_, y| y < 20.0);
        let p = ColumnProfile::of(&g);
        assert!(p.mode1_amplitude() < 1e-9);
        // Cells 0..=19 occupied: the top of the layer is at 19.5.
        assert_eq!(p.mean(), 19.5);
    }

    #[test]
    fn interface_width() {
        // A flat layer has width 0.
        for hood in [Neighbourhood::Square4, Neighbourhood::Hex] {
            let mut g = empty(hood, 40, 50, Boundary::CHANNEL);
            g.occupy_where(|_, y| y < 10.0);
            assert!(super::interface_width(&g) < 1e-9);
        }
        // Half the columns 6 cells higher: heights h and h + 6, standard deviation 3.
        let mut g = empty(Neighbourhood::Square4, 40, 50, Boundary::CHANNEL);
        g.occupy_where(|x, y| y < if x < 20.0 { 10.0 } else { 16.0 });
        assert!((super::interface_width(&g) - 3.0).abs() < 1e-12);
        // An overhang does not count: only the highest occupied cell of a column.
        let c = g.lattice().index(3, 30);
        g.occupy(c).unwrap();
        let p = ColumnProfile::of(&g);
        assert_eq!(p.heights[3], 30.5);
        assert!(super::interface_width(&g) > 3.0);
    }
}
