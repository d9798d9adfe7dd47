//! Samplers that advance a [`Growth`] run: the paper's rejection algorithm, an exact
//! rejection-free equivalent, and the synchronous deterministic cellular automaton.
//!
//! - [`SamplerKind::Rejection`]: the paper's algorithm verbatim. One timestep picks a
//!   uniformly random surface site and accepts it if `R < p`.
//! - [`SamplerKind::Exact`]: the same stochastic process on the same clock, drawn directly
//!   (our reading of the paper's clock: one timestep is one pick, accepted or not): the number of rejected picks before the next acceptance is
//!   geometric with success probability `P = sum(p) / S` over the `S` surface sites, and the
//!   accepted site is chosen with probability proportional to its `p`. Sites are grouped by
//!   `b`; class weights are computed relative to the highest occupied class, so that they
//!   never underflow however large `n` is. Cost per accepted event: `O(z)`, plus `O(z log S)`
//!   with a non-uniform weight; independent of `n`. At `n = 0` with a uniform weight every
//!   site weighs the same: the sampler flattens the surface (no classes to keep up) and
//!   picks one uniform slot of all.
//! - [`SamplerKind::Ca`]: synchronous deterministic growth (Figs. 3 and 4): every surface
//!   site with at least `b_min` occupied neighbours becomes occupied at once.
//!
//! Random numbers come from the engine's [`Stream`] (Xoshiro256++), seeded from the run's
//! `--seed`.

use std::fmt;
use std::str::FromStr;

use rand::RngExt;
use rand_distr::Exp1;
use serde::{Deserialize, Serialize};

use super::state::Growth;
use crate::engine::rng::Stream;

/// Which sampler advances the run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SamplerKind {
    /// The paper's rejection algorithm: one pick per timestep.
    Rejection,
    /// Rejection-free, same process and clock.
    Exact,
    /// Synchronous deterministic cellular automaton.
    Ca,
}

impl SamplerKind {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Rejection => "rejection",
            SamplerKind::Exact => "exact",
            SamplerKind::Ca => "ca",
        }
    }
}

impl fmt::Display for SamplerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for SamplerKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "rejection" => Ok(SamplerKind::Rejection),
            "exact" => Ok(SamplerKind::Exact),
            "ca" => Ok(SamplerKind::Ca),
            _ => Err(format!(
                "unknown sampler '{s}': expected rejection, exact or ca"
            )),
        }
    }
}

/// What one call of a sampler's step ended with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// A site was accepted (occupied) at the current time.
    Accepted(usize),
    /// The step limit was reached with no further acceptance.
    Limit,
    /// There is no surface site left: the lattice is full (or the shape enclosed).
    Exhausted,
    /// Every surface site has `p = 0` (e.g. `v = 0`): nothing can ever be accepted. The clock
    /// was moved to the limit.
    Stalled,
    /// The next acceptance lies beyond the largest `f64` timestep (e.g. `n = 1e4` with only
    /// poorly connected sites): the clock is `+inf` and the run cannot go on.
    ClockOverflow,
}

/// One pick (rejection sampler) or one acceptance (exact sampler), reported for teaching by
/// [`Growth::pick_rejection`] and [`Growth::pick_exact`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Pick {
    /// The picked (rejection) or accepted (exact) cell, `y * width + x`.
    pub cell: usize,
    /// Its occupied neighbours before the pick.
    pub b: usize,
    /// The neighbourhood size.
    pub z: usize,
    /// The direction weight `v` at the cell (1 without Eq. 5).
    pub v: f64,
    /// The sticking probability `p = v (b/z)^n`.
    pub p: f64,
    /// The uniform draw `R` in [0, 1) (rejection sampler only).
    pub r: Option<f64>,
    /// Whether the site was occupied (`R < p`; always true for the exact sampler).
    pub accepted: bool,
    /// Exact sampler: rejected picks skipped before this acceptance (0 for the rejection
    /// sampler, which makes them one by one).
    pub skipped: f64,
    /// Surface sites at the time of the pick.
    pub surface: usize,
}

/// Number of rejected picks before the next acceptance, when each pick is accepted with
/// probability `P = exp(ln_p)`, given `e`, a draw from the unit exponential law.
///
/// `K = floor(e / -ln(1 - P))` is geometric on `{0, 1, ...}`: `Pr(K >= k) = (1 - P)^k`.
/// `P` is given by its logarithm so that it may be far below the smallest `f64` (`n = 1e4`).
/// The count is returned as an `f64` (exact below `2^53`); it is `+inf` when it exceeds the
/// largest `f64`, which the clock then reports as an overflow.
pub fn rejected_picks(ln_p: f64, e: f64) -> f64 {
    if ln_p >= 0.0 {
        return 0.0;
    }
    let ln_rate = ln_rate(ln_p);
    if ln_rate > -700.0 {
        (e / ln_rate.exp()).floor()
    } else {
        (e.ln() - ln_rate).exp().floor()
    }
}

