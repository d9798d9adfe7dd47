//! [`ChartTable`]: the data behind a chart figure, written as CSV (the points) and TOML (the
//! titles, labels and layout) under a figure folder's `data/`, so that a figure whose numbers
//! were measured (error against run time) is redrawn byte for byte from its committed table
//! and re-measured only on request.
//!
//! While [`record_charts`](super::record_charts) is on, every [`line_charts`] call of this thread
//! also keeps its inputs (and the PNG parameters in force) as a table.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::charts::{Chart, ChartTable, Series, line_charts};
use super::{PlotError, with_png_parameters};

/// The TOML side of a table: all but the points.
#[derive(Serialize, Deserialize)]
struct Meta {
    version: String,
    title: String,
    cols: usize,
    chart_px: (u32, u32),
    png_parameters: Option<String>,
    charts: Vec<ChartMeta>,
}

#[derive(Serialize, Deserialize)]
struct ChartMeta {
    title: String,
    x_label: String,
    y_label: String,
    log_x: bool,
    log_y: bool,
    series: Vec<SeriesMeta>,
}

#[derive(Serialize, Deserialize)]
struct SeriesMeta {
    label: String,
    points: bool,
}

/// The table files of figure `name` in folder `dir`: `dir/data/NAME.csv` and `.toml`.
pub fn paths(dir: &Path, name: &str) -> (PathBuf, PathBuf) {
    let d = dir.join("data");
    (
        d.join(format!("{name}.csv")),
        d.join(format!("{name}.toml")),
    )
}

impl ChartTable {
    /// Writes the table of figure `name` into `dir/data/` (atomically, the folder created);
    /// returns the two files.
    pub fn write(&self, dir: &Path, name: &str) -> Result<Vec<PathBuf>, PlotError> {
        let (csv, toml_path) = paths(dir, name);
        std::fs::create_dir_all(dir.join("data"))?;
        let meta = Meta {
            version: crate::engine::VERSION.to_string(),
            title: self.title.clone(),
            cols: self.cols,
            chart_px: self.chart_px,
            png_parameters: self.png_parameters.clone(),
            charts: self
                .charts
                .iter()
                .map(|c| ChartMeta {
                    title: c.title.clone(),
                    x_label: c.x_label.clone(),
                    y_label: c.y_label.clone(),
                    log_x: c.log_x,
                    log_y: c.log_y,
                    series: c
                        .series
                        .iter()
                        .map(|s| SeriesMeta {
                            label: s.label.clone(),
                            points: s.points,
                        })
                        .collect(),
                })
                .collect(),
        };
        let text =
            toml::to_string(&meta).map_err(|e| PlotError::invalid("table", e.to_string()))?;
        let mut rows = format!(
            "# the points of {name}.png (cellsurf {}); titles and labels in {name}.toml\nchart,series,x,y\n",
            crate::engine::VERSION
        );
        for (i, c) in self.charts.iter().enumerate() {
            for (j, s) in c.series.iter().enumerate() {
                for (x, y) in s.x.iter().zip(&s.y) {
                    // Display of f64 is the shortest text that reads back to the same value.
                    rows.push_str(&format!("{i},{j},{x},{y}\n"));
                }
            }
        }
        crate::engine::io::write_atomic(&toml_path, text.as_bytes())?;
        crate::engine::io::write_atomic(&csv, rows.as_bytes())?;
        Ok(vec![csv, toml_path])
    }

    /// Reads the table of figure `name` from `dir/data/`; `None` when it has none.
    pub fn read(dir: &Path, name: &str) -> Result<Option<ChartTable>, PlotError> {
        let (csv, toml_path) = paths(dir, name);
        if !csv.exists() || !toml_path.exists() {
            return Ok(None);
        }
        let meta_text = std::fs::read_to_string(&toml_path)?;
        let text = std::fs::read_to_string(&csv)?;
        ChartTable::from_texts(
            &csv.display().to_string(),
            &text,
            &toml_path.display().to_string(),
            &meta_text,
        )
        .map(Some)
    }

