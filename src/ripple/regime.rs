//! [`Regime`] and [`RegimeReport`]: whether the flow of a run moves sand at all, builds ripples,
//! or washes them out, judged on the median grain by the Shields number.
//!
//! **Bed shear stress.** The free-stream speed `u` gives `tau = rho_w C_D u^2` (the quadratic
//! friction law of R. L. Soulsby (1997), *Dynamics of Marine Sands*, Thomas Telford, Eq. 30;
//! `C_D` is the run's `drag_coefficient`, the same law the rules use for each grain class,
//! [`super::grain`]). With a wave the stress is judged at the largest stress of the cycle, at
//! the wave's crest or trough: alone, that of `U'_w = U_w sqrt(f_w / (2 C_D))`, the wave
//! amplitude that gives the waves' own stress `tau_w = rho_w (f_w / 2) U_w^2`
//! ([`RippleParams::wave_stress_amplitude`]; `U_w` itself when the run has no wave friction
//! factor); with a current, Soulsby's (1997) Eq. 70, `tau_max = sqrt((tau_m + tau_w cos
//! phi)^2 + (tau_w sin phi)^2)` with the current's stress raised by the waves, `tau_m`
//! (Eq. 69), and `phi` the angle between the current and the waves' axis
//! ([`RippleParams::combined_flow`]).
//!
//! **Shields number and threshold.** `theta = tau / ((rho_s - rho_w) g d50)` (Soulsby 1997,
//! Eq. 74) against the threshold `theta_cr(D*)` of Soulsby's Eq. 77 ([`super::grain::theta_cr`]).
//!
//! **Regimes** (Soulsby 1997, Sect. 7.2 and Fig. 22):
//! - [`Regime::NoMotion`], `theta < theta_cr`: the median grain does not move, and the bed
//!   stays as it is;
//! - [`Regime::Ripples`], `theta_cr <= theta <= 0.8`: the ripple regime;
//! - [`Regime::SheetFlow`], `theta > 0.8` ([`THETA_SHEET_FLOW`]): the ripples are washed out and
//!   the bed is flat, with a moving sheet of grains; the rules of this model do not hold there.
//!
//! Coarse sand (d50 above [`D50_RIPPLES_MAX_MM`] = 0.8 mm) forms no current ripples in nature
//! (Soulsby 1997, Sect. 7.2; dunes or a flat bed instead): [`RegimeReport::coarse`] says so.

use super::grain::{G, RHO_S, RHO_W, theta_cr};
use super::params::RippleParams;

/// The Shields number above which ripples are washed out into sheet flow (Soulsby 1997,
/// Sect. 7.2).
pub const THETA_SHEET_FLOW: f64 = 0.8;

/// The largest median grain size, mm, at which current ripples form (Soulsby 1997, Sect. 7.2).
pub const D50_RIPPLES_MAX_MM: f64 = 0.8;

/// The flow regime of a run (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Regime {
    /// Below the threshold of motion.
    NoMotion,
    /// Between the threshold and sheet flow.
    Ripples,
    /// Above `theta = 0.8`.
    SheetFlow,
}

impl Regime {
    /// Its name in the JSON summary: `no motion`, `ripples`, `sheet flow`.
    pub fn name(self) -> &'static str {
        match self {
            Regime::NoMotion => "no motion",
            Regime::Ripples => "ripples",
            Regime::SheetFlow => "sheet flow",
        }
    }

    /// The regime of a Shields number `theta` with the threshold `theta_cr`.
    pub fn of(theta: f64, theta_cr: f64) -> Regime {
        if theta < theta_cr {
            Regime::NoMotion
        } else if theta > THETA_SHEET_FLOW {
            Regime::SheetFlow
        } else {
            Regime::Ripples
        }
    }
}

/// The regime of a run's parameters, with the numbers it was judged on.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RegimeReport {
    /// The regime.
    pub regime: Regime,
    /// The largest speed of the run, m/s, that gives the bed stress through `C_D` (that of
    /// Soulsby's Eq. 70 with a current and waves: module docs).
    pub speed: f64,
    /// Bed shear stress at that speed, Pa.
    pub bed_shear_stress: f64,
    /// Shields number of the median grain.
    pub shields: f64,
    /// Its threshold of motion.
    pub shields_critical: f64,
    /// The free-stream speeds, m/s, between which the median grain is in the ripple regime
    /// (threshold of motion, onset of sheet flow).
    pub ripple_speeds: (f64, f64),
    /// Whether d50 is above [`D50_RIPPLES_MAX_MM`] (no current ripples in nature).
    pub coarse: bool,
}

/// Shields number `theta = tau / ((rho_s - rho_w) g d)` of a stress `tau` (Pa) on grains of
/// diameter `d` (m) (Soulsby 1997, Eq. 74).
pub fn shields(tau: f64, d: f64) -> f64 {
    tau / ((RHO_S - RHO_W) * G * d)
}

/// Quadratic friction law `tau = rho_w C_D u^2` (Soulsby 1997, Eq. 30), Pa.
pub fn bed_shear_stress(u: f64, cd: f64) -> f64 {
    RHO_W * cd * u * u
}

/// The free-stream speed, m/s, that gives the Shields number `theta` on grains of `d` m with
/// drag coefficient `cd` (the inverse of Eqs. 30 and 74).
pub fn speed_for_shields(theta: f64, d: f64, cd: f64) -> f64 {
    (theta * (RHO_S - RHO_W) * G * d / (RHO_W * cd)).sqrt()
}