/// `ln(-ln(1 - P))` for an acceptance probability `P = exp(ln_p) < 1`, without cancellation
/// in every regime: the log of the rate of the exponential law behind the geometric count.
fn ln_rate(ln_p: f64) -> f64 {
    if ln_p < -20.0 {
        // rate = P (1 + P/2 + ...), P < 2e-9.
        ln_p + (0.5 * ln_p.exp()).ln_1p()
    } else {
        let one_minus_p = -ln_p.exp_m1();
        (-one_minus_p.ln()).ln()
    }
}

/// The natural log of [`rejected_picks`]`(ln_p, e)` (up to its rounding down to a whole
/// number), finite where the count itself exceeds the largest `f64`: the log clock of an
/// unbounded run uses it.
pub fn ln_rejected_picks(ln_p: f64, e: f64) -> f64 {
    if ln_p >= 0.0 {
        return f64::NEG_INFINITY;
    }
    e.ln() - ln_rate(ln_p)
}

/// `ln(exp(a) + exp(b))` without overflow.
fn ln_add(a: f64, b: f64) -> f64 {
    let (hi, lo) = if a >= b { (a, b) } else { (b, a) };
    if lo == f64::NEG_INFINITY {
        hi
    } else {
        hi + (lo - hi).exp().ln_1p()
    }
}

/// As [`rejected_picks`], for an acceptance probability `p` given directly (`p` well above
/// the smallest normal `f64`).
///
/// For `p <= 1/4` (every `n >= 2` flame measured) the count usually comes without the
/// logarithm: [`geometric_count_by_series`] brackets it; the logarithm is taken only where the
/// bracket holds a whole number. Both give the same count, bit for bit.
#[inline]
pub fn rejected_picks_linear(p: f64, e: f64) -> f64 {
    if p >= 1.0 {
        return 0.0;
    }
    if p < TINY_P {
        // (the logarithm's count without the logarithm: rejected_picks_by_log; an n = 50
        // flame's faceted front has p of 1e-24, where the series would only decline)
        return rejected_picks_by_log(p, e);
    }
    if let Some(k) = geometric_count_by_series(p, e) {
        return k;
    }
    rejected_picks_by_log(p, e)
}

/// Below this acceptance probability `-ln(1 - p)` rounds to `p` (`2^-54`).
const TINY_P: f64 = 5.551115123125783e-17;

/// `floor(e / -ln(1 - p))` by the logarithm, for `0 < p < 1`.
#[inline]
fn rejected_picks_by_log(p: f64, e: f64) -> f64 {
    // -ln(1 - p) = p (1 + p/2 + ...) is p itself in f64 below 2^-54, and ln_1p returns it
    // there (test `rejected_picks_by_log_skips_the_logarithm_only_where_it_is_p`): the
    // count is then e / p, without the call.
    let rate = if p < TINY_P { p } else { -(-p).ln_1p() };
    let k = e / rate;
    // floor() of a non-negative value below 2^63 by truncation (floor is a library call on
    // the baseline x86-64 target); larger values (and +inf) are whole already (an f64 at or
    // above 2^52 has no fraction).
    if k < 9.2e18 { (k as i64) as f64 } else { k }
}

/// The geometric count `floor(e / r)`, `r = -ln(1 - p)`, without a logarithm, for
/// `0 < p <= 1/4` (else `None`): `r = p + p^2/2 + p^3/3 + ...`, so the sum `S` of its first six
/// terms satisfies `S <= r <= S + p^7 / (7 (1 - p))`, i.e. `r / S - 1 <= (4/21) p^6`. The
/// quotient `e / r` then lies in `[q (1 - (4/21) p^6), q]` for `q = e / S`; widened by
/// `1e-12` on each side (far beyond the rounding of `S`, of the quotient, and of the
/// logarithm [`rejected_picks_linear`] falls back on), the interval gives the count when no
/// whole number lies inside it, and `None` when one does (about `q (4/21) p^6` of the draws:
/// 6e-5 at `p = 0.2` and `e = 1`). The wait is the same whichever way it is computed, so a
/// run's bytes do not depend on it.
#[inline]
pub fn geometric_count_by_series(p: f64, e: f64) -> Option<f64> {
    if !(p > 0.0 && p <= 0.25) {
        return None;
    }
    let p2 = p * p;
    // p (1 + p/2 + p^2/3 + p^3/4 + p^4/5 + p^5/6), in two halves (a shorter dependency chain)
    let sum = p + p2 * ((0.5 + p * (1.0 / 3.0)) + p2 * (0.25 + p * 0.2 + p2 * (1.0 / 6.0)));
    let q = e / sum;
    let hi = q * (1.0 + 1e-12);
    let lo = q * (1.0 - (p2 * p2 * p2 * (4.0 / 21.0) + 1e-12));
    // (below 2^52 the truncation is exact and the count fits an i64)
    if hi >= 4.0e15 {
        return None;
    }
    let k = (hi as i64) as f64;
    (lo >= k).then_some(k)
}

