//! The sticking rule of the growth paper: `p = v(x, y) (b/z)^n`.
//!
//! [`Sticking`] holds the power-law part (Eq. 4 generalised to a neighbourhood of `z` cells)
//! with tables for fast and underflow-free evaluation; [`Weight`] is the pluggable
//! direction weight `v` (isotropic, the paper's Eq. 5, or any user function).

use std::fmt;
use std::sync::Arc;

use thiserror::Error;

use crate::engine::lattice::Lattice;

/// Errors in the sticking rule's parameters.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RuleError {
    /// The exponent is negative or not finite.
    #[error("n = {0} is out of range: expected a finite power-law exponent >= 0")]
    Exponent(f64),
    /// The neighbourhood size is not supported.
    #[error("neighbourhood size z = {0} is out of range: expected 1 to 8")]
    NeighbourhoodSize(usize),
    /// A weight function returned a value outside [0, 1].
    #[error(
        "weight v = {value} at position ({x:.3}, {y:.3}) is out of range: expected a value in [0, 1] (v multiplies a probability)"
    )]
    WeightValue {
        /// The value returned.
        value: f64,
        /// Physical x of the site.
        x: f64,
        /// Physical y of the site.
        y: f64,
    },
    /// The weight name is not known.
    #[error("unknown weight '{0}': expected none (v = 1) or axes (Eq. 5)")]
    UnknownWeight(String),
}

/// The power-law sticking probability `(b/z)^n` of Eq. (4), for `b = 0..=z`.
///
/// `b` is the number of occupied neighbours of the candidate (empty) site, `z` the
/// neighbourhood size, `n >= 0` the power. Besides the plain probabilities it keeps the
/// ratios `(b/b_ref)^n` for every pair, which never overflow and underflow only where the
/// true ratio is below `1e-308`: the exact sampler works with those, so that `n = 1e4` is
/// sampled correctly even though `(1/6)^n` is `0` in `f64`.
#[derive(Clone, Debug)]
pub struct Sticking {
    n: f64,
    z: usize,
    /// `p[b] = (b/z)^n` (may underflow to 0 for large n).
    p: [f64; 9],
    /// `ln p[b] = n ln(b/z)` (finite for b >= 1, `-inf` for b = 0).
    ln_p: [f64; 9],
    /// `ratio[r][b] = (b/r)^n` for `b <= r`.
    ratio: [[f64; 9]; 9],
    /// `inv_ratio[r][b] = 1 / ratio[r][b]` where that ratio is a normal float (else 0).
    inv_ratio: [[f64; 9]; 9],
    /// For a whole `n >= 1` with `z^n <= 2^35`: `int_w[b] = b^n`, the weights `(b/z)^n` times
    /// `z^n`, exact integers (a class's count times its weight, summed over the classes of a
    /// lattice of fewer than 2^28 cells, stays below 2^63); `None` otherwise.
    int_w: Option<[u64; 9]>,
    /// With `int_w`: `int_recip[b] = ceil(2^64 / int_w[b])` for a weight of 2 to 2^32, the
    /// multiplier that divides a number below 2^32 by the weight with one multiplication
    /// ([`Sticking::int_quotient`]); 0 for a weight of 1 or above 2^32.
    int_recip: [u64; 9],
    /// With `int_w`: all ones where `int_w[b]` is 1 (the quotient is the number itself), else 0.
    int_one: [u64; 9],
    /// With `int_w`: `z^n` as an `f64` (exact, at most 2^35); 1 otherwise.
    int_total: f64,
}

/// The largest `z^n` for which [`Sticking::int_weights`] are kept (so that a lattice of fewer
/// than 2^28 cells sums its sites' integer weights below 2^63).
pub const MAX_INT_WEIGHT: u64 = 1 << 35;

