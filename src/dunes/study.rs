//! Error against run time, and the observables over time, from independent seeds.
//!
//! [`run_seeds`] runs one configuration for seeds `first, first + 1, ...` (in parallel with
//! rayon; each run is single-threaded and timed on its own, so its time is its CPU time and
//! the results do not depend on the thread count), recording the observables as it goes.
//! [`error_curve`] turns the runs into the seed-to-seed standard error of an observable's
//! mean against the cumulative run time (the engine's [`ConvergePoint`]s);
//! [`evolution`] gives the mean and standard error of the dune bodies and the bare fraction
//! against iterations.

use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

use super::{DuneConfig, DuneError, DuneModel, DuneStats};
use crate::engine::stats::{self, ConvergePoint, mean_and_se};

/// One seed's run.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct SeedRun {
    /// The seed.
    pub seed: u64,
    /// Run time of the model, seconds (set-up and iterations, single thread; the
    /// measurements are not counted).
    pub cpu_s: f64,
    /// The observables at iteration 0, every `every` iterations, and at the end.
    pub series: Vec<DuneStats>,
}

impl SeedRun {
    /// The observables at the end of the run.
    pub fn last(&self) -> &DuneStats {
        self.series
            .last()
            .expect("a series holds at least iteration 0")
    }
}

/// Runs `cfg` (its iterations) for seeds `first_seed..first_seed + seeds`, in parallel,
/// recording the observables every `every` iterations; the runs come back in seed order.
pub fn run_seeds(
    cfg: &DuneConfig,
    first_seed: u64,
    seeds: usize,
    every: u64,
) -> Result<Vec<SeedRun>, DuneError> {
    cfg.validate()?;
    let every = every.max(1);
    (0..seeds as u64)
        .into_par_iter()
        .map(|k| {
            let mut c = cfg.clone();
            c.seed = first_seed + k;
            let t = Instant::now();
            let mut m = DuneModel::new(&c)?;
            let mut cpu = t.elapsed().as_secs_f64();
            let mut series = vec![m.stats()];
            while m.iteration() < c.iterations {
                let n = every.min(c.iterations - m.iteration());
                let t = Instant::now();
                m.run(n);
                cpu += t.elapsed().as_secs_f64();
                series.push(m.stats());
            }
            Ok(SeedRun {
                seed: c.seed,
                cpu_s: cpu,
                series,
            })
        })
        .collect()
}

/// Standard error of an observable's mean against cumulative run time.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ErrorCurve {
    /// A label for the configuration, e.g. `Q = 1`.
    pub label: String,
    /// The observable's name.
    pub observable: &'static str,
    /// Points for 2, 3, ..., m seeds.
    pub points: Vec<ConvergePoint>,
}

/// The standard error of the mean of `get` (at the end of each run) over the first
/// `2, 3, ...` runs, against their cumulative run time.
pub fn error_curve(
    label: &str,
    observable: &'static str,
    runs: &[SeedRun],
    get: fn(&DuneStats) -> f64,
) -> ErrorCurve {
    let samples: Vec<(f64, f64)> = runs.iter().map(|r| (get(r.last()), r.cpu_s)).collect();
    let points = stats::error_curve(&samples);
    ErrorCurve {
        label: label.to_string(),
        observable,
        points,
    }
}

/// Mean and standard error over seeds of the observables after some iterations.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct EvolutionPoint {
    /// Iterations done.
    pub iteration: u64,
    /// Mean number of dune bodies, and its standard error.
    pub bodies: (f64, f64),
    /// Mean bare fraction, and its standard error.
    pub bare: (f64, f64),
}

/// The mean and standard error over the runs of the dune bodies and the bare fraction at
/// each recorded iteration (runs of one configuration: their series line up).
pub fn evolution(runs: &[SeedRun]) -> Vec<EvolutionPoint> {
    let len = runs.iter().map(|r| r.series.len()).min().unwrap_or(0);
    (0..len)
        .map(|i| {
            let b: Vec<f64> = runs
                .iter()
                .map(|r| r.series[i].dune_bodies as f64)
                .collect();
            let f: Vec<f64> = runs.iter().map(|r| r.series[i].bare_fraction).collect();
            EvolutionPoint {
                iteration: runs[0].series[i].iteration,
                bodies: mean_and_se(&b),
                bare: mean_and_se(&f),
            }
        })
        .collect()
}
