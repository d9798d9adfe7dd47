//! Werner-model dunes: the slab model of the "Werner model" dune article, in its two modes,
//! and the classic Werner (1995) model on the same slab engine.
//!
//! The principal types are:
//!
//! - [`DuneConfig`]: the parameters of a run (mode, grid, iterations, sand quantity, wind,
//!   seed, and the Werner parameters [`WernerParams`]), checked by [`DuneConfig::validate`];
//! - [`Mode`]: the article's ripple mode, its dune mode (`-d`), or the Werner variant;
//! - [`DuneModel`]: the slab engine: an `N x N` periodic grid of sand heights held as integer
//!   grains, one random stream, and the rules of the chosen mode; [`DuneModel::step`] runs one
//!   iteration, [`DuneModel::pick`] one pick;
//! - [`DuneStats`] (from [`DuneModel::stats`]): dune bodies, bare fraction, height range and
//!   the exact sand balance; [`Bodies`] (from [`bodies`]): connected components of the cells
//!   above a threshold (petgraph's union-find on the 8-neighbour torus of a
//!   [`Lattice`](crate::engine::lattice::Lattice));
//! - [`Start`]: the initial state, the mode's random field or one round sand [`Pile`]
//!   ([`DuneModel::with_start`]);
//! - [`DuneError`]: a parameter out of range, naming the parameter, its value and the range.
//!
//! The slab engine lives in `engine.rs`, the torus geometry in `grid.rs`, the Werner rules
//! in `werner.rs`, the measurements in `measure.rs`, the initial states in `start.rs`;
//! [`study`] holds the error-against-run-time study; the figures (feature `plot`) are in
//! `FIGURES`, drawn by the functions of the private `plot` module re-exported here.
//!
//! ```
//! use cellsurf::dunes::{DuneConfig, DuneModel, Mode};
//!
//! // Dune mode (`-d`) with sand quantity Q = 1 on a 32 x 32 torus, 20 iterations.
//! let cfg = DuneConfig { mode: Mode::Dune, grid: 32, iterations: 20, ..DuneConfig::default() };
//! let mut m = DuneModel::new(&cfg).unwrap();
//! let before: u64 = m.grains().iter().sum();
//! for _ in 0..cfg.iterations {
//!     m.step();
//! }
//! // Sand moves but is never created or destroyed (heights are whole grains).
//! assert_eq!(m.grains().iter().sum::<u64>(), before);
//! assert_eq!(m.stats().sand_change, 0);
//! // A grid too small for a torus is refused, naming the parameter.
//! let bad = DuneConfig { grid: 2, ..DuneConfig::default() };
//! assert!(bad.validate().unwrap_err().to_string().starts_with("grid = 2"));
//! ```
//!
//! # The article's model ("Werner model" dune patterns, the follow-up of a Werner wind-ripple
//! article; our readings of its ambiguous passages are stated below)
//!
//! The article's code (`simulate.py`) works on an `N x N` periodic grid of heights `h[i, j]`.
//! Each iteration applies a *jumping rule* (wind lifts sand from random cells and drops it
//! downwind) and then the synchronous *rolling rule*.
//!
//! - **Ripple mode** (the earlier article; the default): initial `h` uniform in
//!   `[2.85, 3.15]`; each iteration `N^2` uniform random picks; a picked cell sends
//!   `q = 0.1` to the cell `jump = int(wind + 1.0 h)` further downwind ([`ripple_jump`]);
//!   then rolling with `D = 0.1`.
//! - **Dune mode** (`-d`): initial `h` uniform in `[0, 2Q]` (`-q Q`); each iteration
//!   `int(0.2 N^2)` picks among the cells with `h > 0`; with the centred slope
//!   `dz/dx = (h[i+1] - h[i-1]) / 2`, the picked cell sends
//!   `sand_quantity = 0.5 + 0.4 tanh(2 dz/dx)` ([`sand_quantity`]) to the cell
//!   `jump_length = int(11.2 - 8.0 tanh(8 dz/dx))` ([`jump_length`]) further downwind; then
//!   rolling with `D = 0.3`. The wind speed is not used in this mode (the article hard-codes
//!   the jump law). Sand quantity 1 gives barchans, 3 transverse ridges.
//! - **Rolling rule** ([`rolling_rule`]), synchronous over the grid:
//!   `h' = (1 - D) h + D (sum of the 4 edge neighbours / 6 + sum of the 4 diagonal
//!   neighbours / 12)`.
//!
//! # Choices made here
//!
//! - **Axes.** Cell `(x, y)` is `h[y * N + x]`, as in [`crate::engine::lattice::Lattice`]. The
//!   article's first index `i` is `x`, the downwind direction: the wind blows towards `+x`
//!   (left to right in the figures, as in the article), `y` is across the wind. Both axes are
//!   periodic.
//! - **Exact sand bookkeeping.** Heights are held as integer *grains*, [`GRAINS_PER_UNIT`]
//!   (10^6) grains per height unit (the height unit is the cell width: the slope
//!   `dz/dx` is in height units per cell). Every move takes grains from one cell and adds the
//!   same grains to another, so the total is conserved exactly: the reported `sand_change` is
//!   an integer count of grains and is always 0. The rolling rule is applied in flux form:
//!   each cell sends `floor(D a / 6)` grains to each edge neighbour and `floor(D a / 12)` to
//!   each diagonal neighbour (`a` its grains) and keeps the rest, which conserves sand exactly
//!   and differs from the formula by less than 8 grains per cell (`D` is applied to 10^-6).
//!   Quantities drawn from the laws are rounded to the nearest grain.
//! - **The defect fixed.** The article's code subtracts `q` even from a cell holding less,
//!   which then goes negative. Here a pick moves `min(q, h)`: heights never go
//!   negative.
//! - **Picks among cells with `h > 0`** (dune mode) are drawn uniformly among the cells that
//!   hold at least one grain at the moment of the pick (a set kept up to date in O(1) per
//!   move), so every pick moves sand. The article's code instead draws a uniform cell and
//!   does nothing when `h <= 0`; the two differ only by the fraction of empty cells, which
//!   the rolling rule keeps small. Picks over all cells (ripple mode, Werner) draw the cell
//!   index uniformly from `0..N^2` (one draw, not one per axis).
//! - **Random stream**: [`crate::engine::rng::stream`] (Xoshiro256++) seeded from `seed`; the
//!   initial field is drawn first, cell by cell in index order, then the picks.
//!
//! # The Werner (1995) variant
//!
//! [`Mode::Werner`]: Werner's classic slab model ("Eolian dunes: computer simulations and
//! attractor interpretation", Geology 23, 1995) on the same engine (grid, random stream,
//! integer grains). Heights are whole *slabs* of [`WernerParams::slab`] height units (0.1:
//! ten slabs make one cell width). Initial heights are uniform whole slabs in `[0, 2Q]`, then
//! relaxed to the angle of repose. Each iteration makes `N^2` uniform picks; a picked cell
//! that holds a slab and is not in a shadow zone loses one slab, which hops `L` cells
//! downwind ([`WernerParams::hop`]) and is deposited with probability `p_sand` (0.6) on a
//! cell holding sand, `p_bare` (0.4) on a bare cell, and always in a shadow zone; otherwise
//! it hops again.
//! - **Shadow zone** (15 degrees): a cell is in the shadow of an upwind cell `k` cells away
//!   when that cell is higher by more than `k tan(15 deg)` cell widths. A slab landing in a
//!   shadow stays there, and sand in a shadow is never picked up.
//! - **Angle of repose** (33 degrees, in the 30-34 degree range of dry sand): after every
//!   erosion and deposition, slabs avalanche one at a time down the steepest of the 8
//!   neighbours while the height difference exceeds `tan(33 deg)` times the distance (1 or
//!   `sqrt 2` cells). With 0.1-unit slabs that keeps every edge difference at most 6 slabs
//!   (31.0 degrees) and every diagonal difference at most 9 slabs (32.5 degrees).
//!
//! # Measuring the article's claim
//!
//! [`DuneStats::dune_bodies`] counts the connected components (8-neighbour, on the torus)
//! of the cells higher than [`BODY_THRESHOLD`], one height unit (one cell width of sand):
//! more than any single pick can move (at most 0.9), so the parcels in transit between the
//! dunes do not count as bodies, while the rolling rule's thin film of sand everywhere does
//! not join them up either (`h > 0` would make the whole grid one body).
//! [`DuneStats::bare_fraction`] is the fraction of cells at or below the threshold, and
//! [`DuneStats::spanning_bodies`] the bodies that wrap round the torus. Separate barchans
//! show as many bodies, none spanning, and much bare ground; connected transverse ridges as
//! one or a few bodies that span the grid across the wind, and less bare ground.
//! [`DuneModel::stats_with_threshold`] takes another threshold.

