//! Insonification of the floor: which vertices a fan of rays reaches first, with grazing angle,
//! travel time and reflection coefficient; the others are in shadow.
//!
//! [`insonify`] traces a [`Fan`] (from a point S over a range of launch angles, or a parallel
//! beam) to each ray's first floor hit (after any number of sea-surface reflections; paths
//! after a floor reflection do not count). The hit position along the floor is a continuous
//! function of the launch parameter except at shadow edges, where a ray grazing a crest jumps
//! to beyond the trough. So for two neighbouring rays whose hits lie on the same or adjacent
//! segments, every vertex between the hits is insonified; otherwise the pair is bisected (new
//! rays between them) until it is, or until the two launch parameters differ by less than
//! `min_dt` (a shadow edge, counted in [`Insonification::edges`]). The direction and travel
//! time at a vertex are interpolated between the two bracketing hits; the grazing angle is taken
//! against the vertex normal (the mean of its two segments' normals). Where several paths reach
//! a vertex, the earliest arrival is kept.
//!
//! Insonification is also measured by length, whatever the vertex spacing (a floor given as a
//! coarse polyline, as BELLHOP bathymetry files usually are, has few vertices): every pair of
//! neighbouring rays marked above lights the stretch of floor between its two hits, so the lit
//! floor is the union of those stretches ([`Insonification::lit`], positions `s = i + u`,
//! fraction `u` of segment `i`), ending at the resolved shadow edges; [`Insonification::spans`]
//! splits the floor into lit and shadowed pieces at those edges and
//! [`Insonification::length_fraction`] is the lit share of the floor's length.
//!
//! [`visibility`] is the straight-line counterpart (line of sight from a point or a plane wave,
//! a sweep in O(n)): the rays of an isovelocity profile, used as a check and for
//! `cellsurf raytrace --straight`.
//!
//! The reflection coefficient at normal incidence is R0 = (Z2 - Z1) / (Z2 + Z1), Z2 the
//! sediment impedance of the vertex and Z1 = rho_w c(z) the water's at the vertex depth
//! (Jensen et al. 2011, ch. 1; rho_w = 1027 kg/m^3).

use super::ray::{Ray, Surface, TraceOptions, Tracer};
use super::seafloor::Seafloor;
use super::{RHO_WATER, RaytraceError, check_range, range_err};
use crate::engine::count::CountRange;

/// `rays`: the rays of a fan.
pub const RAYS: CountRange = CountRange::new(2, 10_000_000, "an integer in [2, 10000000]");

/// Normal-incidence reflection coefficient R0 = (Z2 - Z1) / (Z2 + Z1) of a sediment of
/// impedance `z2` under water of impedance `z1` (Jensen et al. 2011, Computational Ocean Acoustics, ch. 1).
pub fn reflection_coefficient(z2: f64, z1: f64) -> f64 {
    (z2 - z1) / (z2 + z1)
}

/// A fan of rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fan {
    /// From the transducer S at (x, z), launch angles from `min_deg` to `max_deg` below the
    /// horizontal (both in [-90, 90]), `rays` evenly spaced.
    Point {
        /// Range of S, m.
        x: f64,
        /// Depth of S, m.
        z: f64,
        /// Smallest launch angle, degrees below the horizontal.
        min_deg: f64,
        /// Largest launch angle, degrees.
        max_deg: f64,
        /// Rays of the initial fan (>= 2).
        rays: usize,
    },
    /// A parallel beam at `angle_deg` below the horizontal, starting on the segment from
    /// `from` to `to` (x, z), `rays` evenly spaced: a plane wave.
    Parallel {
        /// Angle, degrees below the horizontal.
        angle_deg: f64,
        /// First start point.
        from: (f64, f64),
        /// Last start point.
        to: (f64, f64),
        /// Rays of the initial beam (>= 2).
        rays: usize,
    },
}

impl Fan {
    /// The launch (x, z, angle in degrees) at parameter `t` in [0, 1].
    pub fn launch(&self, t: f64) -> (f64, f64, f64) {
        match *self {
            Fan::Point {
                x,
                z,
                min_deg,
                max_deg,
                ..
            } => (x, z, min_deg + t * (max_deg - min_deg)),
            Fan::Parallel {
                angle_deg,
                from,
                to,
                ..
            } => (
                from.0 + t * (to.0 - from.0),
                from.1 + t * (to.1 - from.1),
                angle_deg,
            ),
        }
    }

    /// Rays of the initial fan.
    pub fn rays(&self) -> usize {
        match *self {
            Fan::Point { rays, .. } | Fan::Parallel { rays, .. } => rays,
        }
    }

    /// Checks the fan against the floor.
    pub fn validate(&self, tracer: &Tracer<'_>) -> Result<(), RaytraceError> {
        if !RAYS.contains(self.rays() as u64) {
            return Err(range_err("rays", self.rays(), RAYS.expected));
        }
        match *self {
            Fan::Point {
                x,
                z,
                min_deg,
                max_deg,
                ..
            } => {
                check_range(
                    "min angle",
                    min_deg,
                    -90.0,
                    90.0,
                    "degrees below the horizontal",
                )?;
                check_range(
                    "max angle",
                    max_deg,
                    min_deg,
                    90.0,
                    "degrees (at least min angle)",
                )?;
                tracer.check_source(x, z)
            }
            Fan::Parallel {
                angle_deg,
                from,
                to,
                ..
            } => {
                check_range(
                    "beam angle",
                    angle_deg,
                    -90.0,
                    90.0,
                    "degrees below the horizontal",
                )?;
                tracer.check_source(from.0, from.1)?;
                tracer.check_source(to.0, to.1)
            }
        }
    }
}

