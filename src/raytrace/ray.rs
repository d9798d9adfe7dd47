//! [`Tracer`]: 2-D rays through c(z), reflected at the sea surface and at a [`Seafloor`].
//!
//! The ray equations are BELLHOP's (Porter, "The BELLHOP Manual and User's Guide", 2011;
//! Porter's BELLHOP; Jensen et al. 2011, Computational Ocean Acoustics, ch. 3), in arc length s:
//! dx/ds = c t_x, dz/ds = c t_z, dt_x/ds = -c_x / c^2 = 0, dt_z/ds = -c_z / c^2,
//! d tau/ds = 1 / c, with t = (cos theta, sin theta) / c. They are integrated by the classical
//! fourth-order Runge-Kutta scheme with a fixed step `ds` (BELLHOP uses a second-order scheme;
//! RK4 makes the error of a step O(ds^5) in a smooth profile). Because c depends on z only,
//! t_x stays exactly constant: the error shows as |t| drifting off 1/c, which is what the Snell
//! invariant xi = cos(theta) / c measures ([`Ray::max_snell_drift`]). Where c changes fast, a
//! step is at most [`GRADIENT_STEP`] times the scale length c / |dc/dz| at its start, a lower
//! bound on the ray's radius of curvature (a fixed step longer than that leaps off the ray's
//! arc; in ocean profiles the limit is 75 m or more and leaves `ds` alone). A step that would
//! cross a profile table row is shortened to end on it, as BELLHOP does (a linear estimate of the
//! length, then Newton iterations on it until the end is within 1e-9 (1 + z) m of the row), and
//! a step starting on a row takes the gradient of the layer it enters, and every stage of a
//! step that ends on a row (or on the surface) the layer it comes through, extended past the
//! row ([`SoundSpeed::eval_piece`]; its last stage, at p + h k3, can overshoot by O(ds^3)), so
//! that RK4 never straddles a gradient jump.
//!
//! Boundaries: each step's chord is tested against the surface z = 0 and the floor's segments
//! ([`Seafloor::first_crossing`]). At a crossing at chord fraction f the step is redone from
//! length f ds, with Newton iterations on its length until the end lies on the boundary's line
//! (to 1e-12 relative), and the point is then put on the boundary (projected, a move of
//! rounding size). If the landing point lies beyond the segment's end, the curved path meets
//! the neighbouring segment instead (landed on in turn) or passes over the crest. The direction is reflected exactly: t' = t - 2 (t.n) n, n the
//! boundary's unit normal.
//!
//! Near grazing, a curved ray's arc can leave the chord's segment before the chord does; the
//! ray then approaches the floor by halving steps until the chord's sagitta h^2 / (8 R), over
//! the sine of the grazing angle, is below 1e-10 m.
//!
//! Termination: at most `2 max_path / ds + 64 (max_bounces + 1) + 16` steps (a step shortened
//! by the gradient limit counts as its fraction of `ds`), `max_bounces` reflections, the end of
//! the floor's range, or (if asked) the first floor hit.

use super::profile::row_tol;
use super::seafloor::Seafloor;
use super::{RaytraceError, SoundSpeed, check_range};
use crate::engine::count::CountRange;

/// `max_bounces`: the most reflections of a ray (surface and floor).
pub const MAX_BOUNCES: CountRange = CountRange::new(0, 100_000, "an integer in [0, 100000]");

/// Options of a trace.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceOptions {
    /// Arc-length step, m.
    pub ds: f64,
    /// Longest path, m.
    pub max_path: f64,
    /// Most reflections (surface and floor together).
    pub max_bounces: usize,
    /// End the ray at its first floor hit.
    pub stop_at_bottom: bool,
    /// Keep the path points.
    pub record: bool,
}

impl TraceOptions {
    /// Checks the options.
    pub fn validate(&self) -> Result<(), RaytraceError> {
        check_range("ds", self.ds, 1e-6, 1e5, "m")?;
        check_range("max path", self.max_path, self.ds, 1e8, "m (at least ds)")?;
        if !MAX_BOUNCES.contains(self.max_bounces as u64) {
            return Err(super::range_err(
                "max bounces",
                self.max_bounces,
                MAX_BOUNCES.expected,
            ));
        }
        let steps = self.max_path / self.ds;
        if steps > 1e9 {
            return Err(super::range_err(
                "max path / ds",
                steps,
                "at most 1e9 steps a ray",
            ));
        }
        Ok(())
    }

    /// The hard cap on the steps of one ray: twice the path in steps, and 64 a reflection
    /// (a curved ray approaches the floor by halving steps).
    pub fn max_steps(&self) -> usize {
        2 * (self.max_path / self.ds).ceil() as usize + 64 * (self.max_bounces + 1) + 16
    }
}

/// Which boundary reflected a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    /// The sea surface z = 0.
    Sea,
    /// Floor segment `segment` at fraction `u` of it.
    Floor {
        /// Segment index.
        segment: usize,
        /// Fraction along the segment.
        u: f64,
    },
}

