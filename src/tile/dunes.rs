//! [`RippledDunes`]: ripples riding on dunes (paper, Sect. 3.4 and Fig. 9: "fractal properties of
//! dunes can be used to generate rippled dunes"). The surface is
//! `h(p) = D(p) + R(p)`: the dune relief `D` ([`DuneField`], bilinear between its nodes) plus the
//! ripple mosaic re-oriented to the local current.
//!
//! **Local current** (a documented modelling choice; the paper gives no rule): the near-bed
//! current is turned away from rising ground, `u = e(theta0) - steering * grad D`, where
//! `theta0` is the user's current angle and `grad D` the dune slope (m/m): flow steered round
//! the highs. Its direction is `theta(p)`; with a flat dune field it is `theta0` everywhere.
//!
//! **Re-orientation**: the tiles' crests are perpendicular to the current that made them
//! (`theta_t`). The mosaic is first turned by `theta0 - theta_t` about the origin (one rotation for
//! the whole surface, so it is exact: no interference), then by the local deflection
//! `delta = theta(p) - theta0` about *anchors* on a grid of `anchor` bins (half a tile):
//! anchor `k` maps `p` to `q_k = c_k + R(-delta_k) (p - c_k)` and the ripple height is the
//! bilinear blend over the four anchors round `p` of the mosaic sampled (bilinear, periodic) at
//! `q_k`. Each copy has its crests perpendicular to its anchor's current; neighbouring copies
//! differ by a shift of about `|delta_k - delta_l| x anchor`, small while the deflection changes
//! slowly over an anchor spacing (the blend then loses little ripple height).
//!
//! **Periodicity**: the dune field spans exactly the mosaic (its period is a whole number of
//! tiles) and the anchors divide the tiles, so with `theta0 = theta_t` (the default) the surface
//! is periodic like the mosaic; a different `theta0` rotates the whole ripple pattern and the
//! output no longer tiles exactly.

use super::TileError;
use super::fractal::{DuneField, FbmParams, Relief};
use super::mosaic::Mosaic;
use super::stream::RowSource;

/// The rms slope of the dune field that the default rms dune height gives
/// ([`RippledDunes::default_rms`]), degrees.
pub const DEFAULT_RMS_DUNE_SLOPE_DEG: f64 = 6.0;

/// Parameters of the rippled dunes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DuneParams {
    /// The dune spectrum ([`Relief::Fbm`] or [`Relief::Wavelength`]).
    pub relief: Relief,
    /// Rms dune height, m.
    pub rms: f64,
    /// Dune-grid nodes along each side: 3 ..= the mosaic's bins along its longer side, at most
    /// [`MAX_DUNE_GRID`] (a shorter side gets at most its own bins).
    pub grid: usize,
    /// Current direction theta0, degrees counter-clockwise from +x.
    pub current_angle: f64,
    /// Steering of the current by the dune slope (dimensionless, >= 0).
    pub steering: f64,
    /// Seed of the dune synthesis.
    pub seed: u64,
}

/// Ripples on dunes, row by row.
#[derive(Clone, Debug)]
pub struct RippledDunes {
    mosaic: Mosaic,
    dunes: DuneField,
    theta0: f64,
    steering: f64,
    /// Global rotation theta0 - theta_t: (cos, sin).
    base: (f64, f64),
    anchor: (usize, usize),
    anchors: (usize, usize),
    dx: f64,
    /// The dune-grid cell of every column ([`DuneField::row_cells`]).
    cells: Vec<(u32, f64)>,
    /// A number unique to this surface (shared by its clones, which are equal), naming it in
    /// the per-thread cache of anchor rotations.
    id: u64,
}

/// The most dune-grid nodes per side (the synthesis's FFT grid).
pub const MAX_DUNE_GRID: usize = 1 << 14;

