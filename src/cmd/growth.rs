//! The growth subcommands: `flame`, `deposit`, `crystal`, `ca`, `grow` (one scene each, or any
//! configuration) and `converge growth` (error against run time).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use cellsurf::engine::VERSION;
use cellsurf::engine::io::write_atomic;
use cellsurf::engine::lattice::{Boundary, Neighbourhood};
use cellsurf::growth::Growth;
use cellsurf::growth::converge;
use cellsurf::growth::figures;
use cellsurf::growth::sampler::SamplerKind;
use cellsurf::growth::scene::{
    self, RunHooks, RunResult, SceneConfig, SceneKind, Shape, WeightKind,
};
use cellsurf::plot::{CellField, GIF_FRAMES, GifWriter, Palette};

use super::conv::{self, Format, Outputs};
use cellsurf::engine::count::CountRange;

/// `converge growth --seeds`: independent seeds per curve.
const SEEDS_RANGE: CountRange = CountRange::new(3, 10_000, "3 to 10000");

#[derive(Args, Clone)]
pub struct GrowArgs {
    /// Scenario file (TOML) to start from instead of the scene's defaults.
    #[arg(long, value_name = "FILE")]
    scenario: Option<PathBuf>,
    /// Lattice: hex (6 neighbours, Eq. 3), square4 (Eq. 2) or square8 (Moore).
    #[arg(long)]
    lattice: Option<Neighbourhood>,
    /// Lattice size in cells: W or WxH (rows must be even on a hex torus).
    #[arg(long, value_name = "W[xH]", value_parser = conv::size_in(scene::SIZE_SIDES))]
    size: Option<conv::Size>,
    /// Boundary: torus, walls, channel (periodic x, walls y) or tube (walls x, periodic y).
    #[arg(long)]
    boundary: Option<Boundary>,
    /// Power-law exponent n >= 0 of p = v (b/z)^n.
    #[arg(long, allow_negative_numbers = true)]
    n: Option<f64>,
    /// Direction weight v: none (v = 1) or axes (Eq. 5).
    #[arg(long)]
    weight: Option<WeightKind>,
    /// Initial shape: point, square, disc, cosine or flat.
    #[arg(long)]
    shape: Option<Shape>,
    /// Size of the initial shape in cell widths: square side, disc diameter, cosine amplitude,
    /// flat thickness.
    #[arg(long, allow_negative_numbers = true)]
    start: Option<f64>,
    /// Monte Carlo timesteps (picks of a surface site, accepted or not; CA updates for ca);
    /// whole numbers, `1e7` accepted. With --events or --until-occupied and no --steps the
    /// exact sampler's clock has no limit; the rejection sampler needs --steps with them.
    #[arg(long, value_name = "N", value_parser = conv::count_in::<u64>(scene::STEPS), allow_negative_numbers = true)]
    steps: Option<u64>,
    /// Stop after N accepted events (cells added), `1e5` accepted: reaches stiff cases
    /// (large n) whose clock runs past 2^53.
    #[arg(long, value_name = "N", value_parser = conv::count_in::<u64>(scene::EVENTS), allow_negative_numbers = true)]
    events: Option<u64>,
    /// Stop when this fraction of the lattice is occupied, in (0, 1].
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    until_occupied: Option<f64>,
    /// Timesteps of the snapshots drawn by --out, comma-separated and increasing; whole
    /// numbers, `1e4` accepted.
    #[arg(long, value_name = "T1,T2,...", value_delimiter = ',', value_parser = conv::count_within::<u64>(scene::SNAPSHOTS), allow_negative_numbers = true)]
    snapshots: Option<Vec<u64>>,
    /// Sampler: exact (rejection-free, same process and clock), rejection (the paper's) or ca.
    #[arg(long)]
    sampler: Option<SamplerKind>,
    /// CA: minimum occupied neighbours for growth, cycled over timesteps (1 = Fig. 3; 1,2 = Fig. 4).
    #[arg(long, value_delimiter = ',', value_parser = conv::count_within::<usize>(scene::CA_RULE))]
    ca_rule: Option<Vec<usize>>,
    /// Seed of the random stream, 0 to 2^63 - 1 (the same seed gives the same output).
    #[arg(long, value_parser = conv::parse_seed)]
    seed: Option<u64>,
    /// Number of evenly spaced times at which observables are recorded (for a .csv output); at
    /// most one a timestep.
    #[arg(long, value_parser = conv::count_in::<usize>(scene::SERIES))]
    series: Option<usize>,
    /// Output file, repeatable; the extension picks the format: .png (the snapshots), .gif
    /// (an animation), .csv (the observable time series, parameters in '#' header lines).
    #[arg(long, value_name = "FILE")]
    out: Vec<PathBuf>,
    /// Old spelling of `--out FILE.csv` (kept for one release).
    #[arg(long, value_name = "FILE.csv", hide = true)]
    csv: Option<PathBuf>,
    /// Old spelling of `--out FILE.gif` (kept for one release).
    #[arg(long, value_name = "FILE.gif", hide = true)]
    gif: Option<PathBuf>,
    /// Frames in the GIF after the initial state (which the GIF also shows), 1 to 2000; at most
    /// one a timestep.
    #[arg(long, default_value_t = 60, value_parser = conv::count_in::<usize>(GIF_FRAMES))]
    gif_frames: usize,
    /// Print one JSON object with the run's summary on stdout (no progress bar).
    #[arg(long)]
    json: bool,
    /// No progress bar and no chatter on stderr.
    #[arg(long)]
    quiet: bool,
    /// Print the configuration as a scenario file and exit.
    #[arg(long)]
    print_scenario: bool,
}

