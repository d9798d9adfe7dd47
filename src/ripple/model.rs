//! [`Ripple`]: the state of a run (sand volume on the engine's lattice, grain classes,
//! compaction rule, water volume, random stream, clock) and its stepping loop.
//!
//! One step draws `activity x automata` activations (at least 1): columns are picked uniformly
//! at random by Monte Carlo and only exposed grains are triggered (paper Sect. 2); picks that
//! find a bare column, a grain in the current shadow, a grain held by the stoss stability rule
//! or a grain below the threshold of motion are rejected and not counted. The number of picks
//! per step is capped at `50 x target + 1000`, so a bed with (almost) nothing exposed cannot loop
//! forever. The rules themselves are in [`super::rules`]. A step costs
//! O(picks x (hops + water reach + avalanche cascade)), independent of the volume's size.

use rand::RngExt;

use super::RippleError;
use super::compaction::Compaction;
use super::grain::GrainClasses;
use super::params::{Frame, Mode, RippleParams, shown};
use super::volume::{Automaton, SandVolume};
use super::water::{Flow, WaterVolume};
use crate::engine::lattice::{Boundary, Lattice, Neighbourhood};
use crate::engine::rng::{self, Stream};

/// Counters of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RippleStats {
    /// Steps done.
    pub steps: u64,
    /// Grains triggered (exposed and picked).
    pub activations: u64,
    /// Picks (accepted or rejected).
    pub picks: u64,
    /// Grains that rolled/hopped at least one bin.
    pub rolls: u64,
    /// Bins travelled by rolling grains.
    pub hops: u64,
    /// Automata moved by avalanches.
    pub avalanches: u64,
    /// Creep moves.
    pub creeps: u64,
    /// Grains that the flow moved from a crest and that settled elsewhere, suspended
    /// (`crest_suspension`); not counted in `rolls`.
    pub suspended: u64,
}

/// A sand-ripple run.
#[derive(Clone, Debug)]
pub struct Ripple {
    pub(crate) p: RippleParams,
    pub(crate) lattice: Lattice,
    pub(crate) nx: usize,
    pub(crate) ny: usize,
    pub(crate) two_d: bool,
    pub(crate) vol: SandVolume,
    pub(crate) classes: GrainClasses,
    pub(crate) compaction: Compaction,
    pub(crate) water: WaterVolume,
    pub(crate) rng: Stream,
    pub(crate) t: u64,
    pub(crate) automata: u64,
    pub(crate) initial_counts: Vec<u64>,
    pub(crate) stats: RippleStats,
    /// Avalanche threshold in automata for an axial and a diagonal neighbour (tan alpha dx / gd).
    pub(crate) alpha_layers: [f64; 2],
    /// Stoss stability threshold in automata, axial and diagonal (tan beta dx / gd).
    pub(crate) beta_layers: [f64; 2],
    /// `floor` and `ceil` of each of [`Self::beta_layers`] (the stoss rules compare whole
    /// automata with them on every grain).
    pub(crate) beta_whole: [(f64, f64); 2],
    /// Whether the stoss cap acts: the current dominates ([`RippleParams::waves_dominate`],
    /// computed once rather than per roll).
    pub(crate) stoss_capped: bool,
    /// Whether the face hold acts in place of Eq. (3)'s foot rule: `stoss_face_hold` where
    /// the stoss cap acts ([`Ripple::held_on_the_face`]).
    pub(crate) face_hold: bool,
    /// Creep threshold gamma Delta s in automata (tan gamma dx / gd).
    pub(crate) gamma_layers: f64,
    pub(crate) stack: Vec<u32>,
    /// The columns a rolling grain passed, for the stoss cap ([`Ripple::roll`]).
    pub(crate) path: Vec<u32>,
    /// An upper bound of the column heights (raised by every deposit, never lowered).
    pub(crate) hmax_bound: usize,
    /// The smallest height difference (automata) an avalanche can move: max(2, the axial
    /// threshold's next integer).
    pub(crate) min_drop: i64,
    /// Crest suspension's length in flat-bed travels (`crest_suspension_hops`) for the last
    /// free-stream speed asked about: (speed m/s, `L` m), so that it is computed once per
    /// flow, not per moved grain (NaN speed: not yet).
    pub(crate) suspension_length: (f64, f64),
}

