//! Wind vectors and wind fields: the article's colour encoding, PNG input and output, and the
//! built-in generators.
//!
//! A [`Wind`] is a vector in the article's units (colour levels, 0 to 255 per component; the
//! model accepts speeds up to [`MAX_WIND`] = 220). A [`WindField`] holds one wind per cell of a
//! `width x height` torus, row-major with row 0 at the *bottom* (as drawn), x to the right, y
//! up; angles are counter-clockwise from +x (east) in degrees and give the direction the wind
//! blows *toward* (where the sand goes), not the meteorological "from" direction.
//!
//! # Colour encoding (article, "Numeric definition of the R, G and B colour components")
//!
//! A pixel's red, green and blue levels (0-255) are three vectors at 120 degrees to one another
//! and the wind is their sum (article Eq. 3; its Fig. 3, which gave the orientation, is lost from
//! the text we have, so the orientation below is our choice). Here
//!
//! - red points toward 0 degrees (right, +x),
//! - green toward 120 degrees (up and left),
//! - blue toward 240 degrees (down and left),
//!
//! so `W = (R - (G + B)/2, (sqrt 3 / 2)(G - B))`. Equal levels cancel: a grey pixel is calm. The
//! winds reachable with levels in 0..=255 fill a hexagon whose inscribed circle has radius
//! `255 cos 30 deg = 220.8`: this is the article's "continuous radial coverage ... only when the
//! actual wind force is not exceeding 220 units". [`Wind::to_rgb`] inverts the encoding as in the
//! article's appendix (solve with red = 0, then raise all three levels together until none is
//! negative), which gives the representation with the smallest levels.
//!
//! PNG rows are stored top first, the lattice bottom first: image row `r` is lattice row
//! `height - 1 - r`, so the landscape is drawn the way the image looks in an image viewer, and
//! "red blows to the right of the picture".

use std::f64::consts::{PI, TAU};
use std::path::Path;

use serde::Serialize;

use super::{CursorError, MAX_CELLS, MAX_WIND};
use crate::engine::count::CountRange;

/// `wind_arms`: arms of each star of the rotating generator.
pub const ARMS: CountRange = CountRange::new(0, 12, "0 to 12");

/// Direction of the red colour vector, degrees counter-clockwise from +x.
pub const RED_DEG: f64 = 0.0;
/// Direction of the green colour vector, degrees.
pub const GREEN_DEG: f64 = 120.0;
/// Direction of the blue colour vector, degrees.
pub const BLUE_DEG: f64 = 240.0;

/// The largest speed accepted: [`MAX_WIND`] plus a relative `1e-12` for the rounding of
/// `f64` components (`220 (cos a, sin a)` may have a length a few ulps above 220); the
/// probabilities such a wind would make a rounding error below 0 are set to 0.
const MAX_WIND_ACCEPTED: f64 = MAX_WIND * (1.0 + 1e-12);

/// True for a finite speed the model accepts.
fn within_limit(speed: f64) -> bool {
    speed.is_finite() && speed <= MAX_WIND_ACCEPTED
}

/// `sqrt(3) / 2`.
const HALF_SQRT3: f64 = 0.866_025_403_784_438_6;

/// A wind vector in the article's units (colour levels; the model accepts `|W| <= 220`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Wind {
    /// Component toward +x (right), article units.
    pub x: f64,
    /// Component toward +y (up), article units.
    pub y: f64,
}

impl Wind {
    /// No wind.
    pub const CALM: Wind = Wind { x: 0.0, y: 0.0 };

    /// The wind blowing toward `angle_deg` (degrees counter-clockwise from +x) with `speed`
    /// article units. Angles that are multiples of 90 degrees give exact components.
    pub fn from_angle(angle_deg: f64, speed: f64) -> Wind {
        let (s, c) = exact_sin_cos(angle_deg);
        Wind {
            x: speed * c,
            y: speed * s,
        }
    }

    /// Speed `|W|`, article units.
    pub fn speed(self) -> f64 {
        self.x.hypot(self.y)
    }

    /// Direction the wind blows toward, degrees in `(-180, 180]` (0 for calm).
    pub fn angle_deg(self) -> f64 {
        self.y.atan2(self.x).to_degrees()
    }

    /// The wind of a pixel: the sum of the red, green and blue vectors (see the module
    /// documentation for their orientation).
    pub fn from_rgb(rgb: [u8; 3]) -> Wind {
        let [r, g, b] = rgb.map(f64::from);
        Wind {
            x: r - 0.5 * (g + b),
            y: HALF_SQRT3 * (g - b),
        }
    }

