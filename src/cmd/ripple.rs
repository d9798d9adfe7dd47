//! `cellsurf ripple`: runs the sand-ripple volume generator ([`cellsurf::ripple`]) and writes
//! the volume as NetCDF-3, `.npy` files or a Zarr v3 store; `--json` prints a summary.
//!
//! Parameters come from a built-in `--recipe` ([`cellsurf::ripple::recipe`]: by default the
//! recipe for mature current ripples where the current dominates, the paper's rules and Fig. 3
//! situation where the waves do), or from a `--scenario` TOML file (`model = "ripple"` and the
//! same keys as the options, with underscores; unknown keys rejected), then the options given
//! on the command line.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use cellsurf::ripple::output::{run_recording, write_netcdf_with, write_npy_with};

use super::conv::{self, Format as ConvFormat, Outputs, Size};
use cellsurf::ripple::clock::StepClock;
use cellsurf::ripple::equilibrium::{EARLIEST_STOP, run_until_mature};
use cellsurf::ripple::params;
use cellsurf::ripple::predictors::{Prediction, largest_resolving_bin, length_along};
use cellsurf::ripple::recipe::{
    DEFAULT_CAP_S, ORBITS_PER_WAVELENGTH, Recipe, TRAVELS_PER_WAVELENGTH, expected_wavelength,
};
use cellsurf::ripple::regime::Regime;
use cellsurf::ripple::waves::{MAX_PERIOD_S, SurfaceWave, run_wave_friction_factor};
use cellsurf::ripple::{
    Abstraction, AcousticModel, Analysis, Field, Format, Mode, OutputSpec, Ripple, RippleParams,
};

/// Options of `cellsurf ripple`. Negative numbers are read as values, so that the model's
/// range checks (not the argument parser) report them with the valid range.
#[derive(clap::Args)]
#[command(
    allow_negative_numbers = true,
    after_help = "Examples:\n  \
        cellsurf ripple --out bed.nc          # mature current ripples: a 1.9 m section\n  \
        cellsurf ripple --size 384x64 --out bed.nc   # a 3-D field, 71 x 12 cm: minutes\n  \
        cellsurf ripple --recipe paper --out bed.nc            # the paper's Fig. 3 situation\n  \
        cellsurf ripple --recipe paper --size 64x32 --steps 2000 --out bed.npy --json\n  \
        cellsurf ripple --current-speed 0 --wave-velocity 0.4 --wave-period 8s --duration 1h\n  \
        cellsurf ripple --recipe paper --size 400x1 --abstraction shadow --out section.npy\n  \
        cellsurf ripple --print-scenario > r.toml && cellsurf ripple --scenario r.toml --d50 0.3\n  \
        cellsurf ripple --d50 0.4 --duration 6000s --json    # 6000 s, not until equilibrium"
)]
pub struct Args {
    /// Start from this scenario file (TOML, `model = "ripple"` and the same keys as the
    /// options, e.g. `current_angle = 30`; `steps` or `duration_s`, the wave period as
    /// `wave_period` in steps or `wave_period_s`); options typed here override it.
    #[arg(long, value_name = "FILE.toml")]
    scenario: Option<PathBuf>,
    /// Start from a built-in recipe: mature-current (current ripples of nature's size that stop
    /// growing, with slip faces: a 2-D section of 1024 bins of 0.75 flat-bed travels of the
    /// median grain, 1.86 mm for 0.2 mm sand at 0.5 m/s, automata a tenth of the bin, 10 cm of
    /// sand, run until equilibrium, at most 6 h; docs/ripple.md, "A recipe for mature current
    /// ripples"), mature-waves (wave ripples that follow the orbit and stop growing: the
    /// recipe's rules with every length in units of the waves' orbital excursion A, bins of A /
    /// 50, run until equilibrium; docs/ripple.md, "A recipe for mature wave ripples") or paper
    /// (the paper's rules in its Fig. 3 situation: 3-D, 128x64 bins of 5 mm, 30 automata of
    /// 0.5 mm, 10000 steps; its current ripples coarsen without end); options typed here
    /// override it. `--print-scenario` shows its keys [default: mature-current; paper where
    /// the waves' bed stress exceeds the current's].
    #[arg(long, value_name = "NAME", conflicts_with = "scenario")]
    recipe: Option<Recipe>,
    /// 2d (one section along the current) or 3d [default: the recipe's (mature-current 2d,
    /// paper 3d); with --size and no --scenario, 2d for NXx1 and 3d otherwise].
    #[arg(long)]
    mode: Option<Mode>,
    /// Hydrodynamics: slices (water volume, Sect. 2.3) or shadow (Eq. 3; not with the flow
    /// separation of --recipe mature-current: give --recipe paper) [default: slices].
    #[arg(long)]
    abstraction: Option<Abstraction>,
    /// Columns along x and y, NXxNY, each 3 to 65536 (NXx1 in 2d) [default: mature-current
    /// 1024x1, 384x64 with --mode 3d; paper 128x64].
    #[arg(long, value_name = "NXxNY", value_parser = conv::size_in(params::SIZE_SIDES))]
    size: Option<Size>,
    /// Old spelling of the x part of --size (kept for one release).
    #[arg(long, hide = true, value_parser = conv::count_in::<usize>(params::NX), conflicts_with = "size")]
    nx: Option<usize>,
    /// Old spelling of the y part of --size (kept for one release).
    #[arg(long, hide = true, value_parser = conv::count_in::<usize>(params::NY), conflicts_with = "size")]
    ny: Option<usize>,
    /// Mean initial sand thickness, automata per column, 1 to 4096 [default: mature-current
    /// 10 cm of sand, 538 in its bins for 0.2 mm sand at 0.5 m/s; paper 30].
    #[arg(long, value_parser = conv::count_in::<usize>(params::LAYERS))]
    layers: Option<usize>,
    /// Horizontal bin size, m, above 0 and at most 100 [default: mature-current 0.75 flat-bed
    /// travels of the median grain in the current (bin_travels), 0.00186 for 0.2 mm sand at
    /// 0.5 m/s; paper 0.005]. With mature-current it sets the automata too (a tenth of the
    /// bin, and the layers of 10 cm of sand) unless --layer-thickness is given.
    #[arg(long)]
    bin_size: Option<f64>,
    /// Layer thickness gd, m, above 0 and at most --bin-size x tan(--avalanche-angle) (one
    /// automaton over one bin no steeper than the avalanche angle) [default: mature-current a
    /// tenth of the bin; paper 0.0005].
    #[arg(long)]
    layer_thickness: Option<f64>,
    /// Steps (`1e4` accepted), 0 to 2^40 [default: mature-current --until equilibrium
    /// --duration 6h; paper 10000].
    #[arg(long, value_name = "N", value_parser = conv::count_in::<u64>(params::STEPS))]
    steps: Option<u64>,
    /// Simulated duration instead of --steps: seconds, or with a unit (`90s`, `30min`, `2h`,
    /// `1d`). The steps follow from the duration of a step, set by the Meyer-Peter & Mueller
    /// bedload (--json reports `step_duration_s`).
    #[arg(long, value_name = "DURATION", value_parser = conv::parse_duration, conflicts_with = "steps", allow_hyphen_values = true)]
    duration: Option<f64>,
    /// Stop early once the field is mature: `equilibrium` (wavelength and height each change
    /// by less than 10 % over two successive doublings of the time, t to 2t and 2t to 4t,
    /// checked at 1000 steps and its doublings, so the earliest stop is at 4000 steps);
    /// --steps or --duration is the cap. Recorded as `until` in the parameters, with the step
    /// and reason of the stop in the output. A field that pauses for long while it coarsens
    /// can still pass the test (docs/ripple.md "Until equilibrium"): check maturity on a
    /// longer run [default: equilibrium, at most 6 h, with --recipe mature-current and no
    /// --steps or --duration; otherwise none].
    #[arg(long, value_name = "WHEN", value_parser = ["equilibrium"])]
    until: Option<String>,
    /// Fraction of automata triggered per step, above 0 and at most 1 [default: 0.001].
    #[arg(long)]
    activity: Option<f64>,
    /// Median grain size, mm, 0.01 to 10 [default: 0.2].
    #[arg(long)]
    d50: Option<f64>,
    /// Sorting sigma_phi, phi units, 0 to 2 [default: 0.5].
    #[arg(long)]
    sorting: Option<f64>,
    /// Current direction, degrees counter-clockwise from east, -360 to 360 (a 2d section runs
    /// along it; with --frame grid only 0 or 180) [default: 0].
    #[arg(long, allow_hyphen_values = true)]
    current_angle: Option<f64>,
    /// Current speed, m/s, 0 to 10 (sheet flow, above the ripple regime, is refused)
    /// [default: 0.5].
    #[arg(long)]
    current_speed: Option<f64>,
    /// Wave period, seconds or with a unit (`8s`), above 0 and at most 1000 s (needs
    /// --wave-velocity or --wave-height); converted to steps with the step duration (--json
    /// reports `wave_period_steps`) [default: no wave].
    #[arg(long, value_name = "DURATION", value_parser = conv::parse_duration, allow_hyphen_values = true)]
    wave_period: Option<f64>,
    /// Near-bed orbital velocity amplitude of the waves, m/s, 0 to 10 (above 0 it needs
    /// --wave-period; 0 is no waves, and switches off a scenario's) [default: 0].
    #[arg(
        long = "wave-velocity",
        alias = "wave-amplitude",
        value_name = "WAVE_VELOCITY"
    )]
    wave_amplitude: Option<f64>,
    /// Surface wave height H (crest to trough), m: the near-bed orbital velocity then follows
    /// from linear wave theory with --wave-period and --water-depth (instead of
    /// --wave-velocity); above 0 and at most 100, refused above 0.78 x depth or 1/7 of the
    /// wavelength (breaking).
    #[arg(
        long,
        value_name = "M",
        conflicts_with = "wave_amplitude",
        allow_hyphen_values = true
    )]
    wave_height: Option<f64>,
    /// Water depth h, m, for --wave-height; above 0 and at most 10000.
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    water_depth: Option<f64>,
    /// Wave friction factor f_w of the waves' bed stress rho (f_w / 2) U_w^2, 0 to 1 (0: the
    /// waves use the current's drag coefficient) [default: with --wave-period, Soulsby (1997)
    /// Eq. 60a, 1.39 (A / z0)^-0.52 with A = U_w T / (2 pi) and z0 = d50 / 12, at most 0.3 and
    /// at least twice the drag coefficient, 0.005: long periods rub like a current].
    #[arg(long, allow_hyphen_values = true)]
    wave_friction_factor: Option<f64>,
    /// The lee vortex of wave ripples (docs/ripple.md "Waves"): the shelter behind a crest
    /// reaches no further than the vortex has travelled since the flow reversed, half the
    /// water's travel, A (1 - cos psi) / 2 with A = U_w T / (2 pi), and grains in it are
    /// carried back towards the crest. It acts where the waves' bed stress exceeds the
    /// current's [default: on with waves and --wave-period; this flag asks for it explicitly:
    /// it needs --wave-period and waves, and warns where the current dominates].
    #[arg(long, conflicts_with = "no_wave_vortex")]
    wave_vortex: bool,
    /// Switch the lee vortex of wave ripples off (the paper's rules alone: flatter wave
    /// ripples, docs/ripple.md "Waves").
    #[arg(long)]
    no_wave_vortex: bool,
    /// The vortex's return speed as a fraction of the free stream's, 0 to 1; refused when the
    /// vortex is off [default: 0.5].
    #[arg(long)]
    vortex_strength: Option<f64>,
    /// Direction the waves propagate towards, degrees counter-clockwise from east, -360 to 360;
    /// 3-D only. With a current, the two bed stresses add as vectors, the current's raised
    /// by the waves (Soulsby 1997, Eqs. 69-70) [default: the current's direction].
    #[arg(long, allow_hyphen_values = true)]
    wave_angle: Option<f64>,
    /// Orientation of the lattice: flow (x along the flow: the current, or the waves without
    /// current; the volume is written in that frame, its x axis at `x_axis_direction_deg` from
    /// east) or grid (x east; an oblique flow crosses the lattice, whose axes and diagonals
    /// pull the crests towards them); in 2d the section runs along the current in the flow
    /// frame (towards -x, its x axis the opposite way, where the current points west of
    /// north-south), and only along the x axis (0 or 180 deg) in the grid frame [default: flow].
    #[arg(long)]
    frame: Option<cellsurf::ripple::Frame>,
    /// Avalanche angle alpha, degrees, above 0 and below 90 [default: 32].
    #[arg(long)]
    avalanche_angle: Option<f64>,
    /// Stoss stability angle beta, degrees, 0 to --avalanche-angle [default: 7].
    #[arg(long)]
    stoss_angle: Option<f64>,
    /// Creep angle gamma, degrees, 0 to below 90 [default: 5].
    #[arg(long)]
    creep_angle: Option<f64>,
    /// Acoustic model: hamilton or apl-uw [default: hamilton].
    #[arg(long)]
    acoustics: Option<AcousticModel>,
    /// Seed of the random stream, 0 to 2^53 = 9007199254740992 [default: 1].
    #[arg(long, value_parser = parse_seed, allow_hyphen_values = true)]
    seed: Option<u64>,
    /// Steps at which to keep the elevation, comma-separated [default: 0 and the last step].
    #[arg(long, value_delimiter = ',', value_parser = conv::count_within::<u64>(SNAPSHOTS))]
    snapshots: Option<Vec<u64>>,
    /// Fields to write (comma-separated): elevation, grain_size, porosity, density,
    /// sound_speed, impedance [default: all; without porosity for apl-uw]. `cellsurf tile` and
    /// `cellsurf raytrace` read the elevation: an output without it cannot be tiled or
    /// ray-traced; .npy needs it (NAME.npy is the elevation).
    #[arg(long, value_delimiter = ',')]
    fields: Option<Vec<Field>>,
    /// Old spelling: netcdf or npy, with --out a file stem (kept for one release).
    #[arg(long, hide = true)]
    format: Option<Format>,
    /// Output file; the extension picks the format: .nc (NetCDF-3, CF-style), .npy
    /// (NAME.npy the elevation snapshots, NAME_FIELD.npy each volume field, NAME.json the
    /// parameters) or .zarr (a Zarr v3 store for xarray, written whole then renamed). Without it nothing is written: the run is measured only (see --json).
    #[arg(long, value_name = "FILE")]
    out: Vec<PathBuf>,
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

