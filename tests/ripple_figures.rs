//! The ripple figures: listed under their names, and (ignored: about 20 s in release) all made
//! into `figures/` (or `$RIPPLE_FIG_DIR`) in one process:
//! `cargo test --release --test ripple_figures -- --ignored`.
#![cfg(feature = "plot")]

use std::time::Instant;

use cellsurf::ripple::FIGURES;

#[test]
fn the_ripple_figures_are_listed() {
    let names: Vec<&str> = FIGURES.iter().map(|f| f.name).collect();
    for n in [
        "ripple_fig2_shadow",
        "ripple_fig3_evolution",
        "ripple_fig4_impedance",
        "ripple_fig7_section",
        "ripple_fig8_surface_grain_size",
        "ripple_error_vs_time",
    ] {
        assert!(names.contains(&n), "{n} missing");
    }
    assert!(cellsurf::figures::all().any(|f| f.name == "ripple_fig3_evolution"));
}

#[test]
#[ignore = "makes every ripple figure (about 20 s in release)"]
fn make_all_ripple_figures() {
    let dir = std::env::var("RIPPLE_FIG_DIR")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|_| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("figures"));
    let t = Instant::now();
    for f in FIGURES {
        let t0 = Instant::now();
        let files = (f.make)(&dir).unwrap();
        for p in &files {
            assert!(std::fs::metadata(p).unwrap().len() > 1000);
        }
        eprintln!("{} {:.1} s: {files:?}", f.name, t0.elapsed().as_secs_f64());
    }
    eprintln!("all ripple figures in {:.1} s", t.elapsed().as_secs_f64());
}
