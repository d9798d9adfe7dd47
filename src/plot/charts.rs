//! A grid of line charts with legends in one PNG.

use std::cell::RefCell;
use std::path::Path;

use std::ops::Range;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{
    AsRangedCoord, DefaultFormatting, KeyPointHint, Ranged, ValueFormatter,
};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{PlotError, check_picture_size, encode_png, ensure_fonts};

/// One data series of a [`Chart`]: points `(x[i], y[i])` for `i < min(x.len(), y.len())`.
///
/// Points with a non-finite coordinate (NaN, infinite), or a non-positive one on a log axis, are
/// skipped, and the line is broken there rather than joined across the gap.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// Legend entry; an empty label leaves the series out of the legend.
    pub label: String,
    /// Abscissae.
    pub x: Vec<f64>,
    /// Ordinates.
    pub y: Vec<f64>,
    /// Draw a marker at every point as well as the line.
    pub points: bool,
}

/// One chart of [`line_charts`]: a mesh with axis labels, its series and a legend.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Chart {
    /// Caption above the chart (may be empty).
    pub title: String,
    /// Label of the x axis.
    pub x_label: String,
    /// Label of the y axis.
    pub y_label: String,
    /// The series, coloured in turn from plotters' `Palette99`.
    pub series: Vec<Series>,
    /// Logarithmic x axis (non-positive x values are skipped).
    pub log_x: bool,
    /// Logarithmic y axis (non-positive y values are skipped).
    pub log_y: bool,
}

/// Smallest accepted chart width and height, in pixels.
const MIN_CHART_PX: u32 = 64;

/// Draws `charts` as a grid of `cols` columns (fewer when there are fewer charts), each
/// `chart_px = (width, height)` pixels, under the figure `title` (omitted when empty), and
/// writes the PNG to `path` atomically.
///
/// Each chart has a mesh, axis labels, a caption, and a legend of the labelled series placed in
/// a corner where it covers no marker or line; where every corner holds data, the y range is
/// stretched upwards (at most twice) to free an upper corner. Axis ranges cover the finite
/// (and, on log axes, positive) data with a 5% margin (a decade's fraction on log axes); a
/// chart without usable data gets a default range `0..1` (`1..10` on log axes). Series with `points` get a filled
/// circle at every point.
///
/// # Errors
///
/// [`PlotError::InvalidInput`] for an empty `charts`, `cols == 0`, a `chart_px` side below 64
/// pixels, or a figure larger than 16384 pixels a side or 64 megapixels;
/// [`PlotError::Drawing`], [`PlotError::Encoding`] or [`PlotError::Io`] when drawing, encoding
/// or writing fails.
pub fn line_charts(
    path: &Path,
    title: &str,
    charts: &[Chart],
    cols: usize,
    chart_px: (u32, u32),
) -> Result<(), PlotError> {
    if charts.is_empty() {
        return Err(PlotError::invalid("charts", "is empty"));
    }
    note(path, title, charts, cols, chart_px);
    if cols == 0 {
        return Err(PlotError::invalid("cols", "must be positive"));
    }
    let (cw, ch) = chart_px;
    if cw < MIN_CHART_PX || ch < MIN_CHART_PX {
        return Err(PlotError::invalid(
            "chart_px",
            format!("is {cw} x {ch}, each side must be at least {MIN_CHART_PX} pixels"),
        ));
    }
    let cols = cols.min(charts.len());
    let rows = charts.len().div_ceil(cols);
    let title_font = (f64::from(ch) / 16.0).clamp(14.0, 34.0);
    let title_h = if title.is_empty() {
        0
    } else {
        (title_font * 1.9).round() as u32
    };
    let width = cols as u64 * u64::from(cw);
    let height = rows as u64 * u64::from(ch) + u64::from(title_h);
    check_picture_size("chart_px", width, height)?;
    let (width, height) = (width as u32, height as u32);

    ensure_fonts();
    let mut buf = vec![255u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::drawing)?;
        let grid_area = if title_h > 0 {
            let (top, rest) = root.split_vertically(title_h);
            let style = ("sans-serif", title_font, FontStyle::Bold)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center));
            top.draw(&Text::new(
                title.to_string(),
                ((width / 2) as i32, (title_h / 2) as i32),
                style,
            ))
            .map_err(PlotError::drawing)?;
            rest
        } else {
            root.clone()
        };
        let areas = grid_area.split_evenly((rows, cols));
        for (chart, area) in charts.iter().zip(areas.iter()) {
            draw_chart_any(area, chart)?;
        }
        root.present().map_err(PlotError::drawing)?;
    }
    let png = encode_png(&buf, width, height)?;
    crate::engine::io::write_atomic(path, &png)?;
    Ok(())
}

