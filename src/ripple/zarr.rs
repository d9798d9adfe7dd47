//! A ripple run as a Zarr v3 store (feature `zarr`, [`crate::engine::zarr`]): the same
//! variables as the NetCDF file ([`super::output`]), chunked and zstd-compressed, readable
//! with `xarray.open_zarr(path)`.
//!
//! Principal item: [`write_zarr`]. The store holds
//! - `elevation(time, y, x)`: the bed elevation at the snapshot steps, m, one chunk per
//!   snapshot;
//! - each volume field asked for, `FIELD(z, y, x)` (`grain_size` mm, `porosity`, `density`
//!   kg m-3, `sound_speed` m s-1, `impedance` kg m-2 s-1), NaN above the bed, in chunks of
//!   whole `(z, x)` planes and as many rows as make about 2^20 values;
//! - the coordinates `x(x)`, `y(y)`, `z(z)` (m, bin and automaton centres) and `time(time)`
//!   (the step of each snapshot);
//! - on the root group, the CF provenance (`Conventions`, `title`, `source`,
//!   `cellsurf_version`, `comment`), `steps_done`, `automata`, and one `param_NAME` per
//!   parameter.
//!
//! The store is written whole into a temporary sibling folder and renamed onto its name when
//! complete ([`crate::engine::zarr::replace_store`]): a run that fails or is interrupted
//! leaves the previous store (or none), never a partial one.

use std::path::Path;

use serde_json::Value;

use super::RippleError;
use super::VERSION;
use super::model::Ripple;
use super::output::{Field, OutputSpec, toml_pairs, volume_field, volume_levels};
use crate::engine::zarr::{ArraySpec, Dtype, Store, ZarrError, attrs, replace_store, toml_to_json};

/// Values a volume chunk aims at: 2^20 (4 MB of float32).
pub const CHUNK_VALUES: usize = 1 << 20;

