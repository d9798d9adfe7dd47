//! [`TileScenario`]: a `cellsurf tile` scenario file read back by the library (the published
//! figures' runs): the subcommand's options as keys, its defaults for the others, over tiles
//! generated in-process (`generate = true`).

use serde::Deserialize;

use super::tileset::tiles_from_run;
use super::{Choose, DuneParams, Mosaic, Relief, RippledDunes, Tile, TileError};
use crate::engine::scenario::{self, GridSize, ScenarioError};
use crate::ripple::{Field, RippleParams};

/// The keys of a `cellsurf tile` scenario file (`model = "tile"`), as the subcommand's
/// `--print-scenario` writes them.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Keys {
    tile: Option<Vec<String>>,
    generate: Option<bool>,
    ripple_scenario: Option<String>,
    size: Option<GridSize>,
    nx: Option<usize>,
    ny: Option<usize>,
    layers: Option<usize>,
    steps: Option<u64>,
    activity: Option<f64>,
    bin_size: Option<f64>,
    seeds: Option<Vec<u64>>,
    snapshots: Option<Vec<u64>>,
    mosaic: Option<String>,
    extent: Option<String>,
    choose: Option<String>,
    blend: Option<usize>,
    volume: Option<String>,
    dunes: Option<bool>,
    hurst: Option<f64>,
    dune_rms: Option<f64>,
    dune_wavelength: Option<f64>,
    current_angle: Option<f64>,
    steering: Option<f64>,
    dune_grid: Option<usize>,
    seed: Option<u64>,
    dune_seed: Option<u64>,
}

/// The options of `cellsurf tile --generate` that set the ripple runs' parameters, as its
/// scenario files name them (the subcommand reads them from its own options by these names).
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
pub struct GenerateOptions {
    /// Tile size in columns.
    pub size: Option<GridSize>,
    /// Columns along x (old spelling of the x part of `size`).
    pub nx: Option<usize>,
    /// Columns along y (old spelling of the y part of `size`).
    pub ny: Option<usize>,
    /// Mean sand thickness, automata per column.
    pub layers: Option<usize>,
    /// Steps of each run.
    pub steps: Option<u64>,
    /// Fraction of automata triggered per step.
    pub activity: Option<f64>,
    /// Bin size, m.
    pub bin_size: Option<f64>,
    /// Current direction, degrees counter-clockwise from east.
    pub current_angle: Option<f64>,
    /// Steps whose snapshots are tiles (they do not change the steps: [`TileScenario::parse`]
    /// raises the runs' steps to the last where `steps` is not given).
    pub snapshots: Option<Vec<u64>>,
}

impl GenerateOptions {
    /// `p` with the options given in place of its own (unchecked).
    pub fn apply(&self, p: &mut RippleParams) {
        if let Some(s) = self.size {
            (p.nx, p.ny) = (s.w, s.h);
        }
        macro_rules! set {
            ($($f:ident),+) => { $(if let Some(v) = self.$f { p.$f = v; })+ };
        }
        set!(nx, ny, layers, steps, activity, bin_size, current_angle);
        // (the snapshots do not move the steps: a snapshot past them is the caller's to
        // refuse, or to reach by raising the steps, and to say so)
    }
}

/// How many tiles the mosaic lays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Layout {
    /// Tiles along x and y (`mosaic = "MXxMY"`, default 3 x 3).
    Tiles(usize, usize),
    /// A surface size in metres, rounded up to whole tiles (`extent = "WxH"`).
    Extent(f64, f64),
}

/// The rippled dunes of a run (`dunes = true`).
#[derive(Clone, Debug, PartialEq)]
pub struct DuneKeys {
    /// Hurst exponent of the fBm relief (default 0.6), unless a wavelength is given.
    pub hurst: f64,
    /// A dune wavelength, m (a band-limited relief instead of fBm).
    pub wavelength: Option<f64>,
    /// Rms dune height, m (default: [`RippledDunes::default_rms`]).
    pub rms: Option<f64>,
    /// Current direction, degrees counter-clockwise from east (default: the tiles' current).
    pub current_angle: Option<f64>,
    /// Steering by the dune slope (default 3).
    pub steering: f64,
    /// Dune-grid nodes per side (default: 256, or the bins of a smaller mosaic).
    pub grid: Option<usize>,
    /// Seed of the dune synthesis (default: the run's seed).
    pub seed: u64,
}

/// A `cellsurf tile --generate` run: the ripple runs that make the tiles, the mosaic and the
/// dunes.
#[derive(Clone, Debug, PartialEq)]
pub struct TileScenario {
    /// The ripple runs' parameters (each run with one seed of [`Self::seeds`]).
    pub ripple: RippleParams,
    /// Seeds of the ripple runs (default: [`Self::seed`]).
    pub seeds: Vec<u64>,
    /// Steps whose snapshots are tiles (default: the last step).
    pub snapshots: Vec<u64>,
    /// A volume field beneath the surface.
    pub volume: Option<Field>,
    /// How many tiles.
    pub layout: Layout,
    /// Tile choice per mosaic cell (default the same tile).
    pub choose: Choose,
    /// Cross-fade band at the tile edges, bins (default 0).
    pub blend: usize,
    /// Seed of the patch choice (default 1).
    pub seed: u64,
    /// The dunes, where asked.
    pub dunes: Option<DuneKeys>,
}

