//! [`density_speed`]: bulk density, sound speed and acoustic impedance of each automaton
//! (paper Sect. 3.2; the paper gives no formula; the relations used are cited below).
//!
//! [`AcousticModel::Hamilton`] (default), from Hamilton & Bachman (1982), "Sound velocity and
//! related properties of marine sediments", J. Acoust. Soc. Am. 72, 1891-1904, and Wood (1930),
//! A Textbook of Sound:
//! - bulk density by the mixture rule `rho_B = eps rho_w + (1 - eps) rho_s`;
//! - sound speed from Hamilton & Bachman (1982)'s representative sand values by mean grain size
//!   Mz (phi): speed ratios 1.201, 1.152, 1.120, 1.086 at Mz 0.5, 2.5, 3.5, 4.5 (c_w = 1510 m/s),
//!   piecewise linear in Mz and clamped outside; their densities (2034, 1962, 1878, 1783 kg/m^3,
//!   rho_w = 1030) give, through the mixture rule, the porosity eps_HB(Mz) at which they were
//!   measured. The porosity correction scales that speed by Wood's (1930) speed ratio
//!   `c_Wood(eps) / c_Wood(eps_HB(Mz))` (`1/K = eps/K_w + (1-eps)/K_s`, `c = sqrt(K / rho_B)`,
//!   K_s = 36.6 GPa): a denser automaton is faster, a looser one slower, and at the measured
//!   porosity the speed is Hamilton & Bachman's;
//! - impedance `Z = rho_B c`.
//!
//! [`AcousticModel::AplUw`]: the APL-UW TR 9407 (1994) regressions of density and speed ratio on
//! Mz, an acoustic look-alike preset (as used by BELLHOP's grain-size bottom). It ignores
//! porosity: its "density" is an acoustic fit, not a bulk density.

use super::grain::{RHO_S, RHO_W};
use super::params::AcousticModel;

/// Sound speed in bottom water used by both presets, m/s (Hamilton & Bachman 1982).
pub const C_W: f64 = 1510.0;
/// Water density of Hamilton & Bachman's table, kg/m^3.
pub const RHO_W_HB: f64 = 1030.0;
/// Bulk modulus of quartz, Pa.
pub const K_S: f64 = 36.6e9;

/// Hamilton & Bachman (1982): (Mz, density kg/m^3, speed ratio).
pub const HAMILTON_BACHMAN: [(f64, f64, f64); 4] = [
    (0.5, 2034.0, 1.201),
    (2.5, 1962.0, 1.152),
    (3.5, 1878.0, 1.120),
    (4.5, 1783.0, 1.086),
];

fn interp(mz: f64, f: impl Fn(&(f64, f64, f64)) -> f64) -> f64 {
    let t = &HAMILTON_BACHMAN;
    if mz <= t[0].0 {
        return f(&t[0]);
    }
    for w in t.windows(2) {
        if mz <= w[1].0 {
            let s = (mz - w[0].0) / (w[1].0 - w[0].0);
            return f(&w[0]) * (1.0 - s) + f(&w[1]) * s;
        }
    }
    f(&t[3])
}

/// Bulk density by the mixture rule, kg/m^3.
pub fn mixture_density(eps: f64) -> f64 {
    eps * RHO_W + (1.0 - eps) * RHO_S
}

/// Wood's (1930) sound speed of a suspension of porosity `eps`, m/s.
pub fn wood_speed(eps: f64) -> f64 {
    let k_w = RHO_W_HB * C_W * C_W;
    let k = 1.0 / (eps / k_w + (1.0 - eps) / K_S);
    let rho = eps * RHO_W_HB + (1.0 - eps) * RHO_S;
    (k / rho).sqrt()
}

/// Hamilton & Bachman sound speed at Mz, corrected to porosity `eps` (module docs), m/s.
pub fn hamilton_speed(mz: f64, eps: f64) -> f64 {
    let ratio = interp(mz, |r| r.2);
    let rho_hb = interp(mz, |r| r.1);
    let eps_hb = (RHO_S - rho_hb) / (RHO_S - RHO_W_HB);
    ratio * C_W * wood_speed(eps) / wood_speed(eps_hb)
}

/// APL-UW TR 9407 density ratio at Mz (clamped to -1..5.3).
pub fn apl_uw_density_ratio(mz: f64) -> f64 {
    let m = mz.clamp(-1.0, 5.3);
    if m < 1.0 {
        0.007797 * m * m - 0.17057 * m + 2.3139
    } else {
        -0.0165406 * m * m * m + 0.2290201 * m * m - 1.1069031 * m + 3.0455
    }
}

/// APL-UW TR 9407 speed ratio at Mz (clamped to -1..5.3).
pub fn apl_uw_speed_ratio(mz: f64) -> f64 {
    let m = mz.clamp(-1.0, 5.3);
    if m < 1.0 {
        0.002709 * m * m - 0.056452 * m + 1.2778
    } else {
        -0.0014881 * m * m * m + 0.0213937 * m * m - 0.1382798 * m + 1.3425
    }
}

/// Density (kg/m^3) and sound speed (m/s) of an automaton of grain size `mz` (phi) and
/// porosity `eps` under `model`.
pub fn density_speed(model: AcousticModel, mz: f64, eps: f64) -> (f64, f64) {
    match model {
        AcousticModel::Hamilton => (mixture_density(eps), hamilton_speed(mz, eps)),
        AcousticModel::AplUw => (
            apl_uw_density_ratio(mz) * RHO_W,
            apl_uw_speed_ratio(mz) * C_W,
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hamilton_values_at_their_own_porosity() {
        for &(mz, rho, ratio) in &HAMILTON_BACHMAN {
            let eps = (RHO_S - rho) / (RHO_S - RHO_W_HB);
            assert!((hamilton_speed(mz, eps) / C_W - ratio).abs() < 1e-9);
        }
    }

    #[test]
    fn denser_is_faster_and_heavier() {
        assert!(hamilton_speed(2.0, 0.37) > hamilton_speed(2.0, 0.46));
        assert!(mixture_density(0.37) > mixture_density(0.46));
        assert!((mixture_density(0.4) - (0.4 * RHO_W + 0.6 * RHO_S)).abs() < 1e-9);
    }

    #[test]
    fn apl_uw_is_continuous_at_mz_1() {
        let a = apl_uw_density_ratio(0.999_999);
        let b = apl_uw_density_ratio(1.0);
        assert!((a - b).abs() < 1e-3);
        assert!((apl_uw_speed_ratio(0.999_999) - apl_uw_speed_ratio(1.0)).abs() < 1e-3);
    }
}