/// The usable points of a series, split into runs between skipped points.
fn segments(s: &Series, log_x: bool, log_y: bool) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut run = Vec::new();
    for (&x, &y) in s.x.iter().zip(s.y.iter()) {
        let ok = x.is_finite() && y.is_finite() && (!log_x || x > 0.0) && (!log_y || y > 0.0);
        if ok {
            run.push((x, y));
        } else if !run.is_empty() {
            out.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        out.push(run);
    }
    out
}

/// Axis range `lo..hi` covering `values` with a margin; log axes pad in log space.
fn axis_range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return if log { (1.0, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        let (l0, l1) = (lo.log10(), hi.log10());
        let pad = if l1 > l0 { 0.05 * (l1 - l0) } else { 0.5 };
        let (a, b) = (10f64.powf(l0 - pad), 10f64.powf(l1 + pad));
        if a > 0.0 && b.is_finite() && b > a {
            (a, b)
        } else {
            (lo, hi.max(lo * 10.0))
        }
    } else {
        let span = hi - lo;
        let pad = if span > 0.0 && span.is_finite() {
            0.05 * span
        } else {
            (0.1 * lo.abs()).max(1.0)
        };
        let (a, b) = (lo - pad, hi + pad);
        let (a, b) = if a.is_finite() && b.is_finite() && b > a {
            (a, b)
        } else {
            (lo, hi)
        };
        // plotters' tick search needs a finite span: cap ranges near the limits of f64.
        if (b - a).is_finite() {
            (a, b)
        } else {
            (a.max(-f64::MAX / 2.0), b.min(f64::MAX / 2.0))
        }
    }
}

/// The four legend corners, in order of preference: (position, is right, is upper).
const CORNERS: [(SeriesLabelPosition, bool, bool); 4] = [
    (SeriesLabelPosition::UpperRight, true, true),
    (SeriesLabelPosition::UpperLeft, false, true),
    (SeriesLabelPosition::LowerRight, true, false),
    (SeriesLabelPosition::LowerLeft, false, false),
];

/// Most a y range is stretched to free room for the legend above the data (the data then
/// fill at least half the chart's height); beyond it the legend covers the fewest data.
const MAX_STRETCH: f64 = 2.0;

