//! The ripple figures (feature `plot`), listed in [`FIGURES`]: the paper's Figs. 2, 3, 4, 7 and
//! 8 regenerated, and the error-versus-CPU-time study.
//!
//! Sizes are reduced so that all of them together take well under a minute in release: the
//! figure run is the scene `scenarios/ripple_fig3.toml` (128 x 64 columns x 30 automata,
//! 10000 steps), shared by Figs. 3, 4, 7 and 8 (run once per process).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::Instant;

use plotters::style::RGBColor;

use super::output::{Field, run_recording, surface_field, volume_field, volume_levels};
use super::spectrum::{Analysis, moore_average};
use super::{Ripple, RippleParams};
use crate::plot::field::{finite_range, states_over};
use crate::plot::{
    CellField, Chart, ColorRamp, Palette, Panel, Series, lattice_panels, line_charts,
};
use crate::plot::{Figure, FigureError};

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
        about: "Sand ripple generator: wavelength, height and ripple index (mean over 6 seeds and its standard error) against CPU time, for steps, grid size and bin size",
        make: error_vs_time,
    },
];

fn model_err(e: impl std::fmt::Display) -> FigureError {
    FigureError::Model(e.to_string())
}

/// The ramp of the ripple and tiling figures: viridis from five anchors, 256 states.
pub(crate) fn ramp_palette() -> Palette {
    ColorRamp::Viridis5.palette(256)
}

