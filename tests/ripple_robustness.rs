//! `cellsurf ripple` at the edges of its input: lattices that cannot hold the avalanche
//! angle, flows just above the threshold of motion, wave periods in steps, runs that move
//! nothing or stop early, and the messages and records of each.
#![cfg(feature = "cli")]

mod common;

use std::path::PathBuf;

use common::cellsurf;

fn tmp(name: &str) -> PathBuf {
    common::tmp_in("ripple-robust", name)
}

/// A small 3-D run with the paper's rules, whose thresholds, lattice and stops these tests
/// measure.
const SMALL: &[&str] = &[
    "ripple", "--recipe", "paper", "--size", "32x16", "--layers", "10",
];

fn run(extra: &[&str]) -> std::process::Output {
    let mut a = SMALL.to_vec();
    a.extend_from_slice(extra);
    cellsurf(&a)
}

fn json(o: &std::process::Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

fn refused(o: &std::process::Output) -> String {
    assert!(!o.status.success(), "accepted");
    let e = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(!e.contains("panicked"), "{e}");
    e
}

#[test]
fn a_bin_or_avalanche_angle_out_of_its_range_is_named_by_its_own_flag() {
    for (args, want) in [
        (["--bin-size", "0"], "--bin-size = 0 is out of range"),
        (
            ["--avalanche-angle", "0"],
            "--avalanche-angle = 0 is out of range",
        ),
    ] {
        let mut a = vec!["--steps", "20"];
        a.extend(args);
        let e = refused(&run(&a));
        assert!(e.contains(want) && !e.contains("--layer-thickness"), "{e}");
    }
}

#[test]
fn lattice_steeper_than_the_avalanche_angle_is_refused() {
    // one automaton of 0.5 mm over a 0.5 mm bin: 45 deg against 32
    let out = tmp("steep.nc");
    let _ = std::fs::remove_file(&out);
    let e = refused(&run(&[
        "--steps",
        "20",
        "--bin-size",
        "0.0005",
        "--out",
        out.to_str().unwrap(),
    ]));
    for flag in [
        "--layer-thickness",
        "--bin-size",
        "--avalanche-angle",
        "45.0 deg",
    ] {
        assert!(e.contains(flag), "{flag}: {e}");
    }
    assert!(!out.exists());
    // 26.6 deg against 20
    let e = refused(&run(&[
        "--steps",
        "20",
        "--bin-size",
        "0.001",
        "--avalanche-angle",
        "20",
    ]));
    assert!(e.contains("26.6 deg") && e.contains("0.0003640 m"), "{e}");
    // at the limit it runs
    let v = json(&run(&[
        "--steps",
        "20",
        "--bin-size",
        "0.001",
        "--avalanche-angle",
        "27",
        "--json",
        "--quiet",
    ]));
    assert_eq!(v["steps"], 20);
}

#[test]
fn a_domain_long_bedform_has_a_height() {
    let v = json(&cellsurf(&[
        "ripple",
        "--size",
        "32x16",
        "--layers",
        "30",
        "--current-speed",
        "0",
        "--wave-velocity",
        "0.4",
        "--wave-period",
        "3s",
        "--steps",
        "10000",
        "--json",
        "--quiet",
    ]));
    let h = v["height_m"].as_f64().unwrap();
    assert!(h > 0.008, "{v}");
    assert!(v["ripple_index"].as_f64().unwrap() > 0.0, "{v}");
    assert!(v["stoss_slope_deg"].as_f64().is_some(), "{v}");
    assert_eq!(v["single_bedform"], true);
    let (l, d) = (
        v["wavelength_m"].as_f64().unwrap(),
        v["domain_length_along_flow_m"].as_f64().unwrap(),
    );
    assert!((l - d).abs() < 1e-9 * d, "{v}");
}

#[test]
fn flows_whose_grains_do_not_move_are_no_motion_not_zero_length_steps() {
    let o = run(&["--current-speed", "0.27", "--steps", "1000", "--json"]);
    let v = json(&o);
    assert_eq!(v["regime"], "no motion");
    assert_eq!(v["steps"], 0);
    assert!(v["step_duration_s"].is_null(), "{v}");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("--current-speed = 0.27") && e.contains("median grain from 0.351 m/s"),
        "{e}"
    );
    // a duration is no longer refused with a bedload reported: nothing runs
    let v = json(&run(&[
        "--current-speed",
        "0.27",
        "--duration",
        "20s",
        "--json",
        "--quiet",
    ]));
    assert_eq!(v["regime"], "no motion");
    assert_eq!(v["duration_s"], 20.0);
    assert_eq!(v["parameters"]["steps"], 0);
    // every moving run has a positive step
    for u in ["0.3", "0.4"] {
        let v = json(&run(&[
            "--current-speed",
            u,
            "--steps",
            "10",
            "--json",
            "--quiet",
        ]));
        assert_eq!(v["regime"], "ripples");
        assert!(v["step_duration_s"].as_f64().unwrap() > 0.0, "{v}");
    }
}

