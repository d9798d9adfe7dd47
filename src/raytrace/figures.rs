//! The ray-tracing figures (feature `plot`), listed in [`FIGURES`]:
//!
//! - `ripple_fig5_raytrace`: the paper's Fig. 5. One row a sound-speed profile, each row one
//!   run of `cellsurf raytrace` read from its scenario file ([`SCENARIOS`]; isovelocity; a
//!   downward-refracting linear thermocline, c = 1525 - 2.5 z; a table with an
//!   upward-refracting bottom layer, 1500 m/s down to 10 m rising to 1506 m/s at 12 m): the
//!   profile on the left, the ray fan from S (10 m depth, 2 m above the bed, launch angles 1.5
//!   to 25 degrees) over 60 m of rippled floor in the middle, with the floor coloured lit or in
//!   shadow, and on the right one ripple tile (0.64 m at 40 m range) magnified, with rays
//!   arriving. The floor is the subcommand's section through the built-in generated ripple
//!   field ([`RippleSurface::generated`](super::RippleSurface::generated), seed 1) along its middle row, 94 tiles (60.16 m)
//!   long, 12 m deep. Exaggerated: the gradients (2.5 and 3 m/s per metre, strong but seen in
//!   coastal thermoclines) so that the bending shows within 60 m; the vertical scale of the
//!   right panel.
//! - `raytrace_error_vs_time`: [`super::error_study`], arc-radius error and Snell drift against
//!   step size and CPU time per ray.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{
    Insonification, InsonifyOptions, Ray, RaytraceScenario, Seafloor, SoundSpeed, TraceOptions,
    Tracer, VERSION, error_study, insonify,
};
use crate::plot::{Chart, PlotError, Series, line_charts};
use crate::plot::{Figure, FigureError};

/// The figures.
pub const FIGURES: &[Figure] = &[
    Figure {
        name: "ripple_fig5_raytrace",
        about: "Sand ripple generator, Fig. 5: ray fans from S through three sound-speed profiles (isovelocity, thermocline, bottom inversion; gradients exaggerated) and the shadows they leave on the rippled floor",
        make: fig5,
    },
    Figure {
        name: "raytrace_error_vs_time",
        about: "Ray tracer: arc-radius error (linear profile) and Snell-invariant drift (linear, Munk) against step size and CPU time per ray",
        make: error_vs_time,
    },
];

fn model_err(e: impl std::fmt::Display) -> FigureError {
    FigureError::Model(e.to_string())
}

/// The scenario files of the rows of `ripple_fig5_raytrace` (`ripple_fig5_raytrace_PROFILE`),
/// by file name, in the figure's order.
pub const SCENARIOS: &[(&str, &str)] = crate::plot::scenario_files![
    "ripple_fig5_raytrace_isovelocity",
    "ripple_fig5_raytrace_thermocline",
    "ripple_fig5_raytrace_table",
];

/// The sound-speed tables the scenario files name, by the path written in them (from the
/// scenarios' folder).
pub const TABLES: &[(&str, &str)] = &[(
    "ripple_fig5_raytrace_table.csv",
    include_str!("../../scenarios/ripple_fig5_raytrace_table.csv"),
)];

/// The text of a table of [`TABLES`].
fn table(path: &str) -> Result<String, String> {
    TABLES
        .iter()
        .find(|(p, _)| *p == path)
        .map(|(_, t)| t.to_string())
        .ok_or_else(|| format!("not a table of the figures ({path})"))
}