mod engine;
mod grid;
mod measure;
#[cfg(feature = "plot")]
mod plot;
mod scenario;
mod start;
pub mod study;
mod werner;

pub use engine::DuneModel;
pub use measure::{Bodies, DuneStats, above_threshold, bodies};
#[cfg(feature = "plot")]
pub use plot::{
    ErrorStudy, FIGURES, FieldPanel, HEIGHT_LEVELS, MigrationRecorder, SCENARIOS, bodies_panel,
    describe, describe_run, draw_field, draw_result, height_color, height_palette, height_panel,
    height_states,
};
pub use scenario::DuneScenario;
pub use start::{Pile, Start, gaussian_pile};

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::engine::count::CountRange;

/// What one pick did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PickEvent {
    /// The picked cell (`y * N + x`).
    pub from: usize,
    /// The cell that received the sand (equal to `from` when nothing moved).
    pub to: usize,
    /// Cells travelled downwind before wrapping: the jump of the article's laws (may exceed
    /// `N`, or be negative in ripple mode with a negative wind); in Werner mode the total of
    /// the hops.
    pub jump: i64,
    /// Grains moved (0 when nothing moved: an empty cell, or a Werner cell without a slab or
    /// in a shadow zone).
    pub grains: u64,
}

/// The crate version, recorded in every output (the engine's).
pub use crate::engine::VERSION;

