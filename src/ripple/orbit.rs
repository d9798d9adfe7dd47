//! Lengths in units of the waves' orbital excursion ([`RippleParams::with_orbit_scale`]): a
//! run with `orbit_reference` scales its bin, automata, grain travel and crest suspension's
//! length with the excursion amplitude of its waves, so that every length of the rules
//! follows the orbit (docs/ripple.md, "A recipe for mature wave ripples").

use super::params::RippleParams;

impl RippleParams {
    /// The factor `wave_vortex / orbit_reference` by which [`RippleParams::with_orbit_scale`]
    /// scales the run's lengths: `Some` where `orbit_reference` is set, the waves dominate
    /// and have the lee vortex (whose reach, `wave_vortex`, is their orbital excursion
    /// amplitude `A = U_w T / (2 pi)`); `None` otherwise.
    pub fn orbit_scale(&self) -> Option<f64> {
        (self.orbit_reference > 0.0
            && self.wave_vortex > 0.0
            && self.has_wave()
            && self.waves_dominate())
        .then(|| self.wave_vortex / self.orbit_reference)
    }

    /// These parameters with `bin_size`, `layer_thickness`, `hop_grains` and
    /// `crest_suspension` scaled by [`RippleParams::orbit_scale`] (to 10 significant digits)
    /// and `orbit_reference` set to the waves' excursion, so that applying it again changes
    /// nothing; themselves where there is no such scale. The depth of sand in layers is kept
    /// (its metres scale with the automata). [`super::Ripple::new`] and
    /// [`super::clock::StepClock::of`] run on these.
    pub fn with_orbit_scale(&self) -> RippleParams {
        match self.orbit_scale() {
            Some(s) if s != 1.0 => RippleParams {
                bin_size: digits(self.bin_size * s),
                layer_thickness: digits(self.layer_thickness * s),
                hop_grains: digits(self.hop_grains * s),
                crest_suspension: digits(self.crest_suspension * s),
                orbit_reference: self.wave_vortex,
                ..self.clone()
            },
            _ => self.clone(),
        }
    }
}

/// `v` to 10 significant digits (as if typed so).
fn digits(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    format!("{v:.9e}").parse().unwrap_or(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Waves alone of 0.4 m/s with the lee vortex of excursion `a` (m), the lengths of the
    /// recipe for mature wave ripples at `A = 0.125 m`.
    fn waves(a: f64) -> RippleParams {
        RippleParams {
            current_speed: 0.0,
            wave_amplitude: 0.4,
            wave_period: 64.0,
            wave_friction_factor: 0.015,
            wave_vortex: a,
            orbit_reference: 0.125,
            bin_size: 0.0025,
            layer_thickness: 0.00025,
            hop_grains: 4.6875,
            crest_suspension: 0.0125,
            ..RippleParams::default()
        }
    }

    /// Every length of the rules follows the excursion: twice the orbit, twice the bin,
    /// automata, travel and crest height; applying it again changes nothing.
    #[test]
    fn lengths_scale_with_the_orbital_excursion() {
        let p = waves(0.1).with_orbit_scale();
        assert_eq!(
            (
                p.bin_size,
                p.layer_thickness,
                p.hop_grains,
                p.crest_suspension
            ),
            (0.002, 0.0002, 3.75, 0.01)
        );
        assert_eq!((p.orbit_reference, p.layers), (0.1, waves(0.1).layers));
        assert_eq!(p.with_orbit_scale(), p);
        let q = waves(0.2).with_orbit_scale();
        assert_eq!(
            (q.bin_size, q.hop_grains, q.crest_suspension),
            (0.004, 7.5, 0.02)
        );
        // at the reference itself, nothing changes
        assert_eq!(waves(0.125).with_orbit_scale(), waves(0.125));
    }

    /// No scale without the key, without the vortex, or where the current dominates.
    #[test]
    fn no_orbit_scale_without_the_key_the_vortex_or_dominant_waves() {
        let off = RippleParams {
            orbit_reference: 0.0,
            ..waves(0.1)
        };
        assert_eq!(off.orbit_scale(), None);
        assert_eq!(off.with_orbit_scale(), off);
        let no_vortex = RippleParams {
            wave_vortex: 0.0,
            ..waves(0.1)
        };
        assert_eq!(no_vortex.orbit_scale(), None);
        let current = RippleParams {
            current_speed: 0.9,
            wave_amplitude: 0.1,
            ..waves(0.1)
        };
        assert!(!current.waves_dominate());
        assert_eq!(current.orbit_scale(), None);
        assert_eq!(waves(0.1).orbit_scale(), Some(0.8));
    }
}
