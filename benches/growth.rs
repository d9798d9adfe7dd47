//! Sampler benchmarks (divan). Run: `cargo bench --bench growth`.
//!
//! - `exact_flame_2048`: accepted events per second of the exact sampler on a 2048 x 2048
//!   hexagonal torus flame (square start of side 20), single thread, n = 0, 2, 8, 50; each
//!   sample grows 1,000,000 cells from a fresh lattice (set-up not timed).
//! - `same_clock_512`: the exact and the rejection sampler over the same number of timesteps
//!   on a 512 x 512 hex torus flame, n = 2, 8, 50: the exact sampler's advantage grows with n.

use cellsurf::engine::lattice::{Boundary, Lattice, Neighbourhood};
use cellsurf::engine::rng::stream;
use cellsurf::growth::Growth;
use cellsurf::growth::rule::{Sticking, Weight};
use cellsurf::growth::sampler::Outcome;
use divan::counter::ItemsCount;
use divan::{Bencher, black_box};

fn main() {
    divan::main();
}

fn flame(size: usize, n: f64) -> Growth {
    let l = Lattice::new(Neighbourhood::Hex, size, size, Boundary::TORUS).unwrap();
    let mut g = Growth::new(l, Sticking::new(n, 6).unwrap(), Weight::Isotropic, false).unwrap();
    let (pw, ph) = g.lattice().physical_size();
    let (cx, cy) = (pw / 2.0, ph / 2.0);
    g.occupy_where(|x, y| (x - cx).abs() < 10.0 && (y - cy).abs() < 10.0);
    g
}

const EVENTS: u64 = 1_000_000;

#[divan::bench(args = [0.0, 2.0, 8.0, 50.0], sample_count = 5, sample_size = 1)]
fn exact_flame_2048(bencher: Bencher, n: f64) {
    bencher
        .counter(ItemsCount::new(EVENTS))
        .with_inputs(|| (flame(2048, n), stream(1)))
        // (by reference: the 16 MB lattice is freed after the timing, as it was built before)
        .bench_local_refs(|(g, rng)| {
            while g.accepted() < EVENTS {
                if !matches!(g.step_exact(rng, f64::INFINITY), Outcome::Accepted(_)) {
                    break;
                }
            }
            black_box(g.occupied())
        });
}

const STEPS: f64 = 2_000_000.0;

#[divan::bench(args = [2.0, 8.0, 50.0], sample_count = 5, sample_size = 1)]
fn same_clock_512_exact(bencher: Bencher, n: f64) {
    bencher
        .counter(ItemsCount::new(STEPS as u64))
        .with_inputs(|| (flame(512, n), stream(2)))
        .bench_local_values(|(mut g, mut rng)| {
            g.run_exact(&mut rng, STEPS);
            black_box(g.occupied())
        });
}

#[divan::bench(args = [2.0, 8.0, 50.0], sample_count = 5, sample_size = 1)]
fn same_clock_512_rejection(bencher: Bencher, n: f64) {
    bencher
        .counter(ItemsCount::new(STEPS as u64))
        .with_inputs(|| (flame(512, n), stream(2)))
        .bench_local_values(|(mut g, mut rng)| {
            g.run_rejection(&mut rng, STEPS);
            black_box(g.occupied())
        });
}
