//! The conventions every subcommand shares (docs/cli.md): the `--json` envelope, `--out` by
//! extension with every file reported on stderr, `--quiet`, and `--print-scenario` /
//! `--scenario` round trips.

mod common;

use common::{cellsurf, tmp_in};

/// Each model's subcommand with small options and the output files it is asked for.
fn cases() -> Vec<(
    &'static str,
    &'static str,
    Vec<&'static str>,
    Vec<&'static str>,
)> {
    vec![
        (
            "flame",
            "growth",
            vec!["--size", "40x46", "--start", "8", "--steps", "2000"],
            vec!["f.png", "f.gif", "f.csv"],
        ),
        (
            "dunes",
            "dunes",
            vec!["--size", "24", "--steps", "10", "-d"],
            vec!["d.png", "d.gif"],
        ),
        (
            "cursor",
            "cursor",
            vec![
                "--size",
                "24",
                "--steps",
                "20000",
                "--wind-field",
                "uniform",
            ],
            vec!["c.png"],
        ),
        (
            "wind-ripples",
            "wind-ripples",
            vec!["--size", "16", "--steps", "4", "--particles", "4000"],
            vec!["w.png", "w.npy"],
        ),
        (
            "raytrace",
            "raytrace",
            vec!["--length", "2", "--rays", "20"],
            vec!["r.csv", "r.bty"],
        ),
        (
            "tile",
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
            vec!["t.npy"],
        ),
        (
            "ripple",
            "ripple",
            vec!["--size", "24x12", "--layers", "10", "--steps", "20"],
            vec!["b.nc"],
        ),
    ]
}

fn json(out: &std::process::Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object on stdout")
}

