//! [`Mosaic`]: a large surface as `mx x my` cells, each showing one toroidal tile of a pool
//! ([`Choose`]: the same tile everywhere, or seeded random "ripple patches"), with the optional
//! edge cross-fade of [`super::seam::edge_weights`]. Only the tiles and the cell grid are held:
//! any bin is computed on demand, so a mosaic far larger than memory can be streamed.
//!
//! Paper, Sect. 3.4: "neighboring tiles can be tiles from the same time step or, since changes
//! in between time steps are relatively small, can be from different but close time steps. The
//! last feature described allows the generation of ripple patches."

use std::fmt;
use std::str::FromStr;

use rand::RngExt;

use super::TileError;
use super::seam::edge_weights;
use super::stream::RowSource;
use super::tileset::{Tile, check_pool};
use crate::engine::rng;
use crate::engine::wrap::{floor_by, wrap};

/// Largest mosaic side in bins (NetCDF-3 dimensions are 32-bit signed).
pub const MAX_SIDE: usize = i32::MAX as usize;

/// How mosaic cells choose their tile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Choose {
    /// The first tile of the pool in every cell.
    Same,
    /// A tile drawn uniformly from the pool for each cell (seeded): ripple patches.
    Patches,
}

impl Choose {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Choose::Same => "same",
            Choose::Patches => "patches",
        }
    }
}

impl FromStr for Choose {
    type Err = TileError;
    fn from_str(s: &str) -> Result<Self, TileError> {
        match s {
            "same" => Ok(Choose::Same),
            "patches" => Ok(Choose::Patches),
            _ => Err(TileError::range("choose", s, "same or patches")),
        }
    }
}

impl fmt::Display for Choose {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A mosaic of tiles.
#[derive(Clone, Debug)]
pub struct Mosaic {
    tiles: Vec<Tile>,
    mx: usize,
    my: usize,
    nx: usize,
    ny: usize,
    grid: Vec<u32>,
    band: usize,
    /// Per column of the mosaic: (cell, neighbour cell, column in the tile, neighbour weight):
    /// one row's worth of memory, so that rows are filled without divisions or cosines.
    columns: Vec<(u32, u32, u32, f32)>,
    /// The same per row of the mosaic (one column's worth), for [`Mosaic::value`] and
    /// [`Mosaic::sample`] at any point without divisions or cosines.
    rows: Vec<(u32, u32, u32, f32)>,
    /// Every tile's elevation, one after another (the pool is small), and per cell of the
    /// grid the offset of its tile there: one load per bin instead of three.
    elevations: Vec<f32>,
    offsets: Vec<usize>,
    /// Per column `x` of the mosaic: (cell, column in the tile) when `x` and `x + 1` lie in
    /// the same cell with no cross-fade weight, else [`NOT_INTERIOR`]; [`Mosaic::sample`] then
    /// reads its four corners from one tile at one offset.
    interior_x: Vec<(u32, u32)>,
    /// The same per row `y`: (first cell of the cell row, `v * nx` with `v` the tile row).
    interior_y: Vec<(u32, u32)>,
}

/// The mark of a column or row whose bilinear cell straddles a tile edge or a cross-fade band.
const NOT_INTERIOR: u32 = u32::MAX;

impl Mosaic {
    /// `mx x my` cells choosing from `tiles` by `choose` (`seed` for patches), cross-faded over
    /// `band` bins at the tile edges (0 = none). Errors: an empty or mismatched pool, zero
    /// cells, a side beyond [`MAX_SIDE`] bins, a band wider than a tile.
    pub fn new(
        tiles: Vec<Tile>,
        mx: usize,
        my: usize,
        choose: Choose,
        seed: u64,
        band: usize,
    ) -> Result<Mosaic, TileError> {
        let n = tiles.len();
        let cells = mx.saturating_mul(my);
        if cells > 1 << 28 {
            return Err(TileError::range(
                "mosaic",
                format!("{mx}x{my}"),
                "at most 2^28 tiles",
            ));
        }
        let grid: Vec<u32> = match choose {
            Choose::Same => vec![0; cells],
            Choose::Patches => {
                let mut rng = rng::stream(seed);
                (0..cells)
                    .map(|_| rng.random_range(0..n.max(1)) as u32)
                    .collect()
            }
        };
        Self::with_grid(tiles, mx, my, grid, band)
    }

