//! [`Figure`]: a published figure that `cellsurf figures` regenerates, and [`FigureError`].
//!
//! Every model lists its figures as a `FIGURES` slice of [`Figure`]s; the crate's figure
//! registry (`cellsurf::figures`) gathers them. [`Figure::make`] records the figure's name in
//! every PNG it writes (a model may record its scenario instead) and writes into a folder.

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
        super::set_png_parameters(Some(format!("figure = \"{}\"", self.name)));
        let r = (self.make)(dir);
        super::set_png_parameters(None);
        r
    }
}
