//! Sessions: one live run per open page, advanced a frame at a time.
//!
//! - [`GrowthSession`]: a growth scene ([`Growth`] and its random stream) with the page's
//!   controls: a frame of `speed` events ([`GrowthSession::frame`]), one explained pick
//!   ([`GrowthSession::explain`]: the paper's algorithm step by step, or the exact sampler's
//!   skipped rejections), the lattice as drawing states ([`GrowthSession::encode`]) and the
//!   live measurements ([`GrowthStats`]).
//! - [`RippleSession`]: a 2-D sand-ripple section (the ripple model's Fig. 2 style: sand,
//!   water slices by speed, exposed grains) with the current's speed and angle.
//!
//! A session depends only on its settings and the sequence of commands: the same seed gives
//! the same frames, and how the run is cut into frames never changes it (the samplers keep
//! their state across pauses).

use serde::Serialize;

use crate::engine::rng::{Stream, stream};
use crate::growth::Growth;
use crate::growth::observe::{self, ColumnProfile};
use crate::growth::sampler::{Outcome, Pick, SamplerKind};
use crate::growth::scene::{MAX_STEPS, Shape, WeightKind};
use crate::ripple::Ripple;

use super::ServeError;
use super::settings::{GrowthSettings, MAX_PICKS_PER_FRAME, RippleSettings};

/// Frame kinds: the first byte of a binary message.
pub const FRAME_GROWTH: u8 = 1;
/// A ripple section frame.
pub const FRAME_RIPPLE: u8 = 2;

/// The live measurements of a growth session, sent with every frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GrowthStats {
    /// The paper's clock: Monte Carlo timesteps (picks; CA updates for the CA).
    pub time: f64,
    /// Accepted events (cells added).
    pub accepted: u64,
    /// Occupied cells.
    pub occupied: usize,
    /// Surface sites.
    pub surface: usize,
    /// Acceptance ratio: accepted events over picks (the clock).
    pub acceptance: f64,
    /// The scene's observable: its name.
    pub observable: &'static str,
    /// The observable's value (`None` where not defined yet).
    pub value: Option<f64>,
    /// Interface width `w` (cell widths) on a flat substrate, else `None`.
    pub width_w: Option<f64>,
    /// Why the run cannot go on (`None` while it can).
    pub stopped: Option<&'static str>,
}

/// One explained step, as sent to the page.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Explained {
    /// The sampler that made it.
    pub sampler: SamplerKind,
    /// The pick (rejection) or acceptance (exact); `None` for a CA update.
    pub pick: Option<Pick>,
    /// Column and row of the picked cell.
    pub x: usize,
    /// Row of the picked cell.
    pub y: usize,
    /// The exponent `n`.
    pub n: f64,
    /// Exact sampler: the mean acceptance probability of a pick before the step,
    /// `P = sum(p) / S`, which makes the skipped count geometric with mean `(1 - P) / P`.
    pub mean_p: Option<f64>,
    /// CA: cells added by the update.
    pub grown: usize,
    /// The clock after the step.
    pub time: f64,
}

/// A growth session.
pub struct GrowthSession {
    settings: GrowthSettings,
    g: Growth,
    rng: Stream,
    stopped: Option<&'static str>,
}

fn outcome_stop(o: Outcome) -> Option<&'static str> {
    match o {
        Outcome::Exhausted => Some("no surface site left: the lattice is full"),
        Outcome::Stalled => Some("every surface site has p = 0: nothing can grow"),
        Outcome::ClockOverflow => Some(
            "the next acceptance lies beyond the largest timestep (n too large for this surface)",
        ),
        _ => None,
    }
}

impl GrowthSession {
    /// A session at time 0.
    pub fn new(settings: GrowthSettings) -> Result<Self, ServeError> {
        let g = settings
            .scene
            .build()
            .map_err(|e| ServeError::Scene(e.to_string()))?;
        let rng = stream(settings.scene.seed);
        Ok(GrowthSession {
            settings,
            g,
            rng,
            stopped: None,
        })
    }

    /// The settings.
    pub fn settings(&self) -> &GrowthSettings {
        &self.settings
    }
    /// The growth state.
    pub fn growth(&self) -> &Growth {
        &self.g
    }

    /// Back to time 0 with the same settings (and seed).
    pub fn reset(&mut self) -> Result<(), ServeError> {
        *self = GrowthSession::new(self.settings.clone())?;
        Ok(())
    }

    /// Events per frame (1..=[`super::settings::MAX_SPEED`]).
    pub fn set_speed(&mut self, speed: u64) {
        self.settings.speed = speed.clamp(1, super::settings::MAX_SPEED);
    }

