//! The sand-ripple volume generator: invariants after every step, the ripple field's
//! shape, grain sorting, stiff and extreme cases, invalid parameters, and the output files.
//! Small grids and few steps keep the suite fast; long runs are `#[ignore]`d.

mod common;

use cellsurf::ripple::morphometry::extrema;
use cellsurf::ripple::output::{run_recording, write_netcdf, write_npy};
use cellsurf::ripple::{
    Abstraction, Analysis, Field, Format, Frame, Mode, OutputSpec, Ripple, RippleError,
    RippleParams,
};

fn small() -> RippleParams {
    RippleParams {
        nx: 32,
        ny: 16,
        layers: 12,
        steps: 150,
        activity: 0.01,
        ..RippleParams::default()
    }
}

/// Runs `p.steps` steps, checking after every step that automata and per-class counts (so
/// per-class mass) are conserved and that no slope exceeds alpha.
fn checked_run(p: &RippleParams) -> Ripple {
    let mut r = Ripple::new(p).unwrap();
    let classes = r.classes().len();
    let counts0 = r.initial_class_counts().to_vec();
    let mass0 = r.class_masses();
    assert_eq!(r.steep_pair(), None, "initial bed relaxed");
    for _ in 0..p.steps {
        r.step();
        assert_eq!(
            r.mass_change(),
            0,
            "automata created or destroyed at step {}",
            r.time()
        );
        assert_eq!(
            r.volume().class_counts(classes),
            counts0,
            "class counts at step {}",
            r.time()
        );
        assert_eq!(
            r.steep_pair(),
            None,
            "a slope exceeds alpha after step {}",
            r.time()
        );
    }
    assert_eq!(r.class_masses(), mass0);
    r
}

#[test]
fn conservation_and_no_slope_above_alpha_after_every_step_3d_slices() {
    checked_run(&small());
}

#[test]
fn conservation_and_no_slope_above_alpha_after_every_step_3d_shadow() {
    checked_run(&RippleParams {
        abstraction: Abstraction::Shadow,
        sorting: 1.0,
        ..small()
    });
}

#[test]
fn conservation_and_no_slope_above_alpha_after_every_step_2d() {
    let r = checked_run(&RippleParams {
        mode: Mode::TwoD,
        nx: 64,
        ny: 1,
        ..small()
    });
    assert!(r.stats().rolls > 0);
}

#[test]
fn conservation_under_waves_and_oblique_current() {
    checked_run(&RippleParams {
        current_angle: 33.0,
        wave_period: 20.0,
        wave_amplitude: 0.4,
        current_speed: 0.2,
        ..small()
    });
}

#[test]
fn conservation_and_no_slope_above_alpha_with_the_wave_vortex() {
    // pure waves with the lee vortex (shelter capped at the water's travel, grains carried
    // back to the crest), in 3-D and in 2-D
    let waves = |p: RippleParams| RippleParams {
        current_speed: 0.0,
        wave_period: 24.0,
        wave_amplitude: 0.5,
        wave_vortex: 0.05,
        steps: 300,
        ..p
    };
    let r = checked_run(&waves(small()));
    assert!(r.stats().rolls > 0);
    checked_run(&waves(RippleParams {
        mode: Mode::TwoD,
        nx: 64,
        ny: 1,
        sorting: 1.0,
        ..small()
    }));
}

#[test]
fn periodic_volume_tiles_without_seams() {
    // The torus has no edge: the differences across the seam (x = nx-1 -> 0, y = ny-1 -> 0)
    // are like those inside, and the bed is relaxed across it.
    let p = RippleParams {
        nx: 48,
        ny: 24,
        layers: 16,
        steps: 400,
        activity: 0.005,
        abstraction: Abstraction::Shadow,
        ..RippleParams::default()
    };
    let mut r = Ripple::new(&p).unwrap();
    r.run(p.steps, |_| {});
    assert_eq!(r.steep_pair(), None);
    let h = r.volume().heights();
    let (nx, ny) = (p.nx, p.ny);
    let mut inner = 0.0;
    let mut seam = 0.0;
    for y in 0..ny {
        for x in 0..nx {
            let d = (h[y * nx + x] as f64 - h[y * nx + (x + 1) % nx] as f64).abs();
            if x == nx - 1 {
                seam += d;
            } else {
                inner += d;
            }
        }
    }
    let inner = inner / ((nx - 1) * ny) as f64;
    let seam = seam / ny as f64;
    assert!(seam < 3.0 * inner + 1.0, "seam {seam} inner {inner}");
}

/// A 64 x 64 run long enough for mature ripples: 1700 steps at 0.6 % activity (as many
/// activations per automaton as the defaults' 10,000 steps at 0.1 %).
fn ripple_run(angle: f64, seed: u64, f: impl FnOnce(&mut RippleParams)) -> Analysis {
    let mut p = RippleParams {
        nx: 64,
        ny: 64,
        layers: 16,
        steps: 1700,
        activity: 0.006,
        current_angle: angle,
        seed,
        ..RippleParams::default()
    };
    f(&mut p);
    let mut r = Ripple::new(&p).unwrap();
    r.run(p.steps, |_| {});
    assert_eq!(r.mass_change(), 0);
    Analysis::of(&r)
}

/// The statistics of [`ripple_run`] averaged over seeds 1, 2 and 3 (`crest_normal_deg` and
/// `faces` from seed 1).
fn mean_of_seeds(angle: f64, f: impl Fn(&mut RippleParams)) -> Analysis {
    let runs: Vec<Analysis> = (1..=3).map(|s| ripple_run(angle, s, &f)).collect();
    let m = |g: fn(&Analysis) -> f64| runs.iter().map(g).sum::<f64>() / runs.len() as f64;
    Analysis {
        wavelength_m: m(|a| a.wavelength_m),
        height_m: m(|a| a.height_m),
        ripple_index: m(|a| a.ripple_index),
        lee_slope_deg: m(|a| a.lee_slope_deg),
        stoss_slope_deg: m(|a| a.stoss_slope_deg),
        symmetry_index: m(|a| a.symmetry_index),
        d50_crest_mm: m(|a| a.d50_crest_mm),
        d50_trough_mm: m(|a| a.d50_trough_mm),
        ..runs[0]
    }
}

fn angle_diff_mod_180(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(180.0);
    d.min(180.0 - d)
}

/// Soulsby (1997), Dynamics of marine sands, Sect. 7.2: current ripples have a steep lee at
/// the angle of repose (about 28 deg in water, avalanches at alpha = 32 deg) and a longer,
/// gentler stoss; the paper's beta is "the maximum slope of the stoss side". On this small grid
/// (64 x 64 bins, 1700 steps) the ripples are young and low (about 0.5 cm): their stoss keeps
/// below beta + 2 deg, their lee is about three times steeper (17-20 deg; 23 deg at the
/// defaults, 28 deg once 1.3 cm high) and their ripple index is about 25-30, above the 8-20
/// of nature (a known shortfall, docs/ripple.md).
#[test]
fn steady_current_makes_asymmetric_ripples_with_a_steep_lee_and_a_stoss_below_beta() {
    let initial = {
        let r = Ripple::new(&RippleParams {
            nx: 64,
            ny: 64,
            layers: 16,
            ..RippleParams::default()
        })
        .unwrap();
        Analysis::of(&r)
    };
    let beta = RippleParams::default().stoss_angle;
    for abstraction in [Abstraction::Slices, Abstraction::Shadow] {
        // one seed's field can lock into an oblique mode of the small torus: the mean of three
        let a = mean_of_seeds(0.0, |p| p.abstraction = abstraction);
        eprintln!("{abstraction}: {a:?}\n  initial {initial:?}");
        assert!(
            a.stoss_slope_deg <= beta + 2.0,
            "{abstraction}: stoss {} above beta + 2 = {}",
            a.stoss_slope_deg,
            beta + 2.0
        );
        assert!(
            a.lee_slope_deg > 2.5 * a.stoss_slope_deg && a.lee_slope_deg <= 32.0,
            "{abstraction}: lee {} stoss {}",
            a.lee_slope_deg,
            a.stoss_slope_deg
        );
        assert!(
            a.symmetry_index > 1.5,
            "{abstraction}: stoss not longer than lee: {a:?}"
        );
        assert!(
            (8.0..=40.0).contains(&a.ripple_index),
            "{abstraction}: ripple index {} outside 8-40",
            a.ripple_index
        );
        assert!(
            a.height_m > 2.0 * initial.height_m,
            "{abstraction}: grew {a:?}"
        );
        assert!(
            a.wavelength_m > 3.0 * initial.wavelength_m,
            "{abstraction}: a wavelength emerged {a:?} from {initial:?}"
        );
    }
}

