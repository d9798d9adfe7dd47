//! [`Compaction`]: porosity of each automaton from how it was deposited and from burial.
//!
//! The paper gives no formula. The rule used here, bounded by Soulsby (1997), Dynamics of
//! marine sands, Thomas Telford, Table 5:
//!
//! - The Table 5 row is chosen by the sorting sigma_phi: well sorted for sigma_phi <= 0.5,
//!   "average" at 1.0, "well mixed" at >= 2.0, linear in between.
//! - A grain deposited by an **avalanche** (lee faces) gets the row's *loose* porosity; a grain
//!   deposited by **roll/saltation** or **creep**, and the initial bed, get the *average* one.
//! - **Burial**: each deposit on a column compacts the `compaction_depth` automata beneath it,
//!   removing the fraction `compaction_rate` of their porosity in excess of the row's *dense*
//!   value. Repeated burial (over time) drives buried grains to the dense packing, never beyond.
//!
//! Porosity is stored per automaton as a `u8` code, porosity = code / [`SCALE`]
//! (resolution 0.002); the integer compaction step converges exactly to the dense code.

/// Porosity = code / SCALE.
pub const SCALE: f64 = 500.0;

/// Soulsby (1997) Table 5: (loose, average, dense) for well sorted, average, well mixed sand.
pub const TABLE5: [[f64; 3]; 3] = [[0.46, 0.42, 0.40], [0.43, 0.40, 0.37], [0.38, 0.33, 0.30]];

/// How an automaton came to rest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Deposit {
    /// Avalanche (Eq. 6): loose packing.
    Avalanche,
    /// Roll/saltation (Eqs. 1-8) or creep (Eqs. 9-10): average packing.
    Rolled,
}

/// The porosity rule of a run.
#[derive(Clone, Copy, Debug)]
pub struct Compaction {
    /// Codes of the loose, average and dense porosities.
    pub codes: [u8; 3],
    /// Numerator (of 256) kept of the excess porosity at each burial.
    keep256: u32,
    /// Automata compacted under each deposit.
    pub depth: usize,
}

/// Porosity bounds (loose, average, dense) of Table 5 for a sorting sigma_phi.
pub fn table5_for_sorting(sigma_phi: f64) -> [f64; 3] {
    let (a, b, t) = if sigma_phi <= 0.5 {
        (0, 0, 0.0)
    } else if sigma_phi <= 1.0 {
        (0, 1, (sigma_phi - 0.5) / 0.5)
    } else if sigma_phi <= 2.0 {
        (1, 2, sigma_phi - 1.0)
    } else {
        (2, 2, 0.0)
    };
    let mut out = [0.0; 3];
    for (i, o) in out.iter_mut().enumerate() {
        *o = TABLE5[a][i] * (1.0 - t) + TABLE5[b][i] * t;
    }
    out
}

/// The code of a porosity.
pub fn code(eps: f64) -> u8 {
    (eps * SCALE).round().clamp(0.0, 255.0) as u8
}

/// The porosity of a code.
pub fn porosity(code: u8) -> f64 {
    code as f64 / SCALE
}

impl Compaction {
    /// The rule for a sorting, burial rate and depth.
    pub fn new(sigma_phi: f64, rate: f64, depth: usize) -> Self {
        let t = table5_for_sorting(sigma_phi);
        Compaction {
            codes: [code(t[0]), code(t[1]), code(t[2])],
            keep256: (256.0 * (1.0 - rate)).round().clamp(0.0, 256.0) as u32,
            depth,
        }
    }

    /// The code given to a grain deposited by `how`.
    #[inline]
    pub fn deposit_code(&self, how: Deposit) -> u8 {
        match how {
            Deposit::Avalanche => self.codes[0],
            Deposit::Rolled => self.codes[1],
        }
    }

    /// The code of the initial bed (average packing).
    pub fn initial_code(&self) -> u8 {
        self.codes[1]
    }

    /// One burial step of a code: removes the fraction `rate` of its excess over dense.
    #[inline]
    pub fn bury(&self, c: u8) -> u8 {
        let dense = self.codes[2];
        if c <= dense {
            return c;
        }
        let excess = (c - dense) as u32;
        dense + ((excess * self.keep256) >> 8) as u8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table5_rows_and_interpolation() {
        assert_eq!(table5_for_sorting(0.3), [0.46, 0.42, 0.40]);
        assert_eq!(table5_for_sorting(1.0), [0.43, 0.40, 0.37]);
        assert_eq!(table5_for_sorting(3.0), [0.38, 0.33, 0.30]);
        let m = table5_for_sorting(0.75);
        assert!((m[1] - 0.41).abs() < 1e-12);
    }

    #[test]
    fn burial_converges_to_dense_and_never_beyond() {
        let c = Compaction::new(0.5, 0.1, 4);
        let mut x = c.deposit_code(Deposit::Avalanche);
        for _ in 0..200 {
            let y = c.bury(x);
            assert!(y <= x && y >= c.codes[2]);
            x = y;
        }
        assert_eq!(x, c.codes[2]);
        assert!((porosity(x) - 0.40).abs() < 0.002);
    }

    #[test]
    fn avalanche_faces_are_looser_than_rolled_grains() {
        let c = Compaction::new(0.5, 0.1, 4);
        assert!(c.deposit_code(Deposit::Avalanche) > c.deposit_code(Deposit::Rolled));
    }
}
