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

/// Largest supported neighbourhood size.
pub const MAX_Z: usize = 8;

/// Surface sites grouped by class, with each site's slot recorded in a per-cell table.
#[derive(Clone, Debug)]
pub struct Surface {
    sites: Vec<u32>,
    /// `end[b]`: one past the last slot of class `b`; class `b` is `end[b+1]..end[b]`,
    /// with `end[z + 1] = 0` and `end[0] = end[1] = sites.len()`.
    end: [usize; MAX_Z + 2],
    z: usize,
}

/// Told of every change of slots, so that the owner can keep its per-cell slot table (and
/// any per-slot weights) in step.
pub trait SlotListener {
    /// The slot of surface site `cell`.
    fn slot_of(&self, cell: usize) -> usize;
    /// Slots `a` and `b` of class `class` exchanged their sites: `cell_a` is now at `a`,
    /// `cell_b` at `b` (both still of class `class`).
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
            sites: Vec::new(),
            end: [0; MAX_Z + 2],
            z,
        }
    }

    /// Number of surface sites.
    #[inline]
    pub fn len(&self) -> usize {
        self.sites.len()
    }

    /// True when there is no surface site.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.sites.is_empty()
    }

    /// The site at `slot`.
    #[inline]
    pub fn site(&self, slot: usize) -> u32 {
        self.sites[slot]
    }

    /// All sites (in slot order).
    pub fn sites(&self) -> &[u32] {
        &self.sites
    }

    /// The slots of class `b`.
    #[inline]
    pub fn class_range(&self, b: usize) -> std::ops::Range<usize> {
        self.end[b + 1]..self.end[b]
    }

    /// Number of sites in class `b`.
    #[inline]
    pub fn class_len(&self, b: usize) -> usize {
        self.end[b] - self.end[b + 1]
    }

    /// The class of the site at `slot`.
    pub fn class_of_slot(&self, slot: usize) -> usize {
        (1..=self.z)
            .find(|&b| self.class_range(b).contains(&slot))
            .expect("slot in range")
    }

    /// Adds `cell` as a class-1 site.
    #[inline]
    pub fn insert_class1(&mut self, cell: u32, l: &mut impl SlotListener) {
        self.sites.push(cell);
        let n = self.sites.len();
        self.end[1] = n;
        self.end[0] = n;
        l.pushed(cell, n - 1);
    }

    /// Moves the site at `slot`, of class `b`, into class `b + 1`.
    #[inline]
    pub fn promote(&mut self, slot: usize, b: usize, l: &mut impl SlotListener) {
        debug_assert!(b < self.z && self.class_range(b).contains(&slot));
        let first = self.end[b + 1];
        if first != slot {
            self.sites.swap(first, slot);
            l.swapped(first, self.sites[first], slot, self.sites[slot], b);
        }
        self.end[b + 1] += 1;
    }

    /// Removes the site at `slot`, of class `b`, from the surface.
    #[inline]
    pub fn remove(&mut self, mut slot: usize, b: usize, l: &mut impl SlotListener) {
        debug_assert!(self.class_range(b).contains(&slot));
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
        self.sites.pop();
        self.end[0] = self.sites.len();
        l.popped(slot);
    }

    /// Checks the partition invariants (for tests): segments ordered and covering the array.
    pub fn check(&self) -> bool {
        let ok_order = (1..=self.z).all(|b| self.end[b + 1] <= self.end[b]);
        ok_order && self.end[1] == self.sites.len() && self.end[self.z + 1] == 0
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
            for (cell, &b) in class.iter().enumerate() {
                if b > 0 {
                    let slot = slots.0[cell];
                    assert_eq!(s.site(slot) as usize, cell);
                    assert_eq!(s.class_of_slot(slot), b);
                }
            }
            assert_eq!(s.len(), class.iter().filter(|&&b| b > 0).count());
            for b in 1..=z {
                assert_eq!(s.class_len(b), class.iter().filter(|&&k| k == b).count());
            }
        }
    }
}
