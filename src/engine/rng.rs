//! [`Stream`]: the one random stream every model draws from.
//!
//! Xoshiro256++ (Blackman and Vigna 2021, "Scrambled linear pseudorandom number generators",
//! ACM TOMS 47(4), <https://doi.org/10.1145/3460772>), seeded through SplitMix64 from a `u64`
//! seed by [`stream`]. The same seed gives the same sequence on every platform; models that
//! run in parallel derive one stream per chunk of work from the run's seed, so their output
//! does not depend on the thread count.

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

/// The random stream of a run: Xoshiro256++ seeded through SplitMix64 from a `u64` seed.
pub type Stream = Xoshiro256PlusPlus;

/// The random stream for `seed` (the same seed gives the same sequence on every platform).
pub fn stream(seed: u64) -> Stream {
    Xoshiro256PlusPlus::seed_from_u64(seed)
}
