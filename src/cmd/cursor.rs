//! `cellsurf cursor`: the wind-field cursor walk of "A model for sedimentation of airborne
//! particles" (article; Eqs. 1-3).
//!
//! The library does the work ([`cellsurf::cursor`]); this file parses the options, builds the
//! wind field (a PNG image or a built-in generator), runs the walk in chunks with a progress
//! bar on stderr for runs longer than a second (never with `--json` or `--quiet`), writes the
//! optional pictures and prints a summary (or one JSON object).

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};

use super::conv::{self, Format, Outputs, Size};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use cellsurf::cursor::stats::{self, NoiseModel};
use cellsurf::cursor::wind::{WindOptions, check_size};
use cellsurf::cursor::{
    ARTICLE_STEPS, CursorWalk, DEFAULT_K, DEFAULT_SIZE, SeaLevel, Transitions, WindField, WindSpec,
    display, draw_landscape,
};
use cellsurf::engine::VERSION;
use cellsurf::engine::io::write_atomic;

/// The built-in wind generators.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Generator {
    /// No wind: a plain random walk (article Fig. 2).
    Calm,
    /// The same wind everywhere (Fig. 4). Options: angle, speed.
    Uniform,
    /// Two winds meeting head-on in alternating bands (Fig. 5). Options: angle, speed, spread,
    /// wavelength.
    Bimodal,
    /// A drift converging around an array of centres (Figs. 6, 7). Options: angle, speed,
    /// radial, wavelength, spacing, radius.
    Converging,
    /// Direction rotating around an array of nodes: star dunes (Fig. 8). Options: angle,
    /// speed, wavelength, arms.
    Rotating,
}

impl Generator {
    fn name(self) -> &'static str {
        match self {
            Generator::Calm => "calm",
            Generator::Uniform => "uniform",
            Generator::Bimodal => "bimodal",
            Generator::Converging => "converging",
            Generator::Rotating => "rotating",
        }
    }
}

