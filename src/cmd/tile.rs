//! `cellsurf tile`: builds a large surface as a mosaic of toroidal ripple tiles
//! ([`cellsurf::tile`]), from ripple NetCDF files (`--tile`, repeatable) and/or tiles generated
//! in-process (`--generate`), optionally with fractal rippled dunes (`--dunes`), and streams it
//! row by row to NetCDF-3 or `.npy` (`--out`), or chunk by chunk to a Zarr v3 store
//! (`--out X.zarr`; `--part i/N` writes one share of the chunks, `--init` the metadata alone,
//! `--check STORE` reports missing and damaged chunks). Without `--out` it only measures the
//! seams and slopes. `--dry-run` prints the size and the disk space the output would take, and
//! stops.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::{Deserialize, Serialize};

use cellsurf::ripple::RippleParams;
use cellsurf::ripple::output::{Field, toml_pairs};

use super::conv::{self, Format, Outputs, Size};
use cellsurf::engine::count::CountRange;
use cellsurf::ripple::params;
use cellsurf::tile::fractal::measured_slope;
use cellsurf::tile::stream::{estimate_bytes, npy_files, write_stream};
use cellsurf::tile::tileset::{tiles_from_file, tiles_from_run};
use cellsurf::tile::zarr::{
    Part, TILES_DIGEST, ZarrLayout, check_store_target, check_zarr, init_zarr, is_store,
    verify_zarr, write_zarr, write_zarr_whole,
};
use cellsurf::tile::{
    ANGLE_OF_REPOSE_DEG, Choose, DuneParams, GenerateOptions, Mosaic, Relief, RippledDunes,
    RowSource, SeamMeter, SeamStats, StreamFormat, StreamSpec, Tile,
};

/// Options of `cellsurf tile`.
#[derive(clap::Args, Serialize, Deserialize)]
#[command(
    allow_negative_numbers = true,
    after_help = "Examples:\n  \
        cellsurf tile --generate --size 64x32 --mosaic 8x8 --out mosaic.nc\n  \
        cellsurf tile --tile bed.nc --extent 20x20 --dunes --out dunes.npy --json\n  \
        cellsurf tile --generate --size 64x32 --mosaic 16x16 --out mosaic.zarr   # Zarr v3 store\n  \
        cellsurf tile --generate --size 100x100 --bin-size 0.01 --extent 1000x1000 --dry-run --out km.nc"
)]
pub struct Args {
    /// Start from this scenario file (TOML, `model = "tile"`); options typed here override it.
    #[arg(long, value_name = "FILE.toml")]
    scenario: Option<PathBuf>,
    /// A ripple NetCDF file (from `cellsurf ripple`) whose snapshots are tiles; repeatable.
    #[arg(long, value_name = "FILE.nc")]
    tile: Vec<PathBuf>,
    /// Generate tiles in-process with the ripple model (one run per --seeds entry).
    #[arg(long)]
    generate: bool,
    /// --generate: the ripple scenario (TOML, as `cellsurf ripple --print-scenario` writes)
    /// [default: the paper's rules, as `cellsurf ripple --recipe paper`].
    #[arg(long, value_name = "FILE.toml")]
    ripple_scenario: Option<PathBuf>,
    /// --generate: tile size in columns, NXxNY [default: the ripple scenario's, else 128x64].
    #[arg(long, value_name = "NXxNY", value_parser = conv::size_in(params::SIZE_SIDES))]
    size: Option<Size>,
    /// Old spelling of the x part of --size (kept for one release).
    #[arg(long, hide = true, value_parser = conv::count_in::<usize>(params::NX), conflicts_with = "size")]
    nx: Option<usize>,
    /// Old spelling of the y part of --size (kept for one release).
    #[arg(long, hide = true, value_parser = conv::count_in::<usize>(params::NY), conflicts_with = "size")]
    ny: Option<usize>,
    /// --generate: mean sand thickness, automata per column [default: the scenario's, else 30].
    #[arg(long, value_parser = conv::count_in::<usize>(params::LAYERS))]
    layers: Option<usize>,
    /// --generate: steps of each run (`1e4` accepted); a --snapshots step past it (or past a
    /// scenario's `steps`) is refused [default: the scenario's, else 10000, raised to the
    /// largest --snapshots step, with a warning].
    #[arg(long, value_name = "N", value_parser = conv::count_in::<u64>(params::STEPS))]
    steps: Option<u64>,
    /// --generate: fraction of automata triggered per step [default: the scenario's, else
    /// 0.001].
    #[arg(long)]
    activity: Option<f64>,
    /// --generate: bin size, m [default: the scenario's, else 0.005].
    #[arg(long)]
    bin_size: Option<f64>,
    /// --generate: seeds of the runs (comma-separated), each 0 to 2^53 [default: --seed].
    #[arg(long, value_delimiter = ',', value_parser = conv::count_in::<u64>(SEEDS))]
    seeds: Option<Vec<u64>>,
    /// Steps whose snapshots are tiles (comma-separated) [default: the last step / snapshot].
    #[arg(long, value_delimiter = ',', value_parser = conv::count_in::<u64>(params::STEPS))]
    snapshots: Option<Vec<u64>>,
    /// Tiles along x and y, MXxMY; instead of --extent [default: 3x3].
    #[arg(long, value_name = "MXxMY", allow_hyphen_values = true, value_parser = counts_form)]
    mosaic: Option<String>,
    /// Surface size in metres, WxH (rounded up to whole tiles); instead of --mosaic.
    #[arg(long, value_name = "WxH", allow_hyphen_values = true, value_parser = lengths_form)]
    extent: Option<String>,
    /// Tile choice per mosaic cell: same (the first tile) or patches (seeded random).
    #[arg(long, default_value = "same")]
    choose: String,
    /// Cross-fade band at the tile edges, bins, 0 (none) to the smaller tile side.
    #[arg(long, default_value_t = 0, value_parser = conv::count_within::<usize>(BLEND))]
    blend: usize,
    /// Volume field to write beneath the surface (grain_size, porosity, density, sound_speed,
    /// impedance).
    #[arg(long)]
    #[serde(with = "conv::opt_name", default)]
    volume: Option<Field>,
    /// Ripples riding on fractal dunes.
    #[arg(long)]
    dunes: bool,
    /// --dunes: Hurst exponent H in (0, 1) of the fBm relief (power spectrum K^-(2H+2)).
    #[arg(long, default_value_t = 0.6)]
    hurst: f64,
    /// --dunes: rms dune height, m, 0 to 1000 [default: the height that gives the dune field an rms slope
    /// of 6 deg at its grid, so it scales with the extent (e.g. 47 mm on 20 x 20 m with the
    /// default grid, H 0.6); its largest slope is then about 20 deg, below the angle of repose, 32 deg].
    /// The slopes are measured and reported; steeper dunes than 32 deg get a warning.
    #[arg(long)]
    dune_rms: Option<f64>,
    /// --dunes: a dune wavelength, m (a band-limited spectrum instead of fBm).
    #[arg(long)]
    dune_wavelength: Option<f64>,
    /// Current direction, degrees counter-clockwise from east, for --dunes (the ripple pattern is
    /// turned to it) and for the --generate runs [default: the tiles' current]; with neither it
    /// is an error. The mosaic is laid in the tiles' frame: its x axis is theirs
    /// (`x_axis_direction_deg` in the output; the flow's direction for ripple runs in the flow
    /// frame).
    #[arg(long, allow_hyphen_values = true)]
    current_angle: Option<f64>,
    /// --dunes: steering of the current by the dune slope, dimensionless, >= 0: u = e - steering
    /// grad D, e the unit vector of --current-angle and grad D the dune slope in m/m.
    #[arg(long, default_value_t = 3.0)]
    steering: f64,
    /// --dunes: dune-grid nodes per side, 3 ..= the surface's bins along its longer side and at
    /// most 16384 (a
    /// shorter side gets at most its own bins) [default: 256, or the bins of a smaller surface].
    #[arg(long, value_parser = conv::count_within::<usize>(DUNE_GRID))]
    dune_grid: Option<usize>,
    /// Output file; the extension picks the format: .nc (NetCDF-3), .npy (NAME.npy the
    /// elevation, NAME_FIELD.npy the volume, NAME.json the parameters) or .zarr (a Zarr v3
    /// store, a folder: chunks of whole tiles, zstd). Without --out nothing is written: the
    /// rows are computed and only the seams and slopes measured.
    #[arg(long, value_name = "FILE")]
    out: Vec<PathBuf>,
    /// Old spelling: netcdf or npy, with --out a file stem (kept for one release).
    #[arg(long, hide = true)]
    format: Option<String>,
    /// --out X.zarr: write only part i of N of the chunks (i in 0..N-1); parts may run at once,
    /// in any order, on any machines sharing the store, and a re-run finishes a killed part.
    #[arg(long, value_name = "i/N")]
    part: Option<String>,
    /// --out X.zarr: tiles per chunk along x and y, KXxKY [default: chunks of about 2^20
    /// values (4 MB), at least one tile].
    #[arg(long, value_name = "KXxKY", value_parser = counts_form)]
    chunk_tiles: Option<String>,
    /// --out X.zarr: write the store's metadata only (the parts then check it).
    #[arg(long)]
    init: bool,
    /// Report the missing and damaged chunks and stale temporary files of a Zarr store, and
    /// exit non-zero when it is incomplete (with --part i/N: the parts to re-run, of N).
    #[arg(long, value_name = "STORE.zarr", conflicts_with = "out")]
    check: Option<PathBuf>,
    /// Seed of the patch choice and, without --dune-seed, of the dune synthesis (and of
    /// --generate without --seeds).
    #[arg(long, default_value_t = 1, value_parser = conv::count_in::<u64>(SEEDS))]
    seed: u64,
    /// --dunes: seed of the dune synthesis alone [default: --seed].
    #[arg(long, value_name = "N", value_parser = conv::count_in::<u64>(SEEDS))]
    dune_seed: Option<u64>,
    /// Print the size and the disk space needed, then stop.
    #[arg(long)]
    dry_run: bool,
    /// Print one JSON object with the run's summary on stdout (no progress bar).
    #[arg(long)]
    json: bool,
    /// No progress bar and no chatter on stderr.
    #[arg(long)]
    quiet: bool,
    /// Print the run's scenario file (TOML) and exit.
    #[arg(long)]
    print_scenario: bool,
}