/// Where a chart's legend goes (with no labelled series there is none: the first corner, the
/// range unchanged): a corner it covers no data in, else the y range stretched
/// upwards (at most [`MAX_STRETCH`] times) so that the data pass under an upper corner, else
/// the corner covering the fewest data. The data are the series' markers and their lines
/// (sampled every few pixels), in pixels of the plotting area `plot` (width, height); the
/// legend is `legend` pixels (width, height) and sits 5 pixels inside the corner, as
/// plotters draws it.
fn place_legend(
    segs: &[Vec<(f64, f64)>],
    x: (f64, f64),
    y: (f64, f64),
    chart: &Chart,
    plot: (f64, f64),
    legend: (f64, f64),
) -> (SeriesLabelPosition, (f64, f64)) {
    let norm = |v: f64, (a, b): (f64, f64), log: bool| {
        if log {
            (v.log10() - a.log10()) / (b.log10() - a.log10())
        } else {
            (v - a) / (b - a)
        }
    };
    if chart.series.iter().all(|s| s.label.is_empty()) {
        return (CORNERS[0].0.clone(), y);
    }
    let (pw, ph) = plot;
    let (lw, lh) = legend;
    // (u, v): the data in axis-normalised coordinates (v up), points and line samples.
    let mut samples: Vec<(f64, f64)> = Vec::new();
    for run in segs {
        let uv: Vec<(f64, f64)> = run
            .iter()
            .map(|&(px, py)| (norm(px, x, chart.log_x), norm(py, y, chart.log_y)))
            .collect();
        samples.extend(uv.iter().copied());
        for w in uv.windows(2) {
            let (du, dv) = ((w[1].0 - w[0].0) * pw, (w[1].1 - w[0].1) * ph);
            let n = (du.hypot(dv) / 3.0).ceil().min(1e4) as usize;
            samples.extend((1..n).map(|i| {
                let t = i as f64 / n as f64;
                (
                    w[0].0 + t * (w[1].0 - w[0].0),
                    w[0].1 + t * (w[1].1 - w[0].1),
                )
            }));
        }
    }
    // The legend's box in normalised coordinates, with 3 pixels to spare around it.
    let span_x = |right: bool| {
        let (a, b) = if right {
            (pw - 5.0 - lw - 3.0, pw)
        } else {
            (0.0, 5.0 + lw + 3.0)
        };
        (a / pw, b / pw)
    };
    let top = 1.0 - (5.0 + lh + 3.0) / ph;
    let bottom = (5.0 + lh + 3.0) / ph;
    let covered = |right: bool, upper: bool| {
        let (u0, u1) = span_x(right);
        samples
            .iter()
            .filter(|&&(u, v)| u >= u0 && u <= u1 && if upper { v >= top } else { v <= bottom })
            .count()
    };
    let counts: Vec<usize> = CORNERS.iter().map(|c| covered(c.1, c.2)).collect();
    if let Some(k) = (0..4).find(|&k| counts[k] == 0) {
        return (CORNERS[k].0.clone(), y);
    }
    // Stretch the range upwards so the highest datum under an upper corner's box falls below
    // it: on the normalised scale, v' = v / stretch.
    let stretch = |right: bool| {
        let (u0, u1) = span_x(right);
        let vmax = samples
            .iter()
            .filter(|&&(u, _)| u >= u0 && u <= u1)
            .map(|&(_, v)| v)
            .fold(0.0, f64::max);
        (vmax / top).max(1.0)
    };
    if top > 0.0 {
        let (k, s) = [0, 1]
            .into_iter()
            .map(|k| (k, stretch(CORNERS[k].1)))
            .fold((0, f64::INFINITY), |b, c| if c.1 < b.1 { c } else { b });
        if s <= MAX_STRETCH {
            let y = if chart.log_y {
                let (a, b) = (y.0.log10(), y.1.log10());
                (y.0, 10f64.powf(a + (b - a) * s))
            } else {
                (y.0, y.0 + (y.1 - y.0) * s)
            };
            return (CORNERS[k].0.clone(), y);
        }
    }
    let best = (0..4).min_by_key(|&k| counts[k]).unwrap_or(0);
    (CORNERS[best].0.clone(), y)
}

