//! [`Flow`] and [`WaterVolume`]: the free-stream flow of a step and the sliced water volume of
//! the paper's Sect. 2.3, which decides which grains are exposed and how fast the water is at
//! the bed.
//!
//! **Flow.** The free-stream velocity at step `t` is, for a current or waves alone, `(U_c + U_w
//! sin(2 pi t / T))` along `current_angle` (on the lattice: less the frame's angle,
//! [`RippleParams::frame_angle`]): a steady current `U_c`, or an oscillating (wave) component
//! of amplitude `U_w` and period `T` steps (for the bed stress, `U_w sqrt(f_w / (2 C_D))` when the run
//! has a wave friction factor: [`RippleParams::wave_stress_amplitude`]), waves alone along their
//! own `wave_angle` where they have one. When it is negative the flow runs
//! the other way (angle + 180 deg), so a pure wave (`U_c = 0`) pushes equally both ways and
//! gives symmetric ripples. With both a current and waves, their bed stresses add as vectors,
//! the current's raised by the waves (R. L. Soulsby (1997), *Dynamics of Marine Sands*, Eqs.
//! 69-70 phase by phase: [`RippleParams::combined_flow`]), and the flow of the step is the
//! speed that rubs the bed as hard, along that stress.
//!
//! **Slices** ([`crate::ripple::Abstraction::Slices`]). The water above the bed is cut into
//! horizontal slices `slice_layers` automata thick; slice `j` lies at level `z_j = j x
//! slice_layers`. A slice is obstructed at a column whose sand rises above `z_j`. Behind an
//! obstruction rising `e` slices above it (e = ceil((H - z_j) / slice_layers)), the slice's
//! speed is zero over `shadow_length x e` bins and then recovers linearly over
//! `recovery_length x e` bins ("depending on the height of the crest ... the water flow will
//! pick up speed again closer or further behind the crest"). The paper's drag ("every
//! hydrodynamic slice drags the underlying slice with a predefined delay in the space domain")
//! is that recovery: the run's `drag_delay` is the recovery length per slice
//! ([`WaterVolume::new`]; 0, no delay, recovers at once). The bed speed of a column is the
//! speed of the lowest slice at or above its surface; zero means the column is in the current
//! shadow.
//!
//! The water volume is a deterministic function of the bed, so it is evaluated lazily, for the
//! column being asked about, from the bed as it is at that moment (looking upstream along the
//! flow as far as the shadow and recovery of the tallest crest reach, at most once around the
//! torus): this is the paper's "recomputed after each step" in its
//! asynchronous limit, and it keeps a step's cost proportional to its activations.
//! [`WaterVolume::section`] computes the whole sliced field of a row for figures.

use std::f64::consts::PI;

use strength_reduce::StrengthReducedU32;

use super::params::RippleParams;

/// The upstream offsets a [`Flow`] tabulates, bins; further upstream they are computed as
/// needed (the look-up itself reaches as far as the tallest crest's shadow and recovery,
/// up to once around the torus).
pub const MAX_REACH: usize = 64;

/// The speed of the lee vortex of a wave ripple as a fraction of the water's: the vortex
/// rolls up in the shear layer between the moving water and the still water behind the
/// crest, whose large eddies travel at the mean of the two speeds, `(U + 0) / 2` (G. L. Brown
/// and A. Roshko (1974), "On density effects and large structure in turbulent mixing
/// layers", *J. Fluid Mech.* 64(4), 775-816, <https://doi.org/10.1017/S002211207400190X>).
/// So the vortex, and the shelter behind the crest, reach half as far as the water has
/// travelled since the flow reversed: at most the excursion amplitude `A`, at the end of a
/// half cycle.
pub const VORTEX_CONVECTION: f64 = 0.5;

/// The free-stream flow during one step.
#[derive(Clone, Debug)]
pub struct Flow {
    /// Free-stream speed, m/s (>= 0).
    pub speed: f64,
    /// Direction the water flows towards, radians counter-clockwise from +x.
    pub angle: f64,
    /// The direction in Moore octants (0 = +x, 1 = +x+y, ..., in [0, 8)).
    pub octant: f64,
    /// Offsets (dx, dy) of the points 1..=MAX_REACH bins upstream.
    pub upstream: Vec<(i32, i32)>,
    /// Whether the flow runs along the rows (the point `k` bins upstream at `(-k, 0)` when
    /// `Some(true)`, at `(k, 0)` when `Some(false)`, for every `k`): a flow at exactly 0 or
    /// 180 deg on the lattice (2-D sections; in 3-D a current along the x axis, as in the
    /// flow frame, alone or with waves along it), whose upstream look-up then scans a row
    /// ([`WaterVolume::speed_at_level`]); `None` for any other direction. Set by
    /// [`Flow::at`] from `upstream`: a flow whose offsets are changed by hand sets it to `None`
    /// (always correct, by offsets) or to what the new offsets are.
    pub along_row: Option<bool>,
    /// The lee vortex of wave ripples (`wave_vortex`, where the waves dominate): how far the
    /// vortex has travelled since the flow last reversed, [`VORTEX_CONVECTION`] times the
    /// water's travel `A (1 - cos psi)`, in bins (at least 1), beyond which no crest shelters
    /// the bed; `None` without the vortex rule.
    pub vortex_reach: Option<usize>,
}