/// The parameters recorded in the output.
#[derive(Serialize)]
struct Recorded {
    tiles: String,
    /// The SHA-256 digest of the tiles' values ([`cellsurf::tile::tileset::digest`]): what
    /// identifies a store's tiles, whatever their files are called.
    tiles_sha256: String,
    tile_nx: usize,
    tile_ny: usize,
    bin_size: f64,
    mosaic: String,
    choose: String,
    blend: usize,
    seed: u64,
    /// The dunes' own seed, where it is not `seed` (`--dune-seed`).
    #[serde(skip_serializing_if = "Option::is_none")]
    dune_seed: Option<u64>,
    volume: String,
    /// The acoustic model of the tiles' density, sound speed or impedance volume (absent for
    /// other volumes and without one).
    #[serde(skip_serializing_if = "Option::is_none")]
    volume_acoustics: Option<String>,
    dunes: bool,
    hurst: f64,
    dune_rms: f64,
    dune_wavelength: f64,
    current_angle: f64,
    steering: f64,
    dune_grid: usize,
    x_axis_direction_deg: f64,
    /// The parameters of the `--generate` runs (absent without `--generate`).
    #[serde(flatten)]
    ripple: Option<RippleRecord>,
}

/// The two counts of `AxB` (`3x3`; scientific notation accepted, `1e1x2`, as by every count).
fn counts(s: &str) -> Option<(usize, usize)> {
    let (a, b) = s.split_once(['x', 'X'])?;
    Some((
        conv::parse_usize(a.trim()).ok()?,
        conv::parse_usize(b.trim()).ok()?,
    ))
}

/// The two lengths of `WxH`, m.
fn lengths(s: &str) -> Option<(f64, f64)> {
    let (a, b) = s.split_once(['x', 'X'])?;
    Some((a.trim().parse().ok()?, b.trim().parse().ok()?))
}

/// The command line's check of `--mosaic` and `--chunk-tiles` (a form it cannot read is
/// refused as the command line is read, status 2); the value is kept as written.
fn counts_form(s: &str) -> Result<String, String> {
    counts(s)
        .map(|_| s.to_string())
        .ok_or_else(|| format!("'{s}' is not two counts AxB (e.g. 3x3 or 1e1x2)"))
}

/// The command line's check of `--extent`.
fn lengths_form(s: &str) -> Result<String, String> {
    lengths(s)
        .map(|_| s.to_string())
        .ok_or_else(|| format!("'{s}' is not two lengths WxH in metres (e.g. 1000x1000)"))
}

fn parse_pair<T>(
    name: &str,
    s: &str,
    example: &str,
    read: fn(&str) -> Option<(T, T)>,
) -> Result<(T, T)> {
    read(s).ok_or_else(|| {
        anyhow::anyhow!("--{name} = '{s}' is not valid: expected AxB, e.g. {example}")
    })
}

