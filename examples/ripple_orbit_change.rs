//! Wave ripples grown under one orbit, then run under another: does the field follow the new
//! orbital diameter? A field is grown from the flat bed under waves of orbital diameter `D0A`
//! for `SECONDS_A`, and its column heights start a second run (`Ripple::from_heights`, fresh
//! grains and random stream) under `D0B` for `SECONDS_B`, reported at four times.
//!
//! The strips of the validation study: 0.3 mm sand, U_w = 0.4 m/s, period `pi d0 / U_w`, the
//! waves' friction factor and the lee vortex as the command line sets them, 512 x 8 bins of
//! 5 mm, 10 cm of sand.
//!
//! `cargo run --release --example ripple_orbit_change -- D0A SECONDS_A D0B SECONDS_B SEED`
//! (defaults 0.4 32000 0.2 32000 1; d0 in metres).

use cellsurf::ripple::{Analysis, Ripple, RippleParams};

/// Orbital velocity amplitude of the waves, m/s.
const UW: f64 = 0.4;

/// The strip's parameters under waves of orbital diameter `d0` (m), and its step duration (s).
fn strip(d0: f64, seed: u64) -> (RippleParams, f64) {
    let period_s = std::f64::consts::PI * d0 / UW;
    let mut p = RippleParams {
        nx: 512,
        ny: 8,
        layers: 200,
        d50: 0.3,
        current_speed: 0.0,
        wave_amplitude: UW,
        // provisional, in steps, until the step duration is known
        wave_period: 64.0,
        wave_vortex: d0 / 2.0,
        seed,
        ..RippleParams::default()
    };
    p.wave_friction_factor = cellsurf::ripple::waves::wave_friction_factor(UW, period_s, 0.3e-3);
    let clock = cellsurf::ripple::clock::StepClock::of(&p).expect("valid parameters");
    p.wave_period = period_s / clock.step_s;
    (p, clock.step_s)
}

fn report(phase: &str, r: &Ripple, seconds: f64) {
    let a = Analysis::of(r);
    println!(
        "{phase}, {seconds:.0} s: wavelength {:.1} cm, height {:.2} cm, ripple index {:.1}, symmetry index {:.2}, bare {:.3}",
        a.wavelength_m * 100.0,
        a.height_m * 100.0,
        a.ripple_index,
        a.symmetry_index,
        r.bare_fraction()
    );
}

/// Argument `i` of `a` (named `name`), `default` when absent; a value that does not parse, or
/// a length or duration that is not above 0, ends the program with a message naming it.
fn arg<T: std::str::FromStr + PartialOrd + Default + Copy>(
    a: &[String],
    i: usize,
    name: &str,
    default: T,
) -> T {
    let Some(s) = a.get(i) else {
        return default;
    };
    match s.parse::<T>() {
        Ok(v) if v > T::default() => v,
        _ => {
            eprintln!(
                "error: {name} = {s} is out of range: expected a number above 0 (usage: D0A SECONDS_A D0B SECONDS_B SEED)"
            );
            std::process::exit(2);
        }
    }
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let d0a = arg(&a, 0, "D0A", 0.4);
    let ta = arg(&a, 1, "SECONDS_A", 32000.0);
    let d0b = arg(&a, 2, "D0B", 0.2);
    let tb = arg(&a, 3, "SECONDS_B", 32000.0);
    let seed: u64 = arg(&a, 4, "SEED", 1);
    let (pa, dta) = strip(d0a, seed);
    let mut r = Ripple::new(&pa).expect("valid parameters");
    r.run((ta / dta).round() as u64, |_| {});
    report(&format!("d0 = {d0a} m"), &r, ta);
    let heights: Vec<usize> = r
        .volume()
        .heights()
        .iter()
        .map(|&h| usize::from(h))
        .collect();
    // another stream for the second run, so that it is not the first one's start replayed
    let (pb, dtb) = strip(d0b, seed + 1000);
    let mut r = Ripple::from_heights(&pb, &heights).expect("valid parameters");
    for i in 1..=4 {
        r.run((tb / 4.0 / dtb).round() as u64, |_| {});
        report(&format!("then d0 = {d0b} m"), &r, tb * i as f64 / 4.0);
    }
}
