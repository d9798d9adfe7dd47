//! Profiling driver for rippled-dune rows: a 4032 x 4000 surface (20 m x 20 m at 5 mm: a
//! 64 x 32 tile of straight crests in a 63 x 125 mosaic) on fBm dunes (H = 0.6, 256 nodes,
//! rms 47 mm, steering 3), rows filled one after another on one thread.
//! `cargo run --release --example profile_dunes -- ROWS [BLEND] [CURRENT_ANGLE_DEG]`
//! (cachegrind: the difference between two ROWS values excludes the set-up).
use cellsurf::tile::{Choose, DuneParams, Mosaic, Relief, RippledDunes, RowSource, Tile};
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let rows: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(400);
    let blend: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(0);
    let angle: f64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(0.0);
    let (nx, ny) = (64, 32);
    let tiles: Vec<Tile> = (0..3)
        .map(|k| {
            let e = (0..nx * ny)
                .map(|i| {
                    let (x, y) = ((i % nx) as f64, (i / nx) as f64);
                    let phase = 2.0 * std::f64::consts::PI * (x / 16.0 + 0.01 * k as f64 * y);
                    (0.05 + 0.01 * phase.cos()) as f32
                })
                .collect();
            Tile::from_elevation(nx, ny, 0.005, e, "sine").unwrap()
        })
        .collect();
    let choose = if blend > 0 {
        Choose::Patches
    } else {
        Choose::Same
    };
    let m = Mosaic::new(tiles, 63, 125, choose, 1, blend).unwrap();
    let p = DuneParams {
        relief: Relief::Fbm { hurst: 0.6 },
        rms: 0.047,
        grid: 256,
        current_angle: angle,
        steering: 3.0,
        seed: 1,
    };
    let d = RippledDunes::new(m, &p).unwrap();
    let w = d.width();
    let mut row = vec![0.0f32; w];
    let mut sum = 0.0f64;
    let t = Instant::now();
    for y in 0..rows {
        d.fill_row(y, &mut row);
        sum += row.iter().map(|&v| v as f64).sum::<f64>();
    }
    let dt = t.elapsed().as_secs_f64();
    println!(
        "rows={rows} width={w} {:.2} M bins/s {:.1} ns/bin checksum={sum:.9e}",
        (rows * w) as f64 / dt / 1e6,
        dt * 1e9 / (rows * w) as f64
    );
}
