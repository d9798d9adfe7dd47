//! The `cellsurf` program: a thin layer over the library (argument parsing, progress, output).

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use cellsurf::growth::scene::SceneKind;
use cmd::growth::{ConvergeArgs, GrowArgs, grow};

mod cmd;

#[derive(Parser)]
#[command(
    name = "cellsurf",
    version,
    about = "Cellular Monte Carlo surface models: growth on square and hexagonal lattices",
    long_about = "Cellular Monte Carlo surface models.\n\n\
        Growth scenes of \"Simple Monte Carlo cellular models for surface growth\": a surface \
        site with b occupied neighbours (of z) sticks with probability p = v (b/z)^n. \
        Each scene starts from the paper's settings; every option overrides them.\n\n\
        Examples:\n  cellsurf flame --out flame.png\n  cellsurf crystal --steps 200000 --json\n  \
        cellsurf grow --lattice square8 --shape disc --start 20 --n 4 --gif grow.gif\n  \
        cellsurf figures --only growth_fig5_flame"
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
    /// dunes, streamed row by row to NetCDF-3 or .npy.
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

fn main() -> ExitCode {
    // Ctrl-C or SIGTERM: no temporary output file is left behind.
    let _ = ctrlc::set_handler(|| {
        cellsurf::engine::io::remove_live_temporaries();
        std::process::exit(130);
    });
    let cli = Cli::parse();
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
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
