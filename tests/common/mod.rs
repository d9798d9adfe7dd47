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