#[test]
fn a_scenario_reruns_the_same_physical_time_and_period() {
    let a = [
        "--current-speed",
        "0.3",
        "--wave-velocity",
        "0.3",
        "--wave-period",
        "3s",
        "--wave-angle",
        "30",
        "--duration",
        "10s",
    ];
    let v = json(&run(&[&a[..], &["--json", "--quiet"]].concat()));
    let o = run(&[&a[..], &["--print-scenario"]].concat());
    assert!(o.status.success());
    assert!(o.stdout.ends_with(b"\n"));
    let scene = tmp("rerun.toml");
    std::fs::write(&scene, &o.stdout).unwrap();
    let w = json(&cellsurf(&[
        "ripple",
        "--scenario",
        scene.to_str().unwrap(),
        "--json",
        "--quiet",
    ]));
    assert_eq!(v["step_duration_s"], w["step_duration_s"]);
    assert_eq!(v["steps"], w["steps"]);
    let t = w["wave_period_s"].as_f64().unwrap();
    assert!((t - 3.0).abs() < 1e-9, "{w}");
}

#[test]
fn no_motion_under_until_equilibrium_says_no_motion() {
    // a run that moves nothing makes no step: it did not run to its cap
    let v = json(&run(&[
        "--current-speed",
        "0.2",
        "--until",
        "equilibrium",
        "--steps",
        "4000",
        "--json",
        "--quiet",
    ]));
    assert_eq!(v["regime"], "no motion");
    assert_eq!(v["parameters"]["steps"], 0);
    assert_eq!(v["stop_reason"], "no motion");
}

#[test]
fn waves_switched_off_leave_the_wave_options_idle_and_refused() {
    // --wave-velocity 0 is no waves: a wave option given with it is refused by name, as
    // without --wave-velocity at all
    let e = refused(&run(&[
        "--wave-velocity",
        "0",
        "--wave-period",
        "8s",
        "--steps",
        "10",
    ]));
    assert!(
        e.contains("--wave-period = 8 s") && e.contains("--wave-velocity = 0"),
        "{e}"
    );
    let e = refused(&run(&[
        "--wave-velocity",
        "0",
        "--wave-angle",
        "30",
        "--steps",
        "10",
    ]));
    assert!(e.contains("--wave-angle = 30"), "{e}");
    // alone it is a run without waves
    let v = json(&run(&[
        "--wave-velocity",
        "0",
        "--steps",
        "10",
        "--json",
        "--quiet",
    ]));
    assert_eq!(v["wave_period_s"], serde_json::Value::Null);
    // it switches off a scenario's waves: their period, vortex and friction are not the run's,
    // are recorded at their no-wave defaults, and no warning offers to keep or reset them
    let f = tmp("waves-off.toml");
    let mut text = std::fs::read_to_string("tests/fixtures/ripple_seconds.toml").unwrap();
    text.push_str("wave_friction_factor = 0.05\nwave_vortex = 0.3\n");
    std::fs::write(&f, text).unwrap();
    let o = cellsurf(&[
        "ripple",
        "--scenario",
        f.to_str().unwrap(),
        "--wave-velocity",
        "0",
        "--json",
    ]);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(!err.contains("is kept"), "{err}");
    let v = json(&o);
    assert_eq!(v["wave_period_s"], serde_json::Value::Null);
    let p = &v["parameters"];
    assert_eq!(p["wave_amplitude"], 0.0);
    assert_eq!(p["wave_period"], 0.0);
    assert!(
        p.get("wave_vortex").is_none() && p.get("wave_friction_factor").is_none(),
        "{p}"
    );
}