fn ripple_params(a: &Args) -> Result<RippleParams> {
    let mut secs = super::ripple::Seconds::default();
    let mut p = match &a.ripple_scenario {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading --ripple-scenario {}", path.display()))?;
            let mut t: toml::Table = text
                .parse()
                .with_context(|| format!("--ripple-scenario {} is not TOML", path.display()))?;
            match t.remove("model") {
                None => {}
                Some(toml::Value::String(m)) if m == "ripple" => {}
                Some(m) => bail!(
                    "--ripple-scenario {}: model = {m} is out of range: expected \"ripple\" (a scenario of `cellsurf ripple`)",
                    path.display()
                ),
            }
            // (its duration_s and wave_period_s converted below, as `cellsurf ripple` does)
            secs = super::ripple::scenario_seconds(&mut t, "--ripple-scenario", path)?;
            RippleParams::from_table(t)
                .with_context(|| format!("in --ripple-scenario {}", path.display()))?
        }
        None => RippleParams::default(),
    };
    // the options that set the runs' parameters, by their names (as in a scenario file)
    let o: GenerateOptions = toml::Value::Table(conv::scenario_table(a)?)
        .try_into()
        .context("the --generate options")?;
    o.apply(&mut p);
    // a scenario's bin in flat-bed travels (`bin_travels`): a typed --bin-size wins, as in
    // `cellsurf ripple`; otherwise the tiles run on the bin of the travel, automata following
    p = if a.bin_size.is_some() {
        RippleParams {
            bin_travels: 0.0,
            ..p
        }
    } else {
        p.with_travel_bin()
    };
    // tiles are 3-D fields: a scenario of a 2-D section (as `cellsurf ripple --print-scenario`
    // writes for its default) would make tiles of one row
    if let (Some(path), cellsurf::ripple::Mode::TwoD) = (&a.ripple_scenario, p.mode) {
        bail!(
            "--ripple-scenario {}: mode = \"2d\" is out of range for --generate: expected \"3d\" (tiles are 3-D fields; print one with `cellsurf ripple --size NXxNY --print-scenario`, NY above 1, or `cellsurf ripple --recipe paper --print-scenario`)",
            path.display()
        );
    }
    // --steps typed wins over the scenario's duration_s
    if a.steps.is_some() {
        secs.duration = None;
    }
    super::ripple::scenario_steps(&secs, &mut p)?;
    // a scenario's lengths in units of the orbit (`orbit_reference`): scaled to the waves'
    // excursion (their period in steps is known now), a typed --bin-size kept with the
    // automata it came with
    if let Some(s) = p.orbit_scale().filter(|&s| s != 1.0) {
        let q = p.with_orbit_scale();
        let r = match a.bin_size {
            Some(_) => RippleParams {
                bin_size: p.bin_size,
                layer_thickness: p.layer_thickness,
                ..q
            },
            None => q,
        };
        conv::note(format_args!(
            "note: the scenario's lengths in units of the waves' orbital excursion A = {} m ({s:.4} x those of orbit_reference = {} m): bin_size = {} m, layer_thickness = {} m, hop_grains = {}, crest_suspension = {} m{}",
            cellsurf::ripple::params::rounded(p.wave_vortex),
            cellsurf::ripple::params::shown(p.orbit_reference),
            cellsurf::ripple::params::shown(r.bin_size),
            cellsurf::ripple::params::shown(r.layer_thickness),
            cellsurf::ripple::params::shown(r.hop_grains),
            cellsurf::ripple::params::shown(r.crest_suspension),
            if a.bin_size.is_some() {
                " (--bin-size and its automata as given)"
            } else {
                ""
            }
        ));
        p = r;
    }

    // a snapshot past the runs' steps: refused against a typed --steps (as `cellsurf ripple`
    // does), else the runs go on to it, said
    if let Some(last) = a.snapshots.as_ref().and_then(|s| s.iter().copied().max())
        && last > p.steps
    {
        let snaps = if conv::typed("snapshots") {
            conv::typed_flag("snapshots").unwrap_or_else(|| "--snapshots".into())
        } else {
            "the scenario's snapshots".into()
        };
        if conv::typed("steps") {
            let flag = conv::typed_flag("steps").unwrap_or_else(|| "--steps".into());
            bail!(
                "{snaps} = {last} is out of range: expected steps in [0, {flag} = {}]",
                p.steps
            );
        }
        if a.steps.is_some() {
            bail!(
                "{snaps} = {last} is out of range: expected steps in [0, steps = {} (the scenario's)]",
                p.steps
            );
        }
        conv::changed(format_args!(
            "warning: {snaps} = {last} is past the runs' {} steps (the default, or the --ripple-scenario's): each run goes on to step {last}; give --steps to set it",
            p.steps
        ));
        p.steps = last;
    }
    // A --bin-size too short for the scenario's automata (tile has no --layer-thickness):
    // named by the flag that was typed, with the least bin that holds them.
    if let Some(b) = a.bin_size
        && b > 0.0
        && p.avalanche_angle > 0.0
        && p.avalanche_angle < 90.0
        && p.lattice_slope_deg() > p.avalanche_angle
    {
        let flag = conv::typed_flag("bin_size").unwrap_or_else(|| "--bin-size".into());
        bail!(
            "{flag} = {b} m is out of range for the generated tiles' automata of {} m (the ripple scenario's layer_thickness) at an avalanche angle of {} deg: one automaton over one bin would be steeper than the avalanche angle, which the lattice cannot hold; expected {flag} at least layer_thickness / tan(avalanche_angle) = {} m (or a --ripple-scenario with a thinner layer_thickness)",
            cellsurf::ripple::params::shown(p.layer_thickness),
            p.avalanche_angle,
            {
                // (rounded up to 4 significant digits, so the value shown is accepted)
                let least = p.layer_thickness / p.avalanche_angle.to_radians().tan();
                let unit = 10f64.powi(least.log10().floor() as i32 - 3);
                cellsurf::ripple::params::rounded((least / unit).ceil() * unit)
            }
        );
    }
    p.validate()?;
    if let Some(u) = p.until.take() {
        // (and not recorded: the tiles' record is the runs that were made)
        conv::note(format_args!(
            "warning: the ripple scenario's until = \"{u}\" is not applied to the --generate runs: each runs its whole length, {} steps (the scenario's steps or duration_s, or --steps)",
            p.steps
        ));
    }
    for &seed in &run_seeds(a) {
        let flag = if a.seeds.is_some() {
            "--seeds"
        } else {
            "--seed"
        };
        RippleParams { seed, ..p.clone() }
            .validate()
            .map_err(|e| anyhow::anyhow!("{flag} = {seed} for the --generate runs: {e}"))?;
    }
    check_regime(a, &p)?;
    Ok(p)
}

/// The most tiles a mosaic lays (its tile index: `cellsurf::tile::mosaic`).
const MAX_TILES: usize = 1 << 28;

/// The seeds of the `--generate` runs: `--seeds`, else `--seed`.
fn run_seeds(a: &Args) -> Vec<u64> {
    a.seeds.clone().unwrap_or_else(|| vec![a.seed])
}

/// The flow regime of the `--generate` runs, judged by the ripple model's own test
/// ([`cellsurf::ripple::regime::regime`]): sheet flow and no motion are refused (the tiles would
/// be beds the model's rules do not describe, or the unmoved starting bed), coarse sand noted.
fn check_regime(a: &Args, p: &RippleParams) -> Result<()> {
    use cellsurf::ripple::regime::{D50_RIPPLES_MAX_MM, Regime, THETA_SHEET_FLOW, regime};
    let r = regime(p);
    let (lo, hi) = r.ripple_speeds;
    let from = match &a.ripple_scenario {
        Some(f) => format!("--ripple-scenario {}", f.display()),
        None => "the ripple defaults (the paper's rules)".into(),
    };
    let flow = format!(
        "current_speed = {} m/s with waves of near-bed orbital velocity wave_amplitude = {} m/s ({from})",
        p.current_speed, p.wave_amplitude
    );
    match r.regime {
        Regime::SheetFlow => bail!(
            "{flow} is out of range for --generate: its largest speed, {:.4} m/s, gives a Shields number of {:.4} on d50 = {} mm, above {THETA_SHEET_FLOW}: sheet flow, where ripples are washed out into a flat bed and the rules of the ripple model do not hold; expected a largest speed of {lo:.4} to {hi:.4} m/s for ripples",
            r.speed,
            r.shields,
            p.d50
        ),
        Regime::NoMotion => bail!(
            "{flow} is out of range for --generate: its largest speed, {:.4} m/s, gives a Shields number of {:.4} on d50 = {} mm, below the threshold of motion {:.4}: no sand moves and the tiles would be the unmoved starting bed; expected a largest speed of {lo:.4} to {hi:.4} m/s for ripples",
            r.speed,
            r.shields,
            p.d50,
            r.shields_critical
        ),
        Regime::Ripples if r.coarse => conv::note(format_args!(
            "d50 = {} mm is above {D50_RIPPLES_MAX_MM} mm: coarse sand forms no current ripples in nature (Soulsby 1997, Sect. 7.2); the model still applies its rules",
            p.d50
        )),
        Regime::Ripples => {}
    }
    // The flow moves sand, but the model's grains may not move on a flat bed (as `cellsurf
    // ripple` finds before its run): the tiles would be the unmoved starting bed.
    let clock = cellsurf::ripple::clock::StepClock::of(p)?;
    if !clock.grains_move() {
        bail!(
            "{flow} gives no motion in the model, so the tiles would be the unmoved starting bed: its largest speed, {:.3} m/s, is above the threshold of motion ({lo:.3} m/s), but {}",
            r.speed,
            super::ripple::model_stuck_reason(p, r.speed, "stoss_angle")
        );
    }
    Ok(())
}

/// The recorded parameters of the `--generate` runs (all of them but the seed in
/// `ripple_scenario`, a TOML file that `--ripple-scenario` reads back; the runs' seeds are
/// `--seeds`, else `--seed`, recorded as `seed` and in `tiles`).
#[derive(Serialize)]
struct RippleRecord {
    ripple_layers: usize,
    ripple_steps: u64,
    ripple_d50_mm: f64,
    ripple_current_speed: f64,
    ripple_current_angle: f64,
    ripple_wave_amplitude: f64,
    ripple_wave_period: f64,
    ripple_activity: f64,
    ripple_scenario: String,
}

impl RippleRecord {
    fn of(p: &RippleParams) -> Result<RippleRecord> {
        let mut t = toml::Table::new();
        t.insert("model".into(), "ripple".into());
        match toml::Value::try_from(p)? {
            toml::Value::Table(own) => t.extend(own),
            _ => bail!("the ripple parameters are not a TOML table"),
        }
        // the runs take their seeds from --seeds or --seed, never from the scenario
        t.remove("seed");
        Ok(RippleRecord {
            ripple_layers: p.layers,
            ripple_steps: p.steps,
            ripple_d50_mm: p.d50,
            ripple_current_speed: p.current_speed,
            ripple_current_angle: p.current_angle,
            ripple_wave_amplitude: p.wave_amplitude,
            ripple_wave_period: p.wave_period,
            ripple_activity: p.activity,
            ripple_scenario: toml::to_string(&t)?,
        })
    }
}

