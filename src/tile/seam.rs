//! The seam statistic ([`SeamMeter`], [`SeamStats`]) and the edge cross-fade of mismatched tiles
//! ([`edge_weights`]).
//!
//! **Seam statistic.** Along x, every pair of neighbouring columns `(i, i + 1)` of the mosaic
//! (periodic: the last column pairs with the first) gives a *line mean*: the mean over all rows
//! of `|h(i + 1, y) - h(i, y)|`. Pairs that straddle a tile edge (`(i + 1) mod nx == 0`, the
//! mosaic's own wrap included) are *across*, the others *inside*. [`DirStats`] reports the mean
//! line mean of each class and the standard deviation of the inside line means, so a seam can be
//! judged against the scatter between the interior lines: a seam "no larger than inside" has an
//! across mean within the spread of the inside ones. The same along y with row pairs. The meter
//! is fed row by row, so it runs alongside the streaming writer in O(one row) memory.
//!
//! **Blending** mismatched tiles (patches from different seeds or distant steps): every tile is
//! toroidal, so each tile is itself continuous across the edges of its own cell when read
//! periodically. The mosaic value is a partition of unity over cells,
//! `h(x, y) = sum_K w_K(x, y) T_K(x mod nx, y mod ny)`, with separable weights that are 1 deep
//! inside a cell and cross-fade with a raised cosine over a band of `band` bins centred on each
//! edge ([`edge_weights`]): the result is continuous, and its jump across an edge is bounded by
//! the tiles' own gradients plus `|T_K - T_L| (pi / 2) / band` per bin.

use serde::Serialize;

/// The angle of repose of sand (the model's avalanche angle), degrees: relief steeper than this
/// would avalanche.
pub const ANGLE_OF_REPOSE_DEG: f64 = 32.0;

/// Slope statistics of a surface (slope = the angle of the gradient magnitude).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SlopeStats {
    /// Largest slope, degrees.
    pub max_deg: f64,
    /// The angle of the rms gradient magnitude, degrees.
    pub rms_deg: f64,
    /// Fraction of the places steeper than [`ANGLE_OF_REPOSE_DEG`].
    pub above_repose: f64,
    /// Places measured.
    pub n: u64,
}

/// Accumulates gradient magnitudes (m/m) into [`SlopeStats`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SlopeAcc {
    n: u64,
    sum_sq: f64,
    max: f64,
    above: u64,
}

impl SlopeAcc {
    /// Adds one gradient `(dh/dx, dh/dy)`.
    #[inline]
    pub fn push(&mut self, gx: f64, gy: f64) {
        let g2 = gx * gx + gy * gy;
        let t = ANGLE_OF_REPOSE_DEG.to_radians().tan();
        self.n += 1;
        self.sum_sq += g2;
        self.max = self.max.max(g2.sqrt());
        if g2 > t * t {
            self.above += 1;
        }
    }

    /// The statistics so far (all 0 when nothing was pushed).
    pub fn stats(&self) -> SlopeStats {
        if self.n == 0 {
            return SlopeStats::default();
        }
        SlopeStats {
            max_deg: self.max.atan().to_degrees(),
            rms_deg: (self.sum_sq / self.n as f64).sqrt().atan().to_degrees(),
            above_repose: self.above as f64 / self.n as f64,
            n: self.n,
        }
    }
}

/// The blend weights of bin `u` (0-based) of a tile of `n` bins with a cross-fade band of `band`
/// bins centred on each edge: `(own weight, neighbour, neighbour weight)` where `neighbour` is
/// -1 (the cell before), +1 (the cell after) or 0 (none; own weight 1). The own weight is the
/// raised cosine `s(t) = (1 - cos(pi t)) / 2` at `t = 1/2 + d / band`, `d` the distance of the
/// bin centre from the nearer edge (bins); it is 1/2 on the edge and 1 at `band / 2` inside.
/// The two sides of an edge get mirror weights, so the fade is symmetric. `band` at most `n`;
/// `band` 0 or 1 blends nothing.
#[inline]
pub fn edge_weights(u: usize, n: usize, band: usize) -> (f32, i8, f32) {
    if band < 2 {
        return (1.0, 0, 0.0);
    }
    let half = band as f64 / 2.0;
    let dl = u as f64 + 0.5;
    let dr = n as f64 - u as f64 - 0.5;
    let (d, side) = if dl <= dr { (dl, -1) } else { (dr, 1) };
    if d >= half {
        return (1.0, 0, 0.0);
    }
    let t = 0.5 + d / band as f64;
    let own = 0.5 - 0.5 * (std::f64::consts::PI * t).cos();
    (own as f32, side, (1.0 - own) as f32)
}