/// Computes ranges and dispatches to [`draw_chart`] with linear or log axis types.
fn draw_chart_any<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &Chart,
) -> Result<(), PlotError> {
    let segs: Vec<Vec<Vec<(f64, f64)>>> = chart
        .series
        .iter()
        .map(|s| segments(s, chart.log_x, chart.log_y))
        .collect();
    let all = || segs.iter().flatten().flatten();
    let xr = axis_range(all().map(|p| p.0), chart.log_x);
    let yr = axis_range(all().map(|p| p.1), chart.log_y);
    let flat: Vec<Vec<(f64, f64)>> = segs.iter().flatten().cloned().collect();
    let (w, h) = area.dim_in_pixel();
    let n_y = (h / 30).clamp(4, 12) as usize;
    // Widest y tick label, to size the label area (plotters' ticks are close to these).
    let y_chars = |yr: (f64, f64)| {
        let ticks = if chart.log_y {
            log_ticks(yr.0, yr.1, n_y)
        } else {
            linear_ticks(yr.0, yr.1, n_y)
        };
        ticks
            .iter()
            .map(|&v| format_tick(v).chars().count())
            .max()
            .unwrap_or(1)
    };
    let caption_font = (f64::from(h) / 20.0).clamp(11.0, 26.0);
    let label_font = (caption_font * 0.72).max(10.0);
    // The plotting area as plotters lays it out (margins of 8 pixels, the caption with its
    // padding, the label areas of [`draw_chart`]) and the legend's size, to place it.
    let caption_h = if chart.title.is_empty() {
        0.0
    } else {
        let (_, th) = area
            .estimate_text_size(&chart.title, &TextStyle::from(("sans-serif", caption_font)))
            .map_err(PlotError::drawing)?;
        f64::from(th + 2 * (th / 2).min(5))
    };
    let plot = (
        f64::from(w) - 16.0 - (label_font * (0.62 * y_chars(yr) as f64 + 2.6)).floor(),
        f64::from(h) - 16.0 - caption_h - (label_font * 3.2).floor(),
    );
    let font = TextStyle::from(("sans-serif", label_font));
    let mut text = MultiLineText::<_, &str>::new((0, 0), &font);
    for s in chart.series.iter().filter(|s| !s.label.is_empty()) {
        text.push_line(s.label.as_str());
    }
    let (tw, th) = text
        .estimate_dimension()
        .map_err(|e| PlotError::drawing(format!("{e:?}")))?;
    // plotters' legend: its text, a 30-pixel key and 10-pixel margins all round.
    let legend = (f64::from(tw) + 30.0 + 20.0, f64::from(th) + 20.0);
    let (corner, yr) = if plot.0 > 0.0 && plot.1 > 0.0 {
        place_legend(&flat, xr, yr, chart, plot, legend)
    } else {
        (CORNERS[0].0.clone(), yr)
    };
    let plan = Plan {
        corner,
        n_x: (w / 45).clamp(4, 12) as usize,
        n_y,
        y_chars: y_chars(yr),
        label_font,
        caption_font,
    };
    let (x, y) = ((xr.0..xr.1), (yr.0..yr.1));
    let (lx, ly) = (LogAxis::new(xr), LogAxis::new(yr));
    match (chart.log_x, chart.log_y) {
        (false, false) => draw_chart(area, chart, &segs, plan, x, y),
        (true, false) => draw_chart(area, chart, &segs, plan, lx, y),
        (false, true) => draw_chart(area, chart, &segs, plan, x, ly),
        (true, true) => draw_chart(area, chart, &segs, plan, lx, ly),
    }
}

/// Layout choices made from the data before the axis types are fixed.
struct Plan {
    /// Legend corner.
    corner: SeriesLabelPosition,
    /// Most x tick labels.
    n_x: usize,
    /// Most y tick labels.
    n_y: usize,
    /// Characters in the widest y tick label.
    y_chars: usize,
    /// Font size of tick labels, axis descriptions and the legend, pixels.
    label_font: f64,
    /// Font size of the caption, pixels.
    caption_font: f64,
}

