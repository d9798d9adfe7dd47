//! [`RippleParams`]: every parameter of a ripple run, with its unit, default and valid range,
//! read from a TOML scene (`deny_unknown_fields`) or set by `cellsurf ripple`.
//!
//! Defaults give the paper's Fig. 3 situation: a rough, flat, moderately well sorted fine-sand
//! bed (d50 = 0.2 mm) under a steady current along +x, evolving into a current-ripple field.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::RippleError;
use crate::engine::count::CountRange;

/// One section (2-D, Sect. 2.1 of the paper) or a whole volume (3-D, Sect. 2.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Mode {
    /// A single row of columns parallel to the current (`ny` is forced to 1; the current runs
    /// along +x or -x, and a wave along the same line). In the flow frame the section runs
    /// along `current_angle`, whatever it is; in the grid frame only along the x axis (0 or
    /// 180 deg).
    #[serde(rename = "2d")]
    TwoD,
    /// The full `nx` x `ny` torus with the 8-neighbour rules (Eqs. 6-10).
    #[serde(rename = "3d")]
    ThreeD,
}

/// The paper's "abstraction levels" of the hydrodynamics.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Abstraction {
    /// The sliced water volume of Sect. 2.3 ([`super::water`]).
    Slices,
    /// The shadow rule of Eq. (3): no motion where `h_x - h_{x-1} < 0`.
    Shadow,
}

/// The orientation of the lattice ([`RippleParams::frame`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Frame {
    /// The lattice's x axis points east (0 deg); the flow crosses it at `current_angle`.
    Grid,
    /// The lattice's x axis points along the flow ([`RippleParams::frame_angle`]): the
    /// default.
    #[default]
    Flow,
}

impl Frame {
    /// Whether this is the default flow frame (left out of scenario and output files).
    pub fn is_flow(&self) -> bool {
        *self == Frame::Flow
    }
}

/// How bulk density and sound speed are obtained ([`super::acoustics`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum AcousticModel {
    /// Mixture-rule density from porosity; Hamilton & Bachman (1982) speed by grain size,
    /// corrected for porosity with Wood's (1930) relation.
    #[serde(rename = "hamilton")]
    Hamilton,
    /// APL-UW TR 9407 (1994) regressions on mean grain size: an acoustic look-alike preset that
    /// ignores porosity (so it cannot be written together with a porosity field).
    #[serde(rename = "apl-uw")]
    AplUw,
}

