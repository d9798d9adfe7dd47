//! Tiling and fractal dunes: seams of mosaics of toroidal ripple tiles (same tile,
//! close steps, different seeds, blended), streaming to NetCDF-3 and `.npy` against the
//! in-memory mosaic, the fBm spectrum slope and periodicity, ripples re-oriented by the current,
//! and the extreme cases (zero sizes, a mosaic of one tile).

mod common;

use std::path::PathBuf;
use std::sync::OnceLock;

use cellsurf::ripple::output::Field;
use cellsurf::ripple::spectrum::dominant_wave;
use cellsurf::ripple::{Ripple, RippleParams};
use cellsurf::tile::fractal::{measured_slope, radial_spectrum};
use cellsurf::tile::stream::write_stream;
use cellsurf::tile::tileset::tiles_from_run;
use cellsurf::tile::{
    Choose, DuneField, DuneParams, FbmParams, Mosaic, Relief, RippledDunes, RowSource, SeamMeter,
    SeamStats, StreamFormat, StreamSpec, Tile,
};

/// A small ripple run's parameters: 48 x 24 bins, ripples after a few hundred steps.
fn small() -> RippleParams {
    RippleParams {
        nx: 48,
        ny: 24,
        layers: 12,
        steps: 600,
        activity: 0.01,
        ..RippleParams::default()
    }
}

/// Tiles shared by the tests: seed 1 at steps 560, 580, 600 (close steps), seeds 2 and 3 at 600.
fn pool() -> &'static (Vec<Tile>, Vec<Tile>) {
    static P: OnceLock<(Vec<Tile>, Vec<Tile>)> = OnceLock::new();
    P.get_or_init(|| {
        let p = small();
        let close =
            tiles_from_run(&p, &[1], &[560, 580, 600], Some(Field::GrainSize), |_| {}).unwrap();
        let seeds = tiles_from_run(&p, &[1, 2, 3], &[600], None, |_| {}).unwrap();
        (close, seeds)
    })
}

fn seams(src: &dyn RowSource) -> SeamStats {
    let (tnx, tny) = src.tile_size();
    let mut m = SeamMeter::new(src.width(), tnx, tny);
    let mut row = vec![0.0f32; src.width()];
    for y in 0..src.height() {
        src.fill_row(y, &mut row);
        m.push_row(&row);
    }
    m.finish()
}

fn tmp(name: &str) -> PathBuf {
    common::tmp_in("tile", name)
}

#[test]
fn seam_no_larger_than_interior_for_same_tile() {
    let t = pool().0[2].clone();
    let (nx, ny) = (t.nx, t.ny);
    let m = Mosaic::new(vec![t.clone()], 3, 3, Choose::Same, 1, 0).unwrap();
    let s = seams(&m);
    // The seam pairs are the tile's own wrap-around pairs: exactly the torus's neighbours.
    let wrap_x: f64 = (0..ny)
        .map(|y| (t.at(0, y) as f64 - t.at(nx - 1, y) as f64).abs())
        .sum::<f64>()
        / ny as f64;
    assert!((s.x.across.unwrap() - wrap_x).abs() < 1e-9);
    for (d, st) in [("x", s.x), ("y", s.y)] {
        let (a, i, sd) = (
            st.across.unwrap(),
            st.inside.unwrap(),
            st.inside_line_sd.unwrap(),
        );
        assert!(i > 0.0, "{d}: a flat tile would make this test empty");
        assert!(
            a <= st.inside_line_max.unwrap() && a <= i + 2.5 * sd,
            "{d}: seam {a} against inside {i} +- {sd}"
        );
    }
}

#[test]
fn close_steps_join_almost_like_the_interior() {
    let tiles = pool().0.clone();
    let m = Mosaic::new(tiles, 4, 4, Choose::Patches, 7, 0).unwrap();
    let s = seams(&m);
    for st in [s.x, s.y] {
        let r = st.ratio().unwrap();
        assert!(r < 1.6, "close-step patches: across / inside = {r}");
    }
}