/// The `--help` text that lists a scene's defaults (its scenario file).
pub fn defaults_help(scene: SceneKind) -> String {
    let mut s = format!(
        "Defaults of `cellsurf {scene}` (options left out keep these; print them with \
         --print-scenario, start from a file with --scenario):\n"
    );
    for line in SceneConfig::defaults(scene).to_toml().lines() {
        s.push_str(&format!("  {line}\n"));
    }
    s
}

#[derive(Args)]
pub struct ConvergeArgs {
    /// Which study to re-measure: growth (flame, deposition, crystal; both samplers), dunes,
    /// raytrace, ripple or windripples (each writes the figure MODEL_error_vs_time.png), or
    /// ripple_validation (ripple_validation.png: the ripples against the Soulsby & Whitehouse
    /// and Wiberg & Harris predictors, crest angle against current angle). Writes the figure
    /// and its table (data/FIGURE.csv and .toml) into --out-dir; `cellsurf figures` then
    /// draws the figure from that table. (`wind-ripples`, the subcommand's name, is taken for
    /// windripples.)
    #[arg(value_parser = ["growth", "dunes", "raytrace", "ripple", "windripples", "wind-ripples", "ripple_validation"])]
    study: String,
    /// Folder of the figure and its table.
    #[arg(long, default_value = "figures")]
    out_dir: PathBuf,
    /// growth only: independent seeds per curve, 3 to 10000.
    #[arg(long, default_value_t = figures::CONVERGE_SEEDS, value_parser = conv::count_in::<usize>(SEEDS_RANGE))]
    seeds: usize,
    /// growth only: print the curves as JSON.
    #[arg(long)]
    json: bool,
    /// No chatter on stderr.
    #[arg(long)]
    quiet: bool,
    /// Run part i of N of the study's runs (i in 0..N-1) and write their records to
    /// --out-dir (growth: growth_error_vs_time.part-i-of-N.json; the others:
    /// FIGURE.part-i-of-N.toml); then --gather.
    #[arg(
        long,
        value_name = "i/N",
        conflicts_with = "gather",
        allow_hyphen_values = true,
        value_parser = parse_part
    )]
    part: Option<cellsurf::engine::part::Part>,
    /// Draw the figure and its table from the part files in --out-dir (every part of one N).
    #[arg(long)]
    gather: bool,
}

/// `--part i/N`, checked as the command line is read (a value that is not a part of the study
/// is refused before any folder is made or run started).
fn parse_part(s: &str) -> std::result::Result<cellsurf::engine::part::Part, String> {
    s.parse()
        .map_err(|e: cellsurf::engine::part::PartError| format!("expected {}", e.expected))
}

/// A progress report on stderr (unless `--quiet`) as the runs of `study` finish: at most one
/// line every 2 seconds, and one for the last run.
fn run_progress(study: &str) -> impl Fn(cellsurf::engine::study::RunDone) + Sync + '_ {
    let start = Instant::now();
    let last = std::sync::Mutex::new(None::<Instant>);
    move |r| {
        let Ok(mut last) = last.lock() else {
            return;
        };
        let due = last.is_none_or(|t| t.elapsed().as_secs_f64() >= 2.0);
        if due || r.done == r.total {
            *last = Some(Instant::now());
            conv::note(format_args!(
                "{study}: {}/{} runs done ({}: {:.1} s; {:.0} s so far)",
                r.done,
                r.total,
                r.run,
                r.seconds,
                start.elapsed().as_secs_f64()
            ));
        }
    }
}