/// A reflection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reflection {
    /// Where.
    pub at: Surface,
    /// Range, m.
    pub x: f64,
    /// Depth, m.
    pub z: f64,
    /// Travel time from the source, s.
    pub tau: f64,
    /// Path length from the source, m.
    pub s: f64,
    /// Grazing angle between the incoming ray and the boundary, radians, in [0, pi/2].
    pub grazing: f64,
    /// Unit direction of the incoming ray (dx, dz).
    pub dir: (f64, f64),
}

/// Why a ray ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayEnd {
    /// It reached the longest path.
    PathLength,
    /// It reached the most reflections.
    Bounces,
    /// It left the floor's range.
    LeftFloor,
    /// It hit the floor (with `stop_at_bottom`).
    Floor,
    /// It used the most steps (a safety cap, not reached in normal runs).
    Steps,
}

impl RayEnd {
    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            RayEnd::PathLength => "path_length",
            RayEnd::Bounces => "bounces",
            RayEnd::LeftFloor => "left_floor",
            RayEnd::Floor => "floor",
            RayEnd::Steps => "steps",
        }
    }
}

/// A traced ray.
#[derive(Clone, Debug, PartialEq)]
pub struct Ray {
    /// Launch angle, degrees below the horizontal.
    pub launch_deg: f64,
    /// Path points (x, z, tau) if recorded, the source first.
    pub path: Vec<[f64; 3]>,
    /// Reflections in order.
    pub reflections: Vec<Reflection>,
    /// Why it ended.
    pub end: RayEnd,
    /// Steps taken (including redone boundary steps).
    pub steps: usize,
    /// Path length, m.
    pub length: f64,
    /// Largest |xi / xi_leg - 1| over the path, xi = cos(theta) / c(z) measured from the
    /// ray's direction and xi_leg its value at the start of the leg (source or last reflection;
    /// a sloping floor changes xi). 0 for a vertical ray.
    pub max_snell_drift: f64,
}

impl Ray {
    /// The first floor reflection.
    pub fn first_floor_hit(&self) -> Option<&Reflection> {
        self.reflections
            .iter()
            .find(|r| matches!(r.at, Surface::Floor { .. }))
    }
    /// Sea-surface reflections before the first floor hit.
    pub fn surface_bounces_before_floor(&self) -> usize {
        self.reflections
            .iter()
            .take_while(|r| r.at == Surface::Sea)
            .count()
    }
}

/// How a step that cuts a boundary ends.
enum Landing {
    /// On the boundary: the end, the boundary (None: the surface), steps taken.
    Hit(State, Option<usize>, usize),
    /// Past a crest, in the water: the end and the steps taken.
    Pass(State, usize),
}

#[derive(Clone, Copy, Debug)]
struct State {
    x: f64,
    z: f64,
    tz: f64,
    tau: f64,
    s: f64,
}

/// A profile and a floor, checked against each other.
#[derive(Clone, Copy, Debug)]
pub struct Tracer<'a> {
    profile: &'a SoundSpeed,
    floor: &'a Seafloor,
}

impl<'a> Tracer<'a> {
    /// A tracer; the profile must cover the water column down to the deepest floor vertex.
    pub fn new(profile: &'a SoundSpeed, floor: &'a Seafloor) -> Result<Self, RaytraceError> {
        profile.check_depth(floor.max_depth())?;
        Ok(Tracer { profile, floor })
    }

    /// The profile.
    pub fn profile(&self) -> &SoundSpeed {
        self.profile
    }
    /// The floor.
    pub fn floor(&self) -> &Seafloor {
        self.floor
    }

    /// Checks that (x0, z0) is in the water above the floor.
    pub fn check_source(&self, x0: f64, z0: f64) -> Result<(), RaytraceError> {
        let (a, b) = self.floor.x_range();
        check_range("source range", x0, a, b, "m (within the seafloor section)")?;
        let zb = self.floor.depth_at(x0).unwrap_or(0.0);
        if !(z0 > 0.0 && z0 < zb) {
            return Err(super::range_err(
                "source depth",
                z0,
                format!("in (0, {zb}) m: below the surface and above the floor at its range"),
            ));
        }
        Ok(())
    }

    /// The right-hand side; on a table row the gradient of the layer below (`down`) or above;
    /// in a step that ends on `end` (a row or the surface), the layer it comes through,
    /// extended past `end` ([`SoundSpeed::eval_piece`]).
    fn deriv(&self, tx: f64, z: f64, tz: f64, down: bool, end: Option<f64>) -> [f64; 4] {
        let (c, g) = match end {
            Some(r) => self.profile.eval_piece(z, r, down),
            None => self.profile.eval_toward(z, down),
        };
        [c * tx, c * tz, -g / (c * c), 1.0 / c]
    }

