//! A surface of any size as a Zarr v3 store ([`crate::engine::zarr`]), written chunk by chunk
//! by one process or by `N` independent parts ([`Part`]) that share the store: a SLURM job
//! array, Kubernetes indexed jobs, GNU parallel on one machine.
//!
//! Principal items:
//! - [`ZarrLayout`]: the chunk grid, aligned with the mosaic's tiling: a chunk is `kx x ky`
//!   whole tiles (about 2^20 values with the volume field, at least one tile), so that a
//!   chunk boundary is a tile boundary.
//! - [`Part`]: part `i` of `N` (`--part i/N`) owns the chunks `i C / N .. (i + 1) C / N` of the
//!   `C` chunks in row-major order (the coordinate chunks go with the first row and column).
//! - [`write_zarr`]: writes the chunks of a part (or all of them) in parallel (rayon), each
//!   computed from the [`RowSource`] spans it covers, compressed (zstd) and written
//!   atomically; chunks already present and sound are kept, so re-running a killed part
//!   finishes the store; the seam statistic and the slopes are measured as the chunks are
//!   computed ([`ZarrReport::seams`]). [`init_zarr`] writes the metadata alone (`--init`).
//!   [`write_zarr_whole`]: one process's new store, through a temporary folder.
//!   [`check_store_target`]: what a run may find at a store's path (nothing, a store, or an
//!   empty folder for a part), checked before it starts.
//! - [`check_zarr`]: the missing and damaged chunks of a store and the temporary files
//!   killed writers left ([`ZarrCheck`]); [`verify_zarr`]: whether a store was made with given
//!   parameters and tiles (their digest, [`TILES_DIGEST`]).
//!
//! The store holds `elevation(y, x)` (float32, m), the coordinates `x(x)`, `y(y)` (float64, m,
//! bin centres), and with a volume field `FIELD(y, z, x)` and `z(z)`; CF attributes on every
//! array; the root group carries `Conventions`, `title`, `source`, `cellsurf_version` and one
//! `param_NAME` per parameter, and nothing that depends on the part or the time, so the
//! metadata and every chunk are the same bytes whether one process or `N` parts wrote them.
//! Memory is one chunk per worker thread (a few MB), whatever the mosaic's size.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;
use serde_json::{Map, Value};

use super::TileError;
use super::seam::{SeamBlock, SeamStats, SeamSums};
use super::stream::{RowSource, StreamSpec};
use crate::engine::VERSION;
use crate::engine::zarr::{
    ArraySpec, ChunkState, Dtype, Store, ZarrError, attrs, is_temporary, remove_temporaries_in,
    toml_to_json,
};

/// Values (elevation and volume) a chunk aims at: 2^20, 4 MB of float32.
pub const CHUNK_VALUES: usize = 1 << 20;

pub use crate::engine::part::Part;

/// The chunk grid of a store.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct ZarrLayout {
    /// Bins along x.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Volume levels (0: no volume field).
    pub levels: usize,
    /// Tiles per chunk along x and y.
    pub tiles: (usize, usize),
    /// Chunk size in bins along x and y.
    pub chunk: (usize, usize),
    /// Chunks along x and y.
    pub grid: (usize, usize),
}

impl ZarrLayout {
    /// The layout for `src` with `levels` volume levels: chunks of whole tiles, square in
    /// metres as near as the tiles allow, about [`CHUNK_VALUES`] values (elevation and volume)
    /// and at least one tile, at most the surface.
    pub fn new(src: &dyn RowSource, levels: usize) -> ZarrLayout {
        let (w, h) = (src.width(), src.height());
        let (tnx, tny) = src.tile_size();
        let (tnx, tny) = (tnx.clamp(1, w), tny.clamp(1, h));
        let side = ((CHUNK_VALUES / (1 + levels)) as f64).sqrt();
        let k = |t: usize, n: usize| ((side / t as f64).round() as usize).clamp(1, n.div_ceil(t));
        let (kx, ky) = (k(tnx, w), k(tny, h));
        let (cx, cy) = ((kx * tnx).min(w), (ky * tny).min(h));
        ZarrLayout {
            width: w,
            height: h,
            levels,
            tiles: (kx, ky),
            chunk: (cx, cy),
            grid: (w.div_ceil(cx), h.div_ceil(cy)),
        }
    }

