//! Animated GIF of successive cell fields.

use std::path::{Path, PathBuf};

use super::PlotError;
use super::raster::{BACKGROUND, CellField, Palette, palette_index, rasterize_codes};
use crate::engine::count::CountRange;

/// The frames of an animation after its initial state (`--gif-frames`).
pub const GIF_FRAMES: CountRange = CountRange::new(1, 2000, "1 to 2000");

/// Most palette colours a GIF frame can use: 256 less one entry for the background.
const GIF_STATE_COLORS: usize = 255;

/// Writes an animated GIF of [`CellField`] frames, drawn as by [`super::rasterize`].
///
/// Frames are encoded into memory as they are added (indexed colour with one global palette:
/// the [`Palette`]'s colours, at most 255, plus the white background; no quantisation, so
/// colours are exact); [`GifWriter::finish`] writes the file atomically. The animation loops
/// forever. A comment extension records the cellsurf version and the parameters set by
/// [`super::set_png_parameters`] when the writer is created.
///
/// ```no_run
/// # use cellsurf::plot::{CellField, GifWriter, Palette};
/// # fn main() -> Result<(), cellsurf::plot::PlotError> {
/// let mut gif = GifWriter::create("growth.gif".as_ref(), 200, 100, true, 600, &Palette::flame(), 8)?;
/// let mut field = CellField::new(200, 100, true);
/// for step in 0..10 {
///     field.states[step] = 2;
///     gif.add_frame(&field)?;
/// }
/// gif.finish()?;
/// # Ok(()) }
/// ```
pub struct GifWriter {
    path: PathBuf,
    nx: usize,
    ny: usize,
    hex: bool,
    width: u16,
    height: u16,
    delay_cs: u16,
    /// Raster code (0 = background, `s + 1` = state `s`) to GIF palette index.
    lut: Vec<u8>,
    encoder: gif::Encoder<Vec<u8>>,
    frames: usize,
}

impl std::fmt::Debug for GifWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GifWriter")
            .field("path", &self.path)
            .field("nx", &self.nx)
            .field("ny", &self.ny)
            .field("hex", &self.hex)
            .field("width", &self.width)
            .field("height", &self.height)
            .field("delay_cs", &self.delay_cs)
            .field("frames", &self.frames)
            .finish_non_exhaustive()
    }
}

impl GifWriter {
    /// Starts an animation of `nx` by `ny` fields (`hex`: hexagonal lattice) to be written to
    /// `path`. The picture's longer side is `max_px` pixels (at most 65535), the other follows
    /// the field's physical aspect ratio ([`CellField::physical_size`]); each frame shows for
    /// `frame_delay_cs` hundredths of a second.
    ///
    /// # Errors
    ///
    /// [`PlotError::InvalidInput`] when `nx`, `ny` or `max_px` is zero, `max_px` is above 65535
    /// or the picture would exceed 64 megapixels; [`PlotError::Encoding`] on an encoder failure.
    pub fn create(
        path: &Path,
        nx: usize,
        ny: usize,
        hex: bool,
        max_px: u32,
        palette: &Palette,
        frame_delay_cs: u16,
    ) -> Result<Self, PlotError> {
        if nx == 0 {
            return Err(PlotError::invalid("nx", "must be positive"));
        }
        if ny == 0 {
            return Err(PlotError::invalid("ny", "must be positive"));
        }
        if max_px == 0 || max_px > u32::from(u16::MAX) {
            return Err(PlotError::invalid(
                "max_px",
                format!("is {max_px}, must be in 1..=65535"),
            ));
        }
        let (pw, ph) = CellField {
            nx,
            ny,
            hex,
            states: Vec::new(),
        }
        .physical_size();
        let side = f64::from(max_px);
        let (w, h) = if pw >= ph {
            (max_px, ((side * ph / pw).round() as u32).clamp(1, max_px))
        } else {
            (((side * pw / ph).round() as u32).clamp(1, max_px), max_px)
        };
        if u64::from(w) * u64::from(h) > super::MAX_PIXELS {
            return Err(PlotError::invalid(
                "max_px",
                format!("gives {w} x {h} pixels, more than {}", super::MAX_PIXELS),
            ));
        }

        // Global palette: the state colours, then the background.
        let mut colors = palette.colors.clone();
        colors.truncate(GIF_STATE_COLORS);
        if colors.is_empty() {
            colors.push(palette.color(0));
        }
        let bg_index = colors.len();
        let mut table = Vec::with_capacity((colors.len() + 1) * 3);
        for c in colors.iter().chain(std::iter::once(&BACKGROUND)) {
            table.extend_from_slice(&[c.0, c.1, c.2]);
        }
        let mut lut = Vec::with_capacity(257);
        lut.push(bg_index as u8);
        for s in 0..=255u8 {
            lut.push(palette_index(colors.len(), s).unwrap_or(0) as u8);
        }

        let enc_err = |e: gif::EncodingError| PlotError::Encoding(e.to_string());
        let mut encoder =
            gif::Encoder::new(Vec::new(), w as u16, h as u16, &table).map_err(enc_err)?;
        encoder.set_repeat(gif::Repeat::Infinite).map_err(enc_err)?;
        // Provenance, as in every PNG: a comment with the version, and the run's parameters
        // when the caller set them (`set_png_parameters`).
        let mut comment = format!("cellsurf {}", crate::engine::VERSION);
        if let Some(p) = super::png_parameters() {
            comment.push_str("\nparameters:\n");
            comment.push_str(&p);
        }
        encoder
            .write_raw_extension(
                gif::AnyExtension(gif::Extension::Comment as u8),
                &[comment.as_bytes()],
            )
            .map_err(enc_err)?;
        Ok(GifWriter {
            path: path.to_path_buf(),
            nx,
            ny,
            hex,
            width: w as u16,
            height: h as u16,
            delay_cs: frame_delay_cs,
            lut,
            encoder,
            frames: 0,
        })
    }