    /// A classical RK4 step of length `h` from `p`; `end`: the depth of the table row or the
    /// surface the step is meant to end on, if any. Its last stage, at p + h k3, may lie past
    /// `end` by O(h^3), beyond [`row_tol`]: it must still see the layer the step comes
    /// through, or the step straddles the gradient jump and the Snell invariant drifts by
    /// O(h) (4e-5 at ds = 0.25 m in a Mackenzie profile).
    fn rk4(&self, tx: f64, p: &State, h: f64, end: Option<f64>) -> State {
        let down = p.tz > 0.0;
        let k1 = self.deriv(tx, p.z, p.tz, down, end);
        let k2 = self.deriv(tx, p.z + 0.5 * h * k1[1], p.tz + 0.5 * h * k1[2], down, end);
        let k3 = self.deriv(tx, p.z + 0.5 * h * k2[1], p.tz + 0.5 * h * k2[2], down, end);
        // the end of a step that lands on a row belongs to the layer it came through
        let k4 = match end {
            Some(_) => self.deriv(tx, p.z + h * k3[1], p.tz + h * k3[2], down, end),
            None => self.deriv(tx, p.z + h * k3[1], p.tz + h * k3[2], !down, None),
        };
        let w = |i: usize| h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        State {
            x: p.x + w(0),
            z: p.z + w(1),
            tz: p.tz + w(2),
            tau: p.tau + w(3),
            s: p.s + h,
        }
    }

    /// The step from `p`: `ds`, shortened to the longest path, to [`GRADIENT_STEP`] times the
    /// speed's scale length c / |dc/dz| at `p`, and, where the linear estimate says the step
    /// would cross a profile row, to end on it (with the row). The last value says whether
    /// the gradient limit shortened the step.
    fn step_length(&self, p: &State, o: &TraceOptions) -> (f64, Option<f64>, bool) {
        let h = o.ds.min(o.max_path - p.s);
        let (c, g) = self.profile.eval_toward(p.z, p.tz > 0.0);
        let hg = GRADIENT_STEP * c / g.abs();
        let limited = hg < h;
        let h = h.min(hg);
        let rows = self.profile.interfaces();
        if !rows.is_empty() && p.tz != 0.0 {
            // (c is continuous across rows: the speed of the layer entered is the speed here)
            let dzds = c * p.tz;
            let tol = row_tol(p.z);
            let next = if dzds > 0.0 {
                rows.iter().find(|&&r| r > p.z + tol)
            } else {
                rows.iter().rev().find(|&&r| r < p.z - tol)
            };
            if let Some(&r) = next {
                let hr = (r - p.z) / dzds;
                if hr > 0.0 && hr < h {
                    return (hr, Some(r), limited);
                }
            }
        }
        (h, None, limited)
    }

    /// An RK4 step of length about `h` from `p` that ends on the profile row `row` (if any):
    /// Newton iterations on the length (each a redone step) until the end depth is within
    /// [`row_tol`] of the row, where it is put exactly.
    fn step_to_row(&self, tx: f64, p: &State, h: f64, row: Option<f64>) -> (State, usize) {
        let mut q = self.rk4(tx, p, h, row);
        let Some(r) = row else {
            return (q, 1);
        };
        let mut hh = h;
        let mut steps = 1;
        for _ in 0..6 {
            let err = q.z - r;
            if err.abs() <= row_tol(r) {
                q.z = r;
                break;
            }
            let dzds = self.profile.eval(q.z).0 * q.tz;
            if dzds == 0.0 {
                break;
            }
            let next = hh - err / dzds;
            if !(next > 0.0 && next < 2.0 * h) {
                break;
            }
            hh = next;
            q = self.rk4(tx, p, hh, row);
            steps += 1;
        }
        (q, steps)
    }

    /// An RK4 step from `p` of length about `h` ending on the line through `anchor` with unit
    /// normal `n`: Newton iterations on the length (each a redone step) on the signed distance
    /// (q - anchor).n, whose derivative along the ray is c (t.n). Returns the end and the steps
    /// taken. `end`: the surface's depth 0 when the line is the surface (the stages must not
    /// overshoot it into the profile's held-constant extension above it), else None.
    fn land(
        &self,
        tx: f64,
        p: &State,
        h: f64,
        (anchor, n): ((f64, f64), (f64, f64)),
        end: Option<f64>,
    ) -> (State, usize) {
        let mut hh = h;
        let mut q = self.rk4(tx, p, hh, end);
        let mut steps = 1;
        for _ in 0..6 {
            let d = (q.x - anchor.0) * n.0 + (q.z - anchor.1) * n.1;
            if d.abs() <= 1e-12 * (1.0 + q.x.abs() + q.z.abs()) {
                break;
            }
            let dds = self.profile.eval(q.z).0 * (tx * n.0 + q.tz * n.1);
            if dds == 0.0 {
                break;
            }
            let next = hh - d / dds;
            if !(next >= 0.0 && next <= 2.0 * h + 1e-12) {
                break;
            }
            hh = next;
            q = self.rk4(tx, p, hh, end);
            steps += 1;
        }
        (q, steps)
    }