    /// The pixel levels that encode this wind, as in the article's appendix: solve with red = 0,
    /// then raise all three levels by the same amount (which does not change the sum) until
    /// none is negative. The levels are rounded to whole numbers, up or down each, to the
    /// combination nearest the wind whose speed stays within 220 when this wind's does (so an
    /// encoded field is always accepted back; the rounding moves a wind by at most about one
    /// unit). `None` when a level would exceed 255 (the wind lies outside the reachable
    /// hexagon; never for `|W| <= 220`) or the wind is not finite.
    pub fn to_rgb(self) -> Option<[u8; 3]> {
        if !self.x.is_finite() || !self.y.is_finite() {
            return None;
        }
        // W = G u_G + B u_B: G + B = -2 Wx, G - B = 2 Wy / sqrt 3.
        let g = -self.x + self.y / (2.0 * HALF_SQRT3);
        let b = -self.x - self.y / (2.0 * HALF_SQRT3);
        let lift = (-g.min(b)).max(0.0);
        let levels = [lift, g + lift, b + lift];
        if levels.iter().any(|&v| v > 255.0 + 1e-9) {
            return None;
        }
        let limit = if self.speed() <= MAX_WIND_ACCEPTED {
            MAX_WIND
        } else {
            f64::INFINITY
        };
        let mut best: Option<([u8; 3], f64)> = None;
        for mask in 0..8u32 {
            let rgb = [0, 1, 2].map(|i| {
                let v = if mask >> i & 1 == 1 {
                    levels[i].ceil()
                } else {
                    levels[i].floor()
                };
                v.clamp(0.0, 255.0) as u8
            });
            let w = Wind::from_rgb(rgb);
            if w.speed() > limit {
                continue;
            }
            let err = (w.x - self.x).hypot(w.y - self.y);
            if best.is_none_or(|(_, e)| err < e) {
                best = Some((rgb, err));
            }
        }
        match best {
            Some((rgb, _)) => Some(rgb),
            // Every rounding left the disc (only within a unit of |W| = 220): shrink slightly.
            None => Wind {
                x: self.x * 0.995,
                y: self.y * 0.995,
            }
            .to_rgb(),
        }
    }
}

/// `(sin, cos)` of an angle in degrees, exact at multiples of 90 degrees.
fn exact_sin_cos(angle_deg: f64) -> (f64, f64) {
    let a = angle_deg.rem_euclid(360.0);
    if a == 0.0 {
        (0.0, 1.0)
    } else if a == 90.0 {
        (1.0, 0.0)
    } else if a == 180.0 {
        (0.0, -1.0)
    } else if a == 270.0 {
        (-1.0, 0.0)
    } else {
        a.to_radians().sin_cos()
    }
}

/// One wind per cell of a `width x height` torus (row-major, row 0 at the bottom).
#[derive(Clone, Debug, PartialEq)]
pub struct WindField {
    width: usize,
    height: usize,
    winds: Vec<Wind>,
}

impl WindField {
    /// The same wind in every cell.
    pub fn uniform(width: usize, height: usize, wind: Wind) -> Result<WindField, CursorError> {
        WindField::from_fn(width, height, |_, _| wind)
    }

    /// Calm air everywhere: the cursor walk is a plain random walk (article Fig. 2).
    pub fn calm(width: usize, height: usize) -> Result<WindField, CursorError> {
        WindField::uniform(width, height, Wind::CALM)
    }

    /// The wind `f(x, y)` in cell `(x, y)` (x to the right, y up, both from 0).
    ///
    /// # Errors
    ///
    /// [`CursorError::GridSize`] for a side below 3 or more than [`MAX_CELLS`] cells;
    /// [`CursorError::WindTooStrong`] when a wind is
    /// not finite or faster than [`MAX_WIND`] (it would make a probability negative).
    pub fn from_fn(
        width: usize,
        height: usize,
        mut f: impl FnMut(usize, usize) -> Wind,
    ) -> Result<WindField, CursorError> {
        check_size(width, height)?;
        let mut winds = Vec::with_capacity(width * height);
        for y in 0..height {
            for x in 0..width {
                winds.push(f(x, y));
            }
        }
        let field = WindField {
            width,
            height,
            winds,
        };
        field.validate("custom wind field")?;
        Ok(field)
    }

    /// A field from row-major winds (row 0 at the bottom).
    ///
    /// # Errors
    ///
    /// [`CursorError::GridSize`] when `winds.len() != width * height` or the size is out of
    /// range;
    /// [`CursorError::WindTooStrong`] as for [`WindField::from_fn`].
    pub fn from_winds(
        width: usize,
        height: usize,
        winds: Vec<Wind>,
    ) -> Result<WindField, CursorError> {
        check_size(width, height)?;
        if winds.len() != width * height {
            return Err(CursorError::GridSize(format!(
                "{width}x{height} does not match the {} winds given",
                winds.len()
            )));
        }
        let field = WindField {
            width,
            height,
            winds,
        };
        field.validate("custom wind field")?;
        Ok(field)
    }

