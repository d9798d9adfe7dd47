//! [`OutputSpec`]: what a run writes, and the writers: NetCDF-3 (64-bit offset, CF-style
//! names, units and attributes; every parameter and the version as global attributes) or one
//! `.npy` file per field plus a JSON sidecar. Every file is written to a temporary sibling and
//! renamed ([`crate::engine::io`]).
//!
//! Variables: `elevation(time, y, x)` (m, bed height above the substrate at the snapshot
//! steps) and the final volume fields `grain_size`, `porosity`, `density`, `sound_speed`,
//! `impedance` on `(z, y, x)`, where `z` indexes automata from the substrate up (cell centre
//! `z = (k + 1/2) gd`); cells above the bed hold the fill value (NetCDF `_FillValue`
//! 9.96921e36, NaN in `.npy`). Only the fields asked for are computed and written.

use std::fmt::Write as _;
use std::fs;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use netcdf3::{DataSet, FileWriter, NC_FILL_F32, Version};

use super::acoustics::density_speed;
use super::compaction::porosity;
use super::model::Ripple;
use super::params::AcousticModel;
use super::{RippleError, VERSION};

/// A field that can be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// Bed elevation at the snapshot steps, m.
    Elevation,
    /// Grain diameter of each automaton, mm.
    GrainSize,
    /// Porosity of each automaton.
    Porosity,
    /// Bulk density, kg/m^3.
    Density,
    /// Sound speed, m/s.
    SoundSpeed,
    /// Acoustic impedance, kg m^-2 s^-1.
    Impedance,
}

impl Field {
    /// Every field, in output order.
    pub const ALL: [Field; 6] = [
        Field::Elevation,
        Field::GrainSize,
        Field::Porosity,
        Field::Density,
        Field::SoundSpeed,
        Field::Impedance,
    ];

    /// Variable name.
    pub fn name(self) -> &'static str {
        match self {
            Field::Elevation => "elevation",
            Field::GrainSize => "grain_size",
            Field::Porosity => "porosity",
            Field::Density => "density",
            Field::SoundSpeed => "sound_speed",
            Field::Impedance => "impedance",
        }
    }

    /// (units, long_name).
    pub fn meta(self) -> (&'static str, &'static str) {
        match self {
            Field::Elevation => ("m", "bed elevation above the non-erodible substrate"),
            Field::GrainSize => ("mm", "grain diameter of the automaton (sediment bin)"),
            Field::Porosity => ("1", "porosity (void volume fraction) of the automaton"),
            Field::Density => ("kg m-3", "sediment bulk density"),
            Field::SoundSpeed => ("m s-1", "compressional sound speed in the sediment"),
            Field::Impedance => (
                "kg m-2 s-1",
                "acoustic impedance (bulk density x sound speed)",
            ),
        }
    }
}

impl std::fmt::Display for Field {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Field {
    type Err = RippleError;
    fn from_str(s: &str) -> Result<Self, RippleError> {
        Field::ALL
            .into_iter()
            .find(|f| f.name() == s.trim())
            .ok_or_else(|| RippleError::Unknown {
                parameter: "fields",
                value: s.to_string(),
                expected: "elevation, grain_size, porosity, density, sound_speed or impedance",
            })
    }
}

/// Output file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// NetCDF-3, 64-bit offset.
    NetCdf,
    /// One `.npy` per field and a `.json` sidecar.
    Npy,
    /// A Zarr v3 store (a folder; feature `zarr`, [`super::zarr`]).
    Zarr,
}

impl FromStr for Format {
    type Err = RippleError;
    fn from_str(s: &str) -> Result<Self, RippleError> {
        match s {
            "netcdf" | "nc" => Ok(Format::NetCdf),
            "npy" => Ok(Format::Npy),
            "zarr" => Ok(Format::Zarr),
            _ => Err(RippleError::Unknown {
                parameter: "format",
                value: s.to_string(),
                expected: "netcdf, npy or zarr",
            }),
        }
    }
}

/// What to write.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputSpec {
    /// Fields, without repeats.
    pub fields: Vec<Field>,
    /// File format.
    pub format: Format,
}