impl Flow {
    /// The flow at step `t` (2-D mode keeps it along +-x).
    pub fn at(p: &RippleParams, t: u64, two_d: bool) -> Flow {
        let phase = if p.wave_period > 0.0 {
            (2.0 * PI * (t as f64 + 0.5) / p.wave_period).sin()
        } else {
            0.0
        };
        // 2-D: the section runs along the current, towards +x (0 deg) or -x (180 deg).
        let base = if two_d {
            if p.section_forward() { 0.0 } else { PI }
        } else {
            p.lattice_current_angle().to_radians()
        };
        let wave_angle = p.lattice_wave_angle().filter(|_| !two_d);
        let (v, angle) = if p.current_speed > 0.0 && p.has_wave() {
            // current and waves: their stresses add (Soulsby's Eqs. 69-70, phase by phase)
            let wa = wave_angle.map_or(base, f64::to_radians);
            let (ux, uy) = p.combined_flow(base, wa, phase);
            // along the current's axis the flow keeps its sign, as a current or waves alone
            if wave_angle.is_none() {
                let along = ux * base.cos() + uy * base.sin();
                (along, if along < 0.0 { base + PI } else { base })
            } else {
                (ux.hypot(uy), uy.atan2(ux))
            }
        } else {
            let wave = if p.wave_period > 0.0 {
                p.wave_stress_amplitude() * phase
            } else {
                0.0
            };
            let v = p.current_speed + wave;
            match wave_angle {
                // waves alone at their own angle (no current)
                Some(wa) => {
                    let wa = wa.to_radians();
                    let ux = p.current_speed * base.cos() + wave * wa.cos();
                    let uy = p.current_speed * base.sin() + wave * wa.sin();
                    (ux.hypot(uy), uy.atan2(ux))
                }
                None => (v, if v < 0.0 { base + PI } else { base }),
            }
        };
        let angle = angle.rem_euclid(2.0 * PI);
        let octant = (angle / (PI / 4.0)).rem_euclid(8.0);
        let (c, s) = (angle.cos(), angle.sin());
        let upstream = (1..=MAX_REACH)
            .map(|k| {
                let dx = (-(k as f64) * c).round() as i32;
                let dy = if two_d {
                    0
                } else {
                    (-(k as f64) * s).round() as i32
                };
                (dx, dy)
            })
            .collect::<Vec<_>>();
        // (cos 180 deg is -1 exactly and sin 180 deg rounds to 0 at any reach, so the
        // offsets beyond the table follow the row too)
        let along_row = if (two_d || angle == 0.0 || angle == PI) && c.abs() == 1.0 {
            let forward = c > 0.0;
            let step = if forward { -1 } else { 1 };
            let on_row = upstream
                .iter()
                .zip(1..)
                .all(|(&o, k): (&(i32, i32), i32)| o == (step * k, 0));
            on_row.then_some(forward)
        } else {
            None
        };
        let vortex_reach =
            (p.wave_vortex > 0.0 && p.wave_period > 0.0 && p.waves_dominate()).then(|| {
                let psi = (2.0 * PI * (t as f64 + 0.5) / p.wave_period).rem_euclid(PI);
                let x = VORTEX_CONVECTION * p.wave_vortex * (1.0 - psi.cos()) / p.bin_size;
                (x.round() as usize).max(1)
            });
        Flow {
            speed: v.abs(),
            angle,
            octant,
            upstream,
            along_row,
            vortex_reach,
        }
    }
}

/// The offset (dx, dy) of the point `k + 1` bins upstream along `flow`, `(c, sn)` the cosine
/// and sine of its angle: tabulated up to [`MAX_REACH`], rounded beyond.
#[inline(always)]
fn upstream_offset(flow: &Flow, k: usize, c: f64, sn: f64) -> (i32, i32) {
    match flow.upstream.get(k) {
        Some(&o) => o,
        None => {
            let d = (k + 1) as f64;
            ((-d * c).round() as i32, (-d * sn).round() as i32)
        }
    }
}

/// The index of column (`x`, `y`) moved by `o`, wrapped on the `nxi` x `nyi` torus of row
/// length `nx`.
#[inline(always)]
fn wrapped(x: usize, y: usize, o: (i32, i32), nxi: i32, nyi: i32, nx: usize) -> usize {
    let mut xx = x as i32 + o.0;
    let mut yy = y as i32 + o.1;
    if xx < 0 || xx >= nxi {
        xx = xx.rem_euclid(nxi);
    }
    if yy < 0 || yy >= nyi {
        yy = yy.rem_euclid(nyi);
    }
    yy as usize * nx + xx as usize
}

