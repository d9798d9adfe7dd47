//! The `cellsurf` program as a user meets it: JSON summaries, files written, reproducible
//! output, and bad input rejected with a message and a non-zero exit (never a panic).

mod common;

use std::path::PathBuf;
use std::process::Output;

use common::cellsurf;

fn tmp(name: &str) -> PathBuf {
    common::tmp_in("cli", name)
}

fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object on stdout")
}

#[test]
fn json_summary_has_the_promised_keys() {
    let small = [
        "--size", "40x46", "--start", "8", "--steps", "3000", "--json",
    ];
    for (scene, keys) in [
        ("flame", vec!["front_radius_cv"]),
        ("crystal", vec!["axis_diagonal_ratio"]),
        ("deposit", vec!["mode1_amplitude", "mean_elevation"]),
    ] {
        let mut args = vec![scene];
        args.extend(small);
        let v = json(&cellsurf(&args));
        for k in [
            "scene",
            "steps",
            "accepted",
            "occupied",
            "elapsed_s",
            "version",
            "parameters",
        ]
        .iter()
        .chain(keys.iter())
        {
            assert!(v.get(k).is_some(), "{scene}: missing {k} in {v}");
        }
        assert_eq!(v["scene"], scene);
        assert_eq!(v["steps"], 3000.0);
    }
}

#[test]
fn same_seed_same_output_bytes() {
    let a = tmp("a.csv");
    let b = tmp("b.csv");
    for p in [&a, &b] {
        let out = cellsurf(&[
            "flame",
            "--size",
            "40x46",
            "--start",
            "8",
            "--steps",
            "4000",
            "--seed",
            "7",
            "--csv",
            p.to_str().unwrap(),
            "--quiet",
        ]);
        assert!(out.status.success());
    }
    let (ta, tb) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert_eq!(ta, tb);
    let text = String::from_utf8(ta).unwrap();
    assert!(text.starts_with("# cellsurf "), "version recorded");
    assert!(text.contains("# seed = 7"), "parameters recorded");
}