impl Ripple {
    /// A run from a rough flat bed: column heights `layers` + uniform noise in
    /// `-roughness..=roughness`, grain classes drawn from the log-normal-in-phi distribution,
    /// initial porosity "average" (Table 5); then relaxed so that no slope exceeds alpha. With
    /// `bin_travels` the run is on the parameters of [`RippleParams::with_travel_bin`].
    pub fn new(p: &RippleParams) -> Result<Self, RippleError> {
        p.validate()?;
        // the bin in flat-bed travels, where `bin_travels` asks for it
        let p = &p.with_orbit_scale().with_travel_bin();
        p.validate()?;
        let mut rng = rng::stream(p.seed);
        let r = p.roughness as i64;
        let heights: Vec<usize> = (0..p.nx * p.rows())
            .map(|_| {
                let noise = if r > 0 { rng.random_range(-r..=r) } else { 0 };
                (p.layers as i64 + noise).max(0) as usize
            })
            .collect();
        Self::build(p, &heights, rng)
    }

    /// A run from given column heights (row-major, `nx x rows` of them, each at most the
    /// column capacity); grain classes drawn as in [`Ripple::new`]. Zero heights are bare spots
    /// (the substrate, which never erodes). With `bin_travels` the parameters must be on their
    /// bin ([`RippleParams::with_travel_bin`]).
    pub fn from_heights(p: &RippleParams, heights: &[usize]) -> Result<Self, RippleError> {
        Self::from_heights_seeded(p, heights, p.seed)
    }

    /// [`Ripple::from_heights`] with the random stream of `stream_seed` instead of `p.seed`
    /// (any 64-bit value: a stream derived from the run's seed, which is not itself a
    /// parameter and is not validated as one).
    pub fn from_heights_seeded(
        p: &RippleParams,
        heights: &[usize],
        stream_seed: u64,
    ) -> Result<Self, RippleError> {
        p.validate()?;
        if let Some(b) = p.travel_bin().filter(|&b| b != p.bin_size) {
            return Err(RippleError::Range {
                parameter: "bin_size",
                value: super::params::shown(p.bin_size),
                expected: format!(
                    "the bin of bin_travels = {}, {} m, where column heights are given (they are counts of automata on that bin: RippleParams::with_travel_bin gives its parameters)",
                    super::params::shown(p.bin_travels),
                    super::params::shown(b)
                ),
            });
        }
        let rng = rng::stream(stream_seed);
        Self::build(p, heights, rng)
    }

    fn build(p: &RippleParams, heights: &[usize], mut rng: Stream) -> Result<Self, RippleError> {
        let two_d = p.mode == Mode::TwoD;
        let (nx, ny) = (p.nx, p.rows());
        if heights.len() != nx * ny {
            return Err(RippleError::Range {
                parameter: "heights",
                value: heights.len().to_string(),
                expected: format!("nx x rows = {} values", nx * ny),
            });
        }
        let boundary = if two_d {
            Boundary::CHANNEL
        } else {
            Boundary::TORUS
        };
        let lattice = Lattice::new(Neighbourhood::Square8, nx, ny, boundary)
            .map_err(|e| RippleError::Lattice(e.to_string()))?;
        let cap = p.capacity();
        if let Some(&h) = heights.iter().find(|&&h| h > cap) {
            return Err(RippleError::Range {
                parameter: "heights",
                value: h.to_string(),
                expected: format!("at most the column capacity {cap}"),
            });
        }
        let classes = GrainClasses::new(p.d50, p.sorting);
        let compaction = Compaction::new(p.sorting, p.compaction_rate, p.compaction_depth);
        let mut vol = SandVolume::new(nx * ny, cap);
        for (c, &h) in heights.iter().enumerate() {
            for _ in 0..h {
                let a = Automaton::new(classes.sample(&mut rng), compaction.initial_code());
                vol.push(c, a);
            }
        }
        let hmax_bound = vol.heights().iter().copied().max().unwrap_or(0) as usize;
        let t = |deg: f64| deg.to_radians().tan() * p.bin_size / p.layer_thickness;
        let sq2 = std::f64::consts::SQRT_2;
        let beta_layers = [t(p.stoss_angle), t(p.stoss_angle) * sq2];
        let mut r = Ripple {
            lattice,
            nx,
            ny,
            two_d,
            automata: vol.automata(),
            initial_counts: Vec::new(),
            vol,
            water: WaterVolume::new(p),
            compaction,
            rng,
            t: 0,
            stats: RippleStats::default(),
            alpha_layers: [t(p.avalanche_angle), t(p.avalanche_angle) * sq2],
            beta_layers,
            beta_whole: beta_layers.map(|b| (b.floor(), b.ceil())),
            stoss_capped: !p.waves_dominate(),
            face_hold: p.stoss_face_hold && !p.waves_dominate(),
            gamma_layers: t(p.creep_angle),
            stack: Vec::new(),
            path: Vec::new(),
            hmax_bound,
            min_drop: ((t(p.avalanche_angle).floor() as i64) + 1).clamp(2, i64::MAX / 4),
            suspension_length: (f64::NAN, 0.0),
            classes,
            p: p.clone(),
        };
        let all: Vec<u32> = (0..(nx * ny) as u32).collect();
        r.relax(&[], &all);
        r.initial_counts = r.vol.class_counts(r.classes.len());
        r.stats = RippleStats::default();
        Ok(r)
    }

