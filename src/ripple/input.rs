//! Reading back a ripple volume written by [`super::output::write_netcdf`]: [`read`] returns a
//! [`RippleFile`] with the grid, the elevation snapshots, the volume fields that were written
//! and the run's parameters (from the `param_*` global attributes).
//!
//! This is how tiling and ray tracing take their seafloor from a file, and how the tests check
//! that a written file says what the run computed.

use std::path::Path;

use netcdf3::{FileReader, NC_FILL_F32};

use super::RippleError;
use super::output::Field;
use super::params::{Frame, RippleParams};

/// The content of a ripple NetCDF file.
#[derive(Clone, Debug, PartialEq)]
pub struct RippleFile {
    /// Columns along x.
    pub nx: usize,
    /// Columns along y.
    pub ny: usize,
    /// Automaton levels of the volume fields (0 when none was written).
    pub nz: usize,
    /// Horizontal bin size, m.
    pub bin_size: f64,
    /// Automaton (layer) thickness, m.
    pub layer_thickness: f64,
    /// Model steps of the elevation snapshots.
    pub times: Vec<u64>,
    /// Elevation above the substrate, m, one `ny x nx` grid (rows of x) per snapshot.
    pub elevation: Vec<Vec<f32>>,
    /// Volume fields, each `nz x ny x nx` (z from the substrate up), NaN above the bed.
    pub fields: Vec<(Field, Vec<f32>)>,
    /// The run's parameters, rebuilt from the file's `param_*` attributes.
    pub params: RippleParams,
    /// The `cellsurf_version` attribute.
    pub version: String,
}

impl RippleFile {
    /// The volume field `f`, if it was written.
    pub fn field(&self, f: Field) -> Option<&[f32]> {
        self.fields
            .iter()
            .find(|(g, _)| *g == f)
            .map(|(_, v)| v.as_slice())
    }

    /// The last elevation snapshot, if any.
    pub fn final_elevation(&self) -> Option<&[f32]> {
        self.elevation.last().map(|v| v.as_slice())
    }
}

/// A short description of a NetCDF read error (the library's own carries byte dumps).
pub fn describe(e: &netcdf3::ReadError) -> String {
    use netcdf3::ReadError as E;
    match e {
        E::ParseHeader(_) => "not a NetCDF-3 file (its header cannot be read)".into(),
        E::IOErrorKind(k) => std::io::Error::from(*k).to_string(),
        E::VariableNotDefined(v) => format!("no variable '{v}'"),
        other => crate::engine::io::short(&format!("{other:?}")),
    }
}

fn read_err(path: &Path, reason: impl std::fmt::Display) -> RippleError {
    RippleError::Input {
        path: path.display().to_string(),
        reason: reason.to_string(),
    }
}

/// Why `path` cannot be read as a ripple NetCDF file before it is opened, if it cannot: it
/// does not exist, it is a folder (a Zarr store or another), or it is a pipe or a socket,
/// which would be waited on. A device is left to the NetCDF reader (`/dev/null`: not a
/// NetCDF-3 file).
fn not_a_file(path: &Path) -> Option<String> {
    let meta = match std::fs::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Some("no such file".into()),
        Err(e) => return Some(e.to_string()),
    };
    let kind = meta.file_type();
    if kind.is_dir() {
        let zarr = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("zarr"))
            || path.join("zarr.json").is_file();
        return Some(if zarr {
            "a Zarr store (a folder), not a NetCDF file: only NetCDF (.nc) ripple files are read \
             here; write the run as one with `cellsurf ripple --out FILE.nc` (the same scenario \
             and seed give the same run)"
                .into()
        } else {
            "a folder, not a file: expected a ripple NetCDF file (`cellsurf ripple --out FILE.nc`)"
                .into()
        });
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() || kind.is_socket() {
            return Some(format!(
                "not a NetCDF-3 file (a {}, not a regular file)",
                if kind.is_fifo() { "pipe" } else { "socket" }
            ));
        }
    }
    None
}

/// What [`read`] will hold of a ripple NetCDF file, from its header alone ([`file_size`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FileSize {
    /// Columns along x.
    pub nx: usize,
    /// Columns along y.
    pub ny: usize,
    /// Elevation snapshots.
    pub snapshots: usize,
    /// Volume fields written.
    pub fields: usize,
    /// Automaton levels of the volume fields (0 when none was written).
    pub levels: usize,
}

impl FileSize {
    /// Bytes [`read`] holds at its peak: 4 per value, the elevation snapshots twice (as read,
    /// then one grid per snapshot) and each volume field once.
    pub fn read_bytes(&self) -> f64 {
        let columns = self.nx as f64 * self.ny as f64;
        4.0 * columns * (2.0 * self.snapshots as f64 + (self.fields * self.levels) as f64)
    }
}