/// Options of `cellsurf cursor`.
#[derive(clap::Args, Serialize, Deserialize)]
#[command(
    long_about = "Wind-field cursor walk: one cursor walks an 8-neighbour torus and each cell it \
        arrives in gains one unit of height. Under a wind W the move in direction i (unit vector \
        u_i) has probability P_i = 1/8 + k (W . u_i) / 1760, which stays in [0, 1/4] for \
        0 <= k <= 1 and |W| <= 220. A wind image's pixels are three colour vectors: red toward \
        +x (right), green toward 120 degrees, blue toward 240 degrees (grey = calm).",
    after_help = "Examples:\n  \
        cellsurf cursor --out brownian.png                       # calm air, 11,520,000 steps\n  \
        cellsurf cursor --wind-field uniform --wind-angle 30 --json\n  \
        cellsurf cursor --wind-field rotating --k 0.5 --out star.png\n  \
        cellsurf cursor --wind-field bimodal --save-wind w.png && cellsurf cursor --wind-image w.png\n  \
        cellsurf cursor --wind-image my_winds.png --wind-scale 0.86 --sea-quantile 0.8 --out m.png"
)]
pub struct Args {
    /// Start from this scenario file (TOML, `model = "cursor"`); options typed here override it.
    #[arg(long, value_name = "FILE.toml")]
    scenario: Option<PathBuf>,
    /// Steps of the walk (particles; 1 to 10^12, `1e7` accepted). The article's runs use
    /// 11,520,000.
    #[arg(long, value_name = "N", value_parser = conv::count_in::<u64>(cellsurf::cursor::STEPS), default_value_t = ARTICLE_STEPS)]
    steps: u64,
    /// Force constant k, 0 to 1 (k = 0: Brownian whatever the wind).
    #[arg(long, default_value_t = DEFAULT_K, allow_negative_numbers = true)]
    k: f64,
    /// Wind field from a PNG image, one pixel per cell (8-bit RGB, RGBA, grey or palette;
    /// image row 0 is the top row of the grid). Its size sets the grid unless --size is given,
    /// which it must then match.
    #[arg(
        long,
        value_name = "FILE.png",
        alias = "wind",
        conflicts_with = "wind_field"
    )]
    wind_image: Option<PathBuf>,
    /// Multiply the wind image's winds by this factor (0.86 = 220/255 admits every colour).
    #[arg(
        long,
        value_name = "F",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    wind_scale: f64,
    /// Built-in wind field [default: calm, unless --wind-image is given].
    #[arg(long, value_name = "NAME", value_enum)]
    wind_field: Option<Generator>,
    /// Generator: direction the wind (uniform, bimodal bands, converging drift) blows toward,
    /// or of one star arm (rotating), degrees counter-clockwise from +x [default: 30 (uniform),
    /// 60 (bimodal), 0 (converging, rotating)].
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    wind_angle: Option<f64>,
    /// Generator: wind speed, article units 0 to 220 (the drift for converging) [default: 220
    /// (uniform, bimodal), 50 (converging), 60 (rotating)].
    #[arg(long, value_name = "SPEED", allow_negative_numbers = true)]
    wind_speed: Option<f64>,
    /// Bimodal: angle between the two winds, degrees, 0 to 180 (180 = exactly opposite)
    /// [default: 150].
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    wind_spread: Option<f64>,
    /// Bimodal: distance between ridges; converging: between centres along x; rotating:
    /// between nodes. Cells, at least 4 [default: 40 (bimodal), 80 (converging), 60 (rotating)].
    #[arg(long, value_name = "CELLS", allow_negative_numbers = true)]
    wind_wavelength: Option<f64>,
    /// Converging: distance between centres along y, cells, at least 4 [default: 120].
    #[arg(long, value_name = "CELLS", allow_negative_numbers = true)]
    wind_spacing: Option<f64>,
    /// Converging: largest radial wind around each centre, article units (> 0 outward,
    /// < 0 inward; speed + |radial| at most 220) [default: 160].
    #[arg(long, value_name = "SPEED", allow_negative_numbers = true)]
    wind_radial: Option<f64>,
    /// Converging: radius of the radial wind, cells (1 to half the smaller distance between
    /// centres) [default: 25].
    #[arg(long, value_name = "CELLS", allow_negative_numbers = true)]
    wind_radius: Option<f64>,
    /// Rotating: arms of each star, 0 to 12 (0: round mounds) [default: 4].
    #[arg(long, value_name = "N", value_parser = conv::count_in::<u32>(cellsurf::cursor::wind::ARMS))]
    wind_arms: Option<u32>,
    /// Grid size in cells, W or WxH, each side 3 or more [default: 240x240 (the article
    /// does not give its grid), or the wind image's size].
    #[arg(long, value_name = "W[xH]", value_parser = conv::size_in(cellsurf::cursor::SIZE_SIDES))]
    size: Option<Size>,
    /// Seed of the random stream, 0 to 2^63 - 1 (the same seed gives the same output).
    #[arg(long, default_value_t = 1, value_parser = conv::parse_seed)]
    seed: u64,
    /// Sea level for --out, in visits: cells lower than this are drawn as water
    /// [default: half the mean height, 100 for the article's steps on 240x240 cells].
    #[arg(
        long,
        value_name = "HEIGHT",
        allow_negative_numbers = true,
        conflicts_with_all = ["sea_fraction", "sea_quantile"]
    )]
    sea_level: Option<f64>,
    /// Sea level as a fraction of the mean height [default: 0.5 when no other sea level is given].
    #[arg(
        long,
        value_name = "F",
        allow_negative_numbers = true,
        conflicts_with = "sea_quantile"
    )]
    sea_fraction: Option<f64>,
    /// Sea level as a quantile of the heights: this fraction of the cells is flooded (0 to 1).
    #[arg(long, value_name = "Q", allow_negative_numbers = true)]
    sea_quantile: Option<f64>,
    /// Output file: .png, the landscape (flooded below the sea level) next to the wind field.
    #[arg(long, value_name = "FILE")]
    out: Vec<PathBuf>,
    /// Write the wind field as a PNG in the article's colour encoding (readable by
    /// --wind-image).
    #[arg(long, value_name = "FILE.png")]
    save_wind: Option<PathBuf>,
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

