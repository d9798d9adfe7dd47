//! The growth models of "Simple Monte Carlo cellular models for surface growth": a surface
//! site with `b` occupied neighbours (of `z`) sticks with probability `p = v (b/z)^n`.
//!
//! A run is three independent choices on the engine's [`Lattice`](crate::engine::lattice::Lattice):
//!
//! - the sticking rule ([`rule`]): [`Sticking`](rule::Sticking), Eq. (4) `p = (b/z)^n`, and
//!   the direction weight [`Weight`](rule::Weight), Eq. (5)
//!   `v = sqrt(x^2 + y^2) / (|x| + |y|)` for the crystal's fastest growth along the axes;
//! - the growth state ([`state`]): [`Growth`], occupied cells and the surface sites
//!   partitioned by `b` (or unpartitioned where every site weighs the same, `n = 0`),
//!   updated in `O(z)` per occupation;
//! - the sampler ([`sampler`]): [`SamplerKind`](sampler::SamplerKind), the paper's rejection
//!   algorithm, an exact rejection-free equivalent on the same clock, or the deterministic
//!   synchronous CA (Figs. 3 and 4).
//!
//! [`scene`] configures and runs the paper's scenes (flame front, Fig. 5; land deposition,
//! Fig. 6; crystal, Fig. 7; CA, Figs. 3-4) from TOML scenario files; [`observe`] measures
//! them (front-radius CV, mode-1 amplitude, axis/diagonal ratio); [`converge`] measures the
//! error of those observables against run time; [`roughness`] measures kinetic roughening on
//! a flat substrate (interface width, growth and roughness exponents, beyond the paper); [`figures`] (feature `plot`) draws the
//! paper's figures.
//!
//! ```
//! use cellsurf::growth::scene::{self, NoHooks, SceneConfig, SceneKind};
//!
//! // The flame front of Fig. 5 on a small hexagonal torus, 2000 events.
//! let mut cfg = SceneConfig::defaults(SceneKind::Flame);
//! (cfg.width, cfg.height, cfg.start) = (80, 92, 8.0);
//! cfg.steps = 0; // no clock limit: stop on events
//! cfg.events = Some(2000);
//! cfg.snapshots.clear();
//! let r = scene::run(&cfg, &mut NoHooks).unwrap();
//! assert_eq!(r.last.accepted, 2000);
//! // Growth only adds cells: the occupied count is the seed's cells plus the events.
//! assert!(r.last.occupied >= 2000);
//! // Same seed, same run.
//! assert_eq!(scene::run(&cfg, &mut NoHooks).unwrap().last.occupied, r.last.occupied);
//! ```

pub mod converge;
#[cfg(feature = "plot")]
pub mod figures;
pub mod observe;
pub mod roughness;
pub mod rule;
pub mod sampler;
pub mod scene;
pub mod state;

pub use state::{Growth, GrowthError, MAX_GROWTH_CELLS, OCCUPIED};
