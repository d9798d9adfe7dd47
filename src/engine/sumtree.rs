//! [`SumTree`]: a binary tree of partial sums over slots, for weighted selection.
//!
//! Each internal node holds the sum of its two children and is recomputed from them on every
//! update (never by adding differences), so rounding errors do not accumulate however long
//! the run. Update, range sum and weighted selection cost `O(log capacity)`.

/// Partial sums over `capacity` slots (a power of two), all starting at 0.
#[derive(Clone, Debug)]
pub struct SumTree {
    cap: usize,
    /// `node[1]` is the root, leaves are `node[cap..2 cap]`.
    node: Vec<f64>,
}

impl SumTree {
    /// A tree with room for at least `len` slots.
    pub fn new(len: usize) -> Self {
        let cap = len.max(1).next_power_of_two();
        SumTree {
            cap,
            node: vec![0.0; 2 * cap],
        }
    }

    /// Number of slots.
    pub fn capacity(&self) -> usize {
        self.cap
    }

    /// Makes room for slot `i`, doubling as needed.
    pub fn reserve_slot(&mut self, i: usize) {
        if i < self.cap {
            return;
        }
        let mut t = SumTree::new(i + 1);
        for k in 0..self.cap {
            t.node[t.cap + k] = self.node[self.cap + k];
        }
        for k in (1..t.cap).rev() {
            t.node[k] = t.node[2 * k] + t.node[2 * k + 1];
        }
        *self = t;
    }

    /// The value of slot `i`.
    #[inline]
    pub fn get(&self, i: usize) -> f64 {
        self.node[self.cap + i]
    }

    /// Sets slot `i` to `v` (`v >= 0`).
    #[inline]
    pub fn set(&mut self, i: usize, v: f64) {
        let mut k = self.cap + i;
        self.node[k] = v;
        k /= 2;
        while k >= 1 {
            self.node[k] = self.node[2 * k] + self.node[2 * k + 1];
            k /= 2;
        }
    }

    /// Sum of all slots.
    #[inline]
    pub fn total(&self) -> f64 {
        self.node[1]
    }

    /// Sum of slots `0..i`.
    pub fn prefix(&self, i: usize) -> f64 {
        if i >= self.cap {
            return self.total();
        }
        // Walk from the leaf up, adding left siblings.
        let mut s = 0.0;
        let mut k = self.cap + i;
        while k > 1 {
            if k % 2 == 1 {
                s += self.node[k - 1];
            }
            k /= 2;
        }
        s
    }

    /// Sum of slots `lo..hi`.
    pub fn range_sum(&self, lo: usize, hi: usize) -> f64 {
        if hi <= lo {
            return 0.0;
        }
        // Bottom-up range sum (exact for the covered nodes).
        let mut s = 0.0;
        let mut l = lo + self.cap;
        let mut r = hi + self.cap;
        while l < r {
            if l % 2 == 1 {
                s += self.node[l];
                l += 1;
            }
            if r % 2 == 1 {
                r -= 1;
                s += self.node[r];
            }
            l /= 2;
            r /= 2;
        }
        s
    }

    /// A slot in `lo..hi` chosen with probability proportional to its value, given
    /// `u` uniform in `[0, 1)`. Returns `None` when the range sums to zero.
    pub fn select_in(&self, lo: usize, hi: usize, u: f64) -> Option<usize> {
        let w = self.range_sum(lo, hi);
        if w <= 0.0 || hi <= lo {
            return None;
        }
        let mut target = self.prefix(lo) + u * w;
        let mut k = 1;
        while k < self.cap {
            let left = self.node[2 * k];
            if target < left {
                k *= 2;
            } else {
                target -= left;
                k = 2 * k + 1;
            }
        }
        let mut i = (k - self.cap).clamp(lo, hi - 1);
        // Rounding can land on a zero slot at a boundary: step to the nearest positive one.
        if self.get(i) <= 0.0 {
            i = (i..hi)
                .find(|&j| self.get(j) > 0.0)
                .or_else(|| (lo..i).rev().find(|&j| self.get(j) > 0.0))?;
        }
        Some(i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_and_prefixes() {
        let mut t = SumTree::new(5);
        for (i, v) in [1.0, 2.0, 0.0, 4.0, 8.0].into_iter().enumerate() {
            t.set(i, v);
        }
        assert_eq!(t.total(), 15.0);
        assert_eq!(t.prefix(3), 3.0);
        assert_eq!(t.range_sum(1, 4), 6.0);
        assert_eq!(t.range_sum(3, 3), 0.0);
        t.reserve_slot(20);
        assert_eq!(t.total(), 15.0);
        assert_eq!(t.get(4), 8.0);
        t.set(20, 1.0);
        assert_eq!(t.range_sum(4, 21), 9.0);
    }

    #[test]
    fn selection_never_picks_zero_slots_or_leaves_range() {
        let mut t = SumTree::new(8);
        for (i, v) in [0.0, 1.0, 0.0, 0.0, 3.0, 0.0, 0.0, 2.0]
            .into_iter()
            .enumerate()
        {
            t.set(i, v);
        }
        for k in 0..1000 {
            let u = k as f64 / 1000.0;
            let i = t.select_in(2, 7, u).unwrap();
            assert_eq!(i, 4);
            let j = t.select_in(0, 8, u).unwrap();
            assert!([1, 4, 7].contains(&j));
        }
        assert_eq!(t.select_in(5, 7, 0.5), None);
    }

    #[test]
    fn selection_frequencies_follow_weights() {
        let mut t = SumTree::new(4);
        let w = [1.0, 2.0, 3.0, 4.0];
        for (i, v) in w.into_iter().enumerate() {
            t.set(i, v);
        }
        let m = 100_000;
        let mut c = [0usize; 4];
        for k in 0..m {
            c[t.select_in(0, 4, (k as f64 + 0.5) / m as f64).unwrap()] += 1;
        }
        for i in 0..4 {
            // Deterministic stratified u: counts match weights to one part in m.
            assert!((c[i] as f64 / m as f64 - w[i] / 10.0).abs() < 2.0 / m as f64);
        }
    }
}
