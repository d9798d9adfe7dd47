//! [`Surface`]: the set of surface sites, partitioned by their number of occupied neighbours.
//!
//! All surface sites sit in one array, grouped into contiguous segments by class `b` (the
//! number of occupied neighbours, 1..=z), highest class first:
//!
//! ```text
//! [ class z | class z-1 | ... | class 2 | class 1 ]
//! ```
//!
//! A uniform pick over all surface sites (the rejection sampler) is one random index; a pick
//! within a class (the exact sampler) is one random index within its segment. Every update
//! the growth rules need is `O(1)` or `O(z)`: a new site joins class 1 at the end; a site
//! whose `b` grows by one swaps with the first element of its segment and the boundary moves
//! past it; a site that leaves the surface leaves a hole that the last site of each segment fills
//! in turn down to the end.
//!
//! A sampler for which every surface site has the same weight (the exact sampler at `n = 0`)
//! has no use for the classes: it may [flatten](Surface::flatten) the surface, which then keeps
//! every site in one segment (as if of class 1) and changes no slot when a site's `b` grows; a
//! site leaving it swaps with the last. [`Surface::partition`] sorts a flat surface back into
//! its classes for a sampler that needs them.

/// Largest supported neighbourhood size.
pub const MAX_Z: usize = 8;

/// Spare slots kept past the last site, which a branch-free update may write through (it
/// adds at most [`MAX_Z`] sites at a time; see [`Surface::flat_parts`]).
pub const SPARE: usize = MAX_Z + 1;

/// Surface sites grouped by class, with each site's slot recorded in a per-cell table.
#[derive(Clone, Debug)]
pub struct Surface {
    /// The sites in slots `0..len`, then at least [`SPARE`] spare slots of any content.
    sites: Vec<u32>,
    /// `end[b]`: one past the last slot of class `b`; class `b` is `end[b+1]..end[b]`,
    /// with `end[z + 1] = 0` and `end[0] = end[1] = len`. Flat: `end[b] = 0` for `b >= 2`.
    end: [usize; MAX_Z + 2],
    z: usize,
    /// True when the classes are not kept (every site in the segment of class 1).
    flat: bool,
}

/// Told of every change of slots, so that the owner can keep its per-cell slot table (and
/// any per-slot weights) in step.
pub trait SlotListener {
    /// The slot of surface site `cell`.
    fn slot_of(&self, cell: usize) -> usize;
    /// Slots `a` and `b` of class `class` exchanged their sites, for a promotion
    /// ([`Surface::promote`]): `cell_a`, the site promoted, is now at `a` (and leaves the
    /// class for the next: the caller records its new class and slot), `cell_b` at `b`
    /// (still of class `class`).
    fn swapped(&mut self, a: usize, cell_a: u32, b: usize, cell_b: u32, class: usize);
    /// `cell`, of class `class`, moved from slot `from` to slot `to` (`from` is left as a
    /// hole, soon filled or popped).
    fn moved(&mut self, from: usize, to: usize, cell: u32, class: usize);
    /// `cell` (not on the surface until now) was appended at `slot`, joining class 1.
    fn pushed(&mut self, cell: u32, slot: usize);
    /// The last slot, `slot`, was removed.
    fn popped(&mut self, slot: usize);
}

impl Surface {
    /// An empty surface for a neighbourhood of `z` cells.
    pub fn new(z: usize) -> Self {
        assert!((1..=MAX_Z).contains(&z));
        Surface {
            sites: vec![0; SPARE],
            end: [0; MAX_Z + 2],
            z,
            flat: false,
        }
    }

    /// Number of surface sites.
    #[inline]
    pub fn len(&self) -> usize {
        self.end[0]
    }

