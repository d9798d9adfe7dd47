//! [`Prediction`]: the ripple that empirical predictors expect for a run's sediment and flow.
//! They are checks on the model, never inputs to it: no length of the rules is computed from
//! them.
//!
//! - Current ripples: R. L. Soulsby and R. J. S. Whitehouse (2005), "Prediction of ripple
//!   properties in shelf seas. Mark 2 predictor for time evolution", HR Wallingford report
//!   TR 154 ([`soulsby_whitehouse`]); the older rule of thumb of R. L. Soulsby (1997),
//!   *Dynamics of Marine Sands*, Thomas Telford, Eq. 81 ([`soulsby_1997`]).
//! - Wave ripples in the orbital regime: P. L. Wiberg and C. K. Harris (1994), "Ripple
//!   geometry in wave-dominated environments", *J. Geophys. Res.* 99(C1), 775-789,
//!   <https://doi.org/10.1029/93JC02726>: orbital, suborbital and anorbital ripples
//!   ([`wiberg_harris`]).
//!
//! [`Prediction::of`] picks the predictor of the dominant flow: waves when their bed stress
//! exceeds the current's ([`super::RippleParams::waves_dominate`]), the current otherwise.
//!
//! - Crest orientation in a flow whose direction varies (a current and waves at an angle):
//!   D. M. Rubin and R. E. Hunter (1987), "Bedform alignment in directionally varying flows",
//!   *Science* 237, 276-278, <https://doi.org/10.1126/science.237.4812.276>: crests align so
//!   that the gross bedform-normal transport is largest ([`rubin_hunter_crest_normal`]).

use super::clock::meyer_peter_mueller;
use super::grain::d_star;
use super::params::RippleParams;
use super::regime::{bed_shear_stress, shields};

/// Eq. of Soulsby & Whitehouse (2005) for equilibrium current ripples, valid for
/// 1.2 < D* < 16: wavelength `lambda = d50 (500 + 1881 D*^-1.5)` and height
/// `eta = 202 d50 D*^-0.554`; (wavelength m, height m) for `d50` in m.
pub fn soulsby_whitehouse(d50: f64) -> (f64, f64) {
    let ds = d_star(d50);
    (
        d50 * (500.0 + 1881.0 * ds.powf(-1.5)),
        d50 * 202.0 * ds.powf(-0.554),
    )
}

/// Soulsby (1997) Eq. 81, current ripples: (wavelength m, height m) = (1000 d50, 1000 d50 / 7).
pub fn soulsby_1997(d50: f64) -> (f64, f64) {
    (1000.0 * d50, 1000.0 * d50 / 7.0)
}

/// The wavelength of orbital wave ripples as a fraction of the orbital diameter d0 (Wiberg &
/// Harris 1994).
pub const ORBITAL_WAVELENGTH_PER_D0: f64 = 0.62;

/// The wavelength of anorbital wave ripples in median grain diameters (Wiberg & Harris 1994).
pub const ANORBITAL_WAVELENGTH_PER_D50: f64 = 535.0;

/// The regime of wave ripples (Wiberg & Harris 1994), by `d0 / eta_ano`, the orbital diameter
/// over the height of the anorbital ripple.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum WaveRippleRegime {
    /// `d0 / eta_ano < 20`: wavelength `0.62 d0`.
    Orbital,
    /// Between: the wavelength interpolated in logarithms.
    Suborbital,
    /// `d0 / eta_ano > 100`: wavelength `535 d50`.
    Anorbital,
}

/// Wiberg & Harris (1994) ripple steepness: the height `eta` of a wave ripple of wavelength
/// `lambda` under orbital diameter `d0`, from `eta / lambda = exp(-0.095 u^2 + 0.442 u - 2.28)`
/// with `u = ln(d0 / eta)`. Written as `0.095 u^2 - 1.442 u + 2.28 + ln(d0 / lambda) = 0`, its
/// root on the branch where the steepness falls with `d0 / eta` (the smaller root). Where
/// `d0 / lambda` exceeds about 24 there is no root: the steepness there is taken at the
/// vertex, its smallest value on that branch (0.012).
pub fn wiberg_harris_height(lambda: f64, d0: f64) -> f64 {
    let c = 2.28 + (d0 / lambda).ln();
    let disc = (1.442f64 * 1.442 - 4.0 * 0.095 * c).max(0.0);
    let u = (1.442 - disc.sqrt()) / (2.0 * 0.095);
    d0 * (-u).exp()
}

