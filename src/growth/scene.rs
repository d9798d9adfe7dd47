//! Growth scenes: the paper's flame front (Fig. 5), land deposition (Fig. 6), anisotropic
//! crystal (Fig. 7), deterministic CA (Figs. 3, 4), and a generic `grow` scene.
//!
//! A [`SceneConfig`] names everything a run needs (lattice, size, boundary, rule, initial
//! [`Shape`], sampler, clock, snapshots, seed); [`SceneConfig::defaults`] gives each scene the
//! values that reproduce the paper's snapshots, and [`SceneConfig::from_toml`] reads a
//! scenario file over those defaults (unknown keys are rejected). [`run`] builds only what the
//! configuration names and returns a [`RunResult`] with snapshots, an observable time series
//! and a summary.

use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::engine::count::CountRange;
use crate::engine::lattice::{Boundary, Lattice, LatticeError, Neighbourhood};
use crate::growth::observe::{self, ColumnProfile};
use crate::growth::rule::{RuleError, Sticking, Weight};
use crate::growth::sampler::{Outcome, SamplerKind};
use crate::growth::{Growth, GrowthError};

/// The crate version, recorded in every output (the engine's).
pub use crate::engine::VERSION;

/// The scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SceneKind {
    /// Flame front from a square burnt region (Fig. 5).
    Flame,
    /// Deposition on a cosine trough, vertical section (Fig. 6).
    Deposit,
    /// Anisotropic crystal from a disc seed, Eq. (5) (Fig. 7).
    Crystal,
    /// Deterministic synchronous CA from a seed cell (Figs. 3 and 4).
    Ca,
    /// Any lattice, rule, shape and sampler.
    Grow,
}

impl SceneKind {
    /// Every scene, in the order of the paper's figures.
    pub const ALL: [SceneKind; 5] = [
        SceneKind::Ca,
        SceneKind::Flame,
        SceneKind::Deposit,
        SceneKind::Crystal,
        SceneKind::Grow,
    ];

    /// The scene's name.
    pub fn name(self) -> &'static str {
        match self {
            SceneKind::Flame => "flame",
            SceneKind::Deposit => "deposit",
            SceneKind::Crystal => "crystal",
            SceneKind::Ca => "ca",
            SceneKind::Grow => "grow",
        }
    }
}

impl fmt::Display for SceneKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The initial occupied region, placed at the centre of the lattice (physical coordinates).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Shape {
    /// The single cell nearest the centre (`start` unused).
    Point,
    /// A square of side `start` (cell widths), axis-aligned.
    Square,
    /// A disc of diameter `start` (cell widths).
    Disc,
    /// Solid below `y = base + start cos(2 pi x / W)`: a trough in the middle of the section,
    /// `start` the amplitude, `base = start + 0.1 H` (all in cell widths).
    Cosine,
    /// Solid below `y = start`: a flat layer `start` cell widths thick.
    Flat,
}

impl Shape {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Point => "point",
            Shape::Square => "square",
            Shape::Disc => "disc",
            Shape::Cosine => "cosine",
            Shape::Flat => "flat",
        }
    }
}

impl FromStr for Shape {
    type Err = SceneError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "point" => Ok(Shape::Point),
            "square" => Ok(Shape::Square),
            "disc" | "circle" => Ok(Shape::Disc),
            "cosine" => Ok(Shape::Cosine),
            "flat" => Ok(Shape::Flat),
            _ => Err(SceneError::Unknown {
                parameter: "shape",
                value: s.to_string(),
                expected: "point, square, disc, cosine or flat",
            }),
        }
    }
}

/// The direction weight of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WeightKind {
    /// `v = 1` (Eq. 4).
    None,
    /// Eq. (5), relative to the shape's centre.
    Axes,
}

impl fmt::Display for WeightKind {
    /// The name `--weight` and scenario files take: `none` or `axes`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            WeightKind::None => "none",
            WeightKind::Axes => "axes",
        })
    }
}

impl FromStr for WeightKind {
    type Err = SceneError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "none" | "isotropic" => Ok(WeightKind::None),
            "axes" => Ok(WeightKind::Axes),
            _ => Err(SceneError::Unknown {
                parameter: "weight",
                value: s.to_string(),
                expected: "none or axes",
            }),
        }
    }
}

/// Errors in a scene's configuration or run.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SceneError {
    /// A lattice parameter is invalid.
    #[error(transparent)]
    Lattice(#[from] LatticeError),
    /// A rule parameter is invalid.
    #[error(transparent)]
    Rule(#[from] RuleError),
    /// Growth could not be set up.
    #[error(transparent)]
    Growth(#[from] GrowthError),
    /// A numeric parameter is out of range.
    #[error("{parameter} = {value} is out of range: expected {expected}")]
    Range {
        /// The parameter's name.
        parameter: &'static str,
        /// The value given.
        value: String,
        /// The valid range.
        expected: String,
    },
    /// A name is not known.
    #[error("unknown {parameter} '{value}': expected {expected}")]
    Unknown {
        /// The parameter's name.
        parameter: &'static str,
        /// The value given.
        value: String,
        /// The valid names.
        expected: &'static str,
    },
    /// A scenario file could not be read.
    #[error("scenario file: {0}")]
    Toml(String),
}

fn range(
    parameter: &'static str,
    value: impl fmt::Display,
    expected: impl Into<String>,
) -> SceneError {
    SceneError::Range {
        parameter,
        value: value.to_string(),
        expected: expected.into(),
    }
}

/// Everything a growth run needs. Units: lengths in cell widths; times in Monte Carlo
/// timesteps (picks), or CA updates for the CA sampler.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneConfig {
    /// The scene.
    pub scene: SceneKind,
    /// Neighbourhood: hex (Eq. 3), square4 (Eq. 2) or square8 (Moore).
    pub lattice: Neighbourhood,
    /// Columns.
    pub width: usize,
    /// Rows (even on a hexagonal lattice periodic in y).
    pub height: usize,
    /// Boundary: torus, walls, channel (periodic x, walls y) or tube.
    pub boundary: Boundary,
    /// Power-law exponent n >= 0 of Eq. (4).
    pub n: f64,
    /// Direction weight v: none (v = 1) or axes (Eq. 5).
    pub weight: WeightKind,
    /// Initial shape.
    pub shape: Shape,
    /// Size of the initial shape (cell widths): square side, disc diameter, cosine amplitude
    /// or flat thickness.
    pub start: f64,
    /// Timesteps to run (the clock limit). 0: no clock limit, allowed only with `events` or
    /// `until_occupied` and a sampler other than rejection (whose clock is its work).
    pub steps: u64,
    /// Stop after this many accepted events (cells added by the sampler), if reached before
    /// `steps`. Default: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub events: Option<u64>,
    /// Stop when this fraction of the lattice's cells is occupied, if reached before `steps`
    /// and `events`; in `(0, 1]`. Default: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until_occupied: Option<f64>,
    /// Timesteps at which to keep a snapshot of the lattice, increasing, at most `steps`.
    pub snapshots: Vec<u64>,
    /// Sampler: rejection (the paper's), exact (rejection-free) or ca (deterministic).
    pub sampler: SamplerKind,
    /// CA only: the minimum number of occupied neighbours for growth, cycled over the
    /// timesteps (`[1]`: Fig. 3; `[1, 2]`: Fig. 4).
    pub ca_rule: Vec<usize>,
    /// Seed of the random stream.
    pub seed: u64,
    /// Number of evenly spaced times at which observables are recorded.
    pub series: usize,
}

/// The scenario keys that hold whole numbers (sizes, counts, timesteps, the seed).
const WHOLE_KEYS: [&str; 8] = [
    "width",
    "height",
    "steps",
    "events",
    "snapshots",
    "ca_rule",
    "seed",
    "series",
];

/// The range of a whole-number key in words, for a value past every count (`steps = 1e30`).
fn whole_key_range(key: &str) -> Option<&'static str> {
    match key {
        "width" | "height" => Some(SIZE_SIDES),
        "steps" => Some(STEPS.expected),
        "events" => Some(EVENTS.expected),
        "snapshots" => Some(SNAPSHOTS),
        "ca_rule" => Some(CA_RULE),
        "series" => Some(SERIES.expected),
        _ => None,
    }
}