impl Growth {
    /// The paper's algorithm: picks uniformly random surface sites, one per timestep, and
    /// accepts a pick if `R < p`. Returns at the first acceptance or when the clock reaches
    /// `limit`.
    pub fn step_rejection(&mut self, rng: &mut Stream, limit: f64) -> Outcome {
        let uniform = self.weight.is_uniform();
        loop {
            if self.time >= limit {
                return Outcome::Limit;
            }
            let s = self.surface.len();
            if s == 0 {
                return Outcome::Exhausted;
            }
            self.time += 1.0;
            let slot = rng.random_range(0..s as u32) as usize;
            let cell = self.surface.site(slot) as usize;
            let b = super::state::b_of(self.cells[cell]) as usize;
            let mut p = self.rule.p(b);
            if !uniform {
                p *= self.weight.at(&self.lattice, cell).unwrap_or(0.0);
            }
            let r: f64 = rng.random();
            if r < p {
                self.occupy_unchecked(cell);
                self.accepted += 1;
                return Outcome::Accepted(cell);
            }
        }
    }

    /// One pick of the paper's algorithm, reported in full (for teaching): a uniformly random
    /// surface site, its `b` and `p = v (b/z)^n`, the draw `R` in [0, 1) and the verdict. The
    /// clock advances by one timestep. Consumes the random stream exactly as
    /// [`Growth::step_rejection`] does, so a run mixing the two is the same run. `None` when the
    /// surface is empty.
    pub fn pick_rejection(&mut self, rng: &mut Stream) -> Option<Pick> {
        let s = self.surface.len();
        if s == 0 {
            return None;
        }
        self.pending = None;
        self.far_ln_time = f64::NAN;
        self.time += 1.0;
        let slot = rng.random_range(0..s as u32) as usize;
        let cell = self.surface.site(slot) as usize;
        let b = super::state::b_of(self.cells[cell]) as usize;
        let v = if self.weight.is_uniform() {
            1.0
        } else {
            self.weight.at(&self.lattice, cell).unwrap_or(0.0)
        };
        let p = v * self.rule.p(b);
        let r: f64 = rng.random();
        let accepted = r < p;
        if accepted {
            self.occupy_unchecked(cell);
            self.accepted += 1;
        }
        Some(Pick {
            cell,
            b,
            z: self.lattice.z(),
            v,
            p,
            r: Some(r),
            accepted,
            skipped: 0.0,
            surface: s,
        })
    }

    /// One acceptance of the exact sampler, reported in full (for teaching): the accepted
    /// site with its `b`, `v` and `p`, and `skipped`, the number of rejected picks the
    /// rejection algorithm would have made first (drawn from their geometric law: the clock
    /// advances by `skipped + 1`, as in [`Growth::step_exact`], which this calls).
    /// `None` when nothing can be accepted (the surface is empty, every `p` is 0 or the clock
    /// overflowed).
    pub fn pick_exact(&mut self, rng: &mut Stream) -> Option<Pick> {
        let s = self.surface.len();
        let t0 = self.time;
        match self.step_exact(rng, f64::INFINITY) {
            Outcome::Accepted(cell) => {
                // b before the acceptance: the occupied neighbours now (occupying `cell`
                // changed no other cell's occupation).
                let b = self
                    .lattice
                    .neighbours(cell)
                    .filter(|&n| self.is_occupied(n))
                    .count();
                let v = self.weight.at(&self.lattice, cell).unwrap_or(0.0);
                Some(Pick {
                    cell,
                    b,
                    z: self.lattice.z(),
                    v,
                    p: v * self.rule.p(b),
                    r: None,
                    accepted: true,
                    skipped: self.time - t0 - 1.0,
                    surface: s,
                })
            }
            _ => None,
        }
    }

    /// Runs the rejection sampler until the clock reaches `limit` (or the surface empties).
    /// Faster than calling [`Growth::step_rejection`] per event when no per-event work is
    /// needed.
    pub fn run_rejection(&mut self, rng: &mut Stream, limit: f64) -> Outcome {
        self.run_rejection_until(rng, limit, u64::MAX)
    }

    /// As [`Growth::run_rejection`], and stops as soon as [`Growth::accepted`] reaches
    /// `accepted` (returning [`Outcome::Limit`]).
    pub fn run_rejection_until(&mut self, rng: &mut Stream, limit: f64, accepted: u64) -> Outcome {
        while self.accepted < accepted {
            match self.step_rejection(rng, limit) {
                Outcome::Accepted(_) => continue,
                o => return o,
            }
        }
        Outcome::Limit
    }

    /// The exact rejection-free sampler: draws the number of rejected picks and the accepted
    /// site directly. Returns at the acceptance, or moves the clock to `limit` if the next
    /// acceptance would come later.
    #[inline]
    pub fn step_exact(&mut self, rng: &mut Stream, limit: f64) -> Outcome {
        // The neighbourhood size as a constant, so that the loops over the classes unroll.
        match self.lattice.z() {
            4 => self.step_exact_z::<4>(rng, limit),
            6 => self.step_exact_z::<6>(rng, limit),
            _ => self.step_exact_z::<8>(rng, limit),
        }
    }

