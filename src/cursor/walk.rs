//! The transition tables and the walker.
//!
//! [`Transitions`] holds, for every cell of an 8-neighbour torus ([`Lattice`], Moore
//! neighbourhood, periodic), the eight probabilities `P_i = 1/8 + k (W . u_i) / s` of the
//! article's Eq. (2) as a cumulative table of integer thresholds, 32 bytes per cell.
//! [`CursorWalk`] moves the cursor: one step costs one 64-bit random number, one table read and
//! seven comparisons; the neighbour follows by arithmetic (wrapping at the torus edges).
//!
//! # Rounded, exactly normalised probabilities
//!
//! Each cell's probabilities (computed in `f64`) are rounded to whole multiples of `2^-31`
//! that sum to exactly 1; a direction with probability 0 (possible only at `k = 1` and
//! `|W| = 220`) keeps weight 0 and is never taken. A step draws `r`, the top 31 bits of one
//! `u64` of the stream, and takes the direction `i` with `T_{i-1} <= r < T_i` (`T` the
//! cumulative weights), counted branch-free as the number of thresholds `T_0..T_6` that `r`
//! reaches. So the walk follows the rounded probabilities exactly
//! ([`Transitions::cell_probabilities`]); each differs from Eq. (2) by at most a few units of
//! `2^-31` (the most probable direction absorbs the rounding remainder), about `2e-9`, far below
//! what any run can resolve (a run of `N` steps measures a probability to about `N^-1/2`).
//! 31-bit thresholds keep the table small (1.8 MB for 240 x 240 cells; one 32-byte row in all
//! when every cell has the same probabilities), so that it stays in the processor's cache.

use rand::Rng;

use crate::engine::lattice::{Boundary, Lattice, MOORE, Neighbourhood};
use crate::engine::rng::{Stream, stream};

use super::wind::{Wind, WindField};
use super::{CursorError, P0, SPRING_SCALE};

/// The eight directions: the engine's [`MOORE`] offsets, counter-clockwise from +x,
/// `(dx, dy)` in cells (y up).
pub const DIRECTIONS: [(i32, i32); 8] = MOORE;

/// The unit vectors `u_i` of the eight directions (diagonals normalised by `1/sqrt 2`).
pub const UNIT: [(f64, f64); 8] = {
    const D: f64 = std::f64::consts::FRAC_1_SQRT_2;
    [
        (1.0, 0.0),
        (D, D),
        (0.0, 1.0),
        (-D, D),
        (-1.0, 0.0),
        (-D, -D),
        (0.0, -1.0),
        (D, -D),
    ]
};

/// `2^31`: the total of each cell's integer weights.
const ONE: u64 = 1 << 31;

/// The article's Eq. (2) for one cell: `P_i = 1/8 + k (W . u_i) / s`, `s = 8 * 220`, in the
/// order of [`DIRECTIONS`].
///
/// For `0 <= k <= 1` and `|W| <= 220` every `P_i` lies in `[0, 1/4]`, and the eight sum to 1
/// (the `u_i` cancel in opposite pairs). Values a rounding error below 0 are returned as 0.
pub fn probabilities(wind: Wind, k: f64) -> [f64; 8] {
    let mut p = [0.0; 8];
    for (pi, &(ux, uy)) in p.iter_mut().zip(UNIT.iter()) {
        *pi = (P0 + k * (wind.x * ux + wind.y * uy) / SPRING_SCALE).max(0.0);
    }
    p
}

/// Integer weights for `p` (which sums to 1 up to rounding) summing to exactly `2^31`: each
/// `P_i 2^31` rounded, and the few units of rounding difference given to (or taken from) the
/// most probable direction, whose weight is at least `2^28`. A zero probability stays 0.
fn integer_weights(p: &[f64; 8]) -> [u64; 8] {
    let mut q = [0u64; 8];
    for (qi, &pi) in q.iter_mut().zip(p) {
        *qi = (pi * ONE as f64).round() as u64;
    }
    let top = (0..8).fold(0, |a, i| if p[i] > p[a] { i } else { a });
    let sum: u64 = q.iter().sum();
    if sum > ONE {
        q[top] -= sum - ONE;
    } else {
        q[top] += ONE - sum;
    }
    q
}