macro_rules! named_enum {
    ($t:ty, $param:literal, $expected:literal, $($name:literal => $v:expr),+) => {
        impl $t {
            /// The name used on the command line and in scene files.
            pub fn name(self) -> &'static str {
                $(if self == $v { return $name; })+
                unreachable!()
            }
        }
        impl FromStr for $t {
            type Err = RippleError;
            fn from_str(s: &str) -> Result<Self, RippleError> {
                match s {
                    $($name => Ok($v),)+
                    _ => Err(RippleError::Unknown {
                        parameter: $param,
                        value: s.to_string(),
                        expected: $expected,
                    }),
                }
            }
        }
        impl fmt::Display for $t {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

named_enum!(Mode, "mode", "2d or 3d", "2d" => Mode::TwoD, "3d" => Mode::ThreeD);
named_enum!(Abstraction, "abstraction", "slices or shadow",
    "slices" => Abstraction::Slices, "shadow" => Abstraction::Shadow);
named_enum!(Frame, "frame", "grid or flow", "grid" => Frame::Grid, "flow" => Frame::Flow);
named_enum!(AcousticModel, "acoustics", "hamilton or apl-uw",
    "hamilton" => AcousticModel::Hamilton, "apl-uw" => AcousticModel::AplUw);

/// Every parameter of a ripple run. Lengths in metres unless stated; angles in degrees; times
/// in model steps (one step = `activity x automata` Monte Carlo activations). A field left out
/// of files at its default (`skip_serializing_if`) must also be set away from its default in
/// `RippleParams::every_key`, or files read back lose it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RippleParams {
    /// 2-D section or 3-D volume. Default `3d`.
    pub mode: Mode,
    /// Hydrodynamics: `slices` (Sect. 2.3) or `shadow` (Eq. 3). Default `slices`.
    pub abstraction: Abstraction,
    /// Columns along x, >= 3. Default 128.
    pub nx: usize,
    /// Columns along y, >= 3 in 3-D (forced to 1 in 2-D). Default 64.
    pub ny: usize,
    /// Mean initial sand thickness, in automata per column, 1..=4096. Default 30.
    pub layers: usize,
    /// Extra capacity of a column above `layers`, in automata; 0 = automatic
    /// (`max(layers, 48)`). A column that is full accepts no grain. Default 0.
    pub headroom: usize,
    /// Horizontal bin size Delta x, m, > 0. Default 0.005 (5 mm).
    pub bin_size: f64,
    /// Layer thickness gd (height of one automaton), m, > 0 and <= `bin_size`.
    /// Default 0.0005 (0.5 mm).
    pub layer_thickness: f64,
    /// Steps to run (the cap with `until`). Default 10000.
    pub steps: u64,
    /// Stop early: `equilibrium` (the field is mature, [`super::equilibrium`]), with `steps`
    /// the cap; absent: run every step. Left out of files when absent. Default absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub until: Option<String>,
    /// Fraction of the automata triggered per step (the paper's 0.1 %), in (0, 1].
    /// Default 0.001.
    pub activity: f64,
    /// Median grain size d50, mm, 0.01..=10. Default 0.2.
    pub d50: f64,
    /// Sorting sigma_phi (standard deviation of phi = -log2(d / 1 mm)), 0..=2 (2 is the upper
    /// limit of "poorly sorted" in Folk & Ward; wider gives grains of metres and of microns in
    /// the 4-sigma tails). Default 0.5.
    pub sorting: f64,
    /// Direction the current flows towards, degrees counter-clockwise from east (the grid
    /// frame's +x), -360..=360. Default 0.
    pub current_angle: f64,
    /// Steady current speed in the free stream, m/s, 0..=10. Default 0.5.
    pub current_speed: f64,
    /// Period of the oscillating (wave) flow component, steps (the command line takes it in
    /// seconds and converts it with the step duration); 0 = no wave. Default 0.
    pub wave_period: f64,
    /// Amplitude of the oscillating flow component (the near-bed orbital velocity), m/s,
    /// 0..=10. Default 0.
    pub wave_amplitude: f64,
    /// Wave friction factor `f_w` of the waves' bed stress `tau_w = rho_w (f_w / 2) U_w^2`
    /// (R. L. Soulsby (1997), *Dynamics of Marine Sands*, Eq. 57), dimensionless, in [0, 1];
    /// 0: the waves use `drag_coefficient` like the current (the paper's single law). The
    /// command line sets it from the orbital excursion and the grain size (Soulsby's Eq. 60a,
    /// [`super::waves::wave_friction_factor`]): the thin wave boundary layer rubs the bed
    /// harder than a current of the same speed. Left out of files when 0. Default 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub wave_friction_factor: f64,
    /// Direction the waves propagate towards, degrees counter-clockwise from east; absent: along
    /// `current_angle`; -360..=360. 3-D only. Default absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wave_angle: Option<f64>,
    /// The lee vortex of wave ripples (`docs/ripple.md`, "Waves"): the orbital excursion
    /// amplitude `A = U_w T / (2 pi)`, m, of the waves (the command line sets it from the waves
    /// whenever `--wave-period` is given, unless `--no-wave-vortex`); 0: off. Where the waves dominate, the
    /// water's shelter behind a crest reaches no further than the lee vortex has travelled
    /// since the flow last reversed, half the water's travel, `A (1 - cos psi) / 2`
    /// ([`crate::ripple::water::VORTEX_CONVECTION`]), and a grain in that shelter is carried
    /// back towards the crest by the vortex. Left out of files when 0. Default 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub wave_vortex: f64,
    /// The vortex's near-bed return speed as a fraction of the free stream's, in [0, 1] (with
    /// `wave_vortex`). Default 0.5.
    #[serde(skip_serializing_if = "is_half")]
    pub vortex_strength: f64,
    /// Orientation of the lattice: `grid`, its x axis east and the flow at
    /// `current_angle` across it, or `flow`, its x axis along the flow (the current's
    /// direction, or the waves' when there is no current: [`RippleParams::frame_angle`]), so
    /// that the lattice does not pull the crests towards its axes and diagonals. The volume is
    /// written in the lattice's frame, its x axis at `frame_angle` degrees from east (recorded
    /// in every output). In 2-D the section runs along the current: in the flow frame its x
    /// axis is the current's direction, or the opposite one where that points west of
    /// north-south (so that 180 deg keeps it east, the flow towards -x); the grid frame takes
    /// only currents along its x axis (0 or 180 deg).
    /// Default `flow`. (Scenario files written before the flow frame became the default meant
    /// `grid`: add `frame = "grid"` to run them as they were.)
    #[serde(skip_serializing_if = "Frame::is_flow")]
    pub frame: Frame,
    /// Avalanche angle alpha (Eq. 6), degrees, in (0, 90). Default 32.
    pub avalanche_angle: f64,
    /// Stoss stability angle beta (Eq. 3), degrees, in [0, avalanche_angle]. Default 7.
    pub stoss_angle: f64,
    /// Hold grains on the whole stoss face (opt-in): where the current dominates, a grain is
    /// not triggered when the rise ahead of it (to the next column downstream) is steeper
    /// than beta, wherever it lies on the rise, in place of Eq. (3)'s second case, which holds
    /// only the grain at the concave foot of such a rise. Rises are whole automata, so a beta
    /// between two of them is met on average, as the stoss cap's (a rise of
    /// `ceil(tan(beta) dx / gd)` automata holds the grain with the probability
    /// `1 - frac(tan(beta) dx / gd)`, at a concave foot too, where the foot rule holds it
    /// always; a steeper rise always). Our reading: beta is "the maximum slope of the stoss
    /// side" (Sect. 2.1 of the paper), and a face steeper than it erodes from its top, where
    /// the rise ahead flattens, not from within, so that erosion, like deposition under the
    /// stoss cap, does not steepen the stoss beyond beta. Off (the paper's foot rule) where
    /// the waves' bed stress exceeds the current's, as the stoss cap is. Left out of files
    /// when false. Default false.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub stoss_face_hold: bool,
    /// Creep angle gamma (Eqs. 9-10), degrees, in [0, 90). Default 5.
    pub creep_angle: f64,
    /// Seed of the random stream, 0..=2^53 (so that every output file records it exactly).
    /// Default 1.
    pub seed: u64,
    /// Initial roughness: each column's height is `layers` plus a uniform integer in
    /// `-roughness..=roughness` automata (then relaxed below alpha). Default 3.
    pub roughness: usize,
    /// Rolling friction coefficient mu of E_friction = mu m g' Delta s (Eq. 4), > 0. Default 0.6.
    pub friction: f64,
    /// Flat-bed travel of a grain per unit excess Shields stage, in bins, > 0 (sets E_x).
    /// Default 1.5.
    pub hop_length: f64,
    /// Flat-bed travel of a grain per unit excess Shields stage, in diameters of the grain
    /// itself (opt-in): when above 0 it replaces `hop_length` (bins), so the grain's travel is
    /// a length in metres, the same whatever the bin size (the last part-bin of a path is
    /// crossed with the probability of the fraction of its cost the budget has left). 37.5
    /// gives the default's travel at 5 mm bins for 0.2 mm sand. 0..=1e5 (0: off). Left out of
    /// files when 0. Default 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub hop_grains: f64,
    /// Draw each activated grain's budget from the exponential law of the same mean (opt-in;
    /// exponentially distributed step lengths: H. A. Einstein (1950), "The bed-load function
    /// for sediment transportation in open channel flows", USDA Technical Bulletin 1026),
    /// instead of the same budget for every grain of a class. Left out of files when false.
    /// Default false.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub hop_exponential: bool,
    /// The bin in flat-bed travels (opt-in): when above 0, a run's bin is `bin_travels x` the
    /// median grain's nominal flat-bed travel in the current, `hop_grains x d50 x (theta /
    /// theta_cr - 1)` at `current_speed` (`travel::median_travel`), to 3 significant
    /// digits (at least the finest bin whose automata hold the sand in 4096 layers,
    /// [`RippleParams::finest_bin`], which binds near the threshold of motion), and its
    /// automata and layers follow, keeping the ratio of `bin_size` to
    /// `layer_thickness` and the depth of sand `layers x layer_thickness`
    /// ([`RippleParams::with_travel_bin`]; where the median grain does not move in the current
    /// the bin is `bin_size`). A bin coarser than the travel makes every hop that moves a grain
    /// a whole bin, longer than the physics' travel, and the ripples with it; with the bin a
    /// fixed part of the travel every grain and current is resolved alike. Needs `hop_grains`
    /// (a travel in metres). 0..=100 (0: off, the bin is `bin_size`). Left out of files when 0.
    /// Default 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub bin_travels: f64,
    /// Lengths in units of the waves' orbital excursion (opt-in), m: `bin_size`,
    /// `layer_thickness`, `hop_grains` and `crest_suspension` are those for waves of orbital
    /// excursion amplitude `A = orbit_reference`, and a run whose waves dominate and have the
    /// lee vortex, whose reach is their amplitude (`wave_vortex`), scales the four by
    /// `wave_vortex / orbit_reference` and records `orbit_reference = wave_vortex`
    /// ([`RippleParams::with_orbit_scale`]; docs/ripple.md, "A recipe for mature wave
    /// ripples"). Every length of the rules then follows the orbit. 0 or 1e-3..=100 (0: off).
    /// Left out of files when 0. Default 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub orbit_reference: f64,
    /// Crest suspension (opt-in), m: a grain that the flow has moved (at least one hop,
    /// outside the lee vortex) from a column whose top stood `zeta` metres above the bed's
    /// mean level was suspended with probability `min(1, (zeta / crest_suspension)^n)` (`n` the
    /// `suspension_exponent`, default 2), and settles on a column drawn uniformly from the
    /// whole volume instead of where it rolled. Our reading of the sand that a crest sheds into the flow above the ripples, which
    /// settles over many ripple lengths: the higher a crest, the more it sheds, so sand passes
    /// from the highest ripples to all the others. A length chosen by the user, not derived
    /// from the grain or the flow. 0..=1 (0: off). Left out of files when 0. Default 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub crest_suspension: f64,
    /// Crest suspension's length in median grain diameters (opt-in): when above 0, crest
    /// suspension acts with `L = crest_suspension_grains x d50` in place of `crest_suspension`
    /// (which must then be 0), so that one scenario scales with the grain. A factor chosen by
    /// the user, not derived. 0..=1e5 (0: off). Left out of files when 0. Default 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub crest_suspension_grains: f64,
    /// Crest suspension's length in flat-bed travels (opt-in): when above 0, crest suspension
    /// acts with `L = crest_suspension_hops x` the median grain's mean travel on a flat bed in
    /// the step's free-stream flow (`travel::median_travel`), the same `L`
    /// for every grain class, in place of `crest_suspension` and `crest_suspension_grains`
    /// (which must then be 0). Our reading: a crest sheds the grains that it lifts out of the
    /// bedload layer, whose thickness grows with the transport stage as the grains' hop
    /// lengths do (L. C. van Rijn (1984), "Sediment transport, part I: bed load transport",
    /// *J. Hydraul. Eng.* 110(10), 1431-1456,
    /// <https://doi.org/10.1061/(ASCE)0733-9429(1984)110:10(1431)>); taking `L` in proportion
    /// to the travel is our choice, not van Rijn's, so that the crests' height follows the
    /// same travel as the ripples' length. Without `hop_grains` the travel is in bins
    /// (`hop_length`), and `L` with it. A factor chosen by the user, not derived. 0..=1000
    /// (0: off). Left out of files when 0. Default 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub crest_suspension_hops: f64,
    /// Crest suspension's exponent `n`: a grain moved from `zeta` above the bed's mean level
    /// is suspended with probability `min(1, (zeta / L)^n)`, so a larger `n` sheds sand
    /// from the crests above `L` and hardly from the lower ones. In [1, 64]. Left out of files
    /// when 2. Default 2.
    #[serde(skip_serializing_if = "is_two")]
    pub suspension_exponent: f64,
    /// Leading bed stress (opt-in), dimensionless factor `B`: the speed fraction at the bed
    /// of an exposed column is multiplied by `max(0, 1 + B r)`, `r` the bed's rise (m per m)
    /// from the column two bins upstream to this one, so the flow is faster on the upstream
    /// face of every bump and slower on its downstream face. Our reading of the linear theory
    /// of turbulent flow over low bumps, in which the bed stress leads the topography (a term
    /// in phase with the slope): P. S. Jackson and J. C. R. Hunt (1975), "Turbulent wind flow
    /// over a low hill", *Q. J. R. Meteorol. Soc.* 101, 929-955,
    /// <https://doi.org/10.1002/qj.49710143015>; F. Charru, B. Andreotti and P. Claudin
    /// (2013), "Sand ripples and dunes", *Annu. Rev. Fluid Mech.* 45, 469-493,
    /// <https://doi.org/10.1146/annurev-fluid-011212-140806>. With `separation_angle` it
    /// starts ripples on a flat bed without the shelter of bumps of an automaton or two.
    /// 0..=100 (0: off). Left out of files when 0. Default 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub stress_lead: f64,
    /// Flow separation angle (opt-in), degrees: an obstruction shelters the bed behind it
    /// (the water slices' zero-speed zone and recovery, Sect. 2.3) only where the bed drops
    /// behind it by at least this angle over the step to the next point downstream, in whole
    /// automata (`ceil(tan(angle) bin / layer_thickness)` over a bin, more over a diagonal
    /// step), since the flow stays attached over gentle bumps. 0 (off: every obstruction
    /// shelters, as in the paper) or an angle whose drop over a bin is 2 automata or more and
    /// no steeper than the avalanche angle (above 5.71 and at most 30.96 deg at the default
    /// bin, layer thickness and avalanche angle). Slices only. Left out of files when 0.
    /// Default 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub separation_angle: f64,
    /// Bed drag coefficient C_D of tau = rho_w C_D u^2 (Soulsby 1997), > 0. Default 0.0025.
    pub drag_coefficient: f64,
    /// Water slices: slice thickness, in automata (layers), >= 1. Default 2.
    pub slice_layers: usize,
    /// Water slices: length behind an obstruction where a slice's speed is zero, bins per slice
    /// the obstruction rises above the slice. Default 1.
    pub shadow_length: usize,
    /// Water slices: the drag, the delay in space (bins) with which a slice drags the one below
    /// it back up to speed behind an obstruction (Sect. 2.3): after its zero-speed zone a
    /// slice's speed recovers linearly over `drag_delay` bins per slice the obstruction rises
    /// above it; 0 recovers at once. 0..=64. Default 1.
    pub drag_delay: usize,
    /// Compaction: fraction of the excess porosity (above the dense packing) removed from each
    /// of the `compaction_depth` automata under a newly deposited one, in [0, 1]. Default 0.1.
    pub compaction_rate: f64,
    /// Compaction: how many automata under a deposit are compacted, 0..=64. Default 4.
    pub compaction_depth: usize,
    /// Acoustic model: `hamilton` or `apl-uw`. Default `hamilton`.
    pub acoustics: AcousticModel,
}

impl Default for RippleParams {
    fn default() -> Self {
        RippleParams {
            mode: Mode::ThreeD,
            abstraction: Abstraction::Slices,
            nx: 128,
            ny: 64,
            layers: 30,
            headroom: 0,
            bin_size: 0.005,
            layer_thickness: 0.0005,
            steps: 10000,
            until: None,
            activity: 0.001,
            d50: 0.2,
            sorting: 0.5,
            current_angle: 0.0,
            current_speed: 0.5,
            wave_period: 0.0,
            wave_amplitude: 0.0,
            wave_friction_factor: 0.0,
            wave_angle: None,
            wave_vortex: 0.0,
            vortex_strength: 0.5,
            frame: Frame::Flow,
            avalanche_angle: 32.0,
            stoss_angle: 7.0,
            stoss_face_hold: false,
            creep_angle: 5.0,
            seed: 1,
            roughness: 3,
            friction: 0.6,
            hop_length: 1.5,
            hop_grains: 0.0,
            bin_travels: 0.0,
            orbit_reference: 0.0,
            crest_suspension: 0.0,
            crest_suspension_grains: 0.0,
            crest_suspension_hops: 0.0,
            suspension_exponent: 2.0,
            stress_lead: 0.0,
            separation_angle: 0.0,
            hop_exponential: false,
            drag_coefficient: 0.0025,
            slice_layers: 2,
            shadow_length: 1,
            drag_delay: 1,
            compaction_rate: 0.1,
            compaction_depth: 4,
            acoustics: AcousticModel::Hamilton,
        }
    }
}

impl RippleParams {
    /// Parameters whose serialization lists every key with its type: the fields left out of
    /// files at their defaults (the stop rule, the waves' angle, friction factor and lee
    /// vortex, the frame, the opt-in travel and suspension keys) set to something else. The
    /// reader of files ([`super::input::read`]) takes the keys and their types from it; the
    /// values are never used (the test `netcdf_round_trip_keeps_every_opt_in_key` fails when a
    /// key is missing here; the frame is read apart).
    pub(crate) fn every_key() -> RippleParams {
        RippleParams {
            until: Some(String::new()),
            wave_angle: Some(0.0),
            wave_friction_factor: 0.5,
            wave_vortex: 0.5,
            vortex_strength: 1.0,
            frame: Frame::Grid,
            hop_grains: 1.0,
            hop_exponential: true,
            bin_travels: 1.0,
            orbit_reference: 0.1,
            stoss_face_hold: true,
            crest_suspension: 0.5,
            crest_suspension_grains: 1.0,
            crest_suspension_hops: 1.0,
            suspension_exponent: 4.0,
            stress_lead: 1.0,
            separation_angle: 10.0,
            ..RippleParams::default()
        }
    }
}

/// `seed`: 0 to 2^53, the largest integer every output records exactly (a NetCDF-3
/// attribute is a double).
pub const SEED: CountRange = CountRange::new(
    0,
    1 << 53,
    "an integer in [0, 2^53 = 9007199254740992] (recorded exactly in the output files)",
);
/// `nx`: bins along x.
pub const NX: CountRange = CountRange::new(3, 1 << 16, "an integer in [3, 65536]");
/// `ny`: bins along y in 3-D mode (a 2-D section has one).
pub const NY: CountRange = CountRange::new(
    3,
    1 << 16,
    "an integer in [3, 65536] in 3-D mode (a 2-D section of one row takes mode = \"2d\", or --size NXx1)",
);
/// `--size NXxNY`, as [`NX`] and [`NY`] hold it.
pub const SIZE_SIDES: &str = "sides of 3 to 65536 bins (NY 1 in 2-D mode)";
/// `layers`: mean initial sand thickness, automata per column.
pub const LAYERS: CountRange = CountRange::new(1, 4096, "an integer in [1, 4096]");
/// `steps`: steps of a run.
pub const STEPS: CountRange = CountRange::new(0, 1 << 40, "an integer in [0, 2^40]");

fn range(parameter: &'static str, value: impl fmt::Display, expected: &str) -> RippleError {
    RippleError::Range {
        parameter,
        value: value.to_string(),
        expected: expected.to_string(),
    }
}

/// A number as an error message shows it ([`crate::engine::shown`]).
pub use crate::engine::shown;

/// The most automata slots of a run's volume: columns x column capacity
/// ([`RippleParams::capacity`]).
pub const MAX_SLOTS: u64 = 1 << 33;

/// Keys of older scenario files that were renamed: (old, new).
pub const RENAMED_KEYS: [(&str, &str); 1] = [("recovery_length", "drag_delay")];

/// A scenario parsing error `msg`, with a hint when it is about a renamed key
/// ([`RENAMED_KEYS`]).
pub fn renamed_key_hint(msg: &str) -> String {
    for (old, new) in RENAMED_KEYS {
        if msg.contains(&format!("unknown field `{old}`")) {
            return format!(
                "{msg}\n`{old}` was renamed `{new}` (the same value, bins per slice): rename the key"
            );
        }
    }
    msg.to_string()
}

/// A positive number to four significant digits (`0.0003124`), for limits computed from
/// other parameters.
pub fn rounded(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return shown(v);
    }
    let decimals = (3 - v.log10().floor() as i64).clamp(0, 17) as usize;
    format!("{v:.decimals$}")
}

