//! Scenario files: every `tests/fixtures/good_*.toml` parses (each key in the file overrides
//! the scene's default, the configuration survives a round trip through `to_toml`) and, where
//! small, runs to completion; every `tests/fixtures/bad_*.toml` is refused with a message that
//! names the offending key or parameter. A bad fixture says what the message must contain in
//! its first line, `# expect: NEEDLE | NEEDLE ...` (every needle must appear).
//!
//! The figures' scenario files (`scenarios/`): each is read by its own model's parser (the one
//! its figure uses; the `scene` or `model` key says which), starts with a comment that names
//! the figure it reproduces and, on a `# Run:` line, the command that runs it; with the
//! program, that command accepts it and means the same run by it (`--print-scenario` read back,
//! and the run's own description in `--json` where one is quick). Every figure of `cellsurf
//! figures --list` has its scenario file (or one a panel, `NAME_PANEL.toml`) or is one of the
//! figures without one ([`WITHOUT_SCENARIO`]); every file's name is a figure's, or a figure's
//! and a panel's; the figures embed the files as they are on disk.

use std::fs;
use std::path::{Path, PathBuf};

use cellsurf::cursor::CursorScenario;
use cellsurf::dunes::DuneScenario;
use cellsurf::growth::scene::{self, NoHooks, SceneConfig, SceneKind, StopReason};
use cellsurf::raytrace::RaytraceScenario;
use cellsurf::ripple::RippleParams;
use cellsurf::tile::TileScenario;
use cellsurf::windripples::WindParams;

#[cfg(feature = "cli")]
mod common;

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The `.toml` files in `dir` whose names start with `prefix`, sorted.
fn toml_files(dir: &Path, prefix: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_string_lossy();
            name.starts_with(prefix) && name.ends_with(".toml")
        })
        .collect();
    v.sort();
    v
}

fn fixtures(prefix: &str) -> Vec<(String, String)> {
    toml_files(&crate_dir().join("tests/fixtures"), prefix)
        .into_iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, fs::read_to_string(&p).unwrap())
        })
        .collect()
}

/// TOML values equal up to integer/float spelling (`n = 2` is the float 2.0).
fn loosely_equal(a: &toml::Value, b: &toml::Value) -> bool {
    use toml::Value::{Array, Float, Integer};
    match (a, b) {
        (Integer(x), Float(y)) | (Float(y), Integer(x)) => *x as f64 == *y,
        (Array(x), Array(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(u, v)| loosely_equal(u, v))
        }
        _ => a == b,
    }
}