/// The records of part `part` of `study` (named `name` on the command line), with progress on
/// stderr, into `out_dir` (created if missing).
fn study_records(
    study: &dyn cellsurf::engine::study::Study,
    name: &str,
    part: cellsurf::engine::part::Part,
    out_dir: &Path,
) -> Result<Vec<(String, toml::Value)>> {
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("cannot create --out-dir {}", out_dir.display()))?;
    conv::begin();
    cellsurf::engine::study::run_part_reporting(study, part, &run_progress(name))
        .map_err(|e| anyhow::anyhow!("{name} study: {e}"))
}

/// `converge STUDY --part i/N` and `--gather` for the studies other than growth
/// ([`cellsurf::engine::study`]).
fn converge_parts(a: &ConvergeArgs) -> Result<()> {
    use cellsurf::engine::study::{PartFile, PartRecord, gather};
    let Some(study) = cellsurf::figures::study(&a.study) else {
        bail!(
            "--part and --gather: `converge {}` is not split into runs (it sweeps step sizes in seconds); run it whole",
            a.study
        );
    };
    // (--part: study_records makes --out-dir; --gather reads it, and makes none)
    let t = Instant::now();
    if let Some(part) = a.part {
        let records = study_records(study, &a.study, part, &a.out_dir)?
            .into_iter()
            .map(|(run, record)| PartRecord { run, record })
            .collect();
        let file = PartFile {
            study: study.name().into(),
            cellsurf_version: VERSION.into(),
            part,
            records,
        };
        let path = a.out_dir.join(PartFile::file_name(&study.figure(), part));
        write_atomic(&path, toml::to_string(&file)?.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
        conv::wrote(&path);
        conv::note(format_args!(
            "{} part {}/{} in {:.1} s",
            a.study,
            part.index,
            part.count,
            t.elapsed().as_secs_f64()
        ));
        return Ok(());
    }
    // (--gather: its inputs are the part files it reads)
    conv::begin();
    let prefix = format!("{}.part-", study.figure());
    let mut names: Vec<PathBuf> = std::fs::read_dir(&a.out_dir)
        .with_context(|| format!("--gather: reading --out-dir {}", a.out_dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .is_some_and(|n| n.starts_with(&prefix) && n.ends_with(".toml"))
        })
        .collect();
    names.sort();
    if names.is_empty() {
        bail!(
            "--gather: no {prefix}i-of-N.toml in {}",
            a.out_dir.display()
        );
    }
    let mut files = Vec::new();
    for f in &names {
        let text =
            std::fs::read_to_string(f).with_context(|| format!("reading {}", f.display()))?;
        let p: PartFile =
            toml::from_str(&text).with_context(|| format!("{}: not a part file", f.display()))?;
        files.push((f.display().to_string(), p));
    }
    let records = gather(study, VERSION, &files).map_err(|e| anyhow::anyhow!("--gather: {e}"))?;
    for p in cellsurf::figures::draw_study(study, &records, &a.out_dir)? {
        conv::wrote(&p);
    }
    Ok(())
}

/// The records a part of the growth study writes.
#[derive(serde::Serialize, serde::Deserialize)]
struct PartFile {
    cellsurf_version: String,
    seeds: usize,
    part: cellsurf::engine::part::Part,
    records: Vec<converge::RunRecord>,
}

/// Reads every part file of the growth study in `dir` and checks they belong together.
fn gather_parts(dir: &Path, seeds: usize) -> Result<Vec<converge::RunRecord>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("--gather: reading --out-dir {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .is_some_and(|n| {
                    n.starts_with("growth_error_vs_time.part-") && n.ends_with(".json")
                })
        })
        .collect();
    files.sort();
    if files.is_empty() {
        bail!(
            "--gather: no growth_error_vs_time.part-i-of-N.json in {}",
            dir.display()
        );
    }
    let mut records = Vec::new();
    let mut count = None;
    for f in &files {
        let text =
            std::fs::read_to_string(f).with_context(|| format!("reading {}", f.display()))?;
        let p: PartFile = serde_json::from_str(&text)
            .with_context(|| format!("{}: not a part file", f.display()))?;
        if p.seeds != seeds {
            bail!(
                "{}: made with --seeds {}, gathering with --seeds {seeds}",
                f.display(),
                p.seeds
            );
        }
        let first = *count.get_or_insert(p.part.count);
        if first != p.part.count {
            bail!(
                "{}: a part of {} parts, among parts of {first}: gather the parts of one split",
                f.display(),
                p.part.count
            );
        }
        records.extend(p.records);
    }
    Ok(records)
}

