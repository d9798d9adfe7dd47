//! [`RaytraceScenario`]: a `cellsurf raytrace` scenario file read back by the library (the
//! published figure's runs): the subcommand's options as keys, its defaults for the others,
//! over the built-in generated floor.

use serde::Deserialize;

use super::profile::{Mackenzie, SalinitySource};
use super::{
    Fan, InsonifyOptions, Munk, RaytraceError, RippleSurface, Seafloor, SectionLine, SoundSpeed,
    TraceOptions,
};
use crate::engine::scenario::{self, ScenarioError};

/// The keys of a `cellsurf raytrace` scenario file (`model = "raytrace"`), as the
/// subcommand's `--print-scenario` writes them.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Keys {
    source_depth: Option<f64>,
    source_range: Option<f64>,
    angle_min: Option<f64>,
    angle_max: Option<f64>,
    opening: Option<f64>,
    centre_angle: Option<f64>,
    rays: Option<usize>,
    profile: Option<String>,
    c0: Option<f64>,
    gradient: Option<f64>,
    profile_table: Option<String>,
    temperature_table: Option<String>,
    salinity_table: Option<String>,
    salinity: Option<f64>,
    water_depth: Option<f64>,
    seafloor_csv: Option<String>,
    seafloor: Option<String>,
    length: Option<f64>,
    azimuth: Option<f64>,
    seed: Option<u64>,
    ds: Option<f64>,
    max_bounces: Option<usize>,
    max_path: Option<f64>,
    max_rays: Option<usize>,
    straight: Option<bool>,
}

/// A `cellsurf raytrace` run over the built-in generated floor: a section through
/// [`RippleSurface::generated`].
#[derive(Clone, Debug, PartialEq)]
pub struct RaytraceScenario {
    /// The sound-speed profile.
    pub profile: SoundSpeed,
    /// The transducer S: range along the section and depth, m (default 0, 10).
    pub source: (f64, f64),
    /// Launch angles, degrees below the horizontal (default 1.5 to 25; from `opening` and
    /// `centre_angle` where both are given).
    pub angles: (f64, f64),
    /// Rays of the initial fan (default 200).
    pub rays: usize,
    /// Seed of the generated ripple field (default 1).
    pub seed: u64,
    /// Depth of the substrate under the generated ripples, m (default 12).
    pub water_depth: f64,
    /// Length of the section, m (default 60).
    pub length: f64,
    /// Direction of the section, degrees from +x (default 0).
    pub azimuth: f64,
    /// Ray step, m (default 0.25).
    pub ds: f64,
    /// Most reflections a ray (default 10).
    pub max_bounces: usize,
    /// Longest ray path, m (default: 3 x (the section's span + its greatest depth)).
    pub max_path: Option<f64>,
    /// Most rays in all (default 2,000,000).
    pub max_rays: usize,
    /// Straight-line visibility instead of rays (default false).
    pub straight: bool,
}

impl RaytraceScenario {
    /// Reads a scenario file as `cellsurf raytrace --scenario` does; `read` returns the text
    /// of a table file the scenario names (`profile_table`, `temperature_table`,
    /// `salinity_table`; paths as written in the file). A floor from a file (`seafloor`,
    /// `seafloor_csv`) is read by the subcommand only.
    pub fn parse(
        text: &str,
        read: &dyn Fn(&str) -> Result<String, String>,
    ) -> Result<RaytraceScenario, ScenarioError> {
        let k: Keys = scenario::read(text, "raytrace")?;
        if let Some(p) = k.seafloor.as_ref().or(k.seafloor_csv.as_ref()) {
            return Err(ScenarioError::new(format!(
                "seafloor {p}: a floor from a file is read by `cellsurf raytrace`; the library reads scenarios of the generated floor"
            )));
        }
        let table = |key: &str, path: &Option<String>| -> Result<String, ScenarioError> {
            let p = path.as_ref().ok_or_else(|| {
                ScenarioError::new(format!(
                    "profile = \"{}\" needs {key}",
                    k.profile.as_deref().unwrap_or("")
                ))
            })?;
            read(p).map_err(|e| ScenarioError::new(format!("{key} {p}: {e}")))
        };
        let c0 = k.c0.unwrap_or(1500.0);
        let profile = match k.profile.as_deref().unwrap_or("isovelocity") {
            "isovelocity" => SoundSpeed::Isovelocity(c0),
            "linear" => SoundSpeed::Linear {
                c0,
                g: k.gradient.unwrap_or(0.0),
            },
            "munk" => SoundSpeed::Munk(Munk::default()),
            "table" => SoundSpeed::parse_table(&table("profile_table", &k.profile_table)?)
                .map_err(ScenarioError::new)?,
            "mackenzie" => {
                let t = table("temperature_table", &k.temperature_table)?;
                let s_text;
                let s = match &k.salinity_table {
                    Some(_) => {
                        s_text = table("salinity_table", &k.salinity_table)?;
                        SalinitySource::Table(&s_text)
                    }
                    None => SalinitySource::Constant(k.salinity.unwrap_or(35.0)),
                };
                SoundSpeed::Mackenzie(Mackenzie::parse(&t, s).map_err(ScenarioError::new)?)
            }
            other => {
                return Err(ScenarioError::new(format!(
                    "profile = \"{other}\" is out of range: expected isovelocity, linear, munk, table or mackenzie"
                )));
            }
        };
        let angles = match (k.opening, k.centre_angle) {
            (Some(o), Some(c)) => (c - o / 2.0, c + o / 2.0),
            (None, None) => (k.angle_min.unwrap_or(1.5), k.angle_max.unwrap_or(25.0)),
            _ => return Err(ScenarioError::new("opening and centre_angle go together")),
        };
        Ok(RaytraceScenario {
            profile,
            source: (
                k.source_range.unwrap_or(0.0),
                k.source_depth.unwrap_or(10.0),
            ),
            angles,
            rays: k.rays.unwrap_or(200),
            seed: k.seed.unwrap_or(1),
            water_depth: k.water_depth.unwrap_or(12.0),
            length: k.length.unwrap_or(60.0),
            azimuth: k.azimuth.unwrap_or(0.0),
            ds: k.ds.unwrap_or(0.25),
            max_bounces: k.max_bounces.unwrap_or(10),
            max_path: k.max_path,
            max_rays: k.max_rays.unwrap_or(2_000_000),
            straight: k.straight.unwrap_or(false),
        })
    }