    /// The step from `p` that ends on the boundary first cut by the chord (`seg`: a floor
    /// segment, or the sea surface), starting from length `h`. The curved path may meet a
    /// neighbouring segment instead (the end on the segment's line lies beyond the segment):
    /// then that one, if the ray enters it; otherwise the ray passes over the crest, and the
    /// step ends on the segment's line beyond the crest, in the water ([`Landing::Pass`]).
    fn land_on(&self, tx: f64, p: &State, h: f64, mut seg: Option<usize>) -> Landing {
        let mut steps = 0;
        let nseg = self.floor.len() - 1;
        let mut last = None;
        for _ in 0..4 {
            let (anchor, nrm) = match seg {
                None => ((0.0, 0.0), (0.0, 1.0)),
                Some(i) => (
                    (self.floor.xs()[i], self.floor.zs()[i]),
                    self.floor.normal(i),
                ),
            };
            let (q, n) = self.land(tx, p, h, (anchor, nrm), seg.is_none().then_some(0.0));
            steps += n;
            let Some(i) = seg else {
                return Landing::Hit(q, seg, steps);
            };
            let u = self
                .floor
                .line_hit(i, (p.x, p.z), (q.x, q.z))
                .map_or(0.5, |v| v.1);
            let j = if u > 1.0 + 1e-9 && i + 1 < nseg {
                i + 1
            } else if u < -1e-9 && i > 0 {
                i - 1
            } else {
                return Landing::Hit(q, seg, steps);
            };
            if last.is_some_and(|(_, s)| s == Some(j)) {
                // back and forth between two segments: the ray meets their common vertex
                return Landing::Hit(q, seg, steps);
            }
            let nj = self.floor.normal(j);
            if tx * nj.0 + q.tz * nj.1 >= 0.0 {
                return Landing::Pass(q, steps);
            }
            last = Some((q, seg));
            seg = Some(j);
        }
        match last {
            Some((q, seg)) => Landing::Hit(q, seg, steps),
            None => Landing::Pass(self.rk4(tx, p, h, None), steps + 1),
        }
    }

    /// Traces one ray from (x0, z0) at `angle_deg` below the horizontal, in [-90, 90]
    /// (rays go towards +x; +-90 is straight down or up).
    pub fn trace(
        &self,
        x0: f64,
        z0: f64,
        angle_deg: f64,
        o: &TraceOptions,
    ) -> Result<Ray, RaytraceError> {
        o.validate()?;
        self.check_source(x0, z0)?;
        check_range(
            "launch angle",
            angle_deg,
            -90.0,
            90.0,
            "degrees below the horizontal",
        )?;
        Ok(self.trace_unchecked(x0, z0, angle_deg, o))
    }