/// `i mod n` for `i < 2 n`, without a division (the row scan looks at most once around its
/// row).
#[inline(always)]
fn wrap(i: usize, n: usize) -> usize {
    debug_assert!(i < 2 * n);
    if i >= n { i - n } else { i }
}

/// The index of the last element of `seg` above `base`.
#[inline]
fn last_above(seg: &[u16], base: u16) -> Option<usize> {
    seg.iter().rposition(|&h| h > base)
}

/// The index of the first element of `seg` above `base`.
#[inline]
fn first_above(seg: &[u16], base: u16) -> Option<usize> {
    seg.iter().position(|&h| h > base)
}

/// The sliced water volume's rules (Sect. 2.3).
#[derive(Clone, Copy, Debug)]
pub struct WaterVolume {
    /// Slice thickness, automata.
    pub(crate) slice_layers: usize,
    /// Zero-speed length per slice of obstruction, bins.
    pub(crate) shadow_length: usize,
    /// Recovery length per slice of obstruction, bins (the run's `drag_delay`).
    pub(crate) recovery_length: usize,
    /// Flow separation (the run's `separation_angle`), `tan(angle) bin / layer_thickness`: an
    /// obstruction shelters only where the bed drops behind it by at least this many automata
    /// per bin of the step to the next point downstream (in whole automata: [`Self::separation_drop`]);
    /// 0: every obstruction shelters.
    pub(crate) separation_slope: f64,
    /// `slice_layers`, strength-reduced: the look-up divides by it for every obstruction.
    slices: StrengthReducedU32,
    /// [`Self::separation_drop`] over one bin, the step between the points of a row.
    axial_drop: usize,
}

impl WaterVolume {
    /// The rules of a run.
    pub fn new(p: &RippleParams) -> Self {
        WaterVolume::with(
            p.slice_layers,
            p.shadow_length,
            // the drag between slices is what brings a slice back up to speed (Sect. 2.3)
            p.drag_delay,
            if p.separation_angle > 0.0 {
                p.separation_angle.to_radians().tan() * p.bin_size / p.layer_thickness
            } else {
                0.0
            },
        )
    }

    /// The rules from their values: `slice_layers`, the slice thickness (automata, at least
    /// 1); `shadow_length`, the zero-speed length per slice of obstruction (bins);
    /// `recovery_length`, the recovery length per slice (bins, the run's `drag_delay`);
    /// `separation_slope`, the flow separation's drop (automata per bin, 0: every obstruction
    /// shelters), as the fields document them. The rules are fixed once built (the look-up
    /// keeps values worked out from them).
    pub fn with(
        slice_layers: usize,
        shadow_length: usize,
        recovery_length: usize,
        separation_slope: f64,
    ) -> Self {
        assert!(
            (1..=u32::MAX as usize).contains(&slice_layers),
            "slice_layers = {slice_layers}: expected at least 1"
        );
        let mut w = WaterVolume {
            slice_layers,
            shadow_length,
            recovery_length,
            separation_slope,
            slices: StrengthReducedU32::new(slice_layers as u32),
            axial_drop: 1,
        };
        w.axial_drop = w.separation_drop(1.0);
        w
    }

    /// The slice thickness, automata.
    pub fn slice_layers(&self) -> usize {
        self.slice_layers
    }

    /// `ceil(a / slice_layers)`: the slices an obstruction `a` automata above a slice's level
    /// rises over it.
    #[inline(always)]
    fn slices_over(&self, a: usize) -> usize {
        match u32::try_from(a) {
            Ok(a) => {
                let (q, r) = StrengthReducedU32::div_rem(a, self.slices);
                q as usize + usize::from(r > 0)
            }
            Err(_) => a.div_ceil(self.slice_layers),
        }
    }

    /// The least drop, in whole automata, behind an obstruction over a step of `len` bins
    /// downstream for the flow to separate there: `ceil(separation_slope x len)` (with a small
    /// margin, so that an angle whose drop is a whole number of automata asks for that number
    /// and not one more), at least 1.
    #[inline]
    pub fn separation_drop(&self, len: f64) -> usize {
        (self.separation_slope * len - 1e-9).ceil().max(1.0) as usize
    }

    /// Speed fraction of a slice at distance `d` bins behind an obstruction `e` slices high.
    #[inline]
    fn ramp(&self, d: usize, e: usize) -> f64 {
        let zero = self.shadow_length * e;
        if d <= zero {
            return 0.0;
        }
        let rec = (self.recovery_length * e) as f64 + 1.0;
        ((d - zero) as f64 / rec).min(1.0)
    }

