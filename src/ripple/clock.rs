//! [`StepClock`]: the physical duration of one step of a ripple run, from a bedload transport
//! law, so that a run can be asked for by duration (`--duration 2h`) and reports the time it
//! simulated.
//!
//! **Transport law.** E. Meyer-Peter and R. Mueller (1948), "Formulas for bed-load transport",
//! *Proc. 2nd Meeting IAHR*, Stockholm, 39-64: `q_b = 8 (theta - theta_cr)^1.5
//! sqrt(g (s - 1) d^3)` (m^2/s of grain volume per metre of width), with the Shields number
//! of the median grain and its threshold as in [`super::regime`]. With a wave, the law is
//! averaged over the cycle (64 phases of the flow of [`RippleParams::combined_flow`]: `U_w
//! sin(phi) e_w` for waves alone; with a current the speed of their combined stress), and so is the model's
//! flux, so that the step duration does not depend on the wave period.
//!
//! **The model's flux.** A step activates `activity x automata` automata; on a flat bed each
//! travels a mean distance `l` (m), measured once per run by setting grains off one at a time
//! on a flat bed of the run's sediment and flow (a 32 x 32 patch, or 64 columns in 2-D; with
//! a travel in metres at least 0.25 m along the flow, and across it too except for a run with
//! its bin in travels in the flow frame; 2,000 grains per wave phase, a stream of its own so
//! the run itself is unchanged): in phases where no grain class can move, nothing is
//! activated. Each automaton holds `gd (1 - eps)`
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

/// The smallest free-stream speed, m/s, at which the model's rules carry a grain of `d` m one
/// bin forward on a flat bed: its budget `friction x bin_size x hop_length x (theta /
/// theta_cr - 1)` must pay the first hop, `friction x sqrt(bin_size^2 + (2 gd)^2) + gd` (onto
/// the neighbour's top, Eqs. 1, 4, 7). Below it a triggered grain of that size stays (or
/// creeps, which a flat bed does not allow), however large the transport law's bedload.
pub fn model_threshold_speed(p: &RippleParams, d: f64) -> f64 {
    let (dx, gd, mu) = (p.bin_size, p.layer_thickness, p.friction);
    let cost = mu * (dx * dx + 4.0 * gd * gd).sqrt() + gd;
    let stage = if p.hop_grains > 0.0 {
        cost / (mu * p.hop_metres(d))
    } else {
        cost / (mu * dx * p.hop_length)
    };
    let theta = (1.0 + stage) * theta_cr(d);
    (theta * (RHO_S - RHO_W) * G * d / (RHO_W * p.drag_coefficient)).sqrt()
}

/// [`model_threshold_speed`] of the run's finest grain class and of its median grain: (finest,
/// median), m/s. Below the first no grain of the model moves on a flat bed; between the two
/// only the rare fine grains do.
pub fn model_threshold_speeds(p: &RippleParams) -> (f64, f64) {
    let classes = super::grain::GrainClasses::new(p.d50, p.sorting);
    let finest = classes
        .d
        .iter()
        .map(|&d| model_threshold_speed(p, d))
        .fold(f64::INFINITY, f64::min);
    (finest, model_threshold_speed(p, p.d50 * 1e-3))
}