    /// [`Tracer::trace`] without the checks (the caller has made them).
    pub(crate) fn trace_unchecked(
        &self,
        x0: f64,
        z0: f64,
        angle_deg: f64,
        o: &TraceOptions,
    ) -> Ray {
        let a = angle_deg.to_radians();
        let (c0, _) = self.profile.eval(z0);
        let (ca, sa) = if angle_deg.abs() == 90.0 {
            (0.0, angle_deg.signum())
        } else {
            (a.cos(), a.sin())
        };
        let mut tx = ca / c0;
        let mut p = State {
            x: x0,
            z: z0,
            tz: sa / c0,
            tau: 0.0,
            s: 0.0,
        };
        let mut ray = Ray {
            launch_deg: angle_deg,
            path: Vec::new(),
            reflections: Vec::new(),
            end: RayEnd::Steps,
            steps: 0,
            length: 0.0,
            max_snell_drift: 0.0,
        };
        if o.record {
            ray.path.push([p.x, p.z, p.tau]);
        }
        // |t| c at the start of the leg (1 at the source)
        let mut leg_norm = 1.0;
        let (xa, xb) = self.floor.x_range();
        let mut h_next: Option<f64> = None;
        // the step cap, in steps of ds: a step shortened by the gradient limit counts as its
        // fraction of ds (it is forced by the profile, and it advances the path)
        let mut budget = o.max_steps() as f64;
        while budget > 0.0 {
            if p.s >= o.max_path {
                ray.end = RayEnd::PathLength;
                break;
            }
            let (q, n) = match h_next.take() {
                Some(hh) => {
                    budget -= 1.0;
                    (self.rk4(tx, &p, hh, None), 1)
                }
                None => {
                    let (h0, row, limited) = self.step_length(&p, o);
                    budget -= if limited { h0 / o.ds } else { 1.0 };
                    self.step_to_row(tx, &p, h0, row)
                }
            };
            let h = q.s - p.s;
            ray.steps += n;
            // the earliest boundary crossed by the chord p -> q
            let sea = (q.z < 0.0).then(|| p.z / (p.z - q.z));
            let bot = self.floor.first_crossing((p.x, p.z), (q.x, q.z));
            let hit = match (sea, bot) {
                (Some(fs), Some(b)) if b.f < fs => Some((b.f, Some(b.segment))),
                (Some(fs), _) => Some((fs, None)),
                (None, Some(b)) => Some((b.f, Some(b.segment))),
                (None, None) => None,
            };
            // a curved ray near grazing: the arc may leave the chord's segment; approach the
            // floor by halves until the chord's sagitta moves the crossing by < 1e-10 m
            if let Some((f, Some(i))) = hit {
                let hf = f * h;
                let (c, g) = self.profile.eval(p.z);
                let n = self.floor.normal(i);
                let tn = (tx * tx + p.tz * p.tz).sqrt();
                let sin_graze = ((tx * n.0 + p.tz * n.1) / tn).abs().max(1e-12);
                if hf * hf * (g.abs() / c) / 8.0 / sin_graze > 1e-10 && hf > 1e-9 {
                    h_next = Some(0.5 * hf);
                    continue;
                }
            }
            // redo the step up to the boundary (Newton on its length); None: the curved path
            // passes a crest that the chord cut
            let landed = hit.map(|(f, seg)| self.land_on(tx, &p, (f * h).max(0.0), seg));
            let (q, seg, n) = match landed {
                Some(Landing::Hit(q, seg, n)) => (q, seg, n),
                other => {
                    let prev = p;
                    p = match other {
                        Some(Landing::Pass(q, n)) => {
                            ray.steps += n;
                            q
                        }
                        _ => q,
                    };
                    ray.max_snell_drift = ray.max_snell_drift.max(self.drift(tx, &p, leg_norm));
                    let left = p.x < xa || p.x > xb;
                    if left {
                        // the last step ends at the section's end (linear along the chord)
                        let edge = if p.x > xb { xb } else { xa };
                        let f = ((edge - prev.x) / (p.x - prev.x)).clamp(0.0, 1.0);
                        let l = |a: f64, b: f64| a + f * (b - a);
                        p = State {
                            x: edge,
                            z: l(prev.z, p.z),
                            tz: l(prev.tz, p.tz),
                            tau: l(prev.tau, p.tau),
                            s: l(prev.s, p.s),
                        };
                    }
                    if o.record {
                        ray.path.push([p.x, p.z, p.tau]);
                    }
                    if left {
                        ray.end = RayEnd::LeftFloor;
                        break;
                    }
                    continue;
                }
            };
            ray.steps += n;
            // put the point on the boundary (a move of rounding size)
            let (pos, normal, at) = match seg {
                None => ((q.x, 0.0), (0.0, 1.0), Surface::Sea),
                Some(i) => {
                    // the end projected onto the segment
                    let (ax, az) = (self.floor.xs()[i], self.floor.zs()[i]);
                    let e = (self.floor.xs()[i + 1] - ax, self.floor.zs()[i + 1] - az);
                    let u = (((q.x - ax) * e.0 + (q.z - az) * e.1) / (e.0 * e.0 + e.1 * e.1))
                        .clamp(0.0, 1.0);
                    (
                        self.floor.point(i, u),
                        self.floor.normal(i),
                        Surface::Floor { segment: i, u },
                    )
                }
            };
            let mut r = State {
                x: pos.0,
                z: pos.1,
                tz: q.tz,
                tau: q.tau,
                s: q.s,
            };
            ray.max_snell_drift = ray.max_snell_drift.max(self.drift(tx, &r, leg_norm));
            let tn = (tx * tx + r.tz * r.tz).sqrt();
            let dir = (tx / tn, r.tz / tn);
            let dn = dir.0 * normal.0 + dir.1 * normal.1;
            ray.reflections.push(Reflection {
                at,
                x: r.x,
                z: r.z,
                tau: r.tau,
                s: r.s,
                grazing: (-dn).clamp(0.0, 1.0).asin(),
                dir,
            });
            // t' = t - 2 (t.n) n
            let tdotn = tx * normal.0 + r.tz * normal.1;
            tx -= 2.0 * tdotn * normal.0;
            r.tz -= 2.0 * tdotn * normal.1;
            leg_norm = (tx * tx + r.tz * r.tz).sqrt() * self.profile.eval(r.z).0;
            p = r;
            if o.record {
                ray.path.push([p.x, p.z, p.tau]);
            }
            if seg.is_some() && o.stop_at_bottom {
                ray.end = RayEnd::Floor;
                break;
            }
            if ray.reflections.len() >= o.max_bounces {
                ray.end = RayEnd::Bounces;
                break;
            }
        }
        ray.length = p.s;
        ray
    }

    /// |xi / xi_leg - 1| at state `p`: xi = cos(theta) / c = t_x / (|t| c); t_x is constant in
    /// a leg, so the ratio is (|t| c)_leg / (|t| c)(s).
    fn drift(&self, tx: f64, p: &State, leg_norm: f64) -> f64 {
        if tx == 0.0 {
            return 0.0;
        }
        let norm = (tx * tx + p.tz * p.tz).sqrt() * self.profile.eval(p.z).0;
        (leg_norm / norm - 1.0).abs()
    }
}