/// Draws one chart with the given axis specifications.
fn draw_chart<DB, X, Y>(
    area: &DrawingArea<DB, Shift>,
    chart: &Chart,
    segs: &[Vec<Vec<(f64, f64)>>],
    plan: Plan,
    x_spec: X,
    y_spec: Y,
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let (caption_font, label_font) = (plan.caption_font, plan.label_font);
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(8)
        .x_label_area_size((label_font * 3.2) as u32)
        .y_label_area_size((label_font * (0.62 * plan.y_chars as f64 + 2.6)) as u32);
    if !chart.title.is_empty() {
        builder.caption(&chart.title, ("sans-serif", caption_font));
    }
    let mut ctx = builder
        .build_cartesian_2d(x_spec, y_spec)
        .map_err(PlotError::drawing)?;
    ctx.configure_mesh()
        .x_desc(chart.x_label.as_str())
        .y_desc(chart.y_label.as_str())
        .x_labels(plan.n_x)
        .y_labels(plan.n_y)
        .x_label_formatter(&|v| format_tick(*v))
        .y_label_formatter(&|v| format_tick(*v))
        .label_style(("sans-serif", label_font))
        .axis_desc_style(("sans-serif", label_font * 1.1))
        .max_light_lines(4)
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(205, 205, 205))
        .draw()
        .map_err(PlotError::drawing)?;

    let marker = (label_font * 0.3).clamp(2.0, 5.0) as u32;
    let mut any_label = false;
    for (k, (s, runs)) in chart.series.iter().zip(segs.iter()).enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let line = color.stroke_width(2);
        let anno = ctx
            .draw_series(runs.iter().map(|r| PathElement::new(r.clone(), line)))
            .map_err(PlotError::drawing)?;
        if !s.label.is_empty() {
            any_label = true;
            // Without markers the legend's circle has radius 0 and lies on the line.
            let r = if s.points { marker } else { 0 };
            anno.label(s.label.as_str()).legend(move |(lx, ly)| {
                EmptyElement::at((lx, ly))
                    + PathElement::new(vec![(0, 0), (20, 0)], color.stroke_width(2))
                    + Circle::new((10, 0), r, color.filled())
            });
        }
        if s.points {
            ctx.draw_series(
                runs.iter()
                    .flatten()
                    .map(|&p| Circle::new(p, marker, color.filled())),
            )
            .map_err(PlotError::drawing)?;
        }
    }
    if any_label {
        ctx.configure_series_labels()
            .position(plan.corner)
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(150, 150, 150))
            .label_font(("sans-serif", label_font))
            .draw()
            .map_err(PlotError::drawing)?;
    }
    Ok(())
}

/// A base-10 logarithmic axis over `lo..hi` (`0 < lo < hi`) whose ticks fall on 1, 2, 5 (or
/// 1..9) times powers of ten as space allows, with linear ticks on ranges too narrow to hold two
/// such values. (plotters' own log axis labels every 1..9 multiple, which overlaps.)
#[derive(Debug, Clone)]
struct LogAxis {
    lo: f64,
    hi: f64,
}

impl LogAxis {
    fn new((lo, hi): (f64, f64)) -> Self {
        LogAxis { lo, hi }
    }
}

impl Ranged for LogAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let (a, b) = (self.lo.log10(), self.hi.log10());
        // Non-positive values are never drawn (they are filtered out); map them far below.
        let t = if *value > 0.0 {
            (value.log10() - a) / (b - a)
        } else {
            -1.0
        };
        let px = f64::from(limit.0) + t * f64::from(limit.1 - limit.0);
        px.round().clamp(-1.0e7, 1.0e7) as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        log_ticks(self.lo, self.hi, hint.max_num_points())
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

/// At most `max` tick values in `lo..=hi` (`0 < lo < hi`) for a log axis.
fn log_ticks(lo: f64, hi: f64, max: usize) -> Vec<f64> {
    if max == 0 || !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let (d0, d1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let with = |mantissas: &[f64], stride: i32| -> Vec<f64> {
        let mut v = Vec::new();
        for d in (d0..=d1).filter(|d| d.rem_euclid(stride) == 0) {
            for &m in mantissas {
                let t = m * 10f64.powi(d);
                if t >= lo * (1.0 - 1e-12) && t <= hi * (1.0 + 1e-12) {
                    v.push(t);
                }
            }
        }
        v
    };
    let sets: [&[f64]; 3] = [
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
        &[1.0, 2.0, 5.0],
        &[1.0],
    ];
    let mut ticks = Vec::new();
    for set in sets {
        ticks = with(set, 1);
        if ticks.len() <= max {
            break;
        }
    }
    if ticks.len() > max {
        let decades = ticks.len();
        let stride = decades.div_ceil(max) as i32;
        ticks = with(&[1.0], stride);
    }
    if ticks.len() < 2 {
        ticks = linear_ticks(lo, hi, max);
    }
    ticks
}

/// At most `max` evenly spaced "nice" values (steps of 1, 2 or 5 times a power of ten) in
/// `lo..=hi`.
fn linear_ticks(lo: f64, hi: f64, max: usize) -> Vec<f64> {
    if max == 0 || hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return Vec::new();
    }
    let raw = (hi - lo) / max as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last)
        .take(max.max(1))
        .map(|k| k as f64 * step)
        .collect()
}

