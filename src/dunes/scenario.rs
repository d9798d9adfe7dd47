//! [`DuneScenario`]: a `cellsurf dunes` scenario file read back by the library (the published
//! figures' runs): the subcommand's options as keys, its defaults for the others.

use serde::Deserialize;

use super::{BODY_THRESHOLD, DuneConfig, Mode, Pile, Start, WernerParams};
use crate::engine::scenario::{self, GridSize, ScenarioError};

/// The keys of a `cellsurf dunes` scenario file (`model = "dunes"`), as the subcommand's
/// `--print-scenario` writes them.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Keys {
    size: Option<GridSize>,
    steps: Option<u64>,
    dune: Option<bool>,
    quantity: Option<f64>,
    wind: Option<f64>,
    seed: Option<u64>,
    variant: Option<String>,
    hop: Option<u32>,
    threshold: Option<f64>,
    start: Option<String>,
    pile_centre: Option<Vec<f64>>,
    pile_height: Option<f64>,
    pile_radius: Option<f64>,
}

/// A `cellsurf dunes` run: its configuration and the dune-body threshold of its pictures.
#[derive(Clone, Debug, PartialEq)]
pub struct DuneScenario {
    /// The model's parameters.
    pub config: DuneConfig,
    /// Dune-body threshold, height units (the subcommand's `--threshold`, default
    /// [`BODY_THRESHOLD`]).
    pub threshold: f64,
    /// The initial state (the subcommand's `--start`, default [`Start::Random`]).
    pub start: Start,
}

impl DuneScenario {
    /// Reads a scenario file as `cellsurf dunes --scenario` does: `size` (a square grid),
    /// `steps` (iterations), `dune` and `variant` (`article` or `werner`: the mode), `quantity`,
    /// `wind`, `seed`, `hop` (Werner's), `threshold`, and `start` (`random` or `pile`) with the
    /// pile's `pile_centre`, `pile_height` and `pile_radius` (read with `start = "pile"` only);
    /// a key not given keeps the subcommand's default. The result is validated.
    pub fn parse(text: &str) -> Result<DuneScenario, ScenarioError> {
        let k: Keys = scenario::read(text, "dunes")?;
        let d = DuneConfig::default();
        let mode = match (k.variant.as_deref(), k.dune.unwrap_or(false)) {
            (Some("werner"), _) => Mode::Werner,
            (None | Some("article"), true) => Mode::Dune,
            (None | Some("article"), false) => Mode::Ripple,
            (Some(v), _) => {
                return Err(ScenarioError::new(format!(
                    "variant = \"{v}\" is out of range: expected \"article\" or \"werner\""
                )));
            }
        };
        let hop = k.hop.unwrap_or(d.werner.hop);
        if !super::HOP.contains(u64::from(hop)) {
            return Err(ScenarioError::new(format!(
                "hop = {hop} is out of range: expected {}",
                super::HOP.expected
            )));
        }
        let config = DuneConfig {
            mode,
            grid: match k.size {
                Some(g) => g.side("size")?,
                None => d.grid,
            },
            iterations: k.steps.unwrap_or(d.iterations),
            quantity: k.quantity.unwrap_or(d.quantity),
            wind: k.wind.unwrap_or(d.wind),
            seed: k.seed.unwrap_or(d.seed),
            werner: WernerParams {
                hop,
                ..WernerParams::default()
            },
        };
        config.validate().map_err(ScenarioError::new)?;
        let threshold = k.threshold.unwrap_or(BODY_THRESHOLD);
        if !(threshold.is_finite() && threshold >= 0.0) {
            return Err(ScenarioError::new(format!(
                "threshold = {threshold} is out of range: expected a finite height of at least 0 cell widths"
            )));
        }
        let start = match k.start.as_deref() {
            None | Some("random") => Start::Random,
            Some("pile") => {
                let d = Pile::DEFAULT;
                Start::Pile(
                    Pile::new(
                        k.pile_centre.as_deref().unwrap_or(&d.centre),
                        k.pile_height.unwrap_or(d.height),
                        k.pile_radius.unwrap_or(d.radius),
                    )
                    .map_err(ScenarioError::new)?,
                )
            }
            Some(s) => {
                return Err(ScenarioError::new(format!(
                    "start = \"{s}\" is out of range: expected \"random\" or \"pile\""
                )));
            }
        };
        Ok(DuneScenario {
            config,
            threshold,
            start,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_become_the_configuration_and_the_rest_keep_the_defaults() {
        let s = DuneScenario::parse("model = \"dunes\"\ndune = true\nquantity = 3.0\nsize = 64\n")
            .unwrap();
        assert_eq!(s.config.mode, Mode::Dune);
        assert_eq!(s.config.quantity, 3.0);
        assert_eq!(s.config.grid, 64);
        assert_eq!(s.config.iterations, DuneConfig::default().iterations);
        assert_eq!(s.threshold, BODY_THRESHOLD);
        let w = DuneScenario::parse("model = \"dunes\"\nvariant = \"werner\"\nhop = 7\n").unwrap();
        assert_eq!((w.config.mode, w.config.werner.hop), (Mode::Werner, 7));
        assert_eq!(w.start, Start::Random);
        let p = DuneScenario::parse("model = \"dunes\"\nstart = \"pile\"\npile_height = 3.0\n")
            .unwrap();
        assert_eq!(
            p.start,
            Start::Pile(Pile {
                height: 3.0,
                ..Pile::DEFAULT
            })
        );
        crate::engine::scenario::assert_refused(
            "dunes",
            DuneScenario::parse,
            &[
                ("variant = \"x\"", "variant"),
                ("size = \"4x5\"", "square"),
                ("hop = 0", "hop"),
                ("threshold = -1.0", "threshold"),
                ("quantity = -1.0", "quantity"),
                ("iterations = 5", "iterations"),
                ("start = \"heap\"", "start"),
                ("start = \"pile\"\npile_radius = 0.0", "pile_radius"),
                ("start = \"pile\"\npile_centre = [0.5]", "pile_centre"),
            ],
        );
    }
}