/// Grains per height unit: heights are held as integer grains, so the sand balance is exact.
/// One height unit is one cell width.
pub const GRAINS_PER_UNIT: u64 = 1_000_000;

/// Threshold of a dune body, height units (one cell width of sand): cells with
/// `h > BODY_THRESHOLD` belong to dune bodies, the others are bare ground. It lies above the
/// largest parcel one pick can move (0.9 in dune mode), so sand in transit between dunes
/// does not count as a body.
pub const BODY_THRESHOLD: f64 = 1.0;

/// Largest grid side accepted (cells); the grid has `N^2` cells.
pub const MAX_GRID: usize = 4096;
/// Largest sand quantity `Q` accepted (height units).
pub const MAX_QUANTITY: f64 = 1e5;
/// Largest absolute wind speed accepted (cells per pick).
pub const MAX_WIND: f64 = 1e9;
/// Largest number of iterations accepted.
pub const MAX_ITERATIONS: u64 = 1_000_000_000;

/// `size`: the side of the square periodic grid, 3 to [`MAX_GRID`] cells.
pub const GRID: CountRange = CountRange::new(
    3,
    MAX_GRID as u64,
    "3 to 4096 cells (a periodic grid needs at least 3 cells a side)",
);
/// `--size`, as [`GRID`] holds it.
pub const SIZE_SIDES: &str = "sides of 3 to 4096 cells (a square grid)";
/// `steps`: iterations, 0 to [`MAX_ITERATIONS`].
pub const ITERATIONS: CountRange = CountRange::new(0, MAX_ITERATIONS, "0 to 10^9");
/// `hop`: Werner's hop length of a slab, cells.
pub const HOP: CountRange = CountRange::new(1, 1_000_000, "1 to 10^6 cells");

/// Sand moved per pick in ripple mode (height units): the article's `q = 0.1`.
pub const RIPPLE_Q: f64 = 0.1;
/// Rolling coefficient of ripple mode: `D = 0.1`.
pub const RIPPLE_D: f64 = 0.1;
/// Rolling coefficient of dune mode: `D = 0.3`.
pub const DUNE_D: f64 = 0.3;
/// Picks per iteration in dune mode, as a fraction of `N^2`: `int(0.2 N^2)`.
pub const DUNE_PICK_FRACTION: f64 = 0.2;
/// Initial heights of ripple mode: uniform in `[2.85, 3.15]` height units.
pub const RIPPLE_INITIAL: (f64, f64) = (2.85, 3.15);

/// Which rules a run follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// The article's ripple mode: `N^2` picks, `jump = int(wind + h)`, `q = 0.1`, `D = 0.1`.
    Ripple,
    /// The article's dune mode (`-d`): `int(0.2 N^2)` picks among cells with sand, the tanh
    /// laws, `D = 0.3`.
    Dune,
    /// Werner (1995): slabs, shadow zone, angle of repose (`--variant werner`).
    Werner,
}