/// Steps between progress updates.
const CHUNK: u64 = 1 << 20;

/// The generator options given.
fn wind_options(a: &Args) -> WindOptions {
    WindOptions {
        angle: a.wind_angle,
        speed: a.wind_speed,
        spread: a.wind_spread,
        wavelength: a.wind_wavelength,
        spacing: a.wind_spacing,
        radial: a.wind_radial,
        radius: a.wind_radius,
        arms: a.wind_arms,
    }
}

/// The flag of a generator option (`--wind-angle` for `wind_angle`).
fn flag(name: &str) -> String {
    format!("--{}", name.replace('_', "-"))
}

/// An option as the run was given it: its flag as typed, else its key in the scenario file
/// (`wind_spread (the scenario's)`).
fn given_as(name: &str) -> String {
    match conv::typed_flag(name).filter(|_| conv::typed(name)) {
        Some(f) => f,
        None => format!("{name} (the scenario's)"),
    }
}

/// The generator from the options: the article's settings ([`WindSpec::article`]) with each
/// given option applied; an option the generator does not take is an error.
fn spec(g: Generator, a: &Args) -> Result<WindSpec> {
    let s = WindSpec::article(g.name()).context("unknown generator")?;
    let s = s.with_options(&wind_options(a)).map_err(|bad| {
        let takes: Vec<String> = s.options().iter().map(|t| flag(t)).collect();
        anyhow::anyhow!(
            "{} does not apply to --wind-field {}: it takes {}",
            given_as(bad),
            g.name(),
            if takes.is_empty() {
                "no options".to_string()
            } else {
                takes.join(", ")
            }
        )
    })?;
    s.validate().map_err(|e| {
        anyhow::anyhow!(
            "in --wind-field {}: {}",
            g.name(),
            flagged(&e.to_string(), a)
        )
    })?;
    Ok(s)
}

/// The field's error `wind NAME = V is out of range: ...` said with the flag that sets it,
/// `--wind-NAME = V`, and `(the scenario's)` or `(the default)` after a value not typed.
fn flagged(msg: &str, a: &Args) -> String {
    // (whether the run's arguments hold the value: typed, or from the scenario file)
    let held = |name: &str| match name {
        "angle" => a.wind_angle.is_some(),
        "arms" => a.wind_arms.is_some(),
        "radial" => a.wind_radial.is_some(),
        "radius" => a.wind_radius.is_some(),
        "scale" => conv::set_by_scenario("wind_scale", &a.wind_scale.to_string()),
        "spacing" => a.wind_spacing.is_some(),
        "speed" => a.wind_speed.is_some(),
        "spread" => a.wind_spread.is_some(),
        "wavelength" => a.wind_wavelength.is_some(),
        _ => false,
    };
    const NAMES: [&str; 9] = [
        "angle",
        "arms",
        "radial",
        "radius",
        "scale",
        "spacing",
        "speed",
        "spread",
        "wavelength",
    ];
    for name in NAMES {
        if let Some(rest) = msg.strip_prefix(&format!("wind {name} = ")) {
            let default = if conv::typed(&format!("wind_{name}")) {
                ""
            } else if held(name) {
                " (the scenario's)"
            } else {
                " (the default)"
            };
            return match rest.split_once(" is ") {
                Some((v, tail)) => format!("--wind-{name} = {v}{default} is {tail}"),
                None => format!("--wind-{name} = {rest}"),
            };
        }
    }
    msg.to_string()
}

/// Where the wind came from, for the summary.
enum Source {
    Image(PathBuf),
    Generator(WindSpec),
}

