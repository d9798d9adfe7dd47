//! Drawing the height field and the wind-ripple figures (feature `plot`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use plotters::style::RGBColor;

use super::model::{WindRun, run};
use super::params::WindParams;
use super::stats::{WindStats, power_spectrum_y};
use crate::plot::{self, Chart, ColorRamp, FigureError, Mark, PlotError, Series, Sheet};

use crate::engine::VERSION;

/// The scenario files of the figures made from one run, by figure name: the
/// `windripples_height` run is the notebook's at its defaults but for its steps, a quarter of
/// its 1024, so that `cellsurf figures` stays quick (`cellsurf wind-ripples --out` draws the
/// full run).
pub const SCENARIOS: &[(&str, &str)] = crate::plot::scenario_files!["windripples_height",];

/// Seeds of the `windripples_error_vs_time` figure.
pub const ERROR_SEEDS: u64 = 8;
/// Steps of each run of the `windripples_error_vs_time` figure.
pub const ERROR_STEPS: u64 = 32;

/// A one-line description of the parameters, for titles.
pub fn describe(p: &WindParams) -> String {
    format!(
        "N={}, {}x{} bins, L={}, kappa={}, D={} {}, seed {}, cellsurf {VERSION}",
        p.particles, p.bins, p.bins, p.hop, p.kappa, p.diffusion, p.schedule, p.seed
    )
}

/// 256 colours of the viridis colormap (dark violet, blue, green, yellow), index 0 for
/// height 0.
fn lut() -> Vec<RGBColor> {
    ColorRamp::Viridis.lut(256)
}

/// The colour index of height `h` on a scale `0..=vmax`.
fn level(h: f64, vmax: f64) -> usize {
    if vmax > 0.0 {
        ((h / vmax).clamp(0.0, 1.0) * 255.0).round() as usize
    } else {
        0
    }
}

/// RGB8 pixels (row 0 at the top) of the `bins x bins` field `h` (layout `ix * bins + iy`)
/// drawn as in the notebook's `imshow(height.T)`: `x` across, `y` (the wind) down, colour
/// scale `0..=vmax`. `smooth`: bilinear interpolation between cell centres, periodic (the
/// notebook draws with `interpolation='lanczos'`); otherwise each cell is a square.
pub fn render(h: &[f64], bins: usize, px: u32, vmax: f64, smooth: bool) -> Vec<u8> {
    let lut = lut();
    let n = bins as f64;
    let px_us = px as usize;
    let mut out = vec![0u8; px_us * px_us * 3];
    let at = |ix: usize, iy: usize| h[(ix % bins) * bins + iy % bins];
    for row in 0..px_us {
        // Position in cell units, cell centres at integer + 0.5.
        let fy = (row as f64 + 0.5) / f64::from(px) * n;
        for col in 0..px_us {
            let fx = (col as f64 + 0.5) / f64::from(px) * n;
            let v = if smooth {
                let (gx, gy) = (fx - 0.5 + n, fy - 0.5 + n);
                let (x0, y0) = (gx.floor(), gy.floor());
                let (tx, ty) = (gx - x0, gy - y0);
                let (x0, y0) = (x0 as usize, y0 as usize);
                let a = at(x0, y0) * (1.0 - tx) + at(x0 + 1, y0) * tx;
                let b = at(x0, y0 + 1) * (1.0 - tx) + at(x0 + 1, y0 + 1) * tx;
                a * (1.0 - ty) + b * ty
            } else {
                at(fx as usize, fy as usize)
            };
            let c = lut[level(v, vmax)];
            let k = (row * px_us + col) * 3;
            out[k..k + 3].copy_from_slice(&[c.0, c.1, c.2]);
        }
    }
    out
}

