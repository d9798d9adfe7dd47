//! The ripple figures (feature `plot`), listed in [`FIGURES`]: the paper's Figs. 2, 3, 4, 7 and
//! 8 regenerated, the error-versus-CPU-time study ([`ErrorStudy`]) and the validation against
//! the ripple predictors ([`ValidationStudy`]).
//!
//! Each of Figs. 2, 3, 4, 7 and 8 takes its parameters from its scenario file ([`SCENARIOS`],
//! `scenarios/NAME.toml`, a `cellsurf ripple` scenario). Sizes are reduced so that all of them
//! together take well under a minute in release: Figs. 3, 4, 7 and 8 draw the same run (128 x
//! 64 columns x 30 automata, 10000 steps; their four files hold the same parameters), made once
//! per process; Fig. 2 is a 2-D section.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
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

/// The scenario files of the figures made from one run, by figure name.
pub const SCENARIOS: &[(&str, &str)] = crate::plot::scenario_files![
    "ripple_fig2_shadow",
    "ripple_fig3_evolution",
    "ripple_fig4_impedance",
    "ripple_fig7_section",
    "ripple_fig8_surface_grain_size",
];

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
    Figure {
        name: "ripple_validation",
        about: "Sand ripple generator against the predictors: current ripples' wavelength and height against d50 (Soulsby & Whitehouse 2005), with the paper's rules and with the recipe for mature current ripples (the command's default for currents), wave ripples' wavelength against d0 (Wiberg & Harris 1994), crest normal against current angle (means over 3 seeds, standard errors)",
        make: validation,
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

/// The parameters of a figure's scenario ([`SCENARIOS`]).
pub fn scenario(name: &str) -> Result<RippleParams, FigureError> {
    crate::plot::read_scenario(
        name,
        crate::plot::scenario_text(SCENARIOS, name)?,
        RippleParams::from_toml,
    )
}

/// A figure run: snapshots at t0, t10, t25, t100 (in hundredths of the run) and the final
/// state.
struct FigRun {
    snaps: Vec<(u64, Vec<f32>)>,
    last: Ripple,
}

/// The run of figure `name`'s scenario, made once per process for all the figures whose
/// scenarios hold the same parameters.
fn fig_run(name: &str) -> Result<Arc<FigRun>, FigureError> {
    type Runs = Vec<(RippleParams, Arc<FigRun>)>;
    static RUNS: Mutex<Runs> = Mutex::new(Vec::new());
    let p = scenario(name)?;
    let mut runs = RUNS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, r)) = runs.iter().find(|(q, _)| *q == p) {
        return Ok(r.clone());
    }
    let mut r = Ripple::new(&p).map_err(model_err)?;
    let times: Vec<u64> = [0u64, 10, 25, 100]
        .iter()
        .map(|k| p.steps * k / 100)
        .collect();
    let snaps = run_recording(&mut r, p.steps, &times, |_| {});
    let run = Arc::new(FigRun { snaps, last: r });
    runs.push((p, run.clone()));
    Ok(run)
}

