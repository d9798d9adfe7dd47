//! `cellsurf wind-ripples`: the particle model of the wind-ripple notebook
//! ([`cellsurf::windripples`]), with a progress bar, a picture, a `.npy` dump and a JSON summary.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use cellsurf::engine::io::write_atomic;
use cellsurf::windripples::{self, Schedule, WindParams, WindRun};

use super::conv::{self, Format, Outputs, Size};
use cellsurf::engine::count::CountRange;

/// `--threads`: worker threads, 0 for all cores.
const THREADS: CountRange = CountRange::new(0, 4096, "0 (all cores) to 4096");

/// Options of `cellsurf wind-ripples` (defaults: the notebook's `Params()`).
#[derive(clap::Args, serde::Serialize, serde::Deserialize)]
#[command(
    long_about = "Wind ripples: the particle model of the wind-ripple notebook.\n\n\
        N particles on the unit torus; each step: diffusion x, y += sigma N(0,1) with \
        sigma = D/sqrt(step+1) (--schedule annealed, the notebook's numpy code) or D (constant, \
        its torch code); wrap to [0,1); height h = 2-D histogram of bins x bins cells with \
        density normalisation (mean 1); saltation y += L sigmoid(-kappa h(cell)).\n\n\
        Examples:\n  cellsurf wind-ripples --out ripples.png\n  \
        cellsurf wind-ripples --steps 128 --json\n  \
        cellsurf wind-ripples --schedule constant --kappa 0 --out h.npy --threads 1"
)]
pub struct Args {
    /// Start from this scenario file (TOML, `model = "wind-ripples"`); options typed here
    /// override it.
    #[arg(long, value_name = "FILE.toml")]
    scenario: Option<PathBuf>,
    /// Steps of the loop (notebook N_step), 1 to 1e9 (`1e3` accepted).
    #[arg(long, value_name = "N", value_parser = conv::count_in::<u64>(windripples::params::STEPS), default_value_t = WindParams::default().steps)]
    steps: u64,
    /// Number of particles N (notebook N_particles = 2**16 * 8), 1 to 2^30; 24 bytes of memory
    /// each (48 while they are re-sorted).
    #[arg(long, default_value_t = WindParams::default().particles, value_parser = conv::count_in::<usize>(windripples::params::PARTICLES))]
    particles: usize,
    /// Histogram size in cells, N or NxN (square, N from 1 to 4096).
    #[arg(long, value_name = "N", alias = "bins", default_value_t = Size::square(WindParams::default().bins), value_parser = conv::size_in(windripples::params::SIZE_SIDES))]
    size: Size,
    /// Saltation sensitivity kappa >= 0 (hop = L sigmoid(-kappa h), h has mean 1).
    #[arg(long, default_value_t = WindParams::default().kappa, allow_negative_numbers = true, value_parser = parse_number)]
    #[serde(deserialize_with = "number_or_fraction")]
    kappa: f64,
    /// Saltation hop L along the wind y, in torus sides (0.015625 = 1/64; fractions such as 1/64
    /// are accepted; L >= 1 wraps around).
    #[arg(long, default_value_t = WindParams::default().hop, allow_negative_numbers = true, value_parser = parse_number)]
    #[serde(deserialize_with = "number_or_fraction")]
    hop: f64,
    /// Diffusion D, in torus sides per step (standard deviation per axis of the first step).
    #[arg(long, default_value_t = WindParams::default().diffusion, allow_negative_numbers = true, value_parser = parse_number)]
    #[serde(deserialize_with = "number_or_fraction")]
    diffusion: f64,
    /// Diffusion schedule: annealed (D/sqrt(step+1), the notebook's numpy code) or constant (D,
    /// its torch code).
    #[arg(long, default_value_t = Schedule::Annealed)]
    schedule: Schedule,
    /// Seed of the random streams, 0 to 2^63 - 1 (the same seed gives the same output,
    /// whatever --threads).
    #[arg(long, default_value_t = WindParams::default().seed, value_parser = conv::parse_seed)]
    seed: u64,
    /// Worker threads; 0 = all cores. The results do not depend on it.
    #[arg(long, default_value_t = 0, value_parser = conv::count_in::<usize>(THREADS))]
    threads: usize,
    /// Output file, repeatable; the extension picks the format: .png (a picture of the final
    /// height field), .npy (the final height field, N x N float64, index [ix, iy] as the
    /// notebook's height; parameters in the sidecar NAME.json).
    #[arg(long, value_name = "FILE")]
    out: Vec<PathBuf>,
    /// Old spelling of `--out FILE.npy` (kept for one release).
    #[arg(long, value_name = "FILE.npy", hide = true)]
    npy: Option<PathBuf>,
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

/// A number, or a fraction `a/b` of two numbers (e.g. `1/64`).
fn parse_number(s: &str) -> Result<f64, String> {
    let bad = || format!("'{s}' is not a number (e.g. 4.5, 8e-4 or 1/64)");
    let v = match s.split_once('/') {
        Some((a, b)) => {
            let a: f64 = a.trim().parse().map_err(|_| bad())?;
            let b: f64 = b.trim().parse().map_err(|_| bad())?;
            a / b
        }
        None => s.trim().parse().map_err(|_| bad())?,
    };
    Ok(v)
}

/// A scenario file's number, or a fraction in a string (`hop = "1/64"`), read as the option
/// reads it on the command line ([`parse_number`]).
fn number_or_fraction<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    #[derive(serde::Deserialize)]
    #[serde(untagged)]
    enum Given {
        Number(f64),
        Whole(i64),
        Text(String),
    }
    match serde::Deserialize::deserialize(d)? {
        Given::Number(v) => Ok(v),
        Given::Whole(v) => Ok(v as f64),
        Given::Text(t) => parse_number(&t).map_err(serde::de::Error::custom),
    }
}