    /// The layout with `kx x ky` tiles per chunk. Errors: zero tiles, more tiles than the
    /// surface holds, or a chunk of more than 2^28 values (1 GiB of float32).
    pub fn with_tiles(
        src: &dyn RowSource,
        levels: usize,
        (kx, ky): (usize, usize),
    ) -> Result<ZarrLayout, TileError> {
        let (w, h) = (src.width(), src.height());
        let (tnx, tny) = src.tile_size();
        let (tnx, tny) = (tnx.clamp(1, w), tny.clamp(1, h));
        let (mx, my) = (w.div_ceil(tnx), h.div_ceil(tny));
        if kx == 0 || ky == 0 || kx > mx || ky > my {
            return Err(TileError::range(
                "--chunk-tiles",
                format!("{kx}x{ky}"),
                format!("KXxKY tiles per chunk with KX in 1..={mx} and KY in 1..={my}"),
            ));
        }
        let (cx, cy) = ((kx * tnx).min(w), (ky * tny).min(h));
        if (cx as u128) * (cy as u128) * (1 + levels as u128) > 1 << 28 {
            return Err(TileError::range(
                "--chunk-tiles",
                format!("{kx}x{ky}"),
                format!(
                    "at most 2^28 values a chunk ({cx} x {cy} bins x {} fields and levels)",
                    1 + levels
                ),
            ));
        }
        Ok(ZarrLayout {
            width: w,
            height: h,
            levels,
            tiles: (kx, ky),
            chunk: (cx, cy),
            grid: (w.div_ceil(cx), h.div_ceil(cy)),
        })
    }

    /// Chunks in all.
    pub fn chunks(&self) -> usize {
        self.grid.0 * self.grid.1
    }
}

/// What [`write_zarr`] did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ZarrReport {
    /// The chunk grid.
    pub layout: ZarrLayout,
    /// The part written.
    pub part: Part,
    /// Chunks of the surface this part owns.
    pub owned: usize,
    /// Chunks computed and written.
    pub written: usize,
    /// Chunks found complete and kept.
    pub kept: usize,
    /// Values written (elevation and volume, float32), as bytes: the uncompressed size.
    pub bytes: u64,
    /// Bytes of the chunk files written (compressed).
    pub stored_bytes: u64,
    /// Bins of the surface computed (the elevation values of the chunks written).
    pub bins: u64,
    /// Seconds.
    pub elapsed_s: f64,
    /// The seam statistic and the surface's slopes, measured while the chunks were computed:
    /// only when this run computed every chunk of the surface (they need every row; a part,
    /// or a re-run that kept chunks, computes only some).
    #[serde(skip)]
    pub seams: Option<SeamStats>,
}

/// The parameter (`param_tiles_sha256` in a store) that records the SHA-256 digest of the
/// tiles' values ([`crate::tile::tileset::digest`]); a tile store without it cannot tell
/// whether its parts were written from the same tiles ([`check_zarr`]).
pub const TILES_DIGEST: &str = "tiles_sha256";

fn zerr(e: ZarrError) -> TileError {
    match e {
        ZarrError::Io { path, reason } => TileError::Output { path, reason },
        ZarrError::Mismatch { ref path, .. } => TileError::Output {
            path: path.clone(),
            reason: e.to_string(),
        },
    }
}