impl RippledDunes {
    /// Ripples from `mosaic` on dunes of `p` spanning the whole mosaic.
    pub fn new(mosaic: Mosaic, p: &DuneParams) -> Result<RippledDunes, TileError> {
        let (w, h) = mosaic.size();
        // (a periodic grid of 2 nodes alternates: its central differences, the slopes the
        // interpolation and the slope statistics use, all vanish)
        // (at most the surface's bins along its longer side, and at most 16384, the largest
        // grid the dune synthesis takes)
        let most = w.max(h).min(MAX_DUNE_GRID);
        if p.grid < 3 || p.grid > most {
            return Err(TileError::range(
                "dune_grid",
                p.grid,
                format!(
                    "3 ..= {most} nodes (the surface's bins along its longer side, {}, and at most {MAX_DUNE_GRID}; a periodic grid of 2 nodes has no slope)",
                    w.max(h)
                ),
            ));
        }
        if !(p.steering.is_finite() && p.steering >= 0.0) {
            return Err(TileError::range("steering", p.steering, ">= 0"));
        }
        if !p.current_angle.is_finite() {
            return Err(TileError::range(
                "current_angle",
                p.current_angle,
                "a finite angle in degrees",
            ));
        }
        let dunes = DuneField::synthesize(&Self::field_params(&mosaic, p))?;
        Self::with_field(mosaic, dunes, p.current_angle, p.steering)
    }

    /// The dune field's synthesis parameters for `mosaic` and `p` (unchecked).
    fn field_params(mosaic: &Mosaic, p: &DuneParams) -> FbmParams {
        let (w, h) = mosaic.size();
        let dx = mosaic.tiles()[0].bin_size;
        let (gx, gy) = (p.grid.min(w).max(2), p.grid.min(h).max(2));
        let relief = match p.relief {
            Relief::Wavelength { wavelength, .. } => Relief::Wavelength {
                wavelength,
                current_angle: p.current_angle,
            },
            r => r,
        };
        FbmParams {
            nx: gx,
            ny: gy,
            dx: w as f64 * dx / gx as f64,
            dy: h as f64 * dx / gy as f64,
            relief,
            rms: p.rms,
            seed: p.seed,
        }
    }

    /// The default rms dune height (m) for `mosaic` and `p` (its `rms` is ignored): the rms that
    /// gives the dune field an rms slope of [`DEFAULT_RMS_DUNE_SLOPE_DEG`] at its grid. The
    /// synthesis is linear in the rms, so this is `tan(6 deg) / s1`, `s1` the rms slope (m/m) of
    /// the same field with an rms of 1 m. It scales with the dune-grid spacing (the extent over
    /// the grid nodes): a 20 m surface on 256 nodes gets centimetres, a 1 km one metres. The
    /// largest slope of a Gaussian field of 256 x 256 nodes is about 3.5 times its rms slope,
    /// about 20 deg: below the angle of repose (32 deg).
    pub fn default_rms(mosaic: &Mosaic, p: &DuneParams) -> Result<f64, TileError> {
        let unit = DuneField::synthesize(&FbmParams {
            rms: 1.0,
            ..Self::field_params(mosaic, p)
        })?;
        let s = unit.slope_stats().rms_deg.to_radians().tan();
        Ok(if s > 0.0 {
            DEFAULT_RMS_DUNE_SLOPE_DEG.to_radians().tan() / s
        } else {
            0.0
        })
    }

    /// Ripples from `mosaic` on a given dune field (its period should span the mosaic for a
    /// periodic result).
    pub fn with_field(
        mosaic: Mosaic,
        dunes: DuneField,
        current_angle: f64,
        steering: f64,
    ) -> Result<RippledDunes, TileError> {
        let (nx, ny) = mosaic.tile_size();
        let (w, h) = mosaic.size();
        let half = |n: usize| {
            if n.is_multiple_of(2) && n >= 8 {
                n / 2
            } else {
                n
            }
        };
        let anchor = (half(nx), half(ny));
        let theta_t = mosaic.tiles()[0].current_angle.to_radians();
        let theta0 = current_angle.to_radians();
        let b = theta0 - theta_t;
        Ok(RippledDunes {
            dx: mosaic.tiles()[0].bin_size,
            anchors: (w / anchor.0, h / anchor.1),
            anchor,
            base: (b.cos(), b.sin()),
            theta0,
            steering,
            cells: dunes.row_cells(mosaic.tiles()[0].bin_size, w),
            dunes,
            mosaic,
            id: NEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
        })
    }

    /// The dune field.
    pub fn dunes(&self) -> &DuneField {
        &self.dunes
    }
    /// The mosaic.
    pub fn mosaic(&self) -> &Mosaic {
        &self.mosaic
    }

    /// Direction of the local current at `(x, y)` m, radians.
    pub fn local_current(&self, x: f64, y: f64) -> f64 {
        let (gx, gy) = self.dunes.gradient(x, y);
        let s = self.steering;
        (self.theta0.sin() - s * gy).atan2(self.theta0.cos() - s * gx)
    }

