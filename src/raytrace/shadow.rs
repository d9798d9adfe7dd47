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
        if !(2..=10_000_000).contains(&self.rays()) {
            return Err(range_err(
                "rays",
                self.rays(),
                "an integer in [2, 10000000]",
            ));
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
}

impl Insonification {
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

/// Marks the vertices between two hits on the same or adjacent segments.
fn mark(floor: &Seafloor, arr: &mut [Option<Arrival>], a: &Hit, b: &Hit) {
    let (pa, pb) = (a.seg as f64 + a.u, b.seg as f64 + b.u);
    let (lo, hi) = (pa.min(pb), pa.max(pb));
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
    };
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
                mark(floor, &mut out.arrivals, a, b);
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
            continue;
        }
        let tm = 0.5 * (ta + tb);
        let hm = trace(tm, &mut out);
        stack.push((tm, hm, tb, hb, depth + 1));
        stack.push((ta, ha, tm, hm, depth + 1));
    }
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
    fn normal_incidence_reflection() {
        assert_eq!(reflection_coefficient(2.0, 2.0), 0.0);
        let r = reflection_coefficient(1962.0 * 1738.0, 1027.0 * 1500.0);
        assert!((r - 0.378).abs() < 1e-3, "{r}");
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
        let p = SoundSpeed::Isovelocity(1500.0);
        let t = Tracer::new(&p, &floor).unwrap();
        let fan = Fan::Point {
            x: 0.0,
            z: 5.0,
            min_deg: 4.0,
            max_deg: 60.0,
            rays: 50,
        };
        let mut o = InsonifyOptions::default();
        o.trace.ds = 1.0;
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
    }
}
