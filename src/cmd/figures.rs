//! `cellsurf figures`: regenerates the published figures of every model into a folder.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;

use cellsurf::figures;

use super::conv;

#[derive(Args)]
pub struct FiguresArgs {
    /// Make only this figure (see --list).
    #[arg(long, value_name = "NAME")]
    only: Option<String>,
    /// Folder to write into (made, with its parents, if missing).
    #[arg(long, default_value = "figures")]
    out_dir: PathBuf,
    /// List the figures and exit.
    #[arg(long)]
    list: bool,
    /// No chatter on stderr (the files written are not listed).
    #[arg(long)]
    quiet: bool,
}

pub fn run(a: FiguresArgs) -> Result<()> {
    conv::set_quiet(a.quiet);
    if a.list {
        // (the list is of every figure; nothing is written)
        for id in ["only", "out_dir"] {
            if conv::typed(id) {
                let flag = conv::typed_flag(id).unwrap_or_else(|| format!("--{id}"));
                conv::note(format_args!(
                    "warning: {flag} has no effect with --list (it lists every figure and writes nothing)"
                ));
            }
        }
        for f in figures::all() {
            outln!("{:24} {}", f.name, f.about)?;
        }
        return Ok(());
    }
    let chosen: Vec<_> = match &a.only {
        Some(name) => {
            let f = figures::all().find(|f| f.name == name.as_str());
            match f {
                Some(f) => vec![f],
                None => bail!(
                    "--only '{name}' is not a figure; expected one of: {}",
                    figures::all()
                        .map(|f| f.name)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            }
        }
        None => figures::all().collect(),
    };
    if a.out_dir.exists() && !a.out_dir.is_dir() {
        bail!(
            "--out-dir {}: not a folder (a file of that name exists); give a folder",
            a.out_dir.display()
        );
    }
    let dir = a.out_dir.display();
    std::fs::create_dir_all(&a.out_dir)
        .with_context(|| format!("cannot create --out-dir {dir}"))?;
    // (a folder the run cannot write in is named before any figure is drawn)
    let check = a
        .out_dir
        .join(format!(".cellsurf-write-check-{}", std::process::id()));
    std::fs::write(&check, b"")
        .and_then(|()| std::fs::remove_file(&check))
        .with_context(|| format!("cannot write in --out-dir {dir}"))?;
    let t0 = Instant::now();
    for f in chosen {
        let files = figures::make(f, &a.out_dir, false)
            .with_context(|| format!("figure {} (into --out-dir {dir})", f.name))?;
        for p in files {
            conv::wrote(&p);
        }
    }
    conv::note(format_args!(
        "figures made in {:.1} s",
        t0.elapsed().as_secs_f64()
    ));
    Ok(())
}
