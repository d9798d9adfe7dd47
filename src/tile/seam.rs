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

    /// Adds the gradients another accumulator took.
    pub fn merge(&mut self, o: &SlopeAcc) {
        self.n += o.n;
        self.sum_sq += o.sum_sq;
        self.max = self.max.max(o.max);
        self.above += o.above;
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

/// Lanes of the row kernel [`pass`]: its sums run in `LANES` interleaved partial sums, so that
/// they vectorise.
const LANES: usize = 4;

/// The slopes of [`pass`], in height units (m): sums, largest values and counts of the squared
/// height differences `dh_x^2 + dh_y^2` to the next bin along x and along y, in lanes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Lanes {
    n: u64,
    sum: [f64; LANES],
    max: [f64; LANES],
    above: [u64; LANES],
}

impl Lanes {
    /// The gradients' accumulator for bins of `dx` m.
    fn slopes(&self, dx: f64) -> SlopeAcc {
        SlopeAcc {
            n: self.n,
            sum_sq: self.sum.iter().sum::<f64>() / (dx * dx),
            max: self.max.iter().fold(0.0f64, |a, &m| a.max(m)).sqrt() / dx,
            above: self.above.iter().sum(),
        }
    }
}

/// The squared height difference above which a bin of `dx` m is steeper than the angle of
/// repose.
fn repose_sq(dx: f64) -> f64 {
    let t = ANGLE_OF_REPOSE_DEG.to_radians().tan() * dx;
    t * t
}

/// The row kernel of [`SeamMeter`] and [`SeamBlock`]: for the bins of `cur` (with `right`, the
/// bin after its last), adds `|h(x + 1) - h(x)|` to `cols`; with the row after it, `next`,
/// also the slopes (`above`: the squared height difference counted as steeper than the angle
/// of repose), and returns the sum over the row of `|h(y + 1) - h(y)|` (0 without `next`).
#[inline]
fn pass(
    cur: &[f32],
    right: f32,
    next: Option<&[f32]>,
    cols: &mut [f64],
    lanes: &mut Lanes,
    above: f64,
) -> f64 {
    let n = cur.len().min(cols.len());
    if n == 0 {
        return 0.0;
    }
    let Some(next) = next.filter(|r| r.len() >= n) else {
        for (i, c) in cols.iter_mut().enumerate().take(n) {
            let after = if i + 1 < n { cur[i + 1] } else { right };
            *c += (after as f64 - cur[i] as f64).abs();
        }
        return 0.0;
    };
    // local lanes (kept in registers), the bins in fixed runs of LANES without bounds checks
    let (mut sum, mut max, mut count) = (lanes.sum, lanes.max, lanes.above);
    let mut row = [0.0f64; LANES];
    let mut bin = |l: usize, h: f32, hr: f32, hn: f32, col: &mut f64| {
        let h = h as f64;
        let (hx, hy) = (hr as f64 - h, hn as f64 - h);
        *col += hx.abs();
        row[l] += hy.abs();
        let d2 = hx * hx + hy * hy;
        sum[l] += d2;
        max[l] = if d2 > max[l] { d2 } else { max[l] };
        count[l] += u64::from(d2 > above);
    };
    let last = n - 1;
    let whole = last - last % LANES;
    for (((c, r), hn), col) in cur[..whole]
        .chunks_exact(LANES)
        .zip(cur[1..=whole].chunks_exact(LANES))
        .zip(next[..whole].chunks_exact(LANES))
        .zip(cols[..whole].chunks_exact_mut(LANES))
    {
        for l in 0..LANES {
            bin(l, c[l], r[l], hn[l], &mut col[l]);
        }
    }
    for i in whole..n {
        let hr = if i < last { cur[i + 1] } else { right };
        bin(i % LANES, cur[i], hr, next[i], &mut cols[i]);
    }
    (lanes.sum, lanes.max, lanes.above) = (sum, max, count);
    lanes.n += n as u64;
    row.iter().sum()
}