    /// Target activations per step: `activity x automata`, at least 1.
    pub fn activations_per_step(&self) -> u64 {
        ((self.p.activity * self.automata as f64).round() as u64).max(1)
    }

    /// Advances one step. While the free stream is below the threshold of motion of every
    /// grain class (zero current; the slack phases of a wave) no grain can move and no column
    /// is picked.
    pub fn step(&mut self) {
        let flow = Flow::at(&self.p, self.t, self.two_d);
        let target = self.activations_per_step();
        if self.classes.any_moves(flow.speed, self.p.drag_coefficient) {
            let max_picks = 50 * target + 1000;
            let cols = self.vol.columns();
            let (mut got, mut picks) = (0, 0);
            while got < target && picks < max_picks {
                picks += 1;
                let c = self.rng.random_range(0..cols);
                if self.trigger(c, &flow) {
                    got += 1;
                }
            }
            self.stats.activations += got;
            self.stats.picks += picks;
        }
        self.t += 1;
        self.stats.steps += 1;
    }

    /// Changes the steady current from the next step on (an interactive run): `speed` in m/s,
    /// 0..=10; `angle` in degrees counter-clockwise from east, finite. In the flow frame the
    /// lattice (or a 2-D section) was turned with the starting flow, so its direction cannot
    /// change, except that a section's current may reverse along it (start in the grid frame
    /// to turn the current during a 3-D run; a section in the grid frame runs along x, 0 or
    /// 180 deg). With `bin_travels` the bin stays the one the run was built on (its parameters
    /// then say `bin_travels = 0`). Errors name the parameter and leave the run unchanged.
    pub fn set_current(&mut self, speed: f64, angle: f64) -> Result<(), RippleError> {
        let mut p = self.p.clone();
        p.current_speed = speed;
        p.current_angle = angle;
        // the lattice is built: its bin no longer follows the travel (`bin_travels`)
        p.bin_travels = 0.0;
        p.validate()?;
        if p.frame == Frame::Flow
            && (p.frame_angle() - self.p.frame_angle()).rem_euclid(360.0) != 0.0
        {
            return Err(RippleError::Range {
                parameter: "current_angle",
                value: shown(angle),
                expected: format!(
                    "a current that leaves the lattice as it is: the flow frame's lattice was turned with the starting flow, its x axis at {} deg from east, and this current would turn it to {} deg (start with frame = grid to turn the current during a run)",
                    shown(self.p.frame_angle()),
                    shown(p.frame_angle())
                ),
            });
        }
        self.stoss_capped = !p.waves_dominate();
        self.face_hold = p.stoss_face_hold && self.stoss_capped;
        self.p = p;
        Ok(())
    }

    /// Advances `n` steps, calling `progress(done)` after each.
    pub fn run(&mut self, n: u64, mut progress: impl FnMut(u64)) {
        for i in 0..n {
            self.step();
            progress(i + 1);
        }
    }

