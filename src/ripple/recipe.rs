//! Recipes: scenario files of opt-in rules that the docs measure, built into the program, so
//! that `cellsurf ripple --recipe NAME` runs one without a copy of the repository.
//!
//! Principal type: [`Recipe`]. Its one recipe, [`Recipe::MatureCurrent`], is the file
//! `docs/ripple_mature_current.toml` (docs/ripple.md, "A recipe for mature current ripples"):
//! bins of 2.5 mm, 0.75-1.5 of the grains' flat-bed travel (1.6-3.4 mm at 0.5 m/s), a short
//! exponential travel in grain diameters, the leading bed stress, flow separation, thicker
//! water slices and crest suspension at `L` = 4.3 flat-bed travels of the median grain with a
//! sharp threshold, which give current ripples that stop growing, with slip faces, at 0.1 to
//! 0.4 mm. Every factor of it was chosen in a screen, not derived; it is for currents (not
//! measured against the wave predictor's 0.62 d0; the previous recipe, with 5 mm bins, gave
//! 7.7 / 2.6 / 0.86 times it at d0 = 0.1 / 0.2 / 0.4 m for 0.3 mm sand).

use std::fmt;
use std::str::FromStr;

use super::RippleError;
use super::params::RippleParams;

/// The text of the recipe for mature current ripples (a ripple scenario file).
pub const MATURE_CURRENT: &str = include_str!("../../docs/ripple_mature_current.toml");

/// A recipe of opt-in rules: the parameters it starts a run from, in place of the defaults.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Recipe {
    /// `mature-current`: current ripples that stop growing ([`MATURE_CURRENT`]).
    MatureCurrent,
}

impl Recipe {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Recipe::MatureCurrent => "mature-current",
        }
    }

    /// Its scenario file's text.
    pub fn text(self) -> &'static str {
        match self {
            Recipe::MatureCurrent => MATURE_CURRENT,
        }
    }

    /// The parameters it starts from: the defaults, with the recipe's keys set.
    pub fn params(self) -> RippleParams {
        RippleParams::from_toml(self.text()).expect("a built-in recipe is a valid scenario")
    }
}

impl FromStr for Recipe {
    type Err = RippleError;
    fn from_str(s: &str) -> Result<Self, RippleError> {
        match s {
            "mature-current" => Ok(Recipe::MatureCurrent),
            _ => Err(RippleError::Unknown {
                parameter: "recipe",
                value: s.to_string(),
                expected: "mature-current",
            }),
        }
    }
}

impl fmt::Display for Recipe {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The recipe sets the keys the docs measure (the bin, the automaton and the sand's depth,
    /// and opt-in rules): every other parameter keeps its default.
    #[test]
    fn the_mature_current_recipe_sets_its_keys_and_keeps_the_other_defaults() {
        let p = Recipe::MatureCurrent.params();
        let expected = RippleParams {
            mode: crate::ripple::Mode::TwoD,
            nx: 1024,
            ny: 1,
            bin_size: 0.0025,
            layer_thickness: 0.00025,
            layers: 400,
            hop_grains: 4.6875,
            hop_exponential: true,
            stress_lead: 4.0,
            separation_angle: 15.0,
            slice_layers: 6,
            crest_suspension_hops: 4.3,
            suspension_exponent: 8.0,
            ..RippleParams::default()
        };
        assert_eq!(p, expected);
        assert!(p.validate().is_ok());
    }

    #[test]
    fn recipe_names_round_trip_and_unknown_names_are_refused() {
        let r: Recipe = "mature-current".parse().unwrap();
        assert_eq!(r, Recipe::MatureCurrent);
        assert_eq!(r.to_string(), "mature-current");
        let e = "mature".parse::<Recipe>().unwrap_err().to_string();
        assert!(e.contains("recipe") && e.contains("mature-current"), "{e}");
    }
}
