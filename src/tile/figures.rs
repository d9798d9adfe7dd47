//! The tiling figures (feature `plot`), listed in [`FIGURES`]: the paper's Fig. 6 (ripple tiles
//! joined into a larger surface) and Fig. 9 (ripples on fractal dunes), with companion charts of
//! the seam statistic and of the dune spectrum.
//!
//! Each mosaic is one `cellsurf tile --generate` run read from its scenario file ([`SCENARIOS`];
//! Fig. 6 one a panel). The tiles are small in-process ripple runs (64 x 32 bins, 20 automata per
//! column, 1500 steps at 0.4 % activity, seeds 1-3), so that both figures take a few seconds in
//! release; each seed's run is made once per process for every scenario that asks for it.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use plotters::style::RGBColor;

use super::fractal::{DuneField, FbmParams, Relief, measured_slope, radial_spectrum};
use super::seam::SeamStats;
use super::stream::RowSource;
use super::{Choose, Mosaic, RippledDunes, SeamMeter, Tile, TileScenario};
use crate::plot::field::{finite_range, states_over};
use crate::plot::{Chart, Palette, Panel, Series, lattice_panels, line_charts};
use crate::plot::{Figure, FigureError, read_scenario, scenario_panels, scenario_text};
use crate::ripple::RippleParams;
use crate::ripple::figures::{field, ramp_palette};

/// The figures.
pub const FIGURES: &[Figure] = &[
    Figure {
        name: "ripple_fig6_tiles",
        about: "Sand ripple generator, Fig. 6: toroidal ripple tiles joined into a larger surface (same tile; patches of three seeds, raw and cross-faded), tile borders dashed; seam statistic",
        make: fig6,
    },
    Figure {
        name: "ripple_fig9_fractal_dunes",
        about: "Sand ripple generator, Fig. 9: ripples riding on fractal (fBm) dunes, oriented by the local current; dune spectrum slope measured against requested",
        make: fig9,
    },
];

fn model_err(e: impl std::fmt::Display) -> FigureError {
    FigureError::Model(e.to_string())
}

/// The scenario files of the figures' runs, by file name (Fig. 6: one a panel,
/// `ripple_fig6_tiles_PANEL`).
pub const SCENARIOS: &[(&str, &str)] = crate::plot::scenario_files![
    "ripple_fig6_tiles_same",
    "ripple_fig6_tiles_patches",
    "ripple_fig6_tiles_blended",
    "ripple_fig9_fractal_dunes",
];

/// The tiles of `s`, seed by seed; each seed's ripple run is made once per process.
fn tiles(s: &TileScenario) -> Result<Vec<Tile>, FigureError> {
    type Key = (RippleParams, Vec<u64>, Option<crate::ripple::Field>, u64);
    static MADE: Mutex<Vec<(Key, Vec<Tile>)>> = Mutex::new(Vec::new());
    let mut made = MADE.lock().unwrap_or_else(|e| e.into_inner());
    let mut all = Vec::new();
    for &seed in &s.seeds {
        let key: Key = (s.ripple.clone(), s.snapshots.clone(), s.volume, seed);
        if let Some((_, t)) = made.iter().find(|(k, _)| *k == key) {
            all.extend(t.iter().cloned());
            continue;
        }
        let t = s.tiles_of_seed(seed).map_err(model_err)?;
        all.extend(t.iter().cloned());
        made.push((key, t));
    }
    Ok(all)
}

/// A panel's name: the tiles it lays and how.
fn panel_name(s: &TileScenario) -> String {
    let lo = s.seeds.iter().min().copied().unwrap_or(0);
    let hi = s.seeds.iter().max().copied().unwrap_or(0);
    match (s.choose, s.blend) {
        (Choose::Same, _) => format!("same tile (seed {})", s.seeds[0]),
        (Choose::Patches, 0) => format!("patches of seeds {lo}-{hi}, no blend"),
        (Choose::Patches, b) => format!("patches, cross-faded over {b} bins"),
    }
}

/// Every row of a source, and its seam statistic.
fn rows(src: &dyn RowSource) -> (Vec<f64>, SeamStats) {
    let (w, h) = (src.width(), src.height());
    let (tnx, tny) = src.tile_size();
    let mut m = SeamMeter::new(w, tnx, tny);
    let mut all = Vec::with_capacity(w * h);
    let mut row = vec![0.0f32; w];
    for y in 0..h {
        src.fill_row(y, &mut row);
        m.push_row(&row);
        all.extend(row.iter().map(|&v| v as f64));
    }
    (all, m.finish())
}

/// States of a mosaic with the tile borders dashed (state 0).
fn with_borders(v: &[f64], w: usize, h: usize, tile: (usize, usize), lo: f64, hi: f64) -> Vec<u8> {
    let mut s = states_over(v, lo, hi);
    for y in 0..h {
        for x in 0..w {
            let on_x = x % tile.0 == 0 && y % 8 < 3;
            let on_y = y % tile.1 == 0 && x % 8 < 3;
            if on_x || on_y {
                s[y * w + x] = 0;
            }
        }
    }
    s
}