/// The free-stream speeds of the phases a run's flux is averaged over: the current alone, or
/// 64 phases of the wave cycle (the magnitude of [`RippleParams::combined_flow`]).
pub fn phase_speeds(p: &RippleParams) -> Vec<f64> {
    if !p.has_wave() {
        return vec![p.current_speed.abs()];
    }
    let c = p.lattice_current_angle().to_radians();
    let w = p
        .lattice_wave_angle()
        .unwrap_or(p.lattice_current_angle())
        .to_radians();
    (0..PHASES)
        .map(|k| {
            let s = (2.0 * std::f64::consts::PI * (k as f64 + 0.5) / PHASES as f64).sin();
            let (ux, uy) = p.combined_flow(c, w, s);
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

pub use super::travel::median_travel;

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
        // the run's own bin ([`RippleParams::with_travel_bin`])
        let p = &p.with_orbit_scale().with_travel_bin();
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

    /// Whether the model's grains move on the flat bed (a positive travel): false when the
    /// transport law moves sand but the rules carry none of the measured grains a bin (flows
    /// just above the threshold of motion, [`model_threshold_speeds`]); the step then has no
    /// duration.
    pub fn grains_move(&self) -> bool {
        self.travel > 0.0 && self.step_s.is_finite() && self.step_s > 0.0
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
                expected: if self.bedload > 0.0 {
                    "a flow whose grains move in the model (the rules carry no grain a bin on a flat bed here, so a step has no duration)".into()
                } else {
                    "a flow that moves sand (the transport law gives no bedload here, so a step has no duration)".into()
                },
            });
        }
        let n = (seconds / self.step_s).round();
        // (the steps' own limit, 2^40)
        let most = (1u64 << 40) as f64;
        if !(n.is_finite() && n <= most) {
            return Err(RippleError::Range {
                parameter: "duration",
                value: shown,
                expected: format!(
                    "at most 2^40 steps (the limit of steps) of {:.4} s ({:.3e} s)",
                    self.step_s,
                    most * self.step_s
                ),
            });
        }
        Ok((n as u64).max(1))
    }
}

/// The phases of the wave cycle the flux is averaged over ([`phase_speeds`],
/// [`flat_bed_travel`]).
pub const PHASES: u64 = 64;

/// The flat calibration patch of the run `p`: its sediment and flow on 32 x 32 columns (64 x 1
/// in 2-D), a wave (if any) of [`PHASES`] steps, so that its steps `0..PHASES` are the phases
/// `(k + 1/2) / PHASES` of one whole cycle whatever the run's period in steps.
fn patch(p: &RippleParams) -> RippleParams {
    let (nx, ny) = if p.mode == Mode::TwoD {
        (64, 1)
    } else {
        (32, 32)
    };
    // A travel in metres (`hop_grains`) must not wrap around the patch: at least 0.25 m along
    // the flow (six mean travels of 4 cm; an exponential travel's tail beyond is e^-6).
    // Across the flow a run with its bin in travels (`bin_travels`) keeps 32 rows in the flow
    // frame, where the travel runs along x (on a flat bed the straight step is the cheapest),
    // so that a patch of fine bins stays small.
    let (nx, ny) = if p.hop_grains > 0.0 {
        let n = ((0.25 / p.bin_size).ceil() as usize).clamp(nx, 4096);
        let across = if p.mode == Mode::TwoD {
            1
        } else if p.bin_travels > 0.0 && p.frame == super::params::Frame::Flow {
            ny
        } else {
            n.max(ny)
        };
        (n, across)
    } else {
        (nx, ny)
    };
    RippleParams {
        nx,
        ny,
        roughness: 0,
        wave_period: if p.has_wave() { PHASES as f64 } else { 0.0 },
        until: None,
        ..p.clone()
    }
}

/// The calibration patch's own random stream, derived from the run's seed (any seed of
/// [`RippleParams::validate`]'s range; the derived value is not a parameter).
fn patch_stream(p: &RippleParams) -> u64 {
    p.seed ^ 0x5EED_C10C
}