/// Turns the whole-valued floats of the [`WHOLE_KEYS`] (`steps = 1e4`, a TOML float) into
/// integers, as `--steps 1e4` is read; any other float there is refused, naming the key. A
/// whole number past every count (`steps = 1e30`, `inf`, in a list too) is refused with the
/// key's own range ([`whole_key_range`], the words its check and its option state), the value
/// as written.
fn whole_numbers(table: &mut toml::Table) -> Result<(), SceneError> {
    const PAST: f64 = 9_223_372_036_854_775_808.0; // 2^63: the largest TOML integer is 2^63 - 1
    let refuse = |key: &'static str, f: f64| match whole_key_range(key) {
        Some(expected) if f >= PAST => SceneError::Range {
            parameter: key,
            value: crate::ripple::params::shown(f),
            expected: expected.into(),
        },
        _ => SceneError::Toml(format!(
            "`{key}` = {}: expected a whole number from 0 to 2^63 - 1 (e.g. 10000 or 1e4)",
            crate::ripple::params::shown(f)
        )),
    };
    let whole = |key: &'static str, v: &mut toml::Value| -> Result<(), SceneError> {
        if let toml::Value::Float(f) = *v {
            if !((0.0..PAST).contains(&f) && f.fract() == 0.0) {
                return Err(refuse(key, f));
            }
            *v = toml::Value::Integer(f as i64);
        }
        Ok(())
    };
    for key in WHOLE_KEYS {
        match table.get_mut(key) {
            Some(toml::Value::Array(a)) => a.iter_mut().try_for_each(|v| whole(key, v))?,
            Some(v) => whole(key, v)?,
            None => {}
        }
    }
    Ok(())
}

/// The largest step count: the clock is exact in `f64` below `2^53`.
pub const MAX_STEPS: u64 = 1 << 53;

/// `steps`: timesteps of a run (0, no clock limit, only where an event count or an occupied
/// fraction stops it).
pub const STEPS: CountRange = CountRange::new(
    0,
    MAX_STEPS,
    "1 to 9007199254740992 (0, no clock limit, only with events or until_occupied)",
);
/// `events`: accepted events that stop a run.
pub const EVENTS: CountRange = CountRange::new(1, MAX_STEPS, "1 to 9007199254740992");
/// `snapshots`: timesteps, each at most the run's `steps` (the check gives its value).
pub const SNAPSHOTS: &str = "timesteps of at most steps";
/// `series`: points of the observables' time series.
pub const SERIES: CountRange = CountRange::new(1, 100_000, "1 to 100000 points");
/// `ca_rule`: neighbour counts, each at most the lattice's neighbours `z` (the check gives
/// its value).
pub const CA_RULE: &str =
    "neighbour counts from 1 to z, the lattice's neighbours (6 on hex, 4 or 8 on square)";
/// `size`, as the lattice's checks hold it.
pub const SIZE_SIDES: &str = "sides of 1 to 2^20 cells (at least 3 along a periodic axis, rows \
     even on a hex torus), at most 2^28 - 1 = 268435455 cells in all";

/// Which keys a scenario file gave whose defaults the command line adjusts to the run: the
/// scene's default `snapshots` are fitted to the steps, and a `series` longer than the run is
/// warned of only where the user asked for it ([`SceneConfig::parse_toml`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Given {
    /// The file gave `snapshots`.
    pub snapshots: bool,
    /// The file gave `series`.
    pub series: bool,
}

impl SceneConfig {
    /// The defaults of a scene, chosen so that the figures show what the paper describes
    /// (the paper gives no lattice sizes):
    /// - flame: hexagonal 120 x 138 torus (physically square), square start of side 20,
    ///   n = 2, snapshots 1000, 8000, 20000, 50000;
    /// - deposit: hexagonal 50 x 200 channel (periodic in x, floor and ceiling walls), cosine
    ///   of amplitude 12 (a narrow section, so that the trough fills within 50000 steps), n = 2, snapshots 10, 5000, 28000, 50000;
    /// - crystal: hexagonal 180 x 208 torus, disc of diameter 30, n = 2, Eq. (5),
    ///   snapshots 1000, 30000, 50000, 80000;
    /// - ca: square4 11 x 11 with walls, a seed cell, updates 1-4, rule `[1]` (Fig. 3);
    /// - grow: hexagonal 128 x 148 torus, a seed cell, n = 2, 20000 steps.
    pub fn defaults(scene: SceneKind) -> Self {
        let base = SceneConfig {
            scene,
            lattice: Neighbourhood::Hex,
            width: 120,
            height: 138,
            boundary: Boundary::TORUS,
            n: 2.0,
            weight: WeightKind::None,
            shape: Shape::Square,
            start: 20.0,
            steps: 50_000,
            events: None,
            until_occupied: None,
            snapshots: vec![1000, 8000, 20_000, 50_000],
            sampler: SamplerKind::Exact,
            ca_rule: vec![1],
            seed: 1,
            series: 50,
        };
        match scene {
            SceneKind::Flame => base,
            SceneKind::Deposit => SceneConfig {
                width: 50,
                height: 200,
                boundary: Boundary::CHANNEL,
                shape: Shape::Cosine,
                start: 12.0,
                snapshots: vec![10, 5000, 28_000, 50_000],
                ..base
            },
            SceneKind::Crystal => SceneConfig {
                width: 180,
                height: 208,
                weight: WeightKind::Axes,
                shape: Shape::Disc,
                start: 30.0,
                steps: 80_000,
                snapshots: vec![1000, 30_000, 50_000, 80_000],
                ..base
            },
            SceneKind::Ca => SceneConfig {
                lattice: Neighbourhood::Square4,
                width: 11,
                height: 11,
                boundary: Boundary::WALLS,
                n: 0.0,
                shape: Shape::Point,
                start: 1.0,
                steps: 4,
                snapshots: vec![1, 2, 3, 4],
                sampler: SamplerKind::Ca,
                series: 4,
                ..base
            },
            SceneKind::Grow => SceneConfig {
                width: 128,
                height: 148,
                shape: Shape::Point,
                start: 1.0,
                steps: 20_000,
                snapshots: vec![5000, 10_000, 20_000],
                ..base
            },
        }
    }

    /// Reads a scenario file: a TOML table with `scene = "..."` and any of the other keys,
    /// each overriding the scene's default. Unknown keys are an error.
    pub fn from_toml(text: &str) -> Result<Self, SceneError> {
        let (cfg, _) = SceneConfig::parse_toml(text)?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Reads a scenario file as [`SceneConfig::from_toml`] does, without checking the ranges
    /// (the command line may still override what is out of range), and says which of the keys
    /// whose defaults the command line adjusts the file gave ([`Given`]). A file that sets
    /// `steps` but no `snapshots` keeps the scene's default snapshots up to `steps`, and
    /// `steps` itself.
    pub fn parse_toml(text: &str) -> Result<(Self, Given), SceneError> {
        let table: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| SceneError::Toml(e.to_string()))?;
        let scene = match table.get("scene") {
            Some(toml::Value::String(s)) => {
                let v = toml::Value::String(s.clone());
                SceneKind::deserialize(v).map_err(|_| SceneError::Unknown {
                    parameter: "scene",
                    value: s.clone(),
                    expected: "flame, deposit, crystal, ca or grow",
                })?
            }
            _ => {
                return Err(SceneError::Toml(
                    "missing key 'scene' (flame, deposit, crystal, ca or grow)".into(),
                ));
            }
        };
        let defaults = SceneConfig::defaults(scene);
        let base = toml::Table::try_from(&defaults).map_err(|e| SceneError::Toml(e.to_string()))?;
        let mut merged = base.clone();
        let mut table = table;
        whole_numbers(&mut table)?;
        let given = Given {
            snapshots: table.contains_key("snapshots"),
            series: table.contains_key("series"),
        };
        let snapshots_given = given.snapshots;
        let steps_given = table.contains_key("steps");
        for (k, v) in table {
            // (a value of the wrong kind is named by its key, with what the key takes)
            if let Err(e) = crate::engine::scenario::key_reads_as::<SceneConfig>(&base, &k, &v) {
                return Err(SceneError::Toml(if e.contains("unknown field") {
                    e
                } else {
                    format!("`{k}` = {v}: {e}")
                }));
            }
            merged.insert(k, v);
        }
        let mut cfg: SceneConfig = toml::Value::Table(merged)
            .try_into()
            .map_err(|e: toml::de::Error| SceneError::Toml(e.to_string()))?;
        if steps_given && !snapshots_given {
            cfg.fit_snapshots_to_steps();
        }
        Ok((cfg, given))
    }

