//! The growth paper's figures, regenerated (feature `plot`).
//!
//! [`FIGURES`] lists them in the paper's order (Figs. 3-7, with companion charts, and the
//! error against run time); each runs its scenario (the TOML files in `scenarios/`, embedded
//! here, so that the same name is used in source, scenario, test and figure file) and
//! records that scenario in every PNG it writes. [`scenario`] returns a figure's
//! configuration.

use std::path::{Path, PathBuf};

use super::converge::{self, ConvergeCurve};
use super::sampler::SamplerKind;
use super::scene::{
    self, NoHooks, Observables, RunResult, SceneConfig, SceneError, Snapshot, StopReason,
};
use crate::engine::VERSION;
use crate::plot::{self, CellField, Chart, Figure, FigureError, Palette, Panel, PlotError, Series};

impl From<SceneError> for FigureError {
    fn from(e: SceneError) -> Self {
        FigureError::Source(Box::new(e))
    }
}

/// The scenario files, by figure name.
pub const SCENARIOS: &[(&str, &str)] = crate::plot::scenario_files![
    "growth_fig3_ca",
    "growth_fig4_ca_axes",
    "growth_fig5_flame",
    "growth_fig6_deposit",
    "growth_fig7_crystal",
];

/// The configuration of a figure's scenario.
pub fn scenario(name: &str) -> Result<SceneConfig, FigureError> {
    let text = SCENARIOS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| *t)
        .ok_or_else(|| FigureError::Unknown(name.to_string()))?;
    Ok(SceneConfig::from_toml(text)?)
}

/// The configuration of a figure's scenario, recorded in every PNG the figure writes from
/// now on ([`recorded`]).
fn load(name: &str) -> Result<SceneConfig, FigureError> {
    let cfg = scenario(name)?;
    if let Some((_, text)) = SCENARIOS.iter().find(|(n, _)| *n == name) {
        plot::set_png_parameters(Some(recorded(text)));
    }
    Ok(cfg)
}

/// A scenario file as a PNG records it: without its `# Run:` line, the command that runs the
/// file (the run's parameters are the rest).
pub fn recorded(text: &str) -> String {
    text.split_inclusive('\n')
        .filter(|l| !l.starts_with("# Run: "))
        .collect()
}

/// The growth paper's figures, in the paper's order.
pub const FIGURES: &[Figure] = &[
    Figure {
        name: "growth_fig3_ca",
        about: "Fig. 3: deterministic CA, growth on all free edges (square lattice)",
        make: |d| ca_figure(d, "growth_fig3_ca", "Fig. 3: CA growth on all free edges"),
    },
    Figure {
        name: "growth_fig4_ca_axes",
        about: "Fig. 4: deterministic CA, growth along the coordinate axes",
        make: |d| {
            ca_figure(
                d,
                "growth_fig4_ca_axes",
                "Fig. 4: CA growth along the axes (b >= 1, then b >= 2)",
            )
        },
    },
    Figure {
        name: "growth_fig5_flame",
        about: "Fig. 5: flame front from a square, and its roundness against time",
        make: flame_figure,
    },
    Figure {
        name: "growth_fig6_deposit",
        about: "Fig. 6: deposition on a cosine trough, and its mode-1 amplitude and mean elevation",
        make: deposit_figure,
    },
    Figure {
        name: "growth_fig7_crystal",
        about: "Fig. 7: anisotropic crystal (Eq. 5), and its axis/diagonal extent ratio",
        make: crystal_figure,
    },
    Figure {
        name: "growth_error_vs_time",
        about: "Standard error of each scene's observable against run time, both samplers",
        make: error_figure,
    },
    Figure {
        name: "growth_kpz_roughness",
        about: "Beyond the paper: kinetic roughening on a flat substrate, interface width against time (beta) and saturated width against substrate width (alpha), against KPZ",
        make: kpz_figure,
    },
];

/// Seeds averaged in the time-series charts.
const CHART_SEEDS: u64 = 24;

/// A panel's title: the timestep, whole while it is exact (at most 2^53), else rounded, else
/// (past the largest `f64`) as a power of ten.
fn clock_label(time: f64, log10_time: f64) -> String {
    if time <= 9_007_199_254_740_992.0 {
        format!("t = {time}")
    } else if time.is_finite() {
        format!("t = {time:.4e}")
    } else {
        format!("t = 10^{log10_time:.4}")
    }
}

/// A snapshot's title: its clock, and for the final state drawn in place of requested times
/// the run did not reach, why it stopped and the first of them (`t = 169: lattice full
/// before t = 500`).
pub fn snapshot_title(s: &Snapshot, stop: StopReason) -> String {
    let clock = clock_label(s.time, s.log10_time);
    match s.unreached.first() {
        Some(t) => format!("{clock}: {} before t = {t}", stop.describe()),
        None => clock,
    }
}