#[test]
fn blend_reduces_seam() {
    let tiles = pool().1.clone();
    let raw = Mosaic::new(tiles.clone(), 4, 4, Choose::Patches, 7, 0).unwrap();
    let blended = Mosaic::new(tiles, 4, 4, Choose::Patches, 7, 12).unwrap();
    let (a, b) = (seams(&raw), seams(&blended));
    let (ra, rb) = (a.x.ratio().unwrap(), b.x.ratio().unwrap());
    // different seeds: a step at the edges, removed by the cross-fade
    assert!(ra > 1.5, "unblended seams should show: ratio {ra}");
    assert!(rb < 1.2 && rb < ra, "blended ratio {rb} (unblended {ra})");
    let (ya, yb) = (a.y.ratio().unwrap(), b.y.ratio().unwrap());
    assert!(yb < ya && yb < 1.2, "y: {ya} -> {yb}");
}

#[test]
fn mosaic_one_tile() {
    let t = pool().1[0].clone();
    let m = Mosaic::new(vec![t.clone()], 1, 1, Choose::Patches, 3, 8).unwrap();
    let mut row = vec![0.0f32; t.nx];
    for y in 0..t.ny {
        m.fill_row(y, &mut row);
        for (x, v) in row.iter().enumerate() {
            assert_eq!(
                *v,
                t.at(x, y),
                "blending a tile with itself changes nothing"
            );
        }
    }
    let s = seams(&m);
    for st in [s.x, s.y] {
        assert_eq!(st.seams, 1);
        assert!(st.across.unwrap().is_finite() && st.inside.unwrap().is_finite());
    }
    let out = tmp("one.nc");
    let rep = write_stream(&out, &m, &spec(StreamFormat::NetCdf, None), |_| {}).unwrap();
    assert_eq!((rep.width, rep.height), (t.nx, t.ny));
    assert!(rep.bytes > 4 * (t.nx * t.ny) as u64);
}

#[test]
fn zero_size_rejected() {
    let e = Tile::from_elevation(0, 5, 0.01, vec![], "empty").unwrap_err();
    assert!(e.to_string().starts_with("tile size = 0x5"), "{e}");
    let t = Tile::from_elevation(4, 4, 0.01, vec![0.0; 16], "t").unwrap();
    let e = Mosaic::new(vec![t.clone()], 3, 0, Choose::Same, 1, 0).unwrap_err();
    assert!(e.to_string().contains("mosaic = 3x0"), "{e}");
    assert!(e.to_string().contains("at least 1x1"), "{e}");
    let e = Mosaic::new(vec![], 2, 2, Choose::Same, 1, 0).unwrap_err();
    assert!(e.to_string().contains("at least one tile"), "{e}");
    let e = Mosaic::new(vec![t.clone()], usize::MAX / 2, 3, Choose::Same, 1, 0).unwrap_err();
    assert!(e.to_string().contains("out of range"), "{e}");
    let nan = Tile::from_elevation(2, 2, 0.01, vec![0.0, f32::NAN, 0.0, 0.0], "nan").unwrap_err();
    assert!(nan.to_string().contains("finite"), "{nan}");
    let other = Tile::from_elevation(5, 4, 0.01, vec![0.0; 20], "other").unwrap();
    let e = Mosaic::new(vec![t, other], 2, 2, Choose::Patches, 1, 0).unwrap_err();
    assert!(e.to_string().contains("size 5x4"), "{e}");
}

fn spec(format: StreamFormat, volume: Option<Field>) -> StreamSpec {
    StreamSpec {
        format,
        volume,
        title: "test mosaic".into(),
        params: vec![("mosaic".into(), toml::Value::String("3x2".into()))],
        elevation_long_name: None,
    }
}

