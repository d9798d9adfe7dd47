//! `cellsurf tile --out X.zarr` written by independent processes: four parts run at once give
//! the single-process store byte for byte; a part killed mid-write leaves no half-written
//! chunk, `--check` reports what is missing (and a damaged chunk), and re-running the part
//! repairs the store; a part whose chunk write fails says the store is incomplete and how to
//! finish it; a folder that is not a store is refused before the run (an empty one is taken
//! by parts and `--init`); `--part` and `--chunk-tiles` errors name the flag, the value and
//! the range.
#![cfg(feature = "cli")]

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::cellsurf;

fn tmp(name: &str) -> PathBuf {
    let p = common::tmp_in("tile-zarr", name);
    let _ = std::fs::remove_dir_all(&p);
    p
}

/// Rippled dunes on 40 x 80 tiles of 64 x 32 bins (2560 x 2560 bins), chunks of 4 x 8 tiles
/// (10 x 10 chunks): about a second of work.
fn args(out: &Path) -> Vec<String> {
    [
        "tile",
        "--generate",
        "--nx",
        "64",
        "--ny",
        "32",
        "--layers",
        "10",
        "--steps",
        "300",
        "--mosaic",
        "40x80",
        "--dunes",
        "--chunk-tiles",
        "4x8",
        "--seed",
        "7",
        "--quiet",
        "--out",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([out.display().to_string()])
    .collect()
}

fn run(out: &Path, extra: &[&str]) -> std::process::Output {
    let mut a = args(out);
    a.extend(extra.iter().map(|s| s.to_string()));
    let refs: Vec<&str> = a.iter().map(String::as_str).collect();
    cellsurf(&refs)
}

fn spawn(out: &Path, extra: &[&str]) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_cellsurf"))
        .args(args(out))
        .args(extra)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start cellsurf")
}

