//! `cellsurf tile` as a user meets it: tiles from a ripple file and generated in-process, the
//! JSON summary (no NaN), the dry run's disk estimate, and bad input rejected with a message
//! naming the parameter and a non-zero exit.
#![cfg(feature = "cli")]

mod common;

use std::path::PathBuf;
use std::process::Output;

use common::cellsurf;

fn tmp(name: &str) -> PathBuf {
    common::tmp_in("tile-cli", name)
}

const GEN: &[&str] = &[
    "tile",
    "--generate",
    "--nx",
    "24",
    "--ny",
    "12",
    "--layers",
    "10",
    "--steps",
    "40",
];

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn tiles_from_a_ripple_file_with_volume() {
    let r = tmp("r.nc");
    let o = cellsurf(&[
        "ripple",
        "--recipe",
        "paper",
        "--nx",
        "24",
        "--ny",
        "12",
        "--layers",
        "10",
        "--steps",
        "40",
        "--quiet",
        "--out",
        r.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m = tmp("m.nc");
    let v = json(&cellsurf(&[
        "tile",
        "--tile",
        r.to_str().unwrap(),
        "--mosaic",
        "3x2",
        "--volume",
        "impedance",
        "--out",
        m.to_str().unwrap(),
        "--json",
    ]));
    assert_eq!(v["width"], 72);
    assert_eq!(v["height"], 24);
    assert!(v["levels"].as_u64().unwrap() > 0);
    assert_eq!(v["bytes"], std::fs::metadata(&m).unwrap().len());
    let est = v["estimated_bytes"].as_f64().unwrap();
    assert!((est - v["bytes"].as_f64().unwrap()).abs() < 8192.0);
    // a snapshot the file does not hold
    let o = cellsurf(&["tile", "--tile", r.to_str().unwrap(), "--snapshots", "7"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("snapshots = 7 is out of range"));
    // snapshots out of order or twice are refused, from a file and generated alike
    for list in ["3,2", "2,2"] {
        for src in [&["--tile", r.to_str().unwrap()][..], &["--generate"][..]] {
            let mut args = vec!["tile", "--snapshots", list];
            args.extend(src);
            let o = cellsurf(&args);
            assert!(!o.status.success(), "{args:?}");
            let e = String::from_utf8_lossy(&o.stderr);
            assert!(
                e.contains(&format!("--snapshots = {list} is out of range"))
                    && e.contains("strictly increasing"),
                "{e}"
            );
        }
    }
}

#[test]
fn one_tile_json_has_no_nan_and_dry_run_estimates() {
    let mut a = GEN.to_vec();
    a.extend(["--mosaic", "1x1", "--json"]);
    let o = cellsurf(&a);
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(!text.contains("NaN") && !text.contains("nan"), "{text}");
    let v = json(&o);
    assert_eq!(v["seams"]["x"]["seams"], 1);
    let mut a = GEN.to_vec();
    a.extend([
        "--bin-size",
        "0.01",
        "--extent",
        "1000x1000",
        "--dry-run",
        "--json",
    ]);
    let v = json(&cellsurf(&a));
    // 1 km at 1 cm: 1e10 bins of 4 bytes, rounded up to whole tiles of 24 x 12 bins
    assert_eq!(v["width"], 100_008);
    assert_eq!(v["height"], 100_008);
    assert!(v["estimated_bytes"].as_f64().unwrap() > 4.0e10);
    assert_eq!(v["bytes"], 0);
}

#[test]
fn bad_input_is_named() {
    for (extra, want) in [
        (&["--mosaic", "0x2"][..], "mosaic = 0x2 is out of range"),
        (&["--mosaic", "2"][..], "'2' is not two counts AxB"),
        (&["--blend", "99"][..], "blend = 99 is out of range"),
        (&["--choose", "all"][..], "choose = all is out of range"),
        (
            &["--dunes", "--hurst", "1.2"][..],
            "hurst = 1.2 is out of range",
        ),
        (&["--extent", "-5x3"][..], "--extent = -5x3 is out of range"),
        // more tiles than a mosaic lays, named by the flag that asked for them
        (
            &["--extent", "1e9x1e9"][..],
            "--extent = 1e9x1e9 is out of range: it takes",
        ),
        (
            &["--mosaic", "20000x20000"][..],
            "--mosaic = 20000x20000 is out of range: expected at most 2^28",
        ),
        (
            &["--volume", "impedance", "--dunes"][..],
            "--volume with --dunes",
        ),
        (
            &["--current-angle", "NaN"][..],
            "--current-angle = NaN is out of range",
        ),
        (
            &["--dunes", "--current-angle", "NaN"][..],
            "--current-angle = NaN is out of range",
        ),
        (
            &["--dunes", "--dune-grid", "100000"][..],
            "--dune-grid = 100000 is out of range: expected 3 ..= 72 nodes",
        ),
        (
            &["--dunes", "--dune-grid", "2"][..],
            "--dune-grid = 2 is out of range: expected 3 ..= 72 nodes",
        ),
        (&["--hurst", "0.5"][..], "--dunes"),
        (&["--dune-rms", "0.1"][..], "--dunes"),
        (&["--dune-wavelength", "0.5"][..], "--dunes"),
        (&["--steering", "1"][..], "--dunes"),
        (&["--dune-grid", "16"][..], "--dunes"),
    ] {
        let mut a = GEN.to_vec();
        a.extend(extra);
        let o = cellsurf(&a);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?} accepted");
        assert!(err.contains(want), "{extra:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let o = cellsurf(&["tile"]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("no tiles"));
}

#[test]
fn current_angle_on_file_tiles_needs_dunes() {
    // tiles read from a file keep their current: without --dunes the angle would do nothing
    let r = tmp("angle-r.nc");
    let mut g = vec![
        "ripple", "--recipe", "paper", "--nx", "24", "--ny", "12", "--layers", "10",
    ];
    g.extend(["--steps", "20", "--quiet", "--out", r.to_str().unwrap()]);
    assert!(cellsurf(&g).status.success());
    let base = ["tile", "--tile", r.to_str().unwrap(), "--mosaic", "2x2"];
    let mut a = base.to_vec();
    a.extend(["--current-angle", "45"]);
    let o = cellsurf(&a);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "accepted: {err}");
    assert!(err.contains("--current-angle = 45 needs --dunes"), "{err}");
    a.extend(["--dunes", "--dune-grid", "24", "--json"]);
    let v = json(&cellsurf(&a));
    assert_eq!(v["dunes"]["current_angle_deg"], 45.0);
}

#[test]
fn dune_slopes_are_reported_and_steep_dunes_warned() {
    let mut a = GEN.to_vec();
    a.extend(["--dunes", "--dune-grid", "32", "--json"]);
    // default rms: an rms dune slope of 6 deg, well below the angle of repose
    let o = cellsurf(&a);
    let v = json(&o);
    let d = &v["dunes"];
    assert!(
        (d["rms_dune_slope_deg"].as_f64().unwrap() - 6.0).abs() < 1e-6,
        "{d}"
    );
    assert!(d["max_dune_slope_deg"].as_f64().unwrap() < 32.0, "{d}");
    assert_eq!(d["dune_slope_above_repose_fraction"], 0.0);
    assert!(v["surface_slope"]["max_deg"].as_f64().unwrap() > 0.0, "{v}");
    assert!(!String::from_utf8_lossy(&o.stderr).contains("warning"));
    // the elevation is not a height above the substrate any more: its long name says so
    let stem = tmp("dunes.npy");
    let mut b = a.clone();
    b.extend(["--format", "npy", "--out", stem.to_str().unwrap()]);
    json(&cellsurf(&b));
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(stem.with_extension("json")).unwrap())
            .unwrap();
    let long = side["fields"]["elevation"]["long_name"].as_str().unwrap();
    assert!(
        long.contains("plus the dune relief about the mean dune level"),
        "{long}"
    );
    // the tiles' automaton, not the bin (the generated tiles' 0.5 mm against 5 mm bins)
    assert_eq!(side["layer_thickness_m"], 0.0005, "{side}");
    assert_eq!(side["bin_size_m"], 0.005, "{side}");
    // 0.3 m rms on a 0.36 m x 0.18 m surface: far steeper than sand can stand
    a.extend(["--dune-rms", "0.3"]);
    let o = cellsurf(&a);
    let v = json(&o);
    assert!(v["dunes"]["max_dune_slope_deg"].as_f64().unwrap() > 32.0);
    assert!(
        v["dunes"]["dune_slope_above_repose_fraction"]
            .as_f64()
            .unwrap()
            > 0.5
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("warning: the dune relief is steeper than sand can stand"),
        "{err}"
    );
    // --quiet silences it, as every warning
    a.push("--quiet");
    let o = cellsurf(&a);
    assert!(o.status.success());
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn a_bin_too_short_for_the_generated_automata_is_named_with_the_least_bin() {
    let mut a = GEN.to_vec();
    a.extend(["--mosaic", "2x2", "--bin-size", "0.0005"]);
    let o = cellsurf(&a);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("--bin-size = 0.0005 m is out of range")
            && e.contains("at least")
            && e.contains("= 0.0008002 m"),
        "{e}"
    );
    // the least bin shown is accepted
    let mut a = GEN.to_vec();
    a.extend([
        "--mosaic",
        "2x2",
        "--bin-size",
        "0.0008002",
        "--json",
        "--quiet",
    ]);
    assert!(cellsurf(&a).status.success());
    // --volume without --out chooses nothing: warned of
    let mut a = GEN.to_vec();
    a.extend(["--mosaic", "2x2", "--volume", "impedance", "--json"]);
    let o = cellsurf(&a);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(e.contains("--volume has no effect without --out"), "{e}");
}

#[test]
fn generate_checks_the_flow_regime_and_the_scenario_model() {
    // sheet flow: the ripple model's own regime test refuses it, as `cellsurf ripple` does
    let sheet = tmp("sheet.toml");
    std::fs::write(&sheet, "model = \"ripple\"\ncurrent_speed = 1.5\n").unwrap();
    let out = tmp("sheet.nc");
    let mut a = GEN.to_vec();
    a.extend(["--ripple-scenario", sheet.to_str().unwrap()]);
    a.extend(["--mosaic", "1x1", "--out", out.to_str().unwrap()]);
    let o = cellsurf(&a);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "sheet flow accepted: {err}");
    assert!(
        err.contains("current_speed = 1.5") && err.contains("sheet flow"),
        "{err}"
    );
    assert!(err.contains("expected a largest speed of"), "{err}");
    assert!(!out.exists());
    // below the threshold of motion nothing would move
    std::fs::write(&sheet, "model = \"ripple\"\ncurrent_speed = 0.1\n").unwrap();
    let o = cellsurf(&a);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "no motion accepted: {err}");
    assert!(err.contains("below the threshold of motion"), "{err}");
    // above the threshold, but the model's rules move no grain (as `cellsurf ripple` finds):
    // the tiles would be the starting bed
    std::fs::write(&sheet, "model = \"ripple\"\nstoss_angle = 0.0\n").unwrap();
    let o = cellsurf(&a);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success(),
        "no motion in the model accepted: {err}"
    );
    assert!(
        err.contains("no motion in the model") && err.contains("stoss_angle = 0 deg"),
        "{err}"
    );
    // a scenario of another model is named
    std::fs::write(&sheet, "model = \"dunes\"\n").unwrap();
    let o = cellsurf(&a);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "a dunes scenario accepted: {err}");
    assert!(err.contains("model = \"dunes\" is out of range"), "{err}");
    assert!(!out.exists());
}