    /// A mosaic with the tile of every cell given (row-major `grid[j * mx + i]`, indices into
    /// `tiles`).
    pub fn with_grid(
        tiles: Vec<Tile>,
        mx: usize,
        my: usize,
        grid: Vec<u32>,
        band: usize,
    ) -> Result<Mosaic, TileError> {
        if mx == 0 || my == 0 {
            return Err(TileError::range(
                "mosaic",
                format!("{mx}x{my}"),
                "at least 1x1 tiles",
            ));
        }
        check_pool(&tiles)?;
        let (nx, ny) = (tiles[0].nx, tiles[0].ny);
        for (name, m, n) in [("mosaic width", mx, nx), ("mosaic height", my, ny)] {
            match m.checked_mul(n) {
                Some(w) if w <= MAX_SIDE => {}
                _ => {
                    return Err(TileError::range(
                        name,
                        format!("{m} tiles x {n} bins"),
                        format!("at most {MAX_SIDE} bins"),
                    ));
                }
            }
        }
        if grid.len() != mx * my {
            return Err(TileError::range(
                "mosaic grid",
                format!("{} cells", grid.len()),
                format!("mx x my = {}", mx * my),
            ));
        }
        if let Some(&g) = grid.iter().find(|&&g| g as usize >= tiles.len()) {
            return Err(TileError::range(
                "mosaic grid",
                g,
                format!("tile indices below {}", tiles.len()),
            ));
        }
        if band > nx.min(ny) {
            return Err(TileError::range(
                "blend",
                band,
                format!("0 ..= {} bins (the smaller tile side)", nx.min(ny)),
            ));
        }
        let columns: Vec<(u32, u32, u32, f32)> = (0..mx * nx)
            .map(|x| {
                let (c, c2, u, o) = Self::axis(x, nx, mx, band);
                (c as u32, c2 as u32, u as u32, o)
            })
            .collect();
        let rows: Vec<(u32, u32, u32, f32)> = (0..my * ny)
            .map(|y| {
                let (c, c2, v, o) = Self::axis(y, ny, my, band);
                (c as u32, c2 as u32, v as u32, o)
            })
            .collect();
        let elevations: Vec<f32> = tiles
            .iter()
            .flat_map(|t| t.elevation.iter().copied())
            .collect();
        let offsets = grid.iter().map(|&g| g as usize * nx * ny).collect();
        let interior_x = Self::interior(&columns, nx, 1, 1);
        let interior_y = Self::interior(&rows, ny, mx, nx);
        Ok(Mosaic {
            tiles,
            mx,
            my,
            nx,
            ny,
            grid,
            band,
            columns,
            rows,
            elevations,
            offsets,
            interior_x,
            interior_y,
        })
    }

    /// The interior table of one axis from its `(cell, neighbour, position, weight)` table
    /// (`n` bins per cell): `(cell * stride, position * scale)` where the bin and the next one
    /// lie in the same cell at full weight, else ([`NOT_INTERIOR`], 0).
    fn interior(
        axis: &[(u32, u32, u32, f32)],
        n: usize,
        stride: usize,
        scale: usize,
    ) -> Vec<(u32, u32)> {
        let full = |k: usize| axis.get(k).is_some_and(|a| a.3 == 0.0);
        (0..axis.len())
            .map(|k| {
                let (c, _, u, _) = axis[k];
                if (u as usize) + 1 < n && full(k) && full(k + 1) {
                    ((c as usize * stride) as u32, (u as usize * scale) as u32)
                } else {
                    (NOT_INTERIOR, 0)
                }
            })
            .collect()
    }

    /// Cells along x and y.
    pub fn cells(&self) -> (usize, usize) {
        (self.mx, self.my)
    }
    /// Tile size in bins.
    pub fn tile_size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }
    /// Bins along x and y.
    pub fn size(&self) -> (usize, usize) {
        (self.mx * self.nx, self.my * self.ny)
    }
    /// The tile pool.
    pub fn tiles(&self) -> &[Tile] {
        &self.tiles
    }
    /// The cross-fade band, bins.
    pub fn band(&self) -> usize {
        self.band
    }
    /// The tile index of cell `(i, j)` (wrapped: the mosaic is periodic).
    #[inline]
    pub fn cell(&self, i: usize, j: usize) -> usize {
        self.grid[(j % self.my) * self.mx + i % self.mx] as usize
    }

    /// Cell, neighbour cell, position in the tile and the neighbour's weight along one axis
    /// for bin `x`.
    #[inline]
    fn axis(x: usize, n: usize, m: usize, band: usize) -> (usize, usize, usize, f32) {
        let (c, u) = (x / n, x % n);
        let (_, side, o) = edge_weights(u, n, band);
        let c2 = match side {
            -1 => (c + m - 1) % m,
            1 => (c + 1) % m,
            _ => c,
        };
        (c, c2, u, o)
    }

    /// The elevation (m) of bin `(x, y)` of the mosaic (indices wrapped).
    #[inline]
    pub fn value(&self, x: usize, y: usize) -> f32 {
        let (w, h) = self.size();
        self.value_in(x % w, y % h)
    }

