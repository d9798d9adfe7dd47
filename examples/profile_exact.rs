//! Profiling driver: grows a 2048 x 2048 hexagonal torus flame with the exact sampler.
//! `cargo run --release --example profile_exact -- N EVENTS [SIZE]` (SIZE x SIZE, default 2048).
use cellsurf::engine::lattice::*;
use cellsurf::engine::rng::stream;
use cellsurf::growth::{Growth, rule::*, sampler::*};
use std::time::Instant;
fn main() {
    let mut args = std::env::args().skip(1);
    let n: f64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(2.0);
    let ev: u64 = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2_000_000);
    let size: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(2048);
    let l = Lattice::new(Neighbourhood::Hex, size, size, Boundary::TORUS).unwrap();
    let mut g = Growth::new(l, Sticking::new(n, 6).unwrap(), Weight::Isotropic, false).unwrap();
    let (pw, ph) = g.lattice().physical_size();
    g.occupy_where(|x, y| (x - pw / 2.0).abs() < 10.0 && (y - ph / 2.0).abs() < 10.0);
    let mut rng = stream(1);
    let t = Instant::now();
    while g.accepted() < ev {
        if !matches!(g.step_exact(&mut rng, f64::INFINITY), Outcome::Accepted(_)) {
            break;
        }
    }
    let dt = t.elapsed().as_secs_f64();
    println!(
        "n={n} events={} {:.2} M/s",
        g.accepted(),
        g.accepted() as f64 / dt / 1e6
    );
}