/// The configuration: scenario file or scene defaults, then each given option; and whether the
/// scenario file gave `series`.
fn config(scene: SceneKind, a: &GrowArgs) -> Result<(SceneConfig, bool)> {
    // Whether the snapshots are the user's (from the scenario file), not the defaults.
    let mut scenario_snapshots = false;
    let mut scenario_series = false;
    let mut c = match &a.scenario {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("cannot read --scenario {}", p.display()))?;
            // Checked once the command line has overridden it (below).
            let (c, given) = SceneConfig::parse_toml(&text)
                .with_context(|| format!("in --scenario {}", p.display()))?;
            scenario_snapshots = given.snapshots;
            scenario_series = given.series;
            // `grow` runs any scene's scenario; a named scene runs only its own.
            if c.scene != scene && scene != SceneKind::Grow {
                bail!(
                    "--scenario {} is a '{}' scene, not '{}': run `cellsurf {}`",
                    p.display(),
                    c.scene,
                    scene,
                    c.scene
                );
            }
            c
        }
        None => SceneConfig::defaults(scene),
    };
    if let Some(v) = a.lattice {
        c.lattice = v;
    }
    if let Some(conv::Size { w, h }) = a.size {
        c.width = w;
        c.height = h;
    }
    if let Some(v) = a.boundary {
        c.boundary = v;
    }
    if let Some(v) = a.n {
        c.n = v;
    }
    if let Some(v) = a.weight {
        c.weight = v;
    }
    if let Some(v) = a.shape {
        c.shape = v;
    }
    if let Some(v) = a.start {
        c.start = v;
    }
    if (a.events.is_some() || a.until_occupied.is_some())
        && a.steps.is_none()
        && a.sampler == Some(SamplerKind::Rejection)
    {
        bail!(
            "--events and --until-occupied with --sampler rejection need --steps (one pick per \
             timestep: its clock is its work); --sampler exact runs the same process with no clock limit"
        );
    }
    if a.events.is_some() || a.until_occupied.is_some() {
        c.events = a.events.or(c.events);
        c.until_occupied = a.until_occupied.or(c.until_occupied);
        if a.steps.is_none() && a.scenario.is_none() {
            // No clock limit; the default snapshots (clock times) are dropped, the final
            // state is drawn.
            c.steps = 0;
            if a.snapshots.is_none() {
                c.snapshots.clear();
            }
        }
    }
    if let Some(v) = a.steps {
        c.steps = v;
        // Default snapshots that no longer fit are thinned to those within the run; a
        // scenario's own, given for its own length, are too, and said so (a printed scenario
        // holds its snapshots, so that its run with a shorter --steps is not refused)
        let beyond: Vec<u64> = c.snapshots.iter().copied().filter(|&t| t > v).collect();
        if a.snapshots.is_none() && !scenario_snapshots {
            c.fit_snapshots_to_steps();
        } else if a.snapshots.is_none() && !beyond.is_empty() && v > 0 {
            c.snapshots.retain(|&t| t <= v);
            if c.snapshots.is_empty() {
                c.snapshots.push(v);
            }
            conv::changed(format_args!(
                "warning: the scenario's snapshots {beyond:?} lie beyond --steps = {v}: the run draws {:?}",
                c.snapshots
            ));
        }
    }
    if let Some(v) = &a.snapshots {
        c.snapshots = v.clone();
    }
    if let Some(v) = a.sampler {
        c.sampler = v;
    }
    if let Some(v) = &a.ca_rule {
        c.ca_rule = v.clone();
    }
    if let Some(v) = a.seed {
        c.seed = v;
    }
    if let Some(v) = a.series {
        c.series = v;
    }
    if !GIF_FRAMES.contains(a.gif_frames as u64) {
        bail!(
            "--gif-frames = {} is out of range: expected {}",
            a.gif_frames,
            GIF_FRAMES.expected
        );
    }
    // (n = -0 is n = 0: recorded as 0 in every output, not as -0)
    c.n += 0.0;
    c.validate().map_err(|e| name_default(e, a))?;
    Ok((c, scenario_series && a.series.is_none()))
}

/// A parameter out of range that the user did not type (neither on the command line nor
/// through --scenario) holds the scene's default: the error names the flag that sets it.
fn name_default(e: scene::SceneError, a: &GrowArgs) -> anyhow::Error {
    if let scene::SceneError::Range {
        parameter,
        value,
        expected,
    } = &e
        && a.scenario.is_none()
        && !conv::typed(parameter)
        && let Some(flag) = conv::typed_flag(parameter)
    {
        return anyhow::anyhow!(
            "{flag} = {value} (the default) is out of range: expected {expected}"
        );
    }
    e.into()
}

