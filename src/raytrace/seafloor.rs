//! [`Seafloor`]: the floor z_b(x) in the plane of the rays, a polyline of vertices with x
//! non-decreasing (two vertices at the same x make a vertical cliff; overhangs are rejected),
//! each with an optional acoustic impedance of the sediment there. [`SectionLine`] cuts a
//! section through a periodic elevation grid (the ripple model's torus, or any mosaic of its
//! tiles): a row, a column, or any straight line, with bilinear interpolation of the bin-centre
//! elevations and the impedance of the nearest column.
//!
//! The floor's depth is `water_depth - elevation` (the ripple elevation is the height above the
//! non-erodible substrate). Ray-segment intersection and the inward normals used for exact
//! reflection are here; blocks of 32 segments carry their shallowest depth so that a ray step
//! well above the floor tests no segment.

use super::{RaytraceError, check_range, range_err};

/// Segments per culling block.
const BLOCK: usize = 32;

/// Most samples of a [`SectionLine::Line`] section.
pub const MAX_SECTION_SAMPLES: usize = 20_000_000;

/// A seafloor polyline.
#[derive(Clone, Debug, PartialEq)]
pub struct Seafloor {
    x: Vec<f64>,
    z: Vec<f64>,
    impedance: Vec<Option<f64>>,
    /// Shallowest depth of the vertices of each block of segments.
    block_zmin: Vec<f64>,
}

/// A crossing of a ray chord with the floor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Fraction of the chord where it crosses.
    pub f: f64,
    /// The segment.
    pub segment: usize,
}