/// Measures seams row by row: feed every row of a `width x height` surface made of tiles of
/// `tile_nx x tile_ny` bins with [`SeamMeter::push_row`], in order, then [`SeamMeter::finish`].
/// Memory: two rows.
#[derive(Clone, Debug)]
pub struct SeamMeter {
    tile_nx: usize,
    tile_ny: usize,
    col_sums: Vec<f64>,
    first: Vec<f32>,
    prev: Vec<f32>,
    rows: usize,
    y_lines: Vec<(f64, bool)>,
    bin_size: Option<f64>,
    lanes: Lanes,
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
            bin_size: None,
            lanes: Lanes::default(),
        }
    }

    /// Also measures the bin-to-bin slopes of the surface, bins of `bin_size` m
    /// ([`SeamStats::slope`]): the gradient at each bin from the forward differences along x
    /// and y (periodic).
    pub fn with_slopes(mut self, bin_size: f64) -> SeamMeter {
        self.bin_size = Some(bin_size);
        self
    }

    /// The jumps from the previous row to `next` (and the slopes at the previous row's bins).
    fn pair(&mut self, next: &[f32], seam: bool) {
        let above = repose_sq(self.bin_size.unwrap_or(1.0));
        let right = self.prev[0];
        let s = pass(
            &self.prev,
            right,
            Some(next),
            &mut self.col_sums,
            &mut self.lanes,
            above,
        );
        self.y_lines.push((s / self.prev.len() as f64, seam));
    }

    /// Adds the next row (its length must be the width).
    pub fn push_row(&mut self, row: &[f32]) {
        let w = self.col_sums.len();
        if row.len() != w || w == 0 {
            return;
        }
        if self.rows == 0 {
            self.first = row.to_vec();
        } else {
            self.pair(row, self.rows.is_multiple_of(self.tile_ny));
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
            let first = std::mem::take(&mut self.first);
            self.pair(&first, self.rows.is_multiple_of(self.tile_ny));
        } else {
            let right = self.prev[0];
            pass(
                &self.prev,
                right,
                None,
                &mut self.col_sums,
                &mut self.lanes,
                0.0,
            );
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
            slope: self.bin_size.map(|dx| self.lanes.slopes(dx).stats()),
        }
    }
}

/// The sums of [`SeamMeter`] over one block of a surface, for a surface written block by block
/// in any order (a Zarr store's chunks): [`SeamBlock::measure`] in each block, then
/// [`SeamSums::add`] in any order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SeamBlock {
    x0: usize,
    y0: usize,
    /// Per column of the block: the sum over its rows of |h(x + 1, y) - h(x, y)|.
    cols: Vec<f64>,
    /// Per row of the block: the sum over its columns of |h(x, y + 1) - h(x, y)|.
    rows: Vec<f64>,
    slope: SlopeAcc,
}

impl SeamBlock {
    /// The sums over the block of `nx x ny` bins at `(x0, y0)`: `block` holds its rows, `stride`
    /// values apart; its periodic neighbours are `next_col`, the bin after each row's last
    /// (`ny` values: column 0 after the surface's last), and `next_row`, the row after its last
    /// (`nx` values: row 0 after the surface's last). `bin_size`, m, also measures the slopes;
    /// `pair_rows` false (a surface of one row) measures no row pairs and no slopes, as
    /// [`SeamMeter`]. The same per-bin arithmetic as the meter's.
    pub fn measure(
        (x0, y0): (usize, usize),
        (nx, ny): (usize, usize),
        (block, stride): (&[f32], usize),
        (next_col, next_row): (&[f32], &[f32]),
        bin_size: Option<f64>,
        pair_rows: bool,
    ) -> SeamBlock {
        let mut b = SeamBlock {
            x0,
            y0,
            cols: vec![0.0; nx],
            rows: vec![0.0; if pair_rows { ny } else { 0 }],
            slope: SlopeAcc::default(),
        };
        if ny == 0 || block.len() < (ny - 1) * stride + nx || next_col.len() < ny {
            return b;
        }
        let above = repose_sq(bin_size.unwrap_or(1.0));
        let mut lanes = Lanes::default();
        for y in 0..ny {
            let cur = &block[y * stride..y * stride + nx];
            let next = if y + 1 < ny {
                &block[(y + 1) * stride..(y + 1) * stride + nx]
            } else {
                next_row
            };
            let s = pass(
                cur,
                next_col[y],
                pair_rows.then_some(next),
                &mut b.cols,
                &mut lanes,
                above,
            );
            if pair_rows {
                b.rows[y] = s;
            }
        }
        if let Some(dx) = bin_size.filter(|_| pair_rows) {
            b.slope = lanes.slopes(dx);
        }
        b
    }
}

/// [`SeamMeter`]'s statistics from [`SeamBlock`]s added in any order: the same line means
/// (summed in another order, so equal to rounding), the same slopes.
#[derive(Clone, Debug)]
pub struct SeamSums {
    tile_nx: usize,
    tile_ny: usize,
    cols: Vec<f64>,
    rows: Vec<f64>,
    slope: Option<SlopeAcc>,
}