/// Refuses `--generate` runs larger than the memory this process may have: one ripple run at
/// a time ([`super::ripple::run_bytes`]) and the tiles kept from all of them (`seeds x
/// snapshots` tiles of an `f32` elevation per column and, with --volume, an `f32` per column
/// and level, the levels as `run_bytes` takes them), named by --size and --layers as typed.
fn check_generate_memory(a: &Args, p: &RippleParams, seeds: usize, steps: &[u64]) -> Result<()> {
    let mut distinct = steps.to_vec();
    distinct.sort_unstable();
    distinct.dedup();
    let tiles = seeds * distinct.len();
    let columns = p.nx as f64 * p.rows() as f64;
    let levels = if a.volume.is_some_and(|f| f != Field::Elevation) {
        ((p.layers + p.roughness) as f64 + p.capacity() as f64) / 2.0
    } else {
        0.0
    };
    let kept = 1.1 * tiles as f64 * columns * 4.0 * (1.0 + levels);
    conv::check_memory(
        &format!(
            "{} {}x{} with {} {} ({tiles} tile{} of the --generate runs)",
            conv::typed_flag("size").unwrap_or_else(|| "--size".into()),
            p.nx,
            p.rows(),
            conv::typed_flag("layers").unwrap_or_else(|| "--layers".into()),
            p.layers,
            if tiles == 1 { "" } else { "s" },
        ),
        super::ripple::run_bytes(p, 0, false) + kept,
    )
}

/// Address space a second malloc arena reserves (64 MiB), which `ulimit -v` counts once a
/// thread other than the main one allocates: the estimates below add it, as measured with and
/// without `MALLOC_ARENA_MAX=1`.
const ARENA_BYTES: f64 = 64.0 * 1024.0 * 1024.0;

/// Refuses a `--tile` file whose tiles would need more memory than this process may have,
/// from its header before any of its data is read: what the reading holds at its peak
/// ([`cellsurf::ripple::input::FileSize::read_bytes`]), 4 bytes per column for each snapshot
/// taken as a tile and, with --volume, 8 per column and level (the field's copy and the
/// tile's); 10 % added, and [`ARENA_BYTES`]. Measured as the least `ulimit -v` of `tile --tile
/// F --mosaic 1x1 --dry-run`, less the program's own 22 MB: a 1024x1024 elevation-only file
/// of 5 snapshots 41.9 MB (8.0 B per column and snapshot); a 1024x512 file of 2 snapshots and
/// 2 fields of 44 levels 189.5 MB with MALLOC_ARENA_MAX=1 (4.0 B per value read, 193 MB
/// computed) and 257.4 MB without; with --volume grain_size 440.9 MB (377.5 MB computed).
fn check_tile_file_memory(a: &Args, path: &std::path::Path) -> Result<()> {
    let Some(s) = cellsurf::ripple::input::file_size(path) else {
        return Ok(());
    };
    let columns = s.nx as f64 * s.ny as f64;
    let picks = a.snapshots.as_ref().map_or(1, |t| t.len()) as f64;
    let volume = match a.volume {
        Some(f) if f != Field::Elevation => s.levels as f64,
        _ => 0.0,
    };
    conv::check_memory(
        &format!(
            "{} {} ({}x{} columns, {} snapshot{}{})",
            conv::typed_flag("tile").unwrap_or_else(|| "--tile".into()),
            path.display(),
            s.nx,
            s.ny,
            s.snapshots,
            if s.snapshots == 1 { "" } else { "s" },
            if s.fields > 0 {
                format!(", {} volume fields of {} levels", s.fields, s.levels)
            } else {
                String::new()
            }
        ),
        1.1 * (s.read_bytes() + 4.0 * columns * (picks + 2.0 * volume)) + ARENA_BYTES,
    )
}

/// Refuses a dune grid (`--dune-grid`, of a surface of `w x h` bins) larger than the memory
/// this process may have: 44 bytes per node, 10 % above the 40 measured (the heights and
/// their two slopes, 24, with the synthesis's complex spectrum, 16, and later the measured
/// slope's complex copy), and [`ARENA_BYTES`]; `given`: whether the grid was asked for (not
/// the default). Measured as the least `ulimit -v` of `tile --tile F --extent 200x200 --dunes
/// --dune-grid N --dry-run`: 532 MB at N = 3072 and 821 MB at N = 4096 (40.2 B per node),
/// 336 MB at 2048 and 262 MB at 1536 on the same line. A grid out of its range is left to the
/// dunes' own check, which names it.
fn check_dune_memory(grid: usize, given: bool, w: usize, h: usize) -> Result<()> {
    if grid < 3 || grid > w.max(h).min(cellsurf::tile::dunes::MAX_DUNE_GRID) {
        return Ok(());
    }
    let (gx, gy) = (grid.min(w).max(2), grid.min(h).max(2));
    conv::check_memory(
        &format!(
            "{} {grid}{} ({gx}x{gy} nodes)",
            conv::typed_flag("dune_grid").unwrap_or_else(|| "--dune-grid".into()),
            if given { "" } else { " (the default)" }
        ),
        44.0 * gx as f64 * gy as f64 + ARENA_BYTES,
    )
}

fn pool(a: &Args, quiet: bool) -> Result<(Vec<Tile>, Option<RippleRecord>)> {
    let mut tiles = Vec::new();
    for f in &a.tile {
        check_tile_file_memory(a, f)?;
        tiles.extend(
            tiles_from_file(f, a.snapshots.as_deref(), a.volume)
                .with_context(|| format!("--tile {}", f.display()))?,
        );
    }
    let mut record = None;
    if a.generate {
        let p = ripple_params(a)?;
        let seeds = run_seeds(a);
        let steps = a.snapshots.clone().unwrap_or_else(|| vec![p.steps]);
        let last = steps.iter().copied().max().unwrap_or(0);
        record = Some(RippleRecord::of(&p)?);
        check_generate_memory(a, &p, seeds.len(), &steps)?;
        // (the warnings about the runs before their minutes of progress bar)
        conv::begin();
        let bar = bar(seeds.len() as u64 * last, "ripple tiles", quiet);
        tiles.extend(tiles_from_run(&p, &seeds, &steps, a.volume, |d| {
            if d % 64 == 0 {
                bar.set_position(d);
            }
        })?);
        bar.finish_and_clear();
    }
    if tiles.is_empty() {
        bail!("no tiles: give --tile FILE.nc (repeatable) and/or --generate");
    }
    Ok((tiles, record))
}

fn bar(len: u64, msg: &str, quiet: bool) -> ProgressBar {
    let target = if quiet {
        ProgressDrawTarget::hidden()
    } else {
        ProgressDrawTarget::stderr()
    };
    let b = ProgressBar::with_draw_target(Some(len.max(1)), target);
    b.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{bar:40}] {percent}% ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    b.set_message(msg.to_string());
    b
}

fn human(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.2} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.1} MB", b / 1e6)
    } else {
        format!("{:.1} kB", b / 1e3)
    }
}

fn opt(v: Option<f64>) -> serde_json::Value {
    match v {
        Some(x) if x.is_finite() => serde_json::json!(x),
        _ => serde_json::Value::Null,
    }
}

fn seam_json(s: &SeamStats) -> serde_json::Value {
    let d = |d: &cellsurf::tile::seam::DirStats| {
        serde_json::json!({
            "inside_m": opt(d.inside),
            "across_m": opt(d.across),
            "ratio": opt(d.ratio()),
            "inside_line_sd_m": opt(d.inside_line_sd),
            "z": opt(d.z()),
            "seams": d.seams,
            "lines": d.lines,
        })
    };
    serde_json::json!({ "x": d(&s.x), "y": d(&s.y) })
}

/// `--seed`, `--seeds` and `--dune-seed`: the ripple model's seeds, 0 to 2^53, the largest
/// integer every output records exactly (a NetCDF-3 attribute is a double; the ripple runs of
/// `--generate` take the same range).
const SEEDS: CountRange = params::SEED;

/// `--blend`, whose largest value is the smaller side of the tiles laid (checked with them).
const BLEND: &str = "0 ..= the smaller tile side, in bins";

/// `--dune-grid`, whose largest value is the surface's bins along its longer side, at most
/// 16384 (checked with the surface).
const DUNE_GRID: &str = "3 ..= the surface's bins along its longer side, at most 16384 nodes";