fn palette(scene: SceneKind) -> Palette {
    match scene {
        SceneKind::Flame => Palette::flame(),
        SceneKind::Deposit => Palette::solid(),
        SceneKind::Crystal => Palette::crystal(),
        _ => Palette::default(),
    }
}

struct CliHooks {
    bar: ProgressBar,
    shown: bool,
    silent: bool,
    start: Instant,
    frames: Vec<f64>,
    gif: Option<GifWriter>,
    gif_error: Option<anyhow::Error>,
    hex: bool,
    /// GIF frames at evenly spaced event counts (runs stopped by events).
    event_frames: usize,
    series: bool,
    snapshots: bool,
}

impl RunHooks for CliHooks {
    fn progress(&mut self, time: f64, steps: f64) {
        if !self.silent && !self.shown && self.start.elapsed().as_secs_f64() > 1.0 {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.shown = true;
        }
        self.bar.set_position((time / steps * 1000.0) as u64);
    }
    fn frame_times(&self) -> Vec<f64> {
        self.frames.clone()
    }
    fn frame_count(&self) -> usize {
        self.event_frames
    }
    fn wants_series(&self) -> bool {
        self.series
    }
    fn wants_snapshots(&self) -> bool {
        self.snapshots
    }
    fn frame(&mut self, _time: f64, g: &Growth) {
        if let Some(gif) = self.gif.as_mut() {
            let l = g.lattice();
            let field = CellField {
                nx: l.width(),
                ny: l.height(),
                hex: self.hex,
                states: g.field_states(),
            };
            if let Err(e) = gif.add_frame(&field) {
                self.gif_error.get_or_insert(e.into());
            }
        }
    }
}

/// The flags given on the command line that this run does not use, each with why: the
/// deterministic CA has no sticking law and draws no random number (`--n`, `--weight`,
/// `--seed`), the stochastic samplers have no CA rule (`--ca-rule`), a point seed has no size
/// (`--start`), and the options of an output
/// not asked for choose nothing (`--snapshots` without a `.png`, `--series` without a `.csv`,
/// `--gif-frames` without a `.gif`).
fn flags_without_effect(cfg: &SceneConfig, a: &GrowArgs, outs: &Outputs) -> Vec<String> {
    let mut out = Vec::new();
    let flag = |id: &str, long: &str| conv::typed_flag(id).unwrap_or_else(|| long.into());
    for (id, format, what) in [
        ("snapshots", Format::Png, "its panels"),
        ("series", Format::Csv, "its rows"),
        ("gif_frames", Format::Gif, "its frames"),
    ] {
        out.extend(outs.unused_option(id, format, what));
    }
    if cfg.sampler == SamplerKind::Ca {
        if a.n.is_some() {
            out.push(format!(
                "{} = {} has no effect: the deterministic CA (--sampler ca) occupies every site \
                 with at least --ca-rule occupied neighbours, with no sticking probability",
                flag("n", "--n"),
                cfg.n
            ));
        }
        if a.weight.is_some() {
            out.push(format!(
                "{} = {} has no effect: the deterministic CA (--sampler ca) has no site weights",
                flag("weight", "--weight"),
                cfg.weight
            ));
        }
        if conv::typed("seed") {
            out.push(format!(
                "{} = {} has no effect: the deterministic CA (--sampler ca) draws no random number",
                flag("seed", "--seed"),
                cfg.seed
            ));
        }
    } else if a.ca_rule.is_some() {
        out.push(format!(
            "{} has no effect with --sampler {}: it is the deterministic CA's rule \
             (--sampler ca)",
            flag("ca_rule", "--ca-rule"),
            cfg.sampler
        ));
    }
    if cfg.shape == Shape::Point && a.start.is_some() {
        out.push(format!(
            "{} = {} has no effect with --shape point: a point seed is one cell",
            flag("start", "--start"),
            cfg.start
        ));
    }
    out
}

