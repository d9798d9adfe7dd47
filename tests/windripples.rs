//! Wind ripples (the notebook "Modelling wind ripples"): the notebook's particle model, its extreme cases and
//! its reproducibility. Small particle counts, so that the suite is fast in debug builds.
//!
//! - Density normalisation: the counts sum to N and the mean height is 1 at every step.
//! - The wrap keeps `x` in `[0, 1)` and `y` in `[0, 1 + L)` (the saltation is wrapped by the
//!   next step, as in the notebook); `L >= 1` wraps around.
//! - Extreme cases: kappa = 0 (every hop is L/2), kappa = 1e6 (no NaN), D = 0 and L = 0 (nothing
//!   moves, bit for bit), one particle, one bin, more bins than particles.
//! - Reproducibility: the same seed gives the same bytes, whatever the number of threads; both
//!   diffusion schedules; the first positions of seed 1998 are pinned.
//! - Statistics: pure diffusion has displacement variance `sum sigma_s^2` (constant: `steps D^2`)
//!   within five standard errors; the wavelength estimators recover synthetic sinusoids.

mod common;

use cellsurf::windripples::{
    self, CHUNK, Schedule, WindError, WindParams, WindRipples, height_stats, mean_wavelength_bins,
    npy_bytes, power_spectrum_y, wavelength_bins,
};

fn small(particles: usize, bins: usize) -> WindParams {
    WindParams {
        particles,
        bins,
        steps: 10,
        ..WindParams::default()
    }
}

fn model(p: WindParams) -> WindRipples {
    WindRipples::new(p).expect("valid parameters")
}

/// Owned copies of the positions (after the pending saltation).
fn positions(w: &mut WindRipples) -> (Vec<f64>, Vec<f64>) {
    let (x, y) = w.positions();
    (x.to_vec(), y.to_vec())
}

#[test]
fn density_normalisation_holds_at_every_step() {
    // N a power of two: the mean is exactly 1. N = 3001 (odd, several chunks): 1 to rounding.
    for (n, bins, exact) in [
        (4096, 16, true),
        (3001, 16, false),
        (2 * CHUNK + 5, 32, false),
    ] {
        let mut w = model(small(n, bins));
        for step in 0..12 {
            let total: u64 = w.counts().iter().map(|&c| u64::from(c)).sum();
            assert_eq!(total, n as u64, "step {step}");
            assert_eq!(w.counts().len(), bins * bins);
            let s = w.stats();
            if exact {
                assert_eq!(s.height_mean, 1.0, "step {step}");
            } else {
                assert!(
                    (s.height_mean - 1.0).abs() < 1e-15,
                    "step {step}: {}",
                    s.height_mean
                );
            }
            // h = count * bins^2 / N, cell by cell.
            let scale = (bins * bins) as f64 / n as f64;
            for (h, &c) in w.height().iter().zip(w.counts()) {
                assert_eq!(*h, f64::from(c) * scale);
            }
            w.step();
        }
    }
}

#[test]
fn positions_stay_on_the_torus() {
    // Large moves: D = 0.7 and L = 0.3 push particles across the edges every step.
    let hop = 0.3;
    let mut w = model(WindParams {
        diffusion: 0.7,
        hop,
        kappa: 0.5,
        schedule: Schedule::Constant,
        ..small(5000, 8)
    });
    let (x, y) = positions(&mut w);
    assert!(x.iter().chain(&y).all(|v| (0.0..1.0).contains(v)));
    for _ in 0..8 {
        w.step();
        let cells = w.cells().to_vec();
        let (x, y) = positions(&mut w);
        assert!(x.iter().all(|v| (0.0..1.0).contains(v)));
        assert!(y.iter().all(|v| (0.0..1.0 + hop).contains(v)));
        // Every particle was histogrammed in a cell of the grid, at its wrapped position.
        for ((&c, &xi), &yi) in cells.iter().zip(&x).zip(&y) {
            assert!((c as usize) < 64);
            assert_eq!(c as usize / 8, (xi * 8.0) as usize);
            // y was salted after the histogram: its cell row is at or after the recorded one
            // (modulo the wrap still to come).
            let row = c as usize % 8;
            assert!(yi * 8.0 >= row as f64 - 1e-9 && yi < 1.0 + hop);
        }
    }
}