/// The root group's attributes: CF provenance, every parameter as `param_NAME` and the chunk
/// layout (nothing that depends on the part or the time).
fn group_attrs(src: &dyn RowSource, spec: &StreamSpec, layout: &ZarrLayout) -> Map<String, Value> {
    let mut a = attrs(&[
        ("Conventions", "CF-1.8"),
        ("title", &spec.title),
        ("source", &format!("cellsurf {VERSION} tile")),
        ("cellsurf_version", VERSION),
        (
            "comment",
            "Mosaic of toroidal ripple tiles, written chunk by chunk (chunks of whole tiles); periodic in x and y.",
        ),
    ]);
    a.insert("bin_size_m".into(), Value::from(src.bin_size()));
    a.insert(
        "chunk_tiles".into(),
        Value::from(vec![layout.tiles.0, layout.tiles.1]),
    );
    let (tnx, tny) = src.tile_size();
    a.insert("tile_bins".into(), Value::from(vec![tnx, tny]));
    for (k, v) in &spec.params {
        a.insert(format!("param_{k}"), toml_to_json(v));
    }
    a
}

fn coord(name: &str, n: usize, chunk: usize, long: &str, axis: &str, standard: &str) -> ArraySpec {
    let mut at = attrs(&[("units", "m"), ("long_name", long), ("axis", axis)]);
    if !standard.is_empty() {
        at.insert("standard_name".into(), Value::from(standard));
    }
    ArraySpec {
        name: name.into(),
        shape: vec![n as u64],
        chunks: vec![chunk as u64],
        dims: vec![name.into()],
        dtype: Dtype::F64,
        attrs: at,
    }
}

/// The arrays of the store.
fn array_specs(spec: &StreamSpec, layout: &ZarrLayout) -> Vec<ArraySpec> {
    let (w, h, nz) = (layout.width, layout.height, layout.levels);
    let (cx, cy) = layout.chunk;
    let (units, long) = spec.elevation_meta();
    let mut v = vec![
        coord(
            "x",
            w,
            cx,
            "x of the bin centre (periodic)",
            "X",
            "projection_x_coordinate",
        ),
        coord(
            "y",
            h,
            cy,
            "y of the bin centre (periodic)",
            "Y",
            "projection_y_coordinate",
        ),
        ArraySpec {
            name: "elevation".into(),
            shape: vec![h as u64, w as u64],
            chunks: vec![cy as u64, cx as u64],
            dims: vec!["y".into(), "x".into()],
            dtype: Dtype::F32,
            attrs: attrs(&[("units", units), ("long_name", long)]),
        },
    ];
    if let Some(f) = spec.volume.filter(|_| nz > 0) {
        let mut z = coord(
            "z",
            nz,
            nz,
            "height of the automaton centre above the substrate",
            "Z",
            "",
        );
        z.attrs.insert("positive".into(), Value::from("up"));
        v.push(z);
        v.push(ArraySpec::data_f32(
            f.name(),
            &["y", "z", "x"],
            &[h, nz, w],
            &[cy, nz, cx],
            f.meta(),
            "NaN above the bed",
        ));
    }
    v
}

/// The volume levels written for `spec` (0 without a volume field), checked against the source.
fn levels_of(src: &dyn RowSource, spec: &StreamSpec) -> Result<usize, TileError> {
    match spec.volume {
        None => Ok(0),
        Some(f) if src.levels() == 0 => Err(TileError::range(
            "volume",
            f.name(),
            "a volume field the tiles carry (tiles with volume levels)",
        )),
        Some(_) => Ok(src.levels()),
    }
}

