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
    /// Dune-grid nodes along each side: 2 ..= the mosaic's bins along its longer side (a shorter
    /// side gets at most its own bins).
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
}

impl RippledDunes {
    /// Ripples from `mosaic` on dunes of `p` spanning the whole mosaic.
    pub fn new(mosaic: Mosaic, p: &DuneParams) -> Result<RippledDunes, TileError> {
        let (w, h) = mosaic.size();
        if p.grid < 2 || p.grid > w.max(h) {
            return Err(TileError::range(
                "dune_grid",
                p.grid,
                format!(
                    "2 ..= {} nodes (the surface's bins along its longer side)",
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
            dunes,
            mosaic,
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
    fn tile_size(&self) -> (usize, usize) {
        self.mosaic.tile_size()
    }
    fn fill_row(&self, y: usize, out: &mut [f32]) {
        self.fill_span(y, 0, out);
    }
    fn fill_span(&self, y: usize, x0: usize, out: &mut [f32]) {
        let ay = self.anchor.1 as i64;
        let j = (y as i64).div_euclid(ay);
        let ax = self.anchor.0 as i64;
        // the anchors round the span: columns i0 ..= i1 + 1
        let i0 = (x0 as i64).div_euclid(ax);
        let i1 = ((x0 + out.len()).max(1) as i64 - 1).div_euclid(ax);
        // the rotations of the two anchor rows round this row, once per row
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
