//! [`CursorScenario`]: a `cellsurf cursor` scenario file read back by the library (the
//! published figures' runs): the subcommand's options as keys, its defaults for the others.

use serde::Deserialize;

use super::wind::WindOptions;
use super::{ARTICLE_STEPS, DEFAULT_K, DEFAULT_SIZE, SeaLevel, WindSpec};
use crate::engine::scenario::{self, GridSize, ScenarioError};

/// The keys of a `cellsurf cursor` scenario file (`model = "cursor"`), as the subcommand's
/// `--print-scenario` writes them.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Keys {
    steps: Option<u64>,
    k: Option<f64>,
    wind_image: Option<String>,
    wind_scale: Option<f64>,
    wind_field: Option<String>,
    wind_angle: Option<f64>,
    wind_speed: Option<f64>,
    wind_spread: Option<f64>,
    wind_wavelength: Option<f64>,
    wind_spacing: Option<f64>,
    wind_radial: Option<f64>,
    wind_radius: Option<f64>,
    wind_arms: Option<u32>,
    size: Option<GridSize>,
    seed: Option<u64>,
    sea_level: Option<f64>,
    sea_fraction: Option<f64>,
    sea_quantile: Option<f64>,
}

/// A `cellsurf cursor` run on a built-in wind field.
#[derive(Clone, Debug, PartialEq)]
pub struct CursorScenario {
    /// Steps of the walk (default [`ARTICLE_STEPS`]).
    pub steps: u64,
    /// Force constant (default [`DEFAULT_K`]).
    pub k: f64,
    /// The wind field's generator, with the article's settings where the file gives none.
    pub wind: WindSpec,
    /// Grid size, cells (default [`DEFAULT_SIZE`]).
    pub size: (usize, usize),
    /// Seed of the walk (default 1).
    pub seed: u64,
    /// Sea level of the pictures (default [`SeaLevel::default`]).
    pub sea: SeaLevel,
}

impl CursorScenario {
    /// Reads a scenario file as `cellsurf cursor --scenario` does: `wind_field` (default
    /// calm) is a generator of [`WindSpec::article`] whose `wind_*` keys replace its settings
    /// (a key the generator does not take is an error), at most one of `sea_level`,
    /// `sea_fraction` and `sea_quantile`, and `steps`, `k`, `size`, `seed`. A `wind_image` is
    /// read by the subcommand only. The result is checked as the subcommand checks it.
    pub fn parse(text: &str) -> Result<CursorScenario, ScenarioError> {
        let k: Keys = scenario::read(text, "cursor")?;
        if let Some(p) = &k.wind_image {
            return Err(ScenarioError::new(format!(
                "wind_image = \"{p}\": a wind image is read by `cellsurf cursor`; the library reads scenarios of a built-in wind_field"
            )));
        }
        if k.wind_scale.is_some_and(|s| s != 1.0) {
            return Err(ScenarioError::new(
                "wind_scale applies to a wind_image only",
            ));
        }
        let name = k.wind_field.as_deref().unwrap_or("calm");
        let options = WindOptions {
            angle: k.wind_angle,
            speed: k.wind_speed,
            spread: k.wind_spread,
            wavelength: k.wind_wavelength,
            spacing: k.wind_spacing,
            radial: k.wind_radial,
            radius: k.wind_radius,
            arms: k.wind_arms,
        };
        let wind = WindSpec::article(name)
            .ok_or_else(|| {
                ScenarioError::new(format!(
                    "wind_field = \"{name}\" is out of range: expected calm, uniform, bimodal, converging or rotating"
                ))
            })?
            .with_options(&options)
            .map_err(|bad| ScenarioError::new(format!("{bad} does not apply to wind_field {name}")))?;
        wind.validate().map_err(ScenarioError::new)?;
        let sea = match (k.sea_level, k.sea_fraction, k.sea_quantile) {
            (Some(v), None, None) => SeaLevel::Height(v),
            (None, Some(f), None) => SeaLevel::MeanFraction(f),
            (None, None, Some(q)) => SeaLevel::Quantile(q),
            (None, None, None) => SeaLevel::default(),
            _ => {
                return Err(ScenarioError::new(
                    "sea_level, sea_fraction and sea_quantile: give one of them",
                ));
            }
        };
        sea.validate().map_err(ScenarioError::new)?;
        let size = match k.size {
            Some(g) => (g.w, g.h),
            None => DEFAULT_SIZE,
        };
        super::wind::check_size(size.0, size.1).map_err(ScenarioError::new)?;
        let s = CursorScenario {
            steps: k.steps.unwrap_or(ARTICLE_STEPS),
            k: k.k.unwrap_or(DEFAULT_K),
            wind,
            size,
            seed: k.seed.unwrap_or(1),
            sea,
        };
        if !super::STEPS.contains(s.steps) {
            return Err(ScenarioError::new(format!(
                "steps = {} is out of range: expected {}",
                s.steps,
                super::STEPS.expected
            )));
        }
        if !(s.k.is_finite() && (0.0..=1.0).contains(&s.k)) {
            return Err(ScenarioError::new(format!(
                "k = {} is out of range: expected 0 to 1",
                s.k
            )));
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generator_keys_replace_the_article_settings() {
        let s = CursorScenario::parse(
            "model = \"cursor\"\nwind_field = \"uniform\"\nwind_angle = 45.0\nsea_quantile = 0.3\n",
        )
        .unwrap();
        assert_eq!(
            s.wind,
            WindSpec::Uniform {
                angle_deg: 45.0,
                speed: 220.0
            }
        );
        assert_eq!(s.sea, SeaLevel::Quantile(0.3));
        assert_eq!(
            (s.steps, s.k, s.size, s.seed),
            (ARTICLE_STEPS, DEFAULT_K, DEFAULT_SIZE, 1)
        );
        let c = CursorScenario::parse(
            "model = \"cursor\"\nwind_field = \"converging\"\nwind_spacing = 40.0\nwind_radius = 20.0\n",
        )
        .unwrap();
        assert_eq!(
            c.wind,
            WindSpec::Converging {
                angle_deg: 0.0,
                speed: 50.0,
                radial: 160.0,
                wavelength: 80.0,
                spacing: 40.0,
                radius: 20.0
            }
        );
        let calm = CursorScenario::parse("model = \"cursor\"\n").unwrap();
        assert_eq!((calm.wind, calm.sea), (WindSpec::Calm, SeaLevel::default()));
        crate::engine::scenario::assert_refused(
            "cursor",
            CursorScenario::parse,
            &[
                ("wind_arms = 3", "wind_arms"),
                ("wind_field = \"storm\"", "storm"),
                ("sea_level = 1.0\nsea_quantile = 0.5", "sea_quantile"),
                ("k = 2.0", "k = 2"),
                ("steps = 0", "steps"),
                ("wind_image = \"w.png\"", "wind_image"),
                ("size = 2", "2x2"),
            ],
        );
    }
}