    /// Runs one frame: `speed` accepted events (exact), acceptances up to
    /// [`MAX_PICKS_PER_FRAME`] picks (rejection) or CA updates. Returns the events done.
    pub fn frame(&mut self) -> u64 {
        if self.stopped.is_some() {
            return 0;
        }
        let speed = self.settings.speed;
        let limit = MAX_STEPS as f64;
        let mut done = 0;
        match self.settings.scene.sampler {
            SamplerKind::Exact => {
                while done < speed {
                    match self.g.step_exact(&mut self.rng, limit) {
                        Outcome::Accepted(_) => done += 1,
                        o => {
                            self.stopped = outcome_stop(o).or(Some(
                                "the clock reached 2^53 timesteps: the next acceptance lies beyond it",
                            ));
                            break;
                        }
                    }
                }
            }
            SamplerKind::Rejection => {
                let end = (self.g.time() + MAX_PICKS_PER_FRAME as f64).min(limit);
                while done < speed {
                    match self.g.step_rejection(&mut self.rng, end) {
                        Outcome::Accepted(_) => done += 1,
                        Outcome::Limit => break,
                        o => {
                            self.stopped = outcome_stop(o);
                            break;
                        }
                    }
                }
            }
            SamplerKind::Ca => {
                let rule = &self.settings.scene.ca_rule;
                for _ in 0..speed.min(64) {
                    if self.stopped.is_some() {
                        break;
                    }
                    if self.g.surface().is_empty() {
                        self.stopped = outcome_stop(Outcome::Exhausted);
                        break;
                    }
                    let k = self.g.time() as usize % rule.len();
                    self.g.step_ca(rule[k]);
                    done += 1;
                }
            }
        }
        if self.settings.scene.shape == Shape::Flat && self.stopped.is_none() {
            // A flat substrate's front must stay clear of the ceiling for its width to mean
            // anything: stop two rows below it.
            let l = self.g.lattice();
            let row = l.height().saturating_sub(3);
            if (0..l.width()).any(|x| self.g.is_occupied(l.index(x, row))) {
                self.stopped = Some("the front reached the top of the lattice");
            }
        }
        done
    }

    /// One step explained: a single pick of the paper's algorithm (rejection sampler), a
    /// single acceptance with its skipped rejections (exact sampler), or one CA update.
    /// `None` when the run cannot go on.
    pub fn explain(&mut self) -> Option<Explained> {
        if self.stopped.is_some() {
            return None;
        }
        let sampler = self.settings.scene.sampler;
        let mean_p = (sampler == SamplerKind::Exact).then(|| {
            let s = self.g.surface().len().max(1) as f64;
            self.g
                .surface()
                .sites()
                .iter()
                .map(|&c| self.g.probability(c as usize))
                .sum::<f64>()
                / s
        });
        let (pick, grown) = match sampler {
            SamplerKind::Rejection => (self.g.pick_rejection(&mut self.rng), 0),
            SamplerKind::Exact => (self.g.pick_exact(&mut self.rng), 0),
            SamplerKind::Ca => {
                if self.g.surface().is_empty() {
                    (None, 0)
                } else {
                    let rule = &self.settings.scene.ca_rule;
                    let k = self.g.time() as usize % rule.len();
                    (None, self.g.step_ca(rule[k]))
                }
            }
        };
        if pick.is_none() && sampler != SamplerKind::Ca {
            self.stopped = Some("nothing can be accepted any more");
            return None;
        }
        let (x, y) = pick.map_or((0, 0), |p| self.g.lattice().coords(p.cell));
        Some(Explained {
            sampler,
            pick,
            x,
            y,
            n: self.settings.scene.n,
            mean_p,
            grown,
            time: self.g.time(),
        })
    }

    /// The live measurements.
    pub fn stats(&self) -> GrowthStats {
        let g = &self.g;
        let cfg = &self.settings.scene;
        let centre = cfg.centre(g.lattice());
        let (observable, value) = match (cfg.shape, cfg.weight, cfg.sampler) {
            (Shape::Flat, _, _) => ("interface width w", Some(observe::interface_width(g))),
            (Shape::Cosine, _, _) => (
                "mode-1 amplitude",
                Some(ColumnProfile::of(g).mode1_amplitude()),
            ),
            (_, WeightKind::Axes, _) | (_, _, SamplerKind::Ca) => (
                "axis/diagonal ratio",
                observe::axis_diagonal_ratio(g, centre),
            ),
            _ => ("front radius CV", observe::front_radius_cv(g, centre, 36)),
        };
        let width_w = (cfg.shape == Shape::Flat).then_some(value).flatten();
        GrowthStats {
            time: g.time(),
            accepted: g.accepted(),
            occupied: g.occupied(),
            surface: g.surface().len(),
            acceptance: if g.time() > 0.0 {
                g.accepted() as f64 / g.time()
            } else {
                0.0
            },
            observable,
            value,
            width_w,
            stopped: self.stopped,
        }
    }