    /// Reads a wind field from a PNG image with one pixel per cell (8-bit grey, grey+alpha,
    /// RGB, RGBA or palette images; 16-bit images are reduced to their high byte; alpha is
    /// ignored; grey pixels are calm). Each pixel's wind ([`Wind::from_rgb`]) is multiplied by
    /// `scale` (1 = the article's units; `220 / 255` admits every colour). `expected`: the grid
    /// size `(width, height)` the image must have, or `None` to take the image's own size.
    ///
    /// # Errors
    ///
    /// [`CursorError::Png`] naming the file when it cannot be read or decoded (missing,
    /// truncated, not a PNG); [`CursorError::PngSize`] when the image is not `expected`
    /// pixels (no resampling is done); [`CursorError::GridSize`] when the image is smaller
    /// than 3 x 3 or larger than [`MAX_CELLS`] pixels; [`CursorError::WindTooStrong`] naming
    /// the file, the pixel and its colour when a pixel's scaled wind exceeds 220;
    /// [`CursorError::Parameter`] for a negative or non-finite `scale`.
    pub fn from_png(
        path: &Path,
        expected: Option<(usize, usize)>,
        scale: f64,
    ) -> Result<WindField, CursorError> {
        let name = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|e| CursorError::Png {
            path: name.clone(),
            reason: e.to_string(),
        })?;
        WindField::from_png_bytes(&bytes, &name, expected, scale)
    }

    /// As [`WindField::from_png`], from the bytes of a PNG file; `name` names it in errors.
    pub fn from_png_bytes(
        bytes: &[u8],
        name: &str,
        expected: Option<(usize, usize)>,
        scale: f64,
    ) -> Result<WindField, CursorError> {
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(CursorError::Parameter {
                name: "wind scale",
                value: scale,
                range: "expected a finite number >= 0".into(),
            });
        }
        let png_err = |reason: String| CursorError::Png {
            path: name.to_string(),
            reason,
        };
        check_palette_indices(bytes).map_err(&png_err)?;
        let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        decoder.set_transformations(png::Transformations::normalize_to_color8());
        let mut reader = decoder
            .read_info()
            .map_err(|e| png_err(format!("not a readable PNG image ({e})")))?;
        let (iw, ih) = (reader.info().width as usize, reader.info().height as usize);
        if let Some((ew, eh)) = expected
            && (iw, ih) != (ew, eh)
        {
            return Err(CursorError::PngSize {
                path: name.to_string(),
                width: iw,
                height: ih,
                expected_width: ew,
                expected_height: eh,
            });
        }
        check_size(iw, ih).map_err(|e| match e {
            CursorError::GridSize(m) => CursorError::GridSize(format!("of wind image {name}: {m}")),
            e => e,
        })?;
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| png_err("the image is too large to decode".into()))?;
        let mut buf = vec![0u8; size];
        let frame = reader
            .next_frame(&mut buf)
            .map_err(|e| png_err(format!("the image data is damaged or incomplete ({e})")))?;
        let channels = match frame.color_type {
            png::ColorType::Grayscale => 1,
            png::ColorType::GrayscaleAlpha => 2,
            png::ColorType::Rgb => 3,
            png::ColorType::Rgba => 4,
            png::ColorType::Indexed => {
                return Err(png_err("palette image was not expanded".into()));
            }
        };
        if frame.bit_depth != png::BitDepth::Eight {
            return Err(png_err(format!(
                "unsupported bit depth {:?} after conversion",
                frame.bit_depth
            )));
        }
        let mut winds = vec![Wind::CALM; iw * ih];
        for r in 0..ih {
            let row = &buf[r * frame.line_size..r * frame.line_size + iw * channels];
            let y = ih - 1 - r;
            for x in 0..iw {
                let p = &row[x * channels..(x + 1) * channels];
                let rgb = if channels < 3 {
                    [p[0]; 3]
                } else {
                    [p[0], p[1], p[2]]
                };
                let w = Wind::from_rgb(rgb);
                let w = Wind {
                    x: w.x * scale,
                    y: w.y * scale,
                };
                if !within_limit(w.speed()) {
                    return Err(CursorError::WindTooStrong {
                        place: format!(
                            "{name}, pixel (column {x}, row {r} from the top), colour {rgb:?}{}",
                            if scale == 1.0 {
                                String::new()
                            } else {
                                format!(" scaled by {scale}")
                            }
                        ),
                        speed: w.speed(),
                    });
                }
                winds[y * iw + x] = w;
            }
        }
        Ok(WindField {
            width: iw,
            height: ih,
            winds,
        })
    }

    /// The field as 8-bit RGB pixels in the article's encoding ([`Wind::to_rgb`]), rows top
    /// first (image order), `3 * width * height` bytes.
    pub fn to_rgb_image(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.winds.len() * 3);
        for r in 0..self.height {
            let y = self.height - 1 - r;
            for w in &self.winds[y * self.width..(y + 1) * self.width] {
                // Every stored wind is within 220, inside the reachable hexagon.
                out.extend_from_slice(&w.to_rgb().unwrap_or([0, 0, 0]));
            }
        }
        out
    }

    /// The field as a PNG file in the article's encoding (8-bit RGB, one pixel per cell), so
    /// that `--wind FILE.png` reads it back (to within the rounding of the levels).
    pub fn to_png_bytes(&self) -> Result<Vec<u8>, CursorError> {
        let mut out = Vec::new();
        let err = |e: png::EncodingError| CursorError::Png {
            path: "(encoding)".into(),
            reason: e.to_string(),
        };
        {
            let mut enc = png::Encoder::new(&mut out, self.width as u32, self.height as u32);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Eight);
            // Provenance, as in every PNG cellsurf writes (the pixels alone are the winds).
            enc.add_text_chunk(
                "Software".to_string(),
                format!("cellsurf {}", crate::engine::VERSION),
            )
            .map_err(err)?;
            #[cfg(feature = "plot")]
            if let Some(p) = crate::plot::png_parameters() {
                enc.add_itxt_chunk("parameters".to_string(), p)
                    .map_err(err)?;
            }
            let mut w = enc.write_header().map_err(err)?;
            w.write_image_data(&self.to_rgb_image()).map_err(err)?;
            w.finish().map_err(err)?;
        }
        Ok(out)
    }

    /// Checks every wind: finite and at most [`MAX_WIND`]; `source` names the field in errors.
    pub fn validate(&self, source: &str) -> Result<(), CursorError> {
        for (i, w) in self.winds.iter().enumerate() {
            let s = w.speed();
            if !within_limit(s) {
                return Err(CursorError::WindTooStrong {
                    place: format!(
                        "{source}, cell (x {}, y {})",
                        i % self.width,
                        i / self.width
                    ),
                    speed: s,
                });
            }
        }
        Ok(())
    }

    /// Columns.
    pub fn width(&self) -> usize {
        self.width
    }
    /// Rows.
    pub fn height(&self) -> usize {
        self.height
    }
    /// The winds, row-major, row 0 at the bottom.
    pub fn winds(&self) -> &[Wind] {
        &self.winds
    }
    /// The wind of cell `(x, y)`.
    pub fn at(&self, x: usize, y: usize) -> Wind {
        self.winds[y * self.width + x]
    }
    /// The largest speed in the field.
    pub fn max_speed(&self) -> f64 {
        self.winds.iter().map(|w| w.speed()).fold(0.0, f64::max)
    }
    /// The common wind when every cell has the same one (then the walk's increments are
    /// independent of position and its visit density is uniform in the long run).
    pub fn uniform_wind(&self) -> Option<Wind> {
        let first = *self.winds.first()?;
        self.winds.iter().all(|&w| w == first).then_some(first)
    }
}