#[test]
fn kappa_zero_gives_half_hops_exactly() {
    let hop = 1.0 / 64.0;
    let mut w = model(WindParams {
        kappa: 0.0,
        diffusion: 0.0,
        hop,
        ..small(3000, 16)
    });
    let (x0, y0) = positions(&mut w);
    w.step();
    let (x1, y1) = positions(&mut w);
    assert_eq!(x0, x1);
    for (a, b) in y0.iter().zip(&y1) {
        assert_eq!(*b, *a + hop / 2.0);
    }
}

#[test]
fn huge_kappa_gives_no_nan_and_no_hop() {
    // Every particle sits in an occupied cell (h >= bins^2 / N > 0), so kappa h >= 1e6 * 0.02
    // and the hop L sigmoid(-kappa h) underflows to exactly 0: nothing moves without diffusion.
    let mut w = model(WindParams {
        kappa: 1e6,
        diffusion: 0.0,
        ..small(3000, 8)
    });
    let before = positions(&mut w);
    for _ in 0..3 {
        w.step();
    }
    assert_eq!(positions(&mut w), before);
    // With diffusion, everything stays finite.
    let mut w = model(WindParams {
        kappa: 1e6,
        ..small(3000, 8)
    });
    for _ in 0..5 {
        w.step();
    }
    let (x, y) = positions(&mut w);
    assert!(x.iter().chain(&y).all(|v| v.is_finite()));
    let s = w.stats();
    assert!(s.height_std.is_finite() && s.height_mean.is_finite());
}

#[test]
fn no_diffusion_and_no_hop_leave_every_position_unchanged() {
    for schedule in [Schedule::Annealed, Schedule::Constant] {
        let mut w = model(WindParams {
            diffusion: 0.0,
            hop: 0.0,
            schedule,
            ..small(2 * CHUNK + 17, 16)
        });
        let before = positions(&mut w);
        let counts = w.counts().to_vec();
        for _ in 0..10 {
            w.step();
        }
        assert_eq!(positions(&mut w), before);
        assert_eq!(w.counts(), &counts[..]);
    }
}

#[test]
fn hops_of_one_torus_side_or_more_wrap_around() {
    // kappa = 0: every hop is L/2. L = 2.5 moves y by 1.25, i.e. by 0.25 on the torus.
    let mut w = model(WindParams {
        kappa: 0.0,
        diffusion: 0.0,
        hop: 2.5,
        ..small(1000, 8)
    });
    let (_, y0) = positions(&mut w);
    for _ in 0..3 {
        w.step();
    }
    let (x, y) = positions(&mut w);
    assert!(x.iter().all(|v| (0.0..1.0).contains(v)));
    for (a, b) in y0.iter().zip(&y) {
        // Two wraps seen, the last hop not yet wrapped: y = (a + 2 * 1.25) mod 1 + 1.25.
        let expect = (a + 2.5).rem_euclid(1.0) + 1.25;
        let d = (b - expect).abs();
        assert!(
            d < 1e-12 || (d - 1.0).abs() < 1e-12,
            "{a} -> {b}, expected {expect}"
        );
    }
    // L = 1 exactly, huge kappa: the validated range includes it and nothing breaks.
    let mut w = model(WindParams {
        hop: 1.0,
        ..small(1000, 8)
    });
    w.step();
    assert!(w.stats().height_std.is_finite());
}

#[test]
fn one_particle() {
    let mut w = model(small(1, 8));
    for _ in 0..5 {
        w.step();
        assert_eq!(w.counts().iter().filter(|&&c| c == 1).count(), 1);
        assert_eq!(w.counts().iter().sum::<u32>(), 1);
        let s = w.stats();
        assert_eq!(s.height_mean, 1.0);
        // One cell at 64, 63 at 0: variance (63^2 + 63) / 64 = 63.
        assert!((s.height_std - 63f64.sqrt()).abs() < 1e-12);
        assert!(s.wavelength_bins.is_some());
    }
}

