//! The sedimentological rules of the paper (Sects. 2.1-2.2), as methods of
//! [`super::Ripple`]: triggering, roll/saltation (Eqs. 1-5, 7-8), avalanche (Eq. 6) and creep
//! (Eqs. 9-10).
//!
//! **Directions.** The rules are written for a current along +x; here "forward" is the Moore
//! octant `k` nearest the flow direction, drawn per activation between the two octants around
//! the flow angle with the probabilities of [`upper_octant_probability`], so that on a flat
//! bed the mean displacement of a grain points along the flow, for any angle. Equally cheap
//! cells are equally likely: in Eq. (10) per move, in Eq. (8) per roll (a rolling grain keeps
//! to one side of the obstacles it skirts).
//! The three forward cells of Eq. (8) are octants `k-1, k, k+1`; the upstream cell `x-1` is
//! octant `k+4`; the creep sets of Eqs. (9)-(10) are `k+3, k+4, k+5` (upstream) and
//! `k-2, k+2, k` (lateral and forward, the "reduced von Neumann neighbourhood").
//! In 2-D only `k` and `k+4` exist.
//!
//! **Exposure (Eq. 3).** A grain is triggered only when the water reaches its column (a bed
//! speed above zero: [`super::water`], or with the `shadow` abstraction `h_x - h_{x-1} >= 0`), it is not held
//! by the stoss stability rule, and the flow exceeds its threshold of motion (E_x > 0,
//! [`super::grain`]). The stoss rule reads Eq. (3)'s second case as: E_x = 0 when the grain lies
//! at a concave foot (`h_x - h_{x-1} < h_{x+1} - h_x`) of a rise ahead steeper than beta
//! (`(h_{x+1} - h_x) gd / Delta x > tan beta`). (The printed `(h_x - h_{x+1}) / Delta x < beta`
//! is always true at a concave foot; we take the rise, our interpretation.)
//! Two opt-in keys change the exposure: `stress_lead` raises the bed speed of an exposed
//! column on a rise and lowers it on a drop (`Ripple::lead`), and `separation_angle` lets only
//! drops of that angle shelter the bed behind them ([`super::water`]).
//!
//! **Stoss cap.** "The angle beta defines the maximum slope of the stoss side of the ripple"
//! (Sect. 2.1): a rolling grain does not come to rest where it would make the rise from the
//! column upstream (along the flow) steeper than beta; it rests at the last column of its path
//! where it would not, the foot of the rise (it rolls back down a stoss it cannot top). Rises
//! are whole automata, so a beta between two of them is met on average (a rise of
//! `ceil(tan(beta) dx / gd)` automata is allowed with the fractional part's probability), and
//! the grain's own origin counts as it was before the grain left. With the foot's grains held
//! (above) and no grain resting on a steeper stoss, no stoss face is built steeper than beta:
//! measured stoss slopes are 4.7 / 6.0 / 7.8 deg for beta = 5 / 7 / 10 deg (18 deg without
//! the cap; test `stoss_cap_beta_sets_the_stoss_slope`). The cap is for the stoss of current
//! ripples: where the waves' bed stress exceeds the current's, each face is the stoss for
//! half a cycle and the lee for the other half, and the cap is off (our reading; capping both
//! faces at beta flattens wave ripples).
//!
//! **Face hold** (`stoss_face_hold`, opt-in; the recipe for mature current ripples sets it).
//! The stoss cap bounds where grains come to rest, not where they are lifted from, and erosion
//! steepened the recipe's stoss faces past beta. With the face hold a grain is not triggered
//! where the rise ahead of it (to the column downstream) is steeper than beta, wherever it lies
//! on the rise (`Ripple::held_on_the_face`), with the cap's rounding between whole automata:
//! a rise of `ceil(B)` automata, `B = tan(beta) dx / gd`, holds it with probability
//! `1 - frac(B)`, a steeper one always. It replaces Eq. (3)'s foot rule (a grain at a concave
//! foot of a rise of `ceil(B)` automata is held with that probability too, where the foot rule
//! holds it always), so a face steeper than beta erodes from its top (our reading of beta as
//! "the maximum slope of the stoss side"). Off where the waves dominate, as the cap is.
//!
//! **Roll/saltation.** The grain leaves its column and, bin by bin, moves to the cheapest of
//! the forward cells, spending Delta e = E_friction + E_gravity = m g' (mu Delta s + Delta h)
//! (Eq. 4), with Delta s = sqrt(Delta x^2 + Delta y^2 + (Delta h + gd)^2) (Eqs. 1 and 7; the
//! paper prints two equations numbered 1, this is the second) and Delta h the rise of the grain's top. A descent costs at least
//! a tenth of the flat friction (`0.1 mu Delta x`, so a grain never gains energy: our choice).
//! It stops before the hop that would make E exceed E_x (Eq. 3: E <= E_x), when it enters the
//! current shadow (it "settles down in the current shadow"), or after `nx + ny` hops. Energies
//! are in units of m g': the mass enters through E_x (see [`super::grain`]).
//!
//! **Avalanche (Eq. 6).** After every move, columns whose slope to a Moore neighbour exceeds
//! alpha shed their top automaton to the steepest such neighbour, repeatedly, until no slope
//! exceeds alpha. A move needs a difference of at least 2 automata (a 1-automaton step is the
//! resolution of the bed, and moving it would just swap the two heights), so the sum of squared
//! heights strictly decreases: the relaxation always ends.
//!
//! **Creep (Eqs. 9-10).** An exposed grain that cannot afford its first hop creeps, without
//! spending energy, to the lowest cell of the reduced von Neumann set when both Booleans hold:
//! `min(upstream three) <= h - gd - gamma Delta s` and `min(settle set) <= h - gd - gamma Delta s`
//! (heights in automata; gamma Delta s read as `tan(gamma) Delta x`).

use rand::RngExt;

use super::compaction::Deposit;
use super::model::Ripple;
use super::params::Abstraction;
use super::water::Flow;
use crate::engine::lattice::MOORE;