#[test]
fn no_motion_records_what_was_asked_and_run() {
    let out = tmp("nm.npy");
    let v = json(&run(&[
        "--current-speed",
        "0.2",
        "--duration",
        "30min",
        "--json",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]));
    assert_eq!(v["regime"], "no motion");
    assert_eq!(v["parameters"]["steps"], 0);
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp("nm.json")).unwrap()).unwrap();
    assert_eq!(side["duration_s"], 1800.0);
    assert_eq!(side["parameters"]["steps"], 0);
    assert_eq!(side["elevation_times"], serde_json::json!([0]));
    assert_eq!(side["stop_reason"], "no motion");
    // waves too weak to move sand: the period is recorded in seconds, not as 64 steps
    let v = json(&run(&[
        "--current-speed",
        "0",
        "--wave-velocity",
        "0.05",
        "--wave-period",
        "8s",
        "--json",
        "--quiet",
    ]));
    assert_eq!(v["regime"], "no motion");
    assert_eq!(v["wave_period_s"], 8.0);
    assert_ne!(v["parameters"]["wave_period"], 64.0);
    // a wave period with no waves is refused
    let e = refused(&run(&["--current-speed", "0", "--wave-period", "8s"]));
    assert!(
        e.contains("--wave-period = 8 s") && e.contains("--wave-velocity"),
        "{e}"
    );
    let e = refused(&run(&["--wave-angle", "30", "--steps", "1"]));
    assert!(e.contains("--wave-angle = 30"), "{e}");
}

#[test]
fn the_largest_seed_runs() {
    let v = json(&run(&[
        "--steps",
        "10",
        "--seed",
        "9007199254740992",
        "--json",
        "--quiet",
    ]));
    assert_eq!(v["parameters"]["seed"], 9_007_199_254_740_992u64);
    for bad in ["9007199254740993", "99999999999999999999", "-1"] {
        let e = refused(&run(&["--steps", "10", "--seed", bad]));
        assert!(
            e.contains("--seed") && e.contains(bad) && e.contains("[0, 2^53 = 9007199254740992]"),
            "{e}"
        );
    }
}

#[test]
fn sheet_flow_names_the_waves_and_periods_are_in_seconds() {
    let e = refused(&run(&[
        "--current-speed",
        "0",
        "--wave-velocity",
        "5",
        "--wave-period",
        "3s",
    ]));
    assert!(
        e.contains("--wave-velocity = 5 m/s is out of range: the waves"),
        "{e}"
    );
    assert!(!e.contains("--current-speed"), "{e}");
    let e = refused(&run(&[
        "--current-speed",
        "0",
        "--wave-velocity",
        "1",
        "--wave-period",
        "3s",
        "--wave-friction-factor",
        "0.5",
    ]));
    assert!(e.contains("--wave-friction-factor"), "{e}");
    // one limit in seconds, from --wave-velocity or --wave-height
    for waves in [
        &["--wave-velocity", "0.1"][..],
        &["--wave-height", "1", "--water-depth", "10"][..],
    ] {
        let e = refused(&run(&[
            waves,
            &["--current-speed", "0.3", "--wave-period", "1e9s"][..],
        ]
        .concat()));
        assert!(
            e.contains("--wave-period = 1e9") && e.contains("1000]"),
            "{e}"
        );
        assert!(!e.contains("e12"), "{e}");
    }
}