/// Checks a grid size: each side at least 3 (a torus on which no cell is its own neighbour),
/// at most [`MAX_CELLS`] cells.
pub fn check_size(width: usize, height: usize) -> Result<(), CursorError> {
    if width < 3 || height < 3 {
        return Err(CursorError::GridSize(format!(
            "{width}x{height} is too small: each side must be at least 3 cells (a torus on which no cell is its own neighbour)"
        )));
    }
    if width.saturating_mul(height) > MAX_CELLS {
        return Err(CursorError::GridSize(format!(
            "{width}x{height} is too large: at most {MAX_CELLS} cells (about 56 bytes of memory per cell)"
        )));
    }
    Ok(())
}

/// A built-in wind field generator. Every generator is periodic on the torus (see
/// [`WindSpec::field`]), and its parameters are checked so that no wind exceeds 220. The
/// defaults named below are those of [`WindSpec::article`] (and of the command line).
///
/// Which generator gives which of the article's forms (its Figs. 2, 4-8), in kind, with the
/// parameters of the figures ([`WindSpec::article`]):
///
/// | generator | article | form |
/// | --- | --- | --- |
/// | [`WindSpec::Calm`] | Fig. 2 | Brownian field |
/// | [`WindSpec::Uniform`] | Fig. 4 | ridges along the wind |
/// | [`WindSpec::Bimodal`] | Fig. 5 | linear dunes along the winds' resultant |
/// | [`WindSpec::Converging`] | Fig. 6 | barchan-like crescents, horns downwind |
/// | [`WindSpec::Converging`], centres closer across the wind | Fig. 7 | crescentic ridges |
/// | [`WindSpec::Rotating`] | Fig. 8 | network of star dunes |
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "field", rename_all = "lowercase")]
pub enum WindSpec {
    /// No wind: every `P_i = 1/8`, a plain random walk (article Fig. 2).
    Calm,
    /// The same wind in every cell (article Fig. 4).
    Uniform {
        /// Direction the wind blows toward, degrees counter-clockwise from +x (default 30).
        angle_deg: f64,
        /// Speed, article units, 0 to 220 (default 220).
        speed: f64,
    },
    /// Two winds of equal speed in alternating bands, meeting head-on at an angle (article
    /// Fig. 5: "winds of uniform strength facing each other head-on at various angles").
    ///
    /// The bands run along `angle_deg`, `wavelength` cells apart. Across the bands the wind
    /// turns smoothly between wind 1, toward `angle_deg + spread_deg / 2`, and wind 2, toward
    /// `angle_deg - spread_deg / 2`: its direction is `angle_deg + (spread_deg / 2) cos(2 pi p)`
    /// at constant speed, `p` the position across the bands in wavelengths. The components
    /// across the bands meet head-on at `p = 1/4` (sand converges: a linear ridge along
    /// `angle_deg`, the winds' resultant) and part at `p = 3/4` (a bare corridor); the common
    /// component along the bands, `speed cos(spread_deg / 2)`, carries sand along the ridges.
    Bimodal {
        /// Direction of the bands and of the winds' resultant, degrees (default 60).
        angle_deg: f64,
        /// Speed of both winds, article units, 0 to 220 (default 220).
        speed: f64,
        /// Angle between the two winds, degrees, 0 to 180 (180 = exactly opposite; default
        /// 150).
        spread_deg: f64,
        /// Distance between ridges, cells, at least 4 (default 40).
        wavelength: f64,
    },
    /// A uniform drift with winds converging around a rectangular array of centres (article
    /// Figs. 6 and 7).
    ///
    /// The wind is the drift, `speed` toward `angle_deg`, plus a radial wind
    /// `radial sin(pi r / radius)` within `radius` of each centre (outward for `radial > 0`,
    /// zero at the centre and beyond `radius`). The centres sit `wavelength` cells apart along
    /// x and `spacing` cells apart along y. With `radial > 0` the drift is deflected around each
    /// centre as around an obstacle: the winds meet head-on on its upwind face and converge
    /// along its flanks, so the sand gathers in a crescent whose horns trail downwind
    /// (barchan-like, Fig. 6); centres closer across the drift join the crescents into wavy
    /// crescentic ridges (Fig. 7). With `radial < 0` the winds point toward the centres and the
    /// sand gathers in mounds.
    Converging {
        /// Direction of the drift, degrees (default 0).
        angle_deg: f64,
        /// Drift speed, article units; `speed + |radial|` at most 220 (default 50).
        speed: f64,
        /// Largest radial wind, article units (> 0 outward, < 0 inward; default 160).
        radial: f64,
        /// Distance between centres along x, cells, at least 4 (default 80).
        wavelength: f64,
        /// Distance between centres along y, cells, at least 4 (default 120).
        spacing: f64,
        /// Radius of the radial wind around each centre, cells, from 1 to half the smaller
        /// distance between centres (default 25).
        radius: f64,
    },
    /// The wind direction rotating with position around each node of a square array
    /// `wavelength` cells apart (article Fig. 8: star dunes grow where "winds are mostly
    /// variable").
    ///
    /// At polar angle `psi` around the nearest node the wind blows toward
    /// `(arms + 1) psi + 180 deg - arms * angle_deg`: it turns `arms + 1` times as fast as the
    /// polar angle. The winds converge onto `arms` rays from the node (at `angle_deg` and every
    /// `360 / arms` degrees from it) and blow inward along them, so the sand gathers in a star
    /// with `arms` arms; arms of neighbouring nodes meet, making a network. The speed is
    /// `speed` except within 3 cells of a node, where it falls linearly to 0. `arms = 0` gives
    /// winds straight toward each node (round mounds).
    Rotating {
        /// Direction of one arm, degrees (default 0).
        angle_deg: f64,
        /// Speed, article units, 0 to 220 (default 60).
        speed: f64,
        /// Distance between nodes, cells, at least 4 (default 60).
        wavelength: f64,
        /// Number of arms of each star, 0 to 12 (default 4).
        arms: u32,
    },
}