    /// Keeps the snapshots within `steps` and adds `steps` itself (for default snapshots
    /// when the run's length changed; nothing to do for a run with no clock limit).
    pub fn fit_snapshots_to_steps(&mut self) {
        let v = self.steps;
        if v == 0 {
            return;
        }
        self.snapshots.retain(|&t| t <= v);
        if self.snapshots.last() != Some(&v) {
            self.snapshots.push(v);
        }
    }

    /// The configuration as a TOML scenario file.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }

    /// Checks every parameter, naming the first one out of range.
    pub fn validate(&self) -> Result<(), SceneError> {
        let cells = self.width as u128 * self.height as u128;
        if cells > crate::growth::state::MAX_GROWTH_CELLS as u128 {
            return Err(range(
                "size",
                format!("{}x{} ({cells} cells)", self.width, self.height),
                format!(
                    "at most {} cells (2^28 - 1) for a growth run, e.g. 16382x16382 (an even row count, as a hexagonal torus takes)",
                    crate::growth::state::MAX_GROWTH_CELLS
                ),
            ));
        }
        let lattice = Lattice::new(self.lattice, self.width, self.height, self.boundary)?;
        Sticking::new(self.n, self.lattice.z())?;
        let event_stop = self.events.is_some() || self.until_occupied.is_some();
        if !STEPS.contains(self.steps) || (self.steps == 0 && !event_stop) {
            return Err(range("steps", self.steps, STEPS.expected));
        }
        if self.steps == 0 && self.sampler == SamplerKind::Rejection {
            return Err(range(
                "steps",
                self.steps,
                "1 to 2^53 with the rejection sampler (one pick per timestep: its clock is its \
                 work); the exact sampler runs the same process with no clock limit",
            ));
        }
        if let Some(e) = self.events
            && !EVENTS.contains(e)
        {
            return Err(range("events", e, EVENTS.expected));
        }
        if let Some(f) = self.until_occupied
            && !(f > 0.0 && f <= 1.0)
        {
            return Err(range(
                "until_occupied",
                f,
                "a fraction of the lattice's cells, above 0 and at most 1",
            ));
        }
        for w in self.snapshots.windows(2) {
            if w[1] <= w[0] {
                return Err(range(
                    "snapshots",
                    format!("{:?}", self.snapshots),
                    "timesteps strictly increasing",
                ));
            }
        }
        if let Some(&last) = self.snapshots.last()
            && self.steps > 0
            && last > self.steps
        {
            return Err(range(
                "snapshots",
                last,
                format!("{SNAPSHOTS} = {}", self.steps),
            ));
        }
        if self.snapshots.len() > 64 {
            return Err(range(
                "snapshots",
                self.snapshots.len(),
                "at most 64 snapshots",
            ));
        }
        if !SERIES.contains(self.series as u64) {
            return Err(range("series", self.series, SERIES.expected));
        }

        let z = self.lattice.z();
        if self.ca_rule.is_empty() || self.ca_rule.iter().any(|&b| b == 0 || b > z) {
            return Err(range(
                "ca_rule",
                format!("{:?}", self.ca_rule),
                format!("a non-empty list of {CA_RULE}; z = {z} here"),
            ));
        }
        let (pw, ph) = lattice.physical_size();
        // The height of the top row of cells: a flat layer must leave it empty.
        let top_row = lattice.position(lattice.len() - 1).1;
        let s = self.start;
        let ok = match self.shape {
            Shape::Point => s.is_finite() && s >= 0.0,
            Shape::Square | Shape::Disc => s.is_finite() && s > 0.0 && s <= pw.min(ph),
            Shape::Cosine => s.is_finite() && s >= 0.0 && 2.0 * s + 0.1 * ph < ph,
            Shape::Flat => s.is_finite() && s > 0.0 && s <= top_row,
        };
        if !ok {
            let expected = match self.shape {
                Shape::Square | Shape::Disc => format!(
                    "a {} above 0 that fits the lattice (at most {:.1} cell widths)",
                    if self.shape == Shape::Square {
                        "square's side"
                    } else {
                        "disc's diameter"
                    },
                    pw.min(ph)
                ),
                Shape::Cosine => format!(
                    "an amplitude >= 0 whose trough fits the lattice (below {:.1})",
                    0.45 * ph
                ),
                Shape::Flat => {
                    format!("a layer above 0 that leaves the top row empty (at most {top_row:.2})")
                }
                Shape::Point => "a finite size >= 0 cell widths (unused by a point)".into(),
            };
            return Err(range("start", s, expected));
        }
        Ok(())
    }

    /// The centre of the initial shape and of the Eq. (5) weight (physical coordinates): half
    /// the lattice's extent on an axis with an even number of cells (a cell's centre, except
    /// on the shifted rows of a hex lattice), and the middle cell's (column `W / 2`, row
    /// `H / 2`, rounded down) on an axis with an odd number: half the extent would fall
    /// between two cells there, half a cell off the lattice's symmetric centre. A point seed
    /// is the cell nearest that centre (so the middle cell on a lattice with odd sides, the
    /// same cell as a disc of diameter 1), and its centre is that cell's.
    pub fn centre(&self, lattice: &Lattice) -> (f64, f64) {
        let (pw, ph) = lattice.physical_size();
        let (w, h) = (lattice.width(), lattice.height());
        let (mx, my) = lattice.position_xy(w / 2, h / 2);
        let c = (
            if w % 2 == 1 { mx } else { pw / 2.0 },
            if h % 2 == 1 { my } else { ph / 2.0 },
        );
        match self.shape {
            Shape::Point => lattice.position(lattice.nearest_cell(c.0, c.1)),
            _ => c,
        }
    }

    /// Builds the run's initial state: lattice, rule, weight and shape. The per-site weight
    /// tree is built only for the exact sampler with a non-uniform weight.
    pub fn build(&self) -> Result<Growth, SceneError> {
        self.validate()?;
        let lattice = Lattice::new(self.lattice, self.width, self.height, self.boundary)?;
        let rule = Sticking::new(self.n, self.lattice.z())?;
        let centre = self.centre(&lattice);
        let weight = match self.weight {
            WeightKind::None => Weight::Isotropic,
            WeightKind::Axes => Weight::Axes { centre },
        };
        let (pw, ph) = lattice.physical_size();
        let per_site = self.sampler == SamplerKind::Exact;
        let mut g = Growth::new(lattice, rule, weight, per_site)?;
        let s = self.start;
        let (cx, cy) = centre;
        match self.shape {
            Shape::Point => {
                let c = g.lattice().nearest_cell(cx, cy);
                g.occupy(c)?;
            }
            Shape::Square => g.occupy_where(|x, y| {
                x >= cx - s / 2.0 && x < cx + s / 2.0 && y >= cy - s / 2.0 && y < cy + s / 2.0
            }),
            Shape::Disc => g.occupy_where(|x, y| (x - cx).hypot(y - cy) < s / 2.0),
            Shape::Cosine => {
                let base = s + 0.1 * ph;
                g.occupy_where(|x, y| y <= base + s * (2.0 * PI * x / pw).cos())
            }
            Shape::Flat => g.occupy_where(|_, y| y < s),
        }
        // A square or disc narrower than the cells' spacing, centred between cells (on the
        // shifted middle row of a hex lattice), holds at least the cell nearest its centre:
        // a seed of one cell, as a point.
        if g.occupied() == 0 && matches!(self.shape, Shape::Square | Shape::Disc) {
            let c = g.lattice().nearest_cell(cx, cy);
            g.occupy(c)?;
        }
        if g.occupied() == 0 {
            return Err(range(
                "start",
                s,
                format!(
                    "an initial {} that holds a cell of the lattice: make it larger",
                    self.shape.name()
                ),
            ));
        }
        Ok(g)
    }
}

