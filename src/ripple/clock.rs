//! [`StepClock`]: the physical duration of one step of a ripple run, from a bedload transport
//! law, so that a run can be asked for by duration (`--duration 2h`) and reports the time it
//! simulated.
//!
//! **Transport law.** E. Meyer-Peter and R. Mueller (1948), "Formulas for bed-load transport",
//! *Proc. 2nd Meeting IAHR*, Stockholm, 39-64: `q_b = 8 (theta - theta_cr)^1.5
//! sqrt(g (s - 1) d^3)` (m^2/s of grain volume per metre of width), with the Shields number
//! of the median grain and its threshold as in [`super::regime`]. With a wave, the law is
//! averaged over the cycle (64 phases of `|U_c e_c + U_w sin(phi) e_w|`), and so is the model's
//! flux, so that the step duration does not depend on the wave period.
//!
//! **The model's flux.** A step activates `activity x automata` automata; on a flat bed each
//! travels a mean distance `l` (m), measured once per run by setting grains off one at a time
//! on a flat bed of the run's sediment and flow (a 32 x 32 patch, or 64 columns in 2-D;
//! 2,000 grains per wave phase, a stream of its own so the run itself is unchanged): in phases
//! where no grain class can move, nothing is activated. Each automaton holds `gd (1 - eps)`
//! m of solid per unit bed area (`eps` the initial bed's porosity), so the model moves
//! `activity x layers x gd (1 - eps) x l` m^2 of grains per metre of width and per step.
//!
//! **Step duration.** Equating the two fluxes on a flat bed:
//! `dt = activity x layers x gd x (1 - eps) x l / q_b`. This is bookkeeping on top of the
//! paper's rules: it gives the steps a duration, it does not change what a step does. The
//! ripples' size is still set by the rules' lengths in bins (`docs/ripple.md`).

use rand::RngExt;

use super::compaction::porosity;
use super::grain::{G, RHO_S, RHO_W, theta_cr};
use super::model::Ripple;
use super::params::{Mode, RippleParams};
use super::regime::{bed_shear_stress, shields};
use super::{RippleError, water::Flow};

/// Grains set off per wave phase to measure the flat-bed travel.
pub const CALIBRATION_GRAINS: usize = 2000;

/// Meyer-Peter & Mueller (1948) bedload `q_b = 8 (theta - theta_cr)^1.5 sqrt(g (s - 1) d^3)`,
/// m^2/s of grain volume per metre of width, for grains of `d` m at a Shields number `theta`;
/// 0 below the threshold of motion (Soulsby 1997, Eq. 77).
pub fn meyer_peter_mueller(theta: f64, d: f64) -> f64 {
    let excess = theta - theta_cr(d);
    if excess <= 0.0 {
        return 0.0;
    }
    let s = RHO_S / RHO_W;
    8.0 * excess.powf(1.5) * (G * (s - 1.0) * d * d * d).sqrt()
}

/// Whether the run has a wave.
fn has_wave(p: &RippleParams) -> bool {
    p.wave_period > 0.0 && p.wave_amplitude > 0.0
}

/// The free-stream speeds of the phases a run's flux is averaged over: the current alone, or
/// 64 phases of the wave cycle (the magnitude of `U_c e_c + U_w sin(phi) e_w`).
pub fn phase_speeds(p: &RippleParams) -> Vec<f64> {
    if !has_wave(p) {
        return vec![p.current_speed.abs()];
    }
    let c = p.lattice_current_angle().to_radians();
    let w = p
        .lattice_wave_angle()
        .unwrap_or(p.lattice_current_angle())
        .to_radians();
    (0..64)
        .map(|k| {
            let s = (2.0 * std::f64::consts::PI * (k as f64 + 0.5) / 64.0).sin();
            let ux = p.current_speed * c.cos() + p.wave_stress_amplitude() * s * w.cos();
            let uy = p.current_speed * c.sin() + p.wave_stress_amplitude() * s * w.sin();
            ux.hypot(uy)
        })
        .collect()
}

/// The bedload of the transport law for the run `p`, averaged over its phases, m^2/s.
pub fn mean_bedload(p: &RippleParams) -> f64 {
    let d = p.d50 * 1e-3;
    let v = phase_speeds(p);
    v.iter()
        .map(|&u| meyer_peter_mueller(shields(bed_shear_stress(u, p.drag_coefficient), d), d))
        .sum::<f64>()
        / v.len() as f64
}

/// The duration of a step and what it was computed from (module docs).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StepClock {
    /// Seconds per step; infinite when the transport law moves nothing (no motion).
    pub step_s: f64,
    /// The transport law's bedload, phase-averaged, m^2/s.
    pub bedload: f64,
    /// The model's mean flat-bed travel per activation, phase-averaged (0 in phases where
    /// nothing is activated), m.
    pub travel: f64,
    /// Porosity of the initial bed.
    pub porosity: f64,
}

impl StepClock {
    /// The clock of the run `p` (module docs).
    pub fn of(p: &RippleParams) -> Result<StepClock, RippleError> {
        let (travel, eps) = flat_bed_travel(p)?;
        let bedload = mean_bedload(p);
        let per_step = p.activity * p.layers as f64 * p.layer_thickness * (1.0 - eps) * travel;
        let step_s = if bedload > 0.0 {
            per_step / bedload
        } else {
            f64::INFINITY
        };
        Ok(StepClock {
            step_s,
            bedload,
            travel,
            porosity: eps,
        })
    }