#[test]
fn a_generated_mosaic_records_its_ripple_runs_and_reproduces_from_them() {
    let first = tmp("gen-a.npy");
    let mut a = GEN.to_vec();
    a.extend(["--activity", "0.002", "--mosaic", "2x1", "--quiet"]);
    a.extend(["--out", first.to_str().unwrap()]);
    assert!(cellsurf(&a).status.success());
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(first.with_extension("json")).unwrap())
            .unwrap();
    let p = &side["parameters"];
    assert_eq!(p["ripple_layers"], 10, "{p}");
    assert_eq!(p["ripple_steps"], 40, "{p}");
    assert_eq!(p["ripple_activity"], 0.002, "{p}");
    assert_eq!(p["ripple_d50_mm"], 0.2, "{p}");
    assert_eq!(p["ripple_current_speed"], 0.5, "{p}");
    assert_eq!(p["ripple_wave_amplitude"], 0.0, "{p}");
    // the whole parameter set, read back as the ripple scenario, gives the same bytes
    let scenario = tmp("gen-a.toml");
    std::fs::write(&scenario, p["ripple_scenario"].as_str().unwrap()).unwrap();
    let second = tmp("gen-b.npy");
    let o = cellsurf(&[
        "tile",
        "--generate",
        "--ripple-scenario",
        scenario.to_str().unwrap(),
        "--mosaic",
        "2x1",
        "--quiet",
        "--out",
        second.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(&first).unwrap(),
        std::fs::read(&second).unwrap()
    );
    // NetCDF: the same record as global attributes
    let nc = tmp("gen-a.nc");
    let mut a = GEN.to_vec();
    a.extend(["--mosaic", "1x1", "--quiet", "--out", nc.to_str().unwrap()]);
    assert!(cellsurf(&a).status.success());
    let bytes = std::fs::read(&nc).unwrap();
    let has = |s: &str| bytes.windows(s.len()).any(|w| w == s.as_bytes());
    assert!(has("param_ripple_scenario") && has("param_ripple_d50_mm"));
    assert!(has("current_speed = 0.5"));
    // tiles read from a file carry their own record: no ripple_* parameters
    let m = tmp("from-file.npy");
    let o = cellsurf(&[
        "tile",
        "--tile",
        nc_ripple().to_str().unwrap(),
        "--mosaic",
        "1x1",
        "--quiet",
        "--out",
        m.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let side = std::fs::read_to_string(m.with_extension("json")).unwrap();
    assert!(!side.contains("ripple_scenario"), "{side}");
}

/// A small ripple NetCDF file.
fn nc_ripple() -> PathBuf {
    let r = tmp("small-ripple.nc");
    if !r.exists() {
        let mut g = vec![
            "ripple", "--recipe", "paper", "--nx", "24", "--ny", "12", "--layers", "10",
        ];
        g.extend(["--steps", "20", "--quiet", "--out", r.to_str().unwrap()]);
        let o = cellsurf(&g);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    r
}

#[test]
fn npy_sidecars_are_checked_before_the_run_and_errors_are_words() {
    let r = nc_ripple();
    for (extra, stem, blocked) in [
        (&[][..], "side-a", "side-a.json"),
        (
            &["--volume", "impedance"][..],
            "side-b",
            "side-b_impedance.npy",
        ),
    ] {
        let out = tmp(&format!("{stem}.npy"));
        std::fs::create_dir_all(tmp(blocked)).unwrap();
        let mut a = vec!["tile", "--tile", r.to_str().unwrap(), "--mosaic", "2x2"];
        a.extend(extra);
        a.extend(["--out", out.to_str().unwrap()]);
        let o = cellsurf(&a);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{err}");
        assert!(err.contains("--out") && err.contains(blocked), "{err}");
        assert!(err.contains("not a regular file"), "{err}");
        assert!(
            !err.contains("Custom {") && !err.contains("kind:") && !err.contains("Os {"),
            "{err}"
        );
        assert!(!out.exists(), "no output on error");
    }
}

#[test]
fn generate_options_need_generate_and_angles_have_the_ripple_range() {
    let r = nc_ripple();
    for (extra, want) in [
        (
            &["--size", "32x16"][..],
            "--size applies to tiles generated",
        ),
        (&["--steps", "30"][..], "--steps applies to tiles generated"),
        (
            &["--layers", "12"][..],
            "--layers applies to tiles generated",
        ),
        (&["--nx", "32"][..], "--nx applies to tiles generated"),
        (
            &["--seeds", "1,2"][..],
            "--seeds applies to tiles generated",
        ),
        (
            &["--dunes", "--current-angle", "400"][..],
            "--current-angle = 400 is out of range: expected -360 to 360",
        ),
        (
            &["--dunes", "--current-angle", "-1e9"][..],
            "--current-angle = -1000000000 is out of range",
        ),
        (
            &["--seed", "9223372036854775808"][..],
            "'9223372036854775808' is out of range: expected an integer in [0, 2^53 = 9007199254740992]",
        ),
        // (a NetCDF-3 attribute is a double: 2^53 + 1 would be recorded as 2^53)
        (
            &["--seed", "9007199254740993"][..],
            "--seed = 9007199254740993 is out of range: expected an integer in [0, 2^53 = 9007199254740992]",
        ),
    ] {
        let mut a = vec!["tile", "--tile", r.to_str().unwrap(), "--mosaic", "2x2"];
        a.extend(extra);
        let o = cellsurf(&a);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?} accepted");
        assert!(err.contains(want), "{extra:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    // the edge of the range is accepted
    let mut a = vec!["tile", "--tile", r.to_str().unwrap(), "--mosaic", "2x2"];
    a.extend(["--dunes", "--dune-grid", "24", "--current-angle", "-360"]);
    a.extend(["--seed", "9007199254740992"]);
    let o = cellsurf(&a);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // generated runs: the seeds the ripple model takes (to 2^53), named by the flag given
    for (extra, want) in [
        (
            &["--seed", "9007199254740993"][..],
            "--seed = 9007199254740993",
        ),
        (
            &["--seeds", "1,9223372036854775808"][..],
            "'9223372036854775808' is out of range: expected an integer in [0, 2^53",
        ),
        (
            &["--seeds", "1,9007199254740993"][..],
            "--seeds = 9007199254740993",
        ),
    ] {
        let mut a = GEN.to_vec();
        a.extend(extra);
        let o = cellsurf(&a);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?} accepted");
        assert!(err.contains(want), "{extra:?}: {err}");
        assert!(err.contains("2^53") || err.contains("2^63"), "{err}");
    }
}

/// `--blend` cross-fades different tiles at their edges: with one tile (`--choose same`, or a
/// single tile) it has no effect, and says so, naming the flag; with several tiles and
/// `--choose patches` it acts, without the warning.
#[test]
fn blend_without_effect_is_warned() {
    let warn = |extra: &[&str]| {
        let o = cellsurf(&[GEN, extra, &["--blend", "3"]].concat());
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{extra:?}: {err}");
        err
    };
    let one = "warning: --blend = 3 has no effect: the mosaic lays one tile";
    assert!(warn(&[]).contains(one));
    assert!(warn(&["--seeds", "1,2"]).contains(one));
    let e = warn(&["--seeds", "1,2", "--choose", "patches"]);
    assert!(!e.contains("no effect"), "{e}");
    assert!(!e.contains("not used"), "{e}");
    // tiles that --choose same leaves out are named
    let e = warn(&["--seeds", "1,2,3"]);
    assert!(
        e.contains("--choose same lays only the first tile (seed 1")
            && e.contains("the other 2 (seed 2")
            && e.contains("are not used"),
        "{e}"
    );
}

#[test]
fn hurst_without_effect_is_warned() {
    let run = |extra: &[&str]| {
        let o = cellsurf(&[GEN, &["--dunes", "--dune-grid", "24"], extra].concat());
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{extra:?}: {err}");
        err
    };
    let e = run(&["--dune-wavelength", "0.1", "--hurst", "0.5"]);
    assert!(e.contains("warning: --hurst = 0.5 has no effect"), "{e}");
    assert!(!run(&["--hurst", "0.5"]).contains("has no effect"));
    assert!(!run(&["--dune-wavelength", "0.1"]).contains("has no effect"));
}

/// A --tile that exists but is no NetCDF file is refused for what it is (a folder, a Zarr
/// store, not a NetCDF-3 file), never as "no such file".
#[test]
fn a_tile_that_is_not_a_netcdf_file_is_refused_for_what_it_is() {
    let dir = tmp("not-a-file");
    let store = tmp("a-store.zarr");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::create_dir_all(&store).unwrap();
    let cases = [
        (dir.to_str().unwrap().to_string(), "a folder, not a file"),
        (
            store.to_str().unwrap().to_string(),
            "a Zarr store (a folder), not a NetCDF file: only NetCDF (.nc) ripple files are read here; write the run as one with `cellsurf ripple --out FILE.nc`",
        ),
        ("/dev/null".to_string(), "not a NetCDF-3 file"),
    ];
    for (path, why) in cases {
        let o = cellsurf(&["tile", "--tile", &path, "--mosaic", "2x2"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{path}: {err}");
        assert!(
            err.contains(&format!("--tile {path}")) && err.contains(why),
            "{path}: {err}"
        );
        assert!(!err.contains("no such file"), "{path}: {err}");
    }
    let missing = tmp("absent.nc");
    let o = cellsurf(&[
        "tile",
        "--tile",
        missing.to_str().unwrap(),
        "--mosaic",
        "2x2",
    ]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("no such file"));
}

/// A scenario's value of a generating option without `generate = true` is warned of by its
/// key (the command line refuses the flag); a printed scenario, which holds every key at its
/// default, runs without a warning.
#[test]
fn a_scenarios_generating_keys_without_generate_are_warned_of() {
    let r = nc_ripple();
    let f = tmp("gen-keys.toml");
    let text = format!(
        "model = \"tile\"\ntile = [{:?}]\nmosaic = \"2x2\"\nlayers = 5\nactivity = 0.5\n",
        r.to_str().unwrap()
    );
    std::fs::write(&f, text).unwrap();
    let o = cellsurf(&["tile", "--scenario", f.to_str().unwrap(), "--json"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    for key in ["layers = 5", "activity = 0.5"] {
        assert!(
            err.contains(&format!("warning: the scenario's {key} has no effect")),
            "{key}: {err}"
        );
    }
    let o = cellsurf(&[
        "tile",
        "--tile",
        r.to_str().unwrap(),
        "--mosaic",
        "2x2",
        "--print-scenario",
    ]);
    std::fs::write(&f, &o.stdout).unwrap();
    let o = cellsurf(&["tile", "--scenario", f.to_str().unwrap(), "--json"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && !err.contains("warning"), "{err}");
}

/// The JSON of a `--dry-run` of one tile generated from the ripple scenario `scenario`, with
/// `extra` options.
fn dry_run(scenario: &str, extra: &[&str]) -> serde_json::Value {
    let a = [
        "tile",
        "--generate",
        "--ripple-scenario",
        scenario,
        "--mosaic",
        "1x1",
        "--dry-run",
        "--json",
        "--quiet",
    ];
    json(&cellsurf(&[&a[..], extra].concat()))
}

/// A ripple scenario that `cellsurf ripple --print-scenario` wrote after `--duration` and
/// `--wave-period` (`duration_s` and `wave_period_s` in place of `steps` and `wave_period`)
/// generates the runs that `cellsurf ripple --scenario` makes of it, with the same steps and
/// wave period in steps (it was refused as unknown keys); a typed --steps wins over its
/// `duration_s`.
#[test]
fn a_ripple_scenario_in_seconds_generates_the_ripple_runs_of_it() {
    let scenario = tmp("seconds.toml");
    let ripple = "ripple --size 24x12 --layers 10 --d50 0.3 --current-speed 0.3 \
                  --wave-velocity 0.2 --wave-period 8s --duration 20s --print-scenario";
    let o = cellsurf(&ripple.split_whitespace().collect::<Vec<_>>());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::write(&scenario, &o.stdout).unwrap();
    let s = scenario.to_str().unwrap();
    let run = json(&cellsurf(&["ripple", "--scenario", s, "--json", "--quiet"]));
    let tile = |extra: &[&str]| dry_run(s, extra)["recorded"].clone();
    let r = tile(&[]);
    assert_eq!(r["ripple_steps"], run["steps"], "{r}");
    assert_eq!(
        r["ripple_wave_period"], run["parameters"]["wave_period"],
        "{r}"
    );
    assert!(run["steps"].as_u64().unwrap() > 1000, "{run}");
    assert_eq!(tile(&["--steps", "50"])["ripple_steps"], 50);
}

/// A ripple scenario's stop at equilibrium is not applied to `--generate` runs, which run their
/// whole length: said in a warning, not dropped silently; a 2-D section's scenario is refused.
#[test]
fn generated_tiles_warn_that_until_is_not_applied_and_refuse_sections() {
    let scene = tmp("until-scene.toml");
    // a --generate run of the scenario `text`, with `extra` options: its status and stderr
    let generate = |text: &str, extra: &[&str]| {
        std::fs::write(
            &scene,
            format!("model = \"ripple\"\nlayers = 10\nsteps = 40\n{text}"),
        )
        .unwrap();
        let mut a = vec![
            "tile",
            "--generate",
            "--ripple-scenario",
            scene.to_str().unwrap(),
        ];
        a.extend_from_slice(extra);
        let o = cellsurf(&a);
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (code, err) = generate(
        "nx = 24\nny = 12\nuntil = \"equilibrium\"\n",
        &["--extent", "0.24x0.12"],
    );
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("until = \"equilibrium\" is not applied") && err.contains("40 steps"),
        "{err}"
    );
    // a 2-D section's scenario (the ripple command's default prints one) makes no tiles
    let (code, err) = generate(
        "mode = \"2d\"\nnx = 64\nny = 1\n",
        &["--size", "32x8", "--extent", "0.32x0.08"],
    );
    assert!(
        code == Some(1) && err.contains("mode = \"2d\" is out of range for --generate"),
        "{err}"
    );
}

/// A ripple scenario with its bin in flat-bed travels (`bin_travels`, as the recipe for mature
/// current ripples has it) generates tiles on the bin of the travel, as `cellsurf ripple` runs
/// it (0.75 travels of 0.2 mm sand at 0.5 m/s: 1.86 mm, the automata a tenth of it); a typed
/// `--bin-size` wins.
#[test]
fn a_ripple_scenario_in_travels_generates_tiles_on_the_bin_of_the_travel() {
    let scenario = tmp("travels.toml");
    std::fs::write(
        &scenario,
        "model = \"ripple\"\nnx = 24\nny = 12\nlayers = 40\nbin_size = 0.0025\n\
         layer_thickness = 0.00025\nhop_grains = 4.6875\nbin_travels = 0.75\nsteps = 10\n",
    )
    .unwrap();
    let s = scenario.to_str().unwrap();
    let tile = |extra: &[&str]| dry_run(s, extra);
    let t = tile(&[]);
    assert_eq!(t["bin_size_m"], 0.00186, "{t}");
    let run = json(&cellsurf(&["ripple", "--scenario", s, "--json", "--quiet"]));
    assert_eq!(run["parameters"]["bin_size"], 0.00186, "{run}");
    assert_eq!(run["parameters"]["layer_thickness"], 0.000186, "{run}");
    assert_eq!(tile(&["--bin-size", "0.005"])["bin_size_m"], 0.005);
}

/// Tiles that would not make one seafloor are refused, naming the tile and what differs: a 2-D
/// section (one row), another depth of sand, and an acoustic volume of another model. The
/// mosaic records the acoustic model of its volume.
#[test]
fn tiles_of_another_sand_depth_acoustics_or_a_section_are_refused() {
    let make = |name: &str, extra: &[&str]| {
        let p = tmp(name);
        let mut g = vec!["ripple", "--recipe", "paper", "--steps", "20", "--quiet"];
        g.extend_from_slice(extra);
        g.extend(["--out", p.to_str().unwrap()]);
        let o = cellsurf(&g);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        p
    };
    const TILE: [&str; 4] = ["--size", "24x12", "--layers", "10"];
    let base = make("pool-base.nc", &TILE);
    let deep = make("pool-deep.nc", &["--size", "24x12", "--layers", "40"]);
    let apl = make(
        "pool-apl.nc",
        &[&TILE[..], &["--acoustics", "apl-uw"]].concat(),
    );
    let seed2 = make("pool-seed2.nc", &[&TILE[..], &["--seed", "2"]].concat());
    let section = make("pool-section.nc", &["--size", "48x1", "--layers", "10"]);
    let tile = |tiles: &[&PathBuf], extra: &[&str], out: &str| {
        let o = tmp(out);
        let mut g = vec!["tile", "--out", o.to_str().unwrap()];
        for t in tiles {
            g.extend(["--tile", t.to_str().unwrap()]);
        }
        g.extend_from_slice(extra);
        cellsurf(&g)
    };
    let refused = |o: &Output, want: &[&str]| {
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert!(want.iter().all(|w| e.contains(w)), "{want:?}: {e}");
    };
    refused(
        &tile(&[&base, &deep], &[], "pool-a.nc"),
        &["tile 1 (", "sand depth 0.02 m", "first 0.005 m"],
    );
    refused(
        &tile(&[&base, &apl], &["--volume", "impedance"], "pool-b.nc"),
        &["impedance of acoustics = apl-uw, first of acoustics = hamilton"],
    );
    refused(
        &tile(&[&section], &[], "pool-c.nc"),
        &["a 3-D ripple field (this is a 2-D section of 48 x 1 bins"],
    );
    assert!(!tmp("pool-a.nc").exists() && !tmp("pool-c.nc").exists());
    // grain sizes do not depend on the acoustic model: that pool is one seafloor
    let o = tile(
        &[&base, &apl],
        &["--volume", "grain_size", "--quiet"],
        "pool-d.nc",
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // the same depth and model: accepted, and the model recorded with the volume
    let o = tile(
        &[&base, &seed2],
        &["--volume", "impedance", "--json"],
        "pool-e.nc",
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(tmp("pool-e.nc")).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    let at = text
        .find("param_volume_acoustics")
        .expect("a volume_acoustics attribute");
    assert!(
        text[at..at + 80].contains("hamilton"),
        "{}",
        &text[at..at + 80]
    );
    // a mosaic's .npy set written over an earlier one with a volume: the old volume goes
    let npy = tmp("pool-f.npy");
    for extra in [&["--volume", "impedance"][..], &[]] {
        let mut g = vec!["tile", "--quiet", "--tile", base.to_str().unwrap()];
        g.extend_from_slice(extra);
        g.extend(["--out", npy.to_str().unwrap()]);
        let o = cellsurf(&g);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    assert!(tmp("pool-f.npy").exists() && !tmp("pool-f_impedance.npy").exists());
}

/// A ripple scenario with lengths in units of the orbit (`orbit_reference`): the generated
/// tiles' lengths are scaled to the waves' excursion and recorded so; a typed --bin-size is
/// kept, not scaled.
#[test]
fn generated_tiles_scale_a_scenarios_orbit_lengths_and_keep_a_typed_bin() {
    let f = tmp("orbit-scenario.toml");
    std::fs::write(
        &f,
        "model = \"ripple\"\nmode = \"3d\"\nnx = 16\nny = 16\nlayers = 10\nsteps = 20\ncurrent_speed = 0.0\nwave_amplitude = 0.4\nwave_period_s = 3.1416\nwave_vortex = 0.2\nwave_friction_factor = 0.013\norbit_reference = 0.1\nbin_size = 0.002\nlayer_thickness = 0.0002\nhop_grains = 3.75\ncrest_suspension = 0.01\n",
    )
    .unwrap();
    let run = |extra: &[&str], out: &str| {
        let o = tmp(out);
        let mut g = vec![
            "tile",
            "--generate",
            "--ripple-scenario",
            f.to_str().unwrap(),
            "--json",
            "--out",
            o.to_str().unwrap(),
        ];
        g.extend_from_slice(extra);
        let r = cellsurf(&g);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let e = String::from_utf8_lossy(&r.stderr).into_owned();
        let text = String::from_utf8_lossy(&std::fs::read(o).unwrap()).into_owned();
        (e, text)
    };
    let (e, text) = run(&[], "orbit-a.nc");
    assert!(
        e.contains("A = 0.2000 m (2.0000 x those of orbit_reference = 0.1 m): bin_size = 0.004 m"),
        "{e}"
    );
    assert!(text.contains("bin_size = 0.004\n") && text.contains("orbit_reference = 0.2\n"));
    let (e, text) = run(&["--bin-size", "0.003"], "orbit-b.nc");
    assert!(
        e.contains("bin_size = 0.003 m, layer_thickness = 0.0002 m, hop_grains = 7.5"),
        "{e}"
    );
    assert!(text.contains("bin_size = 0.003\n") && !text.contains("bin_size = 0.006"));
}
