//! The figure registry (feature `plot`): every model's published figures in one list.
//!
//! Each model lists its own figures ([`crate::growth::figures::FIGURES`],
//! [`crate::ripple::FIGURES`], ...); [`all`] gathers them for `cellsurf figures`. Nothing in
//! the library imports this module: it sits above every model.
//!
//! A figure made from one run of a subcommand (or one run a panel) takes its parameters from
//! its scenario file in `scenarios/` ([`scenarios`]); the others, listed in
//! [`WITHOUT_SCENARIO`], are studies over many runs.
//!
//! The figures of [`MEASURED`] plot measured run times, which differ from run to run. They
//! are drawn from their committed tables (`figures/data/NAME.csv` and `.toml`, see
//! [`ChartTable`]) by [`make`], so that regenerating the figures gives the same bytes (in a
//! folder without its own tables, from the tables the program was built with);
//! `cellsurf converge MODEL` re-measures them ([`make`] with `remeasure`), writing table and
//! figure anew.

use std::path::{Path, PathBuf};

use crate::plot::{ChartTable, Figure, FigureError, PlotError, record_charts};

/// Every figure of every model: the growth paper's, then the related models'.
pub fn all() -> impl Iterator<Item = &'static Figure> {
    crate::growth::figures::FIGURES
        .iter()
        .chain(crate::windripples::FIGURES)
        .chain(crate::dunes::FIGURES)
        .chain(crate::cursor::FIGURES)
        .chain(crate::ripple::FIGURES)
        .chain(crate::raytrace::FIGURES)
        .chain(crate::tile::FIGURES)
}

/// Every scenario file of `scenarios/` that a figure runs, as `(NAME, text)` for
/// `scenarios/NAME.toml`: a figure's own (`NAME` its name), or one of its panels' (`NAME` its
/// name, `_` and the panel). The figures take their parameters from these texts, embedded when
/// the program was built; `cellsurf SUB --scenario scenarios/NAME.toml` runs each (its first
/// comment says which figure of which source it reproduces, its `# Run:` line the command).
pub fn scenarios() -> impl Iterator<Item = &'static (&'static str, &'static str)> {
    crate::growth::figures::SCENARIOS
        .iter()
        .chain(crate::windripples::figures::SCENARIOS)
        .chain(crate::dunes::SCENARIOS)
        .chain(crate::cursor::SCENARIOS)
        .chain(crate::ripple::figures::SCENARIOS)
        .chain(crate::raytrace::figures::SCENARIOS)
        .chain(crate::tile::figures::SCENARIOS)
}

/// The other files of `scenarios/`: the tables a scenario file names (by the path written in
/// it, from the scenarios' folder), with their texts.
pub fn scenario_tables() -> impl Iterator<Item = &'static (&'static str, &'static str)> {
    crate::raytrace::figures::TABLES.iter()
}

/// A study over many runs: its figure has no scenario file.
const STUDY: &str =
    "a study over many runs (seeds, sizes or parameters), not one run of a subcommand";

/// The figures without a scenario file, and why: the studies over many runs.
pub const WITHOUT_SCENARIO: &[(&str, &str)] = &[
    ("growth_error_vs_time", STUDY),
    ("growth_kpz_roughness", STUDY),
    ("windripples_error_vs_time", STUDY),
    ("dunes_error_vs_time", STUDY),
    ("cursor_k_effect", STUDY),
    ("cursor_error_vs_time", STUDY),
    ("ripple_error_vs_time", STUDY),
    ("ripple_validation", STUDY),
    ("raytrace_error_vs_time", STUDY),
];

/// The figure called `name`.
pub fn find(name: &str) -> Option<&'static Figure> {
    all().find(|f| f.name == name)
}

/// The figures whose charts plot measured run times, by model (the `cellsurf converge`
/// argument).
pub const MEASURED: &[(&str, &str)] = &[
    ("growth", "growth_error_vs_time"),
    ("dunes", "dunes_error_vs_time"),
    ("raytrace", "raytrace_error_vs_time"),
    ("ripple", "ripple_error_vs_time"),
    ("windripples", "windripples_error_vs_time"),
    ("ripple_validation", "ripple_validation"),
];

