//! Streaming a surface of any size to disk row by row: [`RowSource`] (anything that can compute
//! one row of a `width x height` surface on demand: a [`super::Mosaic`], [`super::RippledDunes`])
//! and [`write_stream`].
//!
//! Formats ([`StreamFormat`]):
//! - **NetCDF-3, 64-bit offset** (netCDF4-python, scipy, xarray, GDAL and `ncdump` read it):
//!   `y` is the record (unlimited) dimension, so row `j` of `elevation(y, x)` is record `j`,
//!   written as it is computed; a volume field is `FIELD(y, z, x)` (the record dimension has to
//!   come first: one record holds the `(z, x)` slab under row `j`), `_FillValue` above the bed.
//!   CF attributes, every parameter and the version as global attributes. 64-bit offset allows
//!   files beyond 4 GiB (each record under 4 GiB, at most 2^31 - 1 rows).
//! - **`.npy`** (numpy; `numpy.load(path, mmap_mode="r")` maps files larger than memory):
//!   `STEM.npy` is `elevation` as `(y, x)` float32, `STEM_FIELD.npy` the volume field as
//!   `(y, z, x)` (NaN above the bed), `STEM.json` the parameters, version, shapes and units.
//!   The header (shape known in advance) is written first, then the rows.
//!
//! Memory is a block of rows (at most 64, and at most about 64 MB) computed in parallel with
//! rayon and written in order, plus the row source itself: it does not grow with the number of
//! rows. (NetCDF only: the `netcdf3` writer keeps a set of written record numbers, a few bytes
//! per row.) Every file goes to a temporary sibling and is renamed when complete, so a reader
//! never sees a partial output, even when the run is interrupted. The seam statistic is measured
//! on the rows as they are written ([`SeamMeter`]).

use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use netcdf3::{DataSet, FileWriter, NC_FILL_F32, Version};
use rayon::prelude::*;
use serde::Serialize;

use super::TileError;
use super::seam::{SeamMeter, SeamStats};
use crate::ripple::VERSION;
use crate::ripple::output::{Field, add_provenance, json_string, json_value, npy_header};

/// A surface computed row by row.
pub trait RowSource: Sync {
    /// Bins along x (the length of a row).
    fn width(&self) -> usize;
    /// Rows.
    fn height(&self) -> usize;
    /// Bin size, m.
    fn bin_size(&self) -> f64;
    /// The tile size in bins (for the seam statistic).
    fn tile_size(&self) -> (usize, usize);
    /// Writes row `y` (elevation, m) into `out` (`width` values).
    fn fill_row(&self, y: usize, out: &mut [f32]);
    /// Levels of the volume field beneath (0: none).
    fn levels(&self) -> usize {
        0
    }
    /// Height of one volume level (the tiles' automaton), m: every source says its own.
    fn layer_thickness(&self) -> f64;
    /// Writes the volume slab under row `y` on `(z, x)` (`levels x width` values, NaN above the
    /// bed) into `out`.
    fn fill_volume_row(&self, _y: usize, out: &mut [f32]) {
        out.fill(f32::NAN);
    }
    /// Writes bins `x0 .. x0 + out.len()` of row `y` (within the row) into `out`: the values of
    /// [`RowSource::fill_row`], for sources written chunk by chunk (a Zarr store). The default
    /// computes the whole row.
    fn fill_span(&self, y: usize, x0: usize, out: &mut [f32]) {
        let mut row = vec![0.0f32; self.width()];
        self.fill_row(y, &mut row);
        out.copy_from_slice(&row[x0..x0 + out.len()]);
    }
    /// Writes the volume slab under bins `x0 .. x0 + n` of row `y` on `(z, x)` (`levels x n`
    /// values, `n = out.len() / levels`) into `out`: the values of
    /// [`RowSource::fill_volume_row`]. The default computes the whole slab.
    fn fill_volume_span(&self, y: usize, x0: usize, out: &mut [f32]) {
        let (nz, w) = (self.levels(), self.width());
        if nz == 0 {
            out.fill(f32::NAN);
            return;
        }
        let n = out.len() / nz;
        let mut slab = vec![f32::NAN; nz * w];
        self.fill_volume_row(y, &mut slab);
        for k in 0..nz {
            out[k * n..(k + 1) * n].copy_from_slice(&slab[k * w + x0..k * w + x0 + n]);
        }
    }
}

