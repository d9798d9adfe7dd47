//! The cursor model's figures (feature `plot`): the article's Figs. 2 and 4-8 in kind, the
//! effect of `k`, and the density error against the number of steps.
//!
//! Every landscape is one walk of `cellsurf cursor`, its parameters read from the figure's
//! scenario file ([`SCENARIOS`]; one file a panel where the panels differ in `k`): the article's
//! 11,520,000 steps on the default 240 x 240 grid from seed 1, drawn next to its wind field (the
//! article's input image, RGB encoding, lightened, with arrows). The wind fields are the
//! generators' article settings ([`WindSpec::article`]); crescentic ridges use the converging
//! generator with centres 60 x 40 cells apart. Sea levels: Figs. 2 and 4 flood the lowest 30% of
//! the cells (a Brownian field never falls to half its mean); Fig. 6 floods the lowest 85% so
//! that the crescents stand out; the others use a fraction of the mean height, the same for
//! every `k` of a figure, as in the article ("If one keeps the sea level equal for simulations
//! with different k"). The effect of `k` runs the winds and sea levels of Figs. 7 and 8 at four
//! `k`.

use std::path::{Path, PathBuf};

use plotters::style::RGBColor;
use rayon::prelude::*;

use crate::engine::VERSION;
use crate::plot::{self, Chart, Figure, FigureError, Mark, PlotError, Series, Sheet};

use super::display::{SeaLevel, flooded_fraction, terrain_rgb};
use super::stats::{self, NoiseModel};
use super::walk::{CursorWalk, Transitions};
use super::wind::{WindField, WindSpec};
use super::{ARTICLE_STEPS, CursorError, CursorScenario, DEFAULT_K, DEFAULT_SIZE, MAX_WIND};

/// The scenario files of the figures made from one run (or one run a panel), by file name.
pub const SCENARIOS: &[(&str, &str)] = crate::plot::scenario_files![
    "cursor_fig2_brownian",
    "cursor_fig4_uniform",
    "cursor_fig5_linear",
    "cursor_fig6_barchan",
    "cursor_fig7_crescentic_k0.10",
    "cursor_fig7_crescentic_k0.50",
    "cursor_fig8_star_k0.25",
    "cursor_fig8_star_k0.50",
    "cursor_fig8_star_k0.90",
];

/// The runs of figure `name`: its scenario file, or one a panel (`NAME_PANEL`), alike but for
/// `k` (the figure draws one wind field and one sea level).
fn runs(name: &str) -> Result<Vec<CursorScenario>, FigureError> {
    let texts = match plot::scenario_text(SCENARIOS, name) {
        Ok(t) => vec![(name.to_string(), t)],
        Err(_) => plot::scenario_panels(SCENARIOS, name)?
            .into_iter()
            .map(|(p, t)| (format!("{name}_{p}"), t))
            .collect(),
    };
    let runs = texts
        .iter()
        .map(|(n, t)| plot::read_scenario(n, t, CursorScenario::parse))
        .collect::<Result<Vec<_>, _>>()?;
    let first = &runs[0];
    if runs.iter().any(|r| {
        (&r.wind, r.size, r.steps, r.seed, r.sea)
            != (&first.wind, first.size, first.steps, first.seed, first.sea)
    }) {
        return Err(FigureError::Model(format!(
            "{name}: its panels' scenarios differ in more than k"
        )));
    }
    Ok(runs)
}

/// The figures, in the article's order.
pub(super) const FIGURES: &[Figure] = &[
    Figure {
        name: "cursor_fig2_brownian",
        about: "Fig. 2: Brownian field (calm air), 11.52 M steps, lowest 30% flooded",
        make: fig2,
    },
    Figure {
        name: "cursor_fig4_uniform",
        about: "Fig. 4: ridges along a uniform wind",
        make: fig4,
    },
    Figure {
        name: "cursor_fig5_linear",
        about: "Fig. 5: linear dunes under bimodal winds meeting head-on",
        make: fig5,
    },
    Figure {
        name: "cursor_fig6_barchan",
        about: "Fig. 6: barchan-like crescents where a drift meets outflow around centres",
        make: fig6,
    },
    Figure {
        name: "cursor_fig7_crescentic",
        about: "Fig. 7: crescentic ridges at k = 0.10 and 0.50",
        make: fig7,
    },
    Figure {
        name: "cursor_fig8_star",
        about: "Fig. 8: network of star dunes at k = 0.25, 0.50 and 0.90",
        make: fig8,
    },
    Figure {
        name: "cursor_k_effect",
        about: "Effect of k (0.10, 0.25, 0.50, 0.90) on crescentic ridges and star dunes",
        make: k_effect,
    },
    Figure {
        name: "cursor_error_vs_time",
        about: "Density error against steps (calm, uniform wind): slope -1/2, exact expectation",
        make: error_vs_time,
    },
];

