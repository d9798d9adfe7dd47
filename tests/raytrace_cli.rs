//! `cellsurf raytrace` as a user meets it: the JSON summary's keys, the output files with their
//! provenance, a section read back, and bad input rejected with a message naming the
//! parameter, without a panic or a partial file.
#![cfg(feature = "cli")]

mod common;

use std::path::PathBuf;

use common::cellsurf;

fn tmp(name: &str) -> PathBuf {
    common::tmp_in("raytrace-cli", name)
}

/// A 40-ray fan through the linear thermocline.
const LINEAR: &[&str] = &[
    "--rays",
    "40",
    "--profile",
    "linear",
    "--c0",
    "1525",
    "--gradient",
    "-2.5",
    "--json",
];

/// `cellsurf raytrace --json` over the floor in `nc` (3 m of section, 3 m of water), writing
/// the insonification to `ins`: the JSON summary.
fn trace_over(nc: &std::path::Path, ins: &std::path::Path) -> serde_json::Value {
    let o = cellsurf(&[
        "raytrace",
        "--seafloor",
        nc.to_str().unwrap(),
        "--water-depth",
        "3",
        "--source-depth",
        "2.5",
        "--length",
        "3",
        "--json",
        "--out",
        ins.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn json_summary_and_files() {
    let (ins, bty, sec, rays) = (
        tmp("ins.csv"),
        tmp("floor.bty"),
        tmp("floor.csv"),
        tmp("rays.csv"),
    );
    let mut args = vec!["raytrace", "--length", "12"];
    args.extend(LINEAR);
    args.extend([
        "--out",
        ins.to_str().unwrap(),
        "--bty",
        bty.to_str().unwrap(),
        "--seafloor-csv-out",
        sec.to_str().unwrap(),
        "--rays-csv",
        rays.to_str().unwrap(),
    ]);
    let o = cellsurf(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for k in [
        "rays",
        "insonified_fraction",
        "shadowed_fraction",
        "max_snell_drift",
        "elapsed_s",
        "vertices",
        "version",
        "parameters",
    ] {
        assert!(v.get(k).is_some(), "missing {k}");
    }
    let f = v["insonified_fraction"].as_f64().unwrap();
    assert!(f > 0.0 && f < 1.0);
    assert!((f + v["shadowed_fraction"].as_f64().unwrap() - 1.0).abs() < 1e-12);
    assert!(v["max_snell_drift"].as_f64().unwrap() < 1e-9);
    let text = std::fs::read_to_string(&ins).unwrap();
    assert!(text.starts_with("# cellsurf ") && text.contains("# profile = linear"));
    assert!(!text.contains("NaN"));
    let b = std::fs::read_to_string(&bty).unwrap();
    assert!(b.starts_with("'L'"));
    // the section reads back as a floor: the same shadows from a CSV
    let mut args = vec!["raytrace", "--seafloor-csv", sec.to_str().unwrap()];
    args.extend(LINEAR);
    let again = cellsurf(&args);
    assert!(again.status.success());
    let w: serde_json::Value = serde_json::from_slice(&again.stdout).unwrap();
    assert_eq!(w["insonified_fraction"], v["insonified_fraction"]);
    assert!(
        std::fs::read_to_string(&rays)
            .unwrap()
            .contains("ray,launch_deg")
    );
}

#[test]
fn bad_input_is_a_clear_error() {
    let out = tmp("never.csv");
    for (args, what) in [
        (vec!["--source-depth", "13"], "--source-depth = 13"),
        (vec!["--ds", "-1"], "--ds = -1"),
        (
            vec!["--angle-min", "10", "--angle-max", "5"],
            "--angle-max = 5 is out of range: expected at least --angle-min = 10",
        ),
        (vec!["--profile", "table"], "--profile-table"),
        (vec!["--water-depth", "0.001"], "--water-depth = 0.001"),
        (vec!["--opening", "20"], "--centre-angle"),
        // a step longer than the default longest path: --ds is the cause
        (
            vec!["--ds", "50"],
            "--ds = 50 m is out of range: expected at most the longest ray path",
        ),
    ] {
        let mut a = vec!["raytrace", "--length", "2", "--out", out.to_str().unwrap()];
        a.extend(args.iter());
        let o = cellsurf(&a);
        assert!(!o.status.success());
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains(what) && !e.contains("panicked"), "{a:?}: {e}");
        assert!(!out.exists(), "no file on error");
    }
}

#[test]
fn seafloor_from_a_ripple_file() {
    let nc = tmp("ripple.nc");
    let ins = tmp("from_nc.csv");
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
        "--seed",
        "3",
        "--out",
        nc.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v = trace_over(&nc, &ins);
    assert!(
        v["run"]["seafloor"]
            .as_str()
            .unwrap()
            .contains("ripple file")
    );
    // every vertex has the impedance of its column's top automaton and a finite R0
    let text = std::fs::read_to_string(&ins).unwrap();
    let rows: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .collect();
    assert_eq!(rows.len(), v["vertices"].as_u64().unwrap() as usize);
    for r in rows {
        let r0: f64 = r.rsplit(',').next().unwrap().parse().unwrap();
        assert!(r0 > 0.0 && r0 < 1.0, "{r}");
    }
    let bad = cellsurf(&[
        "raytrace",
        "--seafloor",
        tmp("missing.nc").to_str().unwrap(),
    ]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--seafloor"));
}

/// A flat floor at 20 m from 0 to 100 m, a vertex every metre.
fn flat_csv(name: &str) -> PathBuf {
    let p = tmp(name);
    let text: String = (0..=100).map(|x| format!("{x},20\n")).collect();
    std::fs::write(&p, text).unwrap();
    p
}

/// Options of a floor the run does not build are warned of, not silently recorded.
#[test]
fn floor_options_without_effect_are_warned_of() {
    let flat = flat_csv("flat_unused.csv");
    let o = cellsurf(&[
        "raytrace",
        "--seafloor-csv",
        flat.to_str().unwrap(),
        "--azimuth",
        "30",
        "--seed",
        "5",
        "--rays",
        "10",
        "--json",
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("warning: --azimuth, --seed have no effect: --seafloor-csv gives the section"),
        "{e}"
    );
    let o = cellsurf(&[
        "raytrace",
        "--seafloor-csv",
        flat.to_str().unwrap(),
        "--rays",
        "10",
        "--json",
    ]);
    assert!(!String::from_utf8_lossy(&o.stderr).contains("warning"));
}

/// The insonified fraction by length and by vertex.
fn fraction(extra: &[&str]) -> (f64, f64) {
    let flat = flat_csv("flat_fan.csv");
    let mut a = vec![
        "raytrace",
        "--seafloor-csv",
        flat.to_str().unwrap(),
        "--json",
    ];
    a.extend(extra);
    let o = cellsurf(&a);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let by_length = v["insonified_fraction"].as_f64().unwrap();
    let lit = v["lit_length_m"].as_f64().unwrap();
    assert!((by_length - lit / 100.0).abs() < 1e-12);
    (by_length, v["vertex_insonified_fraction"].as_f64().unwrap())
}

#[test]
fn straight_mode_honours_the_fan() {
    // a horizontal fan from S at 10 m never reaches the floor at 20 m, in either mode
    let flat0 = ["--angle-min", "0", "--angle-max", "0"];
    assert_eq!(fraction(&flat0), (0.0, 0.0));
    assert_eq!(
        fraction(&[&flat0[..], &["--straight"]].concat()),
        (0.0, 0.0)
    );
    // 80 to 90 degrees reach x = 0 and 1 m only (x = 2 m is at 78.7 degrees): the floor up
    // to 10 / tan 80 = 1.76 m
    let steep = ["--angle-min", "80", "--angle-max", "90"];
    let rays = fraction(&steep);
    let straight = fraction(&[&steep[..], &["--straight"]].concat());
    assert!((straight.1 - 2.0 / 101.0).abs() < 1e-12, "{straight:?}");
    let want = 10.0 / 80f64.to_radians().tan() / 100.0;
    assert!((straight.0 - want).abs() < 1e-12, "{straight:?}");
    assert_eq!(rays.1, straight.1);
    assert!((rays.0 - want).abs() < 1e-9, "{rays:?}");
    // the default fan (1.5 to 25 degrees) lights x >= 10 / tan 25 = 21.4 m
    let lit = fraction(&["--straight"]);
    assert!((lit.1 - 79.0 / 101.0).abs() < 1e-12, "{lit:?}");
    let want = 1.0 - 10.0 / 25f64.to_radians().tan() / 100.0;
    assert!((lit.0 - want).abs() < 1e-12, "{lit:?}");
}

#[test]
fn horizontal_ray_path_ends_at_the_section_end() {
    let flat = flat_csv("flat_horizontal.csv");
    let rays = tmp("horizontal_rays.csv");
    let o = cellsurf(&[
        "raytrace",
        "--seafloor-csv",
        flat.to_str().unwrap(),
        "--angle-min",
        "0",
        "--angle-max",
        "0",
        "--rays",
        "2",
        "--quiet",
        "--rays-csv",
        rays.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&rays).unwrap();
    let last: Vec<f64> = text
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(last[2], 100.0, "x of the last point");
    assert_eq!(last[3], 10.0, "depth of the last point");
    assert!((last[4] - 100.0 / 1500.0).abs() < 1e-12, "tau {}", last[4]);
    for l in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let x: f64 = l.split(',').nth(2).unwrap().parse().unwrap();
        assert!((0.0..=100.0).contains(&x), "{l}");
    }
}

#[test]
fn section_length_range_is_the_one_enforced() {
    // the generated field has 5 mm bins: 2e7 samples are 1e5 m
    let o = cellsurf(&["raytrace", "--length", "1e6"]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("--length (section length) = 1000000") && e.contains("100000] m"),
        "{e}"
    );
    assert!(!e.contains("samples = "), "{e}");
}

#[test]
fn a_missing_output_directory_fails_before_any_file() {
    let flat = flat_csv("flat_outputs.csv");
    let (ok, rays) = (tmp("partial_ok.csv"), tmp("partial_rays.csv"));
    let o = cellsurf(&[
        "raytrace",
        "--seafloor-csv",
        flat.to_str().unwrap(),
        "--out",
        ok.to_str().unwrap(),
        "--rays-csv",
        rays.to_str().unwrap(),
        "--out",
        "/nonexistent/x.bty",
    ]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("--out /nonexistent/x.bty") && e.contains("does not exist"),
        "{e}"
    );
    assert!(!ok.exists() && !rays.exists(), "no partial set of files");
}

#[test]
fn seafloor_from_a_tile_mosaic() {
    let nc = tmp("mosaic.nc");
    let ins = tmp("from_mosaic.csv");
    let o = cellsurf(&[
        "tile",
        "--generate",
        "--nx",
        "32",
        "--ny",
        "16",
        "--layers",
        "10",
        "--steps",
        "50",
        "--mosaic",
        "2x2",
        "--volume",
        "impedance",
        "--out",
        nc.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v = trace_over(&nc, &ins);
    assert!(
        v["run"]["seafloor"]
            .as_str()
            .unwrap()
            .contains("tile mosaic")
    );
    let f = v["insonified_fraction"].as_f64().unwrap();
    assert!(f > 0.0 && f <= 1.0, "{f}");
    // the top impedance of each column gives a finite R0 at every vertex
    let text = std::fs::read_to_string(&ins).unwrap();
    let rows: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .collect();
    assert_eq!(rows.len(), v["vertices"].as_u64().unwrap() as usize);
    for r in rows {
        let r0: f64 = r.rsplit(',').next().unwrap().parse().unwrap();
        assert!(r0 > 0.0 && r0 < 1.0, "{r}");
    }
}

#[test]
fn unreadable_seafloor_files_give_short_errors() {
    let junk = tmp("junk.npy");
    std::fs::write(&junk, vec![7u8; 4096]).unwrap();
    let o = cellsurf(&["raytrace", "--seafloor", junk.to_str().unwrap()]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("not a NetCDF-3 file") && e.len() < 300, "{e}");
    let missing = tmp("missing_short.nc");
    let o = cellsurf(&["raytrace", "--seafloor", missing.to_str().unwrap()]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("No such file or directory") && !e.contains("Os {") && e.len() < 300,
        "{e}"
    );
}

/// Runs `raytrace` with `args` (a 2 m section), expecting a refusal that contains every one of
/// `want`, without a panic or an output file.
fn refused(args: &[&str], want: &[&str]) {
    let out = tmp("refused.csv");
    let mut a = vec!["raytrace", "--length", "2", "--out", out.to_str().unwrap()];
    a.extend(args);
    let o = cellsurf(&a);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{args:?} accepted: {e}");
    for w in want {
        assert!(e.contains(w), "{args:?}: {e}");
    }
    assert!(!e.contains("panicked"), "{e}");
    assert!(!out.exists(), "no file on error");
}

#[test]
fn errors_name_the_options_given() {
    // the opening's limit, not an internal "max angle"
    refused(
        &["--opening", "20", "--centre-angle", "85"],
        &[
            "--centre-angle = 85 with --opening = 20",
            "75 to 95",
            "-90 to 90",
        ],
    );
    refused(&["--angle-max", "95"], &["--angle-max = 95", "[-90, 90]"]);
    refused(
        &["--angle-min", "30"],
        &["--angle-max = 25 (default) is out of range: expected at least --angle-min = 30"],
    );
    // the default source depth below a shallow floor: the flag and the floor's depth
    let shallow = tmp("shallow.csv");
    std::fs::write(&shallow, "x,depth\n0,5\n10,5.2\n20,5\n").unwrap();
    refused(
        &["--seafloor-csv", shallow.to_str().unwrap()],
        &[
            "--source-depth = 10 (default) is out of range",
            "(0, 5) m",
            "5 m deep",
        ],
    );
    refused(
        &[
            "--seafloor-csv",
            shallow.to_str().unwrap(),
            "--source-range",
            "30",
        ],
        &["--source-range = 30 is out of range", "0 to 20 m"],
    );
    // the generated floor's seed: the ripple model's range, named by the flag
    refused(
        &["--seed", "9007199254740993"],
        &["--seed = 9007199254740993", "2^53"],
    );
    // any seed: at most 2^63 - 1, what a scenario file holds (past it, the parser states it)
    refused(
        &["--seed", "9223372036854775808"],
        &["'9223372036854775808' is out of range", "2^63 - 1"],
    );
    refused(
        &[
            "--seafloor-csv",
            shallow.to_str().unwrap(),
            "--seed",
            "18446744073709551615",
        ],
        &["'18446744073709551615' is out of range", "2^63 - 1"],
    );
}

#[test]
fn options_of_another_profile_are_refused() {
    let ssp = "tests/fixtures/ssp.csv";
    let temp = "tests/fixtures/temperature.csv";
    refused(
        &["--profile-table", ssp],
        &[
            "--profile-table applies to the table profile only",
            "--profile isovelocity (default)",
        ],
    );
    refused(
        &["--gradient", "0.1"],
        &["--gradient applies to the linear profile only"],
    );
    refused(
        &["--profile", "munk", "--c0", "1490"],
        &[
            "--c0 applies to the isovelocity and linear profiles only",
            "--profile munk",
        ],
    );
    refused(
        &["--profile", "linear", "--salinity", "30"],
        &["--salinity applies to the mackenzie profile only"],
    );
    let mackenzie = |salinity: &str, more: &[&str], want: &[&str]| {
        let args = ["--profile", "mackenzie", "--temperature-table", temp];
        refused(&[&args[..], &["--salinity", salinity], more].concat(), want);
    };
    mackenzie(
        "30",
        &["--salinity-table", temp],
        &["--salinity and --salinity-table both given"],
    );
    // a constant salinity out of Mackenzie's range is named by its flag, not as a table row
    for (v, shown) in [("50", "50"), ("10", "10"), ("nan", "NaN")] {
        let want = format!("error: --salinity = {shown} is out of range");
        mackenzie(v, &[], &[&want, "[25, 40] ppt"]);
    }
    // the options of the profile given are fine
    let o = cellsurf(&[
        "raytrace",
        "--length",
        "2",
        "--profile",
        "linear",
        "--c0",
        "1490",
        "--gradient",
        "0.1",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn outputs_are_checked_and_record_the_profile_table() {
    refused(
        &["--rays-csv", tmp("r.txt").to_str().unwrap()],
        &["--rays-csv", "r.txt: expected a .csv file name"],
    );
    refused(
        &["--seafloor-csv-out", tmp("x.bty").to_str().unwrap()],
        &["--seafloor-csv-out", "x.bty: expected a .csv file name"],
    );
    let folder = tmp("folder.csv");
    std::fs::create_dir_all(&folder).unwrap();
    let o = cellsurf(&[
        "raytrace",
        "--length",
        "2",
        "--out",
        folder.to_str().unwrap(),
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        e.contains("exists and is not a regular file (a folder"),
        "{e}"
    );
    // every output's header names the table the profile came from
    let (csv, bty, floor) = (tmp("tab.csv"), tmp("tab.bty"), tmp("tab_floor.csv"));
    let o = cellsurf(&[
        "raytrace",
        "--length",
        "2",
        "--profile",
        "table",
        "--profile-table",
        "tests/fixtures/ssp.csv",
        "--quiet",
        "--out",
        csv.to_str().unwrap(),
        "--out",
        bty.to_str().unwrap(),
        "--seafloor-csv-out",
        floor.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in [&csv, &floor] {
        let text = std::fs::read_to_string(f).unwrap();
        assert!(
            text.lines()
                .any(|l| l == "# profile_table = tests/fixtures/ssp.csv"),
            "{text}"
        );
    }
    let first = std::fs::read_to_string(&bty).unwrap();
    let first = first.lines().next().unwrap();
    assert!(
        first.contains("profile_table=tests/fixtures/ssp.csv"),
        "{first}"
    );
}

#[test]
fn equal_fan_limits_launch_one_angle() {
    // documented: equal limits (or an opening of 0) are one launch angle for every ray
    for args in [
        &["--angle-min", "10", "--angle-max", "10"][..],
        &["--opening", "0", "--centre-angle", "10"][..],
    ] {
        let mut a = vec!["raytrace", "--length", "2", "--json"];
        a.extend(args);
        let o = cellsurf(&a);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(
            v["run"]["angles_deg"],
            serde_json::json!([10.0, 10.0]),
            "{v}"
        );
    }
}

/// The section `--length` m long at 20 deg cut through the seafloor file `from`: the run's
/// JSON summary and the rows of its `--seafloor-csv-out` file `name` (without the header).
fn section_from(
    from: &std::path::Path,
    name: &str,
    length: &str,
) -> (serde_json::Value, Vec<String>) {
    let out = tmp(name);
    let o = cellsurf(&[
        "raytrace",
        "--seafloor",
        from.to_str().unwrap(),
        "--length",
        length,
        "--azimuth",
        "20",
        "--water-depth",
        "1",
        "--source-depth",
        "0.5",
        "--json",
        "--quiet",
        "--seafloor-csv-out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = std::fs::read_to_string(out)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(String::from)
        .collect();
    (v["insonified_fraction"].clone(), rows)
}

#[test]
fn a_netcdf_mosaic_and_its_zarr_store_give_the_same_section() {
    // 3.7 mm bins: the float32 `x` spacing of the NetCDF file is 0.0036999999 m; the recorded
    // bin size is exact, as the store's
    let (nc, zarr) = (tmp("bins.nc"), tmp("bins.zarr"));
    let _ = std::fs::remove_dir_all(&zarr);
    for out in [&nc, &zarr] {
        let o = cellsurf(&[
            "tile",
            "--generate",
            "--size",
            "24x12",
            "--layers",
            "10",
            "--steps",
            "40",
            "--bin-size",
            "0.0037",
            "--mosaic",
            "4x4",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let (a, b) = (
        section_from(&nc, "bins_nc.csv", "0.3").1,
        section_from(&zarr, "bins_zarr.csv", "0.3").1,
    );
    assert!(a.len() > 50, "{}", a.len());
    assert_eq!(a, b);
}

#[test]
fn steep_linear_gradient_matches_the_circular_arcs() {
    // c = 1500 - 74.5 z over a flat floor at 20 m (10 m/s there): every ray of the default fan
    // (1.5 to 25 deg from S at 10 m) is a circle centred where c would vanish; the lit floor
    // runs from the 25-degree ray's hit to the 1.5-degree ray's. The fixed 0.25 m step used
    // to throw the rays off (insonified fraction 0, Snell drift 18).
    let (c0, g, z0) = (1500.0f64, -74.5f64, 10.0f64);
    let zc = z0 - (c0 + g * z0) / g;
    let hit = |deg: f64| {
        let th = deg.to_radians();
        let r = (c0 + g * z0) / (g.abs() * th.cos());
        -r * th.sin() + (r * r - (20.0 - zc).powi(2)).sqrt()
    };
    let want = (hit(1.5) - hit(25.0)) / 100.0;
    assert!((want - 0.0341603).abs() < 1e-6, "{want}");
    let flat = flat_csv("flat_steep.csv");
    let o = cellsurf(&[
        "raytrace",
        "--seafloor-csv",
        flat.to_str().unwrap(),
        "--profile",
        "linear",
        "--gradient",
        "-74.5",
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let got = v["insonified_fraction"].as_f64().unwrap();
    assert!((got - want).abs() < 1e-8, "{got} vs the arcs' {want}");
    let drift = v["max_snell_drift"].as_f64().unwrap();
    assert!(drift < 1e-5, "{drift}");
    assert!(
        !String::from_utf8_lossy(&o.stderr).contains("warning"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn mackenzie_surface_reflected_rays_keep_snell() {
    let flat = flat_csv("flat_mackenzie.csv");
    let t = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/temperature.csv"
    );
    let o = cellsurf(&[
        "raytrace",
        "--seafloor-csv",
        flat.to_str().unwrap(),
        "--profile",
        "mackenzie",
        "--temperature-table",
        t,
        "--angle-min",
        "-30",
        "--angle-max",
        "-30",
        "--rays",
        "2",
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let drift = v["max_snell_drift"].as_f64().unwrap();
    assert!(drift < 1e-9, "drift {drift} after a surface reflection");
}

#[test]
fn typed_fan_limits_override_a_scenario_opening() {
    let flat = flat_csv("flat_scenario.csv");
    let f = flat.to_str().unwrap();
    let o = cellsurf(&[
        "raytrace",
        "--seafloor-csv",
        f,
        "--opening",
        "10",
        "--centre-angle",
        "10",
        "--print-scenario",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let sc = tmp("opening.toml");
    std::fs::write(&sc, &o.stdout).unwrap();
    let sc = sc.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut a = vec!["raytrace", "--scenario", sc, "--json"];
        a.extend(extra);
        let o = cellsurf(&a);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    assert_eq!(
        run(&[])["run"]["angles_deg"],
        serde_json::json!([5.0, 15.0])
    );
    let v = run(&["--angle-min", "2", "--angle-max", "5"]);
    assert_eq!(v["run"]["angles_deg"], serde_json::json!([2.0, 5.0]));
    assert!(v["parameters"].get("opening").is_none(), "{v}");
    // one typed limit: the other is the scenario fan's (10 -+ 10 / 2), not the default 25
    let v = run(&["--angle-min", "2"]);
    assert_eq!(v["run"]["angles_deg"], serde_json::json!([2.0, 15.0]));
    let v = run(&["--angle-max", "12"]);
    assert_eq!(v["run"]["angles_deg"], serde_json::json!([5.0, 12.0]));
    // limits with an opening, both typed: still refused
    let o = cellsurf(&[
        "raytrace",
        "--scenario",
        sc,
        "--angle-min",
        "2",
        "--opening",
        "4",
    ]);
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("give either --opening"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn rays_beyond_max_rays_and_bad_impedance_are_named() {
    refused(
        &["--rays", "10000000"],
        &["--rays = 10000000 is more than --max-rays = 2000000 (default)"],
    );
    refused(
        &["--rays", "50", "--max-rays", "40"],
        &["--rays = 50 is more than --max-rays = 40:"],
    );
    let bad = tmp("bad_impedance.csv");
    std::fs::write(&bad, "0,20\n50,20\n100,20,abc\n").unwrap();
    refused(
        &["--seafloor-csv", bad.to_str().unwrap()],
        &[
            "--seafloor-csv",
            "bad_impedance.csv",
            "line 3",
            "impedance 'abc'",
        ],
    );
}

/// `cellsurf raytrace` run in the folder `dir`.
fn cellsurf_in(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_cellsurf"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

/// Two outputs naming one file in other spellings (`z.csv` and `./z.csv`, a path and its
/// absolute form, `sub/y.csv` and `sub/../sub/y.csv`) are refused before the run, naming both
/// options; the file already there is left as it was.
#[test]
fn one_file_named_twice_in_other_spellings_is_refused_before_the_run() {
    let dir = tmp("spellings");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    let abs = dir.join("w.csv");
    let cases: [(&[&str], &str, &str); 4] = [
        (
            &["--out", "z.csv", "--seafloor-csv-out", "./z.csv"],
            "--seafloor-csv-out ./z.csv: the same file as --out z.csv",
            "z.csv",
        ),
        (
            &["--out", "z.csv", "--rays-csv", "./z.csv"],
            "--rays-csv ./z.csv: the same file as --out z.csv",
            "z.csv",
        ),
        (
            &[
                "--out",
                abs.to_str().unwrap(),
                "--seafloor-csv-out",
                "w.csv",
            ],
            "--seafloor-csv-out w.csv: the same file as --out",
            "w.csv",
        ),
        (
            &[
                "--out",
                "sub/y.csv",
                "--seafloor-csv-out",
                "sub/../sub/y.csv",
            ],
            "--seafloor-csv-out sub/../sub/y.csv: the same file as --out sub/y.csv",
            "sub/y.csv",
        ),
    ];
    for (args, want, file) in cases {
        std::fs::write(dir.join(file), "OLD\n").unwrap();
        let mut a = vec!["raytrace", "--length", "2"];
        a.extend(args);
        let o = cellsurf_in(&dir, &a);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
        assert!(e.contains(want), "{args:?}: {e}");
        // before the run: no summary, and the file as it was
        assert!(o.stdout.is_empty(), "{args:?} ran");
        assert_eq!(
            std::fs::read_to_string(dir.join(file)).unwrap(),
            "OLD\n",
            "{args:?}"
        );
    }
}

/// A run whose ray budget (`--max-rays`) runs out says so on stderr, records the budget and the
/// truncation in its files and JSON, and counts the floor it did not resolve apart from the
/// shadow.
#[test]
fn an_exhausted_ray_budget_is_warned_of_recorded_and_not_called_shadow() {
    let run = |budget: Option<&str>, quiet: bool, out: &PathBuf| {
        let mut a = vec![
            "raytrace",
            "--length",
            "10",
            "--json",
            "--out",
            out.to_str().unwrap(),
        ];
        if let Some(b) = budget {
            a.extend(["--max-rays", b]);
        }
        if quiet {
            a.push("--quiet");
        }
        let o = cellsurf(&a);
        let e = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{e}");
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        (v, e, std::fs::read_to_string(out).unwrap())
    };
    let (full, e, text) = run(None, false, &tmp("budget_full.csv"));
    assert!(!e.contains("warning"), "{e}");
    assert_eq!(full["truncated"], false);
    assert_eq!(full["unresolved_fraction"], 0.0);
    assert!(text.contains("# max_rays = 2000000\n"), "{text}");
    assert!(text.contains("# truncated = false\n"), "{text}");
    let lit = full["insonified_fraction"].as_f64().unwrap();
    assert!(lit > 0.3, "{full}");
    for budget in ["250", "1000"] {
        let (v, e, text) = run(Some(budget), false, &tmp("budget_cut.csv"));
        assert!(
            e.contains(&format!(
                "warning: the ray budget ran out (--max-rays = {budget})"
            )) && e.contains("truncated"),
            "{e}"
        );
        assert_eq!(v["truncated"], true, "{v}");
        assert!(text.contains(&format!("# max_rays = {budget}\n")), "{text}");
        assert!(text.contains("# truncated = true\n"), "{text}");
        assert!(text.contains("# unresolved_fraction = "), "{text}");
        let f = |k: &str| v[k].as_f64().unwrap();
        let (l, s, u) = (
            f("insonified_fraction"),
            f("shadowed_fraction"),
            f("unresolved_fraction"),
        );
        assert!(u > 0.0, "{v}");
        assert!((l + s + u - 1.0).abs() < 1e-9, "{v}");
        // the floor left unresolved is not called shadow: the shadow is at most the
        // complete run's
        assert!(s <= 1.0 - lit + 1e-9, "{s} against {}", 1.0 - lit);
        // --quiet: no warning, the same record
        let (_, e, _) = run(Some(budget), true, &tmp("budget_quiet.csv"));
        assert!(e.is_empty(), "{e}");
    }
}

/// `cellsurf raytrace --scenario FILE --length 2` and `extra`, the file `name` holding `text`.
fn on_scenario(name: &str, text: &str, extra: &[&str]) -> std::process::Output {
    let p = tmp(name);
    std::fs::write(&p, text).unwrap();
    let mut a = vec![
        "raytrace",
        "--scenario",
        p.to_str().unwrap(),
        "--length",
        "2",
    ];
    a.extend_from_slice(extra);
    cellsurf(&a)
}

/// An opening with its centre is recorded as the fan it gives (the parameters, the scenario
/// printed, the files' headers); a scenario with both an opening and limits of its own is
/// refused naming the keys, as the command line refuses both.
#[test]
fn the_fan_of_an_opening_is_recorded_and_a_scenario_with_both_fans_is_refused() {
    let o = cellsurf(&[
        "raytrace",
        "--length",
        "2",
        "--opening",
        "20",
        "--centre-angle",
        "10",
        "--json",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["run"]["angles_deg"], serde_json::json!([0.0, 20.0]));
    assert_eq!(v["parameters"]["angle_min"], 0.0, "{v}");
    assert_eq!(v["parameters"]["angle_max"], 20.0, "{v}");
    let o = cellsurf(&[
        "raytrace",
        "--opening",
        "20",
        "--centre-angle",
        "10",
        "--print-scenario",
    ]);
    let sc = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        sc.contains("angle_min = 0.0") && sc.contains("angle_max = 20.0"),
        "{sc}"
    );
    // the printed scenario runs the same fan
    let o = on_scenario("fan_printed.toml", &sc, &["--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["run"]["angles_deg"], serde_json::json!([0.0, 20.0]));
    // both fans in one scenario: refused, naming the keys
    for (extra, want) in [
        (
            "angle_min = 5.0\nangle_max = 8.0\n",
            "angle_min = 5 and angle_max = 8 given with opening = 20 and centre_angle = 10",
        ),
        ("angle_min = 30\n", "angle_min = 30 given with opening = 20"),
    ] {
        let o = on_scenario(
            "fan_both.toml",
            &format!("model = \"raytrace\"\nopening = 20.0\ncentre_angle = 10\n{extra}"),
            &[],
        );
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert!(e.contains(want) && e.contains("give either opening"), "{e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    }
    // an opening with the default limits (as older cellsurf printed it): the opening's fan
    let o = on_scenario(
        "fan_old.toml",
        "model = \"raytrace\"\nangle_min = 1.5\nangle_max = 25.0\nopening = 20.0\ncentre_angle = 10\n",
        &["--json"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["run"]["angles_deg"], serde_json::json!([0.0, 20.0]));
    assert_eq!(v["parameters"]["angle_max"], 20.0, "{v}");
}

/// A whole-number option past what its type or a scenario file holds is refused naming the
/// option, the value and the range, on the command line and in a scenario file.
#[test]
fn whole_numbers_past_their_type_are_refused_by_name_and_range() {
    for v in [
        "1e19",
        "9223372036854775808",
        "18446744073709551615",
        "1e30",
    ] {
        for extra in [&[][..], &["--print-scenario"][..]] {
            let mut a = vec!["raytrace", "--length", "2", "--max-rays", v];
            a.extend(extra);
            let o = cellsurf(&a);
            let e = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{v}: {e}");
            assert!(
                e.contains(&format!("'{v}' for '--max-rays"))
                    && e.contains("at most 9223372036854775807"),
                "{v}: {e}"
            );
            assert!(!e.contains("u64"), "{e}");
        }
    }
    // in a scenario file, the key's own range where it has one, else what a file holds
    for (model, key, extra, range) in [
        ("raytrace", "max_rays", "", "9223372036854775807"),
        (
            "raytrace",
            "rays",
            "",
            "expected an integer in [2, 10000000]",
        ),
        ("raytrace", "seed", "", "9223372036854775807"),
        ("cursor", "steps", "size = 16\n", "expected 1 to 10^12"),
    ] {
        let p = tmp(&format!("huge_{model}_{key}.toml"));
        std::fs::write(&p, format!("model = \"{model}\"\n{extra}{key} = 1e19\n")).unwrap();
        let o = cellsurf(&[model, "--scenario", p.to_str().unwrap(), "--quiet"]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{key}: {e}");
        assert!(
            e.contains(&format!("{key} = 1e19 is out of range: expected")) && e.contains(range),
            "{key}: {e}"
        );
        assert_eq!(e.trim_end().lines().count(), 1, "{key}: {e}");
    }
}

/// A scenario's whole number written as a float is read as the option reads it, up to 2^63 - 1
/// (`rays = 1e17`, past 2^53), and refused by the option's check with its range; a value the
/// scenario set is marked as the scenario's, not as a default.
#[test]
fn a_scenarios_large_whole_float_is_checked_and_marked_as_the_scenarios() {
    for (value, want) in [
        (
            "1e17",
            "--rays = 100000000000000000 (from --scenario) is out of range: expected an integer \
             in [2, 10000000]",
        ),
        (
            "3000000",
            "--rays = 3000000 (from --scenario) is more than --max-rays = 2000000 (default)",
        ),
    ] {
        let p = tmp(&format!("rays_{value}.toml"));
        std::fs::write(&p, format!("model = \"raytrace\"\nrays = {value}\n")).unwrap();
        let o = cellsurf(&["raytrace", "--scenario", p.to_str().unwrap(), "--quiet"]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{value}: {e}");
        assert!(e.contains(want), "{value}: {e}");
    }
    // typed, the same check names the flag alone
    let o = cellsurf(&["raytrace", "--rays", "1e17", "--quiet"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains(
            "--rays = 100000000000000000 is out of range: expected an integer in [2, 10000000]"
        ),
        "{e}"
    );
}

/// `--straight` traces no rays (without `--rays-csv`): the tracer's options given are warned
/// of by name, not recorded as used, and not range-checked; with `--rays-csv` only
/// `--max-rays` has no effect.
#[test]
fn tracer_options_without_effect_under_straight_are_warned_of() {
    let out = tmp("straight_unused.csv");
    let o = cellsurf(&[
        "raytrace",
        "--length",
        "2",
        "--straight",
        "--ds",
        "1e9",
        "--max-bounces",
        "0",
        "--max-path",
        "50",
        "--max-rays",
        "300",
        "--rays",
        "250",
        "--out",
        out.to_str().unwrap(),
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains(
            "warning: --rays, --ds, --max-bounces, --max-path, --max-rays have no effect with --straight"
        ),
        "{e}"
    );
    let text = std::fs::read_to_string(&out).unwrap();
    for k in [
        "# rays",
        "# ds_m",
        "# max_bounces",
        "# max_path_m",
        "# max_rays",
    ] {
        assert!(!text.contains(k), "{k}: {text}");
    }
    assert!(text.contains("# mode = straight"), "{text}");
    // without them: no warning, the same data
    let plain = tmp("straight_plain.csv");
    let o = cellsurf(&[
        "raytrace",
        "--length",
        "2",
        "--straight",
        "--out",
        plain.to_str().unwrap(),
    ]);
    assert!(!String::from_utf8_lossy(&o.stderr).contains("warning"));
    let data = |p: &PathBuf| {
        std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(data(&out), data(&plain));
    // with --rays-csv the fan is traced: only the budget has no effect
    let rays = tmp("straight_rays.csv");
    let o = cellsurf(&[
        "raytrace",
        "--length",
        "2",
        "--straight",
        "--rays",
        "5",
        "--max-rays",
        "300",
        "--rays-csv",
        rays.to_str().unwrap(),
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("warning: --max-rays has no effect with --straight") && !e.contains("--rays,"),
        "{e}"
    );
    assert!(
        std::fs::read_to_string(&rays)
            .unwrap()
            .contains("# rays = 5")
    );
}

/// A table's errors name the option and the file it came from.
#[test]
fn table_errors_name_the_option_and_the_file() {
    let write = |name: &str, text: &str| {
        let p = tmp(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let hot = write("hot.csv", "0,20\n20,31\n");
    let junk = write("tjunk.csv", "0,20\n20,x\n");
    let shallow_s = write("salshallow.csv", "0,35\n5,35\n");
    let shallow_p = write("ssp_shallow.csv", "0,1500\n5,1500\n");
    let temp = "tests/fixtures/temperature.csv";
    let m = ["--profile", "mackenzie"];
    let cases: Vec<(Vec<&str>, Vec<String>)> = vec![
        (
            [&m[..], &["--temperature-table", &hot]].concat(),
            vec![format!(
                "in --temperature-table {hot}: temperature table value (row 2) = 31"
            )],
        ),
        (
            [&m[..], &["--temperature-table", &junk]].concat(),
            vec![format!(
                "in --temperature-table {junk}: temperature table: line 2"
            )],
        ),
        (
            [
                &m[..],
                &["--temperature-table", temp, "--salinity-table", &shallow_s],
            ]
            .concat(),
            vec![format!(
                "in --salinity-table {shallow_s}: salinity table last depth = 5"
            )],
        ),
        (
            vec!["--profile", "table", "--profile-table", &shallow_p],
            vec![format!(
                "in --profile-table {shallow_p}: profile table last depth = 5"
            )],
        ),
    ];
    for (args, want) in cases {
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        refused(&args, &want);
    }
}

/// A ripple run's Zarr store is a seafloor as its NetCDF file is: the same section.
#[test]
fn a_ripple_netcdf_file_and_its_zarr_store_give_the_same_section() {
    let (nc, zarr) = (tmp("ripple_bed.nc"), tmp("ripple_bed.zarr"));
    let _ = std::fs::remove_dir_all(&zarr);
    for out in [&nc, &zarr] {
        let o = cellsurf(&[
            "ripple",
            "--recipe",
            "paper",
            "--size",
            "32x16",
            "--layers",
            "10",
            "--steps",
            "200",
            "--fields",
            "elevation,impedance",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let (a, b) = (
        section_from(&nc, "ripple_bed_nc.csv", "1"),
        section_from(&zarr, "ripple_bed_zarr.csv", "1"),
    );
    assert!(a.1.len() > 50, "{}", a.1.len());
    // the impedance of each column's top automaton, from both
    assert!(
        a.1[1].split(',').nth(2).is_some_and(|z| !z.is_empty()),
        "{:?}",
        a.1[1]
    );
    assert_eq!(a, b);
}

/// A relative path in a scenario file is read from the scenario's folder, from any working
/// directory (`profile_table = "t.csv"` in `runs/s.toml` reads `runs/t.csv`); an absolute path
/// is kept; a path typed on the command line is read from the working directory.
#[test]
fn scenario_paths_are_read_from_the_scenario_folder() {
    let dir = tmp("scenario_paths");
    let runs = dir.join("runs");
    std::fs::create_dir_all(&runs).unwrap();
    let table = std::fs::read_to_string("tests/fixtures/ssp.csv").unwrap();
    std::fs::write(runs.join("t.csv"), &table).unwrap();
    let scenario = "model = \"raytrace\"\nprofile = \"table\"\nprofile_table = \"t.csv\"\n\
                    length = 2.0\n";
    std::fs::write(runs.join("s.toml"), scenario).unwrap();
    let json = |o: &std::process::Output| -> serde_json::Value {
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    // from the folder above the scenario's, and from the scenario's own folder
    let above = json(&cellsurf_in(
        &dir,
        &["raytrace", "--scenario", "runs/s.toml", "--json"],
    ));
    assert_eq!(above["parameters"]["profile_table"], "runs/t.csv");
    let inside = json(&cellsurf_in(
        &runs,
        &["raytrace", "--scenario", "s.toml", "--json"],
    ));
    assert_eq!(inside["parameters"]["profile_table"], "t.csv");
    assert_eq!(above["insonified_fraction"], inside["insonified_fraction"]);
    // a path typed on the command line is read from the working directory, where there is no
    // t.csv
    let o = cellsurf_in(
        &dir,
        &[
            "raytrace",
            "--scenario",
            "runs/s.toml",
            "--profile-table",
            "t.csv",
        ],
    );
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("--profile-table t.csv"), "{e}");
    // an absolute path in the scenario is kept
    let abs = runs.join("t.csv");
    std::fs::write(
        runs.join("abs.toml"),
        scenario.replace("\"t.csv\"", &format!("{:?}", abs.to_str().unwrap())),
    )
    .unwrap();
    let absolute = json(&cellsurf_in(
        &dir,
        &["raytrace", "--scenario", "runs/abs.toml", "--json"],
    ));
    assert_eq!(
        absolute["parameters"]["profile_table"],
        abs.to_str().unwrap()
    );
    // a missing file is named with the path read
    std::fs::remove_file(runs.join("t.csv")).unwrap();
    let o = cellsurf_in(&dir, &["raytrace", "--scenario", "runs/s.toml"]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("runs/t.csv"), "{e}");
}

/// A scenario's option for another sound-speed profile (`profile_table` with the isovelocity
/// profile) is kept but said to have no effect, as the command line refuses it.
#[test]
fn a_scenarios_option_for_another_profile_is_warned_of() {
    let dir = common::tmp_in("raytrace-other-profile", "");
    let f = dir.join("s.toml");
    std::fs::write(
        &f,
        "model = \"raytrace\"\nprofile = \"isovelocity\"\nprofile_table = \"nonexist.csv\"\n",
    )
    .unwrap();
    let o = common::cellsurf(&[
        "raytrace",
        "--scenario",
        f.to_str().unwrap(),
        "--length",
        "2",
        "--rays",
        "20",
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("warning: the scenario's profile_table =")
            && e.contains("nonexist.csv has no effect: it applies to the table profile only"),
        "{e}"
    );
}

/// A 2-D ripple section is one row: a cut along it is traced, a cut across it (which would be a
/// floor of one height) is refused, naming `--azimuth`.
#[test]
fn a_cut_across_a_two_d_section_is_refused() {
    let nc = tmp("section.nc");
    let o = cellsurf(&[
        "ripple",
        "--size",
        "64x1",
        "--layers",
        "10",
        "--steps",
        "100",
        "--quiet",
        "--out",
        nc.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let trace = |azimuth: &str| {
        cellsurf(&[
            "raytrace",
            "--rays",
            "20",
            "--water-depth",
            "0.5",
            "--source-depth",
            "0.3",
            "--length",
            "0.1",
            "--seafloor",
            nc.to_str().unwrap(),
            "--azimuth",
            azimuth,
            "--quiet",
        ])
    };
    for along in ["0", "180", "-180"] {
        let o = trace(along);
        assert!(
            o.status.success(),
            "{along}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    for across in ["90", "30", "-45"] {
        let o = trace(across);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{across}: {e}");
        assert!(
            e.starts_with(&format!(
                "error: --azimuth = {across} deg crosses the seafloor, a 2-D section"
            )),
            "{e}"
        );
    }
}