/// Draws the height field of `r` into `path` (PNG): the whole field smoothed as in the
/// notebook, a 64 x 64-bin corner cell by cell, a colour bar and the statistics.
pub fn draw_height(path: &Path, r: &WindRun) -> Result<(), PlotError> {
    let p = &r.params;
    let bins = p.bins;
    let main_px: u32 = 768;
    let zoom_bins = bins.min(64);
    let zoom_px: u32 = 384;
    let (gap, title_h, label_h) = (16u32, 64u32, 28u32);
    let width = gap * 3 + main_px + zoom_px;
    let height = title_h + label_h + main_px + gap;
    let vmax = r.height.iter().cloned().fold(0.0, f64::max);
    let mut sheet = Sheet::new("bins", u64::from(width), u64::from(height))?;
    let at = |x: u32, y: u32| (x as i32, y as i32);
    sheet.push(Mark::centred(
        format!(
            "Wind ripples (the notebook's model): height after {} steps",
            p.steps
        ),
        at(width / 2, 20),
        24.0,
        true,
    ));
    sheet.push(Mark::centred(describe(p), at(width / 2, 48), 16.0, false));
    let y0 = title_h + label_h;
    sheet.push(Mark::centred(
        "height field (bilinear, as the notebook's lanczos); x across, wind y down",
        at(gap + main_px / 2, title_h + label_h / 2),
        16.0,
        false,
    ));
    let zx = 2 * gap + main_px;
    sheet.push(Mark::centred(
        format!("corner {zoom_bins} x {zoom_bins} bins, cell by cell"),
        at(zx + zoom_px / 2, title_h + label_h / 2),
        16.0,
        false,
    ));
    sheet.push(Mark::Picture {
        at: at(gap, y0),
        w: main_px,
        h: main_px,
        rgb: render(&r.height, bins, main_px, vmax, true),
    });
    // The corner: the first zoom_bins columns and rows.
    let mut corner = Vec::with_capacity(zoom_bins * zoom_bins);
    for ix in 0..zoom_bins {
        for iy in 0..zoom_bins {
            corner.push(r.height[ix * bins + iy]);
        }
    }
    sheet.push(Mark::Picture {
        at: at(zx, y0),
        w: zoom_px,
        h: zoom_px,
        rgb: render(&corner, zoom_bins, zoom_px, vmax, false),
    });
    // Colour bar under the corner.
    let cb_y = y0 + zoom_px + 40;
    let lut = lut();
    for i in 0..zoom_px {
        let c = lut[(i as usize * 255) / (zoom_px as usize - 1)];
        sheet.push(Mark::Fill {
            corners: [
                (zx as i32 + i as i32, cb_y as i32),
                (zx as i32 + i as i32 + 1, cb_y as i32 + 22),
            ],
            color: c,
        });
    }
    for (frac, name) in [(0.0, "0"), (0.5, ""), (1.0, "")] {
        let x = zx + (frac * f64::from(zoom_px - 1)) as u32;
        let label = if name.is_empty() {
            format!("{:.1}", frac * vmax)
        } else {
            name.to_string()
        };
        sheet.push(Mark::centred(label, at(x, cb_y + 36), 16.0, false));
    }
    sheet.push(Mark::centred(
        "height (mean 1; scale 0 to the maximum, as the notebook)",
        at(zx + zoom_px / 2, cb_y - 12),
        16.0,
        false,
    ));
    let s: &WindStats = &r.stats;
    let f = |v: Option<f64>| v.map_or("n/a".to_string(), |v| format!("{v:.2} bins"));
    let lines = [
        format!("height mean {:.6}, std {:.4}", s.height_mean, s.height_std),
        format!("dominant wavelength {}", f(s.wavelength_bins)),
        format!("mean wavelength {}", f(s.mean_wavelength_bins)),
        format!("hop L = {:.2} bins", p.hop * bins as f64),
    ];
    for (k, l) in lines.into_iter().enumerate() {
        sheet.push(Mark::left(l, at(zx, cb_y + 80 + 26 * k as u32), 16.0));
    }
    sheet.write_png(path)
}

