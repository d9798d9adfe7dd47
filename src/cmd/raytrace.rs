//! `cellsurf raytrace`: acoustic rays from a transducer S over a seafloor section
//! ([`cellsurf::raytrace`]): the insonified and shadowed floor, grazing angles and reflection
//! coefficients, written as CSV; the section as a BELLHOP `.bty` and CSV; `--json` prints a
//! summary.
//!
//! The floor is a section through the built-in generated ripple field (a 3-D ripple run, seed
//! `--seed`, tiled along the section) or through a ripple NetCDF file (`--seafloor`),
//! `--water-depth` below the surface, or a `--seafloor-csv` file; a Zarr store from
//! `cellsurf tile --out X.zarr` is read chunk by chunk along the section, never whole, and one
//! from `cellsurf ripple --out X.zarr` whole, as the run's NetCDF file.
//!
//! `insonified_fraction` is the lit share of the floor's length (lit stretches between the
//! shadow edges), whatever the vertex spacing; `vertex_insonified_fraction` counts vertices.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};

use super::conv::{self, Format, Outputs};
use cellsurf::engine::count::CountRange;
use cellsurf::raytrace::{ray, shadow};

use cellsurf::raytrace::export::{bty_text, floor_csv, insonification_csv, rays_csv};
use cellsurf::raytrace::input::{ZarrSurface, read_ripple_store};
use cellsurf::raytrace::profile::{Mackenzie, SalinitySource};
use cellsurf::raytrace::seafloor::{MAX_SECTION_SAMPLES, cut_section};
use cellsurf::raytrace::shadow::straight_insonify_fan;
use cellsurf::raytrace::{
    Fan, InsonifyOptions, Munk, RaytraceError, RippleSurface, Seafloor, SectionLine, SoundSpeed,
    TraceOptions, Tracer, insonify,
};

/// Sound-speed profile kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ProfileKind {
    /// Constant --c0.
    Isovelocity,
    /// c = --c0 + --gradient z.
    Linear,
    /// Munk (1974) canonical profile.
    Munk,
    /// Piecewise linear from --profile-table (depth, speed rows).
    Table,
    /// Mackenzie (1981) from --temperature-table and --salinity-table or --salinity.
    Mackenzie,
}