    /// [`Growth::step_exact`] for a neighbourhood of `Z` cells (`Z` = the lattice's `z`).
    // The class number b indexes several tables at once; plain index loops read best.
    #[allow(clippy::needless_range_loop)]
    #[inline(always)]
    fn step_exact_z<const Z: usize>(&mut self, rng: &mut Stream, limit: f64) -> Outcome {
        debug_assert_eq!(Z, self.lattice.z());
        let s = self.surface.len();
        if s == 0 {
            return Outcome::Exhausted;
        }
        // An unbounded run on a log clock goes on once its clock is past the largest f64.
        if self.time >= limit && (limit.is_finite() || self.log_clock.is_none()) {
            return Outcome::Limit;
        }
        if self.tree.is_none() && !self.weight.is_uniform() {
            self.build_weight_tree();
        }
        // Every site weighs the same at n = 0 (uniform v): the classes are of no use, and a
        // flat surface spares their upkeep; a pick is then one uniform slot of all.
        let uniform = self.tree.is_none() && self.rule.is_uniform();
        if uniform != self.surface.is_flat() {
            if uniform {
                self.flatten_surface();
            } else {
                self.partition_surface();
            }
        }
        if self.surface.is_flat() {
            return self.step_exact_flat(rng, limit);
        }
        if self.tree.is_none()
            && let Some(iw) = self.rule.int_weights().copied()
        {
            return self.step_exact_int::<Z>(rng, limit, s, &iw);
        }
        // Class masses m_b: count (uniform v) or sum of v (per-site weights), and the top
        // class (highest b with m_b > 0).
        let mut mass = [0.0f64; 9];
        let mut top = 0;
        match &self.tree {
            None => {
                // The classes lie highest first, so the top class is the number of classes
                // whose end is past slot 0 (no branch per class).
                top = (1..=Z)
                    .filter(|&b| self.surface.class_range(b).end > 0)
                    .count();
                for b in 1..=Z {
                    let len = self.surface.class_len(b);
                    // (u32 converts in one instruction; a lattice has < 2^28 cells)
                    mass[b] = f64::from(len as u32);
                }
            }
            Some(t) => {
                for b in 1..=Z {
                    let r = self.surface.class_range(b);
                    mass[b] = t.range_sum(r.start, r.end);
                    if mass[b] > 0.0 {
                        top = b;
                    }
                }
            }
        }
        if top == 0 {
            self.time = limit;
            return Outcome::Stalled;
        }
        // Weights relative to the top class: w_b = m_b (b/top)^n, w_top = m_top >= its
        // smallest v > 0, so the sum never underflows to 0.
        let mut w = [0.0f64; 9];
        let mut total = 0.0;
        let ratio = self.rule.ratio_row(top);
        // (over all Z classes: above the top both the mass and the ratio are 0, adding +0)
        for b in 1..=Z {
            w[b] = mass[b] * ratio[b];
            total += w[b];
        }
        // The time of the next acceptance: drawn now, or kept from a call that stopped at its
        // limit first (so that where a run pauses never changes what it does).
        let at = match self.pending.take() {
            Some(at) => at,
            None => {
                // P = total (top/z)^n / S, in the linear domain unless (top/z)^n underflows.
                // P = 1 (every pick accepted, e.g. n = 0) needs no draw.
                let p_top = self.rule.p(top);
                let mut ln_wait = None;
                let wait = if p_top > 1e-280 {
                    // (u32 converts in one instruction; a lattice has < 2^28 cells)
                    let p = total * p_top / f64::from(s as u32);
                    if p >= 1.0 {
                        0.0
                    } else {
                        rejected_picks_linear(p, rng.sample(Exp1))
                    }
                } else {
                    let e: f64 = rng.sample(Exp1);
                    let ln_p = total.ln() + self.rule.ln_p(top) - f64::from(s as u32).ln();
                    let w = rejected_picks(ln_p, e);
                    if w.is_infinite() {
                        ln_wait = Some(ln_rejected_picks(ln_p, e));
                    }
                    // The log of an acceptance time past the largest f64, kept for a run
                    // that pauses first (Growth::move_clock_to). (The linear branch's waits
                    // are below about 1e290 picks: its clock would pass the largest f64
                    // only after some 1e18 acceptances.)
                    if (self.time + w + 1.0).is_infinite() {
                        let lw = ln_wait.unwrap_or_else(|| (w + 1.0).ln());
                        self.far_ln_time = ln_add(self.time.ln(), lw);
                    }
                    w
                };
                self.acceptance_time(wait, ln_wait, limit)
            }
        };
        if let Some(stop) = self.move_clock_to(at, limit) {
            return stop;
        }
        // The site: its class with probability w_b / total, then a site of the class, uniform
        // (v = 1) or proportional to v (sum tree).
        let mut u = rng.random::<f64>() * total;
        let mut class = top;
        for b in (1..=top).rev() {
            if w[b] > 0.0 {
                class = b;
                if u < w[b] {
                    break;
                }
                u -= w[b];
            }
        }
        let r = self.surface.class_range(class);
        let slot = match &self.tree {
            // u is uniform in [0, w_b) = [0, count_b ratio_b): u / ratio_b is uniform over
            // the class's slots, so one draw picks both class and site.
            None => {
                // u / ratio_b as a product with the stored reciprocal where that is a normal
                // float: the division, about a dozen cycles, lay on the path from one event's
                // class counts to the next event's site (+3 to +5 % events per second at
                // n = 2 / 8 / 50). The two can differ in the last bit, which moves the floor
                // only for a u within an ulp of a slot's edge: the same law, and the same
                // runs wherever checked (performance_details.md, "The reciprocal").
                let inv = self.rule.inv_ratio(top, class);
                let k = if inv > 0.0 {
                    u * inv
                } else {
                    u / self.rule.ratio(top, class)
                };
                r.start + (k as i64 as usize).min(r.end - r.start - 1)
            }
            Some(t) => {
                let u: f64 = rng.random();
                // The class has positive mass, so a slot with v > 0 exists.
                t.select_in(r.start, r.end, u).unwrap_or(r.start)
            }
        };
        let cell = self.surface.site(slot) as usize;
        self.occupy_unchecked(cell);
        self.accepted += 1;
        Outcome::Accepted(cell)
    }