/// Creates the store at `path` (its metadata), or checks that an existing one has the same
/// metadata; returns it with its layout.
/// `tiles`: tiles per chunk along x and y ([`ZarrLayout::with_tiles`]; default
/// [`ZarrLayout::new`]).
pub fn init_zarr(
    path: &Path,
    src: &dyn RowSource,
    spec: &StreamSpec,
    tiles: Option<(usize, usize)>,
) -> Result<(Store, ZarrLayout), TileError> {
    let nz = levels_of(src, spec)?;
    if src.width() == 0 || src.height() == 0 {
        return Err(TileError::range(
            "surface size",
            format!("{}x{}", src.width(), src.height()),
            "at least 1x1 bins",
        ));
    }
    let layout = match tiles {
        Some(t) => ZarrLayout::with_tiles(src, nz, t)?,
        None => ZarrLayout::new(src, nz),
    };
    let store = Store::create(
        path,
        group_attrs(src, spec, &layout),
        array_specs(spec, &layout),
    )
    .map_err(zerr)?;
    Ok((store, layout))
}

/// Checks, writing nothing, that the store at `path` has the metadata [`init_zarr`] would
/// give it for `src` and `spec` (its parameters, the tiles' digest among them, and its
/// arrays); `tiles` as [`init_zarr`], by default the store's own `chunk_tiles`. Errors name
/// what differs.
pub fn verify_zarr(
    path: &Path,
    src: &dyn RowSource,
    spec: &StreamSpec,
    tiles: Option<(usize, usize)>,
) -> Result<ZarrLayout, TileError> {
    let nz = levels_of(src, spec)?;
    let recorded = || -> Option<(usize, usize)> {
        let a = Store::open(path).ok()?.attributes().ok()?;
        let t = a.get("chunk_tiles")?.as_array()?;
        Some((t.first()?.as_u64()? as usize, t.get(1)?.as_u64()? as usize))
    };
    let layout = match tiles.or_else(recorded) {
        Some(t) => ZarrLayout::with_tiles(src, nz, t)?,
        None => ZarrLayout::new(src, nz),
    };
    Store::matches(
        path,
        group_attrs(src, spec, &layout),
        array_specs(spec, &layout),
    )
    .map_err(|e| TileError::Store(e.to_string()))?;
    Ok(layout)
}

/// Whether chunk `idx` of every array in `names` is complete.
fn complete(store: &Store, names: &[&str], idx: &[&[u64]]) -> Result<bool, TileError> {
    for (n, i) in names.iter().zip(idx) {
        if store.chunk_state(n, i).map_err(zerr)? != ChunkState::Ok {
            return Ok(false);
        }
    }
    Ok(true)
}

fn coords(n0: usize, n: usize, len: usize, step: f64) -> Vec<f64> {
    (n0..n0 + n)
        .map(|i| {
            if i < len {
                (i as f64 + 0.5) * step
            } else {
                f64::NAN
            }
        })
        .collect()
}