impl Mode {
    /// The name used in output.
    pub const fn name(self) -> &'static str {
        match self {
            Mode::Ripple => "ripple",
            Mode::Dune => "dune",
            Mode::Werner => "werner",
        }
    }

    /// The rolling coefficient `D` of the mode (`None` for Werner, which avalanches instead).
    pub const fn rolling(self) -> Option<f64> {
        match self {
            Mode::Ripple => Some(RIPPLE_D),
            Mode::Dune => Some(DUNE_D),
            Mode::Werner => None,
        }
    }
}

impl std::fmt::Display for Mode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Parameters of the Werner (1995) variant. The defaults are Werner's classic values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WernerParams {
    /// Hop length `L` of a slab, in cells (default 5). Range 1 to 10^6.
    pub hop: u32,
    /// Deposition probability on a cell holding sand (default 0.6). Range (0, 1].
    pub p_sand: f64,
    /// Deposition probability on a bare cell (default 0.4). Range (0, 1].
    pub p_bare: f64,
    /// Shadow-zone angle, degrees (default 15). Range (0, 89].
    pub shadow_deg: f64,
    /// Angle of repose, degrees (default 33). Range (0, 89], and `tan(repose_deg)` at least
    /// `slab` (an avalanche must be able to move a whole slab).
    pub repose_deg: f64,
    /// Slab thickness, height units (cell widths; default 0.1). Range 10^-6 to 1, a whole
    /// number of grains.
    pub slab: f64,
}

impl Default for WernerParams {
    fn default() -> Self {
        WernerParams {
            hop: 5,
            p_sand: 0.6,
            p_bare: 0.4,
            shadow_deg: 15.0,
            repose_deg: 33.0,
            slab: 0.1,
        }
    }
}

/// The parameters of a run. Defaults as in the article's code: grid 100, 500 iterations,
/// `Q = 1`, wind 3, ripple mode.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DuneConfig {
    /// Which rules (default [`Mode::Ripple`], the article's default; `-d` gives
    /// [`Mode::Dune`]).
    pub mode: Mode,
    /// Grid side `N`, cells (default 100; the grid is `N x N`, periodic). Range 3 to 4096.
    pub grid: usize,
    /// Iterations (default 500). Range 0 to 10^9.
    pub iterations: u64,
    /// Sand quantity `Q`, height units (mean initial height; default 1.0): dune mode and
    /// Werner only. Range 0 to 10^5.
    pub quantity: f64,
    /// Wind speed, cells per pick (default 3.0): ripple mode only (`jump = int(wind + h)`).
    /// Finite, range -10^9 to 10^9.
    pub wind: f64,
    /// Seed of the random stream (default 1): the same seed gives the same run, bit for bit.
    pub seed: u64,
    /// Werner variant parameters (used by [`Mode::Werner`] only).
    pub werner: WernerParams,
}

impl Default for DuneConfig {
    fn default() -> Self {
        DuneConfig {
            mode: Mode::Ripple,
            grid: 100,
            iterations: 500,
            quantity: 1.0,
            wind: 3.0,
            seed: 1,
            werner: WernerParams::default(),
        }
    }
}

impl DuneConfig {
    /// The defaults in `mode`.
    pub fn with_mode(mode: Mode) -> Self {
        DuneConfig {
            mode,
            ..DuneConfig::default()
        }
    }

