//! Settings of a session, read from the page's URL query (`?preset=fig5&n=8`): every control
//! by name, checked before a session starts. An unknown parameter, a value out of range or a
//! lattice above [`MAX_CELLS`] is a [`ServeError`] naming the parameter, the value and the
//! valid range.

use std::collections::BTreeMap;

use crate::engine::lattice::{Boundary, Neighbourhood};
use crate::growth::sampler::SamplerKind;
use crate::growth::scene::{SceneConfig, SceneKind, Shape, WeightKind};
use crate::ripple::{Frame, Mode, RippleParams};

use super::ServeError;

/// The seeds a page may ask for: a scenario file it exports holds whole numbers up to 2^63 - 1.
const SEED_RANGE: &str = "a whole number from 0 to 9223372036854775807 (2^63 - 1)";

/// The largest lattice a session may hold, cells (512 x 512): each session's memory stays
/// below about 8 MB.
pub const MAX_CELLS: usize = 512 * 512;
/// The most events a frame may run (accepted events; picks for the rejection sampler are
/// bounded by [`MAX_PICKS_PER_FRAME`]).
pub const MAX_SPEED: u64 = 100_000;
/// The most picks the rejection sampler makes in one frame, so that a frame at `n = 1e4`
/// (almost every pick rejected) still ends in a few milliseconds.
pub const MAX_PICKS_PER_FRAME: u64 = 2_000_000;
/// The largest exponent the page offers.
pub const MAX_N: f64 = 1e4;

/// The presets: the growth paper's Figs. 3-7 (the scenario files of `scenarios/`, embedded)
/// and the kinetic-roughening lesson.
pub const PRESETS: &[(&str, &str, &str)] = &[
    (
        "fig3",
        "Fig. 3: synchronous CA from a seed cell",
        include_str!("../../scenarios/growth_fig3_ca.toml"),
    ),
    (
        "fig4",
        "Fig. 4: CA along the axes (rule 1, 2)",
        include_str!("../../scenarios/growth_fig4_ca_axes.toml"),
    ),
    (
        "fig5",
        "Fig. 5: flame front, n = 2",
        include_str!("../../scenarios/growth_fig5_flame.toml"),
    ),
    (
        "fig6",
        "Fig. 6: deposition on a cosine trough",
        include_str!("../../scenarios/growth_fig6_deposit.toml"),
    ),
    (
        "fig7",
        "Fig. 7: anisotropic crystal, Eq. (5)",
        include_str!("../../scenarios/growth_fig7_crystal.toml"),
    ),
    (
        "kpz",
        "Kinetic roughening: Eden growth on a flat substrate",
        "scene = \"grow\"\nlattice = \"hex\"\nwidth = 512\nheight = 512\nboundary = \"channel\"\n\
         n = 0.0\nshape = \"flat\"\nstart = 2.0\nsampler = \"exact\"\nsteps = 50000\n\
         snapshots = []\nseed = 1\n",
    ),
];

/// Parameters the page reads itself (the server accepts and ignores them).
const PAGE_ONLY: &[&str] = &["autoplay", "explain", "tab"];

/// A growth session's settings: the scene and the speed.
#[derive(Clone, Debug, PartialEq)]
pub struct GrowthSettings {
    /// The preset it started from (`fig3`..`fig7`, `kpz`, or `custom`).
    pub preset: String,
    /// The scene (lattice, size, boundary, rule, shape, sampler, seed).
    pub scene: SceneConfig,
    /// Events per frame: accepted events (exact), acceptances up to
    /// [`MAX_PICKS_PER_FRAME`] picks (rejection), or CA updates. 1..=[`MAX_SPEED`]; default
    /// 1000 (1 for the CA, 512 for `kpz`: a monolayer per frame).
    pub speed: u64,
}

fn bad(parameter: &str, value: &str, expected: impl Into<String>) -> ServeError {
    ServeError::Parameter {
        parameter: parameter.to_string(),
        value: value.to_string(),
        expected: expected.into(),
    }
}