#[test]
fn good_fixtures_parse_and_keep_every_key() {
    let good = fixtures("good_");
    assert!(good.len() >= 5, "only {} good fixtures", good.len());
    for (name, text) in good {
        let cfg = SceneConfig::from_toml(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        cfg.validate().unwrap();
        // Every key given in the file is the configuration's value.
        let given: toml::Table = text.parse().unwrap();
        let written: toml::Table = cfg.to_toml().parse().unwrap();
        for (k, v) in &given {
            let w = written
                .get(k)
                .unwrap_or_else(|| panic!("{name}: key {k} lost"));
            assert!(loosely_equal(v, w), "{name}: {k} = {v} became {w}");
        }
        // Keys not in the file keep the scene's defaults.
        let defaults: toml::Table = SceneConfig::defaults(cfg.scene).to_toml().parse().unwrap();
        for (k, v) in &defaults {
            if !given.contains_key(k) {
                assert!(loosely_equal(v, &written[k]), "{name}: default {k} changed");
            }
        }
        // Round trip.
        let back = SceneConfig::from_toml(&cfg.to_toml()).unwrap();
        assert_eq!(back, cfg, "{name}");
    }
}

#[test]
fn small_good_fixtures_run_to_completion() {
    // Only lattices up to 64 x 64 (the default-sized ones are too slow in a debug build).
    let mut ran = 0;
    for (name, text) in fixtures("good_") {
        let cfg = SceneConfig::from_toml(&text).unwrap();
        if cfg.width * cfg.height > 64 * 64 {
            continue;
        }
        let r = scene::run(&cfg, &mut NoHooks).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(r.stop, StopReason::Completed, "{name}");
        let times: Vec<f64> = r.snapshots.iter().map(|s| s.time).collect();
        let want: Vec<f64> = cfg.snapshots.iter().map(|&t| t as f64).collect();
        assert_eq!(times, want, "{name}: snapshot times");
        assert!(
            r.snapshots
                .iter()
                .all(|s| s.states.len() == cfg.width * cfg.height)
        );
        assert_eq!(r.series.len(), cfg.series + 1, "{name}: series points");
        assert_eq!(r.last.time, cfg.steps as f64, "{name}: final clock");
        assert!(r.last.occupied > 0);
        ran += 1;
    }
    assert!(ran >= 5, "only {ran} fixtures were small enough to run");
}

/// The needles of a bad fixture's `# expect:` line.
fn expected_needles(name: &str, text: &str) -> Vec<String> {
    let first = text.lines().next().unwrap_or_default();
    let rest = first
        .strip_prefix("# expect:")
        .unwrap_or_else(|| panic!("{name}: first line must be '# expect: NEEDLE | ...'"));
    rest.split('|').map(|s| s.trim().to_string()).collect()
}

#[test]
fn bad_fixtures_fail_naming_the_parameter() {
    let bad = fixtures("bad_");
    // The cases the issue asks for, at least.
    for required in [
        "bad_unknown_key.toml",
        "bad_wrong_type.toml",
        "bad_negative_n.toml",
        "bad_snapshots_order.toml",
        "bad_steps_zero.toml",
        "bad_odd_hex_height.toml",
        "bad_unknown_scene.toml",
    ] {
        assert!(bad.iter().any(|(n, _)| n == required), "{required} missing");
    }
    for (name, text) in bad {
        let needles = expected_needles(&name, &text);
        let e = match SceneConfig::from_toml(&text) {
            Ok(cfg) => panic!("{name} was accepted: {cfg:?}"),
            Err(e) => e.to_string(),
        };
        for needle in needles {
            assert!(
                e.contains(&needle),
                "{name}: the message does not name '{needle}': {e}"
            );
        }
    }
}

#[test]
fn scene_defaults_round_trip_through_toml() {
    for s in [
        SceneKind::Flame,
        SceneKind::Deposit,
        SceneKind::Crystal,
        SceneKind::Ca,
        SceneKind::Grow,
    ] {
        let d = SceneConfig::defaults(s);
        assert_eq!(SceneConfig::from_toml(&d.to_toml()).unwrap(), d, "{s}");
        let only = SceneConfig::from_toml(&format!("scene = \"{s}\"\n")).unwrap();
        assert_eq!(only, d, "{s}");
    }
}

#[test]
fn duplicate_key_error_names_the_key() {
    let e = SceneConfig::from_toml("scene = \"flame\"\nn = 2.0\nn = 3.0\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains('n') && (e.contains("`n`") || e.contains("line 3")),
        "{e}"
    );
}

/// The figures without a scenario file: the studies over many runs (seeds, sizes or
/// parameters).
const WITHOUT_SCENARIO: [&str; 9] = [
    "growth_error_vs_time",
    "growth_kpz_roughness",
    "windripples_error_vs_time",
    "dunes_error_vs_time",
    "cursor_k_effect",
    "cursor_error_vs_time",
    "ripple_error_vs_time",
    "ripple_validation",
    "raytrace_error_vs_time",
];

/// A scenario file as its model's parser reads it.
#[derive(Debug, PartialEq)]
enum Parsed {
    Growth(SceneConfig),
    Ripple(RippleParams),
    WindRipples(WindParams),
    Dunes(DuneScenario),
    Cursor(CursorScenario),
    Raytrace(RaytraceScenario),
    Tile(TileScenario),
}

/// A table file a raytrace scenario names, read from `folder` (a file of `scenarios/` names
/// its tables from that folder, as the program reads a scenario's paths; a scenario the program
/// prints names them from the working directory, the crate's folder in these tests).
fn read_table(folder: &Path, path: &str) -> Result<String, String> {
    fs::read_to_string(folder.join(path)).map_err(|e| e.to_string())
}

/// Reads `text` with the parser of the model its `scene` (growth) or `model` key names, the
/// text of a file of `scenarios/`.
fn parse(name: &str, text: &str) -> Parsed {
    parse_from(name, text, &crate_dir().join("scenarios"))
}

/// [`parse`] for a scenario whose relative paths are read from `folder`.
fn parse_from(name: &str, text: &str, folder: &Path) -> Parsed {
    let t: toml::Table = text
        .parse()
        .unwrap_or_else(|e| panic!("{name}: not TOML: {e}"));
    let fail = |e: &dyn std::fmt::Display| -> ! { panic!("{name}: {e}") };
    if t.contains_key("scene") {
        let cfg = SceneConfig::from_toml(text).unwrap_or_else(|e| fail(&e));
        cfg.validate().unwrap_or_else(|e| fail(&e));
        return Parsed::Growth(cfg);
    }
    match t.get("model").and_then(|m| m.as_str()) {
        Some("ripple") => {
            Parsed::Ripple(RippleParams::from_toml(text).unwrap_or_else(|e| fail(&e)))
        }
        Some("wind-ripples") => {
            Parsed::WindRipples(WindParams::from_scenario(text).unwrap_or_else(|e| fail(&e)))
        }
        Some("dunes") => Parsed::Dunes(DuneScenario::parse(text).unwrap_or_else(|e| fail(&e))),
        Some("cursor") => Parsed::Cursor(CursorScenario::parse(text).unwrap_or_else(|e| fail(&e))),
        Some("raytrace") => Parsed::Raytrace(
            RaytraceScenario::parse(text, &|p: &str| read_table(folder, p))
                .unwrap_or_else(|e| fail(&e)),
        ),
        Some("tile") => Parsed::Tile(TileScenario::parse(text).unwrap_or_else(|e| fail(&e))),
        m => panic!("{name}: no `scene`, and `model` = {m:?} names no model with scenario files"),
    }
}

/// The subcommands that run a scenario of this kind.
fn subcommands(p: &Parsed) -> Vec<String> {
    match p {
        Parsed::Growth(c) => vec![c.scene.to_string(), "grow".into()],
        Parsed::Ripple(_) => vec!["ripple".into()],
        Parsed::WindRipples(_) => vec!["wind-ripples".into()],
        Parsed::Dunes(_) => vec!["dunes".into()],
        Parsed::Cursor(_) => vec!["cursor".into()],
        Parsed::Raytrace(_) => vec!["raytrace".into()],
        Parsed::Tile(_) => vec!["tile".into()],
    }
}

/// Every scenario file of `scenarios/`: (name without `.toml`, text).
fn scenario_files() -> Vec<(String, String)> {
    toml_files(&crate_dir().join("scenarios"), "")
        .into_iter()
        .map(|p| {
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            (name, fs::read_to_string(&p).unwrap())
        })
        .collect()
}

/// The words of a scenario file's `# Run:` line, in its leading comment, checked: `cellsurf
/// SUB --scenario scenarios/NAME.toml`, then only options that choose the run's outputs.
fn run_line(name: &str, text: &str) -> Vec<String> {
    let comment: Vec<&str> = text.lines().take_while(|l| l.starts_with('#')).collect();
    assert!(
        comment.len() >= 2,
        "{name}: the file starts with a comment naming the figure and source it reproduces, and its # Run: line"
    );
    let runs: Vec<&str> = comment
        .iter()
        .filter_map(|l| l.strip_prefix("# Run: "))
        .collect();
    assert_eq!(
        runs.len(),
        1,
        "{name}: one `# Run: cellsurf ...` line in the leading comment"
    );
    let words: Vec<String> = runs[0].split_whitespace().map(String::from).collect();
    let path = format!("scenarios/{name}.toml");
    assert!(
        words.len() >= 4 && words[0] == "cellsurf" && words[2] == "--scenario" && words[3] == path,
        "{name}: the run line is `cellsurf SUB --scenario {path} ...`: {}",
        runs[0]
    );
    let mut rest = words[4..].iter();
    while let Some(w) = rest.next() {
        assert!(
            ["--out", "--fields", "--snapshots"].contains(&w.as_str()) && rest.next().is_some(),
            "{name}: after the scenario, only options that choose the outputs (the file holds the run): {w}"
        );
    }
    words
}

/// `figure` is `name`, or `name` is `figure`, `_` and a panel.
fn names_figure(name: &str, figure: &str) -> bool {
    name == figure
        || name
            .strip_prefix(figure)
            .and_then(|r| r.strip_prefix('_'))
            .is_some_and(|panel| !panel.is_empty())
}

#[test]
fn scenarios_folder_parses_with_each_models_parser() {
    let dir = crate_dir().join("scenarios");
    if !dir.is_dir() {
        eprintln!(
            "no scenarios/ folder at {}: nothing to check",
            dir.display()
        );
        return;
    }
    let files = scenario_files();
    let mut models = std::collections::BTreeSet::new();
    for (name, text) in &files {
        let p = parse(name, text);
        let words = run_line(name, text);
        assert!(
            subcommands(&p).contains(&words[1]),
            "{name}: its run line's subcommand {} does not run a {:?} scenario",
            words[1],
            subcommands(&p)
        );
        models.insert(words[1].clone());
    }
    assert!(
        files.len() >= 30 && models.len() >= 10,
        "{} scenario files of {} subcommands",
        files.len(),
        models.len()
    );
    eprintln!("{} scenario files parsed", files.len());
}

/// The figures as `cellsurf figures --list` lists them (with the program; else the registry
/// that command prints).
#[cfg(feature = "plot")]
fn listed_figures() -> Vec<String> {
    let registry: Vec<String> = cellsurf::figures::all()
        .map(|f| f.name.to_string())
        .collect();
    #[cfg(feature = "cli")]
    {
        let out = common::cellsurf(&["figures", "--list"]);
        assert!(out.status.success());
        let listed: Vec<String> = String::from_utf8_lossy(&out.stdout)
            .lines()
            .filter_map(|l| l.split_whitespace().next().map(String::from))
            .collect();
        assert_eq!(
            listed, registry,
            "`cellsurf figures --list` lists the registry"
        );
    }
    registry
}

#[cfg(feature = "plot")]
#[test]
fn every_figure_has_its_scenarios_or_is_a_study() {
    let figures = listed_figures();
    let files = scenario_files();
    let without: Vec<&str> = cellsurf::figures::WITHOUT_SCENARIO
        .iter()
        .map(|(n, _)| *n)
        .collect();
    assert_eq!(
        without, WITHOUT_SCENARIO,
        "the figures without a scenario file"
    );
    for f in &figures {
        let own: Vec<&str> = files
            .iter()
            .map(|(n, _)| n.as_str())
            .filter(|n| names_figure(n, f))
            .collect();
        let exempt = WITHOUT_SCENARIO.contains(&f.as_str());
        assert!(
            own.is_empty() == exempt,
            "{f}: {} (it must have its scenario file(s) or be listed without one, not both)",
            if exempt {
                format!("listed without a scenario but has {own:?}")
            } else {
                "has no scenarios/{f}.toml nor scenarios/{f}_PANEL.toml".into()
            }
        );
        // A figure has its own file or panels', not both.
        assert!(
            !own.contains(&f.as_str()) || own.len() == 1,
            "{f}: both a scenario file and panels' files: {own:?}"
        );
    }
    for n in WITHOUT_SCENARIO {
        assert!(figures.iter().any(|f| f == n), "{n} is not a figure");
    }
    for (name, _) in &files {
        let of: Vec<&String> = figures.iter().filter(|f| names_figure(name, f)).collect();
        assert_eq!(
            of.len(),
            1,
            "scenarios/{name}.toml names one figure (a figure's name, or a figure's and a panel's): {of:?}"
        );
    }
}

#[cfg(feature = "plot")]
#[test]
fn the_figures_embed_the_scenario_files_as_they_are() {
    let embedded: Vec<(String, String)> = cellsurf::figures::scenarios()
        .map(|(n, t)| (n.to_string(), t.to_string()))
        .collect();
    let mut sorted = embedded.clone();
    sorted.sort();
    assert_eq!(
        sorted,
        scenario_files(),
        "scenarios/*.toml and the figures' embedded texts"
    );
    // The other files are the tables a scenario names, embedded too.
    let dir = crate_dir().join("scenarios");
    let mut others: Vec<String> = fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.ends_with(".toml"))
        .collect();
    others.sort();
    let mut tables: Vec<&str> = cellsurf::figures::scenario_tables()
        .map(|(p, _)| *p)
        .collect();
    tables.sort();
    assert_eq!(
        others, tables,
        "the files of scenarios/ that are not scenarios"
    );
    for (path, text) in cellsurf::figures::scenario_tables() {
        assert_eq!(
            fs::read_to_string(crate_dir().join("scenarios").join(path)).unwrap(),
            *text,
            "{path}"
        );
        let stem = path.trim_end_matches(".csv");
        assert!(
            embedded.iter().any(|(n, t)| n == stem && t.contains(path)),
            "{path}: named by scenarios/{stem}.toml"
        );
    }
}