#[test]
fn stream_matches_in_memory() {
    let tiles = pool().0.clone();
    let m = Mosaic::new(tiles, 3, 2, Choose::Patches, 5, 6).unwrap();
    let (w, h) = m.size();
    let nz = m.levels();
    assert!(nz > 0);
    let mut want = vec![0.0f32; w * h];
    let mut want_vol = vec![0.0f32; h * nz * w];
    for y in 0..h {
        m.fill_row(y, &mut want[y * w..(y + 1) * w]);
        m.fill_volume_row(y, &mut want_vol[y * nz * w..(y + 1) * nz * w]);
    }
    // NetCDF: records read back one by one
    let nc = tmp("m.nc");
    let rep = write_stream(
        &nc,
        &m,
        &spec(StreamFormat::NetCdf, Some(Field::GrainSize)),
        |_| {},
    )
    .unwrap();
    assert_eq!(rep.levels, nz);
    assert_eq!(rep.bytes, std::fs::metadata(&nc).unwrap().len());
    let mut r = netcdf3::FileReader::open(&nc).unwrap();
    let fill = netcdf3::NC_FILL_F32;
    for y in 0..h {
        let row = r.read_record("elevation", y).unwrap();
        assert_eq!(row.get_f32().unwrap(), &want[y * w..(y + 1) * w]);
        let slab = r.read_record("grain_size", y).unwrap();
        let got = slab.get_f32().unwrap();
        for (g, e) in got.iter().zip(&want_vol[y * nz * w..(y + 1) * nz * w]) {
            assert!(
                (e.is_nan() && *g == fill) || g == e,
                "volume row {y}: {g} vs {e}"
            );
        }
    }
    let ys = r.read_var("y").unwrap();
    assert_eq!(ys.get_f32().unwrap().len(), h);
    // .npy: the header, then the rows
    let npy = tmp("m.npy");
    let rep = write_stream(&npy, &m, &spec(StreamFormat::Npy, None), |_| {}).unwrap();
    assert_eq!(rep.files.len(), 2);
    let bytes = std::fs::read(&npy).unwrap();
    let hl = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = String::from_utf8_lossy(&bytes[10..10 + hl]);
    assert!(header.contains(&format!("'shape': ({h}, {w})")), "{header}");
    let data: Vec<f32> = bytes[10 + hl..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    assert_eq!(data, want);
    let side = std::fs::read_to_string(tmp("m.json")).unwrap();
    assert!(side.contains("\"cellsurf_version\"") && side.contains("\"mosaic\": \"3x2\""));
}

#[test]
fn failed_stream_leaves_nothing() {
    let t = Tile::from_elevation(4, 4, 0.01, vec![0.0; 16], "t").unwrap();
    let m = Mosaic::new(vec![t], 2, 2, Choose::Same, 1, 0).unwrap();
    let dir = tmp("no-such-dir").join("sub");
    let e = write_stream(
        &dir.join("x.nc"),
        &m,
        &spec(StreamFormat::NetCdf, None),
        |_| {},
    )
    .unwrap_err();
    assert!(e.to_string().contains("x.nc"), "{e}");
    // asking for a volume the tiles do not carry
    let e = write_stream(
        &tmp("v.nc"),
        &m,
        &spec(StreamFormat::NetCdf, Some(Field::Impedance)),
        |_| {},
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("volume = impedance"), "{e}");
    assert!(!tmp("v.nc").exists());
}

#[test]
fn volume_follows_the_tiles() {
    let t = pool().0[2].clone();
    let m = Mosaic::new(vec![t.clone()], 2, 1, Choose::Same, 1, 0).unwrap();
    let (w, _) = m.size();
    let nz = m.levels();
    let vol = t.volume.as_ref().unwrap();
    let mut slab = vec![0.0f32; nz * w];
    m.fill_volume_row(5, &mut slab);
    for x in 0..w {
        for z in 0..nz {
            let e = vol.data[z * t.nx * t.ny + 5 * t.nx + x % t.nx];
            let g = slab[z * w + x];
            assert!(
                (e.is_nan() && g.is_nan()) || e == g,
                "x {x} z {z}: {g} vs {e}"
            );
        }
    }
}

fn fbm(n: usize, hurst: f64, seed: u64) -> FbmParams {
    FbmParams {
        nx: n,
        ny: n,
        dx: 2.0,
        dy: 2.0,
        relief: Relief::Fbm { hurst },
        rms: 1.0,
        seed,
    }
}

#[test]
fn fbm_spectrum_slope() {
    // The mean slope over seeds matches -(2H + 2) within 3 standard errors (the scatter over
    // seeds), and a neighbouring H (slope 0.2 away) is rejected.
    let seeds = 12;
    for hurst in [0.2, 0.6, 0.9] {
        let s: Vec<f64> = (0..seeds)
            .map(|k| measured_slope(&DuneField::synthesize(&fbm(128, hurst, 100 + k)).unwrap()))
            .map(Option::unwrap)
            .collect();
        let n = s.len() as f64;
        let mean = s.iter().sum::<f64>() / n;
        let sd = (s.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let want = -(2.0 * hurst + 2.0);
        let tol = 3.0 * sd / n.sqrt();
        assert!(
            (mean - want).abs() < tol,
            "H = {hurst}: slope {mean:.3} +- {sd:.3} (sd over {seeds} seeds), want {want}"
        );
        // and the estimate discriminates: a neighbouring H is rejected
        for other in [want - 0.2, want + 0.2] {
            assert!(
                (mean - other).abs() > tol,
                "H = {hurst}: tolerance {tol} too wide"
            );
        }
    }
}

#[test]
fn fbm_periodic() {
    // The seam of the dune field with itself (its periodic wrap) is like its interior.
    let f = DuneField::synthesize(&fbm(64, 0.6, 9)).unwrap();
    let mut m = SeamMeter::new(f.nx, f.nx, f.ny);
    for row in f.h.chunks_exact(f.nx) {
        m.push_row(&row.iter().map(|&v| v as f32).collect::<Vec<_>>());
    }
    let s = m.finish();
    for st in [s.x, s.y] {
        let z = st.z().unwrap();
        assert!(
            z.abs() < 3.0,
            "wrap seam {} vs inside {}: z {z}",
            st.across.unwrap(),
            st.inside.unwrap()
        );
    }
    // height and slope read periodically
    let (lx, ly) = f.period();
    assert!((f.height(3.3, 7.1) - f.height(3.3 + lx, 7.1 - ly)).abs() < 1e-9);
}

#[test]
fn dune_wavelength_is_recovered() {
    let p = FbmParams {
        relief: Relief::Wavelength {
            wavelength: 32.0,
            current_angle: 30.0,
        },
        ..fbm(128, 0.5, 4)
    };
    let f = DuneField::synthesize(&p).unwrap();
    let (wl, ang) = dominant_wave(&f.h, f.nx, f.ny, f.dx);
    assert!((wl - 32.0).abs() < 0.15 * 32.0, "wavelength {wl}");
    let d = (ang - 30.0 + 90.0).rem_euclid(180.0) - 90.0;
    assert!(d.abs() < 25.0, "crest normal {ang}, current 30");
    assert!(radial_spectrum(&f.h, f.nx, f.ny, f.dx, f.dy).len() > 10);
}

/// A tile of straight crests across x: wavelength 8 bins, current along +x.
fn sine_tile() -> Tile {
    let (nx, ny) = (32, 32);
    let e = (0..nx * ny)
        .map(|i| (0.01 * (2.0 * std::f64::consts::PI * (i % nx) as f64 / 8.0).cos()) as f32)
        .collect();
    Tile::from_elevation(nx, ny, 0.01, e, "sine").unwrap()
}

#[test]
fn ripples_turn_with_the_current() {
    let m = Mosaic::new(vec![sine_tile()], 8, 8, Choose::Same, 1, 0).unwrap();
    let flat = DuneField::from_grid(4, 4, 0.64, 0.64, vec![0.0; 16]).unwrap();
    for angle in [0.0, 30.0, 60.0] {
        let d = RippledDunes::with_field(m.clone(), flat.clone(), angle, 3.0).unwrap();
        let n = 128;
        let f: Vec<f64> = (0..n * n)
            .map(|i| d.value((i % n) as i64, (i / n) as i64))
            .collect();
        let (wl, ang) = dominant_wave(&f, n, n, 0.01);
        assert!((wl - 0.08).abs() < 0.01, "wavelength {wl}");
        assert!(
            (ang - angle).abs() < 3.0,
            "crest normal {ang} for current {angle}"
        );
        // a whole turn keeps the ripple height (no interference between anchors)
        let rms = (f.iter().map(|v| v * v).sum::<f64>() / f.len() as f64).sqrt();
        assert!(rms > 0.9 * 0.01 / 2f64.sqrt(), "rms {rms}");
    }
}

#[test]
fn rippled_dunes_periodic_and_flat_dunes_reproduce_the_mosaic() {
    let tiles = pool().1.clone();
    let m = Mosaic::new(tiles, 2, 2, Choose::Patches, 3, 0).unwrap();
    let (w, h) = m.size();
    let p = DuneParams {
        relief: Relief::Fbm { hurst: 0.6 },
        rms: 0.05,
        grid: 32,
        current_angle: 0.0,
        steering: 3.0,
        seed: 5,
    };
    let d = RippledDunes::new(m.clone(), &p).unwrap();
    let (w64, h64) = (w as i64, h as i64);
    for (x, y) in [(0, 0), (5, 7), (w64 - 1, 3), (17, h64 - 1)] {
        let v = d.value(x, y);
        assert!(
            (v - d.value(x + w64, y)).abs() < 1e-6,
            "x period at {x},{y}"
        );
        assert!(
            (v - d.value(x, y - h64)).abs() < 1e-6,
            "y period at {x},{y}"
        );
    }
    // rows agree with single values
    let mut row = vec![0.0f32; w];
    d.fill_row(9, &mut row);
    for x in [0usize, 11, w - 1] {
        assert!((row[x] as f64 - d.value(x as i64, 9)).abs() < 1e-6);
    }
    // the slope deflects the current
    let mut spread = 0.0f64;
    for k in 0..50 {
        let t = d.local_current(0.037 * k as f64, 0.011 * k as f64);
        spread = spread.max(t.abs());
    }
    assert!(spread > 0.01, "no deflection at all: {spread}");
    // flat dunes, current along the tiles': the mosaic itself
    let flat = RippledDunes::new(m.clone(), &DuneParams { rms: 0.0, ..p }).unwrap();
    flat.fill_row(4, &mut row);
    for (x, v) in row.iter().enumerate() {
        assert!((v - m.value(x, 4)).abs() < 1e-6);
    }
}

#[test]
fn generated_tiles_are_toroidal_runs() {
    // tiles_from_run keeps exactly the asked steps, and a tile equals its run's state
    let p = RippleParams {
        steps: 20,
        ..small()
    };
    let t = tiles_from_run(&p, &[4], &[20, 0, 20], None, |_| {}).unwrap();
    assert_eq!(t.len(), 2);
    assert_eq!(t[0].label, "seed 4, step 0");
    let mut r = Ripple::new(&RippleParams { seed: 4, ..p }).unwrap();
    r.run(20, |_| {});
    let e: Vec<f32> = r.elevation().iter().map(|&v| v as f32).collect();
    assert_eq!(t[1].elevation, e);
}

/// A tile keeps its ripple run's frame: from a flow-frame run (the default) its flow runs
/// along its own x axis, which points along the dominant flow (the waves' for a wave run);
/// from a grid-frame run its x axis points east and its current crosses it. Both survive a
/// NetCDF file (with the waves' angle and friction factor), and a pool mixing the two is
/// refused by name; axes that differ by whole turns are the same.
#[test]
fn tiles_keep_the_frame_of_their_run() {
    use cellsurf::ripple::input::read;
    use cellsurf::ripple::output::{run_recording, write_netcdf};
    use cellsurf::ripple::{Format, Frame, OutputSpec};
    use cellsurf::tile::tileset::{check_pool, tiles_from_file};
    let tile_of = |p: RippleParams, name: &str| {
        let mut r = Ripple::new(&p).unwrap();
        let snaps = run_recording(&mut r, 20, &[20], |_| {});
        let mem = Tile::from_ripple(&r, None, name);
        let path = tmp(name);
        let spec = OutputSpec {
            fields: vec![Field::Elevation],
            format: Format::NetCdf,
        };
        write_netcdf(&path, &r, &snaps, &spec).unwrap();
        assert_eq!(
            read(&path).unwrap().params,
            p,
            "{name}: parameters read back"
        );
        let file = tiles_from_file(&path, None, None).unwrap().remove(0);
        assert_eq!(
            (file.current_angle, file.x_axis_deg),
            (mem.current_angle, mem.x_axis_deg),
            "{name}"
        );
        assert_eq!(file.elevation, mem.elevation);
        mem
    };
    let current = RippleParams {
        nx: 24,
        ny: 12,
        layers: 6,
        steps: 20,
        current_angle: 30.0,
        ..RippleParams::default()
    };
    let flow = tile_of(current.clone(), "flow.nc");
    assert_eq!((flow.current_angle, flow.x_axis_deg), (0.0, 30.0));
    let grid = tile_of(
        RippleParams {
            frame: Frame::Grid,
            ..current.clone()
        },
        "grid.nc",
    );
    assert_eq!((grid.current_angle, grid.x_axis_deg), (30.0, 0.0));
    // waves alone at 80 deg: the lattice along the waves
    let waves = tile_of(
        RippleParams {
            current_speed: 0.0,
            wave_amplitude: 0.3,
            wave_period: 40.0,
            wave_angle: Some(80.0),
            wave_friction_factor: 0.015,
            ..current.clone()
        },
        "waves.nc",
    );
    assert_eq!((waves.current_angle, waves.x_axis_deg), (0.0, 80.0));
    let e = check_pool(&[flow.clone(), grid]).unwrap_err().to_string();
    assert!(
        e.contains("x axis at 0 deg from east, first at 30 deg"),
        "{e}"
    );
    assert!(check_pool(&[flow.clone(), flow.clone()]).is_ok());
    let turned = Tile {
        x_axis_deg: 30.0 - 360.0,
        ..flow.clone()
    };
    assert!(check_pool(&[flow, turned]).is_ok());
}

#[test]
fn the_tiles_digest_follows_their_values_not_their_names() {
    let (close, _) = pool();
    let d = cellsurf::tile::tileset::digest(close);
    assert_eq!(d.len(), 64, "{d}");
    assert!(d.bytes().all(|b| b.is_ascii_hexdigit()), "{d}");
    // the same values under other labels: the same digest
    let mut renamed = close.clone();
    for t in &mut renamed {
        t.label = "other.nc, step 1".into();
    }
    assert_eq!(cellsurf::tile::tileset::digest(&renamed), d);
    // one elevation changed by one unit in the last place, one volume value, or the order
    let mut bumped = close.clone();
    bumped[1].elevation[7] = f32::from_bits(bumped[1].elevation[7].to_bits() + 1);
    assert_ne!(cellsurf::tile::tileset::digest(&bumped), d);
    let mut vol = close.clone();
    let v = vol[2].volume.as_mut().unwrap();
    *v.data.iter_mut().find(|x| x.is_finite()).unwrap() += 1.0;
    assert_ne!(cellsurf::tile::tileset::digest(&vol), d);
    let mut swapped = close.clone();
    swapped.swap(0, 1);
    assert_ne!(cellsurf::tile::tileset::digest(&swapped), d);
}
