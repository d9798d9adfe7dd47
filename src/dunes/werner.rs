//! The Werner (1995) rules on the slab engine: erosion outside shadow zones, hops of `L`
//! cells with deposition probabilities, the 15-degree shadow zone and avalanching at the
//! angle of repose.
//!
//! [`WernerState`] holds the rules' constants and row bounds; its methods act on the heights
//! `h` (grains, `h[y * N + x]`) of an `N x N` torus that the slab engine lends them.

use rand::RngExt;

use super::grid;
use super::{GRAINS_PER_UNIT, PickEvent, WernerParams, to_grains};
use crate::engine::lattice::Lattice;
use crate::engine::rng::Stream;

/// The Werner rules' constants, in grains.
#[derive(Clone, Debug)]
pub(super) struct WernerState {
    /// Grains per slab.
    pub(super) slab: u64,
    /// Hop length, cells.
    pub(super) hop: u32,
    pub(super) p_sand: f64,
    pub(super) p_bare: f64,
    /// `shadow_drop[k]`: how far (grains) the 15-degree line from an upwind cell falls over
    /// `k` cells, `floor(k tan(15 deg) G)`, for `k < N`.
    pub(super) shadow_drop: Vec<u64>,
    /// Largest stable height difference to an edge / a diagonal neighbour, grains:
    /// `floor(tan(repose) G)` and `floor(tan(repose) sqrt(2) G)`.
    pub(super) repose_edge: u64,
    pub(super) repose_diag: u64,
    /// Per row, an upper bound of its heights (grains): recomputed each iteration, raised by
    /// deposits (the shadow test scans upwind only while a higher cell could still cast a
    /// shadow).
    pub(super) row_max: Vec<u64>,
}

impl WernerState {
    pub(super) fn new(p: &WernerParams, n: usize) -> Self {
        let g = GRAINS_PER_UNIT as f64;
        let ts = p.shadow_deg.to_radians().tan();
        let tr = p.repose_deg.to_radians().tan();
        WernerState {
            slab: to_grains(p.slab).max(1),
            hop: p.hop,
            p_sand: p.p_sand,
            p_bare: p.p_bare,
            shadow_drop: (0..n).map(|k| (k as f64 * ts * g).floor() as u64).collect(),
            repose_edge: (tr * g).floor() as u64,
            repose_diag: (tr * std::f64::consts::SQRT_2 * g).floor() as u64,
            row_max: vec![0; n],
        }
    }
}

impl WernerState {
    /// Recomputes the row bounds used by the shadow test.
    pub(super) fn refresh_row_max(&mut self, h: &[u64], n: usize) {
        for (m, row) in self.row_max.iter_mut().zip(h.chunks_exact(n)) {
            *m = row.iter().copied().max().unwrap_or(0);
        }
    }

    /// Keeps the row bound of cell `c`'s row at or above its height.
    #[inline]
    fn raise_row_max(&mut self, h: &[u64], n: usize, c: usize) {
        let r = (c as u32 / n as u32) as usize;
        let hc = h[c];
        if self.row_max[r] < hc {
            self.row_max[r] = hc;
        }
    }

    /// True when the cell in column `x` of the row starting at `row` lies in the shadow zone
    /// of an upwind cell: some cell `k` cells upwind (same row, `0 < k < N`) is higher by
    /// more than `k tan(15 deg)` cell widths.
    #[inline]
    pub(super) fn in_shadow_at(&self, h: &[u64], n: usize, x: usize, row: usize) -> bool {
        let hc = h[row + x];
        let room = self.row_max[row / n].max(hc) - hc;
        for k in 1..n {
            let drop = self.shadow_drop[k];
            if drop >= room {
                return false;
            }
            let ux = if x >= k { x - k } else { x + n - k };
            if h[row + ux] > hc + drop {
                return true;
            }
        }
        false
    }