/// What a run was asked for in seconds, from the command line (`--duration`, `--wave-period`)
/// or a scenario file (`duration_s`, `wave_period_s`), each with the name to give in a
/// message (`--duration`, or `duration_s (in --scenario FILE)`).
#[derive(Clone, Default)]
pub struct Seconds {
    pub duration: Option<(f64, String)>,
    pub wave_period: Option<(f64, String)>,
}

impl Seconds {
    fn duration(&self) -> Option<f64> {
        self.duration.as_ref().map(|d| d.0)
    }
    fn wave_period(&self) -> Option<f64> {
        self.wave_period.as_ref().map(|t| t.0)
    }
    /// The name of the wave period for a message.
    fn wave_period_flag(&self) -> &str {
        self.wave_period.as_ref().map_or("--wave-period", |t| &t.1)
    }
}

/// Takes a ripple scenario's keys in seconds, `duration_s` and `wave_period_s`, out of its
/// table `t` (read from `path`, given by `flag`: `--scenario`, or `tile --ripple-scenario`):
/// each gives the same quantity as `steps` and `wave_period` in steps, so a file with both is
/// refused, as `--steps` with `--duration` is.
pub fn scenario_seconds(
    t: &mut toml::Table,
    flag: &str,
    path: &std::path::Path,
) -> Result<Seconds> {
    let mut s = Seconds::default();
    for (key, steps_key, what, max) in [
        (
            "duration_s",
            "steps",
            "the run's length (as --steps and --duration, which cannot be given together)",
            f64::INFINITY,
        ),
        (
            "wave_period_s",
            "wave_period",
            "the wave period",
            MAX_PERIOD_S,
        ),
    ] {
        let Some(v) = t.remove(key) else { continue };
        let name = format!("{key} (in {flag} {})", path.display());
        let secs = match v {
            toml::Value::Float(x) => x,
            toml::Value::Integer(i) => i as f64,
            other => bail!(
                "in {flag} {}: {key} = {other} is not a number: expected a number of seconds",
                path.display()
            ),
        };
        if !(secs.is_finite() && secs > 0.0 && secs <= max) {
            bail!(
                "in {flag} {}: {key} = {} is out of range: expected a number of seconds above 0{}",
                path.display(),
                cellsurf::ripple::params::shown(secs),
                if max.is_finite() {
                    format!(" and at most {max}")
                } else {
                    String::new()
                }
            );
        }
        if let Some(n) = t.get(steps_key) {
            bail!(
                "in {flag} {}: {steps_key} = {n} and {key} = {} both give {what}: keep one, \
                 {steps_key} in steps or {key} in seconds",
                path.display(),
                cellsurf::ripple::params::shown(secs),
            );
        }
        match key {
            "duration_s" => s.duration = Some((secs, name)),
            _ => s.wave_period = Some((secs, name)),
        }
    }
    Ok(s)
}

/// The run's parameters, what it was asked for in seconds, and the recipe it started from
/// (none: a scenario file). Without `--recipe` or `--scenario` the run starts from the recipe
/// for mature current ripples where the current dominates the bed stress (or nothing moves),
/// and from the paper's rules where the waves dominate (under waves the recipe's ripples do
/// not follow the orbit; the lee vortex gives wave ripples their shape there). The last is
/// a note on the bin, for once the run is known to be valid.
fn params(a: &Args) -> Result<(RippleParams, Seconds, Option<Recipe>, Option<String>)> {
    if a.scenario.is_some() {
        let (p, secs, note) = params_from(a, None)?;
        return Ok((p, secs, None, note));
    }
    let recipe = a.recipe.unwrap_or(if waves_dominate_asked(a) {
        Recipe::Paper
    } else {
        Recipe::MatureCurrent
    });
    let (p, secs, note) = params_from(a, Some(recipe)).map_err(|e| recipe_hint(e, a, recipe))?;
    Ok((p, secs, Some(recipe), note))
}

/// Whether the waves typed on the command line rub the bed harder than the current
/// ([`RippleParams::waves_dominate`]), from the options alone, as [`params_from`] sets them:
/// the orbital velocity (`--wave-velocity`, or linear theory from `--wave-height`), the waves'
/// friction factor (`--wave-friction-factor`, or Soulsby's Eq. 60a with `--wave-period`) and
/// the current (none of them is a key of a recipe). Bad wave input counts as no waves; the
/// run's own reading then names it.
fn waves_dominate_asked(a: &Args) -> bool {
    let base = RippleParams::default();
    let d50_m = a.d50.unwrap_or(base.d50) * 1e-3;
    let u_w = match (
        a.wave_amplitude,
        a.wave_height,
        a.wave_period,
        a.water_depth,
    ) {
        (Some(u), _, _, _) => u,
        (None, Some(h), Some(t), Some(d)) => {
            SurfaceWave::new(h, t, d).map_or(0.0, |w| w.orbital_velocity())
        }
        _ => 0.0,
    };
    let f_w = match (a.wave_friction_factor, a.wave_period) {
        (Some(f), _) => f,
        (None, Some(t)) if u_w > 0.0 && t > 0.0 => {
            run_wave_friction_factor(u_w, t, d50_m, base.drag_coefficient)
        }
        _ => 0.0,
    };
    RippleParams {
        current_speed: a.current_speed.unwrap_or(base.current_speed),
        wave_amplitude: u_w,
        wave_friction_factor: f_w,
        ..base
    }
    .waves_dominate()
}

/// An error of a run that started from `recipe` (not a scenario), with what the recipe has to
/// do with it: a key of the recipe that the options typed leave no room for (flow separation
/// with `--abstraction shadow`, or with an avalanche angle or bins that hold no drop of two
/// automata), or the recipe's 2-D section where the options ask for a direction across it
/// (an oblique current in the grid frame).
fn recipe_hint(e: anyhow::Error, a: &Args, recipe: Recipe) -> anyhow::Error {
    let text = e.to_string();
    let given = a.recipe.map_or_else(
        || format!("the default under a current (--recipe {recipe})"),
        |r| format!("--recipe {r}"),
    );
    let range = match e.downcast_ref::<cellsurf::ripple::RippleError>() {
        Some(cellsurf::ripple::RippleError::Range {
            parameter,
            expected,
            ..
        }) => Some((*parameter, expected.as_str())),
        _ => None,
    };
    if recipe == Recipe::MatureCurrent && range.is_some_and(|(k, _)| k == "separation_angle") {
        let typed = conv::given_flags(&[
            ("abstraction", "--abstraction", a.abstraction.is_some()),
            (
                "avalanche_angle",
                "--avalanche-angle",
                a.avalanche_angle.is_some(),
            ),
            ("bin_size", "--bin-size", a.bin_size.is_some()),
            (
                "layer_thickness",
                "--layer-thickness",
                a.layer_thickness.is_some(),
            ),
        ]);
        return anyhow::anyhow!(
            "{text}. This separation_angle (flow separation) comes from {given}, and {} it out of range: give --recipe paper for the paper's rules, or a scenario file with the recipe's keys (docs/ripple_mature_current.toml) and a separation_angle in range",
            if typed.is_empty() {
                "the options typed put".to_string()
            } else {
                format!(
                    "{} as typed here put{}",
                    typed.join(" and "),
                    if typed.len() == 1 { "s" } else { "" }
                )
            }
        );
    }
    // (the mode follows --mode, --size or --ny; --nx alone keeps the recipe's)
    let sized = a.mode.is_some() || a.size.is_some() || a.ny.is_some();
    if recipe.params().mode == Mode::TwoD
        && !sized
        && range.is_some_and(|(_, expected)| expected.contains("2-D mode"))
    {
        let frame = if range.is_some_and(|(k, _)| k == "current_angle") {
            ", or leave out --frame grid (in the flow frame a section runs along any current)"
        } else {
            ""
        };
        return anyhow::anyhow!(
            "{text}. The run is a 2-D section because {given} is one: give --size NXxNY (NY above 1) or --mode 3d for a 3-D field{frame}"
        );
    }
    e
}

