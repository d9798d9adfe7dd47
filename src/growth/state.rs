//! [`Growth`]: the state of a surface-growth run on a lattice.
//!
//! Cells are empty or occupied (burnt, solid, crystal). Every empty cell counts its occupied
//! neighbours `b`; the *surface* (interface) sites are the empty cells with `b >= 1`
//! (our reading of the paper's "surface sites"), kept in a [`Surface`] partitioned by `b`. Occupying a cell updates the
//! counts of its neighbours and the surface incrementally in `O(z)`.
//!
//! The clock ([`Growth::time`]) counts Monte Carlo timesteps as the paper does: one pick of a
//! surface site, accepted or not. The samplers that advance it live in [`crate::growth::sampler`].
//!
//! Memory: 4 bytes per cell (state and slot in one word), plus 4 bytes per surface site, plus 16 bytes per surface slot when a non-uniform weight is sampled exactly.

use thiserror::Error;

use crate::engine::lattice::Lattice;
use crate::engine::sumtree::SumTree;
use crate::engine::surface::{SlotListener, Surface};
use crate::growth::rule::{RuleError, Sticking, Weight};

/// State value of an occupied cell; empty cells hold their occupied-neighbour count.
pub const OCCUPIED: u8 = u8::MAX;

/// Bit position of the state in a cell word.
const B_SHIFT: u32 = 28;
/// Mask of the slot in a cell word.
const SLOT_MASK: u32 = (1 << B_SHIFT) - 1;
/// The state of an occupied cell in a cell word.
pub(crate) const OCC: u32 = 15;
/// The largest lattice a growth run supports: slots have 28 bits.
pub const MAX_GROWTH_CELLS: usize = SLOT_MASK as usize;

/// The state (`b`, or [`OCC`]) of a cell word.
#[inline(always)]
pub(crate) fn b_of(w: u32) -> u32 {
    w >> B_SHIFT
}

/// Errors while setting up or running growth.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GrowthError {
    /// The rule's neighbourhood size does not match the lattice.
    #[error("the sticking rule is for z = {rule} neighbours but the lattice has z = {lattice}")]
    NeighbourhoodMismatch {
        /// z of the rule.
        rule: usize,
        /// z of the lattice.
        lattice: usize,
    },
    /// A cell index is outside the lattice.
    #[error("cell {cell} is outside the lattice of {len} cells")]
    CellOutOfRange {
        /// The index.
        cell: usize,
        /// Number of cells.
        len: usize,
    },
    /// A rule parameter is invalid.
    #[error(transparent)]
    Rule(#[from] RuleError),
}

/// Drawing states of [`Growth::field_states`].
pub mod draw_state {
    /// An empty cell off the surface.
    pub const EMPTY: u8 = 0;
    /// A surface (interface) site.
    pub const SURFACE: u8 = 1;
    /// An occupied cell.
    pub const OCCUPIED: u8 = 2;
}

/// A growth run: lattice, rule, occupancy, surface and clock.
#[derive(Clone, Debug)]
pub struct Growth {
    pub(crate) lattice: Lattice,
    pub(crate) rule: Sticking,
    pub(crate) weight: Weight,
    /// Per cell, one word: the state in the top 4 bits ([`OCC`] for an occupied cell, else
    /// the number of occupied neighbours `b`) and the slot in `surface` in the low 28 bits
    /// (meaningful for surface sites only). State and slot share a cache line, which halves
    /// the memory traffic of an event.
    pub(crate) cells: Vec<u32>,
    pub(crate) surface: Surface,
    /// Per-slot weights `v`, kept only for exact sampling with a non-uniform weight.
    pub(crate) tree: Option<SumTree>,
    pub(crate) time: f64,
    /// The time of the next acceptance, drawn by the exact sampler before a pause.
    pub(crate) pending: Option<f64>,
    /// The natural log of the last acceptance time drawn past the largest `f64` (`inf`): a
    /// run paused at a finite limit before it, then continued without one, takes up the log
    /// clock from it.
    pub(crate) far_ln_time: f64,
    /// Natural log of the clock once it has passed the largest `f64` (unbounded exact runs
    /// only); `time` is then `inf`.
    pub(crate) log_clock: Option<f64>,
    /// Whether an unbounded exact run may go on past the largest `f64` on a log clock.
    pub(crate) log_clock_allowed: bool,
    pub(crate) accepted: u64,
    pub(crate) occupied: usize,
}