/// Tick label: up to 4 significant digits (all integer digits below 1e6) without trailing
/// zeros; scientific notation outside 1e-3..1e6.
fn format_tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let a = v.abs();
    if !(1e-3..1e6).contains(&a) {
        let s = format!("{v:.3e}");
        // Trim the mantissa's trailing zeros: 2.50e3 -> 2.5e3, 1.00e-4 -> 1e-4.
        match s.split_once('e') {
            Some((m, e)) => {
                let m = if m.contains('.') {
                    m.trim_end_matches('0').trim_end_matches('.')
                } else {
                    m
                };
                format!("{m}e{e}")
            }
            None => s,
        }
    } else {
        let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        let s = format!("{v:.decimals$}");
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        };
        if s == "-0" { "0".into() } else { s }
    }
}

#[cfg(test)]
mod unit {
    use super::*;

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(format_tick(0.0), "0");
        assert_eq!(format_tick(0.30000000000000004), "0.3");
        assert_eq!(format_tick(25.0), "25");
        assert_eq!(format_tick(-1.5), "-1.5");
        assert_eq!(format_tick(2500.0), "2500");
        assert_eq!(format_tick(148000.0), "148000");
        assert_eq!(format_tick(2.5e7), "2.5e7");
        assert_eq!(format_tick(1.234e-5), "1.234e-5");
        assert_eq!(format_tick(1e-4), "1e-4");
    }

    #[test]
    fn log_ticks_thin_out_with_space() {
        assert_eq!(
            log_ticks(0.9, 60.0, 10),
            vec![1.0, 2.0, 5.0, 10.0, 20.0, 50.0]
        );
        assert_eq!(log_ticks(0.9, 60.0, 3), vec![1.0, 10.0]);
        assert_eq!(log_ticks(1e-6, 2e6, 4), vec![1e-4, 1.0, 1e4]);
        // Narrow range without a power of ten: linear ticks.
        assert_eq!(
            log_ticks(1.5, 8.0, 10),
            vec![2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]
        );
        assert!(log_ticks(1.5, 8.0, 0).is_empty());
    }

    #[test]
    fn ranges_skip_non_finite_and_pad() {
        let s = Series {
            label: String::new(),
            x: vec![0.0, 1.0, f64::NAN, 3.0, 4.0],
            y: vec![1.0, 0.0, 5.0, f64::INFINITY, 2.0],
            points: false,
        };
        let segs = segments(&s, false, true);
        assert_eq!(segs, vec![vec![(0.0, 1.0)], vec![(4.0, 2.0)]]);
        let (a, b) = axis_range([1.0, 3.0].into_iter(), false);
        assert!((a - 0.9).abs() < 1e-12 && (b - 3.1).abs() < 1e-12);
        assert_eq!(axis_range(std::iter::empty(), true), (1.0, 10.0));
        let (a, b) = axis_range([-1e308, 1e308].into_iter(), false);
        assert!((b - a).is_finite() && b > a);
        let (a, b) = axis_range([5.0].into_iter(), true);
        assert!(a > 0.0 && a < 5.0 && b > 5.0);
    }

    /// A chart with one labelled series (the points are passed apart, as runs).
    fn labelled() -> Chart {
        Chart {
            series: vec![Series {
                label: "a".into(),
                ..Series::default()
            }],
            ..Chart::default()
        }
    }

    /// Runs of points and a chart's x and y ranges.
    type Laid = (Vec<Vec<(f64, f64)>>, (f64, f64), (f64, f64));

    /// The runs of `series` (x, y) and their padded ranges, as [`draw_chart_any`] has them.
    fn laid_out(series: &[(&[f64], &[f64])]) -> Laid {
        let segs: Vec<Vec<(f64, f64)>> = series
            .iter()
            .map(|(x, y)| x.iter().copied().zip(y.iter().copied()).collect())
            .collect();
        let xr = axis_range(segs.iter().flatten().map(|p| p.0), false);
        let yr = axis_range(segs.iter().flatten().map(|p| p.1), false);
        (segs, xr, yr)
    }

    #[test]
    fn the_legend_takes_a_free_corner() {
        let x = [0.0, 1.0, 2.0, 3.0, 4.0];
        let down = [4.0, 3.0, 2.0, 1.0, 0.0];
        // A rising diagonal fills the upper right and lower left corners; a falling one
        // leaves the upper right free, which is preferred.
        for (y, want) in [
            (x, SeriesLabelPosition::UpperLeft),
            (down, SeriesLabelPosition::UpperRight),
        ] {
            let (segs, xr, yr) = laid_out(&[(&x, &y)]);
            let chart = labelled();
            let got = place_legend(&segs, xr, yr, &chart, (400.0, 300.0), (120.0, 60.0));
            assert_eq!(got, (want, yr));
        }
    }

    #[test]
    fn the_legend_stretches_the_range_when_every_corner_holds_data() {
        // Lines along the top and the bottom: no corner is free.
        let x = [0.0, 10.0];
        let (segs, xr, yr) = laid_out(&[(&x, &[1.0, 1.0]), (&x, &[0.0, 0.0])]);
        let chart = labelled();
        let (plot, legend) = ((400.0, 300.0), (120.0, 60.0));
        let (c, y) = place_legend(&segs, xr, yr, &chart, plot, legend);
        assert_eq!(c, SeriesLabelPosition::UpperRight);
        assert_eq!(y.0, yr.0);
        assert!(
            y.1 > yr.1 && y.1 - y.0 <= MAX_STRETCH * (yr.1 - yr.0),
            "{y:?} {yr:?}"
        );
        // On the stretched range the top line passes under the legend (5 px inset, 3 px
        // spare), and placing again finds that corner free, without stretching further.
        let v = (1.0 - y.0) / (y.1 - y.0);
        assert!((1.0 - v) * plot.1 >= 5.0 + legend.1 + 3.0 - 1e-9, "{v}");
        assert_eq!(place_legend(&segs, xr, y, &chart, plot, legend), (c, y));
        // A legend taller than the chart allows: no stretch, the corner covering least.
        let (_, y) = place_legend(&segs, xr, yr, &chart, plot, (120.0, 200.0));
        assert_eq!(y, yr);
        // A chart without labels has no legend, and keeps its range.
        let (_, y) = place_legend(&segs, xr, yr, &Chart::default(), plot, legend);
        assert_eq!(y, yr);
    }
}