/// `--seed`, `--seeds` and `--dune-seed` within [`SEEDS`].
fn check_seeds(a: &Args) -> Result<()> {
    let seeds = std::iter::once(("--seed", a.seed))
        .chain(a.dune_seed.map(|s| ("--dune-seed", s)))
        .chain(a.seeds.iter().flatten().map(|&s| ("--seeds", s)));
    for (flag, s) in seeds {
        if !SEEDS.contains(s) {
            bail!("{flag} = {s} is out of range: expected {}", SEEDS.expected);
        }
    }
    Ok(())
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<()> {
    conv::synonyms(&[("nx", "size"), ("ny", "size")]);
    conv::set_quiet(a.quiet);
    let mut a = a;
    // Old meaning (one release): a --scenario without `model` is the ripple scenario.
    if let Some(p) = a.scenario.clone()
        && std::fs::read_to_string(&p)
            .ok()
            .and_then(|t| t.parse::<toml::Table>().ok())
            .is_some_and(|t| !t.contains_key("model"))
    {
        conv::note(format_args!(
            "note: --scenario {} has no `model = \"tile\"`: read as the ripple scenario of \
             --generate (old meaning; use --ripple-scenario)",
            p.display()
        ));
        a.ripple_scenario = Some(p);
        a.scenario = None;
    }
    check_seeds(&a)?;
    let scenario = a.scenario.clone();
    let a = conv::merge_scenario(a, scenario.as_deref(), "tile")?;
    if a.print_scenario {
        out!("{}", conv::scenario_text(&a, "tile")?)?;
        return Ok(());
    }
    let start = Instant::now();
    let quiet = a.quiet || a.json;
    let part: Option<Part> = match &a.part {
        Some(p) => Some(p.parse()?),
        None => None,
    };
    // --check STORE alone checks the chunks; with the tiles (--tile or --generate) and the
    // other parameters of the run that wrote the store, also that it was made from them
    if let Some(store) = &a.check {
        if a.tile.is_empty() && !a.generate {
            return check(store, part, a.json);
        }
        if a.init || a.dry_run {
            bail!(
                "{} and --check both given: expected one of them",
                if a.init { "--init" } else { "--dry-run" }
            );
        }
        if !store.is_dir() {
            bail!(
                "--check {}: not a folder (a Zarr store is a folder)",
                store.display()
            );
        }
    }
    let choose: Choose = a.choose.parse()?;
    let outs = match &a.format {
        None => Outputs::new(&a.out, "tile", &[Format::Nc, Format::Npy, Format::Zarr])?,
        Some(f) => {
            // Old spelling (one release): `--format npy --out STEM`, the extension replaced.
            let fmt = match f.as_str() {
                "npy" => Format::Npy,
                "netcdf" | "nc" => Format::Nc,
                _ => bail!("--format = {f} is out of range: expected netcdf or npy"),
            };
            let mut o = Outputs::default();
            let path = conv::legacy_format_path(fmt, &a.out)?;
            o.add_legacy(fmt, path.as_ref())?;
            o
        }
    };
    let out: Option<PathBuf> = outs
        .get(Format::Nc)
        .or(outs.get(Format::Npy))
        .or(outs.get(Format::Zarr))
        .map(|p| p.to_path_buf());
    let given = [Format::Nc, Format::Npy, Format::Zarr]
        .iter()
        .filter(|f| outs.get(**f).is_some())
        .count();
    if given > 1 {
        bail!("--out: one mosaic per run (.nc, .npy or .zarr)");
    }
    if out.is_none() && a.check.is_none() && !a.dry_run && a.volume.is_some() {
        let flag = conv::typed_flag("volume").unwrap_or_else(|| "--volume".into());
        conv::note(format_args!(
            "warning: {flag} has no effect without --out: it chooses the field the mosaic file holds, and this run writes none (it measures the seams only)"
        ));
    }
    let zarr = outs.get(Format::Zarr).is_some();
    let format = if outs.get(Format::Npy).is_some() {
        StreamFormat::Npy
    } else {
        StreamFormat::NetCdf
    };
    if let Some(out) = &out {
        if zarr {
            check_store_path("--out", out, part.is_some() || a.init)?;
        } else {
            cellsurf::engine::io::check_output("--out", out)?;
            if format == StreamFormat::Npy {
                // the volume field's file and the JSON sidecar beside NAME.npy
                for side in npy_files(out, a.volume).iter().skip(1) {
                    let opt = format!("--out {}: its file", out.display());
                    cellsurf::engine::io::check_output(&opt, side)?;
                }
            }
        }
    }
    if !zarr && a.check.is_none() && (part.is_some() || a.init || a.chunk_tiles.is_some()) {
        bail!(
            "{} needs --out STORE.zarr (a Zarr store; NetCDF and npy files are written by one process)",
            if a.init {
                "--init"
            } else if part.is_some() {
                "--part"
            } else {
                "--chunk-tiles"
            }
        );
    }
    let chunk_tiles = match &a.chunk_tiles {
        Some(t) => Some(parse_pair("chunk-tiles", t, "8x8", counts)?),
        None => None,
    };
    // What can be checked before the tiles are generated (which may take minutes) is checked
    // here; the upper bounds, which depend on the tiles' size, once they are known.
    if let Some((kx, ky)) = chunk_tiles
        && (kx == 0 || ky == 0)
    {
        bail!("--chunk-tiles = {kx}x{ky} is out of range: expected at least 1x1 tiles per chunk");
    }
    if let Some(s) = &a.snapshots {
        conv::strictly_increasing("snapshots", s)?;
    }
    if a.mosaic.is_some() && a.extent.is_some() {
        bail!("--mosaic and --extent both given: expected one of them");
    }
    let mosaic_given = match &a.mosaic {
        Some(m) => {
            let (mx, my) = parse_pair("mosaic", m, "3x3", counts)?;
            if mx == 0 || my == 0 {
                bail!("--mosaic = {mx}x{my} is out of range: expected at least 1x1 tiles");
            }
            Some((mx, my))
        }
        None => None,
    };
    let extent_given = match &a.extent {
        Some(e) => {
            let (w, h) = parse_pair("extent", e, "1000x1000 (metres)", lengths)?;
            if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0) {
                bail!("--extent = {e} is out of range: expected positive sizes in metres");
            }
            Some((e.as_str(), w, h))
        }
        None => None,
    };
    if !a.dunes {
        for id in DUNE_OPTIONS {
            if conv::typed(id) {
                let flag = conv::typed_flag(id).unwrap_or_default();
                bail!("{flag} applies to rippled dunes only: add --dunes");
            }
        }
        warn_scenario_keys(&a, DUNE_OPTIONS, "rippled dunes only (dunes = true)")?;
    }
    if !a.generate {
        // (the hidden old spellings --nx and --ny are options of their own, not scenario keys)
        for id in GENERATE_OPTIONS.iter().chain(&["nx", "ny"]) {
            if conv::typed(id) {
                let flag = conv::typed_flag(id).unwrap_or_default();
                bail!(
                    "{flag} applies to tiles generated in-process only: add --generate (tiles from --tile files keep their own)"
                );
            }
        }
        warn_scenario_keys(
            &a,
            GENERATE_OPTIONS,
            "tiles generated in-process only (generate = true)",
        )?;
    }
    if a.dunes && a.volume.is_some() {
        bail!(
            "--volume with --dunes is not supported: the volume beneath rippled dunes would need the dune relief in z (write the mosaic's volume without --dunes)"
        );
    }
    if a.volume == Some(Field::Elevation) {
        bail!(
            "--volume = elevation is out of range: expected a volume field (grain_size, porosity, density, sound_speed, impedance)"
        );
    }
    if let Some(c) = a.current_angle {
        if !a.dunes && !a.generate {
            bail!(
                "--current-angle = {c} needs --dunes (it turns the ripple pattern on the dunes) or --generate (the current of the ripple runs); tiles from --tile files keep their own current"
            );
        }
        // the ripple model's range (RippleParams::validate), for --dunes as for --generate
        if !(c.is_finite() && (-360.0..=360.0).contains(&c)) {
            bail!(
                "--current-angle = {c} is out of range: expected -360 to 360 degrees (counter-clockwise from east)"
            );
        }
    }
    // the dunes' ranges that do not depend on the tiles, before any tile is made
    if a.dunes {
        let hurst = a.dune_wavelength.is_none().then_some(a.hurst);
        cellsurf::tile::fractal::check_strength(a.dune_rms.unwrap_or(0.0), hurst)?;
    }
    let (tiles, ripple_record) = pool(&a, quiet)?;
    // (the warnings about the tiles wait, as those about the inputs did, for the checks that
    // need the tiles: the mosaic's blend, the dunes')
    conv::hold_notes();
    let (nx, ny, dx) = (tiles[0].nx, tiles[0].ny, tiles[0].bin_size);
    let (mx, my) = match (mosaic_given, extent_given) {
        (Some(m), _) => m,
        (None, Some((e, w, h))) => {
            let cells = |len: f64, n: usize| (len / (n as f64 * dx) - 1e-9).ceil().max(1.0);
            let (cx, cy) = (cells(w, nx), cells(h, ny));
            if cx * cy > MAX_TILES as f64 {
                let flag = conv::typed_flag("extent").unwrap_or_else(|| "--extent".into());
                bail!(
                    "{flag} = {e} is out of range: it takes {cx}x{cy} tiles of {nx}x{ny} bins of {dx} m, expected at most 2^28 = {MAX_TILES} tiles"
                );
            }
            (cx as usize, cy as usize)
        }
        (None, None) => (3, 3),
    };
    if (mx as u128) * (my as u128) > MAX_TILES as u128 {
        let flag = conv::typed_flag("mosaic").unwrap_or_else(|| "--mosaic".into());
        bail!("{flag} = {mx}x{my} is out of range: expected at most 2^28 = {MAX_TILES} tiles");
    }
    let labels: Vec<String> = tiles.iter().map(|t| t.label.clone()).collect();
    let tiles_digest = cellsurf::tile::tileset::digest(&tiles);
    let volume_acoustics = tiles
        .first()
        .and_then(|t| t.volume.as_ref())
        .filter(|v| {
            matches!(
                v.field,
                Field::Density | Field::SoundSpeed | Field::Impedance
            )
        })
        .map(|v| v.acoustics.name().to_string());
    // The mosaic is laid in the tiles' frame: its x axis is theirs (east for grid-frame runs,
    // the flow for flow-frame runs); --current-angle is from east, the dunes' current is taken
    // in the mosaic's frame.
    let tile_angle = tiles[0].current_angle;
    let x_axis = tiles[0].x_axis_deg;
    let current_in_mosaic = a.current_angle.map(|c| c - x_axis).unwrap_or(tile_angle);
    if a.blend > 0 && (choose == Choose::Same || tiles.len() == 1) {
        conv::note(format_args!(
            "warning: --blend = {} has no effect: the mosaic lays one tile ({}), which meets itself at its edges without a seam; give several tiles (--seeds or --tile) with --choose patches",
            a.blend,
            if tiles.len() == 1 {
                "a single tile"
            } else {
                "--choose same"
            }
        ));
    }
    if choose == Choose::Same && tiles.len() > 1 {
        conv::note(format_args!(
            "warning: --choose same lays only the first tile ({}): the other {} ({}) are not used; give --choose patches to lay them all",
            labels[0],
            tiles.len() - 1,
            labels[1..].join("; ")
        ));
    }
    if a.dune_wavelength.is_some() && conv::typed("hurst") {
        conv::note(format_args!(
            "warning: --hurst = {} has no effect: --dune-wavelength replaces the power-law (fBm) spectrum that the Hurst exponent shapes",
            a.hurst
        ));
    }
    // the mosaic's tile index (a u32 per tile laid; Mosaic::new refuses more than 2^28), held
    // twice with --dunes, whose surface keeps its own copy of the mosaic and its tiles
    let laid = mx as f64 * my as f64;
    if laid <= (1u64 << 28) as f64 {
        let copies = if a.dunes { 2.0 } else { 1.0 };
        let tile_bytes: f64 = if a.dunes {
            tiles.iter().map(|t| 4.0 * t.elevation.len() as f64).sum()
        } else {
            0.0
        };
        let what = match extent_given {
            Some((e, ..)) if mosaic_given.is_none() => format!(
                "{} {e} ({mx}x{my} tiles)",
                conv::typed_flag("extent").unwrap_or_else(|| "--extent".into())
            ),
            _ => format!(
                "{} {mx}x{my}",
                conv::typed_flag("mosaic").unwrap_or_else(|| "--mosaic".into())
            ),
        };
        conv::check_memory(&what, 1.1 * (copies * 4.0 * laid + tile_bytes))?;
    }
    let mosaic = Mosaic::new(tiles, mx, my, choose, a.seed, a.blend)?;
    let relief = match a.dune_wavelength {
        Some(wavelength) => Relief::Wavelength {
            wavelength,
            current_angle: current_in_mosaic,
        },
        None => Relief::Fbm { hurst: a.hurst },
    };
    let (mw, mh) = mosaic.size();
    let dune_grid = a.dune_grid.unwrap_or_else(|| 256.min(mw.max(mh)));
    if a.dunes {
        check_dune_memory(dune_grid, a.dune_grid.is_some(), mw, mh)?;
    }
    let mut dune_params = DuneParams {
        relief,
        rms: a.dune_rms.unwrap_or(0.0),
        grid: dune_grid,
        current_angle: current_in_mosaic,
        steering: a.steering,
        seed: a.dune_seed.unwrap_or(a.seed),
    };
    let dunes = if a.dunes {
        if a.dune_rms.is_none() {
            dune_params.rms = RippledDunes::default_rms(&mosaic, &dune_params)?;
        }
        Some(RippledDunes::new(mosaic.clone(), &dune_params)?)
    } else {
        None
    };
    // (the tiles are read or made and every input is checked: the warnings about them now)
    conv::begin();
    let src: &dyn RowSource = match &dunes {
        Some(d) => d,
        None => &mosaic,
    };
    let (w, h) = (src.width(), src.height());
    let recorded = Recorded {
        tiles: labels.join("; "),
        tiles_sha256: tiles_digest,
        tile_nx: nx,
        tile_ny: ny,
        bin_size: dx,
        mosaic: format!("{mx}x{my}"),
        choose: choose.name().into(),
        blend: a.blend,
        seed: a.seed,
        dune_seed: a.dune_seed.filter(|_| a.dunes),
        volume: a.volume.map(|f| f.name()).unwrap_or("none").into(),
        volume_acoustics,
        dunes: a.dunes,
        hurst: a.hurst,
        dune_rms: dune_params.rms,
        dune_wavelength: a.dune_wavelength.unwrap_or(0.0),
        current_angle: dune_params.current_angle + x_axis,
        steering: a.steering,
        dune_grid,
        x_axis_direction_deg: x_axis,
        ripple: ripple_record,
    };
    let spec = StreamSpec {
        format,
        volume: a.volume,
        title: if a.dunes {
            "Rippled dunes: toroidal ripple tiles on fractal dune relief (cellsurf)".into()
        } else {
            "Mosaic of toroidal sand-ripple tiles (cellsurf)".into()
        },
        params: toml_pairs(&recorded),
        elevation_long_name: a.dunes.then(|| {
            "ripple bed height above the non-erodible substrate plus the dune relief about the mean dune level (zero-mean fractal dunes: negative in the dune troughs)".into()
        }),
    };
    if a.volume.is_some() && src.levels() == 0 {
        bail!("--volume: the tiles carry no volume levels");
    }
    let estimate = estimate_bytes(src, &spec);
    let size_line = format!(
        "{w} x {h} bins ({:.2} x {:.2} m, {mx} x {my} tiles of {nx} x {ny})",
        w as f64 * dx,
        h as f64 * dx,
    );
    if !quiet && a.check.is_none() {
        match &out {
            Some(out) => super::conv::err_line(format_args!(
                "tile: {size_line}; writing about {} to {}",
                human(estimate),
                out.display()
            )),
            None if a.dry_run => super::conv::err_line(format_args!(
                "tile: {size_line}; would take about {} as {} (no --out given)",
                human(estimate),
                if format == StreamFormat::Npy {
                    "npy"
                } else {
                    "netcdf"
                }
            )),
            None => super::conv::err_line(format_args!(
                "tile: {size_line}; no --out: measuring the seams only"
            )),
        }
    }
    let (dune_slope, dune_rms, dune_slopes) = match &dunes {
        Some(d) => (
            measured_slope(d.dunes()),
            Some(d.dunes().rms()),
            Some(d.dunes().slope_stats()),
        ),
        None => (None, None, None),
    };
    if let Some(s) = dune_slopes
        && s.max_deg > ANGLE_OF_REPOSE_DEG
    {
        conv::note(format_args!(
            "warning: the dune relief is steeper than sand can stand: largest dune slope {:.1} deg, {:.1} % of the dune grid above the angle of repose ({ANGLE_OF_REPOSE_DEG} deg), rms slope {:.1} deg (rms height {:.3} m); lower --dune-rms (or leave it out for the default)",
            s.max_deg,
            100.0 * s.above_repose,
            s.rms_deg,
            dune_params.rms
        ));
    }
    // `rows`: the rows' worth of bins computed (a part of a store computes only some)
    let summary = |seams: Option<&SeamStats>, bytes: u64, elapsed: f64, rows: f64| {
        let rate = |v: f64| (elapsed > 0.0 && v > 0.0).then(|| v / elapsed);
        serde_json::json!({
            "width": w,
            "height": h,
            "levels": if a.volume.is_some() { src.levels() } else { 0 },
            "bin_size_m": dx,
            "x_axis_direction_deg": x_axis,
            "extent_m": [w as f64 * dx, h as f64 * dx],
            "mosaic": [mx, my],
            "tile": [nx, ny],
            "tiles": labels,
            "choose": choose.name(),
            "blend": a.blend,
            "estimated_bytes": estimate,
            "bytes": bytes,
            "stream_s": elapsed,
            "rows_per_s": rate(rows),
            "mb_per_s": rate(bytes as f64 / 1e6),
            "seams": seams.map(seam_json),
            "dunes": a.dunes.then(|| serde_json::json!({
                "hurst": matches!(relief, Relief::Fbm { .. }).then_some(a.hurst),
                "requested_slope": matches!(relief, Relief::Fbm { .. }).then_some(-(2.0 * a.hurst + 2.0)),
                "measured_slope": opt(dune_slope),
                "dune_wavelength_m": a.dune_wavelength,
                "rms_m": opt(dune_rms),
                "current_angle_deg": dune_params.current_angle + x_axis,
                "max_dune_slope_deg": dune_slopes.map(|s| s.max_deg),
                "rms_dune_slope_deg": dune_slopes.map(|s| s.rms_deg),
                "dune_slope_above_repose_fraction": dune_slopes.map(|s| s.above_repose),
                "angle_of_repose_deg": ANGLE_OF_REPOSE_DEG,
            })),
            "surface_slope": seams.and_then(|s| s.slope).map(|s| serde_json::json!({
                "max_deg": s.max_deg,
                "rms_deg": s.rms_deg,
                "above_repose_fraction": s.above_repose,
                "angle_of_repose_deg": ANGLE_OF_REPOSE_DEG,
            })),
        })
    };
    let envelope = |own: serde_json::Value| -> Result<String> {
        let mut own = own;
        own["recorded"] = serde_json::to_value(&recorded)?;
        let v = conv::envelope(
            "tile",
            conv::scenario_table(&a)?,
            start.elapsed().as_secs_f64(),
            own,
        )?;
        Ok(serde_json::to_string(&v)?)
    };
    if let Some(store) = &a.check {
        verify_zarr(store, src, &spec, chunk_tiles)
            .map_err(tiles_hint)
            .with_context(|| {
                format!(
                    "--check {}: not made from these tiles and parameters",
                    store.display()
                )
            })?;
        return check(store, part, a.json);
    }
    if a.dry_run {
        if a.json {
            outln!("{}", envelope(summary(None, 0, 0.0, 0.0))?)?;
        } else {
            conv::note("dry run: nothing written");
            outln!("{estimate}")?;
        }
        return Ok(());
    }
    // the measured seams and slopes, as text (the dunes' slopes whatever was measured)
    let measures = |seams: Option<&SeamStats>| -> Result<()> {
        let f = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{:.3}", x * 1e3));
        let r = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.2}"));
        if let Some(seams) = seams {
            outln!(
                "seams (mean |jump|, mm): x inside {} across {} (ratio {}), y inside {} across {} (ratio {})",
                f(seams.x.inside),
                f(seams.x.across),
                r(seams.x.ratio()),
                f(seams.y.inside),
                f(seams.y.across),
                r(seams.y.ratio())
            )?;
        }
        if let Some(s) = seams.and_then(|s| s.slope) {
            outln!(
                "surface slopes (bin to bin): largest {:.1} deg, rms {:.1} deg, {:.2} % above the angle of repose ({ANGLE_OF_REPOSE_DEG} deg)",
                s.max_deg,
                s.rms_deg,
                100.0 * s.above_repose
            )?;
        }
        if let Some(s) = dune_slopes {
            outln!(
                "dune slopes (dune grid): largest {:.1} deg, rms {:.1} deg, {:.2} % above the angle of repose",
                s.max_deg,
                s.rms_deg,
                100.0 * s.above_repose
            )?;
        }
        if let (Some(s), Relief::Fbm { hurst }) = (dune_slope, relief) {
            outln!(
                "dune spectrum slope {s:.2} (requested {:.2})",
                -(2.0 * hurst + 2.0)
            )?;
        }
        Ok(())
    };
    if let (true, Some(out)) = (zarr, &out) {
        let o = StoreOpts {
            part,
            tiles: chunk_tiles,
            init: a.init,
            json: a.json,
            quiet,
        };
        return write_store(out, src, &spec, &o, &summary, &envelope, &measures);
    }
    let bar = bar(h as u64, "tile rows", quiet);
    let t0 = Instant::now();
    let (seams, bytes, files) = match &out {
        Some(out) => {
            let rep = write_stream(out, src, &spec, |d| bar.set_position(d as u64))?;
            (rep.seams, rep.bytes, rep.files)
        }
        None => {
            let (tnx, tny) = src.tile_size();
            let mut m = SeamMeter::new(w, tnx, tny).with_slopes(dx);
            let mut row = vec![0.0f32; w];
            for y in 0..h {
                src.fill_row(y, &mut row);
                m.push_row(&row);
                if y % 64 == 0 {
                    bar.set_position(y as u64);
                }
            }
            (m.finish(), 0, Vec::new())
        }
    };
    bar.finish_and_clear();
    let elapsed = t0.elapsed().as_secs_f64();
    for p in &files {
        conv::wrote(p);
    }
    if a.json {
        outln!(
            "{}",
            envelope(summary(Some(&seams), bytes, elapsed, h as f64))?
        )?;
    } else {
        measures(Some(&seams))?;
        outln!(
            "{} in {elapsed:.2} s ({:.0} rows/s, {:.1} MB/s)",
            human(bytes),
            h as f64 / elapsed.max(1e-9),
            bytes as f64 / 1e6 / elapsed.max(1e-9)
        )?;
    }
    Ok(())
}