/// Wiberg & Harris (1994) wave ripples for orbital diameter `d0` m and median grain size
/// `d50` m: (wavelength m, height m, regime). Orbital `lambda = 0.62 d0`, anorbital
/// `lambda = 535 d50`, suborbital interpolated between them in `ln(d0 / eta_ano)` from 20 to
/// 100; heights by [`wiberg_harris_height`].
pub fn wiberg_harris(d0: f64, d50: f64) -> (f64, f64, WaveRippleRegime) {
    let l_orb = ORBITAL_WAVELENGTH_PER_D0 * d0;
    let l_ano = ANORBITAL_WAVELENGTH_PER_D50 * d50;
    let r = d0 / wiberg_harris_height(l_ano, d0);
    let (l, regime) = if r < 20.0 {
        (l_orb, WaveRippleRegime::Orbital)
    } else if r > 100.0 {
        (l_ano, WaveRippleRegime::Anorbital)
    } else {
        let f = (r.ln() - 100f64.ln()) / (20f64.ln() - 100f64.ln());
        (
            (f * (l_orb.ln() - l_ano.ln()) + l_ano.ln()).exp(),
            WaveRippleRegime::Suborbital,
        )
    };
    (l, wiberg_harris_height(l, d0), regime)
}

/// The ripple a predictor expects for a run.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Prediction {
    /// Wavelength, m.
    pub wavelength: f64,
    /// Height, m.
    pub height: f64,
    /// The predictor: `Soulsby & Whitehouse (2005)` or `Wiberg & Harris (1994), REGIME`.
    pub source: &'static str,
}

impl Prediction {
    /// The prediction for median grain size `d50_mm` (mm) under waves of orbital velocity
    /// amplitude `wave_velocity` m/s and period `wave_period_s` s (0: none) and a current: the
    /// waves' when `waves_dominate` ([`super::RippleParams::waves_dominate`]: their bed stress
    /// is the larger), the current's otherwise.
    pub fn of(
        d50_mm: f64,
        waves_dominate: bool,
        wave_velocity: f64,
        wave_period_s: f64,
    ) -> Prediction {
        if waves_dominate && wave_period_s > 0.0 {
            let d0 = wave_velocity * wave_period_s / std::f64::consts::PI;
            let (wavelength, height, regime) = wiberg_harris(d0, d50_mm * 1e-3);
            Prediction {
                wavelength,
                height,
                source: match regime {
                    WaveRippleRegime::Orbital => "Wiberg & Harris (1994), orbital",
                    WaveRippleRegime::Suborbital => "Wiberg & Harris (1994), suborbital",
                    WaveRippleRegime::Anorbital => "Wiberg & Harris (1994), anorbital",
                },
            }
        } else {
            let (wavelength, height) = soulsby_whitehouse(d50_mm * 1e-3);
            Prediction {
                wavelength,
                height,
                source: "Soulsby & Whitehouse (2005)",
            }
        }
    }
}

/// Rubin & Hunter (1987): the crest normal (degrees counter-clockwise from east, in [0, 180))
/// that makes the gross bedform-normal transport `sum_t |q(t) . n|` over a wave cycle
/// largest, with `q(t)` the Meyer-Peter & Mueller bedload along the flow of each of 256 phases
/// of the run `p` ([`RippleParams::combined_flow`]); searched in steps of 0.1 deg.
/// `None` when the flow moves no sand.
pub fn rubin_hunter_crest_normal(p: &RippleParams) -> Option<f64> {
    let d = p.d50 * 1e-3;
    let c = p.current_angle.to_radians();
    let w = p.wave_angle.unwrap_or(p.current_angle).to_radians();
    let phases = if p.has_wave() { 256 } else { 1 };
    let q: Vec<(f64, f64)> = (0..phases)
        .map(|k| {
            let s = if p.has_wave() {
                (2.0 * std::f64::consts::PI * (k as f64 + 0.5) / phases as f64).sin()
            } else {
                0.0
            };
            let (ux, uy) = p.combined_flow(c, w, s);
            let u = ux.hypot(uy);
            let qb = meyer_peter_mueller(shields(bed_shear_stress(u, p.drag_coefficient), d), d);
            (qb, uy.atan2(ux))
        })
        .collect();
    if q.iter().all(|&(qb, _)| qb <= 0.0) {
        return None;
    }
    let gross = |n: f64| -> f64 { q.iter().map(|&(qb, a)| qb * (a - n).cos().abs()).sum() };
    (0..1800)
        .map(|i| (i as f64 * 0.1, gross((i as f64 * 0.1).to_radians())))
        .fold(None, |best: Option<(f64, f64)>, (a, g)| match best {
            Some((_, bg)) if bg >= g => best,
            _ => Some((a, g)),
        })
        .map(|(a, _)| a)
}