    /// Checks every parameter; the error names the first one out of range.
    pub fn validate(&self) -> Result<(), DuneError> {
        let bad = |name: &'static str, value: String, range: &'static str| {
            Err(DuneError::Parameter { name, value, range })
        };
        if !GRID.contains(self.grid as u64) {
            return bad("grid", self.grid.to_string(), GRID.expected);
        }
        if !ITERATIONS.contains(self.iterations) {
            return bad(
                "iterations",
                self.iterations.to_string(),
                ITERATIONS.expected,
            );
        }
        if !(self.quantity.is_finite() && (0.0..=MAX_QUANTITY).contains(&self.quantity)) {
            return bad(
                "quantity",
                self.quantity.to_string(),
                "0 to 10^5 height units (finite)",
            );
        }
        if !(self.wind.is_finite() && self.wind.abs() <= MAX_WIND) {
            return bad(
                "wind",
                self.wind.to_string(),
                "-10^9 to 10^9 cells per pick (finite)",
            );
        }
        if self.mode == Mode::Werner {
            let w = &self.werner;
            if !HOP.contains(u64::from(w.hop)) {
                return bad("hop", w.hop.to_string(), HOP.expected);
            }
            for (name, p) in [("p_sand", w.p_sand), ("p_bare", w.p_bare)] {
                if !(p > 0.0 && p <= 1.0) {
                    return bad(name, p.to_string(), "(0, 1]: above 0, at most 1");
                }
            }
            for (name, a) in [("shadow_deg", w.shadow_deg), ("repose_deg", w.repose_deg)] {
                if !(a > 0.0 && a <= 89.0) {
                    return bad(name, a.to_string(), "(0, 89] degrees");
                }
            }
            let grains = w.slab * GRAINS_PER_UNIT as f64;
            if !(w.slab.is_finite()
                && (1e-6..=1.0).contains(&w.slab)
                && (grains - grains.round()).abs() < 1e-6)
            {
                return bad(
                    "slab",
                    w.slab.to_string(),
                    "10^-6 to 1 height units, a whole number of grains (10^-6)",
                );
            }
            if w.repose_deg.to_radians().tan() < w.slab {
                return bad(
                    "repose_deg",
                    w.repose_deg.to_string(),
                    "an angle whose tangent is at least the slab thickness",
                );
            }
        }
        Ok(())
    }
}

/// A parameter out of range.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum DuneError {
    /// `name = value` is outside `range`.
    #[error("{name} = {value} is out of range: expected {range}")]
    Parameter {
        /// The parameter (as in [`DuneConfig`]; the command line uses the same names).
        name: &'static str,
        /// The value given.
        value: String,
        /// The valid range, in words.
        range: &'static str,
    },
}

/// Python's `int()` of an `f64`: truncation towards zero, saturating at the `i64` range
/// (NaN gives 0).
#[inline]
pub fn py_int(v: f64) -> i64 {
    v as i64
}

/// Ripple-mode jump (article's earlier code): `int(wind + 1.0 * h)`, cells downwind, with `h`
/// the height of the picked cell (height units) before the pick.
#[inline]
pub fn ripple_jump(wind: f64, h: f64) -> i64 {
    py_int(wind + 1.0 * h)
}

/// Dune-mode jump law: `jump_length = int(11.2 - 8.0 tanh(8 dz/dx))`, cells downwind (4 to
/// 19), with `dz/dx` the centred slope in height units per cell. Steep upwind (stoss)
/// slopes give short jumps, lee slopes long ones.
#[inline]
pub fn jump_length(slope: f64) -> i64 {
    py_int(11.2 - 8.0 * (8.0 * slope).tanh())
}

/// Dune-mode sand-quantity law: `sand_quantity = 0.5 + 0.4 tanh(2 dz/dx)`, height units
/// (0.1 to 0.9): more sand is lifted on the stoss side.
#[inline]
pub fn sand_quantity(slope: f64) -> f64 {
    0.5 + 0.4 * (2.0 * slope).tanh()
}

/// Grains nearest to `v` height units, halves rounded up (`v >= 0`; negative or NaN gives
/// 0, too large saturates).
#[inline]
pub fn to_grains(v: f64) -> u64 {
    (v * GRAINS_PER_UNIT as f64 + 0.5) as u64
}

/// Height units of `g` grains.
#[inline]
pub fn to_units(g: u64) -> f64 {
    g as f64 / GRAINS_PER_UNIT as f64
}

/// The rolling coefficient `D` in millionths, as the rolling rule applies it.
#[inline]
fn d_ppm(d: f64) -> u64 {
    (d.clamp(0.0, 1.0) * 1e6).round() as u64
}

/// Grains a cell holding `a` sends to each edge neighbour (`D a / 6`) and to each diagonal
/// neighbour (`D a / 12`), rounded down; `ppm` is `D` in millionths.
#[inline(always)]
fn rolling_flux(a: u64, ppm: u64) -> (u64, u64) {
    // floor(p / 12e6) = floor(floor(p / 6e6) / 2): one division.
    let e = match a.checked_mul(ppm) {
        Some(p) => p / 6_000_000,
        None => (a as u128 * ppm as u128 / 6_000_000) as u64,
    };
    (e, e / 2)
}

