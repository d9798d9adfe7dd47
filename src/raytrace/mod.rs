//! Acoustic ray tracing over a generated seafloor (Sect. 3.3 and Fig. 5 of Staelens,
//! Dupont & Henriet): 2-D rays in the vertical plane from a transducer S, through a
//! sound-speed profile c(z), reflected at the sea surface and at a seafloor section, and the
//! shadows they leave on the floor.
//!
//! Depth z is positive downward from the sea surface and x is the horizontal range, both in
//! metres (the BELLHOP convention). Angles are measured from the horizontal, positive downward.
//!
//! Principal types:
//! - [`SoundSpeed`] ([`profile`]): isovelocity, linear, Munk (1974), a piecewise-linear
//!   [`Table`], or Mackenzie's (1981) equation from temperature and salinity tables.
//! - [`Seafloor`] ([`seafloor`]): a polyline z_b(x) (vertical cliffs allowed) with an optional
//!   impedance per vertex; [`SectionLine`] extracts a section through a periodic elevation grid
//!   (a ripple volume or a mosaic of its tiles); [`input::read_surface`] reads either file.
//! - [`Tracer`] ([`ray`]): classical fourth-order Runge-Kutta on the BELLHOP ray equations in
//!   arc length, exact reflection t' = t - 2 (t.n) n at the surface and at the floor; each
//!   [`Ray`] reports its reflections, why it ended and its Snell-invariant drift.
//! - [`Fan`] and [`insonify`] ([`shadow`]): which floor vertices a fan of rays reaches first,
//!   with grazing angle, travel time and normal-incidence reflection coefficient; unreached
//!   vertices are in shadow; the lit and shadowed lengths along the floor, split at the shadow
//!   edges ([`Span`]). [`visibility`] and [`visible_stretches`] are the straight-line
//!   (line-of-sight) counterparts.
//! - [`rough`]: periodic Gaussian random surfaces and Smith's (1967) shadowing function.
//! - [`export`]: BELLHOP bathymetry (`.bty`) and CSV files, written atomically.
//! - [`RaytraceScenario`] ([`scenario`]): a `cellsurf raytrace` scenario file read back (the
//!   published figure's runs).
//! - `figures` (feature `plot`): `ripple_fig5_raytrace` and `raytrace_error_vs_time`, listed in
//!   [`FIGURES`].
//!
//! Every run is bounded: at most `2 max_path / ds + 64 (max_bounces + 1) + 16` steps per ray, at most
//! `max_bounces` reflections, and a ray budget for the insonification search.
//!
//! ```
//! use cellsurf::raytrace::{RayEnd, Seafloor, SoundSpeed, TraceOptions, Tracer};
//!
//! // A flat floor at 12 m in isovelocity water; a ray from 10 m depth launched 10 degrees
//! // downward travels in a straight line and meets the floor 2 / tan(10 deg) = 11.34 m away.
//! let floor = Seafloor::flat(0.0, 100.0, 12.0).unwrap();
//! let c = SoundSpeed::Isovelocity(1500.0);
//! let tracer = Tracer::new(&c, &floor).unwrap();
//! let o = TraceOptions { ds: 0.1, max_path: 200.0, max_bounces: 4, stop_at_bottom: true, record: false };
//! let ray = tracer.trace(0.0, 10.0, 10.0, &o).unwrap();
//! assert_eq!(ray.end, RayEnd::Floor);
//! let hit = ray.first_floor_hit().unwrap();
//! assert!((hit.x - 2.0 / 10f64.to_radians().tan()).abs() < 1e-6);
//! // Snell's invariant cos(theta)/c is kept to rounding in uniform water.
//! assert!(ray.max_snell_drift < 1e-12);
//! ```

pub mod export;
#[cfg(feature = "plot")]
pub mod figures;
pub mod input;
pub mod profile;
pub mod ray;
pub mod rough;
pub mod scenario;
pub mod seafloor;
pub mod shadow;

pub use profile::{Mackenzie, Munk, SoundSpeed, Table};
pub use ray::{Ray, RayEnd, Reflection, StepError, Surface, TraceOptions, Tracer, error_study};
pub use scenario::RaytraceScenario;
pub use seafloor::{RippleSurface, Seafloor, SectionLine};
pub use shadow::{
    Arrival, Fan, Insonification, InsonifyOptions, Span, insonify, reflection_coefficient,
    visibility, visible_stretches,
};

/// The crate version, recorded in every output (the engine's).
pub use crate::engine::VERSION;

/// Seawater density used for the water impedance rho_w c_w, kg/m^3 (Soulsby 1997, Dynamics of marine sands).
pub const RHO_WATER: f64 = 1027.0;

/// The figures of the ray tracer, made by `cellsurf figures`.
#[cfg(feature = "plot")]
pub const FIGURES: &[crate::plot::Figure] = figures::FIGURES;

/// Errors of the ray tracer: each names the parameter, the value and the valid range.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum RaytraceError {
    /// A parameter is out of range.
    #[error("{parameter} = {value} is out of range: expected {expected}")]
    Range {
        /// The parameter's name.
        parameter: String,
        /// The value given.
        value: String,
        /// The valid range.
        expected: String,
    },
    /// An input file or table could not be read.
    #[error("{what}: {reason}")]
    Input {
        /// The file or table.
        what: String,
        /// What is wrong.
        reason: String,
    },
    /// Writing an output failed.
    #[error("writing {path}: {reason}")]
    Output {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
}

/// A [`RaytraceError::Range`].
pub(crate) fn range_err(
    parameter: impl Into<String>,
    value: impl std::fmt::Display,
    expected: impl Into<String>,
) -> RaytraceError {
    RaytraceError::Range {
        parameter: parameter.into(),
        value: value.to_string(),
        expected: expected.into(),
    }
}

/// Checks that `v` is finite and in `[lo, hi]`.
pub(crate) fn check_range(
    parameter: &str,
    v: f64,
    lo: f64,
    hi: f64,
    unit: &str,
) -> Result<(), RaytraceError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(range_err(
            parameter,
            v,
            format!("a finite number in [{lo}, {hi}] {unit}"),
        ))
    }
}
