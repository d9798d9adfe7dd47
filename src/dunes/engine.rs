//! The slab engine: integer grains on an `N x N` torus, one random stream, the picks and the
//! rolling rule of each mode.

use rand::RngExt;

use super::grid;
use super::measure::{self, DuneStats};
use super::werner::WernerState;
use super::{
    DUNE_PICK_FRACTION, DuneConfig, DuneError, GRAINS_PER_UNIT, Mode, PickEvent, RIPPLE_INITIAL,
    RIPPLE_Q, jump_length, ripple_jump, rolling_rule, sand_quantity, to_grains, to_units,
};
use crate::engine::lattice::{Boundary, Lattice, Neighbourhood};
use crate::engine::rng::{Stream, stream};

/// Marks a cell that is not in the set of cells holding sand.
const ABSENT: u32 = u32::MAX;

/// The slab engine: heights as integer grains on an `N x N` torus, advanced by the rules of
/// a [`Mode`].
///
/// Heights are `h[y * N + x]` in grains ([`GRAINS_PER_UNIT`] per height unit), `x` downwind.
/// Built by [`DuneModel::new`], which draws the initial field from the seed's stream;
/// [`DuneModel::step`] runs one iteration (the picks, then the rolling rule in the article's
/// modes). Nothing is allocated per pick or per iteration.
#[derive(Clone, Debug)]
pub struct DuneModel {
    pub(super) cfg: DuneConfig,
    pub(super) n: usize,
    pub(super) lattice: Lattice,
    pub(super) h: Vec<u64>,
    /// Scratch for the rolling rule's fluxes.
    pub(super) flux: Vec<u64>,
    /// Dune mode: the cells holding sand, and each cell's slot in that list (or `ABSENT`).
    pub(super) positive: Vec<u32>,
    pub(super) slot: Vec<u32>,
    pub(super) rng: Stream,
    pub(super) iteration: u64,
    pub(super) initial_total: u64,
    pub(super) picks: u64,
    pub(super) moves: u64,
    /// Ripple mode: grains moved per pick (`q = 0.1`).
    pub(super) q_grains: u64,
    /// Dune mode: picks per iteration, `int(0.2 N^2)`.
    pub(super) dune_picks: u64,
    pub(super) werner: Option<WernerState>,
}

impl DuneModel {
    /// Checks `cfg` and draws the initial field: ripple mode uniform in `[2.85, 3.15]`; dune
    /// mode uniform in `[0, 2Q]`; Werner the same law rounded to whole slabs, then relaxed to
    /// the angle of repose. Heights are rounded to the nearest grain.
    pub fn new(cfg: &DuneConfig) -> Result<Self, DuneError> {
        cfg.validate()?;
        let n = cfg.grid;
        let cells = n * n;
        let lattice = Lattice::new(Neighbourhood::Square8, n, n, Boundary::TORUS).map_err(|e| {
            DuneError::Parameter {
                name: "grid",
                value: format!("{n} ({e})"),
                range: super::GRID.expected,
            }
        })?;
        let mut rng = stream(cfg.seed);
        let mut h = vec![0u64; cells];
        let mut werner = None;
        match cfg.mode {
            Mode::Ripple => {
                let (lo, hi) = RIPPLE_INITIAL;
                for v in h.iter_mut() {
                    let u: f64 = rng.random();
                    *v = to_grains(lo + (hi - lo) * u);
                }
            }
            Mode::Dune => {
                for v in h.iter_mut() {
                    let u: f64 = rng.random();
                    *v = to_grains(2.0 * cfg.quantity * u);
                }
            }
            Mode::Werner => {
                let w = WernerState::new(&cfg.werner, n);
                let slabs_max = 2.0 * cfg.quantity / cfg.werner.slab;
                for v in h.iter_mut() {
                    let u: f64 = rng.random();
                    *v = (slabs_max * u).round() as u64 * w.slab;
                }
                werner = Some(w);
            }
        }
        let initial_total = h.iter().sum();
        let mut m = DuneModel {
            cfg: cfg.clone(),
            n,
            lattice,
            h,
            flux: Vec::with_capacity(2 * cells),
            positive: Vec::new(),
            slot: Vec::new(),
            rng,
            iteration: 0,
            initial_total,
            picks: 0,
            moves: 0,
            q_grains: to_grains(RIPPLE_Q),
            dune_picks: (DUNE_PICK_FRACTION * cells as f64) as u64,
            werner,
        };
        if cfg.mode == Mode::Dune {
            m.positive = Vec::with_capacity(cells);
            m.slot = vec![ABSENT; cells];
            m.rebuild_positive();
        }
        if cfg.mode == Mode::Werner {
            m.relax_all();
        }
        Ok(m)
    }