/// Every file of a store (relative path -> bytes).
fn files(root: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(root).unwrap().display().to_string();
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

fn check(store: &Path, extra: &[&str]) -> (bool, serde_json::Value) {
    let mut a = vec!["tile", "--check"];
    let s = store.display().to_string();
    a.push(&s);
    a.extend_from_slice(extra);
    a.push("--json");
    let o = cellsurf(&a);
    let v = serde_json::from_slice(&o.stdout).unwrap_or_else(|_| {
        panic!(
            "--check printed no JSON: {}",
            String::from_utf8_lossy(&o.stderr)
        )
    });
    (o.status.success(), v)
}

fn assert_same_store(a: &Path, b: &Path) {
    let (fa, fb) = (files(a), files(b));
    assert_eq!(
        fa.keys().collect::<Vec<_>>(),
        fb.keys().collect::<Vec<_>>(),
        "the same files"
    );
    for (k, v) in &fa {
        assert!(v == &fb[k], "{k} differs between {a:?} and {b:?}");
    }
}

/// Chunk files (not temporaries) under `dir/elevation/c`.
fn chunks_in(dir: &Path) -> usize {
    std::fs::read_dir(dir.join("elevation/c")).map_or(0, |rd| {
        rd.flatten()
            .map(|e| {
                std::fs::read_dir(e.path()).map_or(0, |r| {
                    r.flatten()
                        .filter(|f| !f.file_name().to_string_lossy().starts_with('.'))
                        .count()
                })
            })
            .sum()
    })
}

/// Waits until `ready()` (at most a minute).
fn wait_for(ready: impl Fn() -> bool) {
    let t0 = Instant::now();
    while !ready() && t0.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Asserts that the run failed, saying each of `needles` on stderr.
fn refused(o: &std::process::Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "accepted: {err}");
    for n in needles {
        assert!(err.contains(n), "no '{n}' in: {err}");
    }
}

#[test]
fn four_parts_at_once_equal_one_process_byte_for_byte() {
    let one = tmp("one.zarr");
    let o = run(&one, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (ok, v) = check(&one, &[]);
    assert!(ok, "{v}");
    let chunks = v["arrays"]
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["name"] == "elevation")
        .unwrap()["chunks"]
        .as_u64()
        .unwrap();
    assert_eq!(chunks, 100);

    let four = tmp("four.zarr");
    let kids: Vec<_> = (0..4)
        .map(|i| spawn(&four, &["--part", &format!("{i}/4")]))
        .collect();
    for k in kids {
        let o = k.wait_with_output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    assert_same_store(&one, &four);
    let (ok, _) = check(&four, &[]);
    assert!(ok);
    // a re-run of a finished part keeps every chunk (and the bytes)
    let o = run(&four, &["--part", "2/4", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["zarr"]["written"], 0, "{v}");
    assert_eq!(v["zarr"]["kept"], 25, "{v}");
    assert_same_store(&one, &four);

    // a part with other parameters is refused, naming what differs
    let mut a = args(&four);
    let seed = a.iter().position(|s| s == "--seed").unwrap();
    a[seed + 1] = "8".into();
    a.extend(["--part".into(), "1/4".into()]);
    let refs: Vec<&str> = a.iter().map(String::as_str).collect();
    let o = cellsurf(&refs);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("other parameters") && err.contains("param_seed"),
        "{err}"
    );
    std::fs::remove_dir_all(&one).unwrap();
    std::fs::remove_dir_all(&four).unwrap();
}

#[test]
fn a_killed_part_is_reported_and_a_rerun_repairs_it() {
    let whole = tmp("whole.zarr");
    assert!(run(&whole, &[]).status.success());

    let store = tmp("killed.zarr");
    assert!(run(&store, &["--init"]).status.success());
    let (ok, v) = check(&store, &["--part", "0/2"]);
    assert!(!ok, "an initialised store is incomplete");
    assert_eq!(v["missing"], 100 + 10 + 10, "{v}");
    // part 0 of 2 runs and is killed once some of its chunks are there
    let mut child = spawn(&store, &["--part", "0/2"]);
    wait_for(|| chunks_in(&store) >= 5);
    child.kill().unwrap();
    child.wait().unwrap();
    let done = chunks_in(&store);
    assert!(
        (5..50).contains(&done),
        "killed with {done} of part 0's 50 chunks written"
    );
    // every chunk there is whole (atomic writes); the others are reported missing
    let (ok, v) = check(&store, &["--part", "0/2"]);
    assert!(!ok);
    assert_eq!(v["damaged"], 0, "{v}");
    let missing = v["missing"].as_u64().unwrap();
    assert!(missing >= 50, "{v}");
    assert_eq!(v["parts_to_rerun"], serde_json::json!([0, 1]), "{v}");
    // a damaged chunk (a flipped byte) is reported
    let victim = (0..10)
        .flat_map(|j| (0..10).map(move |i| (j, i)))
        .map(|(j, i)| store.join(format!("elevation/c/{j}/{i}")))
        .find(|p| p.exists())
        .unwrap();
    let mut b = std::fs::read(&victim).unwrap();
    let n = b.len();
    b[n / 2] ^= 0x5a;
    std::fs::write(&victim, &b).unwrap();
    let (_, v) = check(&store, &[]);
    assert_eq!(v["damaged"], 1, "{v}");
    // a stale temporary file from a killed writer is reported
    let stale = store.join("elevation/c/0/.1.tmp-4000000");
    std::fs::write(&stale, b"half").unwrap();
    let (_, v) = check(&store, &[]);
    // (the killed part may have left a temporary of its own, cut mid-write)
    let listed = v["stale_temporaries"].as_array().unwrap();
    assert!(
        listed
            .iter()
            .any(|t| t.as_str() == Some(stale.to_str().unwrap())),
        "{v}"
    );
    // re-running the parts repairs the store: the same bytes as one process, no temporaries
    for p in ["0/2", "1/2"] {
        let o = run(&store, &["--part", p]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let (ok, v) = check(&store, &[]);
    assert!(ok, "{v}");
    assert!(!stale.exists());
    assert_eq!(v["stale_temporaries"], serde_json::json!([]), "{v}");
    assert_same_store(&whole, &store);
    std::fs::remove_dir_all(&whole).unwrap();
    std::fs::remove_dir_all(&store).unwrap();
}

#[test]
fn bad_part_and_chunk_flags_name_the_flag_value_and_range() {
    let out = tmp("bad.zarr");
    for (flag, value, want) in [
        ("--part", "4/4", "0..=3"),
        ("--part", "1/0", "1..=1000000"),
        ("--part", "x", "i/N"),
        // checked before the tiles are generated, where the upper bound is not known yet
        ("--chunk-tiles", "0x2", "at least 1x1"),
        ("--chunk-tiles", "41x1", "1..=40"),
    ] {
        let o = cellsurf(&[
            "tile",
            "--generate",
            "--nx",
            "64",
            "--ny",
            "32",
            "--steps",
            "10",
            "--mosaic",
            "40x80",
            "--out",
            &out.display().to_string(),
            flag,
            value,
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{flag} {value} accepted");
        assert!(
            err.contains(flag) && err.contains(value) && err.contains(want),
            "{flag} {value}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    let o = cellsurf(&["tile", "--generate", "--part", "0/2", "--out", "x.nc"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("--part needs --out STORE.zarr"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn raytrace_reads_only_the_chunks_the_section_crosses() {
    // the same mosaic as NetCDF and as a store of 4 x 4 chunks, with the impedance beneath
    let nc = tmp("m.nc");
    let store = tmp("m.zarr");
    let base = [
        "tile",
        "--generate",
        "--nx",
        "64",
        "--ny",
        "32",
        "--layers",
        "10",
        "--steps",
        "300",
        "--mosaic",
        "8x16",
        "--volume",
        "impedance",
        "--quiet",
    ];
    let (n, z) = (nc.display().to_string(), store.display().to_string());
    for extra in [
        vec!["--out", n.as_str()],
        vec!["--out", z.as_str(), "--chunk-tiles", "2x4"],
    ] {
        let mut a = base.to_vec();
        a.extend(extra);
        let o = cellsurf(&a);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    // the section runs along x through the middle row (y = 256 bins: chunk row 2 of 4)
    let trace = |floor: &str| {
        let o = cellsurf(&[
            "raytrace",
            "--seafloor",
            floor,
            "--length",
            "2.5",
            "--water-depth",
            "5",
            "--source-depth",
            "4.9",
            "--angle-min",
            "2",
            "--angle-max",
            "40",
            "--ds",
            "0.01",
            "--json",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let from_nc = trace(&n);
    // every chunk off the section's chunk row removed: the trace does not need them
    for j in [0, 1, 3] {
        std::fs::remove_dir_all(store.join(format!("elevation/c/{j}"))).unwrap();
        std::fs::remove_dir_all(store.join(format!("impedance/c/{j}"))).unwrap();
    }
    let from_zarr = trace(&z);
    // the same floor (the NetCDF file's bin size comes from its float32 x coordinate, the
    // store's from its bin_size_m attribute: equal to 1e-7)
    assert_eq!(from_nc["vertices"], from_zarr["vertices"]);
    for k in ["insonified_fraction", "lit_length_m"] {
        let (a, b) = (from_nc[k].as_f64().unwrap(), from_zarr[k].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-6 * a.abs(), "{k}: {a} vs {b}");
    }
    // 2.5 m of the 2.56 m row: the 4 elevation and 4 impedance chunks of the row
    assert_eq!(from_zarr["zarr_chunks_read"], 8, "{from_zarr}");
    assert!(from_zarr["insonified_fraction"].as_f64().unwrap() > 0.0);
    std::fs::remove_dir_all(&store).unwrap();
    std::fs::remove_file(&nc).unwrap();
}

/// Small ripple runs: 32 x 16 bins, a few hundred milliseconds.
const SMALL_RUN: [&str; 8] = [
    "--size",
    "32x16",
    "--layers",
    "10",
    "--steps",
    "200",
    "--activity",
    "0.004",
];

/// A ripple file of [`SMALL_RUN`], remade under the same name.
fn ripple_file(out: &Path, seed: &str) {
    let out = out.display().to_string();
    let mut a = vec!["ripple", "--recipe", "paper"];
    a.extend(SMALL_RUN);
    a.extend(["--seed", seed, "--quiet", "--out", &out]);
    let o = cellsurf(&a);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn parts_from_other_tile_contents_under_one_name_are_refused() {
    let t = tmp("t.nc");
    let store = tmp("mixed.zarr");
    let (ts, ss) = (t.display().to_string(), store.display().to_string());
    let tile = |extra: &[&str]| {
        let mut a = vec![
            "tile",
            "--tile",
            &ts,
            "--mosaic",
            "4x4",
            "--chunk-tiles",
            "2x2",
        ];
        a.extend_from_slice(extra);
        cellsurf(&a)
    };
    ripple_file(&t, "1");
    let o = tile(&["--out", &ss, "--part", "0/2", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // the tile file remade with other contents: part 1 and a whole re-run are refused, naming
    // the tiles' digest, and write nothing
    ripple_file(&t, "99");
    for extra in [&["--part", "1/2"][..], &[][..]] {
        let mut a = vec!["--out", ss.as_str(), "--quiet"];
        a.extend_from_slice(extra);
        refused(&tile(&a), &["param_tiles_sha256", "other values"]);
    }
    let (ok, v) = check(&store, &[]);
    // (part 1's two elevation chunks and its y coordinate chunk)
    assert!(!ok && v["missing"] == 3, "{v}");
    // --check given the tiles: not made from them
    refused(
        &tile(&["--check", &ss]),
        &["not made from these tiles", "param_tiles_sha256"],
    );
    // the first contents back: the store is finished, and --check says complete, also with
    // the tiles
    ripple_file(&t, "1");
    let o = tile(&["--out", &ss, "--part", "1/2", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (ok, v) = check(&store, &[]);
    assert!(ok, "{v}");
    assert_eq!(v["tiles_sha256"].as_str().map(str::len), Some(64), "{v}");
    let o = tile(&["--check", &ss]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // a store that records its tiles by name only (an earlier cellsurf's) cannot be called
    // complete: its parts may have read different contents
    let root = store.join("zarr.json");
    let mut doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&root).unwrap()).unwrap();
    doc["attributes"]
        .as_object_mut()
        .unwrap()
        .remove("param_tiles_sha256");
    std::fs::write(&root, serde_json::to_vec(&doc).unwrap()).unwrap();
    let (ok, v) = check(&store, &[]);
    assert!(!ok, "{v}");
    assert!(
        v["unverified"]
            .as_str()
            .unwrap_or("")
            .contains("file name and step only"),
        "{v}"
    );
    refused(
        &cellsurf(&["tile", "--check", &ss]),
        &["cannot be called complete", "param_tiles_sha256"],
    );
    std::fs::remove_dir_all(&store).unwrap();
    std::fs::remove_file(&t).unwrap();
}

#[test]
fn check_given_the_generating_parameters_verifies_the_store() {
    // generated tiles are identified by their parameters and seeds, and by their values: the
    // same --generate parameters match the store, other steps do not (named by the first
    // parameters that differ)
    let store = tmp("gen.zarr");
    let a = args(&store);
    let o = cellsurf(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let with_check = |steps: &str| {
        let mut c: Vec<String> = a[..a.len() - 2].to_vec();
        let i = c.iter().position(|s| s == "--steps").unwrap();
        c[i + 1] = steps.into();
        c.extend(["--check".into(), store.display().to_string()]);
        cellsurf(&c.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let o = with_check("300");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    refused(
        &with_check("310"),
        &["not made from these tiles", "attributes.param_ripple_s"],
    );
    std::fs::remove_dir_all(&store).unwrap();
}

/// Sends SIGINT (Ctrl-C) to `child`.
#[cfg(unix)]
fn interrupt(child: &std::process::Child) {
    let s = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(s.success());
}

#[test]
#[cfg(unix)]
fn ctrl_c_leaves_no_partial_output_under_its_name() {
    let dir = tmp("ctrl-c");
    std::fs::create_dir_all(&dir).unwrap();
    let leftovers = || {
        std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect::<Vec<_>>()
    };
    // a new store without --part: written into a temporary folder, removed on Ctrl-C
    let store = dir.join("k.zarr");
    let child = spawn(&store, &[]);
    let hidden = dir.join(format!(".k.zarr.tmp-{}", child.id()));
    wait_for(|| chunks_in(&hidden) >= 3);
    assert!(chunks_in(&hidden) >= 3, "no chunks appeared in {hidden:?}");
    assert!(
        !store.exists(),
        "the store is not under its name while written"
    );
    interrupt(&child);
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(!err.contains("error"), "{err}");
    assert_eq!(leftovers(), Vec::<String>::new(), "{err}");
    // the same for a NetCDF file
    let nc = dir.join("k.nc");
    let mut a = args(&nc);
    a.retain(|s| s != "--chunk-tiles" && s != "4x8");
    let child = Command::new(env!("CARGO_BIN_EXE_cellsurf"))
        .args(&a)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let partial = dir.join(format!(".k.nc.tmp-{}", child.id()));
    wait_for(|| std::fs::metadata(&partial).is_ok_and(|m| m.len() > 100_000));
    interrupt(&child);
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130));
    assert_eq!(leftovers(), Vec::<String>::new());
    // a store that exists (here its metadata alone) is finished in place: Ctrl-C leaves its
    // whole chunks and says so, with how to finish and check it; a re-run finishes it
    assert!(run(&store, &["--init"]).status.success());
    let child = spawn(&store, &[]);
    wait_for(|| chunks_in(&store) >= 3);
    interrupt(&child);
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted:")
            && err.contains("keeps the chunks")
            && err.contains("tile --check"),
        "{err}"
    );
    let (ok, v) = check(&store, &[]);
    assert!(!ok && v["damaged"] == 0, "{v}");
    assert!(run(&store, &[]).status.success());
    assert!(check(&store, &[]).0);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_store_reports_the_seams_slopes_and_rate_of_the_streams() {
    let dir = tmp("measures");
    std::fs::create_dir_all(&dir).unwrap();
    let summary = |out: &str, extra: &[&str]| {
        let p = dir.join(out).display().to_string();
        let mut a = vec!["tile", "--generate"];
        a.extend(SMALL_RUN);
        a.extend([
            "--seeds",
            "1,2",
            "--choose",
            "patches",
            "--blend",
            "4",
            "--mosaic",
            "4x4",
            "--volume",
            "impedance",
            "--json",
            "--out",
            &p,
        ]);
        a.extend_from_slice(extra);
        let o = cellsurf(&a);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let nc = summary("m.nc", &[]);
    let z = summary("m.zarr", &["--chunk-tiles", "2x2"]);
    // the same seams and slopes as the stream's (summed in another order: equal to rounding)
    for d in ["x", "y"] {
        for k in ["inside_m", "across_m", "inside_line_sd_m", "z"] {
            let (a, b) = (nc["seams"][d][k].as_f64(), z["seams"][d][k].as_f64());
            let (a, b) = (a.unwrap(), b.unwrap_or(f64::NAN));
            assert!(
                (a - b).abs() <= 1e-9 * a.abs().max(1e-12),
                "{d}.{k}: {a} vs {b}"
            );
        }
        assert_eq!(nc["seams"][d]["seams"], z["seams"][d]["seams"]);
    }
    for k in ["max_deg", "above_repose_fraction"] {
        assert_eq!(nc["surface_slope"][k], z["surface_slope"][k], "{k}");
    }
    let (a, b) = (
        nc["surface_slope"]["rms_deg"].as_f64().unwrap(),
        z["surface_slope"]["rms_deg"].as_f64().unwrap(),
    );
    assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    assert!(z["rows_per_s"].as_f64().unwrap() > 0.0, "{z}");
    // a part computes only some of the chunks: no seams or slopes (they need every row), a
    // rate of what it computed; a re-run that keeps every chunk computes nothing: no rate
    let part = summary("p.zarr", &["--chunk-tiles", "2x2", "--part", "0/2"]);
    assert!(
        part["seams"].is_null() && part["surface_slope"].is_null(),
        "{part}"
    );
    assert!(part["rows_per_s"].as_f64().unwrap() > 0.0, "{part}");
    let kept = summary("m.zarr", &["--chunk-tiles", "2x2"]);
    assert_eq!(kept["zarr"]["written"], 0, "{kept}");
    assert!(
        kept["rows_per_s"].is_null() && kept["mb_per_s"].is_null(),
        "{kept}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A store of 4 x 4 chunks of one tile each, written in a moment.
fn tiny(out: &Path, extra: &[&str]) -> std::process::Output {
    let p = out.display().to_string();
    let mut a = vec![
        "tile",
        "--generate",
        "--size",
        "8x4",
        "--layers",
        "2",
        "--steps",
        "5",
        "--mosaic",
        "4x4",
        "--chunk-tiles",
        "1x1",
        "--quiet",
        "--out",
        &p,
    ];
    a.extend_from_slice(extra);
    cellsurf(&a)
}

/// The names in folder `dir`.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_folder_that_is_not_a_store_is_refused_before_the_run() {
    let dir = tmp("not-a-store");
    // a folder of other files: refused by a whole run, a part and --init alike, untouched
    let mine = dir.join("mydata.zarr");
    std::fs::create_dir_all(mine.join("sub")).unwrap();
    std::fs::write(mine.join("notes.txt"), "precious").unwrap();
    let before = files(&mine);
    let p = mine.display().to_string();
    for extra in [&[][..], &["--part", "0/2"], &["--part", "0/1"], &["--init"]] {
        let o = tiny(&mine, extra);
        refused(
            &o,
            &[&format!(
                "--out {p}: exists and is not a Zarr store (no zarr.json; it holds notes.txt, sub); remove it or choose another name"
            )],
        );
        assert!(!String::from_utf8_lossy(&o.stderr).contains("panicked"));
        assert_eq!(files(&mine), before, "{extra:?} wrote into {mine:?}");
        assert_eq!(names(&mine), ["notes.txt", "sub"], "{extra:?}");
        assert_eq!(
            names(&dir),
            ["mydata.zarr"],
            "{extra:?} left a file beside it"
        );
    }
    // an empty folder: a whole run (a new store, renamed into place) refuses it, untouched ...
    let empty = dir.join("empty.zarr");
    std::fs::create_dir(&empty).unwrap();
    refused(
        &tiny(&empty, &[]),
        &[
            "--out",
            "empty.zarr: exists and is not a Zarr store (no zarr.json); remove it or choose another name",
            "--part and --init write into an empty folder",
        ],
    );
    assert_eq!(names(&empty), Vec::<String>::new());
    // ... parts write into it (a cluster's set-up may make the folder first), as --init does
    for part in ["0/2", "1/2"] {
        let o = tiny(&empty, &["--part", part]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    assert!(check(&empty, &[]).0);
    let init = dir.join("init.zarr");
    std::fs::create_dir(&init).unwrap();
    assert!(tiny(&init, &["--init"]).status.success());
    // a store is finished in place by a whole run; a folder holding only what a part writes
    // before the store's root document (its arrays' metadata) is taken by a part
    assert!(tiny(&init, &[]).status.success());
    assert!(check(&init, &[]).0);
    let made = dir.join("made.zarr");
    assert!(tiny(&made, &["--init"]).status.success());
    std::fs::remove_file(made.join("zarr.json")).unwrap();
    assert!(tiny(&made, &["--part", "0/1"]).status.success());
    assert!(check(&made, &[]).0);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_part_that_fails_writing_a_chunk_says_the_store_is_incomplete() {
    let dir = tmp("chunk-fails");
    std::fs::create_dir_all(&dir).unwrap();
    let store = dir.join("p.zarr");
    let s = store.display().to_string();
    assert!(tiny(&store, &["--init"]).status.success());
    // a folder where chunk [1, 1] must go: writing that chunk fails (as on a full disk)
    let blocker = store.join("elevation/c/1/1");
    std::fs::create_dir_all(blocker.join("x")).unwrap();
    for (extra, rerun) in [
        (
            &["--part", "0/1"][..],
            "re-run the same command (--part 0/1)",
        ),
        (&[][..], "re-run the same command to finish it"),
    ] {
        let o = tiny(&store, extra);
        refused(
            &o,
            &[
                &format!("writing {s}/elevation chunk [1, 1]"),
                &format!("the store is incomplete: {s} keeps the chunks written so far, whole"),
                rerun,
                &format!("`cellsurf tile --check {s}`"),
            ],
        );
        assert!(!String::from_utf8_lossy(&o.stderr).contains("panicked"));
        let (ok, v) = check(&store, &[]);
        assert!(!ok, "{v}");
    }
    // a part refused before it writes (other parameters) leaves the store as it was: no hint
    let o = tiny(&store, &["--part", "0/1", "--seed", "9"]);
    refused(&o, &["other parameters"]);
    assert!(
        !String::from_utf8_lossy(&o.stderr).contains("incomplete"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // the cause mended, the same part finishes the store
    std::fs::remove_dir_all(&blocker).unwrap();
    let o = tiny(&store, &["--part", "0/1"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(check(&store, &[]).0);
    std::fs::remove_dir_all(&dir).unwrap();
}