    /// The floor: the section of `surface` (the generated ripple field of [`Self::seed`]) that
    /// the subcommand cuts, from the centre of column 0 in the middle row along
    /// [`Self::azimuth`], one sample a bin for [`Self::length`] m, [`Self::water_depth`] m
    /// below the surface.
    pub fn floor_of(&self, surface: &RippleSurface) -> Result<Seafloor, RaytraceError> {
        let line = SectionLine::through_middle(surface.ny, surface.bin, self.azimuth, self.length);
        surface.grid().section(line, self.water_depth, 0.0)
    }

    /// The floor over the generated ripple field ([`RippleSurface::generated`]).
    pub fn floor(&self) -> Result<Seafloor, RaytraceError> {
        self.floor_of(&RippleSurface::generated(self.seed)?)
    }

    /// The fan of rays from S.
    pub fn fan(&self) -> Fan {
        Fan::Point {
            x: self.source.0,
            z: self.source.1,
            min_deg: self.angles.0,
            max_deg: self.angles.1,
            rays: self.rays,
        }
    }

    /// The insonification options over `floor` (the longest path by default 3 x (its span +
    /// its greatest depth)).
    pub fn options(&self, floor: &Seafloor) -> InsonifyOptions {
        let (x0, x1) = floor.x_range();
        InsonifyOptions {
            trace: TraceOptions {
                ds: self.ds,
                max_path: self.max_path.unwrap_or(3.0 * (x1 - x0 + floor.max_depth())),
                max_bounces: self.max_bounces,
                stop_at_bottom: true,
                record: false,
            },
            max_rays: self.max_rays,
            ..InsonifyOptions::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn no_file(p: &str) -> Result<String, String> {
        Err(format!("no file {p} here"))
    }

    #[test]
    fn keys_become_the_run_and_the_rest_keep_the_defaults() {
        let s = RaytraceScenario::parse(
            "model = \"raytrace\"\nprofile = \"linear\"\nc0 = 1525.0\ngradient = -2.5\nmax_path = 100.0\n",
            &no_file,
        )
        .unwrap();
        assert_eq!(
            s.profile,
            SoundSpeed::Linear {
                c0: 1525.0,
                g: -2.5
            }
        );
        assert_eq!(
            (s.source, s.angles, s.rays),
            ((0.0, 10.0), (1.5, 25.0), 200)
        );
        assert_eq!(s.max_path, Some(100.0));
        let o = RaytraceScenario::parse(
            "model = \"raytrace\"\nopening = 10.0\ncentre_angle = 20.0\n",
            &no_file,
        )
        .unwrap();
        assert_eq!(o.angles, (15.0, 25.0));
        let t = RaytraceScenario::parse(
            "model = \"raytrace\"\nprofile = \"table\"\nprofile_table = \"t.csv\"\n",
            &|_| Ok("depth, speed\n0, 1500\n12, 1506\n".into()),
        )
        .unwrap();
        assert_eq!(
            t.profile,
            SoundSpeed::parse_table("0,1500\n12,1506").unwrap()
        );
        crate::engine::scenario::assert_refused(
            "raytrace",
            |t: &str| RaytraceScenario::parse(t, &no_file),
            &[
                ("profile = \"table\"", "profile_table"),
                (
                    "profile = \"table\"\nprofile_table = \"t.csv\"",
                    "no file t.csv",
                ),
                ("profile = \"wavy\"", "wavy"),
                ("opening = 5.0", "centre_angle"),
                ("seafloor = \"bed.nc\"", "bed.nc"),
                ("rays_csv = \"r.csv\"", "rays_csv"),
            ],
        );
    }
}