/// Checks the path of a Zarr store before the run ([`check_store_target`]): absent, a store,
/// or (`in_place`: a part or `--init`) an empty folder; errors name `option` and the path.
fn check_store_path(option: &str, path: &std::path::Path, in_place: bool) -> Result<()> {
    check_store_target(path, in_place)
        .map_err(|why| anyhow::anyhow!("{option} {}: {why}", path.display()))
}

/// The options of the rippled dunes (`--dunes`).
const DUNE_OPTIONS: &[&str] = &[
    "hurst",
    "dune_rms",
    "dune_wavelength",
    "steering",
    "dune_grid",
    "dune_seed",
];

/// The options of the tiles generated in-process (`--generate`).
const GENERATE_OPTIONS: &[&str] = &[
    "ripple_scenario",
    "size",
    "layers",
    "steps",
    "activity",
    "bin_size",
    "seeds",
];

/// Warns of each of `ids` that a scenario file set away from its default although it
/// applies to `applies` only (the command line refuses such a flag; a scenario written by
/// --print-scenario holds every key, so only a value away from the default is named).
fn warn_scenario_keys(a: &Args, ids: &[&str], applies: &str) -> Result<()> {
    let t = conv::scenario_table(a)?;
    for id in ids {
        if let Some(v) = t.get(*id) {
            let v = conv::cli_text(v);
            if conv::set_by_scenario(id, &v) {
                conv::note(format_args!(
                    "warning: the scenario's {id} = {v} has no effect: it applies to {applies}"
                ));
            }
        }
    }
    Ok(())
}