impl Seafloor {
    /// A floor from vertex ranges and depths (m) and optional impedances (kg m^-2 s^-1, one a
    /// vertex, or empty). Consecutive identical vertices are merged.
    pub fn new(
        x: Vec<f64>,
        z: Vec<f64>,
        impedance: Vec<Option<f64>>,
    ) -> Result<Self, RaytraceError> {
        if x.len() != z.len() {
            return Err(range_err(
                "seafloor vertices",
                format!("{} ranges and {} depths", x.len(), z.len()),
                "as many depths as ranges",
            ));
        }
        if !impedance.is_empty() && impedance.len() != x.len() {
            return Err(range_err(
                "seafloor impedance",
                format!("{} values for {} vertices", impedance.len(), x.len()),
                "one impedance a vertex, or none",
            ));
        }
        let imp = if impedance.is_empty() {
            vec![None; x.len()]
        } else {
            impedance
        };
        let (mut xs, mut zs, mut is) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..x.len() {
            check_range(
                &format!("seafloor range (vertex {i})"),
                x[i],
                -1e7,
                1e7,
                "m",
            )?;
            check_range(
                &format!("seafloor depth (vertex {i})"),
                z[i],
                1e-9,
                12_000.0,
                "m (below the sea surface)",
            )?;
            if let Some(v) = imp[i] {
                check_range(
                    &format!("seafloor impedance (vertex {i})"),
                    v,
                    1.0,
                    1e9,
                    "kg m^-2 s^-1",
                )?;
            }
            if let Some(&px) = xs.last() {
                if x[i] < px {
                    return Err(range_err(
                        format!("seafloor range (vertex {i})"),
                        x[i],
                        format!("at least the previous range {px} m (no overhangs)"),
                    ));
                }
                if x[i] == px && z[i] == zs[zs.len() - 1] {
                    continue;
                }
            }
            xs.push(x[i]);
            zs.push(z[i]);
            is.push(imp[i]);
        }
        if xs.len() < 2 || xs[xs.len() - 1] <= xs[0] {
            return Err(range_err(
                "seafloor vertices",
                xs.len(),
                "at least 2 distinct vertices spanning a positive range",
            ));
        }
        let nseg = xs.len() - 1;
        let block_zmin = (0..nseg.div_ceil(BLOCK))
            .map(|b| {
                let hi = ((b + 1) * BLOCK).min(nseg);
                zs[b * BLOCK..=hi]
                    .iter()
                    .copied()
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        Ok(Seafloor {
            x: xs,
            z: zs,
            impedance: is,
            block_zmin,
        })
    }

    /// A flat floor at `depth` from `x0` to `x1`.
    pub fn flat(x0: f64, x1: f64, depth: f64) -> Result<Self, RaytraceError> {
        Seafloor::new(vec![x0, x1], vec![depth, depth], Vec::new())
    }

    /// Reads `x, depth[, impedance]` rows (m, m, kg m^-2 s^-1; separators and comments as
    /// [`super::Table::parse`]; a non-numeric first line is a header). A third column that is
    /// not a number, or a fourth column, is an error naming the line and the value.
    pub fn parse_csv(text: &str) -> Result<Self, RaytraceError> {
        let (mut x, mut z, mut imp) = (Vec::new(), Vec::new(), Vec::new());
        let mut any_imp = false;
        let mut header = false;
        for (n, line, cols) in super::profile::table_rows(text) {
            let nums: Vec<Option<f64>> = cols.iter().map(|c| c.parse::<f64>().ok()).collect();
            match (nums.first(), nums.get(1)) {
                (Some(Some(a)), Some(Some(b))) => {
                    let bad = |reason: String| RaytraceError::Input {
                        what: "seafloor csv".into(),
                        reason: format!("line {}: '{line}': {reason}", n + 1),
                    };
                    if cols.len() > 3 {
                        return Err(bad(format!(
                            "{} columns, expected x, depth[, impedance]",
                            cols.len()
                        )));
                    }
                    let i = match cols.get(2) {
                        Some(c) => Some(nums[2].ok_or_else(|| {
                            bad(format!(
                                "impedance '{c}' is not a number (kg m^-2 s^-1; leave the \
                                 column out for no impedance)"
                            ))
                        })?),
                        None => None,
                    };
                    x.push(*a);
                    z.push(*b);
                    any_imp |= i.is_some();
                    imp.push(i);
                }
                _ if x.is_empty() && !header => {
                    header = true;
                    continue;
                }
                _ => {
                    return Err(RaytraceError::Input {
                        what: "seafloor csv".into(),
                        reason: format!("line {}: '{line}' is not x, depth[, impedance]", n + 1),
                    });
                }
            }
        }
        if !any_imp {
            imp.clear();
        }
        Seafloor::new(x, z, imp)
    }

    /// Vertex ranges, m.
    pub fn xs(&self) -> &[f64] {
        &self.x
    }
    /// Vertex depths, m.
    pub fn zs(&self) -> &[f64] {
        &self.z
    }
    /// Vertex impedances.
    pub fn impedances(&self) -> &[Option<f64>] {
        &self.impedance
    }
    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.x.len()
    }
    /// Never true (a floor has at least two vertices).
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }
    /// First and last range, m.
    pub fn x_range(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }
    /// Deepest vertex depth, m.
    pub fn max_depth(&self) -> f64 {
        self.z.iter().copied().fold(0.0, f64::max)
    }
    /// Shallowest vertex depth, m.
    pub fn min_depth(&self) -> f64 {
        self.z.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// The shallowest floor depth at range `x` (at a cliff, its top), or `None` outside.
    pub fn depth_at(&self, x: f64) -> Option<f64> {
        let (a, b) = self.x_range();
        if !(x >= a && x <= b) {
            return None;
        }
        let lo = self.x.partition_point(|&v| v < x).saturating_sub(1);
        let hi = self.x.partition_point(|&v| v <= x).min(self.x.len() - 1);
        let mut best = f64::INFINITY;
        for i in lo..hi.max(lo + 1) {
            let (x0, x1) = (self.x[i], self.x[i + 1]);
            let d = if x1 > x0 {
                self.z[i] + (self.z[i + 1] - self.z[i]) * ((x - x0) / (x1 - x0)).clamp(0.0, 1.0)
            } else {
                self.z[i].min(self.z[i + 1])
            };
            best = best.min(d);
        }
        Some(best)
    }

    /// Unit normal of segment `i`, pointing into the water.
    pub fn normal(&self, i: usize) -> (f64, f64) {
        let (dx, dz) = (self.x[i + 1] - self.x[i], self.z[i + 1] - self.z[i]);
        let l = dx.hypot(dz);
        (dz / l, -dx / l)
    }

    /// Unit normal at vertex `v` (the mean of its segments' normals), pointing into the water.
    pub fn vertex_normal(&self, v: usize) -> (f64, f64) {
        let n = self.x.len() - 1;
        let a = if v > 0 {
            self.normal(v - 1)
        } else {
            self.normal(0)
        };
        let b = if v < n {
            self.normal(v)
        } else {
            self.normal(n - 1)
        };
        let (nx, nz) = (a.0 + b.0, a.1 + b.1);
        let l = nx.hypot(nz);
        if l > 1e-12 { (nx / l, nz / l) } else { b }
    }

    /// Length of segment `i` (cliffs included), m.
    pub fn segment_length(&self, i: usize) -> f64 {
        (self.x[i + 1] - self.x[i]).hypot(self.z[i + 1] - self.z[i])
    }

    /// Length of the whole polyline along the floor (cliffs included), m.
    pub fn length(&self) -> f64 {
        (0..self.x.len() - 1).map(|i| self.segment_length(i)).sum()
    }

    /// Length along the floor between the floor positions `s0 <= s1`, a position `s = i + u`
    /// being fraction `u` of segment `i` (so vertex `v` is at `s = v`), m.
    pub fn length_between(&self, s0: f64, s1: f64) -> f64 {
        let nseg = self.x.len() - 1;
        let (s0, s1) = (s0.clamp(0.0, nseg as f64), s1.clamp(0.0, nseg as f64));
        if s1 <= s0 {
            return 0.0;
        }
        let (i0, i1) = (s0.floor() as usize, (s1.ceil() as usize).min(nseg));
        (i0..i1)
            .map(|i| {
                let (a, b) = (s0.max(i as f64), s1.min(i as f64 + 1.0));
                (b - a).max(0.0) * self.segment_length(i)
            })
            .sum()
    }

    /// The point at floor position `s = i + u` ([`Seafloor::length_between`]).
    pub fn point_at(&self, s: f64) -> (f64, f64) {
        let nseg = self.x.len() - 1;
        let s = s.clamp(0.0, nseg as f64);
        let i = (s.floor() as usize).min(nseg - 1);
        self.point(i, s - i as f64)
    }

    /// The point of segment `i` at fraction `u`.
    pub fn point(&self, i: usize, u: f64) -> (f64, f64) {
        (
            self.x[i] + u * (self.x[i + 1] - self.x[i]),
            self.z[i] + u * (self.z[i + 1] - self.z[i]),
        )
    }

    /// Where the chord from `p0` to `p1` first enters the sediment: the smallest chord
    /// fraction `f` in (0, 1] at which it crosses a segment moving against that segment's
    /// water-side normal. Crossings away from the sediment (a ray leaving the floor it has just
    /// been reflected at) are ignored.
    pub fn first_crossing(&self, p0: (f64, f64), p1: (f64, f64)) -> Option<Crossing> {
        let (xa, xb) = (p0.0.min(p1.0), p0.0.max(p1.0));
        let zdeep = p0.1.max(p1.1);
        let nseg = self.x.len() - 1;
        let first = self.x.partition_point(|&v| v < xa).saturating_sub(1);
        let end = self.x.partition_point(|&v| v <= xb).min(nseg);
        let d = (p1.0 - p0.0, p1.1 - p0.1);
        let mut best: Option<Crossing> = None;
        let mut i = first;
        while i < end.max(first + 1).min(nseg) {
            let b = i / BLOCK;
            if self.block_zmin[b] > zdeep {
                i = (b + 1) * BLOCK;
                continue;
            }
            let e = (self.x[i + 1] - self.x[i], self.z[i + 1] - self.z[i]);
            let n = self.normal(i);
            if d.0 * n.0 + d.1 * n.1 < 0.0 {
                let den = d.0 * e.1 - d.1 * e.0;
                if den != 0.0 {
                    let a = (self.x[i] - p0.0, self.z[i] - p0.1);
                    let f = (a.0 * e.1 - a.1 * e.0) / den;
                    let u = (a.0 * d.1 - a.1 * d.0) / den;
                    const TOL: f64 = 1e-12;
                    if f > 0.0
                        && f <= 1.0 + TOL
                        && (-TOL..=1.0 + TOL).contains(&u)
                        && best.is_none_or(|c| f < c.f)
                    {
                        best = Some(Crossing { f, segment: i });
                    }
                }
            }
            i += 1;
        }
        best
    }

    /// Where the line through `p0` and `p1` meets the line of segment `i`: (line parameter,
    /// segment fraction, outside [0, 1] beyond the segment); `None` when parallel.
    pub fn line_hit(&self, i: usize, p0: (f64, f64), p1: (f64, f64)) -> Option<(f64, f64)> {
        let d = (p1.0 - p0.0, p1.1 - p0.1);
        let e = (self.x[i + 1] - self.x[i], self.z[i + 1] - self.z[i]);
        let den = d.0 * e.1 - d.1 * e.0;
        if den == 0.0 {
            return None;
        }
        let a = (self.x[i] - p0.0, self.z[i] - p0.1);
        let f = (a.0 * e.1 - a.1 * e.0) / den;
        let u = (a.0 * d.1 - a.1 * d.0) / den;
        (f.is_finite() && u.is_finite()).then_some((f, u))
    }
}

/// A straight line through a periodic elevation grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SectionLine {
    /// Row `j` (constant y), along +x, `tiles` periods long (a mosaic of the same tile).
    Row {
        /// Row index.
        j: usize,
        /// Periods.
        tiles: usize,
    },
    /// Column `i` (constant x), along +y, `tiles` periods long.
    Column {
        /// Column index.
        i: usize,
        /// Periods.
        tiles: usize,
    },
    /// Any straight line: start (m, in grid coordinates, bin centre of column 0 at
    /// `bin / 2`), azimuth (degrees counter-clockwise from +x), length (m) and sample spacing
    /// (m).
    Line {
        /// Start x, m.
        x0: f64,
        /// Start y, m.
        y0: f64,
        /// Direction, degrees from +x.
        azimuth_deg: f64,
        /// Length, m.
        length: f64,
        /// Spacing of the samples, m.
        spacing: f64,
    },
}

