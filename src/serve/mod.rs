//! `cellsurf serve`: an interactive teaching page for the growth paper's cellular Monte Carlo
//! growth ("Simple Monte Carlo cellular models for surface growth": a surface site with `b`
//! occupied neighbours of `z` sticks with probability `p = v (b/z)^n`, Eqs. 4 and 5), a live
//! sand-ripple section, and a lesson on kinetic roughening (interface width against time,
//! growth exponent beside the Kardar-Parisi-Zhang value 1/3).
//!
//! Design: the simulation runs in Rust on the crate's engine, server-side, one session per
//! open page; frames stream over a WebSocket (axum on tokio). The page (HTML, CSS and plain
//! JavaScript in `src/serve/page/`) is embedded in the binary with `include_str!`: no network,
//! no CDN and no build step for a user.
//!
//! Principal types and functions:
//! - Settings ([`settings`]): [`GrowthSettings`] and [`RippleSettings`], read from the page's URL query
//!   (every control by name, the presets of Figs. 3-7 and `kpz`), with limits
//!   ([`settings::MAX_CELLS`], [`settings::MAX_SPEED`]).
//! - Sessions ([`session`]): [`GrowthSession`] (frames of events, one explained pick, live statistics)
//!   and [`RippleSession`].
//! - The server ([`http`]): the router ([`http::router`]) and [`http::serve`]: pages, the JSON API and the
//!   two WebSocket streams, `/ws/growth` and `/ws/ripple`.
//!
//! Errors are [`ServeError`]s that name the parameter, the value and the valid range; the
//! server answers them with a 4xx status and never exits on bad input.

pub mod http;
pub mod session;
pub mod settings;

pub use http::{ServerConfig, router, serve};
pub use session::{GrowthSession, GrowthStats, RippleSession};
pub use settings::{GrowthSettings, RippleSettings};

/// Errors of the server's requests and sessions.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ServeError {
    /// A request parameter is unknown or out of range.
    #[error("{parameter} = {value} is out of range: expected {expected}")]
    Parameter {
        /// The parameter's name.
        parameter: String,
        /// The value given.
        value: String,
        /// The valid range or names.
        expected: String,
    },
    /// A request names a parameter that does not exist.
    #[error("unknown parameter '{parameter}': known parameters are {known}")]
    UnknownParameter {
        /// The name given.
        parameter: String,
        /// The known names.
        known: String,
    },
    /// The scene's configuration is invalid (the message names the parameter).
    #[error("{0}")]
    Scene(String),
    /// A request body or command is not valid JSON of the expected form.
    #[error("malformed JSON: {0}")]
    Json(String),
    /// The server holds its maximum number of sessions.
    #[error("too many sessions: the server holds at most {0}; close a tab and retry")]
    Busy(usize),
}