    /// Fraction (0..=1) of the free-stream speed at the bed of column (`x`, `y`) on a grid of
    /// `nx` x `ny` columns with `heights`, under `flow`. Zero: the column is in the current
    /// shadow.
    #[allow(clippy::too_many_arguments)]
    pub fn bed_speed(
        &self,
        heights: &[u16],
        nx: usize,
        ny: usize,
        x: usize,
        y: usize,
        hmax_bound: usize,
        flow: &Flow,
    ) -> f64 {
        let h0 = heights[y * nx + x] as usize;
        self.speed_at_level(heights, nx, ny, x, y, h0, hmax_bound, flow)
    }

    /// Fraction of the free-stream speed in the lowest slice at or above level `level`
    /// (automata) over column (`x`, `y`); `hmax_bound` is an upper bound of the bed's heights
    /// (it limits how far upstream to look).
    #[allow(clippy::too_many_arguments)]
    pub fn speed_at_level(
        &self,
        heights: &[u16],
        nx: usize,
        ny: usize,
        x: usize,
        y: usize,
        level: usize,
        hmax_bound: usize,
        flow: &Flow,
    ) -> f64 {
        let t = self.slice_layers;
        let j0 = self.slices_over(level);
        // Only obstructions up to `hmax_bound` exist, so nothing further upstream than
        // (shadow + recovery) x (slices between the level and hmax_bound) matters.
        let e_bound = self.slices_over(hmax_bound.saturating_sub(j0 * t));
        let per = self.shadow_length + self.recovery_length;
        // Looking further than once around the torus would only meet the same columns again.
        let reach = (per * e_bound + 1)
            .min(nx + ny)
            .min(flow.vortex_reach.unwrap_or(usize::MAX));
        if let Some(forward) = flow.along_row {
            // along a row, once around it: further on the same columns come again, each
            // farther off, so sheltering less (a ramp only grows with the distance)
            let row = &heights[y * nx..(y + 1) * nx];
            return self.speed_along_row(row, x, j0 * t, reach.min(nx), forward);
        }
        let (nxi, nyi) = (nx as i32, ny as i32);
        let (c, sn) = (flow.angle.cos(), flow.angle.sin());
        let reach_of = |e: usize| (self.shadow_length + self.recovery_length) * e;
        let mut s: f64 = 1.0;
        // Each upstream column that rises above the level obstructs the bed's slice (level
        // j0 t) at distance k + 1, e0 = ceil((h - j0 t) / t) slices high.
        for k in 0..reach {
            let o = upstream_offset(flow, k, c, sn);
            let h = heights[wrapped(x, y, o, nxi, nyi, nx)] as usize;
            if h <= j0 * t {
                continue;
            }
            // With flow separation (opt-in), only a drop of at least `separation_drop` automata
            // over the step to the next point downstream shelters (the same point twice, on a
            // digital line, is no drop).
            if self.separation_slope > 0.0 {
                let on = match k {
                    0 => (0, 0),
                    _ => upstream_offset(flow, k - 1, c, sn),
                };
                let below = heights[wrapped(x, y, on, nxi, nyi, nx)] as usize;
                let len = f64::from(o.0 - on.0).hypot(f64::from(o.1 - on.1));
                if h < below + self.separation_drop(len) {
                    continue;
                }
            }
            let e0 = self.slices_over(h - j0 * t);
            // The bed slice is within this obstruction's zero-speed zone.
            if k < self.shadow_length * e0 {
                return 0.0;
            }
            let k = k + 1;
            if k <= reach_of(e0) {
                s = s.min(self.ramp(k, e0));
            }
            if s == 0.0 {
                return 0.0;
            }
        }
        s
    }

