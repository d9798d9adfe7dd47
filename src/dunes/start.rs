//! The initial state of a run ([`Start`]): the mode's random field, or one round sand
//! [`Pile`] on bare ground ([`gaussian_pile`]), as `cellsurf dunes --start` chooses.

use serde::{Deserialize, Serialize};

use super::{DuneConfig, DuneError, DuneModel, MAX_GRID, MAX_QUANTITY, Mode, to_grains};

/// A round pile of sand, `amp` height units high at its centre `(cx, cy)` (cells) and of
/// radius `r` cells (a Gaussian, `amp exp(-d^2 / r^2)`), on bare ground: grains of an `n x n`
/// grid. The pile is cut at the grid's edges, not wrapped round them.
pub fn gaussian_pile(n: usize, cx: f64, cy: f64, amp: f64, r: f64) -> Vec<u64> {
    (0..n * n)
        .map(|c| {
            let (dx, dy) = ((c % n) as f64 - cx, (c / n) as f64 - cy);
            to_grains(amp * (-(dx * dx + dy * dy) / (r * r)).exp())
        })
        .collect()
}

/// One round pile of sand on bare ground ([`gaussian_pile`]), placed by fractions of the grid
/// side so that it keeps its place on any grid. The defaults ([`Pile::DEFAULT`]) are the
/// `dunes_barchan` figure's pile.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pile {
    /// Centre `[x, y]` as fractions of the grid side `N`, each 0 to 1: the centre lies at
    /// `(x N, y N)` cells (`x` downwind, `y` across the wind). Default `[1/3, 1/2]`.
    pub centre: [f64; 2],
    /// Height at the centre, cell widths (height units). Default 6; above 0, at most 10^5.
    pub height: f64,
    /// Radius `r` of the Gaussian `height exp(-d^2 / r^2)`, cells. Default 12; above 0, at
    /// most 4096.
    pub radius: f64,
}

impl Pile {
    /// The `dunes_barchan` figure's pile: centre `[1/3, 1/2]` (a third of the way downwind,
    /// half way across), 6 cell widths high, radius 12 cells.
    pub const DEFAULT: Pile = Pile {
        centre: [1.0 / 3.0, 0.5],
        height: 6.0,
        radius: 12.0,
    };

    /// A pile with this centre (`[x, y]`, fractions of the grid side: exactly two values),
    /// height and radius, checked: the error names the parameter (`pile_centre`,
    /// `pile_height`, `pile_radius`), its value and the range.
    pub fn new(centre: &[f64], height: f64, radius: f64) -> Result<Pile, DuneError> {
        let bad = |name: &'static str, value: String, range: &'static str| {
            Err(DuneError::Parameter { name, value, range })
        };
        let text: Vec<String> = centre.iter().map(f64::to_string).collect();
        let Ok(centre) = <[f64; 2]>::try_from(centre) else {
            return bad(
                "pile_centre",
                text.join(","),
                "X,Y: two fractions of the grid side, each 0 to 1",
            );
        };
        if !centre.iter().all(|c| (0.0..=1.0).contains(c)) {
            return bad(
                "pile_centre",
                text.join(","),
                "X,Y: two fractions of the grid side, each 0 to 1",
            );
        }
        if !(height > 0.0 && height <= MAX_QUANTITY) {
            return bad(
                "pile_height",
                height.to_string(),
                "above 0, at most 10^5 cell widths",
            );
        }
        if !(radius > 0.0 && radius <= MAX_GRID as f64) {
            return bad(
                "pile_radius",
                radius.to_string(),
                "above 0, at most 4096 cells",
            );
        }
        Ok(Pile {
            centre,
            height,
            radius,
        })
    }

    /// The pile's grains on an `n x n` grid: [`gaussian_pile`] centred at `(x n, y n)` cells.
    pub fn grains(&self, n: usize) -> Vec<u64> {
        let [x, y] = self.centre;
        gaussian_pile(n, x * n as f64, y * n as f64, self.height, self.radius)
    }
}

impl Default for Pile {
    fn default() -> Self {
        Pile::DEFAULT
    }
}

/// The initial state of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Start {
    /// The mode's random field ([`DuneModel::new`]): uniform in `[0, 2Q]` in dune mode and
    /// Werner's (whole slabs), in `[2.85, 3.15]` in ripple mode.
    #[default]
    Random,
    /// One round pile on bare ground ([`DuneModel::from_grains`]); the sand quantity `Q` is
    /// not used. In Werner's variant each height is rounded to the nearest whole slab.
    Pile(Pile),
}

impl DuneModel {
    /// A model of `cfg` that starts from `start`: [`DuneModel::new`] for [`Start::Random`],
    /// [`DuneModel::from_grains`] with the pile's grains for [`Start::Pile`] (checked as
    /// [`Pile::new`] checks it).
    pub fn with_start(cfg: &DuneConfig, start: &Start) -> Result<Self, DuneError> {
        let Start::Pile(p) = start else {
            return DuneModel::new(cfg);
        };
        cfg.validate()?;
        let p = Pile::new(&p.centre, p.height, p.radius)?;
        let mut grains = p.grains(cfg.grid);
        if cfg.mode == Mode::Werner {
            let slab = to_grains(cfg.werner.slab).max(1);
            for g in grains.iter_mut() {
                *g = (*g + slab / 2) / slab * slab;
            }
        }
        DuneModel::from_grains(cfg, grains)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pile_out_of_range_is_refused_by_name() {
        for (c, h, r, want) in [
            (&[0.5][..], 6.0, 12.0, "pile_centre = 0.5 "),
            (&[0.5, 1.5][..], 6.0, 12.0, "pile_centre = 0.5,1.5 "),
            (&[f64::NAN, 0.5][..], 6.0, 12.0, "pile_centre = NaN,0.5 "),
            (&[0.5, 0.5][..], 0.0, 12.0, "pile_height = 0 "),
            (&[0.5, 0.5][..], f64::INFINITY, 12.0, "pile_height = inf "),
            (&[0.5, 0.5][..], 6.0, -1.0, "pile_radius = -1 "),
            (&[0.5, 0.5][..], 6.0, 5000.0, "pile_radius = 5000 "),
        ] {
            let e = Pile::new(c, h, r).unwrap_err().to_string();
            assert!(e.starts_with(want) && e.contains("expected"), "{e}");
        }
        assert_eq!(Pile::new(&[1.0 / 3.0, 0.5], 6.0, 12.0), Ok(Pile::DEFAULT));
    }

    #[test]
    fn werner_piles_are_whole_slabs() {
        let cfg = DuneConfig {
            mode: Mode::Werner,
            grid: 16,
            ..DuneConfig::default()
        };
        let m = DuneModel::with_start(&cfg, &Start::Pile(Pile::new(&[0.5; 2], 2.0, 3.0).unwrap()))
            .unwrap();
        assert!(m.grains().iter().all(|g| g % 100_000 == 0));
        assert!(m.grains().iter().any(|&g| g > 0));
    }
}