/// Seam statistics of one direction (all heights in m).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct DirStats {
    /// Mean |height jump| between neighbours inside tiles; `None` without interior pairs (tiles
    /// one bin wide).
    pub inside: Option<f64>,
    /// Mean |height jump| across tile edges; `None` without any.
    pub across: Option<f64>,
    /// Standard deviation of the per-line means inside (the scatter a seam is judged against);
    /// `None` with fewer than two interior lines.
    pub inside_line_sd: Option<f64>,
    /// Largest per-line mean inside.
    pub inside_line_max: Option<f64>,
    /// Lines (neighbour pairs) across tile edges.
    pub seams: usize,
    /// Lines inside tiles.
    pub lines: usize,
}

impl DirStats {
    /// `across / inside`; `None` when either is missing or inside is 0.
    pub fn ratio(&self) -> Option<f64> {
        match (self.across, self.inside) {
            (Some(a), Some(i)) if i > 0.0 => Some(a / i),
            _ => None,
        }
    }

    /// `(across - inside) / inside_line_sd`: how many interior line spreads the seam lies
    /// above the interior mean; `None` when something is missing or the spread is 0.
    pub fn z(&self) -> Option<f64> {
        match (self.across, self.inside, self.inside_line_sd) {
            (Some(a), Some(i), Some(s)) if s > 0.0 => Some((a - i) / s),
            _ => None,
        }
    }

    fn from_lines(lines: &[(f64, bool)]) -> DirStats {
        let (mut n_in, mut s_in, mut ss_in, mut max_in) = (0usize, 0.0, 0.0, f64::NEG_INFINITY);
        let (mut n_ac, mut s_ac) = (0usize, 0.0);
        for &(m, seam) in lines {
            if seam {
                n_ac += 1;
                s_ac += m;
            } else {
                n_in += 1;
                s_in += m;
                ss_in += m * m;
                max_in = max_in.max(m);
            }
        }
        let inside = (n_in > 0).then(|| s_in / n_in as f64);
        let sd = (n_in > 1).then(|| {
            let mean = s_in / n_in as f64;
            ((ss_in - n_in as f64 * mean * mean).max(0.0) / (n_in - 1) as f64).sqrt()
        });
        DirStats {
            inside,
            across: (n_ac > 0).then(|| s_ac / n_ac as f64),
            inside_line_sd: sd,
            inside_line_max: (n_in > 0).then_some(max_in),
            seams: n_ac,
            lines: n_in,
        }
    }
}

/// Seam statistics along x (jumps between neighbouring columns) and y (between rows).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SeamStats {
    /// Jumps along x.
    pub x: DirStats,
    /// Jumps along y.
    pub y: DirStats,
    /// Bin-to-bin slopes of the surface (forward differences along x and y, periodic), when the
    /// meter was given the bin size ([`SeamMeter::with_slopes`]).
    pub slope: Option<SlopeStats>,
}

/// Measures seams row by row: feed every row of a `width x height` surface made of tiles of
/// `tile_nx x tile_ny` bins with [`SeamMeter::push_row`], in order, then [`SeamMeter::finish`].
/// Memory: three rows.
#[derive(Clone, Debug)]
pub struct SeamMeter {
    tile_nx: usize,
    tile_ny: usize,
    col_sums: Vec<f64>,
    first: Vec<f32>,
    prev: Vec<f32>,
    rows: usize,
    y_lines: Vec<(f64, bool)>,
    slope: Option<(f64, SlopeAcc)>,
}

impl SeamMeter {
    /// A meter for rows of `width` values and tiles of `tile_nx x tile_ny` bins (both >= 1).
    pub fn new(width: usize, tile_nx: usize, tile_ny: usize) -> SeamMeter {
        SeamMeter {
            tile_nx: tile_nx.max(1),
            tile_ny: tile_ny.max(1),
            col_sums: vec![0.0; width],
            first: Vec::new(),
            prev: Vec::new(),
            rows: 0,
            y_lines: Vec::new(),
            slope: None,
        }
    }

    /// Also measures the bin-to-bin slopes of the surface, bins of `bin_size` m
    /// ([`SeamStats::slope`]).
    pub fn with_slopes(mut self, bin_size: f64) -> SeamMeter {
        self.slope = Some((bin_size, SlopeAcc::default()));
        self
    }

    /// Slopes between row `prev` and the next row `row` (the gradient at the bins of `prev`).
    fn slopes(acc: &mut SlopeAcc, dx: f64, prev: &[f32], row: &[f32]) {
        let w = prev.len();
        for i in 0..w {
            let j = if i + 1 == w { 0 } else { i + 1 };
            let gx = (prev[j] as f64 - prev[i] as f64) / dx;
            let gy = (row[i] as f64 - prev[i] as f64) / dx;
            acc.push(gx, gy);
        }
    }