/// Whether a number is zero (left out of scenario and output files).
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

fn is_half(v: &f64) -> bool {
    *v == 0.5
}

fn is_two(v: &f64) -> bool {
    *v == 2.0
}

fn check_f(
    parameter: &'static str,
    v: f64,
    lo: f64,
    hi: f64,
    lo_open: bool,
    hi_open: bool,
) -> Result<(), RippleError> {
    let ok = v.is_finite()
        && (if lo_open { v > lo } else { v >= lo })
        && (if hi_open { v < hi } else { v <= hi });
    if ok {
        Ok(())
    } else {
        let expected = format!(
            "a number in {}{lo}, {hi}{}",
            if lo_open { "(" } else { "[" },
            if hi_open { ")" } else { "]" }
        );
        Err(range(parameter, shown(v), &expected))
    }
}

impl RippleParams {
    /// `layer_thickness` is a number in `(0, bin_size x tan(avalanche_angle)]`: one automaton
    /// over one bin is a slope no steeper than the avalanche angle, which the lattice must hold
    /// (the avalanche rule moves whole automata). `bin_size` and `avalanche_angle` are checked
    /// first.
    fn check_layer_thickness(&self) -> Result<(), RippleError> {
        let v = self.layer_thickness;
        if v.is_finite() && v > 0.0 && self.lattice_slope_deg() <= self.avalanche_angle {
            return Ok(());
        }
        let steeper = if v.is_finite() && v > 0.0 {
            format!(
                ": one automaton of layer_thickness over one bin of bin_size is a slope of {:.1} \
                 deg, steeper than the avalanche angle, which the lattice cannot hold (the \
                 avalanche rule moves grains in whole automata)",
                self.lattice_slope_deg()
            )
        } else {
            String::new()
        };
        let max = rounded(self.bin_size * self.avalanche_angle.to_radians().tan());
        Err(range(
            "layer_thickness",
            shown(v),
            &format!(
                "a number in (0, {max}]: at most bin_size x tan(avalanche_angle) = {max} m \
                 (bin_size = {} m, avalanche_angle = {} deg){steeper}",
                shown(self.bin_size),
                self.avalanche_angle,
            ),
        ))
    }