#[test]
fn figure_and_animation_files_are_written() {
    let png = tmp("f.png");
    let gif = tmp("f.gif");
    let out = cellsurf(&[
        "crystal",
        "--size",
        "48x56",
        "--start",
        "10",
        "--steps",
        "4000",
        "--snapshots",
        "1000,4000",
        "--out",
        png.to_str().unwrap(),
        "--gif",
        gif.to_str().unwrap(),
        "--gif-frames",
        "5",
        "--quiet",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    // Provenance chunks: the version and the run's parameters.
    let has = |needle: &[u8]| bytes.windows(needle.len()).any(|w| w == needle);
    assert!(has(b"Software") && has(b"cellsurf "), "version chunk");
    assert!(
        has(b"parameters") && has(b"scene = \"crystal\""),
        "parameters chunk"
    );
    assert_eq!(&std::fs::read(&gif).unwrap()[..3], b"GIF");
}

#[test]
fn bad_input_is_rejected_without_a_panic() {
    let cases: &[(&[&str], &str)] = &[
        (&["flame", "--n", "-1"], "--n = -1"),
        (&["flame", "--n", "NaN"], "--n = NaN"),
        (&["flame", "--size", "0"], "'0' for '--size"),
        (
            &["flame", "--size", "20x21"],
            "--size (lattice height) = 21",
        ),
        (&["flame", "--snapshots", "5,3"], "--snapshots"),
        (&["flame", "--steps", "0"], "--steps = 0"),
        (&["flame", "--steps", "-1"], "'-1' for '--steps"),
        (&["grow", "--start", "-3"], "--start = -3"),
        (&["flame", "--out", "x.nc"], "--out x.nc"),
        (&["flame", "--size", "abc"], "not a size"),
        (&["grow", "--lattice", "tri"], "tri"),
        (&["ca", "--ca-rule", "9"], "--ca-rule"),
        (
            &["flame", "--scenario", "/nonexistent/x.toml"],
            "--scenario",
        ),
        (&["figures", "--only", "nope"], "nope"),
        (&["converge", "growth", "--seeds", "1"], "--seeds = 1"),
    ];
    for (args, needle) in cases {
        let out = cellsurf(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn failed_run_leaves_no_partial_file() {
    let png = tmp("never.png");
    let _ = std::fs::remove_file(&png);
    let out = cellsurf(&["flame", "--n", "-2", "--out", png.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(!png.exists());
}

/// Figures of measured run times are drawn from their committed table: regenerating them
/// gives the same bytes; `cellsurf converge MODEL` re-measures table and figure.
#[test]
fn measured_figures_redraw_from_their_table_byte_for_byte() {
    let dir = common::tmp_in("converge", "figs");
    let d = dir.to_str().unwrap();
    let out = common::cellsurf(&["converge", "raytrace", "--out-dir", d]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let png = dir.join("raytrace_error_vs_time.png");
    let csv = dir.join("data/raytrace_error_vs_time.csv");
    let first = std::fs::read(&png).unwrap();
    let table = std::fs::read_to_string(&csv).unwrap();
    assert!(
        table.lines().filter(|l| !l.starts_with('#')).count() > 5,
        "{table}"
    );
    for _ in 0..2 {
        let out = common::cellsurf(&[
            "figures",
            "--only",
            "raytrace_error_vs_time",
            "--out-dir",
            d,
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(
            std::fs::read(&png).unwrap(),
            first,
            "redrawn from the table"
        );
        assert_eq!(
            std::fs::read_to_string(&csv).unwrap(),
            table,
            "table untouched"
        );
    }
    // A damaged table is an error naming the file, not a silent re-measurement.
    std::fs::write(&csv, "chart,series,x,y\n0,0,one,2\n").unwrap();
    let out = common::cellsurf(&[
        "figures",
        "--only",
        "raytrace_error_vs_time",
        "--out-dir",
        d,
    ]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("raytrace_error_vs_time.csv"));
    std::fs::remove_dir_all(dir.parent().unwrap()).ok();
}

/// A disc of the default size sits on the middle cell of a lattice with odd sides, and holds
/// the cell nearest its centre where it falls between cells (a hex lattice whose middle row is
/// shifted half a cell); a start that holds no cell is refused by its flag.
#[test]
fn a_default_disc_runs_on_every_size_and_an_empty_start_is_named() {
    for size in ["21", "21x20", "20x21"] {
        let args = [
            "grow",
            "--lattice",
            "square4",
            "--size",
            size,
            "--shape",
            "disc",
        ];
        let out = cellsurf(&[&args[..], &["--steps", "10", "--json"]].concat());
        assert!(
            out.status.success(),
            "{size}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // a hex lattice whose middle row is shifted half a cell: the disc of diameter 1 falls
    // between two cells and holds the one nearest its centre, a one-cell seed
    for size in ["6", "10", "10x14"] {
        let out = cellsurf(&[
            "grow", "--size", size, "--shape", "disc", "--events", "1", "--json",
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{size}: {err}");
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        // the seed's one cell and the one event's
        assert_eq!(
            (&v["occupied"], &v["accepted"]),
            (&2.into(), &1.into()),
            "{size}: {v}"
        );
    }
    // a default the run cannot use is named with its flag
    let out = cellsurf(&["grow", "--shape", "flat", "--start", "0"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("--start = 0"), "{err}");
}

/// `--n -0` is n = 0, recorded as 0 (a scenario file or JSON holding `-0.0` reads as a
/// different value to a user comparing runs).
#[test]
fn a_negative_zero_exponent_is_recorded_as_zero() {
    let out = cellsurf(&["flame", "--n", "-0", "--steps", "10", "--print-scenario"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    assert!(
        text.contains("\nn = 0.0\n") && !text.contains("-0"),
        "{text}"
    );
}

/// A flag the run does not use is warned about, naming the flag and why (growth scenes and
/// dunes); the run still succeeds, and the same run where the flag acts has no such warning.
#[test]
fn flags_without_effect_are_warned() {
    let warned = |args: &[&str]| {
        let out = cellsurf(args);
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{args:?}: {err}");
        err
    };
    let ca_flags = [
        "--n", "3", "--weight", "axes", "--start", "4", "--seed", "9",
    ];
    let ca = warned(&[&["ca", "--size", "16x16", "--steps", "5"][..], &ca_flags].concat());
    for w in [
        "warning: --n = 3 has no effect",
        "warning: --weight = axes has no effect",
        "warning: --start = 4 has no effect with --shape point",
        "warning: --seed = 9 has no effect: the deterministic CA",
    ] {
        assert!(ca.contains(w), "{ca}");
    }
    let flame = ["flame", "--size", "64x64", "--steps", "5"];
    let e = warned(&[&flame[..], &["--ca-rule", "1,2"]].concat());
    assert!(
        e.contains("warning: --ca-rule has no effect with --sampler exact"),
        "{e}"
    );
    let output_flags = ["--snapshots", "2,5", "--series", "7", "--gif-frames", "3"];
    let e = warned(&[&flame[..], &output_flags].concat());
    for w in [".png", ".csv", ".gif"] {
        assert_eq!(
            e.matches(&format!("has no effect without a {w} output"))
                .count(),
            1,
            "{e}"
        );
    }
    let dunes = ["dunes", "--size", "16", "--steps", "2", "--gif-frames", "3"];
    let e = warned(&dunes);
    assert!(
        e.contains("warning: --gif-frames has no effect without a .gif output"),
        "{e}"
    );
    // The same flags where they act: no warning.
    let files = [tmp("flags.png"), tmp("flags.csv"), tmp("flags.gif")];
    let dunes_gif = tmp("flags-dunes.gif");
    let outs: Vec<&str> = files
        .iter()
        .flat_map(|f| ["--out", f.to_str().unwrap()])
        .collect();
    for args in [
        [&flame[..], &ca_flags].concat(),
        ["ca", "--size", "16x16", "--steps", "5", "--ca-rule", "1,2"].to_vec(),
        [&flame[..], &output_flags, &outs].concat(),
        [&dunes[..], &["--out", dunes_gif.to_str().unwrap()]].concat(),
    ] {
        let e = warned(&args);
        assert!(!e.contains("has no effect"), "{args:?}: {e}");
    }
}

/// `converge` and `figures` warn of the flags a run would not use, and refuse an `--out-dir`
/// that is a file by name, before any work.
#[test]
fn figures_and_converge_warn_of_flags_they_do_not_use() {
    let dir = tmp("figures-flags");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // --seeds (growth only) is warned of with another study, not refused (the gather then
    // fails: the folder holds no parts)
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let out = common::cellsurf(&[
        "converge",
        "dunes",
        "--seeds",
        "5",
        "--gather",
        "--out-dir",
        empty.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("warning: --seeds has no effect with `converge dunes`"),
        "{err}"
    );
    assert!(
        !out.status.success() && err.contains("no dunes_error_vs_time.part-"),
        "{err}"
    );
    // --list lists every figure: --only and --out-dir are warned of; an --out-dir that is a
    // file is refused by name before any work
    let out = common::cellsurf(&["figures", "--list", "--only", "growth_fig3_ca"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("warning: --only has no effect with --list"),
        "{err}"
    );
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let out = common::cellsurf(&[
        "figures",
        "--only",
        "growth_fig3_ca",
        "--out-dir",
        file.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(
        err.contains("--out-dir") && err.contains("not a folder"),
        "{err}"
    );
    // a folder that cannot be made is named with the flag and the path
    let below = file.join("sub");
    let out = common::cellsurf(&[
        "figures",
        "--only",
        "growth_fig3_ca",
        "--out-dir",
        below.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(
        err.contains(&format!("cannot create --out-dir {}", below.display())),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A GIF or a series asked for with more frames or rows than the run has timesteps has one a
/// timestep (the initial state included), and says so; within the timesteps, as many as asked.
#[test]
fn frames_and_series_beyond_the_timesteps_are_one_a_timestep_and_said() {
    let (gif, csv) = (tmp("ten.gif"), tmp("ten.csv"));
    let (g, c) = (gif.to_str().unwrap(), csv.to_str().unwrap());
    let run = |frames: &str, series: &str| {
        let o = common::cellsurf(&[
            "grow",
            "--size",
            "16",
            "--steps",
            "10",
            "--gif-frames",
            frames,
            "--series",
            series,
            "--out",
            g,
            "--out",
            c,
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let rows = std::fs::read_to_string(&csv)
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .count()
            - 1;
        (
            common::gif_frames(&gif),
            rows,
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (frames, rows, err) = run("2000", "1000");
    assert_eq!((frames, rows), (11, 11), "{err}");
    assert!(
        err.contains("--gif-frames = 2000 is more than the run's 10 timesteps")
            && err.contains("--series = 1000 is more than the run's 10 timesteps"),
        "{err}"
    );
    let (frames, rows, err) = run("5", "4");
    assert_eq!((frames, rows), (6, 5), "{err}");
    assert!(!err.contains("warning"), "{err}");
    // the defaults (60 frames, the scene's series) are not warned of
    let o = common::cellsurf(&[
        "grow", "--size", "16", "--steps", "10", "--out", g, "--out", c,
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && !err.contains("warning"), "{err}");
    assert_eq!(common::gif_frames(&gif), 11, "{err}");
    // a scenario's series is the user's too (a scenario without one keeps the scene's)
    let with = tmp("ten_series.toml");
    let without = tmp("ten_no_series.toml");
    std::fs::write(&with, "scene = \"grow\"\nsteps = 10\nseries = 100\n").unwrap();
    std::fs::write(&without, "scene = \"grow\"\nsteps = 10\n").unwrap();
    let scenario = |file: &std::path::Path| {
        let o = common::cellsurf(&[
            "grow",
            "--scenario",
            file.to_str().unwrap(),
            "--size",
            "16",
            "--out",
            c,
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let err = scenario(&with);
    assert!(
        err.contains("the scenario's series = 100 is more than the run's 10 timesteps"),
        "{err}"
    );
    let err = scenario(&without);
    assert!(!err.contains("warning"), "{err}");
}
