//! Every command the README and `docs/` show runs.
//!
//! The commands are the lines starting with `cellsurf ` in fenced blocks marked ```` ```sh ````.
//! A marker line just before a block adjusts it:
//! - `<!-- small: --size 64x64 --steps 2000 -->`: these flags replace the same flags in each
//!   command of the block (or are appended), so a long documented run is tested at a small size;
//! - `<!-- skip: reason -->`: the block is not run (only where no small version makes sense).
//!
//! Each command runs through `sh` in a fresh folder that holds the repository's `scenarios/`
//! and `tests/fixtures/`, with the test build of `cellsurf` first on the `PATH`, and must exit
//! with status 0 within [`LIMIT`], warning of no flag that has no effect. The docs must also stay within the repository: no link or
//! path into a folder outside it.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longest a documented command may run (with its small flags).
const LIMIT: Duration = Duration::from_secs(120);

/// One command to run, with where it was found.
#[derive(Debug, Clone, PartialEq)]
struct DocCommand {
    file: String,
    line: usize,
    text: String,
}

/// The documentation files: README.md and docs/*.md.
fn doc_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .expect("docs/ exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    files
}

/// Splits flags into (flag, value) pairs: `--size 64x64 --quiet` gives
/// `[("--size", Some("64x64")), ("--quiet", None)]`.
fn flag_pairs(flags: &str) -> Vec<(String, Option<String>)> {
    let words: Vec<&str> = flags.split_whitespace().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < words.len() {
        let f = words[i].to_string();
        let value = words
            .get(i + 1)
            .filter(|w| !w.starts_with("--"))
            .map(|w| w.to_string());
        i += if value.is_some() { 2 } else { 1 };
        out.push((f, value));
    }
    out
}

/// Applies a `small:` marker to one `cellsurf ...` invocation.
fn shrink_one(cmd: &str, small: &[(String, Option<String>)]) -> String {
    let mut words: Vec<String> = cmd.split_whitespace().map(String::from).collect();
    for (flag, value) in small {
        match words.iter().position(|w| w == flag) {
            Some(i) => {
                if let Some(v) = value {
                    let has_value = words.get(i + 1).is_some_and(|w| !w.starts_with('-'));
                    if has_value {
                        words[i + 1] = v.clone();
                    } else {
                        words.insert(i + 1, v.clone());
                    }
                }
            }
            None => {
                words.push(flag.clone());
                if let Some(v) = value {
                    words.push(v.clone());
                }
            }
        }
    }
    words.join(" ")
}

/// Applies a `small:` marker to every `cellsurf` invocation of a line (`a && b`, `a | b`).
fn shrink(line: &str, small: &[(String, Option<String>)]) -> String {
    if small.is_empty() {
        return line.to_string();
    }
    line.split(" && ")
        .map(|part| {
            part.split(" | ")
                .map(|p| {
                    if p.trim_start().starts_with("cellsurf ") {
                        shrink_one(p, small)
                    } else {
                        p.to_string()
                    }
                })
                .collect::<Vec<_>>()
                .join(" | ")
        })
        .collect::<Vec<_>>()
        .join(" && ")
}

/// The commands of one Markdown text.
fn extract(file: &str, text: &str) -> Vec<DocCommand> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i].trim_start();
        if !l.starts_with("```") {
            i += 1;
            continue;
        }
        let lang = l.trim_start_matches('`').trim();
        let marker = lines[..i]
            .iter()
            .rev()
            .find(|m| !m.trim().is_empty())
            .map(|m| m.trim())
            .unwrap_or("");
        let skip = marker.starts_with("<!-- skip:");
        let small = marker
            .strip_prefix("<!-- small:")
            .and_then(|m| m.strip_suffix("-->"))
            .map(flag_pairs)
            .unwrap_or_default();
        let mut j = i + 1;
        let mut pending = String::new();
        let mut start = j;
        while j < lines.len() && !lines[j].trim_start().starts_with("```") {
            let raw = lines[j].trim();
            let raw = raw.strip_prefix("$ ").unwrap_or(raw);
            if pending.is_empty() {
                start = j;
            }
            if let Some(body) = raw.strip_suffix('\\') {
                pending.push_str(body);
                pending.push(' ');
            } else {
                pending.push_str(raw);
                let full = std::mem::take(&mut pending);
                if lang == "sh" && !skip && full.starts_with("cellsurf ") {
                    out.push(DocCommand {
                        file: file.to_string(),
                        line: start + 1,
                        text: shrink(&full, &small),
                    });
                }
            }
            j += 1;
        }
        i = j + 1;
    }
    out
}