pub fn grow(scene: SceneKind, a: GrowArgs) -> Result<()> {
    conv::synonyms(&[
        ("width", "size"),
        ("height", "size"),
        ("lattice width", "size"),
        ("lattice height", "size"),
    ]);
    conv::set_quiet(a.quiet);
    let (cfg, scenario_series) = config(scene, &a)?;
    let scene = cfg.scene;
    if a.print_scenario {
        out!(
            "# cellsurf {} scenario: `cellsurf {} --scenario FILE`\n{}",
            cellsurf::engine::VERSION,
            scene.name(),
            cfg.to_toml()
        )?;
        return Ok(());
    }
    // 4 bytes per cell, a surface of up to a few bytes per cell, and a snapshot or frame of
    // one byte per cell at a time.
    conv::check_memory(
        &format!("--size {}x{}", cfg.width, cfg.height),
        cfg.width as f64 * cfg.height as f64 * 10.0,
    )?;
    let mut outs = Outputs::new(
        &a.out,
        scene.name(),
        &[Format::Png, Format::Gif, Format::Csv],
    )?;
    outs.add_legacy(Format::Csv, a.csv.as_ref())?;
    outs.add_legacy(Format::Gif, a.gif.as_ref())?;
    for w in flags_without_effect(&cfg, &a, &outs) {
        conv::note(format_args!("warning: {w}"));
    }
    let by_events = cfg.events.is_some() || cfg.until_occupied.is_some();
    // A clock-stopped run draws its snapshots only (an event-stopped one its final state too).
    if let Some(p) = outs.get(Format::Png)
        && cfg.snapshots.is_empty()
        && !by_events
    {
        bail!(
            "{} {} needs at least one snapshot ({})",
            conv::typed_flag("out").unwrap_or_else(|| "--out".into()),
            p.display(),
            if a.snapshots.is_none() && conv::scenario_keys().iter().any(|k| k == "snapshots") {
                "the scenario's snapshots = [] gives none: give --snapshots"
            } else {
                "--snapshots"
            }
        );
    }
    conv::begin();
    let bar = ProgressBar::with_draw_target(Some(1000), ProgressDrawTarget::hidden());
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{bar:40}] {percent}% ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(format!("{scene} {}x{}", cfg.width, cfg.height));
    // Every picture (PNG, GIF) records the run's parameters.
    cellsurf::plot::set_png_parameters(Some(cfg.to_toml()));
    let gif = match outs.get(Format::Gif) {
        Some(p) => Some(GifWriter::create(
            p,
            cfg.width,
            cfg.height,
            cfg.lattice.is_hex(),
            480,
            &palette(scene),
            8,
        )?),
        None => None,
    };
    // (frames and series points fall on whole timesteps: a run of fewer timesteps than asked
    // for has one a timestep, and says so where they were typed)
    let fewer = |what: &str, asked: usize, file: &str, unit: &str, from_scenario: bool| {
        // (a default the user did not ask for is not warned of)
        if !by_events && asked as u64 > cfg.steps && (conv::typed(what) || from_scenario) {
            conv::changed(format_args!(
                "warning: {} = {asked} is more than the run's {} timesteps: the {file} has one \
                 {unit} a timestep, {} in all",
                if from_scenario {
                    format!("the scenario's {what}")
                } else {
                    conv::typed_flag(what)
                        .unwrap_or_else(|| format!("--{}", what.replace('_', "-")))
                },
                cfg.steps,
                cfg.steps + 1
            ));
        }
    };
    if outs.get(Format::Csv).is_some() {
        fewer("series", cfg.series, ".csv", "row", scenario_series);
    }
    let frames = if gif.is_some() && !by_events {
        fewer("gif_frames", a.gif_frames, ".gif", "frame", false);
        let k = a.gif_frames.max(1) as u64;
        let mut f: Vec<f64> = (0..=k)
            .map(|i| (cfg.steps as u128 * i as u128 / k as u128) as f64)
            .collect();
        f.dedup();
        f
    } else {
        Vec::new()
    };
    let mut hooks = CliHooks {
        bar,
        shown: false,
        silent: a.quiet || a.json,
        start: Instant::now(),
        frames,
        event_frames: if gif.is_some() && by_events {
            a.gif_frames
        } else {
            0
        },
        gif,
        gif_error: None,
        hex: cfg.lattice.is_hex(),
        series: outs.get(Format::Csv).is_some(),
        snapshots: outs.get(Format::Png).is_some(),
    };
    let r = scene::run(&cfg, &mut hooks).map_err(|e| name_default(e, &a))?;
    hooks.bar.finish_and_clear();
    let flag = conv::typed_flag("out").unwrap_or_else(|| "--out".into());
    if let Some(e) = hooks.gif_error.take() {
        return Err(e.context(format!("writing {flag} .gif")));
    }
    if let (Some(gif), Some(p)) = (hooks.gif.take(), outs.get(Format::Gif)) {
        gif.finish()
            .with_context(|| format!("writing {flag} {}", p.display()))?;
        conv::wrote(p);
    }
    if let Some(p) = outs.get(Format::Png) {
        if r.snapshots.is_empty() {
            bail!(
                "{flag} {} needs at least one snapshot (--snapshots)",
                p.display()
            );
        }
        figures::draw_snapshots(
            p,
            &format!("{scene}: {}", figures::describe(&cfg)),
            &r,
            &palette(scene),
        )
        .with_context(|| format!("writing {flag} {}", p.display()))?;
        conv::wrote(p);
    }
    if let Some(p) = outs.get(Format::Csv) {
        write_csv(p, &r).with_context(|| format!("writing {flag} {}", p.display()))?;
        conv::wrote(p);
    }
    if a.json {
        outln!("{}", serde_json::to_string(&summary(&r)?)?)?;
    } else {
        print_summary(&r)?;
    }
    Ok(())
}