/// Writes the chunks of `part` of `src` to the store at `path` (module docs), creating the
/// store's metadata when absent (`tiles` as [`init_zarr`]). `progress(chunks done)` as it goes
/// (from any thread).
pub fn write_zarr(
    path: &Path,
    src: &dyn RowSource,
    spec: &StreamSpec,
    tiles: Option<(usize, usize)>,
    part: Part,
    progress: impl Fn(usize) + Sync,
) -> Result<ZarrReport, TileError> {
    let start = Instant::now();
    let (store, layout) = init_zarr(path, src, spec, tiles)?;
    let (w, h, nz) = (layout.width, layout.height, layout.levels);
    let (cx, cy) = layout.chunk;
    let vol = spec.volume.filter(|_| nz > 0).map(|f| f.name());
    let dx = src.bin_size();
    let owned = part.range(layout.chunks());
    let n_owned = owned.len();
    let (done, written, stored, values, bins) = (
        AtomicUsize::new(0),
        AtomicUsize::new(0),
        AtomicU64::new(0),
        AtomicU64::new(0),
        AtomicU64::new(0),
    );
    // The seam statistic and the slopes need every chunk: measured by a run of the whole
    // store (a part computes only its share; a run that keeps chunks reports none).
    let measure = part.count == 1;
    let (tnx, tny) = src.tile_size();
    let sums = Mutex::new(SeamSums::new(w, h, tnx, tny, true));
    let size_of = |name: &str, idx: &[u64]| {
        store
            .chunk_path(name, idx)
            .ok()
            .and_then(|p| std::fs::metadata(p).ok())
            .map_or(0, |m| m.len())
    };
    // the temporary files killed writers left for this part's chunks
    let rows = owned.start / layout.grid.0..owned.end.div_ceil(layout.grid.0);
    let mine = |cj: usize, name: &str| {
        name.parse::<usize>()
            .is_ok_and(|ci| ci < layout.grid.0 && owned.contains(&(cj * layout.grid.0 + ci)))
    };
    for cj in rows.clone() {
        let dirs = std::iter::once(format!("elevation/c/{cj}"))
            .chain(vol.map(|v| format!("{v}/c/{cj}/0")));
        for d in dirs {
            remove_temporaries_in(&path.join(d), |n| mine(cj, n));
        }
    }
    remove_temporaries_in(&path.join("x/c"), |n| mine(0, n));
    remove_temporaries_in(&path.join("y/c"), |n| {
        n.parse::<usize>().is_ok_and(|cj| mine(cj, "0"))
    });
    if owned.contains(&0) {
        remove_temporaries_in(&path.join("z/c"), |n| n == "0");
    }
    owned
        .clone()
        .into_par_iter()
        .try_for_each(|k| -> Result<(), TileError> {
            let (ci, cj) = (k % layout.grid.0, k / layout.grid.0);
            let (x0, y0) = (ci * cx, cj * cy);
            let (nxs, nys) = (cx.min(w - x0), cy.min(h - y0));
            let e_idx = [cj as u64, ci as u64];
            let v_idx = [cj as u64, 0, ci as u64];
            // the coordinate chunks go with the first row and column of chunks
            let mut extra: Vec<(&str, u64, Vec<f64>)> = Vec::new();
            if cj == 0 {
                extra.push(("x", ci as u64, coords(x0, cx, w, dx)));
            }
            if ci == 0 {
                extra.push(("y", cj as u64, coords(y0, cy, h, dx)));
            }
            if k == 0 && vol.is_some() {
                extra.push(("z", 0, coords(0, nz, nz, src.layer_thickness())));
            }
            for (name, i, data) in &extra {
                if store.chunk_state(name, &[*i]).map_err(zerr)? != ChunkState::Ok {
                    store.write_chunk_f64(name, &[*i], data).map_err(zerr)?;
                }
            }
            let mut names = vec!["elevation"];
            let mut idxs: Vec<&[u64]> = vec![&e_idx];
            if let Some(v) = vol {
                names.push(v);
                idxs.push(&v_idx);
            }
            if !complete(&store, &names, &idxs)? {
                let mut elev = vec![f32::NAN; cx * cy];
                for r in 0..nys {
                    src.fill_span(y0 + r, x0, &mut elev[r * cx..r * cx + nxs]);
                }
                if measure {
                    // the column and the row after the chunk (periodic)
                    let mut next_col = vec![0.0f32; nys];
                    for (r, v) in next_col.iter_mut().enumerate() {
                        src.fill_span(y0 + r, (x0 + nxs) % w, std::slice::from_mut(v));
                    }
                    let mut next_row = vec![0.0f32; nxs];
                    src.fill_span((y0 + nys) % h, x0, &mut next_row);
                    let block = SeamBlock::measure(
                        (x0, y0),
                        (nxs, nys),
                        (&elev, cx),
                        (&next_col, &next_row),
                        Some(dx),
                        h > 1,
                    );
                    if let Ok(mut s) = sums.lock() {
                        s.add(&block);
                    }
                }
                store
                    .write_chunk_f32("elevation", &e_idx, &elev)
                    .map_err(zerr)?;
                drop(elev);
                let mut n_values = nxs * nys;
                if let Some(v) = vol {
                    let mut chunk = vec![f32::NAN; cy * nz * cx];
                    let mut slab = vec![f32::NAN; nz * nxs];
                    for r in 0..nys {
                        src.fill_volume_span(y0 + r, x0, &mut slab);
                        for z in 0..nz {
                            let o = (r * nz + z) * cx;
                            chunk[o..o + nxs].copy_from_slice(&slab[z * nxs..(z + 1) * nxs]);
                        }
                    }
                    store.write_chunk_f32(v, &v_idx, &chunk).map_err(zerr)?;
                    n_values += nxs * nys * nz;
                }
                let s: u64 = names.iter().zip(&idxs).map(|(n, i)| size_of(n, i)).sum();
                stored.fetch_add(s, Ordering::Relaxed);
                values.fetch_add(4 * n_values as u64, Ordering::Relaxed);
                bins.fetch_add((nxs * nys) as u64, Ordering::Relaxed);
                written.fetch_add(1, Ordering::Relaxed);
            }
            progress(done.fetch_add(1, Ordering::Relaxed) + 1);
            Ok(())
        })?;
    let written = written.into_inner();
    let seams = (measure && written == layout.chunks())
        .then(|| sums.into_inner().ok().map(SeamSums::finish))
        .flatten();
    Ok(ZarrReport {
        layout,
        part,
        owned: n_owned,
        written,
        kept: n_owned - written,
        bytes: values.into_inner(),
        stored_bytes: stored.into_inner(),
        bins: bins.into_inner(),
        elapsed_s: start.elapsed().as_secs_f64(),
        seams,
    })
}

