//! Running a ripple field until it is mature: [`run_until_mature`] measures the field
//! ([`Analysis`]) at doubling checkpoints and stops when its wavelength and its height changed
//! by less than [`TOLERANCE`] over [`PAIRS`] successive doublings (from `t` to `2 t` and from
//! `2 t` to `4 t`: [`mature`] for each pair, [`Judge`] for the sequence), or at a cap.
//!
//! The checkpoints are [`FIRST_CHECK`] steps and its doublings (and the cap, which is judged
//! only where it is a doubling). Two doublings, not one, because fields pause while they
//! coarsen: a field can change by less than 10 % between `t` and `2 t` and then grow again
//! (wave ripples without their lee vortex: 16.0 cm at 32,000 and 64,000 steps, 42.7 cm after
//! two hours, 521,129 steps). Only a field that has grown counts: its height must be at least
//! [`GROWN`] times the initial bed's (a bed that stays at its initial roughness has not formed ripples
//! yet, and coarse sand may need far longer to start), so a bed that never forms ripples runs
//! to the cap.
//!
//! Only a field with sand under all its troughs counts: once a trough has reached the
//! non-erodible substrate ([`Ripple::bare_fraction`] above zero at a checkpoint) the ripples
//! can grow no deeper, and a stop in their growth is the sand running out, not maturity. From
//! that checkpoint on no pair is judged (even if sand covers the spot again), the field runs
//! to the cap, and [`MatureRun::substrate_at`] says from which checkpoint the substrate
//! showed. The bed is looked at only at the checkpoints: a trough that touches the substrate
//! between two of them and is covered again goes unseen.

use super::model::Ripple;
use super::output::run_recording;
use super::spectrum::Analysis;

/// Relative change of wavelength and height below which a field counts as mature.
pub const TOLERANCE: f64 = 0.10;

/// The first checkpoint, steps.
pub const FIRST_CHECK: u64 = 1000;

/// How many times the initial bed's height a field must reach to count as formed.
pub const GROWN: f64 = 2.0;

/// How many successive doublings (pairs of checkpoints `t`, `2 t`) must each pass [`mature`].
pub const PAIRS: usize = 2;

/// The first step at which [`run_until_mature`] can find a field mature: the checkpoint that
/// ends [`PAIRS`] doublings after [`FIRST_CHECK`] (4000 steps).
pub const EARLIEST_STOP: u64 = FIRST_CHECK << PAIRS;

/// The field measured at a checkpoint of [`run_until_mature`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checkpoint {
    /// Steps since the start.
    pub step: u64,
    /// Dominant wavelength, m.
    pub wavelength_m: f64,
    /// Ripple height, m.
    pub height_m: f64,
    /// Share of the columns down to the substrate ([`Ripple::bare_fraction`]), in [0, 1].
    pub bare_fraction: f64,
}

/// Whether the field went from `before` (at `t`) to `after` (at `2 t`) changing its wavelength
/// and its height by less than [`TOLERANCE`] of their values at `t`, with a height at least
/// [`GROWN`] times `initial_height` (the bed's at step 0). False when either is not finite or
/// not positive: no ripples measured. (The steps and bare fractions are not looked at here:
/// [`Judge`] does that.)
pub fn mature(initial_height: f64, before: &Checkpoint, after: &Checkpoint) -> bool {
    let close =
        |a: f64, b: f64| a.is_finite() && b.is_finite() && a > 0.0 && (b - a).abs() < TOLERANCE * a;
    close(before.wavelength_m, after.wavelength_m)
        && close(before.height_m, after.height_m)
        && after.height_m >= GROWN * initial_height
}

/// The maturity test of [`run_until_mature`], fed one checkpoint at a time: a field is mature
/// at the checkpoint that ends [`PAIRS`] successive pairs `(t, 2 t)` each passing [`mature`],
/// with no bare column at any checkpoint so far.
#[derive(Clone, Debug)]
pub struct Judge {
    initial_height: f64,
    last: Option<Checkpoint>,
    passed: usize,
    substrate: bool,
}

impl Judge {
    /// A test for a field whose bed was `initial_height` (m) high at step 0.
    pub fn new(initial_height: f64) -> Self {
        Judge {
            initial_height,
            last: None,
            passed: 0,
            substrate: false,
        }
    }

