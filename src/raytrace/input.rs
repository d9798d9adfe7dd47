//! Reading a seafloor surface from a NetCDF-3 file for [`Grid::section`](super::seafloor::Grid::section):
//! [`read_surface`] takes either a ripple volume (`cellsurf ripple --out`: a `time` record
//! dimension, read by [`crate::ripple::input::read`]) or a mosaic (`cellsurf tile --out`:
//! `elevation(y, x)` with `y` the record dimension, coordinates `x`, `y` in m, and maybe a volume
//! field `FIELD(y, z, x)`). A mosaic's bin size is its recorded `param_bin_size` (a double),
//! else the spacing of its float32 `x` coordinate; its
//! impedance is the top non-fill value of each column of an `impedance(y, z, x)` field, or none.
//!
//! A Zarr store (`cellsurf tile --out X.zarr`, feature `zarr`) is not read whole:
//! [`ZarrSurface`] reads the chunks a section crosses as it goes. A ripple run's store
//! (`cellsurf ripple --out X.zarr`) is read whole, as its NetCDF file is: [`read_ripple_store`].
//!
//! Errors are short: an I/O error's message, or what is wrong with the file, never its bytes.

use std::path::Path;

use netcdf3::error::ReadError;
use netcdf3::error::parse_header_error::ParseHeaderErrorKind;
use netcdf3::{FileReader, NC_FILL_F32};

use super::RaytraceError;
use super::seafloor::RippleSurface;

/// Most cells of a mosaic read whole (8e7: 0.6 GB of elevation).
pub const MAX_MOSAIC_CELLS: usize = 80_000_000;

/// Which kind of file a surface came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceKind {
    /// A ripple volume (`cellsurf ripple --out`).
    Ripple,
    /// A mosaic (`cellsurf tile --out`).
    Mosaic,
}

impl SurfaceKind {
    /// A short name: "ripple file" or "tile mosaic".
    pub fn name(self) -> &'static str {
        match self {
            SurfaceKind::Ripple => "ripple file",
            SurfaceKind::Mosaic => "tile mosaic",
        }
    }
}

/// A short description of a NetCDF-3 read error (never the bytes it carries).
pub fn describe_read_error(e: &ReadError) -> String {
    match e {
        ReadError::ParseHeader(h) => match &h.kind {
            ParseHeaderErrorKind::MagicWord | ParseHeaderErrorKind::VersionNumber => {
                "not a NetCDF-3 file".into()
            }
            _ if h.header_is_incomplete() => "truncated NetCDF-3 header".into(),
            k => format!("invalid NetCDF-3 header ({k:?})"),
        },
        ReadError::DataSet(_) => "inconsistent NetCDF-3 data set".into(),
        ReadError::VariableNotDefined(v) => format!("no variable '{v}'"),
        ReadError::VariableMismatchDataType { var_name, req, .. } => {
            format!("variable '{var_name}' is {req:?}, expected F32")
        }
        ReadError::IOErrorKind(k) => std::io::Error::from(*k).to_string(),
        ReadError::ComputationNumberOfRecords => "cannot compute the number of records".into(),
        ReadError::RecordIndexExceeded { index, num_records } => {
            format!("record {index} beyond the {num_records} records")
        }
        ReadError::Unexpected => "unexpected read error".into(),
    }
}

fn err(path: &Path, reason: impl std::fmt::Display) -> RaytraceError {
    RaytraceError::Input {
        what: path.display().to_string(),
        reason: reason.to_string(),
    }
}