#[test]
fn crest_normal_follows_the_current_for_two_angles() {
    // A field on the 64 x 64 torus can lock into its 63.4 deg mode (wave vector (1, 2)):
    // the median crest normal of three seeds follows the current.
    for angle in [0.0, 90.0] {
        let runs: Vec<Analysis> = (1..=3).map(|s| ripple_run(angle, s, |_| {})).collect();
        let mut d: Vec<f64> = runs
            .iter()
            .map(|a| angle_diff_mod_180(a.crest_normal_deg, angle))
            .collect();
        d.sort_by(f64::total_cmp);
        eprintln!("current {angle}: crest normal off by {d:?}");
        assert!(d[1] < 20.0, "current {angle}: crest normals off by {d:?}");
        let sym = runs.iter().map(|a| a.symmetry_index).sum::<f64>() / 3.0;
        assert!(sym > 1.2, "current {angle}: symmetry index {sym}");
    }
}

#[test]
fn pure_wave_gives_symmetric_ripples() {
    let mut sym = Vec::new();
    let mut slope_asym = 0.0;
    for seed in 1..=3 {
        let a = ripple_run(0.0, seed, |p| {
            p.current_speed = 0.0;
            p.wave_amplitude = 0.5;
            p.wave_period = 20.0;
        });
        eprintln!("wave seed {seed}: {a:?}");
        assert!(a.faces > 50, "wave ripples formed: {a:?}");
        sym.push(a.symmetry_index);
        slope_asym += (a.lee_slope_deg - a.stoss_slope_deg).abs()
            / (a.lee_slope_deg + a.stoss_slope_deg)
            / 3.0;
    }
    // the two faces' slopes differ by under 10 % of their sum (a current's: 30 % and more)
    assert!(
        slope_asym < 0.1,
        "wave: lee and stoss differ by {slope_asym}"
    );
    let c = mean_of_seeds(0.0, |_| {});
    eprintln!("wave symmetry index {sym:?}; current {c:?}");
    for s in &sym {
        assert!((s - 1.0).abs() < 0.15, "wave symmetry index {sym:?}");
        assert!(
            (s - 1.0).abs() < 0.5 * (c.symmetry_index - 1.0),
            "wave {sym:?} vs current {c:?}"
        );
    }
}

/// Paper Figs. 7-8: the fines end up in the crests, the coarse grains in the troughs, at a
/// sorting of 1 phi. (At the defaults' 0.5 phi the contrast on this small grid is within the
/// seed noise since the stoss cap keeps the young ripples low: crest 0.210, trough 0.207 mm;
/// at the defaults' scale, 128 x 64 and 10,000 steps, 0.208 against 0.213 mm.)
#[test]
fn finer_grains_at_crests_than_in_troughs() {
    for sorting in [1.0, 1.5] {
        let (mut crest, mut trough) = (0.0, 0.0);
        for seed in 1..=3 {
            let a = ripple_run(0.0, seed, |p| p.sorting = sorting);
            crest += a.d50_crest_mm / 3.0;
            trough += a.d50_trough_mm / 3.0;
        }
        eprintln!("sorting {sorting}: d50 crest {crest} trough {trough} (mean of 3 seeds)");
        assert!(
            crest < trough,
            "sorting {sorting}: crest {crest} trough {trough}"
        );
    }
}

fn extreme(f: impl FnOnce(&mut RippleParams)) -> Ripple {
    let mut p = RippleParams {
        nx: 16,
        ny: 12,
        layers: 8,
        steps: 60,
        activity: 0.02,
        ..RippleParams::default()
    };
    f(&mut p);
    checked_run(&p)
}

#[test]
fn stiff_alpha_near_90_and_near_beta() {
    extreme(|p| p.avalanche_angle = 89.9);
    extreme(|p| {
        p.avalanche_angle = 7.01;
        p.stoss_angle = 7.0;
    });
    // (an automaton thin enough for the lattice to hold 0.5 deg: 0.04 mm over 5 mm is 0.46 deg)
    extreme(|p| {
        p.avalanche_angle = 0.5;
        p.stoss_angle = 0.5;
        p.layer_thickness = 4e-5;
    });
}

#[test]
fn stiff_beta_zero_and_gamma_zero() {
    extreme(|p| p.stoss_angle = 0.0);
    extreme(|p| p.creep_angle = 0.0);
    extreme(|p| p.creep_angle = 89.0);
}

#[test]
fn zero_current_moves_nothing() {
    let p = RippleParams {
        nx: 16,
        ny: 12,
        layers: 8,
        current_speed: 0.0,
        ..RippleParams::default()
    };
    let mut r = Ripple::new(&p).unwrap();
    let h0 = r.volume().heights().to_vec();
    r.run(50, |_| {});
    assert_eq!(r.volume().heights(), &h0[..]);
    assert_eq!(r.stats().activations, 0);
}

#[test]
fn current_below_the_threshold_of_motion_picks_nothing() {
    // d50 0.2 mm, one size: tau_cr = 0.176 N/m^2 (Soulsby Example 6.3), so with C_D = 0.0025
    // the threshold speed is sqrt(0.176 / (1027 x 0.0025)) = 0.262 m/s.
    let run = |speed: f64| {
        let mut r = Ripple::new(&RippleParams {
            nx: 16,
            ny: 12,
            layers: 8,
            sorting: 0.0,
            current_speed: speed,
            ..RippleParams::default()
        })
        .unwrap();
        r.run(20, |_| {});
        r.stats()
    };
    let below = run(0.25);
    assert_eq!((below.picks, below.activations), (0, 0));
    let above = run(0.28);
    assert!(above.activations > 0, "{above:?}");
}

#[test]
fn current_strong_enough_to_expose_every_grain() {
    let r = extreme(|p| {
        p.current_speed = 10.0;
        p.abstraction = Abstraction::Shadow;
    });
    assert!(r.stats().activations > 0);
    // Every pick of a non-shadowed, non-held column is an activation: most picks are.
    let s = r.stats();
    assert!(s.activations * 3 > s.picks, "{s:?}");
}

#[test]
fn one_grain_size_and_very_wide_sorting() {
    let r = extreme(|p| p.sorting = 0.0);
    assert_eq!(r.classes().len(), 1);
    let r = extreme(|p| p.sorting = 2.0);
    assert!(r.classes().len() > 120);
}

#[test]
fn one_layer_volume_and_bare_spots() {
    extreme(|p| {
        p.layers = 1;
        p.roughness = 1;
    });
    // Columns emptied to the substrate: the substrate never erodes, nothing is lost.
    let p = RippleParams {
        nx: 16,
        ny: 12,
        layers: 6,
        activity: 0.05,
        current_speed: 2.0,
        ..RippleParams::default()
    };
    let mut h = vec![6usize; 16 * 12];
    for c in (0..h.len()).step_by(3) {
        h[c] = 0;
    }
    let mut r = Ripple::from_heights(&p, &h).unwrap();
    let n0 = r.automata();
    for _ in 0..100 {
        r.step();
        assert_eq!(r.volume().automata(), n0);
        assert_eq!(r.steep_pair(), None);
    }
}

#[test]
fn smallest_legal_grids() {
    extreme(|p| {
        p.nx = 3;
        p.ny = 3;
    });
    extreme(|p| {
        p.mode = Mode::TwoD;
        p.nx = 3;
        p.ny = 1;
    });
}