/// The sizes in the header of the ripple NetCDF file `path`, read without its data, so that a
/// caller can check the memory [`read`] will take before it allocates; `None` where the header
/// cannot be read as a ripple file's ([`read`] then says why).
pub fn file_size(path: &Path) -> Option<FileSize> {
    if not_a_file(path).is_some() {
        return None;
    }
    let r = FileReader::open(path).ok()?;
    let ds = r.data_set();
    let (nx, ny) = (ds.dim_size("x")?, ds.dim_size("y")?);
    let columns = nx.checked_mul(ny)?.max(1);
    Some(FileSize {
        nx,
        ny,
        snapshots: ds.var_len("elevation").unwrap_or(0) / columns,
        fields: Field::ALL
            .into_iter()
            .filter(|&f| f != Field::Elevation && ds.get_var(f.name()).is_some())
            .count(),
        levels: ds.dim_size("z").unwrap_or(0),
    })
}

/// Reads a ripple NetCDF file. Errors name the file and what is missing or inconsistent.
pub fn read(path: &Path) -> Result<RippleFile, RippleError> {
    if let Some(reason) = not_a_file(path) {
        return Err(read_err(path, reason));
    }
    let mut r = FileReader::open(path).map_err(|e| read_err(path, describe(&e)))?;
    let ds = r.data_set();
    let dim = |name: &str| {
        ds.dim_size(name).ok_or_else(|| {
            read_err(
                path,
                format!("no dimension '{name}': not a cellsurf ripple file"),
            )
        })
    };
    let nx = dim("x")?;
    let ny = dim("y")?;
    let nz = ds.dim_size("z").unwrap_or(0);
    let version = ds
        .get_global_attr_as_string("cellsurf_version")
        .ok_or_else(|| {
            read_err(
                path,
                "no 'cellsurf_version' attribute: not a cellsurf ripple file",
            )
        })?;

    let mut table = toml::Table::new();
    // Every key, with its type.
    let every = RippleParams::every_key();
    let defaults = match toml::Value::try_from(every) {
        Ok(toml::Value::Table(t)) => t,
        _ => toml::Table::new(),
    };
    for (key, default) in defaults {
        let attr = format!("param_{key}");
        let value = if let Some(v) = ds.get_global_attr_f64(&attr) {
            match (default, v.first()) {
                (toml::Value::Integer(_), Some(&x)) => toml::Value::Integer(x as i64),
                // booleans are written as 0 or 1
                (toml::Value::Boolean(_), Some(&x)) => toml::Value::Boolean(x != 0.0),
                (_, Some(&x)) => toml::Value::Float(x),
                (_, None) => continue,
            }
        } else if let Some(s) = ds.get_global_attr_as_string(&attr) {
            toml::Value::String(s)
        } else {
            continue;
        };
        table.insert(key, value);
    }
    if table.is_empty() {
        return Err(read_err(
            path,
            "the file records no run parameters (param_* attributes)",
        ));
    }
    let mut params: RippleParams = toml::Value::Table(table)
        .try_into()
        .map_err(|e| read_err(path, format!("parameters: {e}")))?;
    // The lattice's frame: recorded as `param_frame` when it is not the default; otherwise told
    // by the x axis's direction (files written before the flow frame have neither: grid).
    params.frame = match ds.get_global_attr_as_string("param_frame") {
        Some(s) => s
            .parse()
            .map_err(|e| read_err(path, format!("parameters: {e}")))?,
        None => match ds
            .get_global_attr_f64("x_axis_direction_deg")
            .and_then(|v| v.first().copied())
        {
            Some(a) if (a - params.frame_angle()).rem_euclid(360.0) == 0.0 => Frame::Flow,
            _ => Frame::Grid,
        },
    };

    let has_elevation = ds.get_var("elevation").is_some();
    let written: Vec<Field> = Field::ALL
        .into_iter()
        .filter(|&f| f != Field::Elevation && ds.get_var(f.name()).is_some())
        .collect();
    let mut times = Vec::new();
    let mut elevation = Vec::new();
    if has_elevation {
        // (a double since steps past 2^24 were written; a float in older files)
        let ts: Vec<f64> = match r
            .read_var("time")
            .map_err(|e| read_err(path, format!("time: {}", describe(&e))))?
        {
            netcdf3::DataVector::F64(v) => v,
            netcdf3::DataVector::F32(v) => v.into_iter().map(f64::from).collect(),
            _ => return Err(read_err(path, "time is neither a float nor a double")),
        };
        let all = r
            .read_var_f32("elevation")
            .map_err(|e| read_err(path, format!("elevation: {}", describe(&e))))?;
        if all.len() != ts.len() * nx * ny {
            return Err(read_err(path, "elevation has the wrong size"));
        }
        times = ts.iter().map(|&t| t as u64).collect();
        elevation = all.chunks(nx * ny).map(|c| c.to_vec()).collect();
    }
    let mut fields = Vec::new();
    for f in written {
        let mut v = r
            .read_var_f32(f.name())
            .map_err(|e| read_err(path, format!("{}: {}", f.name(), describe(&e))))?;
        if v.len() != nz * ny * nx {
            return Err(read_err(path, format!("{} has the wrong size", f.name())));
        }
        for x in &mut v {
            if *x == NC_FILL_F32 {
                *x = f32::NAN;
            }
        }
        fields.push((f, v));
    }
    Ok(RippleFile {
        nx,
        ny,
        nz,
        bin_size: params.bin_size,
        layer_thickness: params.layer_thickness,
        times,
        elevation,
        fields,
        params,
        version,
    })
}