/// Names of the generators, for the command line.
pub const GENERATORS: &[&str] = &["calm", "uniform", "bimodal", "converging", "rotating"];

/// The settings of a generator that replace its article settings ([`WindSpec::with_options`]),
/// each named as its command-line option without the dashes (`wind_angle` for `--wind-angle`,
/// as in a scenario file); `None` where not given.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WindOptions {
    /// `wind_angle`: direction, degrees.
    pub angle: Option<f64>,
    /// `wind_speed`: speed, article units.
    pub speed: Option<f64>,
    /// `wind_spread`: angle between the bimodal winds, degrees.
    pub spread: Option<f64>,
    /// `wind_wavelength`: distance between ridges, centres or nodes, cells.
    pub wavelength: Option<f64>,
    /// `wind_spacing`: distance between converging centres along y, cells.
    pub spacing: Option<f64>,
    /// `wind_radial`: largest radial wind around a converging centre, article units.
    pub radial: Option<f64>,
    /// `wind_radius`: radius of that radial wind, cells.
    pub radius: Option<f64>,
    /// `wind_arms`: arms of each star.
    pub arms: Option<u32>,
}

impl WindOptions {
    /// The names of the settings given, in the order above.
    pub fn given(&self) -> Vec<&'static str> {
        [
            ("wind_angle", self.angle.is_some()),
            ("wind_speed", self.speed.is_some()),
            ("wind_spread", self.spread.is_some()),
            ("wind_wavelength", self.wavelength.is_some()),
            ("wind_spacing", self.spacing.is_some()),
            ("wind_radial", self.radial.is_some()),
            ("wind_radius", self.radius.is_some()),
            ("wind_arms", self.arms.is_some()),
        ]
        .into_iter()
        .filter_map(|(name, given)| given.then_some(name))
        .collect()
    }
}

/// Sets `slot` to `v` where given.
fn set<T>(slot: &mut T, v: Option<T>) {
    if let Some(v) = v {
        *slot = v;
    }
}