/// Peak resident memory of this process, bytes (Linux; `None` elsewhere).
fn peak_rss_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

fn summary(r: &RunResult) -> Result<serde_json::Value> {
    let c = &r.config;
    let mut v = serde_json::json!({
        "scene": c.scene.name(),
        "steps": if r.last.time.is_finite() { serde_json::json!(r.last.time) } else { serde_json::Value::Null },
        "clock_finite": r.last.time.is_finite(),
        "clock_exact": r.clock_exact,
        "log10_clock": r.log10_clock,
        "accepted": r.last.accepted,
        "occupied": r.last.occupied,
        "surface_sites": r.last.surface,
        "stop_reason": r.stop,
        "setup_s": r.setup_s,
        "observe_s": r.observe_s,
        "accepted_per_s": r.last.accepted as f64 / (r.elapsed_s - r.observe_s).max(1e-12),
        "memory_bytes": r.memory_bytes,
        "bytes_per_cell": r.memory_bytes as f64 / (c.width * c.height) as f64,
        "peak_rss_bytes": peak_rss_bytes(),
    });
    if let (Some(obj), Ok(serde_json::Value::Object(o))) =
        (v.as_object_mut(), serde_json::to_value(r.last.values))
    {
        obj.extend(o);
    }
    conv::envelope("growth", c, r.elapsed_s, v)
}

fn print_summary(r: &RunResult) -> Result<()> {
    let c = &r.config;
    outln!(
        "cellsurf {VERSION}: {} on {}",
        c.scene,
        figures::describe(c)
    )?;
    // The clock as a whole number while it is exact, else to 7 digits, else by its log.
    let clock = if r.clock_exact {
        format!("{}", r.last.time)
    } else if r.last.time.is_finite() {
        format!("{:.6e} (rounded)", r.last.time)
    } else {
        format!("10^{:.4} (past the largest f64)", r.log10_clock)
    };
    outln!(
        "  timesteps {clock}  accepted {}  occupied {}  surface sites {}  ({:?})",
        r.last.accepted,
        r.last.occupied,
        r.last.surface,
        r.stop
    )?;
    let v = r.last.values;
    for (name, x) in [
        ("front_radius_cv", v.front_radius_cv),
        ("axis_diagonal_ratio", v.axis_diagonal_ratio),
        ("mode1_amplitude", v.mode1_amplitude),
        ("mean_elevation", v.mean_elevation),
    ] {
        if let Some(x) = x {
            outln!("  {name} = {x:.4}")?;
        }
    }
    outln!("  run {:.3} s, set-up {:.3} s", r.elapsed_s, r.setup_s)?;
    Ok(())
}

fn write_csv(path: &Path, r: &RunResult) -> std::io::Result<()> {
    let mut s = String::new();
    s.push_str(&format!("# cellsurf {VERSION}\n"));
    for line in r.config.to_toml().lines() {
        s.push_str(&format!("# {line}\n"));
    }
    // log10_time stays finite where an unbounded run's time passed the largest f64 (inf).
    s.push_str("time,accepted,occupied,surface_sites,front_radius_cv,axis_diagonal_ratio,mode1_amplitude,mean_elevation,log10_time\n");
    let f = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x}"));
    for o in &r.series {
        let v = o.values;
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{}\n",
            o.time,
            o.accepted,
            o.occupied,
            o.surface,
            f(v.front_radius_cv),
            f(v.axis_diagonal_ratio),
            f(v.mode1_amplitude),
            f(v.mean_elevation),
            o.log10_time
        ));
    }
    write_atomic(path, s.as_bytes())
}