/// A square-lattice field of palette states, `nx x ny` columns.
pub(crate) fn field(nx: usize, ny: usize, states: Vec<u8>) -> CellField {
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
    let (lo, hi) = finite_range(&all);
    let labels = ["t0", "t10", "t25", "t100"];
    let panels = run
        .snaps
        .iter()
        .zip(labels)
        .map(|((t, e), l)| {
            let v: Vec<f64> = e.iter().map(|&x| x as f64).collect();
            Panel {
                title: format!("{l} (step {t})"),
                field: field(nx, ny, states_over(&v, lo, hi)),
            }
        })
        .collect::<Vec<_>>();
    let path = dir.join("ripple_fig3_evolution.png");
    let an = Analysis::of(&run.last);
    lattice_panels(
        &path,
        &format!(
            "Fig. 3 ({:.0}-{:.0} mm): wavelength {:.1} cm, height {:.2} cm, lee {:.0} deg",
            lo * 1e3,
            hi * 1e3,
            an.wavelength_m * 100.0,
            an.height_m * 100.0,
            an.lee_slope_deg
        ),
        &panels,
        2,
        &ramp_palette(),
        1400,
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
    let (lo, hi) = finite_range(&z);
    let path = dir.join("ripple_fig4_impedance.png");
    let elev = r.elevation();
    let (elo, ehi) = finite_range(&elev);
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
                field: field(nx, ny, states_over(&z, lo, hi)),
            },
            Panel {
                title: "elevation".into(),
                field: field(nx, ny, states_over(&elev, elo, ehi)),
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
    let (lo, hi) = finite_range(&avg);
    let mut pal = ramp_palette();
    pal.colors[0] = RGBColor(255, 255, 255);
    let path = dir.join("ripple_fig7_section.png");
    lattice_panels(
        &path,
        &format!("Fig. 7: grain size in a vertical section along the current (y = {y})"),
        &[Panel {
            title: format!(
                "{lo:.3}-{hi:.3} mm (yellow = coarse), vertical exaggeration {:.0}x",
                r.params().bin_size / r.params().layer_thickness
            ),
            field: field(nx, nz, states_over(&avg, lo, hi)),
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
    let (lo, hi) = finite_range(&d);
    let elev = r.elevation();
    let (elo, ehi) = finite_range(&elev);
    let an = Analysis::of(r);
    let path = dir.join("ripple_fig8_surface_grain_size.png");
    lattice_panels(
        &path,
        &format!(
            "Fig. 8: d50 {:.3} mm on crests, {:.3} mm in troughs",
            an.d50_crest_mm, an.d50_trough_mm
        ),
        &[
            Panel {
                title: format!("surface grain size {lo:.3}-{hi:.3} mm (yellow = coarse)"),
                field: field(nx, ny, states_over(&d, lo, hi)),
            },
            Panel {
                title: "elevation".into(),
                field: field(nx, ny, states_over(&elev, elo, ehi)),
            },
        ],
        1,
        &ramp_palette(),
        900,
    )?;
    Ok(vec![path])
}

/// Seeds of each point of the error-against-time study.
const STUDY_SEEDS: u64 = 6;

/// One run of the study: (wavelength m, height m, ripple index) at each of `at` (steps,
/// increasing) and the CPU seconds spent until then (timed on the run's own thread).
fn study_run(p: &RippleParams, at: &[u64]) -> Result<Vec<([f64; 3], f64)>, String> {
    let t = Instant::now();
    let mut r = Ripple::new(p).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for &n in at {
        r.run(n - r.time(), |_| {});
        let a = Analysis::of(&r);
        out.push((
            [a.wavelength_m, a.height_m, a.ripple_index],
            t.elapsed().as_secs_f64(),
        ));
    }
    Ok(out)
}

/// (CPU seconds, means, standard errors of the means) of one study point.
type StudyPoint = (f64, [f64; 3], [f64; 3]);

/// (mean CPU seconds, means, standard errors of the means) over the seeds' `runs` (each
/// [`study_run`]'s checkpoints), at each of `checkpoints` checkpoints.
fn points(runs: &[Vec<([f64; 3], f64)>], checkpoints: usize) -> Vec<StudyPoint> {
    let n = runs.len() as f64;
    (0..checkpoints)
        .map(|j| {
            let secs = runs.iter().map(|r| r[j].1).sum::<f64>() / n;
            let mut mean = [0.0; 3];
            let mut se = [0.0; 3];
            for i in 0..3 {
                mean[i] = runs.iter().map(|r| r[j].0[i]).sum::<f64>() / n;
                let var = runs
                    .iter()
                    .map(|r| (r[j].0[i] - mean[i]).powi(2))
                    .sum::<f64>()
                    / (n - 1.0);
                se[i] = (var / n).sqrt();
            }
            (secs, mean, se)
        })
        .collect()
}

/// One configuration of the error-against-time study: name, parameters, checkpoints (steps).
type StudyConfig = (&'static str, RippleParams, Vec<u64>);

/// The configurations of the error-against-time study (the defaults' sliced water and 10,000
/// steps on smaller grids of 20 automata per column): name, parameters and checkpoints.
fn study_configs() -> Result<Vec<StudyConfig>, String> {
    let base = RippleParams {
        nx: 64,
        ny: 32,
        layers: 20,
        ..scene().map_err(|e| e.to_string())?
    };
    let grid = |nx, ny| RippleParams {
        nx,
        ny,
        ..base.clone()
    };
    let bin = |bin_size, layer_thickness| RippleParams {
        bin_size,
        layer_thickness,
        ..base.clone()
    };
    let end = vec![base.steps];
    Ok(vec![
        ("steps", base.clone(), vec![1250, 2500, 5000, 10000]),
        ("grid 32x16", grid(32, 16), end.clone()),
        ("grid 48x24", grid(48, 24), end.clone()),
        ("grid 96x48", grid(96, 48), end.clone()),
        ("bin 2.5 mm", bin(0.0025, 0.00025), end.clone()),
        ("bin 10 mm", bin(0.01, 0.001), end),
    ])
}

/// The study behind `ripple_error_vs_time.png` as independent runs (each configuration: the
/// steps, three grid sizes and two bin sizes, for 6 seeds from 1000), for `cellsurf converge ripple
/// --part i/N` ([`crate::engine::study`]).
pub struct ErrorStudy;

impl crate::engine::study::Study for ErrorStudy {
    fn name(&self) -> &'static str {
        "ripple"
    }
    fn runs(&self) -> Vec<String> {
        study_configs()
            .unwrap_or_default()
            .iter()
            .flat_map(|(name, _, _)| {
                (0..STUDY_SEEDS).map(move |s| format!("{name} seed {}", 1000 + s))
            })
            .collect()
    }
    fn run(&self, name: &str) -> Result<toml::Value, String> {
        let (config, seed) = name
            .rsplit_once(" seed ")
            .and_then(|(c, s)| Some((c, s.parse::<u64>().ok()?)))
            .ok_or_else(|| format!("not a run of the study: {name}"))?;
        let (_, p, at) = study_configs()?
            .into_iter()
            .find(|c| c.0 == config)
            .ok_or_else(|| format!("not a run of the study: {name}"))?;
        crate::engine::study::record(&study_run(&RippleParams { seed, ..p }, &at)?)
    }
    fn draw(&self, records: &[toml::Value], dir: &Path) -> Result<Vec<PathBuf>, String> {
        draw_error(records, dir).map_err(|e| e.to_string())
    }
}

/// Convergence of wavelength, height and ripple index with steps, grid size and bin size, and
/// their spread over seeds, against CPU time ([`ErrorStudy`], run whole).
fn error_vs_time(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    crate::engine::study::run_whole(&ErrorStudy, dir).map_err(FigureError::Model)
}

fn draw_error(records: &[toml::Value], dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let configs = study_configs().map_err(FigureError::Model)?;
    let base = configs[0].1.clone();
    let mut recs = records.iter();
    let mut pts = Vec::new();
    for (_, _, at) in &configs {
        let runs = recs
            .by_ref()
            .take(STUDY_SEEDS as usize)
            .map(crate::engine::study::from_record::<Vec<([f64; 3], f64)>>)
            .collect::<Result<Vec<_>, _>>()
            .map_err(FigureError::Model)?;
        pts.push(points(&runs, at.len()));
    }
    let by_steps = pts[0].clone();
    let at_base = by_steps[by_steps.len() - 1];
    let studies: Vec<(String, Vec<StudyPoint>)> = vec![
        ("steps 1250-10000 (64 x 32)".into(), by_steps),
        (
            "grid 32 x 16, 64 x 32, 96 x 48".into(),
            vec![pts[1][0], pts[2][0], at_base, pts[3][0]],
        ),
        (
            "bin 2.5, 5, 10 mm (64 x 32, gd = bin / 10)".into(),
            vec![pts[4][0], at_base, pts[5][0]],
        ),
    ];
    let (sw_l, sw_h) = super::predictors::soulsby_whitehouse(base.d50 * 1e-3);
    let reference = [Some(sw_l * 100.0), Some(sw_h * 100.0), Some(sw_l / sw_h)];
    let names = ["wavelength", "height", "ripple index"];
    let units = [" (cm)", " (cm)", ""];
    let scale = [100.0, 100.0, 1.0];
    let (tmin, tmax) = studies
        .iter()
        .flat_map(|(_, pts)| pts.iter().map(|p| p.0))
        .fold((f64::INFINITY, 0.0f64), |(a, b), t| (a.min(t), b.max(t)));
    let mut charts: Vec<Chart> = (0..3)
        .map(|i| {
            let mut series: Vec<Series> = studies
                .iter()
                .map(|(label, pts)| Series {
                    label: label.clone(),
                    x: pts.iter().map(|p| p.0).collect(),
                    y: pts.iter().map(|p| p.1[i] * scale[i]).collect(),
                    points: true,
                })
                .collect();
            if let Some(v) = reference[i] {
                series.push(Series {
                    label: "Soulsby & Whitehouse (2005)".into(),
                    x: vec![tmin, tmax],
                    y: vec![v, v],
                    points: false,
                });
            }
            Chart {
                title: format!("mean {} over {STUDY_SEEDS} seeds", names[i]),
                x_label: "CPU seconds per run".into(),
                y_label: format!("{}{}", names[i], units[i]),
                series,
                log_x: true,
                log_y: false,
            }
        })
        .collect();
    charts.extend((0..3).map(|i| {
        Chart {
            title: format!("standard error of the mean {}", names[i]),
            x_label: "CPU seconds per run".into(),
            y_label: "standard error / mean".into(),
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
            log_y: true,
        }
    }));
    let path = dir.join("ripple_error_vs_time.png");
    line_charts(
        &path,
        "Ripple measures against CPU time: steps, grid and bin size (sliced water, 20 automata per column)",
        &charts,
        3,
        (560, 420),
    )?;
    Ok(vec![path])
}