    /// Picture size in pixels, `(width, height)`.
    pub fn size(&self) -> (u32, u32) {
        (u32::from(self.width), u32::from(self.height))
    }

    /// Number of frames added so far.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Draws `field` as the next frame.
    ///
    /// # Errors
    ///
    /// [`PlotError::InvalidInput`] unless the field has the `nx`, `ny` and `hex` given to
    /// [`GifWriter::create`] and `nx * ny` states; [`PlotError::Encoding`] on an encoder
    /// failure.
    pub fn add_frame(&mut self, field: &CellField) -> Result<(), PlotError> {
        field.validate("field")?;
        if (field.nx, field.ny, field.hex) != (self.nx, self.ny, self.hex) {
            return Err(PlotError::invalid(
                "field",
                format!(
                    "is {} x {} (hex: {}), the animation was created for {} x {} (hex: {})",
                    field.nx, field.ny, field.hex, self.nx, self.ny, self.hex
                ),
            ));
        }
        let codes = rasterize_codes(field, u32::from(self.width), u32::from(self.height));
        let pixels: Vec<u8> = codes.iter().map(|&c| self.lut[usize::from(c)]).collect();
        let mut frame = gif::Frame::from_indexed_pixels(self.width, self.height, pixels, None);
        frame.delay = self.delay_cs;
        self.encoder
            .write_frame(&frame)
            .map_err(|e| PlotError::Encoding(e.to_string()))?;
        self.frames += 1;
        Ok(())
    }

    /// Ends the animation and writes the file atomically.
    ///
    /// # Errors
    ///
    /// [`PlotError::InvalidInput`] naming `frames` when no frame was added (nothing is
    /// written); [`PlotError::Encoding`] or [`PlotError::Io`] when finishing or writing fails.
    pub fn finish(self) -> Result<(), PlotError> {
        if self.frames == 0 {
            return Err(PlotError::invalid("frames", "no frame was added"));
        }
        let bytes = self
            .encoder
            .into_inner()
            .map_err(|e| PlotError::Encoding(e.to_string()))?;
        crate::engine::io::write_atomic(&self.path, &bytes)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gif_records_the_version_and_the_parameters() {
        let dir = std::env::temp_dir().join(format!("cellsurf-gif-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.gif");
        super::super::set_png_parameters(Some("n = 2.5\nseed = 7\n".to_string()));
        let mut gif = GifWriter::create(&path, 8, 8, false, 64, &Palette::flame(), 8).unwrap();
        super::super::set_png_parameters(None);
        gif.add_frame(&CellField::new(8, 8, false)).unwrap();
        gif.finish().unwrap();
        let bytes = std::fs::read(&path).unwrap();
        // A comment extension (0x21 0xFE) holding the text in one sub-block.
        let at = bytes
            .windows(2)
            .position(|w| w == [0x21, 0xFE])
            .expect("a comment extension");
        let len = usize::from(bytes[at + 2]);
        let text = String::from_utf8_lossy(&bytes[at + 3..at + 3 + len]).into_owned();
        assert!(
            text.starts_with(&format!("cellsurf {}", crate::engine::VERSION)),
            "{text}"
        );
        assert!(text.contains("n = 2.5\nseed = 7"), "{text}");
        // The file still decodes, one frame.
        let mut d = gif::DecodeOptions::new()
            .read_info(std::fs::File::open(&path).unwrap())
            .unwrap();
        assert!(d.read_next_frame().unwrap().is_some());
        assert!(d.read_next_frame().unwrap().is_none());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