    /// A table from the texts of its two files (`csv_name` and `toml_name` name them in
    /// errors): the form [`ChartTable::read`] reads, for a table held in memory.
    pub fn from_texts(
        csv_name: &str,
        text: &str,
        toml_name: &str,
        meta_text: &str,
    ) -> Result<ChartTable, PlotError> {
        let bad = |what: String| PlotError::invalid(toml_name.to_string(), what);
        let meta: Meta = toml::from_str(meta_text).map_err(|e| bad(e.to_string()))?;
        let mut charts: Vec<Chart> = meta
            .charts
            .into_iter()
            .map(|c| Chart {
                title: c.title,
                x_label: c.x_label,
                y_label: c.y_label,
                log_x: c.log_x,
                log_y: c.log_y,
                series: c
                    .series
                    .into_iter()
                    .map(|s| Series {
                        label: s.label,
                        points: s.points,
                        x: Vec::new(),
                        y: Vec::new(),
                    })
                    .collect(),
            })
            .collect();
        let bad_row = |k: usize, line: &str| {
            PlotError::invalid(
                csv_name.to_string(),
                format!(
                    "row {}: '{line}' is not chart,series,x,y of the table",
                    k + 1
                ),
            )
        };
        for (k, line) in text.lines().enumerate() {
            if line.starts_with('#') || line.starts_with("chart,") || line.is_empty() {
                continue;
            }
            let f: Vec<&str> = line.split(',').collect();
            let (Ok(i), Ok(j), Ok(x), Ok(y)) = (
                f.first().unwrap_or(&"").parse::<usize>(),
                f.get(1).unwrap_or(&"").parse::<usize>(),
                f.get(2).unwrap_or(&"").parse::<f64>(),
                f.get(3).unwrap_or(&"").parse::<f64>(),
            ) else {
                return Err(bad_row(k, line));
            };
            let s = charts
                .get_mut(i)
                .and_then(|c| c.series.get_mut(j))
                .ok_or_else(|| bad_row(k, line))?;
            s.x.push(x);
            s.y.push(y);
        }
        Ok(ChartTable {
            title: meta.title,
            cols: meta.cols,
            chart_px: meta.chart_px,
            png_parameters: meta.png_parameters,
            charts,
        })
    }

    /// Draws the table into `path` (the same PNG as the run that measured it).
    pub fn draw(&self, path: &Path) -> Result<(), PlotError> {
        with_png_parameters(self.png_parameters.clone(), || {
            line_charts(path, &self.title, &self.charts, self.cols, self.chart_px)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_reads_back_exactly() {
        let t = ChartTable {
            title: "error, against \"time\"".into(),
            cols: 2,
            chart_px: (300, 200),
            png_parameters: Some("figure = \"x\"\nseeds = 3\n".into()),
            charts: vec![Chart {
                title: "a, b".into(),
                x_label: "s".into(),
                y_label: "se".into(),
                log_x: true,
                log_y: false,
                series: vec![Series {
                    label: "exact".into(),
                    x: vec![0.1, 1.0 / 3.0, 1e-300, f64::NAN],
                    y: vec![2.5e-7, f64::INFINITY, -0.0, 7.0],
                    points: true,
                }],
            }],
        };
        let dir = std::env::temp_dir().join(format!("cellsurf-table-{}", std::process::id()));
        t.write(&dir, "fig").unwrap();
        let back = ChartTable::read(&dir, "fig").unwrap().unwrap();
        assert_eq!(back.title, t.title);
        assert_eq!(back.png_parameters, t.png_parameters);
        let (a, b) = (&t.charts[0].series[0], &back.charts[0].series[0]);
        for (u, v) in a.x.iter().chain(&a.y).zip(b.x.iter().chain(&b.y)) {
            assert!(
                u.to_bits() == v.to_bits() || (u.is_nan() && v.is_nan()),
                "{u} {v}"
            );
        }
        assert!(ChartTable::read(&dir, "absent").unwrap().is_none());
        std::fs::write(paths(&dir, "fig").0, "0,0,1,x\n").unwrap();
        assert!(ChartTable::read(&dir, "fig").is_err());
        std::fs::remove_dir_all(&dir).ok();
    }
}