/// Whether `path` is a Zarr store: a folder with a root `zarr.json`, which a run finishes in
/// place.
pub fn is_store(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.is_dir()) && path.join("zarr.json").is_file()
}

/// The entries of the folder `path` (a store without its root `zarr.json`) that no writer of a
/// store made: anything but the arrays' folders with their metadata alone and temporary files
/// (`.NAME.tmp-PID`), which another part leaves there while it creates the store's metadata.
fn foreign_entries(path: &Path) -> Result<Vec<String>, String> {
    let arrays: Vec<&str> = ["x", "y", "z"]
        .into_iter()
        .chain(crate::ripple::output::Field::ALL.iter().map(|f| f.name()))
        .collect();
    let list = |dir: &Path| -> Result<Vec<(String, bool)>, String> {
        let rd = std::fs::read_dir(dir).map_err(|e| format!("cannot be read: {e}"))?;
        Ok(rd
            .flatten()
            .map(|e| {
                let dir = e.file_type().is_ok_and(|t| t.is_dir());
                (e.file_name().to_string_lossy().into_owned(), dir)
            })
            .collect())
    };
    let temporary = |name: &str, dir: bool| !dir && is_temporary(Path::new(name));
    let mut other = Vec::new();
    for (name, dir) in list(path)? {
        let made = temporary(&name, dir)
            || (dir
                && arrays.contains(&name.as_str())
                && list(&path.join(&name))?
                    .iter()
                    .all(|(n, d)| (n == "zarr.json" && !d) || temporary(n, *d)));
        if !made {
            other.push(name);
        }
    }
    other.sort();
    Ok(other)
}

/// Checks, before a run writes anything, that a tile store can be written at `path`: its
/// folder exists, and `path` is absent (a new store) or a Zarr store ([`is_store`]: parts,
/// `--init` or an earlier run made it), which the run finishes in place. With `in_place` (a
/// part, or the metadata alone, written into the folder itself) an existing folder may also be
/// empty, or hold only what another part writes before the store's root document (its arrays'
/// metadata and temporary files). Anything else (a file, a link, a folder with other content)
/// is refused, never written into; the error says why and what to do.
pub fn check_store_target(path: &Path, in_place: bool) -> Result<(), String> {
    if crate::engine::zarr::store_target(path)? != Some(false) {
        return Ok(());
    }
    let other = foreign_entries(path)?;
    if other.is_empty() && in_place {
        return Ok(());
    }
    let holds = if other.is_empty() {
        String::new()
    } else {
        let mut names = other.iter().take(3).cloned().collect::<Vec<_>>().join(", ");
        if other.len() > 3 {
            names.push_str(&format!(" and {} more", other.len() - 3));
        }
        format!("; it holds {names}")
    };
    // (only a whole run refuses a folder without other content)
    let empty_ok = if other.is_empty() {
        " (a new store is written beside it and renamed into place; --part and --init write into an empty folder)"
    } else {
        ""
    };
    Err(format!(
        "exists and is not a Zarr store (no zarr.json{holds}); remove it or choose another name{empty_ok}"
    ))
}