/// The ways the grain can go from a cell, as octant offsets from the forward octant, in the
/// order that breaks ties (the first of equally cheap cells wins): the forward octant, then
/// the counter-clockwise side, then the clockwise side.
const FORWARD_3D: [usize; 3] = [0, 1, 7];
/// The same, breaking ties towards the clockwise side.
const FORWARD_3D_MIRRORED: [usize; 3] = [0, 7, 1];

impl Ripple {
    /// The column in octant `k` (0 = +x, counter-clockwise, the order of the engine's
    /// [`MOORE`] offsets) of column `c`, wrapped on the torus
    /// (in 2-D only octants 0 and 4 exist).
    #[inline(always)]
    pub(crate) fn nb(&self, c: usize, k: usize) -> usize {
        let (dx, dy) = MOORE[k % 8];
        let (nx, ny) = (self.nx, self.ny);
        let (x, y) = self.xy(c);
        let x2 = match dx {
            1 if x + 1 == nx => 0,
            1 => x + 1,
            -1 if x == 0 => nx - 1,
            -1 => x - 1,
            _ => x,
        };
        let y2 = if self.two_d {
            y
        } else {
            match dy {
                1 if y + 1 == ny => 0,
                1 => y + 1,
                -1 if y == 0 => ny - 1,
                -1 => y - 1,
                _ => y,
            }
        };
        y2 * nx + x2
    }

    /// Column `c`'s `(x, y)`, `(c mod nx, c / nx)`, without a division instruction (one per
    /// neighbour looked at would weigh on every rule): a 2-D section is one row, and the
    /// lattice divides by its row length strength-reduced
    /// ([`crate::engine::lattice::Lattice::coords`]).
    #[inline(always)]
    pub(crate) fn xy(&self, c: usize) -> (usize, usize) {
        if self.ny == 1 {
            (c, 0)
        } else {
            self.lattice.coords(c)
        }
    }

    /// Horizontal distance to octant `k`, m.
    #[inline]
    fn dist(&self, k: usize) -> f64 {
        if k % 2 == 1 {
            self.p.bin_size * std::f64::consts::SQRT_2
        } else {
            self.p.bin_size
        }
    }

    /// The forward octant for one activation: stochastic rounding between the two octants
    /// around the flow angle (module docs, "Directions").
    #[inline]
    pub(crate) fn pick_octant(&mut self, flow: &Flow) -> usize {
        if self.two_d {
            let c = flow.angle.cos();
            return if c >= 0.0 { 0 } else { 4 };
        }
        let k0 = flow.octant.floor();
        let p = upper_octant_probability(flow.octant - k0, k0 as usize);
        let up = p > 0.0 && self.rng.random::<f64>() < p;
        (k0 as usize + up as usize) % 8
    }

    /// Speed fraction at the bed of column `c` (0: current shadow), for forward octant `k`.
    #[inline]
    pub(crate) fn bed_speed(&self, c: usize, k: usize, flow: &Flow) -> f64 {
        match self.p.abstraction {
            Abstraction::Shadow => {
                // Eq. (3): E_x = 0 <=> h_x - h_{x-1} < 0.
                let up = self.nb(c, k + 4);
                if self.vol.height(c) < self.vol.height(up) {
                    0.0
                } else {
                    1.0
                }
            }
            Abstraction::Slices => {
                let (x, y) = self.xy(c);
                self.water.bed_speed(
                    self.vol.heights(),
                    self.nx,
                    self.ny,
                    x,
                    y,
                    self.hmax_bound,
                    flow,
                )
            }
        }
    }

    /// The leading bed stress (`stress_lead`, opt-in): the speed fraction `s` of an exposed
    /// column `c` times `max(0, 1 + B r)`, `r` the bed's rise (m per m) from the column two
    /// bins upstream (octant `k + 4`) to `c`; `s` itself when the rule is off or the column is
    /// sheltered.
    #[inline]
    pub(crate) fn lead(&self, c: usize, k: usize, s: f64) -> f64 {
        let b = self.p.stress_lead;
        if b <= 0.0 || s <= 0.0 {
            return s;
        }
        let up2 = self.nb(self.nb(c, k + 4), k + 4);
        let rise = (self.vol.height(c) as f64 - self.vol.height(up2) as f64)
            * self.p.layer_thickness
            / (2.0 * self.dist(k));
        s * (1.0 + b * rise).max(0.0)
    }

    /// Eq. (3), second case (see the module documentation): the grain in `c` is held at the
    /// concave foot of a rise steeper than beta.
    #[inline]
    pub(crate) fn stoss_stable(&self, c: usize, k: usize) -> bool {
        if self.face_hold {
            // the face hold replaces the foot rule ([`Ripple::held_on_the_face`])
            return false;
        }
        let h = self.vol.height(c) as f64;
        let up = self.vol.height(self.nb(c, k + 4)) as f64;
        let dn = self.vol.height(self.nb(c, k)) as f64;
        let rise = dn - h;
        (h - up) < rise && rise > self.beta_layers[k % 2]
    }

    /// The face hold (`stoss_face_hold`, opt-in, where the current dominates): the top grain
    /// of `c` is held when the rise ahead of it (octant `k`) is steeper than beta, wherever it
    /// lies on the rise. As in [`Ripple::stoss_too_steep`], a rise of `ceil(B)` automata, `B =
    /// tan(beta) dx / gd`, holds it with probability `1 - (B - floor(B))`; a steeper one always.
    #[inline]
    pub(crate) fn held_on_the_face(&mut self, c: usize, k: usize) -> bool {
        let rise = self.vol.height(self.nb(c, k)) as f64 - self.vol.height(c) as f64;
        let b = self.beta_layers[k % 2];
        let (lo, hi) = self.beta_whole[k % 2];
        rise > hi || (rise > lo && self.rng.random::<f64>() >= b - lo)
    }