    /// (cos, sin) of the local deflection `theta - theta0` at anchor `(i, j)` (indices wrapped).
    fn anchor_rotation(&self, i: i64, j: i64) -> (f64, f64) {
        let i = i.rem_euclid(self.anchors.0 as i64) as f64;
        let j = j.rem_euclid(self.anchors.1 as i64) as f64;
        let x = i * self.anchor.0 as f64 * self.dx;
        let y = j * self.anchor.1 as f64 * self.dx;
        let d = self.local_current(x, y) - self.theta0;
        (d.cos(), d.sin())
    }

    /// The ripple height at bin `(x, y)` given the rotations of the four anchors round it
    /// (`rot(di, dj)` for the anchor `(i + di, j + dj)`).
    fn ripple(&self, x: i64, y: i64, rot: impl Fn(usize, usize) -> (f64, f64)) -> f64 {
        let (ax, ay) = (self.anchor.0 as i64, self.anchor.1 as i64);
        let (i, j) = (x.div_euclid(ax), y.div_euclid(ay));
        let fx = (x - i * ax) as f64 / ax as f64;
        let fy = (y - j * ay) as f64 / ay as f64;
        let (bc, bs) = self.base;
        let mut sum = 0.0;
        for dj in 0..2usize {
            for di in 0..2usize {
                let w = if di == 0 { 1.0 - fx } else { fx } * if dj == 0 { 1.0 - fy } else { fy };
                if w == 0.0 {
                    continue;
                }
                let cx = ((i + di as i64) * ax) as f64;
                let cy = ((j + dj as i64) * ay) as f64;
                let (c, s) = rot(di, dj);
                let (px, py) = (x as f64 - cx, y as f64 - cy);
                // local deflection about the anchor, then the global turn about the origin
                let (lx, ly) = (cx + c * px + s * py, cy - s * px + c * py);
                let (qx, qy) = (bc * lx + bs * ly, -bs * lx + bc * ly);
                sum += w * self.mosaic.sample(qx, qy);
            }
        }
        sum
    }

    /// The surface height (m) at bin `(x, y)`, any integers (the dune field and anchors wrap).
    pub fn value(&self, x: i64, y: i64) -> f64 {
        let (ax, ay) = (self.anchor.0 as i64, self.anchor.1 as i64);
        let (i, j) = (x.div_euclid(ax), y.div_euclid(ay));
        let r = self.ripple(x, y, |di, dj| {
            self.anchor_rotation(i + di as i64, j + dj as i64)
        });
        self.dunes.height(x as f64 * self.dx, y as f64 * self.dx) + r
    }
}

impl RowSource for RippledDunes {
    fn width(&self) -> usize {
        self.mosaic.size().0
    }
    fn height(&self) -> usize {
        self.mosaic.size().1
    }
    fn bin_size(&self) -> f64 {
        self.dx
    }
    fn layer_thickness(&self) -> f64 {
        RowSource::layer_thickness(&self.mosaic)
    }
    fn tile_size(&self) -> (usize, usize) {
        self.mosaic.tile_size()
    }
    /// The same values as [`RippledDunes::value`], bit for bit: the dune heights of the row
    /// from per-row cubic coefficients, the anchor copies one after another over the bins
    /// between their anchors, the floors compiled to one instruction where the processor has
    /// AVX2.
    fn fill_row(&self, y: usize, out: &mut [f32]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2, checked just above.
            unsafe { self.fill_row_avx2(y, out) };
            return;
        }
        self.fill_row_by::<false>(y, out);
    }
    /// Bins `x0 .. x0 + out.len()` of row `y`, bin by bin from [`RippledDunes::value`]'s
    /// definition (the same bits as [`RowSource::fill_row`]): for stores written chunk by
    /// chunk, where a span is a small part of a row.
    fn fill_span(&self, y: usize, x0: usize, out: &mut [f32]) {
        let ay = self.anchor.1 as i64;
        let j = (y as i64).div_euclid(ay);
        let ax = self.anchor.0 as i64;
        // the anchors round the span: columns i0 ..= i1 + 1
        let i0 = (x0 as i64).div_euclid(ax);
        let i1 = ((x0 + out.len()).max(1) as i64 - 1).div_euclid(ax);
        let rows: Vec<Vec<(f64, f64)>> = (0..2)
            .map(|dj| {
                (i0..=i1 + 1)
                    .map(|i| self.anchor_rotation(i, j + dj))
                    .collect()
            })
            .collect();
        let yy = y as f64 * self.dx;
        for (k, o) in out.iter_mut().enumerate() {
            let x = x0 + k;
            let i = ((x as i64).div_euclid(ax) - i0) as usize;
            let r = self.ripple(x as i64, y as i64, |di, dj| rows[dj][i + di]);
            *o = (self.dunes.height(x as f64 * self.dx, yy) + r) as f32;
        }
    }
}