/// Why a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The clock reached `steps`.
    Completed,
    /// No surface site is left (the lattice filled up); the state is final.
    LatticeFull,
    /// Every surface site has probability 0; the clock ran to `steps` with no growth.
    Stalled,
    /// The next acceptance lies beyond the largest representable timestep.
    ClockOverflow,
    /// The requested number of accepted events was reached (`events`).
    Events,
    /// The requested occupied fraction was reached (`until_occupied`).
    Occupied,
}

impl StopReason {
    /// A few words for titles: `lattice full`, `events reached`, ...
    pub fn describe(self) -> &'static str {
        match self {
            StopReason::Completed => "steps reached",
            StopReason::LatticeFull => "lattice full",
            StopReason::Stalled => "stalled",
            StopReason::ClockOverflow => "clock overflow",
            StopReason::Events => "events reached",
            StopReason::Occupied => "occupied fraction reached",
        }
    }

    /// Whether the state is final before the clock limit: nothing can change it any more
    /// and the clock stops (unlike a stalled run, whose clock still runs to its limit).
    fn is_final(self) -> bool {
        matches!(self, StopReason::LatticeFull | StopReason::ClockOverflow)
    }
}

/// Values of the scene's observables at one time (`None` where not defined).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Observables {
    /// Coefficient of variation of the front radius over angle (flame, grow).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub front_radius_cv: Option<f64>,
    /// Extent along the axes over extent along the diagonals (crystal, ca, grow).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub axis_diagonal_ratio: Option<f64>,
    /// Amplitude of the first Fourier mode of the surface height (deposit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mode1_amplitude: Option<f64>,
    /// Mean surface elevation (deposit), cell widths above the lattice's floor (the hex
    /// lattice's rows are sqrt(3)/2 apart).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mean_elevation: Option<f64>,
}

/// Observables at one time of the run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Observation {
    /// Timestep (`inf` once an unbounded run's clock passed the largest `f64`).
    pub time: f64,
    /// Base-10 log of the timestep, finite however far the clock went (`-inf` at 0).
    #[serde(skip)]
    pub log10_time: f64,
    /// Accepted events so far.
    pub accepted: u64,
    /// Occupied cells.
    pub occupied: usize,
    /// Surface sites.
    pub surface: usize,
    /// The observables.
    #[serde(flatten)]
    pub values: Observables,
}

/// The lattice at one timestep, in drawing states (0 empty, 1 surface, 2 occupied).
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// Timestep (`inf` once an unbounded run's clock passed the largest `f64`).
    pub time: f64,
    /// Base-10 log of the timestep, finite however far the clock went (`-inf` at 0).
    pub log10_time: f64,
    /// Drawing state per cell, `y * width + x`.
    pub states: Vec<u8>,
    /// The requested snapshot times that the run did not reach because it stopped first
    /// (the lattice full, or an event target reached): this final state is drawn once in
    /// their place. Empty for a snapshot at its own time.
    pub unreached: Vec<u64>,
}

/// Everything a run produced.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// The configuration that ran.
    pub config: SceneConfig,
    /// Snapshots at the configured times.
    pub snapshots: Vec<Snapshot>,
    /// Observables at evenly spaced times (the first at time 0).
    pub series: Vec<Observation>,
    /// The final observation.
    pub last: Observation,
    /// Why the run ended.
    pub stop: StopReason,
    /// Seconds spent building the initial state.
    pub setup_s: f64,
    /// Seconds spent running (sampling and observing).
    pub elapsed_s: f64,
    /// Of `elapsed_s`, seconds spent observing (series, snapshots, the hooks' frames, the
    /// final observables).
    pub observe_s: f64,
    /// True when the final clock is an exact whole number of timesteps (at most `2^53`).
    pub clock_exact: bool,
    /// Base-10 log of the final clock: finite even past the largest `f64`.
    pub log10_clock: f64,
    /// Bytes held by the run's state.
    pub memory_bytes: usize,
}

/// Called during a run: progress, and optional extra frames (e.g. an animation).
pub trait RunHooks {
    /// The clock reached `time` of `steps`.
    fn progress(&mut self, _time: f64, _steps: f64) {}
    /// Times (besides snapshots) at which [`RunHooks::frame`] should be called.
    fn frame_times(&self) -> Vec<f64> {
        Vec::new()
    }
    /// The state at one of the frame times.
    fn frame(&mut self, _time: f64, _g: &Growth) {}
    /// Runs stopped by `events` or `until_occupied`: the number of evenly spaced event
    /// counts at which [`RunHooks::frame`] is called (instead of [`RunHooks::frame_times`]).
    fn frame_count(&self) -> usize {
        0
    }
    /// Whether the observables time series is wanted (it costs a pass over the lattice per
    /// point); the result's `series` then holds only the start when not.
    fn wants_series(&self) -> bool {
        true
    }
    /// Whether snapshots of the lattice are wanted.
    fn wants_snapshots(&self) -> bool {
        true
    }
}

/// Hooks that do nothing.
pub struct NoHooks;
impl RunHooks for NoHooks {}

/// Measures the scene's observables on a state.
pub fn observe(cfg: &SceneConfig, g: &Growth) -> Observation {
    let centre = cfg.centre(g.lattice());
    let mut v = Observables::default();
    let profile = matches!(cfg.shape, Shape::Cosine | Shape::Flat);
    match cfg.scene {
        SceneKind::Flame => v.front_radius_cv = observe::front_radius_cv(g, centre, 36),
        SceneKind::Crystal | SceneKind::Ca => {
            v.axis_diagonal_ratio = observe::axis_diagonal_ratio(g, centre)
        }
        SceneKind::Deposit => {}
        SceneKind::Grow if !profile => {
            v.front_radius_cv = observe::front_radius_cv(g, centre, 36);
            v.axis_diagonal_ratio = observe::axis_diagonal_ratio(g, centre);
        }
        SceneKind::Grow => {}
    }
    if cfg.scene == SceneKind::Deposit || (cfg.scene == SceneKind::Grow && profile) {
        let p = ColumnProfile::of(g);
        v.mode1_amplitude = Some(p.mode1_amplitude());
        v.mean_elevation = Some(p.mean());
    }
    Observation {
        time: g.time(),
        log10_time: g.log10_time(),
        accepted: g.accepted(),
        occupied: g.occupied(),
        surface: g.surface().len(),
        values: v,
    }
}

/// Number of progress checkpoints in every run (fixed, so that they never change results).
const PROGRESS_TICKS: u64 = 100;

/// Runs a scene. The result depends only on the configuration (not on hooks, progress or
/// frames): the exact sampler keeps its next acceptance across pauses.
///
/// With `events` or `until_occupied` the run stops at the first of those and `steps` (see
/// [`SceneConfig::steps`]); its checkpoints (series, progress) are then spaced in accepted
/// events, and the final state is the last snapshot.
pub fn run(cfg: &SceneConfig, hooks: &mut dyn RunHooks) -> Result<RunResult, SceneError> {
    let t0 = Instant::now();
    let mut g = cfg.build()?;
    let setup_s = t0.elapsed().as_secs_f64();
    let target = event_target(cfg, &g)?;
    let t1 = Instant::now();
    let mut rng = crate::engine::rng::stream(cfg.seed);
    let mut observe_s = 0.0;
    let (snapshots, series, stop) = match target {
        None => run_by_clock(cfg, &mut g, &mut rng, hooks, &mut observe_s),
        Some(t) => run_by_events(cfg, &mut g, &mut rng, hooks, t, &mut observe_s),
    };
    let t2 = Instant::now();
    let last = observe(cfg, &g);
    observe_s += t2.elapsed().as_secs_f64();
    Ok(RunResult {
        config: cfg.clone(),
        snapshots,
        series,
        last,
        stop,
        setup_s,
        elapsed_s: t1.elapsed().as_secs_f64(),
        observe_s,
        memory_bytes: g.memory_bytes(),
        clock_exact: g.time_exact(),
        log10_clock: g.log10_time(),
    })
}

