//! Bad input, everywhere: every option of every subcommand that takes a value is given values
//! out of any range (`-1`, `nan`, `1e300`, `abc`). Each run must either be accepted (it exits 0,
//! or is still running after a few seconds) or fail with exit status 1 (2 for a value the
//! command line parser refuses) and a message whose
//! first line names the option as typed and what it expects, without a panic.
//!
//! The options are read from each subcommand's `--help`, so a new option is covered without
//! editing this test.

mod common;

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How long an accepted run may go on before it is stopped (it was accepted).
const ACCEPTED_AFTER: Duration = Duration::from_secs(4);

/// Values out of any option's range.
const BAD: [&str; 4] = ["-1", "nan", "1e300", "abc"];

/// The standard library's words for a value that does not parse, which say neither the form
/// expected nor the range: a refused value says what the option expects instead.
const PARSER_JARGON: [&str; 3] = [
    "invalid digit found in string",
    "invalid float literal",
    "number too large to fit",
];

/// Each subcommand with small base options (so an accepted value runs briefly).
fn subcommands() -> Vec<(&'static str, Vec<&'static str>)> {
    vec![
        ("flame", vec!["--size", "40x46", "--steps", "300"]),
        ("grow", vec!["--size", "40x46", "--steps", "300"]),
        ("dunes", vec!["--size", "16", "--steps", "5"]),
        ("cursor", vec!["--size", "16", "--steps", "1000"]),
        (
            "wind-ripples",
            vec!["--size", "16", "--steps", "2", "--particles", "1000"],
        ),
        ("raytrace", vec!["--length", "2", "--rays", "20"]),
        (
            "ripple",
            vec!["--size", "24x12", "--layers", "10", "--steps", "20"],
        ),
        (
            "tile",
            vec![
                "--generate",
                "--size",
                "24x12",
                "--layers",
                "10",
                "--steps",
                "20",
                "--mosaic",
                "2x2",
            ],
        ),
    ]
}