    /// [`Mosaic::value`] of a bin inside the mosaic (`x < width`, `y < height`), from the
    /// column and row tables.
    #[inline(always)]
    fn value_in(&self, x: usize, y: usize) -> f32 {
        let (ci, ci2, u, ox) = self.columns[x];
        let (cj, cj2, v, oy) = self.rows[y];
        let e = v as usize * self.nx + u as usize;
        let (r1, r2) = (cj as usize * self.mx, cj2 as usize * self.mx);
        let t = |r: usize, i: u32| self.elevations[self.offsets[r + i as usize] + e];
        if ox == 0.0 && oy == 0.0 {
            return t(r1, ci);
        }
        // (1 - o) a + o b written as a + o (b - a): exact where the tiles agree
        let lo = t(r1, ci) + ox * (t(r1, ci2) - t(r1, ci));
        let hi = t(r2, ci) + ox * (t(r2, ci2) - t(r2, ci));
        lo + oy * (hi - lo)
    }

    /// The elevation at a point `(x, y)` in bins (bin `i` centred at `i`), bilinear between bin
    /// centres, periodic.
    #[inline]
    pub fn sample(&self, x: f64, y: f64) -> f64 {
        self.sample_by::<false>(x, y)
    }

    /// [`Mosaic::sample`] with the floors by [`floor_by`]`::<LIB>` (the same bits).
    #[inline(always)]
    pub(crate) fn sample_by<const LIB: bool>(&self, x: f64, y: f64) -> f64 {
        let (w, h) = self.size();
        let (fx, fy) = (floor_by::<LIB>(x), floor_by::<LIB>(y));
        let (ax, ay) = (x - fx, y - fy);
        let x0 = wrap(fx as i64, w);
        let y0 = wrap(fy as i64, h);
        let ((ci, u), (r, vn)) = (self.interior_x[x0], self.interior_y[y0]);
        let [v00, v10, v01, v11] = if ci != NOT_INTERIOR && r != NOT_INTERIOR {
            // the four corners in one tile, away from its edges and the cross-fade: the values
            // `value_in` gives there, read at one offset
            let e = self.offsets[(r + ci) as usize] + (vn + u) as usize;
            let (lo, hi) = (
                &self.elevations[e..e + 2],
                &self.elevations[e + self.nx..][..2],
            );
            [lo[0], lo[1], hi[0], hi[1]].map(f64::from)
        } else {
            let x1 = if x0 + 1 == w { 0 } else { x0 + 1 };
            let y1 = if y0 + 1 == h { 0 } else { y0 + 1 };
            [(x0, y0), (x1, y0), (x0, y1), (x1, y1)].map(|(x, y)| self.value_in(x, y) as f64)
        };
        (1.0 - ay) * ((1.0 - ax) * v00 + ax * v10) + ay * ((1.0 - ax) * v01 + ax * v11)
    }

    /// Levels of the volume field (the tallest tile's), 0 without volumes.
    pub fn levels(&self) -> usize {
        self.tiles
            .iter()
            .filter_map(|t| t.volume.as_ref().map(|v| v.nz))
            .max()
            .unwrap_or(0)
    }
}