/// Options of `cellsurf raytrace`. Negative numbers are read as values (upward angles).
#[derive(clap::Args, Serialize, Deserialize)]
#[command(
    allow_negative_numbers = true,
    after_help = "Examples:\n  \
        cellsurf raytrace --out lit.csv                  # generated ripples, 10 m source\n  \
        cellsurf raytrace --profile munk --angle-min 2 --angle-max 20 --json\n  \
        cellsurf raytrace --seafloor bed.nc --azimuth 30 --out lit.csv --out section.bty"
)]
pub struct Args {
    /// Start from this scenario file (TOML, `model = "raytrace"`); options typed here override
    /// it.
    #[arg(long, value_name = "FILE.toml")]
    scenario: Option<PathBuf>,
    /// Depth of the transducer S, m: below the surface and above the floor at --source-range.
    #[arg(long, default_value_t = 10.0)]
    source_depth: f64,
    /// Range of S along the section, m.
    #[arg(long, default_value_t = 0.0)]
    source_range: f64,
    /// Smallest launch angle, degrees below the horizontal (negative: upward), -90 to 90.
    #[arg(long, default_value_t = 1.5)]
    angle_min: f64,
    /// Largest launch angle, degrees below the horizontal, -90 to 90.
    #[arg(long, default_value_t = 25.0)]
    angle_max: f64,
    /// Opening angle of the sonar, degrees (with --centre-angle, instead of the two limits).
    #[arg(long)]
    opening: Option<f64>,
    /// Centre of the opening, degrees below the horizontal.
    #[arg(long)]
    centre_angle: Option<f64>,
    /// Rays of the initial fan, 2 to 1e7 (more are added at shadow edges).
    #[arg(long, default_value_t = 200, value_parser = conv::count_in::<usize>(shadow::RAYS))]
    rays: usize,
    /// Sound-speed profile.
    #[arg(long, value_enum, default_value_t = ProfileKind::Isovelocity)]
    profile: ProfileKind,
    /// Speed at the surface (isovelocity, linear), m/s.
    #[arg(long, default_value_t = 1500.0)]
    c0: f64,
    /// dc/dz of the linear profile, 1/s.
    #[arg(long, default_value_t = 0.0)]
    gradient: f64,
    /// Sound-speed table: `depth, speed` rows (m, m/s), from 0 m to at least the floor.
    #[arg(long, value_name = "FILE")]
    profile_table: Option<PathBuf>,
    /// Mackenzie: `depth, temperature` rows (m, deg C).
    #[arg(long, value_name = "FILE")]
    temperature_table: Option<PathBuf>,
    /// Mackenzie: `depth, salinity` rows (m, ppt); without it --salinity at every depth.
    #[arg(long, value_name = "FILE")]
    salinity_table: Option<PathBuf>,
    /// Mackenzie: constant salinity, ppt.
    #[arg(long, default_value_t = 35.0)]
    salinity: f64,
    /// Depth of the substrate under the generated ripples, m, 1e-6 to 12000 (floor depth = this
    /// - elevation).
    #[arg(long, default_value_t = 12.0)]
    water_depth: f64,
    /// Seafloor from a CSV file of `x, depth[, impedance]` rows (m, m, kg m^-2 s^-1) instead
    /// of the generated ripple field.
    #[arg(long, value_name = "FILE", conflicts_with = "seafloor")]
    seafloor_csv: Option<PathBuf>,
    /// Seafloor from a ripple NetCDF file (`cellsurf ripple --out`: its last elevation and
    /// top-automaton impedance) or a mosaic (`cellsurf tile --out`: its elevation and, with
    /// `--volume impedance`, the top impedance), cut like the generated field (--azimuth,
    /// --length). A Zarr store (`cellsurf tile --out X.zarr`) is read chunk by chunk: only
    /// the chunks the section crosses; a ripple run's store (`cellsurf ripple --out X.zarr`)
    /// is read whole, as its NetCDF file.
    #[arg(long, value_name = "FILE.nc|STORE.zarr")]
    seafloor: Option<PathBuf>,
    /// Length of the section through the generated ripple mosaic, m: at most 1e6 m and 2e7
    /// bins of the surface (1e5 m at the generated field's 5 mm bins).
    #[arg(long, default_value_t = 60.0)]
    length: f64,
    /// Direction of the section through the ripple field, degrees from +x (the current).
    #[arg(long, default_value_t = 0.0)]
    azimuth: f64,
    /// Seed of the generated ripple field.
    #[arg(long, default_value_t = 1, value_parser = conv::count_in::<u64>(SEED))]
    seed: u64,
    /// Ray step (arc length), m, 1e-6 to 1e5 and at most the longest ray path (--max-path).
    #[arg(long, default_value_t = 0.25)]
    ds: f64,
    /// Most reflections a ray (surface and floor), 0 to 100000.
    #[arg(long, default_value_t = 10, value_parser = conv::count_in::<usize>(ray::MAX_BOUNCES))]
    max_bounces: usize,
    /// Longest ray path, m [default: 3 x (section span + water depth)].
    #[arg(long)]
    max_path: Option<f64>,
    /// Most rays in all (initial fan and shadow-edge bisection).
    #[arg(long, default_value_t = 2_000_000, value_parser = conv::parse_usize)]
    max_rays: usize,
    /// Straight-line (line-of-sight) visibility instead of refracted rays: the vertices in view
    /// of S whose direction from S lies within the fan of launch angles.
    #[arg(long)]
    straight: bool,
    /// Output file, repeatable; the extension picks the format: .csv (insonification, one row
    /// a floor vertex: lit, grazing angle, travel time, R0), .bty (BELLHOP bathymetry of the
    /// section).
    #[arg(long, value_name = "FILE")]
    out: Vec<PathBuf>,
    /// Ray paths of the initial fan as CSV (through floor reflections, up to --max-bounces).
    #[arg(long, value_name = "FILE.csv")]
    rays_csv: Option<PathBuf>,
    /// Old spelling of `--out FILE.bty` (kept for one release).
    #[arg(long, value_name = "FILE.bty", hide = true)]
    bty: Option<PathBuf>,
    /// The section as CSV (x, depth, impedance), readable by --seafloor-csv.
    #[arg(long, value_name = "FILE.csv")]
    seafloor_csv_out: Option<PathBuf>,
    /// Print one JSON object with the run's summary on stdout.
    #[arg(long)]
    json: bool,
    /// No chatter on stderr.
    #[arg(long)]
    quiet: bool,
    /// Print the run's scenario file (TOML) and exit.
    #[arg(long)]
    print_scenario: bool,
}

fn read(path: &Path, what: &str) -> Result<String> {
    std::fs::read_to_string(path).with_context(|| format!("reading {what} {}", path.display()))
}

fn profile(a: &Args) -> Result<SoundSpeed> {
    Ok(match a.profile {
        ProfileKind::Isovelocity => SoundSpeed::Isovelocity(a.c0),
        ProfileKind::Linear => SoundSpeed::Linear {
            c0: a.c0,
            g: a.gradient,
        },
        ProfileKind::Munk => SoundSpeed::Munk(Munk::default()),
        ProfileKind::Table => {
            let Some(p) = &a.profile_table else {
                bail!("--profile table needs --profile-table FILE (depth, speed rows)");
            };
            SoundSpeed::parse_table(&read(p, "--profile-table")?)
                .with_context(|| format!("in --profile-table {}", p.display()))?
        }
        ProfileKind::Mackenzie => {
            let Some(t) = &a.temperature_table else {
                bail!(
                    "--profile mackenzie needs --temperature-table FILE (depth, temperature rows)"
                );
            };
            let t_text = read(t, "--temperature-table")?;
            let s_text;
            let s = match &a.salinity_table {
                Some(p) => {
                    s_text = read(p, "--salinity-table")?;
                    SalinitySource::Table(&s_text)
                }
                None => SalinitySource::Constant(a.salinity),
            };
            SoundSpeed::Mackenzie(Mackenzie::parse(&t_text, s).map_err(|e| in_table(a, e))?)
        }
    })
}