fn zerr(path: &Path) -> impl Fn(ZarrError) -> RippleError + '_ {
    move |e| RippleError::Output {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

fn coord(name: &str, values: usize, units: &str, long: &str, axis: &str) -> ArraySpec {
    let mut a = attrs(&[("units", units), ("long_name", long)]);
    if !axis.is_empty() {
        a.insert("axis".into(), Value::from(axis));
    }
    ArraySpec {
        name: name.into(),
        shape: vec![values as u64],
        chunks: vec![values.max(1) as u64],
        dims: vec![name.into()],
        dtype: Dtype::F64,
        attrs: a,
    }
}

/// Rows of a volume chunk: whole `(z, x)` planes, about [`CHUNK_VALUES`] values, at least one.
pub fn chunk_rows(nz: usize, nx: usize, ny: usize) -> usize {
    (CHUNK_VALUES / (nz * nx).max(1)).clamp(1, ny.max(1))
}

/// Writes the run `r` (with its elevation `snapshots`, as [`super::output::run_recording`]
/// returns them) to the store `out` (module docs): the fields of `spec`.
pub fn write_zarr(
    out: &Path,
    r: &Ripple,
    snapshots: &[(u64, Vec<f32>)],
    spec: &OutputSpec,
) -> Result<(), RippleError> {
    write_zarr_with(out, r, snapshots, spec, &[])
}

/// Checks, before a run, that `out` can take the store: its folder exists, and it is absent or
/// already a Zarr store (which the run's store replaces); a file or another folder there is
/// refused, never deleted.
pub fn check_store_target(out: &Path) -> Result<(), RippleError> {
    let refuse = |reason: String| RippleError::Output {
        path: out.display().to_string(),
        reason,
    };
    match crate::engine::zarr::store_target(out).map_err(refuse)? {
        None | Some(true) => Ok(()),
        Some(false) => Err(refuse(
            "exists and is not a Zarr store (no zarr.json); remove it or choose another name"
                .into(),
        )),
    }
}

/// [`write_zarr`] with the run's own attributes `extra`
/// ([`RunAttributes`](super::output::RunAttributes)) on the root group.
pub fn write_zarr_with(
    out: &Path,
    r: &Ripple,
    snapshots: &[(u64, Vec<f32>)],
    spec: &OutputSpec,
    extra: &super::output::RunAttributes,
) -> Result<(), RippleError> {
    let (nx, ny) = r.size();
    let p = r.params();
    let nz = volume_levels(r);
    let rows = chunk_rows(nz, nx, ny);
    let want_elev = spec.fields.contains(&Field::Elevation) && !snapshots.is_empty();
    let volumes: Vec<Field> = spec
        .fields
        .iter()
        .copied()
        .filter(|&f| f != Field::Elevation)
        .collect();

    let mut arrays = vec![
        coord("x", nx, "m", "x of the bin centre (periodic)", "X"),
        coord("y", ny, "m", "y of the bin centre (periodic)", "Y"),
    ];
    if want_elev {
        arrays.push(coord(
            "time",
            snapshots.len(),
            "1",
            "step of the snapshot",
            "T",
        ));
        arrays.push(ArraySpec::data_f32(
            "elevation",
            &["time", "y", "x"],
            &[snapshots.len(), ny, nx],
            &[1, ny, nx],
            Field::Elevation.meta(),
            "",
        ));
    }
    if !volumes.is_empty() && nz > 0 {
        let mut z = coord(
            "z",
            nz,
            "m",
            "height of the automaton centre above the substrate",
            "Z",
        );
        z.attrs.insert("positive".into(), Value::from("up"));
        arrays.push(z);
        for &f in &volumes {
            arrays.push(ArraySpec::data_f32(
                f.name(),
                &["z", "y", "x"],
                &[nz, ny, nx],
                &[nz, rows, nx],
                f.meta(),
                "NaN above the bed",
            ));
        }
    }

    let mut group = attrs(&[
        ("Conventions", "CF-1.8"),
        ("title", "cellsurf sand ripple volume"),
        ("source", &format!("cellsurf {VERSION} ripple")),
        ("cellsurf_version", VERSION),
        (
            "comment",
            "Cellular automaton Monte-Carlo sand ripple volume (Staelens, Dupont and Henriet 2013); periodic in x and y.",
        ),
    ]);
    group.insert("steps_done".into(), Value::from(r.time()));
    group.insert("automata".into(), Value::from(r.automata()));
    group.insert("bin_size_m".into(), Value::from(p.bin_size));
    group.insert("layer_thickness_m".into(), Value::from(p.layer_thickness));
    // the direction of the x axis, degrees counter-clockwise from east (the flow frame turns
    // the lattice with the flow)
    group.insert(
        "x_axis_direction_deg".into(),
        Value::from(p.x_axis_direction_deg()),
    );
    for (k, v) in extra {
        group.insert(k.clone(), toml_to_json(v));
    }
    for (k, v) in toml_pairs(p) {
        group.insert(format!("param_{k}"), toml_to_json(&v));
    }

    replace_store(out, |root| {
        let store = Store::create(root, group, arrays)?;
        let centres =
            |n: usize, step: f64| -> Vec<f64> { (0..n).map(|i| (i as f64 + 0.5) * step).collect() };
        store.write_chunk_f64("x", &[0], &centres(nx, p.bin_size))?;
        store.write_chunk_f64("y", &[0], &centres(ny, p.bin_size))?;
        if want_elev {
            let t: Vec<f64> = snapshots.iter().map(|s| s.0 as f64).collect();
            store.write_chunk_f64("time", &[0], &t)?;
            for (i, s) in snapshots.iter().enumerate() {
                store.write_chunk_f32("elevation", &[i as u64, 0, 0], &s.1)?;
            }
        }
        if !volumes.is_empty() && nz > 0 {
            store.write_chunk_f64("z", &[0], &centres(nz, p.layer_thickness))?;
            for &f in &volumes {
                // (z, y, x) in memory; a chunk is every z and x of `rows` rows, NaN-padded
                let all = volume_field(r, f, f32::NAN);
                for (j, y0) in (0..ny).step_by(rows).enumerate() {
                    let mut chunk = vec![f32::NAN; nz * rows * nx];
                    for z in 0..nz {
                        for dy in 0..rows.min(ny - y0) {
                            let src = (z * ny + y0 + dy) * nx;
                            let dst = (z * rows + dy) * nx;
                            chunk[dst..dst + nx].copy_from_slice(&all[src..src + nx]);
                        }
                    }
                    store.write_chunk_f32(f.name(), &[0, j as u64, 0], &chunk)?;
                }
            }
        }
        Ok(())
    })
    .map_err(zerr(out))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ripple::{Format, RippleParams};

    fn small() -> Ripple {
        let p = RippleParams {
            nx: 24,
            ny: 10,
            layers: 6,
            steps: 30,
            ..RippleParams::default()
        };
        Ripple::new(&p).unwrap()
    }

    #[test]
    fn chunk_rows_make_whole_planes_of_about_a_mebivalue() {
        assert_eq!(chunk_rows(40, 128, 64), 64);
        assert_eq!(chunk_rows(64, 4096, 4096), 4);
        assert_eq!(chunk_rows(4096, 4096, 10), 1);
        assert_eq!(chunk_rows(0, 0, 0), 1);
    }

    #[test]
    fn store_holds_the_volume_and_the_snapshots_bit_for_bit() {
        let mut r = small();
        let snaps = super::super::output::run_recording(&mut r, 30, &[0, 30], |_| {});
        let dir = std::env::temp_dir().join(format!("cellsurf-ripple-zarr-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("bed.zarr");
        let spec = OutputSpec {
            fields: vec![Field::Elevation, Field::Impedance],
            format: Format::Zarr,
        };
        write_zarr(&out, &r, &snaps, &spec).unwrap();
        let s = Store::open(&out).unwrap();
        let (nx, ny) = r.size();
        let nz = volume_levels(&r);
        assert_eq!(
            s.spec("elevation").unwrap().shape,
            vec![2, ny as u64, nx as u64]
        );
        assert_eq!(
            s.read_chunk_f32("elevation", &[1, 0, 0]).unwrap(),
            snaps[1].1
        );
        let want = volume_field(&r, Field::Impedance, f32::NAN);
        let got = s.read_chunk_f32("impedance", &[0, 0, 0]).unwrap();
        assert_eq!(got.len(), nz * ny * nx);
        for (a, b) in got.iter().zip(&want) {
            assert!(a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()));
        }
        let at = s.attributes().unwrap();
        assert_eq!(at["cellsurf_version"], VERSION);
        assert_eq!(at["param_nx"], 24);
        assert!(s.spec("porosity").is_none(), "only the fields asked for");
        // written again over itself: replaced whole, no temporary left beside it
        write_zarr(&out, &r, &snaps, &spec).unwrap();
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, vec!["bed.zarr".to_string()]);
        // a folder that is not a store is refused, not replaced
        let other = dir.join("notes.zarr");
        std::fs::create_dir_all(&other).unwrap();
        std::fs::write(other.join("keep.txt"), b"x").unwrap();
        let e = write_zarr(&other, &r, &snaps, &spec).unwrap_err();
        assert!(e.to_string().contains("not a Zarr store"), "{e}");
        assert!(other.join("keep.txt").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