/// Pixels per cell in the landscape figures.
const CELL_PX: usize = 2;

fn model(e: CursorError) -> FigureError {
    FigureError::Model(e.to_string())
}

/// A picture with a title, drawn by [`draw_pictures`].
pub(super) struct Picture {
    /// Title above the picture.
    pub title: String,
    /// RGB8 pixels, row 0 at the top.
    pub rgb: Vec<u8>,
    /// Width, pixels.
    pub w: u32,
    /// Height, pixels.
    pub h: u32,
    /// Arrows `(from, to)` in the picture's pixel coordinates.
    pub arrows: Vec<((f64, f64), (f64, f64))>,
}

/// The landscape of `heights` flooded at `sea`, each cell `cell_px` pixels.
pub(super) fn landscape_picture(
    title: String,
    heights: &[u64],
    width: usize,
    height: usize,
    sea: f64,
    cell_px: usize,
) -> Picture {
    Picture {
        title,
        rgb: terrain_rgb(heights, width, height, sea, cell_px),
        w: (width * cell_px) as u32,
        h: (height * cell_px) as u32,
        arrows: Vec::new(),
    }
}

/// The wind field as the article's input image (RGB encoding, lightened so the arrows show)
/// with arrows on a coarse grid, each cell `cell_px` pixels.
pub(super) fn wind_picture(title: String, field: &WindField, cell_px: usize) -> Picture {
    let (w, h) = (field.width(), field.height());
    let small = field.to_rgb_image();
    let (pw, ph) = (w * cell_px, h * cell_px);
    let mut rgb = vec![0u8; pw * ph * 3];
    for r in 0..ph {
        for c in 0..pw {
            let s = &small[((r / cell_px) * w + c / cell_px) * 3..][..3];
            for i in 0..3 {
                rgb[(r * pw + c) * 3 + i] = (128 + u16::from(s[i]) / 2) as u8;
            }
        }
    }
    let step = (w.max(h) / 16).max(1);
    let mut arrows = Vec::new();
    for y in (step / 2..h).step_by(step) {
        for x in (step / 2..w).step_by(step) {
            let wind = field.at(x, y);
            let len = wind.speed() / MAX_WIND * 0.9 * (step * cell_px) as f64;
            if len < 1.0 {
                continue;
            }
            let (ux, uy) = (wind.x / wind.speed(), wind.y / wind.speed());
            let cx = (x as f64 + 0.5) * cell_px as f64;
            let cy = (h as f64 - y as f64 - 0.5) * cell_px as f64;
            let (dx, dy) = (ux * len / 2.0, -uy * len / 2.0);
            arrows.push(((cx - dx, cy - dy), (cx + dx, cy + dy)));
        }
    }
    Picture {
        title,
        rgb,
        w: pw as u32,
        h: ph as u32,
        arrows,
    }
}