/// Reads the surface of a ripple or mosaic NetCDF file (module docs).
pub fn read_surface(path: &Path) -> Result<(RippleSurface, SurfaceKind), RaytraceError> {
    // the I/O error with its message (the reader keeps only its kind)
    std::fs::File::open(path).map_err(|e| err(path, e))?;
    let mut r = FileReader::open(path)
        .map_err(|e| err(path, format!("cannot read: {}", describe_read_error(&e))))?;
    let ds = r.data_set();
    if ds.has_var("time") {
        drop(r);
        let f = crate::ripple::input::read(path).map_err(|e| match e {
            crate::ripple::RippleError::Input { reason, .. } => err(path, reason),
            e => err(path, e),
        })?;
        return Ok((RippleSurface::from_file(&f)?, SurfaceKind::Ripple));
    }
    let dims = ds.get_var("elevation").map(|v| v.dim_names());
    // a ripple run's volume written without its elevation (`--fields` without it)
    let volume_only = [
        "grain_size",
        "porosity",
        "density",
        "sound_speed",
        "impedance",
    ]
    .iter()
    .any(|v| ds.has_var(v));
    if dims.is_none() && volume_only {
        return Err(err(
            path,
            "a ripple file without the bed's elevation (written with --fields that leave it \
             out): a seafloor needs it; write the run with --fields elevation,...",
        ));
    }
    if dims.as_deref() != Some(&["y".to_string(), "x".to_string()][..]) {
        return Err(err(
            path,
            "neither a ripple file (no 'time') nor a mosaic (no 'elevation(y, x)')",
        ));
    }
    let nx = ds.dim_size("x").unwrap_or(0);
    let ny = ds.dim_size("y").unwrap_or(0);
    if nx == 0 || ny == 0 {
        return Err(err(path, format!("empty mosaic ({nx} x {ny})")));
    }
    if nx.saturating_mul(ny) > MAX_MOSAIC_CELLS {
        return Err(err(
            path,
            format!("mosaic of {nx} x {ny} cells: at most {MAX_MOSAIC_CELLS} can be read"),
        ));
    }
    let read = |r: &mut FileReader, v: &str| {
        r.read_var_f32(v)
            .map_err(|e| err(path, format!("{v}: {}", describe_read_error(&e))))
    };
    // the recorded bin size (a double) when present: the float32 `x` spacing is off by up to
    // a few parts in 1e7
    let recorded = r
        .data_set()
        .get_global_attr_f64("param_bin_size")
        .and_then(|v| v.first().copied());
    let xs = read(&mut r, "x")?;
    let bin = match (recorded, xs.as_slice()) {
        (Some(b), _) => b,
        (None, [a, b, ..]) => f64::from(*b) - f64::from(*a),
        _ => {
            let ys = read(&mut r, "y")?;
            match ys.as_slice() {
                [a, b, ..] => f64::from(*b) - f64::from(*a),
                [a] => 2.0 * f64::from(*a),
                [] => f64::NAN,
            }
        }
    };
    if !(bin.is_finite() && bin > 0.0) {
        return Err(err(
            path,
            format!(
                "bin size {bin} m from {}",
                if recorded.is_some() {
                    "the attribute 'param_bin_size'"
                } else {
                    "the 'x' coordinate"
                }
            ),
        ));
    }
    let elev = read(&mut r, "elevation")?;
    if elev.len() != nx * ny {
        return Err(err(path, "elevation has the wrong size"));
    }
    let vol = r.data_set().get_var("impedance").map(|v| v.dim_names());
    let impedance = match vol {
        Some(d) if d == ["y", "z", "x"] => {
            let nz = r.data_set().dim_size("z").unwrap_or(0);
            let mut imp = Vec::with_capacity(nx * ny);
            for y in 0..ny {
                let slab = r
                    .read_record_f32("impedance", y)
                    .map_err(|e| err(path, format!("impedance: {}", describe_read_error(&e))))?;
                if slab.len() != nz * nx {
                    return Err(err(path, "impedance has the wrong size"));
                }
                imp.extend((0..nx).map(|x| {
                    (0..nz)
                        .rev()
                        .map(|z| slab[z * nx + x])
                        .find(|&v| v != NC_FILL_F32 && v.is_finite())
                        .map(f64::from)
                }));
            }
            imp
        }
        _ => Vec::new(),
    };
    Ok((
        RippleSurface {
            nx,
            ny,
            bin,
            elevation: elev.iter().map(|&v| f64::from(v)).collect(),
            impedance,
        },
        SurfaceKind::Mosaic,
    ))
}