    /// A model of `cfg` that starts from the given heights (grains, `h[y * N + x]`, `N^2` of
    /// them) instead of the random initial field; the random stream starts afresh from the
    /// seed. In Werner mode every height must be a whole number of slabs, and the field is
    /// relaxed to the angle of repose.
    pub fn from_grains(cfg: &DuneConfig, grains: Vec<u64>) -> Result<Self, DuneError> {
        let mut m = DuneModel::new(&DuneConfig {
            quantity: 0.0,
            ..cfg.clone()
        })?;
        let cells = m.n * m.n;
        if grains.len() != cells {
            return Err(DuneError::Parameter {
                name: "grains",
                value: format!("{} heights", grains.len()),
                range: "exactly grid^2 heights",
            });
        }
        let total: u128 = grains.iter().map(|&g| u128::from(g)).sum();
        if total > 1 << 62 {
            return Err(DuneError::Parameter {
                name: "grains",
                value: format!("{total} grains in all"),
                range: "at most 2^62 grains in all",
            });
        }
        if let Some(w) = m.werner.as_ref()
            && let Some(g) = grains.iter().find(|&&g| g % w.slab != 0)
        {
            return Err(DuneError::Parameter {
                name: "grains",
                value: g.to_string(),
                range: "whole slabs in Werner mode",
            });
        }
        m.cfg.quantity = cfg.quantity;
        m.rng = stream(cfg.seed);
        m.h = grains;
        m.initial_total = total as u64;
        if m.cfg.mode == Mode::Dune {
            m.rebuild_positive();
        }
        if m.cfg.mode == Mode::Werner {
            m.relax_all();
        }
        Ok(m)
    }

    /// The configuration.
    pub fn config(&self) -> &DuneConfig {
        &self.cfg
    }

    /// Grid side `N`.
    pub fn grid(&self) -> usize {
        self.n
    }

