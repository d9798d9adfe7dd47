//! `cellsurf converge STUDY --part i/N` and `--gather`: parts run as separate processes at
//! once, gathered, give the same figure table as the study run whole by one process (apart
//! from the measured run times); a missing or repeated part and bad `--part` values are
//! refused by name; the ray tracer's study splits by step size.
#![cfg(feature = "cli")]

mod common;

use std::path::Path;
use std::process::Command;

use common::cellsurf;

/// The `y` column (the standard errors and means, not the run times) of a figure table,
/// without the `1/sqrt(run time)` guide lines (series 1 of charts 0 and 1), whose ends are
/// set by the measured times.
fn table_values(dir: &Path, study: &str) -> Vec<String> {
    let t = std::fs::read_to_string(dir.join(format!("data/{study}_error_vs_time.csv"))).unwrap();
    t.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("0,1,") && !l.starts_with("1,1,"))
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            format!("{},{},{}", f[0], f[1], f[f.len() - 1])
        })
        .collect()
}

#[test]
fn parts_run_at_once_gather_to_the_whole_study() {
    let base = common::tmp_in("converge-parts", "x");
    let base = base.parent().unwrap();
    let (parts, whole) = (base.join("parts"), base.join("whole"));
    for d in [&parts, &whole] {
        let _ = std::fs::remove_dir_all(d);
        std::fs::create_dir_all(d).unwrap();
    }
    let bin = env!("CARGO_BIN_EXE_cellsurf");
    let children: Vec<_> = (0..3)
        .map(|i| {
            Command::new(bin)
                .args([
                    "converge",
                    "dunes",
                    "--quiet",
                    "--part",
                    &format!("{i}/3"),
                    "--out-dir",
                ])
                .arg(&parts)
                .spawn()
                .unwrap()
        })
        .collect();
    for mut c in children {
        assert!(c.wait().unwrap().success());
    }
    let w = whole.display().to_string();
    let r = cellsurf(&["converge", "dunes", "--out-dir", &w]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success(), "{err}");
    // progress on the way, ending with every run done
    let last = err
        .lines()
        .filter_map(|l| l.strip_prefix("dunes: "))
        .filter_map(|l| l.split_once(" runs done"))
        .next_back()
        .map(|(counts, _)| counts.to_string());
    let (done, total) = last
        .as_deref()
        .and_then(|c| c.split_once('/'))
        .unwrap_or_else(|| panic!("no progress line: {err}"));
    assert_eq!(done, total, "{err}");
    let p = parts.display().to_string();
    // a part missing: refused, naming it
    let moved = base.join("part-2.toml");
    std::fs::rename(parts.join("dunes_error_vs_time.part-2-of-3.toml"), &moved).unwrap();
    let r = cellsurf(&["converge", "dunes", "--gather", "--out-dir", &p]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        !r.status.success() && err.contains("parts without a file: [2]"),
        "{err}"
    );
    // a part twice: refused
    std::fs::copy(&moved, parts.join("dunes_error_vs_time.part-2-of-3.toml")).unwrap();
    std::fs::copy(
        &moved,
        parts.join("dunes_error_vs_time.part-2-of-3.copy.toml"),
    )
    .unwrap();
    let r = cellsurf(&["converge", "dunes", "--gather", "--out-dir", &p]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        !r.status.success() && err.contains("recorded twice"),
        "{err}"
    );
    std::fs::remove_file(parts.join("dunes_error_vs_time.part-2-of-3.copy.toml")).unwrap();
    // all parts: the same table as the whole run
    let r = cellsurf(&["converge", "dunes", "--gather", "--quiet", "--out-dir", &p]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(parts.join("dunes_error_vs_time.png").exists());
    let (a, b) = (table_values(&parts, "dunes"), table_values(&whole, "dunes"));
    assert!(a.len() > 40, "{} points", a.len());
    assert_eq!(a, b);
    std::fs::remove_dir_all(base).unwrap();
}

#[test]
fn bad_parts_are_refused_by_name() {
    for bad in ["3/3", "-1/2", "a/b", "0/0"] {
        let r = cellsurf(&[
            "converge",
            "dunes",
            "--part",
            bad,
            "--out-dir",
            "/nonexistent-x",
        ]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(
            !r.status.success() && err.contains("--part"),
            "{bad}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn the_raytrace_study_splits_by_step_size() {
    let dir = common::tmp_in("converge-raytrace", "x");
    let dir = dir.parent().unwrap().to_path_buf();
    let d = dir.display().to_string();
    for p in ["0/3", "1/3", "2/3"] {
        let r = cellsurf(&[
            "converge",
            "raytrace",
            "--quiet",
            "--part",
            p,
            "--out-dir",
            &d,
        ]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    }
    let r = cellsurf(&[
        "converge",
        "raytrace",
        "--gather",
        "--quiet",
        "--out-dir",
        &d,
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    // chart 0 (error against step size) has no timing in it: 3 series of the 8 step sizes
    let t = std::fs::read_to_string(dir.join("data/raytrace_error_vs_time.csv")).unwrap();
    let ds: Vec<&str> = t
        .lines()
        .filter(|l| l.starts_with("0,0,"))
        .map(|l| l.split(',').nth(2).unwrap())
        .collect();
    assert_eq!(
        ds,
        ["4000", "2000", "1000", "500", "250", "100", "50", "20"]
    );
    // the gathered table records which figure it draws (written into the PNG), as a figure
    // made whole does
    let t = std::fs::read_to_string(dir.join("data/raytrace_error_vs_time.toml")).unwrap();
    assert!(
        t.contains("png_parameters = 'figure = \"raytrace_error_vs_time\"'"),
        "{t}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_subcommands_spelling_names_the_wind_ripple_study() {
    let dir = common::tmp_in("converge-wind-ripples", "x");
    let dir = dir.parent().unwrap().to_path_buf();
    std::fs::create_dir_all(&dir).unwrap();
    let d = dir.display().to_string();
    // An empty folder: the gather finds no part, and says which figure's parts it looked for.
    for name in ["wind-ripples", "windripples"] {
        let r = cellsurf(&["converge", name, "--gather", "--out-dir", &d]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success(), "{name}: {err}");
        assert!(
            err.contains("no windripples_error_vs_time.part-"),
            "{name}: {err}"
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}