/// The article's rolling rule, applied synchronously to an `n x n` periodic grid of grains
/// (`h[y * n + x]`): `h' = (1 - D) h + D (sum of the 4 edge neighbours / 6 + sum of the 4
/// diagonal neighbours / 12)`, with `D = d` (clamped to [0, 1], applied to 10^-6).
///
/// Flux form: every cell sends `floor(D a / 6)` grains to each edge neighbour and
/// `floor(D a / 12)` to each diagonal neighbour and keeps the rest; in exact arithmetic this
/// is the formula (a cell gives away `D a (4/6 + 4/12) = D a`), and in grains it conserves
/// the total exactly and never makes a cell negative. Each new height is within 8 grains of
/// the formula. `flux` is scratch space (resized to `2 n^2`; no allocation once it has that
/// length); the result replaces `h`.
///
/// # Panics
///
/// If `h.len() != n * n` or `n < 3`.
pub fn rolling_rule(h: &mut [u64], n: usize, d: f64, flux: &mut Vec<u64>) {
    assert!(
        n >= 3 && h.len() == n * n,
        "rolling_rule: need an n x n grid, n >= 3"
    );
    let ppm = d_ppm(d);
    let cells = n * n;
    flux.resize(2 * cells, 0);
    let (edge, diag) = flux.split_at_mut(cells);
    for c in 0..cells {
        let (e, g) = rolling_flux(h[c], ppm);
        edge[c] = e;
        diag[c] = g;
        // What the cell keeps: a - 4e - 4g >= a - D a >= 0.
        h[c] -= 4 * e + 4 * g;
    }
    for y in 0..n {
        let (ym, yp) = (if y == 0 { n - 1 } else { y - 1 }, (y + 1) % n);
        let row = |r: usize| r * n..(r + 1) * n;
        let (e0, em, ep) = (&edge[row(y)], &edge[row(ym)], &edge[row(yp)]);
        let (dm, dp) = (&diag[row(ym)], &diag[row(yp)]);
        let out = &mut h[y * n..(y + 1) * n];
        // Interior columns: every neighbour in the same slice position, no wrap.
        for (((((o, e3), d3m), d3p), &u), &v) in out[1..n - 1]
            .iter_mut()
            .zip(e0.windows(3))
            .zip(dm.windows(3))
            .zip(dp.windows(3))
            .zip(&em[1..n - 1])
            .zip(&ep[1..n - 1])
        {
            *o += e3[0] + e3[2] + u + v + d3m[0] + d3m[2] + d3p[0] + d3p[2];
        }
        // The two edge columns wrap round.
        for x in [0, n - 1] {
            let xm = if x == 0 { n - 1 } else { x - 1 };
            let xp = if x + 1 == n { 0 } else { x + 1 };
            out[x] += e0[xm] + e0[xp] + em[x] + ep[x] + dm[xm] + dm[xp] + dp[xm] + dp[xp];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn laws_at_their_limits() {
        assert_eq!(jump_length(0.0), 11);
        assert_eq!(jump_length(10.0), 3);
        assert_eq!(jump_length(-10.0), 19);
        assert!((sand_quantity(0.0) - 0.5).abs() < 1e-15);
        assert_eq!(ripple_jump(3.0, 2.9), 5);
        assert_eq!(ripple_jump(-3.0, 0.5), -2);
        assert_eq!(py_int(f64::NAN), 0);
    }

    #[test]
    fn rolling_flux_never_exceeds_the_cell() {
        for a in [
            0u64,
            1,
            5,
            59,
            60,
            1_000_000,
            123_456_789,
            u64::MAX / 3,
            u64::MAX,
        ] {
            for d in [0.0, 0.1, 0.3, 1.0] {
                let ppm = d_ppm(d);
                let (e, g) = rolling_flux(a, ppm);
                assert!(4 * (e as u128) + 4 * (g as u128) <= a as u128, "{a} {d}");
                let p = a as u128 * ppm as u128;
                assert_eq!((e as u128, g as u128), (p / 6_000_000, p / 12_000_000));
            }
        }
    }

    #[test]
    fn config_validation_names_the_parameter() {
        let mut c = DuneConfig::default();
        assert!(c.validate().is_ok());
        c.grid = 2;
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains("grid = 2") && e.contains("3 to 4096"), "{e}");
        let mut c = DuneConfig::with_mode(Mode::Werner);
        c.werner.p_bare = 0.0;
        assert!(c.validate().unwrap_err().to_string().contains("p_bare"));
    }
}