impl Sticking {
    /// The rule for exponent `n` (>= 0, finite) on a neighbourhood of `z` cells (1..=8).
    pub fn new(n: f64, z: usize) -> Result<Self, RuleError> {
        if !n.is_finite() || n < 0.0 {
            return Err(RuleError::Exponent(n));
        }
        if !(1..=8).contains(&z) {
            return Err(RuleError::NeighbourhoodSize(z));
        }
        let mut p = [0.0; 9];
        let mut ln_p = [f64::NEG_INFINITY; 9];
        let mut ratio = [[0.0; 9]; 9];
        for b in 1..=z {
            p[b] = power_law(b, z, n);
            ln_p[b] = n * (b as f64 / z as f64).ln();
        }
        for (r, row) in ratio.iter_mut().enumerate().take(z + 1).skip(1) {
            for (b, x) in row.iter_mut().enumerate().take(r + 1).skip(1) {
                *x = (n * (b as f64 / r as f64).ln()).exp();
            }
        }
        // (a subnormal ratio's reciprocal may overflow: those classes keep the division)
        let inv_ratio = ratio.map(|row| row.map(|x| if x.is_normal() { 1.0 / x } else { 0.0 }));
        let int_w = (n >= 1.0 && n.fract() == 0.0 && n <= 64.0)
            .then(|| (z as u64).checked_pow(n as u32))
            .flatten()
            .filter(|&zn| zn <= MAX_INT_WEIGHT)
            .map(|_| {
                let mut w = [0u64; 9];
                for (b, x) in w.iter_mut().enumerate().take(z + 1) {
                    *x = (b as u64).pow(n as u32);
                }
                w
            });
        let int_recip = int_w.map_or([0; 9], |w| {
            w.map(|d| {
                if (2..=1 << 32).contains(&d) {
                    // ceil(2^64 / d): at most 2^63 for d >= 2
                    (u64::MAX / d) + 1
                } else {
                    0
                }
            })
        });
        let int_one = int_w.map_or([0; 9], |w| w.map(|d| if d == 1 { u64::MAX } else { 0 }));
        let int_total = int_w.map_or(1.0, |w| w[z] as f64);
        Ok(Sticking {
            n,
            z,
            p,
            ln_p,
            ratio,
            inv_ratio,
            int_w,
            int_recip,
            int_one,
            int_total,
        })
    }

    /// The exponent `n`.
    pub fn n(&self) -> f64 {
        self.n
    }
    /// The neighbourhood size `z`.
    pub fn z(&self) -> usize {
        self.z
    }
    /// True when every surface site has the same `p` (`n = 0`: `p = 1` for every `b >= 1`).
    #[inline]
    pub fn is_uniform(&self) -> bool {
        self.n == 0.0
    }
    /// `(b/z)^n` (Eq. 4). Zero for `b = 0`: a site with no occupied neighbour is not on the
    /// surface.
    #[inline]
    pub fn p(&self, b: usize) -> f64 {
        self.p[b]
    }
    /// `n ln(b/z)`, the logarithm of [`Sticking::p`], finite even where `p` underflows.
    #[inline]
    pub fn ln_p(&self, b: usize) -> f64 {
        self.ln_p[b]
    }
    /// The row `(b/r)^n`, `b = 0..=8` (zero above `r`).
    #[inline]
    pub fn ratio_row(&self, r: usize) -> &[f64; 9] {
        &self.ratio[r]
    }
    /// `(b/r)^n` for `1 <= b <= r`: the weight of class `b` relative to class `r`.
    #[inline]
    pub fn ratio(&self, r: usize, b: usize) -> f64 {
        self.ratio[r][b]
    }
    /// The class weights `b^n` as exact integers (`b = 0..=8`, zero above `z`) for a whole
    /// `n >= 1` with `z^n` at most [`MAX_INT_WEIGHT`]; `None` otherwise. They are proportional to
    /// `(b/z)^n` (Eq. 4) with the factor `z^n`, so the exact sampler draws the class and the
    /// site with one integer draw and no rounding.
    #[inline]
    pub fn int_weights(&self) -> Option<&[u64; 9]> {
        self.int_w.as_ref()
    }
    /// `z^n` as an `f64` (exact: at most 2^35), the factor between the whole-number weights
    /// and the probabilities: `P = sum_b m_b int_w[b] / (z^n S)`. Needs
    /// [`Sticking::int_weights`] (else 1).
    #[inline]
    pub fn int_weight_total(&self) -> f64 {
        self.int_total
    }
    /// `r / int_w[b]` rounded down, for any `r`: the slot within class `b` of the exact
    /// sampler's integer draw (`r`, the remainder after the classes above).
    /// A number below 2^32 is divided by a weight of 2 to 2^32 as `(r m) >> 64` with `m =
    /// ceil(2^64 / w)`: `m w = 2^64 + e` with `0 <= e < w`, so `r m / 2^64 = r / w + r e /
    /// (w 2^64)`, and `r e < 2^64` keeps the second term below `1 / w`, too little to carry
    /// `r / w` past a whole number (test `int_quotient_is_the_division`). The multiplication
    /// takes about a third of a division's latency, on the path from one event to the next.
    /// Needs [`Sticking::int_weights`].
    #[inline]
    pub fn int_quotient(&self, r: u64, b: usize) -> u64 {
        let (m, one) = (self.int_recip[b], self.int_one[b]);
        if r >> 32 == 0 && (m | one) != 0 {
            // (a weight of 1 has m = 0 and takes r itself, without a branch on the class)
            ((u128::from(r) * u128::from(m)) >> 64) as u64 | (r & one)
        } else {
            r / self.int_w.as_ref().map_or(1, |w| w[b])
        }
    }
    /// `(r/b)^n`, the reciprocal of [`Sticking::ratio`], where that ratio is a normal float;
    /// 0 where it is subnormal or zero (divide by the ratio there).
    #[inline]
    pub fn inv_ratio(&self, r: usize, b: usize) -> f64 {
        self.inv_ratio[r][b]
    }
}