/// The long options that take a value, from `--help` (`--name <VALUE>`).
fn value_options(sub: &str) -> Vec<String> {
    let out = common::cellsurf(&[sub, "--help"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let mut v = Vec::new();
    for line in text.lines() {
        let t = line.trim_start();
        let t = t.split_once(", ").map_or(t, |(a, b)| {
            if a.starts_with('-') && !a.starts_with("--") {
                b
            } else {
                t
            }
        });
        if let Some(rest) = t.strip_prefix("--")
            && let Some((name, tail)) = rest.split_once(' ')
            && tail.starts_with('<')
        {
            v.push(format!("--{name}"));
        }
    }
    v
}

/// Runs `cellsurf args`; `None` if it was still running after [`ACCEPTED_AFTER`] (stopped),
/// else its exit code and stderr.
fn try_run(args: &[&str], dir: &std::path::Path) -> Option<(Option<i32>, String)> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_cellsurf"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            let out = child.wait_with_output().unwrap();
            return Some((
                out.status.code(),
                String::from_utf8_lossy(&out.stderr).to_string(),
            ));
        }
        if t.elapsed() > ACCEPTED_AFTER {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn every_option_refuses_bad_values_by_name() {
    let dir = common::tmp_in("bad_input", "work");
    std::fs::create_dir_all(&dir).unwrap();
    let mut cases = Vec::new();
    for (sub, base) in subcommands() {
        let options = value_options(sub);
        assert!(options.len() >= 5, "{sub}: options not found in --help");
        for opt in options {
            for bad in BAD {
                cases.push((sub, base.clone(), opt.clone(), bad));
            }
        }
    }
    let queue = std::sync::Mutex::new(cases);
    let failures = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                loop {
                    let Some((sub, base, opt, bad)) = queue.lock().unwrap().pop() else {
                        break;
                    };
                    // The option given replaces the base option of the same name.
                    let mut args = vec![sub];
                    let mut i = 0;
                    while i < base.len() {
                        if base[i] == opt {
                            i += 2;
                            continue;
                        }
                        args.push(base[i]);
                        i += 1;
                    }
                    args.extend([opt.as_str(), bad]);
                    let Some((code, err)) = try_run(&args, &dir) else {
                        continue;
                    };
                    let first = err.lines().next().unwrap_or("");
                    let ok = code == Some(0)
                        || (matches!(code, Some(1) | Some(2))
                            && !err.contains("panicked")
                            && first.starts_with("error: ")
                            && first.contains(opt.as_str())
                            && !PARSER_JARGON.iter().any(|j| first.contains(j)));
                    if !ok {
                        failures.lock().unwrap().push(format!(
                            "`cellsurf {}`: exit {code:?}: {first}",
                            args.join(" ")
                        ));
                    }
                }
            });
        }
    });
    let failures = failures.into_inner().unwrap();
    assert!(
        failures.is_empty(),
        "{} bad values not refused by name:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// A whole number too large for its option's type or for a scenario file (`1e19`, `1e30`,
/// `inf`: past 2^63 - 1) is refused with the option's own range, the words its check states for
/// a value just past it, and not with the integer type's limit (2^63 - 1, 2^32 - 1, 2^64 - 1).
#[test]
fn a_count_too_large_to_hold_is_refused_with_the_options_range() {
    // (subcommand and the options it needs, option, the range's words, a value just past the
    // range that the option's type holds, refused by the option's check)
    let cases: [(&[&str], &str, &str, Option<&str>); 17] = [
        (&["grow"], "--gif-frames", "1 to 2000", Some("2001")),
        (&["dunes"], "--gif-frames", "1 to 2000", Some("2001")),
        (&["grow"], "--series", "1 to 100000 points", Some("100001")),
        (
            &["converge", "growth"],
            "--seeds",
            "3 to 10000",
            Some("10001"),
        ),
        (&["dunes"], "--hop", "1 to 10^6 cells", Some("1000001")),
        (&["dunes"], "--steps", "0 to 10^9", Some("1000000001")),
        (&["cursor"], "--steps", "1 to 10^12", Some("1000000000001")),
        (
            &["cursor", "--wind-field", "rotating"],
            "--wind-arms",
            "0 to 12",
            Some("13"),
        ),
        (
            &["ripple"],
            "--layers",
            "an integer in [1, 4096]",
            Some("4097"),
        ),
        (
            &["ripple"],
            "--steps",
            "an integer in [0, 2^40]",
            Some("1099511627777"),
        ),
        (
            &["tile", "--generate"],
            "--seed",
            "an integer in [0, 2^53",
            Some("9007199254740993"),
        ),
        (
            &["raytrace", "--max-rays", "1e8"],
            "--rays",
            "an integer in [2, 10000000]",
            Some("10000001"),
        ),
        (
            &["raytrace"],
            "--max-bounces",
            "an integer in [0, 100000]",
            Some("100001"),
        ),
        (
            &["wind-ripples"],
            "--threads",
            "0 (all cores) to 4096",
            Some("4097"),
        ),
        (
            &["wind-ripples"],
            "--steps",
            "1 to 1000000000 (1e9)",
            Some("1000000001"),
        ),
        (
            &["serve"],
            "--max-sessions",
            "1 to 1024 sessions",
            Some("1025"),
        ),
        (&["ripple"], "--size", "sides of 3 to 65536 bins", None),
    ];
    let type_limits = ["9223372036854775807", "4294967295", "18446744073709551615"];
    for (sub, opt, range, past) in cases {
        let values: &[&str] = if opt == "--size" {
            &["1e30", "0", "0x8", "8xinf"]
        } else {
            &["1e19", "1e30", "inf", "18446744073709551616"]
        };
        for v in values {
            let mut args = sub.to_vec();
            args.extend([opt, v]);
            let out = common::cellsurf(&args);
            let err = String::from_utf8_lossy(&out.stderr);
            let first = err.lines().next().unwrap_or("");
            assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
            assert!(
                first.contains(opt)
                    && first.contains(&format!("'{v}' is out of range: expected {range}"))
                    && !type_limits.iter().any(|l| first.contains(l)),
                "{args:?}: {first}"
            );
        }
        if let Some(p) = past {
            let mut args = sub.to_vec();
            args.extend([opt, p]);
            let out = common::cellsurf(&args);
            let err = String::from_utf8_lossy(&out.stderr);
            let first = err.lines().next().unwrap_or("");
            assert!(
                !out.status.success() && first.contains(opt) && first.contains(range),
                "{args:?}: the check states another range: {first}"
            );
        }
    }
}
