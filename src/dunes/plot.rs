//! Figures of the dune model (feature `plot`): height fields in a continuous colour map,
//! dune bodies, the migration GIF and the error against run time.
//!
//! Heights are drawn with the sand colour ramp ([`ColorRamp::Sand`]: dark bare ground to
//! pale crests); a picture is an `N x N` field of colours scaled up nearest-cell
//! ([`FieldPanel`], [`draw_field`], with a colour bar) and drawn by the plot module's
//! [`Sheet`]. Wind blows left to
//! right; row 0 is at the bottom. The GIF ([`MigrationRecorder`]) quantises heights into 255
//! levels of the same ramp and uses [`GifWriter`].

use std::path::{Path, PathBuf};

use plotters::style::{BLACK, RGBColor};
use rayon::prelude::*;

use super::study::{self, ErrorCurve, EvolutionPoint, SeedRun};
use super::{DuneConfig, DuneModel, DuneScenario, Mode, Start, VERSION, above_threshold, bodies};
use crate::engine::lattice::Lattice;
use crate::plot::{
    self, CellField, Chart, ColorRamp, GifWriter, Mark, Palette, PlotError, Series, Sheet,
};
use crate::plot::{Figure, FigureError, read_scenario, scenario_panels, scenario_text};

/// The scenario files of the figures made from one run (or one run a panel), by file name.
pub const SCENARIOS: &[(&str, &str)] = crate::plot::scenario_files![
    "dunes_q1",
    "dunes_q3",
    "dunes_barchan",
    "dunes_werner_q0.5",
    "dunes_werner_q3",
];

/// The figures of this model, made by `cellsurf figures`.
pub const FIGURES: &[Figure] = &[
    Figure {
        name: "dunes_q1",
        about: "Dune mode, Q = 1: separate barchan-like dunes (and dunes_migration.gif)",
        make: q1_figure,
    },
    Figure {
        name: "dunes_q3",
        about: "Dune mode, Q = 3: connected transverse ridges",
        make: q3_figure,
    },
    Figure {
        name: "dunes_barchan",
        about: "Dune mode, one sand pile: it becomes a barchan with its horns downwind",
        make: barchan_figure,
    },
    Figure {
        name: "dunes_werner",
        about: "Werner (1995) variant: shadow zone and angle of repose, little and much sand",
        make: werner_figure,
    },
    Figure {
        name: "dunes_error_vs_time",
        about: "Dune bodies and bare fraction: seed-to-seed standard error against run time",
        make: error_figure,
    },
];

/// Number of height levels in the GIF palette (states `0..HEIGHT_LEVELS`).
pub const HEIGHT_LEVELS: usize = 255;

/// Colour of a height at fraction `v` (clamped to [0, 1]) of the scale.
pub fn height_color(v: f64) -> RGBColor {
    ColorRamp::Sand.color(v)
}

/// The GIF palette: [`HEIGHT_LEVELS`] colours of the height ramp, state `s` for the height
/// `s / (HEIGHT_LEVELS - 1)` of the scale.
pub fn height_palette() -> Palette {
    ColorRamp::Sand.palette(HEIGHT_LEVELS)
}

/// Heights (height units) quantised to palette states of [`height_palette`], with `max`
/// height units at the top of the scale.
pub fn height_states(heights: &[f32], max: f64) -> Vec<u8> {
    let top = (HEIGHT_LEVELS - 1) as f64;
    let scale = if max > 0.0 { top / max } else { 0.0 };
    heights
        .iter()
        .map(|&h| (f64::from(h) * scale).round().clamp(0.0, top) as u8)
        .collect()
}

/// One picture of [`draw_field`]: an `n x n` field of colours (`rgb[y * n + x]`) with a
/// title.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldPanel {
    /// Title drawn above the picture.
    pub title: String,
    /// Side of the field, cells.
    pub n: usize,
    /// Colour per cell, row 0 first.
    pub rgb: Vec<RGBColor>,
}

