//! `cellsurf dunes`: the Werner-model dune article's slab model (ripple mode, dune mode `-d`)
//! and the Werner (1995) variant (`--variant werner`), with the article's short options.
//!
//! The library does the work ([`cellsurf::dunes`]); this file parses options, shows a
//! progress bar on stderr for runs longer than a second (never with `--json` or `--quiet`),
//! writes the optional PNG and GIF and prints the summary (or one JSON object).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};

use super::conv::{self, Format, Outputs, Size};
use cellsurf::dunes;
use cellsurf::plot::GIF_FRAMES;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use cellsurf::dunes::{
    BODY_THRESHOLD, DuneConfig, DuneModel, GRAINS_PER_UNIT, MigrationRecorder, Mode, Pile, Start,
    VERSION, WernerParams, describe_run, draw_result,
};

/// Which model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Variant {
    /// The article's code: ripple mode, or dune mode with -d.
    Article,
    /// Werner (1995): slabs, 15-degree shadow zone, angle of repose (33 degrees).
    Werner,
}

/// The initial state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StartKind {
    /// The mode's random heights (uniform in [0, 2Q] with -d and werner, in [2.85, 3.15] in
    /// ripple mode).
    #[default]
    Random,
    /// One round pile of sand on bare ground, a Gaussian h exp(-d^2 / r^2) (--pile-centre,
    /// --pile-height, --pile-radius).
    Pile,
}

impl StartKind {
    fn is_random(&self) -> bool {
        *self == StartKind::Random
    }
}

/// Options of `cellsurf dunes`. Short options as in the article's `simulate.py`.
#[derive(clap::Args, Serialize, Deserialize)]
#[command(
    after_help = "Examples:\n  cellsurf dunes -d -q 1 --out q1.png       # barchans (dune mode, Q = 1)\n  \
                  cellsurf dunes -d -q 3 --size 140 --out q3.gif  # transverse ridges, animated\n  \
                  cellsurf dunes --variant werner -q 0.5 --steps 1000 --json\n  \
                  cellsurf dunes -d --start pile --out pile.png  # one pile becomes a barchan\n  \
                  cellsurf dunes -w 5 --steps 200            # ripple mode (the earlier article)"
)]
pub struct Args {
    /// Start from this scenario file (TOML, `model = "dunes"`); options typed here override it.
    #[arg(long, value_name = "FILE.toml")]
    scenario: Option<PathBuf>,
    /// Grid size in cells, N or NxN: the grid is square and periodic, N from 3 to 4096.
    #[arg(
        short = 'g',
        long = "size",
        value_name = "N",
        alias = "grid",
        alias = "grid-size",
        alias = "grid_size",
        default_value = "100",
        value_parser = conv::size_in(dunes::SIZE_SIDES)
    )]
    size: Size,
    /// Iterations: each makes the picks, then applies the rolling rule (0 to 10^9; `1e6`
    /// accepted).
    #[arg(
        short = 'i',
        long = "steps",
        value_name = "N",
        alias = "iterations",
        alias = "num-iter",
        alias = "num_iter",
        value_parser = conv::count_in::<u64>(dunes::ITERATIONS),
        default_value = "500"
    )]
    steps: u64,
    /// Dune mode: int(0.2 N^2) picks among cells with sand, tanh jump and quantity laws,
    /// D = 0.3 (without -d: ripple mode, N^2 picks, jump int(wind + h), q = 0.1, D = 0.1;
    /// `--dune=false`, the value joined by `=`, runs ripple mode from a scenario that sets
    /// `dune = true`).
    #[arg(
        short = 'd',
        long = "dune",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "true",
        default_value_t = false,
        action = clap::ArgAction::Set,
        value_name = "BOOL",
        value_parser = clap::builder::BoolishValueParser::new()
    )]
    dune: bool,
    /// Sand quantity Q: mean initial height in cell widths, initial h uniform in [0, 2Q]
    /// (dune mode and werner with --start random; 0 to 10^5).
    #[arg(short = 'q', long = "quantity", default_value_t = 1.0)]
    quantity: f64,
    /// Initial state: random or pile, in every mode; with pile, -q is unused (the pile
    /// replaces the random heights), and werner rounds the pile's heights to whole slabs.
    #[arg(long, value_enum, default_value_t = StartKind::Random)]
    #[serde(default, skip_serializing_if = "StartKind::is_random")]
    start: StartKind,
    /// --start pile: the pile's centre X,Y as fractions of the grid side, each 0 to 1 (X
    /// downwind, Y across the wind; the centre is at X N, Y N cells; the pile is cut at the
    /// grid's edges, not wrapped round them) [default: 0.3333333333333333,0.5: a third of the
    /// way downwind, half way across].
    #[arg(
        long,
        value_name = "X,Y",
        value_delimiter = ',',
        allow_negative_numbers = true
    )]
    pile_centre: Option<Vec<f64>>,
    /// --start pile: the pile's height h at its centre, in cell widths, above 0 and at most
    /// 10^5 [default: 6].
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    pile_height: Option<f64>,
    /// --start pile: the pile's radius r in cells (h exp(-d^2 / r^2) at d cells from the
    /// centre), above 0 and at most 4096 [default: 12].
    #[arg(long, value_name = "R", allow_negative_numbers = true)]
    pile_radius: Option<f64>,
    /// Wind speed in cells (ripple mode: jump = int(wind + h); finite, -10^9 to 10^9).
    #[arg(short = 'w', long = "wind", default_value_t = 3.0)]
    wind: f64,
    /// Seed of the random stream, 0 to 2^63 - 1 (the same seed gives the same output).
    #[arg(short = 's', long = "seed", default_value_t = 1, value_parser = conv::parse_seed)]
    seed: u64,
    /// Model: article (the article's code) or werner (Werner 1995 on the same slab engine).
    #[arg(long, value_enum, default_value_t = Variant::Article)]
    variant: Variant,
    /// Werner: hop length L of a slab, in cells (1 to 10^6).
    #[arg(long, default_value_t = 5, value_parser = conv::count_in::<u32>(dunes::HOP))]
    hop: u32,
    /// Dune-body threshold in cell widths: cells higher than this form dune bodies, the
    /// others are bare ground (finite, at least 0).
    #[arg(long, default_value_t = BODY_THRESHOLD)]
    threshold: f64,
    /// Output file, repeatable; the extension picks the format: .png (final heights and dune
    /// bodies), .gif (an animation of the migration).
    #[arg(long, value_name = "FILE")]
    out: Vec<PathBuf>,
    /// Old spelling of `--out FILE.gif` (kept for one release).
    #[arg(long, value_name = "FILE.gif", hide = true)]
    gif: Option<PathBuf>,
    /// Frames in the GIF after the initial state (1 to 2000), evenly spaced over the
    /// iterations, the last at the end (fewer when the run has fewer iterations).
    #[arg(long, default_value_t = 60, value_parser = conv::count_in::<usize>(GIF_FRAMES))]
    gif_frames: usize,
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