impl SectionLine {
    /// The section `cellsurf raytrace` cuts through a surface of `ny` rows of `bin`-metre bins:
    /// from the centre of column 0 in the middle row (`ny / 2`), along `azimuth_deg`, `length`
    /// metres, one sample a bin.
    pub fn through_middle(ny: usize, bin: f64, azimuth_deg: f64, length: f64) -> SectionLine {
        SectionLine::Line {
            x0: bin / 2.0,
            y0: (ny / 2) as f64 * bin + bin / 2.0,
            azimuth_deg,
            length,
            spacing: bin,
        }
    }
}

/// A periodic elevation grid (`nx x ny`, y-major rows of x, bin-centre values, m) with an
/// optional per-column impedance.
#[derive(Clone, Copy, Debug)]
pub struct Grid<'a> {
    /// Columns along x.
    pub nx: usize,
    /// Rows along y.
    pub ny: usize,
    /// Bin size, m.
    pub bin: f64,
    /// Elevation above the substrate, m.
    pub elevation: &'a [f64],
    /// Impedance of each column's top automaton (None: bare substrate), or empty.
    pub impedance: &'a [Option<f64>],
}

impl Grid<'_> {
    fn check(&self) -> Result<(), RaytraceError> {
        if self.nx == 0 || self.ny == 0 || self.elevation.len() != self.nx * self.ny {
            return Err(range_err(
                "elevation grid",
                format!(
                    "{} values for {} x {}",
                    self.elevation.len(),
                    self.nx,
                    self.ny
                ),
                "nx x ny values, nx, ny >= 1",
            ));
        }
        if !self.impedance.is_empty() && self.impedance.len() != self.elevation.len() {
            return Err(range_err(
                "impedance grid",
                self.impedance.len(),
                "one value a column, or none",
            ));
        }
        check_range("bin size", self.bin, 1e-9, 1e4, "m")
    }

    /// Bilinear periodic elevation at (x, y) m.
    pub fn elevation_at(&self, x: f64, y: f64) -> f64 {
        let c = BilinearCell::at(x, y, self.bin, self.nx, self.ny);
        let e = |i: usize, j: usize| self.elevation[j * self.nx + i];
        c.blend(e(c.i0, c.j0), e(c.i1, c.j0), e(c.i0, c.j1), e(c.i1, c.j1))
    }

    /// Impedance of the column nearest to (x, y).
    pub fn impedance_at(&self, x: f64, y: f64) -> Option<f64> {
        if self.impedance.is_empty() {
            return None;
        }
        let w = |v: f64, n: usize| ((v / self.bin).floor() as i64).rem_euclid(n as i64) as usize;
        self.impedance[w(y, self.ny) * self.nx + w(x, self.nx)]
    }

    /// The floor along `line`: depth `water_depth - elevation`, ranges from `x_start` (m).
    pub fn section(
        &self,
        line: SectionLine,
        water_depth: f64,
        x_start: f64,
    ) -> Result<Seafloor, RaytraceError> {
        self.check()?;
        let mut g = *self;
        cut_section(&mut g, line, water_depth, x_start)
    }
}