/// Eq. (4) of the growth paper, generalised: `p = (b/z)^n`, b = occupied neighbours.
/// `n = 0` gives 1 for every surface site (b >= 1).
pub fn power_law(b: usize, z: usize, n: f64) -> f64 {
    if b == 0 {
        0.0
    } else {
        (b as f64 / z as f64).powf(n)
    }
}

/// Eq. (5) of the growth paper: `v = sqrt(x^2 + y^2) / (|x| + |y|)`, with `(x, y)` the
/// site's position relative to the seed centre; 1 along the coordinate axes, `1/sqrt(2)`
/// where `|x| = |y|`, and 1 at the centre itself.
pub fn axes_weight(x: f64, y: f64) -> f64 {
    let l1 = x.abs() + y.abs();
    if l1 == 0.0 { 1.0 } else { x.hypot(y) / l1 }
}

/// A user weight function `v(x, y)` of the physical position relative to the centre.
pub type WeightFn = Arc<dyn Fn(f64, f64) -> f64 + Send + Sync>;

/// The direction weight `v(x, y)` that multiplies the sticking probability.
#[derive(Clone, Default)]
pub enum Weight {
    /// `v = 1` everywhere (Eq. 4).
    #[default]
    Isotropic,
    /// Eq. (5): fastest growth along the coordinate axes, relative to `centre` (physical).
    Axes {
        /// The seed centre, physical coordinates.
        centre: (f64, f64),
    },
    /// Any function of the position relative to `centre`; must return values in [0, 1].
    Custom {
        /// The centre positions are measured from, physical coordinates.
        centre: (f64, f64),
        /// `v(dx, dy)`.
        f: WeightFn,
    },
}

impl fmt::Debug for Weight {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Weight::Isotropic => f.write_str("Isotropic"),
            Weight::Axes { centre } => write!(f, "Axes {{ centre: {centre:?} }}"),
            Weight::Custom { centre, .. } => write!(f, "Custom {{ centre: {centre:?} }}"),
        }
    }
}

impl Weight {
    /// True when `v = 1` everywhere, so that no per-site weight need be stored.
    pub fn is_uniform(&self) -> bool {
        matches!(self, Weight::Isotropic)
    }