/// The heights `grains` of an `n x n` grid, coloured with the height ramp, `max` height
/// units at the top.
pub fn height_panel(title: &str, grains: &[u64], n: usize, max: f64) -> FieldPanel {
    let lut = ColorRamp::Sand.lut(256);
    let scale = if max > 0.0 { 255.0 / max } else { 0.0 };
    FieldPanel {
        title: title.to_string(),
        n,
        rgb: grains
            .iter()
            .map(|&g| lut[(super::to_units(g) * scale).round().clamp(0.0, 255.0) as usize])
            .collect(),
    }
}

/// Colours of dune bodies (cycled), and of bare ground.
const BODY_COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(90, 90, 90),
];
const BARE: RGBColor = RGBColor(236, 232, 224);

/// The dune bodies of `grains` (cells above `threshold` height units, 8-neighbour torus),
/// one colour per body, bare ground pale grey.
pub fn bodies_panel(title: &str, grains: &[u64], lattice: &Lattice, threshold: f64) -> FieldPanel {
    let b = bodies(&above_threshold(grains, threshold), lattice);
    FieldPanel {
        title: title.to_string(),
        n: lattice.width(),
        rgb: b
            .labels
            .iter()
            .map(|&l| {
                if l == u32::MAX {
                    BARE
                } else {
                    BODY_COLORS[l as usize % BODY_COLORS.len()]
                }
            })
            .collect(),
    }
}

/// Margin and gap between panels, pixels.
const GAP: u32 = 12;
/// Width of the colour-bar column, pixels.
const BAR_W: u32 = 110;

/// Draws `panels` as a grid of `cols` columns, each `panel_px` pixels square, under `title`,
/// with a colour bar of the height ramp from 0 to `bar_max` height units on the right (none
/// when `bar_max` is `None`), and writes the PNG atomically.
///
/// # Errors
///
/// [`PlotError::InvalidInput`] for no panels, `cols` or `panel_px` zero, a panel whose `rgb`
/// is not `n * n` long, or a picture too large; drawing, encoding and i/o errors.
pub fn draw_field(
    path: &Path,
    title: &str,
    panels: &[FieldPanel],
    cols: usize,
    panel_px: u32,
    bar_max: Option<f64>,
) -> Result<(), PlotError> {
    if panels.is_empty() {
        return Err(PlotError::InvalidInput {
            name: "panels".into(),
            reason: "is empty".into(),
        });
    }
    if cols == 0 || panel_px == 0 {
        return Err(PlotError::InvalidInput {
            name: "cols, panel_px".into(),
            reason: "must be positive".into(),
        });
    }
    for (k, p) in panels.iter().enumerate() {
        if p.n == 0 || p.rgb.len() != p.n * p.n {
            return Err(PlotError::InvalidInput {
                name: format!("panels[{k}].rgb"),
                reason: format!(
                    "has {} colours, expected n * n with n = {}",
                    p.rgb.len(),
                    p.n
                ),
            });
        }
    }
    let cols = cols.min(panels.len());
    let rows = panels.len().div_ceil(cols);
    let font = (f64::from(panel_px) / 20.0).clamp(13.0, 22.0);
    let title_font = font * 1.15;
    let lines: Vec<&str> = title.lines().collect();
    let title_h = (title_font * (0.6 + 1.4 * lines.len().max(1) as f64)).round() as u32;
    let ptitle_h = (font * 1.8).round() as u32;
    let bar_w = if bar_max.is_some() { BAR_W } else { 0 };
    let width = u64::from(GAP) + cols as u64 * u64::from(panel_px + GAP) + u64::from(bar_w);
    // Room under the colour bar for its label, when the panels alone are not taller.
    let label_h = if bar_max.is_some() && rows == 1 {
        (font * 2.6).round() as u32
    } else {
        0
    };
    let height = u64::from(title_h)
        + rows as u64 * u64::from(ptitle_h + panel_px + GAP)
        + u64::from(label_h);
    let mut sheet = Sheet::new("panel_px", width, height)?;
    let width = sheet.width();
    for (k, line) in lines.iter().enumerate() {
        let y = title_font * (1.0 + 1.4 * k as f64);
        sheet.push(Mark::centred(
            *line,
            ((width / 2) as i32, y.round() as i32),
            title_font,
            k == 0,
        ));
    }
    for (k, p) in panels.iter().enumerate() {
        let (r, c) = ((k / cols) as u32, (k % cols) as u32);
        let x0 = GAP + c * (panel_px + GAP);
        let y0 = title_h + r * (ptitle_h + panel_px + GAP);
        sheet.push(Mark::centred(
            p.title.clone(),
            ((x0 + panel_px / 2) as i32, (y0 + ptitle_h / 2) as i32),
            font,
            false,
        ));
        let by = y0 + ptitle_h;
        let px = panel_px as usize;
        let mut pixels = Vec::with_capacity(px * px * 3);
        for j in 0..px {
            // Row 0 of the picture is the top: the highest y.
            let y = p.n - 1 - (j * p.n / px).min(p.n - 1);
            for i in 0..px {
                let x = (i * p.n / px).min(p.n - 1);
                let RGBColor(r, g, b) = p.rgb[y * p.n + x];
                pixels.extend_from_slice(&[r, g, b]);
            }
        }
        sheet.push(Mark::Picture {
            at: (x0 as i32, by as i32),
            w: panel_px,
            h: panel_px,
            rgb: pixels,
        });
        sheet.push(Mark::Frame {
            corners: [
                (x0 as i32 - 1, by as i32 - 1),
                ((x0 + panel_px) as i32, (by + panel_px) as i32),
            ],
            color: RGBColor(150, 150, 150),
        });
    }
    if let Some(max) = bar_max {
        sheet.extend(colour_bar(
            width - bar_w,
            title_h + ptitle_h,
            panel_px,
            max,
            font,
        ));
    }
    sheet.write_png(path)
}