#[test]
fn one_bin() {
    // A single cell: h = 1 everywhere, so every particle hops L sigmoid(-kappa) -- through the
    // precomputed table (N < 1024) and through the direct formula (N > 1024) alike.
    for n in [1000, 5000] {
        let mut w = model(WindParams {
            diffusion: 0.0,
            ..small(n, 1)
        });
        let (_, y0) = positions(&mut w);
        w.step();
        assert_eq!(w.height(), vec![1.0]);
        let (_, y1) = positions(&mut w);
        let hop = 1.0 / 64.0 * windripples::sigmoid(-4.5);
        for (a, b) in y0.iter().zip(&y1) {
            assert_eq!(*b, *a + hop);
        }
        let s = w.stats();
        assert_eq!((s.height_mean, s.height_std), (1.0, 0.0));
        assert_eq!(s.wavelength_bins, None);
        assert_eq!(s.mean_wavelength_bins, None);
    }
}

#[test]
fn more_bins_than_particles() {
    let mut w = model(small(100, 64));
    for _ in 0..10 {
        w.step();
    }
    assert_eq!(w.counts().iter().sum::<u32>(), 100);
    let s = w.stats();
    assert!((s.height_mean - 1.0).abs() < 1e-14);
    // 100 occupied cells of 4096 at most, each h = 40.96 per particle.
    assert!(s.height_std > 5.0 && s.height_std.is_finite());
    let w = s.wavelength_bins.unwrap();
    assert!((2.0..=64.0).contains(&w), "{w}");
}

/// Runs `p` for its steps inside a pool of `threads` threads; the heights and positions.
fn run_in_pool(p: &WindParams, threads: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut w = model(p.clone());
        for _ in 0..p.steps {
            w.step();
        }
        let (x, y) = positions(&mut w);
        (w.height(), x, y)
    })
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let p = WindParams {
        steps: 8,
        ..small(5 * CHUNK + 123, 32)
    };
    let one = run_in_pool(&p, 1);
    let four = run_in_pool(&p, 4);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&one.0), bits(&four.0));
    assert_eq!(bits(&one.1), bits(&four.1));
    assert_eq!(bits(&one.2), bits(&four.2));
    let three = run_in_pool(&p, 3);
    assert_eq!(bits(&one.2), bits(&three.2));
}

#[test]
fn same_seed_same_bytes_and_other_seeds_differ() {
    let p = small(3 * CHUNK, 32);
    let bytes = |p: &WindParams| {
        let r = windripples::run(p, |_| {}).unwrap();
        npy_bytes(&r.height, &[p.bins, p.bins])
    };
    let a = bytes(&p);
    assert_eq!(a, bytes(&p));
    assert_ne!(a, bytes(&WindParams { seed: 1999, ..p }));
}

#[test]
fn both_schedules_share_the_first_step_and_then_differ() {
    let base = small(2000, 16);
    let mut a = model(base.clone());
    let mut c = model(WindParams {
        schedule: Schedule::Constant,
        ..base
    });
    assert_eq!(a.next_sigma(), c.next_sigma());
    a.step();
    c.step();
    assert_eq!(positions(&mut a), positions(&mut c));
    assert_eq!(a.next_sigma(), 8e-4 / 2f64.sqrt());
    assert_eq!(c.next_sigma(), 8e-4);
    a.step();
    c.step();
    assert_ne!(positions(&mut a), positions(&mut c));
}

/// The positions of the particles with identities `ids`, as `[x, y, x, y, ...]`.
fn by_id(w: &mut WindRipples, ids: &[u32]) -> Vec<f64> {
    let index: Vec<usize> = ids
        .iter()
        .map(|&i| w.ids().iter().position(|&j| j == i).unwrap())
        .collect();
    let (x, y) = w.positions();
    index.iter().flat_map(|&k| [x[k], y[k]]).collect()
}