/// An error about a table (its value, its format, or its last depth against the floor) with the
/// option and file it was read from, `in --temperature-table FILE: ...`; others as they are.
fn in_table(a: &Args, e: RaytraceError) -> anyhow::Error {
    let name = match &e {
        RaytraceError::Range { parameter, .. } => parameter.as_str(),
        RaytraceError::Input { what, .. } => what.as_str(),
        RaytraceError::Output { .. } => "",
    };
    let tables = [
        ("profile table", "profile_table", &a.profile_table),
        (
            "temperature table",
            "temperature_table",
            &a.temperature_table,
        ),
        ("salinity table", "salinity_table", &a.salinity_table),
    ];
    match tables.into_iter().find(|(n, _, _)| name.starts_with(n)) {
        Some((_, id, Some(p))) => anyhow::Error::new(e).context(format!(
            "in {} {}",
            conv::typed_flag(id).unwrap_or_default(),
            p.display()
        )),
        _ => e.into(),
    }
}

/// Bytes a section of --length cut at `spacing` m allocates, with the rays traced over it:
/// 128 per sample. Measured as the least `ulimit -v` a run of 2 rays needs over the generated
/// 5 mm field: 20 MB at 1,000 m, 211 MB at 10,000 m and 593 MB at 30,000 m past the
/// program's own 22 MB (about 100-110 B per sample).
fn section_bytes(length: f64, spacing: f64) -> f64 {
    128.0 * ((length / spacing).floor() + 1.0)
}

/// Refuses a --length whose section would need more memory than this process may have,
/// naming --length as typed. A section past its sample limit is left to the section's own
/// range check, which names that limit.
fn check_section_memory(a: &Args, spacing: f64) -> Result<()> {
    let samples = (a.length / spacing).floor();
    if !(samples.is_finite() && samples <= MAX_SECTION_SAMPLES as f64 && spacing > 0.0) {
        return Ok(());
    }
    conv::check_memory(
        &format!(
            "{} {} ({samples:.0} samples of {spacing} m)",
            conv::typed_flag("length").unwrap_or_else(|| "--length".into()),
            a.length
        ),
        section_bytes(a.length, spacing),
    )
}

/// The floor, the kind of surface it was cut from, and the chunks read from a Zarr store.
fn floor(a: &Args) -> Result<(Seafloor, &'static str, Option<usize>)> {
    let built = build_floor(a)?;
    // Options of a floor this run does not build: said once, not recorded as if they shaped it.
    let unused = |flags: &[(&str, &str)], why: &str| {
        let given = conv::given_flags(
            &flags
                .iter()
                .map(|&(id, long)| (id, long, conv::typed(id)))
                .collect::<Vec<_>>(),
        );
        if !given.is_empty() {
            conv::note(format_args!(
                "warning: {} {} no effect: {why}",
                given.join(", "),
                if given.len() == 1 { "has" } else { "have" }
            ));
        }
    };
    if a.seafloor_csv.is_some() {
        unused(
            &[
                ("azimuth", "--azimuth"),
                ("length", "--length"),
                ("water_depth", "--water-depth"),
                ("seed", "--seed"),
            ],
            "--seafloor-csv gives the section itself (its x, depth rows), so no section is cut and no floor is generated",
        );
    } else if a.seafloor.is_some() {
        unused(
            &[("seed", "--seed")],
            "--seafloor gives the surface, so none is generated (the seed draws only a generated floor)",
        );
    }
    Ok(built)
}

/// The floor of [`floor`]: a CSV section, a section cut from a tile store or a ripple or
/// mosaic file, or from a generated surface.
fn build_floor(a: &Args) -> Result<(Seafloor, &'static str, Option<usize>)> {
    if let Some(p) = &a.seafloor_csv {
        let f = Seafloor::parse_csv(&read(p, "--seafloor-csv")?)
            .with_context(|| format!("in --seafloor-csv {}", p.display()))?;
        return Ok((f, "csv", None));
    }
    let store = a.seafloor.as_ref().filter(|p| {
        p.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("zarr"))
    });
    // a ripple run's store is read whole, as its NetCDF file; a tile store chunk by chunk
    let ripple_store = match store {
        Some(p) => read_ripple_store(p).context("reading --seafloor")?,
        None => None,
    };
    if let (Some(p), None) = (store, &ripple_store) {
        let mut z = ZarrSurface::open(p).context("reading --seafloor")?;
        let (_, ny, bin) = z.shape();
        check_section_memory(a, bin)?;
        check_azimuth_on_section(a, ny)?;
        let line = SectionLine::through_middle(ny, bin, a.azimuth, a.length);
        let f = cut_section(&mut z, line, a.water_depth, 0.0).context("reading --seafloor")?;
        return Ok((f, "tile store", Some(z.chunks_read)));
    }
    let (surf, kind) = match (ripple_store, &a.seafloor) {
        (Some(s), _) => (s, "ripple store"),
        (None, Some(p)) => {
            let (s, k) =
                cellsurf::raytrace::input::read_surface(p).context("reading --seafloor")?;
            (s, k.name())
        }
        (None, None) => (RippleSurface::generated(a.seed)?, "generated"),
    };
    check_section_memory(a, surf.bin)?;
    check_azimuth_on_section(a, surf.ny)?;
    let line = SectionLine::through_middle(surf.ny, surf.bin, a.azimuth, a.length);
    Ok((surf.grid().section(line, a.water_depth, 0.0)?, kind, None))
}