/// Everything [`line_charts`] drew: redrawing it gives the same PNG.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartTable {
    /// The figure's title.
    pub title: String,
    /// Charts per row.
    pub cols: usize,
    /// Size of each chart, pixels.
    pub chart_px: (u32, u32),
    /// The parameters text recorded in the PNG.
    pub png_parameters: Option<String>,
    /// The charts.
    pub charts: Vec<Chart>,
}

thread_local! {
    static RECORDED: RefCell<Option<Vec<(std::path::PathBuf, ChartTable)>>> =
        const { RefCell::new(None) };
}

/// Starts (`true`) or stops (`false`) recording this thread's [`line_charts`] calls (output
/// file and everything drawn, see [`ChartTable`]); stopping returns what was recorded since
/// the start.
pub fn record_charts(on: bool) -> Vec<(std::path::PathBuf, ChartTable)> {
    RECORDED.with(|r| {
        let mut r = r.borrow_mut();
        let got = r.take().unwrap_or_default();
        if on {
            *r = Some(Vec::new());
        }
        got
    })
}

/// Called by [`line_charts`]: keeps its output file and inputs while recording.
fn note(path: &Path, title: &str, charts: &[Chart], cols: usize, chart_px: (u32, u32)) {
    RECORDED.with(|r| {
        if let Some(v) = r.borrow_mut().as_mut() {
            v.push((
                path.to_path_buf(),
                ChartTable {
                    title: title.to_string(),
                    cols,
                    chart_px,
                    png_parameters: super::png_parameters(),
                    charts: charts.to_vec(),
                },
            ));
        }
    });
}