#[test]
fn invalid_parameters_name_the_parameter() {
    let cases: Vec<(&str, RippleParams)> = vec![
        ("nx", RippleParams { nx: 2, ..small() }),
        ("ny", RippleParams { ny: 0, ..small() }),
        (
            "layers",
            RippleParams {
                layers: 0,
                ..small()
            },
        ),
        (
            "bin_size",
            RippleParams {
                bin_size: -1.0,
                ..small()
            },
        ),
        (
            "layer_thickness",
            RippleParams {
                layer_thickness: 0.01,
                ..small()
            },
        ),
        (
            "d50",
            RippleParams {
                d50: f64::NAN,
                ..small()
            },
        ),
        (
            "sorting",
            RippleParams {
                sorting: -0.1,
                ..small()
            },
        ),
        (
            "avalanche_angle",
            RippleParams {
                avalanche_angle: 90.0,
                ..small()
            },
        ),
        (
            "stoss_angle",
            RippleParams {
                stoss_angle: 40.0,
                ..small()
            },
        ),
        (
            "creep_angle",
            RippleParams {
                creep_angle: -1.0,
                ..small()
            },
        ),
        (
            "activity",
            RippleParams {
                activity: 0.0,
                ..small()
            },
        ),
        (
            "current_speed",
            RippleParams {
                current_speed: -1.0,
                ..small()
            },
        ),
        (
            "wave_period",
            RippleParams {
                wave_period: 1.0,
                ..small()
            },
        ),
    ];
    for (name, p) in cases {
        match Ripple::new(&p) {
            Err(RippleError::Range { parameter, .. }) => assert_eq!(parameter, name),
            other => panic!(
                "{name}: expected a range error, got {:?}",
                other.map(|_| ())
            ),
        }
        let msg = p.validate().unwrap_err().to_string();
        assert!(msg.contains(name), "{msg}");
    }
}

#[test]
fn scene_files_reject_unknown_keys_and_take_defaults() {
    let dir = env!("CARGO_MANIFEST_DIR");
    let good = std::fs::read_to_string(format!("{dir}/tests/fixtures/ripple_small.toml")).unwrap();
    let p = RippleParams::from_toml(&good).unwrap();
    assert_eq!(p.nx, 24);
    assert_eq!(p.avalanche_angle, 32.0);
    let bad = std::fs::read_to_string(format!("{dir}/tests/fixtures/ripple_bad_key.toml")).unwrap();
    let e = RippleParams::from_toml(&bad).unwrap_err().to_string();
    assert!(e.contains("currnt_speed"), "{e}");
    let bad =
        std::fs::read_to_string(format!("{dir}/tests/fixtures/ripple_bad_alpha.toml")).unwrap();
    let e = RippleParams::from_toml(&bad).unwrap_err().to_string();
    assert!(e.contains("avalanche_angle"), "{e}");
    let bad = std::fs::read_to_string(format!(
        "{dir}/tests/fixtures/ripple_bad_crest_suspension.toml"
    ))
    .unwrap();
    let e = RippleParams::from_toml(&bad).unwrap_err().to_string();
    assert!(
        e.starts_with("crest_suspension = 1.5 is out of range") && e.contains("[0, 1]"),
        "{e}"
    );
    for (file, start, range) in [
        (
            "ripple_bad_stress_lead.toml",
            "stress_lead = -2 is out of range",
            "[0, 100]",
        ),
        (
            "ripple_bad_crest_suspension_both.toml",
            "crest_suspension_grains = 50 is out of range",
            "not both",
        ),
        (
            "ripple_bad_separation_angle.toml",
            "separation_angle = 45 is out of range",
            "[0, 32]",
        ),
    ] {
        let bad = std::fs::read_to_string(format!("{dir}/tests/fixtures/{file}")).unwrap();
        let e = RippleParams::from_toml(&bad).unwrap_err().to_string();
        assert!(e.starts_with(start) && e.contains(range), "{file}: {e}");
    }
    let fig3 =
        std::fs::read_to_string(format!("{dir}/scenarios/ripple_fig3_evolution.toml")).unwrap();
    RippleParams::from_toml(&fig3).unwrap();
}

#[test]
fn same_seed_same_volume() {
    let run = || {
        let mut r = Ripple::new(&small()).unwrap();
        r.run(50, |_| {});
        r.volume().heights().to_vec()
    };
    assert_eq!(run(), run());
}

fn tmp(name: &str) -> std::path::PathBuf {
    common::tmp_in("ripple", name)
}

#[test]
fn netcdf_output_has_the_cdf_magic_and_opens_if_a_reader_is_installed() {
    let p = RippleParams {
        steps: 20,
        ..small()
    };
    let mut r = Ripple::new(&p).unwrap();
    let snaps = run_recording(&mut r, 20, &[0, 10, 20], |_| {});
    assert_eq!(snaps.len(), 3);
    let spec = OutputSpec {
        fields: Field::ALL.to_vec(),
        format: Format::NetCdf,
    };
    let path = tmp("vol.nc");
    write_netcdf(&path, &r, &snaps, &spec).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(&bytes[..4], b"CDF\x02", "NetCDF-3 64-bit offset magic");
    assert!(!cellsurf::engine::io::temp_path(&path).exists());
    // Open it with scipy or netCDF4 when one of them happens to be importable.
    let script = format!(
        "import sys\ntry:\n    import netCDF4\n    d = netCDF4.Dataset({0:?})\n    e = d.variables['elevation'][:]\nexcept ImportError:\n    try:\n        from scipy.io import netcdf_file\n        d = netcdf_file({0:?}, mmap=False)\n        e = d.variables['elevation'][:]\n    except ImportError:\n        sys.exit(3)\nassert e.shape == (3, 16, 32), e.shape\nprint('ok')\n",
        path.display().to_string()
    );
    match std::process::Command::new("python3")
        .args(["-c", &script])
        .output()
    {
        Ok(o) if o.status.code() == Some(3) => eprintln!("skipped: no netCDF4 or scipy"),
        Ok(o) => assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr)),
        Err(_) => eprintln!("skipped: no python3"),
    }
}

#[test]
fn netcdf_snapshot_steps_past_2_24_are_kept_exactly() {
    // A float holds whole numbers exactly only up to 2^24: steps 2^24 and 2^24 + 1 must stay
    // two steps in the file (the time coordinate is a double) and read back as written.
    let p = RippleParams {
        steps: 2,
        ..small()
    };
    let mut r = Ripple::new(&p).unwrap();
    let snaps = run_recording(&mut r, 2, &[0, 2], |_| {});
    let big: Vec<(u64, Vec<f32>)> = [16_777_216u64, 16_777_217, (1 << 40) - 1]
        .iter()
        .map(|&t| (t, snaps[1].1.clone()))
        .collect();
    let spec = OutputSpec {
        fields: vec![Field::Elevation],
        format: Format::NetCdf,
    };
    let path = tmp("big_steps.nc");
    write_netcdf(&path, &r, &big, &spec).unwrap();
    let f = cellsurf::ripple::input::read(&path).unwrap();
    assert_eq!(f.times, vec![16_777_216, 16_777_217, (1 << 40) - 1]);
}

#[test]
fn netcdf_round_trip_gives_back_what_the_run_computed() {
    let p = RippleParams {
        steps: 12,
        seed: 17,
        ..small()
    };
    let mut r = Ripple::new(&p).unwrap();
    let snaps = run_recording(&mut r, 12, &[0, 12], |_| {});
    let spec = OutputSpec {
        fields: Field::ALL.to_vec(),
        format: Format::NetCdf,
    };
    let path = tmp("roundtrip.nc");
    write_netcdf(&path, &r, &snaps, &spec).unwrap();
    let f = cellsurf::ripple::input::read(&path).unwrap();
    assert_eq!((f.nx, f.ny), r.size());
    assert_eq!(f.nz, cellsurf::ripple::output::volume_levels(&r));
    assert_eq!(f.times, vec![0, 12]);
    assert_eq!(f.params, p, "every parameter survives the file");
    assert_eq!(f.version, cellsurf::ripple::VERSION);
    assert_eq!(f.elevation[1], snaps[1].1);
    assert_ne!(f.elevation[0], f.elevation[1], "the snapshots differ");
    for field in &Field::ALL[1..] {
        let want = cellsurf::ripple::output::volume_field(&r, *field, f32::NAN);
        let got = f.field(*field).unwrap();
        assert_eq!(got.len(), want.len());
        for (a, b) in got.iter().zip(&want) {
            assert!(
                a == b || (a.is_nan() && b.is_nan()),
                "{field:?}: {a} != {b}"
            );
        }
    }
    // Only what was asked for is in the file.
    let spec = OutputSpec {
        fields: vec![Field::Porosity],
        format: Format::NetCdf,
    };
    write_netcdf(&path, &r, &snaps, &spec).unwrap();
    let f = cellsurf::ripple::input::read(&path).unwrap();
    assert!(f.elevation.is_empty());
    assert_eq!(f.fields.len(), 1);
    assert!(f.field(Field::Porosity).is_some());
}

