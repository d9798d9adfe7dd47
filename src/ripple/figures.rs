//! The ripple figures (feature `plot`), listed in [`FIGURES`]: the paper's Figs. 2, 3, 4, 7 and
//! 8 regenerated, and the error-versus-CPU-time study.
//!
//! Sizes are reduced so that all of them together take well under a minute in release: the
//! figure run is the scene `scenarios/ripple_fig3.toml` (128 x 64 columns x 30 automata,
//! 3000 steps), shared by Figs. 3, 4, 7 and 8 (run once per process).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::Instant;

use plotters::style::RGBColor;

use super::output::{Field, run_recording, surface_field, volume_field, volume_levels};
use super::spectrum::{Analysis, moore_average};
use super::{Ripple, RippleParams};
use crate::figures::{Figure, FigureError};
use crate::plot::{CellField, Chart, Palette, Panel, Series, lattice_panels, line_charts};

/// The figure scene (the defaults: the paper's Fig. 3 situation).
pub const FIG3_SCENE: &str = include_str!("../../scenarios/ripple_fig3.toml");

/// The figures.
pub const FIGURES: &[Figure] = &[
    Figure {
        name: "ripple_fig2_shadow",
        about: "Sand ripple generator, Fig. 2: grains in motion and the current shadow of the sliced water volume in a section",
        make: fig2,
    },
    Figure {
        name: "ripple_fig3_evolution",
        about: "Sand ripple generator, Fig. 3: a rough flat bed becoming a ripple field (t0, t10, t25, t100)",
        make: fig3,
    },
    Figure {
        name: "ripple_fig4_impedance",
        about: "Sand ripple generator, Fig. 4: acoustic impedance of the surface automata",
        make: fig4,
    },
    Figure {
        name: "ripple_fig7_section",
        about: "Sand ripple generator, Fig. 7: grain size in a vertical section (8-cell Moore average) and mean grain size against depth",
        make: fig7,
    },
    Figure {
        name: "ripple_fig8_surface_grain_size",
        about: "Sand ripple generator, Fig. 8: grain size of the surface automata (8-cell Moore average)",
        make: fig8,
    },
    Figure {
        name: "ripple_error_vs_time",
        about: "Sand ripple generator: spread over seeds of wavelength, height and ripple index against CPU time (steps, grid size, bin size)",
        make: error_vs_time,
    },
];

fn model_err(e: impl std::fmt::Display) -> FigureError {
    FigureError::Model(e.to_string())
}

/// A perceptual blue-green-yellow ramp (anchors chosen by eye, viridis-like), 256 entries.
fn ramp_palette() -> Palette {
    const A: [(f64, (f64, f64, f64)); 5] = [
        (0.0, (68.0, 1.0, 84.0)),
        (0.25, (59.0, 82.0, 139.0)),
        (0.5, (33.0, 145.0, 140.0)),
        (0.75, (94.0, 201.0, 98.0)),
        (1.0, (253.0, 231.0, 37.0)),
    ];
    let colors = (0..256)
        .map(|i| {
            let t = i as f64 / 255.0;
            let k = A.iter().rposition(|a| a.0 <= t).unwrap_or(0).min(3);
            let s = (t - A[k].0) / (A[k + 1].0 - A[k].0);
            let m = |a: f64, b: f64| (a + (b - a) * s).round() as u8;
            let (c0, c1) = (A[k].1, A[k + 1].1);
            RGBColor(m(c0.0, c1.0), m(c0.1, c1.1), m(c0.2, c1.2))
        })
        .collect();
    Palette { colors }
}

/// States 1..=255 for finite values scaled over [lo, hi]; 0 for NaN (drawn in the ramp's
/// darkest colour, used as "no data" in sections: there the palette entry 0 is set white).
fn to_states(v: &[f64], lo: f64, hi: f64) -> Vec<u8> {
    let span = if hi > lo { hi - lo } else { 1.0 };
    v.iter()
        .map(|&x| {
            if x.is_finite() {
                (1.0 + 254.0 * ((x - lo) / span).clamp(0.0, 1.0)).round() as u8
            } else {
                0
            }
        })
        .collect()
}