/// The snapshots of a run as panels.
pub fn snapshot_panels(r: &RunResult) -> Vec<Panel> {
    let c = &r.config;
    r.snapshots
        .iter()
        .map(|s| Panel {
            title: snapshot_title(s, r.stop),
            field: CellField {
                nx: c.width,
                ny: c.height,
                hex: c.lattice.is_hex(),
                states: s.states.clone(),
            },
        })
        .collect()
}

/// A one-line description of a configuration, for figure titles.
pub fn describe(c: &SceneConfig) -> String {
    format!(
        "{} {}x{} {}, n={}, {}, seed {}, v{VERSION}",
        c.lattice, c.width, c.height, c.boundary, c.n, c.sampler, c.seed
    )
}

/// Writes the snapshot panels of a run.
pub fn draw_snapshots(
    path: &Path,
    title: &str,
    r: &RunResult,
    palette: &Palette,
) -> Result<(), PlotError> {
    let panels = snapshot_panels(r);
    let c = &r.config;
    let tall =
        (c.height as f64) * if c.lattice.is_hex() { 0.866 } else { 1.0 } > c.width as f64 * 1.5;
    let cols = if panels.len() == 4 && !tall {
        2
    } else {
        panels.len().clamp(1, 4)
    };
    plot::lattice_panels(path, title, &panels, cols, palette, 420)
}

fn ca_figure(dir: &Path, name: &str, title: &str) -> Result<Vec<PathBuf>, FigureError> {
    let cfg = load(name)?;
    let r = scene::run(&cfg, &mut NoHooks)?;
    let path = dir.join(format!("{name}.png"));
    let panels = snapshot_panels(&r);
    plot::lattice_panels(
        &path,
        &format!("{title} (cellsurf {VERSION})"),
        &panels,
        4,
        &Palette::default(),
        220,
    )?;
    Ok(vec![path])
}

/// Runs `cfg` over `CHART_SEEDS` seeds with the given sampler and returns the mean of an
/// observable at each series time.
fn mean_series(
    cfg: &SceneConfig,
    sampler: SamplerKind,
    get: fn(&Observables) -> Option<f64>,
) -> Result<Series, FigureError> {
    let mut sum: Vec<f64> = Vec::new();
    let mut times: Vec<f64> = Vec::new();
    let first = if sampler == SamplerKind::Exact {
        100
    } else {
        200
    };
    for k in 0..CHART_SEEDS {
        let mut c = cfg.clone();
        c.sampler = sampler;
        c.seed = first + k;
        c.snapshots.clear();
        let r = scene::run(&c, &mut NoHooks)?;
        if sum.is_empty() {
            sum = vec![0.0; r.series.len()];
            times = r.series.iter().map(|o| o.time).collect();
        }
        for (s, o) in sum.iter_mut().zip(&r.series) {
            *s += get(&o.values).unwrap_or(f64::NAN);
        }
    }
    Ok(Series {
        label: format!("{sampler} sampler, mean of {CHART_SEEDS} seeds"),
        x: times,
        y: sum.iter().map(|s| s / CHART_SEEDS as f64).collect(),
        points: sampler == SamplerKind::Rejection,
    })
}

fn both_samplers(
    cfg: &SceneConfig,
    get: fn(&Observables) -> Option<f64>,
) -> Result<Vec<Series>, FigureError> {
    Ok(vec![
        mean_series(cfg, SamplerKind::Exact, get)?,
        mean_series(cfg, SamplerKind::Rejection, get)?,
    ])
}

fn flat_line(label: &str, x0: f64, x1: f64, y: f64) -> Series {
    Series {
        label: label.to_string(),
        x: vec![x0, x1],
        y: vec![y, y],
        points: false,
    }
}

fn flame_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let cfg = load("growth_fig5_flame")?;
    let r = scene::run(&cfg, &mut NoHooks)?;
    let p1 = dir.join("growth_fig5_flame.png");
    draw_snapshots(
        &p1,
        &format!("Fig. 5 flame: {}", describe(&cfg)),
        &r,
        &Palette::flame(),
    )?;
    let p2 = dir.join("growth_fig5_flame_roundness.png");
    let chart = Chart {
        title: format!("front radius CV; {}", describe(&cfg)),
        x_label: "timestep".into(),
        y_label: "CV of front radius over 36 sectors".into(),
        series: both_samplers(&cfg, |o| o.front_radius_cv)?,
        log_x: false,
        log_y: false,
    };
    plot::line_charts(
        &p2,
        "Fig. 5 flame: the square front becomes round",
        &[chart],
        1,
        (900, 520),
    )?;
    Ok(vec![p1, p2])
}