/// The committed tables of the [`MEASURED`] figures (`figures/data/NAME.csv` and `.toml`) as
/// this program was built with them: a folder without its own table gets the same figure.
const COMMITTED: &[(&str, &str, &str)] = &[
    (
        "growth_error_vs_time",
        include_str!("../figures/data/growth_error_vs_time.csv"),
        include_str!("../figures/data/growth_error_vs_time.toml"),
    ),
    (
        "dunes_error_vs_time",
        include_str!("../figures/data/dunes_error_vs_time.csv"),
        include_str!("../figures/data/dunes_error_vs_time.toml"),
    ),
    (
        "raytrace_error_vs_time",
        include_str!("../figures/data/raytrace_error_vs_time.csv"),
        include_str!("../figures/data/raytrace_error_vs_time.toml"),
    ),
    (
        "ripple_error_vs_time",
        include_str!("../figures/data/ripple_error_vs_time.csv"),
        include_str!("../figures/data/ripple_error_vs_time.toml"),
    ),
    (
        "windripples_error_vs_time",
        include_str!("../figures/data/windripples_error_vs_time.csv"),
        include_str!("../figures/data/windripples_error_vs_time.toml"),
    ),
    (
        "ripple_validation",
        include_str!("../figures/data/ripple_validation.csv"),
        include_str!("../figures/data/ripple_validation.toml"),
    ),
];

/// Makes figure `f` in `dir`. A [`MEASURED`] figure is drawn from its table in `dir/data/`
/// when there is one and `remeasure` is false, else from the committed table this program was
/// built with (written into `dir/data/` too); with `remeasure` it is measured and its table
/// written (the table files are then among those returned).
pub fn make(f: &Figure, dir: &Path, remeasure: bool) -> Result<Vec<PathBuf>, FigureError> {
    if !MEASURED.iter().any(|(_, n)| *n == f.name) {
        return f.make(dir);
    }
    let png = dir.join(format!("{}.png", f.name));
    if !remeasure {
        if let Some(t) = ChartTable::read(dir, f.name)? {
            std::fs::create_dir_all(dir).map_err(PlotError::Io)?;
            t.draw(&png)?;
            return Ok(vec![png]);
        }
        if let Some((_, csv, toml)) = COMMITTED.iter().find(|(n, _, _)| *n == f.name) {
            let t = ChartTable::from_texts(
                &format!("figures/data/{}.csv", f.name),
                csv,
                &format!("figures/data/{}.toml", f.name),
                toml,
            )?;
            std::fs::create_dir_all(dir).map_err(PlotError::Io)?;
            t.draw(&png)?;
            let mut files = vec![png];
            files.extend(t.write(dir, f.name)?);
            return Ok(files);
        }
    }
    measured(f, dir, || f.make(dir))
}

/// The studies that can be split into parts (`cellsurf converge STUDY --part i/N`), by the
/// `cellsurf converge` argument ([`crate::engine::study`]).
pub fn study(name: &str) -> Option<&'static dyn crate::engine::study::Study> {
    match name {
        "dunes" => Some(&crate::dunes::ErrorStudy),
        "windripples" => Some(&crate::windripples::figures::ErrorStudy),
        "ripple" => Some(&crate::ripple::figures::ErrorStudy),
        "raytrace" => Some(&crate::raytrace::figures::ErrorStudy),
        "ripple_validation" => Some(&crate::ripple::figures::ValidationStudy),
        _ => None,
    }
}

/// Draws the measured figure of `study` from the `records` of all its runs (gathered from
/// parts) into `dir`, with its table, as [`make`] does when it re-measures.
pub fn draw_study(
    study: &dyn crate::engine::study::Study,
    records: &[toml::Value],
    dir: &Path,
) -> Result<Vec<PathBuf>, FigureError> {
    let name = study.figure();
    let f = find(&name).ok_or_else(|| FigureError::Model(format!("no figure {name}")))?;
    // (every PNG records `figure = "NAME"`, as `Figure::make` has it)
    crate::plot::with_png_parameters(Some(format!("figure = \"{}\"", f.name)), || {
        measured(f, dir, || {
            study.draw(records, dir).map_err(FigureError::Model)
        })
    })
}

/// Runs `make` (which draws the measured figure `f` into `dir`) recording its charts, and
/// writes the table of the chart drawn into `dir/NAME.png`.
fn measured(
    f: &Figure,
    dir: &Path,
    make: impl FnOnce() -> Result<Vec<PathBuf>, FigureError>,
) -> Result<Vec<PathBuf>, FigureError> {
    let png = dir.join(format!("{}.png", f.name));
    record_charts(true);
    let made = make();
    let recorded = record_charts(false);
    let mut files = made?;
    let (_, table) = recorded
        .into_iter()
        .rev()
        .find(|(p, _)| *p == png)
        .ok_or_else(|| {
            FigureError::Model(format!("{} drew no chart into {}", f.name, png.display()))
        })?;
    files.extend(table.write(dir, f.name)?);
    Ok(files)
}