/// A depth of sand in metres for a message: to the millimetre, without trailing zeros.
fn depth_m(d: f64) -> String {
    let s = format!("{d:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// A 3-D run of a recipe whose domain is a 2-D section (`--mode 3d` without `--size`): 384 x
/// 64 bins (71 x 12 cm in the recipe's bins for 0.2 mm sand at 0.5 m/s, 1.86 mm: four of the
/// predicted wavelengths along the flow at 0.1-0.4 mm).
pub const RECIPE_3D_SIZE: (usize, usize) = (384, 64);

/// The run's parameters from `recipe` (none: `--scenario`) and the options, what it was
/// asked for in seconds, and a note on the bin where the options or `bin_travels` set it.
fn params_from(
    a: &Args,
    recipe: Option<Recipe>,
) -> Result<(RippleParams, Seconds, Option<String>)> {
    let mut secs = Seconds::default();
    let mut p = match &a.scenario {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read --scenario {}", path.display()))?;
            let mut t: toml::Table = text
                .parse()
                .with_context(|| format!("--scenario {} is not TOML", path.display()))?;
            match t.remove("model") {
                None => {}
                Some(toml::Value::String(m)) if m == "ripple" => {}
                Some(m) => bail!(
                    "--scenario {} is a {m} scenario, not 'ripple': run `cellsurf {m} --scenario {}`",
                    path.display(),
                    path.display()
                ),
            }
            secs = scenario_seconds(&mut t, "--scenario", path)?;
            RippleParams::from_table(t)
                .map_err(|e| anyhow::anyhow!("in --scenario {}: {e}", path.display()))?
        }
        None => recipe.unwrap_or(Recipe::Paper).params(),
    };
    // a recipe's own length where none is given: until the field is mature, at most 6 h
    if recipe.is_some_and(Recipe::runs_until_mature) && a.steps.is_none() && a.duration.is_none() {
        secs.duration = Some((DEFAULT_CAP_S, "--duration".into()));
        p.until = Some("equilibrium".into());
    }
    // the command line's --steps and --duration win over the file's duration_s
    if a.steps.is_some() {
        secs.duration = None;
    }
    if let Some(d) = a.duration {
        secs.duration = Some((d, "--duration".into()));
    }
    if let Some(t) = a.wave_period {
        secs.wave_period = Some((t, "--wave-period".into()));
    }
    if let Some(s) = a.size {
        (p.nx, p.ny) = (s.w, s.h);
    }
    macro_rules! set {
        ($($f:ident),+) => { $(if let Some(v) = a.$f.clone() { p.$f = v; })+ };
    }
    set!(
        mode,
        abstraction,
        nx,
        ny,
        layers,
        bin_size,
        layer_thickness,
        steps,
        activity,
        d50,
        sorting,
        current_angle,
        current_speed,
        wave_amplitude,
        wave_friction_factor,
        frame,
        avalanche_angle,
        stoss_angle,
        creep_angle,
        acoustics,
        seed
    );
    if a.until.is_some() {
        p.until = a.until.clone();
    }
    // a recipe that is one resolution: --bin-size alone brings its automata and layers along
    // (a bin out of its own range is named by its own check; the note once the run is valid)
    let mut bin_note = None;
    if let (Some(r), Some(b), None) = (
        recipe.filter(|r| r.automata_follow_bin()),
        a.bin_size
            .filter(|b| b.is_finite() && *b > 0.0 && *b <= 100.0),
        a.layer_thickness,
    ) {
        let (t, layers) = r.automata_for_bin(b);
        if t <= 0.0 || (a.layers.is_none() && !params::LAYERS.contains(layers as u64)) {
            let rp = r.params();
            // the finest bin whose sand fits in the most layers (rounded up to 3 digits)
            let finest = rp.layers as f64 * rp.bin_size / (params::LAYERS.max as f64 + 0.5);
            let scale = 10f64.powi(2 - finest.log10().floor() as i32);
            bail!(
                "--bin-size = {} m is out of range for the recipe {r}, whose automata are a tenth of the bin and whose {} m of sand must fit in at most {} layers: expected --bin-size of at least {} m, or give --layers, or --layer-thickness to keep other automata",
                cellsurf::ripple::params::shown(b),
                depth_m(rp.layers as f64 * rp.layer_thickness),
                params::LAYERS.max,
                cellsurf::ripple::params::shown((finest * scale).ceil() / scale)
            );
        }
        p.layer_thickness = t;
        if a.layers.is_none() {
            p.layers = layers;
        }
        bin_note = Some(format!(
            "note: the recipe {r} is one resolution, automata a tenth of the bin: --bin-size = {} m gives --layer-thickness = {} m{} (give --layer-thickness to keep other automata)",
            cellsurf::ripple::params::shown(b),
            cellsurf::ripple::params::shown(t),
            if a.layers.is_none() {
                format!(
                    " and --layers = {layers} ({} m of sand)",
                    depth_m(layers as f64 * t)
                )
            } else {
                String::new()
            }
        ));
    }
    // the mode from the size where none is named: NXx1 is a section, NXxNY a 3-D field
    if let Some(h) = a
        .size
        .map(|s| s.h)
        .or(a.ny)
        .filter(|_| a.mode.is_none() && a.scenario.is_none())
    {
        p.mode = if h == 1 { Mode::TwoD } else { Mode::ThreeD };
    }
    // a recipe's 2-D section run in 3-D: the sides not typed (old spellings) from RECIPE_3D_SIZE
    if recipe.is_some_and(|r| r.params().ny == 1) && p.mode == Mode::ThreeD && a.size.is_none() {
        if a.nx.is_none() {
            p.nx = RECIPE_3D_SIZE.0;
        }
        if a.ny.is_none() {
            p.ny = RECIPE_3D_SIZE.1;
        }
    }
    if a.wave_angle.is_some() {
        p.wave_angle = a.wave_angle;
    }
    if let Some(t) = secs.wave_period() {
        // one limit in seconds, whether the period goes with --wave-velocity or --wave-height
        if !(t.is_finite() && t > 0.0 && t <= MAX_PERIOD_S) {
            bail!(
                "{} = {} s is out of range: expected a number of seconds in (0, {MAX_PERIOD_S}]",
                secs.wave_period_flag(),
                cellsurf::ripple::params::shown(t)
            );
        }
        // seconds; a provisional period in steps until the step duration is known (the
        // clock's flux is averaged over whole cycles whatever it is)
        p.wave_period = 64.0;
    }
    match (a.wave_height, secs.wave_period(), a.water_depth) {
        (Some(h), Some(t), Some(d)) => {
            p.wave_amplitude = SurfaceWave::new(h, t, d)?.orbital_velocity();
        }
        (None, _, None) => {}
        (h, _, d) => bail!(
            "{} = {} needs {}: surface waves are given by their height, period and the water depth (linear wave theory)",
            if h.is_some() {
                "--wave-height"
            } else {
                "--water-depth"
            },
            h.or(d).unwrap_or(f64::NAN),
            [
                ("--wave-height", h.is_some()),
                ("--wave-period", secs.wave_period.is_some()),
                ("--water-depth", d.is_some())
            ]
            .iter()
            .filter(|(_, given)| !given)
            .map(|(f, _)| *f)
            .collect::<Vec<_>>()
            .join(" and ")
        ),
    }
    if let Some(v) = a.vortex_strength {
        p.vortex_strength = v;
    }
    // The lee vortex: on by default with waves whose period is given in seconds here (its
    // reach needs the orbital excursion in metres), or asked for with a scenario's period in
    // seconds; a scenario's own `wave_vortex` is kept otherwise.
    let vortex_period = a
        .wave_period
        .or(secs.wave_period().filter(|_| a.wave_vortex));
    match (vortex_period, a.no_wave_vortex) {
        (_, true) => p.wave_vortex = 0.0,
        (Some(t), false) => {
            p.wave_vortex = p.wave_amplitude * t / (2.0 * std::f64::consts::PI);
        }
        (None, false) if a.wave_vortex => {
            bail!("--wave-vortex needs --wave-period (the orbital excursion U_w T / (2 pi))");
        }
        (None, false) => {
            if p.wave_vortex > 0.0
                && p.wave_amplitude > 0.0
                && (a.wave_amplitude.is_some() || a.wave_height.is_some())
            {
                conv::note(format_args!(
                    "warning: the scenario's wave_vortex = {} m (the orbital excursion of its own waves) is kept; give --wave-period in seconds to set it anew from the waves, or --no-wave-vortex",
                    cellsurf::ripple::params::shown(p.wave_vortex)
                ));
            }
        }
    }
    // the waves' own bed friction, from their orbital excursion (seconds given here)
    if let (Some(t), None) = (a.wave_period, a.wave_friction_factor) {
        p.wave_friction_factor =
            run_wave_friction_factor(p.wave_amplitude, t, p.d50 * 1e-3, p.drag_coefficient);
    } else if a.wave_period.is_none()
        && a.wave_friction_factor.is_none()
        && p.wave_friction_factor > 0.0
        && p.wave_amplitude > 0.0
        && (a.d50.is_some() || a.wave_amplitude.is_some())
    {
        conv::note(format_args!(
            "warning: the scenario's wave_friction_factor = {} was set for its own d50 and waves; it is kept (give --wave-period in seconds to compute it anew from the orbital excursion, or --wave-friction-factor)",
            p.wave_friction_factor
        ));
    } else if a.scenario.is_some()
        && a.wave_period.is_none()
        && a.wave_friction_factor.is_none()
        && p.wave_friction_factor == 0.0
        && p.wave_amplitude > 0.0
        && (p.wave_period > 0.0 || secs.wave_period().is_some())
    {
        // a scenario's waves without their own friction factor rub the bed as a current
        // would, more weakly than the same waves typed on the command line
        conv::note(format_args!(
            "warning: the scenario's waves have no wave_friction_factor (0: their bed stress takes the current's drag coefficient, weaker than Soulsby's friction factor of waves){}; --wave-period typed in seconds sets both from the waves, as a run of the same waves without the scenario does",
            if p.wave_vortex == 0.0 && !a.no_wave_vortex {
                " and no lee vortex (wave_vortex = 0)"
            } else {
                ""
            }
        ));
    }
    // wave options with no waves to act on: none given, or switched off on the command line
    // (`--wave-velocity 0`, which leaves a scenario's own wave keys idle without a word)
    let switched_off = a.wave_amplitude.is_some();
    if p.wave_amplitude == 0.0 {
        let period = if switched_off {
            a.wave_period
        } else {
            secs.wave_period()
        };
        let idle: Vec<String> = [
            ("wave_period", period.map(|t| format!("{t} s"))),
            ("wave_angle", a.wave_angle.map(|v| v.to_string())),
            (
                "wave_friction_factor",
                a.wave_friction_factor.map(|v| v.to_string()),
            ),
            ("wave_vortex", a.wave_vortex.then(|| "on".to_string())),
            ("no_wave_vortex", a.no_wave_vortex.then(|| "on".to_string())),
        ]
        .into_iter()
        .filter_map(|(id, v)| {
            v.map(|v| {
                let flag = match &secs.wave_period {
                    Some((_, name)) if id == "wave_period" => name.clone(),
                    _ => conv::typed_flag(id)
                        .unwrap_or_else(|| format!("--{}", id.replace('_', "-"))),
                };
                // (a switch has no value to show)
                if v == "on" {
                    flag
                } else {
                    format!("{flag} = {v}")
                }
            })
        })
        .collect();
        if !idle.is_empty() && switched_off {
            bail!(
                "{} acts on waves, and --wave-velocity = 0 gives none: leave {} out, or give a \
                 near-bed orbital velocity above 0 m/s",
                idle.join(" and "),
                if idle.len() > 1 { "them" } else { "it" }
            );
        }
        if !idle.is_empty() {
            bail!(
                "{} acts on waves, and there are none: give --wave-velocity (near-bed orbital velocity, m/s) or --wave-height with --water-depth",
                idle.join(" and ")
            );
        }
        if switched_off {
            // a scenario's waves switched off: its wave keys are not this run's, and are
            // recorded at their no-wave defaults (no period, vortex or friction of waves)
            let none = RippleParams::default();
            secs.wave_period = None;
            p.wave_period = none.wave_period;
            p.wave_vortex = none.wave_vortex;
            p.wave_friction_factor = none.wave_friction_factor;
            p.wave_angle = none.wave_angle;
        }
    }
    // the lee vortex's options with no vortex to act on, or a vortex the current overrides
    let vortex = p.wave_vortex > 0.0 && p.wave_amplitude > 0.0 && p.wave_period > 0.0;
    if let Some(v) = a.vortex_strength.filter(|_| !vortex) {
        let why = if a.no_wave_vortex {
            "--no-wave-vortex switched it off"
        } else if p.wave_amplitude == 0.0 {
            "there are no waves (give --wave-velocity or --wave-height with --water-depth)"
        } else {
            "it needs the waves' period in seconds (give --wave-period)"
        };
        bail!("--vortex-strength = {v} acts on the lee vortex, which is off: {why}");
    }
    if a.wave_vortex && !vortex {
        bail!(
            "--wave-vortex acts on the waves' lee vortex, and there are no waves: give --wave-velocity (near-bed orbital velocity, m/s, above 0) or --wave-height with --water-depth"
        );
    }
    let asked: Vec<&str> = [
        ("--wave-vortex", a.wave_vortex),
        ("--vortex-strength", a.vortex_strength.is_some()),
    ]
    .into_iter()
    .filter_map(|(f, given)| given.then_some(f))
    .collect();
    if vortex && !asked.is_empty() && !p.waves_dominate() {
        conv::note(format_args!(
            "warning: {} act{} on the lee vortex, which acts only where the waves' bed stress exceeds the current's; here the current dominates (--current-speed = {} m/s against waves rubbing the bed like {:.3} m/s), so the vortex is off for this run",
            asked.join(" and "),
            if asked.len() == 1 { "s" } else { "" },
            p.current_speed,
            p.wave_stress_amplitude()
        ));
    }
    if let Some(beta) = a.stoss_angle.filter(|_| p.waves_dominate()) {
        conv::note(format_args!(
            "warning: --stoss-angle = {beta} deg has no effect here: the stoss cap acts only where the current's bed stress exceeds the waves' (under waves each face is the stoss for half a cycle); here the waves dominate (waves rubbing the bed like {:.3} m/s against --current-speed = {} m/s)",
            p.wave_stress_amplitude(),
            p.current_speed
        ));
    }
    if let Some(r) = a
        .recipe
        .filter(|&r| r == Recipe::MatureCurrent && p.waves_dominate())
    {
        conv::note(format_args!(
            "warning: --recipe {r} is for currents: here the waves dominate (waves rubbing the bed like {:.3} m/s against --current-speed = {} m/s), and under waves its ripples do not follow the orbit (0.3 mm sand, U_w = 0.4 m/s, 8000 s: 2.3 and 0.74 times the wave predictor's 0.62 d0 at d0 = 0.2 and 0.4 m; docs/ripple.md, \"A recipe for mature current ripples\"); without --recipe such a run starts from the paper's rules with the lee vortex, and --recipe mature-waves gives wave ripples that follow the orbit",
            p.wave_stress_amplitude(),
            p.current_speed
        ));
    }
    if let Some(r) = a
        .recipe
        .filter(|&r| r == Recipe::MatureWaves && !p.waves_dominate())
    {
        conv::note(format_args!(
            "warning: --recipe {r} is for waves: here the current dominates (--current-speed = {} m/s against waves rubbing the bed like {:.3} m/s), and its lengths follow the orbit only where the waves dominate (docs/ripple.md, \"A recipe for mature wave ripples\")",
            p.current_speed,
            p.wave_stress_amplitude()
        ));
    }
    // (the recipe for mature current ripples says so in its own warning)
    if p.stoss_face_hold && p.waves_dominate() && a.recipe != Some(Recipe::MatureCurrent) {
        conv::note(format_args!(
            "warning: stoss_face_hold = true has no effect here: the face hold, like the stoss cap, acts only where the current's bed stress exceeds the waves'; here the waves dominate (waves rubbing the bed like {:.3} m/s against --current-speed = {} m/s)",
            p.wave_stress_amplitude(),
            p.current_speed
        ));
    }
    // with waves at their own angle and no current, nothing flows along the current's angle
    if let Some(c) = a
        .current_angle
        .filter(|_| p.current_speed == 0.0 && p.wave_angle.is_some())
    {
        conv::note(format_args!(
            "warning: --current-angle = {c} deg has no effect: there is no current (--current-speed = 0) and the waves run along their own --wave-angle = {} deg",
            p.wave_angle.unwrap_or_default()
        ));
    }
    if p.suspension_exponent != 2.0 && !p.crest_suspension_on() {
        conv::note(format_args!(
            "warning: suspension_exponent = {} has no effect: crest suspension is off (crest_suspension, crest_suspension_grains and crest_suspension_hops are 0)",
            p.suspension_exponent
        ));
    }
    // lengths in units of the waves' orbital excursion (`orbit_reference`, the recipe for
    // mature wave ripples'): a typed --bin-size or --layer-thickness wins; the key's own range
    // first (it is recorded as the excursion once applied)
    if p.orbit_reference != 0.0 {
        let probe = RippleParams {
            orbit_reference: p.orbit_reference,
            ..RippleParams::default()
        };
        probe.validate()?;
    }
    if p.orbit_reference > 0.0 && p.orbit_scale().is_none() && p.wave_amplitude > 0.0 {
        let why = if p.wave_vortex <= 0.0 {
            "the lee vortex, whose reach is the waves' excursion, is off (--no-wave-vortex, or a scenario's wave_vortex = 0)"
        } else {
            "the current dominates the bed stress"
        };
        conv::note(format_args!(
            "warning: orbit_reference = {} has no effect here: {why}; the lengths are those written for an excursion of {} m",
            cellsurf::ripple::params::shown(p.orbit_reference),
            cellsurf::ripple::params::shown(p.orbit_reference)
        ));
    }
    if let Some(s) = p.orbit_scale().filter(|&s| s != 1.0) {
        let q = p.with_orbit_scale();
        if let Err(e) = q.validate() {
            bail!(
                "orbit_reference = {} scales the run's lengths by {s:.4} (the waves' excursion A = {} m): {e}",
                cellsurf::ripple::params::shown(p.orbit_reference),
                cellsurf::ripple::params::rounded(p.wave_vortex)
            );
        }
        let keys = conv::scenario_keys();
        let mut changed = Vec::new();
        let mut set = |key: &str, typed: bool, to: f64, slot: &mut f64| {
            if !typed && *slot != to {
                if keys.iter().any(|k| k == key) {
                    changed.push(key.to_string());
                }
                *slot = to;
            }
        };
        set(
            "bin_size",
            a.bin_size.is_some(),
            q.bin_size,
            &mut p.bin_size,
        );
        set(
            "layer_thickness",
            a.layer_thickness.is_some() || a.bin_size.is_some(),
            q.layer_thickness,
            &mut p.layer_thickness,
        );
        set("hop_grains", false, q.hop_grains, &mut p.hop_grains);
        set(
            "crest_suspension",
            false,
            q.crest_suspension,
            &mut p.crest_suspension,
        );
        let lead = change_lead(&changed, "orbit_reference");
        let msg = format!(
            "{lead} lengths in units of the waves' orbital excursion A = {} m ({s:.4} x those of orbit_reference = {} m): --bin-size = {} m, --layer-thickness = {} m, hop_grains = {}, crest_suspension = {} m, {}",
            cellsurf::ripple::params::rounded(p.wave_vortex),
            cellsurf::ripple::params::shown(p.orbit_reference),
            cellsurf::ripple::params::shown(p.bin_size),
            cellsurf::ripple::params::shown(p.layer_thickness),
            cellsurf::ripple::params::shown(p.hop_grains),
            cellsurf::ripple::params::shown(p.crest_suspension),
            if p.ny > 1 {
                format!(
                    "a field of {} x {} m",
                    cellsurf::ripple::params::rounded(p.bin_size * p.nx as f64),
                    cellsurf::ripple::params::rounded(p.bin_size * p.ny as f64)
                )
            } else {
                format!(
                    "a section of {} m",
                    cellsurf::ripple::params::rounded(p.bin_size * p.nx as f64)
                )
            },
        );
        p.orbit_reference = q.orbit_reference;
        if !a.print_scenario {
            bin_note = Some(match bin_note {
                Some(n) => format!("{n}\n{msg}"),
                None => msg,
            });
        }
    }
    // the bin in flat-bed travels (`bin_travels`, the recipe's): a typed --bin-size wins; the
    // automata and layers follow unless typed (the note once the run is valid)
    if a.bin_size.is_some() {
        p.bin_travels = 0.0;
    }
    if let Some(b) = p
        .travel_bin()
        .filter(|&b| b != p.bin_size && p.validate().is_ok())
    {
        let (t, layers) = p.automata_for_bin(b);
        // typed automata are kept, with the layers they were given (as with --bin-size)
        let layers = a.layers.unwrap_or(if a.layer_thickness.is_some() {
            p.layers
        } else {
            layers
        });
        let t = a.layer_thickness.unwrap_or(t);
        let travel = cellsurf::ripple::clock::median_travel(&p, p.current_speed);
        // (the bin of travels is rounded to 3 digits, within 0.5 %)
        let floored = p.bin_travels * travel < 0.99 * b;
        if !params::LAYERS.contains(layers as u64) {
            bail!(
                "bin_travels = {} gives a bin of {} m here ({} flat-bed travels of {} m, the median grain's in --current-speed = {} m/s), on which {} m of sand takes {layers} layers: expected at most {}; give --bin-size, --layers or --layer-thickness",
                cellsurf::ripple::params::shown(p.bin_travels),
                cellsurf::ripple::params::shown(b),
                cellsurf::ripple::params::shown(p.bin_travels),
                cellsurf::ripple::params::rounded(b / p.bin_travels),
                cellsurf::ripple::params::shown(p.current_speed),
                depth_m(p.layers as f64 * p.layer_thickness),
                params::LAYERS.max
            );
        }
        // (a printed scenario shows the bin itself)
        // a scenario file's own bin, automata and layers are values the run was given: their
        // change is said whatever --quiet says (a recipe's are its fallbacks, a note)
        let keys = conv::scenario_keys();
        let changed: Vec<String> = [
            ("bin_size", a.bin_size.is_some(), p.bin_size != b),
            (
                "layer_thickness",
                a.layer_thickness.is_some(),
                p.layer_thickness != t,
            ),
            ("layers", a.layers.is_some(), p.layers != layers),
        ]
        .into_iter()
        .filter(|&(k, typed, differs)| differs && !typed && keys.iter().any(|x| x == k))
        .map(|(k, _, _)| k.to_string())
        .collect();
        let lead = change_lead(&changed, "bin_travels");
        bin_note = (!a.print_scenario).then(|| format!(
            "{lead} bins of {} flat-bed travels (bin_travels; the median grain's travel is {} m at {} m/s){}: --bin-size = {} m, --layer-thickness = {} m, --layers = {layers} ({} m of sand), {}; --bin-size gives another bin",
            cellsurf::ripple::params::shown(p.bin_travels),
            cellsurf::ripple::params::rounded(travel),
            cellsurf::ripple::params::shown(p.current_speed),
            if floored {
                format!(
                    ", here the finest bin whose {} m of sand fits in {} layers, {:.2} travels (the travel shrinks near the threshold of motion)",
                    depth_m(p.layers as f64 * p.layer_thickness),
                    params::LAYERS.max,
                    b / travel
                )
            } else {
                String::new()
            },
            cellsurf::ripple::params::shown(b),
            cellsurf::ripple::params::shown(t),
            depth_m(layers as f64 * t),
            if p.ny > 1 {
                format!(
                    "a field of {} x {} m",
                    cellsurf::ripple::params::rounded(b * p.nx as f64),
                    cellsurf::ripple::params::rounded(b * p.ny as f64)
                )
            } else {
                format!("a section of {} m", cellsurf::ripple::params::rounded(b * p.nx as f64))
            },
        ));
        (p.bin_size, p.layer_thickness, p.layers) = (b, t, layers);
    }
    // the recipe's ripples follow the travel; nature's current ripples follow the grain alone
    if recipe == Some(Recipe::MatureCurrent) && !p.waves_dominate() && p.validate().is_ok() {
        let sw = Prediction::of(p.d50, false, 0.0, 0.0);
        if let Some(own) = expected_wavelength(&p) {
            let ratio = own / sw.wavelength;
            if ratio.is_finite() && !(0.8..=1.2).contains(&ratio) {
                // (as many digits as show the ratio outside the band: 0.7996 is not "0.80")
                let shown = conv::shown_outside(ratio, 0.8, 1.2);
                conv::note(format_args!(
                    "warning: the recipe {}'s ripples come to about {TRAVELS_PER_WAVELENGTH} flat-bed travels of the median grain (59-70 measured): here {TRAVELS_PER_WAVELENGTH} x {} m = {} m at --current-speed = {} m/s, {} times the {} m of {} for --d50 = {} mm, outside the 20 % it meets at 0.1-0.4 mm and 0.5 m/s; the travel grows with the current and, at a fixed current, stops growing with the grain above about 0.5 mm, where nature's equilibrium current ripples follow the grain alone (docs/ripple.md, \"The current's speed and the grain\")",
                    Recipe::MatureCurrent,
                    cellsurf::ripple::params::rounded(own / TRAVELS_PER_WAVELENGTH),
                    cellsurf::ripple::params::rounded(own),
                    p.current_speed,
                    shown,
                    cellsurf::ripple::params::rounded(sw.wavelength),
                    sw.source,
                    p.d50
                ));
            }
        }
    }
    // the wave recipe's ripples follow the orbit; nature's leave it outside the orbital range
    if recipe == Some(Recipe::MatureWaves)
        && p.orbit_scale().is_some()
        && let Some(t) = secs.wave_period()
    {
        let wh = Prediction::of(p.d50, true, p.wave_amplitude, t);
        let own = ORBITS_PER_WAVELENGTH * p.wave_vortex;
        let ratio = own / wh.wavelength;
        if ratio.is_finite() && !(0.8..=1.2).contains(&ratio) {
            conv::note(format_args!(
                "warning: the recipe {}'s ripples come to about {ORBITS_PER_WAVELENGTH} orbital excursions (1.0-1.5 measured at d0 = 0.1-0.6 m, 0.3 mm, 0.4 m/s): here {} m, {} times the {} m of {}, outside the 20 % it meets at d0 = 0.2-0.4 m; its lengths follow the orbit at every period, where nature's ripples leave it outside the orbital range (docs/ripple.md, \"A recipe for mature wave ripples\")",
                Recipe::MatureWaves,
                cellsurf::ripple::params::rounded(own),
                conv::shown_outside(ratio, 0.8, 1.2),
                cellsurf::ripple::params::rounded(wh.wavelength),
                wh.source
            ));
        }
    }
    // (a bin or an avalanche angle out of its own range is named by its own check)
    if p.bin_size > 0.0
        && p.avalanche_angle > 0.0
        && p.avalanche_angle < 90.0
        && p.lattice_slope_deg() > p.avalanche_angle
    {
        bail!(
            "--layer-thickness = {} m is out of range for --bin-size = {} m and --avalanche-angle = {} deg: one automaton over one bin is a slope of {:.1} deg, steeper than the avalanche angle, which the lattice cannot hold; expected --layer-thickness at most --bin-size x tan(--avalanche-angle) = {} m (or a larger --bin-size or --avalanche-angle)",
            cellsurf::ripple::params::shown(p.layer_thickness),
            cellsurf::ripple::params::shown(p.bin_size),
            p.avalanche_angle,
            p.lattice_slope_deg(),
            cellsurf::ripple::params::rounded(p.bin_size * p.avalanche_angle.to_radians().tan())
        );
    }
    if p.mode == Mode::TwoD {
        if let Some(ny) = a.ny.or(a.size.map(|s| s.h)).filter(|&n| n != 1) {
            let flag = conv::typed_flag("size").unwrap_or_else(|| "--size".into());
            bail!(
                "{flag} = {}x{ny} is out of range: expected NXx1 in 2-D mode, a single section",
                p.nx
            );
        }
        p.ny = 1;
    }
    p.validate()?;
    Ok((p, secs, bin_note))
}

/// Converts what was asked in seconds (`--duration`, `--wave-period`, or a scenario's
/// `duration_s`, `wave_period_s`) to steps of the step duration of `clock` (none: no motion,
/// nothing runs).
fn to_steps(secs: &Seconds, p: &mut RippleParams, clock: Option<&StepClock>) -> Result<()> {
    match (&secs.duration, clock) {
        (Some((d, name)), Some(c)) => {
            let d = *d;
            p.steps = match c.steps_for(d) {
                Ok(n) => n,
                // (named by the scenario's key; --duration is named as typed)
                Err(e) if name != "--duration" => {
                    bail!("{}", e.to_string().replacen("duration", name, 1))
                }
                Err(e) => return Err(e.into()),
            };
            if d < 0.5 * c.step_s {
                conv::changed(format_args!(
                    "warning: {name} = {} s is shorter than one step ({:.4} s): one step is run ({:.4} s)",
                    cellsurf::ripple::params::shown(d),
                    c.step_s,
                    c.step_s
                ));
            }
        }
        // no motion: no step is run, whatever was asked
        (_, None) => p.steps = 0,
        (None, Some(_)) => {}
    }
    if let Some((t, name)) = &secs.wave_period {
        let t = *t;
        p.wave_period = match clock {
            Some(c) if t / c.step_s > 1e12 => bail!(
                "{name} = {} s is out of range: expected at most 1e12 steps of {:.4e} s ({:.4e} s)",
                cellsurf::ripple::params::shown(t),
                c.step_s,
                1e12 * c.step_s
            ),
            Some(c) if t / c.step_s >= 2.0 => t / c.step_s,
            Some(c) => bail!(
                "{name} = {t} s is out of range: expected at least two steps of {:.4} s ({:.4} s)",
                c.step_s,
                2.0 * c.step_s
            ),
            // no motion: the period has no length in steps (it is recorded in seconds)
            None => 0.0,
        };
    }
    p.validate()?;
    Ok(())
}

/// Sets `p`'s steps and wave period from what a ripple scenario asked in seconds (`tile
/// --generate --ripple-scenario`), as a ripple run does with the same file.
pub fn scenario_steps(secs: &Seconds, p: &mut RippleParams) -> Result<()> {
    if secs.duration.is_none() && secs.wave_period.is_none() {
        return Ok(());
    }
    if secs.wave_period.is_some() {
        // a provisional period in steps: the clock's flux is averaged over whole cycles
        p.wave_period = 64.0;
    }
    let clock = clock_of(p, &cellsurf::ripple::regime::regime(p))?;
    to_steps(secs, p, clock.as_ref())
}

/// The step clock of a run that moves sand: `None` with no motion (the transport law moves
/// nothing, or the model's rules carry no grain on a flat bed).
fn clock_of(
    p: &RippleParams,
    reg: &cellsurf::ripple::regime::RegimeReport,
) -> Result<Option<StepClock>> {
    if reg.regime == Regime::NoMotion {
        return Ok(None);
    }
    let c = StepClock::of(p)?;
    Ok(c.grains_move().then_some(c))
}

/// Why the model's rules carry no grain on a flat bed although the flow exceeds the threshold
/// of motion at `speed` (m/s), for a message: a stoss angle of 0 (the stoss cap then lets no
/// grain rest above the column upstream, so every grain rolls back; `beta_flag` names it), or
/// a hop too short to pay a bin's cost at this speed.
pub fn model_stuck_reason(p: &RippleParams, speed: f64, beta_flag: &str) -> String {
    let (finest, median) = cellsurf::ripple::clock::model_threshold_speeds(p);
    if p.stoss_angle == 0.0 && !p.waves_dominate() && speed >= finest {
        format!(
            "{beta_flag} = 0 deg: the stoss cap lets no grain come to rest above the column \
             upstream, so on a flat bed every grain rolls back and none moves (the flat-bed \
             measurement moved none); a stoss angle above 0 deg (default 7) lets grains move"
        )
    } else {
        // between the two, only the finest of the sorting's grains could move
        let few = if speed >= finest {
            format!(
                "; at {speed:.3} m/s only the finest of the sorting's grains could move, a \
                 small part of the sand{}, and the measurement's sample of them moved none",
                if p.has_wave() {
                    ", and only near the waves' peaks"
                } else {
                    ""
                }
            )
        } else {
            String::new()
        };
        format!(
            "the model's rules carry no grain a bin on a flat bed (the flat-bed measurement \
             moved none): they move the finest grains from {finest:.3} m/s and the median grain \
             from {median:.3} m/s (the bin size, the layer thickness and the hop length set that \
             threshold){few}"
        )
    }
}

/// The flag that sets the largest flow speed, and what else adds to it: the current's where it
/// reaches sheet flow on its own or its bed stress dominates the waves'
/// ([`RippleParams::waves_dominate`]), the waves' (with their friction factor) otherwise.
fn flow_cause(a: &Args, p: &RippleParams) -> (String, String) {
    let current = format!("--current-speed = {} m/s", p.current_speed);
    if p.wave_amplitude == 0.0 {
        return (current, String::new());
    }
    let wave_flag = match a.wave_height {
        Some(h) => format!("--wave-height = {h} m"),
        None => format!(
            "{} = {} m/s",
            conv::typed_flag("wave_amplitude").unwrap_or_else(|| "--wave-velocity".into()),
            p.wave_amplitude
        ),
    };
    let waves = format!(
        "the waves (near-bed orbital velocity {} m/s{}) rub the bed like a current of {:.3} m/s",
        p.wave_amplitude,
        if p.wave_friction_factor > 0.0 {
            format!(
                ", wave friction factor {:.4} {}",
                p.wave_friction_factor,
                match (a.wave_friction_factor, a.wave_period) {
                    (Some(_), _) => "from --wave-friction-factor".to_string(),
                    (None, Some(t)) => format!(
                        "from their orbital excursion U_w T / (2 pi) = {:.3e} m with --wave-period = {t} s \
                         (Soulsby Eq. 60a, at least twice the drag coefficient: a longer period \
                         lowers it to that), or set by --wave-friction-factor",
                        p.wave_amplitude * t / (2.0 * std::f64::consts::PI)
                    ),
                    (None, None) => "from their orbital excursion, Soulsby Eq. 60a, or set by \
                                     --wave-friction-factor"
                        .to_string(),
                }
            )
        } else {
            String::new()
        },
        p.wave_stress_amplitude()
    );
    let current_alone = cellsurf::ripple::regime::regime(&RippleParams {
        wave_amplitude: 0.0,
        ..p.clone()
    });
    if current_alone.regime == Regime::SheetFlow || (p.current_speed > 0.0 && !p.waves_dominate()) {
        (current, format!("with {wave_flag}: {waves}"))
    } else if p.current_speed > 0.0 {
        (wave_flag, format!("{waves}, with {current}"))
    } else {
        (wave_flag, waves)
    }
}

/// `--snapshots`: steps of the run, each at most its last step (at most 2^40).
const SNAPSHOTS: &str = "steps in [0, steps], at most 2^40";

/// `--seed`: a whole number (`1e3` accepted) in [`params::SEED`], [0, 2^53] (every output
/// records it exactly as a number); a seed past it, or below 0, is refused with that range.
fn parse_seed(s: &str) -> Result<u64, String> {
    let past = || format!("'{s}' is out of range: expected {}", params::SEED.expected);
    match conv::count_in::<u64>(params::SEED)(s) {
        Ok(v) if params::SEED.contains(v) => Ok(v),
        Ok(_) => Err(past()),
        Err(_) if s.trim().parse::<f64>().is_ok_and(|v| v < 0.0) => Err(past()),
        Err(e) => Err(e),
    }
}

/// Bytes a ripple run of `p` allocates, holding `snapshots` elevation snapshots and, where
/// `volume_out`, writing a volume field: 2 per automaton slot (the volume's `u16` automata,
/// `nx x ny x capacity` of them), 140 per column (the per-column arrays of the run), 8 per
/// column and snapshot, and 8 per column and level of the volume field written (its values
/// and their bytes), its levels taken halfway from the initial bed's top to the column's
/// capacity; 10% added. Measured as the least `ulimit -v` a run of one step needs, less the
/// program's own 22 MB: 1024x1024 columns 312 MB at --layers 30 and 1.41 GB at --layers
/// 300 (2.0 B per slot and 135 B per column), 2048x2048 1.03 GB at --layers 30 (83 B per
/// column); with --out x.npy, 1024x1024 at --layers 30 took 235 MB more (224 B per column).
pub fn run_bytes(p: &RippleParams, snapshots: usize, volume_out: bool) -> f64 {
    let columns = p.nx as f64 * p.rows() as f64;
    let cap = p.capacity() as f64;
    let levels = if volume_out {
        ((p.layers + p.roughness) as f64 + cap) / 2.0
    } else {
        0.0
    };
    1.1 * columns * (2.0 * cap + 140.0 + 8.0 * snapshots as f64 + 8.0 * levels)
}

/// Refuses a run of `p` larger than the memory this process may have ([`run_bytes`]), naming
/// --size and --layers as typed.
fn check_run_memory(p: &RippleParams, snapshots: usize, volume_out: bool) -> Result<()> {
    conv::check_memory(
        &format!(
            "{} {}x{} with {} {}",
            conv::typed_flag("size").unwrap_or_else(|| "--size".into()),
            p.nx,
            p.rows(),
            conv::typed_flag("layers").unwrap_or_else(|| "--layers".into()),
            p.layers
        ),
        run_bytes(p, snapshots, volume_out),
    )
}

/// Runs the subcommand.
/// The lead of the note on lengths a key derives (`bin_travels`, `orbit_reference`): a warning
/// naming the scenario file's own keys it `changed` (values the run was given), a note where
/// it changed none.
fn change_lead(changed: &[String], by: &str) -> String {
    if changed.is_empty() {
        "note:".to_string()
    } else {
        format!(
            "warning: the scenario's {} change{} with its {by}:",
            changed.join(", "),
            if changed.len() == 1 { "s" } else { "" }
        )
    }
}

/// Says the note on the bin: a warning (a change to values a scenario file gave) whatever
/// `--quiet` says, a note otherwise.
fn say_bin_note(n: &str) {
    if n.starts_with("warning:") {
        conv::changed(n);
    } else {
        conv::note(n);
    }
}

pub fn run(a: Args) -> Result<()> {
    conv::synonyms(&[("nx", "size"), ("ny", "size")]);
    conv::set_quiet(a.quiet);
    // (the note on the bin once the whole run is valid: an error is a run's first line)
    let (p, secs, recipe, bin_note) = params(&a)?;
    if a.print_scenario {
        if let Some(n) = &bin_note {
            say_bin_note(n);
        }
        // (the scenario holds the model; these choose what a run writes)
        let run_only = conv::given_flags(&[
            ("out", "--out", !a.out.is_empty()),
            ("fields", "--fields", a.fields.is_some()),
            ("snapshots", "--snapshots", a.snapshots.is_some()),
            ("format", "--format", a.format.is_some()),
        ]);
        if !run_only.is_empty() {
            conv::note(format_args!(
                "note: --print-scenario writes the model's parameters only and runs nothing: {} {} a run's outputs, not part of the scenario; give {} again with --scenario FILE",
                run_only.join(", "),
                if run_only.len() == 1 {
                    "chooses"
                } else {
                    "choose"
                },
                if run_only.len() == 1 { "it" } else { "them" },
            ));
        }
        let mut p = p;
        let mut asked = String::new();
        if secs.duration.is_some() || secs.wave_period.is_some() {
            let reg = cellsurf::ripple::regime::regime(&p);
            let clock = clock_of(&p, &reg)?;
            to_steps(&secs, &mut p, clock.as_ref())?;
            let in_steps: Vec<String> = [
                secs.duration().map(|_| format!("steps = {}", p.steps)),
                secs.wave_period()
                    .map(|_| format!("wave_period = {}", p.wave_period)),
            ]
            .into_iter()
            .flatten()
            .collect();
            asked = match clock {
                Some(c) => format!("# in steps of {:e} s: {}\n", c.step_s, in_steps.join(", ")),
                None => "# no motion: no step is run, and the wave period has no length in steps\n"
                    .into(),
            };
        }
        // what was asked in seconds stays in seconds, in place of its steps (a file cannot give
        // both, as --steps and --duration cannot be given together)
        let mut text = String::new();
        for line in p.to_toml().lines() {
            let key = line.split(" = ").next().unwrap_or_default();
            match (key, secs.duration(), secs.wave_period()) {
                ("steps", Some(d), _) => {
                    text.push_str(&format!("duration_s = {}\n", toml::Value::Float(d)))
                }
                ("wave_period", _, Some(t)) => {
                    text.push_str(&format!("wave_period_s = {}\n", toml::Value::Float(t)))
                }
                _ => {
                    text.push_str(line);
                    text.push('\n');
                }
            }
        }
        out!(
            "# cellsurf {} scenario: `cellsurf ripple --scenario FILE`\n{asked}model = \"ripple\"\n{text}",
            cellsurf::ripple::VERSION,
        )?;
        return Ok(());
    }
    let outs = match a.format {
        None => Outputs::new(
            &a.out,
            "ripple",
            &[ConvFormat::Nc, ConvFormat::Npy, ConvFormat::Zarr],
        )?,
        Some(f) => {
            // Old spelling (one release): `--format npy --out STEM`, the extension replaced.
            let fmt = match f {
                Format::NetCdf => ConvFormat::Nc,
                Format::Npy => ConvFormat::Npy,
                Format::Zarr => ConvFormat::Zarr,
            };
            let mut o = Outputs::default();
            let path = conv::legacy_format_path(fmt, &a.out)?;
            o.add_legacy(fmt, path.as_ref())?;
            o
        }
    };
    let given: Vec<(&std::path::Path, Format)> = [
        (ConvFormat::Nc, Format::NetCdf),
        (ConvFormat::Npy, Format::Npy),
        (ConvFormat::Zarr, Format::Zarr),
    ]
    .into_iter()
    .filter_map(|(c, f)| outs.get(c).map(|p| (p, f)))
    .collect();
    if given.len() > 1 {
        bail!("--out: one volume output per run (.nc, .npy or .zarr)");
    }
    let (out, format) = match given.first() {
        Some(&(p, f)) => (Some(p.to_path_buf()), f),
        None => (None, Format::NetCdf),
    };
    if out.is_none() {
        let unused = conv::given_flags(&[
            ("fields", "--fields", a.fields.is_some()),
            ("snapshots", "--snapshots", a.snapshots.is_some()),
            ("acoustics", "--acoustics", a.acoustics.is_some()),
            ("format", "--format", a.format.is_some()),
        ]);
        if !unused.is_empty() {
            conv::note(format_args!(
                "warning: {} {} no effect without a volume output: {} what --out FILE.nc|.npy|.zarr writes; give --out",
                match unused.split_last() {
                    Some((last, [])) => last.clone(),
                    Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
                    None => String::new(),
                },
                if unused.len() == 1 { "has" } else { "have" },
                if unused.len() == 1 {
                    "it chooses"
                } else {
                    "they choose"
                }
            ));
        }
    }
    let mut fields: Vec<Field> = match &a.fields {
        Some(f) => f.clone(),
        None => Field::ALL
            .into_iter()
            .filter(|f| !(p.acoustics == AcousticModel::AplUw && *f == Field::Porosity))
            .collect(),
    };
    fields.dedup();
    let mut seen = Vec::new();
    fields.retain(|f| {
        let new = !seen.contains(f);
        seen.push(*f);
        new
    });
    if format == Format::Npy && out.is_some() && !fields.contains(&Field::Elevation) {
        let o = out.as_deref().unwrap_or(std::path::Path::new(""));
        bail!(
            "--fields = {} has no elevation, and --out {} names the elevation file (NAME.npy the elevation snapshots, NAME_FIELD.npy each volume field, NAME.json the parameters): add elevation to --fields (`cellsurf tile` and `cellsurf raytrace` need it too), or write .nc or .zarr",
            fields
                .iter()
                .map(|f| f.name())
                .collect::<Vec<_>>()
                .join(","),
            o.display()
        );
    }
    let spec = OutputSpec { fields, format };
    spec.validate(p.acoustics)?;

    if let Some(out) = out.as_ref() {
        if format == Format::Zarr {
            cellsurf::ripple::zarr::check_store_target(out)
                .with_context(|| format!("--out {}", out.display()))?;
        } else {
            cellsurf::engine::io::check_output("--out", out)?;
            if format == Format::Npy {
                // the volume fields' files and the JSON sidecar beside NAME.npy
                let paths = cellsurf::ripple::output::npy_paths(out, &spec);
                for f in paths.iter().filter(|f| f.as_path() != out.as_path()) {
                    let opt = format!("--out {}: its file", out.display());
                    cellsurf::engine::io::check_output(&opt, f)?;
                }
            }
        }
    }

    let reg = cellsurf::ripple::regime::regime(&p);
    let (lo, hi) = reg.ripple_speeds;
    match reg.regime {
        Regime::SheetFlow => bail!(
            "{} is out of range: {}the flow's largest speed, {:.4} m/s{}, gives a Shields number of {:.4} on d50 = {} mm, above {}: sheet flow, where ripples are washed out into a flat bed and the rules of this model do not hold; expected a largest speed of {lo:.4} to {hi:.4} m/s for ripples",
            flow_cause(&a, &p).0,
            match flow_cause(&a, &p).1 {
                d if d.is_empty() => d,
                d => format!("{d}; "),
            },
            reg.speed,
            if p.wave_amplitude > 0.0 {
                " (current and waves as a current of the same bed stress)"
            } else {
                ""
            },
            reg.shields,
            p.d50,
            cellsurf::ripple::regime::THETA_SHEET_FLOW
        ),
        Regime::NoMotion => conv::note(format_args!(
            "no motion: the flow's largest speed{}, {:.3} m/s, gives a Shields number of {:.3} on d50 = {} mm, below the threshold {:.3} (ripples from {lo:.3} m/s): the bed is left as it is",
            if p.wave_amplitude > 0.0 {
                " (current and waves as a current of the same bed stress)"
            } else {
                ""
            },
            reg.speed,
            reg.shields,
            p.d50,
            reg.shields_critical
        )),
        Regime::Ripples if reg.coarse => conv::note(format_args!(
            "d50 = {} mm is above {} mm: coarse sand forms no current ripples in nature (Soulsby 1997, Sect. 7.2); the model still applies its rules",
            p.d50,
            cellsurf::ripple::regime::D50_RIPPLES_MAX_MM
        )),
        Regime::Ripples => {}
    }
    let clock = clock_of(&p, &reg)?;
    // the transport law moves sand but the model's grains do not move on a flat bed
    let stuck = reg.regime != Regime::NoMotion && clock.is_none();
    if stuck {
        conv::note(format_args!(
            "no motion in the model: {}{} gives the flow's largest speed of {:.3} m/s, above the threshold of motion ({lo:.3} m/s), but {}; the bed is left as it is",
            flow_cause(&a, &p).0,
            match flow_cause(&a, &p).1 {
                d if d.is_empty() => d,
                d => format!(" ({d})"),
            },
            reg.speed,
            model_stuck_reason(&p, reg.speed, "--stoss-angle")
        ));
    }
    let regime_name = if stuck {
        Regime::NoMotion.name()
    } else {
        reg.regime.name()
    };
    let mut p = p;
    let asked_steps = p.steps;
    to_steps(&secs, &mut p, clock.as_ref())?;
    // waves without a period (a scenario's `wave_period = 0`, or its velocity without
    // `wave_period_s`) would run as no waves at all: refused, as on the command line
    if p.wave_amplitude > 0.0 && p.wave_period == 0.0 && secs.wave_period.is_none() {
        if conv::typed("wave_amplitude") || a.scenario.is_none() {
            bail!(
                "{} = {} m/s needs a wave period: give --wave-period (seconds)",
                conv::typed_flag("wave_amplitude").unwrap_or_else(|| "--wave-velocity".into()),
                p.wave_amplitude
            );
        }
        bail!(
            "wave_amplitude = {} m/s in the scenario needs a wave period: give wave_period_s \
             (seconds, > 0) in the scenario or --wave-period on the command line",
            p.wave_amplitude
        );
    }
    let steps = p.steps;
    let wave_period_s = match (secs.wave_period(), clock.as_ref()) {
        (Some(t), _) => t,
        (None, Some(c)) => c.step_s * p.wave_period,
        (None, None) => 0.0,
    };
    let predicted = Prediction::of(p.d50, p.waves_dominate(), p.wave_amplitude, wave_period_s);
    // the dominant flow's direction on the lattice (0 in the flow frame, 180 for a section
    // running towards -x)
    let along = length_along(
        p.nx as f64 * p.bin_size,
        p.rows() as f64 * p.bin_size,
        p.lattice_flow_angle(),
    );
    // the ripple the run will build: the recipe's own where it runs a current (its ripples
    // follow the travel, not the predictor), the predictor's otherwise
    let (expected, of_what) = match expected_wavelength(&p) {
        Some(w) if recipe == Some(Recipe::MatureCurrent) && !p.waves_dominate() => (
            w,
            format!(
                "the recipe {}'s, {TRAVELS_PER_WAVELENGTH} flat-bed travels",
                Recipe::MatureCurrent
            ),
        ),
        _ => (
            predicted.wavelength,
            format!("the predicted, {}", predicted.source),
        ),
    };
    if reg.regime == Regime::Ripples && along < 4.0 * expected {
        conv::note(format_args!(
            "warning: the domain is {along:.3} m long along the flow ({} deg from east), less than 4 wavelengths of the ripple ({of_what}: 4 x {expected:.3} m = {:.3} m): the domain, not the sediment, will limit the ripples; give a larger --size or --bin-size",
            p.flow_angle(),
            4.0 * expected,
        ));
    }
    // a bin is a column of sand: one narrower than a grain resolves nothing the grain has
    if p.bin_size < p.d50 * 1e-3 {
        conv::note(format_args!(
            "warning: --bin-size = {} m is narrower than the median grain (--d50 = {} mm): a bin of the model is a column of sand some grains wide, and lengths below a grain's diameter have no physical meaning; give a --bin-size of at least {} m",
            p.bin_size,
            p.d50,
            p.d50 * 1e-3
        ));
    }
    let resolving = largest_resolving_bin(predicted.height, p.avalanche_angle);
    if reg.regime == Regime::Ripples && p.bin_size > resolving {
        conv::note(format_args!(
            "warning: --bin-size = {} m is longer than half the lee face of the predicted ripple (H / (2 tan alpha) = {resolving:.4} m for H = {:.4} m, {}, and alpha = {} deg): the slip face and the shadow behind it span fewer than two bins, so the field will depend on the bin; give a smaller --bin-size (and --layer-thickness)",
            p.bin_size, predicted.height, predicted.source, p.avalanche_angle
        ));
    }
    // a travel in metres that the bin does not resolve (docs/ripple.md, "A recipe for mature
    // current ripples": 5 mm bins lengthen the ripples by 20-43 % where they pass twice it)
    let travel = cellsurf::ripple::clock::median_travel(&p, p.current_speed);
    if p.hop_grains > 0.0
        && reg.regime == Regime::Ripples
        && !p.waves_dominate()
        && p.bin_size > 2.0 * travel
    {
        conv::note(format_args!(
            "warning: --bin-size = {} m is more than twice the median grain's travel on a flat bed ({} m: hop_grains = {} diameters per unit of excess Shields stage at {} m/s): a grain then moves a whole bin or none, so the ripples will be longer than in finer bins; give a smaller --bin-size (and --layer-thickness)",
            p.bin_size,
            cellsurf::ripple::params::rounded(travel),
            p.hop_grains,
            p.current_speed
        ));
    }
    let surface = match (a.wave_height, secs.wave_period(), a.water_depth) {
        (Some(h), Some(t), Some(d)) => Some(SurfaceWave::new(h, t, d)?),
        _ => None,
    };

    let mut times: Vec<u64> = match &a.snapshots {
        Some(t) => t.clone(),
        // (one snapshot where the run has no step: `--steps 0`)
        None if p.steps == 0 => vec![0],
        None => vec![0, p.steps],
    };
    // (with no motion the cap is the steps asked for: none of them is run)
    let cap = if clock.is_some() {
        p.steps
    } else {
        asked_steps
    };
    if let (Some(c), Some(_)) = (&clock, &p.until)
        && cap < EARLIEST_STOP
    {
        conv::note(format_args!(
            "warning: --until equilibrium cannot stop a run of {cap} steps: its test needs the checkpoints at 1000, 2000 and {EARLIEST_STOP} steps (two doublings), so this run goes to its cap untested; give --steps {EARLIEST_STOP} or more (or --duration {:.0}s or more here)",
            (EARLIEST_STOP as f64 * c.step_s).ceil()
        ));
    }
    conv::strictly_increasing("snapshots", &times)?;
    if let Some(&t) = times.iter().find(|&&t| t > cap) {
        bail!(
            "snapshots = {t} is out of range: expected steps in [0, steps = {}]",
            cap
        );
    }
    if clock.is_none() {
        // (typed snapshots that cannot be written are said whatever --quiet says)
        if times.iter().any(|&t| t > 0) {
            let say = format!(
                "{}: no motion, no step is run: the bed of step 0 is the only snapshot",
                if a.snapshots.is_some() {
                    "warning"
                } else {
                    "note"
                }
            );
            if a.snapshots.is_some() {
                conv::changed(say);
            } else {
                conv::note(say);
            }
        }
        times = vec![0];
    }

    let volume_out = out.is_some() && spec.fields.iter().any(|f| *f != Field::Elevation);
    check_run_memory(&p, times.len(), volume_out)?;
    if let Some(n) = &bin_note {
        say_bin_note(n);
    }

    let start = Instant::now();
    let mut r = Ripple::new(&p)?;
    let setup_s = start.elapsed().as_secs_f64();
    conv::begin();
    let bar = ProgressBar::with_draw_target(Some(steps.max(1)), ProgressDrawTarget::hidden());
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{bar:40}] {percent}% ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(format!(
        "ripple {}x{}x{}{}",
        p.nx,
        p.rows(),
        p.layers,
        // (the bar runs to the cap; the run may stop at any checkpoint from 4000 steps)
        if p.until.is_some() {
            ", until equilibrium (the bar and ETA to the cap)"
        } else {
            ""
        }
    ));
    let silent = a.quiet || a.json;
    let mut shown = false;
    let progress = |done: u64| {
        if !silent && !shown && start.elapsed().as_secs_f64() > 1.0 {
            bar.set_draw_target(ProgressDrawTarget::stderr());
            shown = true;
        }
        if done.is_multiple_of(16) || done == steps {
            bar.set_position(done);
        }
    };
    let mut mature = None;
    let mut snaps = if p.until.is_some() {
        let m = run_until_mature(&mut r, steps, &times, progress);
        mature = Some((m.mature_at, m.checkpoints, m.substrate_at));
        m.snapshots
    } else {
        run_recording(&mut r, steps, &times, progress)
    };
    bar.finish_and_clear();
    if steps == 0 {
        // no motion (or no step asked for): the bed of step 0
        let bed = run_recording(&mut r, 0, &[0], |_| {}).remove(0).1;
        snaps = times.iter().map(|&t| (t, bed.clone())).collect();
    }
    let elapsed = start.elapsed().as_secs_f64();
    // why the run stopped where it did
    // (no motion first: such a run makes no step, whatever it was to run until)
    let stop_reason = match (&p.until, mature.as_ref().and_then(|m| m.0)) {
        _ if clock.is_none() => "no motion",
        (Some(_), Some(_)) => "equilibrium",
        (Some(_), None) => "cap (steps)",
        (None, _) => "steps",
    };
    // (the default snapshots, the start and the end, are always written: the end is where the
    // run stopped)
    let missed: Vec<u64> = times.iter().copied().filter(|&t| t > r.time()).collect();
    if !missed.is_empty() && a.snapshots.is_some() {
        conv::note(format_args!(
            "note: the run stopped at step {} ({stop_reason}): the snapshots asked for at {} were not reached",
            r.time(),
            missed
                .iter()
                .map(|t| t.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    // what the run recorded beside its parameters
    let mut extra: Vec<(String, toml::Value)> = vec![
        ("regime".into(), toml::Value::String(regime_name.into())),
        ("stop_step".into(), toml::Value::Integer(r.time() as i64)),
        (
            "stop_reason".into(),
            toml::Value::String(stop_reason.into()),
        ),
        (
            "bare_fraction".into(),
            toml::Value::Float(r.bare_fraction()),
        ),
    ];
    if let Some(d) = secs.duration() {
        extra.push(("duration_s".into(), toml::Value::Float(d)));
    }
    if let Some(t) = secs.wave_period() {
        extra.push(("wave_period_s".into(), toml::Value::Float(t)));
    }
    if let Some(c) = clock {
        extra.push(("step_duration_s".into(), toml::Value::Float(c.step_s)));
    }

    let mut written = Vec::new();
    if let Some(out) = &out {
        match spec.format {
            Format::NetCdf => {
                write_netcdf_with(out, &r, &snaps, &spec, &extra)?;
                written.push(out.clone());
            }
            Format::Npy => written.extend(write_npy_with(out, &r, &snaps, &spec, &extra)?),
            Format::Zarr => {
                cellsurf::ripple::zarr::write_zarr_with(out, &r, &snaps, &spec, &extra)?;
                written.push(out.clone());
            }
        }
    }
    for w in &written {
        conv::wrote(w);
    }
    let an = Analysis::of(&r);
    // Troughs down to the substrate: the field is short of sand, whatever it looks like.
    let bare = r.bare_fraction();
    let substrate_step = mature.as_ref().and_then(|m| m.2);
    if (bare > 0.0 || substrate_step.is_some()) && clock.is_some() {
        let first = match substrate_step {
            Some(t) if t < r.time() => format!(", first seen at step {t}"),
            _ => String::new(),
        };
        let high = if an.height_m.is_finite() {
            format!(", under ripples {:.4} m high", an.height_m)
        } else {
            String::new()
        };
        conv::note(format_args!(
            "warning: the bed has reached the substrate: {} of {} columns ({:.3} %) are bare at step {}{first} ({:.4} m of sand at the start: --layers = {} x --layer-thickness = {} m{high}); the ripples can grow no deeper there, so where they stop growing the sand has run out{}; give more --layers",
            r.bare_columns(),
            r.volume().columns(),
            100.0 * bare,
            r.time(),
            p.layers as f64 * p.layer_thickness,
            p.layers,
            p.layer_thickness,
            if p.until.is_some() {
                ", and --until equilibrium declares no equilibrium on a bed that has shown the substrate"
            } else {
                ""
            }
        ));
    }
    let s = r.stats();
    if a.json {
        let num = |v: f64| {
            if v.is_finite() {
                serde_json::json!(v)
            } else {
                serde_json::Value::Null
            }
        };
        let crest_normal = cellsurf::ripple::predictors::rubin_hunter_crest_normal(&p);
        let waves_and_checks = serde_json::json!({
            "wave_velocity_m_per_s": (p.wave_amplitude > 0.0).then_some(p.wave_amplitude),
            "wave_height_m": surface.map(|w| w.height),
            "water_depth_m": surface.map(|w| w.depth),
            "surface_wavelength_m": surface.map(|w| w.wavelength()),
            // (null where the flow moves no grain by Meyer-Peter & Mueller, as the crest
            // normal is: no ripple to predict, e.g. waves whose orbit does not reach the bed)
            "predicted_wavelength_m": crest_normal.map(|_| predicted.wavelength),
            "predicted_height_m": crest_normal.map(|_| predicted.height),
            "predictor": predicted.source,
            "predicted_crest_normal_deg": crest_normal,
            "domain_length_along_flow_m": along,
            "x_axis_direction_deg": p.x_axis_direction_deg(),
        });
        let mut own = serde_json::json!({
            "regime": regime_name,
            "shields": reg.shields,
            "shields_critical": reg.shields_critical,
            "bed_shear_stress_pa": reg.bed_shear_stress,
            "ripple_regime_speeds_m_per_s": [lo, hi],
            "coarse_sand": reg.coarse,
            "wave_period_s": (wave_period_s > 0.0).then(|| num(wave_period_s)),
            "wave_period_steps": (p.wave_period > 0.0 && p.wave_amplitude > 0.0).then_some(p.wave_period),
            "orbital_diameter_m": (wave_period_s > 0.0).then(|| num(p.wave_amplitude * wave_period_s / std::f64::consts::PI)),
            "step_duration_s": clock.map(|c| num(c.step_s)),
            "simulated_time_s": clock.map(|c| num(c.step_s * s.steps as f64)),
            "bedload_m2_per_s": clock.map(|c| c.bedload),
            "flat_bed_travel_m": clock.map(|c| c.travel),
            "equilibrium": mature.as_ref().map(|m| m.0.is_some()),
            "equilibrium_step": mature.as_ref().and_then(|m| m.0),
            "equilibrium_time_s": mature.as_ref().and_then(|m| m.0).zip(clock).map(|(t, c)| num(c.step_s * t as f64)),
            "checkpoints": mature.as_ref().map(|m| m.1.iter().map(|c| serde_json::json!({"step": c.step, "wavelength_m": num(c.wavelength_m), "height_m": num(c.height_m), "bare_fraction": c.bare_fraction})).collect::<Vec<_>>()),
            "substrate_reached_step": substrate_step,
            "bare_fraction": bare,
            "steps": s.steps,
            "automata": r.automata(),
            "activations": s.activations,
            "wavelength_m": num(an.wavelength_m),
            "crest_normal_deg": num(an.crest_normal_deg),
            "height_m": num(an.height_m),
            "ripple_index": num(an.ripple_index),
            "lee_slope_deg": num(an.lee_slope_deg),
            "stoss_slope_deg": num(an.stoss_slope_deg),
            "symmetry_index": num(an.symmetry_index),
            "mass_change": r.mass_change(),
            "d50_crest_mm": num(an.d50_crest_mm),
            "d50_trough_mm": num(an.d50_trough_mm),
            "setup_s": setup_s,
            "steps_per_s": s.steps as f64 / (elapsed - setup_s).max(1e-9),
            "picks": s.picks,
            "rolls": s.rolls,
            "hops": s.hops,
            "avalanches": s.avalanches,
            "creeps": s.creeps,
            "suspended": s.suspended,
            "bytes_per_automaton": r.bytes_per_automaton(),
        });
        let record = serde_json::json!({
            "recipe": recipe.map(Recipe::name),
            "duration_s": secs.duration(),
            "until": p.until,
            "stop_step": r.time(),
            "stop_reason": stop_reason,
            "single_bedform": an.single_bedform,
        });
        for extra in [waves_and_checks, record] {
            if let (Some(o), serde_json::Value::Object(w)) = (own.as_object_mut(), extra) {
                o.extend(w);
            }
        }
        let v = conv::envelope("ripple", &p, elapsed, own)?;
        outln!("{}", serde_json::to_string(&v)?)?;
    } else {
        outln!(
            "ripple: {} steps ({}{}), {} automata, {} activations in {elapsed:.2} s; wavelength {:.4} m, height {:.4} m, ripple index {:.1}, lee {:.1} deg, stoss {:.1} deg, symmetry index {:.2}, crest normal {:.0} deg, d50 crest/trough {:.3}/{:.3} mm, mass change {}",
            s.steps,
            match clock {
                Some(c) => format!("{:.0} s simulated", c.step_s * s.steps as f64),
                None => regime_name.to_string(),
            },
            match stop_reason {
                "equilibrium" => ", stopped at equilibrium",
                "cap (steps)" => ", the cap: no equilibrium",
                _ => "",
            },
            r.automata(),
            s.activations,
            an.wavelength_m,
            an.height_m,
            an.ripple_index,
            an.lee_slope_deg,
            an.stoss_slope_deg,
            an.symmetry_index,
            an.crest_normal_deg,
            an.d50_crest_mm,
            an.d50_trough_mm,
            r.mass_change()
        )?;
    }
    Ok(())
}