/// Per-cell transition tables for a wind field and a force constant `k` on an 8-neighbour
/// torus.
#[derive(Clone, Debug)]
pub struct Transitions {
    lattice: Lattice,
    k: f64,
    /// Cumulative integer thresholds `T_0..T_7` per cell (`T_7 = 2^31`, never reached by a
    /// draw), 32 bytes; a single row shared by all cells when all are equal.
    thresholds: Vec<[u32; 8]>,
    /// The common wind, when the field is uniform.
    uniform: Option<Wind>,
}

impl Transitions {
    /// Builds the tables for `field` with force constant `k` (article: default 0.95).
    ///
    /// # Errors
    ///
    /// [`CursorError::ForceConstant`] unless `0 <= k <= 1`; [`CursorError::Lattice`] when the
    /// grid is smaller than 3 x 3 or too large; [`CursorError::WindTooStrong`] when a wind
    /// exceeds 220 (a field built through [`WindField`]'s constructors never does).
    pub fn new(field: &WindField, k: f64) -> Result<Transitions, CursorError> {
        if !(k.is_finite() && (0.0..=1.0).contains(&k)) {
            return Err(CursorError::ForceConstant(k));
        }
        field.validate("wind field")?;
        let lattice = Lattice::new(
            Neighbourhood::Square8,
            field.width(),
            field.height(),
            Boundary::TORUS,
        )?;
        let uniform = field.uniform_wind();
        // A uniform field keeps one row for all cells.
        let winds = match uniform {
            Some(_) => &field.winds()[..1],
            None => field.winds(),
        };
        let mut thresholds = Vec::with_capacity(winds.len());
        // Cells with the same wind share a table row computation.
        let mut last: Option<(Wind, [u32; 8])> = None;
        for &w in winds {
            let row = match last {
                Some((lw, row)) if lw == w => row,
                _ => {
                    let q = integer_weights(&probabilities(w, k));
                    let mut row = [0u32; 8];
                    let mut acc = 0u64;
                    for i in 0..8 {
                        acc += q[i];
                        // acc <= 2^31 fits a u32.
                        row[i] = acc as u32;
                    }
                    last = Some((w, row));
                    row
                }
            };
            thresholds.push(row);
        }
        // Identical rows everywhere (k = 0, or a field whose winds differ by less than the
        // rounding): one row for all cells.
        if thresholds.len() > 1 && thresholds.iter().all(|r| *r == thresholds[0]) {
            thresholds.truncate(1);
        }
        Ok(Transitions {
            lattice,
            k,
            thresholds,
            uniform,
        })
    }