fn ratio(s: &SeamStats) -> String {
    let r = |v: Option<f64>| v.map_or("-".into(), |x| format!("{x:.2}"));
    format!("seam/inside x {}, y {}", r(s.x.ratio()), r(s.y.ratio()))
}

fn fig6(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let mut cases: Vec<(String, Mosaic)> = Vec::new();
    for (panel, text) in scenario_panels(SCENARIOS, "ripple_fig6_tiles")? {
        let s = read_scenario(
            &format!("ripple_fig6_tiles_{panel}"),
            text,
            TileScenario::parse,
        )?;
        if s.dunes.is_some() {
            return Err(FigureError::Model(format!(
                "ripple_fig6_tiles_{panel}: Fig. 6 draws mosaics without dunes"
            )));
        }
        let m = s.mosaic(tiles(&s)?).map_err(model_err)?;
        cases.push((panel_name(&s), m));
    }
    let (w, h) = cases[0].1.size();
    let tile = cases[0].1.tile_size();
    if cases
        .iter()
        .any(|(_, m)| (m.size(), m.tile_size()) != ((w, h), tile))
    {
        return Err(FigureError::Model(
            "ripple_fig6_tiles: its panels are mosaics of one size".into(),
        ));
    }
    let measured: Vec<(Vec<f64>, SeamStats)> = cases.iter().map(|(_, m)| rows(m)).collect();
    let all: Vec<f64> = measured.iter().flat_map(|m| m.0.iter().copied()).collect();
    let (lo, hi) = finite_range(&all);
    let panels: Vec<Panel> = cases
        .iter()
        .zip(&measured)
        .map(|((name, _), (v, s))| Panel {
            title: format!("{name}: {}", ratio(s)),
            field: field(w, h, with_borders(v, w, h, tile, lo, hi)),
        })
        .collect();
    let mut pal = ramp_palette();
    pal.colors[0] = RGBColor(230, 30, 30);
    let path = dir.join("ripple_fig6_tiles.png");
    lattice_panels(
        &path,
        &format!(
            "Fig. 6: 3 x 3 tiles, {} x {} bins, {:.0}-{:.0} mm",
            tile.0,
            tile.1,
            lo * 1e3,
            hi * 1e3
        ),
        &panels,
        1,
        &pal,
        900,
    )?;
    // The seam statistic: mean |jump| between neighbouring columns, by column pair.
    let series: Vec<Series> = cases
        .iter()
        .zip(&measured)
        .map(|((name, _), (v, _))| {
            let xs: Vec<f64> = (0..w).map(|i| i as f64 + 0.5).collect();
            let ys: Vec<f64> = (0..w)
                .map(|i| {
                    let j = (i + 1) % w;
                    (0..h)
                        .map(|y| (v[y * w + j] - v[y * w + i]).abs())
                        .sum::<f64>()
                        / h as f64
                        * 1e3
                })
                .collect();
            Series {
                label: name.to_string(),
                x: xs,
                y: ys,
                points: false,
            }
        })
        .collect();
    let path2 = dir.join("ripple_fig6_seams.png");
    line_charts(
        &path2,
        &format!(
            "Mean |h(i+1) - h(i)| over rows; tile edges at i + 1 = {}, {}, {}",
            tile.0,
            2 * tile.0,
            3 * tile.0
        ),
        &[Chart {
            title: cases
                .iter()
                .zip(&measured)
                .map(|((n, _), (_, s))| {
                    format!("{}: {}", n.split(',').next().unwrap_or(n), ratio(s))
                })
                .collect::<Vec<_>>()
                .join("; "),
            x_label: "column pair i (x bins)".into(),
            y_label: "mean |jump| (mm)".into(),
            series,
            log_x: false,
            log_y: false,
        }],
        1,
        (1100, 450),
    )?;
    Ok(vec![path, path2])
}

/// A palette of 127 greys (states 1..=127) and the ramp compressed into 128..=255.
fn shade_and_ramp() -> Palette {
    let ramp = ramp_palette();
    let mut colors = Vec::with_capacity(256);
    colors.push(RGBColor(255, 255, 255));
    for i in 1..128 {
        let g = (2 * i) as u8;
        colors.push(RGBColor(g, g, g));
    }
    for i in 128..256 {
        colors.push(ramp.colors[(i - 128) * 2 + 1]);
    }
    Palette { colors }
}