    /// The lattice as one binary frame: `[FRAME_GROWTH, hex (0/1), width u32 LE,
    /// height u32 LE]` then one drawing state per cell, `y * width + x` (0 empty, 1 surface,
    /// 2 occupied).
    pub fn encode(&self, out: &mut Vec<u8>) {
        let l = self.g.lattice();
        out.clear();
        out.reserve(10 + l.len());
        out.push(FRAME_GROWTH);
        out.push(l.neighbourhood().is_hex() as u8);
        out.extend_from_slice(&(l.width() as u32).to_le_bytes());
        out.extend_from_slice(&(l.height() as u32).to_le_bytes());
        out.extend(self.g.field_states());
    }
}

/// The live measurements of a ripple session.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RippleStats {
    /// Model steps.
    pub time: u64,
    /// Free-stream current speed, m/s.
    pub current_speed: f64,
    /// Current direction, degrees counter-clockwise from +x.
    pub current_angle: f64,
    /// Grains on the bed exposed to the flow (would move).
    pub exposed: usize,
    /// Crest-to-trough height of the bed, automata.
    pub relief: usize,
    /// Activations (grain moves) so far.
    pub activations: u64,
}

/// A 2-D sand-ripple section.
pub struct RippleSession {
    settings: RippleSettings,
    r: Ripple,
}

impl RippleSession {
    /// A section at step 0.
    pub fn new(settings: RippleSettings) -> Result<Self, ServeError> {
        let r = Ripple::new(&settings.params).map_err(|e| ServeError::Scene(e.to_string()))?;
        Ok(RippleSession { settings, r })
    }

    /// Back to step 0 with the same settings (the current as last set).
    pub fn reset(&mut self) -> Result<(), ServeError> {
        let mut p = self.settings.params.clone();
        p.current_speed = self.r.params().current_speed;
        p.current_angle = self.r.params().current_angle;
        self.settings.params = p;
        *self = RippleSession::new(self.settings.clone())?;
        Ok(())
    }

    /// Steps per frame, 1..=200.
    pub fn set_speed(&mut self, speed: u64) {
        self.settings.speed = speed.clamp(1, 200);
    }

    /// The current from the next step on (speed m/s, angle degrees).
    pub fn set_current(&mut self, speed: f64, angle: f64) -> Result<(), ServeError> {
        self.r
            .set_current(speed, angle)
            .map_err(|e| ServeError::Scene(e.to_string()))
    }

    /// Runs one frame of `speed` model steps.
    pub fn frame(&mut self) -> u64 {
        let n = self.settings.speed;
        self.r.run(n, |_| {});
        n
    }

    /// The window of levels drawn: from 20 automata below the initial bed to 30 above.
    fn window(&self) -> (usize, usize) {
        let layers = self.settings.params.layers;
        (layers.saturating_sub(20), layers + 30)
    }

    /// The section as one binary frame: `[FRAME_RIPPLE, 0, nx u32 LE, rows u32 LE]` then one
    /// byte per cell, rows from the bottom up: 255 sand, 250 an exposed grain (the top grain
    /// of a column the flow reaches), 1..=201 water by speed (1 still, 201 free stream).
    pub fn encode(&self, out: &mut Vec<u8>) {
        let r = &self.r;
        let (nx, _) = r.size();
        let (lo, top) = self.window();
        let heights = r.volume().heights();
        let hmax = heights.iter().copied().max().unwrap_or(0) as usize;
        let flow = r.flow_at(r.time());
        let speeds = r.water().section(heights, nx, 1, 0, top, &flow);
        let t = r.water().slice_layers;
        let exposed: Vec<bool> = (0..nx)
            .map(|x| r.water().bed_speed(heights, nx, 1, x, 0, hmax, &flow) > 0.0)
            .collect();
        out.clear();
        out.push(FRAME_RIPPLE);
        out.push(0);
        out.extend_from_slice(&(nx as u32).to_le_bytes());
        out.extend_from_slice(&((top - lo) as u32).to_le_bytes());
        for z in lo..top {
            for x in 0..nx {
                let h = r.volume().height(x);
                let s = if z < h {
                    if z + 1 == h && exposed[x] { 250 } else { 255 }
                } else {
                    let v = speeds[(z / t).min(speeds.len() - 1)][x];
                    if v.is_finite() {
                        (1.0 + 200.0 * v).round() as u8
                    } else {
                        255
                    }
                };
                out.push(s);
            }
        }
    }

