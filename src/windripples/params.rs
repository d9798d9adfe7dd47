//! The parameters of a wind-ripple run ([`WindParams`]), the diffusion [`Schedule`] and the
//! parameter errors ([`WindError`]).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::engine::count::CountRange;
use crate::engine::scenario::{self, GridSize, ScenarioError};

/// Largest number of bins per side (`bins^2` = 16,777,216 cells, 64 MiB of counts).
pub const MAX_BINS: usize = 4096;
/// Largest number of particles (24 bytes each, 48 while they are sorted: 48 GiB at this
/// limit).
pub const MAX_PARTICLES: usize = 1 << 30;
/// `particles`: 1 to [`MAX_PARTICLES`].
pub const PARTICLES: CountRange =
    CountRange::new(1, MAX_PARTICLES as u64, "1 to 1073741824 (2^30)");
/// `bins`: histogram cells per side, 1 to [`MAX_BINS`].
pub const BINS: CountRange =
    CountRange::new(1, MAX_BINS as u64, "1 to 4096 (bins^2 histogram cells)");
/// `--size`, as [`BINS`] holds it.
pub const SIZE_SIDES: &str = "sides of 1 to 4096 cells (a square histogram)";
/// `steps`: steps of the loop.
pub const STEPS: CountRange = CountRange::new(1, 1_000_000_000, "1 to 1000000000 (1e9)");
/// Largest hop `L` and diffusion `D` accepted (the torus has size 1: far larger values only
/// lose the position's precision).
pub const MAX_LENGTH: f64 = 1e6;

/// How the diffusion step size changes with the step number.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Schedule {
    /// `sigma = D / sqrt(step + 1)`, `step` counted from 0: the notebook's numpy code (default).
    #[default]
    Annealed,
    /// `sigma = D` at every step: the notebook's torch code.
    Constant,
}

impl Schedule {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Schedule::Annealed => "annealed",
            Schedule::Constant => "constant",
        }
    }

    /// The diffusion step size of step `step` (counted from 0) for diffusion constant `d`.
    pub fn sigma(self, d: f64, step: u64) -> f64 {
        match self {
            Schedule::Annealed => d / ((step + 1) as f64).sqrt(),
            Schedule::Constant => d,
        }
    }
}

impl fmt::Display for Schedule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Schedule {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "annealed" => Ok(Schedule::Annealed),
            "constant" => Ok(Schedule::Constant),
            _ => Err(format!(
                "unknown schedule '{s}': expected annealed (D/sqrt(step+1), numpy) or constant (D, torch)"
            )),
        }
    }
}

/// A parameter out of its valid range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum WindError {
    /// `name = value` is outside `range`.
    #[error("{name} = {value} is out of range: expected {range}")]
    OutOfRange {
        /// The parameter (as on the command line: `particles`, `bins`, `steps`, `kappa`, `hop`,
        /// `diffusion`).
        name: &'static str,
        /// Its value, as given.
        value: String,
        /// The valid range, in words.
        range: &'static str,
    },
}

impl WindError {
    fn out_of_range(name: &'static str, value: impl fmt::Display, range: &'static str) -> Self {
        WindError::OutOfRange {
            name,
            value: value.to_string(),
            range,
        }
    }
}

/// The parameters of a run. Lengths are in units of the torus side (the torus is `[0, 1)^2`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WindParams {
    /// Histogram cells per side (`bins x bins` cells); default 256 (notebook `bins = 2**8`).
    pub bins: usize,
    /// Number of particles `N`; default 524,288 (notebook `N_particles = 2**16 * 8`).
    pub particles: usize,
    /// Number of steps of [`run`](super::run); default 1024 (notebook `N_step = 2**10`).
    pub steps: u64,
    /// Saltation hop `L` along `y`, torus units; default `1/64` (notebook `L = 1 / 2**6`).
    pub hop: f64,
    /// Saltation sensitivity to the height `kappa` (dimensionless; the height is 1 on average);
    /// default 4.5.
    pub kappa: f64,
    /// Diffusion `D`, torus units per step (standard deviation of one step's displacement per
    /// axis, before the schedule's factor); default `8e-4`.
    pub diffusion: f64,
    /// Diffusion schedule; default [`Schedule::Annealed`] (the notebook's numpy code).
    pub schedule: Schedule,
    /// Seed of the random streams; default 1998.
    pub seed: u64,
}