/// Refuses a cut across a 2-D section (a seafloor one row wide, `ny = 1`): off its row the
/// section repeats that row, so the cut would be a floor of one height labelled as ripples.
fn check_azimuth_on_section(a: &Args, ny: usize) -> Result<()> {
    let along = a.azimuth.rem_euclid(180.0);
    if ny == 1 && along > 1e-9 && along < 180.0 - 1e-9 {
        bail!(
            "--azimuth = {} deg crosses the seafloor, a 2-D section one row wide: cut along \
             it, --azimuth 0 or 180 (or -180, 360, -360), or give a 3-D field",
            a.azimuth
        );
    }
    Ok(())
}

/// Warns of the tracer's options given (typed, or set by a scenario file) that have no effect
/// with `--straight`, each named as typed.
fn straight_unused(a: &Args, options: &[(&str, &str)]) {
    let set = |id: &str| match id {
        "rays" => conv::set_by_scenario(id, &a.rays.to_string()),
        "ds" => conv::set_by_scenario(id, &a.ds.to_string()),
        "max_bounces" => conv::set_by_scenario(id, &a.max_bounces.to_string()),
        "max_path" => a.max_path.is_some() && conv::set_by_scenario(id, "set"),
        _ => conv::set_by_scenario(id, &a.max_rays.to_string()),
    };
    let given = conv::given_flags(
        &options
            .iter()
            .map(|&(id, long)| (id, long, conv::typed(id) || set(id)))
            .collect::<Vec<_>>(),
    );
    if !given.is_empty() {
        conv::note(format_args!(
            "warning: {} {} no effect with --straight: {}",
            given.join(", "),
            if given.len() == 1 { "has" } else { "have" },
            if a.rays_csv.is_some() {
                "straight lines are not traced ray by ray (only --rays-csv traces its fan, and it has no budget)"
            } else {
                "straight lines are not traced ray by ray (only --rays-csv would trace the fan)"
            }
        ));
    }
}

/// `--flag = value` for an option, marked `(from --scenario)` when a scenario file set it
/// and `(default)` when it holds its default, untyped.
fn flag(id: &str, v: f64) -> String {
    let f = conv::typed_flag(id).unwrap_or_default();
    if conv::typed(id) {
        format!("{f} = {v}")
    } else if conv::set_by_scenario(id, &v.to_string()) {
        format!("{f} = {v} (from --scenario)")
    } else {
        format!("{f} = {v} (default)")
    }
}

/// The fan's launch angles, degrees below the horizontal, from `--angle-min`/`--angle-max` or
/// `--opening`/`--centre-angle`; errors name the options given and the valid range.
fn fan_angles(a: &Args) -> Result<(f64, f64)> {
    let limits = conv::typed("angle_min") || conv::typed("angle_max");
    match (a.opening, a.centre_angle) {
        (Some(_), _) | (_, Some(_)) if limits => {
            bail!("give either --opening with --centre-angle, or --angle-min/--angle-max")
        }
        (Some(o), Some(c)) => {
            // an opening of 0 is one launch angle for every ray (documented)
            if !(o.is_finite() && (0.0..=180.0).contains(&o)) {
                bail!("--opening = {o} is out of range: expected degrees in [0, 180]");
            }
            let (lo, hi) = (c - o / 2.0, c + o / 2.0);
            if !(c.is_finite() && lo >= -90.0 && hi <= 90.0) {
                bail!(
                    "--centre-angle = {c} with --opening = {o} is out of range: it gives launch angles {lo} to {hi} degrees; expected both within -90 to 90 degrees below the horizontal (|--centre-angle| + --opening / 2 at most 90)"
                );
            }
            Ok((lo, hi))
        }
        (None, None) => {
            for (id, v) in [("angle_min", a.angle_min), ("angle_max", a.angle_max)] {
                if !(v.is_finite() && (-90.0..=90.0).contains(&v)) {
                    bail!(
                        "{} is out of range: expected degrees below the horizontal in [-90, 90]",
                        flag(id, v)
                    );
                }
            }
            // equal limits are one launch angle for every ray (documented)
            if a.angle_min > a.angle_max {
                bail!(
                    "{} is out of range: expected at least {} (degrees below the horizontal, up to 90)",
                    flag("angle_max", a.angle_max),
                    flag("angle_min", a.angle_min)
                );
            }
            Ok((a.angle_min, a.angle_max))
        }
        _ => bail!("--opening and --centre-angle go together"),
    }
}

