//! Files for established propagation codes and for analysis, written atomically
//! ([`crate::engine::io::write_atomic`]):
//!
//! - [`bty_text`]: a BELLHOP bathymetry file (Acoustics Toolbox, "Altimetry or Bathymetry
//!   File", `ATI_BTY_File.htm` of the BELLHOP documentation, oalib-acoustics.org): the
//!   interpolation type `'L'` (piecewise linear), the number of points, then one
//!   `range (km)  depth (m)` pair a line, depth positive downward. The format requires strictly
//!   increasing ranges, so the lower vertex of a vertical cliff is moved 1 micrometre further in
//!   range ([`CLIFF_NUDGE_M`]). The provenance (version and parameters) goes after the type on
//!   its first line, which BELLHOP's list-directed read ignores.
//! - [`floor_csv`]: the section as `x_m,depth_m[,impedance]` (the `--seafloor-csv` input
//!   format), with `#` header lines recording the version and parameters.
//! - [`insonification_csv`]: one row a floor vertex: insonified or not, grazing angle, travel
//!   time, launch angle, surface bounces, impedance, water impedance and R0.
//! - [`rays_csv`]: the path points of each ray.

use std::fmt::Write as _;
use std::path::Path;

use super::ray::Ray;
use super::seafloor::Seafloor;
use super::shadow::Insonification;
use super::{RHO_WATER, RaytraceError, SoundSpeed, VERSION};

/// How far the lower vertex of a vertical cliff is moved in range in a `.bty` file, m.
pub const CLIFF_NUDGE_M: f64 = 1e-6;

/// Parameters recorded in a file's header, as (name, value).
pub type Params = [(String, String)];

fn header(what: &str, params: &Params) -> String {
    let mut s = format!("# cellsurf {VERSION} raytrace: {what}\n");
    for (k, v) in params {
        let _ = writeln!(s, "# {k} = {}", v.replace('\n', " "));
    }
    s
}

/// The `.bty` text of `floor` (module docs).
pub fn bty_text(floor: &Seafloor, params: &Params) -> String {
    let mut s = String::new();
    let prov: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    let _ = writeln!(
        s,
        "'L'  ! cellsurf {VERSION} raytrace seafloor section; {}",
        prov.join("; ").replace('\n', " ")
    );
    let _ = writeln!(s, "{}", floor.len());
    let mut last = f64::NEG_INFINITY;
    for (&x, &z) in floor.xs().iter().zip(floor.zs()) {
        let x = if x <= last { last + CLIFF_NUDGE_M } else { x };
        last = x;
        let _ = writeln!(s, "{:.12} {:.6}", x / 1000.0, z);
    }
    s
}