/// `"AxB"` as two numbers.
fn pair<T: std::str::FromStr>(key: &str, s: &str) -> Result<(T, T), ScenarioError> {
    let bad = || ScenarioError::new(format!("{key} = \"{s}\" is not valid: expected AxB"));
    let (a, b) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    Ok((
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    ))
}

impl TileScenario {
    /// Reads a scenario file as `cellsurf tile --scenario` does: the ripple runs' parameters
    /// are the ripple defaults with `size` (or `nx`, `ny`), `layers`, `steps` (a `snapshots`
    /// step past it is refused; without it the runs go to the last snapshot), `activity`, `bin_size` and `current_angle`; the mosaic `mosaic` or
    /// `extent`, `choose`, `blend`, `seed`; the dunes `hurst`, `dune_rms`, `dune_wavelength`,
    /// `current_angle`, `steering`, `dune_grid`, `dune_seed`. Tiles from files (`tile`) and a
    /// `ripple_scenario` file are read by the subcommand only.
    pub fn parse(text: &str) -> Result<TileScenario, ScenarioError> {
        let k: Keys = scenario::read(text, "tile")?;
        if k.tile.as_ref().is_some_and(|t| !t.is_empty()) || k.generate != Some(true) {
            return Err(ScenarioError::new(
                "the library reads scenarios of generated tiles (generate = true, no tile files)",
            ));
        }
        if let Some(p) = &k.ripple_scenario {
            return Err(ScenarioError::new(format!(
                "ripple_scenario = \"{p}\": a ripple scenario file is read by `cellsurf tile`; give the ripple runs' keys here"
            )));
        }
        let mut p = RippleParams::default();
        GenerateOptions {
            size: k.size,
            nx: k.nx,
            ny: k.ny,
            layers: k.layers,
            steps: k.steps,
            activity: k.activity,
            bin_size: k.bin_size,
            current_angle: k.current_angle,
            snapshots: k.snapshots.clone(),
        }
        .apply(&mut p);
        p.validate().map_err(ScenarioError::new)?;
        if let Some(last) = k.snapshots.iter().flatten().copied().max()
            && last > p.steps
        {
            if k.steps.is_some() {
                return Err(ScenarioError::new(format!(
                    "snapshots = {last} is out of range: expected steps in [0, steps = {}]",
                    p.steps
                )));
            }
            p.steps = last;
        }
        let seed = k.seed.unwrap_or(1);
        let layout = match (&k.mosaic, &k.extent) {
            (Some(_), Some(_)) => {
                return Err(ScenarioError::new(
                    "mosaic and extent both given: expected one of them",
                ));
            }
            (Some(m), None) => {
                let (mx, my) = pair::<usize>("mosaic", m)?;
                if mx == 0 || my == 0 {
                    return Err(ScenarioError::new(format!(
                        "mosaic = {mx}x{my} is out of range: expected at least 1x1 tiles"
                    )));
                }
                Layout::Tiles(mx, my)
            }
            (None, Some(e)) => {
                let (w, h) = pair::<f64>("extent", e)?;
                if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0) {
                    return Err(ScenarioError::new(format!(
                        "extent = {e} is out of range: expected positive sizes in metres"
                    )));
                }
                Layout::Extent(w, h)
            }
            (None, None) => Layout::Tiles(3, 3),
        };
        let volume = match k.volume.as_deref() {
            Some(v) => Some(v.parse::<Field>().map_err(ScenarioError::new)?),
            None => None,
        };
        Ok(TileScenario {
            seeds: k.seeds.unwrap_or_else(|| vec![seed]),
            snapshots: k.snapshots.unwrap_or_else(|| vec![p.steps]),
            ripple: p,
            volume,
            layout,
            choose: k
                .choose
                .as_deref()
                .unwrap_or("same")
                .parse()
                .map_err(ScenarioError::new)?,
            blend: k.blend.unwrap_or(0),
            seed,
            dunes: k.dunes.unwrap_or(false).then(|| DuneKeys {
                hurst: k.hurst.unwrap_or(0.6),
                wavelength: k.dune_wavelength,
                rms: k.dune_rms,
                current_angle: k.current_angle,
                steering: k.steering.unwrap_or(3.0),
                grid: k.dune_grid,
                seed: k.dune_seed.unwrap_or(seed),
            }),
        })
    }

    /// The tiles of the ripple run with `seed` (the snapshots of [`Self::snapshots`]).
    pub fn tiles_of_seed(&self, seed: u64) -> Result<Vec<Tile>, TileError> {
        tiles_from_run(&self.ripple, &[seed], &self.snapshots, self.volume, |_| {})
    }

    /// Every tile, seed by seed.
    pub fn tiles(&self) -> Result<Vec<Tile>, TileError> {
        tiles_from_run(
            &self.ripple,
            &self.seeds,
            &self.snapshots,
            self.volume,
            |_| {},
        )
    }

    /// The mosaic of `tiles` (the first sets the tile size).
    pub fn mosaic(&self, tiles: Vec<Tile>) -> Result<Mosaic, TileError> {
        let first = tiles
            .first()
            .ok_or_else(|| TileError::range("tiles", "(none)", "at least one tile"))?;
        let (mx, my) = match self.layout {
            Layout::Tiles(mx, my) => (mx, my),
            Layout::Extent(w, h) => {
                let dx = first.bin_size;
                let cells =
                    |len: f64, n: usize| (len / (n as f64 * dx) - 1e-9).ceil().max(1.0) as usize;
                (cells(w, first.nx), cells(h, first.ny))
            }
        };
        Mosaic::new(tiles, mx, my, self.choose, self.seed, self.blend)
    }

    /// The dunes' parameters over `mosaic` (none without `dunes = true`): the current in the
    /// mosaic's frame (its x axis is the tiles'), the default grid and rms where not given.
    pub fn dune_params(&self, mosaic: &Mosaic) -> Result<Option<DuneParams>, TileError> {
        let Some(d) = &self.dunes else {
            return Ok(None);
        };
        let t = &mosaic.tiles()[0];
        let current = d
            .current_angle
            .map(|c| c - t.x_axis_deg)
            .unwrap_or(t.current_angle);
        let (mw, mh) = mosaic.size();
        let mut p = DuneParams {
            relief: match d.wavelength {
                Some(wavelength) => Relief::Wavelength {
                    wavelength,
                    current_angle: current,
                },
                None => Relief::Fbm { hurst: d.hurst },
            },
            rms: d.rms.unwrap_or(0.0),
            grid: d.grid.unwrap_or_else(|| 256.min(mw.max(mh))),
            current_angle: current,
            steering: d.steering,
            seed: d.seed,
        };
        if d.rms.is_none() {
            p.rms = RippledDunes::default_rms(mosaic, &p)?;
        }
        Ok(Some(p))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A snapshot past the given steps is refused; without steps the runs go on to it.
    #[test]
    fn snapshots_past_the_steps_are_refused_unless_the_steps_follow_them() {
        let head = "model = \"tile\"\ngenerate = true\nsize = \"16x8\"\n";
        let e = TileScenario::parse(&format!("{head}steps = 10\nsnapshots = [5, 50]\n"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("snapshots = 50 is out of range: expected steps in [0, steps = 10]"),
            "{e}"
        );
        let s = TileScenario::parse(&format!("{head}snapshots = [5, 20000]\n")).unwrap();
        assert_eq!((s.ripple.steps, s.snapshots), (20000, vec![5, 20000]));
    }

    #[test]
    fn keys_become_the_run_and_the_rest_keep_the_defaults() {
        let s = TileScenario::parse(
            "model = \"tile\"\ngenerate = true\nsize = \"24x12\"\nlayers = 10\nsteps = 20\n\
             seeds = [1, 2]\nmosaic = \"2x3\"\nchoose = \"patches\"\nseed = 4\ndunes = true\n\
             dune_seed = 5\n",
        )
        .unwrap();
        assert_eq!((s.ripple.nx, s.ripple.ny, s.ripple.layers), (24, 12, 10));
        assert_eq!(
            (s.seeds.clone(), s.snapshots.clone()),
            (vec![1, 2], vec![20])
        );
        assert_eq!(
            (s.layout, s.choose, s.blend, s.seed),
            (Layout::Tiles(2, 3), Choose::Patches, 0, 4)
        );
        let d = s.dunes.clone().unwrap();
        assert_eq!((d.hurst, d.steering, d.seed), (0.6, 3.0, 5));
        let m = s.mosaic(s.tiles().unwrap()).unwrap();
        assert_eq!(m.size(), (48, 36));
        let p = s.dune_params(&m).unwrap().unwrap();
        assert_eq!((p.grid, p.seed), (48, 5));
        assert!(p.rms > 0.0);
        let one = TileScenario::parse("model = \"tile\"\ngenerate = true\nseed = 7\n").unwrap();
        assert_eq!(
            (one.seeds, one.layout, one.dunes),
            (vec![7], Layout::Tiles(3, 3), None)
        );
        crate::engine::scenario::assert_refused(
            "tile",
            TileScenario::parse,
            &[
                ("generate = true\ntile = [\"a.nc\"]", "generated"),
                ("generate = true\nripple_scenario = \"r.toml\"", "r.toml"),
                ("generate = true\nmosaic = \"3\"", "mosaic"),
                ("generate = true\nchoose = \"all\"", "choose"),
                ("generate = true\nlayers = 0", "layers"),
                ("generate = true\ndry_run = true", "dry_run"),
            ],
        );
    }
}