/// Output format of the stream: the ripple output's [`Format`](crate::ripple::Format)
/// (`netcdf`: NetCDF-3, 64-bit offset, `y` the record dimension; `npy`: `.npy` files and a
/// JSON sidecar).
pub type StreamFormat = crate::ripple::Format;

/// What to write.
#[derive(Clone, Debug, PartialEq)]
pub struct StreamSpec {
    /// File format.
    pub format: StreamFormat,
    /// The volume field written beneath the surface (the source must have levels), if any.
    pub volume: Option<Field>,
    /// Title (NetCDF `title`, JSON `title`).
    pub title: String,
    /// Parameters recorded in the file (NetCDF global attributes `param_NAME`, JSON
    /// `parameters`).
    pub params: Vec<(String, toml::Value)>,
    /// The `long_name` of `elevation` when it is not the ripple bed's ("bed elevation above the
    /// non-erodible substrate"), e.g. with dune relief added (NetCDF attribute, JSON field).
    pub elevation_long_name: Option<String>,
}

impl StreamSpec {
    /// The units and long name of `elevation`.
    pub(crate) fn elevation_meta(&self) -> (&'static str, &str) {
        let (units, long) = Field::Elevation.meta();
        (units, self.elevation_long_name.as_deref().unwrap_or(long))
    }
}

/// What a stream wrote.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StreamReport {
    /// Bins along x.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Volume levels written (0: none).
    pub levels: usize,
    /// Bytes written, all files.
    pub bytes: u64,
    /// Seam statistic of the written surface.
    pub seams: SeamStats,
    /// Seconds, computing and writing.
    pub elapsed_s: f64,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// The bytes [`write_stream`] will write for `src` (within a few kB of header).
pub fn estimate_bytes(src: &dyn RowSource, spec: &StreamSpec) -> u64 {
    let (w, h) = (src.width() as u64, src.height() as u64);
    let nz = if spec.volume.is_some() {
        src.levels() as u64
    } else {
        0
    };
    let header = 4096 + 64 * spec.params.len() as u64;
    match spec.format {
        StreamFormat::NetCdf => header + 4 * w + 4 * nz + h * (4 + 4 * w + 4 * nz * w),
        // a Zarr store is compressed: the uncompressed size bounds it
        StreamFormat::Npy | StreamFormat::Zarr => header + 4 * w * h * (1 + nz),
    }
}