fn range_of(v: &[f64]) -> (f64, f64) {
    v.iter()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

fn field(nx: usize, ny: usize, states: Vec<u8>) -> CellField {
    CellField {
        nx,
        ny,
        hex: false,
        states,
    }
}

fn scene() -> Result<RippleParams, FigureError> {
    RippleParams::from_toml(FIG3_SCENE).map_err(model_err)
}

/// The shared figure run: snapshots at t0, t10, t25, t100 (in hundredths of the run) and the
/// final state.
struct FigRun {
    snaps: Vec<(u64, Vec<f32>)>,
    last: Ripple,
}

fn fig_run() -> Result<&'static FigRun, FigureError> {
    static RUN: OnceLock<Result<FigRun, String>> = OnceLock::new();
    let r = RUN.get_or_init(|| {
        let p = scene().map_err(|e| e.to_string())?;
        let mut r = Ripple::new(&p).map_err(|e| e.to_string())?;
        let times: Vec<u64> = [0u64, 10, 25, 100]
            .iter()
            .map(|k| p.steps * k / 100)
            .collect();
        let snaps = run_recording(&mut r, p.steps, &times, |_| {});
        Ok(FigRun { snaps, last: r })
    });
    r.as_ref().map_err(|e| FigureError::Model(e.clone()))
}

fn fig2(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    // A 2-D section: a short run from a rough bed, then the sliced water volume over it.
    let p = RippleParams {
        mode: super::Mode::TwoD,
        nx: 160,
        ny: 1,
        layers: 30,
        steps: 6000,
        activity: 0.004,
        ..scene()?
    };
    let mut r = Ripple::new(&p).map_err(model_err)?;
    r.run(p.steps, |_| {});
    let (nx, _) = r.size();
    let hmax = volume_levels(&r);
    let hmin = r.volume().heights().iter().copied().min().unwrap_or(0) as usize;
    let lo = hmin.saturating_sub(4);
    let top = hmax + 12;
    let flow = r.flow_at(r.time());
    let speeds = r
        .water()
        .section(r.volume().heights(), nx, 1, 0, top, &flow);
    let t = r.water().slice_layers;
    // Rows from the bottom up (the panels draw row 0 at the bottom): sand brown (its exposed
    // top grains red), water by speed.
    let rows = top - lo;
    let mut states = vec![0u8; rows * nx];
    for (row, z) in (lo..top).enumerate() {
        for x in 0..nx {
            let h = r.volume().height(x);
            let s = if z < h {
                // sand: red if its column's top grain is exposed (would move), brown otherwise
                if z + 1 == h
                    && r.water()
                        .bed_speed(r.volume().heights(), nx, 1, x, 0, hmax, &flow)
                        > 0.0
                {
                    250
                } else {
                    255
                }
            } else {
                let v = speeds[(z / t).min(speeds.len() - 1)][x];
                if v.is_finite() {
                    (1.0 + 200.0 * v).round() as u8
                } else {
                    255
                }
            };
            states[row * nx + x] = s;
        }
    }
    let mut pal = ramp_palette();
    // water: 1..=201 from dark blue (still) to light blue (free stream)
    for i in 0..256 {
        let v = (i as f64 - 1.0) / 200.0;
        pal.colors[i] = RGBColor(
            (20.0 + 150.0 * v) as u8,
            (40.0 + 170.0 * v) as u8,
            (120.0 + 135.0 * v) as u8,
        );
    }
    pal.colors[0] = RGBColor(255, 255, 255);
    pal.colors[250] = RGBColor(220, 30, 30);
    pal.colors[255] = RGBColor(160, 120, 60);
    let path = dir.join("ripple_fig2_shadow.png");
    lattice_panels(
        &path,
        "Fig. 2: water slices by speed (dark = shadow), exposed grains red",
        &[Panel {
            title: format!(
                "2-D run, {nx} bins x {} automata shown (vertical exaggeration {:.0}x)",
                rows,
                p.bin_size / p.layer_thickness
            ),
            field: field(nx, rows, states),
        }],
        1,
        &pal,
        1100,
    )?;
    Ok(vec![path])
}

fn fig3(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let run = fig_run()?;
    let (nx, ny) = run.last.size();
    let all: Vec<f64> = run
        .snaps
        .iter()
        .flat_map(|s| s.1.iter().map(|&v| v as f64))
        .collect();
    let (lo, hi) = range_of(&all);
    let labels = ["t0", "t10", "t25", "t100"];
    let panels = run
        .snaps
        .iter()
        .zip(labels)
        .map(|((t, e), l)| {
            let v: Vec<f64> = e.iter().map(|&x| x as f64).collect();
            Panel {
                title: format!("{l} (step {t})"),
                field: field(nx, ny, to_states(&v, lo, hi)),
            }
        })
        .collect::<Vec<_>>();
    let path = dir.join("ripple_fig3_evolution.png");
    let an = Analysis::of(&run.last);
    lattice_panels(
        &path,
        &format!(
            "Fig. 3: elevation {:.1}-{:.1} mm; wavelength {:.1} cm, height {:.2} cm, RI {:.1}",
            lo * 1e3,
            hi * 1e3,
            an.wavelength_m * 100.0,
            an.height_m * 100.0,
            an.ripple_index
        ),
        &panels,
        1,
        &ramp_palette(),
        900,
    )?;
    Ok(vec![path])
}