    /// [`Self::speed_at_level`] where the flow runs along the row (`forward`: towards +x):
    /// the same look-up over the `reach` (at most the row's length) points upstream of column
    /// `x` of `row`, for the slice at level `base` automata, each stretch of the row up to the
    /// next column that rises above the slice passed in one search ([`last_above`],
    /// [`first_above`]).
    fn speed_along_row(
        &self,
        row: &[u16],
        x: usize,
        base: usize,
        reach: usize,
        forward: bool,
    ) -> f64 {
        let nx = row.len();
        let Ok(base16) = u16::try_from(base) else {
            return 1.0; // nothing rises above the slice
        };
        // every step to the next point downstream is one bin long: the separation drop over
        // one bin, worked out with the rules
        debug_assert!(reach <= nx);
        let drop = (self.separation_slope > 0.0).then_some(self.axial_drop);
        let mut s: f64 = 1.0;
        let mut k = 0;
        while k < reach {
            // the point k + 1 bins upstream, and the stretch of the row from it that runs
            // upstream without wrapping
            let (p, hit) = if forward {
                let p = wrap(x + nx - 1 - k, nx);
                let run = (reach - k).min(p + 1);
                match last_above(&row[p + 1 - run..=p], base16) {
                    None => {
                        k += run;
                        continue;
                    }
                    Some(i) => (p + 1 - run + i, p - (p + 1 - run + i)),
                }
            } else {
                let p = wrap(x + 1 + k, nx);
                let run = (reach - k).min(nx - p);
                match first_above(&row[p..p + run], base16) {
                    None => {
                        k += run;
                        continue;
                    }
                    Some(i) => (p + i, i),
                }
            };
            k += hit;
            let h = row[p] as usize;
            if let Some(drop) = drop {
                // the next point downstream (k = 0: the bed's own column)
                let on = if forward {
                    wrap(p + 1, nx)
                } else {
                    wrap(p + nx - 1, nx)
                };
                if h < row[on] as usize + drop {
                    k += 1;
                    continue;
                }
            }
            let e0 = self.slices_over(h - base);
            if k < self.shadow_length * e0 {
                return 0.0;
            }
            let d = k + 1;
            if d <= (self.shadow_length + self.recovery_length) * e0 {
                s = s.min(self.ramp(d, e0));
            }
            if s == 0.0 {
                return 0.0;
            }
            k += 1;
        }
        s
    }

