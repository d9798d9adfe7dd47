//! Ray-tracer benchmarks (divan). Run: `cargo bench --bench raytrace`.
//!
//! - `fan_to_floor`: rays per second of a fan of 1000 rays from S (10 m deep, 1.5 to 25
//!   degrees) to their first hit on the Fig. 5 floor (the generated ripple field, 94 tiles,
//!   60.16 m of section, 12 033 vertices), step 0.25 m, for each of the Fig. 5 profiles' kinds
//!   (isovelocity, linear, table); set-up not timed.
//! - `insonify_fig5`: one whole insonification of that floor (initial fan of 200 rays, then the
//!   bisection to the shadow edges), isovelocity.

use cellsurf::raytrace::figures::{fig5_floor, fig5_options, fig5_profiles};
use cellsurf::raytrace::{Fan, SoundSpeed, TraceOptions, Tracer, insonify};
use divan::counter::ItemsCount;
use divan::{Bencher, black_box};

fn main() {
    divan::main();
}

fn profile(kind: &str) -> SoundSpeed {
    fig5_profiles()
        .unwrap()
        .into_iter()
        .map(|(_, p)| p)
        .find(|p| p.name() == kind)
        .unwrap()
}

const RAYS: usize = 1000;

#[divan::bench(args = ["isovelocity", "linear", "table"], sample_count = 10)]
fn fan_to_floor(bencher: Bencher, kind: &str) {
    let f = fig5_floor().unwrap();
    let p = profile(kind);
    let t = Tracer::new(&p, &f).unwrap();
    let o = TraceOptions {
        max_path: 200.0,
        ..fig5_options(&f).unwrap().trace
    };
    bencher.counter(ItemsCount::new(RAYS)).bench_local(|| {
        let mut hits = 0;
        for i in 0..RAYS {
            let a = 1.5 + 23.5 * i as f64 / (RAYS - 1) as f64;
            let r = t.trace(0.0, 10.0, a, &o).unwrap();
            hits += usize::from(r.first_floor_hit().is_some());
        }
        black_box(hits)
    });
}

#[divan::bench(sample_count = 5)]
fn insonify_fig5(bencher: Bencher) {
    let f = fig5_floor().unwrap();
    let p = profile("isovelocity");
    let t = Tracer::new(&p, &f).unwrap();
    let fan = Fan::Point {
        x: 0.0,
        z: 10.0,
        min_deg: 1.5,
        max_deg: 25.0,
        rays: 200,
    };
    let o = fig5_options(&f).unwrap();
    bencher.bench_local(|| black_box(insonify(&t, &fan, &o).unwrap().rays));
}