/// The runs of Fig. 5, one a row, from [`SCENARIOS`]: alike but for the profile (the rows
/// share one floor and one fan).
pub fn fig5_runs() -> Result<Vec<RaytraceScenario>, FigureError> {
    let runs = crate::plot::scenario_panels(SCENARIOS, "ripple_fig5_raytrace")?
        .into_iter()
        .map(|(panel, text)| {
            crate::plot::read_scenario(&format!("ripple_fig5_raytrace_{panel}"), text, |t: &str| {
                RaytraceScenario::parse(t, &table)
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let first = &runs[0];
    if runs.iter().any(|r| {
        r.straight
            || RaytraceScenario {
                profile: first.profile.clone(),
                ..r.clone()
            } != *first
    }) {
        return Err(model_err(
            "ripple_fig5_raytrace: its rows are ray runs that differ in the profile only",
        ));
    }
    Ok(runs)
}

/// A row's title: the profile in words.
fn title(p: &SoundSpeed) -> String {
    match p {
        SoundSpeed::Isovelocity(c) => format!("isovelocity {c} m/s"),
        SoundSpeed::Linear { c0, g } if *g < 0.0 => {
            format!("thermocline: linear {c0} - {} z", -g)
        }
        SoundSpeed::Table(t) => {
            let (z, v) = (t.depths(), t.values());
            let n = z.len();
            let g = (v[n - 1] - v[n - 2]) / (z[n - 1] - z[n - 2]);
            let kind = if g > 0.0 { "inversion" } else { "gradient" };
            format!("table: bottom {kind} {g:+} m/s per m below {} m", z[n - 2])
        }
        p => p.describe(),
    }
}

/// The three profiles of Fig. 5, with their titles.
pub fn fig5_profiles() -> Result<Vec<(String, SoundSpeed)>, FigureError> {
    Ok(fig5_runs()?
        .into_iter()
        .map(|r| (title(&r.profile), r.profile))
        .collect())
}

/// The Fig. 5 floor: the scenarios' section through the generated ripple field (seed 1), 94
/// tiles (60.16 m) of its middle row.
pub fn fig5_floor() -> Result<Seafloor, FigureError> {
    fig5_runs()?[0].floor().map_err(model_err)
}

/// The insonification options of Fig. 5 over `floor`.
pub fn fig5_options(floor: &Seafloor) -> Result<InsonifyOptions, FigureError> {
    Ok(fig5_runs()?[0].options(floor))
}

struct Row {
    title: String,
    profile: SoundSpeed,
    /// The transducer S (range, depth), m.
    source: (f64, f64),
    /// The water depth of the floor's substrate, m (the depth axis).
    water_depth: f64,
    ins: Insonification,
    fan: Vec<Ray>,
    zoom_rays: Vec<Ray>,
}

const ZOOM: (f64, f64) = (40.0, 40.64);

fn fig5_row(run: RaytraceScenario, floor: &Seafloor) -> Result<Row, FigureError> {
    let t = Tracer::new(&run.profile, floor).map_err(model_err)?;
    let (sx, sz) = run.source;
    let angles = run.angles;
    let o = run.options(floor);
    let ins = insonify(&t, &run.fan(), &o).map_err(model_err)?;
    let show = TraceOptions {
        record: true,
        ..o.trace
    };
    let n = 24;
    let fan_rays = (0..n)
        .map(|i| {
            let a = angles.0 + (angles.1 - angles.0) * i as f64 / (n - 1) as f64;
            t.trace(sx, sz, a, &show)
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(model_err)?;
    // rays reaching the magnified tile: the launch angles of some of its lit vertices
    let lit: Vec<f64> = floor
        .xs()
        .iter()
        .zip(&ins.arrivals)
        .filter(|(x, _)| **x >= ZOOM.0 && **x <= ZOOM.1)
        .filter_map(|(_, a)| a.map(|a| a.launch_deg))
        .collect();
    let k = lit.len().div_ceil(14).max(1);
    let zoom_rays = lit
        .iter()
        .step_by(k)
        .map(|&a| t.trace(sx, sz, a, &show))
        .collect::<Result<Vec<_>, _>>()
        .map_err(model_err)?;
    Ok(Row {
        title: title(&run.profile),
        profile: run.profile,
        source: run.source,
        water_depth: run.water_depth,
        ins,
        fan: fan_rays,
        zoom_rays,
    })
}

const LIT: RGBColor = RGBColor(240, 150, 20);
const DARK: RGBColor = RGBColor(25, 25, 60);
const RAY: RGBColor = RGBColor(60, 120, 200);

fn fig5(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let runs = fig5_runs()?;
    let floor = runs[0].floor().map_err(model_err)?;
    let (source, angles) = (runs[0].source, runs[0].angles);
    let rows = runs
        .into_iter()
        .map(|r| fig5_row(r, &floor))
        .collect::<Result<Vec<_>, _>>()?;
    let (w_prof, w_fan, w_zoom, h_row, h_title) = (230u32, 820u32, 420u32, 300u32, 44u32);
    let (w, h) = (w_prof + w_fan + w_zoom, h_row * rows.len() as u32 + h_title);
    crate::plot::ensure_fonts();
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::drawing)?;
        let (top, rest) = root.split_vertically(h_title);
        top.draw(&Text::new(
            format!(
                "Fig. 5: ray fans from S ({} m deep, 2 m above the bed, {}-{} deg) and the shadows on a rippled floor (lit orange, shadow dark; cellsurf {VERSION})",
                source.1, angles.0, angles.1
            ),
            ((w / 2) as i32, (h_title / 2) as i32),
            ("sans-serif", 17.0, FontStyle::Bold)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center)),
        ))
        .map_err(PlotError::drawing)?;
        let bands = rest.split_evenly((rows.len(), 1));
        for (row, band) in rows.iter().zip(bands.iter()) {
            let (a, bc) = band.split_horizontally(w_prof);
            let (b, c) = bc.split_horizontally(w_fan);
            draw_profile(&a, row)?;
            draw_fan(&b, row, &floor)?;
            draw_zoom(&c, row, &floor)?;
        }
        root.present().map_err(PlotError::drawing)?;
    }
    let png = crate::plot::encode_png(&buf, w, h)?;
    let path = dir.join("ripple_fig5_raytrace.png");
    crate::engine::io::write_atomic(&path, &png).map_err(PlotError::Io)?;
    Ok(vec![path])
}

fn depth_fmt(v: &f64) -> String {
    format!("{}", (-v * 100.0).round() / 100.0 + 0.0)
}

fn draw_profile<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    row: &Row,
) -> Result<(), PlotError> {
    let zs: Vec<f64> = (0..=240)
        .map(|i| row.water_depth * i as f64 / 240.0)
        .collect();
    let cs: Vec<f64> = zs.iter().map(|&z| row.profile.speed(z)).collect();
    let lo = cs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = cs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let pad = ((hi - lo) * 0.15).max(3.0);
    let mut ctx = ChartBuilder::on(area)
        .margin(8)
        .caption("c(z)", ("sans-serif", 14))
        .x_label_area_size(34)
        .y_label_area_size(40)
        .build_cartesian_2d(lo - pad..hi + pad, -row.water_depth - 0.3..0.0)
        .map_err(PlotError::drawing)?;
    ctx.configure_mesh()
        .x_desc("m/s")
        .y_desc("depth (m)")
        .x_labels(3)
        .y_labels(7)
        .y_label_formatter(&depth_fmt)
        .x_label_formatter(&|v| format!("{v:.0}"))
        .label_style(("sans-serif", 11))
        .light_line_style(RGBColor(240, 240, 240))
        .draw()
        .map_err(PlotError::drawing)?;
    ctx.draw_series(LineSeries::new(
        cs.iter().zip(&zs).map(|(&c, &z)| (c, -z)),
        RED.stroke_width(2),
    ))
    .map_err(PlotError::drawing)?;
    let cs_s = row.profile.speed(row.source.1);
    ctx.draw_series([Circle::new((cs_s, -row.source.1), 4, BLACK.filled())])
        .map_err(PlotError::drawing)?;
    Ok(())
}

fn draw_floor<DB: DrawingBackend, CT>(
    ctx: &mut ChartContext<'_, DB, CT>,
    floor: &Seafloor,
    ins: &Insonification,
    x_range: (f64, f64),
    width: u32,
) -> Result<(), PlotError>
where
    CT: plotters::coord::CoordTranslate<From = (f64, f64)>,
{
    let (xs, zs) = (floor.xs(), floor.zs());
    let segs = (0..xs.len() - 1).filter(|&i| xs[i + 1] >= x_range.0 && xs[i] <= x_range.1);
    ctx.draw_series(segs.map(|i| {
        let lit = ins.arrivals[i].is_some() && ins.arrivals[i + 1].is_some();
        let col = if lit { LIT } else { DARK };
        PathElement::new(
            vec![(xs[i], -zs[i]), (xs[i + 1], -zs[i + 1])],
            col.stroke_width(width),
        )
    }))
    .map_err(PlotError::drawing)?;
    Ok(())
}

fn draw_fan<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    row: &Row,
    floor: &Seafloor,
) -> Result<(), PlotError> {
    let (x0, x1) = floor.x_range();
    let lit = row.ins.lit_fraction(
        floor.xs().partition_point(|&x| x < 5.0)..floor.xs().partition_point(|&x| x <= x1),
    );
    let mut ctx = ChartBuilder::on(area)
        .margin(8)
        .caption(
            format!(
                "{}: {:.0} % of the floor beyond 5 m insonified",
                row.title,
                lit * 100.0
            ),
            ("sans-serif", 14),
        )
        .x_label_area_size(34)
        .y_label_area_size(40)
        .build_cartesian_2d(x0..x1, -row.water_depth - 0.3..0.0)
        .map_err(PlotError::drawing)?;
    ctx.configure_mesh()
        .x_desc("range (m)")
        .y_desc("depth (m)")
        .y_label_formatter(&depth_fmt)
        .label_style(("sans-serif", 11))
        .light_line_style(RGBColor(240, 240, 240))
        .draw()
        .map_err(PlotError::drawing)?;
    for r in &row.fan {
        ctx.draw_series(LineSeries::new(
            r.path.iter().map(|p| (p[0], -p[1])),
            RAY.stroke_width(1),
        ))
        .map_err(PlotError::drawing)?;
    }
    draw_floor(&mut ctx, floor, &row.ins, (x0, x1), 4)?;
    let s = (row.source.0, -row.source.1);
    ctx.draw_series([EmptyElement::at(s)
        + TriangleMarker::new((0, 0), 7, RED.filled())
        + Text::new("S", (8, -16), ("sans-serif", 15).into_font())])
        .map_err(PlotError::drawing)?;
    Ok(())
}