impl WindSpec {
    /// The generator's name.
    pub fn name(&self) -> &'static str {
        match self {
            WindSpec::Calm => "calm",
            WindSpec::Uniform { .. } => "uniform",
            WindSpec::Bimodal { .. } => "bimodal",
            WindSpec::Converging { .. } => "converging",
            WindSpec::Rotating { .. } => "rotating",
        }
    }

    /// The settings of [`WindOptions`] this generator takes, by name (`wind_angle`, ...).
    pub fn options(&self) -> &'static [&'static str] {
        match self {
            WindSpec::Calm => &[],
            WindSpec::Uniform { .. } => &["wind_angle", "wind_speed"],
            WindSpec::Bimodal { .. } => {
                &["wind_angle", "wind_speed", "wind_spread", "wind_wavelength"]
            }
            WindSpec::Converging { .. } => &[
                "wind_angle",
                "wind_speed",
                "wind_radial",
                "wind_wavelength",
                "wind_spacing",
                "wind_radius",
            ],
            WindSpec::Rotating { .. } => {
                &["wind_angle", "wind_speed", "wind_wavelength", "wind_arms"]
            }
        }
    }

    /// This generator with the settings given in `o` in place of its own (unchecked: see
    /// [`WindSpec::validate`]); `Err` with the name of the first setting given that this
    /// generator does not take ([`WindSpec::options`]).
    pub fn with_options(mut self, o: &WindOptions) -> Result<WindSpec, &'static str> {
        let takes = self.options();
        if let Some(bad) = o.given().into_iter().find(|n| !takes.contains(n)) {
            return Err(bad);
        }
        let (WindSpec::Uniform { angle_deg, speed }
        | WindSpec::Bimodal {
            angle_deg, speed, ..
        }
        | WindSpec::Converging {
            angle_deg, speed, ..
        }
        | WindSpec::Rotating {
            angle_deg, speed, ..
        }) = &mut self
        else {
            return Ok(self);
        };
        set(angle_deg, o.angle);
        set(speed, o.speed);
        match &mut self {
            WindSpec::Bimodal {
                spread_deg,
                wavelength,
                ..
            } => {
                set(spread_deg, o.spread);
                set(wavelength, o.wavelength);
            }
            WindSpec::Converging {
                radial,
                wavelength,
                spacing,
                radius,
                ..
            } => {
                set(radial, o.radial);
                set(wavelength, o.wavelength);
                set(spacing, o.spacing);
                set(radius, o.radius);
            }
            WindSpec::Rotating {
                wavelength, arms, ..
            } => {
                set(wavelength, o.wavelength);
                set(arms, o.arms);
            }
            WindSpec::Calm | WindSpec::Uniform { .. } => {}
        }
        Ok(self)
    }

    /// The generator `name` (one of [`GENERATORS`]) with the parameters of the article's figure
    /// of that form: uniform toward 30 degrees at 220 (Fig. 4); bimodal along 60 degrees, 220,
    /// spread 150 degrees, ridges 40 cells apart (Fig. 5); converging: drift 50 toward 0
    /// degrees, outward radial wind 160 within 25 cells of centres 80 x 120 cells apart
    /// (Fig. 6); rotating: 4 arms along 0 degrees, speed 60, nodes 60 cells apart (Fig. 8).
    /// `None` for an unknown name.
    pub fn article(name: &str) -> Option<WindSpec> {
        Some(match name {
            "calm" => WindSpec::Calm,
            "uniform" => WindSpec::Uniform {
                angle_deg: 30.0,
                speed: 220.0,
            },
            "bimodal" => WindSpec::Bimodal {
                angle_deg: 60.0,
                speed: 220.0,
                spread_deg: 150.0,
                wavelength: 40.0,
            },
            "converging" => WindSpec::Converging {
                angle_deg: 0.0,
                speed: 50.0,
                radial: 160.0,
                wavelength: 80.0,
                spacing: 120.0,
                radius: 25.0,
            },
            "rotating" => WindSpec::Rotating {
                angle_deg: 0.0,
                speed: 60.0,
                wavelength: 60.0,
                arms: 4,
            },
            _ => return None,
        })
    }

    /// Checks the parameters: angles finite, speeds in `[0, 220]` (for `converging`,
    /// `speed + |radial| <= 220`), distances at least 4 cells, `spread_deg` in `[0, 180]`,
    /// `radius` from 1 to half the smaller distance between centres, `arms` at most 12.
    ///
    /// # Errors
    ///
    /// [`CursorError::Parameter`] naming the parameter, its value and the valid range.
    pub fn validate(&self) -> Result<(), CursorError> {
        let speed_why = " article units (a faster wind makes some P_i negative)";
        match *self {
            WindSpec::Calm => Ok(()),
            WindSpec::Uniform { angle_deg, speed } => {
                check_angle(angle_deg)?;
                check("wind speed", speed, 0.0, MAX_WIND, speed_why)
            }
            WindSpec::Bimodal {
                angle_deg,
                speed,
                spread_deg,
                wavelength,
            } => {
                check_angle(angle_deg)?;
                check("wind speed", speed, 0.0, MAX_WIND, speed_why)?;
                check("wind spread", spread_deg, 0.0, 180.0, " degrees")?;
                check_distance("wind wavelength", wavelength)
            }
            WindSpec::Converging {
                angle_deg,
                speed,
                radial,
                wavelength,
                spacing,
                radius,
            } => {
                check_angle(angle_deg)?;
                check("wind speed", speed, 0.0, MAX_WIND, speed_why)?;
                check(
                    "wind radial",
                    radial,
                    -(MAX_WIND - speed),
                    MAX_WIND - speed,
                    " article units (speed + |radial| must be at most 220)",
                )?;
                check_distance("wind wavelength", wavelength)?;
                check_distance("wind spacing", spacing)?;
                check(
                    "wind radius",
                    radius,
                    1.0,
                    0.5 * wavelength.min(spacing),
                    " cells (half the smaller distance between centres)",
                )
            }
            WindSpec::Rotating {
                angle_deg,
                speed,
                wavelength,
                arms,
            } => {
                check_angle(angle_deg)?;
                check("wind speed", speed, 0.0, MAX_WIND, speed_why)?;
                check_distance("wind wavelength", wavelength)?;
                if ARMS.contains(u64::from(arms)) {
                    Ok(())
                } else {
                    Err(CursorError::Parameter {
                        name: "wind arms",
                        value: f64::from(arms),
                        range: format!("expected {}", ARMS.expected),
                    })
                }
            }
        }
    }

    /// True when the generator gives the same wind in every cell (calm, uniform).
    pub fn is_uniform(&self) -> bool {
        matches!(self, WindSpec::Calm | WindSpec::Uniform { .. })
    }

    /// The wind field on a `width x height` torus.
    ///
    /// Spatial patterns are made periodic on the torus, so the actual distances may differ
    /// slightly from those asked for: a band pattern (bimodal) uses the wave vector
    /// `2 pi (m / width, n / height)` with the whole numbers `m, n` nearest to
    /// `width cos(a) / wavelength` and `height sin(a) / wavelength` (`a` the direction across the
    /// bands; at least one period in all); an array of centres or nodes uses
    /// `width / round(width / wavelength)` cells along x (at least one centre) and likewise
    /// along y. Cell `(x, y)` sits at `(x + 1/2, y + 1/2)`; centres at the middle of their
    /// tiles.
    ///
    /// # Errors
    ///
    /// [`CursorError::Parameter`] from [`WindSpec::validate`]; [`CursorError::GridSize`] for a
    /// side below 3 or more than [`MAX_CELLS`] cells.
    pub fn field(&self, width: usize, height: usize) -> Result<WindField, CursorError> {
        self.validate()?;
        check_size(width, height)?;
        let (wf, hf) = (width as f64, height as f64);
        let tile = |l: f64, n: f64| n / (n / l).round().max(1.0);
        match *self {
            WindSpec::Calm => WindField::calm(width, height),
            WindSpec::Uniform { angle_deg, speed } => {
                WindField::uniform(width, height, Wind::from_angle(angle_deg, speed))
            }
            WindSpec::Bimodal {
                angle_deg,
                speed,
                spread_deg,
                wavelength,
            } => {
                let q = periodic_wave(angle_deg + 90.0, wavelength, wf, hf);
                let half = spread_deg / 2.0;
                capped(width, height, speed, |x, y| {
                    let p = q.0 * (x as f64 + 0.5) + q.1 * (y as f64 + 0.5);
                    Wind::from_angle(angle_deg + half * p.cos(), speed)
                })
            }
            WindSpec::Converging {
                angle_deg,
                speed,
                radial,
                wavelength,
                spacing,
                radius,
            } => {
                let (lx, ly) = (tile(wavelength, wf), tile(spacing, hf));
                // the radius against the distances the torus takes, not those asked: beyond half
                // of either, two centres' radial winds would be cut off at a tile's edge
                check(
                    "wind radius",
                    radius,
                    1.0,
                    0.5 * lx.min(ly),
                    &format!(
                        " cells (half the smaller distance between centres as they fit the \
                         {width} x {height} torus: {} x {} cells)",
                        shown_cells(lx),
                        shown_cells(ly)
                    ),
                )?;
                let drift = Wind::from_angle(angle_deg, speed);
                capped(width, height, speed + radial.abs(), |x, y| {
                    let (dx, dy) = offset(x, y, lx, ly);
                    let r = dx.hypot(dy);
                    if r == 0.0 || r >= radius {
                        return drift;
                    }
                    let v = radial * (PI * r / radius).sin();
                    Wind {
                        x: drift.x + v * dx / r,
                        y: drift.y + v * dy / r,
                    }
                })
            }
            WindSpec::Rotating {
                angle_deg,
                speed,
                wavelength,
                arms,
            } => {
                let (lx, ly) = (tile(wavelength, wf), tile(wavelength, hf));
                let m = f64::from(arms);
                capped(width, height, speed, |x, y| {
                    let (dx, dy) = offset(x, y, lx, ly);
                    let r = dx.hypot(dy);
                    if r == 0.0 {
                        return Wind::CALM;
                    }
                    let psi = dy.atan2(dx).to_degrees();
                    let dir = (m + 1.0) * psi + 180.0 - m * angle_deg;
                    Wind::from_angle(dir, speed * (r / CORE).min(1.0))
                })
            }
        }
    }
}

