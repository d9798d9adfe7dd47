//! Wind-ripple benchmarks (divan). Run: `cargo bench --bench windripples`.
//!
//! - `step`: one step of the notebook's model at its default parameters (524,288 particles,
//!   256 x 256 bins, L = 1/64, kappa = 4.5, D = 8e-4 annealed), in rayon pools of 1 and 2
//!   threads (and all cores); items are particle-steps. Each sample starts from a model already
//!   stepped 16 times (set-up not timed).
//! - `statistics_256`: mean, standard deviation and both wavelengths of a 256 x 256 height
//!   field (an FFT of each column along the wind).

use cellsurf::windripples::{WindParams, WindRipples, height_stats};
use divan::counter::ItemsCount;
use divan::{Bencher, black_box};

fn main() {
    divan::main();
}

fn warmed() -> WindRipples {
    let mut w = WindRipples::new(WindParams::default()).expect("default parameters");
    for _ in 0..16 {
        w.step();
    }
    w
}

/// Threads of the pool; 0 = all cores.
#[divan::bench(args = [1, 2, 0], sample_count = 10, sample_size = 4)]
fn step(bencher: Bencher, threads: usize) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let mut w = pool.install(warmed);
    bencher
        .counter(ItemsCount::new(WindParams::default().particles))
        .bench_local(|| pool.install(|| w.step()));
}

#[divan::bench(sample_count = 10)]
fn statistics_256(bencher: Bencher) {
    let w = warmed();
    let h = w.height();
    bencher.bench_local(|| black_box(height_stats(black_box(&h), 256)));
}
