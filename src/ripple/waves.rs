//! [`SurfaceWave`]: the near-bed orbital velocity of surface waves by linear (Airy) wave
//! theory, for waves given by their height, period and the water depth rather than by the
//! orbital velocity itself.
//!
//! Linear wave theory (R. G. Dean and R. A. Dalrymple (1991), *Water Wave Mechanics for
//! Engineers and Scientists*, World Scientific, Advanced Series on Ocean Engineering 2,
//! Chapters 3-4; R. L. Soulsby (1997), *Dynamics of Marine Sands*, Thomas Telford, Sect. 5):
//!
//! - dispersion relation `omega^2 = g k tanh(k h)`, `omega = 2 pi / T` ([`wavenumber`]);
//! - near-bed orbital velocity amplitude `U_w = pi H / (T sinh(k h))` ([`SurfaceWave::orbital_velocity`]);
//! - orbital excursion amplitude `A = U_w T / (2 pi)` and diameter `d0 = 2 A = U_w T / pi`;
//! - the wave friction factor of a rough bed, `f_w = 1.39 (A / z0)^-0.52` with
//!   `z0 = d50 / 12` (Soulsby 1997, Eq. 60a; [`wave_friction_factor`]), at most 0.3 (the upper
//!   limit of I. G. Jonsson (1966) and D. H. Swart (1974), "Offshore sediment transport and
//!   equilibrium beach profiles", Delft Hydraulics Publ. 131, for excursions of a few grain
//!   roughnesses).
//!
//! Linear theory holds for waves that are neither breaking nor too steep: [`SurfaceWave::new`]
//! refuses a height above 0.78 of the depth (the depth-limited breaking of a solitary wave,
//! J. McCowan (1894), "On the highest wave of permanent type", *Phil. Mag.* 38, 351-358) and a
//! steepness `H / L` above 1/7 (J. H. Michell (1893), "The highest waves in water", *Phil. Mag.*
//! 36, 430-437).

use super::RippleError;
use super::grain::G;

/// The largest wave height, as a fraction of the depth, of a wave that does not break
/// (McCowan 1894).
pub const BREAKING_DEPTH_RATIO: f64 = 0.78;

/// The largest steepness `H / L` of a wave that does not break (Michell 1893).
pub const BREAKING_STEEPNESS: f64 = 1.0 / 7.0;

/// The wavenumber `k` (rad/m) of a linear wave of period `period` s in water `depth` m deep:
/// the root of the dispersion relation `(2 pi / T)^2 = g k tanh(k h)`, by Newton's method from
/// the explicit approximation of Soulsby (1997) to within 1e-12 relative.
pub fn wavenumber(period: f64, depth: f64) -> f64 {
    let omega = 2.0 * std::f64::consts::PI / period;
    let x = omega * omega * depth / G; // k0 h, the deep-water value of k h
    // A start above the root: y = kh satisfies y tanh(y) = x, with y >= sqrt(x) and y >= x.
    let mut y = x.max(x.sqrt());
    for _ in 0..100 {
        let t = y.tanh();
        let f = y * t - x;
        let df = t + y * (1.0 - t * t);
        let step = f / df;
        y -= step;
        if step.abs() <= 1e-13 * y {
            break;
        }
    }
    y / depth
}

/// A surface wave train of height, period and depth, with what linear theory gives at the bed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceWave {
    /// Wave height H (crest to trough), m.
    pub height: f64,
    /// Wave period T, s.
    pub period: f64,
    /// Water depth h, m.
    pub depth: f64,
    /// Wavenumber k, rad/m ([`wavenumber`]).
    pub k: f64,
}

/// The longest wave period, s, taken by the command line (`--wave-period`, with
/// `--wave-velocity` or `--wave-height`).
pub const MAX_PERIOD_S: f64 = 1000.0;

