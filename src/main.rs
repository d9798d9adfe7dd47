//! The `cellsurf` program: a thin layer over the library (argument parsing, progress, output).
// A write to a closed stderr must not panic: lines go through `cmd::conv::err_line`.
#![deny(clippy::print_stderr)]

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

use cellsurf::growth::scene::SceneKind;
use cmd::growth::{ConvergeArgs, GrowArgs, grow};

mod cmd;

#[derive(Parser)]
#[command(
    name = "cellsurf",
    version,
    about = "Cellular Monte Carlo surface models: growth, sand-ripple sediment volumes, tiling, \
             ray tracing, wind ripples, Werner dunes, the cursor walk and a teaching page",
    long_about = "Cellular Monte Carlo surface models on one lattice engine.\n\n\
        - Growth (flame, deposit, crystal, ca, grow): a surface site with b occupied neighbours \
          (of z) sticks with probability p = v (b/z)^n.\n\
        - Sand ripples (ripple), tiling and fractal dunes (tile), ray tracing (raytrace): \
          sediment volumes for underwater acoustics.\n\
        - Wind ripples (wind-ripples), Werner dunes (dunes), the wind-field cursor walk \
          (cursor), the live teaching page (serve).\n\n\
        The model subcommands share the conventions of docs/cli.md: --size WxH, --steps (1e7 \
        accepted), --seed, --out FILE (the extension picks the format), --json, --scenario \
        FILE.toml, --print-scenario, --quiet.\n\n\
        Examples:\n  cellsurf flame --out flame.png\n  cellsurf crystal --steps 200000 --json\n  \
        cellsurf grow --lattice square8 --shape disc --start 20 --n 4 --out grow.gif\n  \
        cellsurf ripple --out bed.nc\n  cellsurf figures --only growth_fig5_flame"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Flame front from a square burnt region (Fig. 5): hex torus, n = 2.
    Flame(GrowArgs),
    /// Land deposition on a cosine trough (Fig. 6): vertical hex section, n = 2.
    Deposit(GrowArgs),
    /// Anisotropic crystal from a disc seed with the Eq. (5) weight (Fig. 7).
    Crystal(GrowArgs),
    /// Deterministic synchronous CA from a seed cell (Figs. 3 and 4; --ca-rule 1,2 for Fig. 4).
    Ca(GrowArgs),
    /// Any lattice, boundary, exponent, weight, initial shape and sampler.
    Grow(GrowArgs),
    /// Regenerate the published figures into a folder.
    Figures(cmd::figures::FiguresArgs),
    /// Error against run time: standard error of each scene's observable over seeds.
    Converge(ConvergeArgs),
    /// Sand-ripple volume generator: sand and water volumes, written for acoustic models.
    Ripple(cmd::ripple::Args),
    /// Acoustic ray tracing over a (generated) seafloor section: rays, shadows, grazing angles.
    Raytrace(cmd::raytrace::Args),
    /// Tiling: a large surface (and volume) from toroidal ripple tiles, optionally on fractal
    /// dunes, streamed row by row to NetCDF-3 or .npy, or chunk by chunk to a Zarr v3 store.
    Tile(cmd::tile::Args),
    /// Wind ripples: the particle model of the wind-ripple notebook (diffusion + saltation).
    WindRipples(cmd::windripples::Args),
    /// Werner-model dunes: slab model, ripple mode and dune mode.
    Dunes(cmd::dunes::Args),
    /// Wind-field cursor walk: one random walker on an 8-neighbour torus under a wind field.
    Cursor(cmd::cursor::Args),
    /// Interactive teaching page: growth live in a browser (local web server, page embedded).
    Serve(cmd::serve::Args),
}

/// The command line: every option that takes a value accepts a negative number (so that
/// `--steps -1` is refused by the option's own check, naming it), and each growth scene's help
/// lists its defaults. Records the subcommand's matches for the shared conventions.
fn parse() -> Cli {
    let mut command = Cli::command().mut_subcommands(|sc| {
        sc.mut_args(|a| {
            if a.get_action().takes_values() {
                a.allow_negative_numbers(true)
            } else {
                a
            }
        })
    });
    for scene in SceneKind::ALL {
        let help = cmd::growth::defaults_help(scene);
        command = command.mut_subcommand(scene.name(), |sc| sc.after_help(help));
    }
    let matches = command
        .clone()
        .try_get_matches_from(cmd::conv::negative_words_joined(
            std::env::args_os(),
            |word| cmd::conv::takes_value(&command, word),
        ))
        .unwrap_or_else(|e| cmd::conv::plain_parse_error(&mut command, e).exit());
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let Some((name, sub)) = matches.subcommand() {
        let words: Vec<String> = std::env::args().skip_while(|w| w != name).skip(1).collect();
        if let Some(sc) = command.find_subcommand(name) {
            cmd::conv::init(sc.clone(), sub.clone(), words);
        }
    }
    cli
}

fn main() -> ExitCode {
    // A write past a file-size limit (`ulimit -f`) is an error that removes its temporary
    // file, not a signal that kills the process and leaves it.
    #[cfg(unix)]
    // SAFETY: sets one signal's disposition to "ignore" before any thread of the program
    // starts; no handler runs.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    // Ctrl-C or SIGTERM: no temporary output file is left behind (and an output written in
    // place says what was left).
    let _ = ctrlc::set_handler(|| cmd::conv::interrupted());
    let cli = parse();
    // Every output of a run is moved into place only once the whole run succeeded (the page
    // server writes no output of its own).
    if !matches!(cli.cmd, Cmd::Serve(_)) {
        cellsurf::engine::io::hold_outputs();
    }
    // A bad input's error is stderr's first line: warnings wait until the run begins.
    if !matches!(cli.cmd, Cmd::Serve(_) | Cmd::Figures(_)) {
        cmd::conv::hold_notes();
    }
    let result = match cli.cmd {
        Cmd::Flame(a) => grow(SceneKind::Flame, a),
        Cmd::Deposit(a) => grow(SceneKind::Deposit, a),
        Cmd::Crystal(a) => grow(SceneKind::Crystal, a),
        Cmd::Ca(a) => grow(SceneKind::Ca, a),
        Cmd::Grow(a) => grow(SceneKind::Grow, a),
        Cmd::Figures(a) => cmd::figures::run(a),
        Cmd::Converge(a) => cmd::growth::converge(a),
        Cmd::Ripple(a) => cmd::ripple::run(a),
        Cmd::Raytrace(a) => cmd::raytrace::run(a),
        Cmd::Tile(a) => cmd::tile::run(a),
        Cmd::WindRipples(a) => cmd::windripples::run(a),
        Cmd::Dunes(a) => cmd::dunes::run(a),
        Cmd::Cursor(a) => cmd::cursor::run(a),
        Cmd::Serve(a) => cmd::serve::run(a),
    };
    cmd::conv::finish(result)
}