/// Draws the spectrum `P(k)` of `r`'s height along the wind against the wavelength, with the
/// two wavelength statistics marked.
pub fn draw_spectrum(path: &Path, r: &WindRun) -> Result<(), PlotError> {
    let bins = r.params.bins;
    let p = power_spectrum_y(&r.height, bins);
    let total: f64 = p.iter().skip(1).sum();
    let lam: Vec<f64> = (1..p.len()).map(|k| bins as f64 / k as f64).collect();
    let rel: Vec<f64> = p
        .iter()
        .skip(1)
        .map(|v| v / total.max(f64::MIN_POSITIVE))
        .collect();
    let top = rel.iter().cloned().fold(0.0, f64::max);
    let mut series = vec![Series {
        label: "P(k) / sum P, k = 1..bins/2".into(),
        x: lam,
        y: rel,
        points: true,
    }];
    if let Some(w) = r.stats.wavelength_bins {
        series.push(Series {
            label: format!("dominant (smoothed peak) {w:.2} bins"),
            x: vec![w, w],
            y: vec![0.0, top],
            points: false,
        });
    }
    if let Some(w) = r.stats.mean_wavelength_bins {
        series.push(Series {
            label: format!("spectrum-weighted mean {w:.2} bins"),
            x: vec![w, w],
            y: vec![0.0, top],
            points: false,
        });
    }
    let chart = Chart {
        title: format!(
            "after {} steps; N={}, {} bins, seed {}",
            r.params.steps, r.params.particles, r.params.bins, r.params.seed
        ),
        x_label: "wavelength along the wind (bins)".into(),
        y_label: "share of the power".into(),
        series,
        log_x: true,
        log_y: false,
    };
    plot::line_charts(
        path,
        &format!("Wind ripples: height spectrum along the wind (cellsurf {VERSION})"),
        &[chart],
        1,
        (1000, 520),
    )
}

/// The parameters of a figure's scenario ([`SCENARIOS`]).
pub fn scenario(name: &str) -> Result<WindParams, FigureError> {
    plot::read_scenario(
        name,
        plot::scenario_text(SCENARIOS, name)?,
        WindParams::from_scenario,
    )
}

/// `windripples_height.png` (the notebook's figure, its scenario `windripples_height`) and
/// `windripples_height_spectrum.png`.
pub fn height_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let params = scenario("windripples_height")?;
    let r = run(&params, |_| {}).map_err(|e| FigureError::Model(e.to_string()))?;
    // The run's parameters in the PNG files (`Figure::make` records only the name).
    plot::set_png_parameters(Some(params.describe_toml()));
    let p1 = dir.join("windripples_height.png");
    let p2 = dir.join("windripples_height_spectrum.png");
    let drawn = draw_height(&p1, &r).and_then(|()| draw_spectrum(&p2, &r));
    plot::set_png_parameters(None);
    drawn?;
    Ok(vec![p1, p2])
}

/// `windripples_error_vs_time.png`: [`ERROR_SEEDS`] runs (seeds 1, 2, ...) of
/// [`ERROR_STEPS`] steps at the default parameters; after each, the standard error of the
/// mean over the seeds so far of `height_std` and of both wavelengths, against the
/// cumulative run time, with the `1/sqrt(time)` law through the sd of all the seeds.
pub fn error_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    crate::engine::study::run_whole(&ErrorStudy, dir).map_err(FigureError::Model)
}

/// The study behind `windripples_error_vs_time.png` as independent runs (one per seed), for
/// `cellsurf converge windripples --part i/N` ([`crate::engine::study`]).
pub struct ErrorStudy;

/// One run's record: the statistics the figure uses (NaN: no wavelength found) and its wall
/// time.
#[derive(serde::Serialize, serde::Deserialize)]
struct ErrorRecord {
    height_std: f64,
    wavelength_bins: f64,
    mean_wavelength_bins: f64,
    seconds: f64,
}

fn error_base() -> WindParams {
    WindParams {
        steps: ERROR_STEPS,
        ..WindParams::default()
    }
}