    /// [`Growth::step_exact`] with whole-number class weights (`v` uniform, `n` a whole number
    /// with `z^n` at most [`crate::growth::rule::MAX_INT_WEIGHT`]: [`Sticking::int_weights`]):
    /// the class masses `m_b b^n` are exact integers, so the total, the class and the site
    /// within it come from one uniform integer draw below the total, without rounding, and
    /// the sum of the masses is a chain of integer additions (one cycle each) where the
    /// floating-point weights' is a chain of additions of four cycles, on the path from one
    /// event's class counts to the next event's site. The acceptance probability of a pick,
    /// `P = sum_b m_b (b/z)^n / S`, and the wait are as in the general path.
    #[inline(always)]
    fn step_exact_int<const Z: usize>(
        &mut self,
        rng: &mut Stream,
        limit: f64,
        s: usize,
        iw: &[u64; 9],
    ) -> Outcome {
        let mut w = [0u64; 9];
        let mut total = 0u64;
        for b in 1..=Z {
            w[b] = self.surface.class_len(b) as u64 * iw[b];
            total += w[b];
        }
        if total == 0 {
            // (no site with b >= 1: every p is 0)
            self.time = limit;
            return Outcome::Stalled;
        }
        let at = match self.pending.take() {
            Some(at) => at,
            None => {
                // P = total / (z^n S); z^n = int_w[z], exact in f64 (at most 2^35), and the
                // total below 2^63 converts as an i64 (one instruction; as a u64, several)
                let p =
                    (total as i64) as f64 / (self.rule.int_weight_total() * f64::from(s as u32));
                let wait = if p >= 1.0 {
                    0.0
                } else {
                    rejected_picks_linear(p, rng.sample(Exp1))
                };
                self.acceptance_time(wait, None, limit)
            }
        };
        if let Some(stop) = self.move_clock_to(at, limit) {
            return stop;
        }
        // One uniform integer in [0, total): the class by its mass, the slot by the
        // remainder. Highest class first; an empty class (w = 0, r < 0 never) is passed over
        // without a test of its own, and r < total stops the walk at a class with w > 0.
        let mut r = rng.random_range(0..total);
        let mut class = 1;
        for b in (1..=Z).rev() {
            if r < w[b] {
                class = b;
                break;
            }
            r -= w[b];
        }
        let range = self.surface.class_range(class);
        let k = self.rule.int_quotient(r, class) as usize;
        let slot = range.start + k.min(range.end - range.start - 1);
        let cell = self.surface.site(slot) as usize;
        self.occupy_unchecked(cell);
        self.accepted += 1;
        Outcome::Accepted(cell)
    }

    /// [`Growth::step_exact`] on a flat surface (`n = 0`, uniform `v`: every pick is
    /// accepted): the clock moves by one timestep and the site is one uniform slot of all,
    /// with the random stream drawn as on a partitioned surface (one draw, no wait).
    #[inline(never)]
    fn step_exact_flat(&mut self, rng: &mut Stream, limit: f64) -> Outcome {
        let s = self.surface.len();
        let at = match self.pending.take() {
            Some(at) => at,
            // (every pick accepted: one timestep, so never past the largest f64 unless the
            // clock already is, and then limit-bound at the top of step_exact)
            None => self.acceptance_time(0.0, None, limit),
        };
        if let Some(stop) = self.move_clock_to(at, limit) {
            return stop;
        }
        let total = f64::from(s as u32);
        // (a draw below 1 times s stays below s: the slot is in range)
        let u = rng.random::<f64>() * total;
        let slot = (u as i64 as usize).min(s - 1);
        let cell = self.surface.site(slot) as usize;
        self.occupy_unchecked(cell);
        self.accepted += 1;
        Outcome::Accepted(cell)
    }