/// The summary printed by `--json` and written next to a `.npy` output.
fn summary(a: &Args, r: &WindRun, threads: usize) -> Result<serde_json::Value> {
    let p = &r.params;
    let s = &r.stats;
    let own = serde_json::json!({
        "steps": p.steps,
        "particles": p.particles,
        "bins": p.bins,
        "setup_s": r.setup_s,
        "particle_steps_per_s": p.steps as f64 * p.particles as f64 / r.elapsed_s.max(1e-12),
        "height_mean": s.height_mean,
        "height_std": s.height_std,
        "wavelength_bins": s.wavelength_bins,
        "mean_wavelength_bins": s.mean_wavelength_bins,
        "threads": threads,
        "run": p,
    });
    conv::envelope("wind-ripples", conv::scenario_table(a)?, r.elapsed_s, own)
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<()> {
    conv::synonyms(&[("bins", "size")]);
    conv::set_quiet(a.quiet);
    let scenario = a.scenario.clone();
    let a = conv::merge_scenario(a, scenario.as_deref(), "wind-ripples")?;
    let params = WindParams {
        bins: a.size.side()?,
        particles: a.particles,
        steps: a.steps,
        hop: a.hop,
        kappa: a.kappa,
        diffusion: a.diffusion,
        schedule: a.schedule,
        seed: a.seed,
    };
    params
        .validate()
        .context("invalid wind-ripples parameters")?;
    // (a printed scenario is one that runs)
    if a.print_scenario {
        out!("{}", conv::scenario_text(&a, "wind-ripples")?)?;
        return Ok(());
    }
    // 48 bytes per particle while they are re-sorted, and the histogram.
    conv::check_memory(
        &format!("--particles {}", params.particles),
        params.particles as f64 * 48.0 + (params.bins as f64).powi(2) * 16.0,
    )?;
    let mut outs = Outputs::new(&a.out, "wind-ripples", &[Format::Png, Format::Npy])?;
    outs.add_legacy(Format::Npy, a.npy.as_ref())?;
    if !THREADS.contains(a.threads as u64) {
        bail!(
            "--threads = {} is out of range: expected {}",
            a.threads,
            THREADS.expected
        );
    }
    let flag = conv::typed_flag("out").unwrap_or_else(|| "--out".into());
    // the .npy's sidecar NAME.json is an output too: checked with it, before the run
    if let Some(p) = outs.get(Format::Npy) {
        cellsurf::engine::io::check_output(
            &format!("{flag} (the sidecar of the .npy)"),
            &p.with_extension("json"),
        )?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads)
        .build()
        .context("cannot start the worker threads")?;
    let threads = pool.current_num_threads();

    conv::begin();
    let bar = ProgressBar::with_draw_target(Some(params.steps), ProgressDrawTarget::hidden());
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{bar:40}] {pos}/{len} steps ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(format!(
        "wind ripples N={} {}x{}",
        params.particles, params.bins, params.bins
    ));
    let silent = a.quiet || a.json;
    let start = Instant::now();
    let mut shown = false;
    let r = pool.install(|| {
        windripples::run(&params, |done| {
            if !silent && !shown && start.elapsed().as_secs_f64() > 1.0 {
                bar.set_draw_target(ProgressDrawTarget::stderr());
                shown = true;
            }
            bar.set_position(done);
        })
    })?;
    bar.finish_and_clear();

    if let Some(p) = outs.get(Format::Png) {
        // the run's scenario: fed back to --scenario it makes the same picture
        cellsurf::plot::set_png_parameters(Some(conv::scenario_text(&a, "wind-ripples")?));
        windripples::figures::draw_height(p, &r)
            .with_context(|| format!("writing {flag} {}", p.display()))?;
        conv::wrote(p);
    }
    if let Some(p) = outs.get(Format::Npy) {
        let bytes = windripples::npy_bytes(&r.height, &[params.bins, params.bins]);
        write_atomic(p, &bytes).with_context(|| format!("writing {flag} {}", p.display()))?;
        conv::wrote(p);
        let mut side = summary(&a, &r, threads)?;
        if let Some(o) = side.as_object_mut() {
            // The file records what the run made, not how fast: the same seed gives the same
            // bytes on every machine and thread count (timings and threads are in --json).
            for k in ["elapsed_s", "setup_s", "particle_steps_per_s", "threads"] {
                o.remove(k);
            }
            // (a scenario file: fed back to --scenario it makes the same bytes)
            o.insert(
                "parameters_toml".into(),
                conv::scenario_text(&a, "wind-ripples")?.into(),
            );
            o.insert(
                "layout".into(),
                serde_json::json!(
                    "float64 C-order [ix, iy]: x (across the wind) first, y (the wind) second; \
                     h = count * bins^2 / N, the histogram of the last step"
                ),
            );
            let file = p.file_name().unwrap_or_default().to_string_lossy();
            o.insert(
                "fields".into(),
                serde_json::json!({ "height": {
                    "file": file,
                    "dims": ["x", "y"],
                    "shape": [params.bins, params.bins],
                    "units": "1",
                    "long_name": "sand height: particles per bin over the mean (mean 1)",
                }}),
            );
        }
        let side_path = p.with_extension("json");
        write_atomic(
            &side_path,
            format!("{}\n", serde_json::to_string_pretty(&side)?).as_bytes(),
        )
        .with_context(|| format!("writing {}", side_path.display()))?;
        conv::wrote(&side_path);
    }
    if a.json {
        outln!("{}", serde_json::to_string(&summary(&a, &r, threads)?)?)?;
    } else {
        let s = &r.stats;
        let f = |v: Option<f64>| v.map_or("n/a".to_string(), |v| format!("{v:.3} bins"));
        outln!("wind ripples: {}", windripples::figures::describe(&params))?;
        outln!(
            "  {} steps ({} schedule) in {:.3} s on {threads} threads (set-up {:.3} s), {:.3e} particle-steps/s",
            params.steps,
            params.schedule,
            r.elapsed_s,
            r.setup_s,
            params.steps as f64 * params.particles as f64 / r.elapsed_s.max(1e-12)
        )?;
        outln!(
            "  height mean {:.6}, std {:.4}; dominant wavelength {}, mean wavelength {}",
            s.height_mean,
            s.height_std,
            f(s.wavelength_bins),
            f(s.mean_wavelength_bins)
        )?;
    }
    Ok(())
}