impl Default for WindParams {
    /// The notebook's `Params()`.
    fn default() -> Self {
        WindParams {
            bins: 256,
            particles: 524_288,
            steps: 1024,
            hop: 1.0 / 64.0,
            kappa: 4.5,
            diffusion: 8e-4,
            schedule: Schedule::Annealed,
            seed: 1998,
        }
    }
}

/// The keys of a `cellsurf wind-ripples` scenario file (`model = "wind-ripples"`): the
/// options of the subcommand, `size` for [`WindParams::bins`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Scenario {
    steps: Option<u64>,
    particles: Option<usize>,
    size: Option<GridSize>,
    kappa: Option<f64>,
    hop: Option<f64>,
    diffusion: Option<f64>,
    schedule: Option<Schedule>,
    seed: Option<u64>,
}

impl WindParams {
    /// Reads a `cellsurf wind-ripples` scenario file (as `--print-scenario` writes it): the
    /// keys given replace the defaults ([`WindParams::default`], the subcommand's too); the
    /// result is validated.
    pub fn from_scenario(text: &str) -> Result<WindParams, ScenarioError> {
        let s: Scenario = scenario::read(text, "wind-ripples")?;
        let d = WindParams::default();
        let p = WindParams {
            bins: match s.size {
                Some(g) => g.side("size")?,
                None => d.bins,
            },
            particles: s.particles.unwrap_or(d.particles),
            steps: s.steps.unwrap_or(d.steps),
            hop: s.hop.unwrap_or(d.hop),
            kappa: s.kappa.unwrap_or(d.kappa),
            diffusion: s.diffusion.unwrap_or(d.diffusion),
            schedule: s.schedule.unwrap_or(d.schedule),
            seed: s.seed.unwrap_or(d.seed),
        };
        p.validate().map_err(ScenarioError::new)?;
        Ok(p)
    }

    /// The parameters as `key = value` lines (TOML), with the model's name and the cellsurf
    /// version: recorded in the PNG files and the `.npy` sidecar.
    pub fn describe_toml(&self) -> String {
        format!(
            "model = \"wind-ripples\"\nversion = \"{}\"\nsteps = {}\nparticles = {}\nbins = {}\n\
             hop = {:?}\nkappa = {:?}\ndiffusion = {:?}\nschedule = \"{}\"\nseed = {}\n",
            crate::engine::VERSION,
            self.steps,
            self.particles,
            self.bins,
            self.hop,
            self.kappa,
            self.diffusion,
            self.schedule,
            self.seed
        )
    }

    /// Checks every parameter; the error names the first one out of range.
    pub fn validate(&self) -> Result<(), WindError> {
        for (name, v, r) in [
            ("particles", self.particles as u64, PARTICLES),
            ("bins", self.bins as u64, BINS),
            ("steps", self.steps, STEPS),
        ] {
            if !r.contains(v) {
                return Err(WindError::out_of_range(name, v, r.expected));
            }
        }
        if !(self.kappa.is_finite() && self.kappa >= 0.0) {
            return Err(WindError::out_of_range(
                "kappa",
                self.kappa,
                "a finite number >= 0",
            ));
        }
        if !(self.hop.is_finite() && (0.0..=MAX_LENGTH).contains(&self.hop)) {
            return Err(WindError::out_of_range(
                "hop",
                self.hop,
                "0 to 1e6 torus sides (L >= 1 wraps around)",
            ));
        }
        if !(self.diffusion.is_finite() && (0.0..=MAX_LENGTH).contains(&self.diffusion)) {
            return Err(WindError::out_of_range(
                "diffusion",
                self.diffusion,
                "0 to 1e6 torus sides per step",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedules_parse_and_give_the_notebook_step_sizes() {
        assert_eq!("annealed".parse::<Schedule>(), Ok(Schedule::Annealed));
        assert_eq!("constant".parse::<Schedule>(), Ok(Schedule::Constant));
        assert!(
            "numpy"
                .parse::<Schedule>()
                .unwrap_err()
                .contains("annealed")
        );
        assert_eq!(Schedule::default(), Schedule::Annealed);
        assert_eq!(Schedule::Annealed.sigma(8e-4, 0), 8e-4);
        assert_eq!(Schedule::Annealed.sigma(8e-4, 3), 4e-4);
        assert_eq!(Schedule::Constant.sigma(8e-4, 1000), 8e-4);
        assert_eq!(Schedule::Constant.to_string(), "constant");
    }
}