/// A scenario file that gives both fans, an opening (with its centre) and limits away from
/// their defaults: refused naming the keys, as the command line refuses `--opening` with
/// `--angle-min`. (Limits typed on the command line replace a scenario's opening, and a typed
/// opening its limits: those are settled before this.)
fn check_scenario_fan(a: &Args, scenario: Option<&Path>) -> Result<()> {
    let Some(path) = scenario else {
        return Ok(());
    };
    if conv::typed("opening") || conv::typed("centre_angle") {
        return Ok(());
    }
    let opening: Vec<String> = [("opening", a.opening), ("centre_angle", a.centre_angle)]
        .into_iter()
        .filter_map(|(k, v)| v.map(|v| format!("{k} = {v}")))
        .collect();
    let limits: Vec<String> = [("angle_min", a.angle_min), ("angle_max", a.angle_max)]
        .into_iter()
        .filter(|(k, v)| conv::set_by_scenario(k, &v.to_string()))
        .map(|(k, v)| format!("{k} = {v}"))
        .collect();
    if !opening.is_empty() && !limits.is_empty() {
        bail!(
            "{} {}: {} given with {}: give either opening with centre_angle, or \
             angle_min/angle_max (one fan), as on the command line",
            conv::typed_flag("scenario").unwrap_or_else(|| "--scenario".into()),
            path.display(),
            limits.join(" and "),
            opening.join(" and ")
        );
    }
    Ok(())
}

/// Options of one sound-speed profile given with another, and `--salinity` with
/// `--salinity-table`: refused, naming both (they would be ignored).
fn check_profile_options(a: &Args) -> Result<()> {
    use ProfileKind::*;
    let applies: [(&str, &[ProfileKind], &str); 6] = [
        ("c0", &[Isovelocity, Linear], "isovelocity and linear"),
        ("gradient", &[Linear], "linear"),
        ("profile_table", &[Table], "table"),
        ("temperature_table", &[Mackenzie], "mackenzie"),
        ("salinity_table", &[Mackenzie], "mackenzie"),
        ("salinity", &[Mackenzie], "mackenzie"),
    ];
    let name = |k: ProfileKind| match k {
        Isovelocity => "isovelocity",
        Linear => "linear",
        Munk => "munk",
        Table => "table",
        Mackenzie => "mackenzie",
    };
    let profile = if conv::typed("profile") {
        format!("--profile {}", name(a.profile))
    } else {
        format!("--profile {} (default)", name(a.profile))
    };
    let path = |p: &Option<PathBuf>| p.as_ref().map(|p| p.display().to_string());
    let value = |id: &str| -> Option<String> {
        match id {
            "c0" => Some(a.c0.to_string()),
            "gradient" => Some(a.gradient.to_string()),
            "salinity" => Some(a.salinity.to_string()),
            "profile_table" => path(&a.profile_table),
            "temperature_table" => path(&a.temperature_table),
            "salinity_table" => path(&a.salinity_table),
            _ => None,
        }
    };
    for (id, kinds, names) in applies {
        // (a scenario's value for another profile is kept in the file, and said)
        if !conv::typed(id)
            && !kinds.contains(&a.profile)
            && let Some(v) = value(id).filter(|v| conv::set_by_scenario(id, v))
        {
            conv::note(format_args!(
                "warning: the scenario's {id} = {v} has no effect: it applies to the {names} profile{} only, not {profile}",
                if kinds.len() > 1 { "s" } else { "" },
            ));
        }
        if conv::typed(id) && !kinds.contains(&a.profile) {
            bail!(
                "{} applies to the {names} profile{} only, not {profile}: leave it out or give --profile {}",
                conv::typed_flag(id).unwrap_or_default(),
                if kinds.len() > 1 { "s" } else { "" },
                name(kinds[0])
            );
        }
    }
    if conv::typed("salinity") && conv::typed("salinity_table") {
        bail!(
            "--salinity and --salinity-table both given: expected one of them (a constant salinity, or a table of depth, salinity rows)"
        );
    }
    Ok(())
}

/// A Snell-invariant drift above this gets a warning naming --ds: the integrator keeps the
/// drift below 1e-9 in ocean profiles at the default step, and near 1e-6 where the gradient
/// limit of its step binds (steep profiles, where a smaller --ds would not help).
const SNELL_DRIFT_WARN: f64 = 1e-5;

/// `--seed`: 0 to 2^63 - 1, the largest integer a TOML scenario file holds.
const SEED: CountRange = CountRange::new(
    0,
    conv::MAX_SEED,
    "an integer in [0, 2^63 - 1 = 9223372036854775807] (the largest a scenario file holds)",
);

/// `--seed` within the ripple model's range when it seeds the generated floor (checked by
/// the ripple model); [`SEED`], what a scenario file holds, is its parser's.
fn check_seed(a: &Args) -> Result<()> {
    if a.seafloor.is_none() && a.seafloor_csv.is_none() {
        cellsurf::ripple::RippleParams {
            seed: a.seed,
            ..cellsurf::ripple::RippleParams::default()
        }
        .validate()
        .map_err(|e| anyhow::anyhow!("--seed = {} of the generated ripple floor: {e}", a.seed))?;
    }
    Ok(())
}

