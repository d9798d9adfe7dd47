//! Cell fields, palettes and the rasterizer shared by the lattice panels and the GIF frames.

use plotters::style::RGBColor;

use super::PlotError;

/// `sqrt(3) / 2`: the distance between hexagonal rows.
const ROW_STEP: f64 = 0.866_025_403_784_438_6;
/// Circumradius of a pointy-top hexagon of width 1 (`1 / sqrt(3)`): the half height.
const HEX_RADIUS: f64 = 0.577_350_269_189_625_8;
/// Below this many pixels per cell width, each pixel also shows the most salient state among
/// the cells whose centres fall in it (see [`rasterize`]).
const PRIORITY_SAMPLING_BELOW: f64 = 2.0;

/// Colour of pixels outside the field (around it where the aspect ratios differ, and in the
/// notches along the zig-zag edges of a hexagonal field): white.
pub const BACKGROUND: RGBColor = RGBColor(255, 255, 255);
/// Colour used for every state when a palette has no colours at all: mid grey.
const FALLBACK: RGBColor = RGBColor(128, 128, 128);

/// A lattice of cell states to draw.
///
/// `states[y * nx + x]` is the state of cell `(x, y)`; row `y = 0` is drawn at the bottom of the
/// picture. States: 0 = empty, 1 = surface/interface site, 2 = occupied (burnt/solid); other
/// values are extra classes drawn with palette entries 3.. (see [`Palette`]).
///
/// With `hex` false the lattice is square (cell `(x, y)` is the unit square centred at
/// `(x, y)`); with `hex` true it is hexagonal with offset rows (odd rows shifted right by half a
/// cell, cells drawn as pointy-top hexagons of width 1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CellField {
    /// Number of columns (cells per row).
    pub nx: usize,
    /// Number of rows.
    pub ny: usize,
    /// Hexagonal (offset rows) rather than square lattice.
    pub hex: bool,
    /// Row-major states, `nx * ny` of them, row 0 first.
    pub states: Vec<u8>,
}

impl CellField {
    /// An all-empty (state 0) field of `nx` by `ny` cells.
    pub fn new(nx: usize, ny: usize, hex: bool) -> Self {
        CellField {
            nx,
            ny,
            hex,
            states: vec![0; nx.saturating_mul(ny)],
        }
    }

    /// Physical width and height of the drawn field in units of the cell width: `(nx, ny)` for a
    /// square lattice; `(nx + 0.5, (ny - 1) * sqrt(3)/2 + 2/sqrt(3))` for a hexagonal one (the
    /// half-cell shift of the odd rows counts only when there are at least two rows).
    pub fn physical_size(&self) -> (f64, f64) {
        let (xmin, xmax, ymin, ymax) = extent(self.nx, self.ny, self.hex);
        (xmax - xmin, ymax - ymin)
    }

    /// Checks that the field is non-empty and that `states` has `nx * ny` entries.
    ///
    /// # Errors
    ///
    /// [`PlotError::InvalidInput`] naming `{name}.nx`, `{name}.ny` or `{name}.states`, where
    /// `name` names the field (e.g. `panels[2].field`).
    pub fn validate(&self, name: &str) -> Result<(), PlotError> {
        if self.nx == 0 {
            return Err(PlotError::invalid(format!("{name}.nx"), "must be positive"));
        }
        if self.ny == 0 {
            return Err(PlotError::invalid(format!("{name}.ny"), "must be positive"));
        }
        match self.nx.checked_mul(self.ny) {
            Some(n) if n == self.states.len() => Ok(()),
            Some(n) => Err(PlotError::invalid(
                format!("{name}.states"),
                format!(
                    "has {} entries, expected nx * ny = {} * {} = {n}",
                    self.states.len(),
                    self.nx,
                    self.ny
                ),
            )),
            None => Err(PlotError::invalid(
                format!("{name}.nx"),
                "nx * ny overflows usize",
            )),
        }
    }
}