#[test]
fn netcdf_round_trip_keeps_every_opt_in_key() {
    // The keys left out of files at their defaults are written when set and must be read
    // back: every one of them away from its default at once (crest suspension's two lengths,
    // which exclude each other, in two files).
    let grains = RippleParams {
        crest_suspension: 0.0,
        crest_suspension_grains: 50.0,
        suspension_exponent: 8.0,
        ..every_opt_in_key()
    };
    // and an oblique 2-D section in the flow frame (its x axis at 330 deg for a current at
    // 150 deg) is read back in the flow frame
    let section = RippleParams {
        mode: Mode::TwoD,
        nx: 32,
        ny: 1,
        layers: 6,
        steps: 4,
        current_angle: 150.0,
        ..RippleParams::default()
    };
    assert_eq!(section.x_axis_direction_deg(), 330.0);
    for (p, name) in [
        (every_opt_in_key(), "roundtrip_opt_in.nc"),
        (grains, "roundtrip_opt_in_grains.nc"),
        (section, "roundtrip_oblique_section.nc"),
    ] {
        let mut r = Ripple::new(&p).unwrap();
        let snaps = run_recording(&mut r, 4, &[4], |_| {});
        let spec = OutputSpec {
            fields: vec![Field::Elevation],
            format: Format::NetCdf,
        };
        let path = tmp(name);
        write_netcdf(&path, &r, &snaps, &spec).unwrap();
        let f = cellsurf::ripple::input::read(&path).unwrap();
        assert_eq!(f.params, p, "every opt-in key survives the file");
    }
}

/// Parameters with every key that files leave out at its default set to something else.
fn every_opt_in_key() -> RippleParams {
    RippleParams {
        steps: 4,
        until: Some("equilibrium".into()),
        wave_period: 200.0,
        wave_amplitude: 0.2,
        wave_friction_factor: 0.01,
        wave_angle: Some(30.0),
        wave_vortex: 0.05,
        vortex_strength: 0.8,
        frame: cellsurf::ripple::Frame::Grid,
        hop_grains: 37.5,
        hop_exponential: true,
        crest_suspension: 0.02,
        stress_lead: 2.0,
        separation_angle: 15.0,
        ..small()
    }
}