    /// True when there is no surface site.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.end[0] == 0
    }

    /// The site at `slot`.
    #[inline]
    pub fn site(&self, slot: usize) -> u32 {
        debug_assert!(slot < self.end[0]);
        self.sites[slot]
    }

    /// All sites (in slot order).
    pub fn sites(&self) -> &[u32] {
        &self.sites[..self.end[0]]
    }

    /// True when the classes are not kept ([`Surface::flatten`]).
    #[inline]
    pub fn is_flat(&self) -> bool {
        self.flat
    }

    /// The slots of class `b` (on a flat surface: every slot for `b = 1`, none for the others).
    #[inline]
    pub fn class_range(&self, b: usize) -> std::ops::Range<usize> {
        self.end[b + 1]..self.end[b]
    }

    /// Number of sites in class `b` (on a flat surface: every site for `b = 1`).
    #[inline]
    pub fn class_len(&self, b: usize) -> usize {
        self.end[b] - self.end[b + 1]
    }

    /// The class of the site at `slot` (1 on a flat surface).
    pub fn class_of_slot(&self, slot: usize) -> usize {
        (1..=self.z)
            .find(|&b| self.class_range(b).contains(&slot))
            .expect("slot in range")
    }

    /// Stops keeping the classes: every site joins the segment of class 1, in its slot.
    /// Costs nothing; [`Surface::partition`] undoes it.
    pub fn flatten(&mut self) {
        self.flat = true;
        self.end[2..].fill(0);
    }

    /// Sorts a flat surface back into its classes (`class_of(cell)` gives a site's `b`),
    /// keeping the slot order within each class, and tells `l` of every site's new slot
    /// (through [`SlotListener::moved`]). `O(len)`; nothing to do on a partitioned surface.
    pub fn partition(&mut self, class_of: impl Fn(u32) -> usize, l: &mut impl SlotListener) {
        if !self.flat {
            return;
        }
        let len = self.end[0];
        let mut count = [0usize; MAX_Z + 2];
        for &c in &self.sites[..len] {
            count[class_of(c)] += 1;
        }
        // Class z first: end[b] = sites of class >= b.
        self.end = [0; MAX_Z + 2];
        for b in (1..=self.z).rev() {
            self.end[b] = self.end[b + 1] + count[b];
        }
        self.end[0] = len;
        // next[b]: the next free slot of class b, from its start end[b + 1].
        let mut next: [usize; MAX_Z + 2] = [0; MAX_Z + 2];
        next[1..=self.z].copy_from_slice(&self.end[2..=self.z + 1]);
        let old: Vec<u32> = self.sites[..len].to_vec();
        for (from, &c) in old.iter().enumerate() {
            let b = class_of(c);
            let to = next[b];
            next[b] += 1;
            self.sites[to] = c;
            l.moved(from, to, c, b);
        }
        self.flat = false;
    }

    /// The slot array (the sites, then at least [`SPARE`] spare slots) and the number of
    /// sites, of a flat surface: its owner removes a site by moving the last into its slot,
    /// adds sites by writing them at the end (in the spare slots), and sets the new number
    /// with [`Surface::set_flat_len`].
    #[inline(always)]
    pub fn flat_parts(&mut self) -> (&mut [u32], usize) {
        debug_assert!(self.flat);
        (&mut self.sites, self.end[0])
    }

    /// Sets the number of sites of a flat surface after [`Surface::flat_parts`] (at most
    /// [`SPARE`] more than before), and restores the spare slots.
    #[inline(always)]
    pub fn set_flat_len(&mut self, len: usize) {
        debug_assert!(self.flat && len <= self.end[0] + SPARE);
        self.end[0] = len;
        self.end[1] = len;
        self.restore_spare();
    }

    /// Grows the slot array so that at least [`SPARE`] spare slots follow the last site.
    #[inline(always)]
    fn restore_spare(&mut self) {
        if self.sites.len() < self.end[0] + SPARE {
            self.grow_spare();
        }
    }

    #[cold]
    #[inline(never)]
    fn grow_spare(&mut self) {
        let want = (self.end[0] + SPARE).max(2 * self.sites.len());
        self.sites.resize(want, 0);
    }

    /// Adds `cell` as a class-1 site; returns its slot.
    #[inline]
    pub fn insert_class1(&mut self, cell: u32, l: &mut impl SlotListener) -> usize {
        let slot = self.end[0];
        self.sites[slot] = cell;
        self.end[1] = slot + 1;
        self.end[0] = slot + 1;
        self.restore_spare();
        l.pushed(cell, slot);
        slot
    }

    /// Moves the site at `slot`, of class `b`, into class `b + 1` (partitioned surface);
    /// returns its new slot.
    #[inline]
    pub fn promote(&mut self, slot: usize, b: usize, l: &mut impl SlotListener) -> usize {
        debug_assert!(!self.flat && b < self.z && self.class_range(b).contains(&slot));
        let first = self.end[b + 1];
        if first != slot {
            self.sites.swap(first, slot);
            l.swapped(first, self.sites[first], slot, self.sites[slot], b);
        }
        self.end[b + 1] += 1;
        first
    }

    /// Removes the site at `slot`, of class `b`, from the surface (partitioned surface).
    #[inline]
    pub fn remove(&mut self, mut slot: usize, b: usize, l: &mut impl SlotListener) {
        debug_assert!(!self.flat && self.class_range(b).contains(&slot));
        // Walk the hole down to the end: in each class, its last element fills the hole
        // (the site order a swap with the removed site would give, without rewriting it).
        for c in (1..=b).rev() {
            let last = self.end[c] - 1;
            if last != slot {
                let moved = self.sites[last];
                self.sites[slot] = moved;
                l.moved(last, slot, moved, c);
            }
            self.end[c] -= 1;
            slot = last;
        }
        self.end[0] = self.end[1];
        l.popped(slot);
    }

    /// Checks the partition invariants (for tests): segments ordered and covering the sites,
    /// the spare slots in place; a flat surface has one segment.
    pub fn check(&self) -> bool {
        let ok_order = (1..=self.z).all(|b| self.end[b + 1] <= self.end[b]);
        let ok_flat = !self.flat || self.end[2..].iter().all(|&e| e == 0);
        ok_order
            && ok_flat
            && self.end[1] == self.end[0]
            && self.sites.len() >= self.end[0] + SPARE
            && self.end[self.z + 1] == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Slots(Vec<usize>);
    impl SlotListener for Slots {
        fn slot_of(&self, cell: usize) -> usize {
            self.0[cell]
        }
        fn swapped(&mut self, a: usize, cell_a: u32, b: usize, cell_b: u32, _class: usize) {
            self.0[cell_a as usize] = a;
            self.0[cell_b as usize] = b;
        }
        fn moved(&mut self, _from: usize, to: usize, cell: u32, _class: usize) {
            self.0[cell as usize] = to;
        }
        fn pushed(&mut self, cell: u32, slot: usize) {
            self.0[cell as usize] = slot;
        }
        fn popped(&mut self, _slot: usize) {}
    }

    #[test]
    fn partition_keeps_classes_and_slots_consistent() {
        let z = 6;
        let mut s = Surface::new(z);
        let mut slots = Slots(vec![usize::MAX; 64]);
        let mut class = vec![0usize; 64];
        // Insert, promote and remove in a fixed pseudo-random order; check after each op.
        let mut x: u64 = 12345;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for _ in 0..5000 {
            let c = (next() % 64) as usize;
            match class[c] {
                0 => {
                    s.insert_class1(c as u32, &mut slots);
                    class[c] = 1;
                }
                b if b < z && next() % 3 != 0 => {
                    s.promote(slots.0[c], b, &mut slots);
                    class[c] = b + 1;
                }
                b => {
                    s.remove(slots.0[c], b, &mut slots);
                    class[c] = 0;
                }
            }
            assert!(s.check());
            assert_consistent(&s, &slots, &class);
        }
    }

    /// Every site of class `class[cell] > 0` is at the slot the listener recorded, in that
    /// class; the counts match.
    fn assert_consistent(s: &Surface, slots: &Slots, class: &[usize]) {
        for (cell, &b) in class.iter().enumerate() {
            if b > 0 {
                let slot = slots.0[cell];
                assert_eq!(s.site(slot) as usize, cell);
                assert_eq!(s.class_of_slot(slot), b, "cell {cell}");
            }
        }
        assert_eq!(s.len(), class.iter().filter(|&&b| b > 0).count());
        for b in 1..=s.z {
            assert_eq!(s.class_len(b), class.iter().filter(|&&k| k == b).count());
        }
    }

    #[test]
    fn flatten_then_partition_restores_the_classes() {
        let z = 6;
        let mut s = Surface::new(z);
        let mut slots = Slots(vec![usize::MAX; 200]);
        let mut class = vec![0usize; 200];
        for (c, k) in class.iter_mut().enumerate() {
            s.insert_class1(c as u32, &mut slots);
            *k = 1;
            // Raise some sites by a cell-dependent number of classes.
            for _ in 0..(c * 7) % z {
                s.promote(slots.0[c], *k, &mut slots);
                *k += 1;
            }
        }
        let before: Vec<u32> = s.sites().to_vec();
        s.flatten();
        assert!(s.is_flat() && s.check());
        // One segment, the same slots.
        assert_eq!(s.class_len(1), 200);
        assert!((2..=z).all(|b| s.class_len(b) == 0));
        assert_eq!(s.sites(), &before[..]);
        s.partition(|c| class[c as usize], &mut slots);
        assert!(!s.is_flat() && s.check());
        assert_consistent(&s, &slots, &class);
        for b in 1..=z {
            // Within a class the flat order is kept.
            let r: Vec<u32> = s.sites()[s.class_range(b)].to_vec();
            let want: Vec<u32> = before
                .iter()
                .copied()
                .filter(|&c| class[c as usize] == b)
                .collect();
            assert_eq!(r, want);
        }
    }
}