/// The regime of the run `p` (module docs).
pub fn regime(p: &RippleParams) -> RegimeReport {
    let d = p.d50 * 1e-3;
    let cd = p.drag_coefficient;
    // the largest speed of the cycle: at the wave's crest or trough
    let speed = if p.has_wave() {
        let c = p.current_angle.to_radians();
        let w = p.wave_angle.unwrap_or(p.current_angle).to_radians();
        [1.0, -1.0]
            .iter()
            .map(|s| {
                let (ux, uy) = p.combined_flow(c, w, *s);
                ux.hypot(uy)
            })
            .fold(0.0, f64::max)
    } else {
        p.current_speed.abs()
    };
    let tau = bed_shear_stress(speed, cd);
    let theta = shields(tau, d);
    let cr = theta_cr(d);
    RegimeReport {
        regime: Regime::of(theta, cr),
        speed,
        bed_shear_stress: tau,
        shields: theta,
        shields_critical: cr,
        ripple_speeds: (
            speed_for_shields(cr, d, cd),
            speed_for_shields(THETA_SHEET_FLOW, d, cd),
        ),
        coarse: p.d50 > D50_RIPPLES_MAX_MM,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq30_quadratic_friction_law() {
        // 0.5 m/s with C_D = 0.0025 in seawater: 1027 x 0.0025 x 0.25 Pa
        assert!((bed_shear_stress(0.5, 0.0025) - 0.641_875).abs() < 1e-12);
    }

    #[test]
    fn eq74_shields_number() {
        // Soulsby (1997) Example 6.3 style: 0.2 mm quartz under 0.641875 Pa
        let t = shields(0.641_875, 0.2e-3);
        assert!((t - 0.641_875 / (1623.0 * 9.81 * 0.2e-3)).abs() < 1e-12);
        assert!((t - 0.2016).abs() < 1e-3, "{t}");
        // the inverse
        assert!((speed_for_shields(t, 0.2e-3, 0.0025) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn regimes_by_current_speed_for_0_2_mm_sand() {
        let at = |u: f64| {
            regime(&RippleParams {
                current_speed: u,
                ..RippleParams::default()
            })
        };
        let slow = at(0.2);
        assert_eq!(slow.regime, Regime::NoMotion, "{slow:?}");
        assert!(slow.shields < slow.shields_critical);
        let mid = at(0.5);
        assert_eq!(mid.regime, Regime::Ripples, "{mid:?}");
        let fast = at(1.5);
        assert_eq!(fast.regime, Regime::SheetFlow, "{fast:?}");
        assert!((fast.shields - 1.81).abs() < 0.01, "{fast:?}");
        // the bounds of the ripple regime are the speeds at theta_cr and 0.8
        let (lo, hi) = mid.ripple_speeds;
        assert_eq!(at(lo * 0.999).regime, Regime::NoMotion);
        assert_eq!(at(lo * 1.001).regime, Regime::Ripples);
        assert_eq!(at(hi * 0.999).regime, Regime::Ripples);
        assert_eq!(at(hi * 1.001).regime, Regime::SheetFlow);
        assert!(!mid.coarse);
    }

    #[test]
    fn combined_flow_is_judged_by_soulsby_eq_70() {
        // a 0.6 m/s current with 0.3 m/s waves of 6 s over 0.2 mm sand, at 0 and 60 deg
        let d = 0.2e-3;
        for phi in [0.0_f64, 60.0] {
            let p = RippleParams {
                d50: 0.2,
                current_speed: 0.6,
                wave_amplitude: 0.3,
                wave_period: 300.0,
                wave_angle: Some(phi),
                wave_friction_factor: crate::ripple::waves::run_wave_friction_factor(
                    0.3, 6.0, d, 0.0025,
                ),
                drag_coefficient: 0.0025,
                ..RippleParams::default()
            };
            let tau_c = RHO_W * 0.0025 * 0.36;
            let tau_w = RHO_W * 0.5 * p.wave_friction_factor * 0.09;
            let tau_m = tau_c * (1.0 + 1.2 * (tau_w / (tau_c + tau_w)).powf(3.2));
            let phi = phi.to_radians();
            let tau_max =
                ((tau_m + tau_w * phi.cos()).powi(2) + (tau_w * phi.sin()).powi(2)).sqrt();
            let r = regime(&p);
            assert!(
                (r.bed_shear_stress - tau_max).abs() < 1e-9 * tau_max,
                "{r:?} {tau_max}"
            );
            assert!((r.shields - shields(tau_max, d)).abs() < 1e-12);
            // ripples: adding the friction velocities would have been sheet flow
            assert_eq!(r.regime, Regime::Ripples, "{r:?}");
            let added = RHO_W * 0.0025 * (0.6 + p.wave_stress_amplitude()).powi(2);
            assert!(
                shields(added, d) > THETA_SHEET_FLOW && r.shields < 0.5,
                "{r:?}"
            );
        }
    }

    #[test]
    fn waves_count_at_the_top_of_their_cycle_and_coarse_sand_is_marked() {
        let r = regime(&RippleParams {
            current_speed: 0.0,
            wave_amplitude: 0.5,
            wave_period: 20.0,
            ..RippleParams::default()
        });
        assert_eq!(r.speed, 0.5);
        assert_eq!(r.regime, Regime::Ripples);
        let c = regime(&RippleParams {
            d50: 1.0,
            ..RippleParams::default()
        });
        assert!(c.coarse);
        // coarser grains need more flow: the threshold speed rises with d50
        let f = regime(&RippleParams::default());
        assert!(c.ripple_speeds.0 > f.ripple_speeds.0);
    }
}
