//! Error-against-time studies split into independent runs, so that a study can be run whole by
//! one process or in parts by independent jobs ([`Part`]) and gathered.
//!
//! Principal items:
//! - [`Study`]: a study as a list of named runs ([`Study::runs`]), one run into a record
//!   ([`Study::run`], a TOML value: the numbers the figure needs and the run's CPU seconds), and
//!   the figure drawn from every record in run order ([`Study::draw`]).
//! - [`run_part`]: the records of a part's runs (every run for `0/1`), in parallel;
//!   [`run_part_reporting`] also tells a callback of each run as it finishes ([`RunDone`]).
//! - [`PartFile`]: what a part writes (study, version, part, records); [`gather`] checks that
//!   part files belong together and cover every run exactly once, and returns the records in
//!   run order.
//!
//! A run is fully determined by its name (case and seed), so the records, apart from the
//! measured run times, are the same whether one process or `N` parts made them.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

pub use super::part::Part;

/// A study split into independent runs (module docs).
pub trait Study: Sync {
    /// The study's name (`dunes`, `windripples`, ...).
    fn name(&self) -> &'static str;
    /// The name of the figure it draws (`NAME.png`, its table `data/NAME.csv`); by default
    /// `STUDY_error_vs_time`.
    fn figure(&self) -> String {
        format!("{}_error_vs_time", self.name())
    }
    /// Whether its runs may run at once (false when each run uses every core itself, or its
    /// timing is wall-clock time).
    fn parallel(&self) -> bool {
        true
    }
    /// The runs, in the order the figure uses them; names are unique.
    fn runs(&self) -> Vec<String>;
    /// Runs the run named `run` and returns its record.
    fn run(&self, run: &str) -> Result<toml::Value, String>;
    /// Draws the figure (and whatever files it writes) into `dir` from the records of every
    /// run, in the order of [`Study::runs`].
    fn draw(&self, records: &[toml::Value], dir: &Path) -> Result<Vec<PathBuf>, String>;
}

/// The records of part `part` of `study`'s runs (contiguous shares of the run list,
/// [`Part::range`]), as `(run name, record)`, run in parallel when [`Study::parallel`].
pub fn run_part(study: &dyn Study, part: Part) -> Result<Vec<(String, toml::Value)>, String> {
    run_part_reporting(study, part, &|_| {})
}

/// One finished run of a part, for progress reports ([`run_part_reporting`]).
#[derive(Clone, Copy, Debug)]
pub struct RunDone<'a> {
    /// Runs of the part finished so far, this one included.
    pub done: usize,
    /// Runs in the part.
    pub total: usize,
    /// This run's name.
    pub run: &'a str,
    /// Its wall-clock seconds.
    pub seconds: f64,
}

/// As [`run_part`], telling `progress` of every run as it finishes (from the thread that ran
/// it, in the order they finish). The records are the same, in run order.
pub fn run_part_reporting(
    study: &dyn Study,
    part: Part,
    progress: &(dyn Fn(RunDone) + Sync),
) -> Result<Vec<(String, toml::Value)>, String> {
    let runs = study.runs();
    let mine = &runs[part.range(runs.len())];
    let done = AtomicUsize::new(0);
    let one = |r: &String| {
        let t = Instant::now();
        let v = study.run(r)?;
        progress(RunDone {
            done: done.fetch_add(1, Ordering::Relaxed) + 1,
            total: mine.len(),
            run: r,
            seconds: t.elapsed().as_secs_f64(),
        });
        Ok((r.clone(), v))
    };
    if study.parallel() {
        mine.par_iter().map(one).collect()
    } else {
        mine.iter().map(one).collect()
    }
}

/// Runs every run of `study` and draws its figure into `dir`.
pub fn run_whole(study: &dyn Study, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let records: Vec<toml::Value> = run_part(study, Part::WHOLE)?
        .into_iter()
        .map(|(_, v)| v)
        .collect();
    study.draw(&records, dir)
}

/// The records a part of a study writes (`FIGURE.part-i-of-N.toml`, [`Study::figure`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartFile {
    /// The study.
    pub study: String,
    /// The cellsurf version that ran it.
    pub cellsurf_version: String,
    /// The part.
    pub part: Part,
    /// `(run name, record)` of every run of the part.
    pub records: Vec<PartRecord>,
}

/// One run's record in a [`PartFile`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartRecord {
    /// The run's name ([`Study::runs`]).
    pub run: String,
    /// Its record.
    pub record: toml::Value,
}

impl PartFile {
    /// The file name of part `part` of the study that draws `figure` ([`Study::figure`]).
    pub fn file_name(figure: &str, part: Part) -> String {
        format!("{figure}.part-{}-of-{}.toml", part.index, part.count)
    }
}

