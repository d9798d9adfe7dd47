//! [`Figure`]: a published figure that `cellsurf figures` regenerates, and [`FigureError`].
//!
//! Every model lists its figures as a `FIGURES` slice of [`Figure`]s; the crate's figure
//! registry (`cellsurf::figures`) gathers them. [`Figure::make`] records the figure's name in
//! every PNG it writes (a model may record its scenario instead) and writes into a folder.
//!
//! A figure made from one run of a subcommand (or one run per panel) takes its parameters from
//! its scenario file, `scenarios/NAME.toml` (a panel's `scenarios/NAME_PANEL.toml`), which its
//! model embeds as a `SCENARIOS` slice of `(file name, text)` pairs: [`scenario_text`] and
//! [`scenario_panels`] look them up.

use std::path::{Path, PathBuf};

use thiserror::Error;

use super::PlotError;

/// Errors while making a figure.
#[derive(Debug, Error)]
pub enum FigureError {
    /// Drawing failed.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// No figure has this name.
    #[error("unknown figure '{0}': `cellsurf figures --list` lists them")]
    Unknown(String),
    /// A model's own error, as text.
    #[error("{0}")]
    Model(String),
    /// A model's own typed error (a scene that failed, ...).
    #[error(transparent)]
    Source(Box<dyn std::error::Error + Send + Sync + 'static>),
}

/// A figure that `cellsurf figures` regenerates.
pub struct Figure {
    /// File name without extension; also the scenario's name.
    pub name: &'static str,
    /// What it shows.
    pub about: &'static str,
    /// Writes the figure's files into a folder.
    pub make: fn(&Path) -> Result<Vec<PathBuf>, FigureError>,
}

impl Figure {
    /// Writes the figure (and its companion charts) into `dir`; returns the files written.
    /// Every PNG records `figure = "NAME"` unless the figure records its own scenario.
    pub fn make(&self, dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
        std::fs::create_dir_all(dir).map_err(PlotError::Io)?;
        super::with_png_parameters(Some(format!("figure = \"{}\"", self.name)), || {
            (self.make)(dir)
        })
    }
}

/// A model's scenario files, embedded: `scenario_files!["a", "b"]` is the `(file name, text)`
/// pairs of `scenarios/a.toml` and `scenarios/b.toml`.
macro_rules! scenario_files {
    ($($name:literal),* $(,)?) => {
        &[$((
            $name,
            include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/", $name, ".toml")),
        )),*]
    };
}
pub(crate) use scenario_files;

/// The text of the scenario file `name` (`scenarios/NAME.toml`) among a model's embedded
/// `(file name, text)` pairs.
pub fn scenario_text(
    scenarios: &'static [(&'static str, &'static str)],
    name: &str,
) -> Result<&'static str, FigureError> {
    scenarios
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| *t)
        .ok_or_else(|| FigureError::Model(format!("no scenario file scenarios/{name}.toml")))
}

/// The run of the scenario file `name` with the text `text`, as a model's `parse` reads it; an
/// error names the file.
pub fn read_scenario<T, E: std::fmt::Display>(
    name: &str,
    text: &str,
    parse: impl FnOnce(&str) -> Result<T, E>,
) -> Result<T, FigureError> {
    parse(text).map_err(|e| FigureError::Model(format!("scenarios/{name}.toml: {e}")))
}

/// The panels of figure `figure`: each scenario file `FIGURE_PANEL` among a model's embedded
/// pairs as `(PANEL, text)`, in the order listed; an error when there is none.
pub fn scenario_panels(
    scenarios: &'static [(&'static str, &'static str)],
    figure: &str,
) -> Result<Vec<(&'static str, &'static str)>, FigureError> {
    let panels: Vec<_> = scenarios
        .iter()
        .filter_map(|(n, t)| {
            n.strip_prefix(figure)
                .and_then(|rest| rest.strip_prefix('_'))
                .map(|panel| (panel, *t))
        })
        .collect();
    if panels.is_empty() {
        return Err(FigureError::Model(format!(
            "no scenario file scenarios/{figure}_PANEL.toml"
        )));
    }
    Ok(panels)
}