/// The surface of a ripple run's Zarr store (`cellsurf ripple --out X.zarr`,
/// [`crate::ripple::zarr`]): its last elevation snapshot, `elevation(time, y, x)`, and, when
/// the store has the field, the top non-NaN value of each column of `impedance(z, y, x)`: the
/// surface [`RippleSurface::from_file`] reads from the NetCDF file of the same run. `None`
/// for a store without `elevation(time, y, x)` (a tile store, [`ZarrSurface`]).
#[cfg(feature = "zarr")]
pub fn read_ripple_store(path: &Path) -> Result<Option<RippleSurface>, RaytraceError> {
    let store = crate::engine::zarr::Store::open(path).map_err(|e| err(path, e))?;
    let Some(spec) = store
        .spec("elevation")
        .filter(|s| s.dims == ["time", "y", "x"])
        .cloned()
    else {
        return Ok(None);
    };
    let [nt, ny, nx] = [0, 1, 2].map(|k| spec.shape[k] as usize);
    if nt == 0 {
        return Err(err(
            path,
            "no elevation snapshot (write it with --fields elevation,...)",
        ));
    }
    if nx == 0 || ny == 0 {
        return Err(err(path, format!("empty surface ({nx} x {ny})")));
    }
    if nx.saturating_mul(ny) > MAX_MOSAIC_CELLS {
        return Err(err(
            path,
            format!("surface of {nx} x {ny} cells: at most {MAX_MOSAIC_CELLS} can be read"),
        ));
    }
    if spec.chunks != [1, ny as u64, nx as u64] {
        return Err(err(
            path,
            "elevation is not one chunk a snapshot, as `cellsurf ripple` writes it",
        ));
    }
    let attrs = store.attributes().map_err(|e| err(path, e))?;
    let bin = attrs
        .get("bin_size_m")
        .and_then(|v| v.as_f64())
        .unwrap_or(f64::NAN);
    if !(bin.is_finite() && bin > 0.0) {
        return Err(err(
            path,
            format!("bin size {bin} m (attribute 'bin_size_m')"),
        ));
    }
    let elev = store
        .read_chunk_f32("elevation", &[nt as u64 - 1, 0, 0])
        .map_err(|e| err(path, e))?;
    if elev.len() != nx * ny || elev.iter().any(|v| !v.is_finite()) {
        return Err(err(path, "the last elevation snapshot is incomplete"));
    }
    let vol = store
        .spec("impedance")
        .filter(|s| {
            s.dims == ["z", "y", "x"]
                && s.shape[1..] == [ny as u64, nx as u64]
                && s.chunks[0] == s.shape[0]
                && s.chunks[2] == nx as u64
                && s.chunks[1] > 0
        })
        .cloned();
    let mut impedance = Vec::new();
    if let Some(v) = vol {
        let (nz, rows) = (v.shape[0] as usize, v.chunks[1] as usize);
        impedance.reserve(nx * ny);
        for (j, y0) in (0..ny).step_by(rows).enumerate() {
            let chunk = store
                .read_chunk_f32("impedance", &[0, j as u64, 0])
                .map_err(|e| err(path, format!("impedance: {e}")))?;
            if chunk.len() != nz * rows * nx {
                return Err(err(path, "impedance has the wrong size"));
            }
            for dy in 0..rows.min(ny - y0) {
                impedance.extend((0..nx).map(|x| {
                    (0..nz)
                        .rev()
                        .map(|z| chunk[(z * rows + dy) * nx + x])
                        .find(|v| v.is_finite())
                        .map(f64::from)
                }));
            }
        }
    }
    Ok(Some(RippleSurface {
        nx,
        ny,
        bin,
        elevation: elev.iter().map(|&v| f64::from(v)).collect(),
        impedance,
    }))
}

/// A Zarr store written by `cellsurf tile --out X.zarr` ([`crate::engine::zarr`]) read chunk by
/// chunk as a section goes: `elevation(y, x)` (m) and, when the store has it, the top
/// non-NaN value of each column of `impedance(y, z, x)`. Only the chunks that the section's
/// samples (and their bilinear neighbours) fall in are read, and at most
/// [`ZarrSurface::CACHE`] chunks are held at once, so memory does not grow with the store.
#[cfg(feature = "zarr")]
pub struct ZarrSurface {
    store: crate::engine::zarr::Store,
    nx: usize,
    ny: usize,
    bin: f64,
    /// Chunk size along x and y, bins.
    chunk: (usize, usize),
    levels: usize,
    impedance: bool,
    elev: Vec<((usize, usize), Vec<f32>)>,
    imp: Vec<((usize, usize), Vec<f32>)>,
    /// Chunks read (elevation and impedance).
    pub chunks_read: usize,
}

#[cfg(feature = "zarr")]
impl ZarrSurface {
    /// Chunks held at once per array (the four round a bin at a chunk corner, and a few more).
    pub const CACHE: usize = 6;

