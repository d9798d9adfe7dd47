//! The median grain's nominal flat-bed travel ([`median_travel`]), and the bin that a run
//! with `bin_travels` takes from it ([`RippleParams::travel_bin`],
//! [`RippleParams::with_travel_bin`]): a part of the travel, so that every grain and current
//! is resolved alike (docs/ripple.md, "A recipe for mature current ripples", "The bin").

use super::grain::theta_cr;
use super::params::RippleParams;
use super::regime::{bed_shear_stress, shields};

/// The median grain's mean travel on a flat bed of the run `p` in a free-stream flow of
/// `speed` m/s, metres: `hop x (theta / theta_cr - 1)` for `d50`
/// ([`RippleParams::hop_metres`]; `theta` from the quadratic friction law at `speed`, Soulsby
/// 1997, Eqs. 30 and 74; `theta_cr` of Eq. 77), 0 in a flow that does not move it. Crest
/// suspension's length in travels (`crest_suspension_hops`) and the bin of `bin_travels` are
/// multiples of it. (The calibration, [`super::clock::flat_bed_travel`], measures the travel
/// of every class on the lattice.)
pub fn median_travel(p: &RippleParams, speed: f64) -> f64 {
    let d = p.d50 * 1e-3;
    let theta = shields(bed_shear_stress(speed, p.drag_coefficient), d);
    (p.hop_metres(d) * (theta / theta_cr(d) - 1.0)).max(0.0)
}

impl RippleParams {
    /// The bin of a run with `bin_travels` ([`RippleParams::bin_travels`]): `bin_travels x`
    /// the median grain's nominal flat-bed travel in the current ([`median_travel`] at
    /// `current_speed`), m, to 3 significant digits, and at least [`RippleParams::finest_bin`]
    /// (near the threshold of motion the travel shrinks towards 0); `None` where the key is 0,
    /// there is no travel in metres, or the median grain does not move in the current.
    pub fn travel_bin(&self) -> Option<f64> {
        if self.bin_travels <= 0.0 || self.hop_grains <= 0.0 {
            return None;
        }
        let b = self.bin_travels * median_travel(self, self.current_speed);
        (b.is_finite() && b > 0.0).then(|| rounded_to(b, 3).max(self.finest_bin()))
    }

    /// The finest bin whose automata (following the bin, [`RippleParams::automata_for_bin`])
    /// hold this depth of sand, `layers x layer_thickness`, in at most 4096 layers, m, rounded
    /// up to 3 significant digits: the least bin of `bin_travels`.
    pub fn finest_bin(&self) -> f64 {
        let depth = self.layers as f64 * self.layer_thickness;
        let b = depth * self.bin_size / self.layer_thickness / (super::params::LAYERS.max as f64);
        let scale = 10f64.powi(2 - b.log10().floor() as i32);
        let up = (b * scale - 1e-9).ceil() / scale;
        format!("{up:.2e}").parse().unwrap_or(up)
    }

    /// These parameters on the bin of [`RippleParams::travel_bin`], the automata and layers
    /// following ([`RippleParams::automata_for_bin`]: the ratio of bin to automaton and the
    /// depth of sand kept); themselves where there is no such bin or it is already theirs.
    /// [`super::Ripple::new`] and [`super::clock::StepClock::of`] run on these.
    pub fn with_travel_bin(&self) -> RippleParams {
        match self.travel_bin() {
            Some(b) if b != self.bin_size => {
                let (t, layers) = self.automata_for_bin(b);
                RippleParams {
                    bin_size: b,
                    layer_thickness: t,
                    layers,
                    ..self.clone()
                }
            }
            _ => self.clone(),
        }
    }
}

/// A positive finite number to `digits` significant digits (as if typed so: `0.00186`).
fn rounded_to(v: f64, digits: i32) -> f64 {
    let scale = 10f64.powi(digits - 1 - v.log10().floor() as i32);
    let r = (v * scale).round() / scale;
    format!("{r:.e$e}", e = (digits - 1) as usize)
        .parse()
        .unwrap_or(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `bin_travels`: the bin is that many nominal flat-bed travels of the median grain in
    /// the current, `hop_grains x d50 x (theta / theta_cr - 1)`, to 3 significant digits; the
    /// automata follow (the ratio of bin to automaton and the depth of sand kept), once (the
    /// parameters on their bin are their own); the bin grows with the grain and the current;
    /// no bin where the grain does not move.
    #[test]
    fn bin_travels_sets_the_bin_from_the_travel() {
        let p = RippleParams {
            hop_grains: 4.6875,
            bin_size: 0.0025,
            layer_thickness: 0.00025,
            layers: 400,
            bin_travels: 0.75,
            ..RippleParams::default()
        };
        let travel = median_travel(&p, 0.5);
        let b = p.travel_bin().unwrap();
        assert!((b / (0.75 * travel) - 1.0).abs() < 5e-3, "{b} {travel}");
        assert_eq!(b, 0.00186);
        let q = p.with_travel_bin();
        assert_eq!(
            (q.bin_size, q.layer_thickness, q.layers),
            (0.00186, 0.000186, 538)
        );
        assert_eq!(q.with_travel_bin(), q);
        assert!(q.validate().is_ok());
        // grain and current: a longer travel, a coarser bin
        let bin = |d50: f64, u: f64| {
            RippleParams {
                d50,
                current_speed: u,
                ..p.clone()
            }
            .travel_bin()
        };
        assert!(bin(0.1, 0.5) < bin(0.2, 0.5) && bin(0.2, 0.5) < bin(0.4, 0.5));
        assert!(bin(0.2, 0.4) < bin(0.2, 0.5) && bin(0.2, 0.5) < bin(0.2, 0.65));
        assert_eq!(bin(0.2, 0.1), None);
        // near the threshold the travel shrinks: the bin stops at the finest that holds the
        // 10 cm of sand in 4096 layers (0.2 mm sand at 0.3 m/s: 0.75 travels are 0.219 mm)
        assert_eq!(p.finest_bin(), 0.000245);
        let gentle = RippleParams {
            current_speed: 0.3,
            ..p.clone()
        };
        assert!(0.75 * median_travel(&gentle, 0.3) < 0.000245);
        let g = gentle.with_travel_bin();
        assert_eq!((g.bin_size, g.layers), (0.000245, 4082));
        assert!(g.validate().is_ok());
        let still = RippleParams {
            current_speed: 0.1,
            ..p.clone()
        };
        assert_eq!(still.with_travel_bin(), still);
        // off: the bin is bin_size
        let off = RippleParams {
            bin_travels: 0.0,
            ..p.clone()
        };
        assert_eq!(
            (off.travel_bin(), off.with_travel_bin()),
            (None, off.clone())
        );
    }

    #[test]
    fn rounded_to_gives_significant_digits() {
        assert_eq!(rounded_to(0.001_855_4, 3), 0.00186);
        assert_eq!(rounded_to(0.002_509_9, 3), 0.00251);
        assert_eq!(rounded_to(123.45, 2), 120.0);
    }
}