/// A vertical colour bar of the height ramp from 0 (bottom) to `max` (top), `h` pixels tall,
/// with ticks and the label "height (cell widths)".
fn colour_bar(x0: u32, y0: u32, h: u32, max: f64, font: f64) -> Vec<Mark> {
    let bw = 18u32;
    let lut = ColorRamp::Sand.lut(256);
    let mut pixels = Vec::with_capacity((bw * h * 3) as usize);
    for j in 0..h {
        let v = 1.0 - f64::from(j) / f64::from(h.max(2) - 1);
        let RGBColor(r, g, b) = lut[(v * 255.0).round() as usize];
        for _ in 0..bw {
            pixels.extend_from_slice(&[r, g, b]);
        }
    }
    let mut marks = vec![Mark::Picture {
        at: (x0 as i32, y0 as i32),
        w: bw,
        h,
        rgb: pixels,
    }];
    let size = font * 0.9;
    for k in 0..=4 {
        let v = max * f64::from(k) / 4.0;
        let y = y0 as i32 + ((1.0 - f64::from(k) / 4.0) * f64::from(h - 1)).round() as i32;
        marks.push(Mark::Line {
            points: vec![((x0 + bw) as i32, y), ((x0 + bw + 5) as i32, y)],
            color: BLACK,
        });
        marks.push(Mark::left(
            format!("{v:.1}"),
            ((x0 + bw + 8) as i32, y),
            size,
        ));
    }
    let line = (font * 1.1).round() as u32;
    marks.push(Mark::left(
        "height",
        (x0 as i32, (y0 + h + line) as i32),
        size,
    ));
    marks.push(Mark::left(
        "(cell widths)",
        (x0 as i32, (y0 + h + 2 * line) as i32),
        size,
    ));
    marks
}

/// Collects frames of a run for an animated GIF: heights sampled on at most `side x side`
/// cells (point sampling of larger grids), kept as `f32` so that the colour scale can be
/// fixed from the whole run when the GIF is written.
#[derive(Clone, Debug)]
pub struct MigrationRecorder {
    side: usize,
    frames: Vec<Vec<f32>>,
}

impl MigrationRecorder {
    /// A recorder for pictures of at most `side` cells a side (at least 1).
    pub fn new(side: usize) -> Self {
        MigrationRecorder {
            side: side.max(1),
            frames: Vec::new(),
        }
    }

    /// Number of frames so far.
    pub fn frames(&self) -> usize {
        self.frames.len()
    }