/// The longest step, as a fraction of the speed's scale length c / |dc/dz| where the step
/// starts. That length bounds the ray's radius of curvature from below
/// (R = c / (|dc/dz| cos theta)), and over a step of this fraction of it c changes by at most
/// about that fraction of itself, so that the fourth-order expansion behind RK4 holds: in a
/// steep linear profile (c0 = 1500 m/s, g = -74.5 1/s, c = 10 m/s on a floor at 20 m, scale
/// length 0.13 m there) a fixed 0.25 m step would leap past the curvature of the ray, which is
/// a circle (Jensen, Kuperman, Porter & Schmidt 2011, Computational Ocean Acoustics, 2nd ed.,
/// Springer, ch. 3), and move it by metres off it. In the ocean's profiles (c about
/// 1500 m/s, |dc/dz| at most about 1 1/s) the limit is 75 m or more.
pub const GRADIENT_STEP: f64 = 0.05;

/// Radius of the circular ray of a linear profile c = c0 + g z launched at depth `z0` and
/// angle `theta0` (radians): R = c(z0) / (|g| cos theta0) (Snell's law in a linear profile).
pub fn linear_arc_radius(c0: f64, g: f64, z0: f64, theta0: f64) -> f64 {
    (c0 + g * z0) / (g.abs() * theta0.cos())
}

/// Centre (x, z) of that circle for a ray launched at (x0, z0) towards +x: the centre lies on
/// the depth where c would vanish, z0 - c(z0) / g.
pub fn linear_arc_centre(c0: f64, g: f64, x0: f64, z0: f64, theta0: f64) -> (f64, f64) {
    let r = linear_arc_radius(c0, g, z0, theta0);
    let sign = g.signum();
    (x0 + sign * r * theta0.sin(), z0 - (c0 + g * z0) / g)
}

/// One step size of [`error_study`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepError {
    /// Step, m.
    pub ds: f64,
    /// Linear profile: largest |distance to the predicted centre - R| / R over the path points.
    pub arc_radius_error: f64,
    /// Linear profile: largest Snell-invariant drift.
    pub snell_drift: f64,
    /// Munk profile: largest Snell-invariant drift.
    pub munk_snell_drift: f64,
    /// CPU seconds per ray (linear profile, path not recorded; mean of repeated traces).
    pub cpu_s_per_ray: f64,
    /// Steps per ray (linear profile).
    pub steps: usize,
}