impl OutputSpec {
    /// Checks the combination: the APL-UW preset has no porosity, so it cannot be written with
    /// a porosity field.
    pub fn validate(&self, model: AcousticModel) -> Result<(), RippleError> {
        if model == AcousticModel::AplUw && self.fields.contains(&Field::Porosity) {
            return Err(RippleError::Range {
                parameter: "fields",
                value: self
                    .fields
                    .iter()
                    .map(|f| f.name())
                    .collect::<Vec<_>>()
                    .join(","),
                expected: "fields without porosity with acoustics = apl-uw (a look-alike preset \
                           that ignores porosity)"
                    .into(),
            });
        }
        if self.fields.is_empty() {
            return Err(RippleError::Unknown {
                parameter: "fields",
                value: String::new(),
                expected: "at least one of elevation, grain_size, porosity, density, sound_speed, impedance",
            });
        }
        Ok(())
    }
}

/// Runs `steps` steps, keeping the elevation (m, f32) at each of `times` (steps since the start
/// of this call, at most `steps`; 0 = before the first step). `progress(done)` after each step.
pub fn run_recording(
    r: &mut Ripple,
    steps: u64,
    times: &[u64],
    mut progress: impl FnMut(u64),
) -> Vec<(u64, Vec<f32>)> {
    let mut out = Vec::new();
    let grab = |r: &Ripple| {
        r.elevation()
            .iter()
            .map(|&v| v as f32)
            .collect::<Vec<f32>>()
    };
    let t0 = r.time();
    if times.contains(&0) {
        out.push((t0, grab(r)));
    }
    for i in 1..=steps {
        r.step();
        if times.contains(&i) {
            out.push((t0 + i, grab(r)));
        }
        progress(i);
    }
    out
}

/// The top height of the volume (largest column), automata.
pub fn volume_levels(r: &Ripple) -> usize {
    r.volume().heights().iter().copied().max().unwrap_or(0) as usize
}

/// A volume field on `(z, y, x)`, `levels x ny x nx` values, `fill` above the bed.
pub fn volume_field(r: &Ripple, field: Field, fill: f32) -> Vec<f32> {
    let (nx, ny) = r.size();
    let nz = volume_levels(r);
    let vol = r.volume();
    let cls = r.classes();
    let model = r.params().acoustics;
    let mut out = vec![fill; nz * ny * nx];
    for c in 0..nx * ny {
        for z in 0..vol.height(c) {
            let a = vol.get(c, z);
            let k = a.class() as usize;
            let eps = porosity(a.porosity_code());
            let v = match field {
                Field::GrainSize => cls.d[k] * 1e3,
                Field::Porosity => eps,
                Field::Density | Field::SoundSpeed | Field::Impedance => {
                    let (rho, c_s) = density_speed(model, cls.phi[k], eps);
                    match field {
                        Field::Density => rho,
                        Field::SoundSpeed => c_s,
                        _ => rho * c_s,
                    }
                }
                Field::Elevation => vol.height(c) as f64 * r.params().layer_thickness,
            };
            out[z * nx * ny + c] = v as f32;
        }
    }
    out
}

/// The value of `field` for the top automaton of each column, row-major (`None` on bare
/// columns, where the substrate shows).
pub fn surface_field(r: &Ripple, field: Field) -> Vec<Option<f64>> {
    let (nx, ny) = r.size();
    let vol = volume_field(r, field, f32::NAN);
    (0..nx * ny)
        .map(|c| {
            let h = r.volume().height(c);
            (h > 0).then(|| vol[(h - 1) * nx * ny + c] as f64)
        })
        .collect()
}

fn out_err(path: &Path, e: impl std::fmt::Debug) -> RippleError {
    RippleError::Output {
        path: path.display().to_string(),
        reason: crate::engine::io::short(&format!("{e:?}")),
    }
}

/// A NetCDF writer's error on `path`: an I/O error's own text ("no storage space"), else the
/// writer's description.
fn nc_err(path: &Path, e: netcdf3::WriteError) -> RippleError {
    RippleError::Output {
        path: path.display().to_string(),
        reason: crate::engine::io::netcdf_write_reason(&e),
    }
}