#[test]
fn an_early_stop_is_recorded_with_until_and_the_missed_snapshots() {
    let out = tmp("eq.npy");
    // (a 12 cm field that reaches the domain's length and then settles: it stops at 32,000
    // steps, two doublings after its first quiet one)
    let until = [
        "ripple",
        "--recipe",
        "paper",
        "--size",
        "24x12",
        "--layers",
        "10",
        "--seed",
        "3",
        "--until",
        "equilibrium",
        "--steps",
        "64000",
    ];
    let o = cellsurf(
        &[
            &until[..],
            &[
                "--snapshots",
                "0,40000,64000",
                "--out",
                out.to_str().unwrap(),
            ],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let e = String::from_utf8_lossy(&o.stderr);
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp("eq.json")).unwrap()).unwrap();
    assert_eq!(side["parameters"]["until"], "equilibrium");
    let stop = side["stop_step"].as_u64().unwrap();
    assert!(stop < 40000, "{side}");
    assert_eq!(side["stop_reason"], "equilibrium");
    assert_eq!(side["bare_fraction"], 0.0);
    assert_eq!(side["elevation_times"], serde_json::json!([0, stop]));
    assert!(
        e.contains("were not reached") && e.contains("40000, 64000"),
        "{e}"
    );
    // the default snapshots (start and end) were not asked for: the end is the stop, no note
    let quiet_out = tmp("eq_default.npy");
    let o = cellsurf(&[&until[..], &["--out", quiet_out.to_str().unwrap()]].concat());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && !e.contains("were not reached"), "{e}");
    // (and the end written is the bed where it stopped)
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp("eq_default.json")).unwrap()).unwrap();
    let stop = side["stop_step"].as_u64().unwrap();
    assert!(stop < 64000, "{side}");
    assert_eq!(side["elevation_times"], serde_json::json!([0, stop]));
    // the scenario keeps `until`
    let o = cellsurf(&["ripple", "--until", "equilibrium", "--print-scenario"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("until = \"equilibrium\""));
}

#[test]
fn npy_without_elevation_and_bad_zarr_targets_are_refused_before_the_run() {
    let e = refused(&run(&[
        "--steps",
        "10",
        "--fields",
        "impedance",
        "--out",
        tmp("x.npy").to_str().unwrap(),
    ]));
    assert!(e.contains("--fields") && e.contains("elevation"), "{e}");
    assert!(!tmp("x_impedance.npy").exists());
    // Zarr: a missing folder, a file, a folder that is not a store: before any step
    let file = tmp("plain.zarr");
    std::fs::write(&file, b"x").unwrap();
    let dir = tmp("notstore.zarr");
    std::fs::create_dir_all(&dir).unwrap();
    let missing = tmp("nodir/x.zarr");
    for (out, why) in [
        (&missing, "does not exist"),
        (&file, "not a folder"),
        (&dir, "not a Zarr store"),
    ] {
        let o = run(&["--steps", "2000000", "--out", out.to_str().unwrap()]);
        let e = refused(&o);
        assert!(e.contains("--out") && e.contains(why), "{e}");
    }
    assert_eq!(std::fs::read(&file).unwrap(), b"x");
}

#[test]
fn minor_records_and_messages() {
    // the x axis in [0, 360)
    for (angle, want) in [("360", 0.0), ("-360", 0.0), ("-10", 350.0)] {
        let v = json(&run(&[
            "--current-angle",
            angle,
            "--steps",
            "1",
            "--json",
            "--quiet",
        ]));
        assert_eq!(v["x_axis_direction_deg"], want, "{angle}");
    }
    // an old key gets the hint of its new name
    let scene = tmp("old.toml");
    std::fs::write(&scene, "model = \"ripple\"\nrecovery_length = 2\n").unwrap();
    let e = refused(&cellsurf(&[
        "ripple",
        "--scenario",
        scene.to_str().unwrap(),
    ]));
    assert!(e.contains("drag_delay"), "{e}");
    // a duration shorter than a step is noted
    let o = run(&["--duration", "0.0001s", "--json"]);
    let v = json(&o);
    assert_eq!(v["steps"], 1);
    assert!(String::from_utf8_lossy(&o.stderr).contains("shorter than one step"));
    // the help gives the ranges
    let h = String::from_utf8_lossy(&cellsurf(&["ripple", "--help"]).stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    for r in [
        "0.01 to 10",
        "1 to 4096",
        "tan(--avalanche-angle)",
        "at most 1000 s",
        "0 to 2^53",
    ] {
        assert!(h.contains(r), "{r}: {h}");
    }
}