    fn row_jump(a: &[f32], b: &[f32]) -> f64 {
        let s: f64 = a
            .iter()
            .zip(b)
            .map(|(&p, &q)| (q as f64 - p as f64).abs())
            .sum();
        s / a.len().max(1) as f64
    }

    /// Adds the next row (its length must be the width).
    pub fn push_row(&mut self, row: &[f32]) {
        let w = self.col_sums.len();
        if row.len() != w || w == 0 {
            return;
        }
        for i in 0..w {
            let j = if i + 1 == w { 0 } else { i + 1 };
            self.col_sums[i] += (row[j] as f64 - row[i] as f64).abs();
        }
        if self.rows == 0 {
            self.first = row.to_vec();
        } else {
            let seam = self.rows.is_multiple_of(self.tile_ny);
            self.y_lines.push((Self::row_jump(&self.prev, row), seam));
            if let Some((dx, acc)) = &mut self.slope {
                Self::slopes(acc, *dx, &self.prev, row);
            }
        }
        self.prev.clear();
        self.prev.extend_from_slice(row);
        self.rows += 1;
    }

    /// The statistics of the rows fed so far (the last row pairs with the first, periodic).
    pub fn finish(mut self) -> SeamStats {
        if self.rows == 0 {
            return SeamStats::default();
        }
        if self.rows > 1 {
            let seam = self.rows.is_multiple_of(self.tile_ny);
            self.y_lines
                .push((Self::row_jump(&self.prev, &self.first), seam));
            if let Some((dx, acc)) = &mut self.slope {
                Self::slopes(acc, *dx, &self.prev, &self.first);
            }
        }
        let h = self.rows as f64;
        let x_lines: Vec<(f64, bool)> = self
            .col_sums
            .iter()
            .enumerate()
            .map(|(i, &s)| (s / h, (i + 1) % self.tile_nx == 0))
            .collect();
        let x = if x_lines.len() > 1 {
            DirStats::from_lines(&x_lines)
        } else {
            DirStats::default()
        };
        SeamStats {
            x,
            y: DirStats::from_lines(&self.y_lines),
            slope: self.slope.map(|(_, acc)| acc.stats()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_weights_are_symmetric_and_fade_smoothly() {
        let (n, band) = (16, 8);
        // last bin of a cell and first bin of the next: mirror weights
        let (a, sa, _) = edge_weights(n - 1, n, band);
        let (b, sb, _) = edge_weights(0, n, band);
        assert_eq!(sa, 1);
        assert_eq!(sb, -1);
        assert!((a - b).abs() < 1e-7);
        assert!(a > 0.5 && a < 0.6, "{a}");
        // deep inside: own weight 1
        assert_eq!(edge_weights(n / 2, n, band), (1.0, 0, 0.0));
        // increasing towards the interior
        let w: Vec<f32> = (0..band / 2).map(|u| edge_weights(u, n, band).0).collect();
        assert!(w.windows(2).all(|p| p[1] > p[0]), "{w:?}");
        assert_eq!(edge_weights(3, n, 0), (1.0, 0, 0.0));
    }

    #[test]
    fn meter_finds_a_step_at_a_tile_edge() {
        // two tiles of 4 columns, the second one 1 higher: the seams at columns 3|4 and 7|0
        // jump by 1, inside nothing moves.
        let mut m = SeamMeter::new(8, 4, 2);
        for _ in 0..4 {
            m.push_row(&[0., 0., 0., 0., 1., 1., 1., 1.]);
        }
        let s = m.finish();
        assert_eq!(s.x.across, Some(1.0));
        assert_eq!(s.x.inside, Some(0.0));
        assert_eq!(s.x.seams, 2);
        assert_eq!(s.y.across, Some(0.0));
        assert_eq!(s.y.seams, 2);
        assert_eq!(s.y.lines, 2);
        assert_eq!(s.slope, None);
    }

    #[test]
    fn meter_measures_slopes() {
        // a ramp rising 1 bin per bin along y (45 deg) with a 2-bin step (63.4 deg) at x 3|0
        let mut m = SeamMeter::new(4, 4, 4).with_slopes(0.5);
        for y in 0..4 {
            let z = 0.5 * y as f32;
            m.push_row(&[z, z, z, z + 1.0]);
        }
        let s = m.finish().slope.unwrap();
        assert_eq!(s.n, 16);
        // the wrap pair of rows (3 -> 0) falls by 3 bins, with the x step: atan(sqrt(13))
        assert!(
            (s.max_deg - 13f64.sqrt().atan().to_degrees()).abs() < 1e-9,
            "{s:?}"
        );
        assert!((s.above_repose - 1.0).abs() < 1e-12, "{s:?}");
    }
}