impl crate::engine::study::Study for ErrorStudy {
    fn name(&self) -> &'static str {
        "windripples"
    }
    fn parallel(&self) -> bool {
        false // each run uses every core, and the figure plots wall time
    }
    fn runs(&self) -> Vec<String> {
        (1..=ERROR_SEEDS).map(|s| format!("seed {s}")).collect()
    }
    fn run(&self, name: &str) -> Result<toml::Value, String> {
        let seed: u64 = name
            .strip_prefix("seed ")
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| format!("not a run of the study: {name}"))?;
        let params = WindParams {
            seed,
            ..error_base()
        };
        let t = Instant::now();
        let r = run(&params, |_| {}).map_err(|e| e.to_string())?;
        let s = r.stats;
        crate::engine::study::record(&ErrorRecord {
            height_std: s.height_std,
            wavelength_bins: s.wavelength_bins.unwrap_or(f64::NAN),
            mean_wavelength_bins: s.mean_wavelength_bins.unwrap_or(f64::NAN),
            seconds: t.elapsed().as_secs_f64(),
        })
    }
    fn draw(&self, records: &[toml::Value], dir: &Path) -> Result<Vec<PathBuf>, String> {
        draw_error(records, dir).map_err(|e| e.to_string())
    }
}

fn draw_error(records: &[toml::Value], dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let mut values: [Vec<f64>; 3] = Default::default();
    let mut time = 0.0;
    let mut xs = Vec::new();
    let mut se: [Vec<f64>; 3] = Default::default();
    let base = error_base();
    for (k, rec) in records.iter().enumerate() {
        let r: ErrorRecord = crate::engine::study::from_record(rec).map_err(FigureError::Model)?;
        time += r.seconds;
        for (v, x) in
            values
                .iter_mut()
                .zip([r.height_std, r.wavelength_bins, r.mean_wavelength_bins])
        {
            v.push(x);
        }
        if k >= 1 {
            xs.push(time);
            for (e, v) in se.iter_mut().zip(&values) {
                e.push(crate::engine::stats::mean_and_se(v).1);
            }
        }
    }
    // sd / sqrt(seeds), with the sd of all the seeds: the 1/sqrt(time) law.
    let guide = |v: &[f64]| {
        let sd = crate::engine::stats::mean_and_se(v).1 * (v.len() as f64).sqrt();
        let per_seed = time / v.len() as f64;
        Series {
            label: "sd of all seeds / sqrt(seeds): 1/sqrt(time)".into(),
            x: xs.clone(),
            y: xs.iter().map(|t| sd * (per_seed / t).sqrt()).collect(),
            points: false,
        }
    };
    let [se_std, se_peak, se_mean] = se;
    let mean_of = |v: &[f64]| crate::engine::stats::mean_and_se(v).0;
    let charts = [
        Chart {
            title: format!("height_std = {:.4}", mean_of(&values[0])),
            x_label: "cumulative run time (s, wall, all threads)".into(),
            y_label: "standard error of the mean over seeds".into(),
            series: vec![
                Series {
                    label: "height_std".into(),
                    x: xs.clone(),
                    y: se_std.clone(),
                    points: true,
                },
                guide(&values[0]),
            ],
            log_x: true,
            log_y: true,
        },
        Chart {
            title: format!(
                "wavelengths: dominant {:.2}, mean {:.3} bins",
                mean_of(&values[1]),
                mean_of(&values[2])
            ),
            x_label: "cumulative run time (s, wall, all threads)".into(),
            y_label: "standard error of the mean over seeds (bins)".into(),
            series: vec![
                Series {
                    label: "dominant (smoothed peak)".into(),
                    x: xs.clone(),
                    y: se_peak,
                    points: true,
                },
                Series {
                    label: "mean (spectrum-weighted)".into(),
                    x: xs.clone(),
                    y: se_mean.clone(),
                    points: true,
                },
                guide(&values[2]),
            ],
            log_x: true,
            log_y: true,
        },
    ];
    let path = dir.join("windripples_error_vs_time.png");
    plot::set_png_parameters(Some(format!(
        "{}seeds = \"1..={ERROR_SEEDS}\"\n",
        base.describe_toml()
    )));
    let drawn = plot::line_charts(
        &path,
        &format!(
            "Wind ripples: error against run time, seeds 1..{ERROR_SEEDS} of the {ERROR_STEPS}-step default run (cellsurf {VERSION})"
        ),
        &charts,
        2,
        (660, 460),
    );
    plot::set_png_parameters(None);
    drawn?;
    Ok(vec![path])
}
