//! Display of a height field: the article's "sea level" flooding and a continuous colour map.
//!
//! The article draws its landscapes with part of the area "evenly flooded" for better
//! perception: every cell lower than the *sea level* is drawn as water (its program starts with
//! `sea_level = 100`). [`SeaLevel`] sets the threshold as an absolute height, a fraction of the
//! mean height, or a quantile of the heights. The default, half the mean height, is 100 visits
//! for the article's 11,520,000 steps on the default 240 x 240 grid (mean height 200), the
//! article's starting value, and scales with the run length, so that runs of different lengths
//! or different `k` on the same grid are flooded alike (the article keeps "the sea level equal
//! for simulations with different k").
//!
//! [`terrain_rgb`] maps heights to colours: land from dark ochre just above the sea to pale sand
//! on the crests (linear in height up to the 99.5th percentile, which keeps a few extreme cells
//! from washing out the rest), water from light to deep blue with depth below the sea level,
//! and a light hill-shading from the north-west.

use serde::Serialize;

use super::CursorError;

/// How the sea level is set.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "rule", content = "value", rename_all = "snake_case")]
pub enum SeaLevel {
    /// An absolute height, in visits.
    Height(f64),
    /// A fraction of the mean height (the default is 0.5).
    MeanFraction(f64),
    /// Flood this fraction of the cells (0 to 1): the level of [`quantile_level`].
    Quantile(f64),
}

impl Default for SeaLevel {
    /// Half the mean height: 100 visits for 11,520,000 steps on 240 x 240 cells, as in the
    /// article.
    fn default() -> Self {
        SeaLevel::MeanFraction(0.5)
    }
}

impl SeaLevel {
    /// Checks the value: a finite height or fraction at least 0, a quantile in `[0, 1]`.
    ///
    /// # Errors
    ///
    /// [`CursorError::Parameter`] naming the scenario key that sets it: `sea_level`,
    /// `sea_fraction` or `sea_quantile`.
    pub fn validate(&self) -> Result<(), CursorError> {
        let (name, v, ok, range) = match *self {
            SeaLevel::Height(v) => (
                "sea_level",
                v,
                v >= 0.0,
                "expected a height of at least 0 visits",
            ),
            SeaLevel::MeanFraction(v) => (
                "sea_fraction",
                v,
                v >= 0.0,
                "expected a fraction of the mean height of at least 0",
            ),
            SeaLevel::Quantile(v) => (
                "sea_quantile",
                v,
                (0.0..=1.0).contains(&v),
                "expected 0 to 1",
            ),
        };
        if v.is_finite() && ok {
            Ok(())
        } else {
            Err(CursorError::Parameter {
                name,
                value: v,
                range: range.into(),
            })
        }
    }

    /// The sea level for `heights`, in visits.
    pub fn resolve(&self, heights: &[u64]) -> f64 {
        match *self {
            SeaLevel::Height(v) => v,
            SeaLevel::MeanFraction(f) => {
                let n = heights.len().max(1) as f64;
                f * heights.iter().sum::<u64>() as f64 / n
            }
            SeaLevel::Quantile(q) => quantile_level(heights, q),
        }
    }
}

/// The sea level that floods the fraction `q` of the cells (cells strictly below it are water):
/// the round(q n) lowest of the n cells. The level is the height of the lowest cell left dry,
/// or the highest height + 1 when every cell is flooded (q n rounds to n), so that
/// [`flooded_fraction`] gives round(q n) / n exactly. Cells of equal height are flooded
/// together (a level cannot split them): where a run of equal heights straddles the
/// round(q n)-th cell, the level floods the whole run or none of it, whichever count is
/// nearer to round(q n) (none of it on a tie). 0 for an empty slice; `q` outside [0, 1] is
/// taken as the nearer end ([`SeaLevel::validate`] refuses it).
pub fn quantile_level(heights: &[u64], q: f64) -> f64 {
    let n = heights.len();
    if n == 0 {
        return 0.0;
    }
    let mut v = heights.to_vec();
    v.sort_unstable();
    let k = ((q.clamp(0.0, 1.0) * n as f64).round() as usize).min(n);
    let level_for = |count: usize| {
        if count == n {
            v[n - 1] as f64 + 1.0
        } else {
            v[count] as f64
        }
    };
    if k == n {
        return level_for(n);
    }
    let u = v[k];
    // the cells below the run of heights equal to v[k], and below its end
    let below = v.partition_point(|&h| h < u);
    let through = v.partition_point(|&h| h <= u);
    if k - below <= through - k {
        level_for(below)
    } else {
        level_for(through)
    }
}