/// How many missing or damaged chunks `tile --check` lists per array on stderr.
const CHECK_LISTED: usize = 10;

/// `tile --check STORE`: prints the report; an error (non-zero exit) when incomplete.
fn check(store: &std::path::Path, part: Option<Part>, json: bool) -> Result<()> {
    if !store.is_dir() {
        bail!(
            "--check {}: not a folder (a Zarr store is a folder)",
            store.display()
        );
    }
    let c = check_zarr(store).with_context(|| format!("--check {}", store.display()))?;
    let rerun = part.map(|p| c.parts_to_rerun(p.count));
    if json {
        let mut v = serde_json::to_value(&c)?;
        v["missing"] = c.missing().into();
        v["damaged"] = c.damaged().into();
        if let Some(r) = &rerun {
            v["parts_to_rerun"] = serde_json::json!(r);
        }
        outln!("{}", serde_json::to_string(&v)?)?;
    } else {
        for arr in &c.arrays {
            super::conv::err_line(format_args!(
                "{}: {} of {} chunks complete, {} missing, {} damaged",
                arr.name,
                arr.complete,
                arr.chunks,
                arr.missing.len(),
                arr.damaged.len()
            ));
            // the first CHECK_LISTED of each kind, and how many more (`--json` lists them all)
            let list = |lines: Vec<String>, kind: &str| {
                for l in lines.iter().take(CHECK_LISTED) {
                    super::conv::err_line(l);
                }
                if lines.len() > CHECK_LISTED {
                    super::conv::err_line(format_args!(
                        "  ... and {} more {kind} chunks (--json lists every chunk)",
                        lines.len() - CHECK_LISTED
                    ));
                }
            };
            list(
                arr.damaged
                    .iter()
                    .map(|(idx, why)| format!("  damaged chunk {idx:?}: {why}"))
                    .collect(),
                "damaged",
            );
            list(
                arr.missing
                    .iter()
                    .map(|idx| format!("  missing chunk {idx:?}"))
                    .collect(),
                "missing",
            );
        }
        for t in &c.stale_temporaries {
            super::conv::err_line(format_args!(
                "stale temporary file (a killed writer): {}",
                t.display()
            ));
        }
        if let (Some(r), Some(p)) = (&rerun, part) {
            super::conv::err_line(format_args!("parts to re-run (of {}): {r:?}", p.count));
        }
    }
    if let Some(why) = &c.unverified {
        bail!("{}: cannot be called complete: {why}", store.display());
    }
    if !c.complete {
        bail!(
            "{}: incomplete: {} missing and {} damaged chunks; re-run the parts that own them",
            store.display(),
            c.missing(),
            c.damaged()
        );
    }
    if !json {
        super::conv::err_line(format_args!("{}: complete", store.display()));
    }
    Ok(())
}