impl SurfaceWave {
    /// A wave of `height` m, `period` s in `depth` m of water; refuses non-positive or
    /// non-finite values and breaking waves (module docs). The error names the option
    /// (`--wave-height`, `--wave-period`, `--water-depth`) and its valid range.
    pub fn new(height: f64, period: f64, depth: f64) -> Result<SurfaceWave, RippleError> {
        for (name, v, hi) in [
            ("wave_height", height, 100.0),
            ("wave_period", period, MAX_PERIOD_S),
            ("water_depth", depth, 10_000.0),
        ] {
            if !(v.is_finite() && v > 0.0 && v <= hi) {
                return Err(RippleError::Range {
                    parameter: name,
                    value: super::params::shown(v),
                    expected: format!("a number in (0, {hi}]"),
                });
            }
        }
        let k = wavenumber(period, depth);
        let w = SurfaceWave {
            height,
            period,
            depth,
            k,
        };
        if height > BREAKING_DEPTH_RATIO * depth {
            return Err(RippleError::Range {
                parameter: "wave_height",
                value: super::params::shown(height),
                expected: format!(
                    "at most {BREAKING_DEPTH_RATIO} x water_depth = {:.3} m: a higher wave breaks (McCowan 1894) and linear theory does not hold",
                    BREAKING_DEPTH_RATIO * depth
                ),
            });
        }
        if height / w.wavelength() > BREAKING_STEEPNESS {
            return Err(RippleError::Range {
                parameter: "wave_height",
                value: super::params::shown(height),
                expected: format!(
                    "at most 1/7 of the wavelength {:.2} m = {:.3} m: a steeper wave breaks (Michell 1893)",
                    w.wavelength(),
                    BREAKING_STEEPNESS * w.wavelength()
                ),
            });
        }
        Ok(w)
    }

    /// The surface wavelength `L = 2 pi / k`, m.
    pub fn wavelength(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.k
    }

    /// Linear theory's near-bed orbital velocity amplitude `U_w = pi H / (T sinh(k h))`, m/s.
    pub fn orbital_velocity(&self) -> f64 {
        std::f64::consts::PI * self.height / (self.period * (self.k * self.depth).sinh())
    }

    /// The near-bed orbital diameter `d0 = U_w T / pi = H / sinh(k h)`, m.
    pub fn orbital_diameter(&self) -> f64 {
        self.orbital_velocity() * self.period / std::f64::consts::PI
    }
}

/// The largest wave friction factor (Jonsson 1966; Swart 1974).
pub const WAVE_FRICTION_MAX: f64 = 0.3;

/// The wave friction factor `f_w` of a rough bed of grains `d50` m under an orbital velocity
/// amplitude `u_w` m/s of period `period` s: `f_w = 1.39 (A / z0)^-0.52`, `A = U_w T / (2 pi)`,
/// `z0 = d50 / 12` (Soulsby 1997, Eq. 60a), at most [`WAVE_FRICTION_MAX`]; 0 without a wave.
pub fn wave_friction_factor(u_w: f64, period: f64, d50: f64) -> f64 {
    let a = u_w * period / (2.0 * std::f64::consts::PI);
    if a <= 0.0 || d50 <= 0.0 {
        return 0.0;
    }
    (1.39 * (a / (d50 / 12.0)).powf(-0.52)).min(WAVE_FRICTION_MAX)
}