fn num<T: std::str::FromStr>(
    q: &BTreeMap<String, String>,
    k: &str,
    what: &str,
) -> Result<Option<T>, ServeError> {
    match q.get(k) {
        None => Ok(None),
        Some(v) => parse_number(v).map(Some).ok_or_else(|| bad(k, v, what)),
    }
}

/// `v` as a `T`; for a whole-number `T`, also a whole number written as a float (`1e3`,
/// `64.0`: a JSON body's numbers arrive so, and the command line and scenario files accept
/// them), up to 2^53. A fraction (`1.9`) is no whole number: `None`, never truncated.
fn parse_number<T: std::str::FromStr>(v: &str) -> Option<T> {
    let t = v.trim();
    if let Ok(x) = t.parse() {
        return Some(x);
    }
    let f: f64 = t.parse().ok()?;
    let whole = f.is_finite() && f.fract() == 0.0 && f.abs() <= 9_007_199_254_740_992.0;
    // (-0.0 reads as 0)
    whole
        .then(|| format!("{}", f as i64).parse().ok())
        .flatten()
}

/// The preset's scene.
pub fn preset(name: &str) -> Result<SceneConfig, ServeError> {
    let (_, _, text) = PRESETS
        .iter()
        .find(|(n, _, _)| *n == name)
        .ok_or_else(|| bad("preset", name, "fig3, fig4, fig5, fig6, fig7 or kpz"))?;
    SceneConfig::from_toml(text).map_err(|e| ServeError::Scene(e.to_string()))
}

impl GrowthSettings {
    /// Reads the query: `preset` (default `fig5`), then any of `lattice`, `boundary`,
    /// `width`, `height`, `n`, `weight`, `shape`, `start`, `sampler`, `seed`, `speed`,
    /// `ca_rule` (comma-separated) over it. Unknown names are an error.
    pub fn from_query(q: &BTreeMap<String, String>) -> Result<Self, ServeError> {
        const KNOWN: &[&str] = &[
            "preset", "lattice", "boundary", "width", "height", "n", "weight", "shape", "start",
            "sampler", "seed", "speed", "ca_rule",
        ];
        for k in q.keys() {
            if !KNOWN.contains(&k.as_str()) && !PAGE_ONLY.contains(&k.as_str()) {
                return Err(ServeError::UnknownParameter {
                    parameter: k.clone(),
                    known: KNOWN.join(", "),
                });
            }
        }
        let name = q.get("preset").map_or("fig5", String::as_str);
        let mut c = preset(name)?;
        let mut custom = false;
        if let Some(v) = q.get("lattice") {
            c.lattice = v
                .parse::<Neighbourhood>()
                .map_err(|_| bad("lattice", v, "hex, square4 or square8"))?;
            custom = true;
        }
        if let Some(v) = q.get("boundary") {
            c.boundary = v
                .parse::<Boundary>()
                .map_err(|_| bad("boundary", v, "torus, walls, channel or tube"))?;
            custom = true;
        }
        if let Some(w) = num::<usize>(q, "width", "a whole number of columns, 4 to 1024")? {
            c.width = w;
            custom = true;
        }
        if let Some(h) = num::<usize>(q, "height", "a whole number of rows, 4 to 1024")? {
            c.height = h;
            custom = true;
        }
        for (k, v) in [("width", c.width), ("height", c.height)] {
            if !(4..=1024).contains(&v) {
                return Err(bad(k, &v.to_string(), "4 to 1024"));
            }
        }
        if c.width * c.height > MAX_CELLS {
            return Err(bad(
                "width",
                &format!("{} x {}", c.width, c.height),
                format!("width x height at most {MAX_CELLS} cells (512 x 512)"),
            ));
        }
        if let Some(n) = num::<f64>(q, "n", "a number from 0 to 10000")? {
            if !(0.0..=MAX_N).contains(&n) {
                return Err(bad("n", &q["n"], "a number from 0 to 10000"));
            }
            c.n = n;
            custom = true;
        }
        if let Some(v) = q.get("weight") {
            c.weight = v
                .parse::<WeightKind>()
                .map_err(|_| bad("weight", v, "none or axes (Eq. 5)"))?;
            custom = true;
        }
        if let Some(v) = q.get("shape") {
            c.shape = v
                .parse::<Shape>()
                .map_err(|_| bad("shape", v, "point, square, disc, cosine or flat"))?;
            custom = true;
        }
        if let Some(s) = num::<f64>(q, "start", "a size in cell widths")? {
            c.start = s;
            custom = true;
        }
        if let Some(v) = q.get("sampler") {
            c.sampler = v
                .parse::<SamplerKind>()
                .map_err(|_| bad("sampler", v, "exact, rejection or ca"))?;
            custom = true;
        }
        if let Some(s) = num::<u64>(q, "seed", SEED_RANGE)? {
            if s > i64::MAX as u64 {
                return Err(bad("seed", &s.to_string(), SEED_RANGE));
            }
            c.seed = s;
        }
        if let Some(v) = q.get("ca_rule") {
            c.ca_rule = v
                .split(',')
                .map(|x| x.trim().parse::<usize>())
                .collect::<Result<_, _>>()
                .map_err(|_| bad("ca_rule", v, "comma-separated neighbour counts, e.g. 1,2"))?;
            custom = true;
        }
        // The page runs without an end: the scenario's clock limit and snapshots go.
        c.steps = crate::growth::scene::MAX_STEPS;
        c.snapshots.clear();
        c.validate().map_err(|e| ServeError::Scene(e.to_string()))?;
        let default_speed = match (c.sampler, name) {
            (SamplerKind::Ca, _) => 1,
            // One monolayer of the kpz preset's substrate per frame.
            (_, "kpz") => 512,
            _ => 1000,
        };
        let speed =
            num::<u64>(q, "speed", "events per frame, 1 to 100000")?.unwrap_or(default_speed);
        if !(1..=MAX_SPEED).contains(&speed) {
            return Err(bad("speed", &q["speed"], "events per frame, 1 to 100000"));
        }
        Ok(GrowthSettings {
            preset: if custom {
                format!("{name}+custom")
            } else {
                name.to_string()
            },
            scene: c,
            speed,
        })
    }