    /// Whether a grain from `origin` deposited on `c` would make the rise to `c` from the
    /// column upstream (octant `k + 4`) steeper than beta: the stoss cap of [`Ripple::roll`].
    /// The rise is judged on the bed the grain lands on, its origin counted as it was before
    /// the grain left (the pit a single grain leaves is not a stoss face). The bed's rises are
    /// whole automata, so a beta between two of them is met on average: a rise of `ceil(B)`
    /// automata, `B = tan(beta) dx / gd` the largest rise beta allows, is allowed with
    /// probability `B - floor(B)`.
    #[inline]
    pub(crate) fn stoss_too_steep(&mut self, c: usize, k: usize, origin: usize) -> bool {
        let h = self.vol.height(c) as f64 + 1.0;
        let u = self.nb(c, k + 4);
        let up = (self.vol.height(u) + usize::from(u == origin)) as f64;
        let b = self.beta_layers[k % 2];
        let (lo, hi) = self.beta_whole[k % 2];
        let rise = h - up;
        if rise <= lo {
            false
        } else if rise > hi {
            true
        } else {
            self.rng.random::<f64>() >= b - lo
        }
    }

    /// E_x of the top grain of `c` in units of m g' (m): 0 when it is not exposed (without the
    /// face hold, which [`Ripple::trigger`] applies before the budget; its callers run with the
    /// hold off).
    #[cfg(test)]
    pub(crate) fn budget(&self, c: usize, k: usize, flow: &Flow) -> f64 {
        if self.vol.height(c) == 0 {
            return 0.0;
        }
        self.budget_at(c, k, flow, self.lead(c, k, self.bed_speed(c, k, flow)))
    }

    /// [`Ripple::budget`] of a non-empty column `c` whose bed speed fraction `s` is known.
    fn budget_at(&self, c: usize, k: usize, flow: &Flow, s: f64) -> f64 {
        // Heights first (cache-resident); the automaton itself only for exposed grains.
        if s <= 0.0 || self.stoss_stable(c, k) {
            return 0.0;
        }
        let Some(a) = self.vol.top(c) else {
            return 0.0;
        };
        let stage = self
            .classes
            .excess_stage(a.class(), s * flow.speed, self.p.drag_coefficient);
        if stage <= 0.0 {
            return 0.0;
        }
        if self.p.hop_grains > 0.0 {
            let d = self.classes.d[a.class() as usize];
            self.p.friction * self.p.hop_metres(d) * stage
        } else {
            // (the product in its former order, so that default runs keep their bytes)
            self.p.friction * self.p.bin_size * self.p.hop_length * stage
        }
    }

    /// Monte Carlo trigger of column `c`: true when its top grain was exposed (an activation).
    pub(crate) fn trigger(&mut self, c: usize, flow: &Flow) -> bool {
        if self.vol.height(c) == 0 {
            return false;
        }
        let k = self.pick_octant(flow);
        // The water's speed at the bed, looked up once (the look-up upstream is the costly
        // part of an activation).
        let s = self.bed_speed(c, k, flow);
        if flow.vortex_reach.is_some() && s <= 0.0 {
            // in the lee vortex: carried back towards the crest at the vortex's speed
            let Some(a) = self.vol.top(c) else {
                return false;
            };
            let stage = self.classes.excess_stage(
                a.class(),
                self.p.vortex_strength * flow.speed,
                self.p.drag_coefficient,
            );
            if stage <= 0.0 {
                return false;
            }
            let d = self.classes.d[a.class() as usize];
            let budget = self.p.friction * self.p.hop_metres(d) * stage;
            self.roll_dir(c, k, budget, flow, true);
            return true;
        }
        if self.face_hold && s > 0.0 && self.held_on_the_face(c, k) {
            return false;
        }
        let mut budget = self.budget_at(c, k, flow, self.lead(c, k, s));
        if budget <= 0.0 {
            return false;
        }
        if self.p.hop_exponential {
            budget *= self.rng.sample::<f64, _>(rand_distr::Exp1);
        }
        if !self.roll(c, k, budget, flow) {
            self.creep(c, k);
        }
        true
    }

    /// Crest suspension (`crest_suspension`, `crest_suspension_grains` or
    /// `crest_suspension_hops`, opt-in): where a grain that the flow `flow` has just moved (at
    /// least one hop, not in the lee vortex) from a column whose top stood at `start_level`
    /// automata settles instead of where it rolled, `L` being the fixed length
    /// ([`crate::ripple::RippleParams::crest_suspension_m`]) or `crest_suspension_hops` times
    /// [`super::clock::median_travel`] at the flow's free-stream speed (no suspension where
    /// that is 0).
    /// With probability `min(1, (zeta / L)^n)` (`n` the `suspension_exponent`), `zeta` the
    /// height of that top above the bed's mean level (the automata per column, constant as the
    /// mass is), it was suspended and settles on a column drawn uniformly from the whole volume
    /// (upstream or downstream, the grain's own column included; a full column leaves it where
    /// it rolled), with a rolled grain's porosity.
    /// `None`: it rolled. No random draw when the rule is off, `zeta` is not above 0 or `L` is 0.
    fn suspension_landing(
        &mut self,
        start_level: usize,
        vortex: bool,
        flow: &Flow,
    ) -> Option<usize> {
        if vortex || !self.p.crest_suspension_on() {
            return None;
        }
        let columns = self.vol.columns();
        let mean = self.automata as f64 / columns as f64;
        let zeta = (start_level as f64 - mean) * self.p.layer_thickness;
        if zeta <= 0.0 {
            return None;
        }
        let l = if self.p.crest_suspension_hops > 0.0 {
            // (computed once per free-stream speed: it changes only with the waves' phase)
            if self.suspension_length.0 != flow.speed {
                let travel = super::clock::median_travel(&self.p, flow.speed);
                self.suspension_length = (flow.speed, self.p.crest_suspension_hops * travel);
            }
            self.suspension_length.1
        } else {
            self.p.crest_suspension_m()
        };
        if l <= 0.0 {
            return None;
        }
        let n = self.p.suspension_exponent;
        let q = zeta / l;
        let u = self.rng.random::<f64>();
        let suspended = below_power(u, q, n);
        if !suspended {
            return None;
        }
        let to = self.rng.random_range(0..columns);
        if self.vol.is_full(to) {
            return None;
        }
        self.stats.suspended += 1;
        Some(to)
    }

    /// Whether a candidate costing `cost` replaces the best so far (`best`, `None` before the
    /// first): when it is cheaper, or, among `ties` equally cheap candidates, with probability
    /// `1 / ties` (reservoir sampling), so that equally cheap cells are equally likely whatever
    /// order they are looked at in.
    #[inline]
    fn cheaper(&mut self, best: Option<f64>, cost: f64, ties: &mut u32) -> bool {
        match best {
            Some(b) if cost > b => false,
            Some(b) if cost == b => {
                *ties += 1;
                self.rng.random_range(0..*ties) == 0
            }
            _ => {
                *ties = 1;
                true
            }
        }
    }

