//! Figures and animations of lattice fields and time series (cargo feature `plot`).
//!
//! The principal types are:
//!
//! - [`CellField`]: a square or hexagonal lattice of cell states (0 = empty, 1 = surface or
//!   interface site, 2 = occupied, 3.. = extra classes), drawn with a [`Palette`];
//! - [`Panel`]: a titled field, several of which [`lattice_panels`] draws as a grid into one PNG;
//! - [`Series`] and [`Chart`]: line charts (optionally with markers and log axes), drawn as a grid
//!   with legends into one PNG by [`line_charts`];
//! - [`ColorRamp`], [`Sheet`] and [`Mark`] (module [`field`]): continuous colour maps and
//!   the one renderer of every model's continuous fields (heights, grain size, wind);
//! - [`GifWriter`]: an animated GIF of successive [`CellField`] frames;
//! - [`Figure`] and [`FigureError`]: a published figure that `cellsurf figures` regenerates;
//!   every model lists its own, and the crate's figure registry gathers them;
//! - [`PlotError`]: the error type of everything here.
//!
//! [`rasterize`] turns a field into RGB8 pixels; the lattice panels and the GIF frames both use
//! it, so the figures and the animation look the same.
//!
//! Everything is drawn in memory and written with [`crate::engine::io::write_atomic`], so a reader never
//! sees a partial file. Text uses the DejaVu Sans font bundled by the `dejavu` crate (registered
//! with plotters on first use), so no system font library is needed.
//!
//! # Geometry
//!
//! Square lattice: cell `(x, y)` is the unit square centred at `(x, y)`. Hexagonal lattice
//! (offset rows): cell `(x, y)` is centred at `(x + 0.5 * (y mod 2), y * sqrt(3) / 2)` and drawn
//! as a pointy-top regular hexagon of width 1, so the hexagons tile without gaps. Row 0 is at the
//! bottom of the picture, and pictures keep the physical aspect ratio of the field (see
//! [`CellField::physical_size`]).

mod animation;
mod charts;
pub mod field;
mod figure;
mod panels;
mod raster;
pub mod table;
#[cfg(test)]
mod tests;

pub use animation::{GIF_FRAMES, GifWriter};
pub use charts::{Chart, ChartTable, Series, line_charts, record_charts};
pub use field::{ColorRamp, Mark, Sheet};
pub(crate) use figure::scenario_files;
pub use figure::{Figure, FigureError, read_scenario, scenario_panels, scenario_text};
pub use panels::{Panel, lattice_panels};
pub use raster::{BACKGROUND, CellField, Palette, rasterize};

use std::sync::Once;

/// Errors from drawing, encoding and writing figures.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// Writing the output file failed.
    #[error("i/o error: {0}")]
    Io(#[from] std::io::Error),
    /// plotters failed to draw (text, chart, mesh), with its message.
    #[error("drawing failed: {0}")]
    Drawing(String),
    /// Encoding the PNG or GIF failed, with the encoder's message.
    #[error("encoding failed: {0}")]
    Encoding(String),
    /// A parameter is unusable (zero size, empty list, mismatched lengths, too large).
    #[error("invalid {name}: {reason}")]
    InvalidInput {
        /// The parameter at fault, e.g. `cols`, `panels[1].field.nx`.
        name: String,
        /// Why it was rejected.
        reason: String,
    },
}

impl PlotError {
    /// A [`PlotError::InvalidInput`] for parameter `name`.
    pub(crate) fn invalid(name: impl Into<String>, reason: impl Into<String>) -> Self {
        PlotError::InvalidInput {
            name: name.into(),
            reason: reason.into(),
        }
    }

    /// A [`PlotError::Drawing`] from any plotters error.
    pub(crate) fn drawing(e: impl std::fmt::Display) -> Self {
        PlotError::Drawing(e.to_string())
    }
}

/// Largest width or height, in pixels, of any picture produced here.
pub(crate) const MAX_SIDE: u32 = 16_384;
/// Largest number of pixels of any picture produced here (64 megapixels).
pub(crate) const MAX_PIXELS: u64 = 64 * 1024 * 1024;

/// Checks a picture size against [`MAX_SIDE`] and [`MAX_PIXELS`]; `name` names the parameter
/// that determined it.
pub(crate) fn check_picture_size(name: &str, w: u64, h: u64) -> Result<(), PlotError> {
    if w == 0 || h == 0 {
        return Err(PlotError::invalid(name, "gives a picture of zero size"));
    }
    if w > u64::from(MAX_SIDE) || h > u64::from(MAX_SIDE) || w * h > MAX_PIXELS {
        return Err(PlotError::invalid(
            name,
            format!(
                "gives a picture of {w} x {h} pixels, more than {MAX_SIDE} per side or {MAX_PIXELS} in all"
            ),
        ));
    }
    Ok(())
}

/// Registers the bundled DejaVu Sans (regular and bold) as plotters' `sans-serif` family, once
/// per process.
pub(crate) fn ensure_fonts() {
    static FONTS: Once = Once::new();
    FONTS.call_once(|| {
        use plotters::style::{FontStyle, register_font};
        // The bundled fonts are valid; were registration to fail anyway, drawing text reports
        // `FontUnavailable` as a `PlotError::Drawing`.
        let _ = register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular());
        let _ = register_font("sans-serif", FontStyle::Bold, dejavu::sans::bold());
    });
}

/// Encodes `rgb` (RGB8, `w * h * 3` bytes, row 0 at the top) as a PNG in memory.
pub(crate) fn encode_png(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>, PlotError> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        // Provenance: the version always, the run's parameters when the caller set them.
        let enc_err = |e: png::EncodingError| PlotError::Encoding(e.to_string());
        enc.add_text_chunk(
            "Software".to_string(),
            format!("cellsurf {}", crate::engine::VERSION),
        )
        .map_err(enc_err)?;
        if let Some(p) = PNG_PARAMETERS.with(|m| m.borrow().clone()) {
            enc.add_itxt_chunk("parameters".to_string(), p)
                .map_err(enc_err)?;
        }
        let mut writer = enc.write_header().map_err(enc_err)?;
        writer.write_image_data(rgb).map_err(enc_err)?;
        writer.finish().map_err(enc_err)?;
    }
    Ok(out)
}

thread_local! {
    static PNG_PARAMETERS: std::cell::RefCell<Option<String>> =
        const { std::cell::RefCell::new(None) };
}

/// Sets the parameters text recorded (as an iTXt chunk named `parameters`) in every PNG this
/// thread writes from now on; `None` records the version only. Every PNG carries a
/// `Software` chunk with the cellsurf version.
pub fn set_png_parameters(text: Option<String>) {
    PNG_PARAMETERS.with(|m| *m.borrow_mut() = text);
}

/// Runs `f` with `text` as the parameters text of the PNGs this thread writes
/// ([`set_png_parameters`]), then restores the text in force before.
pub fn with_png_parameters<T>(text: Option<String>, f: impl FnOnce() -> T) -> T {
    let before = png_parameters();
    set_png_parameters(text);
    let r = f();
    set_png_parameters(before);
    r
}

/// The parameters text in force on this thread ([`set_png_parameters`]).
pub fn png_parameters() -> Option<String> {
    PNG_PARAMETERS.with(|m| m.borrow().clone())
}