fn write(path: &Path, text: &str) -> Result<(), RaytraceError> {
    crate::engine::io::write_atomic(path, text.as_bytes()).map_err(|e| RaytraceError::Output {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}

/// Writes [`bty_text`] to `path`.
pub fn write_bty(path: &Path, floor: &Seafloor, params: &Params) -> Result<(), RaytraceError> {
    write(path, &bty_text(floor, params))
}

/// The section as CSV: `x_m,depth_m,impedance_kg_m2_s` (impedance empty where unknown).
pub fn floor_csv(floor: &Seafloor, params: &Params) -> String {
    let mut s = header(
        "seafloor section (x positive in range, depth positive down)",
        params,
    );
    s.push_str("x_m,depth_m,impedance_kg_m2_s\n");
    for i in 0..floor.len() {
        let imp = floor.impedances()[i].map_or(String::new(), |v| format!("{v}"));
        let _ = writeln!(s, "{},{},{imp}", floor.xs()[i], floor.zs()[i]);
    }
    s
}

/// Writes [`floor_csv`] to `path`.
pub fn write_floor_csv(
    path: &Path,
    floor: &Seafloor,
    params: &Params,
) -> Result<(), RaytraceError> {
    write(path, &floor_csv(floor, params))
}

/// One row a floor vertex (module docs).
pub fn insonification_csv(
    floor: &Seafloor,
    profile: &SoundSpeed,
    ins: &Insonification,
    params: &Params,
) -> String {
    let mut s = header(
        "insonification of the seafloor vertices (first arrivals)",
        params,
    );
    s.push_str("x_m,depth_m,insonified,grazing_deg,tau_s,launch_deg,surface_bounces,impedance_kg_m2_s,water_impedance_kg_m2_s,r0\n");
    for v in 0..floor.len() {
        let (x, z) = (floor.xs()[v], floor.zs()[v]);
        let z1 = RHO_WATER * profile.speed(z);
        let imp = floor.impedances()[v];
        let r0 = imp.map(|z2| super::reflection_coefficient(z2, z1));
        let o = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v}"));
        match ins.arrivals[v] {
            Some(a) => {
                let _ = writeln!(
                    s,
                    "{x},{z},1,{},{},{},{},{},{z1},{}",
                    a.grazing_deg,
                    a.tau,
                    a.launch_deg,
                    a.surface_bounces,
                    o(imp),
                    o(r0)
                );
            }
            None => {
                let _ = writeln!(s, "{x},{z},0,,,,,{},{z1},{}", o(imp), o(r0));
            }
        }
    }
    s
}

/// Writes [`insonification_csv`] to `path`.
pub fn write_insonification_csv(
    path: &Path,
    floor: &Seafloor,
    profile: &SoundSpeed,
    ins: &Insonification,
    params: &Params,
) -> Result<(), RaytraceError> {
    write(path, &insonification_csv(floor, profile, ins, params))
}

/// The path points of each ray: `ray,launch_deg,x_m,depth_m,tau_s`.
pub fn rays_csv(rays: &[Ray], params: &Params) -> String {
    let mut s = header("ray paths", params);
    s.push_str("ray,launch_deg,x_m,depth_m,tau_s\n");
    for (i, r) in rays.iter().enumerate() {
        for p in &r.path {
            let _ = writeln!(s, "{i},{},{},{},{}", r.launch_deg, p[0], p[1], p[2]);
        }
    }
    s
}

/// Writes [`rays_csv`] to `path`.
pub fn write_rays_csv(path: &Path, rays: &[Ray], params: &Params) -> Result<(), RaytraceError> {
    write(path, &rays_csv(rays, params))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bty_format() {
        // a cliff at x = 2 m: its lower vertex is moved 1 um in range
        let f = Seafloor::new(
            vec![0.0, 2.0, 2.0, 5.0],
            vec![10.0, 10.0, 10.5, 10.5],
            vec![],
        )
        .unwrap();
        let p = vec![("seed".to_string(), "3".to_string())];
        let t = bty_text(&f, &p);
        let lines: Vec<&str> = t.lines().collect();
        assert!(lines[0].starts_with("'L'"), "{}", lines[0]);
        assert!(lines[0].contains("seed=3") && lines[0].contains(VERSION));
        assert_eq!(lines[1].trim(), "4");
        assert_eq!(lines.len(), 6);
        let pairs: Vec<(f64, f64)> = lines[2..]
            .iter()
            .map(|l| {
                let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
                assert_eq!(v.len(), 2);
                (v[0], v[1])
            })
            .collect();
        assert_eq!(pairs[0], (0.0, 10.0));
        assert_eq!(pairs[1], (0.002, 10.0));
        assert!((pairs[2].0 - 0.002_000_001).abs() < 1e-13 && pairs[2].1 == 10.5);
        assert_eq!(pairs[3], (0.005, 10.5));
        for w in pairs.windows(2) {
            assert!(w[1].0 > w[0].0, "ranges strictly increasing");
        }
        // the CSV section reads back
        let csv = floor_csv(&f, &p);
        assert!(csv.starts_with("# cellsurf"));
        assert_eq!(Seafloor::parse_csv(&csv).unwrap(), f);
    }
}