#[test]
fn json_envelope_lists_every_output_and_stderr_reports_it() {
    for (sub, model, args, files) in cases() {
        let dir = tmp_in("conventions", sub);
        std::fs::create_dir_all(&dir).unwrap();
        let paths: Vec<String> = files
            .iter()
            .map(|f| dir.join(f).display().to_string())
            .collect();
        let mut a = vec![sub];
        a.extend(&args);
        for p in &paths {
            a.extend(["--out", p.as_str()]);
        }
        a.push("--json");
        let out = cellsurf(&a);
        let v = json(&out);
        let keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
        assert_eq!(
            keys[..5],
            ["model", "version", "parameters", "elapsed_s", "outputs"],
            "{sub}"
        );
        assert_eq!(v["model"], model, "{sub}");
        assert_eq!(v["version"], env!("CARGO_PKG_VERSION"));
        assert!(v["elapsed_s"].as_f64().unwrap() >= 0.0);
        // Typed parameters: the seed is a number, not a string.
        assert!(
            v["parameters"]["seed"].is_u64(),
            "{sub}: {}",
            v["parameters"]
        );
        let outputs: Vec<&str> = v["outputs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_str().unwrap())
            .collect();
        let err = String::from_utf8_lossy(&out.stderr);
        for p in &paths {
            assert!(
                outputs.contains(&p.as_str()),
                "{sub}: {p} not in {outputs:?}"
            );
            assert!(err.contains(&format!("wrote {p}")), "{sub}: {err}");
            assert!(std::path::Path::new(p).exists());
        }
        // --quiet: nothing on stderr.
        a.push("--quiet");
        let out = cellsurf(&a);
        assert!(out.status.success());
        assert!(
            out.stderr.is_empty(),
            "{sub}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn printed_scenario_reruns_the_same_run() {
    for (sub, _, args, _) in cases() {
        let dir = tmp_in("conventions-scenario", sub);
        std::fs::create_dir_all(&dir).unwrap();
        let mut a = vec![sub];
        a.extend(&args);
        a.extend(["--seed", "5"]);
        let mut p = a.clone();
        p.push("--print-scenario");
        let out = cellsurf(&p);
        assert!(out.status.success(), "{sub}");
        // the scenario records the version that wrote it and the command that runs it
        let first = String::from_utf8_lossy(&out.stdout)
            .lines()
            .next()
            .unwrap_or_default()
            .to_string();
        assert_eq!(
            first,
            format!(
                "# cellsurf {} scenario: `cellsurf {sub} --scenario FILE`",
                env!("CARGO_PKG_VERSION")
            ),
            "{sub}"
        );
        let file = dir.join("s.toml");
        std::fs::write(&file, &out.stdout).unwrap();
        let f = file.display().to_string();
        let mut direct = a.clone();
        direct.push("--json");
        let from_file = [sub, "--scenario", f.as_str(), "--json"];
        let (x, y) = (json(&cellsurf(&direct)), json(&cellsurf(&from_file)));
        assert_eq!(x["parameters"], y["parameters"], "{sub}");
        // What a ripple run started from: the default's recipe, or the file (no recipe).
        if sub == "ripple" {
            assert_eq!(x["recipe"], "mature-current");
            assert!(y["recipe"].is_null(), "{y}");
        }
        // The same run: every key but the timings (and that start) agrees.
        let strip = |v: &serde_json::Value| {
            let mut o = v.as_object().unwrap().clone();
            o.retain(|k, _| {
                !k.ends_with("_s") && !k.ends_with("per_s") && !k.contains("rss") && k != "recipe"
            });
            o
        };
        assert_eq!(strip(&x), strip(&y), "{sub}");
        // An option typed on the command line wins over the file.
        let over = json(&cellsurf(&[
            sub,
            "--scenario",
            f.as_str(),
            "--seed",
            "6",
            "--json",
        ]));
        assert_eq!(over["parameters"]["seed"], 6, "{sub}");
    }
}

#[test]
fn unknown_extension_and_wrong_scenario_model_are_refused_by_name() {
    let out = cellsurf(&["dunes", "--size", "16", "--steps", "2", "--out", "x.nc"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(err.contains("--out x.nc") && err.contains(".png"), "{err}");
    let f = tmp_in("conventions", "cursor.toml");
    std::fs::write(&f, "model = \"cursor\"\n").unwrap();
    let out = cellsurf(&["dunes", "--scenario", f.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(err.contains("'cursor' scenario, not 'dunes'"), "{err}");
}

/// Every output of a run is moved into place only when the whole run succeeded: a run that
/// fails on a later output leaves none of the others (and no temporary file). The write fails
/// for real: a file-size limit (`ulimit -f`) that the picture, written first, fits and the
/// `.npy` does not (the program ignores the signal the limit raises, SIGXFSZ, which would
/// otherwise kill it with its temporary file left).
#[test]
fn a_run_that_fails_late_leaves_none_of_its_outputs() {
    let dir = tmp_in("conventions", "late_failure");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let npy = dir.join("s.npy");
    let png = dir.join("s.png");
    // (a 256 x 256 grid: the .npy is 512 KiB, the picture about 40 KB; the limit, 300 blocks,
    // is 150 KiB in the 512-byte blocks of a POSIX shell, 300 KiB in 1024-byte ones)
    let args = format!(
        "wind-ripples --size 256 --particles 100 --steps 3 --out {} --out {}",
        npy.display(),
        png.display()
    );
    let run = |limit: &str| {
        std::process::Command::new("sh")
            .arg("-c")
            .arg(format!("ulimit -f {limit}; exec \"$0\" {args}"))
            .arg(env!("CARGO_BIN_EXE_cellsurf"))
            .output()
            .expect("run cellsurf under sh")
    };
    let out = run("300");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("s.npy"), "{err}");
    assert!(err.contains("no output was written"), "{err}");
    // and no file rolled back is reported as written
    assert!(!err.contains("wrote "), "{err}");
    let left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(left.is_empty(), "{left:?}: {err}");
    // The same run without the limit writes all three.
    let out = run("unlimited");
    assert!(out.status.success());
    assert!(npy.is_file() && png.is_file() && dir.join("s.json").is_file());
    // reported once they are in place
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!("wrote {}", npy.display()))
            && err.contains(&format!("wrote {}", png.display())),
        "{err}"
    );
}

/// The `.npy`'s sidecar `NAME.json` is an output like the others: one in the way (a folder) is
/// refused before the run, naming it, and nothing is written.
#[test]
fn a_sidecar_in_the_way_is_refused_before_the_run() {
    let dir = tmp_in("conventions", "sidecar_in_the_way");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("s.json")).unwrap();
    let npy = dir.join("s.npy");
    let out = cellsurf(&[
        "wind-ripples",
        "--size",
        "8",
        "--particles",
        "100",
        "--steps",
        "3",
        "--out",
        npy.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.starts_with("error: --out (the sidecar of the .npy)") && err.contains("s.json"),
        "{err}"
    );
    assert!(!npy.exists(), "{err}");
}

/// A reader that closes standard output early (`| head`) ends the run quietly: exit 0, no
/// panic, and the outputs are still written.
#[test]
fn a_closed_standard_output_is_not_a_panic() {
    use std::process::{Command, Stdio};
    let dir = tmp_in("conventions", "closed_stdout");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("g.csv");
    let mut child = Command::new(env!("CARGO_BIN_EXE_cellsurf"))
        .args([
            "grow",
            "--size",
            "64",
            "--steps",
            "1e5",
            "--json",
            "--out",
            csv.to_str().unwrap(),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Close the reading end before the run prints anything.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(csv.is_file());
}

/// Two outputs of one run may not share a path, and an old single-format option names its
/// format by the extension too.
#[test]
fn two_outputs_with_one_path_are_refused() {
    let dir = tmp_in("conventions", "same_path");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let w = dir.join("w.png");
    let out = cellsurf(&[
        "cursor",
        "--size",
        "16",
        "--steps",
        "100",
        "--out",
        w.to_str().unwrap(),
        "--save-wind",
        w.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--save-wind") && err.contains("same file"),
        "{err}"
    );
    assert!(!w.exists());
    let x = dir.join("same.x");
    let out = cellsurf(&[
        "grow",
        "--size",
        "32",
        "--steps",
        "100",
        "--csv",
        x.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--csv") && err.contains(".csv"), "{err}");
    assert!(!x.exists());
}

/// A measured figure (run times) drawn into a new folder comes out as the committed figure,
/// byte for byte, from the table the program was built with.
#[test]
fn a_measured_figure_in_a_new_folder_is_the_committed_one() {
    let dir = tmp_in("conventions", "measured_new_folder");
    let _ = std::fs::remove_dir_all(&dir);
    let name = "windripples_error_vs_time";
    let (made, committed) = common::figure_and_committed(name, &dir);
    assert!(
        made == committed,
        "{name}.png differs from the committed figure"
    );
    assert!(dir.join(format!("data/{name}.csv")).is_file());
}

/// Each of these is refused by name before any work: an option the chosen model does not use,
/// a scenario that gives what the command line refuses together, a printed scenario that could
/// not run, a seed a scenario file cannot hold, a growth lattice beyond its slots.
#[test]
fn unused_options_and_impossible_scenarios_are_refused_by_name() {
    let dir = tmp_in("conventions", "refused");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let both = dir.join("both.toml");
    std::fs::write(
        &both,
        "model = \"cursor\"\nsea_level = 3.0\nsea_quantile = 0.5\n",
    )
    .unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["dunes", "--size", "8", "--steps", "3", "-q", "2"],
            "-q applies",
        ),
        (
            vec!["dunes", "-d", "--size", "8", "--steps", "3", "-w", "5"],
            "-w applies",
        ),
        (
            vec!["dunes", "--size", "8", "--steps", "3", "--hop", "4"],
            "--hop applies",
        ),
        (
            vec!["dunes", "--variant", "werner", "--hop", "0"],
            "--hop = 0",
        ),
        (
            vec![
                "cursor",
                "--steps",
                "10",
                "--scenario",
                both.to_str().unwrap(),
            ],
            "sea_level (the scenario's), sea_quantile (the scenario's) are given together",
        ),
        (vec!["cursor", "--k", "5", "--print-scenario"], "--k = 5"),
        (
            vec!["wind-ripples", "--kappa", "-1", "--print-scenario"],
            "--kappa = -1",
        ),
        (
            vec!["wind-ripples", "--steps", "1e12"],
            "--steps = 1000000000000",
        ),
        (vec!["grow", "--seed", "9223372036854775808"], "--seed"),
        (
            vec!["grow", "--size", "20000", "--steps", "10"],
            "--size = 20000x20000",
        ),
    ];
    for (args, needle) in cases {
        let out = cellsurf(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} ran");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?} printed a scenario");
    }
}

/// A run that needs more memory than the machine has is refused by name before it starts
/// (an allocation that fails would abort the program).
#[test]
fn a_run_larger_than_the_memory_is_refused_by_name() {
    let avail_kb: Option<u64> = std::fs::read_to_string("/proc/meminfo").ok().and_then(|t| {
        t.lines()
            .find(|l| l.starts_with("MemAvailable:"))?
            .split_whitespace()
            .nth(1)?
            .parse()
            .ok()
    });
    // 2^30 particles need about 51.5 GB: checked where the machine has less.
    let Some(kb) = avail_kb.filter(|&kb| (kb as f64) * 1024.0 < 50e9) else {
        return;
    };
    let out = cellsurf(&[
        "wind-ripples",
        "--particles",
        "1073741824",
        "--size",
        "16",
        "--steps",
        "1",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--particles 1073741824") && err.contains("GB"),
        "{err} ({kb} kB)"
    );
}

/// A limit set on the process (here `ulimit -v`, as batch schedulers and containers set limits
/// of their own) counts as the memory available: the run is refused by name, not aborted by
/// the allocation that fails.
#[test]
fn a_run_larger_than_the_process_may_have_is_refused_by_name() {
    let (code, err) = under_600_mb("grow --lattice square4 --size 16383x16383 --steps 1 --quiet");
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("--size 16383x16383 needs about 2.7 GB") && err.contains("ulimit -v"),
        "{err}"
    );
}

/// `cellsurf ARGS` under `ulimit -v 600000` (600 MB of address space): its exit code and
/// standard error.
fn under_600_mb(args: &str) -> (Option<i32>, String) {
    under_ulimit(600000, args)
}

/// `cellsurf ARGS` under `ulimit -v KB`: its exit code and standard error.
fn under_ulimit(kb: u64, args: &str) -> (Option<i32>, String) {
    let bin = env!("CARGO_BIN_EXE_cellsurf");
    let out = std::process::Command::new("bash")
        .arg("-c")
        .arg(format!("ulimit -v {kb} && exec {bin} {args}"))
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A ripple volume larger than the process may have is refused by --size and --layers.
#[test]
fn a_ripple_run_larger_than_the_process_may_have_is_refused_by_name() {
    let (code, err) = under_600_mb("ripple --size 4096x4096 --layers 30 --steps 1 --quiet");
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("error: --size 4096x4096 with --layers 30 needs about")
            && err.contains("ulimit -v")
            && err.contains("choose a smaller one"),
        "{err}"
    );
    // a small run is not refused
    let (code, err) = under_600_mb("ripple --size 64x32 --layers 10 --steps 5 --quiet");
    assert_eq!(code, Some(0), "{err}");
}

/// The runs of `tile --generate`, and a mosaic index larger than the process may have, are
/// refused by name.
#[test]
fn a_tile_run_larger_than_the_process_may_have_is_refused_by_name() {
    let (code, err) = under_600_mb(
        "tile --generate --size 4096x4096 --layers 30 --steps 1 --mosaic 1x1 --quiet --dry-run",
    );
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains(
            "error: --size 4096x4096 with --layers 30 (1 tile of the --generate runs) needs about"
        ) && err.contains("ulimit -v"),
        "{err}"
    );
    let (code, err) = under_600_mb(
        "tile --generate --size 16x16 --layers 5 --steps 1 --mosaic 16000x16000 --quiet --dry-run",
    );
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("error: --mosaic 16000x16000 needs about") && err.contains("ulimit -v"),
        "{err}"
    );
    let (code, err) = under_600_mb(
        "tile --generate --size 16x16 --layers 5 --steps 1 --mosaic 4x4 --quiet --dry-run",
    );
    assert_eq!(code, Some(0), "{err}");
}

/// A copy of the NetCDF-3 file `from` whose header declares `n x n` columns (its data cut
/// short: what is refused from the header is never read).
fn with_columns(from: &std::path::Path, to: &std::path::Path, n: u32) {
    let mut b = std::fs::read(from).unwrap();
    let be = |b: &[u8], at: usize| u32::from_be_bytes(b[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!(&b[..3], b"CDF");
    assert_eq!(be(&b, 8), 10, "the header's dimension list");
    let mut at = 16;
    for _ in 0..be(&b, 12) {
        let len = be(&b, at);
        let name = b[at + 4..at + 4 + len].to_vec();
        at += 4 + len.div_ceil(4) * 4;
        if name == b"x" || name == b"y" {
            b[at..at + 4].copy_from_slice(&n.to_be_bytes());
        }
        at += 4;
    }
    std::fs::write(to, b).unwrap();
}

/// `tile --dunes` with a dune grid, and `tile --tile FILE` with a file, larger than the process
/// may have are refused by name (`--dune-grid`, `--tile FILE`) with status 1 before they are
/// allocated, with no output left: both aborted on the failed allocation before.
#[test]
fn a_dune_grid_or_tile_file_larger_than_the_process_may_have_is_refused_by_name() {
    let dir = tmp_in("conventions-memory", "");
    let t = dir.join("t.nc");
    let small = "ripple --size 32x16 --layers 10 --steps 20 --fields elevation --quiet --out";
    let o = cellsurf(
        &[
            &small.split(' ').collect::<Vec<_>>()[..],
            &[t.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (t, x) = (t.display(), dir.join("x.npy"));
    let (code, err) = under_ulimit(
        400000,
        &format!(
            "tile --tile {t} --extent 200x200 --dunes --dune-grid 16384 --out {}",
            x.display()
        ),
    );
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("error: --dune-grid 16384 (16384x16384 nodes) needs about")
            && err.contains("ulimit -v")
            && !err.contains("memory allocation"),
        "{err}"
    );
    assert!(!x.exists() && !dir.join("x.json").exists());
    // the default grid fits
    let (code, err) = under_ulimit(
        400000,
        &format!("tile --tile {t} --extent 20x20 --dunes --dry-run --quiet"),
    );
    assert_eq!(code, Some(0), "{err}");
    // a file whose header declares 16384 x 16384 columns: refused from its header
    let huge = dir.join("huge.nc");
    with_columns(&dir.join("t.nc"), &huge, 16384);
    let (code, err) = under_ulimit(
        400000,
        &format!("tile --tile {} --mosaic 1x1 --dry-run", huge.display()),
    );
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains(&format!(
            "error: --tile {} (16384x16384 columns, 2 snapshots) needs about",
            huge.display()
        )) && err.contains("ulimit -v")
            && !err.contains("memory allocation"),
        "{err}"
    );
    let (code, err) = under_ulimit(
        400000,
        &format!("tile --tile {t} --mosaic 1x1 --dry-run --quiet"),
    );
    assert_eq!(code, Some(0), "{err}");
}

/// A raytrace section longer than the process may hold is refused by --length.
#[test]
fn a_raytrace_section_larger_than_the_process_may_have_is_refused_by_name() {
    let (code, err) = under_600_mb("raytrace --length 100000 --rays 2 --quiet");
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("error: --length 100000 (20000000 samples of 0.005 m) needs about")
            && err.contains("ulimit -v"),
        "{err}"
    );
    let (code, err) = under_600_mb("raytrace --length 100 --rays 2 --quiet");
    assert_eq!(code, Some(0), "{err}");
}

/// A sand quantity below one grain per cell runs, and says that nothing will move.
#[test]
fn a_dune_grid_without_sand_says_so() {
    let out = cellsurf(&["dunes", "-d", "-q", "1e-7", "--size", "8", "--steps", "3"]);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("-q = 0.0000001 puts no sand"), "{err}");
    let out = cellsurf(&["dunes", "-d", "-q", "1", "--size", "8", "--steps", "3"]);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("puts no sand"));
}

/// A reader that closes standard error early (`cellsurf ... 2>&1 | head`) does not turn a run
/// into a panic: the run finishes with its own status (0 with its outputs in place, 1 for a
/// refused run), whatever it had to say on stderr ("wrote", warnings, the error).
#[test]
fn a_closed_stderr_keeps_the_runs_own_exit_status() {
    use std::process::{Command, Stdio};
    let dir = tmp_in("conventions", "closed_stderr");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("f.png");
    let png = png.to_str().unwrap();
    // (a run that prints its summary and "wrote", and two refused runs)
    let cases: [(&[&str], i32); 3] = [
        (
            &[
                "flame",
                "--size",
                "32",
                "--steps",
                "100",
                "--sampler",
                "rejection",
                "--out",
                png,
            ],
            0,
        ),
        (&["dunes", "--size", "2"], 1),
        (
            &[
                "flame", "--size", "32", "--steps", "100", "--out", png, "--seed", "1", "--n", "-1",
            ],
            1,
        ),
    ];
    for (args, code) in cases {
        let mut child = Command::new(env!("CARGO_BIN_EXE_cellsurf"))
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Close the reading end before the run prints anything.
        drop(child.stderr.take());
        let status = child.wait().unwrap();
        assert_eq!(status.code(), Some(code), "{args:?}");
    }
    assert!(std::path::Path::new(png).is_file());
}

/// The scenario files of the models other than growth and ripple (`tests/fixtures/model_*.toml`):
/// each `model_bad_*` is refused in one line naming the key, its value and what the option
/// takes (its first line says what the message must hold: `# expect: NEEDLE | NEEDLE`), never
/// in the parser's words (Rust types, enum names); each `model_good_*` runs.
#[test]
fn model_scenario_fixtures_are_refused_by_key_or_run() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
    let mut seen = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if !name.starts_with("model_") || !name.ends_with(".toml") {
            continue;
        }
        seen += 1;
        let text = std::fs::read_to_string(&p).unwrap();
        let model = text
            .lines()
            .find_map(|l| l.strip_prefix("model = \""))
            .and_then(|r| r.split('"').next())
            .unwrap()
            .to_lowercase();
        let out = cellsurf(&[&model, "--scenario", p.to_str().unwrap(), "--quiet"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{name}: {err}");
        if name.starts_with("model_good_") {
            assert!(out.status.success(), "{name}: {err}");
            continue;
        }
        assert_eq!(out.status.code(), Some(1), "{name}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{name}: one line: {err}");
        for bad in ["u64", "f64", "enum", "invalid type"] {
            assert!(!err.contains(bad), "{name}: the parser's words: {err}");
        }
        let expect = text
            .lines()
            .next()
            .unwrap()
            .strip_prefix("# expect:")
            .unwrap();
        for needle in expect.split('|').map(str::trim) {
            assert!(err.contains(needle), "{name}: no '{needle}' in {err}");
        }
    }
    assert!(seen >= 6, "{seen} fixtures");
}

/// An old spelling given together with the flag that replaced it (docs/cli.md, "Old
/// spellings") is refused with a message naming both as typed, whichever comes first: before,
/// `ripple --nx 30 --size 24x12` ran with nx = 30, and an alias given with its flag was refused
/// naming only one of them.
#[test]
fn an_old_spelling_with_the_flag_that_replaced_it_is_refused_naming_both() {
    let dir = tmp_in("conventions-old", "");
    let f = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let (csv, gif, npy, bty) = (f("old.csv"), f("old.gif"), f("old.npy"), f("old.bty"));
    let (csv2, gif2, npy2, bty2) = (f("new.csv"), f("new.gif"), f("new.npy"), f("new.bty"));
    // (the command, its exit code, what the message must say)
    let cases: Vec<(Vec<&str>, i32, Vec<&str>)> = vec![
        (
            vec![
                "ripple",
                "--nx",
                "30",
                "--size",
                "24x12",
                "--print-scenario",
            ],
            2,
            vec!["--nx and --size both given: --nx is the old spelling of the x part of --size"],
        ),
        (
            vec![
                "ripple",
                "--size",
                "24x12",
                "--nx",
                "30",
                "--print-scenario",
            ],
            2,
            vec!["--nx and --size both given", "give --size only"],
        ),
        (
            vec![
                "ripple",
                "--size",
                "24x12",
                "--ny",
                "30",
                "--print-scenario",
            ],
            2,
            vec!["--ny and --size both given: --ny is the old spelling of the y part of --size"],
        ),
        (
            vec![
                "tile",
                "--generate",
                "--nx",
                "30",
                "--size",
                "24x12",
                "--dry-run",
            ],
            2,
            vec!["--nx and --size both given"],
        ),
        (
            vec![
                "tile",
                "--generate",
                "--size=24x12",
                "--ny",
                "12",
                "--dry-run",
            ],
            2,
            vec!["--ny and --size both given"],
        ),
        (
            vec!["dunes", "--grid", "50", "--size", "60"],
            2,
            vec!["--grid and --size both given: both set --size (--grid is its old spelling)"],
        ),
        (
            vec!["dunes", "-g", "50", "--size", "60"],
            2,
            vec!["-g and --size both given: both set --size (-g is its short form)"],
        ),
        (
            vec!["dunes", "--steps", "6", "--iterations", "5"],
            2,
            vec![
                "--steps and --iterations both given: both set --steps (--iterations is its old spelling)",
            ],
        ),
        (
            vec!["wind-ripples", "--bins", "10", "--size", "20"],
            2,
            vec!["--bins and --size both given"],
        ),
        (
            vec!["cursor", "--wind", &gif, "--wind-image", &gif2],
            2,
            vec!["--wind and --wind-image both given"],
        ),
        (
            vec![
                "ripple",
                "--wave-amplitude",
                "0.3",
                "--wave-velocity",
                "0.2",
            ],
            2,
            vec!["--wave-amplitude and --wave-velocity both given"],
        ),
        (
            vec!["flame", "--steps", "10", "--csv", &csv, "--out", &csv2],
            1,
            vec![
                "--csv",
                "--out",
                "both given: --csv is the old spelling of --out FILE.csv",
            ],
        ),
        (
            vec!["flame", "--steps", "10", "--out", &gif2, "--gif", &gif],
            1,
            vec![
                "--gif",
                "--out",
                "both given: --gif is the old spelling of --out FILE.gif",
            ],
        ),
        (
            vec!["dunes", "--steps", "1", "--gif", &gif, "--out", &gif2],
            1,
            vec!["--gif is the old spelling of --out FILE.gif"],
        ),
        (
            vec![
                "wind-ripples",
                "--steps",
                "1",
                "--npy",
                &npy,
                "--out",
                &npy2,
            ],
            1,
            vec!["--npy is the old spelling of --out FILE.npy"],
        ),
        (
            vec!["raytrace", "--length", "2", "--bty", &bty, "--out", &bty2],
            1,
            vec!["--bty is the old spelling of --out FILE.bty"],
        ),
    ];
    for (args, code, want) in &cases {
        let out = cellsurf(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(*code), "{args:?}: {err}");
        for w in want {
            assert!(err.contains(w), "{args:?}: {w}\n{err}");
        }
        assert!(!err.contains("panicked"), "{err}");
    }
    for p in [&csv, &gif, &npy, &bty, &csv2, &gif2, &npy2, &bty2] {
        assert!(!std::path::Path::new(p).exists(), "{p}");
    }
    // each spelling alone still works
    let out = cellsurf(&["ripple", "--nx", "30", "--ny", "12", "--print-scenario"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("\nnx = 30\n") && text.contains("\nny = 12\n"),
        "{text}"
    );
    let out = cellsurf(&["dunes", "--grid", "12", "--iterations", "2"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A refused run says its error on stderr's first line, and not the warnings about the run it
/// did not make; values out of range are refused by their flag (a dune height that would overflow, a
/// snapshot past a typed `--steps`, `-inf` given apart from its option, a wind field's default
/// radius), and a value the run changes is warned of even with `--quiet`.
#[test]
fn the_error_comes_first_and_no_value_is_changed_silently() {
    let stderr = |args: &[&str]| {
        let o = cellsurf(args);
        let e = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(!e.contains("panicked"), "{args:?}: {e}");
        (o.status.code(), e)
    };
    // tiles of 16 x 8 bins generated in-process, and the same for 10 steps on 2 x 2 tiles
    let tiles = ["tile", "--generate", "--size", "16x8", "--layers", "10"];
    let tiles_with = |extra: &[&'static str]| -> Vec<&'static str> {
        tiles.iter().chain(extra).copied().collect()
    };
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        tiles_with(&["--steps", "10", "--mosaic", "2x2"])
            .into_iter()
            .chain(extra.iter().copied())
            .collect()
    };
    let ripple = [
        "ripple", "--recipe", "paper", "--size", "16x8", "--layers", "10", "--steps", "10",
    ];
    let ripple_with = |extra: &[&'static str]| -> Vec<&'static str> {
        ripple.iter().chain(extra).copied().collect()
    };
    let refused: Vec<(Vec<&str>, &str)> = vec![
        (
            ripple_with(&["--snapshots", "20"]),
            "error: --snapshots = 20 is out of range",
        ),
        (
            with(&["--blend", "100"]),
            "error: --blend = 100 is out of range",
        ),
        (
            with(&["--dunes", "--dune-rms", "1e200"]),
            "error: --dune-rms = 1e200 is out of range: expected 0 to 1000 m",
        ),
        (
            with(&["--snapshots", "50"]),
            "error: --snapshots = 50 is out of range: expected steps in [0, --steps = 10]",
        ),
        (
            vec!["grow", "--size", "16x8", "--steps", "10", "--n", "-inf"],
            "error: --n = -inf is out of range",
        ),
        (
            vec![
                "cursor",
                "--size",
                "64",
                "--wind-field",
                "converging",
                "--wind-spacing",
                "4",
            ],
            "error: in --wind-field converging: --wind-radius = 25 (the default) is out of range",
        ),
        (
            vec!["converge", "dunes", "--seeds", "5", "--part", "9/2"],
            "error: invalid value '9/2' for '--part <i/N>': expected i/N with i in 0..N-1",
        ),
    ];
    for (args, first) in refused {
        let (code, e) = stderr(&args);
        assert_ne!(code, Some(0), "{args:?}: {e}");
        assert!(e.starts_with(first), "{args:?}: {e}");
    }
    // an output's folder that takes no file is refused before the run (/sys, even as root)
    if std::fs::create_dir("/sys/cellsurf-probe-test").is_err() {
        let (code, e) = stderr(&ripple_with(&["--out", "/sys/cellsurf-probe.nc"]));
        assert_eq!(code, Some(1), "{e}");
        assert!(
            e.starts_with("error: --out /sys/cellsurf-probe.nc: its folder cannot be written"),
            "{e}"
        );
    }
    // a scenario's steps are the scenario's to keep; past the default steps the runs go on,
    // said even with --quiet
    let dir = tmp_in("conventions-tile-steps", "");
    let scenario = dir.join("t.toml");
    std::fs::write(
        &scenario,
        "model = \"tile\"\ngenerate = true\nsize = \"16x8\"\nlayers = 10\nsteps = 10\nsnapshots = [20]\n",
    )
    .unwrap();
    let (code, e) = stderr(&["tile", "--scenario", scenario.to_str().unwrap()]);
    assert_eq!(code, Some(1), "{e}");
    assert!(
        e.starts_with(
            "error: the scenario's snapshots = 20 is out of range: expected steps in [0, steps = 10 (the scenario's)]"
        ),
        "{e}"
    );
    let (code, e) = stderr(&tiles_with(&[
        "--snapshots",
        "10001",
        "--mosaic",
        "1x1",
        "--quiet",
    ]));
    assert_eq!(code, Some(0), "{e}");
    assert!(
        e.contains("warning: --snapshots = 10001 is past the runs' 10000 steps"),
        "{e}"
    );
    // the warnings about the run that was not made are not said
    let (_, e) = stderr(&ripple_with(&["--snapshots", "20"]));
    assert!(!e.contains("warning:"), "{e}");
    // changed values are warned of with --quiet
    let dir = tmp_in("conventions-quiet-warnings", "");
    let gif = dir.join("a.gif");
    let gif = gif.to_str().unwrap();
    let quiet_cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![
                "dunes",
                "--size",
                "16",
                "--steps",
                "10",
                "--out",
                gif,
                "--gif-frames",
                "2000",
                "--quiet",
            ],
            "warning: --gif-frames = 2000 is more than the run's 10 iterations: the GIF has one frame an iteration, 11 in all",
        ),
        (
            vec![
                "ripple",
                "--recipe",
                "paper",
                "--size",
                "16x8",
                "--layers",
                "10",
                "--duration",
                "1e-300s",
                "--quiet",
            ],
            "warning: --duration = 1e-300 s is shorter than one step",
        ),
    ];
    for (args, warned) in quiet_cases {
        let (code, e) = stderr(&args);
        assert_eq!(code, Some(0), "{args:?}: {e}");
        assert!(e.contains(warned), "{args:?}: {e}");
        assert!(
            !e.contains("note:"),
            "{args:?}: --quiet keeps the notes: {e}"
        );
    }
}

/// A sea quantile that ties among equal heights keep from being met is warned of (a short
/// walk leaves most cells at 0 visits: 30 % cannot be flooded), and one met is not.
#[test]
fn a_sea_quantile_that_cannot_be_met_is_warned_of() {
    let run = |args: &[&str]| {
        let o = cellsurf(args);
        let e = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{e}");
        e
    };
    let e = run(&[
        "cursor",
        "--size",
        "16",
        "--steps",
        "100",
        "--sea-quantile",
        "0.3",
    ]);
    assert!(
        e.contains("warning: --sea-quantile = 0.3 floods 0.0 % of the cells, not 30.0 %"),
        "{e}"
    );
    let e = run(&["cursor", "--size", "64", "--sea-quantile", "0.3"]);
    assert!(!e.contains("floods"), "{e}");
}

/// A value a scenario file gave that a command refuses is named by the file's key, not by a
/// flag that was never typed; and a printed growth scenario runs with a shorter `--steps`, its
/// snapshots beyond it dropped and said so (whatever `--quiet` says).
#[test]
fn a_scenarios_values_are_named_by_their_keys_and_its_snapshots_fit_a_shorter_run() {
    let file = |name: &str, text: &str| {
        let p = tmp_in("conventions", name);
        std::fs::write(&p, text).unwrap();
        p
    };
    for (model, text, first) in [
        (
            "wind-ripples",
            "model = \"wind-ripples\"\nsize = \"32x16\"\n",
            "error: size = 32x16 is out of range",
        ),
        (
            "dunes",
            "model = \"dunes\"\nsize = 2\n",
            "error: size (grid) = 2 is out of range",
        ),
    ] {
        let p = file(&format!("keys-{model}.toml"), text);
        let out = cellsurf(&[model, "--scenario", p.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(
            err.starts_with(first) && err.contains("(the scenario file's size)"),
            "{model}: {err}"
        );
    }
    // typed, the same value is named by its flag
    let out = cellsurf(&["dunes", "--size", "2"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("scenario"), "{err}");
    // a printed growth scenario and a shorter run
    let printed = cellsurf(&["grow", "--size", "16", "--steps", "50", "--print-scenario"]);
    assert!(printed.status.success());
    let p = tmp_in("conventions", "printed-grow.toml");
    std::fs::write(&p, &printed.stdout).unwrap();
    let out = cellsurf(&[
        "grow",
        "--scenario",
        p.to_str().unwrap(),
        "--steps",
        "10",
        "--quiet",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains(
            "warning: the scenario's snapshots [50] lie beyond --steps = 10: the run draws [10]"
        ),
        "{err}"
    );
    // a longer run keeps the scenario's snapshots as they are, without a word
    let out = cellsurf(&[
        "grow",
        "--scenario",
        p.to_str().unwrap(),
        "--steps",
        "60",
        "--quiet",
    ]);
    assert!(
        out.status.success() && out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