/// The value of `f` for the top automaton of each column (NaN on bare columns).
fn surface_values(r: &Ripple, f: Field) -> Vec<f64> {
    surface_field(r, f)
        .into_iter()
        .map(|v| v.unwrap_or(f64::NAN))
        .collect()
}

fn fig4(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let run = fig_run()?;
    let r = &run.last;
    let (nx, ny) = r.size();
    let z = surface_values(r, Field::Impedance);
    let (lo, hi) = range_of(&z);
    let path = dir.join("ripple_fig4_impedance.png");
    let elev = r.elevation();
    let (elo, ehi) = range_of(&elev);
    lattice_panels(
        &path,
        &format!(
            "Fig. 4: surface impedance {:.3}-{:.3} MRayl (dark = lower)",
            lo / 1e6,
            hi / 1e6
        ),
        &[
            Panel {
                title: "impedance of the surface automata".into(),
                field: field(nx, ny, to_states(&z, lo, hi)),
            },
            Panel {
                title: "elevation".into(),
                field: field(nx, ny, to_states(&elev, elo, ehi)),
            },
        ],
        1,
        &ramp_palette(),
        900,
    )?;
    Ok(vec![path])
}

fn fig7(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let run = fig_run()?;
    let r = &run.last;
    let (nx, ny) = r.size();
    let nz = volume_levels(r);
    let gs = volume_field(r, Field::GrainSize, f32::NAN);
    // Vertical section along x at y = ny / 2, 8-cell Moore average in the (x, z) plane.
    let y = ny / 2;
    let sec = |x: usize, z: usize| gs[z * nx * ny + y * nx + x] as f64;
    let mut avg = vec![f64::NAN; nz * nx];
    for z in 0..nz {
        for x in 0..nx {
            if !sec(x, z).is_finite() {
                continue;
            }
            let (mut s, mut n) = (0.0, 0.0);
            for dz in -1i64..=1 {
                for dx in -1i64..=1 {
                    let zz = z as i64 + dz;
                    if zz < 0 || zz >= nz as i64 {
                        continue;
                    }
                    let xx = (x as i64 + dx).rem_euclid(nx as i64) as usize;
                    let v = sec(xx, zz as usize);
                    if v.is_finite() {
                        s += v;
                        n += 1.0;
                    }
                }
            }
            // rows bottom-up (the panels draw row 0 at the bottom)
            avg[z * nx + x] = s / n;
        }
    }
    let (lo, hi) = range_of(&avg);
    let mut pal = ramp_palette();
    pal.colors[0] = RGBColor(255, 255, 255);
    let path = dir.join("ripple_fig7_section.png");
    lattice_panels(
        &path,
        &format!(
            "Fig. 7: grain size {:.3}-{:.3} mm (yellow = coarse), section y = {y}, exaggeration {:.0}x",
            lo,
            hi,
            r.params().bin_size / r.params().layer_thickness
        ),
        &[Panel {
            title: "vertical section along the current".into(),
            field: field(nx, nz, to_states(&avg, lo, hi)),
        }],
        1,
        &pal,
        1100,
    )?;
    // Mean grain size against depth below the local surface, over the whole volume.
    let mut sum = vec![0.0; nz];
    let mut cnt = vec![0.0; nz];
    for c in 0..nx * ny {
        let h = r.volume().height(c);
        for z in 0..h {
            let depth = h - 1 - z;
            sum[depth] += gs[z * nx * ny + c] as f64;
            cnt[depth] += 1.0;
        }
    }
    let gd = r.params().layer_thickness;
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for d in 0..nz {
        if cnt[d] >= (nx * ny) as f64 * 0.2 {
            xs.push(d as f64 * gd * 1e3);
            ys.push(sum[d] / cnt[d]);
        }
    }
    let path2 = dir.join("ripple_fig7_depth_profile.png");
    line_charts(
        &path2,
        "Fig. 7 (right): mean grain size against depth below the surface",
        &[Chart {
            title: "all columns".into(),
            x_label: "depth below the surface (mm)".into(),
            y_label: "mean grain size (mm)".into(),
            series: vec![Series {
                label: "mean d".into(),
                x: xs,
                y: ys,
                points: true,
            }],
            log_x: false,
            log_y: false,
        }],
        1,
        (800, 500),
    )?;
    Ok(vec![path, path2])
}