    /// Opens the store at `path`: it needs `elevation(y, x)` and its bin size (the spacing of
    /// `x`, or the attribute `bin_size_m`).
    pub fn open(path: &Path) -> Result<ZarrSurface, RaytraceError> {
        let store = crate::engine::zarr::Store::open(path).map_err(|e| err(path, e))?;
        let spec = store
            .spec("elevation")
            .filter(|s| s.dims == ["y", "x"])
            .ok_or_else(|| {
                err(
                    path,
                    "no 'elevation(y, x)' array (a tile store, `cellsurf tile --out X.zarr`) \
                     nor 'elevation(time, y, x)' (a ripple store, `cellsurf ripple --out X.zarr`)",
                )
            })?
            .clone();
        let (ny, nx) = (spec.shape[0] as usize, spec.shape[1] as usize);
        let chunk = (spec.chunks[1] as usize, spec.chunks[0] as usize);
        let attrs = store.attributes().map_err(|e| err(path, e))?;
        let bin = match attrs.get("bin_size_m").and_then(|v| v.as_f64()) {
            Some(b) => b,
            None => {
                let xs = store.read_chunk_f64("x", &[0]).map_err(|e| err(path, e))?;
                match xs.as_slice() {
                    [a, b, ..] => b - a,
                    [a] => 2.0 * a,
                    [] => f64::NAN,
                }
            }
        };
        if !(bin.is_finite() && bin > 0.0) {
            return Err(err(path, format!("bin size {bin} m")));
        }
        if nx == 0 || ny == 0 {
            return Err(err(path, format!("empty mosaic ({nx} x {ny})")));
        }
        let vol = store
            .spec("impedance")
            .filter(|s| s.dims == ["y", "z", "x"] && s.chunks[0] == spec.chunks[0])
            .map(|s| s.shape[1] as usize);
        Ok(ZarrSurface {
            store,
            nx,
            ny,
            bin,
            chunk,
            levels: vol.unwrap_or(0),
            impedance: vol.is_some(),
            elev: Vec::new(),
            imp: Vec::new(),
            chunks_read: 0,
        })
    }

    /// Bins along x and y, and the bin size (m).
    pub fn shape(&self) -> (usize, usize, f64) {
        (self.nx, self.ny, self.bin)
    }

    /// The chunk holding bin `(i, j)`, read if not held (the oldest dropped beyond
    /// [`ZarrSurface::CACHE`]); returns its slot.
    fn chunk_of(&mut self, vol: bool, ci: usize, cj: usize) -> Result<usize, RaytraceError> {
        let cache = if vol { &self.imp } else { &self.elev };
        if let Some(k) = cache.iter().position(|c| c.0 == (ci, cj)) {
            return Ok(k);
        }
        let path = self.store.root().to_path_buf();
        let data = if vol {
            self.store
                .read_chunk_f32("impedance", &[cj as u64, 0, ci as u64])
        } else {
            self.store
                .read_chunk_f32("elevation", &[cj as u64, ci as u64])
        }
        .map_err(|e| err(&path, e))?;
        self.chunks_read += 1;
        let cache = if vol { &mut self.imp } else { &mut self.elev };
        if cache.len() >= Self::CACHE {
            cache.remove(0);
        }
        cache.push(((ci, cj), data));
        Ok(cache.len() - 1)
    }

    fn value(&mut self, i: usize, j: usize) -> Result<f64, RaytraceError> {
        let (cx, cy) = self.chunk;
        let k = self.chunk_of(false, i / cx, j / cy)?;
        let v = self.elev[k].1[(j % cy) * cx + i % cx];
        if v.is_nan() {
            return Err(err(
                self.store.root(),
                format!(
                    "elevation of bin ({i}, {j}) missing (an unwritten chunk: run `cellsurf tile --check`)"
                ),
            ));
        }
        Ok(f64::from(v))
    }
}

#[cfg(feature = "zarr")]
impl super::seafloor::SurfaceSampler for ZarrSurface {
    fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }
    fn bin(&self) -> f64 {
        self.bin
    }
    /// Bilinear and periodic, as [`super::seafloor::Grid::elevation_at`].
    fn elevation(&mut self, x: f64, y: f64) -> Result<f64, RaytraceError> {
        let k = super::seafloor::BilinearCell::at(x, y, self.bin, self.nx, self.ny);
        let (a, b) = (self.value(k.i0, k.j0)?, self.value(k.i1, k.j0)?);
        let (c, d) = (self.value(k.i0, k.j1)?, self.value(k.i1, k.j1)?);
        Ok(k.blend(a, b, c, d))
    }
    fn impedance(&mut self, x: f64, y: f64) -> Result<Option<f64>, RaytraceError> {
        if !self.impedance {
            return Ok(None);
        }
        let w = |v: f64, n: usize| ((v / self.bin).floor() as i64).rem_euclid(n as i64) as usize;
        let (i, j) = (w(x, self.nx), w(y, self.ny));
        let (cx, cy) = self.chunk;
        let k = self.chunk_of(true, i / cx, j / cy)?;
        let (r, c, nz) = (j % cy, i % cx, self.levels);
        let slab = &self.imp[k].1;
        Ok((0..nz)
            .rev()
            .map(|z| slab[(r * nz + z) * cx + c])
            .find(|v| v.is_finite())
            .map(f64::from))
    }
    fn has_impedance(&self) -> bool {
        self.impedance
    }
}
