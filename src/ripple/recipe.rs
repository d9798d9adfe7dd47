//! Recipes: scenario files of opt-in rules that the docs measure, built into the program, so
//! that `cellsurf ripple --recipe NAME` runs one without a copy of the repository.
//!
//! Principal type: [`Recipe`]. [`Recipe::Paper`] is the paper's rules and its Fig. 3
//! situation, the library's [`RippleParams::default`]; [`Recipe::MatureCurrent`] is the file
//! `docs/ripple_mature_current.toml` (docs/ripple.md, "A recipe for mature current ripples"):
//! bins of 0.75 of the median grain's flat-bed travel in the current
//! ([`RippleParams::bin_travels`]; 1.23 / 1.86 / 2.51 mm at 0.1 / 0.2 / 0.4 mm and 0.5 m/s),
//! automata a tenth of the bin and 10 cm of sand, a short exponential travel in grain
//! diameters, the leading bed stress, flow separation, thicker
//! water slices, crest suspension at `L` = 4 flat-bed travels of the median grain with a
//! sharp threshold, and the face hold (a grain is held wherever the rise ahead of it is
//! steeper than beta, [`RippleParams::stoss_face_hold`]), which give current ripples that stop
//! growing, with slip faces and stoss faces at beta + 2 deg or less (on 2-D sections in its
//! bins), at 0.1 to 0.4 mm. Every
//! factor of it was chosen in a screen, not derived; it is for currents (under waves, 0.3 mm
//! sand and U_w = 0.4 m/s, its ripples are 2.3 and 0.74 times the wave predictor's 0.62 d0 at
//! d0 = 0.2 and 0.4 m after 8000 s: they do not follow the orbit).

use std::fmt;
use std::str::FromStr;

use super::RippleError;
use super::params::RippleParams;
use super::travel::median_travel;

/// The longest a run of a recipe that runs until its field is mature lasts by default,
/// simulated seconds: 6 hours (the recipe's sections stop at 969-5155 s at 0.1-0.4 mm;
/// docs/ripple.md, "A recipe for mature current ripples").
pub const DEFAULT_CAP_S: f64 = 21_600.0;

/// The length of the recipe's ripples at equilibrium, in nominal flat-bed travels of the median
/// grain in the current ([`median_travel`]): 66, the mean of the 59-70 measured on its 2-D
/// sections (`cellsurf ripple --d50 D --current-speed U --seed N`, until equilibrium: 0.07 to
/// 0.8 mm at 0.5 m/s, seeds 1-3, and 0.2 mm at 0.35 to 0.65 m/s; docs/ripple.md, "The
/// current's speed and the grain"). A measured property of the recipe, not an input: all of its lengths are in
/// travels (its bin 0.75, its crest suspension 4), so its ripples follow the travel, which grows
/// with the current and, at a fixed current, stops growing with the grain above about 0.5 mm,
/// where nature's equilibrium current ripples follow the grain alone.
pub const TRAVELS_PER_WAVELENGTH: f64 = 66.0;

/// The length of the recipe for mature wave ripples' ripples at equilibrium, in orbital
/// excursion amplitudes `A = U_w T / (2 pi)`: 1.15, a round value within the 1.07-1.21 measured
/// at d0 = 0.2-0.4 m on its 2-D sections (means of seeds 1-3, whose mean is 1.12; 0.3 mm sand,
/// 0.4 m/s) and the 1.02-1.46 of d0 = 0.1-0.6 m (seed 1; docs/ripple.md, "A recipe for mature
/// wave ripples"). A measured
/// property of the recipe, not an input: all of its lengths are in units of `A`, so its
/// ripples follow the orbit at every period, where nature's leave it outside the orbital
/// range; `cellsurf ripple` warns where `1.15 A` is more than 20 % off Wiberg & Harris's.
pub const ORBITS_PER_WAVELENGTH: f64 = 1.15;

/// The wavelength the recipe's current ripples come to in the run `p`'s current, m:
/// [`TRAVELS_PER_WAVELENGTH`] nominal flat-bed travels of the median grain at
/// `p.current_speed`; `None` where the median grain does not move. `cellsurf ripple` compares
/// it with Soulsby & Whitehouse (2005) and warns where the two differ by more than 20 %.
pub fn expected_wavelength(p: &RippleParams) -> Option<f64> {
    let travel = median_travel(p, p.current_speed);
    (travel.is_finite() && travel > 0.0).then_some(TRAVELS_PER_WAVELENGTH * travel)
}

/// The text of the recipe for mature current ripples (a ripple scenario file).
pub const MATURE_CURRENT: &str = include_str!("../../docs/ripple_mature_current.toml");