/// The model a mode runs, in words.
fn describe_mode(m: Mode) -> &'static str {
    match m {
        Mode::Ripple => "ripple mode (the article's code without -d)",
        Mode::Dune => "dune mode (-d)",
        Mode::Werner => "--variant werner",
    }
}

/// The run's configuration and initial state from the options.
fn config(a: &Args) -> Result<(DuneConfig, Start)> {
    let mode = match (a.variant, a.dune) {
        (Variant::Werner, _) => Mode::Werner,
        (Variant::Article, true) => Mode::Dune,
        (Variant::Article, false) => Mode::Ripple,
    };
    let cfg = DuneConfig {
        mode,
        grid: a.size.side()?,
        iterations: a.steps,
        quantity: a.quantity,
        wind: a.wind,
        seed: a.seed,
        werner: WernerParams {
            hop: a.hop,
            ..WernerParams::default()
        },
    };
    cfg.validate()?;
    if !dunes::HOP.contains(u64::from(a.hop)) {
        bail!(
            "hop = {} is out of range: expected {}",
            a.hop,
            dunes::HOP.expected
        );
    }
    // An option the chosen model does not use is refused, not ignored; a scenario file's
    // value of it (away from its default: --print-scenario writes every key) is warned of.
    // (The pile's options hold a value only when given, on the command line or in a scenario.)
    let join = |v: &[f64]| v.iter().map(f64::to_string).collect::<Vec<_>>().join(",");
    let value = |id: &str| match id {
        "quantity" => Some(a.quantity.to_string()),
        "wind" => Some(a.wind.to_string()),
        "hop" => Some(a.hop.to_string()),
        "pile_centre" => a.pile_centre.as_deref().map(join),
        "pile_height" => a.pile_height.map(|v| v.to_string()),
        "pile_radius" => a.pile_radius.map(|v| v.to_string()),
        _ => Some(a.dune.to_string()),
    };
    let unused_in = |id: &str, applies: &str, here: &str| -> Result<()> {
        if conv::typed(id) {
            let flag = conv::typed_flag(id).unwrap_or_else(|| format!("--{id}"));
            bail!("{flag} applies to {applies}, not to {here}");
        }
        if let Some(v) = value(id)
            && conv::set_by_scenario(id, &v)
        {
            conv::note(format_args!(
                "warning: the scenario's {id} = {v} has no effect: it applies to {applies}, not to {here}"
            ));
        }
        Ok(())
    };
    let unused = |id: &str, applies: &str| unused_in(id, applies, describe_mode(mode));
    match mode {
        Mode::Ripple => unused("quantity", "dune mode (-d) and --variant werner")?,
        Mode::Dune => {
            unused("wind", "ripple mode (no -d)")?;
            unused("hop", "--variant werner")?;
        }
        Mode::Werner => {
            unused("wind", "ripple mode (no -d)")?;
            unused("dune", "--variant article")?;
        }
    }
    if mode == Mode::Ripple {
        unused("hop", "--variant werner")?;
    }
    let start = match a.start {
        StartKind::Random => {
            for id in ["pile_centre", "pile_height", "pile_radius"] {
                unused_in(id, "--start pile", "--start random")?;
            }
            Start::Random
        }
        StartKind::Pile => {
            if mode != Mode::Ripple {
                unused_in(
                    "quantity",
                    "--start random (the pile replaces the random heights)",
                    "--start pile",
                )?;
            }
            let d = Pile::DEFAULT;
            Start::Pile(Pile::new(
                a.pile_centre.as_deref().unwrap_or(&d.centre),
                a.pile_height.unwrap_or(d.height),
                a.pile_radius.unwrap_or(d.radius),
            )?)
        }
    };
    if !(a.threshold.is_finite() && a.threshold >= 0.0) {
        bail!(
            "threshold = {} is out of range: expected a finite height of at least 0 cell widths",
            a.threshold
        );
    }
    if !GIF_FRAMES.contains(a.gif_frames as u64) {
        bail!(
            "gif_frames = {} is out of range: expected {}",
            a.gif_frames,
            GIF_FRAMES.expected
        );
    }
    Ok((cfg, start))
}