    /// The name used on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Weight::Isotropic => "none",
            Weight::Axes { .. } => "axes",
            Weight::Custom { .. } => "custom",
        }
    }

    /// `v` at a cell, checked to lie in [0, 1].
    #[inline]
    pub fn at(&self, lattice: &Lattice, cell: usize) -> Result<f64, RuleError> {
        let (centre, f): ((f64, f64), Option<&WeightFn>) = match self {
            Weight::Isotropic => return Ok(1.0),
            Weight::Axes { centre } => (*centre, None),
            Weight::Custom { centre, f } => (*centre, Some(f)),
        };
        let (dx, dy) = lattice.displacement(centre, lattice.position(cell));
        let v = match f {
            None => axes_weight(dx, dy),
            Some(f) => f(dx, dy),
        };
        if (0.0..=1.0).contains(&v) {
            Ok(v)
        } else {
            Err(RuleError::WeightValue {
                value: v,
                x: dx,
                y: dy,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq4_power_law_ratios_match_the_paper() {
        // n = 1: a surrounded site beats a site with one neighbour 6:1; n = 2: 36:1.
        let s1 = Sticking::new(1.0, 6).unwrap();
        assert!((s1.p(6) / s1.p(1) - 6.0).abs() < 1e-12);
        let s2 = Sticking::new(2.0, 6).unwrap();
        assert!((s2.p(6) / s2.p(1) - 36.0).abs() < 1e-12);
        assert_eq!(s2.p(6), 1.0);
        assert!((s2.p(3) - 0.25).abs() < 1e-15);
        // n = 0: every surface site has the same probability 1.
        let s0 = Sticking::new(0.0, 6).unwrap();
        for b in 1..=6 {
            assert_eq!(s0.p(b), 1.0);
        }
        assert_eq!(s0.p(0), 0.0);
    }

    #[test]
    fn int_quotient_is_the_division() {
        // Every table of whole-number weights: the multiplication gives the quotient of the
        // division for numbers below 2^32 (random, and those next to each multiple of the
        // weight and to 2^32), and the division itself above.
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let mut tables = 0;
        for z in [4usize, 6, 8] {
            for n in 1..=24u32 {
                let s = Sticking::new(f64::from(n), z).unwrap();
                let Some(&w) = s.int_weights() else {
                    continue;
                };
                tables += 1;
                for (b, &d) in w.iter().enumerate().take(z + 1).skip(1) {
                    let mut rs = vec![0, 1, d - 1, d, d + 1, u32::MAX as u64, 1 << 32, 1 << 40];
                    // (the largest multiple below 2^32 and its neighbours, for a weight below it)
                    if d <= u32::MAX as u64 {
                        let top = (u32::MAX as u64 / d) * d;
                        rs.extend([top - 1, top, top + 1]);
                    }
                    rs.extend((0..2000).map(|_| next() >> 32));
                    rs.extend((0..200).map(|_| next() >> 1));
                    for r in rs {
                        assert_eq!(s.int_quotient(r, b), r / d, "z {z} n {n} b {b} r {r}");
                    }
                }
            }
        }
        assert!(tables >= 20, "{tables} tables");
    }

    #[test]
    fn eq4_log_and_ratio_tables_survive_underflow() {
        let s = Sticking::new(1e4, 6).unwrap();
        assert_eq!(s.p(1), 0.0); // (1/6)^1e4 underflows
        let expect = 1e4 * (1.0f64 / 6.0).ln();
        assert!((s.ln_p(1) - expect).abs() < 1e-9 * expect.abs());
        assert_eq!(s.ratio(6, 6), 1.0);
        assert_eq!(s.ratio(1, 1), 1.0);
        assert!(s.ratio(6, 5) >= 0.0 && s.ratio(6, 5) < 1e-300);
        let s = Sticking::new(50.0, 6).unwrap();
        assert!((s.ratio(3, 2) - (2.0f64 / 3.0).powf(50.0)).abs() < 1e-20);
    }

    #[test]
    fn eq4_integer_weights_are_the_powers_where_they_fit() {
        // n = 2 on the hexagonal lattice: b^2; proportional to (b/6)^2 with the factor 6^2
        let r = Sticking::new(2.0, 6).unwrap();
        let w = r.int_weights().unwrap();
        assert_eq!(w[..7], [0, 1, 4, 9, 16, 25, 36]);
        for b in 1..=6 {
            assert!((w[b] as f64 / w[6] as f64 - r.p(b)).abs() < 1e-15);
        }
        // a fractional n, n = 0 (the flat surface), and z^n past 2^35 keep the floats
        assert!(Sticking::new(1.7, 6).unwrap().int_weights().is_none());
        assert!(Sticking::new(0.0, 6).unwrap().int_weights().is_none());
        assert!(Sticking::new(13.0, 6).unwrap().int_weights().is_some());
        assert!(Sticking::new(14.0, 6).unwrap().int_weights().is_none());
        assert!(Sticking::new(50.0, 6).unwrap().int_weights().is_none());
        assert_eq!(
            Sticking::new(11.0, 8).unwrap().int_weights().unwrap()[8],
            1 << 33
        );
    }

    #[test]
    fn eq4_inverse_ratios_are_reciprocals_where_the_ratio_is_normal() {
        // n = 2: (r/b)^2 within an ulp or two; n = 1e4: (1/6)^1e4 underflows to 0 and
        // (5/6)^1e4 = 1e-792 too, so their reciprocals are 0 (the sampler divides there).
        let s = Sticking::new(2.0, 6).unwrap();
        for r in 1..=6 {
            for b in 1..=r {
                let want = (r as f64 / b as f64).powi(2);
                assert!((s.inv_ratio(r, b) - want).abs() <= 4.0 * f64::EPSILON * want);
            }
            assert_eq!(s.inv_ratio(r, r), 1.0);
        }
        let s = Sticking::new(1e4, 6).unwrap();
        assert_eq!(s.inv_ratio(6, 6), 1.0);
        assert_eq!(s.inv_ratio(6, 5), 0.0);
        assert_eq!(s.inv_ratio(6, 1), 0.0);
        // a subnormal ratio: (1/2)^1060 = 2^-1060 is below the smallest normal 2^-1022
        let s = Sticking::new(1060.0, 4).unwrap();
        assert!(s.ratio(2, 1) > 0.0 && !s.ratio(2, 1).is_normal());
        assert_eq!(s.inv_ratio(2, 1), 0.0);
    }

    #[test]
    fn eq5_axes_weight() {
        assert_eq!(axes_weight(3.0, 0.0), 1.0);
        assert_eq!(axes_weight(0.0, -2.0), 1.0);
        assert!((axes_weight(2.0, 2.0) - 1.0 / 2f64.sqrt()).abs() < 1e-15);
        assert!((axes_weight(-1.0, 1.0) - 1.0 / 2f64.sqrt()).abs() < 1e-15);
        assert_eq!(axes_weight(0.0, 0.0), 1.0);
        // Bounded by [1/sqrt 2, 1] everywhere.
        for i in -20..=20 {
            for j in -20..=20 {
                let v = axes_weight(i as f64 * 0.37, j as f64 * 0.91);
                assert!((1.0 / 2f64.sqrt() - 1e-12..=1.0 + 1e-12).contains(&v));
            }
        }
    }

    #[test]
    fn invalid_parameters_name_the_parameter() {
        for n in [-1.0, f64::NAN, f64::INFINITY] {
            let e = Sticking::new(n, 6).unwrap_err();
            assert!(e.to_string().starts_with("n = "), "{e}");
        }
        assert!(Sticking::new(2.0, 0).is_err());
        assert!(Sticking::new(2.0, 9).is_err());
    }

    #[test]
    fn custom_weight_out_of_range_is_an_error() {
        use crate::engine::lattice::{Boundary, Lattice, Neighbourhood};
        let l = Lattice::new(Neighbourhood::Square4, 5, 5, Boundary::WALLS).unwrap();
        let w = Weight::Custom {
            centre: (2.0, 2.0),
            f: Arc::new(|x, _| x),
        };
        assert!(w.at(&l, l.index(3, 2)).is_ok());
        let e = w.at(&l, l.index(0, 2)).unwrap_err();
        assert!(e.to_string().contains("v = -2"), "{e}");
    }
}