#[test]
fn first_positions_of_seed_1998_are_pinned() {
    // Chunk c's stream is Xoshiro256++ seeded with 1998 (SplitMix64) and jumped c times; it
    // places its particles in turn (x then y, uniform), which are then sorted by cell, and then
    // gives two ziggurat normals per particle per step in the sorted order. A change here
    // changes every published number.
    let ids = [0, 1, CHUNK as u32];
    let mut w = model(small(CHUNK + 1, 256));
    // Sorted by cell once placed.
    assert!(w.cells().windows(2).all(|c| c[0] <= c[1]));
    let start = by_id(&mut w, &ids);
    w.step();
    let after = by_id(&mut w, &ids);
    let pinned_start = [
        0.06020487971267374,
        0.31627884971608045,
        0.9363136915871016,
        0.8942444363297881,
        0.742026711493122,
        0.4632093600986835,
    ];
    let pinned_after = [
        0.0598034664793431,
        0.31600647060902576,
        0.9363914505059261,
        0.8942112993676451,
        0.7431885536940974,
        0.46178441302254253,
    ];
    assert_eq!(start, pinned_start);
    assert_eq!(after, pinned_after);
}

#[test]
fn identities_follow_the_particles_through_the_sorts() {
    // kappa = 0, D = 0: every particle moves by exactly L/2 = 0.05 along y per step, and the
    // sorts by cell (at placement and every SORT_EVERY steps) permute them.
    let steps = windripples::SORT_EVERY + 6;
    let mut w = model(WindParams {
        kappa: 0.0,
        diffusion: 0.0,
        hop: 0.1,
        ..small(3000, 16)
    });
    let (x0, y0) = positions(&mut w);
    let id0 = w.ids().to_vec();
    for _ in 0..steps {
        w.step();
    }
    let id1 = w.ids().to_vec();
    assert_ne!(id0, id1, "the particles were reordered");
    let mut seen = id1.clone();
    seen.sort_unstable();
    assert_eq!(seen, (0..3000).collect::<Vec<u32>>());
    let (x1, y1) = positions(&mut w);
    let mut at = vec![0usize; 3000];
    for (k, &i) in id0.iter().enumerate() {
        at[i as usize] = k;
    }
    for (k, &i) in id1.iter().enumerate() {
        let k0 = at[i as usize];
        assert_eq!(x1[k], x0[k0]);
        let moved = (y1[k] - y0[k0] - steps as f64 * 0.05).rem_euclid(1.0);
        assert!(!(1e-9..=1.0 - 1e-9).contains(&moved), "id {i}: {moved}");
    }
}

#[test]
fn pure_diffusion_has_the_predicted_displacement_variance() {
    // L = 0: each coordinate performs a random walk; on the torus the displacement is read as
    // the nearest image, unambiguous while its spread (0.04) is far below 1/2.
    let (d, steps) = (0.01, 16u64);
    for (schedule, expect) in [
        (Schedule::Constant, steps as f64 * d * d),
        (
            Schedule::Annealed,
            (1..=steps).map(|s| d * d / s as f64).sum::<f64>(),
        ),
    ] {
        let n = 20_000;
        let mut w = model(WindParams {
            hop: 0.0,
            diffusion: d,
            schedule,
            seed: 7,
            ..small(n, 16)
        });
        let (x0, y0) = positions(&mut w);
        for _ in 0..steps {
            w.step();
        }
        let (x1, y1) = positions(&mut w);
        let mut sum2 = 0.0;
        for (a, b) in x0.iter().zip(&x1).chain(y0.iter().zip(&y1)) {
            let dd = b - a;
            let dd = dd - dd.round();
            sum2 += dd * dd;
        }
        // Mean square of 2n normal displacements of variance `expect`; its standard error is
        // expect * sqrt(2 / 2n).
        let m = 2 * n;
        let msd = sum2 / m as f64;
        let se = expect * (2.0 / m as f64).sqrt();
        assert!(
            (msd - expect).abs() < 5.0 * se,
            "{schedule}: mean square displacement {msd}, expected {expect} +- {se}"
        );
    }
}

/// A `bins x bins` field of crests along x: `1 + 0.5 cos(2 pi iy / lambda + tilt ix)`.
fn sinusoid(bins: usize, lambda: f64, tilt: f64) -> Vec<f64> {
    let mut h = vec![0.0; bins * bins];
    for ix in 0..bins {
        for iy in 0..bins {
            let phase = tilt * ix as f64;
            h[ix * bins + iy] =
                1.0 + 0.5 * (std::f64::consts::TAU * iy as f64 / lambda + phase).cos();
        }
    }
    h
}