/// Draws `pictures` in a grid of `cols` columns under `title`, with `caption` (may be empty)
/// at the bottom, and writes the PNG atomically.
pub(super) fn draw_pictures(
    path: &Path,
    title: &str,
    caption: &str,
    pictures: &[Picture],
    cols: usize,
) -> Result<(), PlotError> {
    const GAP: u32 = 12;
    let cols = cols.clamp(1, pictures.len().max(1)) as u32;
    let rows = (pictures.len() as u32).div_ceil(cols);
    let cw = pictures.iter().map(|p| p.w).max().unwrap_or(1);
    let ch = pictures.iter().map(|p| p.h).max().unwrap_or(1);
    let font = (f64::from(cw) / 26.0).clamp(13.0, 22.0);
    let title_h = (font * 2.4) as u32;
    let sub_h = (font * 1.7) as u32;
    let cap_h = if caption.is_empty() {
        0
    } else {
        (font * 1.6) as u32 * (caption.lines().count() as u32)
    };
    let width = GAP + cols * (cw + GAP);
    let height = title_h + rows * (sub_h + ch + GAP) + cap_h + GAP / 2;
    let mut sheet = Sheet::new("pictures", u64::from(width), u64::from(height))?;
    sheet.push(Mark::centred(
        title,
        ((width / 2) as i32, (title_h / 2) as i32),
        font * 1.2,
        true,
    ));
    for (k, p) in pictures.iter().enumerate() {
        let (r, c) = (k as u32 / cols, k as u32 % cols);
        let x0 = GAP + c * (cw + GAP) + (cw - p.w) / 2;
        let y0 = title_h + r * (sub_h + ch + GAP);
        sheet.push(Mark::centred(
            p.title.clone(),
            ((x0 + p.w / 2) as i32, (y0 + sub_h / 2) as i32),
            font,
            false,
        ));
        let top = y0 + sub_h;
        sheet.push(Mark::Picture {
            at: (x0 as i32, top as i32),
            w: p.w,
            h: p.h,
            rgb: p.rgb.clone(),
        });
        sheet.push(Mark::Frame {
            corners: [
                (x0 as i32 - 1, top as i32 - 1),
                ((x0 + p.w) as i32, (top + p.h) as i32),
            ],
            color: RGBColor(120, 120, 120),
        });
        let ink = RGBColor(20, 20, 20);
        for &(from, to) in &p.arrows {
            sheet.extend(Mark::arrow((x0 as f64, top as f64), from, to, ink));
        }
    }
    for (i, line) in caption.lines().enumerate() {
        let y = height - cap_h - GAP / 2 + (font * 1.6) as u32 * i as u32 + (font * 0.8) as u32;
        sheet.push(Mark::centred(
            line,
            ((width / 2) as i32, y as i32),
            font * 0.85,
            false,
        ));
    }
    sheet.write_png(path)
}

/// Runs the walk on `field` with `k` for `steps` steps from seed `seed`; returns the heights.
pub(super) fn simulate(
    field: &WindField,
    k: f64,
    steps: u64,
    seed: u64,
) -> Result<Vec<u64>, CursorError> {
    let tr = Transitions::new(field, k)?;
    let mut walk = CursorWalk::new(&tr, seed);
    walk.run(steps);
    Ok(walk.into_heights())
}

/// The generator's article settings.
fn article(name: &str) -> Result<WindSpec, FigureError> {
    WindSpec::article(name).ok_or_else(|| FigureError::Model(format!("no generator {name}")))
}

/// A short description of a generator's parameters, for captions.
fn describe(spec: &WindSpec) -> String {
    match *spec {
        WindSpec::Calm => "calm".into(),
        WindSpec::Uniform { angle_deg, speed } => {
            format!("uniform: toward {angle_deg} deg at {speed}")
        }
        WindSpec::Bimodal {
            angle_deg,
            speed,
            spread_deg,
            wavelength,
        } => format!(
            "bimodal: bands along {angle_deg} deg, speed {speed}, spread {spread_deg} deg, wavelength {wavelength} cells"
        ),
        WindSpec::Converging {
            angle_deg,
            speed,
            radial,
            wavelength,
            spacing,
            radius,
        } => format!(
            "converging: drift {speed} toward {angle_deg} deg, radial {radial} within {radius} cells of centres {wavelength} x {spacing} cells apart"
        ),
        WindSpec::Rotating {
            angle_deg,
            speed,
            wavelength,
            arms,
        } => format!(
            "rotating: {arms} arms from {angle_deg} deg, speed {speed}, nodes {wavelength} cells apart"
        ),
    }
}

/// Runs the walk of `run` once per `k` in parallel; returns the field and the heights.
fn landscapes(run: &CursorScenario, ks: &[f64]) -> Result<(WindField, Vec<Vec<u64>>), FigureError> {
    let (w, h) = run.size;
    let field = run.wind.field(w, h).map_err(model)?;
    let runs: Result<Vec<Vec<u64>>, CursorError> = ks
        .par_iter()
        .map(|&k| simulate(&field, k, run.steps, run.seed))
        .collect();
    Ok((field, runs.map_err(model)?))
}