    /// Energy Delta e (units of m g', m) of one space step to octant `o` rising `dh` metres
    /// (Eqs. 1, 4, 7).
    #[inline]
    pub(crate) fn delta_e(&self, o: usize, dh: f64) -> f64 {
        let dx = self.dist(o);
        let gd = self.p.layer_thickness;
        let ds = delta_s(dx, dh, gd);
        (self.p.friction * ds + dh).max(0.1 * self.p.friction * dx)
    }

    /// Roll/saltation of the top grain of `c` with budget `budget` (Eqs. 1-5, 7-8); false when
    /// it could not afford a single hop (it then stays).
    pub(crate) fn roll(&mut self, c: usize, k: usize, budget: f64, flow: &Flow) -> bool {
        self.roll_dir(c, k, budget, flow, false)
    }

    /// [`Ripple::roll`] downstream, or with `vortex` upstream (octant `k + 4`, the lee
    /// vortex's return flow), stopping where the grain leaves the shelter (the crest) instead
    /// of where it enters it, without the stoss cap.
    pub(crate) fn roll_dir(
        &mut self,
        c: usize,
        k: usize,
        budget: f64,
        flow: &Flow,
        vortex: bool,
    ) -> bool {
        let dir = if vortex { (k + 4) % 8 } else { k };
        let gd = self.p.layer_thickness;
        let start_level = self.vol.height(c);
        let Some(a) = self.vol.pop(c) else {
            return false;
        };
        let mut p = c;
        let mut level = start_level; // top of the moving grain, automata
        let mut spent = 0.0;
        let mut hops = 0usize;
        let mut path = std::mem::take(&mut self.path);
        path.clear();
        let max_hops = self.nx + self.ny;
        // Eq. (8): the cheapest forward cell. Equally cheap cells (the two sides of the forward
        // octant) are broken towards one side for the whole roll, the side drawn per roll with
        // probability 1/2, so a grain skirts an obstacle on one side, either side equally often.
        let options: &[usize] = if self.two_d {
            &[0]
        } else if self.rng.random::<bool>() {
            &FORWARD_3D
        } else {
            &FORWARD_3D_MIRRORED
        };
        loop {
            let mut best: Option<(f64, usize, usize)> = None;
            for &off in options {
                let o = (dir + off) % 8;
                let n = self.nb(p, o);
                if self.vol.is_full(n) {
                    continue;
                }
                let target = self.vol.height(n) + 1;
                let dh = (target as f64 - level as f64) * gd;
                let de = self.delta_e(o, dh);
                if best.is_none_or(|(b, _, _)| de < b) {
                    best = Some((de, n, target));
                }
            }
            let Some((de, n, target)) = best else { break };
            if spent + de > budget {
                // With a travel in metres (`hop_grains`), the last part-bin is crossed with the
                // fraction of its cost that is left, so the mean travel does not depend on
                // the bin size.
                let left = budget - spent;
                if !(self.p.hop_grains > 0.0 && left > 0.0 && self.rng.random::<f64>() * de < left)
                {
                    break;
                }
                path.push(p as u32);
                p = n;
                hops += 1;
                break;
            }
            spent += de;
            path.push(p as u32);
            p = n;
            level = target;
            hops += 1;
            if hops >= max_hops || (self.bed_speed(p, k, flow) <= 0.0) != vortex {
                break;
            }
        }
        // The stoss cap (beta, "the maximum slope of the stoss side"): a grain does not come
        // to rest where it would make the rise from the column upstream steeper than beta; it
        // rests at the last column of its path where it would not (the foot of the rise).
        while self.stoss_capped && !vortex && hops > 0 && self.stoss_too_steep(p, k, c) {
            p = path.pop().expect("one column per hop") as usize;
            hops -= 1;
        }
        self.path = path;
        if hops == 0 {
            self.vol.push(c, a);
            return false;
        }
        // Crest suspension (opt-in): a grain that the flow has moved may settle elsewhere.
        let p = match self.suspension_landing(start_level, vortex, flow) {
            Some(to) => to,
            None => {
                self.stats.rolls += 1;
                self.stats.hops += hops as u64;
                p
            }
        };
        self.deposit(p, a, Deposit::Rolled);
        self.relax(&[c as u32], &[p as u32]);
        true
    }

    /// Puts `a` on column `c` with the porosity of `how` and compacts the automata beneath it.
    /// The column must not be full.
    pub(crate) fn deposit(&mut self, c: usize, a: super::volume::Automaton, how: Deposit) {
        let code = self.compaction.deposit_code(how);
        let ok = self.vol.push(c, a.with_porosity_code(code));
        debug_assert!(ok, "deposit on a full column");
        let h = self.vol.height(c);
        self.hmax_bound = self.hmax_bound.max(h);
        let lo = h.saturating_sub(1 + self.compaction.depth);
        for z in lo..h.saturating_sub(1) {
            let b = self.vol.get(c, z);
            let buried = self.compaction.bury(b.porosity_code());
            self.vol.set(c, z, b.with_porosity_code(buried));
        }
    }

    /// Avalanche relaxation (Eq. 6) after the columns `lowered` lost and `raised` gained an
    /// automaton: until no slope exceeds alpha. A lowered column can only steepen the slopes of
    /// its neighbours towards it, a raised one only its own slopes, so those are the columns
    /// checked; every avalanche move queues the same way.
    pub(crate) fn relax(&mut self, lowered: &[u32], raised: &[u32]) {
        let mut stack = std::mem::take(&mut self.stack);
        stack.clear();
        for &s in lowered {
            self.for_each_next(s as usize, |n| stack.push(n as u32));
        }
        stack.extend_from_slice(raised);
        while let Some(c) = stack.pop() {
            let c = c as usize;
            while let Some(n) = self.steepest_descent(c) {
                let a = self.vol.pop(c).expect("a steep column has sand");
                self.deposit(n, a, Deposit::Avalanche);
                self.stats.avalanches += 1;
                stack.push(n as u32);
                self.for_each_next(c, |m| stack.push(m as u32));
            }
        }
        self.stack = stack;
    }