    /// The live measurements.
    pub fn stats(&self) -> RippleStats {
        let r = &self.r;
        let (nx, _) = r.size();
        let heights = r.volume().heights();
        let hmax = heights.iter().copied().max().unwrap_or(0) as usize;
        let hmin = heights.iter().copied().min().unwrap_or(0) as usize;
        let flow = r.flow_at(r.time());
        let exposed = (0..nx)
            .filter(|&x| r.water().bed_speed(heights, nx, 1, x, 0, hmax, &flow) > 0.0)
            .count();
        RippleStats {
            time: r.time(),
            current_speed: r.params().current_speed,
            current_angle: r.params().current_angle,
            exposed,
            relief: hmax - hmin,
            activations: r.stats().activations,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    fn settings(s: &[(&str, &str)]) -> GrowthSettings {
        let q: BTreeMap<String, String> = s
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
        GrowthSettings::from_query(&q).unwrap()
    }

    #[test]
    fn frames_do_not_change_the_run() {
        // 10 frames of 100 events and 1 frame of 1000: the same lattice.
        let a = settings(&[("preset", "fig5"), ("speed", "100")]);
        let mut s1 = GrowthSession::new(a.clone()).unwrap();
        for _ in 0..10 {
            assert_eq!(s1.frame(), 100);
        }
        let mut s2 = GrowthSession::new(GrowthSettings { speed: 1000, ..a }).unwrap();
        s2.frame();
        assert_eq!(s1.growth().field_states(), s2.growth().field_states());
        assert_eq!(s1.stats(), s2.stats());
        assert_eq!(s1.stats().accepted, 1000);
    }

    #[test]
    fn explained_picks_follow_the_rule() {
        let mut s =
            GrowthSession::new(settings(&[("preset", "fig5"), ("sampler", "rejection")])).unwrap();
        let mut accepted = 0;
        for k in 1..=200 {
            let e = s.explain().unwrap();
            let p = e.pick.unwrap();
            assert_eq!(p.z, 6);
            assert!((p.p - (p.b as f64 / 6.0).powi(2)).abs() < 1e-12);
            assert_eq!(p.accepted, p.r.unwrap() < p.p);
            accepted += p.accepted as u64;
            assert_eq!(e.time, k as f64);
        }
        assert_eq!(s.stats().accepted, accepted);
        // The exact sampler: the clock advances by the skipped picks plus one.
        let mut s = GrowthSession::new(settings(&[("preset", "fig5"), ("n", "6")])).unwrap();
        let mut t = 0.0;
        for _ in 0..50 {
            let e = s.explain().unwrap();
            let p = e.pick.unwrap();
            assert!(p.accepted && p.skipped >= 0.0);
            assert_eq!(e.time, t + p.skipped + 1.0);
            assert!(e.mean_p.unwrap() > 0.0 && e.mean_p.unwrap() <= 1.0);
            t = e.time;
        }
    }

    #[test]
    fn explained_and_plain_rejection_runs_agree() {
        // Explain mode consumes the random stream as the plain sampler does.
        let a = settings(&[
            ("preset", "fig5"),
            ("sampler", "rejection"),
            ("speed", "30"),
        ]);
        let mut s1 = GrowthSession::new(a.clone()).unwrap();
        s1.frame();
        let t = s1.growth().time();
        let mut s2 = GrowthSession::new(a).unwrap();
        while s2.growth().time() < t {
            s2.explain().unwrap();
        }
        assert_eq!(s1.growth().field_states(), s2.growth().field_states());
    }

    #[test]
    fn ripple_section_frames() {
        let q = BTreeMap::new();
        let mut r = RippleSession::new(RippleSettings::from_query(&q).unwrap()).unwrap();
        r.frame();
        let mut buf = Vec::new();
        r.encode(&mut buf);
        assert_eq!(buf[0], FRAME_RIPPLE);
        assert_eq!(buf.len(), 10 + 160 * 50);
        assert!(buf[10..].contains(&255) && buf[10..].iter().any(|&b| (1..=201).contains(&b)));
        r.set_current(0.8, 180.0).unwrap();
        assert_eq!(r.stats().current_speed, 0.8);
        assert!(r.set_current(-1.0, 0.0).is_err());
    }
}