    /// The time of the next acceptance after `wait` rejected picks (`ln_wait`: its log where
    /// `wait` overflowed), keeping the log clock of an unbounded run that allows one: it goes
    /// on past the largest `f64`; otherwise the run stops there
    /// ([`Outcome::ClockOverflow`], from [`Growth::move_clock_to`]).
    #[inline(always)]
    fn acceptance_time(&mut self, wait: f64, ln_wait: Option<f64>, limit: f64) -> f64 {
        let at = self.time + wait + 1.0;
        if limit.is_infinite()
            && self.log_clock_allowed
            && (at.is_infinite() || self.log_clock.is_some())
        {
            let prev = self.log_clock.unwrap_or(self.time.ln());
            let lw = ln_wait.unwrap_or_else(|| (wait + 1.0).ln());
            self.log_clock = Some(ln_add(prev, lw));
        }
        at
    }

    /// Moves the clock to the next acceptance, at `at`; or says why the run stops first: the
    /// acceptance comes after `limit` (the run pauses at the limit and keeps `at` for its next
    /// call), or, in a run without a limit, the clock overflowed. An acceptance past the
    /// largest `f64` comes after every finite limit: such a run reaches its limit with
    /// nothing accepted, as the rejection sampler does (where it would take longer than any
    /// run can).
    #[inline(always)]
    fn move_clock_to(&mut self, at: f64, limit: f64) -> Option<Outcome> {
        if at.is_infinite() && self.log_clock.is_none() {
            if limit.is_finite() {
                self.pending = Some(at);
                self.time = limit;
                return Some(Outcome::Limit);
            }
            // (an acceptance kept by a pause, now without a limit: its log was kept too, and
            // the run goes on where a run that never paused would)
            let ln_at = std::mem::replace(&mut self.far_ln_time, f64::NAN);
            if !(self.log_clock_allowed && ln_at.is_finite()) {
                self.time = at;
                return Some(Outcome::ClockOverflow);
            }
            self.log_clock = Some(ln_at);
        }
        if at > limit {
            self.pending = Some(at);
            self.time = limit;
            return Some(Outcome::Limit);
        }
        self.time = at;
        None
    }

    /// Runs the exact sampler until the clock reaches `limit` (or the surface empties).
    pub fn run_exact(&mut self, rng: &mut Stream, limit: f64) -> Outcome {
        self.run_exact_until(rng, limit, u64::MAX)
    }

    /// As [`Growth::run_exact`], and stops as soon as [`Growth::accepted`] reaches `accepted`
    /// (returning [`Outcome::Limit`]). With `limit = inf` and
    /// [`Growth::allow_log_clock`] the clock may pass the largest `f64`: it goes on as a log
    /// clock ([`Growth::log10_time`]).
    pub fn run_exact_until(&mut self, rng: &mut Stream, limit: f64, accepted: u64) -> Outcome {
        // One loop per neighbourhood size, with the step inlined in it.
        match self.lattice.z() {
            4 => self.run_exact_until_z::<4>(rng, limit, accepted),
            6 => self.run_exact_until_z::<6>(rng, limit, accepted),
            _ => self.run_exact_until_z::<8>(rng, limit, accepted),
        }
    }

    /// [`Growth::run_exact_until`] for a neighbourhood of `Z` cells.
    fn run_exact_until_z<const Z: usize>(
        &mut self,
        rng: &mut Stream,
        limit: f64,
        accepted: u64,
    ) -> Outcome {
        while self.accepted < accepted {
            match self.step_exact_z::<Z>(rng, limit) {
                Outcome::Accepted(_) => continue,
                o => return o,
            }
        }
        Outcome::Limit
    }

