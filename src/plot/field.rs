//! Continuous-colour fields: the one renderer of every model's height, grain-size, impedance
//! and wind pictures.
//!
//! - [`ColorRamp`]: the continuous colour maps (a sand ramp for dune heights, viridis, and
//!   the five-anchor viridis of the ripple figures), sampled at any number of levels
//!   ([`ColorRamp::lut`]) or turned into a lattice [`Palette`] ([`ColorRamp::palette`]).
//! - [`states_over`] and [`finite_range`]: values scaled to palette states for the lattice
//!   panels (state 0 kept for "no data").
//! - [`Sheet`] and [`Mark`]: a picture laid out by a model (titles, RGB pictures, frames,
//!   colour bars, arrows) and drawn here, in the order the marks were added, with the bundled
//!   font, then written atomically as a PNG. The layouts stay with the figures; the drawing
//!   exists once.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::raster::Palette;
use super::{PlotError, check_picture_size, encode_png, ensure_fonts};

/// A continuous colour map from low (`t = 0`) to high (`t = 1`) values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorRamp {
    /// Dark bare ground to pale sand crests (lightness increases monotonically): the dune
    /// heights.
    Sand,
    /// The viridis map (dark violet, blue, green, yellow) as plotters gives it: the
    /// wind-ripple heights, as the notebook draws them.
    Viridis,
    /// Viridis from five anchors, linearly interpolated and rounded: the ripple and tiling
    /// figures.
    Viridis5,
}

/// The anchors of [`ColorRamp::Sand`], low to high.
const SAND: [RGBColor; 6] = [
    RGBColor(24, 24, 44),
    RGBColor(70, 44, 72),
    RGBColor(138, 72, 62),
    RGBColor(200, 124, 64),
    RGBColor(236, 190, 112),
    RGBColor(255, 244, 210),
];

/// The anchors `(t, (r, g, b))` of [`ColorRamp::Viridis5`].
const VIRIDIS5: [(f64, (f64, f64, f64)); 5] = [
    (0.0, (68.0, 1.0, 84.0)),
    (0.25, (59.0, 82.0, 139.0)),
    (0.5, (33.0, 145.0, 140.0)),
    (0.75, (94.0, 201.0, 98.0)),
    (1.0, (253.0, 231.0, 37.0)),
];

impl ColorRamp {
    /// The colour at `t` in `[0, 1]` (clamped; NaN gives the lowest colour).
    pub fn color(self, t: f64) -> RGBColor {
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        match self {
            ColorRamp::Sand => DerivedColorMap::new(&SAND).get_color_normalized(t, 0.0, 1.0),
            ColorRamp::Viridis => ViridisRGB::get_color_normalized(t, 0.0, 1.0),
            ColorRamp::Viridis5 => {
                let a = &VIRIDIS5;
                let k = a.iter().rposition(|x| x.0 <= t).unwrap_or(0).min(3);
                let s = (t - a[k].0) / (a[k + 1].0 - a[k].0);
                let m = |p: f64, q: f64| (p + (q - p) * s).round() as u8;
                let (c0, c1) = (a[k].1, a[k + 1].1);
                RGBColor(m(c0.0, c1.0), m(c0.1, c1.1), m(c0.2, c1.2))
            }
        }
    }

    /// The ramp sampled at `levels` evenly spaced points from 0 to 1 (at least 2).
    pub fn lut(self, levels: usize) -> Vec<RGBColor> {
        let levels = levels.max(2);
        (0..levels)
            .map(|i| self.color(i as f64 / (levels - 1) as f64))
            .collect()
    }

    /// A lattice palette of `levels` colours of the ramp: state `s` has colour
    /// `s / (levels - 1)`.
    pub fn palette(self, levels: usize) -> Palette {
        Palette {
            colors: self.lut(levels),
        }
    }
}

/// Palette states for `v` scaled over `[lo, hi]`: 1 to 255 for finite values, 0 for NaN or
/// infinite ones ("no data": a palette of [`ColorRamp::palette`]`(256)` draws them in the
/// ramp's lowest colour unless the caller sets entry 0).
pub fn states_over(v: &[f64], lo: f64, hi: f64) -> Vec<u8> {
    let span = if hi > lo { hi - lo } else { 1.0 };
    v.iter()
        .map(|&x| {
            if x.is_finite() {
                (1.0 + 254.0 * ((x - lo) / span).clamp(0.0, 1.0)).round() as u8
            } else {
                0
            }
        })
        .collect()
}

/// The smallest and largest finite values of `v` (`(inf, -inf)` when there are none).
pub fn finite_range(v: &[f64]) -> (f64, f64) {
    v.iter()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

/// Where a text's anchor point sits on the text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    /// The centre of the text.
    Centre,
    /// The middle of its left edge.
    Left,
}

