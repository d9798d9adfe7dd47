//! [`GrainClasses`]: the grain-size classes of the automata and the flow's energy budget per
//! class.
//!
//! Grain sizes are normal in Krumbein phi (phi = -log2(d / 1 mm); Krumbein 1934),
//! i.e. log-normal in d, with median `d50` and standard deviation `sorting` (phi units). The
//! distribution is cut at +-4 sigma and binned into classes 0.125 phi wide (at most 255
//! classes); each automaton stores its class as a `u8`. Sorting 0 gives one class.
//!
//! The energy budget E_x of the paper (Eqs. 2-3) is taken from the excess Shields stage: the
//! bed shear stress `tau = rho_w C_D u^2` gives `theta = tau / ((rho_s - rho_w) g d)`, compared
//! with Soulsby's threshold `theta_cr(D*)` (Soulsby 1997, Dynamics of marine sands, Eqs. 75 and 77). A grain
//! with `theta > theta_cr` receives `E_x = m g' mu L (theta / theta_cr - 1)` with
//! `L = hop_length x bin_size`: in units of `m g'` (g' = g (s - 1) / s, buoyancy-reduced), the
//! budget is a flat-bed friction path. Because theta grows as 1/d faster than theta_cr falls,
//! fine grains receive a larger budget per unit mass and travel further (our reading: the paper gives the budget no formula).

use rand::RngExt;
use rand_distr::{Distribution, Normal};

use crate::engine::rng::Stream;

/// Gravity, m/s^2.
pub const G: f64 = 9.81;
/// Seawater density, kg/m^3 (Soulsby 1997, Sect. 2.1).
pub const RHO_W: f64 = 1027.0;
/// Quartz density, kg/m^3.
pub const RHO_S: f64 = 2650.0;
/// Kinematic viscosity of seawater, m^2/s.
pub const NU: f64 = 1.36e-6;
/// Width of a grain-size class, phi units.
pub const CLASS_WIDTH_PHI: f64 = 0.125;

/// Dimensionless grain size D* = d [g (s - 1) / nu^2]^(1/3) (Soulsby 1997, Eq. 75); `d` in m.
pub fn d_star(d: f64) -> f64 {
    let s = RHO_S / RHO_W;
    d * (G * (s - 1.0) / (NU * NU)).cbrt()
}

/// Threshold Shields parameter theta_cr = 0.30 / (1 + 1.2 D*) + 0.055 [1 - exp(-0.020 D*)]
/// (Soulsby 1997, Eq. 77); `d` in m.
pub fn theta_cr(d: f64) -> f64 {
    let ds = d_star(d);
    0.30 / (1.0 + 1.2 * ds) + 0.055 * (1.0 - (-0.020 * ds).exp())
}

/// The grain-size classes of a run.
#[derive(Clone, Debug)]
pub struct GrainClasses {
    /// phi of each class centre.
    pub phi: Vec<f64>,
    /// Diameter of each class centre, m.
    pub d: Vec<f64>,
    /// theta_cr of each class.
    pub theta_cr: Vec<f64>,
    /// Grain mass of each class, kg (a quartz sphere).
    pub mass: Vec<f64>,
    phi_lo: f64,
    phi50: f64,
    sigma: f64,
}

impl GrainClasses {
    /// Classes for median `d50_mm` (mm) and sorting `sigma_phi`.
    pub fn new(d50_mm: f64, sigma_phi: f64) -> Self {
        let phi50 = -d50_mm.log2();
        let half = (4.0 * sigma_phi / CLASS_WIDTH_PHI).ceil() as usize;
        let half = half.min(127);
        let n = 2 * half + 1;
        let phi_lo = phi50 - half as f64 * CLASS_WIDTH_PHI;
        let phi: Vec<f64> = (0..n)
            .map(|k| phi_lo + k as f64 * CLASS_WIDTH_PHI)
            .collect();
        let d: Vec<f64> = phi.iter().map(|p| 1e-3 * (-p).exp2()).collect();
        let theta_cr = d.iter().map(|&d| theta_cr(d)).collect();
        let mass = d
            .iter()
            .map(|&d| RHO_S * std::f64::consts::PI * d * d * d / 6.0)
            .collect();
        GrainClasses {
            phi,
            d,
            theta_cr,
            mass,
            phi_lo,
            phi50,
            sigma: sigma_phi,
        }
    }