    /// One synchronous CA timestep: every surface site with at least `b_min` occupied
    /// neighbours becomes occupied at once. Returns the number of cells added.
    pub fn step_ca(&mut self, b_min: usize) -> usize {
        let b_min = b_min.max(1);
        self.partition_surface();
        if b_min > self.lattice.z() {
            self.time += 1.0;
            return 0;
        }
        // Sites of class >= b_min are the leading slots of the surface array.
        let hi = self.surface.class_range(b_min).end;
        let chosen: Vec<u32> = self.surface.sites()[..hi].to_vec();
        for &c in &chosen {
            self.occupy_unchecked(c as usize);
        }
        self.time += 1.0;
        self.accepted += chosen.len() as u64;
        chosen.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::lattice::{Boundary, Lattice, Neighbourhood};
    use crate::engine::rng::stream;
    use crate::growth::rule::{Sticking, Weight};

    fn flame(n: f64, size: usize, weight: Weight, per_site: bool) -> Growth {
        let l = Lattice::new(Neighbourhood::Hex, size, size, Boundary::TORUS).unwrap();
        let mut g = Growth::new(l, Sticking::new(n, 6).unwrap(), weight, per_site).unwrap();
        let c = size as f64 / 2.0;
        g.occupy_where(|x, y| (x - c).abs() < 2.5 && (y - c * 0.866).abs() < 2.5);
        g
    }

    #[test]
    fn geometric_wait_has_the_right_law() {
        // Pr(K >= k) = (1-P)^k: check the mean (1-P)/P with e drawn from Exp(1).
        let mut rng = stream(7);
        for p in [0.9, 0.3, 0.01] {
            let m = 200_000;
            let mut sum = 0.0;
            let mut sum2 = 0.0;
            for _ in 0..m {
                let e: f64 = rng.sample(Exp1);
                let k = rejected_picks(f64::ln(p), e);
                sum += k;
                sum2 += k * k;
            }
            let mean = sum / m as f64;
            let var = sum2 / m as f64 - mean * mean;
            let expect = (1.0 - p) / p;
            let se = (var / m as f64).sqrt();
            assert!(
                (mean - expect).abs() < 5.0 * se,
                "p={p}: {mean} vs {expect}"
            );
        }
        assert_eq!(rejected_picks(0.0, 3.0), 0.0);
        // P = e^-1e5: the wait ~ e^1e5 overflows f64 and is reported as +inf.
        assert_eq!(rejected_picks(-1e5, 1.0), f64::INFINITY);
        // P = 1e-15 and 1e-300: wait = e / P, in both branches.
        let k = rejected_picks((1e-15f64).ln(), 2.0);
        assert!((k / 2e15 - 1.0).abs() < 1e-6);
        let k = rejected_picks((1e-300f64).ln(), 2.0);
        assert!((k / 2e300 - 1.0).abs() < 1e-9);
        let k = rejected_picks(-705.0, 1.0);
        assert!((k.ln() - 705.0).abs() < 1e-9);
        assert_eq!(rejected_picks(-800.0, 1.0), f64::INFINITY);
        // The linear form agrees with the log form.
        for p in [0.999, 0.5, 1e-3, 1e-12] {
            for e in [0.01, 1.0, 7.0] {
                let (a, b) = (rejected_picks_linear(p, e), rejected_picks(f64::ln(p), e));
                assert!((a - b).abs() <= 1.0 + 1e-9 * a, "{p} {e}: {a} {b}");
            }
        }
    }

    #[test]
    fn geometric_count_by_series_is_the_logarithms_count() {
        // Over the acceptance probabilities of flames (n >= 2: 0.1-0.2) and beyond, and
        // exponential draws: the series gives the logarithm's count, bit for bit, or declines.
        let mut rng = stream(11);
        let (mut given, mut declined) = (0u32, 0u32);
        for i in 0..200_000 {
            let p = if i % 2 == 0 {
                rng.random::<f64>() * 0.25
            } else {
                0.1 + 0.1 * rng.random::<f64>()
            };
            let e: f64 = rng.sample(Exp1);
            match geometric_count_by_series(p, e) {
                Some(k) => {
                    given += 1;
                    assert_eq!(k, rejected_picks_by_log(p, e), "p = {p}, e = {e}");
                }
                None => declined += 1,
            }
        }
        // The bracket declines rarely: about q (4/21) p^6 of the draws.
        assert!(
            declined < 200,
            "declined {declined} of {}",
            given + declined
        );
        // Draws that put e / r on a whole number: the series declines or agrees.
        for p in [0.01f64, 0.1, 0.2, 0.25] {
            let r = -(-p).ln_1p();
            for k in [1.0, 5.0, 37.0] {
                for e in [k * r, k * r * (1.0 + 1e-15), k * r * (1.0 - 1e-15)] {
                    if let Some(c) = geometric_count_by_series(p, e) {
                        assert_eq!(c, rejected_picks_by_log(p, e), "p = {p}, e = {e}");
                    }
                }
            }
        }
        // Out of its range it declines: p above 1/4, zero, NaN, or a count beyond 2^52.
        assert_eq!(geometric_count_by_series(0.3, 1.0), None);
        assert_eq!(geometric_count_by_series(0.0, 1.0), None);
        assert_eq!(geometric_count_by_series(f64::NAN, 1.0), None);
        assert_eq!(geometric_count_by_series(1e-17, 1.0), None);
    }

    #[test]
    fn rejected_picks_by_log_skips_the_logarithm_only_where_it_is_p() {
        // Below 2^-54, -ln(1 - p) rounds to p (the next term, p/2 relative, is under half an
        // ulp): the library's ln_1p returns it, so the count e / p taken without the call is
        // the logarithm's, bit for bit (n = 50 flames reach p of 1e-24 on a faceted front).
        assert_eq!(TINY_P, 2f64.powi(-54));
        let mut rng = stream(12);
        let below = |p: f64| p * (1.0 - f64::EPSILON);
        let mut ps = vec![below(TINY_P), 1e-20, 1e-100, 1e-300, f64::MIN_POSITIVE];
        ps.extend((0..100_000).map(|_| TINY_P * (-700.0 * rng.random::<f64>()).exp()));
        for p in ps {
            assert!(p < TINY_P);
            assert_eq!(-(-p).ln_1p(), p, "p = {p:e}");
            let e: f64 = rng.sample(Exp1);
            let k = e / p;
            let by_log = if k < 9.2e18 { (k as i64) as f64 } else { k };
            assert_eq!(rejected_picks_by_log(p, e), by_log, "p = {p:e}, e = {e}");
            assert_eq!(rejected_picks_linear(p, e), by_log, "p = {p:e}, e = {e}");
        }
        // The bound is on the safe side: ln_1p keeps returning p a little above 2^-54 (up to
        // about 2^-52.5), where the logarithm is still taken. Well above it the two differ,
        // and the count is the logarithm's.
        let p = 1e-8f64;
        assert_ne!(-(-p).ln_1p(), p);
        assert_eq!(rejected_picks_by_log(p, 1.0), (1.0 / -(-p).ln_1p()).floor());
    }

    #[test]
    fn exact_keeps_invariants_with_and_without_weights() {
        for (w, per) in [
            (Weight::Isotropic, false),
            (
                Weight::Axes {
                    centre: (10.0, 8.66),
                },
                true,
            ),
        ] {
            let mut g = flame(2.0, 20, w, per);
            let mut rng = stream(3);
            for _ in 0..150 {
                assert!(matches!(
                    g.step_exact(&mut rng, f64::INFINITY),
                    Outcome::Accepted(_)
                ));
            }
            g.check_invariants().unwrap();
        }
    }

    #[test]
    fn exact_at_n0_runs_flat_and_the_ca_sorts_the_classes_back() {
        let mut g = flame(0.0, 24, Weight::Isotropic, false);
        let mut rng = stream(5);
        for _ in 0..200 {
            assert!(matches!(
                g.step_exact(&mut rng, f64::INFINITY),
                Outcome::Accepted(_)
            ));
        }
        assert!(g.surface().is_flat());
        g.check_invariants().unwrap();
        // The CA needs the classes (its sites are the leading slots).
        let grown = g.step_ca(3);
        assert!(!g.surface().is_flat());
        g.check_invariants().unwrap();
        let want = g.surface().class_range(3).end;
        // A second CA step from the sorted surface adds what the classes say.
        assert_eq!(g.step_ca(3), want);
        assert!(grown > 0);
        // The rejection sampler runs on either; the exact one flattens again.
        g.run_rejection_until(&mut rng, f64::INFINITY, g.accepted() + 50);
        g.check_invariants().unwrap();
        g.run_exact_until(&mut rng, f64::INFINITY, g.accepted() + 50);
        assert!(g.surface().is_flat());
        g.check_invariants().unwrap();
        // n > 0 keeps the classes.
        let mut g = flame(2.0, 24, Weight::Isotropic, false);
        g.run_exact_until(&mut rng, f64::INFINITY, 100);
        assert!(!g.surface().is_flat());
    }

    #[test]
    fn value_stability_of_the_stream_and_samplers() {
        // Pins the random stream and both samplers' first events: a change here changes
        // every published run, and must be deliberate.
        let mut rng = stream(1);
        let first: [u64; 3] = [rng.random(), rng.random(), rng.random()];
        assert_eq!(
            first,
            [
                14971601782005023387,
                13781649495232077965,
                1847458086238483744
            ]
        );
        let mut g = flame(2.0, 16, Weight::Isotropic, false);
        let mut rng = stream(42);
        let ev: Vec<(f64, usize)> = (0..5)
            .map(|_| match g.step_exact(&mut rng, f64::INFINITY) {
                Outcome::Accepted(c) => (g.time(), c),
                o => panic!("{o:?}"),
            })
            .collect();
        assert_eq!(
            ev,
            vec![
                (11.0, 149),
                (26.0, 183),
                (40.0, 86),
                (43.0, 165),
                (45.0, 186),
            ],
            "exact events"
        );
        let mut g = flame(2.0, 16, Weight::Isotropic, false);
        let mut rng = stream(42);
        let ev: Vec<(f64, usize)> = (0..5)
            .map(|_| match g.step_rejection(&mut rng, f64::INFINITY) {
                Outcome::Accepted(c) => (g.time(), c),
                o => panic!("{o:?}"),
            })
            .collect();
        assert_eq!(
            ev,
            vec![(9.0, 86), (35.0, 88), (39.0, 87), (52.0, 89), (74.0, 71)],
            "rejection events"
        );
        // n = 0 on the flat surface: every pick accepted, one timestep each.
        let mut g = flame(0.0, 16, Weight::Isotropic, false);
        let mut rng = stream(42);
        let ev: Vec<usize> = (0..8)
            .map(|_| match g.step_exact(&mut rng, f64::INFINITY) {
                Outcome::Accepted(c) => c,
                o => panic!("{o:?}"),
            })
            .collect();
        assert_eq!(g.time(), 8.0);
        assert_eq!(
            ev,
            vec![107, 89, 74, 165, 73, 186, 86, 181],
            "exact events, n = 0"
        );
    }
}