pub fn converge(mut a: ConvergeArgs) -> Result<()> {
    conv::set_quiet(a.quiet);
    // the subcommand's spelling names the study and figure prefix `windripples`
    if a.study == "wind-ripples" {
        a.study = "windripples".into();
    }
    if a.study != "growth" {
        // (flags that the run would not use are warned of, not refused: docs/cli.md)
        for id in ["seeds", "json"] {
            if conv::typed(id) {
                conv::note(format_args!(
                    "warning: --{id} has no effect with `converge {}`: it is for `converge growth` only",
                    a.study
                ));
            }
        }
        if a.part.is_some() || a.gather {
            return converge_parts(&a);
        }
        let name = cellsurf::figures::MEASURED
            .iter()
            .find(|(s, _)| *s == a.study)
            .map_or_else(
                || format!("{}_error_vs_time", a.study),
                |(_, f)| f.to_string(),
            );
        let f = cellsurf::figures::find(&name).with_context(|| format!("no figure {name}"))?;
        let t = Instant::now();
        let made = match cellsurf::figures::study(&a.study) {
            // a study split into runs: the same runs and figure, with progress on the way
            Some(study) => {
                let records: Vec<toml::Value> = study_records(
                    study,
                    &a.study,
                    cellsurf::engine::part::Part::WHOLE,
                    &a.out_dir,
                )?
                .into_iter()
                .map(|(_, v)| v)
                .collect();
                cellsurf::figures::draw_study(study, &records, &a.out_dir)?
            }
            None => {
                conv::begin();
                cellsurf::figures::make(f, &a.out_dir, true)?
            }
        };
        for p in made {
            conv::wrote(&p);
        }
        conv::note(format_args!(
            "{} re-measured in {:.1} s",
            a.study,
            t.elapsed().as_secs_f64()
        ));
        return Ok(());
    }
    if !SEEDS_RANGE.contains(a.seeds as u64) {
        bail!(
            "--seeds = {} is out of range: expected {}",
            a.seeds,
            SEEDS_RANGE.expected
        );
    }
    let t0 = Instant::now();
    // (--gather reads --out-dir and writes into it: it makes none)
    if !a.gather {
        std::fs::create_dir_all(&a.out_dir)
            .with_context(|| format!("cannot create --out-dir {}", a.out_dir.display()))?;
    }
    if let Some(part) = a.part {
        conv::begin();
        let records = converge::growth_runs(a.seeds, part)?;
        let path = a.out_dir.join(format!(
            "growth_error_vs_time.part-{}-of-{}.json",
            part.index, part.count
        ));
        let file = PartFile {
            cellsurf_version: VERSION.into(),
            seeds: a.seeds,
            part,
            records,
        };
        write_atomic(&path, serde_json::to_string_pretty(&file)?.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
        conv::wrote(&path);
        return Ok(());
    }
    conv::begin();
    let curves = if a.gather {
        let records = gather_parts(&a.out_dir, a.seeds)?;
        converge::gather_growth(a.seeds, &records).map_err(|e| anyhow::anyhow!("--gather: {e}"))?
    } else {
        converge::converge_growth(a.seeds)?
    };
    let name = "growth_error_vs_time";
    let out = a.out_dir.join(format!("{name}.png"));
    cellsurf::plot::set_png_parameters(Some(format!(
        "figure = \"{name}\"\nseeds = {}\ngathered = {}",
        a.seeds, a.gather
    )));
    cellsurf::plot::record_charts(true);
    let drawn = figures::draw_error_vs_time(&out, &curves, a.seeds);
    let recorded = cellsurf::plot::record_charts(false);
    cellsurf::plot::set_png_parameters(None);
    drawn?;
    let mut written = vec![out.clone()];
    if let Some((_, table)) = recorded.into_iter().last() {
        written.extend(table.write(&a.out_dir, name)?);
    }
    for p in &written {
        conv::wrote(p);
    }
    if a.json {
        let v = conv::envelope(
            "growth",
            serde_json::json!({ "study": "converge", "seeds": a.seeds }),
            t0.elapsed().as_secs_f64(),
            serde_json::json!({ "curves": curves }),
        )?;
        outln!("{}", serde_json::to_string(&v)?)?;
        return Ok(());
    }
    outln!(
        "{:14} {:10} {:20} {:>10} {:>12} {:>12}",
        "case",
        "sampler",
        "observable",
        "mean",
        "std error",
        "run time s"
    )?;
    for c in &curves {
        if let Some(p) = c.points.last() {
            outln!(
                "{:14} {:10} {:20} {:>10.5} {:>12.3e} {:>12.3}",
                c.label,
                c.sampler.name(),
                c.observable,
                p.mean,
                p.std_error,
                p.cpu_s
            )?;
        }
    }
    Ok(())
}
