//! The range of a whole-number parameter: [`CountRange`], its bounds and the words in which
//! its checks state them.
//!
//! A model's check of a count (`layers`, `steps`, `gif_frames`), the reader of its scenario
//! files and the command line's parser of its option share one `CountRange`, so that the three
//! state one range: `--layers 5000` and `--layers 1e19` are both refused with "expected an
//! integer in [1, 4096]", though the second is past what a scenario file holds (2^63 - 1) and
//! is refused by the parser before any check runs.
//!
//! ```
//! use cellsurf::engine::count::CountRange;
//!
//! const FRAMES: CountRange = CountRange::new(1, 2000, "1 to 2000");
//! assert!(FRAMES.contains(2000) && !FRAMES.contains(0) && !FRAMES.contains(2001));
//! assert_eq!(FRAMES.expected, "1 to 2000");
//! ```

/// The valid values of a whole-number parameter, `min ..= max`, and the words that state them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CountRange {
    /// The smallest valid value.
    pub min: u64,
    /// The largest valid value.
    pub max: u64,
    /// The range in words, as read after "expected" (`1 to 2000`, `an integer in [0, 2^40]`).
    pub expected: &'static str,
}

impl CountRange {
    /// The range `min ..= max`, stated as `expected`.
    pub const fn new(min: u64, max: u64, expected: &'static str) -> Self {
        assert!(min <= max, "a count range's min must not exceed its max");
        CountRange { min, max, expected }
    }

    /// Whether `v` lies in `min ..= max`.
    pub const fn contains(&self, v: u64) -> bool {
        self.min <= v && v <= self.max
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn count_range_holds_its_ends_and_nothing_past_them() {
        let r = CountRange::new(3, 65536, "an integer in [3, 65536]");
        assert!(r.contains(3) && r.contains(65536));
        assert!(!r.contains(2) && !r.contains(65537) && !r.contains(u64::MAX));
        let one = CountRange::new(7, 7, "7");
        assert!(one.contains(7) && !one.contains(6) && !one.contains(8));
    }
}