/// Writes the whole store (every chunk) as one output: a store absent at `path` is written
/// into a temporary folder beside it (`.NAME.tmp-PID`) and moved into place only once complete
/// ([`crate::engine::io::publish`]), so that a failed or interrupted run leaves no store under
/// its name (the `cellsurf` program removes the folder on Ctrl-C); an existing store at `path`
/// (parts or a run left it) is finished in place, its complete chunks kept ([`write_zarr`]).
/// Anything else at `path` (a file, a link, a folder that is not a store, even an empty one)
/// is refused ([`check_store_target`]), never written into.
pub fn write_zarr_whole(
    path: &Path,
    src: &dyn RowSource,
    spec: &StreamSpec,
    tiles: Option<(usize, usize)>,
    progress: impl Fn(usize) + Sync,
) -> Result<ZarrReport, TileError> {
    let out = |reason: String| TileError::Output {
        path: path.display().to_string(),
        reason,
    };
    check_store_target(path, false).map_err(out)?;
    if is_store(path) {
        return write_zarr(path, src, spec, tiles, Part::WHOLE, progress);
    }
    let tmp = crate::engine::io::temp_path(path);
    let _ = std::fs::remove_dir_all(&tmp);
    let guard = crate::engine::io::TempFile::new(path);
    let result = write_zarr(&tmp, src, spec, tiles, Part::WHOLE, progress).and_then(|rep| {
        if std::fs::symlink_metadata(path).is_ok() {
            return Err(out(format!(
                "appeared while this run wrote the store into {} (another process writing it?); this run's store was discarded",
                tmp.display()
            )));
        }
        crate::engine::io::publish(&tmp, path).map_err(|e| out(e.to_string()))?;
        Ok(rep)
    });
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&tmp);
    }
    drop(guard);
    result
}

/// The state of one array of a store.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ArrayCheck {
    /// The array.
    pub name: String,
    /// Its chunks.
    pub chunks: usize,
    /// Chunks present and sound.
    pub complete: usize,
    /// Chunk indices not written.
    pub missing: Vec<Vec<u64>>,
    /// Chunk indices present that do not decode, with the reason.
    pub damaged: Vec<(Vec<u64>, String)>,
}

/// What [`check_zarr`] found.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ZarrCheck {
    /// The store.
    pub store: PathBuf,
    /// Per array.
    pub arrays: Vec<ArrayCheck>,
    /// Temporary files left by killed writers.
    pub stale_temporaries: Vec<PathBuf>,
    /// Every chunk of every array present and sound, and (for a tile store) the tiles it was
    /// made from identified ([`ZarrCheck::unverified`] empty).
    pub complete: bool,
    /// The SHA-256 digest of the tiles' values the store was made from ([`TILES_DIGEST`]),
    /// where recorded.
    pub tiles_sha256: Option<String>,
    /// Why the chunks cannot be known to come from one set of tiles: a tile store (it records
    /// `param_tiles`) without the tiles' digest, made by a cellsurf that recorded only the tile
    /// files' names and steps, whose parts may have read different contents under one name.
    pub unverified: Option<String>,
    /// Chunks of the surface along x and y.
    pub grid: (usize, usize),
}