impl WindSpec {
    /// What fitting the pattern to a `width x height` torus ([`WindSpec::field`]) makes of the
    /// distances and direction asked: `(option, asked, used)` for each that changes by more
    /// than one part in a million (`wind_wavelength`, `wind_spacing`, and a bimodal pattern's
    /// `wind_angle`; a rotating pattern's wavelength along y as `wind_wavelength (y)`), in
    /// cells and degrees. Empty for calm, uniform and patterns that fit as asked.
    pub fn fitted(&self, width: usize, height: usize) -> Vec<(&'static str, f64, f64)> {
        let (wf, hf) = (width as f64, height as f64);
        let tile = |l: f64, n: f64| n / (n / l).round().max(1.0);
        let mut out = Vec::new();
        let mut keep = |name: &'static str, asked: f64, used: f64| {
            if (used - asked).abs() > 1e-6 * asked.abs().max(1.0) {
                out.push((name, asked, used));
            }
        };
        match *self {
            WindSpec::Calm | WindSpec::Uniform { .. } => {}
            WindSpec::Bimodal {
                angle_deg,
                wavelength,
                ..
            } => {
                let (qx, qy) = periodic_wave(angle_deg + 90.0, wavelength, wf, hf);
                keep("wind_wavelength", wavelength, TAU / qx.hypot(qy));
                // the bands' direction, the one of the two opposite ones nearest that asked
                let across = qy.atan2(qx).to_degrees() - 90.0;
                let used = angle_deg + (across - angle_deg + 90.0).rem_euclid(180.0) - 90.0;
                keep("wind_angle", angle_deg, used);
            }
            WindSpec::Converging {
                wavelength,
                spacing,
                ..
            } => {
                keep("wind_wavelength", wavelength, tile(wavelength, wf));
                keep("wind_spacing", spacing, tile(spacing, hf));
            }
            WindSpec::Rotating { wavelength, .. } => {
                keep("wind_wavelength", wavelength, tile(wavelength, wf));
                keep("wind_wavelength (y)", wavelength, tile(wavelength, hf));
            }
        }
        out
    }
}