/// Colours for cell states: `colors[s]` draws state `s`.
///
/// A state beyond the palette cycles through the extra entries `3..` (or takes the last entry
/// when the palette has at most 3 colours); a palette with no colours draws everything grey.
/// All the named palettes carry 8 extra colours for classes 3..=10.
#[derive(Debug, Clone, PartialEq)]
pub struct Palette {
    /// Colour per state, index = state.
    pub colors: Vec<RGBColor>,
}

/// Extra class colours (states 3..), shared by the named palettes: a qualitative set that stays
/// distinct from each other and from the base colours.
const EXTRA: [RGBColor; 8] = [
    RGBColor(31, 119, 180),  // blue
    RGBColor(44, 160, 44),   // green
    RGBColor(148, 103, 189), // purple
    RGBColor(23, 190, 207),  // cyan
    RGBColor(227, 119, 194), // pink
    RGBColor(188, 189, 34),  // olive
    RGBColor(127, 127, 127), // grey
    RGBColor(140, 86, 75),   // brown
];

impl Palette {
    fn with_base(empty: RGBColor, interface: RGBColor, occupied: RGBColor) -> Self {
        let mut colors = vec![empty, interface, occupied];
        colors.extend_from_slice(&EXTRA);
        Palette { colors }
    }

    /// Forest fire / flame front: cream unburnt ground, bright yellow-orange burning front,
    /// charcoal burnt cells.
    pub fn flame() -> Self {
        Palette::with_base(
            RGBColor(250, 244, 222),
            RGBColor(255, 176, 0),
            RGBColor(58, 44, 40),
        )
    }

    /// Deposition / solid growth: sky blue empty space, light yellow surface sites, brown
    /// solid.
    pub fn solid() -> Self {
        Palette::with_base(
            RGBColor(135, 206, 235),
            RGBColor(255, 244, 170),
            RGBColor(139, 69, 19),
        )
    }

    /// Crystal growth: pale ice-white melt, bright cyan interface, deep blue crystal.
    pub fn crystal() -> Self {
        Palette::with_base(
            RGBColor(236, 242, 250),
            RGBColor(0, 191, 255),
            RGBColor(25, 42, 120),
        )
    }

    /// Colour for state `state`, following the rules in the type's documentation.
    pub fn color(&self, state: u8) -> RGBColor {
        match palette_index(self.colors.len(), state) {
            Some(i) => self.colors[i],
            None => FALLBACK,
        }
    }
}

impl Default for Palette {
    /// White-ish empty cells, orange interface, dark red occupied cells.
    fn default() -> Self {
        Palette::with_base(
            RGBColor(248, 248, 244),
            RGBColor(255, 140, 0),
            RGBColor(139, 0, 0),
        )
    }
}

/// Index into a palette of `len` colours for `state`; `None` when `len` is 0.
pub(crate) fn palette_index(len: usize, state: u8) -> Option<usize> {
    let s = usize::from(state);
    if len == 0 {
        None
    } else if s < len {
        Some(s)
    } else if len > 3 {
        Some(3 + (s - 3) % (len - 3))
    } else {
        Some(len - 1)
    }
}

/// Physical bounding box `(xmin, xmax, ymin, ymax)` of the drawn cells, in cell widths.
fn extent(nx: usize, ny: usize, hex: bool) -> (f64, f64, f64, f64) {
    let (nx, ny) = (nx as f64, ny as f64);
    if hex {
        let shift = if ny >= 2.0 { 0.5 } else { 0.0 };
        (
            -0.5,
            nx - 0.5 + shift,
            -HEX_RADIUS,
            (ny - 1.0).max(0.0) * ROW_STEP + HEX_RADIUS,
        )
    } else {
        (-0.5, nx - 0.5, -0.5, ny - 0.5)
    }
}