    /// Number of classes.
    pub fn len(&self) -> usize {
        self.phi.len()
    }

    /// Always false: there is at least one class.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The class of phi (nearest class centre, clamped to the range).
    pub fn class_of_phi(&self, phi: f64) -> u8 {
        let k = ((phi - self.phi_lo) / CLASS_WIDTH_PHI).round();
        k.clamp(0.0, (self.len() - 1) as f64) as u8
    }

    /// Draws a class from the normal-in-phi distribution.
    pub fn sample(&self, rng: &mut Stream) -> u8 {
        if self.sigma == 0.0 {
            return 0;
        }
        let normal = Normal::new(self.phi50, self.sigma).expect("sigma is finite and > 0");
        let phi: f64 = normal.sample(rng);
        // Keep the cut at +-4 sigma symmetric: resample the rare tails uniformly in range.
        if (phi - self.phi50).abs() > 4.0 * self.sigma {
            return rng.random_range(0..self.len()) as u8;
        }
        self.class_of_phi(phi)
    }

    /// Shields stage excess `theta / theta_cr - 1` of class `k` under a bed speed `u` (m/s)
    /// with drag coefficient `cd`; negative below the threshold of motion.
    pub fn excess_stage(&self, k: u8, u: f64, cd: f64) -> f64 {
        let k = k as usize;
        let tau = RHO_W * cd * u * u;
        let theta = tau / ((RHO_S - RHO_W) * G * self.d[k]);
        theta / self.theta_cr[k] - 1.0
    }

    /// Whether a bed speed `u` (m/s) moves a grain of any class (a fully exposed bed moves at
    /// most the free-stream speed, so below this no grain can be activated).
    pub fn any_moves(&self, u: f64, cd: f64) -> bool {
        (0..self.len()).any(|k| self.excess_stage(k as u8, u, cd) > 0.0)
    }
}

/// Median (by count) grain diameter of class counts, mm, interpolated linearly in phi within
/// the median class (classes are 0.125 phi wide); NaN when empty.
pub fn median_d_mm(classes: &GrainClasses, counts: &[u64]) -> f64 {
    let total: u64 = counts.iter().sum();
    if total == 0 {
        return f64::NAN;
    }
    let half = total as f64 / 2.0;
    let mut acc = 0.0;
    for (k, &c) in counts.iter().enumerate() {
        let c = c as f64;
        if c > 0.0 && acc + c >= half {
            let frac = (half - acc) / c;
            let phi = classes.phi[k] - CLASS_WIDTH_PHI / 2.0 + frac * CLASS_WIDTH_PHI;
            let phi = if classes.len() == 1 {
                classes.phi[0]
            } else {
                phi
            };
            return (-phi).exp2();
        }
        acc += c;
    }
    classes.d[classes.len() - 1] * 1e3
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn soulsby_example_6_3() {
        // Soulsby (1997) Example 6.3: d = 200 um -> D* = 4.06, theta_cr = 0.0553 (s = 2.58 there).
        assert!((d_star(200e-6) - 4.06).abs() < 0.05);
        assert!((theta_cr(200e-6) - 0.0553).abs() < 0.001);
    }

    #[test]
    fn fine_grains_get_a_larger_stage() {
        let c = GrainClasses::new(0.2, 1.0);
        let fine = c.class_of_phi(3.3);
        let coarse = c.class_of_phi(1.3);
        assert!(c.excess_stage(fine, 0.5, 0.0025) > c.excess_stage(coarse, 0.5, 0.0025));
    }

    #[test]
    fn sorting_zero_gives_one_class() {
        let c = GrainClasses::new(0.2, 0.0);
        assert_eq!(c.len(), 1);
        assert!((c.d[0] - 0.2e-3).abs() < 1e-12);
    }

    #[test]
    fn samples_are_centred_on_d50() {
        let c = GrainClasses::new(0.25, 0.5);
        let mut rng = crate::engine::rng::stream(3);
        let mut counts = vec![0u64; c.len()];
        for _ in 0..20000 {
            counts[c.sample(&mut rng) as usize] += 1;
        }
        let d = median_d_mm(&c, &counts);
        assert!((d - 0.25).abs() < 0.01, "median {d}");
        assert_eq!(median_d_mm(&GrainClasses::new(0.2, 0.0), &[5]), 0.2);
    }
}