    /// Adds the model's heights as the next frame.
    pub fn add(&mut self, m: &DuneModel) {
        let n = m.grid();
        let side = self.side.min(n);
        self.side = side;
        let g = m.grains();
        let mut f = Vec::with_capacity(side * side);
        for j in 0..side {
            let y = j * n / side;
            for i in 0..side {
                f.push(super::to_units(g[y * n + i * n / side]) as f32);
            }
        }
        self.frames.push(f);
    }

    /// Writes the GIF (`max_px` pixels a side, `delay_cs` hundredths of a second per frame),
    /// colour scale from 0 to the highest height of any frame.
    ///
    /// # Errors
    ///
    /// [`PlotError`] when there is no frame, or on an encoding or i/o failure.
    pub fn write(&self, path: &Path, max_px: u32, delay_cs: u16) -> Result<(), PlotError> {
        let max = self
            .frames
            .iter()
            .flatten()
            .fold(0.0f64, |m, &v| m.max(f64::from(v)));
        let side = self.side;
        let mut gif =
            GifWriter::create(path, side, side, false, max_px, &height_palette(), delay_cs)?;
        for f in &self.frames {
            gif.add_frame(&CellField {
                nx: side,
                ny: side,
                hex: false,
                states: height_states(f, max),
            })?;
        }
        gif.finish()
    }
}

/// A short description of a configuration for titles.
pub fn describe(cfg: &DuneConfig) -> String {
    match cfg.mode {
        Mode::Ripple => format!(
            "ripple mode, wind {}, grid {}, seed {}",
            cfg.wind, cfg.grid, cfg.seed
        ),
        Mode::Dune => format!(
            "dune mode, Q = {}, grid {}, seed {}",
            cfg.quantity, cfg.grid, cfg.seed
        ),
        Mode::Werner => format!(
            "Werner, Q = {}, L = {}, grid {}, seed {}",
            cfg.quantity, cfg.werner.hop, cfg.grid, cfg.seed
        ),
    }
}

/// [`describe`] for a run that starts from `start`: from a pile, the pile's height and radius
/// take the place of the sand quantity, which such a run does not use.
pub fn describe_run(cfg: &DuneConfig, start: &Start) -> String {
    let Start::Pile(p) = start else {
        return describe(cfg);
    };
    let pile = format!("one pile {} high, radius {}", p.height, p.radius);
    match cfg.mode {
        Mode::Ripple => format!(
            "ripple mode, wind {}, {pile}, grid {}, seed {}",
            cfg.wind, cfg.grid, cfg.seed
        ),
        Mode::Dune => format!("dune mode, {pile}, grid {}, seed {}", cfg.grid, cfg.seed),
        Mode::Werner => format!(
            "Werner, L = {}, {pile}, grid {}, seed {}",
            cfg.werner.hop, cfg.grid, cfg.seed
        ),
    }
}

/// The final heights and the dune bodies of a model, as two panels with a colour bar, under
/// the title `about` (the run in words: [`describe_run`]): the picture `cellsurf dunes --out`
/// writes.
pub fn draw_result(path: &Path, m: &DuneModel, about: &str) -> Result<(), PlotError> {
    let s = m.stats();
    let max = s.max_height.max(1e-6);
    let n = m.grid();
    let panels = [
        height_panel(&format!("heights, t = {}", s.iteration), m.grains(), n, max),
        bodies_panel(
            &format!(
                "{} bodies ({} spanning), bare {:.0}%",
                s.dune_bodies,
                s.spanning_bodies,
                100.0 * s.bare_fraction
            ),
            m.grains(),
            m.lattice(),
            s.threshold,
        ),
    ];
    draw_field(
        path,
        &format!("{about}  (wind →, cellsurf {VERSION})"),
        &panels,
        2,
        420,
        Some(max),
    )
}

/// Records `cfg` (as TOML, under the figure's name) in the PNGs this thread writes next.
fn record_parameters(figure: &str, cfgs: &[&DuneConfig]) {
    record_runs(figure, cfgs, &Start::Random);
}