fn fig2(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    // A 2-D section: a short run from a rough bed, then the sliced water volume over it.
    let p = scenario("ripple_fig2_shadow")?;
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
                    && r.lead(
                        x,
                        0,
                        r.water()
                            .bed_speed(r.volume().heights(), nx, 1, x, 0, hmax, &flow),
                    ) > 0.0
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
    let run = fig_run("ripple_fig3_evolution")?;
    let (nx, ny) = run.last.size();
    let all: Vec<f64> = run
        .snaps
        .iter()
        .flat_map(|s| s.1.iter().map(|&v| v as f64))
        .collect();
    let (lo, hi) = finite_range(&all);
    let labels = ["t0", "t10", "t25", "t100"];
    // physical time of each snapshot: the step duration of the Meyer-Peter & Mueller bedload
    let step_s = super::clock::StepClock::of(run.last.params())
        .map_err(model_err)?
        .step_s;
    let panels = run
        .snaps
        .iter()
        .zip(labels)
        .map(|((t, e), l)| {
            let v: Vec<f64> = e.iter().map(|&x| x as f64).collect();
            Panel {
                title: format!("{l} (step {t}, {:.0} s of flow)", *t as f64 * step_s),
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
    let run = fig_run("ripple_fig4_impedance")?;
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
    let run = fig_run("ripple_fig7_section")?;
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
    let run = fig_run("ripple_fig8_surface_grain_size")?;
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
        ..scenario("ripple_fig3_evolution").map_err(|e| e.to_string())?
    };
    let grid = |nx, ny| RippleParams {
        nx,
        ny,
        ..base.clone()
    };
    // Bin sizes at fixed physics: the same domain in metres and the same simulated time (the
    // steps from each bin size's step duration).
    let seconds = super::clock::StepClock::of(&base)
        .map_err(|e| e.to_string())?
        .step_s
        * base.steps as f64;
    let bin = |bin_size: f64| -> Result<(RippleParams, Vec<u64>), String> {
        let f = base.bin_size / bin_size;
        let p = RippleParams {
            bin_size,
            layer_thickness: bin_size / 10.0,
            nx: (base.nx as f64 * f).round() as usize,
            ny: (base.ny as f64 * f).round() as usize,
            ..base.clone()
        };
        let steps = super::clock::StepClock::of(&p)
            .and_then(|c| c.steps_for(seconds))
            .map_err(|e| e.to_string())?;
        Ok((RippleParams { steps, ..p }, vec![steps]))
    };
    let end = vec![base.steps];
    let (fine, fine_end) = bin(0.0025)?;
    let (coarse, coarse_end) = bin(0.01)?;
    Ok(vec![
        ("steps", base.clone(), vec![1250, 2500, 5000, 10000]),
        ("grid 32x16", grid(32, 16), end.clone()),
        ("grid 48x24", grid(48, 24), end.clone()),
        ("grid 96x48", grid(96, 48), end),
        ("bin 2.5 mm", fine, fine_end),
        ("bin 10 mm", coarse, coarse_end),
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
            "bin 2.5, 5, 10 mm (32 x 16 cm, same simulated time)".into(),
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

/// Seeds of each point of the validation study.
const VALIDATION_SEEDS: [u64; 3] = [1, 2, 3];

/// Median grain sizes (mm) of the current-ripple runs of the validation study.
const VALIDATION_D50_MM: [f64; 3] = [0.1, 0.2, 0.4];

/// Orbital diameters (m) of the wave-ripple runs (0.3 mm sand, U_w = 0.4 m/s, no current).
const VALIDATION_D0_M: [f64; 3] = [0.2, 0.3, 0.4];

/// Near-bed orbital velocity (m/s) of the wave-ripple runs.
const VALIDATION_UW: f64 = 0.4;

/// Current angles (degrees) of the crest-orientation runs: 0 to 180 in steps of 15.
fn validation_angles() -> Vec<f64> {
    (0..=12).map(|i| 15.0 * i as f64).collect()
}

/// Simulated seconds of the validation runs of current ripples (both) and angles (the first).
const VALIDATION_SECONDS: [f64; 2] = [300.0, 1800.0];

/// Simulated seconds of the wave-ripple runs (4.4 and 8.9 hours of waves: the lee vortex's
/// fields take hours to stop growing); the second is twice the first, for the test of
/// maturity between the two (wavelength and height within 10 % between t and 2t).
const VALIDATION_WAVE_SECONDS: [f64; 2] = [16_000.0, 32_000.0];

/// Automata per column of the wave-ripple runs: 10 cm of sand (automata of 0.5 mm), so that
/// the troughs of the vortex ripples (about 4 cm high) stay off the substrate.
const VALIDATION_WAVE_LAYERS: usize = 200;

/// Simulated seconds of the recipe's runs (docs/ripple.md, "A recipe for mature current
/// ripples": the lengths they keep until 24,000 s).
const RECIPE_SECONDS: f64 = 6000.0;

/// Columns of the recipe's 2-D sections: 1024 of its bins of 0.75 flat-bed travels, 1.26 /
/// 1.90 / 2.57 m at 0.1 / 0.2 / 0.4 mm (ten or more of its ripples, whose lengths come in
/// steps of the section over k, 6-10 % apart).
const RECIPE_NX: usize = 1024;

/// One case of the validation study: current ripples of a grain size (with the paper's rules,
/// the library's defaults, or with the recipe for mature current ripples, the command's default
/// for currents), wave ripples of an orbital diameter, or a current
/// angle.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ValidationCase {
    /// d50 (mm), seconds of flow.
    Current(f64, f64),
    /// d50 (mm), under the recipe for mature current ripples ([`super::recipe::Recipe`]).
    Recipe(f64),
    /// d0 (m), seconds of waves.
    Wave(f64, f64),
    /// Current angle (deg).
    Angle(f64),
}

impl ValidationCase {
    fn all() -> Vec<ValidationCase> {
        VALIDATION_SECONDS
            .iter()
            .flat_map(|&t| {
                VALIDATION_D50_MM
                    .iter()
                    .map(move |&d| ValidationCase::Current(d, t))
            })
            .chain(VALIDATION_WAVE_SECONDS.iter().flat_map(|&t| {
                VALIDATION_D0_M
                    .iter()
                    .map(move |&d| ValidationCase::Wave(d, t))
            }))
            .chain(validation_angles().into_iter().map(ValidationCase::Angle))
            .chain(VALIDATION_D50_MM.iter().map(|&d| ValidationCase::Recipe(d)))
            .collect()
    }

    /// Its seconds of flow.
    fn seconds(self) -> f64 {
        match self {
            ValidationCase::Current(_, t) => t,
            ValidationCase::Recipe(_) => RECIPE_SECONDS,
            ValidationCase::Wave(_, t) => t,
            ValidationCase::Angle(_) => VALIDATION_SECONDS[0],
        }
    }

    fn name(self) -> String {
        match self {
            ValidationCase::Current(d, t) => format!("current d50 {d} mm {t} s"),
            ValidationCase::Recipe(d) => format!("recipe d50 {d} mm {RECIPE_SECONDS} s"),
            ValidationCase::Wave(d, t) => format!("wave d0 {d} m {t} s"),
            ValidationCase::Angle(a) => format!("current angle {a} deg"),
        }
    }

    /// The run's parameters (before the step duration sets steps and wave period): the
    /// figure scene on 192 x 48 bins of 5 mm (96 x 24 cm) along the flow, 128 x 128 bins
    /// (64 x 64 cm) in the grid frame for the angles, 20 automata per column; the waves on a
    /// narrow strip along them, 512 x 8 bins (256 x 4 cm: wave ripples under regular waves are
    /// long-crested), with 200 automata per column, the lee vortex and the command line's
    /// sorting; the recipe on a 2-D section of [`RECIPE_NX`] bins with its own bins,
    /// automata and sand (10 cm), at the command line's 0.5 m/s.
    fn params(self, seed: u64) -> Result<RippleParams, String> {
        let base = RippleParams {
            layers: 20,
            seed,
            ..scenario("ripple_fig3_evolution").map_err(|e| e.to_string())?
        };
        Ok(match self {
            ValidationCase::Current(d50, _) => RippleParams {
                nx: 192,
                ny: 48,
                d50,
                ..base
            },
            ValidationCase::Wave(d0, _) => RippleParams {
                nx: 512,
                ny: 8,
                layers: VALIDATION_WAVE_LAYERS,
                // the orbital excursion A = U_w T / (2 pi) = d0 / 2, as the command line sets it
                wave_vortex: d0 / 2.0,
                // the command line's well-sorted sand (the figure scene's is poorly sorted)
                sorting: RippleParams::default().sorting,
                d50: 0.3,
                current_speed: 0.0,
                wave_amplitude: VALIDATION_UW,
                wave_period: 64.0,
                ..base
            },
            ValidationCase::Angle(a) => RippleParams {
                nx: 128,
                ny: 128,
                current_angle: a,
                frame: super::Frame::Grid,
                ..base
            },
            ValidationCase::Recipe(d50) => RippleParams {
                mode: super::Mode::TwoD,
                nx: RECIPE_NX,
                ny: 1,
                d50,
                seed,
                ..super::recipe::Recipe::MatureCurrent.params()
            },
        })
    }
}

/// One run's record in the validation study.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
struct ValidationRecord {
    wavelength_m: f64,
    height_m: f64,
    ripple_index: f64,
    symmetry_index: f64,
    crest_normal_deg: f64,
    steps: u64,
}

/// Runs `case` with `seed` for its seconds of flow ([`ValidationCase::seconds`]).
fn validation_run(case: ValidationCase, seed: u64) -> Result<ValidationRecord, String> {
    let mut p = case.params(seed)?;
    if let ValidationCase::Wave(d0, _) = case {
        // the waves' own bed friction, as the command line sets it
        let period_s = std::f64::consts::PI * d0 / VALIDATION_UW;
        p.wave_friction_factor = super::waves::run_wave_friction_factor(
            VALIDATION_UW,
            period_s,
            p.d50 * 1e-3,
            p.drag_coefficient,
        );
    }
    let clock = super::clock::StepClock::of(&p).map_err(|e| e.to_string())?;
    p.steps = clock.steps_for(case.seconds()).map_err(|e| e.to_string())?;
    if let ValidationCase::Wave(d0, _) = case {
        let period_s = std::f64::consts::PI * d0 / VALIDATION_UW;
        p.wave_period = period_s / clock.step_s;
    }
    let mut r = Ripple::new(&p).map_err(|e| e.to_string())?;
    r.run(p.steps, |_| {});
    let a = Analysis::of(&r);
    Ok(ValidationRecord {
        wavelength_m: a.wavelength_m,
        height_m: a.height_m,
        ripple_index: a.ripple_index,
        symmetry_index: a.symmetry_index,
        crest_normal_deg: a.crest_normal_deg,
        steps: p.steps,
    })
}

/// The study behind `ripple_validation.png` as independent runs: current ripples for three
/// grain sizes after 300 s and 1800 s of flow with the paper's rules, and under the recipe for
/// mature current ripples after 6000 s on 2-D sections of 1024 of its bins, wave ripples (with the lee vortex, on narrow strips with 10 cm of sand)
/// for three orbital diameters after 16,000 s and 32,000 s, and the crest normal for current
/// angles 0-180 deg after 300 s, 3 seeds each
/// (`cellsurf converge ripple_validation`, in parts with `--part i/N`).
pub struct ValidationStudy;

impl crate::engine::study::Study for ValidationStudy {
    fn name(&self) -> &'static str {
        "ripple_validation"
    }
    fn figure(&self) -> String {
        "ripple_validation".into()
    }
    fn runs(&self) -> Vec<String> {
        ValidationCase::all()
            .into_iter()
            .flat_map(|c| {
                VALIDATION_SEEDS
                    .iter()
                    .map(move |s| format!("{} seed {s}", c.name()))
            })
            .collect()
    }
    fn run(&self, name: &str) -> Result<toml::Value, String> {
        let (case, seed) = name
            .rsplit_once(" seed ")
            .and_then(|(c, s)| Some((c, s.parse::<u64>().ok()?)))
            .ok_or_else(|| format!("not a run of the study: {name}"))?;
        let case = ValidationCase::all()
            .into_iter()
            .find(|c| c.name() == case)
            .ok_or_else(|| format!("not a run of the study: {name}"))?;
        crate::engine::study::record(&validation_run(case, seed)?)
    }
    fn draw(&self, records: &[toml::Value], dir: &Path) -> Result<Vec<PathBuf>, String> {
        draw_validation(records, dir).map_err(|e| e.to_string())
    }
}

/// The validation figure, run whole ([`ValidationStudy`]).
fn validation(dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    crate::engine::study::run_whole(&ValidationStudy, dir).map_err(FigureError::Model)
}

/// Mean and standard error of the mean of `v`.
fn mean_se(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (m, (var / n).sqrt())
}

/// A crest normal (an axis, degrees) folded onto the representative nearest `angle`.
fn fold_axis(normal: f64, angle: f64) -> f64 {
    normal - 180.0 * ((normal - angle) / 180.0).round()
}

/// The model's means (points) and their standard errors (one vertical bar per point, in one
/// series broken by NaN) at abscissae `x`.
fn model_series(label: &str, x: &[f64], ms: &[(f64, f64)]) -> [Series; 2] {
    let mut bx = Vec::new();
    let mut by = Vec::new();
    for (&x, &(m, se)) in x.iter().zip(ms) {
        bx.extend([x, x, f64::NAN]);
        by.extend([m - se, m + se, f64::NAN]);
    }
    [
        Series {
            label: format!("{label}: mean over {} seeds", VALIDATION_SEEDS.len()),
            x: x.to_vec(),
            y: ms.iter().map(|m| m.0).collect(),
            points: true,
        },
        Series {
            label: "+- one standard error".into(),
            x: bx,
            y: by,
            points: false,
        },
    ]
}

fn draw_validation(records: &[toml::Value], dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let cases = ValidationCase::all();
    let n = VALIDATION_SEEDS.len();
    if records.len() != cases.len() * n {
        return Err(FigureError::Model(format!(
            "{} records for {} runs",
            records.len(),
            cases.len() * n
        )));
    }
    let recs: Vec<ValidationRecord> = records
        .iter()
        .map(crate::engine::study::from_record)
        .collect::<Result<_, _>>()
        .map_err(FigureError::Model)?;
    let stat = |case: ValidationCase, f: &dyn Fn(&ValidationRecord) -> f64| {
        let i = cases.iter().position(|c| *c == case).unwrap_or(0);
        mean_se(&recs[i * n..(i + 1) * n].iter().map(f).collect::<Vec<_>>())
    };
    let d50: Vec<f64> = VALIDATION_D50_MM.to_vec();
    let curve_d50: Vec<f64> = (0..=40).map(|i| 0.08 + 0.42 * i as f64 / 40.0).collect();
    let sw: Vec<(f64, f64)> = curve_d50
        .iter()
        .map(|&d| super::predictors::soulsby_whitehouse(d * 1e-3))
        .collect();
    let cur = |t: f64, f: &dyn Fn(&ValidationRecord) -> f64| -> Vec<(f64, f64)> {
        d50.iter()
            .map(|&d| {
                let (m, se) = stat(ValidationCase::Current(d, t), f);
                (100.0 * m, 100.0 * se)
            })
            .collect()
    };
    let [t1, t2] = VALIDATION_SECONDS;
    let recipe = |f: &dyn Fn(&ValidationRecord) -> f64, scale: f64| -> Vec<(f64, f64)> {
        d50.iter()
            .map(|&d| {
                let (m, se) = stat(ValidationCase::Recipe(d), f);
                (scale * m, scale * se)
            })
            .collect()
    };
    // the recipe's standard errors stay out of the legends (the bars are drawn alike)
    let recipe_series = |label: String, ms: &[(f64, f64)]| {
        let [mean, mut se] = model_series(&label, &d50, ms);
        se.label.clear();
        [mean, se]
    };
    let recipe_label = format!("recipe (the default's rules), 2-D, {RECIPE_SECONDS} s");
    let mut wl = model_series(
        &format!("paper's rules, 96 x 24 cm, {t1} s"),
        &d50,
        &cur(t1, &|r| r.wavelength_m),
    )
    .to_vec();
    wl.extend(model_series(
        &format!("paper's rules, 96 x 24 cm, {t2} s"),
        &d50,
        &cur(t2, &|r| r.wavelength_m),
    ));
    wl.push(Series {
        label: "Soulsby & Whitehouse (2005)".into(),
        x: curve_d50.clone(),
        y: sw.iter().map(|p| 100.0 * p.0).collect(),
        points: false,
    });
    wl.extend(recipe_series(
        recipe_label.clone(),
        &recipe(&|r| r.wavelength_m, 100.0),
    ));
    let mut ht = model_series(
        &format!("paper's rules, 96 x 24 cm, {t1} s"),
        &d50,
        &cur(t1, &|r| r.height_m),
    )
    .to_vec();
    ht.extend(model_series(
        &format!("paper's rules, 96 x 24 cm, {t2} s"),
        &d50,
        &cur(t2, &|r| r.height_m),
    ));
    ht.push(Series {
        label: "Soulsby & Whitehouse (2005)".into(),
        x: curve_d50,
        y: sw.iter().map(|p| 100.0 * p.1).collect(),
        points: false,
    });
    ht.extend(recipe_series(recipe_label, &recipe(&|r| r.height_m, 100.0)));
    let d0: Vec<f64> = VALIDATION_D0_M.iter().map(|d| 100.0 * d).collect();
    let [w1, w2] = VALIDATION_WAVE_SECONDS;
    let waves = |t: f64| -> Vec<(f64, f64)> {
        VALIDATION_D0_M
            .iter()
            .map(|&d| {
                let (m, se) = stat(ValidationCase::Wave(d, t), &|r| r.wavelength_m);
                (100.0 * m, 100.0 * se)
            })
            .collect()
    };
    let mut wv = model_series(&format!("model, {w1} s"), &d0, &waves(w1)).to_vec();
    wv.extend(model_series(&format!("model, {w2} s"), &d0, &waves(w2)));
    let d0_line = [15.0, 45.0];
    wv.push(Series {
        label: "Wiberg & Harris (1994): 0.62 d0".into(),
        x: d0_line.to_vec(),
        y: d0_line.iter().map(|d| 0.62 * d).collect(),
        points: false,
    });
    let angles = validation_angles();
    let crest: Vec<(f64, f64)> = angles
        .iter()
        .map(|&a| {
            stat(ValidationCase::Angle(a), &|r| {
                fold_axis(r.crest_normal_deg, a)
            })
        })
        .collect();
    let mut an = model_series("grid frame (--frame grid), 64 x 64 cm", &angles, &crest).to_vec();
    // In the flow frame (the default) the lattice turns with the current: the bed at any angle
    // is the bed at 0 deg, turned (the same run byte for byte), so its crest normal is the
    // angle plus the offset of the 0 deg current runs (0.2 mm, 96 x 24 cm, same time).
    let zero = stat(ValidationCase::Current(0.2, t1), &|r| {
        fold_axis(r.crest_normal_deg, 0.0)
    });
    an.extend(model_series(
        "flow frame (default), 96 x 24 cm",
        &angles,
        &angles
            .iter()
            .map(|a| (a + zero.0, zero.1))
            .collect::<Vec<_>>(),
    ));
    an.push(Series {
        label: "crest normal = current angle".into(),
        x: vec![0.0, 180.0],
        y: vec![0.0, 180.0],
        points: false,
    });
    let shape = |case: &dyn Fn(f64) -> ValidationCase, xs: &[f64], xv: &[f64]| {
        let ri: Vec<(f64, f64)> = xs
            .iter()
            .map(|&x| stat(case(x), &|r| r.ripple_index))
            .collect();
        let si: Vec<(f64, f64)> = xs
            .iter()
            .map(|&x| stat(case(x), &|r| r.symmetry_index))
            .collect();
        let mut v = model_series("ripple index", xv, &ri).to_vec();
        v.extend(model_series("symmetry index", xv, &si));
        v
    };
    let mut cur_shape = shape(&|d| ValidationCase::Current(d, t2), &d50, &d50);
    cur_shape.push(Series {
        label: "Soulsby & Whitehouse (2005): ripple index".into(),
        x: d50.clone(),
        y: d50
            .iter()
            .map(|&d| {
                let (l, h) = super::predictors::soulsby_whitehouse(d * 1e-3);
                l / h
            })
            .collect(),
        points: false,
    });
    cur_shape.push(Series {
        label: "current ripples: symmetry index at least 2".into(),
        x: vec![d50[0], d50[d50.len() - 1]],
        y: vec![2.0, 2.0],
        points: false,
    });
    cur_shape.extend(recipe_series(
        format!("recipe, {RECIPE_SECONDS} s: ripple index"),
        &recipe(&|r| r.ripple_index, 1.0),
    ));
    cur_shape.extend(recipe_series(
        format!("recipe, {RECIPE_SECONDS} s: symmetry index"),
        &recipe(&|r| r.symmetry_index, 1.0),
    ));
    let mut wave_shape = shape(&|d| ValidationCase::Wave(d, w2), &VALIDATION_D0_M, &d0);
    wave_shape.push(Series {
        label: "Wiberg & Harris (1994), orbital: ripple index".into(),
        x: d0.clone(),
        y: VALIDATION_D0_M
            .iter()
            .map(|&d| {
                let (l, h, _) = super::predictors::wiberg_harris(d, 0.3e-3);
                l / h
            })
            .collect(),
        points: false,
    });
    wave_shape.push(Series {
        label: "symmetric (symmetry index 1)".into(),
        x: vec![d0[0], d0[d0.len() - 1]],
        y: vec![1.0, 1.0],
        points: false,
    });
    let charts = vec![
        Chart {
            title: "current ripples (0.5 m/s): wavelength".into(),
            x_label: "d50 (mm)".into(),
            y_label: "wavelength (cm)".into(),
            series: wl,
            log_x: false,
            log_y: false,
        },
        Chart {
            title: "current ripples (0.5 m/s): height".into(),
            x_label: "d50 (mm)".into(),
            y_label: "height (cm)".into(),
            series: ht,
            log_x: false,
            log_y: false,
        },
        Chart {
            title: format!("wave ripples (0.3 mm, U_w = {VALIDATION_UW} m/s, 256 x 4 cm, vortex)"),
            x_label: "orbital diameter d0 (cm)".into(),
            y_label: "wavelength (cm)".into(),
            series: wv,
            log_x: false,
            log_y: false,
        },
        Chart {
            title: format!("crest normal against current angle ({t1} s)"),
            x_label: "current angle (deg)".into(),
            y_label: "crest normal (deg)".into(),
            series: an,
            log_x: false,
            log_y: false,
        },
        Chart {
            title: format!("current ripples ({t2} s): ripple and symmetry index"),
            x_label: "d50 (mm)".into(),
            y_label: "ripple index, symmetry index".into(),
            series: cur_shape,
            log_x: false,
            log_y: true,
        },
        Chart {
            title: format!("wave ripples ({w2} s): ripple index and symmetry index"),
            x_label: "orbital diameter d0 (cm)".into(),
            y_label: "ripple index, symmetry index".into(),
            series: wave_shape,
            log_x: false,
            log_y: true,
        },
    ];
    let path = dir.join("ripple_validation.png");
    line_charts(
        &path,
        "Sand ripples against the predictors (the model's means and standard errors over 3 seeds)",
        &charts,
        2,
        (640, 460),
    )?;
    Ok(vec![path])
}