/// The source S in the water above the floor at its range; errors name `--source-range` and
/// `--source-depth` (marked when they are the defaults) and the floor's depth there.
fn check_source(a: &Args, fl: &Seafloor) -> Result<()> {
    let (x0, x1) = fl.x_range();
    let x = a.source_range;
    if !(x.is_finite() && x >= x0 && x <= x1) {
        bail!(
            "{} is out of range: expected a range within the seafloor section, {x0} to {x1} m",
            flag("source_range", x)
        );
    }
    let zb = fl.depth_at(x).unwrap_or(0.0);
    let z = a.source_depth;
    if !(z.is_finite() && z > 0.0 && z < zb) {
        bail!(
            "{} is out of range: expected a depth in (0, {zb}) m, below the surface and above the floor, which is {zb} m deep at {}",
            flag("source_depth", z),
            flag("source_range", x)
        );
    }
    Ok(())
}

/// The output options given, as (option, path).
fn outputs<'a>(a: &'a Args, outs: &'a Outputs) -> Vec<(&'static str, &'a Path)> {
    [
        ("--out", outs.get(Format::Csv)),
        ("--rays-csv", a.rays_csv.as_deref()),
        ("--out", outs.get(Format::Bty)),
        ("--seafloor-csv-out", a.seafloor_csv_out.as_deref()),
    ]
    .into_iter()
    .filter_map(|(o, p)| p.map(|p| (o, p)))
    .collect()
}