fn deposit_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let cfg = load("growth_fig6_deposit")?;
    let r = scene::run(&cfg, &mut NoHooks)?;
    let p1 = dir.join("growth_fig6_deposit.png");
    draw_snapshots(
        &p1,
        &format!("Fig. 6 deposition: {}", describe(&cfg)),
        &r,
        &Palette::solid(),
    )?;
    let p2 = dir.join("growth_fig6_deposit_profile.png");
    let charts = [
        Chart {
            title: "First Fourier mode of the surface height".into(),
            x_label: "timestep".into(),
            y_label: "mode-1 amplitude (cell widths)".into(),
            series: both_samplers(&cfg, |o| o.mode1_amplitude)?,
            log_x: false,
            log_y: false,
        },
        Chart {
            title: "Mean elevation".into(),
            x_label: "timestep".into(),
            y_label: "mean surface height (cell widths)".into(),
            series: both_samplers(&cfg, |o| o.mean_elevation)?,
            log_x: false,
            log_y: false,
        },
    ];
    plot::line_charts(
        &p2,
        &format!("Fig. 6 deposition: the trough fills ({})", describe(&cfg)),
        &charts,
        2,
        (640, 480),
    )?;
    Ok(vec![p1, p2])
}

fn crystal_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let cfg = load("growth_fig7_crystal")?;
    let r = scene::run(&cfg, &mut NoHooks)?;
    let p1 = dir.join("growth_fig7_crystal.png");
    draw_snapshots(
        &p1,
        &format!("Fig. 7 crystal: {}", describe(&cfg)),
        &r,
        &Palette::crystal(),
    )?;
    let p2 = dir.join("growth_fig7_crystal_shape.png");
    let mut series = both_samplers(&cfg, |o| o.axis_diagonal_ratio)?;
    let t1 = cfg.steps as f64;
    series.push(flat_line("disc: 1", 0.0, t1, 1.0));
    series.push(flat_line("diamond: sqrt 2", 0.0, t1, 2f64.sqrt()));
    let chart = Chart {
        title: format!("axis / diagonal extent; {}", describe(&cfg)),
        x_label: "timestep".into(),
        y_label: "axis / diagonal support ratio".into(),
        series,
        log_x: false,
        log_y: false,
    };
    plot::line_charts(
        &p2,
        "Fig. 7 crystal (Eq. 5): the disc becomes a diamond",
        &[chart],
        1,
        (900, 520),
    )?;
    Ok(vec![p1, p2])
}

/// Seeds per curve in the error-against-time figure.
pub const CONVERGE_SEEDS: usize = 24;

/// Draws error-against-time curves, one chart per scene case; `seeds` is the most seeds of
/// a point (its title says 2..seeds).
pub fn draw_error_vs_time(
    path: &Path,
    curves: &[ConvergeCurve],
    seeds: usize,
) -> Result<(), PlotError> {
    let mut charts: Vec<Chart> = Vec::new();
    for c in curves {
        let s = Series {
            label: format!("{} sampler", c.sampler),
            x: c.points.iter().map(|p| p.cpu_s).collect(),
            y: c.points.iter().map(|p| p.std_error).collect(),
            points: true,
        };
        match charts.iter_mut().find(|ch| ch.title.starts_with(&c.label)) {
            Some(ch) => ch.series.push(s),
            None => charts.push(Chart {
                title: format!("{}: {}", c.label, c.observable),
                x_label: "cumulative run time (s)".into(),
                y_label: "standard error of the mean".into(),
                series: vec![s],
                log_x: true,
                log_y: true,
            }),
        }
    }
    plot::line_charts(
        path,
        &format!("Error against run time: 2..{seeds} seeds per point (cellsurf {VERSION})"),
        &charts,
        2,
        (600, 420),
    )
}

fn error_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let curves = converge::converge_growth(CONVERGE_SEEDS)?;
    let p = dir.join("growth_error_vs_time.png");
    draw_error_vs_time(&p, &curves, CONVERGE_SEEDS)?;
    Ok(vec![p])
}

/// Kinetic roughening: substrate width, monolayers and seeds of the growth-exponent runs.
const KPZ_WIDTH: usize = 1024;
const KPZ_MONOLAYERS: f64 = 1000.0;
const KPZ_SEEDS: u64 = 8;
/// The growth exponent is fitted from this many monolayers on (the early, intrinsic-width
/// dominated regime left out).
const KPZ_FIT_FROM: f64 = 20.0;
/// Substrate widths of the saturated-width runs, each `6 L^(3/2)` monolayers,
/// [`KPZ_SAT_SEEDS`] seeds.
const KPZ_SAT_WIDTHS: [usize; 4] = [16, 32, 64, 128];
const KPZ_SAT_SEEDS: u64 = 4;