/// A distance in cells as a message shows it: whole cells plainly, others to 4 digits.
fn shown_cells(v: f64) -> String {
    if v.fract() == 0.0 {
        format!("{v}")
    } else {
        format!("{v:.4}")
    }
}

/// Checks that every pixel of a palette PNG names an entry of its palette (the decoder expands
/// an index beyond the palette to black, which would read as calm air): `Err(reason)` naming
/// the first pixel that does not; `Ok` for other images and for bytes it cannot read (whose
/// error the decoding itself reports).
fn check_palette_indices(bytes: &[u8]) -> Result<(), String> {
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::IDENTITY);
    let Ok(mut reader) = decoder.read_info() else {
        return Ok(());
    };
    let info = reader.info();
    if info.color_type != png::ColorType::Indexed {
        return Ok(());
    }
    let entries = info.palette.as_ref().map_or(0, |p| p.len() / 3);
    let bits = match info.bit_depth {
        png::BitDepth::One => 1,
        png::BitDepth::Two => 2,
        png::BitDepth::Four => 4,
        _ => 8,
    };
    let (w, h) = (info.width as usize, info.height as usize);
    let Some(size) = reader.output_buffer_size() else {
        return Ok(());
    };
    let mut buf = vec![0u8; size];
    let Ok(frame) = reader.next_frame(&mut buf) else {
        return Ok(());
    };
    for r in 0..h {
        let row = &buf[r * frame.line_size..];
        for x in 0..w {
            let bit = x * bits;
            let byte = row[bit / 8];
            let index = (byte >> (8 - bits - bit % 8)) & ((1u16 << bits) - 1) as u8;
            if usize::from(index) >= entries {
                return Err(format!(
                    "pixel (column {x}, row {r} from the top) has palette index {index}, beyond \
                     the palette's {entries} entries: the image is damaged"
                ));
            }
        }
    }
    Ok(())
}

/// Radius of the calm-ward core of a rotating node, cells.
const CORE: f64 = 3.0;

fn check(name: &'static str, value: f64, lo: f64, hi: f64, unit: &str) -> Result<(), CursorError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(CursorError::Parameter {
            name,
            value,
            range: format!("expected {lo} to {hi}{unit}"),
        })
    }
}

fn check_angle(a: f64) -> Result<(), CursorError> {
    check("wind angle", a, -36_000.0, 36_000.0, " degrees")
}

fn check_distance(name: &'static str, l: f64) -> Result<(), CursorError> {
    check(name, l, 4.0, 1e6, " cells")
}

/// Offset of cell `(x, y)`'s centre from the centre of its tile in an array of `lx x ly`
/// tiles.
fn offset(x: usize, y: usize, lx: f64, ly: f64) -> (f64, f64) {
    (
        (x as f64 + 0.5).rem_euclid(lx) - 0.5 * lx,
        (y as f64 + 0.5).rem_euclid(ly) - 0.5 * ly,
    )
}

/// The wave vector (radians per cell) of a pattern of `wavelength` cells along `angle_deg`,
/// rounded to whole numbers of periods across a `w x h` torus (at least one in all).
fn periodic_wave(angle_deg: f64, wavelength: f64, w: f64, h: f64) -> (f64, f64) {
    let (s, c) = exact_sin_cos(angle_deg);
    let mut m = (w * c / wavelength).round();
    let mut n = (h * s / wavelength).round();
    if m == 0.0 && n == 0.0 {
        if c.abs() >= s.abs() {
            m = c.signum();
        } else {
            n = s.signum();
        }
    }
    (TAU * m / w, TAU * n / h)
}

/// A field from `f`, each wind scaled down to `limit` where rounding takes it a hair above
/// (the parameters already bound the speeds; this only removes `f64` rounding excess).
fn capped(
    width: usize,
    height: usize,
    limit: f64,
    mut f: impl FnMut(usize, usize) -> Wind,
) -> Result<WindField, CursorError> {
    WindField::from_fn(width, height, |x, y| {
        let w = f(x, y);
        let s = w.speed();
        if s > limit && s > 0.0 {
            Wind {
                x: w.x * limit / s,
                y: w.y * limit / s,
            }
        } else {
            w
        }
    })
}
