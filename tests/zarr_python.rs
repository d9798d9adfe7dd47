//! The Zarr store that `cellsurf tile --out X.zarr` writes, read by the Python tools it is
//! made for: `xarray.open_zarr` gives a Dataset with the named dimensions, CF units and the
//! parameters; its values equal the `.npy` output of the same mosaic; Dask reduces it chunk by
//! chunk (one Dask block per Zarr chunk) to numpy's statistics.
//!
//! The interpreter is `$CELLSURF_PYTHON` (`.ci/run` makes a virtual environment with numpy,
//! zarr, xarray and dask and sets it), else `target/py-venv/bin/python` (the README's test
//! command makes it), else `python3`. With `CELLSURF_SKIP_PYTHON=1` the test
//! says so and passes without running; without it, a missing package fails the test.
#![cfg(feature = "cli")]

mod common;

use std::process::Command;

use common::cellsurf;

const SCRIPT: &str = r#"
import sys, warnings
warnings.simplefilter("error")  # no fallback without consolidated metadata, no decoding warning
import numpy as np, xarray as xr, dask
store, npy, vol = sys.argv[1], sys.argv[2], sys.argv[3]
ds = xr.open_zarr(store)
assert ds.elevation.dims == ("y", "x"), ds.elevation.dims
assert ds.impedance.dims == ("y", "z", "x"), ds.impedance.dims
assert ds.elevation.attrs["units"] == "m"
assert ds.impedance.attrs["units"] == "kg m-2 s-1", ds.impedance.attrs
for c in "xyz":
    assert ds[c].attrs["units"] == "m" and ds[c].attrs["axis"] == c.upper(), ds[c].attrs