impl SeamSums {
    /// Sums for a `width x height` surface of tiles of `tile_nx x tile_ny` bins; `slopes`:
    /// whether the blocks measure slopes ([`SeamMeter::with_slopes`]).
    pub fn new(width: usize, height: usize, tile_nx: usize, tile_ny: usize, slopes: bool) -> Self {
        SeamSums {
            tile_nx: tile_nx.max(1),
            tile_ny: tile_ny.max(1),
            cols: vec![0.0; width],
            rows: vec![0.0; height],
            slope: slopes.then(SlopeAcc::default),
        }
    }

    /// Adds a block's sums (blocks must not overlap).
    pub fn add(&mut self, b: &SeamBlock) {
        for (s, v) in self.cols.iter_mut().skip(b.x0).zip(&b.cols) {
            *s += v;
        }
        for (s, v) in self.rows.iter_mut().skip(b.y0).zip(&b.rows) {
            *s += v;
        }
        if let Some(acc) = &mut self.slope {
            acc.merge(&b.slope);
        }
    }

    /// The statistics, once every bin of the surface is in one block added.
    pub fn finish(self) -> SeamStats {
        let (w, h) = (self.cols.len(), self.rows.len());
        if w == 0 || h == 0 {
            return SeamStats::default();
        }
        let x_lines: Vec<(f64, bool)> = self
            .cols
            .iter()
            .enumerate()
            .map(|(i, &s)| (s / h as f64, (i + 1) % self.tile_nx == 0))
            .collect();
        let y_lines: Vec<(f64, bool)> = if h > 1 {
            self.rows
                .iter()
                .enumerate()
                .map(|(j, &s)| (s / w as f64, (j + 1) % self.tile_ny == 0))
                .collect()
        } else {
            Vec::new()
        };
        SeamStats {
            x: if w > 1 {
                DirStats::from_lines(&x_lines)
            } else {
                DirStats::default()
            },
            y: DirStats::from_lines(&y_lines),
            slope: self.slope.map(|acc| acc.stats()),
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
    fn blocks_in_any_order_give_the_meter_s_statistics() {
        // a 7 x 5 surface of 3 x 2 tiles (partial tiles at the edges), blocks of 3 x 2
        let (w, h) = (7usize, 5usize);
        let v = |x: usize, y: usize| ((x * 7 + y * 13) % 11) as f32 * 0.01 + (x / 3) as f32;
        let mut m = SeamMeter::new(w, 3, 2).with_slopes(0.5);
        for y in 0..h {
            let row: Vec<f32> = (0..w).map(|x| v(x, y)).collect();
            m.push_row(&row);
        }
        let want = m.finish();
        let mut sums = SeamSums::new(w, h, 3, 2, true);
        let mut blocks = Vec::new();
        for y0 in (0..h).step_by(2) {
            for x0 in (0..w).step_by(3) {
                let (nx, ny) = (3.min(w - x0), 2.min(h - y0));
                // the block in a chunk of stride 4, its next column and row
                let stride = 4;
                let mut vals = vec![f32::NAN; stride * ny];
                for r in 0..ny {
                    for c in 0..nx {
                        vals[r * stride + c] = v(x0 + c, y0 + r);
                    }
                }
                let col: Vec<f32> = (0..ny).map(|r| v((x0 + nx) % w, y0 + r)).collect();
                let row: Vec<f32> = (0..nx).map(|c| v(x0 + c, (y0 + ny) % h)).collect();
                blocks.push(SeamBlock::measure(
                    (x0, y0),
                    (nx, ny),
                    (&vals, stride),
                    (&col, &row),
                    Some(0.5),
                    true,
                ));
            }
        }
        for b in blocks.iter().rev() {
            sums.add(b);
        }
        let got = sums.finish();
        let close = |a: Option<f64>, b: Option<f64>| match (a, b) {
            (Some(a), Some(b)) => (a - b).abs() <= 1e-12 * a.abs().max(1.0),
            (a, b) => a == b,
        };
        for (g, e) in [(got.x, want.x), (got.y, want.y)] {
            assert!(
                close(g.inside, e.inside) && close(g.across, e.across),
                "{g:?} {e:?}"
            );
            assert!(close(g.inside_line_sd, e.inside_line_sd), "{g:?} {e:?}");
            assert_eq!((g.seams, g.lines), (e.seams, e.lines));
        }
        let (gs, es) = (got.slope.unwrap(), want.slope.unwrap());
        assert_eq!((gs.n, gs.above_repose), (es.n, es.above_repose));
        assert!((gs.max_deg - es.max_deg).abs() < 1e-12 && (gs.rms_deg - es.rms_deg).abs() < 1e-9);
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