impl SurfaceSampler for Grid<'_> {
    fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }
    fn bin(&self) -> f64 {
        self.bin
    }
    fn elevation(&mut self, x: f64, y: f64) -> Result<f64, RaytraceError> {
        Ok(self.elevation_at(x, y))
    }
    fn impedance(&mut self, x: f64, y: f64) -> Result<Option<f64>, RaytraceError> {
        Ok(self.impedance_at(x, y))
    }
    fn has_impedance(&self) -> bool {
        !self.impedance.is_empty()
    }
}

/// A periodic surface sampled point by point: a [`Grid`] in memory, or a store read chunk by
/// chunk as the section goes ([`super::input`]).
pub trait SurfaceSampler {
    /// Bins along x and y.
    fn size(&self) -> (usize, usize);
    /// Bin size, m.
    fn bin(&self) -> f64;
    /// Bilinear periodic elevation at (x, y) m, bin `i` centred at `(i + 0.5) bin`.
    fn elevation(&mut self, x: f64, y: f64) -> Result<f64, RaytraceError>;
    /// Impedance of the column nearest to (x, y) (None: bare substrate or no impedance).
    fn impedance(&mut self, x: f64, y: f64) -> Result<Option<f64>, RaytraceError>;
    /// Whether the surface carries an impedance.
    fn has_impedance(&self) -> bool;
}