/// Per-cell words as the surface's listener: slot changes are written into the low bits.
trait CellWords: SlotListener {
    fn word(&self, cell: usize) -> u32;
    fn set_word(&mut self, cell: usize, w: u32);
}

/// Keeps the per-cell slots in step with the surface.
struct SlotSink<'a> {
    cells: &'a mut [u32],
}

/// The word of a surface site of class `b` at `slot`. Written whole (the class is known
/// where a slot changes), so that moving a far-away site is one store, with no load of its
/// old word (a cache miss on the critical path at low `n`, where the front is wide).
#[inline(always)]
fn site_word(b: usize, slot: usize) -> u32 {
    ((b as u32) << B_SHIFT) | slot as u32
}

impl SlotListener for SlotSink<'_> {
    #[inline(always)]
    fn slot_of(&self, cell: usize) -> usize {
        (self.cells[cell] & SLOT_MASK) as usize
    }
    #[inline(always)]
    fn swapped(&mut self, _a: usize, _cell_a: u32, b: usize, cell_b: u32, class: usize) {
        // (the promoted cell_a's word is written by the occupation, with its new class)
        self.cells[cell_b as usize] = site_word(class, b);
    }
    #[inline(always)]
    fn moved(&mut self, _from: usize, to: usize, cell: u32, class: usize) {
        self.cells[cell as usize] = site_word(class, to);
    }
    #[inline(always)]
    fn pushed(&mut self, cell: u32, slot: usize) {
        // (state 0: the caller raises it to 1)
        self.cells[cell as usize] = site_word(0, slot);
    }
    #[inline(always)]
    fn popped(&mut self, _slot: usize) {}
}

impl CellWords for SlotSink<'_> {
    #[inline(always)]
    fn word(&self, cell: usize) -> u32 {
        self.cells[cell]
    }
    #[inline(always)]
    fn set_word(&mut self, cell: usize, w: u32) {
        self.cells[cell] = w;
    }
}

/// Keeps the slots (through a [`SlotSink`]) and the per-slot weights in step with the surface.
struct WeightSink<'a> {
    slots: SlotSink<'a>,
    tree: &'a mut SumTree,
    lattice: &'a Lattice,
    weight: &'a Weight,
}

impl SlotListener for WeightSink<'_> {
    #[inline(always)]
    fn slot_of(&self, cell: usize) -> usize {
        self.slots.slot_of(cell)
    }
    #[inline]
    fn swapped(&mut self, a: usize, cell_a: u32, b: usize, cell_b: u32, class: usize) {
        self.slots.swapped(a, cell_a, b, cell_b, class);
        let (va, vb) = (self.tree.get(b), self.tree.get(a));
        self.tree.set(a, va);
        self.tree.set(b, vb);
    }
    #[inline]
    fn moved(&mut self, from: usize, to: usize, cell: u32, class: usize) {
        self.slots.moved(from, to, cell, class);
        self.tree.set(to, self.tree.get(from));
    }
    #[inline]
    fn pushed(&mut self, cell: u32, slot: usize) {
        self.slots.pushed(cell, slot);
        self.tree.reserve_slot(slot);
        // Checked over the whole lattice when the run was built.
        let v = self.weight.at(self.lattice, cell as usize).unwrap_or(0.0);
        self.tree.set(slot, v);
    }
    #[inline]
    fn popped(&mut self, slot: usize) {
        self.tree.set(slot, 0.0);
    }
}