/// The accepted-event count at which an event-stopped run ends, and why; `None` for a run
/// stopped by its clock alone.
fn event_target(cfg: &SceneConfig, g: &Growth) -> Result<Option<(u64, StopReason)>, SceneError> {
    let mut t: Option<(u64, StopReason)> = cfg.events.map(|e| (e, StopReason::Events));
    if let Some(f) = cfg.until_occupied {
        let cells = g.lattice().len();
        // The least whole count `k` with `k / cells >= f`: the product `f * cells` can lie
        // an ulp above a whole number (0.07 x 100 = 7.000000000000001), whose ceiling would
        // ask for one cell more.
        let mut want = (f * cells as f64).ceil() as usize;
        if want > 0 && (want - 1) as f64 / cells as f64 >= f {
            want -= 1;
        }
        if want <= g.occupied() {
            return Err(range(
                "until_occupied",
                f,
                format!(
                    "above the initial occupied fraction {:.6} ({} of {} cells) and at most 1",
                    g.occupied() as f64 / cells as f64,
                    g.occupied(),
                    cells
                ),
            ));
        }
        let e = (want - g.occupied()) as u64;
        if t.is_none_or(|(x, _)| e < x) {
            t = Some((e, StopReason::Occupied));
        }
    }
    Ok(t)
}

type Recorded = (Vec<Snapshot>, Vec<Observation>, StopReason);

/// The run stopped by its clock: checkpoints at snapshot, series, progress and frame times.
fn run_by_clock(
    cfg: &SceneConfig,
    g: &mut Growth,
    rng: &mut crate::engine::rng::Stream,
    hooks: &mut dyn RunHooks,
    observe_s: &mut f64,
) -> Recorded {
    let steps = cfg.steps as f64;
    // Checkpoints: snapshots, series points, progress ticks and frames.
    // (whole timesteps: a series longer than the run has one point per timestep)
    let series_times: Vec<f64> = if hooks.wants_series() {
        let mut t: Vec<f64> = (1..=cfg.series as u64)
            .map(|k| (cfg.steps as u128 * k as u128 / cfg.series as u128) as f64)
            .filter(|&t| t > 0.0)
            .collect();
        t.dedup();
        t
    } else {
        Vec::new()
    };
    let snap_times: &[u64] = if hooks.wants_snapshots() {
        &cfg.snapshots
    } else {
        &[]
    };
    let frames = hooks.frame_times();
    let mut checkpoints: Vec<f64> = snap_times.iter().map(|&t| t as f64).collect();
    checkpoints.extend(&series_times);
    checkpoints.extend(
        (1..=PROGRESS_TICKS)
            .map(|k| (cfg.steps as u128 * k as u128 / PROGRESS_TICKS as u128) as f64),
    );
    checkpoints.extend(frames.iter().copied().filter(|&t| t >= 0.0 && t <= steps));
    checkpoints.push(0.0);
    checkpoints.push(steps);
    checkpoints.sort_by(f64::total_cmp);
    checkpoints.dedup();

    let mut snapshots: Vec<Snapshot> = Vec::new();
    let t = Instant::now();
    let mut series = vec![observe(cfg, g)];
    *observe_s += t.elapsed().as_secs_f64();
    let mut stop = StopReason::Completed;
    let mut next_snap = 0;
    let mut next_series = 0;
    let mut next_frame = 0;
    // Accepted events at the last frame drawn (the state it shows).
    let mut frame_at = None;
    for &cp in &checkpoints {
        if stop == StopReason::Completed || stop == StopReason::Stalled {
            stop = stop_of(advance(cfg, g, rng, cp, u64::MAX), stop);
        }
        let t = Instant::now();
        if stop.is_final() {
            // The state is final (the lattice full) and the clock has stopped before `cp`:
            // what is left of the series and the snapshots is this state, recorded once.
            if !series_times.is_empty() {
                push_final_observation(cfg, g, &mut series);
            }
            if next_snap < snap_times.len() {
                push_final_snapshot(g, &mut snapshots, &snap_times[next_snap..]);
            }
            *observe_s += t.elapsed().as_secs_f64();
            if next_frame < frames.len() && frame_at != Some(g.accepted()) {
                timed(observe_s, || hooks.frame(g.time(), g));
            }
            break;
        }
        while next_snap < snap_times.len() && snap_times[next_snap] as f64 <= cp {
            snapshots.push(Snapshot {
                time: cp,
                log10_time: cp.log10(),
                states: g.field_states(),
                unreached: Vec::new(),
            });
            next_snap += 1;
        }
        while next_series < series_times.len() && series_times[next_series] <= cp {
            series.push(observe(cfg, g));
            next_series += 1;
        }
        *observe_s += t.elapsed().as_secs_f64();
        while next_frame < frames.len() && frames[next_frame] <= cp {
            timed(observe_s, || hooks.frame(frames[next_frame], g));
            frame_at = Some(g.accepted());
            next_frame += 1;
        }
        hooks.progress(g.time().min(steps), steps);
    }
    if stop.is_final() && cfg.sampler == SamplerKind::Ca && !series_times.is_empty() {
        let t = Instant::now();
        if let Some(s) = ca_series_replay(cfg, g.time()) {
            series = s;
        }
        *observe_s += t.elapsed().as_secs_f64();
    }
    (snapshots, series, stop)
}

/// Runs `f` (a hook's frame: drawing and encoding it), adding its time to `observe_s`, so
/// that the sampling rate counts the sampling alone.
fn timed(observe_s: &mut f64, f: impl FnOnce()) {
    let t = Instant::now();
    f();
    *observe_s += t.elapsed().as_secs_f64();
}

/// Appends the observation of the final state to `series`, unless its last point already is
/// that state at that time.
fn push_final_observation(cfg: &SceneConfig, g: &Growth, series: &mut Vec<Observation>) {
    if series
        .last()
        .is_none_or(|o| o.accepted != g.accepted() || o.time != g.time())
    {
        series.push(observe(cfg, g));
    }
}

/// Draws the final state once in place of the requested snapshot times `pending` (those not
/// taken yet); the times it did not reach (all but the final time itself) are recorded in its
/// `unreached`. A snapshot that already shows the final state at its time takes them instead
/// of a second panel.
fn push_final_snapshot(g: &Growth, snapshots: &mut Vec<Snapshot>, pending: &[u64]) {
    let unreached: Vec<u64> = pending
        .iter()
        .copied()
        .filter(|&t| t as f64 != g.time())
        .collect();
    match snapshots.last_mut() {
        Some(s) if s.time == g.time() => s.unreached.extend(unreached),
        _ => snapshots.push(Snapshot {
            time: g.time(),
            log10_time: g.log10_time(),
            states: g.field_states(),
            unreached,
        }),
    }
}

/// The series of a CA run that stopped for good (the lattice full) at update `end`, before
/// its clock limit: the CA is deterministic, so it is run again from the start and observed
/// at `series` evenly spaced updates of the `end` it ran (every update when there are at
/// most `series` of them), not at the times of a run it never finished. `None` if the
/// replay does not end in the same state (it always should).
fn ca_series_replay(cfg: &SceneConfig, end: f64) -> Option<Vec<Observation>> {
    let mut g = cfg.build().ok()?;
    let mut rng = crate::engine::rng::stream(cfg.seed);
    let end = end as u64;
    let mut times: Vec<u64> = (1..=cfg.series as u64)
        .map(|k| (end as u128 * k as u128 / cfg.series as u128) as u64)
        .filter(|&t| t > 0)
        .collect();
    times.dedup();
    let mut series = vec![observe(cfg, &g)];
    for t in times {
        advance(cfg, &mut g, &mut rng, t as f64, u64::MAX);
        series.push(observe(cfg, &g));
    }
    (g.time() == end as f64 && g.surface().is_empty()).then_some(series)
}

/// The stop reason after an [`advance`] that ended with `o` (the run so far: `stop`).
fn stop_of(o: Outcome, stop: StopReason) -> StopReason {
    match o {
        Outcome::Exhausted => StopReason::LatticeFull,
        Outcome::Stalled => StopReason::Stalled,
        Outcome::ClockOverflow => StopReason::ClockOverflow,
        _ => stop,
    }
}

