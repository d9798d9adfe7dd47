//! Helpers shared by the integration tests: running the `cellsurf` program and a scratch
//! folder per test program.
#![allow(dead_code)]

use std::path::PathBuf;

/// Runs the `cellsurf` program with `args` and returns what it printed and its exit status.
#[cfg(feature = "cli")]
pub fn cellsurf(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_cellsurf"))
        .args(args)
        .output()
        .expect("run cellsurf")
}

/// `name` in the folder `cellsurf-TAG-PID` of the system's temporary folder (created).
pub fn tmp_in(tag: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cellsurf-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("create a scratch folder");
    d.join(name)
}

/// Makes the figure `name` with `cellsurf figures --only NAME` into `dir` (it must succeed) and
/// returns the PNG it made and the committed `figures/NAME.png`.
#[cfg(feature = "cli")]
pub fn figure_and_committed(name: &str, dir: &std::path::Path) -> (Vec<u8>, Vec<u8>) {
    let out = cellsurf(&[
        "figures",
        "--only",
        name,
        "--out-dir",
        dir.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let made = std::fs::read(dir.join(format!("{name}.png"))).unwrap();
    let committed = std::fs::read(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("figures/{name}.png")),
    )
    .unwrap();
    (made, committed)
}

/// Frames in a GIF file.
#[cfg(feature = "plot")]
pub fn gif_frames(path: &std::path::Path) -> usize {
    let mut dec = gif::DecodeOptions::new()
        .read_info(std::fs::File::open(path).unwrap())
        .unwrap();
    let mut n = 0;
    while dec.next_frame_info().unwrap().is_some() {
        n += 1;
    }
    n
}

/// The `parameters` text (iTXt chunk) that a PNG written by cellsurf records.
pub fn png_parameters(path: &std::path::Path) -> Option<String> {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).ok()?));
    let reader = dec.read_info().ok()?;
    reader
        .info()
        .utf8_text
        .iter()
        .find(|t| t.keyword == "parameters")
        .and_then(|t| t.get_text().ok())
}

/// Runs `cellsurf SUB ARGS --out a.png` in `dir`, then the scenario its PNG records with
/// `--out b.png`, and returns both files' bytes (they must be equal: the recorded parameters
/// reproduce the run).
#[cfg(feature = "cli")]
pub fn png_scenario_round_trip(
    dir: &std::path::Path,
    sub: &str,
    args: &[&str],
) -> (Vec<u8>, Vec<u8>) {
    std::fs::create_dir_all(dir).unwrap();
    let (a, b, s) = (dir.join("a.png"), dir.join("b.png"), dir.join("a.toml"));
    let mut first = vec![sub];
    first.extend_from_slice(args);
    first.extend(["--quiet", "--out", a.to_str().unwrap()]);
    let o = cellsurf(&first);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = png_parameters(&a).expect("the PNG records its parameters");
    std::fs::write(&s, text).unwrap();
    let o = cellsurf(&[
        sub,
        "--scenario",
        s.to_str().unwrap(),
        "--quiet",
        "--out",
        b.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap())
}
