//! Bad input, everywhere: every option of every subcommand that takes a value is given values
//! out of any range (`-1`, `nan`, `1e300`, `abc`). Each run must either be accepted (it exits 0,
//! or is still running after a few seconds) or fail with exit status 1 (2 for a value the
//! command line parser refuses) and a message whose
//! error line (the first, after any warnings) names the option as typed and what it expects,
//! without a panic.
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
                    // (the error line, after any warnings)
                    let first = err
                        .lines()
                        .find(|l| l.starts_with("error: "))
                        .or(err.lines().next())
                        .unwrap_or("");
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

/// Whole-number options, one a line: the subcommand and the options it needs, then the option
/// and a value just past its range. A huge value must be refused with the same range as the
/// value just past it.
const WHOLE_OPTIONS: &[&str] = &[
    "grow --size 16 --steps 9007199254740993",
    "grow --size 16 --steps 200 --events 9007199254740993",
    "grow --size 16 --steps 200 --snapshots 201",
    "grow --size 16 --steps 200 --sampler ca --ca-rule 7",
    "grow --size 16 --steps 200 --series 100001",
    "grow --size 16 --steps 200 --gif-frames 2001",
    "grow --size 16 --steps 200 --seed 9223372036854775808",
    "converge growth --seeds 10001",
    "ripple --size 8x4 --steps 5 --layers 4097",
    "ripple --size 8x4 --layers 2 --steps 1099511627777",
    "ripple --size 8x4 --layers 2 --steps 5 --seed 9007199254740993",
    "ripple --size 8x4 --layers 2 --steps 5 --out r.nc --snapshots 6",
    "tile --generate --size 8x4 --steps 5 --mosaic 2x2 --dry-run --layers 4097",
    "tile --generate --size 8x4 --layers 2 --mosaic 2x2 --dry-run --steps 1099511627777",
    "tile --generate --size 8x4 --layers 2 --steps 5 --mosaic 2x2 --dry-run --seeds 9007199254740993",
    "tile --generate --size 8x4 --layers 2 --steps 5 --mosaic 2x2 --dry-run --seed 9007199254740993",
    "tile --generate --size 8x4 --layers 2 --steps 5 --mosaic 2x2 --dry-run --dunes --dune-seed 9007199254740993",
    "tile --generate --size 8x4 --layers 2 --steps 5 --mosaic 2x2 --dry-run --dunes --dune-grid 16385",
    "tile --generate --size 8x4 --layers 2 --steps 5 --mosaic 2x2 --dry-run --seeds 1,2 --choose patches --blend 5",
    "raytrace --length 2 --rays 10000001",
    "raytrace --length 2 --max-bounces 100001",
    "raytrace --length 2 --max-rays 9007199254740993",
    "raytrace --length 2 --seed 9223372036854775808",
    "wind-ripples --size 16 --steps 1000000001",
    "wind-ripples --size 16 --steps 2 --particles 1073741825",
    "wind-ripples --size 16 --steps 2 --threads 4097",
    "dunes --size 16 -i 1000000001",
    "dunes --size 16 --steps 5 --variant werner --hop 1000001",
    "dunes --size 16 --steps 5 --gif-frames 2001",
    "cursor --size 16 --steps 1000000000001",
    "cursor --size 16 --steps 100 --wind-field rotating --wind-arms 13",
    "serve --max-sessions 1025",
    "serve --port 65536",
];

/// `--size` of each model, one a line: the subcommand and the options it needs, then a side
/// just below its range and one just above it.
const SIZES: &[&str] = &[
    "grow --steps 200 0 16384",
    "ripple --layers 2 --steps 5 2 65537",
    "tile --generate --layers 2 --steps 5 --mosaic 2x2 --dry-run 2 65537",
    "dunes --steps 5 2 4097",
    "cursor --steps 100 2 4097",
    "wind-ripples --steps 2 0 4097",
];

/// A line of [`WHOLE_OPTIONS`] or [`SIZES`]: the words before its last two, and those two.
fn last_two(line: &str) -> (String, &str, &str) {
    let words: Vec<&str> = line.split_whitespace().collect();
    let n = words.len();
    (words[..n - 2].join(" "), words[n - 2], words[n - 1])
}

/// The error line of what `cellsurf args` prints on stderr (after any warnings), which must
/// be a refusal (exit 1 or 2, no panic).
fn refusal(args: &[&str], dir: &std::path::Path) -> String {
    let (code, err) = try_run(args, dir).unwrap_or_else(|| panic!("`{args:?}` was accepted"));
    assert!(
        matches!(code, Some(1) | Some(2)) && !err.contains("panicked"),
        "`cellsurf {}`: exit {code:?}: {err}",
        args.join(" ")
    );
    let line = err.lines().find(|l| l.starts_with("error: "));
    line.unwrap_or("").to_string()
}

/// What a refusal says the range is: the text after its last ": " (`1 to 2000`).
fn range_text(line: &str) -> &str {
    line.rsplit(": ").next().unwrap_or(line)
}

/// Checks that `huge` given to `opt` is refused naming the option, the value as typed and
/// the range that `past` (just past the range) is refused with; the failures are pushed.
fn same_range(base: &str, opt: &str, past: &str, huge: &str, failures: &mut Vec<String>) {
    let dir = common::tmp_in("bad_input", "whole");
    std::fs::create_dir_all(&dir).unwrap();
    let run = |v: &str| {
        let mut args: Vec<&str> = base.split_whitespace().collect();
        args.extend([opt, v]);
        refusal(&args, &dir)
    };
    let (expected, got) = (run(past), run(huge));
    let named = |line: &str, v: &str| {
        line.starts_with("error: ")
            && line.contains(opt)
            && line.contains(v)
            && range_text(line) == range_text(&expected)
    };
    if !named(&expected, past) {
        failures.push(format!("{base} {opt} {past}: no range: {expected}"));
    } else if !named(&got, huge) {
        failures.push(format!(
            "{base} {opt} {huge}: {got}\n    (expected the range of {past}: {expected})"
        ));
    }
}

#[test]
fn huge_whole_numbers_are_refused_with_the_options_range() {
    let mut failures = Vec::new();
    for line in WHOLE_OPTIONS {
        let (base, opt, past) = last_two(line);
        for huge in ["1e19", "1e30", "inf"] {
            same_range(&base, opt, past, huge, &mut failures);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn sizes_are_refused_with_the_models_range_of_sides() {
    let mut failures = Vec::new();
    for line in SIZES {
        let (base, below, above) = last_two(line);
        same_range(&base, "--size", below, "0", &mut failures);
        for huge in ["1e30", "nan"] {
            same_range(&base, "--size", above, huge, &mut failures);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