/// One element of a [`Sheet`], in pixels from the top-left corner.
#[derive(Clone, Debug, PartialEq)]
pub enum Mark {
    /// Black sans-serif text of `size` pixels.
    Text {
        /// The text.
        text: String,
        /// Its anchor point.
        at: (i32, i32),
        /// Font size, pixels.
        size: f64,
        /// Bold face.
        bold: bool,
        /// Which point of the text `at` is.
        anchor: Anchor,
    },
    /// An RGB8 picture (`w * h * 3` bytes, row 0 at the top) with its top-left corner at `at`.
    Picture {
        /// Top-left corner.
        at: (i32, i32),
        /// Width, pixels.
        w: u32,
        /// Height, pixels.
        h: u32,
        /// The pixels.
        rgb: Vec<u8>,
    },
    /// A one-pixel outline of the rectangle between two corners.
    Frame {
        /// Opposite corners.
        corners: [(i32, i32); 2],
        /// Line colour.
        color: RGBColor,
    },
    /// A filled rectangle between two corners.
    Fill {
        /// Opposite corners.
        corners: [(i32, i32); 2],
        /// Fill colour.
        color: RGBColor,
    },
    /// A one-pixel polyline.
    Line {
        /// Its points.
        points: Vec<(i32, i32)>,
        /// Line colour.
        color: RGBColor,
    },
    /// A filled polygon.
    Polygon {
        /// Its corners.
        points: Vec<(i32, i32)>,
        /// Fill colour.
        color: RGBColor,
    },
}

impl Mark {
    /// Text anchored at its centre.
    pub fn centred(text: impl Into<String>, at: (i32, i32), size: f64, bold: bool) -> Mark {
        Mark::Text {
            text: text.into(),
            at,
            size,
            bold,
            anchor: Anchor::Centre,
        }
    }

    /// Text anchored at the middle of its left edge.
    pub fn left(text: impl Into<String>, at: (i32, i32), size: f64) -> Mark {
        Mark::Text {
            text: text.into(),
            at,
            size,
            bold: false,
            anchor: Anchor::Left,
        }
    }

    /// An arrow from `from` to `to` (pixels, fractional positions truncated towards zero
    /// after `offset` is added): a one-pixel shaft and a filled head of `0.35` of its length,
    /// between 2 and 6 pixels.
    pub fn arrow(
        offset: (f64, f64),
        from: (f64, f64),
        to: (f64, f64),
        color: RGBColor,
    ) -> [Mark; 2] {
        let at = |x: f64, y: f64| ((offset.0 + x) as i32, (offset.1 + y) as i32);
        let ((ax, ay), (bx, by)) = (from, to);
        let (dx, dy) = (bx - ax, by - ay);
        let l = dx.hypot(dy).max(1e-9);
        let (ux, uy) = (dx / l, dy / l);
        let head = (l * 0.35).clamp(2.0, 6.0);
        let left = at(bx - head * (ux + 0.5 * uy), by - head * (uy - 0.5 * ux));
        let right = at(bx - head * (ux - 0.5 * uy), by - head * (uy + 0.5 * ux));
        [
            Mark::Line {
                points: vec![at(ax, ay), at(bx, by)],
                color,
            },
            Mark::Polygon {
                points: vec![at(bx, by), left, right],
                color,
            },
        ]
    }
}

/// A white picture of `width x height` pixels and the [`Mark`]s drawn on it, in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Sheet {
    width: u32,
    height: u32,
    marks: Vec<Mark>,
}

impl Sheet {
    /// An empty sheet.
    ///
    /// # Errors
    ///
    /// [`PlotError::InvalidInput`] naming `name` (the parameter that set the size) for a
    /// zero or too large size.
    pub fn new(name: &str, width: u64, height: u64) -> Result<Sheet, PlotError> {
        check_picture_size(name, width, height)?;
        Ok(Sheet {
            width: width as u32,
            height: height as u32,
            marks: Vec::new(),
        })
    }

    /// Width, pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height, pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Adds a mark on top of those already there.
    pub fn push(&mut self, m: Mark) {
        self.marks.push(m);
    }

    /// Adds several marks.
    pub fn extend(&mut self, m: impl IntoIterator<Item = Mark>) {
        self.marks.extend(m);
    }