    /// Reads a TOML scene, a `cellsurf ripple` scenario file: the same keys as the fields,
    /// unknown keys rejected, missing keys default, and `model = "ripple"` (which
    /// `--print-scenario` writes; optional here, another model refused). The result is
    /// validated.
    pub fn from_toml(text: &str) -> Result<Self, RippleError> {
        let mut t: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| RippleError::Toml(e.to_string()))?;
        match t.remove("model") {
            None => {}
            Some(toml::Value::String(m)) if m == "ripple" => {}
            Some(m) => {
                return Err(RippleError::Toml(format!(
                    "model = {m} is not \"ripple\": a scenario of another subcommand"
                )));
            }
        }
        let p = Self::from_table(t)?;
        p.validate()?;
        Ok(p)
    }

    /// The parameters a scenario's keys give (the others at their defaults; not validated).
    /// A value is read as the command line reads its option: a whole number may be written
    /// `2e4` or `20000.0`, and a value that is not one of the key's kind is named by its key,
    /// with the value and what the key takes (`layers = 2.5 is not a valid value: expected a
    /// whole number >= 0`), not by the TOML reader's type names. A whole number too large for
    /// any count (`steps = 1e30`) is refused with the key's own range, the value as written.
    pub fn from_table(t: toml::Table) -> Result<Self, RippleError> {
        let none = toml::Table::new();
        let fits = |k: &str, v: &toml::Value| {
            crate::engine::scenario::key_reads_as::<RippleParams>(&none, k, v)
        };
        let mut read = toml::Table::new();
        for (k, v) in t {
            let v = match v {
                toml::Value::Float(f)
                    if (f.fract() == 0.0 || f.is_infinite()) && fits(&k, &v).is_err() =>
                {
                    // (past the largest count, the largest: the key's range check refuses it,
                    // and names the value as written)
                    let whole = toml::Value::Integer(if f.abs() < 9.223_372_036_854_775e18 {
                        f as i64
                    } else if f > 0.0 {
                        i64::MAX
                    } else {
                        i64::MIN
                    });
                    if fits(&k, &whole).is_ok() {
                        if f.abs() >= 9.223_372_036_854_775e18 {
                            let one = fits(&k, &whole).expect("checked");
                            return Err(match one.validate() {
                                Err(RippleError::Range {
                                    parameter,
                                    expected,
                                    ..
                                }) if parameter == k => RippleError::Range {
                                    parameter,
                                    value: shown(f),
                                    expected,
                                },
                                _ => RippleError::Toml(format!(
                                    "{k} = {} is not a valid value: expected a whole number \
                                     below 2^63",
                                    shown(f)
                                )),
                            });
                        }
                        whole
                    } else {
                        v
                    }
                }
                v => v,
            };
            if let Err(e) = fits(&k, &v) {
                if e.contains("unknown field") {
                    return Err(RippleError::Toml(renamed_key_hint(&e)));
                }
                return Err(RippleError::Toml(format!(
                    "{k} = {v} is not a valid value: {e}"
                )));
            }
            read.insert(k, v);
        }
        toml::Value::Table(read)
            .try_into()
            .map_err(|e: toml::de::Error| RippleError::Toml(renamed_key_hint(&e.to_string())))
    }

    /// The parameters as a TOML scene.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }

    /// Whether the run has waves: an orbital velocity and a period (a velocity without a
    /// period, which a run with no motion records, moves nothing). The rules, the step clock,
    /// the regime and Rubin & Hunter's crest normal all ask this.
    pub fn has_wave(&self) -> bool {
        self.wave_period > 0.0 && self.wave_amplitude > 0.0
    }

    /// Whether the waves dominate the flow: their own bed stress (through
    /// [`RippleParams::wave_stress_amplitude`]) exceeds the current's alone (not raised by the
    /// waves, as [`RippleParams::mean_stress_speed`] raises it for the bed stress). The one
    /// criterion for the frame, the stoss cap, the predictor and the direction along which
    /// ripples are measured; it asks for an orbital velocity only, as the command line judges
    /// it before the period has a length in steps.
    pub fn waves_dominate(&self) -> bool {
        self.wave_amplitude > 0.0 && self.wave_stress_amplitude() > self.current_speed
    }

    /// The direction of the dominant flow, degrees counter-clockwise from east: the waves'
    /// ([`RippleParams::waves_dominate`]; along the current when they have no angle of their
    /// own), the current's otherwise.
    pub fn flow_angle(&self) -> f64 {
        if self.waves_dominate() {
            self.wave_angle.unwrap_or(self.current_angle)
        } else {
            self.current_angle
        }
    }

    /// The direction of the lattice's x axis, degrees counter-clockwise from east: 0 in the
    /// grid frame; in the flow frame the current's, or the waves' when there is no current (a
    /// 2-D section's: the current's, or the opposite one where the section runs towards -x,
    /// [`RippleParams::section_forward`]). (With both, the lattice follows the current even where the waves dominate:
    /// turned along waves at 60 deg to a current of 0.3 m/s, the 0.4 m/s waves of 0.3 mm sand
    /// built one domain-long bedform in three seeds of three, against ripples of 28.6 cm with
    /// the lattice along the current, when the flows' friction velocities were added; not
    /// measured since they add by their stresses, [`RippleParams::combined_flow`].)
    pub fn frame_angle(&self) -> f64 {
        if self.frame == Frame::Grid {
            0.0
        } else if self.mode == Mode::TwoD {
            // the section along the current, its x axis within 90 deg of east (so 0 and 180
            // keep it east, the flow towards +x or -x)
            if self.section_forward() {
                self.current_angle
            } else {
                self.current_angle - 180.0
            }
        } else if self.current_speed > 0.0 || self.wave_amplitude == 0.0 {
            self.current_angle
        } else {
            self.wave_angle.unwrap_or(self.current_angle)
        }
    }

    /// Whether a 2-D section's current runs towards +x (its direction within 90 deg of east,
    /// north included, south not: `current_angle` in (-90, 90] modulo 360), so that one
    /// direction typed two ways (270 and -90 deg) makes one section.
    pub fn section_forward(&self) -> bool {
        let a = self.current_angle.rem_euclid(360.0);
        a <= 90.0 || a > 270.0
    }

    /// The dominant flow's direction on the lattice, degrees: 0 in the flow frame; in 2-D 0 or
    /// 180 (the section runs towards +x or -x); in the grid frame its angle from east.
    pub fn lattice_flow_angle(&self) -> f64 {
        if self.mode == Mode::TwoD {
            if self.section_forward() { 0.0 } else { 180.0 }
        } else {
            self.flow_angle() - self.frame_angle()
        }
    }

    /// The direction on the lattice along which the lee and stoss faces are measured, degrees:
    /// the dominant flow's ([`RippleParams::lattice_flow_angle`]), turned by 180 deg where
    /// waves dominate a current they point against (more than 90 deg from it): a wave's
    /// direction is a sign that means nothing to its to-and-fro, while the current's drift
    /// sets which face is the lee (0.4 m/s waves at 0 and 180 deg over a 0.3 m/s current, their
    /// friction velocities added, gave symmetry indices of 1.4-1.6 and 0.75-0.84 before, lee
    /// and stoss swapped by the sign; 1.56 and 1.18 after, seed 1, fields that still differ by
    /// the wave's phase; with the stresses added, [`RippleParams::combined_flow`], 0.91 and
    /// 0.94: the waves' to-and-fro dominates the current's drift the more).
    pub fn lattice_face_angle(&self) -> f64 {
        let a = self.lattice_flow_angle();
        let against = (self.flow_angle() - self.current_angle).to_radians().cos() < -1e-9;
        if self.mode == Mode::ThreeD && self.current_speed > 0.0 && self.waves_dominate() && against
        {
            a + 180.0
        } else {
            a
        }
    }

    /// The wave amplitude, m/s, that gives the waves' bed stress through `drag_coefficient`:
    /// `U_w sqrt(f_w / (2 C_D))`, or `U_w` itself when `wave_friction_factor` is 0. The rules,
    /// the step clock, the regime and Rubin & Hunter's crest normal combine it with the
    /// current by their stresses ([`RippleParams::combined_flow`]).
    pub fn wave_stress_amplitude(&self) -> f64 {
        if self.wave_friction_factor > 0.0 {
            self.wave_amplitude * (0.5 * self.wave_friction_factor / self.drag_coefficient).sqrt()
        } else {
            self.wave_amplitude
        }
    }

    /// The current's bed stress raised by the waves, as the speed of a current that rubs the
    /// bed as hard through `drag_coefficient`, m/s: Eq. 69 of R. L. Soulsby (1997),
    /// *Dynamics of Marine Sands*, Thomas Telford, `tau_m = tau_c [1 + 1.2 (tau_w / (tau_c +
    /// tau_w))^3.2]`, with `tau_c = rho_w C_D U_c^2` and the waves' own stress `tau_w`
    /// ([`RippleParams::wave_stress_amplitude`]). `U_c` itself without waves
    /// ([`RippleParams::has_wave`]); 0 without a current.
    pub fn mean_stress_speed(&self) -> f64 {
        let (c2, w) = (
            self.current_speed * self.current_speed,
            self.wave_stress_amplitude(),
        );
        if c2 == 0.0 || !self.has_wave() {
            return self.current_speed;
        }
        let w2 = w * w;
        self.current_speed * (1.0 + 1.2 * (w2 / (c2 + w2)).powf(3.2)).sqrt()
    }

    /// The flow of one phase of the wave cycle, `s = sin(2 pi t / T)`, as a velocity `(u_x,
    /// u_y)` in m/s whose quadratic stress `rho_w C_D |u|^2` along `u` is the bed stress of
    /// current and waves together; `c` and `w` are the current's and the waves' directions,
    /// radians. The stresses add as vectors, the current's raised by the waves (Soulsby 1997,
    /// Eq. 69, [`RippleParams::mean_stress_speed`]) and the waves' quadratic in their
    /// velocity: `tau(t) = tau_m e_c + tau_w s |s| e_w`, whose mean over the cycle is Eq. 69's
    /// `tau_m` along the current and whose largest magnitude is Eq. 70's
    /// `tau_max = sqrt((tau_m + tau_w cos phi)^2 + (tau_w sin phi)^2)`, `phi` the angle
    /// between the current and the waves' axis, 0-90 deg (our reading of Eqs. 69-70 phase by
    /// phase). A current alone gives
    /// `U_c e_c`, waves alone `U'_w s e_w` (`U'_w` the [`RippleParams::wave_stress_amplitude`]),
    /// each exactly as written; a run without waves ([`RippleParams::has_wave`]) the current
    /// alone. The rules, the step clock, the regime and Rubin & Hunter's
    /// crest normal all take their flow from here.
    pub fn combined_flow(&self, c: f64, w: f64, s: f64) -> (f64, f64) {
        let cw = if self.has_wave() {
            self.wave_stress_amplitude()
        } else {
            0.0
        };
        if self.current_speed == 0.0 || cw == 0.0 {
            return (
                self.current_speed * c.cos() + cw * s * w.cos(),
                self.current_speed * c.sin() + cw * s * w.sin(),
            );
        }
        let m = self.mean_stress_speed();
        let (tm, tw) = (m * m, cw * cw * s * s.abs());
        let (tx, ty) = (tm * c.cos() + tw * w.cos(), tm * c.sin() + tw * w.sin());
        let t = tx.hypot(ty);
        if t == 0.0 {
            return (0.0, 0.0);
        }
        let u = t.sqrt();
        (u * tx / t, u * ty / t)
    }

    /// The current's direction on the lattice, degrees (`current_angle - frame_angle`).
    pub fn lattice_current_angle(&self) -> f64 {
        self.current_angle - self.frame_angle()
    }

    /// The waves' direction on the lattice, degrees, when they have their own.
    pub fn lattice_wave_angle(&self) -> Option<f64> {
        self.wave_angle.map(|w| w - self.frame_angle())
    }

    /// The flat-bed travel per unit excess Shields stage of a grain of `d` m, metres:
    /// `hop_grains x d` when `hop_grains` is set, `hop_length x bin_size` otherwise.
    pub fn hop_metres(&self, d: f64) -> f64 {
        if self.hop_grains > 0.0 {
            self.hop_grains * d
        } else {
            self.hop_length * self.bin_size
        }
    }

    /// The automaton (m) and layers that go with a bin of `bin` m where the automata follow
    /// the bin: this bin's ratio of bin to automaton and its depth of sand in metres (the
    /// automaton to 10 significant digits, as if typed; the layers rounded, at least 1).
    pub fn automata_for_bin(&self, bin: f64) -> (f64, usize) {
        let t = bin * self.layer_thickness / self.bin_size;
        let t: f64 = format!("{t:.9e}").parse().unwrap_or(t);
        let layers = (self.layers as f64 * self.layer_thickness / t)
            .round()
            .max(1.0) as usize;
        (t, layers)
    }

    /// Whether crest suspension acts (one of its three lengths is set).
    pub fn crest_suspension_on(&self) -> bool {
        self.crest_suspension_hops > 0.0 || self.crest_suspension_m() > 0.0
    }

    /// Crest suspension's fixed length `L`, metres: `crest_suspension_grains x d50` when that
    /// is set, `crest_suspension` otherwise (0 as well when the length is in flat-bed travels,
    /// `crest_suspension_hops`, which the rule computes per grain and step).
    pub fn crest_suspension_m(&self) -> f64 {
        if self.crest_suspension_grains > 0.0 {
            self.crest_suspension_grains * self.d50 * 1e-3
        } else {
            self.crest_suspension
        }
    }

    /// The slope of one automaton over one bin, degrees: `atan(layer_thickness / bin_size)`,
    /// the smallest slope the lattice can make between two neighbouring columns (at most the
    /// avalanche angle, [`RippleParams::validate`]).
    pub fn lattice_slope_deg(&self) -> f64 {
        (self.layer_thickness / self.bin_size).atan().to_degrees()
    }

    /// [`RippleParams::frame_angle`] as recorded in the outputs (`x_axis_direction_deg`):
    /// degrees counter-clockwise from east, in [0, 360).
    pub fn x_axis_direction_deg(&self) -> f64 {
        let a = self.frame_angle().rem_euclid(360.0);
        if a >= 360.0 { 0.0 } else { a + 0.0 }
    }

    /// Rows actually simulated: 1 in 2-D, `ny` in 3-D.
    pub fn rows(&self) -> usize {
        match self.mode {
            Mode::TwoD => 1,
            Mode::ThreeD => self.ny,
        }
    }

    /// Capacity of a column, in automata.
    pub fn capacity(&self) -> usize {
        let head = if self.headroom == 0 {
            self.layers.max(48)
        } else {
            self.headroom
        };
        self.layers + self.roughness + head
    }

    /// What the volume's size limit expects, with this run's numbers: the slots are the columns
    /// (`nx x ny`, `ny` = 1 in 2-D) times a column's capacity ([`RippleParams::capacity`]).
    fn slots_expected(&self) -> String {
        let cap = self.capacity();
        let head = cap - self.layers - self.roughness;
        let head_note = if self.headroom == 0 {
            format!(" (headroom 0: automatic, max(layers, 48) = {head})")
        } else {
            String::new()
        };
        let (nx, ny) = (self.nx as u128, self.rows() as u128);
        let columns_max = MAX_SLOTS / cap as u64;
        format!(
            "nx x ny x capacity at most 2^33 = {MAX_SLOTS} automata slots, a column's capacity \
             being layers + roughness + headroom = {} + {} + {head} = {cap}{head_note}: here \
             {nx} x {ny} x {cap} = {}; at this capacity nx x ny at most {columns_max} columns \
             (or fewer layers)",
            self.layers,
            self.roughness,
            nx * ny * cap as u128,
        )
    }

    /// Checks every parameter; the error names the parameter, its value and the valid range.
    pub fn validate(&self) -> Result<(), RippleError> {
        if !SEED.contains(self.seed) {
            return Err(range("seed", self.seed, SEED.expected));
        }
        if self.mode == Mode::TwoD && self.frame == Frame::Grid {
            let a = self.current_angle.rem_euclid(360.0);
            if a != 0.0 && a != 180.0 {
                return Err(range(
                    "current_angle",
                    self.current_angle,
                    "0 (flow along +x) or 180 (along -x) in 2-D mode with frame = grid, whose section runs along its x axis, east (frame = flow runs a section along any current)",
                ));
            }
        }
        if !NX.contains(self.nx as u64) {
            return Err(range("nx", self.nx, NX.expected));
        }
        if self.mode == Mode::ThreeD && !NY.contains(self.ny as u64) {
            return Err(range("ny", self.ny, NY.expected));
        }
        if !LAYERS.contains(self.layers as u64) {
            return Err(range("layers", self.layers, LAYERS.expected));
        }
        if self.headroom > 16384 {
            return Err(range("headroom", self.headroom, "an integer in [0, 16384]"));
        }
        if self.roughness > 1024 {
            return Err(range(
                "roughness",
                self.roughness,
                "an integer in [0, 1024]",
            ));
        }
        if self.capacity() > u16::MAX as usize {
            return Err(range(
                "headroom",
                self.capacity(),
                "layers + roughness + headroom at most 65535",
            ));
        }
        let cells = self.nx as u128 * self.rows() as u128 * self.capacity() as u128;
        if cells > MAX_SLOTS as u128 {
            return Err(range("nx", self.nx, &self.slots_expected()));
        }
        check_f("bin_size", self.bin_size, 0.0, 100.0, true, false)?;
        check_f(
            "avalanche_angle",
            self.avalanche_angle,
            0.0,
            90.0,
            true,
            true,
        )?;
        self.check_layer_thickness()?;
        if !STEPS.contains(self.steps) {
            return Err(range("steps", self.steps, STEPS.expected));
        }
        if let Some(u) = &self.until
            && u != "equilibrium"
        {
            return Err(range("until", u, "equilibrium (or absent)"));
        }
        check_f("activity", self.activity, 0.0, 1.0, true, false)?;
        check_f("d50", self.d50, 0.01, 10.0, false, false)?;
        check_f("sorting", self.sorting, 0.0, 2.0, false, false)?;
        check_f(
            "current_angle",
            self.current_angle,
            -360.0,
            360.0,
            false,
            false,
        )?;
        check_f("current_speed", self.current_speed, 0.0, 10.0, false, false)?;
        check_f("wave_period", self.wave_period, 0.0, 1e12, false, false)?;
        if self.wave_period > 0.0 && self.wave_period < 2.0 {
            return Err(range(
                "wave_period",
                self.wave_period,
                "0 (no wave) or at least 2 steps",
            ));
        }
        check_f(
            "wave_amplitude",
            self.wave_amplitude,
            0.0,
            10.0,
            false,
            false,
        )?;
        if let Some(a) = self.wave_angle {
            check_f("wave_angle", a, -360.0, 360.0, false, false)?;
            if self.mode == Mode::TwoD {
                return Err(range(
                    "wave_angle",
                    a,
                    "no wave angle in 2-D mode (the section runs along the current, and so do its waves)",
                ));
            }
        }
        check_f(
            "stoss_angle",
            self.stoss_angle,
            0.0,
            self.avalanche_angle,
            false,
            false,
        )?;
        check_f("creep_angle", self.creep_angle, 0.0, 90.0, false, true)?;
        check_f("friction", self.friction, 0.0, 100.0, true, false)?;
        check_f("hop_length", self.hop_length, 0.0, 1e4, true, false)?;
        check_f("hop_grains", self.hop_grains, 0.0, 1e5, false, false)?;
        check_f("bin_travels", self.bin_travels, 0.0, 100.0, false, false)?;
        if self.orbit_reference != 0.0 {
            check_f(
                "orbit_reference",
                self.orbit_reference,
                1e-3,
                100.0,
                false,
                false,
            )?;
        }
        if self.bin_travels > 0.0 && self.hop_grains <= 0.0 {
            return Err(range(
                "bin_travels",
                shown(self.bin_travels),
                "0 when hop_grains is 0 (the bin in flat-bed travels needs a travel in metres, hop_grains > 0)",
            ));
        }
        check_f(
            "crest_suspension",
            self.crest_suspension,
            0.0,
            1.0,
            false,
            false,
        )?;
        check_f(
            "crest_suspension_grains",
            self.crest_suspension_grains,
            0.0,
            1e5,
            false,
            false,
        )?;
        if self.crest_suspension_grains > 0.0 && self.crest_suspension > 0.0 {
            return Err(range(
                "crest_suspension_grains",
                shown(self.crest_suspension_grains),
                "0 when crest_suspension is set (crest suspension's length in metres or in grain diameters, not both)",
            ));
        }
        check_f(
            "crest_suspension_hops",
            self.crest_suspension_hops,
            0.0,
            1e3,
            false,
            false,
        )?;
        if self.crest_suspension_hops > 0.0
            && (self.crest_suspension > 0.0 || self.crest_suspension_grains > 0.0)
        {
            return Err(range(
                "crest_suspension_hops",
                shown(self.crest_suspension_hops),
                "0 when crest_suspension or crest_suspension_grains is set (crest suspension's length in metres, grain diameters or flat-bed travels: one of them)",
            ));
        }
        check_f(
            "suspension_exponent",
            self.suspension_exponent,
            1.0,
            64.0,
            false,
            false,
        )?;
        check_f("stress_lead", self.stress_lead, 0.0, 100.0, false, false)?;
        check_f(
            "separation_angle",
            self.separation_angle,
            0.0,
            self.avalanche_angle,
            false,
            false,
        )?;
        if self.separation_angle > 0.0 && self.lattice_slope_deg() <= self.avalanche_angle {
            // Along an axis the least drop is ceil(tan(angle) bin / gd) automata: 1 shelters
            // as without the rule (a column at least as high downstream is itself a nearer
            // obstruction), and a drop steeper than the avalanche angle never stands.
            let per_automaton = self.layer_thickness / self.bin_size;
            let drop = (self.separation_angle.to_radians().tan() / per_automaton - 1e-9).ceil();
            let most = (self.avalanche_angle.to_radians().tan() / per_automaton + 1e-9).floor();
            if most < 2.0 {
                // no angle can work: the steepest drop that stands is one automaton
                return Err(range(
                    "separation_angle",
                    shown(self.separation_angle),
                    &format!(
                        "0 (off) here: flow separation needs a drop of 2 automata or more over a bin that the avalanche angle lets stand, and here tan(avalanche_angle) x bin_size / layer_thickness = {:.4} automata (avalanche_angle = {} deg, bin_size = {} m, layer_thickness = {} m); a thinner layer_thickness, a larger bin_size or a steeper avalanche_angle gives it room",
                        self.avalanche_angle.to_radians().tan() / per_automaton,
                        shown(self.avalanche_angle),
                        shown(self.bin_size),
                        shown(self.layer_thickness)
                    ),
                ));
            }
            if drop < 2.0 || drop > most {
                let deg = |automata: f64| (automata * per_automaton).atan().to_degrees();
                return Err(range(
                    "separation_angle",
                    shown(self.separation_angle),
                    &format!(
                        "0 (off) or an angle whose drop over a bin, ceil(tan(angle) x bin_size / layer_thickness) automata, is 2 to {most} (1 shelters as without the rule; more than {most} is steeper than the avalanche angle and never stands): here above {:.3} and at most {:.3} deg",
                        deg(1.0),
                        deg(most)
                    ),
                ));
            }
        }
        if self.separation_angle > 0.0 && self.abstraction == Abstraction::Shadow {
            return Err(range(
                "separation_angle",
                shown(self.separation_angle),
                "0 with abstraction = \"shadow\" (flow separation is a rule of the water slices)",
            ));
        }
        check_f(
            "drag_coefficient",
            self.drag_coefficient,
            0.0,
            1.0,
            true,
            false,
        )?;
        check_f(
            "wave_friction_factor",
            self.wave_friction_factor,
            0.0,
            1.0,
            false,
            false,
        )?;
        check_f("wave_vortex", self.wave_vortex, 0.0, 1e4, false, false)?;
        check_f(
            "vortex_strength",
            self.vortex_strength,
            0.0,
            1.0,
            false,
            false,
        )?;
        if !(1..=4096).contains(&self.slice_layers) {
            return Err(range(
                "slice_layers",
                self.slice_layers,
                "an integer in [1, 4096]",
            ));
        }
        for (name, v) in [
            ("shadow_length", self.shadow_length),
            ("drag_delay", self.drag_delay),
        ] {
            if v > 64 {
                return Err(range(name, v, "an integer in [0, 64]"));
            }
        }
        check_f(
            "compaction_rate",
            self.compaction_rate,
            0.0,
            1.0,
            false,
            false,
        )?;
        if self.compaction_depth > 64 {
            return Err(range(
                "compaction_depth",
                self.compaction_depth,
                "an integer in [0, 64]",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn out_of_range_numbers_are_shown_readably() {
        assert_eq!(shown(1e300), "1e300");
        assert_eq!(shown(2.5e-9), "2.5e-9");
        assert_eq!(shown(0.5), "0.5");
        assert_eq!(shown(-3.0), "-3");
        let e = RippleParams {
            current_speed: 1e300,
            ..RippleParams::default()
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("current_speed = 1e300 is out of range"),
            "{e}"
        );
    }

    #[test]
    fn opt_in_travel_and_vortex_keys_are_checked() {
        let bad = |f: fn(&mut RippleParams)| {
            let mut p = RippleParams::default();
            f(&mut p);
            p.validate().unwrap_err().to_string()
        };
        for (e, key) in [
            (bad(|p| p.hop_grains = -1.0), "hop_grains = -1"),
            (bad(|p| p.bin_travels = -1.0), "bin_travels = -1"),
            (bad(|p| p.bin_travels = 101.0), "bin_travels = 101"),
            // a travel in metres is needed
            (bad(|p| p.bin_travels = 0.75), "bin_travels = 0.75"),
            (bad(|p| p.hop_grains = f64::NAN), "hop_grains = NaN"),
            (
                bad(|p| p.crest_suspension = -0.01),
                "crest_suspension = -0.01",
            ),
            (bad(|p| p.crest_suspension = 2.0), "crest_suspension = 2"),
            (
                bad(|p| p.crest_suspension = f64::INFINITY),
                "crest_suspension = inf",
            ),
            (bad(|p| p.wave_vortex = -0.1), "wave_vortex = -0.1"),
            (bad(|p| p.vortex_strength = 1.5), "vortex_strength = 1.5"),
            (
                bad(|p| p.crest_suspension_grains = -1.0),
                "crest_suspension_grains = -1",
            ),
            (
                bad(|p| {
                    p.crest_suspension_grains = 50.0;
                    p.crest_suspension = 0.02;
                }),
                "crest_suspension_grains = 50",
            ),
            (
                bad(|p| p.crest_suspension_hops = -2.0),
                "crest_suspension_hops = -2",
            ),
            (
                bad(|p| p.crest_suspension_hops = 2000.0),
                "crest_suspension_hops = 2000",
            ),
            (
                bad(|p| {
                    p.crest_suspension_hops = 5.0;
                    p.crest_suspension_grains = 40.0;
                }),
                "crest_suspension_hops = 5",
            ),
            (
                bad(|p| {
                    p.crest_suspension_hops = 5.0;
                    p.crest_suspension = 0.01;
                }),
                "crest_suspension_hops = 5",
            ),
            (
                bad(|p| p.suspension_exponent = 0.5),
                "suspension_exponent = 0.5",
            ),
            (
                bad(|p| p.suspension_exponent = f64::NAN),
                "suspension_exponent = NaN",
            ),
            (bad(|p| p.stress_lead = -1.0), "stress_lead = -1"),
            (bad(|p| p.stress_lead = f64::NAN), "stress_lead = NaN"),
            (bad(|p| p.stress_lead = 200.0), "stress_lead = 200"),
            (bad(|p| p.separation_angle = -5.0), "separation_angle = -5"),
            (bad(|p| p.separation_angle = 40.0), "separation_angle = 40"),
            // a drop of 1 automaton, which shelters as without the rule
            (bad(|p| p.separation_angle = 3.0), "separation_angle = 3"),
            // a drop of 7 automata, steeper than the avalanche angle (6.25 automata)
            (
                bad(|p| p.separation_angle = 31.5),
                "separation_angle = 31.5",
            ),
            (
                bad(|p| {
                    p.separation_angle = 15.0;
                    p.abstraction = Abstraction::Shadow;
                }),
                "separation_angle = 15",
            ),
        ] {
            assert!(e.starts_with(key) && e.contains("out of range"), "{e}");
        }
        // no room at all for flow separation: the steepest standing drop is one automaton
        let e = bad(|p| {
            p.separation_angle = 15.0;
            p.bin_size = 0.001;
            p.layer_thickness = 0.00025;
            p.avalanche_angle = 20.0;
        });
        assert!(
            e.starts_with("separation_angle = 15")
                && e.contains("0 (off) here")
                && e.contains("1.4559 automata"),
            "{e}"
        );
        let mut ok = RippleParams {
            hop_grains: 37.5,
            hop_exponential: true,
            ..RippleParams::default()
        };
        assert!(ok.validate().is_ok());
        // the travel per unit stage: N d, or hop_length bins
        assert!((ok.hop_metres(2e-4) - 37.5 * 2e-4).abs() < 1e-15);
        ok.hop_grains = 0.0;
        assert_eq!(ok.hop_metres(2e-4), 1.5 * ok.bin_size);
        // crest suspension's length: in metres, or in median grain diameters (d50 in mm)
        ok.crest_suspension = 0.02;
        assert_eq!(ok.crest_suspension_m(), 0.02);
        ok.crest_suspension = 0.0;
        ok.crest_suspension_grains = 50.0;
        assert!(ok.validate().is_ok());
        assert!((ok.crest_suspension_m() - 50.0 * 0.2e-3).abs() < 1e-15);
        assert!(ok.crest_suspension_on());
        // or in flat-bed travels: on, with no fixed length
        ok.crest_suspension_grains = 0.0;
        assert!(!ok.crest_suspension_on());
        ok.crest_suspension_hops = 5.0;
        assert!(ok.validate().is_ok());
        assert!(ok.crest_suspension_on() && ok.crest_suspension_m() == 0.0);
    }

    #[test]
    fn combined_flow_soulsby_eq_69_70() {
        use std::f64::consts::PI;
        let (rho, cd, fw) = (1027.0, 0.0025, 0.0087);
        let p = RippleParams {
            current_speed: 0.6,
            wave_amplitude: 0.3,
            wave_period: 300.0,
            wave_friction_factor: fw,
            drag_coefficient: cd,
            ..RippleParams::default()
        };
        // the stresses in pascals, written out
        let tau_c = rho * cd * 0.6 * 0.6;
        let tau_w = rho * 0.5 * fw * 0.3 * 0.3;
        let tau_m = tau_c * (1.0 + 1.2 * (tau_w / (tau_c + tau_w)).powf(3.2));
        let stress = |(ux, uy): (f64, f64)| rho * cd * ux.hypot(uy).powi(2);
        // Eq. 69: the current's stress, raised by the waves
        let m = p.mean_stress_speed();
        assert!((rho * cd * m * m - tau_m).abs() < 1e-12 * tau_m, "{m}");
        assert!(tau_m > tau_c);
        for phi_deg in [0.0_f64, 30.0, 90.0, 150.0, 180.0] {
            let (c, w) = (0.3_f64, 0.3 + phi_deg.to_radians());
            // Eq. 70: the largest stress of the cycle (at the wave's crest or trough: the
            // angle between the current and the waves' axis, 0-90 deg)
            let phi = w - c;
            let tau_max =
                ((tau_m + tau_w * phi.cos().abs()).powi(2) + (tau_w * phi.sin()).powi(2)).sqrt();
            let phases: Vec<f64> = (0..256)
                .map(|k| (2.0 * PI * (k as f64 + 0.5) / 256.0).sin())
                .collect();
            let at_crests =
                stress(p.combined_flow(c, w, 1.0)).max(stress(p.combined_flow(c, w, -1.0)));
            assert!(
                (at_crests - tau_max).abs() < 1e-12 * tau_max,
                "{phi_deg}: {at_crests} {tau_max}"
            );
            // between them the waves' stress is quadratic in their velocity: at half their
            // velocity a quarter of it, along the vector sum
            let (ux, uy) = p.combined_flow(c, w, 0.5);
            let (tx, ty) = (
                tau_m * c.cos() + 0.25 * tau_w * w.cos(),
                tau_m * c.sin() + 0.25 * tau_w * w.sin(),
            );
            let t = tx.hypot(ty);
            assert!((stress((ux, uy)) - t).abs() < 1e-12 * t, "{phi_deg}");
            assert!((uy.atan2(ux) - ty.atan2(tx)).abs() < 1e-12, "{phi_deg}");
            // the cycle's mean stress vector is Eq. 69's, along the current
            let (mut sx, mut sy) = (0.0, 0.0);
            for &s in &phases {
                let (ux, uy) = p.combined_flow(c, w, s);
                let u = ux.hypot(uy);
                sx += rho * cd * u * ux;
                sy += rho * cd * u * uy;
            }
            let n = phases.len() as f64;
            assert!(
                (sx / n - tau_m * c.cos()).abs() < 1e-9,
                "{phi_deg}: {}",
                sx / n
            );
            assert!(
                (sy / n - tau_m * c.sin()).abs() < 1e-9,
                "{phi_deg}: {}",
                sy / n
            );
        }
        // aligned: softer on the bed than adding friction velocities would be
        let aligned = stress(p.combined_flow(0.0, 0.0, 1.0));
        let added = rho * cd * (0.6 + p.wave_stress_amplitude()).powi(2);
        assert!(aligned < 0.8 * added, "{aligned} {added}");
        // a current alone and waves alone, exactly as written
        let current = RippleParams {
            wave_amplitude: 0.0,
            ..p.clone()
        };
        assert_eq!(
            current.combined_flow(0.3, 1.0, 0.7),
            (0.6 * 0.3_f64.cos(), 0.6 * 0.3_f64.sin())
        );
        assert_eq!(current.mean_stress_speed(), 0.6);
        let waves = RippleParams {
            current_speed: 0.0,
            ..p.clone()
        };
        let a = waves.wave_stress_amplitude();
        assert_eq!(
            waves.combined_flow(0.3, 1.0, -0.7),
            (a * -0.7 * 1.0_f64.cos(), a * -0.7 * 1.0_f64.sin())
        );
        assert_eq!(waves.mean_stress_speed(), 0.0);
    }

    #[test]
    fn wave_stress_amplitude_gives_the_waves_own_stress() {
        // rho_w C_D (U'_w)^2 = rho_w (f_w / 2) U_w^2
        let p = RippleParams {
            wave_amplitude: 0.4,
            wave_period: 100.0,
            wave_friction_factor: 0.013,
            ..RippleParams::default()
        };
        let u = p.wave_stress_amplitude();
        assert!(
            (p.drag_coefficient * u * u - 0.5 * 0.013 * 0.16).abs() < 1e-15,
            "{u}"
        );
        // no wave friction factor: the current's law
        let q = RippleParams {
            wave_friction_factor: 0.0,
            ..p.clone()
        };
        assert_eq!(q.wave_stress_amplitude(), 0.4);
        // left out of files when 0, refused out of [0, 1]
        assert!(!q.to_toml().contains("wave_friction_factor"));
        assert!(p.to_toml().contains("wave_friction_factor = 0.013"));
        let e = RippleParams {
            wave_friction_factor: 1.5,
            ..p
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("wave_friction_factor = 1.5 is out of range"),
            "{e}"
        );
    }

    #[test]
    fn frame_angle_follows_the_dominant_flow() {
        let p = RippleParams {
            current_angle: 30.0,
            wave_angle: Some(80.0),
            frame: Frame::Grid,
            ..RippleParams::default()
        };
        // grid frame: the lattice's x axis east, the flow across it
        assert_eq!(p.frame_angle(), 0.0);
        assert_eq!(p.lattice_current_angle(), 30.0);
        // flow frame: along the current, the waves at their angle to it
        let f = RippleParams {
            frame: Frame::Flow,
            ..p.clone()
        };
        assert_eq!(f.frame_angle(), 30.0);
        assert_eq!(f.lattice_current_angle(), 0.0);
        assert_eq!(f.lattice_wave_angle(), Some(50.0));
        // no current: along the waves
        let w = RippleParams {
            current_speed: 0.0,
            wave_amplitude: 0.4,
            wave_period: 100.0,
            ..f.clone()
        };
        assert_eq!(w.frame_angle(), 80.0);
        assert_eq!(w.lattice_wave_angle(), Some(0.0));
        assert_eq!(w.lattice_flow_angle(), 0.0);
        // current and waves: the one whose bed stress is larger; the waves' own friction
        // counts (0.25 m/s of orbital velocity with f_w = 0.0083 rub like a current of
        // 0.32 m/s)
        let both = RippleParams {
            current_speed: 0.3,
            wave_amplitude: 0.25,
            wave_period: 100.0,
            ..f.clone()
        };
        assert!(!both.waves_dominate());
        assert_eq!(both.frame_angle(), 30.0);
        assert_eq!(both.lattice_flow_angle(), 0.0);
        let rubbing = RippleParams {
            wave_friction_factor: 0.0083,
            ..both.clone()
        };
        assert!(rubbing.waves_dominate());
        assert_eq!(rubbing.flow_angle(), 80.0);
        // the lattice stays along the current; the dominant flow crosses it
        assert_eq!(rubbing.frame_angle(), 30.0);
        assert_eq!(rubbing.lattice_flow_angle(), 50.0);
        // the faces along the waves, in the current's sense: as they are for waves within
        // 90 deg of the current, turned for waves against it
        assert_eq!(rubbing.lattice_face_angle(), 50.0);
        let against = RippleParams {
            wave_angle: Some(210.0),
            ..rubbing.clone()
        };
        assert!(against.waves_dominate());
        assert_eq!(against.lattice_flow_angle(), 180.0);
        assert_eq!(against.lattice_face_angle(), 360.0);
        let still = RippleParams {
            current_speed: 0.0,
            ..against.clone()
        };
        assert_eq!(still.lattice_face_angle(), still.lattice_flow_angle());
        assert_eq!(both.lattice_face_angle(), both.lattice_flow_angle());
        let grid = RippleParams {
            frame: Frame::Grid,
            ..rubbing
        };
        assert_eq!(grid.lattice_flow_angle(), 80.0);
        // the default is the flow frame
        assert_eq!(RippleParams::default().frame, Frame::Flow);
        // 2-D: the section runs along the current
        let e = RippleParams {
            mode: Mode::TwoD,
            ny: 1,
            current_angle: 180.0,
            wave_angle: None,
            ..f
        };
        assert!(e.validate().is_ok());
        assert_eq!(e.frame_angle(), 0.0);
        assert_eq!(e.lattice_current_angle(), 180.0);
        assert_eq!(e.lattice_flow_angle(), 180.0);
        // an oblique section in the flow frame: its x axis along the current, or against it
        // where the current points west of north-south
        for (a, frame, flow) in [
            (30.0, 30.0, 0.0),
            (90.0, 90.0, 0.0),
            (150.0, 330.0, 180.0),
            (-120.0, 60.0, 180.0),
            // one direction typed two ways makes one section
            (270.0, 90.0, 180.0),
            (-90.0, 90.0, 180.0),
            (-270.0, 90.0, 0.0),
            (360.0, 0.0, 0.0),
            (-180.0, 0.0, 180.0),
        ] {
            let o = RippleParams {
                current_angle: a,
                ..e.clone()
            };
            assert!(o.validate().is_ok(), "{a}");
            assert_eq!(o.x_axis_direction_deg(), frame, "{a}");
            assert_eq!(o.lattice_flow_angle(), flow, "{a}");
            assert!(
                (o.lattice_current_angle() - flow).rem_euclid(360.0) < 1e-9,
                "{a}"
            );
        }
        // the grid frame takes only sections along its x axis
        let g = RippleParams {
            current_angle: 30.0,
            frame: Frame::Grid,
            ..e.clone()
        };
        let err = g.validate().unwrap_err().to_string();
        assert!(
            err.contains("current_angle = 30") && err.contains("frame = grid"),
            "{err}"
        );
    }

    /// A scenario's values are read as the command line reads its options: whole numbers
    /// written as floats are counts, and a value of the wrong kind, or a count past every
    /// range, is named by its key with the value as written and what the key takes.
    #[test]
    fn scenario_values_are_read_as_the_options_read_them() {
        let read = |text: &str| RippleParams::from_table(text.parse().unwrap());
        let p = read("layers = 2.0\nsteps = 2e4\nseed = 7.0\nd50 = 1").unwrap();
        assert_eq!((p.layers, p.steps, p.seed), (2, 20_000, 7));
        assert_eq!(p.d50, 1.0);
        for (text, needles) in [
            ("layers = 2.5", &["layers = 2.5", "a whole number >= 0"][..]),
            ("layers = -3", &["layers = -3", "a whole number >= 0"]),
            ("d50 = \"x\"", &["d50 = \"x\"", "expected a number"]),
            ("frame = 3", &["frame = 3", "`grid` or `flow`"]),
            (
                "hop_exponential = 1",
                &["hop_exponential = 1", "true or false"],
            ),
        ] {
            let e = read(text).unwrap_err().to_string();
            for n in needles {
                assert!(e.contains(n), "{text}: {e}");
            }
            assert!(!e.contains("usize") && !e.contains("f64"), "{e}");
        }
        // past every count: the key's own range, the value as written
        let past = RippleParams {
            steps: (1 << 40) + 1,
            ..RippleParams::default()
        };
        let Err(RippleError::Range { expected, .. }) = past.validate() else {
            panic!("steps past 2^40 is refused");
        };
        for v in ["1e30", "inf", "1e19"] {
            let e = read(&format!("steps = {v}")).unwrap_err();
            assert_eq!(
                e,
                RippleError::Range {
                    parameter: "steps",
                    value: v.into(),
                    expected: expected.clone()
                }
            );
        }
    }

    /// The range a refused `layer_thickness` states is the one the check applies: its upper end
    /// (rounded to four figures) is accepted a little below and refused a little above, for
    /// other bins and avalanche angles too.
    #[test]
    fn layer_thickness_states_the_range_it_applies() {
        for (bin_size, avalanche_angle) in [(0.005, 32.0), (0.002, 20.0), (0.01, 45.0)] {
            let at = |layer_thickness: f64| RippleParams {
                bin_size,
                avalanche_angle,
                layer_thickness,
                ..RippleParams::default()
            };
            for bad in [f64::NAN, 0.0, -1.0, f64::INFINITY] {
                let e = at(bad).validate().unwrap_err().to_string();
                let stated = e
                    .split("a number in (0, ")
                    .nth(1)
                    .and_then(|r| r.split(']').next())
                    .unwrap_or_else(|| panic!("no range in: {e}"));
                let max: f64 = stated.parse().unwrap();
                assert!(at(max * 0.999).validate().is_ok(), "{e}");
                assert!(at(max * 1.001).validate().is_err(), "{e}");
                assert!(e.contains("layer_thickness"), "{e}");
            }
        }
    }

    #[test]
    fn a_lattice_steeper_than_the_avalanche_angle_is_refused() {
        // one automaton of 0.5 mm over 0.5 mm: 45 deg against 32
        let p = RippleParams {
            bin_size: 0.0005,
            ..RippleParams::default()
        };
        assert!((p.lattice_slope_deg() - 45.0).abs() < 1e-12);
        let e = p.validate().unwrap_err().to_string();
        for name in ["layer_thickness", "bin_size", "avalanche_angle", "45.0 deg"] {
            assert!(e.contains(name), "{name}: {e}");
        }
        // 26.6 deg against 20
        let q = RippleParams {
            bin_size: 0.001,
            avalanche_angle: 20.0,
            ..RippleParams::default()
        };
        assert!(
            q.validate()
                .unwrap_err()
                .to_string()
                .contains("0.0003640 m")
        );
        // the defaults: 5.7 deg
        assert!(RippleParams::default().validate().is_ok());
    }

    #[test]
    fn the_x_axis_is_recorded_in_0_to_360() {
        for (a, want) in [(360.0, 0.0), (-360.0, 0.0), (-10.0, 350.0), (30.0, 30.0)] {
            let p = RippleParams {
                current_angle: a,
                ..RippleParams::default()
            };
            let x = p.x_axis_direction_deg();
            assert_eq!(x, want, "{a}");
            assert!(x.is_sign_positive());
        }
    }

    #[test]
    fn renamed_keys_and_until() {
        let e = RippleParams::from_toml("recovery_length = 2")
            .unwrap_err()
            .to_string();
        assert!(e.contains("renamed `drag_delay`"), "{e}");
        let p = RippleParams::from_toml("until = \"equilibrium\"").unwrap();
        assert_eq!(p.until.as_deref(), Some("equilibrium"));
        assert!(p.to_toml().contains("until = \"equilibrium\""));
        assert!(!RippleParams::default().to_toml().contains("until"));
        let e = RippleParams::from_toml("until = \"never\"")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("until = never is out of range"), "{e}");
    }
}