/// [`record_parameters`] for runs that start from `start`: a pile's keys (those of the
/// scenario file, `start = "pile"`, `pile_centre`, `pile_height`, `pile_radius`) join each
/// run's, so that the record says the run that was made.
fn record_runs(figure: &str, cfgs: &[&DuneConfig], start: &Start) {
    #[derive(serde::Serialize)]
    struct PileKeys {
        start: &'static str,
        pile_centre: [f64; 2],
        pile_height: f64,
        pile_radius: f64,
    }
    let pile = match start {
        Start::Random => String::new(),
        Start::Pile(p) => toml::to_string(&PileKeys {
            start: "pile",
            pile_centre: p.centre,
            pile_height: p.height,
            pile_radius: p.radius,
        })
        .unwrap_or_default(),
    };
    let mut text = format!("figure = \"{figure}\"\n");
    for c in cfgs {
        text.push_str("\n[[run]]\n");
        let run = toml::to_string(c).unwrap_or_default();
        // (the run's own keys come before its [werner] table)
        let (keys, tables) = run.split_at(run.find("\n[werner]").unwrap_or(run.len()));
        text.push_str(keys);
        text.push_str(&pile);
        text.push_str(&tables.replace("[werner]", "[run.werner]"));
    }
    plot::set_png_parameters(Some(text));
}

/// Grains kept at some iterations: `(iteration, grains)`.
type Snapshots = Vec<(u64, Vec<u64>)>;

/// Runs `cfg`, keeping the grains at the iterations in `at`, and feeding every
/// `frame_every`-th iteration (if any) to `rec`. Returns the kept fields and the model.
fn run_with_snapshots(
    cfg: &DuneConfig,
    at: &[u64],
    rec: Option<(&mut MigrationRecorder, u64)>,
) -> Result<(Snapshots, DuneModel), FigureError> {
    let m = DuneModel::new(cfg).map_err(|e| FigureError::Model(e.to_string()))?;
    run_model_with_snapshots(m, at, rec)
}

/// [`run_with_snapshots`] from a model already built.
fn run_model_with_snapshots(
    mut m: DuneModel,
    at: &[u64],
    mut rec: Option<(&mut MigrationRecorder, u64)>,
) -> Result<(Snapshots, DuneModel), FigureError> {
    let cfg = m.config().clone();
    let mut kept = Vec::new();
    loop {
        let t = m.iteration();
        if at.contains(&t) {
            kept.push((t, m.grains().to_vec()));
        }
        if let Some((r, every)) = rec.as_mut()
            && (t.is_multiple_of(*every) || t == cfg.iterations)
        {
            r.add(&m);
        }
        if t >= cfg.iterations {
            break;
        }
        m.step();
    }
    Ok((kept, m))
}

/// Iterations between frames of `dunes_migration.gif` (51 frames over 500 iterations).
const GIF_EVERY: u64 = 10;
/// Side of `dunes_migration.gif`, pixels.
const GIF_PX: u32 = 360;

/// The run of scenario `name` (the article's dune mode at its defaults, grid 100, 500
/// iterations, seed 1, with a sand quantity `Q`): heights at t = 0, 100 and the last
/// iteration, and the dune bodies then, under the title `Q = ..., claim`.
fn dune_mode_figure(
    dir: &Path,
    name: &str,
    claim: &str,
    gif: Option<&str>,
) -> Result<Vec<PathBuf>, FigureError> {
    let s = read_scenario(name, scenario_text(SCENARIOS, name)?, DuneScenario::parse)?;
    let cfg = s.config;
    let claim = format!("Q = {}, {claim}", cfg.quantity);
    record_parameters(name, &[&cfg]);
    let at = [0, 100, cfg.iterations];
    let mut rec = MigrationRecorder::new(cfg.grid);
    let (kept, m) = run_with_snapshots(&cfg, &at, gif.map(|_| (&mut rec, GIF_EVERY)))?;
    let stats = m.stats_with_threshold(s.threshold);
    let max = kept
        .iter()
        .flat_map(|(_, g)| g.iter())
        .copied()
        .max()
        .map_or(1.0, super::to_units);
    let n = cfg.grid;
    let mut panels: Vec<FieldPanel> = kept
        .iter()
        .map(|(t, g)| height_panel(&format!("heights, t = {t}"), g, n, max))
        .collect();
    panels.push(bodies_panel(
        &format!(
            "t = {}: {} bodies ({} spanning), bare {:.0}%",
            stats.iteration,
            stats.dune_bodies,
            stats.spanning_bodies,
            100.0 * stats.bare_fraction
        ),
        m.grains(),
        m.lattice(),
        s.threshold,
    ));
    let path = dir.join(format!("{name}.png"));
    draw_field(
        &path,
        &format!("{claim}: {}  (wind →, cellsurf {VERSION})", describe(&cfg)),
        &panels,
        4,
        300,
        Some(max),
    )?;
    let mut out = vec![path];
    if let Some(g) = gif {
        let p = dir.join(g);
        rec.write(&p, GIF_PX, 8)?;
        out.push(p);
    }
    Ok(out)
}

