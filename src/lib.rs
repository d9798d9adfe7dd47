//! cellsurf: cellular Monte Carlo surface models.
pub mod io;
#[cfg(feature = "plot")]
pub mod plot;