/// The wave friction factor a run takes by default: Eq. 60a ([`wave_friction_factor`]), but
/// at least `2 C_D` (`drag_coefficient`; the floor itself at most [`WAVE_FRICTION_MAX`]), so that waves rub the bed at least as a steady
/// current of their speed does. Eq. 60a falls with the excursion, and for long periods (an
/// excursion of some 5 x 10^4 roughness lengths and more: 0.4 m/s waves over 0.2 mm sand
/// from a period of about 13 s) it would make the waves rub less than that current, where a
/// slow oscillation's boundary layer grows towards the steady flow's (our reading; Eq. 60a
/// is fitted to excursions of up to about 10^4 roughness lengths). 0 without a wave.
pub fn run_wave_friction_factor(u_w: f64, period: f64, d50: f64, drag_coefficient: f64) -> f64 {
    match wave_friction_factor(u_w, period, d50) {
        f if f > 0.0 => f.max((2.0 * drag_coefficient).min(WAVE_FRICTION_MAX)),
        f => f,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn dispersion_relation_is_satisfied() {
        for (t, h) in [
            (1.0, 0.1),
            (4.0, 2.0),
            (8.0, 10.0),
            (12.0, 30.0),
            (20.0, 4000.0),
        ] {
            let k = wavenumber(t, h);
            let omega = 2.0 * PI / t;
            let r = G * k * (k * h).tanh() / (omega * omega);
            assert!((r - 1.0).abs() < 1e-12, "T {t} h {h}: {r}");
        }
    }

    #[test]
    fn dispersion_relation_deep_and_shallow_limits() {
        // deep water (h > L/2): L = g T^2 / (2 pi)
        let t = 6.0;
        let deep = 2.0 * PI / wavenumber(t, 1000.0);
        assert!((deep - G * t * t / (2.0 * PI)).abs() < 1e-9, "{deep}");
        // shallow water (h < L/20): L = T sqrt(g h), to the first correction k h^2 / 3
        let h = 0.5;
        let l = 2.0 * PI / wavenumber(60.0, h);
        let c = (G * h).sqrt() * 60.0;
        assert!((l / c - 1.0).abs() < 1e-4, "{l} against {c}");
    }

    #[test]
    fn orbital_velocity_check_value() {
        // T = 8 s, h = 10 m: h / L0 = 10 / 99.92 = 0.1001, k h = 0.8862, so H = 1 m gives
        // U_w = pi / (8 sinh 0.8862) = 0.3900 m/s.
        let w = SurfaceWave::new(1.0, 8.0, 10.0).unwrap();
        assert!((w.k * w.depth - 0.8862).abs() < 1e-4, "{}", w.k * w.depth);
        assert!(
            (w.orbital_velocity() - 0.3900).abs() < 1e-4,
            "{}",
            w.orbital_velocity()
        );
        assert!((w.orbital_diameter() - w.orbital_velocity() * 8.0 / PI).abs() < 1e-12);
        // in deep water the bed does not feel the wave
        let deep = SurfaceWave::new(1.0, 4.0, 200.0).unwrap();
        assert!(
            deep.orbital_velocity() < 1e-20,
            "{}",
            deep.orbital_velocity()
        );
    }

    #[test]
    fn breaking_and_bad_waves_are_refused() {
        let e = SurfaceWave::new(1.0, 8.0, 1.2).unwrap_err().to_string();
        assert!(e.contains("wave_height") && e.contains("0.936"), "{e}");
        // steepness: T = 2 s in deep water has L = 6.25 m, H 1 m is steeper than 1/7
        let e = SurfaceWave::new(1.0, 2.0, 50.0).unwrap_err().to_string();
        assert!(e.contains("wave_height") && e.contains("1/7"), "{e}");
        for (h, t, d, name) in [
            (0.0, 8.0, 10.0, "wave_height"),
            (1.0, -8.0, 10.0, "wave_period"),
            (1.0, 8.0, f64::NAN, "water_depth"),
        ] {
            let e = SurfaceWave::new(h, t, d).unwrap_err().to_string();
            assert!(e.contains(name), "{e}");
        }
    }

    /// The run's factor is Eq. 60a's for the usual excursions and `2 C_D` for long periods.
    #[test]
    fn run_wave_friction_factor_is_at_least_twice_the_drag_coefficient() {
        let (cd, d50) = (0.0025, 0.2e-3);
        // 0.4 m/s, 8 s: A = 0.51 m, A / z0 = 3.1e4, f_w = 0.0062
        let f8 = wave_friction_factor(0.4, 8.0, d50);
        assert!(f8 > 2.0 * cd, "{f8}");
        assert_eq!(run_wave_friction_factor(0.4, 8.0, d50, cd), f8);
        // 1000 s: Eq. 60a gives 6e-4, below 2 C_D
        assert!(wave_friction_factor(0.3, 1000.0, d50) < 2.0 * cd);
        assert_eq!(run_wave_friction_factor(0.3, 1000.0, d50, cd), 2.0 * cd);
        assert_eq!(run_wave_friction_factor(0.0, 8.0, d50, cd), 0.0);
        // the floor keeps to the factor's own limit, whatever the drag coefficient
        assert_eq!(
            run_wave_friction_factor(0.3, 1000.0, d50, 0.6),
            WAVE_FRICTION_MAX
        );
    }

    #[test]
    fn wave_friction_factor_soulsby_eq_60a() {
        // A = 0.4 m/s x pi s / (2 pi) = 0.2 m over 0.3 mm sand: z0 = 25 um, A / z0 = 8000,
        // f_w = 1.39 x 8000^-0.52 = 0.01299
        let f = wave_friction_factor(0.4, PI, 0.3e-3);
        assert!((f - 0.012_99).abs() < 1e-5, "{f}");
        // the same law in the roughness ks = 2.5 d50 (z0 = ks / 30): 0.237 (A / ks)^-0.52
        let ks: f64 = 2.5 * 0.3e-3;
        assert!((f - 0.237 * (0.2 / ks).powf(-0.52)).abs() < 1e-5);
        // longer excursions rub less; a few grain roughnesses hit the upper limit
        assert!(wave_friction_factor(0.4, 2.0 * PI, 0.3e-3) < f);
        assert_eq!(wave_friction_factor(0.001, 0.1, 0.3e-3), WAVE_FRICTION_MAX);
        assert_eq!(wave_friction_factor(0.0, 8.0, 0.3e-3), 0.0);
    }
}