/// The floor along `line` through `surf`: depth `water_depth - elevation`, ranges from
/// `x_start` (m) ([`Grid::section`] for a grid in memory).
pub fn cut_section(
    surf: &mut dyn SurfaceSampler,
    line: SectionLine,
    water_depth: f64,
    x_start: f64,
) -> Result<Seafloor, RaytraceError> {
    check_range("water depth", water_depth, 1e-6, 12_000.0, "m")?;
    let (nx, ny) = surf.size();
    let b = surf.bin();
    let (x0, y0, az, n, step) = match line {
        SectionLine::Row { j, tiles } => {
            if j >= ny || tiles == 0 || tiles > 100_000 {
                return Err(range_err(
                    "section row",
                    format!("{j} x {tiles} tiles"),
                    format!("a row in [0, {}) and 1..=100000 tiles", ny),
                ));
            }
            (b / 2.0, (j as f64 + 0.5) * b, 0.0f64, nx * tiles, b)
        }
        SectionLine::Column { i, tiles } => {
            if i >= nx || tiles == 0 || tiles > 100_000 {
                return Err(range_err(
                    "section column",
                    format!("{i} x {tiles} tiles"),
                    format!("a column in [0, {}) and 1..=100000 tiles", nx),
                ));
            }
            ((i as f64 + 0.5) * b, b / 2.0, 90.0, ny * tiles, b)
        }
        SectionLine::Line {
            x0,
            y0,
            azimuth_deg,
            length,
            spacing,
        } => {
            check_range("section x0", x0, -1e7, 1e7, "m")?;
            check_range("section y0", y0, -1e7, 1e7, "m")?;
            check_range("section azimuth", azimuth_deg, -360.0, 360.0, "degrees")?;
            check_range("section spacing", spacing, 1e-6, 1e4, "m")?;
            // at most 1e6 m and 2e7 samples: the stated range is the one enforced
            let max_length = (MAX_SECTION_SAMPLES as f64 * spacing).min(1e6);
            check_range(
                "section length",
                length,
                spacing,
                max_length,
                &format!("m (at most 1e6 m and 2e7 samples of {spacing} m)"),
            )?;
            let n = (length / spacing).floor() as usize;
            if n > MAX_SECTION_SAMPLES {
                return Err(range_err(
                    "section length / spacing",
                    n,
                    "at most 2e7 samples",
                ));
            }
            (x0, y0, azimuth_deg, n, spacing)
        }
    };
    let (ca, sa) = (az.to_radians().cos(), az.to_radians().sin());
    let (mut xs, mut zs, mut imp) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..=n {
        let s = k as f64 * step;
        let (px, py) = (x0 + s * ca, y0 + s * sa);
        let e = surf.elevation(px, py)?;
        if e.is_nan() || e >= water_depth {
            return Err(range_err(
                "water depth",
                water_depth,
                format!("more than the bed elevation {e} m at section sample {k}"),
            ));
        }
        xs.push(x_start + s);
        zs.push(water_depth - e);
        imp.push(surf.impedance(px, py)?);
    }
    if !surf.has_impedance() {
        imp.clear();
    }
    Seafloor::new(xs, zs, imp)
}