    /// Creep (Eqs. 9-10) of the top grain of `c` for forward octant `k`; true when it moved.
    pub(crate) fn creep(&mut self, c: usize, k: usize) -> bool {
        let h = self.vol.height(c);
        if h == 0 {
            return false;
        }
        let limit = h as f64 - 1.0 - self.gamma_layers;
        let (up, set): (&[usize], &[usize]) = if self.two_d {
            (&[4], &[0])
        } else {
            (&[3, 4, 5], &[6, 2, 0])
        };
        let up_min = up
            .iter()
            .map(|&o| self.vol.height(self.nb(c, k + o)))
            .min()
            .unwrap_or(0);
        if up_min as f64 > limit {
            return false; // Eq. (9): not exposed enough
        }
        let mut best: Option<(usize, usize)> = None;
        let mut ties = 0u32;
        for &o in set {
            let n = self.nb(c, k + o);
            let hn = self.vol.height(n);
            if n != c
                && !self.vol.is_full(n)
                && self.cheaper(best.map(|b| b.0 as f64), hn as f64, &mut ties)
            {
                best = Some((hn, n));
            }
        }
        let Some((hn, n)) = best else { return false };
        if hn as f64 > limit {
            return false; // Eq. (10): nowhere to settle
        }
        let a = self.vol.pop(c).expect("checked above");
        self.deposit(n, a, Deposit::Rolled);
        self.stats.creeps += 1;
        self.relax(&[c as u32], &[n as u32]);
        true
    }
}

/// The probability of the upper of the two octants `k0` and `k0 + 1` around a flow at
/// `frac` (0..1) of the way from `k0` to `k0 + 1`, such that the mean displacement of a grain
/// on a flat bed points along the flow. On a flat bed Eq. (8) sends a grain of an axis octant
/// along that axis, and a grain of a diagonal octant along one of the two axes beside it
/// (they are cheaper than the diagonal), equally likely: the mean step of octant `k` is
/// `w_k (cos k pi/4, sin k pi/4)` bins with `w = 1` on the axes and `1/sqrt 2` on the
/// diagonals. Mixing octants `a = k0` and `b = k0 + 1` with probabilities `1 - p` and `p`
/// gives a mean along the flow angle `phi = frac pi/4` past `a` when
/// `p = w_a sin(phi) / (w_a sin(phi) + w_b sin(pi/4 - phi))`.
pub fn upper_octant_probability(frac: f64, k0: usize) -> f64 {
    if frac <= 0.0 {
        return 0.0;
    }
    let (wa, wb) = if k0.is_multiple_of(2) {
        (1.0, std::f64::consts::FRAC_1_SQRT_2)
    } else {
        (std::f64::consts::FRAC_1_SQRT_2, 1.0)
    };
    let phi = frac * std::f64::consts::FRAC_PI_4;
    let a = wa * phi.sin();
    a / (a + wb * (std::f64::consts::FRAC_PI_4 - phi).sin())
}

/// Whether a uniform draw `u` falls below `q^n` (`q > 0`): crest suspension's test. A whole
/// exponent up to 64 goes by multiplications (pow is costly, and asked for on every moved grain
/// above the mean level), with `q^n` itself only where `u` falls within 1e-12 of the product,
/// far further than the products can stray from `q^n` (each squaring doubles the relative
/// error, so at most about `n - 1` roundings of 2^-53, below 7e-15 for `n <= 64`, the product
/// being a normal number; `below_power_compares_with_pow` pins the margin): the outcome of
/// comparing with `q^n` (`powf`), and the product `q q` itself for `n = 2`.
#[inline]
pub(crate) fn below_power(u: f64, q: f64, n: f64) -> bool {
    if n == 2.0 {
        return u < q.powi(2);
    }
    if n.fract() == 0.0 && (1.0..=64.0).contains(&n) {
        let near = q.powi(n as i32);
        if near.is_normal() {
            if u >= near * (1.0 + 1e-12) {
                return false;
            }
            if u < near * (1.0 - 1e-12) {
                return true;
            }
        }
    }
    u < q.powf(n)
}