/// The part of the segment a-b inside the box (Liang-Barsky), if any.
fn clip(
    a: (f64, f64),
    b: (f64, f64),
    (xl, xh): (f64, f64),
    (yl, yh): (f64, f64),
) -> Option<[(f64, f64); 2]> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - xl),
        (dx, xh - a.0),
        (-dy, a.1 - yl),
        (dy, yh - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some([
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    ])
}

fn draw_zoom<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    row: &Row,
    floor: &Seafloor,
) -> Result<(), PlotError> {
    let (i0, i1) = (
        floor.xs().partition_point(|&x| x < ZOOM.0),
        floor.xs().partition_point(|&x| x <= ZOOM.1),
    );
    let zs = &floor.zs()[i0..i1];
    let zlo = zs.iter().copied().fold(f64::INFINITY, f64::min);
    let zhi = zs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let pad = (zhi - zlo) * 0.6 + 1e-3;
    let yr = (-zhi - pad * 0.4, -zlo + pad);
    let (w, h) = area.dim_in_pixel();
    let exaggeration = ((ZOOM.1 - ZOOM.0) / f64::from(w.saturating_sub(60).max(1)))
        / ((yr.1 - yr.0) / f64::from(h.saturating_sub(70).max(1)));
    let lit = row.ins.lit_fraction(i0..i1);
    let mut ctx = ChartBuilder::on(area)
        .margin(8)
        .caption(
            format!(
                "one tile at 40 m: {:.0} % lit (vertical x{:.0})",
                lit * 100.0,
                exaggeration
            ),
            ("sans-serif", 14),
        )
        .x_label_area_size(34)
        .y_label_area_size(52)
        .build_cartesian_2d(ZOOM.0..ZOOM.1, yr.0..yr.1)
        .map_err(PlotError::drawing)?;
    ctx.configure_mesh()
        .x_desc("range (m)")
        .y_desc("depth (m)")
        .x_labels(5)
        .y_labels(5)
        .y_label_formatter(&|v| format!("{:.3}", -v))
        .label_style(("sans-serif", 11))
        .light_line_style(RGBColor(240, 240, 240))
        .draw()
        .map_err(PlotError::drawing)?;
    for r in &row.zoom_rays {
        let segs: Vec<[(f64, f64); 2]> = r
            .path
            .windows(2)
            .filter_map(|p| clip((p[0][0], -p[0][1]), (p[1][0], -p[1][1]), ZOOM, yr))
            .collect();
        ctx.draw_series(
            segs.into_iter()
                .map(|s| PathElement::new(s.to_vec(), RAY.stroke_width(1))),
        )
        .map_err(PlotError::drawing)?;
    }
    draw_floor(&mut ctx, floor, &row.ins, ZOOM, 3)?;
    Ok(())
}