/// The bed elevation and the impedance of each column's top automaton of a ripple run: the
/// grid that [`Grid::section`] cuts.
#[derive(Clone, Debug, PartialEq)]
pub struct RippleSurface {
    /// Columns along x.
    pub nx: usize,
    /// Rows along y.
    pub ny: usize,
    /// Bin size, m.
    pub bin: f64,
    /// Elevation above the substrate, m, y-major rows of x.
    pub elevation: Vec<f64>,
    /// Impedance of the top automaton (None: bare substrate), kg m^-2 s^-1.
    pub impedance: Vec<Option<f64>>,
}

impl RippleSurface {
    /// The surface of a run in memory.
    pub fn of(r: &crate::ripple::Ripple) -> Self {
        let (nx, ny) = r.size();
        RippleSurface {
            nx,
            ny,
            bin: r.params().bin_size,
            elevation: r.elevation(),
            impedance: crate::ripple::output::surface_field(r, crate::ripple::Field::Impedance),
        }
    }

    /// The surface of a ripple NetCDF file ([`crate::ripple::input::read`]): its last
    /// elevation snapshot and, if the file has the `impedance` field, the impedance of each
    /// column's top automaton.
    pub fn from_file(f: &crate::ripple::input::RippleFile) -> Result<Self, RaytraceError> {
        let elev = f.final_elevation().ok_or_else(|| RaytraceError::Input {
            what: "ripple file".into(),
            reason: "no elevation snapshot (write it with --fields elevation,...)".into(),
        })?;
        let (nx, ny, nz) = (f.nx, f.ny, f.nz);
        let impedance = match f.field(crate::ripple::Field::Impedance) {
            Some(v) if v.len() == nx * ny * nz => (0..nx * ny)
                .map(|c| {
                    (0..nz)
                        .rev()
                        .map(|z| v[z * nx * ny + c])
                        .find(|x| x.is_finite())
                        .map(f64::from)
                })
                .collect(),
            _ => Vec::new(),
        };
        Ok(RippleSurface {
            nx,
            ny,
            bin: f.bin_size,
            elevation: elev.iter().map(|&v| f64::from(v)).collect(),
            impedance,
        })
    }

    /// The built-in generated seafloor: a 3-D ripple run with the paper's Fig. 3 settings
    /// (scenario `ripple_fig3_evolution`: d50 0.2 mm, sorting 1 phi, current 0.5 m/s along +x) on
    /// 128 x 16 columns of 5 mm (a 0.64 m x 0.08 m tile), the defaults' 10,000 steps, seed
    /// `seed`.
    pub fn generated(seed: u64) -> Result<Self, RaytraceError> {
        let p = crate::ripple::RippleParams {
            nx: 128,
            ny: 16,
            layers: 30,
            steps: 10000,
            sorting: 1.0,
            seed,
            ..crate::ripple::RippleParams::default()
        };
        let mut r = crate::ripple::Ripple::new(&p).map_err(|e| RaytraceError::Input {
            what: "generated ripple".into(),
            reason: e.to_string(),
        })?;
        r.run(p.steps, |_| {});
        Ok(RippleSurface::of(&r))
    }