    /// The parameters.
    pub fn params(&self) -> &RippleParams {
        &self.p
    }
    /// The lattice of columns.
    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }
    /// Columns along x and rows along y (1 in 2-D).
    pub fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }
    /// The sand volume.
    pub fn volume(&self) -> &SandVolume {
        &self.vol
    }
    /// The grain classes.
    pub fn classes(&self) -> &GrainClasses {
        &self.classes
    }
    /// The compaction rule.
    pub fn compaction(&self) -> &Compaction {
        &self.compaction
    }
    /// The water volume's rules.
    pub fn water(&self) -> &WaterVolume {
        &self.water
    }
    /// Steps done.
    pub fn time(&self) -> u64 {
        self.t
    }
    /// Counters.
    pub fn stats(&self) -> RippleStats {
        self.stats
    }
    /// Automata at the start (constant: they are only moved).
    pub fn automata(&self) -> u64 {
        self.automata
    }
    /// Automata of each class at the start.
    pub fn initial_class_counts(&self) -> &[u64] {
        &self.initial_counts
    }
    /// Automata now in the volume minus at the start (0: conservation).
    pub fn mass_change(&self) -> i64 {
        self.vol.automata() as i64 - self.automata as i64
    }
    /// Mass of each class now (kg of grains, `count x grain mass`), for conservation checks.
    pub fn class_masses(&self) -> Vec<f64> {
        self.vol
            .class_counts(self.classes.len())
            .iter()
            .zip(&self.classes.mass)
            .map(|(&n, &m)| n as f64 * m)
            .collect()
    }
    /// Bed elevation of every column, m, row-major.
    pub fn elevation(&self) -> Vec<f64> {
        let gd = self.p.layer_thickness;
        self.vol.heights().iter().map(|&h| h as f64 * gd).collect()
    }
    /// Share of the columns that are bare (no automaton left: the non-erodible substrate
    /// shows), in [0, 1]. A field whose troughs have reached the substrate is short of sand:
    /// its ripples can grow no deeper, and a stop in their growth there is the sand running
    /// out, not an equilibrium ([`crate::ripple::equilibrium`]).
    pub fn bare_fraction(&self) -> f64 {
        self.bare_columns() as f64 / self.vol.columns().max(1) as f64
    }

    /// Number of bare columns (see [`Ripple::bare_fraction`]).
    pub fn bare_columns(&self) -> usize {
        self.vol.heights().iter().filter(|&&v| v == 0).count()
    }
    /// The flow during step `t`.
    pub fn flow_at(&self, t: u64) -> Flow {
        Flow::at(&self.p, t, self.two_d)
    }
    /// Bytes of memory held by the volume, per automaton.
    pub fn bytes_per_automaton(&self) -> f64 {
        self.vol.memory_bytes() as f64 / self.automata.max(1) as f64
    }

    /// The first pair of neighbouring columns (`c`, `n`) whose slope exceeds alpha (Eq. 6):
    /// `h_c - h_n >= 2` automata, `(h_c - h_n) gd / dist > tan alpha`, `n` not full. `None`
    /// when the bed is relaxed.
    pub fn steep_pair(&self) -> Option<(usize, usize)> {
        for c in 0..self.vol.columns() {
            if let Some(n) = self.steepest_descent(c) {
                return Some((c, n));
            }
        }
        None
    }

    /// Calls `f` with each column next to `c`, in the lattice's order
    /// ([`Lattice::for_each_neighbour`]): in a 2-D section the columns at +x and -x, found
    /// without the lattice's boundary rules (every column of a one-row section is on its
    /// edge).
    #[inline(always)]
    pub(crate) fn for_each_next(&self, c: usize, mut f: impl FnMut(usize)) {
        if self.two_d {
            f(self.nb(c, 0));
            f(self.nb(c, 4));
        } else {
            self.lattice.for_each_neighbour(c, f);
        }
    }

    /// The neighbour of `c` that an avalanche from `c` would feed, if any (Eq. 6).
    pub(crate) fn steepest_descent(&self, c: usize) -> Option<usize> {
        let h = self.vol.height(c) as i64;
        if h < self.min_drop {
            return None;
        }
        let mut best: Option<(f64, usize)> = None;
        let mut i = 0;
        self.for_each_next(c, |n| {
            let diag = !self.two_d && i % 2 == 1;
            i += 1;
            let diff = h - self.vol.height(n) as i64;
            if diff < self.min_drop || self.vol.is_full(n) {
                return;
            }
            let thr = self.alpha_layers[diag as usize];
            if diff as f64 > thr {
                let score = diff as f64 / if diag { std::f64::consts::SQRT_2 } else { 1.0 };
                if best.is_none_or(|(s, _)| score > s) {
                    best = Some((score, n));
                }
            }
        });
        best.map(|(_, n)| n)
    }
}
