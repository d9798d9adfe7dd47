//! The subcommands, one file per family: the growth scenes (and their convergence study),
//! the figures, and each related model.

/// `print!` that hands a failed write (standard output closed by a pipe, a full disk) back to
/// the caller's `?` instead of panicking.
macro_rules! out {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        write!(std::io::stdout().lock(), $($t)*).map_err(|e| {
            std::io::Error::new(e.kind(), format!("writing to standard output: {e}"))
        })
    }};
}

/// `println!` that hands a failed write back to the caller's `?` (see `out!`).
macro_rules! outln {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($t)*).map_err(|e| {
            std::io::Error::new(e.kind(), format!("writing to standard output: {e}"))
        })
    }};
}

pub mod conv;
pub mod cursor;
pub mod dunes;
pub mod figures;
pub mod growth;
pub mod raytrace;
pub mod ripple;
pub mod serve;
pub mod tile;
pub mod windripples;