    /// The lattice (8-neighbour torus).
    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }
    /// Columns.
    pub fn width(&self) -> usize {
        self.lattice.width()
    }
    /// Rows.
    pub fn height(&self) -> usize {
        self.lattice.height()
    }
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.lattice.len()
    }
    /// Always false: a grid has at least 9 cells.
    pub fn is_empty(&self) -> bool {
        false
    }
    /// The force constant `k`.
    pub fn k(&self) -> f64 {
        self.k
    }
    /// The common wind of a uniform field (calm included), `None` otherwise.
    pub fn uniform_wind(&self) -> Option<Wind> {
        self.uniform
    }

    /// True when every cell has the same probabilities (a uniform field, or any field at
    /// `k = 0`): the steps are then independent of position, the long-run density is uniform
    /// and [`crate::cursor::stats::NoiseModel`] gives the exact expected density error.
    pub fn is_translation_invariant(&self) -> bool {
        self.thresholds.len() == 1
    }

    /// The probabilities the walk actually uses in `cell` (the rounded ones, exact multiples
    /// of `2^-63` summing to 1), in the order of [`DIRECTIONS`].
    pub fn cell_probabilities(&self, cell: usize) -> [f64; 8] {
        let t = &self.thresholds[self.row(cell)];
        let mut p = [0.0; 8];
        let mut prev = 0u32;
        for i in 0..8 {
            p[i] = f64::from(t[i] - prev) / ONE as f64;
            prev = t[i];
        }
        p
    }

    /// The table row of `cell`.
    fn row(&self, cell: usize) -> usize {
        if self.thresholds.len() == 1 { 0 } else { cell }
    }

    /// The eight neighbours of `cell`, in the order of [`DIRECTIONS`].
    pub fn neighbours(&self, cell: usize) -> [u32; 8] {
        let mut ids = [0u32; 8];
        ids.copy_from_slice(self.lattice.neighbour_list(cell).as_slice());
        ids
    }

    /// The largest deviation from 1 of the probability of arriving in a cell,
    /// `max_c |sum_i P_{c - d_i}(i) - 1|`, over the rounded probabilities. It is 0 (up to
    /// `2^-60`) exactly when the transition matrix is doubly stochastic, i.e. the wind's
    /// discrete divergence vanishes, and then the long-run visit density is uniform.
    pub fn arrival_deviation(&self) -> f64 {
        let n = self.len();
        let mut arrive = vec![0u64; n];
        for c in 0..n {
            let t = &self.thresholds[self.row(c)];
            let ids = self.neighbours(c);
            let mut prev = 0u32;
            for i in 0..8 {
                arrive[ids[i] as usize] += u64::from(t[i] - prev);
                prev = t[i];
            }
        }
        arrive
            .iter()
            .map(|&a| (a as f64 - ONE as f64).abs() / ONE as f64)
            .fold(0.0, f64::max)
    }

    /// True when every cell receives total probability 1 (within `2^-27`, eight roundings of
    /// the probabilities): the uniform density is stationary and the expected long-run height
    /// is `steps / cells` everywhere.
    pub fn is_doubly_stochastic(&self) -> bool {
        self.arrival_deviation() <= 8.0 / ONE as f64
    }
}

/// `dx + 1` of the eight [`DIRECTIONS`], two bits each (direction `i` at bits `2i`).
const DX_PACKED: u32 = pack(0);
/// `dy + 1` of the eight [`DIRECTIONS`], two bits each.
const DY_PACKED: u32 = pack(1);

const fn pack(axis: usize) -> u32 {
    let mut v = 0u32;
    let mut i = 0;
    while i < 8 {
        let d = if axis == 0 {
            DIRECTIONS[i].0
        } else {
            DIRECTIONS[i].1
        };
        v |= ((d + 1) as u32) << (2 * i);
        i += 1;
    }
    v
}

/// `v + d` modulo `n`, for `v < n` and `d` in `-1..=1`.
#[inline(always)]
fn wrap(v: usize, d: i32, n: usize) -> usize {
    let u = v.wrapping_add(d as isize as usize);
    if u == usize::MAX {
        n - 1
    } else if u == n {
        0
    } else {
        u
    }
}

/// The cursor: its position, the heights (visit counts) and its random stream.
///
/// Counting rule: the cursor starts in the centre cell `(width / 2, height / 2)` (article:
/// "Simulation begins with the cursor placed in the center of grid") with every height 0; each
/// step moves it to a neighbour and adds 1 to the height of the cell it arrives in. The start
/// is not counted as a visit, so the heights always sum to the number of steps.
#[derive(Clone, Debug)]
pub struct CursorWalk<'t> {
    tr: &'t Transitions,
    heights: Vec<u64>,
    cell: usize,
    steps: u64,
    rng: Stream,
    /// Unwrapped displacement since the start, cells.
    dx: i64,
    dy: i64,
}