/// The run stopped after `target.0` accepted events (or by its clock or a full lattice
/// first): checkpoints at evenly spaced event counts; snapshots at their times while the
/// clock passes them, and the final state.
fn run_by_events(
    cfg: &SceneConfig,
    g: &mut Growth,
    rng: &mut crate::engine::rng::Stream,
    hooks: &mut dyn RunHooks,
    target: (u64, StopReason),
    observe_s: &mut f64,
) -> Recorded {
    let (events, reason) = target;
    // steps = 0: no clock limit (refused for the rejection sampler by validate).
    let limit = match cfg.steps {
        0 => f64::INFINITY,
        s => s as f64,
    };
    g.allow_log_clock(limit.is_infinite());
    let ticks = if hooks.wants_series() {
        cfg.series as u64
    } else {
        0
    };
    let spaced = |n: u64| (1..=n).map(move |k| (events as u128 * k as u128 / n as u128) as u64);
    let frames: Vec<u64> = spaced(hooks.frame_count() as u64).collect();
    let mut checkpoints: Vec<u64> = spaced(ticks)
        .chain(spaced(PROGRESS_TICKS))
        .chain(frames.iter().copied())
        .filter(|&e| e > 0)
        .collect();
    checkpoints.push(events);
    checkpoints.sort_unstable();
    checkpoints.dedup();
    // (one point per event at most)
    let mut series_at: Vec<u64> = spaced(ticks).filter(|&e| e > 0).collect();
    series_at.dedup();
    let snap_times: Vec<u64> = if hooks.wants_snapshots() {
        cfg.snapshots.clone()
    } else {
        Vec::new()
    };
    let start = g.accepted();
    let mut snapshots = Vec::new();
    let t = Instant::now();
    let mut series = vec![observe(cfg, g)];
    *observe_s += t.elapsed().as_secs_f64();
    let mut next_snap = 0;
    let mut next_series = 0;
    let mut next_frame = 0;
    let mut stop = reason;
    // Accepted events at the last frame drawn (the state it shows).
    let mut frame_at = None;
    if !frames.is_empty() {
        timed(observe_s, || hooks.frame(g.time(), g));
        frame_at = Some(g.accepted());
    }
    'run: for &cp in &checkpoints {
        loop {
            let snap_at = snap_times.get(next_snap).map(|&t| t as f64);
            let lim = snap_at.map_or(limit, |t| t.min(limit));
            let o = advance(cfg, g, rng, lim, start + cp);
            let s = stop_of(o, StopReason::Completed);
            if s != StopReason::Completed {
                stop = s;
                break 'run;
            }
            if g.accepted() >= start + cp {
                break;
            }
            // The clock reached `lim`: a snapshot time, or the clock limit.
            if snap_at.is_some_and(|t| t <= g.time()) {
                let t = Instant::now();
                snapshots.push(Snapshot {
                    time: g.time(),
                    log10_time: g.log10_time(),
                    states: g.field_states(),
                    unreached: Vec::new(),
                });
                *observe_s += t.elapsed().as_secs_f64();
                next_snap += 1;
            } else {
                stop = StopReason::Completed;
                break 'run;
            }
        }
        // (the CA adds many cells per update: several event counts can fall on one state,
        // which is recorded once)
        let t = Instant::now();
        if next_series < series_at.len() && series_at[next_series] <= cp {
            push_final_observation(cfg, g, &mut series);
        }
        while next_series < series_at.len() && series_at[next_series] <= cp {
            next_series += 1;
        }
        *observe_s += t.elapsed().as_secs_f64();
        if next_frame < frames.len() && frames[next_frame] <= cp && frame_at != Some(g.accepted()) {
            timed(observe_s, || hooks.frame(g.time(), g));
            frame_at = Some(g.accepted());
        }
        while next_frame < frames.len() && frames[next_frame] <= cp {
            next_frame += 1;
        }
        hooks.progress((g.accepted() - start) as f64, events as f64);
    }
    // The final state, once: the run may have stopped (its clock limit, the lattice full)
    // between two checkpoints.
    let t = Instant::now();
    if hooks.wants_series() {
        push_final_observation(cfg, g, &mut series);
    }
    if hooks.wants_snapshots() {
        push_final_snapshot(g, &mut snapshots, &snap_times[next_snap..]);
    }
    *observe_s += t.elapsed().as_secs_f64();
    if !frames.is_empty() && frame_at != Some(g.accepted()) {
        timed(observe_s, || hooks.frame(g.time(), g));
    }
    // A count reached by the event that filled the lattice: the state is final, which says
    // more (the CA, adding whole updates, can pass the count on its last update).
    if matches!(stop, StopReason::Events | StopReason::Occupied) && g.surface().is_empty() {
        stop = StopReason::LatticeFull;
    }
    (snapshots, series, stop)
}