/// The longest bin that resolves a ripple `height` metres high whose lee face stands at the
/// avalanche angle `alpha_deg` (degrees): half the lee face's horizontal length,
/// `H / (2 tan alpha)`, m, so that the slip face and the shadow behind it span at least two
/// bins. Measured in 3-D (docs/ripple.md, "The bin in 3-D: the lee face's resolution"):
/// at 300 s, ripples whose lee face spans one to one and a half 10 mm bins came out 22 % lower
/// than with 5 mm bins; at 1800 s, with faces of three to four bins, the 10 mm bins' fields
/// agreed with the 5 mm bins' within 1 % (travel in grain diameters) and 5 % (default rules).
pub fn largest_resolving_bin(height: f64, alpha_deg: f64) -> f64 {
    height / (2.0 * alpha_deg.to_radians().tan())
}

/// The length of the torus along direction `angle_deg` (degrees from +x) before a straight
/// line leaves the `lx` x `ly` m rectangle: `min(lx / |cos|, ly / |sin|)`, m.
pub fn length_along(lx: f64, ly: f64, angle_deg: f64) -> f64 {
    let (s, c) = angle_deg.to_radians().sin_cos();
    let along_x = if c.abs() > 1e-12 {
        lx / c.abs()
    } else {
        f64::INFINITY
    };
    let along_y = if s.abs() > 1e-12 {
        ly / s.abs()
    } else {
        f64::INFINITY
    };
    along_x.min(along_y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn soulsby_whitehouse_check_value() {
        // Soulsby & Whitehouse (2005): d50 = 0.2 mm -> lambda = 14.6 cm, height = 1.86 cm.
        let (l, h) = soulsby_whitehouse(0.2e-3);
        assert!((l - 0.146).abs() < 0.002, "{l}");
        assert!((h - 0.0186).abs() < 0.0005, "{h}");
    }

    #[test]
    fn soulsby_whitehouse_grows_with_d50_and_keeps_the_ripple_index() {
        let mut last = (0.0, 0.0);
        for d in [0.1e-3, 0.2e-3, 0.4e-3, 0.6e-3] {
            let (l, h) = soulsby_whitehouse(d);
            assert!(l > last.0 && h > last.1, "d50 {d}: {l} {h}");
            assert!(
                (6.0..=12.0).contains(&(l / h)),
                "d50 {d}: ripple index {}",
                l / h
            );
            last = (l, h);
        }
    }

    #[test]
    fn soulsby_1997_eq81() {
        let (l, h) = soulsby_1997(0.3e-3);
        assert!((l - 0.3).abs() < 1e-12 && (h - 0.3 / 7.0).abs() < 1e-12);
    }

    #[test]
    fn wiberg_harris_steepness_equation() {
        // the height solves eta / lambda = exp(-0.095 u^2 + 0.442 u - 2.28), u = ln(d0 / eta)
        for (l, d0) in [(0.248, 0.4), (0.107, 1.0), (0.05, 0.3)] {
            let h = wiberg_harris_height(l, d0);
            let u = (d0 / h).ln();
            let rhs = (-0.095 * u * u + 0.442 * u - 2.28).exp();
            assert!(
                (h / l - rhs).abs() < 1e-12,
                "{l} {d0}: {} against {rhs}",
                h / l
            );
        }
        // orbital ripples: steepness 0.17 (the largest the relation gives)
        let h = wiberg_harris_height(0.62 * 0.4, 0.4);
        assert!(
            (h / (0.62 * 0.4) - 0.171).abs() < 0.001,
            "{}",
            h / (0.62 * 0.4)
        );
    }

    #[test]
    fn wiberg_harris_regimes() {
        // 0.3 mm sand, d0 = 0.2 m: orbital, lambda = 0.62 d0
        let (l, _, r) = wiberg_harris(0.2, 0.3e-3);
        assert_eq!(r, WaveRippleRegime::Orbital);
        assert!((l - 0.124).abs() < 1e-12, "{l}");
        // 0.2 mm sand, d0 = 3 m: anorbital, lambda = 535 d50
        let (l, _, r) = wiberg_harris(3.0, 0.2e-3);
        assert_eq!(r, WaveRippleRegime::Anorbital);
        assert!((l - 0.107).abs() < 1e-12, "{l}");
        // between, the wavelength lies between the two
        let (l, _, r) = wiberg_harris(0.8, 0.2e-3);
        assert_eq!(r, WaveRippleRegime::Suborbital);
        assert!(l > 0.107 && l < 0.62 * 0.8, "{l}");
    }

    #[test]
    fn prediction_follows_the_dominant_flow() {
        let c = Prediction::of(0.2, false, 0.0, 0.0);
        assert_eq!(c.source, "Soulsby & Whitehouse (2005)");
        // U_w = 0.4 m/s, T = pi s: d0 = 0.4 m
        let w = Prediction::of(0.3, true, 0.4, std::f64::consts::PI);
        assert_eq!(w.source, "Wiberg & Harris (1994), orbital");
        assert!((w.wavelength - 0.248).abs() < 1e-12, "{}", w.wavelength);
        // waves that do not dominate leave the current's prediction
        assert_eq!(Prediction::of(0.2, false, 0.3, 8.0), c);
        // which flow dominates is told by the bed stress: 0.25 m/s of waves with their own
        // friction outweigh a current of 0.3 m/s
        let p = crate::ripple::RippleParams {
            current_speed: 0.3,
            wave_amplitude: 0.25,
            wave_period: 100.0,
            ..crate::ripple::RippleParams::default()
        };
        assert!(!p.waves_dominate());
        assert!(
            crate::ripple::RippleParams {
                wave_friction_factor: 0.0083,
                ..p
            }
            .waves_dominate()
        );
    }

    #[test]
    fn rubin_hunter_crest_normal_maximises_gross_normal_transport() {
        // a steady current: crests normal to it
        let p = RippleParams {
            current_angle: 30.0,
            ..RippleParams::default()
        };
        assert!((rubin_hunter_crest_normal(&p).unwrap() - 30.0).abs() < 0.05);
        // pure waves: crests normal to the waves
        let w = RippleParams {
            current_speed: 0.0,
            wave_amplitude: 0.4,
            wave_period: 100.0,
            wave_angle: Some(70.0),
            ..RippleParams::default()
        };
        assert!((rubin_hunter_crest_normal(&w).unwrap() - 70.0).abs() < 0.05);
        // a current and waves at 60 deg to it: between the two
        let cw = RippleParams {
            current_speed: 0.3,
            wave_amplitude: 0.4,
            wave_period: 100.0,
            wave_angle: Some(60.0),
            d50: 0.3,
            ..RippleParams::default()
        };
        let n = rubin_hunter_crest_normal(&cw).unwrap();
        assert!(n > 0.0 && n < 60.0, "{n}");
        // no motion: none
        let still = RippleParams {
            current_speed: 0.05,
            ..RippleParams::default()
        };
        assert_eq!(rubin_hunter_crest_normal(&still), None);
    }

    #[test]
    fn largest_resolving_bin_is_half_the_lee_face() {
        // a lee face at alpha spans H / tan(alpha) horizontally: exactly two such bins
        for (h, alpha) in [(0.0186, 32.0), (0.01, 30.0), (0.05, 45.0)] {
            let b = largest_resolving_bin(h, alpha);
            let face = h / f64::to_radians(alpha).tan();
            assert!((face / b - 2.0).abs() < 1e-12, "{h} {alpha}: {b}");
        }
        // the defaults' predicted ripple (0.2 mm sand) is resolved by bins up to 14.9 mm
        let (_, h) = soulsby_whitehouse(0.2e-3);
        let b = largest_resolving_bin(h, 32.0);
        assert!((0.0148..0.0150).contains(&b), "{b}");
        // taller ripples and gentler faces resolve with longer bins
        assert!(largest_resolving_bin(2.0 * h, 32.0) > b);
        assert!(largest_resolving_bin(h, 25.0) > b);
    }

    #[test]
    fn length_along_axes_and_diagonal() {
        assert_eq!(length_along(0.64, 0.32, 0.0), 0.64);
        assert!((length_along(0.64, 0.32, 90.0) - 0.32).abs() < 1e-12);
        assert!((length_along(0.64, 0.32, 180.0) - 0.64).abs() < 1e-12);
        let d = length_along(1.0, 1.0, 45.0);
        assert!((d - 2f64.sqrt()).abs() < 1e-12, "{d}");
    }
}