/// A figure of a wind field and its landscapes, one a run of figure `name`'s scenarios, all
/// flooded at the sea level that the scenarios' sea level resolves to on the first landscape.
fn landscape_figure(dir: &Path, name: &str, title: &str) -> Result<Vec<PathBuf>, FigureError> {
    let all = runs(name)?;
    let run = &all[0];
    let ks: Vec<f64> = all.iter().map(|r| r.k).collect();
    let (w, h) = run.size;
    let (field, runs) = landscapes(run, &ks)?;
    let level = run.sea.resolve(&runs[0]);
    let mut pics = vec![wind_picture(
        "wind field (RGB encoding, arrows)".into(),
        &field,
        CELL_PX,
    )];
    for (k, hts) in ks.iter().zip(&runs) {
        pics.push(landscape_picture(
            format!(
                "k = {k:.2}: max height {}, {:.0}% flooded",
                hts.iter().max().copied().unwrap_or(0),
                100.0 * flooded_fraction(hts, level)
            ),
            hts,
            w,
            h,
            level,
            CELL_PX,
        ));
    }
    let caption = format!(
        "{}\n{w} x {h} torus, {} steps, seed {}; sea level {level:.0} visits ({}); cellsurf {VERSION}",
        describe(&run.wind),
        run.steps,
        run.seed,
        sea_words(&run.sea)
    );
    let path = dir.join(format!("{name}.png"));
    draw_pictures(&path, title, &caption, &pics, pics.len().min(4))?;
    Ok(vec![path])
}

fn sea_words(sea: &SeaLevel) -> String {
    match *sea {
        SeaLevel::Height(v) => format!("set to {v}"),
        SeaLevel::MeanFraction(f) => format!("{f} x the mean height"),
        SeaLevel::Quantile(q) => format!("lowest {:.0}% of the cells", 100.0 * q),
    }
}

fn fig2(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    landscape_figure(
        dir,
        "cursor_fig2_brownian",
        "Fig. 2: dune field generated by sheer Brownian motion (calm air)",
    )
}

fn fig4(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    landscape_figure(
        dir,
        "cursor_fig4_uniform",
        "Fig. 4: ridges form along the wind path in a uniform wind",
    )
}

fn fig5(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    landscape_figure(
        dir,
        "cursor_fig5_linear",
        "Fig. 5: linear dunes under bimodal winds meeting head-on",
    )
}

fn fig6(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    landscape_figure(
        dir,
        "cursor_fig6_barchan",
        "Fig. 6: barchan-like crescents, horns downwind (drift to the right)",
    )
}

fn fig7(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    landscape_figure(
        dir,
        "cursor_fig7_crescentic",
        "Fig. 7: effect of k on crescentic dunes (a: k = 0.10, b: k = 0.50)",
    )
}

fn fig8(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    landscape_figure(
        dir,
        "cursor_fig8_star",
        "Fig. 8: effect of k on a network of star dunes (k = 0.25, 0.50, 0.90)",
    )
}

/// The effect of `k`: the runs of Figs. 7 and 8 (their scenarios' winds, sea levels, grids,
/// steps and seeds) at four `k`.
fn k_effect(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let ks = [0.10, 0.25, 0.50, 0.90];
    let rows = [
        runs("cursor_fig7_crescentic")?.remove(0),
        runs("cursor_fig8_star")?.remove(0),
    ];
    let (w, h) = rows[0].size;
    let mut pics = Vec::new();
    let mut lines = Vec::new();
    for run in &rows {
        let (spec, sea) = (&run.wind, &run.sea);
        let (field, runs) = landscapes(run, &ks)?;
        let level = sea.resolve(&runs[0]);
        pics.push(wind_picture(
            format!("{} wind", spec.name()),
            &field,
            CELL_PX,
        ));
        for (k, hts) in ks.iter().zip(&runs) {
            pics.push(landscape_picture(
                format!(
                    "k = {k:.2}: max {}, {:.0}% flooded",
                    hts.iter().max().copied().unwrap_or(0),
                    100.0 * flooded_fraction(hts, level)
                ),
                hts,
                w,
                h,
                level,
                CELL_PX,
            ));
        }
        lines.push(format!(
            "{}; sea level {level:.0} visits ({})",
            describe(spec),
            sea_words(sea)
        ));
    }
    lines.push(format!(
        "{w} x {h} torus, {} steps, seed {}; lower k: fuzzier, lower dunes (more Brownian); cellsurf {VERSION}",
        rows[0].steps, rows[0].seed
    ));
    let path = dir.join("cursor_k_effect.png");
    draw_pictures(
        &path,
        "Effect of the force constant k: crescentic ridges (top), star dunes (bottom)",
        &lines.join("\n"),
        &pics,
        5,
    )?;
    Ok(vec![path])
}