/// The step sizes of the error-against-time figure, m.
const ERROR_STEPS: [f64; 8] = [4000.0, 2000.0, 1000.0, 500.0, 250.0, 100.0, 50.0, 20.0];

/// The study behind `raytrace_error_vs_time.png` as independent runs (one per step size), for
/// `cellsurf converge raytrace --part i/N` ([`crate::engine::study`]).
pub struct ErrorStudy;

impl crate::engine::study::Study for ErrorStudy {
    fn name(&self) -> &'static str {
        "raytrace"
    }
    fn parallel(&self) -> bool {
        false // each run times its rays
    }
    fn runs(&self) -> Vec<String> {
        ERROR_STEPS.iter().map(|ds| format!("ds {ds} m")).collect()
    }
    fn run(&self, name: &str) -> Result<toml::Value, String> {
        let ds: f64 = name
            .strip_prefix("ds ")
            .and_then(|r| r.strip_suffix(" m"))
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| format!("not a run of the study: {name}"))?;
        let e = error_study(&[ds]).map_err(|e| e.to_string())?;
        crate::engine::study::record(&e[0])
    }
    fn draw(&self, records: &[toml::Value], dir: &Path) -> Result<Vec<PathBuf>, String> {
        let e = records
            .iter()
            .map(crate::engine::study::from_record::<super::StepError>)
            .collect::<Result<Vec<_>, _>>()?;
        draw_error(&e, dir).map_err(|e| e.to_string())
    }
}