    /// The field at the next checkpoint; true when the field is mature there. A pair whose
    /// second checkpoint is not at twice the first's step (a cap) counts as failed.
    pub fn mature_at(&mut self, c: &Checkpoint) -> bool {
        self.substrate |= c.bare_fraction > 0.0;
        let pass = self.last.as_ref().is_some_and(|b| {
            !self.substrate && c.step == 2 * b.step && mature(self.initial_height, b, c)
        });
        self.passed = if pass { self.passed + 1 } else { 0 };
        self.last = Some(*c);
        self.passed >= PAIRS
    }
}

/// What [`run_until_mature`] did.
#[derive(Clone, Debug)]
pub struct MatureRun {
    /// The elevation at each snapshot reached (steps since the start, elevation), and at the
    /// last step.
    pub snapshots: Vec<(u64, Vec<f32>)>,
    /// The step at which the field was found mature (`None`: the cap came first).
    pub mature_at: Option<u64>,
    /// The field at every checkpoint.
    pub checkpoints: Vec<Checkpoint>,
    /// The first checkpoint at which a trough had reached the substrate (`None`: sand under
    /// every trough at every checkpoint). From then on no pair of checkpoints is judged.
    pub substrate_at: Option<u64>,
}

/// Runs `r` until it is mature ([`Judge`]: [`PAIRS`] successive doublings each passing
/// [`mature`], with no bare column at any checkpoint so far) or `cap` steps, keeping the
/// elevation at each of `times` reached; `progress(done)` after each step.
pub fn run_until_mature(
    r: &mut Ripple,
    cap: u64,
    times: &[u64],
    mut progress: impl FnMut(u64),
) -> MatureRun {
    let mut snapshots = Vec::new();
    let mut checkpoints = Vec::new();
    let mut done = 0u64;
    let mut next = FIRST_CHECK.min(cap);
    let mut mature_at = None;
    let mut substrate_at = None;
    let mut judge = Judge::new(Analysis::of(r).height_m);
    while done < cap {
        let n = next - done;
        let rel: Vec<u64> = times
            .iter()
            .filter(|&&t| t > done && t <= next || (t == 0 && done == 0))
            .map(|&t| t - done)
            .collect();
        let base = done;
        for (t, e) in run_recording(r, n, &rel, |k| progress(base + k)) {
            snapshots.push((t, e));
        }
        done = next;
        let a = Analysis::of(r);
        let c = Checkpoint {
            step: done,
            wavelength_m: a.wavelength_m,
            height_m: a.height_m,
            bare_fraction: r.bare_fraction(),
        };
        checkpoints.push(c);
        if c.bare_fraction > 0.0 && substrate_at.is_none() {
            substrate_at = Some(done);
        }
        if judge.mature_at(&c) {
            mature_at = Some(done);
            break;
        }
        next = (2 * done).min(cap);
    }
    if snapshots.last().is_none_or(|s| s.0 != r.time()) {
        let e = r.elevation().iter().map(|&v| v as f32).collect();
        snapshots.push((r.time(), e));
    }
    MatureRun {
        snapshots,
        mature_at,
        checkpoints,
        substrate_at,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(wavelength_m: f64, height_m: f64) -> Checkpoint {
        Checkpoint {
            step: 1000,
            wavelength_m,
            height_m,
            bare_fraction: 0.0,
        }
    }

    /// Checkpoints at 1000 steps and its doublings, with these wavelengths and heights.
    fn run_of(fields: &[(f64, f64)]) -> Vec<Checkpoint> {
        fields
            .iter()
            .enumerate()
            .map(|(i, &(w, h))| Checkpoint {
                step: FIRST_CHECK << i,
                wavelength_m: w,
                height_m: h,
                bare_fraction: 0.0,
            })
            .collect()
    }

    /// The checkpoint (index) at which a [`Judge`] declares the run mature.
    fn judged(h0: f64, cps: &[Checkpoint]) -> Option<usize> {
        let mut j = Judge::new(h0);
        cps.iter().position(|c| j.mature_at(c))
    }

    #[test]
    fn mature_over_two_successive_doublings_not_at_a_pause() {
        let h0 = 0.002;
        // a pause (1.00 -> 1.05), growth again (+30 %), then two quiet doublings
        let cps = run_of(&[
            (0.10, 0.010),
            (0.105, 0.0102),
            (0.14, 0.014),
            (0.145, 0.0145),
            (0.15, 0.015),
            (0.15, 0.015),
        ]);
        assert_eq!(judged(h0, &cps), Some(4), "{cps:?}");
        // a field quiet from the start stops at the earliest checkpoint it can
        let still = run_of(&[(0.1, 0.01); 4]);
        assert_eq!(judged(h0, &still), Some(2));
        assert_eq!(still[2].step, EARLIEST_STOP);
        // one quiet doubling alone is a pause, not maturity
        assert_eq!(judged(h0, &cps[..4]), None);
        // a pair that is not a doubling (a cap at 1.5 t) does not count
        let mut capped = cps[..4].to_vec();
        capped.push(Checkpoint {
            step: 12_000,
            ..cps[4]
        });
        assert_eq!(judged(h0, &capped), None);
        // bare columns at any checkpoint: never mature from then on, even covered again
        let mut bare = cps.clone();
        bare[2].bare_fraction = 0.01;
        assert_eq!(judged(h0, &bare), None);
        assert_eq!(PAIRS, 2);
    }

    #[test]
    fn mature_when_both_change_by_under_ten_percent() {
        let h0 = 0.002;
        assert!(mature(h0, &field(0.10, 0.010), &field(0.109, 0.0091)));
        assert!(
            !mature(h0, &field(0.10, 0.010), &field(0.111, 0.010)),
            "wavelength grew 11 %"
        );
        assert!(
            !mature(h0, &field(0.10, 0.010), &field(0.10, 0.0115)),
            "height grew 15 %"
        );
        assert!(
            !mature(h0, &field(0.10, 0.010), &field(0.10, 0.0085)),
            "height fell 15 %"
        );
        assert!(
            !mature(h0, &field(f64::NAN, 0.010), &field(0.10, 0.010)),
            "no ripples measured"
        );
        assert!(
            !mature(h0, &field(0.0, 0.0), &field(0.0, 0.0)),
            "a flat bed is not mature"
        );
        assert!(
            !mature(h0, &field(0.06, 0.0025), &field(0.06, 0.0025)),
            "a bed still at its initial roughness has formed no ripples"
        );
    }

    #[test]
    fn a_field_down_to_the_substrate_is_never_mature() {
        use crate::ripple::RippleParams;
        // 3 mm of sand (6 automata) on a 12 x 6 cm domain: the troughs reach the substrate,
        // and the field then stalls at about 6 mm high
        let p = RippleParams {
            nx: 24,
            ny: 12,
            layers: 6,
            roughness: 1,
            seed: 3,
            ..RippleParams::default()
        };
        let mut r = Ripple::new(&p).unwrap();
        let h0 = Analysis::of(&r).height_m;
        let m = run_until_mature(&mut r, 128_000, &[], |_| {});
        let cps = &m.checkpoints;
        assert!(m.substrate_at.is_some(), "{cps:?}");
        assert_eq!(m.mature_at, None, "{cps:?}");
        assert_eq!(cps.last().unwrap().step, 128_000);
        // ... although wavelength and height alone pass the test between two checkpoints,
        // both with bare troughs
        let stalled = cps.windows(2).any(|w| {
            w[0].bare_fraction > 0.0 && w[1].bare_fraction > 0.0 && mature(h0, &w[0], &w[1])
        });
        assert!(stalled, "{cps:?}");
        assert_eq!(r.mass_change(), 0);
    }

    #[test]
    fn a_run_of_fewer_than_two_doublings_runs_to_the_cap() {
        use crate::ripple::RippleParams;
        let p = RippleParams {
            nx: 24,
            ny: 12,
            layers: 8,
            ..RippleParams::default()
        };
        let mut r = Ripple::new(&p).unwrap();
        let m = run_until_mature(&mut r, 2500, &[0, 2500], |_| {});
        // checkpoints 1000, 2000 and the cap: one doubling, and the cap's pair is no doubling,
        // so the field cannot be declared mature
        let steps: Vec<u64> = m.checkpoints.iter().map(|c| c.step).collect();
        assert_eq!(steps, [1000, 2000, 2500]);
        assert_eq!(m.mature_at, None);
        assert_eq!(m.snapshots.first().unwrap().0, 0);
        assert_eq!(m.snapshots.last().unwrap().0, r.time());
        assert_eq!(r.mass_change(), 0);
    }
}
