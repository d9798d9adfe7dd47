//! [`SandVolume`]: the sand volume as columns of automata ("bins" of sand, paper Sect. 2).
//!
//! Column `c` (a cell of the engine's [`crate::engine::lattice::Lattice`]) holds `height[c]`
//! automata stacked from the substrate (z = 0) upwards; each automaton is a `u16`
//! ([`Automaton`]): its grain-size class in the low byte, its porosity code in the high byte.
//! Storage is one flat array of `columns x capacity` automata plus a `u16` height per column,
//! i.e. `2 capacity / layers + 2 / layers` bytes per automaton (about 5-7 bytes with the
//! default head room). Automata are only ever moved between columns ([`SandVolume::pop`] then
//! [`SandVolume::push`]), never created or destroyed after [`SandVolume::new`].

/// One automaton: grain-size class (low byte) and porosity code (high byte).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Automaton(pub u16);

impl Automaton {
    /// Builds an automaton.
    #[inline]
    pub fn new(class: u8, porosity_code: u8) -> Self {
        Automaton(class as u16 | (porosity_code as u16) << 8)
    }
    /// Grain-size class index.
    #[inline]
    pub fn class(self) -> u8 {
        (self.0 & 0xff) as u8
    }
    /// Porosity code ([`super::compaction::porosity`]).
    #[inline]
    pub fn porosity_code(self) -> u8 {
        (self.0 >> 8) as u8
    }
    /// The same automaton with another porosity code.
    #[inline]
    pub fn with_porosity_code(self, code: u8) -> Self {
        Automaton::new(self.class(), code)
    }
}

/// Columns of automata.
#[derive(Clone, Debug)]
pub struct SandVolume {
    heights: Vec<u16>,
    cells: Vec<u16>,
    cap: usize,
}

impl SandVolume {
    /// An empty volume of `columns` columns of capacity `cap` automata.
    pub fn new(columns: usize, cap: usize) -> Self {
        SandVolume {
            heights: vec![0; columns],
            cells: vec![0; columns * cap],
            cap,
        }
    }

    /// Number of columns.
    pub fn columns(&self) -> usize {
        self.heights.len()
    }

    /// Capacity of a column, in automata.
    pub fn capacity(&self) -> usize {
        self.cap
    }

    /// Height of column `c`, in automata.
    #[inline(always)]
    pub fn height(&self, c: usize) -> usize {
        self.heights[c] as usize
    }

    /// All heights, row-major.
    pub fn heights(&self) -> &[u16] {
        &self.heights
    }

    /// True when column `c` is full.
    #[inline(always)]
    pub fn is_full(&self, c: usize) -> bool {
        self.heights[c] as usize >= self.cap
    }

    /// The automaton at level `z` of column `c` (z < height).
    #[inline(always)]
    pub fn get(&self, c: usize, z: usize) -> Automaton {
        debug_assert!(z < self.height(c));
        Automaton(self.cells[c * self.cap + z])
    }

    /// Replaces the automaton at level `z` of column `c`.
    #[inline(always)]
    pub fn set(&mut self, c: usize, z: usize, a: Automaton) {
        self.cells[c * self.cap + z] = a.0;
    }

    /// The top automaton of column `c`.
    #[inline(always)]
    pub fn top(&self, c: usize) -> Option<Automaton> {
        let h = self.height(c);
        (h > 0).then(|| self.get(c, h - 1))
    }

    /// Removes and returns the top automaton of column `c`.
    #[inline(always)]
    pub fn pop(&mut self, c: usize) -> Option<Automaton> {
        let h = self.height(c);
        if h == 0 {
            return None;
        }
        self.heights[c] -= 1;
        Some(Automaton(self.cells[c * self.cap + h - 1]))
    }

    /// Puts `a` on top of column `c`; false (and nothing changes) when the column is full.
    #[inline(always)]
    pub fn push(&mut self, c: usize, a: Automaton) -> bool {
        let h = self.height(c);
        if h >= self.cap {
            return false;
        }
        self.cells[c * self.cap + h] = a.0;
        self.heights[c] += 1;
        true
    }

    /// Total number of automata.
    pub fn automata(&self) -> u64 {
        self.heights.iter().map(|&h| h as u64).sum()
    }

    /// Number of automata of each class (`classes` classes).
    pub fn class_counts(&self, classes: usize) -> Vec<u64> {
        let mut n = vec![0u64; classes];
        for c in 0..self.columns() {
            for z in 0..self.height(c) {
                n[self.get(c, z).class() as usize] += 1;
            }
        }
        n
    }

    /// Bytes of memory held by the volume (heights and automata).
    pub fn memory_bytes(&self) -> usize {
        self.heights.capacity() * 2 + self.cells.capacity() * 2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn push_pop_round_trip_and_capacity() {
        let mut v = SandVolume::new(3, 2);
        assert!(v.push(1, Automaton::new(4, 200)));
        assert!(v.push(1, Automaton::new(5, 210)));
        assert!(!v.push(1, Automaton::new(6, 1)));
        assert_eq!(v.automata(), 2);
        let a = v.pop(1).unwrap();
        assert_eq!((a.class(), a.porosity_code()), (5, 210));
        assert_eq!(v.pop(0), None);
        assert_eq!(v.class_counts(8)[4], 1);
    }
}