impl RowSource for Mosaic {
    fn width(&self) -> usize {
        self.size().0
    }
    fn height(&self) -> usize {
        self.size().1
    }
    fn bin_size(&self) -> f64 {
        self.tiles[0].bin_size
    }
    fn tile_size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }
    fn fill_row(&self, y: usize, out: &mut [f32]) {
        self.fill_span(y, 0, out);
    }
    fn fill_span(&self, y: usize, x0: usize, out: &mut [f32]) {
        // the same arithmetic as `value`, with the row's y terms and the column table hoisted
        let y = y % self.height();
        let (cj, cj2, v, oy) = Self::axis(y, self.ny, self.my, self.band);
        let (r1, r2) = (cj * self.mx, cj2 * self.mx);
        let base = v * self.nx;
        for (o, &(ci, ci2, u, ox)) in out.iter_mut().zip(&self.columns[x0..]) {
            let e = base + u as usize;
            let t = |r: usize, i: u32| self.elevations[self.offsets[r + i as usize] + e];
            *o = if ox == 0.0 && oy == 0.0 {
                t(r1, ci)
            } else {
                let lo = t(r1, ci) + ox * (t(r1, ci2) - t(r1, ci));
                let hi = t(r2, ci) + ox * (t(r2, ci2) - t(r2, ci));
                lo + oy * (hi - lo)
            };
        }
    }
    fn levels(&self) -> usize {
        Mosaic::levels(self)
    }
    fn layer_thickness(&self) -> f64 {
        self.tiles[0].layer_thickness
    }
    /// The volume under row `y` on `(z, x)`, NaN above the bed: each column is the column of
    /// the bin's own cell's tile (the tile with the largest blend weight), cut or extended
    /// (repeating its top automaton) to the blended surface height, rounded to whole layers.
    fn fill_volume_row(&self, y: usize, out: &mut [f32]) {
        self.fill_volume_span(y, 0, out);
    }
    fn fill_volume_span(&self, y: usize, x0: usize, out: &mut [f32]) {
        let nz = self.levels();
        out.fill(f32::NAN);
        if nz == 0 {
            return;
        }
        let w = out.len() / nz;
        let gd = self.tiles[0].layer_thickness;
        let yy = y % self.height();
        let (cj, v) = (yy / self.ny, yy % self.ny);
        for i in 0..w {
            let x = x0 + i;
            let (ci, u) = (x / self.nx, x % self.nx);
            let t = &self.tiles[self.cell(ci, cj)];
            let Some(vol) = &t.volume else { continue };
            let e = v * self.nx + u;
            let plane = self.nx * self.ny;
            let own = (0..vol.nz)
                .take_while(|&k| vol.data[k * plane + e].is_finite())
                .count();
            let top = ((self.value(x, y) as f64 / gd).round().max(0.0) as usize).min(nz);
            for k in 0..top {
                let src = k.min(own.saturating_sub(1));
                out[k * w + i] = if own == 0 {
                    f32::NAN
                } else {
                    vol.data[src * plane + e]
                };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tile(nx: usize, ny: usize, f: impl Fn(usize, usize) -> f32) -> Tile {
        let e = (0..nx * ny).map(|i| f(i % nx, i / nx)).collect();
        Tile::from_elevation(nx, ny, 0.01, e, "t").unwrap()
    }

    #[test]
    fn same_tile_mosaic_repeats_the_tile() {
        let t = tile(5, 3, |x, y| (x * 10 + y) as f32);
        let m = Mosaic::new(vec![t.clone()], 3, 2, Choose::Same, 1, 0).unwrap();
        assert_eq!(m.size(), (15, 6));
        for y in 0..6 {
            for x in 0..15 {
                assert_eq!(m.value(x, y), t.at(x, y));
            }
        }
    }

    #[test]
    fn blend_of_identical_tiles_changes_nothing() {
        let t = tile(8, 8, |x, y| ((x * 7 + y * 3) % 5) as f32);
        let a = Mosaic::new(vec![t.clone(), t.clone()], 3, 3, Choose::Patches, 4, 0).unwrap();
        let b = Mosaic::new(vec![t.clone(), t], 3, 3, Choose::Patches, 4, 6).unwrap();
        for y in 0..24 {
            for x in 0..24 {
                assert!((a.value(x, y) - b.value(x, y)).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn rows_agree_with_single_values() {
        let a = tile(8, 6, |x, y| ((x * 7 + y * 3) % 5) as f32);
        let b = tile(8, 6, |x, y| ((x + y * 5) % 7) as f32 * 0.3);
        let m = Mosaic::new(vec![a, b], 3, 4, Choose::Patches, 9, 6).unwrap();
        let (w, h) = m.size();
        let mut row = vec![0.0; w];
        for y in 0..h {
            m.fill_row(y, &mut row);
            for (x, v) in row.iter().enumerate() {
                assert_eq!(*v, m.value(x, y), "({x}, {y})");
            }
        }
    }

    #[test]
    fn bilinear_sample_hits_bin_centres_and_wraps() {
        let t = tile(4, 4, |x, y| (x + 4 * y) as f32);
        let m = Mosaic::new(vec![t], 2, 1, Choose::Same, 1, 0).unwrap();
        assert_eq!(m.sample(2.0, 1.0), 6.0);
        assert_eq!(m.sample(2.5, 1.0), 6.5);
        assert_eq!(m.sample(10.0, 5.0), m.sample(2.0, 1.0));
        assert_eq!(m.sample(-6.0, -3.0), m.sample(2.0, 1.0));
    }

    #[test]
    fn zero_cells_and_wide_band_rejected() {
        let t = tile(4, 4, |_, _| 0.0);
        let e = Mosaic::new(vec![t.clone()], 0, 3, Choose::Same, 1, 0).unwrap_err();
        assert!(e.to_string().contains("mosaic = 0x3"), "{e}");
        let e = Mosaic::new(vec![t], 2, 2, Choose::Same, 1, 5).unwrap_err();
        assert!(e.to_string().contains("blend = 5"), "{e}");
        let e = Mosaic::new(vec![], 2, 2, Choose::Same, 1, 0).unwrap_err();
        assert!(e.to_string().contains("tiles"), "{e}");
    }
}