/// The text of the recipe for mature wave ripples (a ripple scenario file): the rules of the
/// recipe for mature current ripples with a weaker leading stress, crest suspension at a fixed
/// height and no face hold (which acts under a current only), every length in units of the
/// waves' orbital excursion amplitude `A` (`orbit_reference`,
/// [`RippleParams::with_orbit_scale`]): bins of `A / 50`, automata a tenth of the bin, a
/// grain's flat-bed travel of `37.5 A` grain diameters (`A` in metres) per unit excess Shields
/// stage, crests suspended above `A / 10`. Every factor of it was chosen in a screen; its
/// ripples stop growing near 0.62 `d0` (0.3 mm sand, 0.4 m/s, `d0` = 0.2 to 0.4 m;
/// docs/ripple.md).
pub const MATURE_WAVES: &str = include_str!("../../docs/ripple_mature_waves.toml");

/// A recipe: the parameters a run starts from. `cellsurf ripple` starts from
/// [`Recipe::MatureCurrent`] where the current dominates the bed stress and from
/// [`Recipe::Paper`] where the waves do, unless `--recipe` or `--scenario` says otherwise.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Recipe {
    /// `paper`: the paper's rules in its Fig. 3 situation (3-D, 128 x 64 bins of 5 mm, 30
    /// automata of 0.5 mm, 10,000 steps), [`RippleParams::default`]; current ripples coarsen
    /// without end under them (docs/ripple.md).
    Paper,
    /// `mature-current`: current ripples that stop growing ([`MATURE_CURRENT`]).
    MatureCurrent,
    /// `mature-waves`: wave ripples whose lengths follow the orbit and that stop growing
    /// ([`MATURE_WAVES`]).
    MatureWaves,
}

impl Recipe {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Recipe::Paper => "paper",
            Recipe::MatureCurrent => "mature-current",
            Recipe::MatureWaves => "mature-waves",
        }
    }

    /// Its scenario file's text (the paper's: none, every key at its default).
    pub fn text(self) -> &'static str {
        match self {
            Recipe::Paper => "",
            Recipe::MatureCurrent => MATURE_CURRENT,
            Recipe::MatureWaves => MATURE_WAVES,
        }
    }

    /// The parameters it starts from: the defaults, with the recipe's keys set.
    pub fn params(self) -> RippleParams {
        RippleParams::from_toml(self.text()).expect("a built-in recipe is a valid scenario")
    }

    /// Whether a run of it without a length (`--steps`, `--duration`) runs until the field is
    /// mature (`--until equilibrium`, capped at [`DEFAULT_CAP_S`]) rather than for the default
    /// steps: the recipe for mature current ripples does, the paper's rules (whose fields
    /// coarsen without end) do not.
    pub fn runs_until_mature(self) -> bool {
        matches!(self, Recipe::MatureCurrent | Recipe::MatureWaves)
    }

    /// Whether its automata follow its bin where only the bin is given (`--bin-size` without
    /// `--layer-thickness`), as they follow its bin of flat-bed travels: the recipe for mature
    /// current ripples is one resolution, automata a tenth of the bin, so a bin of half its
    /// size halves the automata as well (and doubles `layers`, keeping its 10 cm of sand). Its
    /// ripples depend on the two together: in its former fixed bins of 2.5 mm, before the face
    /// hold, with the automata kept at 0.25 mm, bins of 1.25 mm made them 33-41 % shorter and
    /// bins of 5 mm 33-34 % longer, against 11-17 % shorter and 13-46 % longer with the
    /// automata following (docs/ripple.md, "The bin"). The paper's rules keep their automata
    /// (the paper gives the two apart).
    pub fn automata_follow_bin(self) -> bool {
        matches!(self, Recipe::MatureCurrent | Recipe::MatureWaves)
    }

    /// The layer thickness (m) and layers that go with `bin_size` (m) where the automata
    /// follow the bin ([`Recipe::automata_follow_bin`]): the recipe's ratio of bin to
    /// automaton and its depth of sand in metres (layers rounded to a whole number, at least
    /// 1). The thickness is rounded to 10 significant digits, as if typed.
    pub fn automata_for_bin(self, bin_size: f64) -> (f64, usize) {
        self.params().automata_for_bin(bin_size)
    }
}