/// What the program prints on stdout, run from the crate's folder with `args` (it must
/// succeed; `what` names the run in a failure).
#[cfg(feature = "cli")]
fn stdout_of(what: &str, args: &[&str]) -> Vec<u8> {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_cellsurf"))
        .current_dir(crate_dir())
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{what}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// With the program: each file's run line accepts it, and the scenario it prints back
/// (`--print-scenario`, every parameter written out) is the same run to the model's parser.
#[cfg(feature = "cli")]
#[test]
fn each_run_line_accepts_its_file_and_means_the_same_run() {
    for (name, text) in scenario_files() {
        let words = run_line(&name, &text);
        let mut args: Vec<&str> = words[1..4].iter().map(String::as_str).collect();
        args.push("--print-scenario");
        let printed = String::from_utf8(stdout_of(&name, &args)).unwrap();
        assert_eq!(
            parse_from(&format!("{name} (printed)"), &printed, &crate_dir()),
            parse(&name, &text),
            "{name}: the subcommand's scenario and the file are not the same run"
        );
    }
}

/// The program's `--json` of a run of `sub` with the scenario `name` and `extra` options (run
/// from the crate's folder).
#[cfg(feature = "cli")]
fn json_of(name: &str, sub: &str, extra: &[&str]) -> serde_json::Value {
    let path = format!("scenarios/{name}.toml");
    let mut args = vec![sub, "--scenario", &path];
    args.extend(extra);
    args.extend(["--json", "--quiet"]);
    serde_json::from_slice(&stdout_of(name, &args)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// `t` as JSON.
#[cfg(feature = "cli")]
fn v<T: serde::Serialize>(t: &T) -> serde_json::Value {
    serde_json::to_value(t).unwrap()
}

/// With the program: where a run of a scenario is quick (shortened by options typed on the
/// command line, or on a small floor), its own description in `--json` is the model's parser's
/// reading of the file.
#[cfg(feature = "cli")]
#[test]
fn the_subcommands_runs_are_the_parsers_runs() {
    let floor = common::tmp_in("scenarios", "floor.csv");
    fs::write(&floor, "x, depth\n0, 12\n70, 12\n").unwrap();
    let floor = floor.display().to_string();
    let mut checked = 0;
    for (name, text) in scenario_files() {
        match parse(&name, &text) {
            Parsed::Dunes(s) => {
                let j = json_of(&name, "dunes", &["--steps", "0"]);
                let cfg = cellsurf::dunes::DuneConfig {
                    iterations: 0,
                    ..s.config
                };
                assert_eq!(j["config"], v(&cfg), "{name}");
                assert_eq!(j["threshold"], serde_json::json!(s.threshold), "{name}");
                assert_eq!(j["start"], v(&s.start), "{name}");
            }
            Parsed::WindRipples(p) => {
                let j = json_of(
                    &name,
                    "wind-ripples",
                    &["--steps", "1", "--particles", "4096"],
                );
                let p = WindParams {
                    steps: 1,
                    particles: 4096,
                    ..p
                };
                assert_eq!(j["run"], v(&p), "{name}");
            }
            Parsed::Cursor(s) => {
                let j = json_of(&name, "cursor", &["--steps", "1"]);
                assert_eq!(j["run"]["wind"], v(&s.wind), "{name}");
                assert_eq!(j["run"]["sea"], v(&s.sea), "{name}");
                assert_eq!(
                    (&j["run"]["width"], &j["run"]["height"]),
                    (&serde_json::json!(s.size.0), &serde_json::json!(s.size.1)),
                    "{name}"
                );
                assert_eq!(j["parameters"]["k"], serde_json::json!(s.k), "{name}");
                assert_eq!(j["parameters"]["seed"], serde_json::json!(s.seed), "{name}");
            }
            Parsed::Raytrace(s) => {
                let j = json_of(&name, "raytrace", &["--seafloor-csv", &floor]);
                assert_eq!(
                    j["run"]["profile"],
                    serde_json::json!(s.profile.describe()),
                    "{name}"
                );
                assert_eq!(
                    j["run"]["angles_deg"],
                    serde_json::json!([s.angles.0, s.angles.1]),
                    "{name}"
                );
                if let Some(m) = s.max_path {
                    assert_eq!(j["run"]["max_path_m"], serde_json::json!(m), "{name}");
                }
                assert_eq!(j["fan_rays"], serde_json::json!(s.rays), "{name}");
            }
            Parsed::Tile(s) => {
                let j = json_of(&name, "tile", &["--dry-run"]);
                let r = &j["recorded"];
                let mosaic = s.mosaic(s.tiles().unwrap()).unwrap();
                let (mx, my) = mosaic.cells();
                assert_eq!(
                    r["mosaic"],
                    serde_json::json!(format!("{mx}x{my}")),
                    "{name}"
                );
                assert_eq!(r["choose"], serde_json::json!(s.choose.name()), "{name}");
                assert_eq!(
                    (&r["blend"], &r["seed"]),
                    (&serde_json::json!(s.blend), &serde_json::json!(s.seed)),
                    "{name}"
                );
                assert_eq!(
                    j["tiles"].as_array().map(|t| t.len()),
                    Some(s.seeds.len() * s.snapshots.len()),
                    "{name}"
                );
                let generated =
                    RippleParams::from_toml(r["ripple_scenario"].as_str().unwrap()).unwrap();
                assert_eq!(
                    generated,
                    RippleParams {
                        seed: generated.seed,
                        ..s.ripple.clone()
                    },
                    "{name}"
                );
                match s.dune_params(&mosaic).unwrap() {
                    Some(d) => {
                        assert_eq!(r["dunes"], serde_json::json!(true), "{name}");
                        assert_eq!(r["dune_rms"], serde_json::json!(d.rms), "{name}");
                        assert_eq!(r["dune_grid"], serde_json::json!(d.grid), "{name}");
                        assert_eq!(r["steering"], serde_json::json!(d.steering), "{name}");
                        let seed = r.get("dune_seed").unwrap_or(&r["seed"]);
                        assert_eq!(seed, &serde_json::json!(d.seed), "{name}");
                    }
                    None => assert_eq!(r["dunes"], serde_json::json!(false), "{name}"),
                }
            }
            // (growth and ripple print the model's own parameters: the printed scenario is the run)
            Parsed::Growth(_) | Parsed::Ripple(_) => continue,
        }
        checked += 1;
    }
    assert!(
        checked >= 20,
        "{checked} scenario files checked against their runs"
    );
}