fn fig8(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let run = fig_run()?;
    let r = &run.last;
    let (nx, ny) = r.size();
    let d = moore_average(r, &surface_values(r, Field::GrainSize));
    let (lo, hi) = range_of(&d);
    let elev = r.elevation();
    let (elo, ehi) = range_of(&elev);
    let an = Analysis::of(r);
    let path = dir.join("ripple_fig8_surface_grain_size.png");
    lattice_panels(
        &path,
        &format!(
            "Fig. 8: surface d {:.3}-{:.3} mm (yellow = coarse); d50 crest {:.3}, trough {:.3} mm",
            lo, hi, an.d50_crest_mm, an.d50_trough_mm
        ),
        &[
            Panel {
                title: "surface grain size".into(),
                field: field(nx, ny, to_states(&d, lo, hi)),
            },
            Panel {
                title: "elevation".into(),
                field: field(nx, ny, to_states(&elev, elo, ehi)),
            },
        ],
        1,
        &ramp_palette(),
        900,
    )?;
    Ok(vec![path])
}

/// Spread (standard deviation over seeds) and mean of (wavelength, height, ripple index) and
/// the mean CPU seconds of runs of `p` over `seeds`.
fn spread(p: &RippleParams, seeds: u64) -> Result<([f64; 3], [f64; 3], f64), FigureError> {
    let mut vals: Vec<[f64; 3]> = Vec::new();
    let mut secs = 0.0;
    for s in 0..seeds {
        let q = RippleParams {
            seed: 1000 + s,
            ..p.clone()
        };
        let t = Instant::now();
        let mut r = Ripple::new(&q).map_err(model_err)?;
        r.run(q.steps, |_| {});
        secs += t.elapsed().as_secs_f64();
        let a = Analysis::of(&r);
        vals.push([a.wavelength_m, a.height_m, a.ripple_index]);
    }
    let n = vals.len() as f64;
    let mut mean = [0.0; 3];
    let mut sd = [0.0; 3];
    for i in 0..3 {
        mean[i] = vals.iter().map(|v| v[i]).sum::<f64>() / n;
        sd[i] = (vals.iter().map(|v| (v[i] - mean[i]).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    }
    Ok((mean, sd, secs / n))
}

/// (CPU seconds, means, standard deviations) of one study point.
type StudyPoint = (f64, [f64; 3], [f64; 3]);

fn error_vs_time(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let base = RippleParams {
        nx: 64,
        ny: 32,
        layers: 20,
        abstraction: super::Abstraction::Shadow,
        ..scene()?
    };
    let seeds = 4;
    let mut studies: Vec<(String, Vec<StudyPoint>)> = Vec::new();
    let mut steps_pts = Vec::new();
    for steps in [500u64, 1000, 2000, 4000] {
        let (m, s, t) = spread(
            &RippleParams {
                steps,
                ..base.clone()
            },
            seeds,
        )?;
        steps_pts.push((t, m, s));
    }
    studies.push(("steps 500-4000".into(), steps_pts));
    let mut grid_pts = Vec::new();
    for (nx, ny) in [(32usize, 16usize), (64, 32), (128, 64)] {
        let (m, s, t) = spread(
            &RippleParams {
                nx,
                ny,
                steps: 2000,
                ..base.clone()
            },
            seeds,
        )?;
        grid_pts.push((t, m, s));
    }
    studies.push(("grid 32x16-128x64".into(), grid_pts));
    let mut bin_pts = Vec::new();
    // Same physical area and layer thickness, finer bins (so gd / dx changes too).
    for (bin, nx, ny) in [(0.01, 32usize, 16usize), (0.005, 64, 32), (0.0025, 128, 64)] {
        let (m, s, t) = spread(
            &RippleParams {
                nx,
                ny,
                bin_size: bin,
                steps: 2000,
                ..base.clone()
            },
            seeds,
        )?;
        bin_pts.push((t, m, s));
    }
    studies.push(("bin 10-2.5 mm (same area, gd 0.5 mm)".into(), bin_pts));
    let names = ["wavelength", "height", "ripple index"];
    let charts: Vec<Chart> = (0..3)
        .map(|i| Chart {
            title: format!("spread over {seeds} seeds of the {}", names[i]),
            x_label: "CPU seconds per run".into(),
            y_label: format!("std. dev. / mean of the {}", names[i]),
            series: studies
                .iter()
                .map(|(label, pts)| Series {
                    label: label.clone(),
                    x: pts.iter().map(|p| p.0).collect(),
                    y: pts.iter().map(|p| p.2[i] / p.1[i].abs()).collect(),
                    points: true,
                })
                .collect(),
            log_x: true,
            log_y: false,
        })
        .collect();
    let path = dir.join("ripple_error_vs_time.png");
    line_charts(
        &path,
        "Relative spread over seeds against CPU time (shadow abstraction, 20 automata per column)",
        &charts,
        3,
        (520, 420),
    )?;
    Ok(vec![path])
}