/// How a field maps onto a `w` by `h` pixel buffer: uniform scale, centred.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Fit {
    xmin: f64,
    ymax: f64,
    /// Pixels per cell width.
    scale: f64,
    off_x: f64,
    off_y: f64,
}

impl Fit {
    fn new(field: &CellField, w: u32, h: u32) -> Self {
        let (xmin, xmax, ymin, ymax) = extent(field.nx, field.ny, field.hex);
        let (pw, ph) = (xmax - xmin, ymax - ymin);
        let scale = (f64::from(w) / pw).min(f64::from(h) / ph);
        Fit {
            xmin,
            ymax,
            scale,
            off_x: (f64::from(w) - pw * scale) / 2.0,
            off_y: (f64::from(h) - ph * scale) / 2.0,
        }
    }

    /// Physical x of the centre of pixel column `i`.
    fn phys_x(&self, i: u32) -> f64 {
        self.xmin + (f64::from(i) + 0.5 - self.off_x) / self.scale
    }

    /// Physical y of the centre of pixel row `j` (row 0 at the top).
    fn phys_y(&self, j: u32) -> f64 {
        self.ymax - (f64::from(j) + 0.5 - self.off_y) / self.scale
    }
}

/// Rasterizes `field` into a `w * h` buffer of codes: 0 = background, `s + 1` = state `s`.
///
/// Missing states (a `states` vector shorter than `nx * ny`) count as 0. Returns an empty
/// vector when `w` or `h` is 0, and all background for an empty field.
pub(crate) fn rasterize_codes(field: &CellField, w: u32, h: u32) -> Vec<u16> {
    let (wu, hu) = (w as usize, h as usize);
    if wu == 0 || hu == 0 {
        return Vec::new();
    }
    let mut codes = vec![0u16; wu * hu];
    if field.nx == 0 || field.ny == 0 {
        return codes;
    }
    let fit = Fit::new(field, w, h);
    let nx = i64::try_from(field.nx).unwrap_or(i64::MAX);
    let ny = i64::try_from(field.ny).unwrap_or(i64::MAX);
    let code_at = |x: i64, y: i64| -> u16 {
        if x < 0 || y < 0 || x >= nx || y >= ny {
            0
        } else {
            let state = (y as usize)
                .checked_mul(field.nx)
                .and_then(|i| i.checked_add(x as usize))
                .and_then(|i| field.states.get(i).copied())
                .unwrap_or(0);
            u16::from(state) + 1
        }
    };
    let xs: Vec<f64> = (0..w).map(|i| fit.phys_x(i)).collect();

    for (j, row) in codes.chunks_exact_mut(wu).enumerate() {
        let py = fit.phys_y(j as u32);
        if field.hex {
            // The nearest centre lies in one of the two rows bracketing py: a hexagon of row r
            // reaches only HEX_RADIUS < ROW_STEP above its centre, so rows further away never
            // win. Within a row the nearest centre is the rounded shifted x.
            let ra = (py / ROW_STEP).floor() as i64;
            let rb = ra + 1;
            let (sa, sb) = (0.5 * ra.rem_euclid(2) as f64, 0.5 * rb.rem_euclid(2) as f64);
            let (dya, dyb) = (py - ra as f64 * ROW_STEP, py - rb as f64 * ROW_STEP);
            let (dya2, dyb2) = (dya * dya, dyb * dyb);
            for (px, out) in xs.iter().zip(row.iter_mut()) {
                let ca = (px - sa + 0.5).floor();
                let cb = (px - sb + 0.5).floor();
                let dxa = px - (ca + sa);
                let dxb = px - (cb + sb);
                *out = if dxa * dxa + dya2 <= dxb * dxb + dyb2 {
                    code_at(ca as i64, ra)
                } else {
                    code_at(cb as i64, rb)
                };
            }
        } else {
            let r = (py + 0.5).floor() as i64;
            if r < 0 || r >= ny {
                continue;
            }
            for (px, out) in xs.iter().zip(row.iter_mut()) {
                *out = code_at((px + 0.5).floor() as i64, r);
            }
        }
    }

    if fit.scale < PRIORITY_SAMPLING_BELOW {
        // Cells about as small as pixels or smaller: every pixel also takes the most salient
        // state among the cells whose centres fall inside it, so one-cell-thin interfaces
        // survive.
        // Only rows that have states (a short `states` leaves the rest empty, drawn above).
        let rows = field.states.len().div_ceil(field.nx).min(field.ny);
        for y in 0..rows {
            let shift = if field.hex && y % 2 == 1 { 0.5 } else { 0.0 };
            let cy = if field.hex {
                y as f64 * ROW_STEP
            } else {
                y as f64
            };
            let jf = ((fit.ymax - cy) * fit.scale + fit.off_y).floor();
            if jf < 0.0 || jf >= f64::from(h) {
                continue;
            }
            let row = &mut codes[jf as usize * wu..(jf as usize + 1) * wu];
            let states = field
                .states
                .get(y * field.nx..((y + 1) * field.nx).min(field.states.len()))
                .unwrap_or(&[]);
            for (x, &s) in states.iter().enumerate() {
                let i = ((x as f64 + shift - fit.xmin) * fit.scale + fit.off_x).floor();
                if i >= 0.0 && i < f64::from(w) {
                    let c = &mut row[i as usize];
                    if salience(s) > salience_of_code(*c) {
                        *c = u16::from(s) + 1;
                    }
                }
            }
        }
    }
    codes
}