fn out_err(path: &Path, e: impl std::fmt::Display) -> TileError {
    TileError::Output {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// A NetCDF writer's error as a message: an I/O error's own text, else the writer's
/// description.
fn nc_err(path: &Path, e: netcdf3::WriteError) -> TileError {
    out_err(path, crate::engine::io::netcdf_write_reason(&e))
}

/// The files of a `.npy` stream to `path`, in order: `STEM.npy` (elevation), `STEM_FIELD.npy`
/// (the volume field, if any) and the JSON sidecar `STEM.json`.
pub fn npy_files(path: &Path, volume: Option<Field>) -> Vec<PathBuf> {
    let stem = path.with_extension("");
    let named = |suffix: &str| {
        let mut s = stem.as_os_str().to_owned();
        s.push(suffix);
        PathBuf::from(s)
    };
    let mut files = vec![named(".npy")];
    if let Some(f) = volume {
        files.push(named(&format!("_{}.npy", f.name())));
    }
    files.push(named(".json"));
    files
}

/// Rows per block: at most 64 and about 64 MB of rows (and slabs), at least 1.
fn block_rows(width: usize, nz: usize) -> usize {
    let per_row = 4 * width * (1 + nz);
    ((64usize << 20) / per_row.max(1)).clamp(1, 64)
}

/// Computes the rows of `src` block by block (in parallel within a block) and hands each row,
/// with its volume slab when `nz > 0`, in order to `sink`; `progress(rows done)` after each
/// block.
fn for_each_row(
    src: &dyn RowSource,
    nz: usize,
    mut sink: impl FnMut(usize, &[f32], &[f32]) -> Result<(), TileError>,
    mut progress: impl FnMut(usize),
) -> Result<(), TileError> {
    let (w, h) = (src.width(), src.height());
    let block = block_rows(w, nz);
    let mut y0 = 0;
    while y0 < h {
        let y1 = (y0 + block).min(h);
        let rows: Vec<(Vec<f32>, Vec<f32>)> = (y0..y1)
            .into_par_iter()
            .map(|y| {
                let mut row = vec![0.0f32; w];
                src.fill_row(y, &mut row);
                let mut slab = vec![f32::NAN; nz * w];
                if nz > 0 {
                    src.fill_volume_row(y, &mut slab);
                }
                (row, slab)
            })
            .collect();
        for (k, (row, slab)) in rows.iter().enumerate() {
            sink(y0 + k, row, slab)?;
        }
        y0 = y1;
        progress(y0);
    }
    Ok(())
}

/// Checks the source against the format's limits.
fn check_source(src: &dyn RowSource, nz: usize) -> Result<(), TileError> {
    let (w, h) = (src.width(), src.height());
    if w == 0 || h == 0 {
        return Err(TileError::range(
            "surface size",
            format!("{w}x{h}"),
            "at least 1x1 bins",
        ));
    }
    let limit = i32::MAX as usize;
    if w > limit || h > limit || nz > limit {
        return Err(TileError::range(
            "surface size",
            format!("{w}x{h}x{nz}"),
            format!("at most {limit} bins a side"),
        ));
    }
    // a record (one row, or one slab) of a 64-bit offset file stays under 4 GiB
    if (4 * w as u64) * (nz.max(1) as u64) >= 1 << 32 {
        return Err(TileError::range(
            "surface width x levels",
            format!("{w} x {nz}"),
            "under 2^30 values per row (a NetCDF-3 record under 4 GiB)",
        ));
    }
    Ok(())
}

/// Streams `src` to `path` as `spec` says; `progress(rows done)` as it goes. For `.npy`,
/// `path`'s extension is replaced (`STEM.npy`, `STEM_FIELD.npy`, `STEM.json`), and an earlier
/// mosaic's `STEM_FIELD.npy` that its sidecar lists and this one does not write is removed
/// once this one's files are in place ([`crate::engine::io::retire`]). Every file is
/// written to a temporary sibling and renamed when complete; on error nothing is left behind.
pub fn write_stream(
    path: &Path,
    src: &dyn RowSource,
    spec: &StreamSpec,
    progress: impl FnMut(usize),
) -> Result<StreamReport, TileError> {
    let nz = if spec.volume.is_some() {
        src.levels()
    } else {
        0
    };
    if spec.volume.is_some() && nz == 0 {
        return Err(TileError::range(
            "volume",
            spec.volume.map(|f| f.name()).unwrap_or(""),
            "a volume field the tiles carry (tiles with volume levels)",
        ));
    }
    check_source(src, nz)?;
    let start = Instant::now();
    let (tnx, tny) = src.tile_size();
    let mut meter = SeamMeter::new(src.width(), tnx, tny).with_slopes(src.bin_size());
    let files = match spec.format {
        StreamFormat::NetCdf => {
            write_netcdf_stream(path, src, spec, nz, &mut meter, progress)?;
            vec![path.to_path_buf()]
        }
        StreamFormat::Npy => {
            // an earlier mosaic's volume file (listed by its sidecar) that this one does not
            // write goes with it, once this one's files are in place
            let new = npy_files(path, spec.volume);
            let stale = crate::engine::io::stale_npy_files(new.last().expect("a sidecar"), &new);
            let files = write_npy_stream(path, src, spec, nz, &mut meter, progress)?;
            crate::engine::io::retire(&stale).map_err(|e| out_err(path, e.to_string()))?;
            files
        }
        StreamFormat::Zarr => {
            return Err(TileError::range(
                "format",
                "zarr",
                "netcdf or npy for a single-file stream (Zarr stores are written chunk by chunk by tile::zarr::write_zarr)",
            ));
        }
    };
    let bytes = files
        .iter()
        .map(|f| crate::engine::io::output_len(f).unwrap_or(0))
        .sum();
    Ok(StreamReport {
        width: src.width(),
        height: src.height(),
        levels: nz,
        bytes,
        seams: meter.finish(),
        elapsed_s: start.elapsed().as_secs_f64(),
        files,
    })
}

fn write_netcdf_stream(
    path: &Path,
    src: &dyn RowSource,
    spec: &StreamSpec,
    nz: usize,
    meter: &mut SeamMeter,
    progress: impl FnMut(usize),
) -> Result<(), TileError> {
    let (w, h) = (src.width(), src.height());
    let mut ds = DataSet::new();
    ds.add_fixed_dim("x", w).map_err(|x| out_err(path, x))?;
    ds.set_unlimited_dim("y", h).map_err(|x| out_err(path, x))?;
    let coord = |ds: &mut DataSet, name: &str, units: &str, long: &str, axis: &str| {
        ds.add_var_f32(name, &[name])?;
        ds.add_var_attr_string(name, "units", units)?;
        ds.add_var_attr_string(name, "long_name", long)?;
        ds.add_var_attr_string(name, "axis", axis)
    };
    coord(&mut ds, "x", "m", "x of the bin centre (periodic)", "X")
        .map_err(|x| out_err(path, x))?;
    coord(&mut ds, "y", "m", "y of the bin centre (periodic)", "Y")
        .map_err(|x| out_err(path, x))?;
    let (units, long) = spec.elevation_meta();
    ds.add_var_f32("elevation", &["y", "x"])
        .map_err(|x| out_err(path, x))?;
    ds.add_var_attr_string("elevation", "units", units)
        .map_err(|x| out_err(path, x))?;
    ds.add_var_attr_string("elevation", "long_name", long)
        .map_err(|x| out_err(path, x))?;
    let vol = spec.volume.filter(|_| nz > 0);
    if let Some(f) = vol {
        ds.add_fixed_dim("z", nz).map_err(|x| out_err(path, x))?;
        coord(
            &mut ds,
            "z",
            "m",
            "height of the automaton centre above the substrate",
            "Z",
        )
        .map_err(|x| out_err(path, x))?;
        ds.add_var_attr_string("z", "positive", "up")
            .map_err(|x| out_err(path, x))?;
        let (units, long) = f.meta();
        ds.add_var_f32(f.name(), &["y", "z", "x"])
            .map_err(|x| out_err(path, x))?;
        ds.add_var_attr_string(f.name(), "units", units)
            .map_err(|x| out_err(path, x))?;
        ds.add_var_attr_string(f.name(), "long_name", long)
            .map_err(|x| out_err(path, x))?;
        ds.add_var_attr_f32(f.name(), "_FillValue", vec![NC_FILL_F32])
            .map_err(|x| out_err(path, x))?;
    }
    add_provenance(
        &mut ds,
        &spec.title,
        "tile",
        "Mosaic of toroidal ripple tiles, written row by row (y is the record dimension); periodic in x and y.",
        &spec.params,
    )
    .map_err(|x| out_err(path, x))?;

    // Listed while alive, so that an interrupted run removes it (crate::engine::io).
    let guard = crate::engine::io::TempFile::new(path);
    let tmp = guard.path().to_path_buf();
    let result = (|| -> Result<(), TileError> {
        let file = fs::File::create(&tmp).map_err(|x| out_err(path, x))?;
        let tmp_str = tmp.to_string_lossy().to_string();
        let mut wr = FileWriter::open_seek_write(
            &tmp_str,
            Box::new(BufWriter::with_capacity(1 << 20, file)),
        )
        .map_err(|x| nc_err(path, x))?;
        wr.set_def(&ds, Version::Offset64Bit, 0)
            .map_err(|x| nc_err(path, x))?;
        let dx = src.bin_size();
        let xs: Vec<f32> = (0..w).map(|i| ((i as f64 + 0.5) * dx) as f32).collect();
        wr.write_var_f32("x", &xs).map_err(|x| nc_err(path, x))?;
        if let Some(_f) = vol {
            let gd = src.layer_thickness();
            let zs: Vec<f32> = (0..nz).map(|k| ((k as f64 + 0.5) * gd) as f32).collect();
            wr.write_var_f32("z", &zs).map_err(|x| nc_err(path, x))?;
        }
        let mut slab_nc = Vec::new();
        for_each_row(
            src,
            if vol.is_some() { nz } else { 0 },
            |y, row, slab| {
                meter.push_row(row);
                wr.write_record_f32("y", y, &[((y as f64 + 0.5) * dx) as f32])
                    .map_err(|x| nc_err(path, x))?;
                wr.write_record_f32("elevation", y, row)
                    .map_err(|x| nc_err(path, x))?;
                if let Some(f) = vol {
                    slab_nc.clear();
                    slab_nc.extend(
                        slab.iter()
                            .map(|&v| if v.is_finite() { v } else { NC_FILL_F32 }),
                    );
                    wr.write_record_f32(f.name(), y, &slab_nc)
                        .map_err(|x| nc_err(path, x))?;
                }
                Ok(())
            },
            progress,
        )?;
        wr.close().map_err(|x| nc_err(path, x))?;
        fs::File::open(&tmp)
            .and_then(|f| f.sync_all())
            .map_err(|x| out_err(path, x))?;
        crate::engine::io::publish(&tmp, path).map_err(|x| out_err(path, x))
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

fn write_npy_stream(
    path: &Path,
    src: &dyn RowSource,
    spec: &StreamSpec,
    nz: usize,
    meter: &mut SeamMeter,
    progress: impl FnMut(usize),
) -> Result<Vec<PathBuf>, TileError> {
    let (w, h) = (src.width(), src.height());
    let vol = spec.volume.filter(|_| nz > 0);
    let mut finals = npy_files(path, vol);
    let side = finals.pop().unwrap_or_else(|| path.with_extension("json"));
    // every file's place checked before any work (a sidecar that cannot be written would
    // otherwise fail after the arrays)
    for p in finals.iter().chain([&side]) {
        crate::engine::io::check_output("output", p).map_err(|x| out_err(p, x))?;
    }
    // Listed while alive, so that an interrupted run removes them (crate::engine::io).
    let guards: Vec<crate::engine::io::TempFile> = finals
        .iter()
        .map(|p| crate::engine::io::TempFile::new(p))
        .collect();
    let temps: Vec<PathBuf> = guards.iter().map(|g| g.path().to_path_buf()).collect();
    let result = (|| -> Result<(), TileError> {
        let open = |p: &Path, shape: &[usize]| -> Result<BufWriter<fs::File>, TileError> {
            let f = fs::File::create(p).map_err(|x| out_err(p, x))?;
            let mut b = BufWriter::with_capacity(1 << 20, f);
            b.write_all(&npy_header(shape)).map_err(|x| out_err(p, x))?;
            Ok(b)
        };
        let mut elev = open(&temps[0], &[h, w])?;
        let mut volw = match vol {
            Some(_) => Some(open(&temps[1], &[h, nz, w])?),
            None => None,
        };
        let mut bytes = Vec::with_capacity(4 * w * nz.max(1));
        for_each_row(
            src,
            if vol.is_some() { nz } else { 0 },
            |_y, row, slab| {
                meter.push_row(row);
                bytes.clear();
                bytes.extend(row.iter().flat_map(|v| v.to_le_bytes()));
                elev.write_all(&bytes).map_err(|x| out_err(&temps[0], x))?;
                if let Some(vw) = volw.as_mut() {
                    bytes.clear();
                    bytes.extend(slab.iter().flat_map(|v| v.to_le_bytes()));
                    vw.write_all(&bytes).map_err(|x| out_err(&temps[1], x))?;
                }
                Ok(())
            },
            progress,
        )?;
        let sync = |b: BufWriter<fs::File>, p: &Path| -> Result<(), TileError> {
            let f = b
                .into_inner()
                .map_err(|x| out_err(p, x.error().to_string()))?;
            f.sync_all().map_err(|x| out_err(p, x))
        };
        sync(elev, &temps[0])?;
        if let Some(vw) = volw {
            sync(vw, &temps[1])?;
        }
        Ok(())
    })();
    if let Err(err) = result {
        for t in &temps {
            let _ = fs::remove_file(t);
        }
        return Err(err);
    }
    for (t, f) in temps.iter().zip(&finals) {
        crate::engine::io::publish(t, f).map_err(|x| out_err(f, x))?;
    }
    drop(guards);
    let file_name = |p: &Path| {
        json_string(
            &p.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
        )
    };
    let (eu, el) = spec.elevation_meta();
    let mut fields = vec![format!(
        "    \"elevation\": {{\"file\": {}, \"dims\": [\"y\", \"x\"], \"shape\": [{h}, {w}], \"units\": {}, \"long_name\": {}}}",
        file_name(&finals[0]),
        json_string(eu),
        json_string(el)
    )];
    if let Some(f) = vol {
        let (u, l) = f.meta();
        fields.push(format!(
            "    {}: {{\"file\": {}, \"dims\": [\"y\", \"z\", \"x\"], \"shape\": [{h}, {nz}, {w}], \"units\": {}, \"long_name\": {}, \"fill\": \"NaN above the bed\"}}",
            json_string(f.name()),
            file_name(&finals[1]),
            json_string(u),
            json_string(l)
        ));
    }
    let params: Vec<String> = spec
        .params
        .iter()
        .map(|(k, v)| format!("    {}: {}", json_string(k), json_value(v)))
        .collect();
    let json = format!(
        "{{\n  \"cellsurf_version\": {},\n  \"model\": \"tile\",\n  \"title\": {},\n  \"bin_size_m\": {},\n  \"layer_thickness_m\": {},\n  \"x_of_bin_i_m\": \"(i + 0.5) * bin_size_m\",\n  \"fields\": {{\n{}\n  }},\n  \"parameters\": {{\n{}\n  }}\n}}\n",
        json_string(VERSION),
        json_string(&spec.title),
        src.bin_size(),
        src.layer_thickness(),
        fields.join(",\n"),
        params.join(",\n")
    );
    crate::engine::io::write_atomic(&side, json.as_bytes()).map_err(|x| out_err(&side, x))?;
    finals.push(side);
    Ok(finals)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat surface of 8 x 6 bins.
    struct Flat;

    impl RowSource for Flat {
        fn width(&self) -> usize {
            8
        }
        fn height(&self) -> usize {
            6
        }
        fn bin_size(&self) -> f64 {
            0.01
        }
        fn layer_thickness(&self) -> f64 {
            0.001
        }
        fn tile_size(&self) -> (usize, usize) {
            (4, 3)
        }
        fn fill_row(&self, _y: usize, out: &mut [f32]) {
            out.fill(0.01);
        }
    }

    #[test]
    fn a_failed_write_says_what_went_wrong_in_words() {
        let dir = std::env::temp_dir().join(format!("cellsurf-stream-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(dir.join("m.json")).unwrap();
        let spec = StreamSpec {
            format: StreamFormat::Npy,
            volume: None,
            title: "t".into(),
            params: Vec::new(),
            elevation_long_name: None,
        };
        let err = write_stream(&dir.join("m.npy"), &Flat, &spec, |_| {})
            .unwrap_err()
            .to_string();
        // the I/O error's message, not its debug form (`Custom { kind: ... }`, `Os { code ... }`)
        assert!(err.contains("m.json"), "{err}");
        assert!(err.contains("not a regular file"), "{err}");
        assert!(
            !err.contains("Custom {") && !err.contains("kind:") && !err.contains("Os {"),
            "{err}"
        );
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn npy_files_are_the_elevation_the_volume_and_the_sidecar() {
        let f = npy_files(Path::new("a/m.npy"), Some(Field::Impedance));
        let want = ["a/m.npy", "a/m_impedance.npy", "a/m.json"];
        assert_eq!(f, want.map(PathBuf::from));
        assert_eq!(
            npy_files(Path::new("m.npy"), None),
            ["m.npy", "m.json"].map(PathBuf::from)
        );
    }
}