/// Options of [`insonify`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InsonifyOptions {
    /// Step, longest path and most reflections of each ray (`stop_at_bottom` and `record` are
    /// set by [`insonify`]).
    pub trace: TraceOptions,
    /// Most rays in all (initial fan and bisection).
    pub max_rays: usize,
    /// Smallest launch-parameter interval that is bisected (of the whole fan's 1).
    pub min_dt: f64,
}

impl Default for InsonifyOptions {
    fn default() -> Self {
        InsonifyOptions {
            trace: TraceOptions {
                ds: 0.1,
                max_path: 1000.0,
                max_bounces: 10,
                stop_at_bottom: true,
                record: false,
            },
            max_rays: 2_000_000,
            min_dt: 1e-10,
        }
    }
}

/// The first arrival at a floor vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arrival {
    /// Grazing angle against the vertex normal, degrees.
    pub grazing_deg: f64,
    /// Travel time, s.
    pub tau: f64,
    /// Launch angle (interpolated between the bracketing rays), degrees.
    pub launch_deg: f64,
    /// Sea-surface reflections on the way.
    pub surface_bounces: usize,
}

/// Which floor vertices are reached, and how.
#[derive(Clone, Debug, PartialEq)]
pub struct Insonification {
    /// The first arrival at each vertex; `None` in shadow.
    pub arrivals: Vec<Option<Arrival>>,
    /// Rays traced.
    pub rays: usize,
    /// Shadow edges resolved to `min_dt`.
    pub edges: usize,
    /// The ray budget ran out before every interval was resolved.
    pub truncated: bool,
    /// Largest Snell-invariant drift over the rays.
    pub max_snell_drift: f64,
    /// The lit stretches of the floor, sorted and disjoint, as floor positions `(s0, s1)`
    /// (`s = i + u`: fraction `u` of segment `i`; [`Seafloor::length_between`]).
    pub lit: Vec<(f64, f64)>,
    /// Where the ray budget ran out ([`Insonification::truncated`]): the stretches of floor
    /// between the hits of two neighbouring rays that were left unbisected, less the lit
    /// stretches (sorted and disjoint, as [`Insonification::lit`]). Neither lit nor known to
    /// be in shadow; empty when the run was not truncated.
    pub unresolved: Vec<(f64, f64)>,
}

/// A piece of the floor between shadow edges ([`Insonification::spans`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    /// Start (range, depth), m.
    pub from: (f64, f64),
    /// End (range, depth), m.
    pub to: (f64, f64),
    /// Length along the floor, m.
    pub length: f64,
    /// Insonified (else in shadow).
    pub lit: bool,
}

/// Sorts stretches and merges those that overlap or touch.
fn merge(mut v: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    v.retain(|&(a, b)| b > a);
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(v.len());
    for (a, b) in v {
        match out.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => out.push((a, b)),
        }
    }
    out
}

/// The parts of the sorted, disjoint stretches `a` outside the sorted, disjoint stretches `b`,
/// in one forward pass over both.
fn subtract(a: &[(f64, f64)], b: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut j = 0;
    for &(mut s0, s1) in a {
        // (the stretches of b that end before this one of a starts end before every later one)
        while j < b.len() && b[j].1 <= s0 {
            j += 1;
        }
        for &(c0, c1) in b[j..].iter().take_while(|&&(c0, _)| c0 < s1) {
            if c0 > s0 {
                out.push((s0, c0));
            }
            s0 = s0.max(c1);
        }
        if s1 > s0 {
            out.push((s0, s1));
        }
    }
    out
}

/// Length along the floor of the disjoint `stretches`, m.
fn stretches_length(stretches: &[(f64, f64)], floor: &Seafloor) -> f64 {
    // from +0 (a float sum starts from -0: an unlit floor would print as -0 %)
    stretches
        .iter()
        .map(|&(a, b)| floor.length_between(a, b))
        .fold(0.0, |s, l| s + l)
}