/// Before any work: every output is a file name with its option's extension in an existing
/// folder, not a folder or a link, and no two outputs are the same file.
fn check_outputs(a: &Args, outs: &Outputs) -> Result<()> {
    let outs = outputs(a, outs);
    for (i, &(opt, p)) in outs.iter().enumerate() {
        if p.file_name().is_none() {
            bail!("{opt} {}: not a file name", p.display());
        }
        if matches!(opt, "--rays-csv" | "--seafloor-csv-out")
            && !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"))
        {
            bail!(
                "{opt} {}: expected a .csv file name (the file is CSV)",
                p.display()
            );
        }
        cellsurf::engine::io::check_output(opt, p)?;
        // (`z.csv`, `./z.csv` and its absolute path are one file)
        if let Some(&(other, q)) = outs[..i].iter().find(|(_, q)| conv::same_path(q, p)) {
            bail!(
                "{opt} {}: the same file as {other} {}; give each output its own name",
                p.display(),
                q.display()
            );
        }
    }
    Ok(())
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<()> {
    conv::synonyms(&[
        ("max angle", "angle_max"),
        ("min angle", "angle_min"),
        ("section azimuth", "azimuth"),
        ("section length", "length"),
        ("max rays", "max_rays"),
    ]);
    conv::set_quiet(a.quiet);
    // (the seed's parser holds it to what the scenario merge can hold: SEED)
    let scenario = a.scenario.clone();
    let mut a = conv::merge_scenario(a, scenario.as_deref(), "raytrace")?;
    // limits typed on the command line replace a scenario's opening and centre, as a typed
    // opening and centre replace its limits
    if (conv::typed("angle_min") || conv::typed("angle_max"))
        && !conv::typed("opening")
        && !conv::typed("centre_angle")
    {
        // a limit not typed keeps the scenario's fan: centre -+ opening / 2
        if let (Some(o), Some(c)) = (a.opening, a.centre_angle) {
            if !conv::typed("angle_min") {
                a.angle_min = c - o / 2.0;
            }
            if !conv::typed("angle_max") {
                a.angle_max = c + o / 2.0;
            }
        }
        a.opening = None;
        a.centre_angle = None;
    }
    check_scenario_fan(&a, scenario.as_deref())?;
    check_seed(&a)?;
    // the fan as used, recorded by its limits: an opening and centre become the two limits
    // (the parameters, the scenario printed and the files' headers say the angles that shaped
    // the run, never the unused default limits)
    let (amin, amax) = fan_angles(&a)?;
    if a.opening.is_some() {
        (a.angle_min, a.angle_max) = (amin, amax);
        (a.opening, a.centre_angle) = (None, None);
    }
    if a.print_scenario {
        out!("{}", conv::scenario_text(&a, "raytrace")?)?;
        return Ok(());
    }
    let mut outs = Outputs::new(&a.out, "raytrace", &[Format::Csv, Format::Bty])?;
    outs.add_legacy(Format::Bty, a.bty.as_ref())?;
    let start = Instant::now();
    check_outputs(&a, &outs)?;
    check_profile_options(&a)?;
    let prof = profile(&a)?;
    let (fl, kind, chunks_read) = floor(&a)?;
    let tracer = Tracer::new(&prof, &fl).map_err(|e| in_table(&a, e))?;
    check_source(&a, &fl)?;
    conv::begin();
    let (x0, x1) = fl.x_range();
    let max_path = a.max_path.unwrap_or(3.0 * (x1 - x0 + fl.max_depth()));
    // The tracer's options: with --straight only --rays-csv traces rays (the fan's --rays,
    // --ds, --max-path and --max-bounces), and nothing uses --max-rays. Those without effect
    // are said once, neither checked nor recorded as if they shaped the run.
    let traced = !a.straight || a.rays_csv.is_some();
    if a.straight {
        let tracer_options: &[(&str, &str)] = if traced {
            &[("max_rays", "--max-rays")]
        } else {
            &[
                ("rays", "--rays"),
                ("ds", "--ds"),
                ("max_bounces", "--max-bounces"),
                ("max_path", "--max-path"),
                ("max_rays", "--max-rays"),
            ]
        };
        straight_unused(&a, tracer_options);
    }
    // A step longer than the longest path: --ds is the cause where --max-path is the default.
    if traced && a.max_path.is_none() && a.ds > max_path {
        bail!(
            "--ds = {} m is out of range: expected at most the longest ray path, {} m here (--max-path's default, 3 x (the floor's length + its greatest depth)); give a smaller --ds or a --max-path",
            a.ds,
            cellsurf::ripple::params::rounded(max_path)
        );
    }
    let trace = TraceOptions {
        ds: a.ds,
        max_path,
        max_bounces: a.max_bounces,
        stop_at_bottom: true,
        record: false,
    };
    let fan = Fan::Point {
        x: a.source_range,
        z: a.source_depth,
        min_deg: amin,
        max_deg: amax,
        rays: a.rays,
    };
    if !a.straight && !shadow::RAYS.contains(a.rays as u64) {
        bail!(
            "{} is out of range: expected {}",
            flag("rays", a.rays as f64),
            shadow::RAYS.expected
        );
    }
    if !a.straight && a.max_rays < a.rays {
        bail!(
            "{} is more than {}: expected --rays at most --max-rays, the most rays in all \
             (initial fan and shadow-edge bisection); raise --max-rays or lower --rays",
            flag("rays", a.rays as f64),
            flag("max_rays", a.max_rays as f64)
        );
    }
    let ins = if a.straight {
        if traced {
            fan.validate(&tracer)?;
            trace.validate()?;
        } else {
            // the fan's angles and source (its number of rays has no effect here)
            Fan::Point {
                x: a.source_range,
                z: a.source_depth,
                min_deg: amin,
                max_deg: amax,
                rays: 2,
            }
            .validate(&tracer)?;
        }
        let c = prof.speed(a.source_depth);
        straight_insonify_fan(&fl, a.source_range, a.source_depth, amin, amax, c)
    } else {
        let o = InsonifyOptions {
            trace,
            max_rays: a.max_rays,
            ..InsonifyOptions::default()
        };
        insonify(&tracer, &fan, &o)?
    };
    let unresolved = ins.unresolved_fraction(&fl);
    if ins.truncated {
        conv::note(format_args!(
            "warning: the ray budget ran out ({}): the result is truncated; {:.1} % of the \
             floor's length lies between rays whose shadow edges were not resolved, counted \
             as unresolved (neither insonified nor shadowed); raise --max-rays",
            flag("max_rays", a.max_rays as f64),
            unresolved * 100.0
        ));
    }
    if ins.max_snell_drift > SNELL_DRIFT_WARN {
        conv::note(format_args!(
            "warning: the Snell invariant cos(theta) / c drifted by {:.1e} along the rays (more than {SNELL_DRIFT_WARN:.0e}): the integration is inaccurate at {}; give a smaller --ds",
            ins.max_snell_drift,
            flag("ds", a.ds)
        ));
    }
    let mut params: Vec<(String, String)> = vec![("profile".into(), prof.describe())];
    // the files the profile was read from
    let tables = match a.profile {
        ProfileKind::Table => vec![("profile_table", &a.profile_table)],
        ProfileKind::Mackenzie => vec![
            ("temperature_table", &a.temperature_table),
            ("salinity_table", &a.salinity_table),
        ],
        _ => Vec::new(),
    };
    for (k, p) in tables {
        if let Some(p) = p {
            params.push((k.into(), p.display().to_string()));
        }
    }
    if a.profile == ProfileKind::Mackenzie && a.salinity_table.is_none() {
        params.push(("salinity_ppt".into(), a.salinity.to_string()));
    }
    params.extend::<[(String, String); 3]>([
        ("source_range_m".into(), a.source_range.to_string()),
        ("source_depth_m".into(), a.source_depth.to_string()),
        ("angles_deg".into(), format!("{amin} to {amax}")),
    ]);
    if traced {
        params.extend::<[(String, String); 4]>([
            ("rays".into(), a.rays.to_string()),
            ("ds_m".into(), a.ds.to_string()),
            ("max_bounces".into(), a.max_bounces.to_string()),
            ("max_path_m".into(), max_path.to_string()),
        ]);
    }
    if a.straight {
        params.push(("mode".into(), "straight".into()));
    } else {
        params.extend::<[(String, String); 3]>([
            ("mode".into(), "rays".into()),
            ("max_rays".into(), a.max_rays.to_string()),
            ("truncated".into(), ins.truncated.to_string()),
        ]);
        if ins.truncated {
            params.push((
                "unresolved_fraction".into(),
                format!(
                    "{unresolved} (the ray budget ran out: the floor between rays whose \
                     shadow edges were not resolved, its vertices written as not insonified)"
                ),
            ));
        }
    }
    match (&a.seafloor_csv, &a.seafloor) {
        (Some(p), _) => params.push(("seafloor".into(), format!("csv {}", p.display()))),
        (None, Some(p)) => params.push((
            "seafloor".into(),
            format!(
                "{} {}, section azimuth {} deg, length {} m, water depth {} m",
                kind,
                p.display(),
                a.azimuth,
                a.length,
                a.water_depth
            ),
        )),
        (None, None) => params.push((
            "seafloor".into(),
            format!(
                "generated ripple (seed {}), section azimuth {} deg, length {} m, water depth {} m",
                a.seed, a.azimuth, a.length, a.water_depth
            ),
        )),
    }
    // every output is produced before any is written: an error leaves no partial set
    let mut files: Vec<(PathBuf, String)> = Vec::new();
    if let Some(p) = outs.get(Format::Csv) {
        files.push((
            p.to_path_buf(),
            insonification_csv(&fl, &prof, &ins, &params),
        ));
    }
    if let Some(p) = &a.rays_csv {
        let show = TraceOptions {
            stop_at_bottom: false,
            record: true,
            ..trace
        };
        let n = a.rays;
        let rays = (0..n)
            .map(|i| {
                let t = if n > 1 {
                    i as f64 / (n - 1) as f64
                } else {
                    0.0
                };
                let (x, z, ang) = fan.launch(t);
                tracer.trace(x, z, ang, &show)
            })
            .collect::<Result<Vec<_>, _>>()?;
        files.push((p.clone(), rays_csv(&rays, &params)));
    }
    if let Some(p) = outs.get(Format::Bty) {
        files.push((p.to_path_buf(), bty_text(&fl, &params)));
    }
    if let Some(p) = &a.seafloor_csv_out {
        files.push((p.clone(), floor_csv(&fl, &params)));
    }
    for (p, text) in &files {
        cellsurf::engine::io::write_atomic(p, text.as_bytes())
            .with_context(|| format!("writing {}", p.display()))?;
        conv::wrote(p);
    }
    let elapsed = start.elapsed().as_secs_f64();
    let lit = ins.length_fraction(&fl);
    let lit_m = ins.lit_length(&fl);
    let floor_m = fl.length();
    let unresolved_m = ins.unresolved_length(&fl);
    let spans = ins.spans(&fl);
    if a.json {
        let own = serde_json::json!({
            "profile": prof.name(),
            "vertices": fl.len(),
            "rays": ins.rays,
            "fan_rays": a.rays,
            "shadow_edges": ins.edges,
            "truncated": ins.truncated,
            "insonified_fraction": lit,
            "shadowed_fraction": (1.0 - lit - unresolved).max(0.0),
            "unresolved_fraction": unresolved,
            "lit_length_m": lit_m,
            "shadowed_length_m": (floor_m - lit_m - unresolved_m).max(0.0),
            "unresolved_length_m": unresolved_m,
            "floor_length_m": floor_m,
            "lit_spans": spans.iter().filter(|s| s.lit).count(),
            "shadowed_spans": spans.iter().filter(|s| !s.lit).count(),
            "vertex_insonified_fraction": ins.insonified_fraction(),
            "zarr_chunks_read": chunks_read,
            "max_snell_drift": ins.max_snell_drift,
            "run": {
                "angles_deg": [amin, amax],
                "max_path_m": traced.then_some(max_path),
                "max_rays": (!a.straight).then_some(a.max_rays),
                "seafloor": params.iter().find(|(k, _)| k == "seafloor").map(|(_, v)| v),
                "profile": prof.describe(),
            },
        });
        let v = conv::envelope("raytrace", conv::scenario_table(&a)?, elapsed, own)?;
        outln!("{}", serde_json::to_string(&v)?)?;
    } else {
        outln!(
            "raytrace: {} floor vertices, {} rays ({} shadow edges{}), insonified {:.1} % of {floor_m:.2} m ({lit_m:.2} m lit, {} lit stretches), shadowed {:.1} %{}, max Snell drift {:.1e}, {elapsed:.2} s",
            fl.len(),
            ins.rays,
            ins.edges,
            if ins.truncated {
                ", ray budget exhausted: truncated"
            } else {
                ""
            },
            lit * 100.0,
            spans.iter().filter(|s| s.lit).count(),
            (1.0 - lit - unresolved).max(0.0) * 100.0,
            if ins.truncated {
                format!(", unresolved {:.1} %", unresolved * 100.0)
            } else {
                String::new()
            },
            ins.max_snell_drift
        )?;
    }
    Ok(())
}
