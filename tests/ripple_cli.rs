//! `cellsurf ripple` as a user meets it: the JSON summary's keys, the NetCDF and npy files,
//! scene files, and bad input rejected with a message naming the parameter.
#![cfg(feature = "cli")]

mod common;

use std::path::PathBuf;

use common::cellsurf;

fn tmp(name: &str) -> PathBuf {
    common::tmp_in("ripple-cli", name)
}

/// The run with `extra` failed without a panic, its message naming `flag` and `why`.
fn assert_refused(extra: &[&str], o: &std::process::Output, flag: &str, why: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_ne!(o.status.code(), Some(0), "{extra:?}: {err}");
    assert!(!err.contains("panicked"), "{extra:?}: {err}");
    assert!(err.contains(flag) && err.contains(why), "{extra:?}: {err}");
}

/// Waves alone (no current), with the period in seconds: they dominate, and get the lee vortex.
const WAVES: [&str; 6] = [
    "--current-speed",
    "0",
    "--wave-velocity",
    "0.4",
    "--wave-period",
    "2s",
];

const SMALL: &[&str] = &[
    "ripple", "--recipe", "paper", "--size", "24x12", "--layers", "10", "--steps", "40", "--seed",
    "3",
];

#[test]
fn json_summary_has_the_promised_keys_and_conserves_mass() {
    let out = tmp("a.nc");
    let mut args = SMALL.to_vec();
    args.extend([
        "--json",
        "--snapshots",
        "0,20,40",
        "--out",
        out.to_str().unwrap(),
    ]);
    let o = cellsurf(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for k in [
        "steps",
        "automata",
        "activations",
        "elapsed_s",
        "wavelength_m",
        "crest_normal_deg",
        "height_m",
        "ripple_index",
        "lee_slope_deg",
        "stoss_slope_deg",
        "mass_change",
        "d50_crest_mm",
        "d50_trough_mm",
        "bare_fraction",
    ] {
        assert!(v.get(k).is_some(), "missing {k}");
    }
    assert_eq!(v["mass_change"], 0);
    assert_eq!(v["steps"], 40);
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(&bytes[..4], b"CDF\x02");
}

#[test]
fn only_the_fields_asked_for_are_written_as_npy() {
    let out = tmp("b.npy");
    let mut args = SMALL.to_vec();
    args.extend([
        "--quiet",
        "--fields",
        "elevation,porosity",
        "--out",
        out.to_str().unwrap(),
    ]);
    let o = cellsurf(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(tmp("b.npy").exists());
    assert!(tmp("b_porosity.npy").exists());
    assert!(!tmp("b_impedance.npy").exists());
    let side = std::fs::read_to_string(tmp("b.json")).unwrap();
    assert!(side.contains("\"porosity\"") && !side.contains("\"impedance\""));
}

#[test]
fn scene_file_and_bad_input() {
    let dir = env!("CARGO_MANIFEST_DIR");
    let scene = format!("{dir}/tests/fixtures/ripple_small.toml");
    let o = cellsurf(&["ripple", "--scenario", &scene, "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bad = format!("{dir}/tests/fixtures/ripple_bad_key.toml");
    let o = cellsurf(&["ripple", "--scenario", &bad]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("currnt_speed"));
    let o = cellsurf(&["ripple", "--avalanche-angle", "95"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--avalanche-angle = 95"));
    // A negative value reaches the range check, which names the parameter.
    let o = cellsurf(&["ripple", "--d50", "-1"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("d50 = -1"));
    let o = cellsurf(&["ripple", "--steps", "10", "--snapshots", "20"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("snapshots"));
    // snapshots out of order or twice are refused, not sorted
    for list in ["3,2", "2,2", "0,5,3"] {
        let o = cellsurf(&[
            "ripple",
            "--size",
            "8x4",
            "--layers",
            "2",
            "--steps",
            "5",
            "--snapshots",
            list,
        ]);
        assert!(!o.status.success(), "{list}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(
            e.contains(&format!("--snapshots = {list}")) && e.contains("strictly increasing"),
            "{e}"
        );
    }
    let o = cellsurf(&[
        "ripple",
        "--acoustics",
        "apl-uw",
        "--fields",
        "porosity",
        "--steps",
        "1",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("fields"));
}

#[test]
fn outputs_are_checked_before_the_run() {
    let o = cellsurf(&[
        "ripple",
        "--nx",
        "8",
        "--ny",
        "8",
        "--steps",
        "1",
        "--out",
        "/nonexistent-dir/x.nc",
    ]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("--out /nonexistent-dir/x.nc: the folder does not exist"),
        "{e}"
    );
    let o = cellsurf(&["ripple", "--mode", "2d", "--size", "128x5", "--steps", "1"]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("--size = 128x5 is out of range"), "{e}");
    assert!(!e.contains("panicked"), "{e}");
    // `.npy`: the sidecar and each volume field's file are checked too, before the run
    for (blocked, fields) in [
        ("blk.json", "elevation"),
        ("blk_porosity.npy", "elevation,porosity"),
    ] {
        let dir = tmp(blocked);
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let out = tmp("blk.npy");
        let o = cellsurf(&[
            "ripple",
            "--size",
            "128x64",
            "--steps",
            "20000",
            "--fields",
            fields,
            "--out",
            &out.display().to_string(),
        ]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{e}");
        // (the words of the check before the run; a write failing after it says "writing")
        assert!(e.contains(&format!("its file {}", dir.display())), "{e}");
        assert!(!e.contains("writing"), "{e}");
        assert!(!out.exists(), "an output was written");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// Soulsby (1997), Sect. 7.2: below the threshold of motion nothing moves, above a Shields
/// number of 0.8 ripples are washed out (sheet flow); the JSON always says which.
#[test]
fn regimes_no_motion_ripples_and_sheet_flow() {
    let run = |speed: &str, out: Option<&PathBuf>| {
        let mut args = SMALL.to_vec();
        args.extend(["--json", "--current-speed", speed, "--snapshots", "0,40"]);
        let o = out.map(|p| p.display().to_string());
        if let Some(o) = &o {
            args.extend(["--out", o.as_str()]);
        }
        cellsurf(&args)
    };
    // no motion: the bed is left as it is, and said so
    let npy = tmp("still.npy");
    let o = run("0.2", Some(&npy));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["regime"], "no motion");
    assert!(v["shields"].as_f64().unwrap() < v["shields_critical"].as_f64().unwrap());
    assert_eq!(v["steps"], 0);
    assert_eq!(v["activations"], 0);
    // no step was run: the bed of step 0 is the one snapshot (not one per step asked for)
    assert_eq!(v["parameters"]["steps"], 0);
    let b = std::fs::read(&npy).unwrap();
    assert!(String::from_utf8_lossy(&b[..128]).contains("'shape': (1, 12, 24)"));
    let side = std::fs::read_to_string(tmp("still.json")).unwrap();
    assert!(side.contains("\"elevation_times\": [0]"), "{side}");
    assert!(String::from_utf8_lossy(&o.stderr).contains("the only snapshot"));
    // a flow above the threshold that the model's rules cannot move: a stoss angle of 0 lets
    // no grain rest above the column upstream; the note names the flag that causes it
    let mut args = SMALL.to_vec();
    args.extend(["--json", "--stoss-angle", "0"]);
    let o = cellsurf(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["regime"], "no motion");
    assert!(v["shields"].as_f64().unwrap() > v["shields_critical"].as_f64().unwrap());
    assert!(
        err.contains("no motion in the model") && err.contains("--stoss-angle = 0 deg"),
        "{err}"
    );
    // ripples, with the Shields number of the law
    let o = run("0.5", None);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["regime"], "ripples");
    let t = v["shields"].as_f64().unwrap();
    assert!((t - 0.2016).abs() < 1e-3, "{t}");
    assert!((v["shields_critical"].as_f64().unwrap() - 0.0553).abs() < 1e-3);
    // sheet flow: refused, naming the flag, the value and the range
    let o = run("1.5", None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--current-speed = 1.5")
            && err.contains("sheet flow")
            && err.contains("expected"),
        "{err}"
    );
    assert!(!err.contains("panicked"));
    // current and waves: the bed stress of Soulsby's Eq. 70 judges them, and the refusal
    // names the flow whose stress dominates (0.2 mm sand: sheet flow from 0.996 m/s)
    let both = |current: &str, waves: &str| {
        let mut args = SMALL.to_vec();
        args.extend([
            "--json",
            "--current-speed",
            current,
            "--wave-velocity",
            waves,
            "--wave-period",
            "6s",
        ]);
        cellsurf(&args)
    };
    // a 0.97 m/s current with weak waves: sheet flow by the two together, the current's
    let o = both("0.97", "0.2");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("sheet flow") && err.contains("--current-speed = 0.97 m/s is out of range"),
        "{err}"
    );
    // a slower current with weaker waves: ripples (adding friction velocities made it sheet
    // flow, a largest speed of 1.16 m/s, and named --wave-velocity)
    let o = both("0.9", "0.17");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["regime"], "ripples", "{err}");
    // waves that dominate: theirs
    let o = both("0.2", "1.0");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("sheet flow") && err.contains("--wave-velocity = 1 m/s is out of range"),
        "{err}"
    );
}

/// `--duration` sets the steps from the step duration of the transport law; `--until
/// equilibrium` stops at a checkpoint or the cap and says which.
#[test]
fn duration_and_until_equilibrium() {
    let run = |extra: &[&str]| {
        let mut args = vec![
            "ripple", "--recipe", "paper", "--size", "24x12", "--layers", "10", "--seed", "3",
            "--json",
        ];
        args.extend_from_slice(extra);
        cellsurf(&args)
    };
    let o = run(&["--duration", "30s"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let dt = v["step_duration_s"].as_f64().unwrap();
    let steps = v["steps"].as_u64().unwrap();
    assert!(dt > 0.0 && dt < 1.0, "{dt}");
    assert_eq!(steps, (30.0 / dt).round() as u64);
    let t = v["simulated_time_s"].as_f64().unwrap();
    assert!((t - 30.0).abs() <= dt, "{t}");
    assert!(v["bedload_m2_per_s"].as_f64().unwrap() > 0.0);
    // the same run by --steps: the same bed
    let by_steps = run(&["--steps", &steps.to_string()]);
    let w: serde_json::Value = serde_json::from_slice(&by_steps.stdout).unwrap();
    assert_eq!(v["height_m"], w["height_m"]);
    // one or the other, and a duration it can read
    let both = run(&["--steps", "10", "--duration", "1h"]);
    assert_eq!(both.status.code(), Some(2));
    let bad = run(&["--duration", "2 weeks"]);
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(!bad.status.success() && err.contains("--duration"), "{err}");
    // a cap shorter than two doublings: warned, run to the cap untested
    let o = run(&["--until", "equilibrium", "--steps", "3000"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && err.contains("--until equilibrium cannot stop a run of 3000 steps"),
        "{err}"
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["equilibrium"], false);
    assert_eq!(v["steps"], 3000);
    // until equilibrium, capped at 64,000 steps: this 12 cm field reaches the domain's length
    // by 8,000 steps, and its height then settles; it stops at the first checkpoint that ends
    // two successive doublings each changing wavelength and height by under 10 %
    let o = run(&["--until", "equilibrium", "--steps", "64000"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && !err.contains("cannot stop"), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["equilibrium"], true, "{v}");
    let checkpoints = v["checkpoints"].as_array().unwrap();
    let cps: Vec<u64> = checkpoints
        .iter()
        .map(|c| c["step"].as_u64().unwrap())
        .collect();
    let doublings: Vec<u64> = (0..cps.len()).map(|i| 1000 << i).collect();
    assert_eq!(cps, doublings);
    assert_eq!(v["equilibrium_step"], *cps.last().unwrap());
    let quiet: Vec<bool> = checkpoints
        .windows(2)
        .map(|w| {
            ["wavelength_m", "height_m"].iter().all(|k| {
                let (a, b) = (w[0][k].as_f64().unwrap(), w[1][k].as_f64().unwrap());
                (b - a).abs() < 0.1 * a
            })
        })
        .collect();
    let n = quiet.len();
    assert!(n >= 2 && quiet[n - 1] && quiet[n - 2], "{quiet:?}");
    assert!(cps.len() > 1 && cps[n] > 2000, "{cps:?}");
    assert!(
        !quiet[..n - 1].windows(2).any(|w| w[0] && w[1]),
        "two quiet doublings before the stop: {quiet:?}"
    );
    // (so the run went on past its first quiet doubling, where a one-doubling test stops)
    let t = v["equilibrium_time_s"].as_f64().unwrap();
    assert!((t - v["step_duration_s"].as_f64().unwrap() * cps[n] as f64).abs() < 1e-9);
    assert_eq!(v["steps"].as_u64().unwrap(), *cps.last().unwrap());
    // 5 mm of sand under these ripples: the substrate never shows
    assert!(!String::from_utf8_lossy(&o.stderr).contains("substrate"));
    assert_eq!(v["bare_fraction"], 0.0);
    assert!(v["substrate_reached_step"].is_null());
    for c in v["checkpoints"].as_array().unwrap() {
        assert_eq!(c["bare_fraction"], 0.0);
    }
}

/// The old `--format F --out STEM` spelling never replaces an extension the user typed: a file
/// name of another format is refused, and nothing is written; `--steps 0` records one
/// snapshot (step 0), not two of the same step.
#[test]
fn format_never_renames_an_output_and_a_run_of_no_step_has_one_snapshot() {
    let npy = tmp("fmt_c.npy");
    let nc = npy.with_extension("nc");
    for p in [&npy, &nc] {
        let _ = std::fs::remove_file(p);
    }
    let small = |steps: &str, extra: &[&str]| {
        let mut a = vec!["ripple", "--size", "24x12", "--layers", "10", "--quiet"];
        a.extend(["--steps", steps, "--out", npy.to_str().unwrap()]);
        a.extend(extra);
        cellsurf(&a)
    };
    let o = small("5", &["--format", "nc"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("names a .npy file but --format asks for .nc"),
        "{err}"
    );
    assert!(!npy.exists() && !nc.exists());
    let o = small("0", &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(npy.with_extension("json")).unwrap())
            .unwrap();
    assert_eq!(side["elevation_times"], serde_json::json!([0]), "{side}");
}

/// `--print-scenario` writes the model only: the run's output options given with it are named
/// in a note (they are not in the file, and nothing is written).
#[test]
fn print_scenario_names_the_run_options_it_leaves_out() {
    let out = tmp("not_written.nc");
    let _ = std::fs::remove_file(&out);
    let o = cellsurf(&[
        "ripple",
        "--print-scenario",
        "--snapshots",
        "0,100",
        "--steps",
        "200",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("--out, --snapshots choose a run's outputs")
            && err.contains("--scenario FILE"),
        "{err}"
    );
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("steps = 200") && !text.contains("snapshots"),
        "{text}"
    );
    assert!(!out.exists());
    // Without them, no note.
    let o = cellsurf(&["ripple", "--print-scenario"]);
    assert!(o.status.success());
    assert!(!String::from_utf8_lossy(&o.stderr).contains("note:"));
}

/// Troughs down to the substrate: a warning naming the bare columns and `--layers`, JSON's
/// `bare_fraction` (and per checkpoint), and no equilibrium declared on a bed that has shown
/// the substrate although the stalled field passes the 10 % test on wavelength and height
/// (a field on ample sand: `duration_and_until_equilibrium`).
#[test]
fn a_bed_down_to_the_substrate_is_warned_and_never_at_equilibrium() {
    let scenario = tmp("thin_sand.toml");
    let o = cellsurf(&[
        "ripple",
        "--print-scenario",
        "--size",
        "24x12",
        "--layers",
        "6",
        "--bin-size",
        "0.0025",
    ]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout).replace("roughness = 3", "roughness = 1");
    assert!(text.contains("roughness = 1"), "{text}");
    std::fs::write(&scenario, text).unwrap();
    let s = scenario.to_str().unwrap();
    let o = cellsurf(&[
        "ripple",
        "--scenario",
        s,
        "--seed",
        "3",
        "--until",
        "equilibrium",
        "--steps",
        "128000",
        "--json",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("reached the substrate")
            && err.contains("of 288 columns")
            && err.contains("--layers = 6")
            && err.contains("declares no equilibrium"),
        "{err}"
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["equilibrium"], false);
    assert_eq!(v["stop_reason"], "cap (steps)");
    assert!(v["bare_fraction"].as_f64().unwrap() > 0.0);
    let first = v["substrate_reached_step"].as_u64().unwrap();
    let cps: Vec<(u64, f64, f64, f64)> = v["checkpoints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let f = |k: &str| c[k].as_f64().unwrap();
            (
                c["step"].as_u64().unwrap(),
                f("wavelength_m"),
                f("height_m"),
                f("bare_fraction"),
            )
        })
        .collect();
    for &(step, _, _, bare) in &cps {
        assert!((0.0..=1.0).contains(&bare));
        if step < first {
            assert_eq!(bare, 0.0, "{cps:?}");
        }
        if step == first {
            assert!(bare > 0.0, "{cps:?}");
        }
    }
    // the stalled field passes the 10 % test between two checkpoints on a bare bed, yet no
    // equilibrium is declared
    let close = |a: f64, b: f64| (b - a).abs() < 0.1 * a;
    assert!(
        cps.windows(2).any(|w| w[0].3 > 0.0
            && w[1].3 > 0.0
            && close(w[0].1, w[1].1)
            && close(w[0].2, w[1].2)),
        "{cps:?}"
    );
}

/// Waves in physical units: near-bed orbital velocity, period in seconds (converted with the
/// step duration), their own direction; the orbital diameter U_w T / pi is reported.
#[test]
fn waves_by_orbital_velocity_period_and_angle() {
    let run = |extra: &[&str]| {
        let mut args = vec![
            "ripple", "--recipe", "paper", "--layers", "10", "--seed", "3", "--json", "--d50",
            "0.3",
        ];
        if !extra.contains(&"--size") {
            args.extend(["--size", "24x12"]);
        }
        args.extend_from_slice(extra);
        cellsurf(&args)
    };
    let o = run(&[
        "--current-speed",
        "0",
        "--wave-velocity",
        "0.4",
        "--wave-period",
        "2.5s",
        "--steps",
        "200",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let d0 = v["orbital_diameter_m"].as_f64().unwrap();
    assert!(
        (d0 - 0.4 * 2.5 / std::f64::consts::PI).abs() < 1e-12,
        "{d0}"
    );
    let dt = v["step_duration_s"].as_f64().unwrap();
    let steps = v["wave_period_steps"].as_f64().unwrap();
    assert!((steps * dt - 2.5).abs() < 1e-9);
    assert_eq!(v["parameters"]["wave_amplitude"], 0.4);
    // at an angle to a current
    let o = run(&[
        "--current-speed",
        "0.3",
        "--wave-velocity",
        "0.4",
        "--wave-period",
        "3s",
        "--wave-angle",
        "60",
        "--steps",
        "200",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["parameters"]["wave_angle"], 60.0);
    // refused by name: a velocity without a period, a period shorter than two steps, an angle in 2-D
    for (extra, flag) in [
        (&["--wave-velocity", "0.4"][..], "--wave-velocity"),
        (
            &[
                "--wave-velocity",
                "0.4",
                "--wave-period",
                "0.01s",
                "--wave-friction-factor",
                "0",
            ][..],
            "--wave-period",
        ),
        (
            &[
                "--mode",
                "2d",
                "--size",
                "40x1",
                "--wave-velocity",
                "0.4",
                "--wave-period",
                "3s",
                "--wave-angle",
                "30",
            ][..],
            "--wave-angle",
        ),
    ] {
        let o = run(extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{extra:?}: {err}");
        assert!(err.contains(flag), "{extra:?}: {err}");
    }
}

/// Surface waves by linear wave theory: height, period and depth give the near-bed orbital
/// velocity `pi H / (T sinh kh)`; breaking waves, angles outside [-360, 360] and periods that
/// are not positive are refused by name.
#[test]
fn surface_waves_by_linear_theory_and_bad_wave_input() {
    let run = |extra: &[&str]| {
        let mut args = vec![
            "ripple",
            "--size",
            "24x12",
            "--layers",
            "10",
            "--seed",
            "3",
            "--steps",
            "100",
            "--json",
            "--d50",
            "0.3",
            "--current-speed",
            "0",
        ];
        args.extend_from_slice(extra);
        cellsurf(&args)
    };
    // T = 8 s, h = 10 m: k h = 0.8862; H = 1 m gives U_w = pi / (8 sinh 0.8862)
    let surface = [
        "--wave-height",
        "1",
        "--wave-period",
        "8s",
        "--water-depth",
        "10",
    ];
    let o = run(&surface);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // waves by their surface height get the lee vortex by default, as by their velocity
    let scenario = run(&[&surface[..], &["--print-scenario"]].concat()).stdout;
    assert!(String::from_utf8_lossy(&scenario).contains("\nwave_vortex = "));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let uw = v["wave_velocity_m_per_s"].as_f64().unwrap();
    assert!((uw - 0.39002).abs() < 1e-4, "{uw}");
    assert_eq!(v["parameters"]["wave_amplitude"].as_f64(), Some(uw));
    assert_eq!(v["water_depth_m"], 10.0);
    let d0 = v["orbital_diameter_m"].as_f64().unwrap();
    assert!((d0 - uw * 8.0 / std::f64::consts::PI).abs() < 1e-9, "{d0}");
    // the waves' own bed friction (Soulsby 1997, Eq. 60a): f_w = 1.39 (A / z0)^-0.52 with
    // A = d0 / 2 and z0 = d50 / 12; their Shields number is f_w / (2 C_D) times that of the
    // current's drag law (--wave-friction-factor 0)
    let fw = 1.39 * (0.5 * d0 / (0.3e-3 / 12.0)).powf(-0.52);
    let got = v["parameters"]["wave_friction_factor"].as_f64().unwrap();
    assert!((got - fw).abs() < 1e-12, "{got} {fw}");
    let o = run(&[&surface[..], &["--wave-friction-factor", "0"]].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v0: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v0["parameters"].get("wave_friction_factor").is_none());
    let ratio = v["shields"].as_f64().unwrap() / v0["shields"].as_f64().unwrap();
    assert!((ratio - fw / 2.0 / 0.0025).abs() < 1e-9, "{ratio}");
    // the prediction the run is checked against: Wiberg & Harris for a wave-dominated flow
    assert!(
        v["predictor"]
            .as_str()
            .unwrap()
            .starts_with("Wiberg & Harris (1994)"),
        "{}",
        v["predictor"]
    );
    for (extra, flag, range) in [
        (
            &[
                "--wave-height",
                "2",
                "--wave-period",
                "8s",
                "--water-depth",
                "2",
            ][..],
            "--wave-height",
            "0.78",
        ),
        (
            &[
                "--wave-height",
                "-1",
                "--wave-period",
                "8s",
                "--water-depth",
                "5",
            ][..],
            "--wave-height",
            "(0, 100]",
        ),
        (
            &["--current-angle", "400"][..],
            "--current-angle",
            "[-360, 360]",
        ),
        (
            &[
                "--wave-velocity",
                "0.3",
                "--wave-period",
                "4s",
                "--wave-angle",
                "-361",
            ][..],
            "--wave-angle",
            "[-360, 360]",
        ),
        (
            &["--wave-velocity", "0.3", "--wave-period", "0"][..],
            "--wave-period",
            "above 0",
        ),
        (
            &["--wave-velocity", "0.3", "--wave-period", "-4s"][..],
            "--wave-period",
            "above 0",
        ),
        (
            &["--duration", "two hours"][..],
            "--duration",
            "s, min, h or d",
        ),
        (
            &[
                "--wave-velocity",
                "0.3",
                "--wave-period",
                "4s",
                "--wave-friction-factor",
                "2",
            ][..],
            "--wave-friction-factor",
            "[0, 1]",
        ),
    ] {
        assert_refused(extra, &run(extra), flag, range);
    }
}

/// The lee vortex's flags: on by default with waves and a period, off with `--no-wave-vortex`;
/// each flag rejects what it cannot act on, naming itself; a current that dominates the waves
/// turns an explicitly asked vortex off with a warning (and a default one silently); and a run
/// with it is recorded.
#[test]
fn wave_vortex_flags_and_bad_input() {
    let run = |extra: &[&str]| cellsurf(&[SMALL, extra].concat());
    let waves = WAVES;
    for (extra, flag, why) in [
        (&["--wave-vortex"][..], "--wave-vortex", "--wave-period"),
        (
            &[
                "--wave-vortex",
                "--wave-velocity",
                "0",
                "--wave-period",
                "2s",
            ][..],
            "--wave-vortex",
            "--wave-velocity = 0 gives none",
        ),
        (
            &["--no-wave-vortex"][..],
            "--no-wave-vortex",
            "there are none",
        ),
        (
            &["--vortex-strength", "0.3"][..],
            "--vortex-strength",
            "there are no waves",
        ),
        (
            &[
                &waves[..],
                &["--no-wave-vortex", "--vortex-strength", "0.3"],
            ]
            .concat()[..],
            "--vortex-strength",
            "--no-wave-vortex switched it off",
        ),
        (
            &[&waves[..], &["--no-wave-vortex", "--wave-vortex"]].concat()[..],
            "--no-wave-vortex",
            "cannot be used with",
        ),
        (
            &[&waves[..], &["--wave-vortex", "--vortex-strength", "1.5"]].concat()[..],
            "--vortex-strength",
            "[0, 1]",
        ),
        (
            &[&waves[..], &["--wave-vortex", "--vortex-strength", "nan"]].concat()[..],
            "--vortex-strength",
            "[0, 1]",
        ),
    ] {
        assert_refused(extra, &run(extra), flag, why);
    }
    // a combined flow where the current dominates: warned when the vortex is asked for, not
    // by default
    let combined = [
        "--current-speed",
        "0.5",
        "--wave-velocity",
        "0.1",
        "--wave-period",
        "2s",
    ];
    for (extra, warned) in [
        (&["--wave-vortex"][..], Some("--wave-vortex")),
        (&["--vortex-strength", "0.3"][..], Some("--vortex-strength")),
        (&[][..], None),
    ] {
        let o = run(&[&combined[..], extra].concat());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{err}");
        match warned {
            Some(flag) => assert!(
                err.contains(flag) && err.contains("the vortex is off"),
                "{extra:?}: {err}"
            ),
            None => assert!(!err.contains("vortex"), "{extra:?}: {err}"),
        }
    }
    // and the same bed as without it, byte for byte (the vortex acts only where the waves
    // dominate), where waves alone get another bed from it
    let bed = |flow: &[&str], extra: &[&str], name: &str| {
        let out = tmp(name);
        let o = cellsurf(
            &[
                &["ripple", "--size", "24x12", "--layers", "10", "--seed", "3"][..],
                flow,
                &["--steps", "400", "--quiet", "--out", out.to_str().unwrap()][..],
                extra,
            ]
            .concat(),
        );
        assert_eq!(o.status.code(), Some(0), "{flow:?} {extra:?}");
        std::fs::read(&out).unwrap()
    };
    assert_eq!(
        bed(&combined, &[], "vortex-combined-on.npy"),
        bed(&combined, &["--no-wave-vortex"], "vortex-combined-off.npy")
    );
    assert_ne!(
        bed(&waves, &[], "vortex-waves-on.npy"),
        bed(&waves, &["--no-wave-vortex"], "vortex-waves-off.npy")
    );
    // A = U_w T / (2 pi) = 0.4 x 2 / (2 pi) m, by default and when asked for; absent (0) when
    // switched off
    let recorded = |extra: &[&str]| -> Option<f64> {
        let o = run(&[&waves[..], extra, &["--print-scenario"]].concat());
        assert_eq!(o.status.code(), Some(0), "{extra:?}");
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .find_map(|l| l.strip_prefix("wave_vortex = "))
            .map(|v| v.parse().unwrap())
    };
    for extra in [&[][..], &["--wave-vortex"][..]] {
        let a = recorded(extra).expect("wave_vortex recorded");
        assert!(
            (a - 0.8 / (2.0 * std::f64::consts::PI)).abs() < 1e-12,
            "{extra:?}: {a}"
        );
    }
    assert_eq!(recorded(&["--no-wave-vortex"]), None);
    // a scenario file's own vortex: kept without --wave-period (with a warning where the waves
    // change), cleared by --no-wave-vortex; a file without the key has none
    let file = tmp("vortex-scenario.toml");
    std::fs::write(
        &file,
        run(&[&waves[..], &["--print-scenario"]].concat()).stdout,
    )
    .unwrap();
    let from_file = |extra: &[&str]| {
        let o = cellsurf(
            &[
                &[
                    "ripple",
                    "--scenario",
                    file.to_str().unwrap(),
                    "--print-scenario",
                ][..],
                extra,
            ]
            .concat(),
        );
        assert_eq!(o.status.code(), Some(0), "{extra:?}");
        (
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .find_map(|l| l.strip_prefix("wave_vortex = "))
                .map(|v| v.parse::<f64>().unwrap()),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let a = 0.8 / (2.0 * std::f64::consts::PI);
    let (kept, err) = from_file(&[]);
    assert_eq!(kept, Some(a));
    assert!(!err.contains("wave_vortex"), "{err}");
    let (kept, err) = from_file(&["--wave-velocity", "0.6"]);
    assert_eq!(kept, Some(a));
    assert!(
        err.contains("wave_vortex") && err.contains("is kept"),
        "{err}"
    );
    assert_eq!(from_file(&["--no-wave-vortex"]).0, None);
    let text = std::fs::read_to_string(&file).unwrap();
    let without: String = text
        .lines()
        .filter(|l| !l.starts_with("wave_vortex"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&file, without).unwrap();
    assert_eq!(from_file(&[]).0, None);
}

/// A domain shorter than 4 wavelengths along the flow of the ripple the run builds (the
/// predictor's with the paper's rules, the recipe's own 66 travels with the recipe for mature
/// current ripples) gets a warning naming both lengths; a long enough one gets none.
#[test]
fn domain_shorter_than_four_predicted_wavelengths_is_warned() {
    let run = |size: &str, angle: &str| {
        cellsurf(&[
            "ripple",
            "--recipe",
            "paper",
            "--size",
            size,
            "--layers",
            "10",
            "--steps",
            "20",
            "--current-angle",
            angle,
        ])
    };
    // 0.2 mm sand: Soulsby & Whitehouse predict 0.146 m, 4 wavelengths 0.584 m; the domain's
    // length along the flow is its x side in the flow frame (the default)
    let o = run("64x128", "90");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("0.320 m") && err.contains("0.584 m") && err.contains("Soulsby"),
        "{err}"
    );
    for angle in ["0", "90"] {
        let o = run("128x64", angle);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{err}");
        assert!(!err.contains("less than 4 wavelengths"), "{angle}: {err}");
    }
    // the recipe's own ripples: 66 travels, 0.163 m at the default (0.654 m for 4), on 128 bins
    // of 1.86 mm; at 0.35 m/s its 1024 bins of 0.551 mm (0.564 m) hold 11 of its 5 cm ripples
    // though fewer than 4 of the predictor's
    let recipe = |args: &[&str]| {
        let mut all = vec!["ripple", "--steps", "1", "--json"];
        all.extend_from_slice(args);
        let o = cellsurf(&all);
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{err}");
        err
    };
    let err = recipe(&["--size", "128x1"]);
    assert!(
        err.contains("0.238 m long")
            && err.contains("recipe mature-current's, 66 flat-bed travels: 4 x 0.163 m = 0.654 m"),
        "{err}"
    );
    let err = recipe(&["--current-speed", "0.35"]);
    assert!(!err.contains("less than 4 wavelengths"), "{err}");
}

/// A bin longer than half the lee face of the predicted ripple (`H / (2 tan alpha)`) gets a
/// warning naming the bin, that length and the predicted height; bins of 5 mm and 1 cm get none.
#[test]
fn bin_longer_than_half_the_predicted_lee_face_is_warned() {
    // stderr of a run that succeeds, on 64 x 8 bins of `bin` m (automata of a tenth of it)
    let stderr_of = |bin: &str, extra: &[&str]| {
        let lt = format!("{}", bin.parse::<f64>().unwrap() / 10.0);
        let mut args = vec![
            "ripple", "--layers", "10", "--steps", "20", "--size", "64x8",
        ];
        args.extend_from_slice(&["--bin-size", bin, "--layer-thickness", &lt]);
        args.extend_from_slice(extra);
        let o = cellsurf(&args);
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{err}");
        err
    };
    // 0.2 mm sand: Soulsby & Whitehouse predict H = 0.0186 m; at alpha = 32 deg half its lee
    // face is 0.0149 m. A 2 cm bin (1.28 m along the flow: no domain warning) is warned,
    let err = stderr_of("0.02", &[]);
    for part in ["--bin-size = 0.02 m", "0.0149 m", "0.0186 m", "Soulsby"] {
        assert!(err.contains(part), "{part}: {err}");
    }
    // a steeper avalanche angle shortens the face: 1 cm bins are warned at alpha = 60 deg
    assert!(stderr_of("0.01", &["--avalanche-angle", "60"]).contains("0.0054 m"));
    // and 5 mm or 1 cm bins at alpha = 32 deg are not
    for bin in ["0.005", "0.01"] {
        let err = stderr_of(bin, &[]);
        assert!(!err.contains("half the lee face"), "{bin}: {err}");
    }
}

/// The flow frame (the default) runs the lattice with its x axis along the current: the bed is
/// the same whatever the current's angle (the lattice no longer pulls the crests towards its
/// axes and diagonals), the crest normal is reported from east (the lattice's normal plus the
/// angle), and the x axis's direction is recorded; `--frame grid` keeps the lattice east and
/// is recorded in the parameters; in 2-D both frames run the same section at 0 and 180 deg.
#[test]
fn flow_frame_turns_the_lattice_with_the_current() {
    let run = |args: &[&str]| {
        let mut all = vec![
            "ripple", "--layers", "10", "--steps", "600", "--seed", "2", "--json",
        ];
        if !args.contains(&"--size") {
            all.extend_from_slice(&["--size", "48x24"]);
        }
        all.extend_from_slice(args);
        let o = cellsurf(&all);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let a0 = run(&["--current-angle", "0"]);
    let a35 = run(&["--current-angle", "35"]);
    assert_eq!(a35["x_axis_direction_deg"], 35.0);
    assert!(a35["parameters"].get("frame").is_none(), "the default");
    let same = |a: &serde_json::Value, b: &serde_json::Value| {
        for k in [
            "parameters",
            "wavelength_m",
            "height_m",
            "crest_normal_deg",
            "activations",
        ] {
            assert_eq!(a[k], b[k], "{k}");
        }
    };
    same(&run(&["--current-angle", "35", "--frame", "flow"]), &a35);
    assert_eq!(a0["wavelength_m"], a35["wavelength_m"]);
    assert_eq!(a0["height_m"], a35["height_m"]);
    let n0 = a0["crest_normal_deg"].as_f64().unwrap();
    let n35 = a35["crest_normal_deg"].as_f64().unwrap();
    let d = (n35 - n0 - 35.0).rem_euclid(180.0);
    assert!(d.min(180.0 - d) < 1e-9, "{n0} {n35}");
    // the grid frame runs another bed at 35 deg, its x axis east
    let g35 = run(&["--current-angle", "35", "--frame", "grid"]);
    assert_eq!(g35["x_axis_direction_deg"], 0.0);
    assert_eq!(g35["parameters"]["frame"], "grid");
    assert_ne!(g35["height_m"], a35["height_m"]);
    // 2-D at 180 deg: the same section in either frame, its x axis east
    let two_d = |frame: &str| {
        let mut v = run(&[
            "--mode",
            "2d",
            "--size",
            "40x1",
            "--current-angle",
            "180",
            "--frame",
            frame,
        ]);
        v["parameters"]["frame"] = serde_json::Value::Null;
        (
            v["wavelength_m"].clone(),
            v["height_m"].clone(),
            v["x_axis_direction_deg"].clone(),
        )
    };
    assert_eq!(two_d("flow"), two_d("grid"));
    assert_eq!(two_d("flow").2, 0.0);
}

/// Flags the run does not use are warned about, naming the flag and why, and the run goes on:
/// the volume's options without a volume output, and the stoss cap where the waves dominate.
/// Where they act (with `--out`; under a current) there is no such warning.
#[test]
fn flags_without_effect_are_warned() {
    let stderr = |extra: &[&str]| {
        let mut args = SMALL.to_vec();
        args.extend_from_slice(extra);
        args.push("--json");
        let o = cellsurf(&args);
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{extra:?}: {err}");
        err
    };
    let e = stderr(&["--snapshots", "20,40", "--fields", "grain_size"]);
    assert!(
        e.contains("warning: --fields and --snapshots have no effect without a volume output"),
        "{e}"
    );
    let e = stderr(&["--acoustics", "apl-uw"]);
    assert!(
        e.contains("warning: --acoustics has no effect without a volume output"),
        "{e}"
    );
    let waves = WAVES;
    let mut w = waves.to_vec();
    w.extend(["--stoss-angle", "5"]);
    let e = stderr(&w);
    assert!(
        e.contains("warning: --stoss-angle = 5 deg has no effect here"),
        "{e}"
    );
    let out = tmp("flags.nc");
    let out = out.to_str().unwrap();
    for extra in [
        &[
            "--snapshots",
            "20,40",
            "--fields",
            "grain_size",
            "--out",
            out,
        ][..],
        &["--stoss-angle", "5"][..],
    ] {
        let e = stderr(extra);
        assert!(!e.contains("no effect"), "{extra:?}: {e}");
    }
}

/// The volume's size limit states the formula it checks, with the run's numbers: evaluated on
/// a refused size it exceeds the stated limit, and on the accepted neighbour (one layer less)
/// it does not.
#[test]
fn the_size_limit_states_the_formula_it_checks() {
    let o = cellsurf(&[
        "ripple",
        "--size",
        "8192x8192",
        "--layers",
        "63",
        "--print-scenario",
    ]);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("--size (nx) = 8192 is out of range"), "{err}");
    let num = |after: &str| -> u128 {
        let rest =
            &err[err.find(after).unwrap_or_else(|| panic!("{after}: {err}")) + after.len()..];
        let digits: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
        digits.parse().unwrap_or_else(|_| panic!("{after}: {err}"))
    };
    let limit = num("at most 2^33 = ");
    assert_eq!(limit, 1 << 33);
    // "layers + roughness + headroom = L + R + H = CAP", "here NX x NY x CAP = SLOTS"
    let (layers, roughness) = (
        num("layers + roughness + headroom = "),
        num("layers + roughness + headroom = 63 + "),
    );
    let headroom = num(&format!("= {layers} + {roughness} + "));
    let cap = layers + roughness + headroom;
    assert_eq!(layers, 63);
    assert_eq!(num(&format!("{headroom} = ")), cap, "{err}");
    assert!(err.contains("max(layers, 48)"), "{err}");
    let slots = num(&format!("here 8192 x 8192 x {cap} = "));
    assert_eq!(slots, 8192 * 8192 * cap);
    assert!(slots > limit, "{err}");
    // the neighbour: one layer less, its automatic headroom max(62, 48) = 62
    let o = cellsurf(&[
        "ripple",
        "--size",
        "8192x8192",
        "--layers",
        "62",
        "--print-scenario",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(8192 * 8192 * (62 + roughness + 62) <= limit);
}

/// `--print-scenario` keeps what was asked in seconds, `duration_s` and `wave_period_s` in
/// place of `steps` and `wave_period` in steps: the scenario reruns the same run, whose output
/// file is byte for byte the direct run's (which records `duration_s` and `wave_period_s`);
/// a run given in steps keeps its steps.
#[test]
fn a_printed_scenario_keeps_the_seconds_and_reruns_the_same_bytes() {
    let base = [
        "ripple",
        "--size",
        "24x12",
        "--layers",
        "10",
        "--current-angle",
        "30",
        "--d50",
        "0.3",
    ];
    let waves = ["--wave-velocity", "0.2", "--wave-period", "8s"];
    for (i, extra) in [
        vec!["--duration", "20s"],
        [&["--duration", "20s"][..], &waves[..]].concat(),
        [&["--steps", "300"][..], &waves[..]].concat(),
        vec!["--steps", "300"],
    ]
    .iter()
    .enumerate()
    {
        let args = [&base[..], &extra[..]].concat();
        let o = cellsurf(&[&args[..], &["--print-scenario"]].concat());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = String::from_utf8_lossy(&o.stdout).into_owned();
        let has = |k: &str| text.lines().any(|l| l.starts_with(&format!("{k} = ")));
        let (duration, period) = (
            extra.contains(&"--duration"),
            extra.contains(&"--wave-period"),
        );
        assert_eq!(has("duration_s"), duration, "{extra:?}\n{text}");
        assert_eq!(has("steps"), !duration, "{extra:?}\n{text}");
        assert_eq!(has("wave_period_s"), period, "{extra:?}\n{text}");
        assert_eq!(has("wave_period"), !period, "{extra:?}\n{text}");
        let scene = tmp(&format!("seconds-{i}.toml"));
        std::fs::write(&scene, &text).unwrap();
        let (direct, rerun) = (
            tmp(&format!("seconds-d{i}.nc")),
            tmp(&format!("seconds-s{i}.nc")),
        );
        let o = cellsurf(&[&args[..], &["--out", direct.to_str().unwrap(), "--quiet"]].concat());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let o = cellsurf(&[
            "ripple",
            "--scenario",
            scene.to_str().unwrap(),
            "--out",
            rerun.to_str().unwrap(),
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let (d, s) = (
            std::fs::read(&direct).unwrap(),
            std::fs::read(&rerun).unwrap(),
        );
        // a NetCDF attribute's name, after its length (not the tail of `step_duration_s`)
        let holds = |b: &[u8], name: &[u8]| {
            let key = [&(name.len() as u32).to_be_bytes()[..], name].concat();
            b.windows(key.len()).any(|w| w == key)
        };
        assert_eq!(holds(&d, b"duration_s"), duration, "{extra:?}");
        assert_eq!(holds(&d, b"wave_period_s"), period, "{extra:?}");
        assert!(
            d == s,
            "{extra:?}: the rerun's file differs from the direct run's"
        );
    }
}

/// A scenario's keys in seconds: `duration_s` and `wave_period_s` are converted to steps as
/// `--duration` and `--wave-period` are, and a file that also gives `steps` or `wave_period`
/// (the same quantity in steps) is refused naming both keys; --steps typed over a file's
/// `duration_s` wins, as any option typed over a scenario.
#[test]
fn scenario_keys_in_seconds_and_their_steps_are_not_both_given() {
    let dir = env!("CARGO_MANIFEST_DIR");
    let good = format!("{dir}/tests/fixtures/ripple_seconds.toml");
    let json = |extra: &[&str]| -> serde_json::Value {
        let o = cellsurf(
            &[
                &["ripple", "--scenario", &good, "--json", "--quiet"][..],
                extra,
            ]
            .concat(),
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let v = json(&[]);
    let step = v["step_duration_s"].as_f64().unwrap();
    assert_eq!(v["duration_s"], 20.0);
    assert_eq!(v["wave_period_s"], 8.0);
    assert_eq!(v["steps"].as_u64(), Some((20.0 / step).round() as u64));
    assert!((v["wave_period_steps"].as_f64().unwrap() - 8.0 / step).abs() < 1e-9);
    let v = json(&["--steps", "50"]);
    assert_eq!(v["steps"], 50);
    assert_eq!(v["duration_s"], serde_json::Value::Null);
    for (file, keys) in [
        (
            "ripple_bad_steps_and_duration.toml",
            ["steps = 100", "duration_s = 20"],
        ),
        (
            "ripple_bad_wave_period_twice.toml",
            ["wave_period = 1000.0", "wave_period_s = 8"],
        ),
    ] {
        let o = cellsurf(&[
            "ripple",
            "--scenario",
            &format!("{dir}/tests/fixtures/{file}"),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{file}: {err}");
        assert!(
            keys.iter().all(|k| err.contains(k)) && err.contains(file),
            "{err}"
        );
        assert!(err.contains("keep one"), "{err}");
    }
}

/// `--recipe mature-current` starts from the built-in recipe (the keys of
/// docs/ripple_mature_current.toml), options typed with it override it, it cannot be given
/// with `--scenario`, an unknown name is refused naming the valid one, and it warns where the
/// waves dominate (it is for currents).
#[test]
fn the_recipe_flag_starts_from_the_built_in_recipe() {
    use cellsurf::ripple::RippleParams;
    use cellsurf::ripple::recipe::Recipe;
    let o = cellsurf(&[
        "ripple",
        "--recipe",
        "mature-current",
        "--d50",
        "0.3",
        "--print-scenario",
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // without a length it runs until equilibrium, for at most 6 h of flow
    assert!(
        text.contains("\nduration_s = 21600.0\n") && text.contains("\nuntil = \"equilibrium\"\n"),
        "{text}"
    );
    let keys: String = text
        .lines()
        .filter(|l| !l.starts_with("duration_s"))
        .map(|l| format!("{l}\n"))
        .collect();
    let printed = RippleParams::from_toml(&keys).unwrap();
    // on its bin of 0.75 flat-bed travels of the 0.3 mm grain, the automata following
    let expected = RippleParams {
        d50: 0.3,
        until: Some("equilibrium".into()),
        ..Recipe::MatureCurrent.params()
    }
    .with_travel_bin();
    assert!(expected.bin_size != Recipe::MatureCurrent.params().bin_size);
    assert_eq!(printed, expected, "{text}");
    let file = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/docs/ripple_mature_current.toml"
    ))
    .unwrap();
    assert_eq!(
        RippleParams::from_toml(&file).unwrap(),
        Recipe::MatureCurrent.params()
    );

    let scene = tmp("recipe_scene.toml");
    std::fs::write(&scene, "model = \"ripple\"\nd50 = 0.3\n").unwrap();
    let args = [
        "ripple",
        "--recipe",
        "mature-current",
        "--scenario",
        scene.to_str().unwrap(),
        "--print-scenario",
    ];
    let o = cellsurf(&args);
    assert_refused(&args, &o, "--recipe", "--scenario");

    let args = ["ripple", "--recipe", "mature", "--print-scenario"];
    // the recipe runs a 2-D section: a short one of 64 bins
    let recipe_small = [
        "ripple", "--size", "64x1", "--layers", "20", "--steps", "40", "--seed", "3",
    ];
    let o = cellsurf(&args);
    assert_refused(&args, &o, "recipe", "mature-current");

    let mut args = recipe_small.to_vec();
    args.extend(["--recipe", "mature-current"]);
    args.extend(WAVES);
    let o = cellsurf(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("warning: --recipe mature-current is for currents"),
        "{err}"
    );
    // (one warning: the recipe's own says it; its face hold read from a file is warned of)
    assert!(!err.contains("stoss_face_hold"), "{err}");
    let file = tmp("recipe-under-waves.toml");
    let printed = cellsurf(&[&args[..], &["--print-scenario"]].concat());
    std::fs::write(&file, printed.stdout).unwrap();
    let o = cellsurf(&[
        "ripple",
        "--scenario",
        file.to_str().unwrap(),
        "--steps",
        "40",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success()
            && err.contains("warning: stoss_face_hold = true has no effect here")
            && err.contains("the waves dominate"),
        "{err}"
    );
    let mut args = recipe_small.to_vec();
    args.extend(["--recipe", "mature-current"]);
    let o = cellsurf(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && !err.contains("is for currents"),
        "{err}"
    );
    // the recipe's bins of 2.5 mm are about the travel of 0.2 mm sand (2.48 mm at 0.5 m/s);
    // 5 mm bins are three times that of 0.1 mm sand (1.64 mm)
    assert!(!err.contains("travel on a flat bed"), "{err}");
    let mut args = recipe_small.to_vec();
    args.extend([
        "--recipe",
        "mature-current",
        "--d50",
        "0.1",
        "--bin-size",
        "0.005",
    ]);
    args.extend(["--layer-thickness", "0.0005"]);
    let o = cellsurf(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success()
            && err.contains("--bin-size = 0.005 m is more than twice the median grain's travel on a flat bed (0.001644 m"),
        "{err}"
    );
}

/// `cellsurf ripple EXTRA --print-scenario`, which must succeed: its scenario file and its
/// standard error.
fn printed_scenario(extra: &[&str]) -> (String, String) {
    let mut a = vec!["ripple"];
    a.extend_from_slice(extra);
    a.push("--print-scenario");
    let o = cellsurf(&a);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (
        String::from_utf8_lossy(&o.stdout).to_string(),
        String::from_utf8_lossy(&o.stderr).to_string(),
    )
}

/// That a printed ripple scenario `s` has automata of `thickness` (m, as printed) and `layers`.
fn assert_automata(s: &str, thickness: &str, layers: usize) {
    assert!(
        s.contains(&format!("\nlayer_thickness = {thickness}\n"))
            && s.contains(&format!("\nlayers = {layers}\n")),
        "{s}"
    );
}

/// A 2-D section runs along the current whatever its direction (the flow frame): rotating
/// the current rotates the section and its crests, not its physics (the same bed, byte for
/// byte, as along the x axis), and the outputs say where its x axis points.
#[test]
fn an_oblique_current_runs_its_section_along_it() {
    let run = |angle: &str| {
        let o = cellsurf(&[
            "ripple",
            "--size",
            "128x1",
            "--current-angle",
            angle,
            "--duration",
            "300",
            "--seed",
            "2",
            "--json",
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    for (a, along, x_axis) in [("30", "0", 30.0), ("150", "180", 330.0)] {
        let (v, w) = (run(a), run(along));
        for key in ["wavelength_m", "height_m", "activations", "hops"] {
            assert_eq!(v[key], w[key], "{a} {key}");
        }
        assert_eq!(v["x_axis_direction_deg"], x_axis, "{a}");
        let normal = v["crest_normal_deg"].as_f64().unwrap();
        let want: f64 = a.parse().unwrap();
        assert!((normal - want).abs() < 1e-9, "{a}: {normal}");
        assert_eq!(v["predicted_crest_normal_deg"], want, "{a}");
    }
}

/// The recipe for mature current ripples is one resolution: `--bin-size` alone brings its
/// automata (a tenth of the bin) and its 10 cm of sand along, saying so; a typed
/// `--layer-thickness` or `--layers` wins; the paper's rules and scenario files keep their
/// automata; a bin too
/// fine for 10 cm of sand in at most 4096 layers is refused naming `--bin-size`; and the run
/// is the one typed in full, byte for byte.
#[test]
fn the_recipes_bin_size_brings_its_automata_along() {
    let scenario = printed_scenario;
    let (s, e) = scenario(&["--bin-size", "0.005"]);
    assert_automata(&s, "0.0005", 200);
    assert!(
        e.contains("--layer-thickness = 0.0005 m and --layers = 200 (0.1 m of sand)"),
        "{e}"
    );
    let (s, e) = scenario(&["--bin-size", "0.00125", "--layers", "100"]);
    assert_automata(&s, "0.000125", 100);
    assert!(
        e.contains("gives --layer-thickness = 0.000125 m (give --layer-thickness"),
        "{e}"
    );
    // a bin that is not round: the thickness as if typed, the depth said as it is
    let (s, e) = scenario(&["--bin-size", "0.003"]);
    assert_automata(&s, "0.0003", 333);
    assert!(e.contains("--layers = 333 (0.1 m of sand)"), "{e}");
    // a 3-D field and --quiet: the same automata, the note not with --quiet
    let (s, _) = scenario(&["--bin-size", "0.005", "--mode", "3d", "--quiet"]);
    assert!(
        s.contains("\nlayer_thickness = 0.0005\n") && s.contains("\nmode = \"3d\"\n"),
        "{s}"
    );
    let o = cellsurf(&[
        "ripple",
        "--bin-size",
        "0.005",
        "--quiet",
        "--print-scenario",
    ]);
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // a scenario file keeps its own automata: --bin-size alone changes the bin only
    let dir = std::env::temp_dir().join(format!("cellsurf-binfollow-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("recipe.toml");
    std::fs::write(&file, printed_scenario(&[]).0).unwrap();
    let (s, e) = scenario(&["--scenario", file.to_str().unwrap(), "--bin-size", "0.005"]);
    // (the printed recipe's automata: a tenth of its bin of 0.75 travels, 1.86 mm at 0.2 mm)
    assert!(
        s.contains("\nbin_size = 0.005\n") && s.contains("\nlayer_thickness = 0.000186\n"),
        "{s}"
    );
    assert!(!e.contains("tenth of the bin"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
    let (s, e) = scenario(&["--bin-size", "0.005", "--layer-thickness", "0.00025"]);
    assert_automata(&s, "0.00025", 400);
    assert!(!e.contains("tenth of the bin"), "{e}");
    let (s, e) = scenario(&["--recipe", "paper", "--bin-size", "0.01"]);
    assert_automata(&s, "0.0005", 30);
    assert!(!e.contains("tenth of the bin"), "{e}");
    let o = cellsurf(&["ripple", "--bin-size", "0.0000001", "--size", "32x1"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(!e.contains("panicked"), "{e}");
    assert!(
        e.contains("--bin-size = 1e-7 m is out of range")
            && e.contains("at most 4096 layers: expected --bin-size of at least 0.000245 m"),
        "{e}"
    );
    // the same run as the one typed in full
    let run = |extra: &[&str]| {
        let mut a = vec![
            "ripple",
            "--size",
            "64x1",
            "--duration",
            "60",
            "--seed",
            "3",
            "--json",
            "--quiet",
            "--bin-size",
            "0.005",
        ];
        a.extend_from_slice(extra);
        let o = cellsurf(&a);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let mut v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        for k in ["elapsed_s", "setup_s", "steps_per_s"] {
            v[k] = serde_json::Value::Null;
        }
        v
    };
    assert_eq!(
        run(&[]),
        run(&["--layer-thickness", "0.0005", "--layers", "200"])
    );
}

/// Without `--recipe` or `--scenario`, a current's run starts from the recipe for mature
/// current ripples and runs until its field is mature (at most 6 h of flow): a section of
/// 256 of its bins (0.48 m in bins of 1.86 mm) stops at equilibrium with ripples of a
/// current's shape (measured: 1674 s, 15.9 cm, 1.54 cm, ripple index 10.3, lee 30.4 deg,
/// symmetry index 3.0; Soulsby & Whitehouse predict 14.6 cm and 1.86 cm at 0.2 mm).
/// Where the waves dominate it starts from the paper's rules; a size sets the mode, `--mode
/// 3d` alone a 3-D field of 384 x 64 bins, and a typed length runs without the stop.
#[test]
fn the_default_run_is_the_mature_current_recipe_until_equilibrium() {
    let o = cellsurf(&[
        "ripple", "--size", "256x1", "--seed", "1", "--json", "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["recipe"], "mature-current");
    assert_eq!(v["until"], "equilibrium");
    assert_eq!(v["duration_s"], 21600.0);
    // bins of 0.75 flat-bed travels of the 0.2 mm grain (2.48 mm at 0.5 m/s)
    assert_eq!(v["parameters"]["bin_size"], 0.00186);
    assert_eq!(v["parameters"]["bin_travels"], 0.75);
    assert_eq!(v["parameters"]["mode"], "2d");
    assert_eq!(v["equilibrium"], true, "{v}");
    let t = v["simulated_time_s"].as_f64().unwrap();
    assert!(t < 21600.0, "{t}");
    let (l, h) = (
        v["wavelength_m"].as_f64().unwrap(),
        v["height_m"].as_f64().unwrap(),
    );
    let (ri, lee, si) = (
        v["ripple_index"].as_f64().unwrap(),
        v["lee_slope_deg"].as_f64().unwrap(),
        v["symmetry_index"].as_f64().unwrap(),
    );
    // against the predictor's 14.6 cm and 1.86 cm: the 20 % and 25 %; the shape of
    // current ripples (ripple index 6-12, slip faces, asymmetric)
    assert!((l / 0.146 - 1.0).abs() < 0.2, "{l}");
    assert!((h / 0.0186 - 1.0).abs() < 0.25, "{h}");
    assert!(
        (6.0..=12.0).contains(&ri) && lee >= 28.0 && si >= 2.0,
        "{ri} {lee} {si}"
    );

    let scenario = |extra: &[&str]| printed_scenario(extra).0;
    // waves dominating: the paper's rules, 5 mm bins, the fixed steps, and the JSON says so
    let mut a = vec![
        "ripple", "--size", "24x12", "--layers", "10", "--steps", "20", "--json",
    ];
    a.extend(WAVES);
    let o = cellsurf(&a);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let w: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(w["recipe"], "paper");
    let s = scenario(&WAVES);
    assert!(
        s.contains("\nbin_size = 0.005\n") && !s.contains("until") && !s.contains("hop_grains"),
        "{s}"
    );
    // a size NXxNY makes it 3-D, NXx1 a section; --mode 3d alone 384 x 64 bins
    let s = scenario(&["--size", "24x12"]);
    assert!(
        s.contains("\nmode = \"3d\"\n") && s.contains("\nbin_size = 0.00186\n"),
        "{s}"
    );
    let s = scenario(&["--recipe", "paper", "--size", "64x1"]);
    assert!(
        s.contains("\nmode = \"2d\"\n") && s.contains("\nbin_size = 0.005\n"),
        "{s}"
    );
    let s = scenario(&["--mode", "3d"]);
    assert!(s.contains("\nnx = 384\nny = 64\n"), "{s}");
    let s = scenario(&["--mode", "3d", "--ny", "32"]);
    assert!(s.contains("\nnx = 384\nny = 32\n"), "{s}");
    // the old spelling of the x side keeps it, the y side from the 3-D default
    let s = scenario(&["--nx", "512", "--mode", "3d"]);
    assert!(s.contains("\nnx = 512\nny = 64\n"), "{s}");
    // the waves' dominance read from the options, even where the paper's lattice would be
    // refused (here too many automata slots for 64 rows): still the paper's rules, refused
    let mut a = vec![
        "ripple",
        "--nx",
        "65536",
        "--layers",
        "4000",
        "--print-scenario",
    ];
    a.extend(WAVES);
    let o = cellsurf(&a);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("65536 x 64"), "{err}");
    // options that leave the recipe's flow separation no room, or a direction across its
    // section: refused, saying what the recipe has to do with it
    for (extra, says) in [
        (&["--abstraction", "shadow"][..], "--recipe paper"),
        (&["--avalanche-angle", "15"][..], "--recipe paper"),
        (
            &["--current-angle", "30", "--frame", "grid"][..],
            "--mode 3d for a 3-D field, or leave out --frame grid",
        ),
    ] {
        let mut a = vec!["ripple", "--print-scenario"];
        a.extend_from_slice(extra);
        let o = cellsurf(&a);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            o.status.code() == Some(1) && err.contains("mature-current") && err.contains(says),
            "{extra:?}: {err}"
        );
    }
    // the printed default reruns the same run, its stop and cap with it
    let dir = std::env::temp_dir().join(format!("cellsurf-default-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("default.toml");
    std::fs::write(&file, scenario(&["--size", "256x1", "--seed", "1"])).unwrap();
    let o = cellsurf(&[
        "ripple",
        "--scenario",
        file.to_str().unwrap(),
        "--json",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let w: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for key in [
        "parameters",
        "stop_step",
        "wavelength_m",
        "height_m",
        "until",
    ] {
        assert_eq!(v[key], w[key], "{key}");
    }
    assert!(w["recipe"].is_null());
    let _ = std::fs::remove_dir_all(&dir);
    // a typed length: that long, no stop
    let s = scenario(&["--duration", "600s"]);
    assert!(
        s.contains("\nduration_s = 600.0\n") && !s.contains("until"),
        "{s}"
    );
    let s = scenario(&["--steps", "500"]);
    assert!(s.contains("\nsteps = 500\n") && !s.contains("until"), "{s}");
}

/// The defaults `--help` gives for each recipe are the recipes' own values (the help's text
/// is written by hand).
#[test]
fn help_gives_each_recipes_own_defaults() {
    use cellsurf::ripple::recipe::Recipe;
    let o = cellsurf(&["ripple", "--help"]);
    let help = String::from_utf8_lossy(&o.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    let (m, p) = (Recipe::MatureCurrent.params(), Recipe::Paper.params());
    for said in [
        format!("[default: mature-current {}x{},", m.nx, m.ny),
        format!("paper {}x{}]", p.nx, p.ny),
        format!(
            "[default: mature-current 10 cm of sand, {} in its bins for 0.2 mm sand at 0.5 m/s; paper {}]",
            m.with_travel_bin().layers,
            p.layers
        ),
        format!(
            "[default: mature-current {} flat-bed travels of the median grain in the current (bin_travels), {} for 0.2 mm sand at 0.5 m/s; paper {}]",
            m.bin_travels,
            m.with_travel_bin().bin_size,
            p.bin_size
        ),
        format!(
            "[default: mature-current a tenth of the bin; paper {}]",
            p.layer_thickness
        ),
        format!("paper {}]", p.steps),
        format!(
            "at most {} h",
            cellsurf::ripple::recipe::DEFAULT_CAP_S / 3600.0
        ),
    ] {
        assert!(help.contains(&said), "{said}: {help}");
    }
}

/// The recipe for mature current ripples warns where the current takes the grains' flat-bed
/// travel outside 0.8 to 1.25 times that at the speed it was measured at (its ripples follow
/// the travel, nature's current ripples keep their size), naming the speed and the ratio
/// (0.2 mm sand: 0.45 m/s warns, 0.47 m/s does not); not with the paper's rules, not where the
/// waves dominate. Its bin follows the travel (the printed scenarios' `bin_size`), down to the
/// finest bin that holds the sand near the threshold of motion (0.3 m/s), which a run's note
/// says.
#[test]
fn the_recipe_warns_where_the_current_changes_its_travel() {
    let warned = "warning: the recipe mature-current's ripples come to about 66 flat-bed travels";
    // 0.2 mm sand: 66 nominal travels are 0.33 / 2.19 times Soulsby & Whitehouse's 0.146 m
    let (slow, e) = printed_scenario(&["--current-speed", "0.35"]);
    assert!(
        e.contains(warned)
            && e.contains("at --current-speed = 0.35 m/s, 0.33 times the 0.1459 m of Soulsby"),
        "{e}"
    );
    let (fast, e) = printed_scenario(&["--current-speed", "0.65"]);
    assert!(e.contains(warned) && e.contains("2.19 times"), "{e}");
    let bin = |s: &str| -> f64 {
        let line = s.lines().find(|l| l.starts_with("bin_size = ")).unwrap();
        line["bin_size = ".len()..].parse().unwrap()
    };
    assert!(
        bin(&slow) < 0.00186 && bin(&fast) > 0.00186,
        "{slow}\n{fast}"
    );
    // just outside the 20 % band either side of the default's 1.12
    let (_, e) = printed_scenario(&["--current-speed", "0.42"]);
    assert!(e.contains(warned) && e.contains("0.67 times"), "{e}");
    let (_, e) = printed_scenario(&["--current-speed", "0.52"]);
    assert!(e.contains(warned) && e.contains("1.25 times"), "{e}");
    // at a fixed current the travel stops growing with the grain: coarse sand's ripples short
    let (_, e) = printed_scenario(&["--d50", "0.8"]);
    assert!(
        e.contains(warned) && e.contains("0.40 times the 0.4230 m") && e.contains("0.8 mm"),
        "{e}"
    );
    for quiet in [
        vec!["--current-speed", "0.47"],
        vec!["--current-speed", "0.5"],
        vec!["--d50", "0.1"],
        vec!["--d50", "0.4"],
        vec!["--current-speed", "0.35", "--recipe", "paper"],
        vec![
            "--recipe",
            "mature-current",
            "--current-speed",
            "0.35",
            "--wave-velocity",
            "0.6",
            "--wave-period",
            "4s",
        ],
    ] {
        let (_, e) = printed_scenario(&quiet);
        assert!(!e.contains(warned), "{quiet:?}: {e}");
    }
    // near the threshold: the finest bin that holds the 10 cm of sand, said in the note
    let (gentle, _) = printed_scenario(&["--current-speed", "0.3"]);
    assert!(
        gentle.contains("\nbin_size = 0.000245\n") && gentle.contains("\nlayers = 4082\n"),
        "{gentle}"
    );
    let o = cellsurf(&[
        "ripple",
        "--current-speed",
        "0.3",
        "--size",
        "16x1",
        "--steps",
        "1",
        "--json",
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("note: bins of 0.75 flat-bed travels")
            && e.contains("here the finest bin whose 0.1 m of sand fits in 4096 layers")
            && e.contains("a section of 0.00392"),
        "{e}"
    );
    // a 3-D field's note gives both its sides (16 x 4 bins of 1.86 mm)
    let o = cellsurf(&["ripple", "--size", "16x4", "--steps", "1", "--json"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(e.contains("a field of 0.02976 x 0.00744"), "{e}");
}

/// The predictor's values are null, as its crest normal is, where the flow moves no grain
/// (below the threshold of motion; deep-water waves whose orbit does not reach the bed gave a
/// wavelength of 1e-19 m); in the ripple regime they are the predictor's.
#[test]
fn predictions_are_null_where_the_flow_moves_no_grain() {
    let run = |extra: &[&str]| {
        let mut args = vec!["ripple", "--size", "64x1", "--steps", "10", "--json"];
        args.extend_from_slice(extra);
        let o = cellsurf(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let deep = [
        "--current-speed",
        "0",
        "--wave-height",
        "2",
        "--wave-period",
        "3s",
        "--water-depth",
        "100",
    ];
    for v in [run(&deep), run(&["--current-speed", "0.26"])] {
        assert_eq!(v["regime"], "no motion");
        for key in [
            "predicted_wavelength_m",
            "predicted_height_m",
            "predicted_crest_normal_deg",
        ] {
            assert!(v[key].is_null(), "{key}: {v}");
        }
    }
    let v = run(&[]);
    assert_eq!(v["regime"], "ripples");
    let w = v["predicted_wavelength_m"].as_f64().unwrap();
    assert!((w - 0.1459).abs() < 1e-3, "{w}");
}

/// A `.npy` set written over an earlier one is the new run's alone: the earlier run's fields
/// that the new one does not write are removed, so the sidecar lists every file beside it.
#[test]
fn an_earlier_runs_npy_fields_are_not_left_beside_a_new_one() {
    let out = tmp("stale.npy");
    let run = |fields: &str| {
        let mut args = SMALL.to_vec();
        args.extend([
            "--quiet",
            "--fields",
            fields,
            "--out",
            out.to_str().unwrap(),
        ]);
        let o = cellsurf(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    run("elevation,porosity,impedance");
    assert!(tmp("stale_porosity.npy").exists() && tmp("stale_impedance.npy").exists());
    run("elevation,impedance");
    assert!(!tmp("stale_porosity.npy").exists());
    assert!(tmp("stale.npy").exists() && tmp("stale_impedance.npy").exists());
    let side = std::fs::read_to_string(tmp("stale.json")).unwrap();
    assert!(side.contains("\"impedance\"") && !side.contains("\"porosity\""));
    // a file of another name beside it is not the set's, and stays
    std::fs::write(tmp("stale_notes.npy"), b"x").unwrap();
    run("elevation");
    assert!(!tmp("stale_impedance.npy").exists() && tmp("stale_notes.npy").exists());
    // nor is a field file the earlier sidecar does not list (the user's own)
    std::fs::write(tmp("stale_density.npy"), b"mine").unwrap();
    run("elevation,porosity");
    run("elevation");
    assert!(!tmp("stale_porosity.npy").exists() && tmp("stale_density.npy").exists());
    // a run that fails leaves the earlier set whole: its fields are removed only once the new
    // files are in place (here the grain sizes pass a file-size limit the elevation fits)
    run("elevation,porosity,impedance");
    let mut args = SMALL.to_vec();
    args.extend([
        "--quiet",
        "--fields",
        "elevation,grain_size",
        "--out",
        out.to_str().unwrap(),
    ]);
    let o = std::process::Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -f 8; exec \"$0\" {}", args.join(" ")))
        .arg(env!("CARGO_BIN_EXE_cellsurf"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("stale_grain_size.npy"), "{err}");
    assert!(tmp("stale_porosity.npy").exists() && tmp("stale_impedance.npy").exists());
    assert!(!tmp("stale_grain_size.npy").exists());
    // the removal is said
    let mut args = SMALL.to_vec();
    args.extend([
        "--fields",
        "elevation,grain_size",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(cellsurf(&args).status.success());
    let mut args = SMALL.to_vec();
    args.extend(["--fields", "elevation", "--out", out.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&cellsurf(&args).stderr).into_owned();
    assert!(
        err.contains(&format!(
            "removed {}",
            tmp("stale_grain_size.npy").display()
        )),
        "{err}"
    );
}

/// What a scenario file or a flag asks for that the run would not do is refused or said,
/// whatever `--quiet` says where a value given is changed.
#[test]
fn scenario_waves_bins_and_idle_angles_are_said() {
    let scene = |name: &str, text: &str| {
        let p = tmp(name);
        std::fs::write(&p, format!("model = \"ripple\"\nmode = \"2d\"\nnx = 32\nny = 1\nlayers = 10\nsteps = 20\n{text}")).unwrap();
        p
    };
    // waves without a period, in a scenario: refused as on the command line
    for (name, text) in [
        ("w_none.toml", "current_speed = 0\nwave_amplitude = 0.3\n"),
        (
            "w_zero.toml",
            "current_speed = 0\nwave_amplitude = 0.3\nwave_period = 0\n",
        ),
    ] {
        let p = scene(name, text);
        let o = cellsurf(&["ripple", "--scenario", p.to_str().unwrap()]);
        assert_refused(
            &[name],
            &o,
            "wave_amplitude = 0.3",
            "needs a wave period: give wave_period_s",
        );
    }
    // a scenario's waves without a friction factor rub the bed more weakly than the same waves
    // typed: warned
    let p = scene(
        "w_nof.toml",
        "current_speed = 0\nwave_amplitude = 0.4\nwave_period_s = 8\n",
    );
    let o = cellsurf(&["ripple", "--scenario", p.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("the scenario's waves have no wave_friction_factor")
            && err.contains("no lee vortex"),
        "{err}"
    );
    // the same waves typed: no such warning
    let o = cellsurf(&[
        "ripple",
        "--recipe",
        "paper",
        "--size",
        "32x1",
        "--layers",
        "10",
        "--steps",
        "20",
        "--current-speed",
        "0",
        "--wave-velocity",
        "0.4",
        "--wave-period",
        "8",
    ]);
    assert!(!String::from_utf8_lossy(&o.stderr).contains("no wave_friction_factor"));
    // --current-angle with no current and waves at their own angle acts on nothing
    let mut args = SMALL.to_vec();
    args.extend([
        "--current-speed",
        "0",
        "--wave-velocity",
        "0.3",
        "--wave-period",
        "8",
        "--wave-angle",
        "60",
        "--current-angle",
        "10",
    ]);
    let err = String::from_utf8_lossy(&cellsurf(&args).stderr).into_owned();
    assert!(
        err.contains("warning: --current-angle = 10 deg has no effect"),
        "{err}"
    );
    // and with the waves along the current's axis (no --wave-angle) it sets their direction
    args.truncate(args.len() - 4);
    args.extend(["--current-angle", "10"]);
    let err = String::from_utf8_lossy(&cellsurf(&args).stderr).into_owned();
    assert!(
        !err.contains("--current-angle = 10 deg has no effect"),
        "{err}"
    );
    // a bin narrower than a grain
    let mut args = SMALL.to_vec();
    args.extend(["--bin-size", "0.0001", "--layer-thickness", "0.00001"]);
    let err = String::from_utf8_lossy(&cellsurf(&args).stderr).into_owned();
    assert!(
        err.contains(
            "warning: --bin-size = 0.0001 m is narrower than the median grain (--d50 = 0.2 mm)"
        ),
        "{err}"
    );
    // a scenario's own bin and layers that its bin_travels changes: said under --quiet
    let printed = cellsurf(&[
        "ripple",
        "--size",
        "64x1",
        "--layers",
        "20",
        "--steps",
        "30",
        "--print-scenario",
    ]);
    assert!(printed.status.success());
    let p = tmp("travels.toml");
    std::fs::write(&p, &printed.stdout).unwrap();
    let o = cellsurf(&[
        "ripple",
        "--scenario",
        p.to_str().unwrap(),
        "--d50",
        "0.4",
        "--quiet",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains(
            "warning: the scenario's bin_size, layer_thickness, layers change with its bin_travels"
        ),
        "{err}"
    );
    // typed, the automata are kept and only the bin changes
    let o = cellsurf(&[
        "ripple",
        "--scenario",
        p.to_str().unwrap(),
        "--d50",
        "0.4",
        "--layers",
        "20",
        "--layer-thickness",
        "0.0002",
        "--quiet",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("warning: the scenario's bin_size changes with its bin_travels"),
        "{err}"
    );
    // unchanged (the scenario's own grain): nothing to say
    let o = cellsurf(&["ripple", "--scenario", p.to_str().unwrap(), "--quiet"]);
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // a scenario that gives no bin of its own: the bin of travels is a note, not a change
    let p = tmp("travels_only.toml");
    std::fs::write(
        &p,
        "model = \"ripple\"\nmode = \"2d\"\nnx = 32\nny = 1\nsteps = 20\nbin_travels = 0.75\nhop_grains = 4.6875\n",
    )
    .unwrap();
    let o = cellsurf(&["ripple", "--scenario", p.to_str().unwrap(), "--quiet"]);
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = cellsurf(&["ripple", "--scenario", p.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("note: bins of 0.75 flat-bed travels"), "{err}");
}

/// The recipe for mature wave ripples: every length in units of the waves' orbital excursion A
/// (bins of A / 50, crests suspended above A / 10, the travel scaled with them), a typed bin
/// kept; it runs until equilibrium by default; under a dominant current it is warned of.
#[test]
fn the_mature_waves_recipe_scales_its_lengths_with_the_orbit() {
    let run = |period: &str, extra: &[&str]| {
        let mut args = vec![
            "ripple",
            "--recipe",
            "mature-waves",
            "--current-speed",
            "0",
            "--wave-velocity",
            "0.4",
            "--wave-period",
            period,
            "--d50",
            "0.3",
            "--size",
            "64x1",
            "--duration",
            "100s",
            "--json",
        ];
        args.extend_from_slice(extra);
        let o = cellsurf(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        (v, String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let p = |v: &serde_json::Value, k: &str| v["parameters"][k].as_f64().unwrap();
    // d0 = 0.2 and 0.4 m (T = pi d0 / U_w): A = 0.1 and 0.2 m
    let (a, note) = run("1.570796327s", &[]);
    let (b, _) = run("3.141592654s", &[]);
    assert_eq!(a["recipe"], "mature-waves");
    assert!(
        note.contains("lengths in units of the waves' orbital excursion A = 0.1000 m"),
        "{note}"
    );
    for (v, excursion) in [(&a, 0.1), (&b, 0.2)] {
        assert!((p(v, "wave_vortex") - excursion).abs() < 1e-6);
        assert_eq!(p(v, "orbit_reference"), p(v, "wave_vortex"));
        assert!((p(v, "bin_size") - excursion / 50.0).abs() < 1e-8, "{v}");
        assert!((p(v, "layer_thickness") - excursion / 500.0).abs() < 1e-9);
        assert!((p(v, "crest_suspension") - excursion / 10.0).abs() < 1e-8);
        assert!((p(v, "hop_grains") - 37.5 * excursion).abs() < 1e-6);
    }
    // a typed bin is kept, its automata a tenth of it; the travel and the crest height follow A
    let (c, _) = run("1.570796327s", &["--bin-size", "0.003"]);
    assert_eq!(
        (p(&c, "bin_size"), p(&c, "layer_thickness")),
        (0.003, 0.0003)
    );
    assert!((p(&c, "crest_suspension") - 0.01).abs() < 1e-8);
    // a current that dominates: warned, and the lengths are the file's
    let o = cellsurf(&[
        "ripple",
        "--recipe",
        "mature-waves",
        "--current-speed",
        "0.5",
        "--wave-velocity",
        "0.1",
        "--wave-period",
        "4s",
        "--size",
        "64x1",
        "--duration",
        "100s",
        "--json",
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("warning: --recipe mature-waves is for waves: here the current dominates"),
        "{e}"
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(p(&v, "bin_size"), 0.0025);
    // without the vortex (no excursion to scale by): warned, the file's lengths
    let (n, e) = run("1.570796327s", &["--no-wave-vortex"]);
    assert!(
        e.contains("warning: orbit_reference = 0.125 has no effect here"),
        "{e}"
    );
    assert_eq!(p(&n, "bin_size"), 0.0025);
    // long waves (d0 = 1.5 m, anorbital): the recipe's length against the predictor's, warned
    let (_, e) = run("12s", &[]);
    assert!(
        e.contains(
            "warning: the recipe mature-waves's ripples come to about 1.15 orbital excursions"
        ),
        "{e}"
    );
    assert!(!note.contains("warning: the recipe"), "{note}");
    // the key's own range, named before it is applied
    for bad in ["200", "0.0001", "-1"] {
        let f = tmp("orbit_bad.toml");
        std::fs::write(
            &f,
            format!("model = \"ripple\"\nmode = \"2d\"\nnx = 64\nny = 1\ncurrent_speed = 0\norbit_reference = {bad}\n"),
        )
        .unwrap();
        let o = cellsurf(&[
            "ripple",
            "--scenario",
            f.to_str().unwrap(),
            "--wave-velocity",
            "0.4",
            "--wave-period",
            "2s",
            "--duration",
            "50s",
        ]);
        assert_refused(&[bad], &o, "orbit_reference", "is out of range");
    }
}