    /// A scenario file that reproduces the lattice at time `time` with
    /// `cellsurf grow --scenario FILE`: the scene's settings as a `grow` scene, `steps` =
    /// `time` (at least 1), one snapshot at the end.
    pub fn scenario_toml(&self, time: f64) -> String {
        let steps = (time.max(1.0).ceil() as u64).min(crate::growth::scene::MAX_STEPS);
        let cfg = SceneConfig {
            scene: SceneKind::Grow,
            steps,
            snapshots: vec![steps],
            ..self.scene.clone()
        };
        format!(
            "# Made by `cellsurf serve` (preset {}, {} scene) after {steps} timesteps.\n\
             # Reproduce: cellsurf grow --scenario this.toml --out run.png\n{}",
            self.preset,
            self.scene.scene,
            cfg.to_toml()
        )
    }
}

/// A ripple session's settings: a 2-D section (Fig. 2 of the ripple paper).
#[derive(Clone, Debug, PartialEq)]
pub struct RippleSettings {
    /// The run's parameters (2-D, `nx` bins).
    pub params: RippleParams,
    /// Model steps per frame, 1..=200; default 20.
    pub speed: u64,
}

impl RippleSettings {
    /// Reads the query: `nx` (bins, 16 to 1024, default 160), `current_speed` (m/s, 0 to
    /// 10, default 0.5), `current_angle` (degrees, 0 or 180: the
    /// section runs along x; default 0), `seed`, `speed` (steps per
    /// frame, 1 to 200, default 20). Unknown names are an error.
    pub fn from_query(q: &BTreeMap<String, String>) -> Result<Self, ServeError> {
        const KNOWN: &[&str] = &["nx", "current_speed", "current_angle", "seed", "speed"];
        for k in q.keys() {
            if !KNOWN.contains(&k.as_str()) && !PAGE_ONLY.contains(&k.as_str()) {
                return Err(ServeError::UnknownParameter {
                    parameter: k.clone(),
                    known: KNOWN.join(", "),
                });
            }
        }
        // a section along x (the page draws it so): the current towards +x or -x, 0 or 180 deg
        let mut p = RippleParams {
            mode: Mode::TwoD,
            frame: Frame::Grid,
            nx: 160,
            ny: 1,
            layers: 30,
            activity: 0.004,
            ..RippleParams::default()
        };
        if let Some(nx) = num::<usize>(q, "nx", "bins, 16 to 1024")? {
            if !(16..=1024).contains(&nx) {
                return Err(bad("nx", &q["nx"], "bins, 16 to 1024"));
            }
            p.nx = nx;
        }
        if let Some(v) = num::<f64>(q, "current_speed", "m/s, 0 to 10")? {
            p.current_speed = v;
        }
        if let Some(v) = num::<f64>(q, "current_angle", "degrees")? {
            p.current_angle = v;
        }
        if let Some(v) = num::<u64>(q, "seed", SEED_RANGE)? {
            if v > i64::MAX as u64 {
                return Err(bad("seed", &v.to_string(), SEED_RANGE));
            }
            p.seed = v;
        }
        p.validate().map_err(|e| ServeError::Scene(e.to_string()))?;
        let speed = num::<u64>(q, "speed", "steps per frame, 1 to 200")?.unwrap_or(20);
        if !(1..=200).contains(&speed) {
            return Err(bad("speed", &q["speed"], "steps per frame, 1 to 200"));
        }
        Ok(RippleSettings { params: p, speed })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(s: &[(&str, &str)]) -> BTreeMap<String, String> {
        s.iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect()
    }

    #[test]
    fn presets_load_and_overrides_apply() {
        for (name, _, _) in PRESETS {
            let s = GrowthSettings::from_query(&q(&[("preset", name)])).unwrap();
            assert_eq!(&s.preset, name);
        }
        let s = GrowthSettings::from_query(&q(&[("preset", "fig5"), ("n", "8")])).unwrap();
        assert_eq!(s.scene.n, 8.0);
        assert_eq!(s.scene.lattice, Neighbourhood::Hex);
    }

    #[test]
    fn bad_values_name_the_parameter() {
        for (k, v, needle) in [
            ("n", "-1", "n = -1"),
            ("n", "1e5", "n = 1e5"),
            ("n", "abc", "n = abc"),
            ("width", "2000", "width = 2000"),
            ("foo", "1", "foo"),
            ("preset", "fig9", "preset = fig9"),
            ("lattice", "tri", "lattice = tri"),
            ("speed", "0", "speed = 0"),
            ("sampler", "gibbs", "sampler = gibbs"),
        ] {
            let e = GrowthSettings::from_query(&q(&[(k, v)]))
                .unwrap_err()
                .to_string();
            assert!(e.contains(needle), "{k}={v}: {e}");
        }
        for (k, v, needle) in [
            ("speed", "1.9", "speed = 1.9"),
            ("width", "64.5", "width = 64.5"),
        ] {
            let e = GrowthSettings::from_query(&q(&[(k, v)]))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(needle),
                "a fraction is refused, not truncated: {e}"
            );
        }
        // a whole number written as a float is one
        let s = GrowthSettings::from_query(&q(&[("speed", "1e3"), ("width", "64.0")])).unwrap();
        assert_eq!((s.speed, s.scene.width), (1000, 64));
        let e = GrowthSettings::from_query(&q(&[("width", "1024"), ("height", "1024")]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("262144"), "{e}");
    }

    #[test]
    fn scenario_reproduces_the_settings() {
        let s = GrowthSettings::from_query(&q(&[("preset", "fig7"), ("seed", "4")])).unwrap();
        let text = s.scenario_toml(1234.0);
        let c = SceneConfig::from_toml(&text).unwrap();
        assert_eq!(c.steps, 1234);
        assert_eq!(c.seed, 4);
        assert_eq!(c.weight, WeightKind::Axes);
    }
}