/// Runs `cellsurf cursor`.
pub fn run(a: Args) -> Result<()> {
    conv::set_quiet(a.quiet);
    let scenario = a.scenario.clone();
    let a = conv::merge_scenario(a, scenario.as_deref(), "cursor")?;
    // A scenario file and the command line together may give what the command line alone
    // refuses: two sources of wind, or two sea levels.
    if a.wind_image.is_some() && a.wind_field.is_some() {
        bail!(
            "{} and {} are both given: the wind comes from one of them; remove the other",
            given_as("wind_image"),
            given_as("wind_field")
        );
    }
    let seas = [
        a.sea_level.map(|_| "sea_level"),
        a.sea_fraction.map(|_| "sea_fraction"),
        a.sea_quantile.map(|_| "sea_quantile"),
    ];
    let seas: Vec<String> = seas.into_iter().flatten().map(given_as).collect();
    if seas.len() > 1 {
        bail!(
            "{} are given together: the sea level is set by one of them; remove the others",
            seas.join(", ")
        );
    }
    let outs = Outputs::new(&a.out, "cursor", &[Format::Png])?;
    if let Some(p) = &a.save_wind {
        if Format::of(p) != Some(Format::Png) {
            bail!(
                "--save-wind {}: the wind field is saved as a PNG image, so the file name must \
                 end in .png",
                p.display()
            );
        }
        outs.check_distinct("--save-wind", p)?;
        cellsurf::engine::io::check_output("--save-wind", p)?;
    }
    let size = a.size.map(|s| (s.w, s.h));
    if !cellsurf::cursor::STEPS.contains(a.steps) {
        bail!(
            "steps = {} is out of range: expected {}",
            a.steps,
            cellsurf::cursor::STEPS.expected
        );
    }
    if !(a.k.is_finite() && (0.0..=1.0).contains(&a.k)) {
        bail!(
            "k = {} is out of range: expected a force constant from 0 to 1, so that every probability P_i = 1/8 + k (W . u_i) / 1760 stays between 0 and 1",
            a.k
        );
    }
    let sea = match (a.sea_level, a.sea_fraction, a.sea_quantile) {
        (Some(v), _, _) => SeaLevel::Height(v),
        (_, Some(f), _) => SeaLevel::MeanFraction(f),
        (_, _, Some(q)) => SeaLevel::Quantile(q),
        _ => SeaLevel::default(),
    };
    sea.validate()?;
    if let Some((w, h)) = size {
        check_size(w, h).context("in --size")?;
    }
    let (field, source) = match (&a.wind_image, a.wind_field) {
        (Some(path), _) => {
            if let Some(f) = wind_options(&a).given().first() {
                bail!(
                    "{} applies to --wind-field generators, not to a --wind-image",
                    flag(f)
                );
            }
            let field = WindField::from_png(path, size, a.wind_scale)
                .with_context(|| format!("in --wind-image {}", path.display()))?;
            (field, Source::Image(path.clone()))
        }
        (None, g) => {
            if a.wind_scale != 1.0 {
                bail!(
                    "{} = {} applies to a --wind-image only",
                    given_as("wind_scale"),
                    a.wind_scale
                );
            }
            let g = g.unwrap_or(Generator::Calm);
            let s = spec(g, &a)?;
            let (w, h) = size.unwrap_or(DEFAULT_SIZE);
            let field = s.field(w, h).map_err(|e| match e {
                // (a parameter: named by its flag and where its value came from)
                e @ cellsurf::cursor::CursorError::Parameter { .. } => anyhow::anyhow!(
                    "in --wind-field {}: {}",
                    g.name(),
                    flagged(&e.to_string(), &a)
                ),
                e => anyhow::Error::new(e).context(format!("in --wind-field {}", g.name())),
            })?;
            // the pattern fits the torus: a distance or direction given (typed or by the
            // scenario) that it changes is said, whatever --quiet says
            let mut parts = Vec::new();
            let mut angle_changed = false;
            for (name, asked, used) in s.fitted(w, h) {
                let (option, axis) = match name.split_once(' ') {
                    Some((o, _)) => (o, " along y"),
                    None => (name, ""),
                };
                let given = match option {
                    "wind_wavelength" => a.wind_wavelength.is_some(),
                    "wind_spacing" => a.wind_spacing.is_some(),
                    "wind_angle" => a.wind_angle.is_some(),
                    _ => true,
                };
                if !given {
                    continue;
                }
                let asked_as = match conv::typed_flag(option).filter(|_| conv::typed(option)) {
                    Some(flag) => format!("{flag} = {asked}"),
                    None => format!("the scenario's {option} = {asked}"),
                };
                let along_x = if matches!(g, Generator::Bimodal) || !axis.is_empty() {
                    axis
                } else if option == "wind_spacing" {
                    " along y"
                } else {
                    " along x"
                };
                parts.push(if option == "wind_angle" {
                    angle_changed = true;
                    format!(
                        "its bands run at {used:.4} deg ({asked_as}; the winds' resultant stays at {asked} deg)"
                    )
                } else {
                    format!("{used:.4} cells apart{along_x} ({asked_as})")
                });
            }
            if !parts.is_empty() {
                conv::changed(format_args!(
                    "warning: --wind-field {} repeats a whole number of times across the {w} x {h} torus: {}{}",
                    g.name(),
                    parts.join(", "),
                    if angle_changed {
                        ""
                    } else {
                        " (a --size that holds whole periods of it keeps them)"
                    }
                ));
            }
            (field, Source::Generator(s))
        }
    };
    let (w, h) = (field.width(), field.height());
    // (printed once every option is checked: a printed scenario is one that runs)
    if a.print_scenario {
        out!("{}", conv::scenario_text(&a, "cursor")?)?;
        return Ok(());
    }
    // Every picture (the landscape, the saved wind) records the run's parameters.
    cellsurf::plot::set_png_parameters(Some(conv::scenario_text(&a, "cursor")?));
    if let Some(p) = &a.save_wind {
        let bytes = field.to_png_bytes()?;
        write_atomic(p, &bytes).with_context(|| format!("writing --save-wind {}", p.display()))?;
        conv::wrote(p);
    }
    let setup = Instant::now();
    let tr = Transitions::new(&field, a.k)?;
    let setup_s = setup.elapsed().as_secs_f64();

    let silent = a.quiet || a.json;
    conv::begin();
    let bar = ProgressBar::with_draw_target(Some(a.steps), ProgressDrawTarget::hidden());
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{bar:40}] {percent}% ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(format!("cursor {w}x{h}"));
    let start = Instant::now();
    let mut walk = CursorWalk::new(&tr, a.seed);
    let mut shown = false;
    while walk.steps() < a.steps {
        walk.run(CHUNK.min(a.steps - walk.steps()));
        if !silent && !shown && start.elapsed().as_secs_f64() > 1.0 {
            bar.set_draw_target(ProgressDrawTarget::stderr());
            shown = true;
        }
        bar.set_position(walk.steps());
    }
    let elapsed = start.elapsed().as_secs_f64();
    bar.finish_and_clear();

    let heights = walk.heights();
    let total = walk.height_total();
    if total != walk.steps() {
        bail!(
            "internal error: heights sum to {total}, not to the {} steps",
            walk.steps()
        );
    }
    let doubly = tr.is_doubly_stochastic();
    let density_error = if doubly {
        stats::density_error(heights)
    } else {
        None
    };
    let noise = NoiseModel::for_transitions(&tr);
    let expected_error = noise.as_ref().map(|m| m.expected_error(walk.steps()));
    let (dx, dy) = walk.displacement();
    let n = walk.steps() as f64;
    let drift = (dx as f64 / n, dy as f64 / n);
    let drift_expected = tr
        .is_translation_invariant()
        .then(|| stats::mean_step(&tr.cell_probabilities(0)));
    let level = sea.resolve(heights);
    let flooded = display::flooded_fraction(heights, level);
    // (cells of one height are all flooded or none: ties can keep the fraction from the
    // quantile; said beyond a percentage point)
    if let SeaLevel::Quantile(q) = sea
        && (flooded - q).abs() > (0.5 / heights.len() as f64).max(0.01)
    {
        conv::changed(format_args!(
            "warning: {} = {q} floods {:.1} % of the cells, not {:.1} %: cells of the same height are flooded together, and no sea level floods that fraction here",
            conv::typed_flag("sea_quantile").unwrap_or_else(|| "--sea-quantile".into()),
            100.0 * flooded,
            100.0 * q
        ));
    }
    let max_h = heights.iter().copied().max().unwrap_or(0);
    let min_h = heights.iter().copied().min().unwrap_or(0);
    let mean_h = total as f64 / heights.len() as f64;
    let wind_text = match &source {
        Source::Image(p) => format!("wind image {} (scale {})", p.display(), a.wind_scale),
        Source::Generator(s) => format!("{} wind", s.name()),
    };
    let describe = format!(
        "{wind_text}, {w}x{h} torus, k = {}, {} steps, seed {}",
        a.k,
        walk.steps(),
        a.seed
    );

    if let Some(p) = outs.get(Format::Png) {
        let caption = format!(
            "{describe}\nsea level {level:.1} visits ({}); cellsurf {VERSION}",
            sea_words(&sea)
        );
        draw_landscape(
            p,
            "Wind-field cursor walk: heights = visits",
            &caption,
            &field,
            heights,
            level,
        )
        .with_context(|| format!("writing --out {}", p.display()))?;
        conv::wrote(p);
    }

    let wind_json = match &source {
        Source::Image(p) => serde_json::json!({
            "image": p.display().to_string(),
            "scale": a.wind_scale,
        }),
        Source::Generator(s) => serde_json::to_value(s)?,
    };
    // Output errors (a closed pipe) are reported, not panicked on.
    let mut out = std::io::stdout().lock();
    if a.json {
        let own = serde_json::json!({
            "steps": walk.steps(),
            "setup_s": setup_s,
            "steps_per_s": n / elapsed.max(1e-12),
            "height_total": total,
            "density_error": density_error,
            "density_error_expected": expected_error,
            "density_reference": if doubly { serde_json::json!("uniform") } else { serde_json::Value::Null },
            "drift_per_step": [drift.0, drift.1],
            "drift_expected": drift_expected.map(|d| [d.0, d.1]),
            "min_height": min_h,
            "max_height": max_h,
            "mean_height": mean_h,
            "sea_level": level,
            "flooded_fraction": flooded,
            "final_position": [walk.position().0, walk.position().1],
            "max_wind": field.max_speed(),
            "run": {
                "width": w,
                "height": h,
                "wind": wind_json,
                "sea": sea,
                "start": [w / 2, h / 2],
            },
        });
        let v = conv::envelope("cursor", conv::scenario_table(&a)?, elapsed, own)?;
        writeln!(out, "{}", serde_json::to_string(&v)?)?;
    } else {
        let lines = [
            format!("cellsurf {VERSION} cursor: {describe}"),
            format!(
                "  {} steps in {elapsed:.3} s ({:.1} M steps/s; tables {setup_s:.3} s); heights sum to {total}",
                walk.steps(),
                n / elapsed.max(1e-12) / 1e6
            ),
            format!(
                "  heights: min {min_h}, mean {mean_h:.1}, max {max_h}; sea level {level:.1} ({}), {:.1}% flooded",
                sea_words(&sea),
                100.0 * flooded
            ),
            match (density_error, expected_error) {
                (Some(e), Some(x)) => format!(
                    "  density error {e:.4} (relative RMS deviation from uniform; {x:.4} expected from noise alone)"
                ),
                (Some(e), None) => {
                    format!("  density error {e:.4} (relative RMS deviation from uniform)")
                }
                _ => "  density error: not defined (this wind field's long-run density is not uniform)"
                    .to_string(),
            },
            match drift_expected {
                Some(d) => format!(
                    "  drift per step ({:.4}, {:.4}) cells, expected ({:.4}, {:.4})",
                    drift.0, drift.1, d.0, d.1
                ),
                None => format!("  drift per step ({:.4}, {:.4}) cells", drift.0, drift.1),
            },
        ];
        writeln!(out, "{}", lines.join("\n"))?;
    }
    Ok(())
}

fn sea_words(sea: &SeaLevel) -> String {
    match *sea {
        SeaLevel::Height(v) => format!("--sea-level {v}"),
        SeaLevel::MeanFraction(f) => format!("{f} x the mean height"),
        SeaLevel::Quantile(q) => format!("lowest {:.0}% of the cells", 100.0 * q),
    }
}