#[test]
fn reading_a_file_that_is_not_a_ripple_volume_names_the_file() {
    let path = tmp("not.nc");
    std::fs::write(&path, b"CDF\x02 but nothing else").unwrap();
    let e = cellsurf::ripple::input::read(&path)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not.nc"), "{e}");
    let e = cellsurf::ripple::input::read(&tmp("missing.nc"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.nc"), "{e}");
}

#[test]
fn npy_output_one_file_per_field_and_a_sidecar() {
    let mut r = Ripple::new(&small()).unwrap();
    let snaps = run_recording(&mut r, 5, &[5], |_| {});
    let spec = OutputSpec {
        fields: vec![Field::Elevation, Field::Impedance],
        format: Format::Npy,
    };
    let files = write_npy(&tmp("vol.npy"), &r, &snaps, &spec).unwrap();
    assert_eq!(files.len(), 3);
    let e = std::fs::read(&files[0]).unwrap();
    assert_eq!(&e[..6], b"\x93NUMPY");
    let hl = u16::from_le_bytes([e[8], e[9]]) as usize;
    assert_eq!(e.len(), 10 + hl + 4 * 16 * 32);
    let side = std::fs::read_to_string(&files[2]).unwrap();
    assert!(side.contains("\"cellsurf_version\"") && side.contains("\"avalanche_angle\": 32"));
}

#[test]
fn apl_uw_preset_cannot_be_mixed_with_porosity() {
    let spec = OutputSpec {
        fields: vec![Field::Porosity],
        format: Format::NetCdf,
    };
    let e = spec
        .validate(cellsurf::ripple::AcousticModel::AplUw)
        .unwrap_err()
        .to_string();
    assert!(e.contains("fields") && e.contains("apl-uw"), "{e}");
}

#[test]
fn memory_under_16_bytes_per_automaton() {
    let r = Ripple::new(&RippleParams {
        nx: 64,
        ny: 64,
        layers: 20,
        ..RippleParams::default()
    })
    .unwrap();
    assert!(
        r.bytes_per_automaton() < 16.0,
        "{}",
        r.bytes_per_automaton()
    );
}

#[test]
#[ignore = "long: the default (Fig. 3) run, about 6-10 s in release"]
fn default_run_against_soulsby() {
    let p = RippleParams::default();
    let mut r = Ripple::new(&p).unwrap();
    r.run(p.steps, |_| {});
    let a = Analysis::of(&r);
    let (l, h) = cellsurf::ripple::predictors::soulsby_whitehouse(p.d50 * 1e-3);
    eprintln!("{a:?}\nSoulsby & Whitehouse: wavelength {l} m, height {h} m");
    assert!((25.0..=32.0).contains(&a.lee_slope_deg), "{a:?}");
    assert!(a.lee_slope_deg > 1.3 * a.stoss_slope_deg, "{a:?}");
    assert!((8.0..=20.0).contains(&a.ripple_index), "{a:?}");
    assert!(a.d50_crest_mm < a.d50_trough_mm, "{a:?}");
    // within a factor of 2 of the predictors
    assert!(
        a.wavelength_m > 0.5 * l && a.wavelength_m < 2.0 * l,
        "{a:?}"
    );
    assert!(a.height_m > 0.5 * h && a.height_m < 2.0 * h, "{a:?}");
    assert_eq!(r.mass_change(), 0);
}

#[test]
fn seed_beyond_2_pow_53_is_refused_and_a_2d_section_runs_either_way() {
    let e = Ripple::new(&RippleParams {
        seed: (1 << 53) + 1,
        ..small()
    })
    .err()
    .unwrap()
    .to_string();
    assert!(
        e.starts_with("seed = 9007199254740993 is out of range"),
        "{e}"
    );
    let two_d = |angle: f64| RippleParams {
        mode: Mode::TwoD,
        nx: 64,
        ny: 1,
        layers: 10,
        current_angle: angle,
        ..RippleParams::default()
    };
    // in the grid frame a section runs only along its x axis
    let e = Ripple::new(&RippleParams {
        frame: cellsurf::ripple::Frame::Grid,
        ..two_d(90.0)
    })
    .err()
    .unwrap()
    .to_string();
    assert!(e.starts_with("current_angle = 90 is out of range"), "{e}");
    // 180 deg: the grains roll towards -x; in the flow frame (the default) a section runs
    // along any current, towards +x or -x
    for (angle, sign) in [(0.0, 1.0), (180.0, -1.0), (90.0, 1.0), (200.0, -1.0)] {
        let r = Ripple::new(&two_d(angle)).unwrap();
        let f = r.flow_at(0);
        assert!((f.angle.cos() - sign).abs() < 1e-12, "{angle}: {}", f.angle);
    }
}

/// Mean and standard error of the mean of `x`.
fn mean_se(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// Mean and standard error of the mean of `g` over [`ripple_run`]s with seeds 1-4.
fn mean_se_of_seeds(f: impl Fn(&mut RippleParams), g: fn(&Analysis) -> f64) -> (f64, f64) {
    let x: Vec<f64> = (1..=4).map(|s| g(&ripple_run(0.0, s, &f))).collect();
    mean_se(&x)
}

/// Whether two means differ by more than 4 standard errors of their difference.
fn beyond_noise(a: (f64, f64), b: (f64, f64)) -> bool {
    (a.0 - b.0).abs() > 4.0 * (a.1 * a.1 + b.1 * b.1).sqrt()
}

/// The stoss cap acts: beta ("the maximum slope of the stoss side") sets the stoss slope, at
/// most beta + 2 deg and rising with it; with beta at the avalanche angle (the cap off) the
/// stoss is far steeper, beyond the seed noise.
#[test]
fn stoss_cap_beta_sets_the_stoss_slope() {
    let stoss = |beta: f64| mean_se_of_seeds(|p| p.stoss_angle = beta, |a| a.stoss_slope_deg);
    let mut last = 0.0;
    for beta in [5.0, 7.0, 10.0] {
        let s = stoss(beta);
        eprintln!("beta {beta}: stoss {s:?}");
        assert!(s.0 <= beta + 2.0, "beta {beta}: stoss {s:?}");
        assert!(s.0 > last, "beta {beta}: stoss {s:?} not above {last}");
        last = s.0;
    }
    let on = stoss(7.0);
    let off = stoss(32.0);
    eprintln!("cap off: stoss {off:?}");
    assert!(
        off.0 > 12.0 && beyond_noise(on, off),
        "on {on:?} off {off:?}"
    );
}

/// Creep (Eqs. 9-10) acts: switching it off (gamma near 90 deg) changes the symmetry index of
/// the field beyond the seed noise (creep smooths the lee's foot and lengthens the stoss).
#[test]
fn creep_switched_off_changes_the_symmetry_index() {
    let on = mean_se_of_seeds(|_| {}, |a| a.symmetry_index);
    let off = mean_se_of_seeds(|p| p.creep_angle = 89.9, |a| a.symmetry_index);
    eprintln!("creep on {on:?} off {off:?}");
    assert!(beyond_noise(on, off), "on {on:?} off {off:?}");
}

/// The slice drag acts: it is what brings the water behind a crest back up to speed (Sect.
/// 2.3); without its delay (`drag_delay = 0`, the speed recovers at once behind the zero zone)
/// the shelter behind the crests is shorter and the ripples lower, beyond the seed noise.
#[test]
fn slice_drag_switched_off_lowers_the_ripples() {
    let on = mean_se_of_seeds(|_| {}, |a| a.height_m);
    let off = mean_se_of_seeds(|p| p.drag_delay = 0, |a| a.height_m);
    eprintln!("drag on {on:?} off {off:?}");
    assert!(
        off.0 < on.0 && beyond_noise(on, off),
        "on {on:?} off {off:?}"
    );
}

#[test]
fn flow_frame_keeps_its_lattice_when_the_current_changes() {
    let p = RippleParams {
        nx: 16,
        ny: 8,
        layers: 6,
        current_angle: 30.0,
        ..RippleParams::default()
    };
    // the flow frame's lattice was turned with the starting current: its speed may change,
    // its direction may not
    let mut r = Ripple::new(&p).unwrap();
    r.set_current(0.3, 30.0).unwrap();
    let e = r.set_current(0.3, 40.0).unwrap_err().to_string();
    assert!(
        e.starts_with("current_angle = 40 is out of range") && e.contains("frame = grid"),
        "{e}"
    );
    assert_eq!(r.params().current_angle, 30.0);
    assert_eq!(r.params().current_speed, 0.3);
    // in the grid frame the current turns freely
    let mut g = Ripple::new(&RippleParams {
        frame: Frame::Grid,
        ..p
    })
    .unwrap();
    g.set_current(0.3, 40.0).unwrap();
    assert_eq!(g.params().current_angle, 40.0);
    // a 2-D section in the flow frame runs along its starting current: it may reverse along
    // it, not turn
    let mut s = Ripple::new(&RippleParams {
        mode: Mode::TwoD,
        nx: 16,
        ny: 1,
        layers: 6,
        current_angle: 30.0,
        ..RippleParams::default()
    })
    .unwrap();
    s.set_current(0.3, 210.0).unwrap();
    s.set_current(0.3, -150.0).unwrap();
    let e = s.set_current(0.3, 40.0).unwrap_err().to_string();
    assert!(e.starts_with("current_angle = 40 is out of range"), "{e}");
    assert_eq!(s.params().current_angle, -150.0);
}

/// A 2-D section run at 180 deg flows towards -x: its lee and stoss faces are measured along
/// that flow, so they keep their sides (lee steeper than stoss, symmetry index above 1) as at
/// 0 deg.
#[test]
fn two_d_section_at_180_deg_keeps_lee_and_stoss() {
    for angle in [0.0, 180.0] {
        let (mut lee, mut stoss, mut sym) = (0.0, 0.0, 0.0);
        for seed in 1..=3 {
            let p = RippleParams {
                mode: Mode::TwoD,
                nx: 400,
                ny: 1,
                steps: 3000,
                current_angle: angle,
                seed,
                ..RippleParams::default()
            };
            let mut r = Ripple::new(&p).unwrap();
            r.run(p.steps, |_| {});
            let a = Analysis::of(&r);
            lee += a.lee_slope_deg / 3.0;
            stoss += a.stoss_slope_deg / 3.0;
            sym += a.symmetry_index / 3.0;
        }
        assert!(
            lee > 1.8 * stoss && sym > 1.2,
            "{angle} deg: lee {lee:.1}, stoss {stoss:.1}, symmetry index {sym:.2}"
        );
    }
}

/// Median, over the ripples of a 2-D bed, of the distance from a crest to the foot of the next
/// ripple's stoss in heights of that crest: crests and troughs are the bed's extrema with a
/// hysteresis of 5 mm ([`extrema`]); `H` is a crest's drop to the next trough; the stoss foot
/// is the last column before the next crest within 1 mm (two automata) of that trough.
fn median_stoss_foot_in_heights(r: &Ripple, p: &RippleParams) -> f64 {
    let z: Vec<f64> = r
        .volume()
        .heights()
        .iter()
        .map(|&h| f64::from(h) * p.layer_thickness)
        .collect();
    let ext = extrema(&z, 0.005);
    let mut ratios: Vec<f64> = ext
        .windows(3)
        .filter(|w| w[0].1 && !w[1].1 && w[2].1)
        .map(|w| {
            let (crest, trough, next) = (w[0].0, w[1].0, w[2].0);
            let h = z[crest] - z[trough];
            let foot = (trough..next)
                .rev()
                .find(|&k| z[k] <= z[trough] + 0.001)
                .unwrap();
            (foot - crest) as f64 * p.bin_size / h
        })
        .collect();
    assert!(ratios.len() >= 5, "too few ripples: {}", ratios.len());
    ratios.sort_by(f64::total_cmp);
    ratios[ratios.len() / 2]
}

/// What sets the current ripples' spacing (docs/ripple.md, "What sets the spacing"): a ripple's
/// stoss begins where the water behind the crest upstream regains the threshold of motion,
/// after the zero-speed zone (`shadow_length` bins per slice of obstruction) and the part of
/// the linear recovery (`drag_delay` bins per slice) below the speed fraction
/// `sqrt(theta_cr / theta)`: `x / H = (bin / slice) (shadow_length + drag_delay sqrt(theta_cr /
/// theta))`, so the troughs hold no bed where a new ripple could start. Checked on 2-D sections
/// of 5.12 m after 1500 s, with the drag's delay at 0 and 2 (predicted 5.0 and 10.2 H at
/// 0.5 m/s over 0.2 mm sand): the median within 15 %. Over seeds 1-3 the medians were 5.56 /
/// 5.56 / 5.20 and 10.18 / 10.00 / 10.58 H (+4 to +11 % and -2 to +3 %; seed scatter 3-4 %),
/// so the bound allows the largest offset seen (+11 %) and about the seeds' scatter again.
#[test]
fn stoss_foot_lies_where_the_flow_regains_the_threshold_of_motion() {
    for drag_delay in [0, 2] {
        let mut p = RippleParams {
            mode: Mode::TwoD,
            nx: 1024,
            ny: 1,
            layers: 80,
            d50: 0.2,
            current_speed: 0.5,
            hop_grains: 37.5,
            hop_exponential: true,
            drag_delay,
            seed: 1,
            ..RippleParams::default()
        };
        p.steps = cellsurf::ripple::clock::StepClock::of(&p)
            .unwrap()
            .steps_for(1500.0)
            .unwrap();
        let reg = cellsurf::ripple::regime::regime(&p);
        let s_motion = (reg.shields_critical / reg.shields).sqrt();
        let slice = p.slice_layers as f64 * p.layer_thickness;
        let predicted =
            p.bin_size / slice * (p.shadow_length as f64 + drag_delay as f64 * s_motion);
        let mut r = Ripple::new(&p).unwrap();
        r.run(p.steps, |_| {});
        let measured = median_stoss_foot_in_heights(&r, &p);
        assert!(
            (measured / predicted - 1.0).abs() < 0.15,
            "drag_delay {drag_delay}: stoss foot at {measured:.2} H, predicted {predicted:.2} H"
        );
    }
}

/// Crest suspension (`crest_suspension`, opt-in) conserves the mass and keeps every slope
/// within alpha, as every other rule does; it sheds grains from the crests.
#[test]
fn conservation_and_no_slope_above_alpha_with_crest_suspension() {
    let shed = |p: RippleParams| RippleParams {
        crest_suspension: 0.002,
        steps: 300,
        ..p
    };
    let r = checked_run(&shed(small()));
    assert!(r.stats().suspended > 0);
    let r = checked_run(&shed(RippleParams {
        mode: Mode::TwoD,
        nx: 64,
        ny: 1,
        ..small()
    }));
    assert!(r.stats().suspended > 0);
}

/// Crest suspension in flat-bed travels (`crest_suspension_hops = k`) is crest suspension at
/// `L = k x hop x (theta / theta_cr - 1)`, the median grain's mean travel on a flat bed in the
/// run's current (0.5 travels of 0.2 mm sand at 0.5 m/s: 0.5 x 0.94 mm x 2.64 = 1.24 mm), for
/// every grain class: after 400 steps the run has the same bed as the same rules with that
/// `L` in metres (`crest_suspension`), and it does shed grains.
#[test]
fn crest_suspension_in_travels_is_crest_suspension_at_the_median_grains_travel() {
    let base = RippleParams {
        mode: Mode::TwoD,
        nx: 128,
        ny: 1,
        hop_grains: 4.6875,
        ..small()
    };
    let hops = RippleParams {
        crest_suspension_hops: 0.5,
        ..base.clone()
    };
    let l = 0.5 * cellsurf::ripple::clock::median_travel(&hops, base.current_speed);
    assert!((l - 1.24e-3).abs() < 0.01e-3, "{l}");
    let fixed = RippleParams {
        crest_suspension: l,
        ..base
    };
    let (mut a, mut b) = (Ripple::new(&hops).unwrap(), Ripple::new(&fixed).unwrap());
    assert!(a.classes().len() > 1);
    a.run(400, |_| {});
    b.run(400, |_| {});
    assert!(a.stats().suspended > 0, "{:?}", a.stats());
    assert_eq!(a.stats().suspended, b.stats().suspended);
    assert_eq!(a.volume().heights(), b.volume().heights());
}

/// The leading bed stress and flow separation (`stress_lead`, `separation_angle`, opt-in)
/// conserve the mass and keep every slope within alpha.
#[test]
fn conservation_and_no_slope_above_alpha_with_the_leading_stress_and_flow_separation() {
    let lead = |p: RippleParams| RippleParams {
        stress_lead: 2.0,
        separation_angle: 15.0,
        steps: 300,
        ..p
    };
    checked_run(&lead(small()));
    checked_run(&lead(RippleParams {
        mode: Mode::TwoD,
        nx: 64,
        ny: 1,
        ..small()
    }));
}

/// Mean and standard error of the mean of the height of a 2-D section of 2.56 m (0.2 mm sand,
/// 0.5 m/s, 10 cm of sand, the travel in grain diameters) after 300 s, seeds 1-4.
fn section_height_300s(stress_lead: f64, separation_angle: f64) -> (f64, f64) {
    let x: Vec<f64> = (1..=4)
        .map(|seed| {
            let p = RippleParams {
                mode: Mode::TwoD,
                nx: 512,
                ny: 1,
                layers: 200,
                hop_grains: 37.5,
                stress_lead,
                separation_angle,
                seed,
                ..RippleParams::default()
            };
            let clock = cellsurf::ripple::clock::StepClock::of(&p).unwrap();
            let mut r = Ripple::new(&p).unwrap();
            r.run(clock.steps_for(300.0).unwrap(), |_| {});
            assert_eq!(r.mass_change(), 0);
            Analysis::of(&r).height_m
        })
        .collect();
    mean_se(&x)
}

/// Flow separation acts: with `separation_angle = 15` (only drops of 3 automata shelter) the
/// flat bed's instability, which in the paper's rules comes from the shelter behind bumps of
/// an automaton or two, is switched off, and the bed keeps its initial roughness for 300 s;
/// the leading bed stress (`stress_lead = 2`) starts ripples on that bed again. Measured
/// (seeds 1-3): 1.04 / 1.13 / 0.99 cm high without the rule, 0.19 / 0.20 / 0.18 cm with
/// it, 1.40 / 1.55 / 1.16 cm with both (docs/ripple.md, "The leading bed stress and flow
/// separation"). The bounds: each change beyond 4 standard errors of the difference, and the
/// bed with separation alone below 0.4 cm (the roughness of 3 automata is 0.15 cm).
#[test]
fn flow_separation_stops_and_the_leading_stress_restarts_the_instability() {
    let paper = section_height_300s(0.0, 0.0);
    let separated = section_height_300s(0.0, 15.0);
    let led = section_height_300s(2.0, 15.0);
    eprintln!("heights (m): paper {paper:?}, separation {separated:?}, both {led:?}");
    assert!(
        separated.0 < 0.004 && beyond_noise(paper, separated),
        "{paper:?} {separated:?}"
    );
    assert!(
        led.0 > 2.0 * separated.0 && beyond_noise(led, separated),
        "{led:?} {separated:?}"
    );
}

/// The analysis of a 2-D section of 512 bins (0.2 mm sand, 0.5 m/s, 10 cm of sand in the
/// recipe's bins of 0.75 flat-bed travels, 1.86 mm: 0.95 m) under the recipe for mature
/// current ripples (`docs/ripple_mature_current.toml`; docs/ripple.md, "A recipe for mature
/// current ripples"), after each of `times` seconds of flow, one run continued; `vary` changes
/// the recipe's factors first.
fn recipe_section(seed: u64, vary: impl Fn(&mut RippleParams), times: &[f64]) -> Vec<Analysis> {
    let mut p = recipe_params(seed);
    vary(&mut p);
    analyses_at(&p, times)
}

/// A run with `bin_travels` (the recipe's bin, 0.75 flat-bed travels) runs on the bin of its
/// travel, its automata following, and its step clock is that bin's; column heights given on
/// another bin are refused, naming the bin.
#[test]
fn bin_travels_runs_on_the_bin_of_the_travel() {
    let p = RippleParams {
        nx: 32,
        d50: 0.1,
        ..recipe_params(1)
    };
    let q = p.with_travel_bin();
    assert_eq!(
        (q.bin_size, q.layer_thickness, q.layers),
        (0.00123, 0.000123, 813)
    );
    let mut r = Ripple::new(&p).unwrap();
    assert_eq!(r.params(), &q);
    // a current changed on the built lattice keeps its bin
    r.set_current(0.6, 0.0).unwrap();
    assert_eq!(
        (r.params().bin_size, r.params().bin_travels),
        (0.00123, 0.0)
    );
    let clock = |p: &RippleParams| cellsurf::ripple::clock::StepClock::of(p).unwrap();
    assert_eq!(clock(&p), clock(&q));
    let e = Ripple::from_heights(&p, &vec![400; 32])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bin_size = 0.0025") && e.contains("0.00123 m"),
        "{e}"
    );
    assert!(Ripple::from_heights(&q, &vec![813; 32]).is_ok());
}

/// The parameters of [`recipe_section`] before `vary`.
fn recipe_params(seed: u64) -> RippleParams {
    let dir = env!("CARGO_MANIFEST_DIR");
    let text = std::fs::read_to_string(format!("{dir}/docs/ripple_mature_current.toml")).unwrap();
    let recipe = RippleParams::from_toml(&text).unwrap();
    assert_eq!(
        (
            recipe.suspension_exponent,
            recipe.crest_suspension_hops,
            recipe.bin_size,
            recipe.layers,
            recipe.stoss_face_hold,
            recipe.bin_travels
        ),
        (8.0, 4.0, 0.0025, 400, true, 0.75),
        "the recipe the docs measure"
    );
    RippleParams {
        mode: Mode::TwoD,
        nx: 512,
        ny: 1,
        seed,
        ..recipe
    }
}

/// The analysis of one run of `p` after each of `times` seconds of flow, the run continued.
fn analyses_at(p: &RippleParams, times: &[f64]) -> Vec<Analysis> {
    let clock = cellsurf::ripple::clock::StepClock::of(p).unwrap();
    let mut r = Ripple::new(p).unwrap();
    times
        .iter()
        .map(|&t| {
            let n = clock.steps_for(t).unwrap();
            r.run(n - r.time(), |_| {});
            assert_eq!(r.mass_change(), 0);
            Analysis::of(&r)
        })
        .collect()
}

/// The recipe for mature current ripples holds its length and height from 6000 s to 24,000 s
/// with slip faces at the angle of repose and a ripple index near nature's; with crest
/// suspension's default exponent (2) in place of 8 the same section is flatter. Measured (512
/// of its bins of 1.86 mm, 0.95 m, 0.2 mm, seed 1): 15.9 cm at both times, 1.52 / 1.55 cm
/// high, lee 30.6 deg, ripple index 10.3, and 11.8 with the exponent 2 (in its former 2.5 mm
/// bins, on 1.28 m: 16.0 cm, 1.48 / 1.54 cm, 10.4 against 12.6). The bounds: at most one
/// ripple fewer or more on the section (lengths are the section over k, neither coarsening nor
/// splitting by more), the height within 10 %, lee at least 27 deg (the avalanche angle is
/// 32), ripple index at most 12; with the exponent 2, a ripple index above the exponent 8's by
/// at least 1 (ten times the standard error of the recipe's ripple index over three seeds).
#[test]
#[ignore = "long: 0.95 m in bins of 1.86 mm to 24,000 s, twice (about 7 minutes in release)"]
fn the_mature_current_recipe_holds_a_length_with_slip_faces() {
    let a = recipe_section(1, |_| {}, &[6000.0, 24_000.0]);
    let (early, late) = (&a[0], &a[1]);
    eprintln!(
        "recipe: {:.1} / {:.1} cm, {:.2} / {:.2} cm high, lee {:.1}, ripple index {:.1}",
        early.wavelength_m * 100.0,
        late.wavelength_m * 100.0,
        early.height_m * 100.0,
        late.height_m * 100.0,
        late.lee_slope_deg,
        late.ripple_index
    );
    let p = recipe_params(1).with_travel_bin();
    let ripples = |a: &Analysis| (p.nx as f64 * p.bin_size / a.wavelength_m).round();
    assert!(
        (ripples(late) - ripples(early)).abs() <= 1.0,
        "{early:?} {late:?}"
    );
    assert!(
        (late.height_m / early.height_m - 1.0).abs() < 0.1,
        "{early:?} {late:?}"
    );
    assert!(
        late.lee_slope_deg >= 27.0 && late.ripple_index <= 12.0,
        "{late:?}"
    );
    let square = recipe_section(1, |p| p.suspension_exponent = 2.0, &[24_000.0]);
    eprintln!("exponent 2: ripple index {:.1}", square[0].ripple_index);
    assert!(
        square[0].ripple_index >= late.ripple_index + 1.0,
        "{:?}",
        square[0]
    );
}

/// Crest suspension's length sets the crests' height: with the sharp threshold of the recipe
/// a crest that rises above `L` over the bed's mean level sheds its grains, so the height
/// (crest to trough) stays near `2 L`, and a longer `L` gives higher ripples. Measured (the
/// recipe's rules with `L` in grain diameters, in 5 mm bins to keep the test short, on
/// 1.28 m, 0.2 mm sand, 6000 s, seed 1): `L` = 30 d50 (6 mm): 1.18 cm, `H / 2L` 0.99; `L` =
/// 60 d50 (12 mm): 1.82 cm, 0.76 (the previous recipe's screen in 5 mm bins: 0.67-1.04; the
/// recipe in its former 2.5 mm bins: 0.77-0.82). The bounds are empirical: `H / 2L` in [0.6, 1.1], around
/// the screen's range (the rule bounds the crest's rise above the mean level, not the trough's
/// depth, so `H / 2L` can pass 1), and the height with the longer `L` at least 1.3 times the
/// shorter's (measured 1.5-1.6).
#[test]
fn crest_suspension_sets_the_crest_height() {
    let height = |f: f64| {
        let in_grains = |p: &mut RippleParams| {
            p.crest_suspension_hops = 0.0;
            p.crest_suspension_grains = f;
            (p.nx, p.layers, p.bin_size, p.layer_thickness) = (256, 200, 0.005, 0.0005);
            p.bin_travels = 0.0;
        };
        let a = recipe_section(1, in_grains, &[6000.0]);
        let l = f * 0.2e-3;
        eprintln!(
            "L = {f} d50: {:.2} cm high, H / 2L = {:.2}",
            a[0].height_m * 100.0,
            a[0].height_m / (2.0 * l)
        );
        assert!(
            (0.6..=1.1).contains(&(a[0].height_m / (2.0 * l))),
            "L = {f} d50: {:?}",
            a[0]
        );
        a[0].height_m
    };
    let (short, long) = (height(30.0), height(60.0));
    assert!(long >= 1.3 * short, "{short} m against {long} m");
}

/// The recipe's bins of 0.75 flat-bed travels (1.23 mm for 0.1 mm sand at 0.5 m/s) resolve the
/// fine sand's ripples: on a 2-D section of 0.63 m (512 bins) after 3000 s (seed 1) they have
/// the shape of current ripples, where the same rules in 5 mm bins (0.64 m), the grains'
/// travel (1.6 mm) being a third of a bin, make them longer and flatter, without it (on 2.56
/// m after 6000 s the 5 mm bins give ripple index 14.2, symmetry index 1.7, lee 26.6 deg,
/// seeds 1-3). Measured: 10.5 cm, 1.01 cm, lee 30.8 deg, ripple index 10.4, symmetry index
/// 3.18 in the recipe's bins; 16.0 cm, 1.13 cm, lee 28.7 deg, ripple index 14.2, symmetry
/// index 1.62 in 5 mm bins. The bounds are the goals of current ripples (lee at least 27 deg,
/// ripple index at most 12, symmetry index at least 2) and, in 5 mm bins, their opposite
/// (ripple index above 13, symmetry index below 2).
#[test]
fn the_recipes_bins_give_the_fine_sand_current_ripples_shape() {
    let fine = |p: &mut RippleParams| {
        p.d50 = 0.1;
        p.nx = 512;
    };
    let resolved = &recipe_section(1, fine, &[3000.0])[0];
    let coarse = &recipe_section(
        1,
        |p| {
            fine(p);
            (p.nx, p.layers, p.bin_size, p.layer_thickness) = (128, 200, 0.005, 0.0005);
            p.bin_travels = 0.0;
        },
        &[3000.0],
    )[0];
    for (bins, a) in [("the recipe's", resolved), ("5 mm", coarse)] {
        eprintln!(
            "{bins} bins: {:.1} cm, {:.2} cm, lee {:.1}, ripple index {:.1}, symmetry index {:.2}",
            a.wavelength_m * 100.0,
            a.height_m * 100.0,
            a.lee_slope_deg,
            a.ripple_index,
            a.symmetry_index
        );
    }
    assert!(
        resolved.lee_slope_deg >= 27.0
            && resolved.ripple_index <= 12.0
            && resolved.symmetry_index >= 2.0,
        "{resolved:?}"
    );
    assert!(
        coarse.ripple_index > 13.0 && coarse.symmetry_index < 2.0,
        "{coarse:?}"
    );
}

/// The recipe's face hold acts (`stoss_face_hold`: a grain is held wherever the rise ahead of
/// it is steeper than beta): on 2-D sections of 256 of its bins (0.48 m: 0.2 mm sand, 1500 s,
/// seeds 1-3) the recipe's stoss slopes follow beta, at most beta + 2 deg and rising with it,
/// and with Eq. (3)'s foot rule in its place (the hold off) the stoss is steeper at beta = 7
/// deg, beyond the seed noise (4 standard errors of the difference). Measured: 5.86 / 8.64 /
/// 11.22 deg for beta = 5 / 7 / 10 deg, and 10.44 deg with the foot rule. The bound beta + 2
/// is the goal for stoss slopes, not a noise tolerance (at 7 deg the mean is 0.36 deg under
/// it, with a standard error of 0.15 deg). About a minute in release (12 runs of 256 bins).
#[test]
fn the_recipes_face_hold_keeps_its_stoss_at_beta() {
    let stoss = |hold: bool, beta: f64| {
        let x: Vec<f64> = (1..=3)
            .map(|seed| {
                let vary = |p: &mut RippleParams| {
                    p.nx = 256;
                    p.stoss_angle = beta;
                    p.stoss_face_hold = hold;
                };
                recipe_section(seed, vary, &[1500.0])[0].stoss_slope_deg
            })
            .collect();
        mean_se(&x)
    };
    let mut last = 0.0;
    for beta in [5.0, 7.0, 10.0] {
        let s = stoss(true, beta);
        eprintln!("face hold, beta {beta}: stoss {s:?}");
        assert!(s.0 <= beta + 2.0 && s.0 > last, "beta {beta}: {s:?}");
        last = s.0;
    }
    let (on, off) = (stoss(true, 7.0), stoss(false, 7.0));
    eprintln!("foot rule, beta 7: stoss {off:?}");
    assert!(off.0 > on.0 && beyond_noise(on, off), "{on:?} {off:?}");
}

/// The wavelength of a 2-D section of 1.28 m (0.2 mm sand, 0.5 m/s, 10 cm of sand) after each
/// of `times` seconds of flow, one run continued.
fn section_wavelengths(seed: u64, crest_suspension: f64, times: &[f64]) -> Vec<f64> {
    let p = RippleParams {
        mode: Mode::TwoD,
        nx: 256,
        ny: 1,
        layers: 200,
        d50: 0.2,
        current_speed: 0.5,
        crest_suspension,
        seed,
        ..RippleParams::default()
    };
    analyses_at(&p, times)
        .iter()
        .map(|a| a.wavelength_m)
        .collect()
}

/// With crest suspension (0.02 m) a 1.28 m section keeps several ripples and nearly their
/// length from 3000 s to 24,000 s; without it the section coarsens towards one ripple
/// (docs/ripple.md, "Crest suspension"). Measured, seeds 1-3: 25.6 / 25.6 / 32.0 cm at 3000 s
/// and 32.0 cm at 24,000 s with it (five ripples on the section, then four); 84.2 cm at
/// 12,000 s without (seed 1). The bounds: over 8 times the time at most one ripple fewer
/// (lengths on the section are 128 / n cm, so at most 40 % longer: 25.6 to 32.0 or 32.0 to
/// 42.7 cm), where a length growing as t^0.45, as without the rule, would grow 2.5-fold; at
/// least three ripples with the rule at 24,000 s, at most two without at 12,000 s.
#[test]
fn crest_suspension_stops_the_coarsening() {
    for seed in 1..=3 {
        let on = section_wavelengths(seed, 0.02, &[3000.0, 24_000.0]);
        assert!(
            on[1] <= 1.4 * on[0] && on[1] <= 0.45,
            "seed {seed}: {:.1} cm at 3000 s, {:.1} cm at 24,000 s with crest suspension",
            on[0] * 100.0,
            on[1] * 100.0
        );
    }
    let off = section_wavelengths(1, 0.0, &[12_000.0]);
    assert!(
        off[0] >= 0.64,
        "{:.1} cm at 12,000 s without crest suspension",
        off[0] * 100.0
    );
}

/// Value stability of the default rules: two small default runs (3-D and a 2-D section) give
/// the same beds as when these values were pinned (2026-11-28, after the opt-in keys of the
/// leading stress, flow separation and crest suspension's exponent were added, which must not
/// change a default run; a build from before those keys gives the same 3-D bed, byte for byte,
/// and the same 8698 rolls). A change of the default rules, the random stream or the order of its
/// draws changes them; if that is meant, pin the new values and say so in the commit.
#[test]
fn value_stability_of_default_ripple_runs() {
    let checksum = |r: &Ripple| {
        let h = r.volume().heights();
        let weighted: u64 = h
            .iter()
            .enumerate()
            .map(|(i, &v)| (i as u64 + 1) * v as u64)
            .sum();
        let squares: u64 = h.iter().map(|&v| (v as u64) * (v as u64)).sum();
        (weighted, squares, r.stats().rolls)
    };
    let mut r = Ripple::new(&small()).unwrap();
    r.run(small().steps, |_| {});
    let three_d = checksum(&r);
    let p = RippleParams {
        mode: Mode::TwoD,
        nx: 64,
        ny: 1,
        steps: 600,
        ..small()
    };
    let mut r = Ripple::new(&p).unwrap();
    r.run(p.steps, |_| {});
    let two_d = checksum(&r);
    eprintln!("3-D {three_d:?}, 2-D {two_d:?}");
    assert_eq!(three_d, (1_579_902, 74_478, 8698));
    assert_eq!(two_d, (23_891, 9825, 4314));
}

/// The regime, the step clock, the rules and Rubin & Hunter's normal take one flow for a current
/// with waves (`RippleParams::combined_flow`), and none of them counts waves without a period.
#[test]
fn the_regime_the_clock_and_the_rules_see_one_combined_flow() {
    use cellsurf::ripple::clock::phase_speeds;
    use cellsurf::ripple::predictors::rubin_hunter_crest_normal;
    use cellsurf::ripple::regime::regime;
    use cellsurf::ripple::water::Flow;
    let p = RippleParams {
        d50: 0.2,
        current_speed: 0.4,
        current_angle: 0.0,
        wave_amplitude: 0.3,
        wave_period: 64.0,
        wave_angle: Some(50.0),
        wave_friction_factor: 0.01,
        frame: cellsurf::ripple::Frame::Grid,
        ..RippleParams::default()
    };
    let (c, w) = (0.0_f64, 50.0_f64.to_radians());
    let magnitude = |s: f64| {
        let (ux, uy) = p.combined_flow(c, w, s);
        ux.hypot(uy)
    };
    // the regime: the largest speed of the cycle, at the wave's crest or trough
    let r = regime(&p);
    assert!((r.speed - magnitude(1.0).max(magnitude(-1.0))).abs() < 1e-12);
    // the clock's phases and the rules' steps: the same flow, never above the regime's
    for (k, &v) in phase_speeds(&p).iter().enumerate() {
        let s = (2.0 * std::f64::consts::PI * (k as f64 + 0.5) / 64.0).sin();
        assert!((v - magnitude(s)).abs() < 1e-12 && v <= r.speed, "{k}");
    }
    for t in 0..64u64 {
        let s = (2.0 * std::f64::consts::PI * (t as f64 + 0.5) / 64.0).sin();
        let f = Flow::at(&p, t, false);
        assert!((f.speed - magnitude(s)).abs() < 1e-12, "{t}");
    }
    // an orbital velocity without a period moves nothing: the current alone everywhere
    let still = RippleParams {
        wave_period: 0.0,
        ..p.clone()
    };
    let alone = RippleParams {
        wave_amplitude: 0.0,
        ..p.clone()
    };
    assert_eq!(regime(&still), regime(&alone));
    assert_eq!(phase_speeds(&still), vec![0.4]);
    assert_eq!(Flow::at(&still, 3, false).speed, 0.4);
    assert_eq!(
        rubin_hunter_crest_normal(&still),
        rubin_hunter_crest_normal(&alone)
    );
}
