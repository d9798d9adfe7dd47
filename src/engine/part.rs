//! [`Part`]: one share of a job split over independent processes (`--part i/N`): a SLURM job
//! array, Kubernetes indexed jobs, GNU parallel. Part `i` of `N` owns the items
//! `i n / N .. (i + 1) n / N` of `n` items in a fixed order, so the shares are contiguous,
//! disjoint, cover every item and differ by at most one item.

use std::str::FromStr;

/// Part `index` of `count` (`--part i/N`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Part {
    /// This part, `0 .. count`.
    pub index: usize,
    /// Parts in all, at least 1.
    pub count: usize,
}

/// A `--part` value that is not `i/N` with `N` in 1..=1000000 and `i` in 0..N-1.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[error("--part = {value} is out of range: expected {expected}")]
pub struct PartError {
    /// The value given.
    pub value: String,
    /// The valid range.
    pub expected: String,
}

impl Part {
    /// The whole job, one process.
    pub const WHOLE: Part = Part { index: 0, count: 1 };

    /// The items this part owns of `n` (module docs).
    pub fn range(&self, n: usize) -> std::ops::Range<usize> {
        let at = |i: usize| ((i as u128 * n as u128) / self.count as u128) as usize;
        at(self.index)..at(self.index + 1)
    }
}

impl FromStr for Part {
    type Err = PartError;
    /// `i/N` with `N` in 1..=1000000 and `i` in 0..N-1.
    fn from_str(s: &str) -> Result<Self, PartError> {
        let bad = |why: String| PartError {
            value: s.to_string(),
            expected: why,
        };
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| bad("i/N, e.g. 0/4 (part i of N, i in 0..N-1)".into()))?;
        let n: usize = n
            .trim()
            .parse()
            .map_err(|_| bad("i/N with N a whole number in 1..=1000000".into()))?;
        if !(1..=1_000_000).contains(&n) {
            return Err(bad("i/N with N in 1..=1000000".into()));
        }
        let i: usize = i.trim().parse().map_err(|_| {
            bad(format!(
                "i/N with i a whole number in 0..N-1 (0..={})",
                n - 1
            ))
        })?;
        if i >= n {
            return Err(bad(format!("i/N with i in 0..N-1 (0..={})", n - 1)));
        }
        Ok(Part { index: i, count: n })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_cover_every_item_once_in_balanced_shares() {
        for n in [0, 1, 7, 100, 101] {
            for count in [1, 2, 3, 4, 13, 200] {
                let mut next = 0;
                for index in 0..count {
                    let r = Part { index, count }.range(n);
                    assert_eq!(r.start, next);
                    assert!(r.len() == n / count || r.len() == n / count + 1);
                    next = r.end;
                }
                assert_eq!(next, n);
            }
        }
    }

    #[test]
    fn bad_parts_name_the_flag_value_and_range() {
        assert_eq!("3/4".parse::<Part>().unwrap(), Part { index: 3, count: 4 });
        let e = "4/4".parse::<Part>().unwrap_err().to_string();
        assert!(e.contains("--part = 4/4") && e.contains("0..=3"), "{e}");
        for bad in ["1/0", "x", "1/x", "-1/2"] {
            assert!(bad.parse::<Part>().is_err(), "{bad}");
        }
    }
}