    /// Werner's pick: a uniform cell that holds a slab and is not in a shadow zone loses one
    /// slab (avalanches fill the hole); the slab hops `L` cells downwind until it is
    /// deposited (always in a shadow zone, else with probability `p_sand` on sand and
    /// `p_bare` on a bare cell), then avalanches down the steepest slope while it exceeds the
    /// angle of repose.
    pub(super) fn pick(&mut self, h: &mut [u64], n: usize, rng: &mut Stream) -> PickEvent {
        let cells = (n * n) as u32;
        let c = rng.random_range(0..cells) as usize;
        let (slab, hop, ps, pb) = (self.slab, i64::from(self.hop), self.p_sand, self.p_bare);
        let (x0, row) = grid::split(n, c);
        let still = PickEvent {
            from: c,
            to: c,
            jump: 0,
            grains: 0,
        };
        if h[c] < slab || self.in_shadow_at(h, n, x0, row) {
            return still;
        }
        h[c] -= slab;
        self.avalanche(h, n, c, false);
        let step = grid::downwind_x(n, 0, hop);
        let mut x = x0;
        let mut dist = 0i64;
        loop {
            x += step;
            if x >= n {
                x -= n;
            }
            dist = dist.saturating_add(hop);
            if self.in_shadow_at(h, n, x, row) {
                break;
            }
            let p = if h[row + x] > 0 { ps } else { pb };
            if rng.random::<f64>() < p {
                break;
            }
        }
        let to = row + x;
        h[to] += slab;
        self.raise_row_max(h, n, to);
        self.avalanche(h, n, to, true);
        PickEvent {
            from: c,
            to,
            jump: dist,
            grains: slab,
        }
    }

    /// The avalanche walk from `c`. `downhill` (after a deposit on `c`): while some
    /// neighbour lies lower than the angle of repose allows, one slab slides to the one with
    /// the largest excess, and the check goes on from there. Otherwise (after an erosion at
    /// `c`): while some neighbour stands higher than the angle of repose allows, one slab
    /// slides from the one with the largest excess into the hole, and the check goes on from
    /// that neighbour.
    fn avalanche(&mut self, h: &mut [u64], n: usize, c: usize, downhill: bool) {
        let (slab, le, ld) = (self.slab, self.repose_edge, self.repose_diag);
        let (mut x, mut row) = grid::split(n, c);
        loop {
            let c = row + x;
            let hc = h[c];
            let mut best = None;
            let mut best_excess = 0u64;
            for (k, &(nb, nx, nrow)) in grid::moore(n, x, row).iter().enumerate() {
                let lim = if k % 2 == 0 { le } else { ld };
                let hn = h[nb];
                let (hi, lo) = if downhill { (hc, hn) } else { (hn, hc) };
                if hi > lo + lim && hi - lo - lim > best_excess {
                    best_excess = hi - lo - lim;
                    best = Some((nb, nx, nrow));
                }
            }
            let Some((nb, nx, nrow)) = best else {
                return;
            };
            let (from, to) = if downhill { (c, nb) } else { (nb, c) };
            h[from] -= slab;
            h[to] += slab;
            self.raise_row_max(h, n, to);
            (x, row) = (nx, nrow);
        }
    }

    /// Relaxes the whole grid to the angle of repose: sweeps over every neighbour pair,
    /// moving whole slabs (about half the excess at once) from the higher to the lower cell,
    /// until no pair is steeper than the angle of repose. Each move lowers the sum of squared
    /// heights, so the sweeps end.
    pub(super) fn relax_all(&mut self, h: &mut [u64], n: usize, lattice: &Lattice) {
        let (slab, le, ld) = (self.slab, self.repose_edge, self.repose_diag);
        let cells = n * n;
        loop {
            let mut moved = false;
            for c in 0..cells {
                let list = lattice.neighbour_list(c);
                // Offsets (1,0), (1,1), (0,1), (-1,1): each unordered pair once.
                for (k, &nb) in list.as_slice().iter().enumerate().take(4) {
                    let nb = nb as usize;
                    let lim = if k % 2 == 0 { le } else { ld };
                    let (hi, lo) = if h[c] >= h[nb] { (c, nb) } else { (nb, c) };
                    let diff = h[hi] - h[lo];
                    if diff > lim {
                        let m = (diff - lim).div_ceil(2 * slab) * slab;
                        h[hi] -= m;
                        h[lo] += m;
                        moved = true;
                    }
                }
            }
            if !moved {
                break;
            }
        }
        self.refresh_row_max(h, n);
    }

    /// True when every neighbour pair of `h` is within the angle of repose.
    pub(super) fn within_repose(&self, h: &[u64], n: usize, lattice: &Lattice) -> bool {
        (0..n * n).all(|c| {
            let list = lattice.neighbour_list(c);
            list.as_slice().iter().enumerate().all(|(k, &nb)| {
                let lim = if k % 2 == 0 {
                    self.repose_edge
                } else {
                    self.repose_diag
                };
                h[c].abs_diff(h[nb as usize]) <= lim
            })
        })
    }
}