impl RippledDunes {
    /// [`RippledDunes::fill_row_by`] compiled for AVX2 (the library floor is then `roundsd`).
    ///
    /// # Safety
    /// The processor must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn fill_row_avx2(&self, y: usize, out: &mut [f32]) {
        self.fill_row_by::<true>(y, out);
    }

    /// Row `y` rounded to f32 from [`RippledDunes::row_by`].
    #[inline(always)]
    fn fill_row_by<const LIB: bool>(&self, y: usize, out: &mut [f32]) {
        let row = self.row_by::<LIB>(y, out.len());
        for (o, v) in out.iter_mut().zip(&row) {
            *o = *v as f32;
        }
    }

    /// Row `y`: the same values as [`RippledDunes::value`], bit for bit. The dune heights come
    /// from [`DuneField`]'s per-row cubic coefficients; then each anchor copy in turn over the
    /// bins between its anchors (its rotation and offsets hoisted), the four copies added in
    /// the order `value` adds them. The anchor rotations of the two anchor rows round `y` are
    /// kept per thread while the rows come in order. `LIB`: floors by the library
    /// ([`crate::engine::wrap::floor_by`]). `w`: the bins wanted (at most the width).
    #[inline(always)]
    fn row_by<const LIB: bool>(&self, y: usize, w: usize) -> Vec<f64> {
        let w = w.min(self.cells.len());
        let mut ripple = vec![0.0f64; w];
        let (ax, ay) = (self.anchor.0 as i64, self.anchor.1 as i64);
        let yi = y as i64;
        let j = yi.div_euclid(ay);
        let fy = (yi - j * ay) as f64 / ay as f64;
        // fx for every offset from the anchor column
        let fxs: Vec<f64> = (0..ax).map(|d| d as f64 / ax as f64).collect();
        let (bc, bs) = self.base;
        let turned = (bc, bs) != (1.0, 0.0);
        ANCHOR_ROWS.with_borrow_mut(|cache| {
            let rot = cache.rows(self, j);
            for (i, seg) in ripple.chunks_mut(ax as usize).enumerate() {
                let x_start = i as i64 * ax;
                for (dj, wy) in [(0, 1.0 - fy), (1, fy)] {
                    if wy == 0.0 {
                        continue; // every weight of this anchor row is zero
                    }
                    for di in 0..2 {
                        let cx = ((i as i64 + di) * ax) as f64;
                        let cy = ((j + dj) * ay) as f64;
                        let (c, s) = rot[dj as usize][i + di as usize];
                        let py = y as f64 - cy;
                        let (spy, cpy) = (s * py, c * py);
                        // the right anchor's weight fx is zero on its left anchor's column
                        let skip = di as usize;
                        let bins = seg.iter_mut().zip(&fxs).zip(x_start..).skip(skip);
                        for ((r, &fx), x) in bins {
                            let wx = if di == 0 { 1.0 - fx } else { fx };
                            let px = x as f64 - cx;
                            // local deflection about the anchor, then the global turn about the
                            // origin (none when the tiles' current is the user's: then
                            // `(qx, qy) = (lx, ly)` up to the sign of a zero, which the
                            // sampling ignores)
                            let (lx, ly) = (cx + c * px + spy, cy - s * px + cpy);
                            let (qx, qy) = if turned {
                                (bc * lx + bs * ly, -bs * lx + bc * ly)
                            } else {
                                (lx, ly)
                            };
                            *r += wx * wy * self.mosaic.sample_by::<LIB>(qx, qy);
                        }
                    }
                }
            }
        });
        let mut height = vec![0.0; w];
        self.dunes
            .height_row::<LIB>(y as f64 * self.dx, &self.cells[..w], &mut height);
        for (r, h) in ripple.iter_mut().zip(&height) {
            *r += h; // `value` adds the ripple to the height: the same sum
        }
        ripple
    }
}