/// Advances the run to time `limit`, or until `accepted` events, with the configured sampler.
fn advance(
    cfg: &SceneConfig,
    g: &mut Growth,
    rng: &mut crate::engine::rng::Stream,
    limit: f64,
    accepted: u64,
) -> Outcome {
    if g.time() >= limit && limit.is_finite() {
        return Outcome::Limit;
    }
    match cfg.sampler {
        SamplerKind::Rejection => g.run_rejection_until(rng, limit, accepted),
        SamplerKind::Exact => g.run_exact_until(rng, limit, accepted),
        SamplerKind::Ca => {
            // The CA is deterministic: once a whole cycle of its rules adds no cell, no later
            // step will (no cell can reach its threshold), and the run has stalled.
            let period = cfg.ca_rule.len();
            let mut idle = 0;
            while g.time() < limit && g.accepted() < accepted {
                if g.surface().is_empty() {
                    return Outcome::Exhausted;
                }
                let k = g.time() as usize % period;
                if g.step_ca(cfg.ca_rule[k]) > 0 {
                    idle = 0;
                } else {
                    idle += 1;
                    if idle >= period {
                        if limit.is_finite() {
                            g.time = limit;
                        }
                        return Outcome::Stalled;
                    }
                }
            }
            Outcome::Limit
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weight_names_parse_back() {
        for w in [WeightKind::None, WeightKind::Axes] {
            assert_eq!(w.to_string().parse::<WeightKind>(), Ok(w));
        }
    }

    #[test]
    fn defaults_are_valid() {
        for s in [
            SceneKind::Flame,
            SceneKind::Deposit,
            SceneKind::Crystal,
            SceneKind::Ca,
            SceneKind::Grow,
        ] {
            SceneConfig::defaults(s).validate().unwrap();
        }
    }

    #[test]
    fn toml_round_trip_and_overrides() {
        let c = SceneConfig::from_toml("scene = \"flame\"\nn = 3.5\nseed = 9\n").unwrap();
        assert_eq!(c.n, 3.5);
        assert_eq!(c.seed, 9);
        assert_eq!(c.width, SceneConfig::defaults(SceneKind::Flame).width);
        let back = SceneConfig::from_toml(&c.to_toml()).unwrap();
        assert_eq!(back, c);
    }

    #[test]
    fn a_scenario_with_steps_alone_keeps_the_default_snapshots_within_them() {
        // Alone, a file's steps = 100 is out of reach of the default snapshots (up to 50,000):
        // they are fitted to the run, as --steps fits them.
        let (c, given) = SceneConfig::parse_toml("scene = \"flame\"\nsteps = 100\n").unwrap();
        assert_eq!(
            given,
            Given {
                snapshots: false,
                series: false
            }
        );
        let (_, given) =
            SceneConfig::parse_toml("scene = \"flame\"\nseries = 7\nsnapshots = [5]\n").unwrap();
        assert!(given.snapshots && given.series);
        assert_eq!(c.snapshots.last(), Some(&100));
        assert!(c.snapshots.iter().all(|&t| t <= 100));
        c.validate().unwrap();
        // Snapshots the file gives are its own, checked as they are.
        let e = SceneConfig::from_toml("scene = \"flame\"\nsteps = 100\nsnapshots = [500]\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("snapshots = 500"), "{e}");
        // A value out of range in the file is only refused once nothing overrides it.
        let (mut c, _) = SceneConfig::parse_toml("scene = \"flame\"\nn = -1.0\n").unwrap();
        assert!(c.validate().is_err());
        c.n = 2.0;
        c.validate().unwrap();
    }

    #[test]
    fn a_ca_that_can_never_grow_stalls_at_once() {
        // Rule 2 from one seed cell: every surface site has one occupied neighbour, so no
        // synchronous update ever adds a cell. An event target must not spin for ever.
        let mut c = SceneConfig::defaults(SceneKind::Ca);
        c.ca_rule = vec![2];
        c.events = Some(5);
        c.steps = 0;
        c.snapshots.clear();
        let r = run(&c, &mut NoHooks).unwrap();
        assert_eq!(r.stop, StopReason::Stalled);
        assert_eq!(r.last.accepted, 0);
        // With a clock limit the clock is moved to it, as the exact sampler does.
        let mut c = SceneConfig::defaults(SceneKind::Ca);
        c.ca_rule = vec![2];
        c.steps = 1_000_000_000;
        c.snapshots = vec![1_000_000_000];
        let t = std::time::Instant::now();
        let r = run(&c, &mut NoHooks).unwrap();
        assert!(t.elapsed().as_secs_f64() < 5.0);
        assert_eq!(r.stop, StopReason::Stalled);
        assert_eq!(r.last.time, 1e9);
        // Alternating rules 1, 2 grow: a step that adds nothing under rule 2 is not a stall.
        let mut c = SceneConfig::defaults(SceneKind::Ca);
        c.ca_rule = vec![1, 2];
        let r = run(&c, &mut NoHooks).unwrap();
        assert!(r.last.accepted > 0);
    }

    #[test]
    fn series_and_snapshots_never_repeat_a_time() {
        // A series longer than the run: one point per timestep, none twice.
        let mut c = SceneConfig::defaults(SceneKind::Grow);
        c.width = 32;
        c.height = 32;
        c.steps = 10;
        c.snapshots = vec![10];
        c.series = 1000;
        let r = run(&c, &mut NoHooks).unwrap();
        let times: Vec<f64> = r.series.iter().map(|o| o.time).collect();
        assert_eq!(times, (0..=10).map(f64::from).collect::<Vec<_>>());
        // Per event, likewise.
        c.steps = 0;
        c.events = Some(5);
        c.snapshots.clear();
        let r = run(&c, &mut NoHooks).unwrap();
        let acc: Vec<u64> = r.series.iter().map(|o| o.accepted).collect();
        assert_eq!(acc, vec![0, 1, 2, 3, 4, 5]);
        // An event run stopped by its clock at a snapshot time draws that state once.
        c.steps = 50;
        c.events = Some(100_000);
        c.snapshots = vec![50];
        let r = run(&c, &mut NoHooks).unwrap();
        assert_eq!(r.stop, StopReason::Completed);
        assert_eq!(r.snapshots.len(), 1);
    }

    /// Hooks that record the accepted events of every frame drawn.
    struct Frames {
        times: Vec<f64>,
        count: usize,
        drawn: Vec<u64>,
    }
    impl RunHooks for Frames {
        fn frame_times(&self) -> Vec<f64> {
            self.times.clone()
        }
        fn frame_count(&self) -> usize {
            self.count
        }
        fn frame(&mut self, _time: f64, g: &Growth) {
            self.drawn.push(g.accepted());
        }
    }

    /// Hooks whose every frame takes `pause` (drawing and encoding, as a GIF's do).
    struct SlowFrames {
        times: Vec<f64>,
        count: usize,
        pause: std::time::Duration,
        drawn: usize,
    }
    impl RunHooks for SlowFrames {
        fn frame_times(&self) -> Vec<f64> {
            self.times.clone()
        }
        fn frame_count(&self) -> usize {
            self.count
        }
        fn frame(&mut self, _time: f64, _g: &Growth) {
            std::thread::sleep(self.pause);
            self.drawn += 1;
        }
    }

    #[test]
    fn the_hooks_frames_count_as_observing_not_sampling() {
        // Runs stopped by their clock and by events: every frame's time is in observe_s, so
        // the sampling time (elapsed_s - observe_s) and the rate reported from it do not
        // depend on the frames asked for.
        let pause = std::time::Duration::from_millis(20);
        let mut by_clock = SceneConfig::defaults(SceneKind::Flame);
        by_clock.steps = 2000;
        by_clock.snapshots = Vec::new();
        let mut by_events = by_clock.clone();
        by_events.steps = 0;
        by_events.events = Some(500);
        for (c, times, count) in [
            (&by_clock, vec![0.0, 500.0, 1000.0, 2000.0], 0),
            (&by_events, Vec::new(), 4),
        ] {
            let mut h = SlowFrames {
                times,
                count,
                pause,
                drawn: 0,
            };
            let r = run(c, &mut h).unwrap();
            assert!(h.drawn >= 4, "{}", h.drawn);
            let frames_s = h.drawn as f64 * pause.as_secs_f64();
            assert!(r.observe_s >= frames_s, "{} < {frames_s}", r.observe_s);
            assert!(r.elapsed_s - r.observe_s < frames_s / 2.0, "{r:?}");
        }
    }

    /// A 6 x 6 square torus from a seed cell: it fills within a few hundred timesteps.
    fn filling(sampler: SamplerKind) -> SceneConfig {
        let mut c = SceneConfig::defaults(SceneKind::Grow);
        c.lattice = Neighbourhood::Square4;
        c.width = 6;
        c.height = 6;
        c.sampler = sampler;
        c.steps = 1000;
        c.snapshots = vec![5, 500, 1000];
        c.series = 50;
        c
    }

    /// The series holds each state once, in order, and ends at the final state.
    fn assert_series_ends_once(r: &RunResult) {
        for w in r.series.windows(2) {
            assert!(
                w[1].time > w[0].time || w[1].accepted > w[0].accepted,
                "{:?} repeats {:?}",
                w[1],
                w[0]
            );
        }
        let end = r.series.last().unwrap();
        assert_eq!((end.time, end.accepted), (r.last.time, r.last.accepted));
    }

    #[test]
    fn a_run_that_fills_its_lattice_records_its_final_state_once() {
        for sampler in [SamplerKind::Exact, SamplerKind::Rejection] {
            let r = run(&filling(sampler), &mut NoHooks).unwrap();
            assert_eq!(r.stop, StopReason::LatticeFull, "{sampler}");
            assert!(r.last.time < 500.0, "{sampler}: {}", r.last.time);
            assert_series_ends_once(&r);
            // The snapshot at 5, then the final state once for 500 and 1000.
            let times: Vec<f64> = r.snapshots.iter().map(|s| s.time).collect();
            assert_eq!(times, vec![5.0, r.last.time], "{sampler}");
            assert!(r.snapshots[0].unreached.is_empty());
            assert_eq!(r.snapshots[1].unreached, vec![500, 1000]);
            assert!(r.snapshots[1].states.iter().all(|&s| s == 2));
            // The animation ends at the final state, drawn once.
            let mut h = Frames {
                times: (0..=20).map(|k| f64::from(k) * 50.0).collect(),
                count: 0,
                drawn: Vec::new(),
            };
            run(&filling(sampler), &mut h).unwrap();
            assert_eq!(h.drawn.last(), Some(&r.last.accepted));
            let finals = h.drawn.iter().filter(|&&a| a == r.last.accepted).count();
            assert_eq!(finals, 1, "{:?}", h.drawn);
        }
        // The CA fills the torus in a few updates: its series has every one of them, spaced
        // over the run it made rather than the 1000 it was given.
        let r = run(&filling(SamplerKind::Ca), &mut NoHooks).unwrap();
        assert_eq!(r.stop, StopReason::LatticeFull);
        let end = r.last.time as u64;
        assert!((2..50).contains(&end), "{end}");
        let times: Vec<f64> = r.series.iter().map(|o| o.time).collect();
        assert_eq!(times, (0..=end).map(|t| t as f64).collect::<Vec<_>>());
        assert_series_ends_once(&r);
        let times: Vec<f64> = r.snapshots.iter().map(|s| s.time).collect();
        assert_eq!(times, vec![5.0, r.last.time]);
        assert_eq!(r.snapshots[1].unreached, vec![500, 1000]);
        // The same state reached by a run that is not replayed: the CA's updates up to `end`.
        let mut c = filling(SamplerKind::Ca);
        c.steps = end;
        c.snapshots = vec![end];
        c.series = end as usize;
        let whole = run(&c, &mut NoHooks).unwrap();
        assert_eq!(whole.series, r.series);
        // Longer than the series: 50 points evenly spaced over the updates it ran.
        let mut c = filling(SamplerKind::Ca);
        c.width = 200;
        c.height = 6;
        c.steps = 10_000;
        c.snapshots.clear();
        c.series = 10;
        let r = run(&c, &mut NoHooks).unwrap();
        assert_eq!(r.stop, StopReason::LatticeFull);
        let end = r.last.time as u64;
        let times: Vec<u64> = r.series.iter().map(|o| o.time as u64).collect();
        let expect: Vec<u64> = (0..=10).map(|k| end * k / 10).collect();
        assert_eq!(times, expect);
    }

    #[test]
    fn an_event_run_records_its_final_state_once() {
        // Stopped by a full lattice before its event target.
        let mut c = filling(SamplerKind::Exact);
        c.events = Some(1000);
        c.snapshots.clear();
        let mut h = Frames {
            times: Vec::new(),
            count: 60,
            drawn: Vec::new(),
        };
        let r = run(&c, &mut h).unwrap();
        assert_eq!(r.stop, StopReason::LatticeFull);
        assert_series_ends_once(&r);
        assert_eq!(h.drawn.last(), Some(&r.last.accepted));
        assert!(h.drawn.windows(2).all(|w| w[1] > w[0]), "{:?}", h.drawn);
        // Stopped by its clock between two event checkpoints: a last row at the clock limit.
        let mut c = SceneConfig::defaults(SceneKind::Grow);
        c.width = 20;
        c.height = 20;
        c.events = Some(100);
        c.steps = 300;
        c.snapshots.clear();
        let r = run(&c, &mut NoHooks).unwrap();
        assert_eq!(r.stop, StopReason::Completed);
        assert_eq!(r.last.time, 300.0);
        assert_series_ends_once(&r);
        // The CA adds many cells per update: an update that passes several event counts is
        // one row and one frame.
        let mut c = SceneConfig::defaults(SceneKind::Ca);
        c.events = Some(5);
        c.steps = 0;
        c.snapshots.clear();
        let mut h = Frames {
            times: Vec::new(),
            count: 5,
            drawn: Vec::new(),
        };
        let r = run(&c, &mut h).unwrap();
        assert_series_ends_once(&r);
        assert_eq!(r.series.len(), r.last.time as usize + 1);
        assert_eq!(h.drawn.len(), r.last.time as usize + 1);
        assert!(h.drawn.windows(2).all(|w| w[1] > w[0]), "{:?}", h.drawn);
        // A snapshot the event target came before: the final state, saying so.
        let mut c = SceneConfig::defaults(SceneKind::Grow);
        c.width = 20;
        c.height = 20;
        c.events = Some(10);
        c.steps = 1000;
        c.snapshots = vec![1000];
        let r = run(&c, &mut NoHooks).unwrap();
        assert_eq!(r.stop, StopReason::Events);
        assert_eq!(r.snapshots.len(), 1);
        assert_eq!(r.snapshots[0].time, r.last.time);
        assert_eq!(r.snapshots[0].unreached, vec![1000]);
    }

    #[test]
    fn a_default_disc_sits_on_the_middle_cell_of_an_odd_lattice() {
        for (lattice, w, h) in [
            (Neighbourhood::Square4, 21, 21),
            (Neighbourhood::Square8, 21, 20),
            (Neighbourhood::Square4, 20, 21),
            (Neighbourhood::Hex, 21, 20),
            (Neighbourhood::Hex, 21, 22),
        ] {
            let mut c = SceneConfig::defaults(SceneKind::Grow);
            c.lattice = lattice;
            c.width = w;
            c.height = h;
            c.shape = Shape::Disc;
            let g = c.build().unwrap();
            assert_eq!(g.occupied(), 1, "{lattice} {w}x{h}");
            let l = g.lattice();
            let (cx, cy) = c.centre(l);
            let (pw, ph) = l.physical_size();
            if w % 2 == 1 {
                assert_eq!(cx, l.position_xy(w / 2, h / 2).0, "{lattice} {w}x{h}");
            } else {
                assert_eq!(cx, pw / 2.0);
            }
            if h % 2 == 1 {
                assert_eq!(cy, (h / 2) as f64);
            } else {
                assert_eq!(cy, ph / 2.0);
            }
            // A disc of 5 cell widths on a square lattice: the same cells either side of the
            // centre, so symmetric about the lattice's middle on an odd side.
            c.start = 5.0;
            let g = c.build().unwrap();
            if lattice == Neighbourhood::Square4 && w % 2 == 1 && h % 2 == 1 {
                let states = g.field_states();
                for y in 0..h {
                    for x in 0..w {
                        assert_eq!(states[y * w + x], states[(h - 1 - y) * w + (w - 1 - x)]);
                    }
                }
            }
        }
        // Even sizes keep half the extent, as before.
        let c = SceneConfig::defaults(SceneKind::Flame);
        let l = Lattice::new(c.lattice, c.width, c.height, c.boundary).unwrap();
        let (pw, ph) = l.physical_size();
        assert_eq!(c.centre(&l), (pw / 2.0, ph / 2.0));
    }

    #[test]
    fn a_scenario_takes_whole_floats_for_counts() {
        let c = SceneConfig::from_toml(
            "scene = \"grow\"\nsteps = 1e4\nsnapshots = [1e3, 1e4]\nwidth = 64.0\nseed = 7.0\n",
        )
        .unwrap();
        assert_eq!(c.steps, 10_000);
        assert_eq!(c.snapshots, vec![1000, 10_000]);
        assert_eq!((c.width, c.seed), (64, 7));
        for (text, needle) in [
            ("steps = 1.5", "`steps` = 1.5: expected a whole number"),
            ("snapshots = [10, 2.5]", "`snapshots` = 2.5"),
            ("events = -1e3", "`events` = -1000"),
            // a seed past every count, as written (its range is what a file holds)
            (
                "seed = 1e30",
                "`seed` = 1e30: expected a whole number from 0 to 2^63 - 1",
            ),
            // past every count: the key's own range, the value as written
            (
                "series = 1e30",
                "series = 1e30 is out of range: expected 1 to 100000",
            ),
            (
                "steps = inf",
                "steps = inf is out of range: expected 1 to 9007199254740992",
            ),
            // in a list too, with the words the option's parser states
            (
                "snapshots = [1, 1e30]",
                "snapshots = 1e30 is out of range: expected timesteps of at most steps",
            ),
            (
                "ca_rule = [inf]",
                "ca_rule = inf is out of range: expected neighbour counts",
            ),
        ] {
            let e = SceneConfig::from_toml(&format!("scene = \"grow\"\n{text}\n"))
                .unwrap_err()
                .to_string();
            assert!(e.contains(needle), "{text}: {e}");
            assert!(!e.contains('\n'), "{text}: {e}");
        }
    }

    #[test]
    fn a_flat_layer_leaves_the_top_row_empty() {
        // On a 32-row hex lattice the rows sit 0.866 apart: the top row at 26.85.
        let mut c = SceneConfig::defaults(SceneKind::Grow);
        c.width = 32;
        c.height = 32;
        c.shape = Shape::Flat;
        c.start = 27.7;
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains("start = 27.7") && e.contains("top row"), "{e}");
        c.start = 26.8;
        c.validate().unwrap();
    }

    #[test]
    fn bad_scenarios_name_the_parameter() {
        let cases = [
            ("scene = \"flame\"\nfoo = 1\n", "foo"),
            ("n = 2\n", "scene"),
            ("scene = \"volcano\"\n", "volcano"),
            ("scene = \"flame\"\nn = -1.0\n", "n = -1"),
            ("scene = \"flame\"\nwidth = 0\n", "width = 0"),
            ("scene = \"flame\"\nheight = 231\n", "height = 231"),
            ("scene = \"flame\"\nsnapshots = [5, 3]\n", "snapshots"),
            (
                "scene = \"flame\"\nsnapshots = [60000]\n",
                "snapshots = 60000",
            ),
            ("scene = \"flame\"\nsteps = 0\n", "steps = 0"),
            ("scene = \"flame\"\nstart = 1e6\n", "start"),
            ("scene = \"flame\"\nlattice = \"tri\"\n", "lattice"),
            ("scene = \"ca\"\nca_rule = [5]\n", "ca_rule"),
        ];
        for (text, needle) in cases {
            let e = SceneConfig::from_toml(text).unwrap_err().to_string();
            assert!(e.contains(needle), "{text:?}: {e}");
        }
    }
}