fn error_vs_time(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    crate::engine::study::run_whole(&ErrorStudy, dir).map_err(FigureError::Model)
}

fn draw_error(e: &[super::StepError], dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let series = |x: &dyn Fn(&super::StepError) -> f64| {
        vec![
            Series {
                label: "arc radius error, linear".into(),
                x: e.iter().map(x).collect(),
                y: e.iter().map(|p| p.arc_radius_error).collect(),
                points: true,
            },
            Series {
                label: "Snell drift, linear".into(),
                x: e.iter().map(x).collect(),
                y: e.iter().map(|p| p.snell_drift).collect(),
                points: true,
            },
            Series {
                label: "Snell drift, Munk".into(),
                x: e.iter().map(x).collect(),
                y: e.iter().map(|p| p.munk_snell_drift).collect(),
                points: true,
            },
        ]
    };
    let charts = [
        Chart {
            title: "relative error against step size".into(),
            x_label: "ds (m)".into(),
            y_label: "largest relative error over the ray".into(),
            series: series(&|p| p.ds),
            log_x: true,
            log_y: true,
        },
        Chart {
            title: "relative error against run time".into(),
            x_label: "CPU seconds per ray (linear, 30 km)".into(),
            y_label: "largest relative error over the ray".into(),
            series: series(&|p| p.cpu_s_per_ray),
            log_x: true,
            log_y: true,
        },
    ];
    let path = dir.join("raytrace_error_vs_time.png");
    line_charts(
        &path,
        &format!(
            "RK4 ray tracer: linear profile (10 deg, R = 89.6 km) and Munk (cellsurf {VERSION})"
        ),
        &charts,
        2,
        (620, 460),
    )?;
    Ok(vec![path])
}
