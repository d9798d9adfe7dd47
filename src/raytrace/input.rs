//! Reading a seafloor surface from a NetCDF-3 file for [`Grid::section`](super::seafloor::Grid::section):
//! [`read_surface`] takes either a ripple volume (`cellsurf ripple --out`: a `time` record
//! dimension, read by [`crate::ripple::input::read`]) or a mosaic (`cellsurf tile --out`:
//! `elevation(y, x)` with `y` the record dimension, coordinates `x`, `y` in m, and maybe a volume
//! field `FIELD(y, z, x)`). A mosaic's bin size is the spacing of its `x` coordinate; its
//! impedance is the top non-fill value of each column of an `impedance(y, z, x)` field, or none.
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
    let xs = read(&mut r, "x")?;
    let bin = match xs.as_slice() {
        [a, b, ..] => f64::from(*b) - f64::from(*a),
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
            format!("bin size {bin} m from the 'x' coordinate"),
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