/// The `q`-quantile of `heights` (nearest rank, round(q (n - 1)); 0 for an empty slice): the
/// colour map's top. The sea level of [`SeaLevel::Quantile`] is [`quantile_level`].
pub fn quantile(heights: &[u64], q: f64) -> f64 {
    if heights.is_empty() {
        return 0.0;
    }
    let mut v = heights.to_vec();
    let i = ((q.clamp(0.0, 1.0) * (v.len() - 1) as f64).round() as usize).min(v.len() - 1);
    let (_, x, _) = v.select_nth_unstable(i);
    *x as f64
}

/// The fraction of cells strictly below the sea level `sea` (drawn as water).
pub fn flooded_fraction(heights: &[u64], sea: f64) -> f64 {
    if heights.is_empty() {
        return 0.0;
    }
    heights.iter().filter(|&&h| (h as f64) < sea).count() as f64 / heights.len() as f64
}

/// Colour stops of the land, from just above the sea (0) to the crests (1).
const LAND: [(f64, [f64; 3]); 4] = [
    (0.0, [112.0, 74.0, 38.0]),
    (0.35, [190.0, 132.0, 66.0]),
    (0.7, [232.0, 198.0, 136.0]),
    (1.0, [255.0, 248.0, 228.0]),
];
/// Colour stops of the water, from the shore (0) to the deepest (1).
const WATER: [(f64, [f64; 3]); 3] = [
    (0.0, [126.0, 192.0, 230.0]),
    (0.5, [52.0, 118.0, 186.0]),
    (1.0, [14.0, 40.0, 104.0]),
];

fn ramp(stops: &[(f64, [f64; 3])], t: f64) -> [f64; 3] {
    let t = t.clamp(0.0, 1.0);
    for w in stops.windows(2) {
        let ((t0, c0), (t1, c1)) = (w[0], w[1]);
        if t <= t1 {
            let f = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
            return [0, 1, 2].map(|i| c0[i] + f * (c1[i] - c0[i]));
        }
    }
    stops[stops.len() - 1].1
}

/// The colour of one cell of height `h`: water below `sea`, land from `sea` to `top`, with
/// the shading factor `shade` (1 = none) applied to land.
pub fn terrain_color(h: f64, sea: f64, top: f64, shade: f64) -> [u8; 3] {
    let c = if h < sea {
        let depth = if sea > 0.0 { (sea - h) / sea } else { 1.0 };
        ramp(&WATER, depth)
    } else {
        let t = if top > sea {
            (h - sea) / (top - sea)
        } else {
            1.0
        };
        ramp(&LAND, t).map(|v| v * shade)
    };
    c.map(|v| v.round().clamp(0.0, 255.0) as u8)
}

/// RGB8 pixels (`3 * width * cell_px * height * cell_px` bytes, picture row 0 at the top =
/// lattice row `height - 1`) of the height field `heights` (row-major, row 0 at the bottom),
/// each cell a `cell_px` square, flooded below `sea` (see the module documentation).
pub fn terrain_rgb(
    heights: &[u64],
    width: usize,
    height: usize,
    sea: f64,
    cell_px: usize,
) -> Vec<u8> {
    let cell_px = cell_px.max(1);
    let n = width * height;
    let top = quantile(&heights[..n.min(heights.len())], 0.995).max(sea + 1.0);
    let at = |x: usize, y: usize| heights.get(y * width + x).copied().unwrap_or(0) as f64;
    let (pw, ph) = (width * cell_px, height * cell_px);
    let mut out = vec![0u8; pw * ph * 3];
    for y in 0..height {
        for x in 0..width {
            let h = at(x, y);
            // Hill-shading: light from the upper left (north-west), periodic differences.
            let gx = at((x + 1) % width, y) - at((x + width - 1) % width, y);
            let gy = at(x, (y + 1) % height) - at(x, (y + height - 1) % height);
            let slope = (-gx + gy) / (2.0 * (top - sea).max(1.0));
            let shade = (1.0 + 1.5 * slope).clamp(0.75, 1.15);
            let c = terrain_color(h, sea, top, shade);
            let r0 = (height - 1 - y) * cell_px;
            for r in r0..r0 + cell_px {
                let row = &mut out[(r * pw + x * cell_px) * 3..(r * pw + (x + 1) * cell_px) * 3];
                for px in row.chunks_exact_mut(3) {
                    px.copy_from_slice(&c);
                }
            }
        }
    }
    out
}