    /// The RGB8 pixels (row 0 at the top).
    ///
    /// # Errors
    ///
    /// [`PlotError::InvalidInput`] for a picture whose pixels do not match its size;
    /// [`PlotError::Drawing`] when plotters fails.
    pub fn render(&self) -> Result<Vec<u8>, PlotError> {
        let (w, h) = (self.width, self.height);
        ensure_fonts();
        let mut buf = vec![255u8; w as usize * h as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
            root.fill(&WHITE).map_err(PlotError::drawing)?;
            for (k, m) in self.marks.iter().enumerate() {
                match m {
                    Mark::Text {
                        text,
                        at,
                        size,
                        bold,
                        anchor,
                    } => {
                        let style = if *bold {
                            FontStyle::Bold
                        } else {
                            FontStyle::Normal
                        };
                        let pos = match anchor {
                            Anchor::Centre => Pos::new(HPos::Center, VPos::Center),
                            Anchor::Left => Pos::new(HPos::Left, VPos::Center),
                        };
                        let font = ("sans-serif", *size, style)
                            .into_font()
                            .color(&BLACK)
                            .pos(pos);
                        root.draw(&Text::new(text.clone(), *at, font))
                            .map_err(PlotError::drawing)?;
                    }
                    Mark::Picture { at, w, h, rgb } => {
                        let bitmap = BitMapElement::with_owned_buffer(*at, (*w, *h), rgb.clone())
                            .ok_or_else(|| {
                            PlotError::invalid(
                                format!("marks[{k}].rgb"),
                                format!("has {} bytes, expected {w} x {h} x 3", rgb.len()),
                            )
                        })?;
                        root.draw(&bitmap).map_err(PlotError::drawing)?;
                    }
                    Mark::Frame { corners, color } => {
                        root.draw(&Rectangle::new(*corners, color.stroke_width(1)))
                            .map_err(PlotError::drawing)?;
                    }
                    Mark::Fill { corners, color } => {
                        root.draw(&Rectangle::new(*corners, color.filled()))
                            .map_err(PlotError::drawing)?;
                    }
                    Mark::Line { points, color } => {
                        root.draw(&PathElement::new(points.clone(), color.stroke_width(1)))
                            .map_err(PlotError::drawing)?;
                    }
                    Mark::Polygon { points, color } => {
                        root.draw(&Polygon::new(points.clone(), color.filled()))
                            .map_err(PlotError::drawing)?;
                    }
                }
            }
            root.present().map_err(PlotError::drawing)?;
        }
        Ok(buf)
    }

    /// Draws the sheet and writes it as a PNG, atomically.
    ///
    /// # Errors
    ///
    /// Those of [`Sheet::render`], encoding and i/o errors.
    pub fn write_png(&self, path: &Path) -> Result<(), PlotError> {
        let rgb = self.render()?;
        let png = encode_png(&rgb, self.width, self.height)?;
        crate::engine::io::write_atomic(path, &png)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramps_run_from_their_first_to_their_last_anchor() {
        assert_eq!(ColorRamp::Sand.color(0.0), SAND[0]);
        assert_eq!(ColorRamp::Sand.color(1.0), SAND[5]);
        assert_eq!(ColorRamp::Viridis5.color(0.0), RGBColor(68, 1, 84));
        assert_eq!(ColorRamp::Viridis5.color(1.0), RGBColor(253, 231, 37));
        assert_eq!(ColorRamp::Viridis5.color(0.5), RGBColor(33, 145, 140));
        // Out of range and NaN are clamped to the ends.
        assert_eq!(ColorRamp::Sand.color(7.0), SAND[5]);
        assert_eq!(
            ColorRamp::Viridis.color(f64::NAN),
            ColorRamp::Viridis.color(0.0)
        );
    }

    #[test]
    fn sand_ramp_brightens_monotonically() {
        let lum =
            |c: RGBColor| 0.299 * f64::from(c.0) + 0.587 * f64::from(c.1) + 0.114 * f64::from(c.2);
        let lut = ColorRamp::Sand.lut(256);
        assert_eq!(lut.len(), 256);
        assert!(lut.windows(2).all(|w| lum(w[1]) >= lum(w[0]) - 1.0));
        assert!(lum(lut[255]) > lum(lut[0]) + 150.0);
    }

    #[test]
    fn states_keep_zero_for_missing_values() {
        let s = states_over(&[0.0, 0.5, 1.0, f64::NAN, 2.0], 0.0, 1.0);
        assert_eq!(s, vec![1, 128, 255, 0, 255]);
        assert_eq!(finite_range(&[3.0, f64::NAN, -1.0]), (-1.0, 3.0));
    }

    #[test]
    fn a_sheet_draws_pictures_where_they_are_placed() {
        let mut s = Sheet::new("test", 20, 10).unwrap();
        s.push(Mark::Picture {
            at: (5, 2),
            w: 2,
            h: 1,
            rgb: vec![255, 0, 0, 0, 0, 255],
        });
        let px = s.render().unwrap();
        let at = |x: usize, y: usize| &px[(y * 20 + x) * 3..][..3];
        assert_eq!(at(5, 2), &[255, 0, 0]);
        assert_eq!(at(6, 2), &[0, 0, 255]);
        assert_eq!(at(0, 0), &[255, 255, 255]);
        // A picture whose pixels do not match its size is an error, not a panic.
        s.push(Mark::Picture {
            at: (0, 0),
            w: 3,
            h: 3,
            rgb: vec![0; 5],
        });
        assert!(matches!(s.render(), Err(PlotError::InvalidInput { .. })));
        assert!(Sheet::new("width", 0, 10).is_err());
    }
}