/// Runs one command in `dir`; `Err` with its output if it fails or runs past [`LIMIT`].
fn run(cmd: &DocCommand, dir: &Path, path_env: &str) -> Result<f64, String> {
    let t = Instant::now();
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(&cmd.text)
        .current_dir(dir)
        .env("PATH", path_env)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start sh: {e}"))?;
    loop {
        match child.try_wait() {
            Ok(Some(_)) => break,
            Ok(None) if t.elapsed() > LIMIT => {
                let _ = child.kill();
                return Err(format!("ran past {} s", LIMIT.as_secs()));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => return Err(e.to_string()),
        }
    }
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    let err = String::from_utf8_lossy(&out.stderr);
    if out.status.success()
        && let Some(w) = err.lines().find(|l| l.contains(" no effect"))
    {
        // A documented example teaches its flags: each must act.
        Err(format!("a flag shown has no effect:\n    {w}"))
    } else if out.status.success() {
        Ok(t.elapsed().as_secs_f64())
    } else {
        let tail: String = err
            .lines()
            .rev()
            .take(4)
            .collect::<Vec<_>>()
            .into_iter()
            .rev()
            .collect::<Vec<_>>()
            .join("\n    ");
        Err(format!("exit {:?}:\n    {tail}", out.status.code()))
    }
}

/// A fresh folder holding the repository's scenarios and test fixtures by relative path.
fn workdir(name: &str) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("cellsurf-docs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("tests")).unwrap();
    std::os::unix::fs::symlink(root.join("scenarios"), dir.join("scenarios")).unwrap();
    std::os::unix::fs::symlink(root.join("tests/fixtures"), dir.join("tests/fixtures")).unwrap();
    dir
}

#[test]
fn every_documented_command_runs() {
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_cellsurf"));
    let path_env = format!(
        "{}:{}",
        bin.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut commands = Vec::new();
    for f in doc_files() {
        let text = std::fs::read_to_string(&f).unwrap();
        let name = f.file_name().unwrap().to_string_lossy().to_string();
        commands.extend(extract(&name, &text));
    }
    assert!(
        commands.len() >= 20,
        "only {} commands found in the docs",
        commands.len()
    );
    // Two workers (the CI machine has two cores); each file's commands run in order in one
    // folder, since a later command may read what an earlier one wrote.
    let mut by_file: Vec<Vec<DocCommand>> = Vec::new();
    for c in commands {
        match by_file.iter_mut().find(|g| g[0].file == c.file) {
            Some(g) => g.push(c),
            None => by_file.push(vec![c]),
        }
    }
    let queue = std::sync::Mutex::new(by_file);
    let failures = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                loop {
                    let Some(group) = queue.lock().unwrap().pop() else {
                        break;
                    };
                    let dir = workdir(&group[0].file);
                    for c in &group {
                        if let Err(e) = run(c, &dir, &path_env) {
                            failures
                                .lock()
                                .unwrap()
                                .push(format!("{}:{}: `{}`: {e}", c.file, c.line, c.text));
                        }
                    }
                    let _ = std::fs::remove_dir_all(&dir);
                }
            });
        }
    });
    let failures = failures.into_inner().unwrap();
    assert!(
        failures.is_empty(),
        "{} documented commands failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The targets of the Markdown links and images on `line` (`[text](target)`), without a
/// `#anchor` or a title.
fn link_targets(line: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(i) = rest.find("](") {
        let after = &rest[i + 2..];
        let end = after.find(')').unwrap_or(after.len());
        let target = after[..end].split([' ', '#']).next().unwrap_or("");
        out.push(target);
        rest = &after[end..];
    }
    out
}

/// Whether a link `target` in a file of folder `dir` (relative to the repository root) stays
/// inside the repository: a web address, an anchor, or a relative path that does not climb
/// above the root. A root-absolute path (`/figures/x.png`) is refused: it resolves against
/// the file system's root outside a web host.
fn stays_inside(dir: &Path, target: &str) -> bool {
    if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
        return true;
    }
    if target.starts_with('/') {
        return false;
    }
    let mut depth = dir.components().count() as i64;
    for part in Path::new(target).components() {
        match part {
            std::path::Component::ParentDir => depth -= 1,
            std::path::Component::Normal(_) => depth += 1,
            _ => {}
        }
        if depth < 0 {
            return false;
        }
    }
    true
}