fn q1_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    dune_mode_figure(
        dir,
        "dunes_q1",
        "separate barchan-like dunes",
        Some("dunes_migration.gif"),
    )
}

fn q3_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    dune_mode_figure(dir, "dunes_q3", "connected transverse ridges", None)
}

/// The run of scenario `dunes_barchan`: dune mode from one round pile (6 cell widths high,
/// radius 12 cells, a third of the way downwind on the default grid): a barchan forms, its
/// horns pointing downwind. Heights at t = 0, 50, 200 and the last iteration, and the dune
/// bodies then.
fn barchan_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let name = "dunes_barchan";
    let s = read_scenario(name, scenario_text(SCENARIOS, name)?, DuneScenario::parse)?;
    if !matches!(s.start, Start::Pile(_)) {
        return Err(FigureError::Model(format!(
            "{name}: its run starts from one pile (start = \"pile\")"
        )));
    }
    let cfg = s.config;
    record_runs(name, &[&cfg], &s.start);
    let n = cfg.grid;
    let m = DuneModel::with_start(&cfg, &s.start).map_err(|e| FigureError::Model(e.to_string()))?;
    let (kept, m) = run_model_with_snapshots(m, &[0, 50, 200, cfg.iterations], None)?;
    let max = kept
        .iter()
        .flat_map(|(_, g)| g.iter())
        .copied()
        .max()
        .map_or(1.0, super::to_units);
    let mut panels: Vec<FieldPanel> = kept
        .iter()
        .map(|(t, g)| height_panel(&format!("heights, t = {t}"), g, n, max))
        .collect();
    let st = m.stats_with_threshold(s.threshold);
    panels.push(bodies_panel(
        &format!(
            "t = {}: {} bodies, bare {:.0}%",
            st.iteration,
            st.dune_bodies,
            100.0 * st.bare_fraction
        ),
        m.grains(),
        m.lattice(),
        s.threshold,
    ));
    let path = dir.join(format!("{name}.png"));
    draw_field(
        &path,
        &format!(
            "One pile becomes a barchan, horns downwind: dune mode, grid {n}, seed {} (wind →, cellsurf {VERSION})",
            cfg.seed
        ),
        &panels,
        5,
        240,
        Some(max),
    )?;
    Ok(vec![path])
}