    /// The speed fraction of every slice over row `y`: `out[j][x]` for slices `j` whose level
    /// is below `levels` automata (NaN inside the sand). For figures.
    pub fn section(
        &self,
        heights: &[u16],
        nx: usize,
        ny: usize,
        y: usize,
        levels: usize,
        flow: &Flow,
    ) -> Vec<Vec<f64>> {
        let t = self.slice_layers;
        let hb = heights.iter().copied().max().unwrap_or(0) as usize;
        (0..levels.div_ceil(t))
            .map(|j| {
                (0..nx)
                    .map(|x| {
                        let z = j * t;
                        if (heights[y * nx + x] as usize) > z {
                            f64::NAN
                        } else {
                            self.speed_at_level(heights, nx, ny, x, y, z, hb, flow)
                        }
                    })
                    .collect()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flow_x() -> Flow {
        let p = RippleParams::default();
        Flow::at(&p, 0, true)
    }

    #[test]
    fn slices_over_is_the_ceiling_of_the_quotient() {
        for t in (1..=64).chain([100, 4096]) {
            let w = WaterVolume::with(t, 1, 1, 0.0);
            for a in (0..5000).chain([65_535, 65_536, 1 << 33]) {
                assert_eq!(w.slices_over(a), a.div_ceil(t), "{a} / {t}");
            }
        }
        assert_eq!(wrap(4, 3), 1);
        assert_eq!(wrap(3, 3), 0);
        assert_eq!(wrap(2, 3), 2);
    }

    #[test]
    fn flat_bed_is_fully_exposed() {
        let w = WaterVolume::new(&RippleParams::default());
        let h = vec![10u16; 20];
        for x in 0..20 {
            assert_eq!(w.bed_speed(&h, 20, 1, x, 0, 10, &flow_x()), 1.0);
        }
    }

    /// Slices of one automaton, one bin of shadow and one of recovery per slice, over a 400-bin
    /// section at level 10 with a crest 100 slices high at x = 20.
    fn tall_crest() -> (WaterVolume, Vec<u16>, usize) {
        let w = WaterVolume::with(1, 1, 1, 0.0);
        let n = 400;
        let mut h = vec![10u16; n];
        h[20] = 110;
        (w, h, n)
    }

    #[test]
    fn sect_2_3_shadows_longer_than_the_tabulated_look_up_are_whole() {
        // a crest 100 slices above the bed: 100 bins of shadow, then 100 of recovery, far more
        // than the MAX_REACH offsets a Flow tabulates
        let (w, h, n) = tall_crest();
        let f = flow_x();
        let s = |x: usize| w.bed_speed(&h, n, 1, x, 0, 110, &f);
        const { assert!(100 > MAX_REACH) };
        assert_eq!(
            s(20 + 90),
            0.0,
            "90 bins behind: still in the 100-bin shadow"
        );
        assert_eq!(s(20 + 100), 0.0);
        let mid = s(20 + 150);
        assert!(
            mid > 0.3 && mid < 0.7,
            "half-way through the recovery: {mid}"
        );
        assert_eq!(s(20 + 250), 1.0, "recovered");
    }

    #[test]
    fn sect_2_3_zero_behind_a_crest_then_recovering() {
        let w = WaterVolume::with(1, 2, 2, 0.0);
        let mut h = vec![10u16; 40];
        h[5] = 12; // a crest two slices high
        let f = flow_x();
        let s: Vec<f64> = (0..40)
            .map(|x| w.bed_speed(&h, 40, 1, x, 0, 12, &f))
            .collect();
        assert_eq!(s[4], 1.0, "upstream of the crest");
        assert_eq!(s[6], 0.0);
        assert_eq!(s[9], 0.0, "shadow over 2 x 2 bins");
        assert!(s[10] > 0.0 && s[10] < 1.0, "recovering: {}", s[10]);
        assert_eq!(s[30], 1.0, "recovered");
        for x in 6..30 {
            assert!(s[x + 1] >= s[x], "monotone recovery");
        }
    }

    /// The bed's slice by its definition: every upstream obstruction at its distance, the
    /// slowest of their ramps.
    fn speed_by_slices(w: &WaterVolume, h: &[u16], x: usize, level: usize, f: &Flow) -> f64 {
        let t = w.slice_layers;
        let z = level.div_ceil(t) * t;
        let mut s: f64 = 1.0;
        let at = |dx: i32| h[(x as i32 + dx).rem_euclid(h.len() as i32) as usize] as usize;
        for (k, &(dx, _)) in f.upstream.iter().enumerate() {
            let hk = at(dx);
            // the next column downstream of the obstruction (k = 0: the bed's own)
            let below = at(if k == 0 { 0 } else { f.upstream[k - 1].0 });
            let separates = w.separation_slope == 0.0 || hk >= below + w.separation_drop(1.0);
            if hk > z && separates {
                s = s.min(w.ramp(k + 1, (hk - z).div_ceil(t)));
            }
        }
        s
    }

    #[test]
    fn sect_2_3_slices_agree_with_their_definition() {
        use rand::RngExt;
        let mut rng = crate::engine::rng::stream(5);
        let f = flow_x();
        let mut partial = 0;
        for case in 0..300 {
            let w = WaterVolume::with(
                1 + case % 3,
                case % 4,
                (case / 3) % 5,
                ((case / 15) % 4) as f64,
            );
            let nx = 90;
            let h: Vec<u16> = (0..nx).map(|_| rng.random_range(10..30)).collect();
            let hb = *h.iter().max().unwrap() as usize;
            for x in 0..nx {
                let level = h[x] as usize;
                let want = speed_by_slices(&w, &h, x, level, &f);
                let got = w.speed_at_level(&h, nx, 1, x, 0, level, hb, &f);
                assert_eq!(got, want, "{w:?} x {x}");
                partial += (got > 0.0 && got < 1.0) as usize;
            }
        }
        assert!(partial > 1000, "few recovering slices: {partial}");
    }

    /// The row scan of a flow along the rows ([`Flow::along_row`]) gives what the look-up by
    /// offsets gives, both ways along the row, wrapping, with and without separation, at the
    /// bed, above it and above every height, on any row of a field (a field many times longer
    /// across than along the flow: the look-up by offsets goes round the row many times),
    /// with heights near the most a column holds, and within a vortex's reach.
    #[test]
    fn the_row_scan_agrees_with_the_look_up_by_offsets() {
        use rand::RngExt;
        let mut rng = crate::engine::rng::stream(9);
        let forward = flow_x();
        assert_eq!(forward.along_row, Some(true));
        let mut backward = forward.clone();
        backward.angle = PI;
        backward.upstream = (1..=MAX_REACH as i32).map(|k| (k, 0)).collect();
        backward.along_row = Some(false);
        let mut compared = [0usize; 3];
        for case in 0..400 {
            let w = WaterVolume::with(
                1 + case % 6,
                case % 3,
                (case / 3) % 4,
                ((case / 12) % 3) as f64 * 0.7,
            );
            let nx = [7, 40, 150][case % 3];
            // rows of a field (3-D: the scan reads row y), some many times longer than wide
            let ny = [1, 3, 25][(case / 3) % 3];
            let y = rng.random_range(0..ny);
            // a low bed with a few crests, some near the highest height a column holds
            let floor = if case % 7 == 0 { 65_400 } else { 100 };
            let mut h: Vec<u16> = (0..nx * ny)
                .map(|_| rng.random_range(floor..floor + 4))
                .collect();
            for _ in 0..rng.random_range(0..5) * ny {
                let at = rng.random_range(0..nx * ny);
                h[at] = rng.random_range(floor + 4..floor + 80);
            }
            let hb = *h.iter().max().unwrap() as usize + rng.random_range(0..30);
            for flow in [&forward, &backward] {
                let mut by_offsets = flow.clone();
                by_offsets.along_row = None;
                let mut flow = flow.clone();
                if case % 5 == 0 {
                    let r = Some(rng.random_range(1..60));
                    (flow.vortex_reach, by_offsets.vortex_reach) = (r, r);
                }
                for x in 0..nx {
                    // at the bed, above it, and above every height (65,536 and more)
                    let level = h[y * nx + x] as usize + [0, 1, 7, 200][x % 4];
                    let want = w.speed_at_level(&h, nx, ny, x, y, level, hb, &by_offsets);
                    let got = w.speed_at_level(&h, nx, ny, x, y, level, hb, &flow);
                    assert_eq!(got, want, "{w:?} {nx} x {ny} row {y} x {x} level {level}");
                    compared[if got == 0.0 {
                        0
                    } else if got < 1.0 {
                        1
                    } else {
                        2
                    }] += 1;
                }
            }
        }
        assert!(compared.iter().all(|&n| n > 1000), "{compared:?}");
    }

    /// A flow along neither axis scans by offsets.
    #[test]
    fn only_flows_along_the_rows_scan_a_row() {
        let p = RippleParams::default();
        assert_eq!(Flow::at(&p, 0, true).along_row, Some(true));
        let grid = |current_angle: f64| RippleParams {
            current_angle,
            frame: super::super::params::Frame::Grid,
            ..RippleParams::default()
        };
        assert_eq!(Flow::at(&grid(30.0), 0, false).along_row, None);
        assert_eq!(Flow::at(&grid(90.0), 0, false).along_row, None);
        assert_eq!(Flow::at(&grid(180.0), 0, false).along_row, Some(false));
        assert_eq!(Flow::at(&grid(0.0), 0, false).along_row, Some(true));
        // the flow frame turns the lattice to the current
        let flow_frame = RippleParams {
            current_angle: 30.0,
            ..RippleParams::default()
        };
        assert_eq!(Flow::at(&flow_frame, 0, false).along_row, Some(true));
    }

    /// `separation_angle`: a bump whose lee drops less than the separation drop shelters
    /// nothing, a step that drops at least as much shelters as without the rule.
    #[test]
    fn flow_separation_only_behind_a_drop_of_the_separation_angle() {
        let f = flow_x();
        let p = RippleParams {
            separation_angle: 15.0,
            ..RippleParams::default()
        };
        let w = WaterVolume::new(&p);
        // tan(15 deg) x 5 mm / 0.5 mm = 2.68: a drop of 3 automata over a bin, 4 over a
        // diagonal step (3.79)
        assert_eq!(w.separation_drop(1.0), 3);
        assert_eq!(w.separation_drop(std::f64::consts::SQRT_2), 4);
        let off = WaterVolume::new(&RippleParams::default());
        assert_eq!(off.separation_slope, 0.0);
        // a bump 4 automata high at x = 10 whose lee steps down 2 automata per bin, and a step
        // 4 automata high at x = 30 that drops at once
        let mut h = vec![10u16; 60];
        h[10] = 14;
        h[11] = 12;
        h[30] = 14;
        let s = |w: &WaterVolume, x: usize| w.bed_speed(&h, 60, 1, x, 0, 14, &f);
        // behind the bump: sheltered without the rule (x = 12 is 2 bins behind its top), not
        // with it (each column drops 2 automata, less than 3)
        assert_eq!(s(&off, 12), 0.0);
        assert_eq!(s(&w, 12), 1.0);
        // behind the step: sheltered either way
        for x in 31..=32 {
            assert_eq!(s(&off, x), 0.0, "x {x}");
            assert_eq!(s(&w, x), 0.0, "x {x}");
        }
        // an angle whose drop is a whole number of automata asks for that number
        let q = RippleParams {
            separation_angle: 5.710593137499643, // atan(0.1): one automaton over a bin
            ..RippleParams::default()
        };
        assert_eq!(WaterVolume::new(&q).separation_drop(1.0), 1);
    }

    /// On a diagonal flow the step to the next point downstream is a diagonal of sqrt(2) bins,
    /// so a drop that separates the flow along an axis (3 automata at 15 deg) does not
    /// separate it there; 4 automata do.
    #[test]
    fn flow_separation_scales_with_the_diagonal_step() {
        let p = RippleParams {
            separation_angle: 15.0,
            current_angle: 45.0,
            frame: crate::ripple::Frame::Grid,
            ..RippleParams::default()
        };
        let f = Flow::at(&p, 0, false);
        let w = WaterVolume::new(&p);
        let n = 16;
        // the column (4, 4), and the bed's (5, 5), diagonally downstream of it, one step away
        let bed = |drop: u16| {
            let mut h = vec![20u16; n * n];
            h[4 * n + 4] = 20 + drop;
            h
        };
        for (drop, sheltered) in [(3, false), (4, true)] {
            let h = bed(drop);
            let s = w.bed_speed(&h, n, n, 5, 5, 20 + drop as usize, &f);
            assert_eq!(s == 0.0, sheltered, "drop {drop}: speed {s}");
        }
    }

    #[test]
    fn waves_at_their_own_angle_add_to_the_current_by_their_stresses() {
        let p = RippleParams {
            current_speed: 0.3,
            current_angle: 0.0,
            wave_amplitude: 0.4,
            wave_period: 8.0,
            wave_angle: Some(90.0),
            // the lattice's x axis east (in the flow frame it would follow the waves)
            frame: crate::ripple::Frame::Grid,
            ..RippleParams::default()
        };
        // stresses in units of rho_w C_D: the current's raised by the waves (Soulsby 1997,
        // Eq. 69), the waves' quadratic in their velocity, added as vectors
        let tm = 0.09 * (1.0 + 1.2 * (0.16f64 / (0.09 + 0.16)).powf(3.2));
        for t in 0..8u64 {
            let f = Flow::at(&p, t, false);
            let s = (2.0 * PI * (t as f64 + 0.5) / 8.0).sin();
            let tw = 0.16 * s * s.abs();
            assert!((f.speed - tm.hypot(tw).sqrt()).abs() < 1e-12, "{t}");
            assert!(
                (f.angle - tw.atan2(tm).rem_euclid(2.0 * PI)).abs() < 1e-12,
                "{t}"
            );
        }
        // along the current, the stresses' vector sum is the scalar one
        let q = RippleParams {
            wave_angle: Some(0.0),
            ..p.clone()
        };
        let r = RippleParams {
            wave_angle: None,
            ..p
        };
        for t in 0..8u64 {
            let (a, b) = (Flow::at(&q, t, false), Flow::at(&r, t, false));
            assert!((a.speed - b.speed).abs() < 1e-12 && (a.angle - b.angle).abs() < 1e-12);
        }
        // a 2-D section, forward (current east) and backward (current west): the stresses add
        // along it, and the flow reverses where the waves' stress exceeds the current's
        let tm = 0.09 * (1.0 + 1.2 * (0.25f64 / (0.09 + 0.25)).powf(3.2));
        let mut reversed = 0;
        for (current_angle, forward) in [(0.0, 0.0), (180.0, PI)] {
            let q = RippleParams {
                current_angle,
                wave_amplitude: 0.5,
                mode: crate::ripple::Mode::TwoD,
                frame: crate::ripple::Frame::Flow,
                ..r.clone()
            };
            for t in 0..8u64 {
                let s = (2.0 * PI * (t as f64 + 0.5) / 8.0).sin();
                let along = tm + 0.25 * s * s.abs();
                reversed += usize::from(along < 0.0);
                let f = Flow::at(&q, t, true);
                assert!((f.speed - along.abs().sqrt()).abs() < 1e-12, "{t}");
                let want = if along < 0.0 { forward + PI } else { forward };
                assert!((f.angle - want.rem_euclid(2.0 * PI)).abs() < 1e-12, "{t}");
                assert_eq!(f.along_row, Some(f.angle == 0.0), "{t}");
            }
        }
        // (two phases a cycle on each section)
        assert_eq!(reversed, 4);
    }

    #[test]
    fn vortex_reach_is_half_the_waters_travel_since_the_reversal() {
        // A = 0.05 m = 10 bins of 5 mm; a period of 40 steps: psi = 2 pi (t + 1/2) / 40 mod pi;
        // the vortex travels at half the water's speed: A (1 - cos psi) / 2 = 5 (1 - cos psi)
        let p = RippleParams {
            current_speed: 0.0,
            wave_amplitude: 0.4,
            wave_period: 40.0,
            wave_vortex: 0.05,
            ..RippleParams::default()
        };
        for t in 0..80u64 {
            let psi = (2.0 * PI * (t as f64 + 0.5) / 40.0).rem_euclid(PI);
            let want = ((5.0 * (1.0 - psi.cos())).round() as usize).max(1);
            assert_eq!(Flow::at(&p, t, true).vortex_reach, Some(want), "{t}");
        }
        // off without the vortex, and where the current dominates
        let off = RippleParams {
            wave_vortex: 0.0,
            ..p.clone()
        };
        assert_eq!(Flow::at(&off, 3, true).vortex_reach, None);
        let current = RippleParams {
            current_speed: 0.6,
            ..p.clone()
        };
        assert_eq!(Flow::at(&current, 3, true).vortex_reach, None);
        // a crest 100 slices high shelters 100 bins, but only as far as the water has gone
        let (w, h, n) = tall_crest();
        let mut f = Flow::at(&p, 0, true);
        f.vortex_reach = Some(15);
        assert_eq!(w.bed_speed(&h, n, 1, 20 + 15, 0, 110, &f), 0.0);
        assert_eq!(w.bed_speed(&h, n, 1, 20 + 16, 0, 110, &f), 1.0);
    }

    #[test]
    fn wave_reverses_the_flow() {
        let p = RippleParams {
            current_speed: 0.0,
            wave_amplitude: 0.4,
            wave_period: 10.0,
            ..RippleParams::default()
        };
        let a = Flow::at(&p, 1, false);
        let b = Flow::at(&p, 6, false);
        assert!((a.angle - 0.0).abs() < 1e-9);
        assert!((b.angle - PI).abs() < 1e-9);
        assert!((a.speed - b.speed).abs() < 1e-9);
    }
}
