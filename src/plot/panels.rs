//! A grid of titled lattice pictures in one PNG.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::raster::{CellField, Palette, rasterize};
use super::{PlotError, check_picture_size, encode_png, ensure_fonts};

/// A titled field: one picture of [`lattice_panels`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Panel {
    /// Title drawn above the picture (may be empty).
    pub title: String,
    /// The field to draw.
    pub field: CellField,
}

/// Outer margin and gap between panels, in pixels.
const GAP: u32 = 10;

/// Draws `panels` as a grid of `cols` columns (fewer when there are fewer panels), each with its
/// title above it, under the figure `title` (omitted when empty), and writes the PNG to `path`
/// atomically.
///
/// Every panel gets a box of the same size whose longer side is `panel_px` pixels and whose
/// aspect ratio is that of the largest physical width by the largest physical height among the
/// fields ([`CellField::physical_size`]); each field is scaled to fit its box keeping its own
/// aspect ratio (see [`rasterize`] for the sampling) and framed by a thin grey line. Font sizes
/// follow `panel_px`.
///
/// # Errors
///
/// [`PlotError::InvalidInput`] naming the parameter for an empty `panels`, `cols == 0`,
/// `panel_px == 0`, a field with `nx` or `ny` zero or a `states` length other than `nx * ny`
/// (e.g. `panels[1].field.nx`), or a figure larger than 16384 pixels a side or 64 megapixels;
/// [`PlotError::Drawing`], [`PlotError::Encoding`] or [`PlotError::Io`] when drawing, encoding
/// or writing fails.
pub fn lattice_panels(
    path: &Path,
    title: &str,
    panels: &[Panel],
    cols: usize,
    palette: &Palette,
    panel_px: u32,
) -> Result<(), PlotError> {
    if panels.is_empty() {
        return Err(PlotError::invalid("panels", "is empty"));
    }
    if cols == 0 {
        return Err(PlotError::invalid("cols", "must be positive"));
    }
    if panel_px == 0 {
        return Err(PlotError::invalid("panel_px", "must be positive"));
    }
    for (k, p) in panels.iter().enumerate() {
        p.field.validate(&format!("panels[{k}].field"))?;
    }

    // Common box: the envelope of the physical sizes, longer side panel_px.
    let (pw, ph) = panels
        .iter()
        .map(|p| p.field.physical_size())
        .fold((0.0f64, 0.0f64), |(a, b), (w, h)| (a.max(w), b.max(h)));
    let (box_w, box_h) = if pw >= ph {
        (
            panel_px,
            ((f64::from(panel_px) * ph / pw).round() as u32).max(1),
        )
    } else {
        (
            ((f64::from(panel_px) * pw / ph).round() as u32).max(1),
            panel_px,
        )
    };

    let cols = cols.min(panels.len());
    let rows = panels.len().div_ceil(cols);
    let panel_font = (f64::from(panel_px) / 22.0).clamp(12.0, 28.0);
    let title_font = panel_font * 1.3;
    let panel_title_h = (panel_font * 1.7).round() as u32;
    let fig_title_h = if title.is_empty() {
        0
    } else {
        (title_font * 1.9).round() as u32
    };
    let cell_w = u64::from(box_w) + u64::from(GAP);
    let cell_h = u64::from(panel_title_h) + u64::from(box_h) + u64::from(GAP);
    let width = cols as u64 * cell_w + u64::from(GAP);
    let height = u64::from(fig_title_h) + rows as u64 * cell_h + u64::from(GAP) / 2;
    check_picture_size("panel_px", width, height)?;
    let (width, height) = (width as u32, height as u32);

    ensure_fonts();
    let mut buf = vec![255u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::drawing)?;
        if !title.is_empty() {
            let avail = f64::from(width.saturating_sub(2 * GAP));
            let title_font = fit_font(&root, title, title_font, FontStyle::Bold, avail);
            let style = ("sans-serif", title_font, FontStyle::Bold)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center));
            root.draw(&Text::new(
                title.to_string(),
                ((width / 2) as i32, (fig_title_h / 2) as i32),
                style,
            ))
            .map_err(PlotError::drawing)?;
        }
        let panel_style = ("sans-serif", panel_font)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center));
        let frame = RGBColor(160, 160, 160);
        for (k, p) in panels.iter().enumerate() {
            let (r, c) = ((k / cols) as u32, (k % cols) as u32);
            let x0 = GAP + c * cell_w as u32;
            let y0 = fig_title_h + r * cell_h as u32;
            if !p.title.is_empty() {
                let size = fit_font(
                    &root,
                    &p.title,
                    panel_font,
                    FontStyle::Normal,
                    f64::from(box_w),
                );
                let style = if size < panel_font {
                    ("sans-serif", size)
                        .into_font()
                        .color(&BLACK)
                        .pos(Pos::new(HPos::Center, VPos::Center))
                } else {
                    panel_style.clone()
                };
                root.draw(&Text::new(
                    p.title.clone(),
                    ((x0 + box_w / 2) as i32, (y0 + panel_title_h / 2) as i32),
                    style,
                ))
                .map_err(PlotError::drawing)?;
            }
            let by = y0 + panel_title_h;
            let pixels = rasterize(&p.field, palette, box_w, box_h);
            let bitmap =
                BitMapElement::with_owned_buffer((x0 as i32, by as i32), (box_w, box_h), pixels)
                    .ok_or_else(|| PlotError::Drawing("panel bitmap size mismatch".into()))?;
            root.draw(&bitmap).map_err(PlotError::drawing)?;
            // Frame the picture itself (the field is centred in its box).
            let (fw, fh) = p.field.physical_size();
            let scale = (f64::from(box_w) / fw).min(f64::from(box_h) / fh);
            let left = x0 as i32 + ((f64::from(box_w) - fw * scale) / 2.0).floor() as i32;
            let top = by as i32 + ((f64::from(box_h) - fh * scale) / 2.0).floor() as i32;
            let right = x0 as i32 + ((f64::from(box_w) + fw * scale) / 2.0).ceil() as i32;
            let bottom = by as i32 + ((f64::from(box_h) + fh * scale) / 2.0).ceil() as i32;
            root.draw(&Rectangle::new(
                [(left - 1, top - 1), (right, bottom)],
                frame.stroke_width(1),
            ))
            .map_err(PlotError::drawing)?;
        }
        root.present().map_err(PlotError::drawing)?;
    }
    let png = encode_png(&buf, width, height)?;
    crate::engine::io::write_atomic(path, &png)?;
    Ok(())
}

/// `size`, shrunk so that `text` in that font is at most `avail` pixels wide.
fn fit_font<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    text: &str,
    size: f64,
    style: FontStyle,
    avail: f64,
) -> f64 {
    match root.estimate_text_size(
        text,
        &("sans-serif", size, style)
            .into_font()
            .into_text_style(root),
    ) {
        Ok((w, _)) if f64::from(w) > avail && w > 0 => size * avail / f64::from(w),
        _ => size,
    }
}