/// Checks that the part files `files` (contents, with their names for messages) are parts of
/// `study` made by this `version`, all of one count, and cover every run exactly once; returns
/// the records in run order.
pub fn gather(
    study: &dyn Study,
    version: &str,
    files: &[(String, PartFile)],
) -> Result<Vec<toml::Value>, String> {
    let runs = study.runs();
    let mut slots: Vec<Option<toml::Value>> = vec![None; runs.len()];
    let mut count = None;
    let mut seen_parts = std::collections::BTreeSet::new();
    for (name, f) in files {
        if f.study != study.name() {
            return Err(format!("{name}: a part of study {}", f.study));
        }
        if f.cellsurf_version != version {
            return Err(format!(
                "{name}: made by cellsurf {}, gathering with {version}",
                f.cellsurf_version
            ));
        }
        if *count.get_or_insert(f.part.count) != f.part.count {
            return Err(format!(
                "{name}: part {}/{} among parts of {}",
                f.part.index,
                f.part.count,
                count.unwrap_or(0)
            ));
        }
        seen_parts.insert(f.part.index);
        for r in &f.records {
            let Some(i) = runs.iter().position(|n| n == &r.run) else {
                return Err(format!("{name}: run '{}' is not part of the study", r.run));
            };
            if slots[i].replace(r.record.clone()).is_some() {
                return Err(format!("{name}: run '{}' recorded twice", r.run));
            }
        }
    }
    let missing: Vec<&str> = runs
        .iter()
        .zip(&slots)
        .filter(|(_, s)| s.is_none())
        .map(|(n, _)| n.as_str())
        .collect();
    if !missing.is_empty() {
        let parts: Vec<usize> = (0..count.unwrap_or(1))
            .filter(|p| !seen_parts.contains(p))
            .collect();
        return Err(format!(
            "{} of {} runs missing (first: '{}'); parts without a file: {parts:?}",
            missing.len(),
            runs.len(),
            missing[0]
        ));
    }
    Ok(slots.into_iter().flatten().collect())
}

/// A record from a serialisable value.
pub fn record<T: Serialize>(v: &T) -> Result<toml::Value, String> {
    toml::Value::try_from(v).map_err(|e| format!("record: {e}"))
}

/// A value back from a record.
pub fn from_record<T: for<'de> Deserialize<'de>>(v: &toml::Value) -> Result<T, String> {
    v.clone().try_into().map_err(|e| format!("record: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A study of `n` runs whose record is the square of the run's index.
    struct Squares(usize);

    impl Study for Squares {
        fn name(&self) -> &'static str {
            "squares"
        }
        fn runs(&self) -> Vec<String> {
            (0..self.0).map(|i| format!("run {i}")).collect()
        }
        fn run(&self, run: &str) -> Result<toml::Value, String> {
            let i: i64 = run[4..].parse().map_err(|e| format!("{e}"))?;
            Ok(toml::Value::Integer(i * i))
        }
        fn draw(&self, _: &[toml::Value], _: &Path) -> Result<Vec<PathBuf>, String> {
            Ok(Vec::new())
        }
    }

    fn part_file(s: &Squares, index: usize, count: usize) -> (String, PartFile) {
        let part = Part { index, count };
        let records = run_part(s, part)
            .unwrap()
            .into_iter()
            .map(|(run, record)| PartRecord { run, record })
            .collect();
        let f = PartFile {
            study: s.name().into(),
            cellsurf_version: "v".into(),
            part,
            records,
        };
        // through the file format and back
        let text = toml::to_string(&f).unwrap();
        (
            PartFile::file_name("squares_error_vs_time", part),
            toml::from_str(&text).unwrap(),
        )
    }

    #[test]
    fn parts_gather_to_the_whole_in_run_order() {
        let s = Squares(11);
        let whole: Vec<toml::Value> = (0..11).map(|i| toml::Value::Integer(i * i)).collect();
        for n in [1, 2, 3, 11, 13] {
            // any order of the part files
            let files: Vec<_> = (0..n).rev().map(|i| part_file(&s, i, n)).collect();
            assert_eq!(gather(&s, "v", &files).unwrap(), whole, "{n} parts");
        }
    }

    #[test]
    fn a_missing_or_repeated_part_is_an_error() {
        let s = Squares(10);
        let mut files: Vec<_> = (0..3).map(|i| part_file(&s, i, 3)).collect();
        let e = gather(&s, "v", &files[..2]).unwrap_err();
        assert!(e.contains("parts without a file: [2]"), "{e}");
        files.push(files[1].clone());
        let e = gather(&s, "v", &files).unwrap_err();
        assert!(e.contains("recorded twice"), "{e}");
        let mixed = vec![part_file(&s, 0, 2), part_file(&s, 1, 3)];
        assert!(
            gather(&s, "v", &mixed)
                .unwrap_err()
                .contains("among parts of")
        );
        assert!(
            gather(&s, "w", &files[..1])
                .unwrap_err()
                .contains("made by")
        );
    }
}