impl CellWords for WeightSink<'_> {
    #[inline(always)]
    fn word(&self, cell: usize) -> u32 {
        self.slots.word(cell)
    }
    #[inline(always)]
    fn set_word(&mut self, cell: usize, w: u32) {
        self.slots.set_word(cell, w);
    }
}

/// The new words of the sites a [`Surface::partition`] moved.
struct Moves<'a>(&'a mut Vec<(u32, u32)>);

impl SlotListener for Moves<'_> {
    fn slot_of(&self, _cell: usize) -> usize {
        unreachable!("a partition reports moves only")
    }
    fn swapped(&mut self, _a: usize, _ca: u32, _b: usize, _cb: u32, _class: usize) {
        unreachable!("a partition reports moves only")
    }
    fn moved(&mut self, _from: usize, to: usize, cell: u32, class: usize) {
        self.0.push((cell, site_word(class, to)));
    }
    fn pushed(&mut self, _cell: u32, _slot: usize) {
        unreachable!("a partition reports moves only")
    }
    fn popped(&mut self, _slot: usize) {}
}

/// Occupies `cell` on a flat surface (no classes, no per-slot weights): the surface site
/// leaves (the last site takes its slot) and the neighbours' counts grow, with no branch that
/// depends on a neighbour's state (whether it is occupied, empty or on the surface, it takes
/// the same path: an empty one joins the surface, whose spare slots take the writes of the
/// others). The cell words are those [`occupy_cell`] writes; the slots are the flat surface's.
#[inline(always)]
fn occupy_flat(lattice: &Lattice, surface: &mut Surface, cells: &mut [u32], cell: usize) -> bool {
    let w = cells[cell];
    let s = b_of(w);
    if s == OCC {
        return false;
    }
    let (sites, mut len) = surface.flat_parts();
    if s >= 1 {
        // The last site fills the hole (itself when it is the one leaving).
        let slot = (w & SLOT_MASK) as usize;
        len -= 1;
        let moved = sites[len] as usize;
        sites[slot] = moved as u32;
        cells[moved] = (cells[moved] & !SLOT_MASK) | slot as u32;
    }
    cells[cell] = OCC << B_SHIFT;
    // b + 1 for an empty or surface neighbour, its word unchanged for an occupied one; an
    // empty one joins at the end (its slot written either way, into a spare slot if not).
    let mut raise = |n: usize| {
        let wn = cells[n];
        let sn = b_of(wn);
        let joins = sn == 0;
        let raised = wn + (((sn != OCC) as u32) << B_SHIFT);
        sites[len] = n as u32;
        cells[n] = std::hint::select_unpredictable(joins, site_word(1, len), raised);
        len += joins as usize;
    };
    match lattice.interior_offsets(cell) {
        Some(offsets) => {
            for &d in offsets {
                raise((cell as i64 + d) as usize);
            }
        }
        None => lattice.for_each_neighbour(cell, raise),
    }
    surface.set_flat_len(len);
    true
}

/// Occupies `cell`, updating the neighbours' counts and the surface; `sink` holds the cell
/// words and hears of every slot change.
#[inline(always)]
fn occupy_cell<L: CellWords>(
    lattice: &Lattice,
    surface: &mut Surface,
    cell: usize,
    sink: &mut L,
) -> bool {
    let w = sink.word(cell);
    let s = b_of(w);
    if s == OCC {
        return false;
    }
    if s >= 1 {
        surface.remove((w & SLOT_MASK) as usize, s as usize, sink);
    }
    sink.set_word(cell, OCC << B_SHIFT);
    // The neighbours in the order of `for_each_neighbour`; an interior cell's by their
    // offsets, in a loop with the body inlined.
    match lattice.interior_offsets(cell) {
        Some(offsets) => {
            for &d in offsets {
                raise_neighbour(surface, sink, (cell as i64 + d) as usize);
            }
        }
        None => lattice.for_each_neighbour(cell, |n| raise_neighbour(surface, sink, n)),
    }
    true
}