/// Eq. (1) (second form) and Eq. (7): the length of one space step,
/// `Delta s = sqrt(Delta x^2 + (Delta h + gd)^2)` with `Delta x` the horizontal distance
/// (including Delta y), all in metres.
#[inline]
pub fn delta_s(dx: f64, dh: f64, gd: f64) -> f64 {
    (dx * dx + (dh + gd) * (dh + gd)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ripple::params::{Frame, Mode, RippleParams};

    fn two_d(heights: &[usize], f: impl FnOnce(&mut RippleParams)) -> Ripple {
        let mut p = RippleParams {
            mode: Mode::TwoD,
            nx: heights.len(),
            ny: 1,
            sorting: 0.0,
            roughness: 0,
            ..RippleParams::default()
        };
        f(&mut p);
        Ripple::from_heights(&p, heights).unwrap()
    }

    /// A run of `nx` x `ny` columns of 4 layers (a section when `ny` is 1).
    fn small(nx: usize, ny: usize) -> Ripple {
        let p = RippleParams {
            mode: if ny == 1 { Mode::TwoD } else { Mode::ThreeD },
            nx,
            ny,
            layers: 4,
            ..RippleParams::default()
        };
        Ripple::new(&p).unwrap()
    }

    #[test]
    fn xy_divides_by_the_row_length() {
        for (nx, ny) in [(5, 3), (64, 33), (7, 7), (1024, 1)] {
            let r = small(nx, ny);
            for c in 0..nx * ny {
                assert_eq!(r.xy(c), (c % nx, c / nx), "{nx} x {ny}: {c}");
            }
        }
    }

    #[test]
    fn the_next_columns_are_the_lattice_neighbours_in_its_order() {
        for (nx, ny) in [(5, 1), (64, 1), (6, 4)] {
            let r = small(nx, ny);
            for c in 0..nx * ny {
                let mut next = Vec::new();
                r.for_each_next(c, |n| next.push(n));
                let want: Vec<usize> = r.lattice.neighbours(c).collect();
                assert_eq!(next, want, "{nx} x {ny}: {c}");
                assert_eq!(next.len(), if ny == 1 { 2 } else { 8 });
            }
        }
    }

    #[test]
    fn below_power_compares_with_pow() {
        use rand::RngExt;
        let mut rng = crate::engine::rng::stream(11);
        let mut agree = [0usize; 2];
        for i in 0..200_000 {
            let n = [2.0, 3.0, 8.0, 13.0, 64.0, 2.5, 70.0][i % 7];
            let q: f64 = match i % 4 {
                0 => rng.random_range(0.0..1.5),
                1 => 10f64.powf(rng.random_range(-40.0..1.0)),
                _ => rng.random::<f64>().powf(1.0 / n),
            };
            let pow = q.powf(n);
            // draws at the power itself and a few roundings either side
            let u = match i % 3 {
                0 => rng.random::<f64>(),
                1 => pow,
                _ => pow * (1.0 + rng.random_range(-4.0..4.0) * f64::EPSILON),
            };
            let want = if n == 2.0 { u < q * q } else { u < pow };
            // the products stay well inside the band where pow decides
            let near = q.powi(n as i32);
            if n.fract() == 0.0 && n <= 64.0 && near.is_normal() {
                assert!(
                    (near / pow - 1.0).abs() < 1e-13,
                    "q {q} n {n}: {near} {pow}"
                );
            }
            assert_eq!(below_power(u, q, n), want, "u {u} q {q} n {n}");
            agree[usize::from(want)] += 1;
        }
        assert!(agree.iter().all(|&a| a > 10_000), "{agree:?}");
        // powers that underflow to 0 or to subnormal numbers go by pow itself
        for q in [1e-50, 1e-39, 1e-38] {
            assert_eq!(below_power(0.0, q, 8.0), 0.0 < q.powf(8.0), "{q}");
        }
        assert!(below_power(0.0, 1e-39, 8.0), "1e-312 is above 0");
    }

    #[test]
    fn eq1_delta_s() {
        assert!((delta_s(3.0, 3.0, 1.0) - 5.0).abs() < 1e-12);
        assert!((delta_s(0.005, -0.0005, 0.0005) - 0.005).abs() < 1e-15);
    }

    #[test]
    fn eq4_energy_is_friction_plus_gravity() {
        let r = two_d(&[10; 8], |_| {});
        let (dx, gd, mu) = (0.005, 0.0005, 0.6);
        let up = r.delta_e(0, gd);
        assert!((up - (mu * delta_s(dx, gd, gd) + gd)).abs() < 1e-15);
        // uphill costs more than level, level more than downhill
        assert!(up > r.delta_e(0, 0.0));
        assert!(r.delta_e(0, 0.0) > r.delta_e(0, -gd));
        // a steep descent never gives energy back: floor of a tenth of the flat friction
        assert!((r.delta_e(0, -0.1) - 0.1 * mu * dx).abs() < 1e-15);
        // diagonal steps (Eq. 7) are longer
        assert!(r.delta_e(1, 0.0) > r.delta_e(0, 0.0));
    }

    #[test]
    fn eq3_shadow_behind_a_step_down() {
        let mut h = vec![10usize; 12];
        h[4] = 12;
        let r = two_d(&h, |p| p.abstraction = Abstraction::Shadow);
        let f = r.flow_at(0);
        assert_eq!(
            r.bed_speed(5, 0, &f),
            0.0,
            "lee of the step: h_x - h_(x-1) < 0"
        );
        assert_eq!(r.bed_speed(4, 0, &f), 1.0);
        assert_eq!(r.budget(5, 0, &f), 0.0);
        assert!(r.budget(4, 0, &f) > 0.0);
    }

    /// `stress_lead`: the speed fraction times `max(0, 1 + B r)`, `r` the rise from the column
    /// two bins upstream over their run; a sheltered column (0) stays sheltered.
    #[test]
    fn the_leading_stress_scales_the_speed_by_the_rise_upstream() {
        // a rise of 2 automata over the two bins before x = 6, a drop of 2 over those before
        // x = 10
        let mut h = vec![10usize; 16];
        h[5] = 11;
        h[6] = 12;
        h[7] = 12;
        h[8] = 12;
        let r = two_d(&h, |p| p.stress_lead = 2.0);
        let (gd, dx) = (0.0005, 0.005);
        let rise = 2.0 * gd / (2.0 * dx);
        assert!((r.lead(6, 0, 1.0) - (1.0 + 2.0 * rise)).abs() < 1e-12);
        assert!((r.lead(6, 0, 0.5) - 0.5 * (1.0 + 2.0 * rise)).abs() < 1e-12);
        assert!((r.lead(10, 0, 1.0) - (1.0 - 2.0 * rise)).abs() < 1e-12);
        assert_eq!(r.lead(12, 0, 1.0), 1.0, "flat: no change");
        assert_eq!(r.lead(6, 0, 0.0), 0.0, "a sheltered column stays sheltered");
        // a drop steeper than 1 / B clamps the speed to 0
        let steep = two_d(&h, |p| p.stress_lead = 20.0);
        assert_eq!(steep.lead(10, 0, 1.0), 0.0);
        // off: the speed itself
        let off = two_d(&h, |_| {});
        assert_eq!(off.lead(6, 0, 0.7), 0.7);
    }

    #[test]
    fn eq3_stoss_stability_beta() {
        // a concave foot before a rise of 3 automata over one bin: 3 gd / dx = 0.3 > tan 7 deg
        let mut h = vec![10usize; 12];
        h[5] = 13;
        h[6] = 13;
        let r = two_d(&h, |p| p.abstraction = Abstraction::Shadow);
        assert!(r.stoss_stable(4, 0));
        let r0 = two_d(&h, |p| {
            p.abstraction = Abstraction::Shadow;
            p.stoss_angle = 20.0; // tan 20 = 0.36 > 0.3: not held
        });
        assert!(!r0.stoss_stable(4, 0));
    }

    /// The face hold (`stoss_face_hold`): a grain is held wherever the rise ahead of it is
    /// steeper than beta, not only at a concave foot, and replaces Eq. (3)'s foot rule. With
    /// 5 mm bins and automata of 0.5 mm, beta = 7 deg allows `B = 1.228` automata a bin: a rise
    /// of 3 holds always, of 1 never, of 2 with probability `1 - 0.228`.
    #[test]
    fn eq3_face_hold_holds_a_grain_anywhere_on_a_rise_steeper_than_beta() {
        // a uniform rise of 3 automata a bin from column 3 on: column 3 is no concave foot
        let face = |step: usize, hold: bool| {
            let h: Vec<usize> = (0..12)
                .map(|c| 10 + step * c.clamp(2, 6) - 2 * step)
                .collect();
            two_d(&h, |p| {
                p.abstraction = Abstraction::Shadow;
                p.stoss_face_hold = hold;
            })
        };
        let foot = face(3, false);
        assert!(
            !foot.stoss_stable(3, 0),
            "the foot rule holds only a concave foot"
        );
        let mut r = face(3, true);
        assert!(r.face_hold && !r.stoss_stable(3, 0));
        assert!((0..100).all(|_| r.held_on_the_face(3, 0)));
        let mut gentle = face(1, true);
        assert!((0..100).all(|_| !gentle.held_on_the_face(3, 0)));
        let mut two = face(2, true);
        let b = 7f64.to_radians().tan() * 10.0;
        let n = 20_000;
        let held = (0..n).filter(|_| two.held_on_the_face(3, 0)).count() as f64 / n as f64;
        let p = 1.0 - (b - b.floor());
        let se = (p * (1.0 - p) / n as f64).sqrt();
        assert!(
            (held - p).abs() < 4.0 * se,
            "held {held}, expected {p} +- {se}"
        );
        // off where the waves dominate, as the stoss cap is, and on again once a current
        // dominates (`set_current`)
        let mut waves = two_d(&[10; 12], |p| {
            p.stoss_face_hold = true;
            p.current_speed = 0.0;
            p.wave_amplitude = 0.4;
            p.wave_period = 64.0;
        });
        assert!(!waves.face_hold);
        waves.set_current(1.5, 0.0).unwrap();
        assert!(waves.face_hold && waves.stoss_capped);
        waves.set_current(0.0, 0.0).unwrap();
        assert!(!waves.face_hold);
    }

    #[test]
    fn eq5_roll_moves_one_automaton_forward() {
        let mut r = two_d(&[10; 16], |p| p.abstraction = Abstraction::Shadow);
        let f = r.flow_at(0);
        let cost = r.delta_e(0, 0.0005); // first hop onto a level neighbour rises one automaton
        assert!(r.roll(3, 0, cost * 1.0001, &f));
        let h: Vec<usize> = (0..16).map(|c| r.vol.height(c)).collect();
        assert_eq!(h[3], 9);
        assert_eq!(h[4], 11);
        assert_eq!(r.vol.automata(), 160);
    }

    #[test]
    fn the_lee_vortex_carries_a_sheltered_grain_back_towards_the_crest() {
        // a crest at x = 10, two slices above a flat bed: the columns behind it are sheltered
        let mut h = vec![20usize; 40];
        h[10] = 24;
        h[9] = 22;
        h[11] = 22;
        let mut r = two_d(&h, |p| {
            p.current_speed = 0.0;
            p.wave_amplitude = 0.6;
            p.wave_period = 40.0;
            p.wave_vortex = 0.1;
            p.vortex_strength = 1.0;
        });
        let f = r.flow_at(9); // psi near pi / 2, flow along +x
        assert!(f.vortex_reach.is_some() && f.angle.cos() > 0.0);
        assert_eq!(r.bed_speed(12, 0, &f), 0.0, "behind the crest");
        let before: Vec<usize> = (0..40).map(|c| r.vol.height(c)).collect();
        assert!(r.trigger(12, &f));
        let after: Vec<usize> = (0..40).map(|c| r.vol.height(c)).collect();
        assert_eq!(after[12], before[12] - 1);
        let gained = (0..40).find(|&c| after[c] > before[c]).unwrap();
        assert!(gained < 12, "carried upstream, to {gained}");
        assert_eq!(r.vol.automata(), before.iter().sum::<usize>() as u64);
        // without the vortex the sheltered grain stays
        let mut r0 = two_d(&h, |p| {
            p.current_speed = 0.0;
            p.wave_amplitude = 0.6;
            p.wave_period = 40.0;
        });
        let f0 = r0.flow_at(9);
        assert!(!r0.trigger(12, &f0));
    }

    #[test]
    fn fine_grains_travel_further_for_the_same_flow() {
        // On a flat bed, with the budget of the flow for each grain size (Eq. 3 with E_x from
        // the Shields stage), a fine grain hops further than a coarse one.
        let p = RippleParams {
            mode: Mode::TwoD,
            nx: 200,
            ny: 1,
            sorting: 1.5,
            roughness: 0,
            hop_length: 4.0,
            abstraction: Abstraction::Shadow,
            ..RippleParams::default()
        };
        let classes = crate::ripple::GrainClasses::new(p.d50, p.sorting);
        let travel = |phi: f64| {
            let mut r = Ripple::from_heights(&p, &[20; 200]).unwrap();
            let k = classes.class_of_phi(phi);
            let a = r.vol.pop(10).unwrap();
            r.vol
                .push(10, crate::ripple::Automaton::new(k, a.porosity_code()));
            let f = r.flow_at(0);
            let b = r.budget(10, 0, &f);
            r.roll(10, 0, b, &f);
            (0..200).find(|&c| r.vol.height(c) == 21).unwrap_or(10)
        };
        let fine = travel(3.3);
        let coarse = travel(1.3);
        assert!(fine > coarse, "fine {fine} coarse {coarse}");
    }

    #[test]
    fn eq8_cheapest_of_three_forward_cells() {
        let p = RippleParams {
            nx: 6,
            ny: 6,
            sorting: 0.0,
            roughness: 0,
            abstraction: Abstraction::Shadow,
            ..RippleParams::default()
        };
        let mut h = vec![10usize; 36];
        // from (2, 2): forward cells (3, 1), (3, 2), (3, 3); make (3, 3) the lowest.
        h[2 * 6 + 3] = 11;
        h[6 + 3] = 11;
        h[3 * 6 + 3] = 6;
        let mut r = Ripple::from_heights(&p, &h).unwrap();
        let f = r.flow_at(0);
        // (3, 3) is diagonal (longer Delta s, Eq. 7) but 3 automata down: the cheapest.
        let one_hop = r.delta_e(1, -3.0 * p.layer_thickness) * 1.0001;
        assert!(r.roll(2 * 6 + 2, 0, one_hop, &f));
        let h: Vec<usize> = (0..36).map(|c| r.vol.height(c)).collect();
        assert_eq!(h[3 * 6 + 3], 7, "went to the cheapest (lowest) cell: {h:?}");
    }

    #[test]
    fn eq6_avalanche_relaxes_a_spike_below_alpha() {
        let mut h = vec![5usize; 64];
        h[27] = 60;
        let p = RippleParams {
            nx: 8,
            ny: 8,
            sorting: 0.0,
            roughness: 0,
            ..RippleParams::default()
        };
        let r = Ripple::from_heights(&p, &h).unwrap();
        assert_eq!(r.vol.automata(), 63 * 5 + 60);
        assert_eq!(r.steep_pair(), None);
        assert!(r.vol.height(27) < 60);
        let loose = r.compaction.codes[0];
        assert!((0..64).any(|c| c != 27 && r.vol.top(c).unwrap().porosity_code() == loose));
    }

    #[test]
    fn eq9_creep_needs_exposure_and_eq10_a_lower_place() {
        // 3-D, forward +x. Column (2,2) sticks out 3 automata above its upstream cells.
        let p = RippleParams {
            nx: 5,
            ny: 5,
            sorting: 0.0,
            roughness: 0,
            creep_angle: 5.0, // gamma dx / gd = 0.87 automata
            ..RippleParams::default()
        };
        let mut h = vec![10usize; 25];
        h[2 * 5 + 2] = 13;
        let mut r = Ripple::from_heights(&p, &h).unwrap();
        assert!(r.creep(12, 0));
        assert_eq!(r.vol.height(12), 12);
        assert_eq!(r.vol.automata(), 25 * 10 + 3);
        // Eq. (9) false: the upstream cells are as high as the grain.
        let mut h2 = vec![10usize; 25];
        for y in 1..4 {
            h2[y * 5 + 1] = 13;
        }
        h2[12] = 13;
        let mut r2 = Ripple::from_heights(&p, &h2).unwrap();
        assert!(!r2.creep(12, 0));
        // Eq. (10) false: nowhere lower to settle (lateral and forward cells as high).
        let mut h3 = vec![10usize; 25];
        for c in [12, 7, 17, 13] {
            h3[c] = 13;
        }
        let mut r3 = Ripple::from_heights(&p, &h3).unwrap();
        assert!(!r3.creep(12, 0));
    }

    #[test]
    fn octant_probability_points_the_flat_bed_mean_along_the_flow() {
        for k0 in 0..8 {
            assert_eq!(upper_octant_probability(0.0, k0), 0.0);
            assert!((upper_octant_probability(1.0, k0) - 1.0).abs() < 1e-15);
        }
        for i in 1..20 {
            let f = i as f64 / 20.0;
            // mirror symmetry: from an axis towards a diagonal, and back from the diagonal
            let (pe, po) = (
                upper_octant_probability(f, 0),
                upper_octant_probability(1.0 - f, 1),
            );
            assert!((pe + po - 1.0).abs() < 1e-12, "{f}: {pe} {po}");
            // the mixed mean step (1 - p) (1, 0) + p (1/2, 1/2) points at f x 45 deg
            let ang = (pe / 2.0).atan2(1.0 - pe / 2.0);
            assert!((ang - f * std::f64::consts::FRAC_PI_4).abs() < 1e-12);
        }
    }

    /// The mean displacement of grains set off one at a time on a flat bed, as an angle
    /// (degrees, 0..360), and the number of moves measured.
    fn flat_bed_mean_direction(angle: f64, frame: Frame, seed: u64, trials: usize) -> (f64, usize) {
        let (nx, ny) = (32usize, 32usize);
        let p = RippleParams {
            nx,
            ny,
            sorting: 0.0,
            roughness: 0,
            current_angle: angle,
            frame,
            seed,
            ..RippleParams::default()
        };
        let mut r = Ripple::from_heights(&p, &vec![10usize; nx * ny]).unwrap();
        let f = r.flow_at(0);
        let (mut sx, mut sy, mut n) = (0.0, 0.0, 0);
        let wrap = |d: i64, len: usize| {
            let l = len as i64;
            (d + l / 2).rem_euclid(l) - l / 2
        };
        for i in 0..trials {
            let c = (i * 7919) % (nx * ny);
            if !r.trigger(c, &f) {
                continue;
            }
            let q = (0..nx * ny).find(|&q| r.vol.height(q) > 10).unwrap();
            sx += wrap((q % nx) as i64 - (c % nx) as i64, nx) as f64;
            sy += wrap((q / nx) as i64 - (c / nx) as i64, ny) as f64;
            n += 1;
            let a = r.vol.pop(q).unwrap();
            r.vol.push(c, a);
        }
        // from the lattice's frame to east-based degrees
        (
            (sy.atan2(sx).to_degrees() + p.frame_angle()).rem_euclid(360.0),
            n,
        )
    }

    #[test]
    fn mean_hop_direction_on_a_flat_bed_follows_the_current() {
        // 3000 grains each: the angle of the mean has a standard error of about
        // 1 / (hops x sqrt(n)) rad ~ 0.4 deg; 2 deg is 5 standard errors.
        // In the grid frame the hops are rounded stochastically between octants; in the flow
        // frame they run along the lattice's x axis, turned to the current.
        for frame in [Frame::Grid, Frame::Flow] {
            for step in 0..24 {
                let angle = 15.0 * step as f64;
                let (dir, n) = flat_bed_mean_direction(angle, frame, 7 + step as u64, 3000);
                assert!(n > 2500, "{angle}: only {n} grains moved");
                let err = ((dir - angle + 180.0).rem_euclid(360.0) - 180.0).abs();
                assert!(
                    err < 2.0,
                    "{frame:?} frame, current {angle} deg: mean hop direction {dir:.2} deg"
                );
            }
        }
    }
}