/// The mean distance (m) an activated grain travels on a flat bed of the run's sediment and
/// flow, averaged over the wave phases (0 in phases where nothing is activated), and the
/// porosity of that (initial) bed.
pub fn flat_bed_travel(p: &RippleParams) -> Result<(f64, f64), RippleError> {
    // on the run's own bin ([`RippleParams::with_travel_bin`])
    let q = patch(&p.with_orbit_scale().with_travel_bin());
    let (nx, ny) = (q.nx, q.rows());
    let h0 = q.layers.max(1);
    let mut r = Ripple::from_heights_seeded(&q, &vec![h0; nx * ny], patch_stream(p))?;
    let eps = porosity(r.compaction().initial_code());
    // the wave's phases: step k of the patch's 64-step period is phase (k + 1/2) / 64, whatever
    // the run's period (so the step duration does not depend on it)
    let phases: Vec<u64> = if p.has_wave() {
        (0..PHASES).collect()
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

    /// `hop x (theta / theta_cr - 1)` of the median grain: 0.2 mm sand (theta_cr 0.0554) at
    /// 0.5 m/s (theta 0.2016), 37.5 d50 per unit of excess stage: 7.5 mm x 2.642 = 19.8 mm.
    #[test]
    fn median_travel_is_the_hop_times_the_excess_shields_stage() {
        let p = RippleParams {
            hop_grains: 37.5,
            ..RippleParams::default()
        };
        let t = median_travel(&p, 0.5);
        assert!(
            (t - 37.5 * 0.2e-3 * (0.201573 / 0.0553544 - 1.0)).abs() < 1e-5,
            "{t}"
        );
        // none in a flow that does not move the median grain
        assert_eq!(median_travel(&p, 0.1), 0.0);
        // in bins without `hop_grains`: 1.5 bins of 5 mm per unit of excess stage
        let bins = median_travel(&RippleParams::default(), 0.5);
        assert!((bins - 1.5 * 0.005 * 2.6415).abs() < 1e-5, "{bins}");
    }

    #[test]
    fn a_travel_in_grain_diameters_does_not_depend_on_the_bin() {
        // `hop_grains`: the flat-bed travel is a length in metres (37.5 d50 per unit excess
        // Shields stage), so bins of 2.5, 5 and 10 mm give the same mean travel (within the
        // calibration's sampling noise and the part-bin rounding); `hop_length` (bins) doubles
        // with the bin.
        let travel = |b: f64, grains: f64, exponential: bool| {
            let p = RippleParams {
                mode: Mode::TwoD,
                nx: 64,
                ny: 1,
                bin_size: b,
                layer_thickness: b / 10.0,
                layers: 20,
                hop_grains: grains,
                hop_exponential: exponential,
                ..RippleParams::default()
            };
            flat_bed_travel(&p).unwrap().0
        };
        for exponential in [false, true] {
            let mid = travel(0.005, 37.5, exponential);
            assert!(mid > 0.015 && mid < 0.025, "{mid}");
            for b in [0.0025, 0.01] {
                let t = travel(b, 37.5, exponential);
                assert!(
                    (t / mid - 1.0).abs() < 0.08,
                    "exponential {exponential}: bin {b} travel {t} against {mid}"
                );
            }
        }
        let (a, b) = (travel(0.0025, 0.0, false), travel(0.01, 0.0, false));
        assert!(b / a > 3.0, "hop_length in bins: {a} {b}");
    }

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

    #[test]
    fn the_largest_seed_has_a_clock() {
        let p = RippleParams {
            nx: 16,
            ny: 8,
            layers: 8,
            seed: 1 << 53,
            ..RippleParams::default()
        };
        let c = StepClock::of(&p).unwrap();
        assert!(c.grains_move(), "{c:?}");
    }

    #[test]
    fn the_step_does_not_depend_on_the_wave_period_in_steps() {
        let p = RippleParams {
            nx: 16,
            ny: 8,
            layers: 8,
            current_speed: 0.3,
            wave_amplitude: 0.3,
            wave_angle: Some(30.0),
            wave_friction_factor: 0.01,
            wave_period: 64.0,
            ..RippleParams::default()
        };
        let c = StepClock::of(&p).unwrap();
        for period in [2.5, 412.2, 1e6] {
            let q = RippleParams {
                wave_period: period,
                ..p.clone()
            };
            assert_eq!(StepClock::of(&q).unwrap(), c, "{period}");
        }
    }

    #[test]
    fn grains_move_from_the_model_threshold() {
        // one grain class: the rules move it from model_threshold_speed on
        let p = RippleParams {
            sorting: 0.0,
            ..RippleParams::default()
        };
        let (finest, median) = model_threshold_speeds(&p);
        assert_eq!(finest, median);
        // above the transport law's threshold (0.262 m/s), below the model's (0.351 m/s)
        assert!((median - 0.351).abs() < 0.001, "{median}");
        let at = |u: f64| {
            StepClock::of(&RippleParams {
                current_speed: u,
                ..p.clone()
            })
            .unwrap()
        };
        let below = at(0.995 * median);
        assert!(below.bedload > 0.0 && !below.grains_move(), "{below:?}");
        let e = below.steps_for(20.0).unwrap_err().to_string();
        assert!(e.contains("rules carry no grain"), "{e}");
        assert!(at(1.005 * median).grains_move());
    }
}