fn kpz_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    use super::roughness::{RoughnessRun, growth_exponent, log_times, roughness_exponent};
    use crate::engine::lattice::Neighbourhood;
    let l = KPZ_WIDTH as f64;
    let times = log_times(l / 4.0, KPZ_MONOLAYERS * l, 28);
    let monolayers: Vec<f64> = times.iter().map(|t| t / l).collect();
    let mut width_series = Vec::new();
    let mut betas = Vec::new();
    for n in [0.0, 2.0] {
        let base = RoughnessRun {
            lattice: Neighbourhood::Hex,
            width: KPZ_WIDTH,
            n,
            monolayers: KPZ_MONOLAYERS,
            seed: 1,
        };
        let (mean, beta, se, _) =
            growth_exponent(&base, &times, KPZ_SEEDS, KPZ_FIT_FROM * l, f64::INFINITY)?;
        width_series.push(Series {
            label: format!("n = {n}: beta = {beta:.3} +- {se:.3}"),
            x: monolayers.clone(),
            y: mean,
            points: true,
        });
        betas.push((n, beta, se));
    }
    // A t^(1/3) guide through the Eden curve's last point.
    let last = width_series[0].y.last().copied().unwrap_or(1.0);
    let t_end = KPZ_MONOLAYERS;
    let guide: Vec<f64> = monolayers
        .iter()
        .map(|&m| last * (m / t_end).powf(1.0 / 3.0))
        .collect();
    width_series.push(Series {
        label: "KPZ slope 1/3".into(),
        x: monolayers.clone(),
        y: guide,
        points: false,
    });
    let base = RoughnessRun {
        lattice: Neighbourhood::Hex,
        width: 16,
        n: 0.0,
        monolayers: 1.0,
        seed: 1,
    };
    let (alpha, pts) = roughness_exponent(&base, &KPZ_SAT_WIDTHS, 6.0, KPZ_SAT_SEEDS)?;
    let alpha = alpha.unwrap_or(f64::NAN);
    let ls: Vec<f64> = pts.iter().map(|p| p.0 as f64).collect();
    let ws: Vec<f64> = pts.iter().map(|p| p.1).collect();
    let w0 = ws.last().copied().unwrap_or(1.0);
    let l0 = ls.last().copied().unwrap_or(1.0);
    let se_txt: Vec<String> = pts
        .iter()
        .map(|p| format!("{:.2}+-{:.2}", p.1, p.2))
        .collect();
    let charts = [
        Chart {
            title: format!(
                "w(t): hex, L = {KPZ_WIDTH}, {KPZ_SEEDS} seeds, fit t/L >= {KPZ_FIT_FROM}"
            ),
            x_label: "t / L (monolayers; t = the paper's timesteps)".into(),
            y_label: "w (cell widths)".into(),
            series: width_series,
            log_x: true,
            log_y: true,
        },
        Chart {
            title: format!("w_sat(L): n = 0, {KPZ_SAT_SEEDS} seeds, alpha = {alpha:.3}"),
            x_label: format!("L (columns); w_sat {}", se_txt.join(", ")),
            y_label: "w_sat (cell widths)".into(),
            series: vec![
                Series {
                    label: format!("measured, alpha = {alpha:.3}"),
                    x: ls.clone(),
                    y: ws,
                    points: true,
                },
                Series {
                    label: "KPZ slope 1/2".into(),
                    x: ls.clone(),
                    y: ls.iter().map(|&x| w0 * (x / l0).sqrt()).collect(),
                    points: false,
                },
            ],
            log_x: true,
            log_y: true,
        },
    ];
    let beta_txt: Vec<String> = betas
        .iter()
        .map(|(n, b, se)| format!("beta(n={n}) = {b:.3}+-{se:.3}"))
        .collect();
    let p = dir.join("growth_kpz_roughness.png");
    plot::line_charts(
        &p,
        &format!("Kinetic roughening: {}", beta_txt.join(", ")),
        &charts,
        2,
        (760, 520),
    )?;
    Ok(vec![p])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panel_drawn_for_times_the_run_did_not_reach_says_so() {
        let mut s = Snapshot {
            time: 169.0,
            log10_time: 169f64.log10(),
            states: Vec::new(),
            unreached: Vec::new(),
        };
        assert_eq!(snapshot_title(&s, StopReason::LatticeFull), "t = 169");
        s.unreached = vec![500, 1000];
        assert_eq!(
            snapshot_title(&s, StopReason::LatticeFull),
            "t = 169: lattice full before t = 500"
        );
        assert_eq!(
            snapshot_title(&s, StopReason::Events),
            "t = 169: events reached before t = 500"
        );
    }
}