    /// The grid view.
    pub fn grid(&self) -> Grid<'_> {
        Grid {
            nx: self.nx,
            ny: self.ny,
            bin: self.bin,
            elevation: &self.elevation,
            impedance: &self.impedance,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cliffs_and_normals() {
        // a step down at x = 1: vertical cliff from 10 m to 11 m
        let f = Seafloor::new(
            vec![0.0, 1.0, 1.0, 2.0],
            vec![10.0, 10.0, 11.0, 11.0],
            vec![],
        )
        .unwrap();
        assert_eq!(f.normal(0), (0.0, -1.0));
        assert_eq!(f.normal(1), (1.0, 0.0));
        assert_eq!(f.depth_at(1.0), Some(10.0));
        assert_eq!(f.depth_at(1.5), Some(11.0));
        // a horizontal chord at 10.5 m going -x hits the cliff face
        let c = f.first_crossing((1.5, 10.5), (0.5, 10.5)).unwrap();
        assert_eq!(c.segment, 1);
        assert!((c.f - 0.5).abs() < 1e-12);
        // going +x it starts inside the sediment and leaves through the face: no crossing
        assert!(f.first_crossing((0.5, 10.5), (1.5, 10.5)).is_none());
        assert!(Seafloor::new(vec![0.0, 2.0, 1.0], vec![1.0; 3], vec![]).is_err());
        assert!(Seafloor::new(vec![0.0, 1.0], vec![1.0, -1.0], vec![]).is_err());
    }

    #[test]
    fn section_of_a_periodic_grid() {
        let (nx, ny) = (4, 2);
        let elev: Vec<f64> = (0..nx * ny).map(|c| (c % nx) as f64 * 0.01).collect();
        let g = Grid {
            nx,
            ny,
            bin: 0.1,
            elevation: &elev,
            impedance: &[],
        };
        let f = g
            .section(SectionLine::Row { j: 1, tiles: 2 }, 5.0, 0.0)
            .unwrap();
        assert_eq!(f.len(), 9);
        assert!((f.zs()[3] - 4.97).abs() < 1e-12);
        // periodic: sample 4 is column 0 again
        assert!((f.zs()[4] - 5.0).abs() < 1e-12);
        // halfway between columns 0 and 1 by bilinear interpolation
        assert!((g.elevation_at(0.1, 0.05) - 0.005).abs() < 1e-12);
        assert!(
            g.section(SectionLine::Row { j: 0, tiles: 1 }, 0.02, 0.0)
                .is_err()
        );
    }
}

/// The four cells round a point of a periodic grid of bin-centred values, and its weights: the
/// bilinear interpolation shared by every elevation grid (in memory or in a store).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BilinearCell {
    /// Column and row of the lower-left cell.
    pub i0: usize,
    pub j0: usize,
    /// Column and row of the upper-right cell (wrapped).
    pub i1: usize,
    pub j1: usize,
    /// Fractions along x and y from the lower-left cell's centre.
    pub tx: f64,
    pub ty: f64,
}

impl BilinearCell {
    /// The cell round (x, y) m on an `nx x ny` torus of bins `bin` m wide.
    pub fn at(x: f64, y: f64, bin: f64, nx: usize, ny: usize) -> BilinearCell {
        let gx = x / bin - 0.5;
        let gy = y / bin - 0.5;
        let (fx, fy) = (gx.floor(), gy.floor());
        let w = |i: f64, n: usize| (i as i64).rem_euclid(n as i64) as usize;
        let (i0, j0) = (w(fx, nx), w(fy, ny));
        BilinearCell {
            i0,
            j0,
            i1: (i0 + 1) % nx,
            j1: (j0 + 1) % ny,
            tx: gx - fx,
            ty: gy - fy,
        }
    }

    /// The interpolated value from the corners (i0, j0), (i1, j0), (i0, j1), (i1, j1).
    pub fn blend(&self, a: f64, b: f64, c: f64, d: f64) -> f64 {
        let (tx, ty) = (self.tx, self.ty);
        (1.0 - ty) * ((1.0 - tx) * a + tx * b) + ty * ((1.0 - tx) * c + tx * d)
    }
}