#[test]
fn link_checks_follow_the_files_folder() {
    assert!(stays_inside(Path::new("docs"), "../figures/a.png"));
    assert!(stays_inside(Path::new("docs"), "cli.md"));
    assert!(stays_inside(Path::new(""), "docs/cli.md"));
    assert!(!stays_inside(Path::new(""), "../figures/a.png"));
    assert!(!stays_inside(Path::new("docs"), "../../shared/x"));
    assert!(!stays_inside(Path::new("docs"), "/figures/a.png"));
    assert!(stays_inside(Path::new("docs"), "https://doi.org/10.1/x"));
    assert_eq!(
        link_targets("![a](../figures/a.png) and [b](cli.md#errors \"t\")"),
        ["../figures/a.png", "cli.md"]
    );
}

#[test]
fn docs_stay_inside_the_repository() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for f in doc_files() {
        let text = std::fs::read_to_string(&f).unwrap();
        let dir = f.parent().unwrap().strip_prefix(root).unwrap();
        for (i, line) in text.lines().enumerate() {
            assert!(
                !line.contains("../shared") && !line.contains("/shared/"),
                "{}:{}: refers to a folder outside the repository: {line}",
                f.display(),
                i + 1
            );
            for target in link_targets(line) {
                assert!(
                    stays_inside(dir, target),
                    "{}:{}: the link {target} leaves the repository (or is root-absolute): {line}",
                    f.display(),
                    i + 1
                );
            }
        }
    }
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let n = readme.lines().count();
    assert!(n < 250, "README.md has {n} lines; keep it under 250");
}

#[test]
fn extraction_applies_markers_and_joins_continued_lines() {
    let md = "text\n\n```sh\ncellsurf flame --size 512 \\\n  --out a.png\ncargo build\n```\n\n\
              <!-- small: --size 32 --steps 100 -->\n```sh\n$ cellsurf dunes --size 400 && \
              cellsurf dunes --quiet\n```\n<!-- skip: 40 GB -->\n```sh\ncellsurf tile\n```\n\
              ```text\ncellsurf not-run\n```\n";
    let got = extract("x.md", md);
    let texts: Vec<&str> = got.iter().map(|c| c.text.as_str()).collect();
    assert_eq!(
        texts,
        [
            "cellsurf flame --size 512  --out a.png",
            "cellsurf dunes --size 32 --steps 100 && cellsurf dunes --quiet --size 32 --steps 100",
        ]
    );
    assert_eq!(got[0].line, 4);
}

/// The messages the docs quote after a `$ cellsurf ...` line (an `error:` or `warning:` line in
/// a text block) are what that command prints on stderr, word for word.
#[test]
fn quoted_messages_are_what_the_commands_print() {
    let dir = workdir("quoted");
    let mut checked = 0;
    for path in doc_files() {
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        for (i, line) in lines.iter().enumerate() {
            let Some(args) = line.strip_prefix("$ cellsurf ") else {
                continue;
            };
            let quoted: Vec<&str> = lines[i + 1..]
                .iter()
                .take_while(|l| !l.starts_with("$ ") && !l.starts_with("```"))
                .filter(|l| l.starts_with("error: ") || l.starts_with("warning: "))
                .copied()
                .collect();
            let out = Command::new(env!("CARGO_BIN_EXE_cellsurf"))
                .args(args.split_whitespace())
                .current_dir(&dir)
                .stdin(Stdio::null())
                .output()
                .unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            for q in quoted {
                assert!(
                    stderr.lines().any(|l| l == q),
                    "{}:{}: `cellsurf {args}` no longer prints\n  {q}\nbut:\n{stderr}",
                    path.display(),
                    i + 1
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 4, "only {checked} quoted messages found");
}