/// Drawing priority of state `s` when several cells share a pixel: 0 (empty) < 2 (occupied) <
/// 3..=255 (extra classes, by value) < 1 (interface).
fn salience(s: u8) -> u16 {
    match s {
        0 => 1,
        1 => 300,
        2 => 2,
        s => u16::from(s),
    }
}

/// [`salience`] of a raster code (0 = background, lowest of all).
fn salience_of_code(c: u16) -> u16 {
    match c {
        0 => 0,
        c => salience((c - 1) as u8),
    }
}

/// Colour lookup for [`rasterize_codes`] output: entry 0 is [`BACKGROUND`], entry `s + 1` the
/// colour of state `s`.
fn color_lut(palette: &Palette) -> Vec<[u8; 3]> {
    std::iter::once(BACKGROUND)
        .chain((0..=255u8).map(|s| palette.color(s)))
        .map(|RGBColor(r, g, b)| [r, g, b])
        .collect()
}

/// Draws `field` into RGB8 pixels (`width_px * height_px * 3` bytes, row 0 of the buffer at the
/// top, lattice row 0 at the bottom).
///
/// The field is scaled uniformly to fit the buffer, keeping its physical aspect ratio, and
/// centred; the rest is [`BACKGROUND`] (white), as are the notches along the zig-zag edges of a
/// hexagonal field. Each pixel shows the cell nearest to the pixel centre (for hexagonal
/// lattices the exact Voronoi cell, which is the hexagon). When a cell is smaller than about two
/// pixels, a pixel instead shows the most salient state among that cell and the cells whose
/// centres fall inside the pixel, so one-cell-thin interfaces stay visible in downscaled
/// pictures. Salience, highest first: interface (1), extra classes (255 down to 3), occupied
/// (2), empty (0). (Plain max sampling would let the occupied bulk (2) hide the interface.)
///
/// Never panics: missing states count as empty, an empty field gives an all-background picture,
/// and a zero `width_px` or `height_px` gives an empty vector.
pub fn rasterize(field: &CellField, palette: &Palette, width_px: u32, height_px: u32) -> Vec<u8> {
    let codes = rasterize_codes(field, width_px, height_px);
    let lut = color_lut(palette);
    let mut rgb = Vec::with_capacity(codes.len() * 3);
    for &c in &codes {
        rgb.extend_from_slice(&lut[usize::from(c)]);
    }
    rgb
}