/// The integrator's error against step size and run time: the linear profile
/// (c0 = 1500 m/s, g = 0.017 1/s, a ray launched at 10 degrees from 1 m depth, 30 km of path
/// down through its turning point at 1.36 km and back up, R = 89.6 km) and a Munk ray (10
/// degrees from 1000 m, 50 km, two turning points), over 5 km deep water.
pub fn error_study(steps: &[f64]) -> Result<Vec<StepError>, RaytraceError> {
    let (c0, g, th) = (1500.0, 0.017, 10f64.to_radians());
    let lin = SoundSpeed::Linear { c0, g };
    let munk = SoundSpeed::Munk(super::Munk::default());
    let floor = Seafloor::flat(-1.0, 200_000.0, 5000.0)?;
    let tl = Tracer::new(&lin, &floor)?;
    let tm = Tracer::new(&munk, &floor)?;
    let z0 = 1.0;
    let r = linear_arc_radius(c0, g, z0, th);
    let (xc, zc) = linear_arc_centre(c0, g, 0.0, z0, th);
    let mut out = Vec::new();
    for &ds in steps {
        let o = TraceOptions {
            ds,
            max_path: 30_000.0,
            max_bounces: 4,
            stop_at_bottom: false,
            record: true,
        };
        let ray = tl.trace(0.0, z0, 10.0, &o)?;
        let arc = ray
            .path
            .iter()
            .map(|q| ((q[0] - xc).hypot(q[1] - zc) - r).abs() / r)
            .fold(0.0, f64::max);
        let quiet = TraceOptions { record: false, ..o };
        let t0 = std::time::Instant::now();
        let mut n = 0u32;
        while n < 3 || (t0.elapsed().as_secs_f64() < 0.02 && n < 100_000) {
            std::hint::black_box(tl.trace_unchecked(0.0, z0, 10.0, &quiet));
            n += 1;
        }
        let cpu = t0.elapsed().as_secs_f64() / f64::from(n);
        let mo = TraceOptions {
            max_path: 50_000.0,
            record: false,
            ..o
        };
        let m = tm.trace(0.0, 1000.0, 10.0, &mo)?;
        out.push(StepError {
            ds,
            arc_radius_error: arc,
            snell_drift: ray.max_snell_drift,
            munk_snell_drift: m.max_snell_drift,
            cpu_s_per_ray: cpu,
            steps: ray.steps,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::profile::Table;
    use super::*;

    fn deep() -> Seafloor {
        Seafloor::flat(-1.0, 200_000.0, 5000.0).unwrap()
    }

    #[test]
    fn linear_profile_arc_radius() {
        // Circular arc of the linear profile: c0 = 1500, g = 0.017 1/s, theta0 = 10 deg -> R = 89.6 km
        let (c0, g) = (1500.0, 0.017);
        let th = 10f64.to_radians();
        let r = linear_arc_radius(c0, g, 0.0, th);
        assert!((r - 89_600.0).abs() < 50.0, "R = {r}");
        let p = SoundSpeed::Linear { c0, g };
        let floor = deep();
        let t = Tracer::new(&p, &floor).unwrap();
        let z0 = 1.0;
        let o = TraceOptions {
            ds: 200.0,
            max_path: 25_000.0,
            max_bounces: 4,
            stop_at_bottom: false,
            record: true,
        };
        let ray = t.trace(0.0, z0, 10.0, &o).unwrap();
        let r = linear_arc_radius(c0, g, z0, th);
        let (xc, zc) = linear_arc_centre(c0, g, 0.0, z0, th);
        let worst = ray
            .path
            .iter()
            .map(|q| ((q[0] - xc).hypot(q[1] - zc) - r).abs() / r)
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "relative radius error {worst}");
        assert!(ray.path.len() > 100);
        // the ray turns at c = c(z0) / cos(theta0)
        let zmax = ray.path.iter().map(|q| q[1]).fold(0.0, f64::max);
        let zturn = ((c0 + g * z0) / th.cos() - c0) / g;
        assert!((zmax - zturn).abs() < 1.0, "{zmax} vs {zturn}");
    }

    #[test]
    fn fourth_order_convergence() {
        // halving the step divides the arc-radius error by about 2^4 = 16 (RK4), until
        // rounding (1e-13) is reached
        let e = error_study(&[4000.0, 2000.0, 1000.0]).unwrap();
        for w in e.windows(2) {
            let ratio = w[0].arc_radius_error / w[1].arc_radius_error;
            assert!(ratio > 10.0 && ratio < 40.0, "{ratio}: {e:?}");
            assert!(w[0].snell_drift > w[1].snell_drift);
        }
    }

    #[test]
    fn snell_invariant_kept() {
        let p = SoundSpeed::Munk(super::super::Munk::default());
        let floor = deep();
        let t = Tracer::new(&p, &floor).unwrap();
        let o = TraceOptions {
            ds: 50.0,
            max_path: 60_000.0,
            max_bounces: 50,
            stop_at_bottom: false,
            record: false,
        };
        for a in [-12.0, -5.0, 0.0, 3.0, 11.0] {
            let ray = t.trace(0.0, 1000.0, a, &o).unwrap();
            assert!(
                ray.max_snell_drift < 1e-9,
                "{a}: drift {}",
                ray.max_snell_drift
            );
            assert!(ray.max_snell_drift > 0.0 || a == 0.0);
        }
        // a coarse step drifts more: the check can fail
        let coarse = TraceOptions { ds: 2000.0, ..o };
        let ray = t.trace(0.0, 1000.0, 11.0, &coarse).unwrap();
        assert!(ray.max_snell_drift > 1e-9, "{}", ray.max_snell_drift);
    }

    #[test]
    fn steep_linear_gradient_follows_the_circle() {
        // c = 1500 - 74.5 z: 10 m/s on a floor at 20 m, the scale length c / |g| 0.13 m there;
        // the rays are circles centred where c would vanish, 20.134 m deep. A fixed 0.25 m step
        // once threw a 10-degree ray from 19.75 m back up to 13.6 m.
        let (c0, g) = (1500.0, -74.5);
        let p = SoundSpeed::Linear { c0, g };
        let floor = Seafloor::flat(0.0, 100.0, 20.0).unwrap();
        let t = Tracer::new(&p, &floor).unwrap();
        let o = TraceOptions {
            ds: 0.25,
            max_path: 360.0,
            max_bounces: 10,
            stop_at_bottom: true,
            record: true,
        };
        let z0 = 10.0;
        for deg in [1.5, 10.0, 25.0] {
            let th = f64::to_radians(deg);
            let ray = t.trace(0.0, z0, deg, &o).unwrap();
            let r = linear_arc_radius(c0, g, z0, th);
            let (xc, zc) = linear_arc_centre(c0, g, 0.0, z0, th);
            assert!((zc - 1500.0 / 74.5).abs() < 1e-12);
            let worst = ray
                .path
                .iter()
                .map(|q| ((q[0] - xc).hypot(q[1] - zc) - r).abs() / r)
                .fold(0.0, f64::max);
            // steps of 0.05 c / |g| near the floor: 4e-8 R and a drift of 1.3e-6
            assert!(worst < 1e-7, "{deg} deg: relative radius error {worst}");
            assert!(ray.max_snell_drift < 1e-5, "{deg}: {}", ray.max_snell_drift);
            // the first floor hit is where the circle meets z = 20
            let h = ray.first_floor_hit().unwrap();
            let x_exact = xc + (r * r - (20.0 - zc).powi(2)).sqrt();
            assert!((h.x - x_exact).abs() < 1e-6, "{deg}: {} vs {x_exact}", h.x);
            // the grazing angle is the tangent's: cos = (20 - zc) / r against the vertical
            let graze = ((h.x - xc) / r).asin();
            assert!(
                (h.grazing - graze).abs() < 1e-5,
                "{deg}: {} vs {graze}",
                h.grazing
            );
        }
    }

    #[test]
    fn mackenzie_surface_reflection_keeps_snell() {
        // an upward ray reflects at the surface, where the depth term's gradient must not
        // vanish: after the reflection the ray keeps the Snell invariant as a downward one does
        let t = Table::new(
            "t",
            vec![0.0, 8.0, 12.0, 40.0],
            vec![18.0, 16.0, 12.0, 11.0],
            (-2.0, 30.0, ""),
        )
        .unwrap();
        let s = Table::new("s", vec![0.0, 40.0], vec![35.0, 35.0], (25.0, 40.0, "")).unwrap();
        let p = SoundSpeed::Mackenzie(super::super::Mackenzie::new(t, s));
        let floor = Seafloor::flat(0.0, 100.0, 20.0).unwrap();
        let tr = Tracer::new(&p, &floor).unwrap();
        let o = TraceOptions {
            ds: 0.25,
            max_path: 360.0,
            max_bounces: 10,
            stop_at_bottom: true,
            record: false,
        };
        let up = tr.trace(0.0, 10.0, -30.0, &o).unwrap();
        assert_eq!(up.reflections[0].at, Surface::Sea);
        assert!(up.first_floor_hit().is_some());
        let down = tr.trace(0.0, 10.0, 30.0, &o).unwrap();
        assert!(down.max_snell_drift < 1e-9, "{}", down.max_snell_drift);
        assert!(up.max_snell_drift < 1e-9, "{}", up.max_snell_drift);
        // the gradient at the surface is the one just below it
        let (_, g0) = p.eval_toward(0.0, true);
        let (_, g1) = p.eval(1e-6);
        assert!((g0 - g1).abs() < 1e-6, "{g0} vs {g1}");
    }

    #[test]
    fn reflection_law() {
        // isovelocity, a floor tilted by 10 degrees: the reflected ray leaves at the mirror angle
        let p = SoundSpeed::Isovelocity(1500.0);
        let tilt = 10f64.to_radians();
        let floor = Seafloor::new(
            vec![0.0, 100.0],
            vec![20.0, 20.0 + 100.0 * tilt.tan()],
            vec![],
        )
        .unwrap();
        let t = Tracer::new(&p, &floor).unwrap();
        let o = TraceOptions {
            ds: 0.7,
            max_path: 30.0,
            max_bounces: 1,
            stop_at_bottom: false,
            record: true,
        };
        let ray = t.trace(0.0, 5.0, 60.0, &o).unwrap();
        let h = ray.first_floor_hit().unwrap();
        // grazing angle = 60 - 10 degrees
        assert!(
            (h.grazing.to_degrees() - 50.0).abs() < 1e-9,
            "{}",
            h.grazing.to_degrees()
        );
        // the hit lies on the floor
        assert!((h.z - (20.0 + h.x * tilt.tan())).abs() < 1e-9);
        // outgoing direction: the mirror of 60 degrees about a 10-degree floor, 40 degrees up
        let two = t
            .trace(
                0.0,
                5.0,
                60.0,
                &TraceOptions {
                    max_bounces: 2,
                    ..o
                },
            )
            .unwrap();
        let k = two
            .path
            .iter()
            .position(|q| q[0] == h.x && q[1] == h.z)
            .unwrap();
        let (a, b) = (two.path[k], two.path[k + 1]);
        let dir = (b[1] - a[1]).atan2(b[0] - a[0]).to_degrees();
        assert!((dir + 40.0).abs() < 1e-9, "{dir}");
        assert_eq!(ray.end, RayEnd::Bounces);
        // the surface reflection flips t_z
        let o2 = TraceOptions {
            max_bounces: 3,
            max_path: 200.0,
            ..o
        };
        let up = t.trace(0.0, 5.0, -30.0, &o2).unwrap();
        let s = up.reflections[0];
        assert_eq!(s.at, Surface::Sea);
        assert!((s.grazing.to_degrees() - 30.0).abs() < 1e-9);
        assert!((s.x - 5.0 / 30f64.to_radians().tan()).abs() < 1e-9);
        let f = up.reflections[1];
        assert!(
            (f.grazing.to_degrees() - 20.0).abs() < 1e-9,
            "{}",
            f.grazing.to_degrees()
        );
    }
}