assert ds.attrs["Conventions"] == "CF-1.8" and ds.attrs["param_seed"] == 5, ds.attrs
assert ds.attrs["cellsurf_version"]
e, v = np.load(npy), np.load(vol)
assert ds.elevation.shape == e.shape and ds.impedance.shape == v.shape
assert np.array_equal(ds.elevation.values, e), "elevation differs from the npy output"
assert np.array_equal(np.isnan(ds.impedance.values), np.isnan(v))
assert np.array_equal(np.nan_to_num(ds.impedance.values), np.nan_to_num(v))
dx = float(ds.attrs["bin_size_m"])
assert np.allclose(ds.x.values, (np.arange(e.shape[1]) + 0.5) * dx)
# Dask: one block per Zarr chunk, reduced block by block
blocks = ds.elevation.data.numblocks
zchunks = ds.elevation.encoding["chunks"]
assert blocks == tuple(-(-n // c) for n, c in zip(e.shape, zchunks)), (blocks, zchunks)
mean, std, top = dask.compute(ds.elevation.mean(), ds.elevation.std(), ds.impedance.max())
assert abs(float(mean) - e.mean(dtype=np.float64)) < 1e-6 * abs(e.mean()), (float(mean), e.mean())
assert abs(float(std) - e.std(dtype=np.float64)) < 1e-5 * e.std(), (float(std), e.std())
assert float(top) == np.nanmax(v)
print("ok", blocks, float(mean), float(std))
"#;

/// The ripple store: `elevation(time, y, x)` and the volume fields on `(z, y, x)`, equal to
/// the `.npy` output of the same run.
const RIPPLE_SCRIPT: &str = r#"
import sys, warnings
warnings.simplefilter("error")
import numpy as np, xarray as xr
store, npy, vol = sys.argv[1], sys.argv[2], sys.argv[3]
ds = xr.open_zarr(store)
assert ds.elevation.dims == ("time", "y", "x"), ds.elevation.dims
assert ds.porosity.dims == ("z", "y", "x"), ds.porosity.dims
assert ds.elevation.attrs["units"] == "m" and ds.z.attrs["units"] == "m"
assert ds.attrs["param_seed"] == 9 and ds.attrs["steps_done"] == 200, ds.attrs
assert list(ds.time.values) == [0.0, 100.0, 200.0], ds.time.values
e, v = np.load(npy), np.load(vol)
assert np.array_equal(ds.elevation.values, e), "elevation differs from the npy output"
assert np.array_equal(np.isnan(ds.porosity.values), np.isnan(v))
assert np.array_equal(np.nan_to_num(ds.porosity.values), np.nan_to_num(v))
print("ok", ds.porosity.shape)
"#;

/// Whether the Python checks are skipped (`CELLSURF_SKIP_PYTHON=1`), saying so.
fn skipped() -> bool {
    let skip = std::env::var("CELLSURF_SKIP_PYTHON").is_ok_and(|v| v == "1");
    if skip {
        eprintln!(
            "SKIPPED: CELLSURF_SKIP_PYTHON=1, the Zarr store is not checked with xarray and Dask"
        );
    }
    skip
}

/// Runs `script` with `args` under the interpreter of the module docs; fails unless it exits 0.
fn run_python(script: &str, args: &[String]) -> std::process::Output {
    let venv = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/py-venv/bin/python");
    let python = std::env::var("CELLSURF_PYTHON").unwrap_or_else(|_| {
        if venv.exists() {
            venv.display().to_string()
        } else {
            "python3".into()
        }
    });
    let out = Command::new(&python)
        .arg("-c")
        .arg(script)
        .args(args)
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run {python} ({e}): set CELLSURF_PYTHON, or CELLSURF_SKIP_PYTHON=1")
        });
    assert!(
        out.status.success(),
        "{python} failed (numpy, zarr, xarray and dask are needed; .ci/run installs them; CELLSURF_SKIP_PYTHON=1 skips):\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

#[test]
fn xarray_reads_the_ripple_store() {
    if skipped() {
        return;
    }
    let dir = common::tmp_in("zarr-python-ripple", "x");
    let dir = dir.parent().unwrap();
    let store = dir.join("r.zarr");
    let npy = dir.join("r.npy");
    for out in [&store, &npy] {
        let o = out.display().to_string();
        let r = cellsurf(&[
            "ripple",
            "--recipe",
            "paper",
            "--size",
            "40x16",
            "--layers",
            "8",
            "--steps",
            "200",
            "--snapshots",
            "0,100,200",
            "--seed",
            "9",
            "--fields",
            "elevation,porosity",
            "--quiet",
            "--out",
            &o,
        ]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    }
    let out = run_python(
        RIPPLE_SCRIPT,
        &[
            store.display().to_string(),
            npy.display().to_string(),
            dir.join("r_porosity.npy").display().to_string(),
        ],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with("ok (") && text.contains(", 16, 40)"),
        "{text}"
    );
    std::fs::remove_dir_all(&store).unwrap();
}

#[test]
fn xarray_and_dask_read_the_tile_store() {
    if skipped() {
        return;
    }
    let dir = common::tmp_in("zarr-python", "x");
    let dir = dir.parent().unwrap();
    let store = dir.join("m.zarr");
    let npy = dir.join("m.npy");
    let _ = std::fs::remove_dir_all(&store);
    let base = [
        "tile",
        "--generate",
        "--nx",
        "48",
        "--ny",
        "24",
        "--layers",
        "10",
        "--steps",
        "300",
        "--seeds",
        "5,6",
        "--seed",
        "5",
        "--choose",
        "patches",
        "--mosaic",
        "7x9",
        "--volume",
        "impedance",
        "--quiet",
    ];
    for (out, extra) in [
        (&store, ["--chunk-tiles", "3x4"]),
        (&npy, ["--format", "npy"]),
    ] {
        let mut a = base.to_vec();
        let o = out.display().to_string();
        a.extend(["--out", &o]);
        a.extend(extra);
        let r = cellsurf(&a);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    }
    let out = run_python(
        SCRIPT,
        &[
            store.display().to_string(),
            npy.display().to_string(),
            dir.join("m_impedance.npy").display().to_string(),
        ],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("ok (3, 3)"), "{text}");
    std::fs::remove_dir_all(&store).unwrap();
}