/// The Werner variant with little sand and much sand (scenarios `dunes_werner_q0.5` and
/// `dunes_werner_q3`: Q = 0.5 and Q = 3, 1000 iterations on the default grid): heights and
/// dune bodies of each, the runs alike but for Q.
fn werner_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let runs: Vec<DuneScenario> = scenario_panels(SCENARIOS, "dunes_werner")?
        .into_iter()
        .map(|(panel, text)| {
            read_scenario(&format!("dunes_werner_{panel}"), text, DuneScenario::parse)
        })
        .collect::<Result<_, _>>()?;
    let first = &runs[0].config;
    if runs.iter().any(|r| {
        let c = &r.config;
        (c.mode, c.grid, c.iterations, c.seed, &c.werner, r.threshold)
            != (
                Mode::Werner,
                first.grid,
                first.iterations,
                first.seed,
                &first.werner,
                runs[0].threshold,
            )
    }) {
        return Err(FigureError::Model(
            "dunes_werner: its panels are Werner runs that differ in Q only".into(),
        ));
    }
    let cfgs: Vec<&DuneConfig> = runs.iter().map(|r| &r.config).collect();
    record_parameters("dunes_werner", &cfgs);
    // The runs are independent: one per core.
    let models = cfgs
        .par_iter()
        .map(|c| run_with_snapshots(c, &[], None).map(|(_, m)| m))
        .collect::<Result<Vec<_>, _>>()?;
    let threshold = runs[0].threshold;
    let max = models
        .iter()
        .map(|m| m.stats_with_threshold(threshold).max_height)
        .fold(0.0f64, f64::max);
    let mut panels = Vec::new();
    for (c, m) in cfgs.iter().zip(&models) {
        let (q, s) = (c.quantity, m.stats_with_threshold(threshold));
        panels.push(height_panel(
            &format!("Q = {q}: heights, t = {}", s.iteration),
            m.grains(),
            m.grid(),
            max,
        ));
        panels.push(bodies_panel(
            &format!(
                "Q = {q}: {} bodies ({} spanning), bare {:.0}%",
                s.dune_bodies,
                s.spanning_bodies,
                100.0 * s.bare_fraction
            ),
            m.grains(),
            m.lattice(),
            threshold,
        ));
    }
    let w = &first.werner;
    let qs: Vec<String> = cfgs.iter().map(|c| format!("Q = {}", c.quantity)).collect();
    let path = dir.join("dunes_werner.png");
    draw_field(
        &path,
        &format!(
            "Werner (1995) variant: little sand ({}) and much sand ({})\n\
             L = {}, p_sand {}, p_bare {}, shadow {}°, repose {}°, slab {}\n\
             grid {}, seed {} (wind →, cellsurf {VERSION})",
            qs[0],
            qs[qs.len() - 1],
            w.hop,
            w.p_sand,
            w.p_bare,
            w.shadow_deg,
            w.repose_deg,
            w.slab,
            first.grid,
            first.seed
        ),
        &panels,
        2,
        330,
        Some(max),
    )?;
    Ok(vec![path])
}

/// Seeds per sand quantity in the error-against-time figure.
pub const ERROR_SEEDS: usize = 12;
/// Iterations between recorded observables in the error-against-time figure.
const ERROR_EVERY: u64 = 25;

/// The sand quantities of the error-against-time figure, and the first seed of each.
const ERROR_CASES: [(f64, u64); 2] = [(1.0, 1000), (3.0, 3000)];

fn error_config(q: f64) -> DuneConfig {
    DuneConfig {
        mode: Mode::Dune,
        quantity: q,
        ..DuneConfig::default()
    }
}

/// The error-against-time study behind `dunes_error_vs_time.png`: dune mode at the
/// defaults, 12 seeds for each of Q = 1 and Q = 3, one run per seed, for
/// `cellsurf converge dunes --part i/N` ([`crate::engine::study`]).
pub struct ErrorStudy;

impl crate::engine::study::Study for ErrorStudy {
    fn name(&self) -> &'static str {
        "dunes"
    }
    fn runs(&self) -> Vec<String> {
        ERROR_CASES
            .iter()
            .flat_map(|&(q, first)| {
                (0..ERROR_SEEDS as u64).map(move |k| format!("Q = {q} seed {}", first + k))
            })
            .collect()
    }
    fn run(&self, name: &str) -> Result<toml::Value, String> {
        let parsed = name
            .strip_prefix("Q = ")
            .and_then(|r| r.split_once(" seed "))
            .and_then(|(q, s)| Some((q.parse::<f64>().ok()?, s.parse::<u64>().ok()?)));
        let Some((q, seed)) = parsed else {
            return Err(format!("not a run of the study: {name}"));
        };
        let mut runs =
            study::run_seeds(&error_config(q), seed, 1, ERROR_EVERY).map_err(|e| e.to_string())?;
        crate::engine::study::record(&runs.pop())
    }
    fn draw(&self, records: &[toml::Value], dir: &Path) -> Result<Vec<PathBuf>, String> {
        let mut runs = records
            .iter()
            .map(crate::engine::study::from_record::<SeedRun>);
        let study = ERROR_CASES
            .iter()
            .map(|&(q, _)| {
                let seeds = runs
                    .by_ref()
                    .take(ERROR_SEEDS)
                    .collect::<Result<Vec<_>, _>>()?;
                Ok((q, seeds))
            })
            .collect::<Result<Vec<_>, String>>()?;
        error_figure_of(&study, dir).map_err(|e| e.to_string())
    }
}