/// How to write a Zarr store.
struct StoreOpts {
    part: Option<Part>,
    tiles: Option<(usize, usize)>,
    init: bool,
    json: bool,
    quiet: bool,
}

/// A store's metadata that differs in the tiles' digest: said in words (the tiles' names and
/// steps may be the same, their values are not).
fn tiles_hint(e: cellsurf::tile::TileError) -> anyhow::Error {
    let text = e.to_string();
    if text.contains(&format!("attributes.param_{TILES_DIGEST}")) {
        anyhow::anyhow!(
            "{text}\n(the tiles hold other values than those the store was made from, whatever their file names and steps: a --tile file remade since, or --generate runs that computed other values; every part of a store must read the same tiles)"
        )
    } else {
        e.into()
    }
}

/// The measured seams and slopes, as text, of the dunes as well (`run`'s).
type Measures<'a> = dyn Fn(Option<&SeamStats>) -> Result<()> + 'a;

/// The JSON summary of `run` from the seams, bytes written, seconds and rows' worth of bins
/// computed.
type Summary<'a> = dyn Fn(Option<&SeamStats>, u64, f64, f64) -> serde_json::Value + 'a;

/// Writes a Zarr store (all of it, one part, or its metadata with `init`). Without a part, a
/// new store is written into a temporary folder and moved into place when complete
/// ([`write_zarr_whole`]); a part, or a run that finishes an existing store, writes in place,
/// and an interrupt (Ctrl-C) or an error while writing its chunks (a full disk) then says on
/// stderr that the store is incomplete, what was left and how to finish and check it.
fn write_store(
    out: &std::path::Path,
    src: &dyn RowSource,
    spec: &StreamSpec,
    o: &StoreOpts,
    summary: &Summary,
    envelope: &dyn Fn(serde_json::Value) -> Result<String>,
    measures: &Measures,
) -> Result<()> {
    let (json, quiet) = (o.json, o.quiet);
    let t0 = Instant::now();
    if o.init {
        let (_, layout) = init_zarr(out, src, spec, o.tiles).map_err(tiles_hint)?;
        let el = t0.elapsed().as_secs_f64();
        if json {
            conv::wrote(out);
            let mut v = summary(None, 0, el, 0.0);
            v["zarr"] = serde_json::json!({ "layout": layout, "init": true });
            outln!("{}", envelope(v)?)?;
        } else {
            conv::wrote(out);
            outln!(
                "initialised {}: {} x {} chunks of {} x {} bins ({} x {} tiles)",
                out.display(),
                layout.grid.0,
                layout.grid.1,
                layout.chunk.0,
                layout.chunk.1,
                layout.tiles.0,
                layout.tiles.1
            )?;
        }
        return Ok(());
    }
    let part = o.part.unwrap_or(Part::WHOLE);
    let levels = if spec.volume.is_some() {
        src.levels()
    } else {
        0
    };
    let layout = match o.tiles {
        Some(t) => ZarrLayout::with_tiles(src, levels, t)?,
        None => ZarrLayout::new(src, levels),
    };
    let bar = bar(
        part.range(layout.chunks()).len() as u64,
        "zarr chunks",
        quiet,
    );
    let progress = |d: usize| bar.set_position(d as u64);
    let in_place = o.part.is_some() || is_store(out);
    let rep = if in_place {
        let rerun = match o.part {
            Some(p) => format!("the same command (--part {}/{})", p.index, p.count),
            None => "the same command".into(),
        };
        let kept = format!(
            "{} keeps the chunks written so far, whole (a chunk is renamed into place when complete)",
            out.display()
        );
        let finish = format!(
            "re-run {rerun} to finish it (its complete chunks are kept), or `cellsurf tile --check {}` to list what is missing",
            out.display()
        );
        let _said = conv::say_on_interrupt(format!("interrupted: {kept}; {finish}"));
        // The metadata first: a store made with other parameters is refused as it was; a
        // failure after it (writing a chunk: a full disk, say) leaves a partial store, said so.
        init_zarr(out, src, spec, o.tiles).map_err(tiles_hint)?;
        write_zarr(out, src, spec, o.tiles, part, progress).map_err(|e| {
            anyhow::anyhow!(
                "{e}\nthe store is incomplete: {kept}; once the cause of the error is mended, {finish}"
            )
        })?
    } else {
        write_zarr_whole(out, src, spec, o.tiles, progress).map_err(tiles_hint)?
    };
    bar.finish_and_clear();
    let el = rep.elapsed_s;
    let rows = rep.bins as f64 / layout.width.max(1) as f64;
    conv::wrote(out);
    if json {
        let mut v = summary(rep.seams.as_ref(), rep.bytes, el, rows);
        v["zarr"] = serde_json::to_value(&rep)?;
        outln!("{}", envelope(v)?)?;
    } else {
        outln!(
            "{} part {}/{}: {} of {} chunks written ({} kept), {} of values as {} in {el:.2} s ({:.1} MB/s of values)",
            out.display(),
            part.index,
            part.count,
            rep.written,
            rep.owned,
            rep.kept,
            human(rep.bytes),
            human(rep.stored_bytes),
            rep.bytes as f64 / 1e6 / el.max(1e-9)
        )?;
        if rep.seams.is_none() {
            outln!(
                "seams and slopes not measured: this run computed {} of the {} chunks (they need every row of the surface)",
                rep.written,
                layout.chunks()
            )?;
        }
        measures(rep.seams.as_ref())?;
    }
    Ok(())
}