    /// The 8-neighbour torus of the grid.
    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }

    /// Heights in grains, `h[y * N + x]`.
    pub fn grains(&self) -> &[u64] {
        &self.h
    }

    /// Heights in height units, `h[y * N + x]`.
    pub fn heights(&self) -> Vec<f64> {
        self.h.iter().map(|&g| to_units(g)).collect()
    }

    /// Height of cell `(x, y)` in height units.
    pub fn height(&self, x: usize, y: usize) -> f64 {
        to_units(self.h[y * self.n + x])
    }

    /// Iterations done.
    pub fn iteration(&self) -> u64 {
        self.iteration
    }

    /// Picks made so far, and how many of them moved sand.
    pub fn picks(&self) -> (u64, u64) {
        (self.picks, self.moves)
    }

    /// Total sand now, grains.
    pub fn total_grains(&self) -> u64 {
        self.h.iter().sum()
    }

    /// Total sand at the start, grains.
    pub fn initial_grains(&self) -> u64 {
        self.initial_total
    }

    /// Total sand now minus at the start, grains: always 0.
    pub fn sand_change(&self) -> i128 {
        self.total_grains() as i128 - self.initial_total as i128
    }

    /// The observables now (see [`DuneStats`]), with the body threshold
    /// [`BODY_THRESHOLD`](super::BODY_THRESHOLD).
    pub fn stats(&self) -> DuneStats {
        self.stats_with_threshold(super::BODY_THRESHOLD)
    }

    /// The observables now, with dune bodies made of the cells higher than `threshold`
    /// height units.
    pub fn stats_with_threshold(&self, threshold: f64) -> DuneStats {
        measure::stats(
            &self.h,
            &self.lattice,
            self.iteration,
            self.sand_change(),
            threshold,
        )
    }

    /// `(x, row start)` of cell `c` ([`grid::split`]).
    #[inline(always)]
    pub(super) fn split(&self, c: usize) -> (usize, usize) {
        grid::split(self.n, c)
    }

    /// Column `jump` cells downwind of column `x` ([`grid::downwind_x`]).
    #[inline(always)]
    pub(super) fn downwind_x(&self, x: usize, jump: i64) -> usize {
        grid::downwind_x(self.n, x, jump)
    }

    /// Cell `jump` cells downwind of `c` (wrapping, any `jump`).
    #[inline(always)]
    pub fn downwind(&self, c: usize, jump: i64) -> usize {
        let (x, row) = self.split(c);
        row + self.downwind_x(x, jump)
    }

    /// One pick of the mode's jumping rule. Returns `None` when no pick can be made (dune
    /// mode with no sand left anywhere), else what the pick did.
    pub fn pick(&mut self) -> Option<PickEvent> {
        let ev = match self.cfg.mode {
            Mode::Ripple => Some(self.pick_ripple()),
            Mode::Dune => self.pick_dune(),
            Mode::Werner => Some(self.pick_werner()),
        };
        if let Some(e) = ev {
            self.picks += 1;
            if e.grains > 0 {
                self.moves += 1;
            }
        }
        ev
    }

    /// Ripple mode: a uniform cell sends `min(q, h)` to `int(wind + h)` cells downwind.
    fn pick_ripple(&mut self) -> PickEvent {
        let cells = (self.n * self.n) as u32;
        let c = self.rng.random_range(0..cells) as usize;
        let a = self.h[c];
        let jump = ripple_jump(self.cfg.wind, to_units(a));
        let (x, row) = self.split(c);
        let to = row + self.downwind_x(x, jump);
        let m = a.min(self.q_grains);
        self.h[c] -= m;
        self.h[to] += m;
        PickEvent {
            from: c,
            to,
            jump,
            grains: m,
        }
    }

    /// Dune mode: a uniform cell among those holding sand sends `min(sand_quantity, h)` to
    /// `jump_length` cells downwind, both from the centred slope `(h[x+1] - h[x-1]) / 2`.
    fn pick_dune(&mut self) -> Option<PickEvent> {
        let len = self.positive.len();
        if len == 0 {
            return None;
        }
        let k = self.rng.random_range(0..len as u32) as usize;
        let c = self.positive[k] as usize;
        let n = self.n;
        let (x, row) = self.split(c);
        let xm = if x == 0 { n - 1 } else { x - 1 };
        let xp = if x + 1 == n { 0 } else { x + 1 };
        let dz = self.h[row + xp] as i64 - self.h[row + xm] as i64;
        let slope = dz as f64 / (2 * GRAINS_PER_UNIT) as f64;
        let jump = jump_length(slope);
        let q = to_grains(sand_quantity(slope));
        let a = self.h[c];
        let m = a.min(q);
        let to = row + self.downwind_x(x, jump);
        self.h[c] -= m;
        if self.h[c] == 0 {
            self.remove_positive(c);
        }
        if m > 0 && self.h[to] == 0 {
            self.add_positive(to);
        }
        self.h[to] += m;
        Some(PickEvent {
            from: c,
            to,
            jump,
            grains: m,
        })
    }

    #[inline]
    fn add_positive(&mut self, c: usize) {
        if self.slot[c] == ABSENT {
            self.slot[c] = self.positive.len() as u32;
            self.positive.push(c as u32);
        }
    }

    #[inline]
    fn remove_positive(&mut self, c: usize) {
        let s = self.slot[c];
        if s != ABSENT {
            let last = self.positive.pop().unwrap_or(c as u32);
            if last as usize != c {
                self.positive[s as usize] = last;
                self.slot[last as usize] = s;
            }
            self.slot[c] = ABSENT;
        }
    }

    fn rebuild_positive(&mut self) {
        self.positive.clear();
        for (c, (&v, s)) in self.h.iter().zip(self.slot.iter_mut()).enumerate() {
            if v > 0 {
                *s = self.positive.len() as u32;
                self.positive.push(c as u32);
            } else {
                *s = ABSENT;
            }
        }
    }

    /// Number of cells holding sand (dune mode keeps this set; other modes count).
    pub fn cells_with_sand(&self) -> usize {
        if self.cfg.mode == Mode::Dune {
            self.positive.len()
        } else {
            self.h.iter().filter(|&&v| v > 0).count()
        }
    }

    /// Picks per iteration: `N^2` (ripple, Werner) or `int(0.2 N^2)` (dune).
    pub fn picks_per_iteration(&self) -> u64 {
        match self.cfg.mode {
            Mode::Dune => self.dune_picks,
            _ => (self.n * self.n) as u64,
        }
    }

    /// One iteration: the mode's picks, then (ripple and dune modes) the rolling rule.
    pub fn step(&mut self) {
        match self.cfg.mode {
            Mode::Ripple | Mode::Dune => {
                for _ in 0..self.picks_per_iteration() {
                    if self.pick().is_none() {
                        break;
                    }
                }
                let d = self.cfg.mode.rolling().unwrap_or(0.0);
                rolling_rule(&mut self.h, self.n, d, &mut self.flux);
                if self.cfg.mode == Mode::Dune {
                    self.rebuild_positive();
                }
            }
            Mode::Werner => {
                self.refresh_row_max();
                for _ in 0..self.picks_per_iteration() {
                    self.pick();
                }
            }
        }
        self.iteration += 1;
    }

    /// Runs `iterations` iterations.
    pub fn run(&mut self, iterations: u64) {
        for _ in 0..iterations {
            self.step();
        }
    }

    /// Runs the configured number of iterations (those not yet done).
    pub fn run_to_end(&mut self) {
        let left = self.cfg.iterations.saturating_sub(self.iteration);
        self.run(left);
    }

    /// Werner mode's pick ([`WernerState::pick`]).
    fn pick_werner(&mut self) -> PickEvent {
        let w = self
            .werner
            .as_mut()
            .expect("Werner state exists in Werner mode");
        w.pick(&mut self.h, self.n, &mut self.rng)
    }

    /// Werner mode: relaxes the whole grid to the angle of repose.
    fn relax_all(&mut self) {
        if let Some(w) = self.werner.as_mut() {
            w.relax_all(&mut self.h, self.n, &self.lattice);
        }
    }

    /// Werner mode: recomputes the row bounds of the shadow test.
    fn refresh_row_max(&mut self) {
        if let Some(w) = self.werner.as_mut() {
            w.refresh_row_max(&self.h, self.n);
        }
    }

    /// True when cell `c` lies in the shadow zone of an upwind cell: some cell `k` cells
    /// upwind (same row, `0 < k < N`) is higher by more than `k tan(15 deg)` cell widths.
    /// Always false outside Werner mode.
    pub fn in_shadow(&self, c: usize) -> bool {
        let (x, row) = self.split(c);
        self.werner
            .as_ref()
            .is_some_and(|w| w.in_shadow_at(&self.h, self.n, x, row))
    }

    /// True when every neighbour pair is within the angle of repose (Werner mode; always
    /// true in the other modes).
    pub fn within_repose(&self) -> bool {
        self.werner
            .as_ref()
            .is_none_or(|w| w.within_repose(&self.h, self.n, &self.lattice))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moore_matches_the_lattice_neighbour_order() {
        for n in [3, 4, 7] {
            let m = DuneModel::new(&DuneConfig {
                grid: n,
                ..DuneConfig::default()
            })
            .unwrap();
            for c in 0..n * n {
                let (x, row) = m.split(c);
                let mine: Vec<u32> = grid::moore(m.n, x, row)
                    .iter()
                    .map(|t| t.0 as u32)
                    .collect();
                assert_eq!(
                    mine,
                    m.lattice.neighbour_list(c).as_slice(),
                    "n {n} cell {c}"
                );
                for &(nb, nx, nrow) in &grid::moore(m.n, x, row) {
                    assert_eq!(nb, nrow + nx);
                    assert_eq!(m.split(nb), (nx, nrow));
                }
            }
        }
    }

    #[test]
    fn the_set_of_cells_with_sand_stays_exact() {
        let mut m = DuneModel::new(&DuneConfig {
            mode: Mode::Dune,
            grid: 9,
            quantity: 0.05,
            ..DuneConfig::default()
        })
        .unwrap();
        for _ in 0..400 {
            m.pick();
            let want: Vec<usize> = (0..81).filter(|&c| m.h[c] > 0).collect();
            let mut have: Vec<usize> = m.positive.iter().map(|&c| c as usize).collect();
            have.sort_unstable();
            assert_eq!(have, want);
            for (s, &c) in m.positive.iter().enumerate() {
                assert_eq!(m.slot[c as usize] as usize, s);
            }
        }
    }

    #[test]
    fn downwind_wraps_any_jump() {
        let m = DuneModel::new(&DuneConfig {
            grid: 5,
            ..DuneConfig::default()
        })
        .unwrap();
        for jump in [
            -1_000_000_007i64,
            -6,
            -5,
            -1,
            0,
            1,
            4,
            5,
            6,
            13,
            i64::MAX,
            i64::MIN,
        ] {
            for c in 0..25 {
                let x = (c % 5) as i64;
                let want = c - c % 5 + ((x as i128 + jump as i128).rem_euclid(5)) as usize;
                assert_eq!(m.downwind(c, jump), want, "{c} {jump}");
            }
        }
    }
}