/// The options with the pile's written out when the run starts from a pile, so that its
/// scenario (`--print-scenario`, the PNG's parameters) names every one.
fn with_pile_written_out(mut a: Args, start: &Start) -> Args {
    if let Start::Pile(p) = start {
        a.pile_centre = Some(p.centre.to_vec());
        a.pile_height = Some(p.height);
        a.pile_radius = Some(p.radius);
    }
    a
}

/// Runs `cellsurf dunes`.
pub fn run(a: Args) -> Result<()> {
    conv::synonyms(&[("grid", "size"), ("iterations", "steps")]);
    conv::set_quiet(a.quiet);
    let scenario = a.scenario.clone();
    let a = conv::merge_scenario(a, scenario.as_deref(), "dunes")?;
    let (cfg, initial) = config(&a)?;
    let a = with_pile_written_out(a, &initial);
    if a.print_scenario {
        out!("{}", conv::scenario_text(&a, "dunes")?)?;
        return Ok(());
    }
    let mut outs = Outputs::new(&a.out, "dunes", &[Format::Png, Format::Gif])?;
    outs.add_legacy(Format::Gif, a.gif.as_ref())?;
    // (about 50 bytes a cell at its peak, measured with a PNG at --size 2048: the heights,
    // fluxes and index lists, the analysis and the picture; 64 with room to spare)
    conv::check_memory(
        &format!(
            "{} {}",
            conv::typed_flag("size").unwrap_or_else(|| "--size".into()),
            cfg.grid
        ),
        64.0 * (cfg.grid * cfg.grid) as f64,
    )?;
    if let Some(w) = outs.unused_option("gif_frames", Format::Gif, "its frames") {
        conv::note(format_args!("warning: {w}"));
    }
    let flag = conv::typed_flag("out").unwrap_or_else(|| "--out".into());
    let silent = a.quiet || a.json;
    conv::begin();
    let bar =
        ProgressBar::with_draw_target(Some(cfg.iterations.max(1)), ProgressDrawTarget::hidden());
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{bar:40}] {pos}/{len} ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(format!("dunes {} {}x{}", cfg.mode, cfg.grid, cfg.grid));
    let start = Instant::now();
    let mut m = DuneModel::with_start(&cfg, &initial)?;
    if m.grains().iter().all(|&g| g == 0) {
        let (flag, value) = match &initial {
            Start::Random => (
                conv::typed_flag("quantity").unwrap_or_else(|| "-q".into()),
                cfg.quantity,
            ),
            Start::Pile(p) => (
                conv::typed_flag("pile_height").unwrap_or_else(|| "--pile-height".into()),
                p.height,
            ),
        };
        let counted = match (&initial, cfg.mode) {
            (Start::Pile(_), Mode::Werner) => format!(
                "--variant werner rounds each height to whole slabs of {} cell widths, and every \
                 height of this pile rounds to none",
                cfg.werner.slab
            ),
            _ => "heights are counted in grains of 1e-6 cell widths".to_string(),
        };
        conv::note(format!(
            "note: {flag} = {value} puts no sand on the grid ({counted}): nothing will move"
        ));
    }
    let mut rec = outs.get(Format::Gif).map(|_| MigrationRecorder::new(480));
    // The initial state, then --gif-frames states evenly spaced up to the last iteration (as
    // a growth run's GIF): iteration `iterations i / frames` for i = 1..=frames, once each.
    let frames = a.gif_frames as u64;
    // (a typed frame count the run cannot give; the default gives what it can)
    if (conv::typed("gif_frames") || conv::set_by_scenario("gif_frames", &frames.to_string()))
        && let Some(flag) = conv::typed_flag("gif_frames")
        && rec.is_some()
        && frames > cfg.iterations
    {
        conv::changed(format_args!(
            "warning: {flag} = {frames} is more than the run's {} iterations: the GIF has one frame an iteration, {} in all",
            cfg.iterations,
            cfg.iterations + 1
        ));
    }
    let mut next_frame = 1u64;
    let frame_at = |i: u64| (cfg.iterations as u128 * i as u128 / frames as u128) as u64;
    if let Some(r) = rec.as_mut() {
        r.add(&m);
    }
    let mut shown = false;
    while m.iteration() < cfg.iterations {
        m.step();
        let t = m.iteration();
        if let Some(r) = rec.as_mut()
            && next_frame <= frames
            && frame_at(next_frame) <= t
        {
            r.add(&m);
            while next_frame <= frames && frame_at(next_frame) <= t {
                next_frame += 1;
            }
        }
        if !silent && !shown && start.elapsed().as_secs_f64() > 1.0 {
            bar.set_draw_target(ProgressDrawTarget::stderr());
            shown = true;
        }
        bar.set_position(t);
    }
    let elapsed = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let s = m.stats_with_threshold(a.threshold);
    if s.sand_change != 0 || m.grains().len() != cfg.grid * cfg.grid {
        bail!("internal error: sand changed by {} grains", s.sand_change);
    }
    // The run's scenario goes into the PNG (iTXt `parameters`) and the GIF (a comment): fed
    // back to --scenario it makes the same picture.
    cellsurf::plot::set_png_parameters(Some(conv::scenario_text(&a, "dunes")?));
    if let (Some(r), Some(p)) = (rec.as_ref(), outs.get(Format::Gif)) {
        r.write(p, 480, 8)
            .with_context(|| format!("writing {flag} {}", p.display()))?;
        conv::wrote(p);
    }
    if let Some(p) = outs.get(Format::Png) {
        draw_result(p, &m, &describe_run(&cfg, &initial))
            .with_context(|| format!("writing {flag} {}", p.display()))?;
        conv::wrote(p);
    }
    let (picks, moves) = m.picks();
    let rate = if elapsed > 0.0 {
        cfg.iterations as f64 / elapsed
    } else {
        0.0
    };
    if a.json {
        let own = serde_json::json!({
            "mode": cfg.mode.name(),
            "variant": match a.variant { Variant::Article => "article", Variant::Werner => "werner" },
            "iterations": m.iteration(),
            "elapsed_s": elapsed,
            "iterations_per_s": rate,
            "picks": picks,
            "moves": moves,
            "dune_bodies": s.dune_bodies,
            "spanning_bodies": s.spanning_bodies,
            "bare_fraction": s.bare_fraction,
            "largest_body_fraction": s.largest_body_fraction,
            "threshold": s.threshold,
            "min_height": s.min_height,
            "max_height": s.max_height,
            "mean_height": s.mean_height,
            "total_grains": s.total_grains,
            "grains_per_unit": GRAINS_PER_UNIT,
            "sand_change": s.sand_change,
            "config": cfg,
            "start": initial,
        });
        let v = conv::envelope("dunes", conv::scenario_table(&a)?, elapsed, own)?;
        outln!("{}", serde_json::to_string(&v)?)?;
    } else {
        outln!("cellsurf {VERSION} dunes: {}", describe_run(&cfg, &initial))?;
        if let Start::Pile(p) = &initial {
            let n = cfg.grid as f64;
            outln!(
                "  start: one pile {} cell widths high, radius {} cells, centred at ({}, {}) cells",
                p.height,
                p.radius,
                format!("{:.2}", p.centre[0] * n),
                format!("{:.2}", p.centre[1] * n)
            )?;
        }
        outln!(
            "  iterations {} in {elapsed:.3} s ({rate:.0} iterations/s); picks {picks}, of which {moves} moved sand",
            m.iteration()
        )?;
        outln!(
            "  dune bodies {} ({} spanning the grid), bare fraction {:.3} (h <= {} cell widths), largest body {:.1}% of the grid",
            s.dune_bodies,
            s.spanning_bodies,
            s.bare_fraction,
            s.threshold,
            100.0 * s.largest_body_fraction
        )?;
        outln!(
            "  heights {:.4} .. {:.4}, mean {:.4} cell widths; sand change {} grains (exact)",
            s.min_height,
            s.max_height,
            s.mean_height,
            s.sand_change
        )?;
    }
    Ok(())
}