fn io_err(path: &Path, e: std::io::Error) -> RippleError {
    RippleError::Output {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// The fields of a serialisable parameter set as (name, value) pairs, values as TOML values.
pub fn toml_pairs<T: serde::Serialize>(params: &T) -> Vec<(String, toml::Value)> {
    match toml::Value::try_from(params) {
        Ok(toml::Value::Table(t)) => t.into_iter().collect(),
        _ => Vec::new(),
    }
}

/// Adds the provenance every cellsurf NetCDF file carries as global attributes:
/// `Conventions` (CF-1.8), `title`, `source` (`cellsurf VERSION command`),
/// `cellsurf_version`, `comment`, and one `param_NAME` per parameter (numbers and booleans as
/// doubles, the rest as text).
pub fn add_provenance(
    ds: &mut DataSet,
    title: &str,
    command: &str,
    comment: &str,
    params: &[(String, toml::Value)],
) -> Result<(), netcdf3::InvalidDataSet> {
    ds.add_global_attr_string("Conventions", "CF-1.8")?;
    ds.add_global_attr_string("title", title)?;
    ds.add_global_attr_string("source", format!("cellsurf {VERSION} {command}"))?;
    ds.add_global_attr_string("cellsurf_version", VERSION)?;
    ds.add_global_attr_string("comment", comment)?;
    for (k, v) in params {
        let name = format!("param_{k}");
        match v {
            toml::Value::Integer(i) => ds.add_global_attr_f64(&name, vec![*i as f64]),
            toml::Value::Float(f) => ds.add_global_attr_f64(&name, vec![*f]),
            toml::Value::Boolean(b) => ds.add_global_attr_f64(&name, vec![f64::from(u8::from(*b))]),
            toml::Value::String(s) => ds.add_global_attr_string(&name, s),
            other => ds.add_global_attr_string(&name, other.to_string()),
        }?;
    }
    Ok(())
}

/// Writes the NetCDF-3 file (64-bit offset) at `path`, atomically.
pub fn write_netcdf(
    path: &Path,
    r: &Ripple,
    snapshots: &[(u64, Vec<f32>)],
    spec: &OutputSpec,
) -> Result<(), RippleError> {
    write_netcdf_with(path, r, snapshots, spec, &[])
}

/// What a run recorded beside its parameters (global attributes of the NetCDF file and the
/// Zarr store, keys of the `.npy` sidecar): e.g. the duration asked for in seconds, the wave
/// period in seconds, why and where a run stopped.
pub type RunAttributes = [(String, toml::Value)];

/// [`write_netcdf`] with the run's own attributes `extra` ([`RunAttributes`]).
pub fn write_netcdf_with(
    path: &Path,
    r: &Ripple,
    snapshots: &[(u64, Vec<f32>)],
    spec: &OutputSpec,
    extra: &RunAttributes,
) -> Result<(), RippleError> {
    let (nx, ny) = r.size();
    let p = r.params();
    let nz = volume_levels(r);
    let mut ds = DataSet::new();
    ds.add_fixed_dim("x", nx).map_err(|x| out_err(path, x))?;
    ds.add_fixed_dim("y", ny).map_err(|x| out_err(path, x))?;
    let want_elev = spec.fields.contains(&Field::Elevation) && !snapshots.is_empty();
    let vol_fields: Vec<Field> = spec
        .fields
        .iter()
        .copied()
        .filter(|f| *f != Field::Elevation)
        .collect();
    let coord = |ds: &mut DataSet, name: &str, dim: &str, units: &str, long: &str, axis: &str| {
        ds.add_var_f32(name, &[dim])?;
        ds.add_var_attr_string(name, "units", units)?;
        ds.add_var_attr_string(name, "long_name", long)?;
        ds.add_var_attr_string(name, "axis", axis)
    };
    coord(
        &mut ds,
        "x",
        "x",
        "m",
        "x of the bin centre (periodic)",
        "X",
    )
    .map_err(|x| out_err(path, x))?;
    coord(
        &mut ds,
        "y",
        "y",
        "m",
        "y of the bin centre (periodic)",
        "Y",
    )
    .map_err(|x| out_err(path, x))?;
    if want_elev {
        ds.add_fixed_dim("time", snapshots.len())
            .map_err(|x| out_err(path, x))?;
        // (a double: steps run to 2^40, and a float holds whole numbers exactly only to 2^24)
        (|| {
            ds.add_var_f64("time", &["time"])?;
            ds.add_var_attr_string("time", "units", "1")?;
            ds.add_var_attr_string("time", "long_name", "model step of the snapshot")?;
            ds.add_var_attr_string("time", "axis", "T")
        })()
        .map_err(|x| out_err(path, x))?;
    }
    if !vol_fields.is_empty() && nz > 0 {
        ds.add_fixed_dim("z", nz).map_err(|x| out_err(path, x))?;
        coord(
            &mut ds,
            "z",
            "z",
            "m",
            "height of the automaton centre above the substrate",
            "Z",
        )
        .map_err(|x| out_err(path, x))?;
        ds.add_var_attr_string("z", "positive", "up")
            .map_err(|x| out_err(path, x))?;
    }
    let mut vars: Vec<(Field, &[&str])> = Vec::new();
    if want_elev {
        vars.push((Field::Elevation, &["time", "y", "x"]));
    }
    if nz > 0 {
        for &f in &vol_fields {
            vars.push((f, &["z", "y", "x"]));
        }
    }
    for (f, dims) in &vars {
        let (units, long) = f.meta();
        ds.add_var_f32(f.name(), dims)
            .map_err(|x| out_err(path, x))?;
        ds.add_var_attr_string(f.name(), "units", units)
            .map_err(|x| out_err(path, x))?;
        ds.add_var_attr_string(f.name(), "long_name", long)
            .map_err(|x| out_err(path, x))?;
        if *f != Field::Elevation {
            ds.add_var_attr_f32(f.name(), "_FillValue", vec![NC_FILL_F32])
                .map_err(|x| out_err(path, x))?;
        }
        if matches!(f, Field::Density | Field::SoundSpeed | Field::Impedance) {
            let method = match p.acoustics {
                AcousticModel::Hamilton => {
                    "mixture-rule density; Hamilton & Bachman (1982) speed by grain size, porosity-corrected with Wood (1930)"
                }
                AcousticModel::AplUw => {
                    "APL-UW TR 9407 (1994) regressions on mean grain size: acoustic look-alike preset, not a bulk density"
                }
            };
            ds.add_var_attr_string(f.name(), "comment", method)
                .map_err(|x| out_err(path, x))?;
        }
    }
    add_provenance(
        &mut ds,
        "Sand ripple volume (cellular automaton Monte Carlo, Staelens, Dupont & Henriet)",
        "ripple",
        "Toroidal (periodic in x and y): the volume tiles without seams.",
        &toml_pairs(p),
    )
    .map_err(|x| out_err(path, x))?;
    ds.add_global_attr_f64("steps_done", vec![r.time() as f64])
        .map_err(|x| out_err(path, x))?;
    ds.add_global_attr_f64("automata", vec![r.automata() as f64])
        .map_err(|x| out_err(path, x))?;
    // The direction of the x axis (degrees counter-clockwise from east): 0 unless the lattice
    // runs in the flow's frame.
    ds.add_global_attr_f64("x_axis_direction_deg", vec![p.x_axis_direction_deg()])
        .map_err(|x| out_err(path, x))?;
    for (k, v) in extra {
        match v {
            toml::Value::Integer(i) => ds.add_global_attr_f64(k, vec![*i as f64]),
            toml::Value::Float(f) => ds.add_global_attr_f64(k, vec![*f]),
            toml::Value::String(s) => ds.add_global_attr_string(k, s),
            other => ds.add_global_attr_string(k, other.to_string()),
        }
        .map_err(|x| out_err(path, x))?;
    }

    crate::engine::io::check_output("output", path).map_err(|x| io_err(path, x))?;
    let tmp = crate::engine::io::TempFile::new(path);
    {
        let file = fs::File::create(tmp.path()).map_err(|x| io_err(path, x))?;
        let tmp_str = tmp.path().to_string_lossy().to_string();
        let mut w = FileWriter::open_seek_write(&tmp_str, Box::new(BufWriter::new(file)))
            .map_err(|x| nc_err(path, x))?;
        w.set_def(&ds, Version::Offset64Bit, 0)
            .map_err(|x| nc_err(path, x))?;
        let dx = p.bin_size;
        let xs: Vec<f32> = (0..nx).map(|i| ((i as f64 + 0.5) * dx) as f32).collect();
        let ys: Vec<f32> = (0..ny).map(|i| ((i as f64 + 0.5) * dx) as f32).collect();
        w.write_var_f32("x", &xs).map_err(|x| nc_err(path, x))?;
        w.write_var_f32("y", &ys).map_err(|x| nc_err(path, x))?;
        if want_elev {
            let ts: Vec<f64> = snapshots.iter().map(|s| s.0 as f64).collect();
            w.write_var_f64("time", &ts).map_err(|x| nc_err(path, x))?;
            let mut all = Vec::with_capacity(snapshots.len() * nx * ny);
            for s in snapshots {
                all.extend_from_slice(&s.1);
            }
            w.write_var_f32("elevation", &all)
                .map_err(|x| nc_err(path, x))?;
        }
        if !vol_fields.is_empty() && nz > 0 {
            let gd = p.layer_thickness;
            let zs: Vec<f32> = (0..nz).map(|k| ((k as f64 + 0.5) * gd) as f32).collect();
            w.write_var_f32("z", &zs).map_err(|x| nc_err(path, x))?;
            for &f in &vol_fields {
                let data = volume_field(r, f, NC_FILL_F32);
                w.write_var_f32(f.name(), &data)
                    .map_err(|x| nc_err(path, x))?;
            }
        }
        w.close().map_err(|x| nc_err(path, x))?;
    }
    fs::File::open(tmp.path())
        .and_then(|f| f.sync_all())
        .map_err(|x| io_err(path, x))?;
    tmp.commit(path).map_err(|x| io_err(path, x))
}

/// The header of a little-endian f32 `.npy` (format 1.0, C order) of `shape`, padded so that
/// the data starts on a 64-byte boundary: the data (`shape` product x 4 bytes) may follow it
/// as a whole or be appended row by row.
pub fn npy_header(shape: &[usize]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let shape_s = if dims.len() == 1 {
        format!("({},)", dims[0])
    } else {
        format!("({})", dims.join(", "))
    };
    let mut header = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': {shape_s}, }}");
    let total = 10 + header.len() + 1;
    let pad = (64 - total % 64) % 64;
    header.push_str(&" ".repeat(pad));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    out
}

/// The bytes of a little-endian f32 `.npy` (format 1.0) of `shape`.
pub fn npy_bytes(shape: &[usize], data: &[f32]) -> Vec<u8> {
    let mut out = npy_header(shape);
    out.reserve(data.len() * 4);
    for v in data {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// A scalar TOML value as JSON: strings quoted and escaped, non-finite floats as `null`.
pub fn json_value(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => json_string(s),
        toml::Value::Float(f) if !f.is_finite() => "null".into(),
        other => other.to_string(),
    }
}

/// A JSON string literal of `s` (quotes and control characters escaped).
pub fn json_string(s: &str) -> String {
    let mut o = String::from("\"");
    for ch in s.chars() {
        match ch {
            '"' => o.push_str("\\\""),
            '\\' => o.push_str("\\\\"),
            c if (c as u32) < 0x20 => {
                let _ = write!(o, "\\u{:04x}", c as u32);
            }
            c => o.push(c),
        }
    }
    o.push('"');
    o
}

/// The `.npy` files of a run, next to `out` with its extension dropped: `STEM.npy` the
/// elevation snapshots, `STEM_FIELD.npy` each volume field, and the sidecar `STEM.json`
/// (parameters, version, shapes, units). The field files of an earlier set that its sidecar
/// lists and this run does not write (a field it was not asked for) are removed once this
/// run's files are in place ([`crate::engine::io::retire`]), so that the files beside the
/// sidecar are this run's alone. Returns the files written.
pub fn write_npy(
    out: &Path,
    r: &Ripple,
    snapshots: &[(u64, Vec<f32>)],
    spec: &OutputSpec,
) -> Result<Vec<PathBuf>, RippleError> {
    write_npy_with(out, r, snapshots, spec, &[])
}

/// The files [`write_npy`] writes for `out` and `spec`, in the order written: one `.npy` per
/// field (`STEM.npy` the elevation, `STEM_FIELD.npy` a volume field), then the sidecar
/// `STEM.json`. A caller checks them all before a run, so that a run never fails at its end
/// on a path it could not write.
pub fn npy_paths(out: &Path, spec: &OutputSpec) -> Vec<PathBuf> {
    let stem = out.with_extension("");
    let file = |suffix: &str| {
        let mut s = stem.as_os_str().to_owned();
        s.push(suffix);
        PathBuf::from(s)
    };
    let mut v: Vec<PathBuf> = spec
        .fields
        .iter()
        .map(|&f| {
            if f == Field::Elevation {
                file(".npy")
            } else {
                file(&format!("_{}.npy", f.name()))
            }
        })
        .collect();
    v.push(file(".json"));
    v
}

/// [`write_npy`] with the run's own attributes `extra` ([`RunAttributes`]) in the sidecar.
pub fn write_npy_with(
    out: &Path,
    r: &Ripple,
    snapshots: &[(u64, Vec<f32>)],
    spec: &OutputSpec,
    extra: &RunAttributes,
) -> Result<Vec<PathBuf>, RippleError> {
    let (nx, ny) = r.size();
    let paths = npy_paths(out, spec);
    // (read before this run's sidecar replaces the earlier one)
    let stale = crate::engine::io::stale_npy_files(paths.last().expect("a sidecar"), &paths);
    let mut written = Vec::new();
    let mut entries = Vec::new();
    for (&f, path) in spec.fields.iter().zip(&paths) {
        let (shape, data) = if f == Field::Elevation {
            let mut all = Vec::new();
            for s in snapshots {
                all.extend_from_slice(&s.1);
            }
            (vec![snapshots.len(), ny, nx], all)
        } else {
            let nz = volume_levels(r);
            (vec![nz, ny, nx], volume_field(r, f, f32::NAN))
        };
        crate::engine::io::write_atomic(path, &npy_bytes(&shape, &data))
            .map_err(|e| io_err(path, e))?;
        let (units, long) = f.meta();
        let dims = if f == Field::Elevation {
            "[\"time\", \"y\", \"x\"]"
        } else {
            "[\"z\", \"y\", \"x\"]"
        };
        entries.push(format!(
            "    {}: {{\"file\": {}, \"dims\": {dims}, \"shape\": {:?}, \"units\": {}, \"long_name\": {}}}",
            json_string(f.name()),
            json_string(&path.file_name().unwrap_or_default().to_string_lossy()),
            shape,
            json_string(units),
            json_string(long)
        ));
        written.push(path.clone());
    }
    let mut params = Vec::new();
    for (k, v) in toml_pairs(r.params()) {
        params.push(format!("    {}: {}", json_string(&k), json_value(&v)));
    }
    let times: Vec<String> = snapshots.iter().map(|s| s.0.to_string()).collect();
    let run: String = extra
        .iter()
        .map(|(k, v)| format!("  {}: {},\n", json_string(k), json_value(v)))
        .collect();
    let json = format!(
        "{{\n  \"cellsurf_version\": {},\n  \"model\": \"ripple\",\n{run}  \"steps_done\": {},\n  \"automata\": {},\n  \"elevation_times\": [{}],\n  \"bin_size_m\": {},\n  \"layer_thickness_m\": {},\n  \"x_axis_direction_deg\": {},\n  \"fill\": \"NaN above the bed\",\n  \"fields\": {{\n{}\n  }},\n  \"parameters\": {{\n{}\n  }}\n}}\n",
        json_string(VERSION),
        r.time(),
        r.automata(),
        times.join(", "),
        r.params().bin_size,
        r.params().layer_thickness,
        r.params().x_axis_direction_deg(),
        entries.join(",\n"),
        params.join(",\n")
    );
    let side = paths.last().expect("the sidecar is the last path");
    crate::engine::io::write_atomic(side, json.as_bytes()).map_err(|e| io_err(side, e))?;
    written.push(side.clone());
    // an earlier run's fields that this one does not write go with it, once this run's are
    // in place
    crate::engine::io::retire(&stale).map_err(|e| io_err(out, e))?;
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn npy_header_is_aligned() {
        let b = npy_bytes(&[2, 3], &[0.0; 6]);
        assert_eq!(&b[..6], b"\x93NUMPY");
        let hl = u16::from_le_bytes([b[8], b[9]]) as usize;
        assert_eq!((10 + hl) % 64, 0);
        assert_eq!(b.len(), 10 + hl + 24);
        assert_eq!(b[10 + hl - 1], b'\n');
    }
}