impl ZarrCheck {
    /// Missing chunks, all arrays.
    pub fn missing(&self) -> usize {
        self.arrays.iter().map(|a| a.missing.len()).sum()
    }
    /// Damaged chunks, all arrays.
    pub fn damaged(&self) -> usize {
        self.arrays.iter().map(|a| a.damaged.len()).sum()
    }
    /// The parts of `count` that own a missing or damaged surface chunk (elevation or volume,
    /// whose chunk grids are the same in y and x; a coordinate chunk goes with the first row
    /// or column of chunks), to re-run.
    pub fn parts_to_rerun(&self, count: usize) -> Vec<usize> {
        let (gx, gy) = self.grid;
        let total = gx * gy;
        let count = count.max(1);
        let starts: Vec<usize> = (0..count)
            .map(|p| Part { index: p, count }.range(total).start)
            .collect();
        let mut parts = std::collections::BTreeSet::new();
        for a in &self.arrays {
            for idx in a.missing.iter().chain(a.damaged.iter().map(|d| &d.0)) {
                let k = match a.name.as_str() {
                    "x" => idx[0] as usize,
                    "y" => idx[0] as usize * gx,
                    "z" => 0,
                    _ => idx[0] as usize * gx + idx[idx.len() - 1] as usize,
                };
                // the last part whose range starts at or before k
                let p = starts.partition_point(|&s| s <= k).saturating_sub(1);
                parts.insert(p);
            }
        }
        parts.into_iter().collect()
    }
}

/// Checks every chunk of every array of the store at `path` (module docs).
pub fn check_zarr(path: &Path) -> Result<ZarrCheck, TileError> {
    let store = Store::open(path).map_err(zerr)?;
    let mut arrays = Vec::new();
    for spec in store.arrays() {
        let grid = spec.grid();
        let n: u64 = grid.iter().product();
        let states: Vec<(Vec<u64>, ChunkState)> = (0..n)
            .into_par_iter()
            .map(|k| {
                let mut idx = vec![0u64; grid.len()];
                let mut r = k;
                for d in (0..grid.len()).rev() {
                    idx[d] = r % grid[d];
                    r /= grid[d];
                }
                let s = store
                    .chunk_state(&spec.name, &idx)
                    .unwrap_or_else(|e| ChunkState::Damaged(e.to_string()));
                (idx, s)
            })
            .collect();
        let mut a = ArrayCheck {
            name: spec.name.clone(),
            chunks: n as usize,
            complete: 0,
            missing: Vec::new(),
            damaged: Vec::new(),
        };
        for (idx, s) in states {
            match s {
                ChunkState::Ok => a.complete += 1,
                ChunkState::Missing => a.missing.push(idx),
                ChunkState::Damaged(why) => a.damaged.push((idx, why)),
            }
        }
        arrays.push(a);
    }
    let grid = store
        .spec("elevation")
        .map(|e| {
            let g = e.grid();
            (g[1] as usize, g[0] as usize)
        })
        .unwrap_or((1, 1));
    let stale = store.stale_temporaries();
    let at = store.attributes().map_err(zerr)?;
    let tiles_sha256 = at
        .get(&format!("param_{TILES_DIGEST}"))
        .and_then(Value::as_str)
        .map(str::to_string);
    let unverified = (at.contains_key("param_tiles") && tiles_sha256.is_none()).then(|| {
        format!(
            "the store records its tiles by file name and step only (param_tiles), not their values (param_{TILES_DIGEST}): parts written from different contents under one file name cannot be told apart; write it again"
        )
    });
    let complete = unverified.is_none()
        && arrays
            .iter()
            .all(|a| a.missing.is_empty() && a.damaged.is_empty());
    Ok(ZarrCheck {
        store: path.to_path_buf(),
        arrays,
        stale_temporaries: stale,
        complete,
        tiles_sha256,
        unverified,
        grid,
    })
}