fn curve_series(c: &ErrorCurve) -> Series {
    Series {
        label: c.label.clone(),
        x: c.points.iter().map(|p| p.cpu_s).collect(),
        y: c.points.iter().map(|p| p.std_error).collect(),
        points: true,
    }
}

/// A reference line `y = y0 (x / x0)^-1/2` over the range of `c`'s points.
fn inverse_sqrt(c: &ErrorCurve) -> Series {
    let (Some(a), Some(b)) = (c.points.first(), c.points.last()) else {
        return Series::default();
    };
    Series {
        label: "∝ (run time)^-1/2".into(),
        x: vec![a.cpu_s, b.cpu_s],
        y: vec![a.std_error, a.std_error * (a.cpu_s / b.cpu_s).sqrt()],
        points: false,
    }
}

/// The mean over seeds of an observable against iterations.
fn evolution_series(
    q: f64,
    ev: &[EvolutionPoint],
    get: fn(&EvolutionPoint) -> (f64, f64),
) -> Series {
    Series {
        label: format!("Q = {q}, mean of {ERROR_SEEDS} seeds"),
        x: ev.iter().map(|p| p.iteration as f64).collect(),
        y: ev.iter().map(|p| get(p).0).collect(),
        points: true,
    }
}

fn error_figure(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    crate::engine::study::run_whole(&ErrorStudy, dir).map_err(FigureError::Model)
}

fn error_figure_of(study: &[(f64, Vec<SeedRun>)], dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let base = DuneConfig {
        mode: Mode::Dune,
        ..DuneConfig::default()
    };
    plot::set_png_parameters(Some(format!(
        "figure = \"dunes_error_vs_time\"\nseeds = {ERROR_SEEDS}\nquantities = [1.0, 3.0]\n\n[run]\n{}",
        toml::to_string(&base)
            .unwrap_or_default()
            .replace("[werner]", "[run.werner]")
    )));
    let mut se_bare = Vec::new();
    let mut se_bodies = Vec::new();
    let mut ev_bare = Vec::new();
    let mut ev_bodies = Vec::new();
    for (q, runs) in study {
        let label = format!("Q = {q}");
        let cb = study::error_curve(&label, "bare_fraction", runs, |s| s.bare_fraction);
        let cn = study::error_curve(&label, "dune_bodies", runs, |s| s.dune_bodies as f64);
        se_bare.push(curve_series(&cb));
        se_bodies.push(curve_series(&cn));
        if *q == 1.0 {
            se_bare.push(inverse_sqrt(&cb));
            se_bodies.push(inverse_sqrt(&cn));
        }
        let ev = study::evolution(runs);
        ev_bare.push(evolution_series(*q, &ev, |p| p.bare));
        ev_bodies.push(evolution_series(*q, &ev, |p| p.bodies));
    }
    let charts = [
        Chart {
            title: "bare fraction: standard error of the mean".into(),
            x_label: "cumulative run time, s (one core)".into(),
            y_label: "standard error".into(),
            series: se_bare,
            log_x: true,
            log_y: true,
        },
        Chart {
            title: "dune bodies: standard error of the mean".into(),
            x_label: "cumulative run time, s (one core)".into(),
            y_label: "standard error".into(),
            series: se_bodies,
            log_x: true,
            log_y: true,
        },
        Chart {
            title: "bare fraction against iterations".into(),
            x_label: "iteration".into(),
            y_label: "bare fraction (h <= 1)".into(),
            series: ev_bare,
            log_x: false,
            log_y: false,
        },
        Chart {
            title: "dune bodies against iterations".into(),
            x_label: "iteration".into(),
            y_label: "bodies (h > 1, 8-neighbour torus)".into(),
            series: ev_bodies,
            log_x: false,
            log_y: false,
        },
    ];
    let path = dir.join("dunes_error_vs_time.png");
    plot::line_charts(
        &path,
        &format!(
            "Dune mode, grid 100, 500 iterations: 2..{ERROR_SEEDS} seeds per point (cellsurf {VERSION})"
        ),
        &charts,
        2,
        (640, 440),
    )?;
    Ok(vec![path])
}