impl<'t> CursorWalk<'t> {
    /// A walk on `tr` from the centre cell, with the random stream of `seed`
    /// ([`crate::engine::rng::stream`]: Xoshiro256++).
    pub fn new(tr: &'t Transitions, seed: u64) -> CursorWalk<'t> {
        let start = (tr.height() / 2) * tr.width() + tr.width() / 2;
        CursorWalk::from_cell(tr, seed, start)
    }

    /// A walk from `cell` (taken modulo the number of cells).
    pub fn from_cell(tr: &'t Transitions, seed: u64, cell: usize) -> CursorWalk<'t> {
        CursorWalk {
            tr,
            heights: vec![0; tr.len()],
            cell: cell % tr.len(),
            steps: 0,
            rng: stream(seed),
            dx: 0,
            dy: 0,
        }
    }

    /// Makes `steps` more steps.
    pub fn run(&mut self, steps: u64) {
        self.run_with(steps, |_, _, _| {});
    }

    /// Makes `steps` more steps, calling `f(from, direction, to)` after each (`direction`
    /// indexes [`DIRECTIONS`]). Splitting a run into several calls does not change it.
    #[inline]
    pub fn run_with(&mut self, steps: u64, f: impl FnMut(usize, usize, usize)) {
        if self.tr.thresholds.len() == 1 {
            self.steps_impl::<true>(steps, f);
        } else {
            self.steps_impl::<false>(steps, f);
        }
    }

    /// The walk loop; `UNIFORM`: every cell shares table row 0 (translation invariant), so the
    /// loop reads no per-cell memory but the height it increments.
    #[inline(always)]
    fn steps_impl<const UNIFORM: bool>(
        &mut self,
        steps: u64,
        mut f: impl FnMut(usize, usize, usize),
    ) {
        let thresholds = &self.tr.thresholds[..];
        let heights = &mut self.heights[..];
        let (w, h) = (self.tr.width(), self.tr.height());
        let (mut x, mut y) = (self.cell % w, self.cell / w);
        let mut cell = self.cell;
        let (mut dx, mut dy) = (self.dx, self.dy);
        let mut rng = self.rng.clone();
        for _ in 0..steps {
            let r = (rng.next_u64() >> 33) as u32;
            let t = &thresholds[if UNIFORM { 0 } else { cell }];
            let mut dir = 0u32;
            for &ti in &t[..7] {
                dir += u32::from(r >= ti);
            }
            // The offset of direction `dir` from two packed constants (no memory load), and
            // the neighbour wrapped on the torus (arithmetic, no neighbour table).
            let ox = ((DX_PACKED >> (2 * dir)) & 3) as i32 - 1;
            let oy = ((DY_PACKED >> (2 * dir)) & 3) as i32 - 1;
            x = wrap(x, ox, w);
            y = wrap(y, oy, h);
            let next = y * w + x;
            heights[next] += 1;
            dx += i64::from(ox);
            dy += i64::from(oy);
            f(cell, dir as usize, next);
            cell = next;
        }
        self.rng = rng;
        self.cell = cell;
        self.dx = dx;
        self.dy = dy;
        self.steps += steps;
    }

    /// The heights (visit counts), row-major, row 0 at the bottom.
    pub fn heights(&self) -> &[u64] {
        &self.heights
    }
    /// The heights, consuming the walk.
    pub fn into_heights(self) -> Vec<u64> {
        self.heights
    }
    /// The sum of the heights; always equal to [`CursorWalk::steps`].
    pub fn height_total(&self) -> u64 {
        self.heights.iter().sum()
    }
    /// Steps made so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }
    /// The current cell index (`y * width + x`).
    pub fn cell(&self) -> usize {
        self.cell
    }
    /// The current position `(x, y)`.
    pub fn position(&self) -> (usize, usize) {
        (self.cell % self.tr.width(), self.cell / self.tr.width())
    }
    /// Displacement since the start, unwrapped (as on the infinite plane), cells.
    pub fn displacement(&self) -> (i64, i64) {
        (self.dx, self.dy)
    }
    /// The tables walked on.
    pub fn transitions(&self) -> &'t Transitions {
        self.tr
    }
}
