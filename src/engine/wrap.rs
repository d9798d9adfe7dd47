//! Periodic indices and a fast floor for the hot loops of the streaming and sampling code.
//!
//! [`wrap`] is `i mod n` in `0..n` with no division when `i` is already in range (the common
//! case); [`floor`] is `f64::floor` without the library call that the baseline x86-64 target
//! makes for it (no SSE4.1 `roundsd`), exact for every `|x| < 2^63`; [`floor_by`] chooses
//! between it and the library's (for code compiled with SSE4.1 or later enabled).

/// `i mod n` in `0..n` (`n > 0`): `i` itself when it is in range, else `i.rem_euclid(n)`.
#[inline(always)]
pub fn wrap(i: i64, n: usize) -> usize {
    if (0..n as i64).contains(&i) {
        i as usize
    } else {
        i.rem_euclid(n as i64) as usize
    }
}

/// `x.floor()`, bit for bit, without a library call for `|x| < 2^63` (beyond, and for NaN,
/// the library's).
#[inline(always)]
pub fn floor(x: f64) -> f64 {
    if x.abs() < 9.2e18 {
        let t = x as i64 as f64;
        if t > x {
            t - 1.0
        } else if t == x {
            x // keeps the sign of -0.0
        } else {
            t
        }
    } else {
        x.floor()
    }
}

/// `x.floor()` by [`floor`] (`LIB = false`) or by the library (`LIB = true`: one `roundsd`
/// instruction when inlined into code compiled for SSE4.1 or later, a library call
/// otherwise); the same bits either way.
#[inline(always)]
pub fn floor_by<const LIB: bool>(x: f64) -> f64 {
    if LIB { x.floor() } else { floor(x) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_agrees_with_rem_euclid() {
        for n in [1usize, 2, 3, 7, 64] {
            for i in -200i64..200 {
                assert_eq!(wrap(i, n), i.rem_euclid(n as i64) as usize, "{i} mod {n}");
            }
        }
    }

    #[test]
    fn floor_agrees_with_the_library() {
        let xs = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.999_999_999,
            -2.000_000_001,
            1e15 + 0.5,
            -1e15 - 0.5,
            4.5e18,
            -4.5e18,
            1e300,
            -1e300,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
        ];
        for x in xs {
            assert_eq!(floor(x).to_bits(), x.floor().to_bits(), "{x}");
        }
        assert!(floor(f64::NAN).is_nan());
        assert_eq!(floor(f64::INFINITY), f64::INFINITY);
    }
}