/// The anchor rotations of two consecutive anchor rows of one [`RippledDunes`], kept per
/// thread: the rows of a block come in order, so a row mostly reuses its predecessor's.
#[derive(Default)]
struct AnchorRows {
    /// [`RippledDunes::id`] of the surface they belong to, 0 for none.
    owner: u64,
    /// The first of the two anchor rows.
    j: i64,
    rows: [Vec<(f64, f64)>; 2],
}

impl AnchorRows {
    /// The rotations of anchor rows `j` and `j + 1` of `d` (anchor columns `0 ..= anchors`).
    fn rows(&mut self, d: &RippledDunes, j: i64) -> &[Vec<(f64, f64)>; 2] {
        let row = |j: i64| -> Vec<(f64, f64)> {
            (0..=d.anchors.0 as i64)
                .map(|i| d.anchor_rotation(i, j))
                .collect()
        };
        if self.owner != d.id || self.j != j {
            if self.owner == d.id && self.j + 1 == j {
                self.rows.swap(0, 1);
            } else {
                self.rows[0] = row(j);
            }
            self.rows[1] = row(j + 1);
            (self.owner, self.j) = (d.id, j);
        }
        &self.rows
    }
}

thread_local! {
    static ANCHOR_ROWS: std::cell::RefCell<AnchorRows> = std::cell::RefCell::default();
}

/// The source of [`RippledDunes::id`].
static NEXT_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tile::{Choose, Tile};

    /// Tiles of oblique crests (`nx x ny` bins of 1 cm), a little different per tile.
    fn tiles(nx: usize, ny: usize, n: usize) -> Vec<Tile> {
        (0..n)
            .map(|k| {
                let e = (0..nx * ny)
                    .map(|i| {
                        let (x, y) = ((i % nx) as f64, (i / nx) as f64);
                        let a = 2.0 * std::f64::consts::PI * (x / 7.0 + y / (23.0 + k as f64));
                        (0.02 + 0.01 * a.cos() + 0.001 * k as f64) as f32
                    })
                    .collect();
                Tile::from_elevation(nx, ny, 0.01, e, "t").unwrap()
            })
            .collect()
    }

    /// Every bin of every row, by both floors, is `value`, bit for bit (in f64, before the
    /// rounding to f32 hides most differences; and after it): tile
    /// edges, cross-fade bands, patches, a turned pattern, whole-tile anchors, both reliefs.
    #[test]
    fn rows_are_the_values_bit_for_bit() {
        let fbm = Relief::Fbm { hurst: 0.6 };
        let band = Relief::Wavelength {
            wavelength: 0.3,
            current_angle: 0.0,
        };
        // (tile nx, ny, pool, cells, choose, blend, relief, current angle, steering, grid)
        let cases = [
            (16, 8, 1, (5, 9), Choose::Same, 0, fbm, 0.0, 3.0, 24),
            (16, 8, 3, (4, 6), Choose::Patches, 6, fbm, 0.0, 5.0, 17),
            (16, 8, 2, (4, 5), Choose::Patches, 0, fbm, 30.0, 3.0, 32),
            (9, 7, 2, (5, 6), Choose::Patches, 4, band, -70.0, 1.0, 40),
            (12, 10, 1, (3, 3), Choose::Same, 0, fbm, 0.0, 0.0, 3),
        ];
        for (nx, ny, n, (mx, my), choose, blend, relief, angle, steering, grid) in cases {
            let m = Mosaic::new(tiles(nx, ny, n), mx, my, choose, 7, blend).unwrap();
            let p = DuneParams {
                relief,
                rms: 0.05,
                grid,
                current_angle: angle,
                steering,
                seed: 3,
            };
            let d = RippledDunes::new(m, &p).unwrap();
            let (w, h) = (d.width(), d.height());
            let mut row = vec![0.0f32; w];
            // rows out of order as well as in order (the per-thread anchor rows)
            for y in (0..h).chain([h - 1, 0, 5, 4]) {
                d.fill_row(y, &mut row);
                let (a, b) = (d.row_by::<true>(y, w), d.row_by::<false>(y, w));
                for x in 0..w {
                    let v = d.value(x as i64, y as i64);
                    let at = format!("{nx}x{ny} ({x}, {y})");
                    assert_eq!(a[x].to_bits(), v.to_bits(), "{at}");
                    assert_eq!(b[x].to_bits(), v.to_bits(), "{at}");
                    assert_eq!(row[x].to_bits(), (v as f32).to_bits(), "{at}");
                }
            }
        }
    }
}
