//! Steps per second of the ripple model block by block, from the flat bed to mature ripples:
//! the per-step cost grows with the ripples (the sliced water looks further upstream behind
//! higher crests), so a rate measured on the first steps alone flatters it.
//!
//! `cargo run --release --example ripple_rate -- NX NY STEPS BLOCK [slices|shadow]`
//! (defaults 576 288 10000 1000 slices: the paper's 5,000,000 automata).

use std::time::Instant;

use cellsurf::ripple::{Abstraction, Analysis, Ripple, RippleParams};

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let num = |i: usize, d: u64| a.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (nx, ny, steps, block) = (num(0, 576), num(1, 288), num(2, 10000), num(3, 1000));
    let abstraction = match a.get(4).map(String::as_str) {
        Some("shadow") => Abstraction::Shadow,
        _ => Abstraction::Slices,
    };
    let p = RippleParams {
        nx: nx as usize,
        ny: ny as usize,
        steps,
        abstraction,
        ..RippleParams::default()
    };
    let t0 = Instant::now();
    let mut r = Ripple::new(&p).expect("valid parameters");
    println!(
        "{} automata, {} activations/step, setup {:.2} s",
        r.automata(),
        r.activations_per_step(),
        t0.elapsed().as_secs_f64()
    );
    let mut done = 0;
    while done < steps {
        let n = block.min(steps - done);
        let t = Instant::now();
        r.run(n, |_| {});
        done += n;
        let dt = t.elapsed().as_secs_f64();
        let an = Analysis::of(&r);
        println!(
            "steps {done:>6}: {:>7.1} steps/s, height {:.2} cm, lee {:.1} deg",
            n as f64 / dt,
            an.height_m * 100.0,
            an.lee_slope_deg
        );
    }
}