#[test]
fn wavelength_estimators_recover_synthetic_sinusoids() {
    // Integer wavenumber: exact, for both estimators, straight or wavy crests.
    for (bins, lambda) in [(256, 8.0), (256, 32.0), (64, 4.0), (128, 2.0)] {
        for tilt in [0.0, 0.3] {
            let h = sinusoid(bins, lambda, tilt);
            let w = wavelength_bins(&h, bins).unwrap();
            let m = mean_wavelength_bins(&h, bins).unwrap();
            assert!((w - lambda).abs() < 1e-9 * lambda, "peak {w} vs {lambda}");
            assert!((m - lambda).abs() < 1e-9 * lambda, "mean {m} vs {lambda}");
        }
    }
    // Non-integer wavenumber: the peak within 1.5 %, the mean (leakage) within 6 %.
    for lambda in [5.5, 10.0, 12.3] {
        let h = sinusoid(256, lambda, 0.0);
        let w = wavelength_bins(&h, 256).unwrap();
        let m = mean_wavelength_bins(&h, 256).unwrap();
        assert!((w / lambda - 1.0).abs() < 0.015, "peak {w} vs {lambda}");
        assert!((m / lambda - 1.0).abs() < 0.06, "mean {m} vs {lambda}");
    }
    // With noise on top the peak still stands out.
    let mut h = sinusoid(128, 8.0, 0.0);
    let mut state = 12345u64;
    for v in h.iter_mut() {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        *v += 0.3 * ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
    }
    let w = wavelength_bins(&h, 128).unwrap();
    assert!((w - 8.0).abs() < 0.1, "{w}");
    // No variation along y (stripes along the wind): no wavelength; the spectrum is zero.
    let mut h = vec![0.0; 64 * 64];
    for ix in 0..64 {
        for iy in 0..64 {
            h[ix * 64 + iy] = 1.0 + (ix as f64).sin();
        }
    }
    assert!(power_spectrum_y(&h, 64).iter().skip(1).all(|&p| p < 1e-20));
    assert_eq!(height_stats(&h, 64).wavelength_bins, None);
}

#[test]
fn invalid_parameters_are_rejected_with_the_parameter_named() {
    let e = WindRipples::new(WindParams {
        kappa: -4.5,
        ..WindParams::default()
    })
    .unwrap_err();
    assert_eq!(
        e,
        WindError::OutOfRange {
            name: "kappa",
            value: "-4.5".into(),
            range: "a finite number >= 0",
        }
    );
    assert_eq!(
        e.to_string(),
        "kappa = -4.5 is out of range: expected a finite number >= 0"
    );
    let e = windripples::run(
        &WindParams {
            bins: 5000,
            ..WindParams::default()
        },
        |_| {},
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("bins = 5000 is out of range"));
}

#[cfg(feature = "cli")]
mod cli {
    use std::path::PathBuf;

    use super::common::cellsurf;

    fn tmp(name: &str) -> PathBuf {
        super::common::tmp_in("wr", name)
    }

    const SMALL: [&str; 6] = ["--steps", "5", "--particles", "5000", "--bins", "32"];

    /// The parameters a PNG records are the run's scenario: fed back, the same picture.
    #[test]
    fn the_pngs_parameters_reproduce_the_run() {
        let mut args = SMALL.to_vec();
        args.extend(["--kappa", "2", "--seed", "9"]);
        let (a, b) =
            super::common::png_scenario_round_trip(&tmp("png-scenario"), "wind-ripples", &args);
        assert!(a == b, "the PNGs differ");
    }