impl FromStr for Recipe {
    type Err = RippleError;
    fn from_str(s: &str) -> Result<Self, RippleError> {
        match s {
            "paper" => Ok(Recipe::Paper),
            "mature-current" => Ok(Recipe::MatureCurrent),
            "mature-waves" => Ok(Recipe::MatureWaves),
            _ => Err(RippleError::Unknown {
                parameter: "recipe",
                value: s.to_string(),
                expected: "paper, mature-current or mature-waves",
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
            bin_travels: 0.75,
            hop_grains: 4.6875,
            hop_exponential: true,
            stress_lead: 4.0,
            separation_angle: 15.0,
            slice_layers: 6,
            crest_suspension_hops: 4.0,
            suspension_exponent: 8.0,
            stoss_face_hold: true,
            ..RippleParams::default()
        };
        assert_eq!(p, expected);
        assert!(p.validate().is_ok());
    }

    /// The paper's recipe is the library's defaults, and only the recipe for mature current
    /// ripples runs until its field is mature by default.
    #[test]
    fn the_paper_recipe_is_the_defaults() {
        assert_eq!(Recipe::Paper.params(), RippleParams::default());
        assert!(!Recipe::Paper.runs_until_mature());
        assert!(Recipe::MatureCurrent.runs_until_mature());
        assert!(Recipe::MatureWaves.runs_until_mature());
    }

    /// The recipe for mature wave ripples sets its keys, its lengths for waves of excursion
    /// 0.125 m, and keeps the other defaults; its lengths follow the orbit.
    #[test]
    fn the_mature_waves_recipe_sets_its_keys_in_units_of_the_orbit() {
        let p = Recipe::MatureWaves.params();
        let expected = RippleParams {
            mode: crate::ripple::Mode::TwoD,
            nx: 1024,
            ny: 1,
            orbit_reference: 0.125,
            bin_size: 0.0025,
            layer_thickness: 0.00025,
            layers: 400,
            hop_grains: 4.6875,
            hop_exponential: true,
            stress_lead: 2.0,
            separation_angle: 15.0,
            slice_layers: 6,
            crest_suspension: 0.0125,
            suspension_exponent: 8.0,
            ..RippleParams::default()
        };
        assert_eq!(p, expected);
        assert!(p.validate().is_ok());
        assert!(Recipe::MatureWaves.automata_follow_bin());
        // waves of d0 = 0.2 m (A = 0.1 m): bins of 2 mm, crests above 1 cm
        let w = RippleParams {
            current_speed: 0.0,
            wave_amplitude: 0.4,
            wave_period: 64.0,
            wave_friction_factor: 0.0186,
            wave_vortex: 0.1,
            ..p
        }
        .with_orbit_scale();
        assert_eq!(
            (w.bin_size, w.crest_suspension, w.hop_grains),
            (0.002, 0.01, 3.75)
        );
    }

    /// The recipe's automata follow its bin (a tenth of it, 10 cm of sand), exactly as if
    /// typed; the paper's do not.
    #[test]
    fn the_recipes_automata_follow_its_bin() {
        let r = Recipe::MatureCurrent;
        assert!(r.automata_follow_bin() && !Recipe::Paper.automata_follow_bin());
        assert_eq!(r.automata_for_bin(0.0025), (0.00025, 400));
        assert_eq!(r.automata_for_bin(0.00125), (0.000125, 800));
        assert_eq!(r.automata_for_bin(0.005), (0.0005, 200));
        assert_eq!(r.automata_for_bin(0.003), (0.0003, 333));
        assert_eq!(r.automata_for_bin(1.0), (0.1, 1));
    }

    /// The recipe's expected wavelength is 66 nominal travels of the median grain in the current,
    /// growing with the current; none below the threshold of motion.
    #[test]
    fn expected_wavelength_is_66_travels_of_the_current() {
        let mut p = Recipe::MatureCurrent.params();
        let at = |p: &RippleParams| expected_wavelength(p).unwrap();
        let default = at(&p);
        assert_eq!(default, 66.0 * median_travel(&p, 0.5));
        // 0.2 mm sand at 0.5 m/s: a nominal travel of 2.48 mm, 16.4 cm
        assert!((default - 0.164).abs() < 0.001, "{default}");
        p.current_speed = 0.65;
        assert!(at(&p) > 1.5 * default);
        p.current_speed = 0.1;
        assert_eq!(expected_wavelength(&p), None);
    }

    #[test]
    fn recipe_names_round_trip_and_unknown_names_are_refused() {
        for r in [Recipe::Paper, Recipe::MatureCurrent, Recipe::MatureWaves] {
            assert_eq!(r.name().parse::<Recipe>().unwrap(), r);
            assert_eq!(r.to_string(), r.name());
        }
        let e = "mature".parse::<Recipe>().unwrap_err().to_string();
        assert!(
            e.contains("recipe") && e.contains("mature-current") && e.contains("paper"),
            "{e}"
        );
    }
}