/// Hill shading (light from the north-west, 45 degrees up) as states 1..=127.
fn hillshade(v: &[f64], w: usize, h: usize, dx: f64, exaggeration: f64) -> Vec<u8> {
    let (az, alt) = (135f64.to_radians(), 45f64.to_radians());
    let l = (az.cos() * alt.cos(), az.sin() * alt.cos(), alt.sin());
    (0..w * h)
        .map(|c| {
            let (x, y) = (c % w, c / w);
            let at = |x: usize, y: usize| v[y * w + x];
            let gx = (at((x + 1) % w, y) - at((x + w - 1) % w, y)) / (2.0 * dx) * exaggeration;
            let gy = (at(x, (y + 1) % h) - at(x, (y + h - 1) % h)) / (2.0 * dx) * exaggeration;
            let n = (gx * gx + gy * gy + 1.0).sqrt();
            let s = (-gx * l.0 - gy * l.1 + l.2) / n;
            (1.0 + 126.0 * s.clamp(0.0, 1.0)).round() as u8
        })
        .collect()
}

fn fbm_only(name: &str) -> FigureError {
    FigureError::Model(format!(
        "{name}: Fig. 9 draws fractal (fBm) dunes: dunes = true, no dune_wavelength"
    ))
}

fn fig9(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let name = "ripple_fig9_fractal_dunes";
    let s = read_scenario(name, scenario_text(SCENARIOS, name)?, TileScenario::parse)?;
    let mosaic = s.mosaic(tiles(&s)?).map_err(model_err)?;
    let (p, hurst) = match s.dune_params(&mosaic).map_err(model_err)? {
        Some(p) => match p.relief {
            Relief::Fbm { hurst } => (p, hurst),
            Relief::Wavelength { .. } => return Err(fbm_only(name)),
        },
        None => return Err(fbm_only(name)),
    };
    let d = RippledDunes::new(mosaic, &p).map_err(model_err)?;
    let (w, h) = (d.width(), d.height());
    let dx = d.bin_size();
    let (v, _) = rows(&d);
    let dune: Vec<f64> = (0..w * h)
        .map(|c| d.dunes().height((c % w) as f64 * dx, (c / w) as f64 * dx))
        .collect();
    let (lo, hi) = finite_range(&dune);
    let to_upper = |s: Vec<u8>| s.into_iter().map(|x| 128 + x / 2).collect::<Vec<u8>>();
    let slope = measured_slope(d.dunes()).unwrap_or(f64::NAN);
    let panels = vec![
        Panel {
            title: "rippled dunes, shaded relief".into(),
            field: field(w, h, hillshade(&v, w, h, dx, 1.0)),
        },
        Panel {
            title: format!(
                "dune relief {:.0}-{:.0} mm (yellow high)",
                lo * 1e3,
                hi * 1e3
            ),
            field: field(w, h, to_upper(states_over(&dune, lo, hi))),
        },
    ];
    let path = dir.join("ripple_fig9_fractal_dunes.png");
    lattice_panels(
        &path,
        &format!(
            "Fig. 9: rippled fBm dunes, {:.1} x {:.1} m, H {hurst}, rms {:.0} mm; slope {slope:.2} vs {:.2}",
            w as f64 * dx,
            h as f64 * dx,
            p.rms * 1e3,
            -(2.0 * hurst + 2.0)
        ),
        &panels,
        2,
        &shade_and_ramp(),
        700,
    )?;
    // Radially averaged spectra of fBm fields, 256 x 256, for three H: measured vs requested.
    let mut series = Vec::new();
    for (k, hh) in [0.3, 0.6, 0.9].into_iter().enumerate() {
        let slopes: Vec<f64> = (0..6)
            .filter_map(|s| {
                let f = DuneField::synthesize(&fbm(hh, 10 + s)).ok()?;
                measured_slope(&f)
            })
            .collect();
        let mean = slopes.iter().sum::<f64>() / slopes.len().max(1) as f64;
        let f = DuneField::synthesize(&fbm(hh, 10)).map_err(model_err)?;
        let spec = radial_spectrum(&f.h, f.nx, f.ny, f.dx, f.dy);
        series.push(Series {
            label: format!(
                "H = {hh}: slope {mean:.2} (mean of 6 seeds), requested {:.1}",
                -(2.0 * hh + 2.0)
            ),
            x: spec.iter().map(|s| s.0).collect(),
            y: spec
                .iter()
                .map(|s| s.1 * 10f64.powi(2 * k as i32))
                .collect(),
            points: false,
        });
    }
    let path2 = dir.join("ripple_fig9_dune_spectrum.png");
    line_charts(
        &path2,
        "fBm relief (Saupe 1988 synthesis): radial power spectrum",
        &[Chart {
            title: "curves offset by factors of 100; slopes fitted from 2 rings to half Nyquist"
                .into(),
            x_label: "wavenumber K (cycles/m)".into(),
            y_label: "power (arbitrary units)".into(),
            series,
            log_x: true,
            log_y: true,
        }],
        1,
        (900, 550),
    )?;
    Ok(vec![path, path2])
}

fn fbm(hurst: f64, seed: u64) -> FbmParams {
    FbmParams {
        nx: 256,
        ny: 256,
        dx: 0.5,
        dy: 0.5,
        relief: Relief::Fbm { hurst },
        rms: 1.0,
        seed,
    }
}