/// Seeds averaged in the error-against-steps figure.
const ERROR_SEEDS: u64 = 4;

/// The density error against steps for one uniform wind: the RMS over seeds of the measured
/// error, and the exact expectation, at `checkpoints`.
fn error_series(spec: &WindSpec, checkpoints: &[u64]) -> Result<(Vec<f64>, Vec<f64>), FigureError> {
    let (w, h) = DEFAULT_SIZE;
    let field = spec.field(w, h).map_err(model)?;
    let tr = Transitions::new(&field, DEFAULT_K).map_err(model)?;
    let curves: Vec<Vec<stats::ErrorPoint>> = (0..ERROR_SEEDS)
        .into_par_iter()
        .map(|s| stats::error_curve(&tr, 100 + s, checkpoints))
        .collect();
    let measured = (0..checkpoints.len())
        .map(|i| {
            let ms: f64 = curves
                .iter()
                .map(|c| c[i].density_error.powi(2))
                .sum::<f64>()
                / curves.len() as f64;
            ms.sqrt()
        })
        .collect();
    let noise = NoiseModel::for_transitions(&tr)
        .ok_or_else(|| FigureError::Model("the error figure needs a uniform wind".into()))?;
    let expected = checkpoints
        .iter()
        .map(|&n| noise.expected_error(n))
        .collect();
    Ok((measured, expected))
}

/// The first step count of the slope fit: well past the slowest mode's relaxation (about
/// 4,000 steps for calm air on 240 x 240 cells).
const FIT_FROM: u64 = 100_000;

fn error_vs_time(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let checkpoints = stats::log_spaced(1_000, ARTICLE_STEPS, 25);
    let x: Vec<f64> = checkpoints.iter().map(|&n| n as f64).collect();
    let mut err_series = Vec::new();
    let mut scaled_series = Vec::new();
    for spec in [WindSpec::Calm, article("uniform")?] {
        let (measured, expected) = error_series(&spec, &checkpoints)?;
        let fit: Vec<(f64, f64)> = x
            .iter()
            .zip(&measured)
            .filter(|(n, _)| **n >= FIT_FROM as f64)
            .map(|(&n, &e)| (n, e))
            .collect();
        let slope = crate::engine::stats::loglog_slope(&fit)
            .map(|s| s.0)
            .unwrap_or(f64::NAN);
        let name = spec.name();
        err_series.push(Series {
            label: format!(
                "{name}: RMS of {ERROR_SEEDS} seeds, slope {slope:.3} (fit from N = {FIT_FROM})"
            ),
            x: x.clone(),
            y: measured.clone(),
            points: true,
        });
        err_series.push(Series {
            label: format!("{name}: exact expectation"),
            x: x.clone(),
            y: expected.clone(),
            points: false,
        });
        scaled_series.push(Series {
            label: format!("{name}: measured"),
            x: x.clone(),
            y: measured.iter().zip(&x).map(|(e, n)| e * n.sqrt()).collect(),
            points: true,
        });
        scaled_series.push(Series {
            label: format!("{name}: exact expectation"),
            x: x.clone(),
            y: expected.iter().zip(&x).map(|(e, n)| e * n.sqrt()).collect(),
            points: false,
        });
    }
    let (w, h) = DEFAULT_SIZE;
    let charts = [
        Chart {
            title: "relative RMS deviation of the visit density from uniform".into(),
            x_label: "steps N".into(),
            y_label: "density error".into(),
            series: err_series,
            log_x: true,
            log_y: true,
        },
        Chart {
            title: "error x sqrt(N): flat where the error falls like 1/sqrt(N)".into(),
            x_label: "steps N".into(),
            y_label: "density error x sqrt(N)".into(),
            series: scaled_series,
            log_x: true,
            log_y: false,
        },
    ];
    let path = dir.join("cursor_error_vs_time.png");
    plot::line_charts(
        &path,
        &format!("Cursor walk: density error against steps ({w} x {h} torus, k = {DEFAULT_K})"),
        &charts,
        2,
        (760, 540),
    )?;
    Ok(vec![path])
}