    /// Steps that make `seconds` (at least 1), or an error naming `--duration` when the
    /// transport law moves nothing.
    pub fn steps_for(&self, seconds: f64) -> Result<u64, RippleError> {
        let shown = if seconds.abs() >= 1e6 {
            format!("{seconds:e} s")
        } else {
            format!("{seconds} s")
        };
        if !(self.step_s.is_finite() && self.step_s > 0.0) {
            return Err(RippleError::Range {
                parameter: "duration",
                value: shown.clone(),
                expected: "a flow that moves sand (the transport law gives no bedload here, so a step has no duration)".into(),
            });
        }
        let n = (seconds / self.step_s).round();
        if !(n.is_finite() && n <= 1e12) {
            return Err(RippleError::Range {
                parameter: "duration",
                value: shown,
                expected: format!(
                    "at most 1e12 steps of {:.4} s ({:.3e} s)",
                    self.step_s,
                    1e12 * self.step_s
                ),
            });
        }
        Ok((n as u64).max(1))
    }
}

/// The flat calibration patch of the run `p`: its sediment and flow on 32 x 32 columns (64 x 1
/// in 2-D), seeded from the run's seed.
fn patch(p: &RippleParams) -> RippleParams {
    let (nx, ny) = if p.mode == Mode::TwoD {
        (64, 1)
    } else {
        (32, 32)
    };
    RippleParams {
        nx,
        ny,
        roughness: 0,
        seed: p.seed ^ 0x5EED_C10C,
        ..p.clone()
    }
}

/// The mean distance (m) an activated grain travels on a flat bed of the run's sediment and
/// flow, averaged over the wave phases (0 in phases where nothing is activated), and the
/// porosity of that (initial) bed.
pub fn flat_bed_travel(p: &RippleParams) -> Result<(f64, f64), RippleError> {
    let q = patch(p);
    let (nx, ny) = (q.nx, q.rows());
    let h0 = q.layers.max(1);
    let mut r = Ripple::from_heights(&q, &vec![h0; nx * ny])?;
    let eps = porosity(r.compaction().initial_code());
    // the wave's phases: step k of a 64-step period is phase (k + 1/2) / 64, whatever the
    // run's period (so the step duration does not depend on it)
    let phases: Vec<u64> = if has_wave(p) {
        (0..64).collect()
    } else {
        vec![0]
    };
    let wrap = |d: i64, len: usize| {
        let l = len as i64;
        (d + l / 2).rem_euclid(l) - l / 2
    };
    let mut total = 0.0;
    for &t in &phases {
        let f: Flow = r.flow_at(t);
        if !r.classes().any_moves(f.speed, p.drag_coefficient) {
            continue;
        }
        let (mut sum, mut n) = (0.0, 0usize);
        let mut tries = 0;
        while n < CALIBRATION_GRAINS && tries < 50 * CALIBRATION_GRAINS {
            tries += 1;
            let c = r.rng.random_range(0..nx * ny);
            if !r.trigger(c, &f) {
                continue;
            }
            n += 1;
            // where it went (the one column above the flat bed), and back
            if let Some(to) = (0..nx * ny).find(|&k| r.vol.height(k) > h0) {
                let dx = wrap((to % nx) as i64 - (c % nx) as i64, nx) as f64;
                let dy = wrap((to / nx) as i64 - (c / nx) as i64, ny) as f64;
                sum += dx.hypot(dy) * p.bin_size;
                if let Some(a) = r.vol.pop(to) {
                    r.vol.push(c, a);
                }
            }
        }
        if n > 0 {
            total += sum / n as f64;
        }
    }
    Ok((total / phases.len() as f64, eps))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meyer_peter_mueller_law() {
        let d = 0.2e-3;
        assert_eq!(meyer_peter_mueller(0.5 * theta_cr(d), d), 0.0);
        // theta = theta_cr + 0.1: 8 x 0.1^1.5 sqrt(g (s - 1) d^3)
        let s = RHO_S / RHO_W;
        let want = 8.0 * 0.1f64.powf(1.5) * (G * (s - 1.0) * d.powi(3)).sqrt();
        assert!((meyer_peter_mueller(theta_cr(d) + 0.1, d) - want).abs() < 1e-18);
        // by hand: 8 x 0.0316228 x sqrt(9.81 x 1.5803 x 8e-12) = 0.252982 x 1.11362e-5
        assert!((want - 2.8173e-6).abs() < 0.0005e-6, "{want}");
    }

    #[test]
    fn step_duration_balances_the_fluxes_and_scales_with_activity() {
        let p = RippleParams::default();
        let c = StepClock::of(&p).unwrap();
        assert!(c.travel > 0.0 && c.bedload > 0.0, "{c:?}");
        let want = p.activity * p.layers as f64 * p.layer_thickness * (1.0 - c.porosity) * c.travel
            / c.bedload;
        assert!((c.step_s - want).abs() < 1e-15 * want);
        // twice the activity moves twice the sand per step: twice the duration
        let c2 = StepClock::of(&RippleParams {
            activity: 2.0 * p.activity,
            ..p.clone()
        })
        .unwrap();
        assert!((c2.step_s / c.step_s - 2.0).abs() < 1e-12);
        // a faster current moves more sand per second: shorter steps
        let fast = StepClock::of(&RippleParams {
            current_speed: 0.8,
            ..p.clone()
        })
        .unwrap();
        assert!(fast.step_s < c.step_s, "{fast:?} vs {c:?}");
        // steps for a duration
        assert_eq!(c.steps_for(100.0 * c.step_s).unwrap(), 100);
        // no motion: no duration
        let still = StepClock::of(&RippleParams {
            current_speed: 0.1,
            ..p
        })
        .unwrap();
        assert!(still.step_s.is_infinite());
        assert!(
            still
                .steps_for(10.0)
                .unwrap_err()
                .to_string()
                .contains("duration")
        );
    }
}