    /// A scenario file's value is read as the option reads it: `hop = "1/64"` as `--hop 1/64`;
    /// a string that is not a number is refused, naming the key.
    #[test]
    fn a_scenarios_fraction_is_read_as_the_option_reads_it() {
        let run = |text: &str| {
            let p = tmp("fraction.toml");
            std::fs::write(&p, text).unwrap();
            cellsurf(&[
                "wind-ripples",
                "--scenario",
                p.to_str().unwrap(),
                "--json",
                "--quiet",
            ])
        };
        let out =
            run("model = \"wind-ripples\"\nhop = \"1/64\"\nsteps = 2\nsize = 16\nparticles = 10\n");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["parameters"]["hop"], 0.015625);
        let out = run("model = \"wind-ripples\"\nhop = \"x/64\"\n");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(err.contains("hop = \"x/64\" is not a valid value"), "{err}");
    }

    #[test]
    fn json_has_the_promised_keys() {
        let mut args = SMALL.to_vec();
        args.push("--json");
        let out = cellsurf(&[&["wind-ripples"], &args[..]].concat());
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        for k in [
            "steps",
            "particles",
            "elapsed_s",
            "height_mean",
            "height_std",
            "wavelength_bins",
            "mean_wavelength_bins",
            "version",
            "parameters",
        ] {
            assert!(v.get(k).is_some(), "missing {k}: {v}");
        }
        assert_eq!(v["steps"], 5);
        assert_eq!(v["particles"], 5000);
        assert!((v["height_mean"].as_f64().unwrap() - 1.0).abs() < 1e-12);
        assert_eq!(v["parameters"]["schedule"], "annealed");
        assert!(out.stderr.is_empty(), "no progress bar with --json");
    }

    #[test]
    fn npy_is_reproducible_across_thread_counts_and_has_a_sidecar() {
        let (a, b) = (tmp("a.npy"), tmp("b.npy"));
        for (p, t) in [(&a, "1"), (&b, "2")] {
            let mut args = vec!["wind-ripples", "--quiet", "--threads", t, "--npy"];
            args.push(p.to_str().unwrap());
            args.extend(SMALL);
            let out = cellsurf(&args);
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        let bytes = std::fs::read(&a).unwrap();
        assert_eq!(bytes, std::fs::read(&b).unwrap());
        assert_eq!(&bytes[..6], b"\x93NUMPY");
        let hl = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!(bytes.len(), 10 + hl + 8 * 32 * 32);
        let side: serde_json::Value =
            serde_json::from_slice(&std::fs::read(tmp("a.json")).unwrap()).unwrap();
        assert_eq!(side["parameters"]["size"], "32x32");
        assert_eq!(side["run"]["bins"], 32);
        assert!(side["version"].is_string());
        // shapes, dims and units, as every .npy sidecar has them
        let h = &side["fields"]["height"];
        assert_eq!(h["file"], "a.npy");
        assert_eq!(h["shape"], serde_json::json!([32, 32]));
        assert_eq!(h["dims"], serde_json::json!(["x", "y"]));
        assert!(h["units"].is_string());
        // the same record whatever the thread count: no timings, no thread count (the file
        // names, in `outputs` and `fields`, are the only difference)
        let mut other: serde_json::Value =
            serde_json::from_slice(&std::fs::read(tmp("b.json")).unwrap()).unwrap();
        for k in ["elapsed_s", "setup_s", "particle_steps_per_s", "threads"] {
            assert!(side.get(k).is_none(), "{k} recorded");
        }
        let mut side = side;
        for v in [&mut side, &mut other] {
            let o = v.as_object_mut().unwrap();
            o.remove("outputs");
            o.remove("fields");
        }
        assert_eq!(side, other);
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        for (args, needle) in [
            (vec!["--kappa", "-1"], "--kappa = -1"),
            (vec!["--bins", "0"], "'0' for '--size"),
            (vec!["--particles", "0"], "--particles = 0"),
            (vec!["--steps", "0"], "--steps = 0"),
            (vec!["--hop", "nan"], "--hop = NaN"),
            (vec!["--diffusion", "inf"], "--diffusion = inf"),
            (vec!["--hop", "abc"], "not a number"),
            (vec!["--schedule", "numpy"], "unknown schedule"),
            (vec!["--npy", "/nonexistent-dir/x.npy"], "does not exist"),
        ] {
            let mut all = vec!["wind-ripples"];
            for pair in SMALL.chunks(2) {
                if !args.contains(&pair[0]) {
                    all.extend(pair);
                }
            }
            all.extend(args.iter().copied());
            let out = cellsurf(&all);
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(!out.status.success(), "{args:?} succeeded");
            assert!(err.contains(needle), "{args:?}: {err}");
            assert!(!err.contains("panicked"), "{args:?}: {err}");
        }
    }
}