/// One neighbour of a cell just occupied (on a partitioned surface): an empty one joins the
/// surface in class 1, a surface one moves up a class, an occupied one is left as it is.
#[inline(always)]
fn raise_neighbour<L: CellWords>(surface: &mut Surface, sink: &mut L, n: usize) {
    let wn = sink.word(n);
    let sn = b_of(wn);
    if sn == OCC {
        return;
    }
    // Its slot after the surface update, and b raised by one.
    let slot = if sn == 0 {
        surface.insert_class1(n as u32, sink)
    } else {
        surface.promote((wn & SLOT_MASK) as usize, sn as usize, sink)
    };
    sink.set_word(n, site_word(sn as usize + 1, slot));
}

/// Asks the cache for the cell words of the rows above and below `cell` (`width` words
/// apart), where its neighbours' words lie, before they are read: on a wide front they are
/// not in cache, and the request overlaps their fetch with that of `cell`'s own word (2048 x
/// 2048 hexagonal flame at n = 2: about 5 % more events per second over 1e6 events, 10 % over
/// 3e6, where the front is wider). A hint only: nothing is read or written, and a cell on the
/// first or last row asks for nothing.
#[inline(always)]
fn prefetch_rows_around(cells: &[u32], cell: usize, width: usize) {
    #[cfg(target_arch = "x86_64")]
    if cell >= width && cell + width < cells.len() {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let base = cells.as_ptr();
        // SAFETY: both addresses lie inside `cells` (checked above), and a prefetch neither
        // reads nor writes memory as far as the program can tell.
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(base.add(cell - width).cast::<i8>());
            _mm_prefetch::<_MM_HINT_T0>(base.add(cell + width).cast::<i8>());
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (cells, cell, width);
}

/// `len` zero words, with every page of them mapped now: a zeroed allocation is mapped
/// lazily, and each first write to a page during the run would stall the sampler on a page
/// fault. One store per 4 KiB page, of a value the compiler cannot see is zero (so that the
/// store is made).
fn zeroed_words(len: usize) -> Vec<u32> {
    let mut v = vec![0u32; len];
    for w in v.iter_mut().step_by(1024) {
        *w = std::hint::black_box(0);
    }
    v
}

impl Growth {
    /// An empty lattice with the rule `p = v (b/z)^n`. With `per_site_weights` (used by the
    /// exact sampler when `weight` is not uniform) the surface keeps a sum tree of `v` from the
    /// start; without it, the exact sampler builds the tree on its first call.
    ///
    /// A custom weight is evaluated on every cell here, so that a value outside [0, 1] is
    /// reported before the run starts.
    pub fn new(
        lattice: Lattice,
        rule: Sticking,
        weight: Weight,
        per_site_weights: bool,
    ) -> Result<Self, GrowthError> {
        if rule.z() != lattice.z() {
            return Err(GrowthError::NeighbourhoodMismatch {
                rule: rule.z(),
                lattice: lattice.z(),
            });
        }
        if let Weight::Custom { .. } = weight {
            for c in 0..lattice.len() {
                weight.at(&lattice, c)?;
            }
        }
        let n = lattice.len();
        if n > MAX_GROWTH_CELLS {
            return Err(GrowthError::CellOutOfRange {
                cell: n,
                len: MAX_GROWTH_CELLS,
            });
        }
        let z = lattice.z();
        let tree = (per_site_weights && !weight.is_uniform()).then(|| SumTree::new(1024));
        Ok(Growth {
            lattice,
            rule,
            weight,
            cells: zeroed_words(n),
            surface: Surface::new(z),
            tree,
            time: 0.0,
            pending: None,
            far_ln_time: f64::NAN,
            log_clock: None,
            log_clock_allowed: false,
            accepted: 0,
            occupied: 0,
        })
    }

    /// The lattice.
    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }
    /// The sticking rule.
    pub fn rule(&self) -> &Sticking {
        &self.rule
    }
    /// The direction weight.
    pub fn weight(&self) -> &Weight {
        &self.weight
    }
    /// The surface sites. After the exact sampler ran at `n = 0` the surface is flat
    /// ([`Surface::is_flat`]): its sites are all in the segment of class 1, and a site's `b`
    /// is [`Growth::occupied_neighbours`].
    pub fn surface(&self) -> &Surface {
        &self.surface
    }
    /// Monte Carlo timesteps so far (picks, accepted or not; CA updates for the CA). An
    /// `f64`: exact integers below `2^53`; beyond, a relative precision of `1e-16`, which
    /// large `n` needs (a pick succeeds with probability as low as `(1/z)^n`).
    pub fn time(&self) -> f64 {
        self.time
    }
    /// Lets the exact sampler, run with no clock limit (`limit = inf`), go on past the largest
    /// `f64` on a log clock ([`Growth::log10_time`]) instead of stopping with
    /// [`ClockOverflow`](crate::growth::sampler::Outcome::ClockOverflow). Off by default.
    pub fn allow_log_clock(&mut self, on: bool) {
        self.log_clock_allowed = on;
    }
    /// The base-10 log of the clock, finite however far an unbounded run took it (past the
    /// largest `f64`, where [`Growth::time`] is `inf`); `-inf` at time 0.
    pub fn log10_time(&self) -> f64 {
        match self.log_clock {
            Some(l) => l / std::f64::consts::LN_10,
            None => self.time.log10(),
        }
    }
    /// True while [`Growth::time`] is an exact whole number of timesteps (at most `2^53`).
    pub fn time_exact(&self) -> bool {
        self.log_clock.is_none() && self.time <= 9_007_199_254_740_992.0
    }
    /// Accepted events (cells added by the samplers, not counting the initial shape).
    pub fn accepted(&self) -> u64 {
        self.accepted
    }
    /// Occupied cells.
    pub fn occupied(&self) -> usize {
        self.occupied
    }
    /// True when `cell` is occupied.
    #[inline]
    pub fn is_occupied(&self, cell: usize) -> bool {
        b_of(self.cells[cell]) == OCC
    }

    /// [`OCCUPIED`] for an occupied cell, else its number of occupied neighbours.
    #[inline]
    pub fn state(&self, cell: usize) -> u8 {
        match b_of(self.cells[cell]) {
            OCC => OCCUPIED,
            b => b as u8,
        }
    }
    /// Occupied neighbours of an empty cell (`None` for an occupied one).
    pub fn occupied_neighbours(&self, cell: usize) -> Option<usize> {
        let s = self.state(cell);
        (s != OCCUPIED).then_some(s as usize)
    }

    /// Occupies `cell` (no effect if it already is), updating the surface.
    pub fn occupy(&mut self, cell: usize) -> Result<(), GrowthError> {
        if cell >= self.cells.len() {
            return Err(GrowthError::CellOutOfRange {
                cell,
                len: self.cells.len(),
            });
        }
        self.pending = None;
        self.far_ln_time = f64::NAN;
        self.occupy_unchecked(cell);
        Ok(())
    }

    /// Occupies every cell for which `inside(x, y)` holds, given physical positions.
    pub fn occupy_where(&mut self, mut inside: impl FnMut(f64, f64) -> bool) {
        for c in 0..self.lattice.len() {
            let (x, y) = self.lattice.position(c);
            if inside(x, y) {
                self.pending = None;
                self.far_ln_time = f64::NAN;
                self.occupy_unchecked(c);
            }
        }
    }

    #[inline]
    pub(crate) fn occupy_unchecked(&mut self, cell: usize) {
        prefetch_rows_around(&self.cells, cell, self.lattice.width());
        let added = match self.tree.as_mut() {
            None if self.surface.is_flat() => {
                occupy_flat(&self.lattice, &mut self.surface, &mut self.cells, cell)
            }
            None => occupy_cell(
                &self.lattice,
                &mut self.surface,
                cell,
                &mut SlotSink {
                    cells: &mut self.cells,
                },
            ),
            Some(tree) => occupy_cell(
                &self.lattice,
                &mut self.surface,
                cell,
                &mut WeightSink {
                    slots: SlotSink {
                        cells: &mut self.cells,
                    },
                    tree,
                    lattice: &self.lattice,
                    weight: &self.weight,
                },
            ),
        };
        self.occupied += added as usize;
    }

    /// Stops keeping the surface's classes (see [`Surface::flatten`]), for a sampler to which
    /// every site weighs the same. Not with per-slot weights, whose tree follows the slots.
    pub(crate) fn flatten_surface(&mut self) {
        debug_assert!(self.tree.is_none());
        self.surface.flatten();
    }

    /// Sorts a flat surface back into its classes (see [`Surface::partition`]), for a sampler
    /// that needs them.
    pub(crate) fn partition_surface(&mut self) {
        let cells = &self.cells;
        let class_of = |c: u32| b_of(cells[c as usize]) as usize;
        let mut words: Vec<(u32, u32)> = Vec::new();
        self.surface.partition(class_of, &mut Moves(&mut words));
        for (cell, w) in words {
            self.cells[cell as usize] = w;
        }
    }

    /// Builds the per-slot weight tree from the current surface (the exact sampler calls this
    /// when a non-uniform weight was set up without `per_site_weights`).
    pub(crate) fn build_weight_tree(&mut self) {
        let mut t = SumTree::new(self.surface.len().max(1024));
        for (slot, &c) in self.surface.sites().iter().enumerate() {
            t.set(
                slot,
                self.weight.at(&self.lattice, c as usize).unwrap_or(0.0),
            );
        }
        self.tree = Some(t);
    }

    /// The sticking probability `p = v (b/z)^n` of a surface site (Eq. 4 and 5).
    #[inline]
    pub fn probability(&self, cell: usize) -> f64 {
        let s = self.state(cell);
        if s == OCCUPIED || s == 0 {
            return 0.0;
        }
        let v = self.weight.at(&self.lattice, cell).unwrap_or(0.0);
        v * self.rule.p(s as usize)
    }

    /// The state of every cell for drawing: see [`draw_state`].
    pub fn field_states(&self) -> Vec<u8> {
        self.cells
            .iter()
            .map(|&w| match b_of(w) {
                OCC => draw_state::OCCUPIED,
                0 => draw_state::EMPTY,
                _ => draw_state::SURFACE,
            })
            .collect()
    }

    /// Bytes of memory held by the run (lattice tables, per-cell state, surface).
    pub fn memory_bytes(&self) -> usize {
        self.cells.capacity() * 4
            + self.surface.sites().len() * 4
            + self.tree.as_ref().map_or(0, |t| t.capacity() * 16)
    }

    /// Checks every invariant against a recount from scratch (for tests): neighbour counts,
    /// surface membership and classes, slot table, occupied count, per-slot weights.
    pub fn check_invariants(&self) -> Result<(), String> {
        let mut occ = 0;
        let mut on_surface = 0;
        for c in 0..self.lattice.len() {
            if self.is_occupied(c) {
                occ += 1;
                continue;
            }
            let b = self
                .lattice
                .neighbours(c)
                .filter(|&n| self.is_occupied(n))
                .count();
            if b != self.state(c) as usize {
                return Err(format!(
                    "cell {c}: stored b = {}, counted {b}",
                    self.state(c)
                ));
            }
            if b >= 1 {
                on_surface += 1;
                let slot = (self.cells[c] & SLOT_MASK) as usize;
                if self.surface.site(slot) as usize != c {
                    return Err(format!("cell {c}: slot {slot} holds another site"));
                }
                if !self.surface.is_flat() && self.surface.class_of_slot(slot) != b {
                    return Err(format!("cell {c}: in the wrong class"));
                }
                if let Some(t) = &self.tree {
                    let v = self.weight.at(&self.lattice, c).unwrap_or(0.0);
                    if t.get(slot) != v {
                        return Err(format!("cell {c}: tree weight {} != {v}", t.get(slot)));
                    }
                }
            }
        }
        if occ != self.occupied {
            return Err(format!("occupied {} != counted {occ}", self.occupied));
        }
        if on_surface != self.surface.len() || !self.surface.check() {
            return Err(format!(
                "surface holds {} sites, counted {on_surface}",
                self.surface.len()
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::lattice::{Boundary, Neighbourhood};

    #[test]
    fn occupying_updates_counts_and_surface() {
        for hood in [
            Neighbourhood::Square4,
            Neighbourhood::Square8,
            Neighbourhood::Hex,
        ] {
            let l = Lattice::new(hood, 9, 8, Boundary::TORUS).unwrap();
            let rule = Sticking::new(2.0, hood.z()).unwrap();
            let mut g = Growth::new(l, rule, Weight::Isotropic, false).unwrap();
            let c = g.lattice().index(4, 4);
            g.occupy(c).unwrap();
            assert_eq!(g.surface().len(), hood.z());
            assert_eq!(g.surface().class_len(1), hood.z());
            let mut x: u64 = 99;
            for _ in 0..60 {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                g.occupy(((x >> 33) % 72) as usize).unwrap();
                g.check_invariants().unwrap();
            }
            // Fill the torus: the surface empties.
            for c in 0..72 {
                g.occupy(c).unwrap();
            }
            assert_eq!(g.occupied(), 72);
            assert!(g.surface().is_empty());
            g.check_invariants().unwrap();
        }
    }

    #[test]
    fn memory_stays_under_64_bytes_per_cell() {
        // The budget for the flame scene: 64 bytes per cell. One word per cell plus
        // the surface array.
        let l = Lattice::new(Neighbourhood::Hex, 256, 256, Boundary::TORUS).unwrap();
        let mut g =
            Growth::new(l, Sticking::new(2.0, 6).unwrap(), Weight::Isotropic, false).unwrap();
        g.occupy_where(|x, y| (x - 128.0).abs() < 40.0 && (y - 110.0).abs() < 40.0);
        let per_cell = g.memory_bytes() as f64 / (256.0 * 256.0);
        assert!(per_cell < 5.0, "{per_cell} bytes per cell");
    }

    #[test]
    fn per_site_weights_follow_swaps() {
        let l = Lattice::new(Neighbourhood::Hex, 12, 10, Boundary::WALLS).unwrap();
        let rule = Sticking::new(2.0, 6).unwrap();
        let w = Weight::Axes { centre: (6.0, 4.0) };
        let mut g = Growth::new(l, rule, w, true).unwrap();
        assert!(g.tree.is_some());
        for c in [50, 51, 63, 62, 40, 75, 0, 119] {
            g.occupy(c).unwrap();
            g.check_invariants().unwrap();
        }
    }

    #[test]
    fn out_of_range_cell_and_mismatched_rule_are_errors() {
        let l = Lattice::new(Neighbourhood::Hex, 4, 4, Boundary::TORUS).unwrap();
        let e = Growth::new(
            l.clone(),
            Sticking::new(1.0, 4).unwrap(),
            Weight::Isotropic,
            false,
        )
        .unwrap_err();
        assert!(e.to_string().contains("z = 4"));
        let mut g =
            Growth::new(l, Sticking::new(1.0, 6).unwrap(), Weight::Isotropic, false).unwrap();
        assert!(g.occupy(16).is_err());
    }
}