/// `length` as a share of the floor's length (0 to 1; 0 for a floor of no length).
fn floor_share(length: f64, floor: &Seafloor) -> f64 {
    let l = floor.length();
    if l > 0.0 {
        (length / l).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

impl Insonification {
    /// Length of the unresolved floor, m (the union of [`Insonification::unresolved`]).
    pub fn unresolved_length(&self, floor: &Seafloor) -> f64 {
        stretches_length(&self.unresolved, floor)
    }

    /// Unresolved share of the floor's length (0 to 1; 0 unless the run was truncated).
    pub fn unresolved_fraction(&self, floor: &Seafloor) -> f64 {
        floor_share(self.unresolved_length(floor), floor)
    }

    /// Fraction of the vertices in `range` that are insonified (0 for an empty range).
    pub fn lit_fraction(&self, range: std::ops::Range<usize>) -> f64 {
        let n = range.len();
        if n == 0 {
            return 0.0;
        }
        self.arrivals[range].iter().filter(|a| a.is_some()).count() as f64 / n as f64
    }

    /// Fraction of all vertices insonified.
    pub fn insonified_fraction(&self) -> f64 {
        self.lit_fraction(0..self.arrivals.len())
    }

    /// Length of the lit floor, m (the union of [`Insonification::lit`]).
    pub fn lit_length(&self, floor: &Seafloor) -> f64 {
        stretches_length(&self.lit, floor)
    }

    /// Lit share of the floor's length (0 to 1): insonification by length, not by vertex.
    pub fn length_fraction(&self, floor: &Seafloor) -> f64 {
        floor_share(self.lit_length(floor), floor)
    }

    /// The floor from its first to its last vertex as alternating lit and shadowed pieces,
    /// split at the shadow edges (pieces of zero length left out).
    pub fn spans(&self, floor: &Seafloor) -> Vec<Span> {
        let end = (floor.len() - 1) as f64;
        let mut out = Vec::new();
        let mut push = |a: f64, b: f64, lit: bool| {
            let length = floor.length_between(a, b);
            if length > 0.0 {
                out.push(Span {
                    from: floor.point_at(a),
                    to: floor.point_at(b),
                    length,
                    lit,
                });
            }
        };
        let mut at = 0.0;
        for &(a, b) in &self.lit {
            push(at, a, false);
            push(a, b, true);
            at = b;
        }
        push(at, end, false);
        out
    }

    /// Normal-incidence reflection coefficient at vertex `v` (None without an impedance).
    pub fn r0(&self, floor: &Seafloor, tracer: &Tracer<'_>, v: usize) -> Option<f64> {
        let z2 = floor.impedances().get(v).copied().flatten()?;
        let z1 = RHO_WATER * tracer.profile().speed(floor.zs()[v]);
        Some(reflection_coefficient(z2, z1))
    }
}

#[derive(Clone, Copy, Debug)]
struct Hit {
    seg: usize,
    u: f64,
    dir: (f64, f64),
    tau: f64,
    launch: f64,
    bounces: usize,
}

/// Launch parameters and hits of two rays, and the bisection depth.
type Interval = (f64, Option<Hit>, f64, Option<Hit>, u32);

fn first_hit(r: &Ray) -> Option<Hit> {
    let h = r.first_floor_hit()?;
    let Surface::Floor { segment, u } = h.at else {
        return None;
    };
    Some(Hit {
        seg: segment,
        u,
        dir: h.dir,
        tau: h.tau,
        launch: r.launch_deg,
        bounces: r.surface_bounces_before_floor(),
    })
}

fn offer(arr: &mut [Option<Arrival>], v: usize, a: Arrival) {
    if arr[v].is_none_or(|old| a.tau < old.tau) {
        arr[v] = Some(a);
    }
}

fn grazing_at(floor: &Seafloor, v: usize, dir: (f64, f64)) -> f64 {
    let n = floor.vertex_normal(v);
    (-(dir.0 * n.0 + dir.1 * n.1))
        .clamp(0.0, 1.0)
        .asin()
        .to_degrees()
}

/// Marks the vertices between two hits on the same or adjacent segments, and the stretch of
/// floor between them as lit.
fn mark(
    floor: &Seafloor,
    arr: &mut [Option<Arrival>],
    lit: &mut Vec<(f64, f64)>,
    a: &Hit,
    b: &Hit,
) {
    let (pa, pb) = (a.seg as f64 + a.u, b.seg as f64 + b.u);
    let (lo, hi) = (pa.min(pb), pa.max(pb));
    lit.push((lo, hi));
    let first = lo.ceil() as usize;
    let last = (hi.floor() as usize).min(arr.len() - 1);
    for v in first..=last {
        let w = if pb != pa {
            (v as f64 - pa) / (pb - pa)
        } else {
            0.0
        };
        let l = |x: f64, y: f64| x + w * (y - x);
        let (dx, dz) = (l(a.dir.0, b.dir.0), l(a.dir.1, b.dir.1));
        let n = dx.hypot(dz);
        let dir = if n > 0.0 { (dx / n, dz / n) } else { a.dir };
        offer(
            arr,
            v,
            Arrival {
                grazing_deg: grazing_at(floor, v, dir),
                tau: l(a.tau, b.tau),
                launch_deg: l(a.launch, b.launch),
                surface_bounces: a.bounces.max(b.bounces),
            },
        );
    }
}

/// A hit within 1e-7 of a segment's end reaches that vertex (a ray grazing a crest).
fn mark_own(floor: &Seafloor, arr: &mut [Option<Arrival>], h: &Hit) {
    let v = if h.u <= 1e-7 {
        h.seg
    } else if h.u >= 1.0 - 1e-7 {
        h.seg + 1
    } else {
        return;
    };
    offer(
        arr,
        v,
        Arrival {
            grazing_deg: grazing_at(floor, v, h.dir),
            tau: h.tau,
            launch_deg: h.launch,
            surface_bounces: h.bounces,
        },
    );
}

/// At a resolved shadow edge the ray with the nearer hit grazes the occluding vertex just
/// beyond its hit (within 1 % of the segment): that vertex is lit.
fn mark_edge(floor: &Seafloor, arr: &mut [Option<Arrival>], a: &Hit, b: &Hit) {
    let (pa, pb) = (a.seg as f64 + a.u, b.seg as f64 + b.u);
    let near = if pa <= pb { a } else { b };
    let p = pa.min(pb);
    let v = p.ceil() as usize;
    if v < arr.len() && v as f64 - p < 0.01 {
        offer(
            arr,
            v,
            Arrival {
                grazing_deg: grazing_at(floor, v, near.dir),
                tau: near.tau,
                launch_deg: near.launch,
                surface_bounces: near.bounces,
            },
        );
    }
}

/// Traces `fan` to the floor and finds the insonified vertices (module docs).
pub fn insonify(
    tracer: &Tracer<'_>,
    fan: &Fan,
    opts: &InsonifyOptions,
) -> Result<Insonification, RaytraceError> {
    fan.validate(tracer)?;
    let o = TraceOptions {
        stop_at_bottom: true,
        record: false,
        ..opts.trace
    };
    o.validate()?;
    check_range("min dt", opts.min_dt, 1e-15, 0.5, "")?;
    if opts.max_rays < fan.rays() {
        return Err(range_err(
            "max rays",
            opts.max_rays,
            format!("at least the rays of the fan ({})", fan.rays()),
        ));
    }
    let floor = tracer.floor();
    let mut out = Insonification {
        arrivals: vec![None; floor.len()],
        rays: 0,
        edges: 0,
        truncated: false,
        max_snell_drift: 0.0,
        lit: Vec::new(),
        unresolved: Vec::new(),
    };
    let mut stretches = Vec::new();
    let mut unresolved = Vec::new();
    let trace = |t: f64, out: &mut Insonification| -> Option<Hit> {
        let (x, z, a) = fan.launch(t);
        let r = tracer.trace_unchecked(x, z, a, &o);
        out.rays += 1;
        out.max_snell_drift = out.max_snell_drift.max(r.max_snell_drift);
        let h = first_hit(&r);
        if let Some(h) = &h {
            mark_own(floor, &mut out.arrivals, h);
        }
        h
    };
    let n = fan.rays();
    let ts: Vec<f64> = (0..n).map(|i| i as f64 / (n - 1) as f64).collect();
    let hits: Vec<Option<Hit>> = ts.iter().map(|&t| trace(t, &mut out)).collect();
    let mut stack: Vec<Interval> = (0..n - 1)
        .rev()
        .map(|i| (ts[i], hits[i], ts[i + 1], hits[i + 1], 0))
        .collect();
    while let Some((ta, ha, tb, hb, depth)) = stack.pop() {
        match (&ha, &hb) {
            (Some(a), Some(b)) if a.seg.abs_diff(b.seg) <= 1 => {
                mark(floor, &mut out.arrivals, &mut stretches, a, b);
                continue;
            }
            (None, None) => continue,
            _ => {}
        }
        if tb - ta <= opts.min_dt || depth >= 64 {
            out.edges += 1;
            if let (Some(a), Some(b)) = (&ha, &hb) {
                mark_edge(floor, &mut out.arrivals, a, b);
            }
            continue;
        }
        if out.rays >= opts.max_rays {
            out.truncated = true;
            // (an interval with one ray off the floor bounds no stretch)
            if let (Some(a), Some(b)) = (&ha, &hb) {
                let (pa, pb) = (a.seg as f64 + a.u, b.seg as f64 + b.u);
                unresolved.push((pa.min(pb), pa.max(pb)));
            }
            continue;
        }
        let tm = 0.5 * (ta + tb);
        let hm = trace(tm, &mut out);
        stack.push((tm, hm, tb, hb, depth + 1));
        stack.push((ta, ha, tm, hm, depth + 1));
    }
    out.lit = merge(stretches);
    out.unresolved = subtract(&merge(unresolved), &out.lit);
    Ok(out)
}

/// A straight-line light: a point source, or a plane wave from -x.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// A point at (x, z).
    Point(f64, f64),
    /// A plane wave travelling towards +x at this many degrees below the horizontal.
    Plane(f64),
}

/// Straight-line visibility of each floor vertex (module docs): a vertex is lit when no part
/// of the floor is above the straight line from the light to it. A vertex exactly on a
/// grazing line is lit.
pub fn visibility(floor: &Seafloor, light: Light) -> Vec<bool> {
    let (xs, zs) = (floor.xs(), floor.zs());
    let n = xs.len();
    let mut lit = vec![false; n];
    let sweep =
        |idx: &mut dyn Iterator<Item = usize>, key: &dyn Fn(usize) -> f64, lit: &mut [bool]| {
            let mut best = f64::INFINITY;
            for i in idx {
                let k = key(i);
                if k <= best + 1e-12 * (1.0 + best.abs()) {
                    lit[i] = true;
                }
                best = best.min(k);
            }
        };
    match light {
        Light::Plane(angle) => {
            let t = angle.to_radians().tan();
            sweep(&mut (0..n), &|i| zs[i] - xs[i] * t, &mut lit);
        }
        Light::Point(x0, z0) => {
            sweep(
                &mut (0..n).filter(|&i| xs[i] > x0),
                &|i| (zs[i] - z0) / (xs[i] - x0),
                &mut lit,
            );
            sweep(
                &mut (0..n).rev().filter(|&i| xs[i] < x0),
                &|i| (zs[i] - z0) / (x0 - xs[i]),
                &mut lit,
            );
            let below = (0..n).filter(|&i| xs[i] == x0).map(|i| zs[i]);
            let top = below.fold(f64::INFINITY, f64::min);
            for i in 0..n {
                if xs[i] == x0 && zs[i] == top {
                    lit[i] = true;
                }
            }
        }
    }
    lit
}

/// The floor positions `[t0, t1]` of one segment piece whose key (the tangent of the
/// depression angle from a point source, or the depth along a plane wave) runs monotonically
/// from `k0` at `ts` to `k1` at 1 and lies in `[lo, hi]`, `solve(k)` giving the position of key
/// `k`; only a piece whose key falls (it faces the light) can be seen over its length.
fn seen(
    ts: f64,
    k0: f64,
    k1: f64,
    lo: f64,
    hi: f64,
    solve: impl Fn(f64) -> f64,
) -> Option<(f64, f64)> {
    let tol = 1e-12 * (1.0 + k0.abs());
    if k0.is_finite() && (k1 - k0).abs() <= tol {
        // along the line of sight (grazing): seen when nothing nearer is higher
        let hi = hi + 1e-12 * (1.0 + hi.abs());
        return (k0 >= lo && k0 <= hi).then_some((ts, 1.0));
    }
    if k1 > k0 {
        // rising: turned away from the light, seen only edge-on
        return None;
    }
    if hi < k1 || lo > k0 {
        return None;
    }
    let t0 = if hi >= k0 {
        ts
    } else {
        solve(hi).clamp(ts, 1.0)
    };
    let t1 = if lo <= k1 {
        1.0
    } else {
        solve(lo).clamp(ts, 1.0)
    };
    (t1 > t0).then_some((t0, t1))
}

/// The stretches of the floor in straight line of sight of `light` (floor positions, as
/// [`Insonification::lit`]); with `cone = (lo, hi)` only the points towards +x of a point light
/// whose depression angle has a tangent in `[lo, hi]` (a fan of launch angles). A point is in
/// sight when its key (the tangent of its depression angle seen from a point light, or its
/// depth along a plane wave) is at most the least key of the floor between it and the light;
/// along a segment the key is monotonic, so each segment's seen part is one piece.
pub fn visible_stretches(
    floor: &Seafloor,
    light: Light,
    cone: Option<(f64, f64)>,
) -> Vec<(f64, f64)> {
    let (xs, zs) = (floor.xs(), floor.zs());
    let nseg = xs.len() - 1;
    let (lo, hi) = cone.unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
    let mut out = Vec::new();
    match light {
        Light::Plane(angle) => {
            let t = angle.to_radians().tan();
            let mut best = f64::INFINITY;
            for i in 0..nseg {
                let a = zs[i] - xs[i] * t;
                let b = (zs[i + 1] - zs[i]) - (xs[i + 1] - xs[i]) * t;
                let (k0, k1) = (a, a + b);
                if let Some((u0, u1)) = seen(0.0, k0, k1, lo, hi.min(best), |k| (k - a) / b) {
                    out.push((i as f64 + u0, i as f64 + u1));
                }
                best = best.min(k0).min(k1);
            }
        }
        Light::Point(x0, z0) => {
            // towards +x, segment by segment from the source
            let mut best = f64::INFINITY;
            for i in 0..nseg {
                let (xa, xb, za) = (xs[i], xs[i + 1], zs[i]);
                if xb <= x0 {
                    continue;
                }
                let (dx, dz) = (xb - xa, zs[i + 1] - za);
                let ts = if xa >= x0 { 0.0 } else { (x0 - xa) / dx };
                let key = |u: f64| {
                    let d = xa + u * dx - x0;
                    if d > 0.0 {
                        (za + u * dz - z0) / d
                    } else {
                        f64::INFINITY
                    }
                };
                let (k0, k1) = (key(ts), key(1.0));
                let solve = |k: f64| (k * (xa - x0) - (za - z0)) / (dz - k * dx);
                if let Some((u0, u1)) = seen(ts, k0, k1, lo, hi.min(best), solve) {
                    out.push((i as f64 + u0, i as f64 + u1));
                }
                best = best.min(k0).min(k1);
            }
            if cone.is_none() {
                // towards -x, segment by segment from the source, v running from the segment's
                // end (v = 0) to its start
                let mut best = f64::INFINITY;
                for i in (0..nseg).rev() {
                    let (xa, xb, zb) = (xs[i], xs[i + 1], zs[i + 1]);
                    if xa >= x0 {
                        continue;
                    }
                    let (dx, dz) = (xb - xa, zs[i + 1] - zs[i]);
                    let vs = if xb <= x0 { 0.0 } else { (xb - x0) / dx };
                    let key = |v: f64| {
                        let d = x0 - (xb - v * dx);
                        if d > 0.0 {
                            (zb - v * dz - z0) / d
                        } else {
                            f64::INFINITY
                        }
                    };
                    let (k0, k1) = (key(vs), key(1.0));
                    let solve = |k: f64| (zb - z0 - k * (x0 - xb)) / (dz + k * dx);
                    if let Some((v0, v1)) = seen(vs, k0, k1, lo, hi.min(best), solve) {
                        out.push((i as f64 + 1.0 - v1, i as f64 + 1.0 - v0));
                    }
                    best = best.min(k0).min(k1);
                }
            }
        }
    }
    merge(out)
}

/// Straight-line insonification: [`visibility`] with arrivals (grazing angle against the
/// vertex normal, travel time at the constant speed `c`).
pub fn straight_insonify(floor: &Seafloor, light: Light, c: f64) -> Insonification {
    let lit = visibility(floor, light);
    let arrivals = lit
        .iter()
        .enumerate()
        .map(|(v, &l)| {
            if !l {
                return None;
            }
            let (x, z) = (floor.xs()[v], floor.zs()[v]);
            let (dir, dist, launch) = match light {
                Light::Point(x0, z0) => {
                    let d = (x - x0).hypot(z - z0);
                    let dir = if d > 0.0 {
                        ((x - x0) / d, (z - z0) / d)
                    } else {
                        (0.0, 1.0)
                    };
                    (dir, d, dir.1.atan2(dir.0).to_degrees())
                }
                Light::Plane(a) => {
                    let r = a.to_radians();
                    ((r.cos(), r.sin()), 0.0, a)
                }
            };
            Some(Arrival {
                grazing_deg: grazing_at(floor, v, dir),
                tau: dist / c,
                launch_deg: launch,
                surface_bounces: 0,
            })
        })
        .collect();
    Insonification {
        arrivals,
        rays: 0,
        edges: 0,
        truncated: false,
        max_snell_drift: 0.0,
        lit: visible_stretches(floor, light, None),
        unresolved: Vec::new(),
    }
}

/// [`straight_insonify`] from a point S at (`x`, `z`) limited to a fan of launch angles: only
/// the vertices whose direction from S (degrees below the horizontal, the launch angle of
/// [`Fan::Point`], so towards +x or straight down) lies in [`min_deg`, `max_deg`] can be
/// insonified; the others are in shadow as the fan's rays never point at them.
pub fn straight_insonify_fan(
    floor: &Seafloor,
    x: f64,
    z: f64,
    min_deg: f64,
    max_deg: f64,
    c: f64,
) -> Insonification {
    let mut ins = straight_insonify(floor, Light::Point(x, z), c);
    let tan = |d: f64| {
        if d >= 90.0 {
            f64::INFINITY
        } else if d <= -90.0 {
            f64::NEG_INFINITY
        } else {
            d.to_radians().tan()
        }
    };
    ins.lit = visible_stretches(
        floor,
        Light::Point(x, z),
        Some((tan(min_deg), tan(max_deg))),
    );
    const TOL_DEG: f64 = 1e-9;
    for a in &mut ins.arrivals {
        if a.is_some_and(|a| a.launch_deg < min_deg - TOL_DEG || a.launch_deg > max_deg + TOL_DEG) {
            *a = None;
        }
    }
    ins
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raytrace::SoundSpeed;

    #[test]
    fn subtract_keeps_what_lies_outside_the_other_stretches() {
        // Against the definition, point by point: on random sorted, disjoint stretches (some
        // touching, some empty of overlap), a point lies in the result exactly when it lies in
        // a and in no stretch of b; and the result is sorted and disjoint.
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move |k: u64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x % k
        };
        let mut stretches = |n: usize| {
            let mut at = 0.0;
            (0..n)
                .map(|_| {
                    at += next(3) as f64;
                    let s = (at, at + 1.0 + next(4) as f64);
                    at = s.1;
                    s
                })
                .collect::<Vec<_>>()
        };
        let inside = |v: &[(f64, f64)], p: f64| v.iter().any(|&(a, b)| a < p && p < b);
        for _ in 0..200 {
            let (a, b) = (stretches(12), stretches(12));
            let d = subtract(&a, &b);
            assert!(d.windows(2).all(|w| w[0].1 <= w[1].0) && d.iter().all(|s| s.0 < s.1));
            for k in 0..200 {
                let p = k as f64 * 0.5 + 0.25;
                assert_eq!(
                    inside(&d, p),
                    inside(&a, p) && !inside(&b, p),
                    "{p} {a:?} {b:?}"
                );
            }
        }
    }

    #[test]
    fn normal_incidence_reflection() {
        assert_eq!(reflection_coefficient(2.0, 2.0), 0.0);
        let r = reflection_coefficient(1962.0 * 1738.0, 1027.0 * 1500.0);
        assert!((r - 0.378).abs() < 1e-3, "{r}");
    }

    /// Isovelocity water, a fan of `rays` rays from S at (0, 5) between 4 and 60 deg, and
    /// steps of 1 m.
    fn point_fan_from_s(rays: usize) -> (SoundSpeed, Fan, InsonifyOptions) {
        let fan = Fan::Point {
            x: 0.0,
            z: 5.0,
            min_deg: 4.0,
            max_deg: 60.0,
            rays,
        };
        let mut o = InsonifyOptions::default();
        o.trace.ds = 1.0;
        (SoundSpeed::Isovelocity(1500.0), fan, o)
    }

    #[test]
    fn a_truncated_run_reports_the_unresolved_floor_apart_from_the_shadow() {
        // a flat floor at 10 m in 0.25 m segments, lit from S at (0, 5) between 4 and 60 deg:
        // every vertex in the fan is lit; 40 rays alone leave gaps of several segments
        let xs: Vec<f64> = (0..=320).map(|i| f64::from(i) * 0.25).collect();
        let floor = Seafloor::new(xs, vec![10.0; 321], vec![]).unwrap();
        let (p, fan, mut o) = point_fan_from_s(40);
        let t = Tracer::new(&p, &floor).unwrap();
        let full = insonify(&t, &fan, &o).unwrap();
        assert!(!full.truncated && full.unresolved.is_empty());
        let lit = full.length_fraction(&floor);
        assert!(lit > 0.85, "{lit}");
        for budget in [40, 100, 200] {
            o.max_rays = budget;
            let cut = insonify(&t, &fan, &o).unwrap();
            assert!(cut.truncated, "{budget}");
            let (l, u) = (cut.length_fraction(&floor), cut.unresolved_fraction(&floor));
            // what was not resolved is unresolved, not shadow: lit + unresolved is the lit floor
            assert!(u > 0.0, "{budget}: {u}");
            assert!(
                (l + u - lit).abs() < 1e-9,
                "{budget}: {l} + {u} against {lit}"
            );
            // and never overlaps the lit stretches
            for &(a, b) in &cut.unresolved {
                assert!(cut.lit.iter().all(|&(c, d)| d <= a || c >= b), "{a}..{b}");
            }
        }
    }

    #[test]
    fn an_unlit_floor_is_positive_zero() {
        // a horizontal fan from 5 m never reaches a flat floor at 10 m
        let xs: Vec<f64> = (0..=10).map(f64::from).collect();
        let floor = Seafloor::new(xs, vec![10.0; 11], vec![]).unwrap();
        let ins = straight_insonify_fan(&floor, 0.0, 5.0, 0.0, 0.0, 1500.0);
        let (l, f) = (ins.lit_length(&floor), ins.length_fraction(&floor));
        assert!(l == 0.0 && l.is_sign_positive(), "{l}");
        assert!(f == 0.0 && f.is_sign_positive(), "{f}");
    }

    #[test]
    fn a_step_casts_a_shadow() {
        // flat at 10 m, a 1 m high block from x = 20 to 21, light from S at (0, 5)
        let x = [0.0, 20.0, 20.0, 21.0, 21.0, 60.0];
        let z = [10.0, 10.0, 9.0, 9.0, 10.0, 10.0];
        let mut xs = Vec::new();
        let mut zs = Vec::new();
        for w in 0..x.len() - 1 {
            let n = if z[w] == z[w + 1] { 40 } else { 1 };
            for k in 0..n {
                xs.push(x[w] + (x[w + 1] - x[w]) * k as f64 / n as f64);
                zs.push(z[w] + (z[w + 1] - z[w]) * k as f64 / n as f64);
            }
        }
        xs.push(60.0);
        zs.push(10.0);
        let floor = Seafloor::new(xs, zs, vec![]).unwrap();
        let lit = visibility(&floor, Light::Point(0.0, 5.0));
        // the shadow behind the block's top corner (21, 9) reaches 10 m depth at x = 26.25
        for (i, (&x, &l)) in floor.xs().iter().zip(&lit).enumerate() {
            let z = floor.zs()[i];
            if z == 10.0 && x > 21.0 {
                assert_eq!(l, x >= 21.0 * 5.0 / 4.0, "x = {x}");
            }
        }
        // the ray tracer in isovelocity finds the same vertices
        let (p, fan, o) = point_fan_from_s(50);
        let t = Tracer::new(&p, &floor).unwrap();
        let ins = insonify(&t, &fan, &o).unwrap();
        let first = floor
            .xs()
            .iter()
            .position(|&x| x >= 5.0 / 60f64.to_radians().tan())
            .unwrap();
        let last = floor
            .xs()
            .iter()
            .rposition(|&x| x <= 5.0 / 4f64.to_radians().tan())
            .unwrap();
        for (v, &l) in lit.iter().enumerate().take(last).skip(first + 1) {
            assert_eq!(
                ins.arrivals[v].is_some(),
                l,
                "vertex {v} at x = {}",
                floor.xs()[v]
            );
        }
        assert!(ins.edges >= 1 && !ins.truncated);
        // by length: the flat up to the block, its front face and top, and the flat from the
        // shadow's end (x = 26.25) to the floor's end; the back face is turned away
        let want = (20.0 - 5.0 / 60f64.to_radians().tan()) + 1.0 + 1.0 + (60.0 - 26.25);
        let straight = straight_insonify_fan(&floor, 0.0, 5.0, 4.0, 60.0, 1500.0);
        for (how, got) in [
            ("rays", ins.lit_length(&floor)),
            ("straight", straight.lit_length(&floor)),
        ] {
            assert!(
                (got - want).abs() < 1e-6 * want,
                "{how}: {got} m, want {want} m"
            );
        }
        let spans = ins.spans(&floor);
        let lit: f64 = spans.iter().filter(|s| s.lit).map(|s| s.length).sum();
        let all: f64 = spans.iter().map(|s| s.length).sum();
        assert!((all - floor.length()).abs() < 1e-9 && (lit - want).abs() < 1e-6 * want);
        // the shadow behind the block starts at its top corner and ends at x = 26.25
        let shadow = spans
            .iter()
            .find(|s| !s.lit && s.from.0 >= 21.0 - 1e-6)
            .unwrap();

        assert!((shadow.from.0 - 21.0).abs() < 1e-6 && (shadow.to.0 - 26.25).abs() < 1e-6);
    }

    /// A flat floor's lit length between the footprints of the steepest and the shallowest ray
    /// of a fan from S, `h` above the floor: `h / tan(min) - h / tan(max)` (clipped to the
    /// floor), whatever the vertices.
    fn flat_floor_lit_fraction(vertices: usize, min_deg: f64, straight: bool) -> (f64, f64) {
        let xs: Vec<f64> = (0..vertices)
            .map(|i| 100.0 * i as f64 / (vertices - 1) as f64)
            .collect();
        let floor = Seafloor::new(xs, vec![12.0; vertices], vec![]).unwrap();
        let ins = if straight {
            straight_insonify_fan(&floor, 0.0, 10.0, min_deg, 20.0, 1500.0)
        } else {
            let p = SoundSpeed::Isovelocity(1500.0);
            let t = Tracer::new(&p, &floor).unwrap();
            let fan = Fan::Point {
                x: 0.0,
                z: 10.0,
                min_deg,
                max_deg: 20.0,
                rays: 200,
            };
            insonify(&t, &fan, &InsonifyOptions::default()).unwrap()
        };
        (ins.length_fraction(&floor), ins.insonified_fraction())
    }

    #[test]
    fn insonification_by_length_not_by_vertex() {
        let footprint = |a: f64| (2.0 / a.to_radians().tan()).min(100.0);
        for min_deg in [2.0, 1.0] {
            let want = (footprint(min_deg) - footprint(20.0)) / 100.0;
            for straight in [false, true] {
                let (two, by_vertex) = flat_floor_lit_fraction(2, min_deg, straight);
                let (fine, _) = flat_floor_lit_fraction(101, min_deg, straight);
                // at 2 deg the two end points are not lit, yet half the floor is
                if min_deg == 2.0 {
                    assert_eq!(by_vertex, 0.0);
                }
                assert!((two - want).abs() < 1e-9, "{min_deg} deg: {two} vs {want}");
                assert!(
                    (fine - want).abs() < 1e-9,
                    "{min_deg} deg: {fine} vs {want}"
                );
            }
        }
        // rays down to 1 deg reach the floor's end: 94.5 % of it is lit
        let (f, _) = flat_floor_lit_fraction(2, 1.0, false);
        assert!((f - 0.9451).abs() < 1e-4, "{f}");
    }

    #[test]
    fn a_plane_wave_and_the_far_side_of_a_point() {
        // a V-shaped trough: from a point above its middle both flanks are in sight; a plane
        // wave from -x at 10 deg sees the far flank only (the near one falls away from it)
        let floor = Seafloor::new(vec![0.0, 10.0, 20.0], vec![10.0, 11.0, 10.0], vec![]).unwrap();
        let all = visible_stretches(&floor, Light::Point(10.0, 5.0), None);
        assert_eq!(all, vec![(0.0, 2.0)]);
        let plane = visible_stretches(&floor, Light::Plane(10.0), None);
        assert_eq!(plane, vec![(0.0, 2.0)]);
        // at 3 deg the near flank falls away and the rim at x = 0 shades the far flank up to
        // u = (1 - 10 t) / (1 + 10 t), t = tan 3 deg
        let steep = visible_stretches(&floor, Light::Plane(3.0), None);
        let t = 3f64.to_radians().tan();
        assert_eq!(steep.len(), 1);
        assert!((steep[0].0 - (1.0 + (1.0 - 10.0 * t) / (1.0 + 10.0 * t))).abs() < 1e-12);
        assert_eq!(steep[0].1, 2.0);
        // a ridge seen from the left: its steep far flank is turned away, and it shades the
        // flat beyond up to x = 15 (the line of sight over the crest, slope 4/20)
        let ridge = Seafloor::new(
            vec![0.0, 10.0, 12.0, 40.0],
            vec![10.0, 9.0, 10.0, 10.0],
            vec![],
        )
        .unwrap();
        let seen = visible_stretches(&ridge, Light::Point(-10.0, 5.0), None);
        assert_eq!(seen.len(), 2, "{seen:?}");
        assert_eq!(seen[0], (0.0, 1.0));
        assert!((seen[1].0 - (2.0 + 3.0 / 28.0)).abs() < 1e-12 && seen[1].1 == 3.0);
    }
}
