//! [`SoundSpeed`]: the sound-speed profile c(z) and its gradient dc/dz, z positive downward.
//!
//! - [`SoundSpeed::Isovelocity`]: c constant (straight rays).
//! - [`SoundSpeed::Linear`]: c = c0 + g z; rays are circular arcs of radius
//!   c(z0) / (|g| cos theta0) (Snell's law; Jensen, Kuperman, Porter & Schmidt 2011,
//!   Computational Ocean Acoustics, Springer, ch. 3).
//! - [`SoundSpeed::Munk`]: Munk's (1974) canonical deep-water profile ([`Munk`]).
//! - [`SoundSpeed::Table`]: piecewise linear in depth ([`Table`]; depths strictly increasing,
//!   speeds positive), as BELLHOP's 'C' (c-linear) interpolation.
//! - [`SoundSpeed::Mackenzie`]: Mackenzie's (1981) nine-term equation from piecewise-linear
//!   temperature and salinity tables ([`Mackenzie`]).
//!
//! A table must cover the water column it is used in: [`SoundSpeed::check_depth`] rejects a
//! seafloor deeper than the last row (no silent extrapolation). Inside the ray integrator the
//! Runge-Kutta stages may look a hair outside the table (above the surface, below the floor);
//! there the end value is held constant.

use super::{RaytraceError, check_range, range_err};

/// A piecewise-linear function of depth: `z` strictly increasing, values finite.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    z: Vec<f64>,
    v: Vec<f64>,
}

impl Table {
    /// A table from depths (m, strictly increasing, the first at most 0 so that it covers the
    /// sea surface) and values. `what` names the table in errors; each value must lie in
    /// `[lo, hi]` (`unit` for the message).
    pub fn new(
        what: &str,
        depths: Vec<f64>,
        values: Vec<f64>,
        (lo, hi, unit): (f64, f64, &str),
    ) -> Result<Self, RaytraceError> {
        if depths.len() != values.len() {
            return Err(range_err(
                format!("{what} rows"),
                format!("{} depths and {} values", depths.len(), values.len()),
                "as many values as depths",
            ));
        }
        if depths.len() < 2 {
            return Err(range_err(
                format!("{what} rows"),
                depths.len(),
                "at least 2 rows (depth, value)",
            ));
        }
        for (i, (&z, &v)) in depths.iter().zip(&values).enumerate() {
            check_range(
                &format!("{what} depth (row {})", i + 1),
                z,
                -1e4,
                12_000.0,
                "m",
            )?;
            check_range(&format!("{what} value (row {})", i + 1), v, lo, hi, unit)?;
            if i > 0 && z <= depths[i - 1] {
                return Err(range_err(
                    format!("{what} depth (row {})", i + 1),
                    z,
                    format!("strictly greater than the previous depth {}", depths[i - 1]),
                ));
            }
        }
        if depths[0] > 0.0 {
            return Err(range_err(
                format!("{what} depth (row 1)"),
                depths[0],
                "at most 0 m: the table must start at the sea surface",
            ));
        }
        Ok(Table {
            z: depths,
            v: values,
        })
    }

    /// Reads `depth, value` rows (comma, semicolon, tab or space separated; `#` comments and
    /// blank lines skipped; a first line that is not numeric is taken as a header).
    pub fn parse(what: &str, text: &str, limits: (f64, f64, &str)) -> Result<Self, RaytraceError> {
        let (mut z, mut v) = (Vec::new(), Vec::new());
        let mut header = false;
        for (n, line, cols) in table_rows(text) {
            let nums: Option<Vec<f64>> = cols.iter().map(|c| c.parse::<f64>().ok()).collect();
            match nums {
                Some(n2) if n2.len() == 2 => {
                    z.push(n2[0]);
                    v.push(n2[1]);
                }
                // (a third column, say a temperature left in, is refused rather than dropped)
                Some(n2) if n2.len() > 2 => {
                    return Err(RaytraceError::Input {
                        what: what.to_string(),
                        reason: format!(
                            "line {}: '{line}' has {} columns, expected two (depth, value)",
                            n + 1,
                            n2.len()
                        ),
                    });
                }
                _ if z.is_empty() && !header => {
                    header = true;
                    continue;
                }
                _ => {
                    return Err(RaytraceError::Input {
                        what: what.to_string(),
                        reason: format!(
                            "line {}: '{line}' is not two numbers (depth, value)",
                            n + 1
                        ),
                    });
                }
            }
        }
        Table::new(what, z, v, limits)
    }

    /// Depths of the rows, m.
    pub fn depths(&self) -> &[f64] {
        &self.z
    }
    /// Values of the rows.
    pub fn values(&self) -> &[f64] {
        &self.v
    }
    /// The last depth, m.
    pub fn last_depth(&self) -> f64 {
        self.z[self.z.len() - 1]
    }

    /// Value and derivative at `z` in the layer entered when moving down (`down`) or up from
    /// `z`: within [`row_tol`] of a row depth the row's value and the gradient of the layer on
    /// that side; elsewhere as [`Table::eval`].
    pub fn eval_toward(&self, z: f64, down: bool) -> (f64, f64) {
        let i = self.z.partition_point(|&d| d < z - row_tol(z));
        if i < self.z.len() && (self.z[i] - z).abs() <= row_tol(z) {
            let j = if down { Some(i) } else { i.checked_sub(1) };
            if let Some(j) = j.filter(|&j| j + 1 < self.z.len()) {
                let g = (self.v[j + 1] - self.v[j]) / (self.z[j + 1] - self.z[j]);
                return (self.v[i] + g * (z - self.z[i]), g);
            }
            return (self.v[i], 0.0);
        }
        self.eval(z)
    }

    /// Value and derivative at `z` on the linear piece that meets depth `row` from above
    /// (`above`) or from below, extended past its ends: the Runge-Kutta stages of a step that
    /// ends on `row` may overshoot it by a hair (O(ds^3)), and must not take the next piece's
    /// gradient there. Beyond the table's ends the end value, with derivative 0.
    pub fn eval_piece(&self, z: f64, row: f64, above: bool) -> (f64, f64) {
        let n = self.z.len();
        let tol = row_tol(row);
        // the piece [z[j], z[j + 1]]: above, the last one starting above the row; below, the
        // last one starting at or above it
        let starts = if above {
            self.z.partition_point(|&d| d < row - tol)
        } else {
            self.z.partition_point(|&d| d <= row + tol)
        };
        match starts.checked_sub(1) {
            None => (self.v[0], 0.0),
            Some(j) if j + 1 >= n => (self.v[n - 1], 0.0),
            Some(j) => {
                let g = (self.v[j + 1] - self.v[j]) / (self.z[j + 1] - self.z[j]);
                (self.v[j] + g * (z - self.z[j]), g)
            }
        }
    }

    /// Value and derivative at `z`; outside the table the end value, with derivative 0.
    /// At a row depth the layer below is used (the first row included).
    pub fn eval(&self, z: f64) -> (f64, f64) {
        let n = self.z.len();
        if z < self.z[0] {
            return (self.v[0], 0.0);
        }
        if z >= self.z[n - 1] {
            return (self.v[n - 1], 0.0);
        }
        let i = self.z.partition_point(|&d| d <= z) - 1;
        let g = (self.v[i + 1] - self.v[i]) / (self.z[i + 1] - self.z[i]);
        (self.v[i] + g * (z - self.z[i]), g)
    }
}

/// How close (m) a depth must be to a table row to count as on it: 1e-9 (1 + |z|).
pub fn row_tol(z: f64) -> f64 {
    1e-9 * (1.0 + z.abs())
}

/// Munk's (1974) canonical profile c(z) = c_axis [1 + eps (zt - 1 + exp(-zt))],
/// zt = 2 (z - z_axis) / scale (Munk 1974, J. Acoust. Soc. Am. 55, 220-226: c_axis = 1500, z_axis = 1300,
/// scale = 1300, eps = 0.00737).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Munk {
    /// Speed on the sound channel axis, m/s.
    pub c_axis: f64,
    /// Depth of the axis, m.
    pub z_axis: f64,
    /// Scale depth B, m.
    pub scale: f64,
    /// Perturbation coefficient epsilon.
    pub eps: f64,
}

impl Default for Munk {
    fn default() -> Self {
        Munk {
            c_axis: 1500.0,
            z_axis: 1300.0,
            scale: 1300.0,
            eps: 0.00737,
        }
    }
}

/// Mackenzie's (1981) sound speed of seawater, m/s, at temperature `t` (deg C), salinity `s`
/// (ppt) and depth `d` (m) (Mackenzie 1981, J. Acoust. Soc. Am. 70, 807-812:
/// T=10, S=35, D=10 gives 1489.97 m/s), with its partial
/// derivatives (dc/dT, dc/dS, dc/dD).
pub fn mackenzie(t: f64, s: f64, d: f64) -> (f64, [f64; 3]) {
    let ds = s - 35.0;
    let c = 1448.96 + 4.591 * t - 5.304e-2 * t * t
        + 2.374e-4 * t * t * t
        + 1.340 * ds
        + 1.630e-2 * d
        + 1.675e-7 * d * d
        - 1.025e-2 * t * ds
        - 7.139e-13 * t * d * d * d;
    let dt =
        4.591 - 2.0 * 5.304e-2 * t + 3.0 * 2.374e-4 * t * t - 1.025e-2 * ds - 7.139e-13 * d * d * d;
    let dsal = 1.340 - 1.025e-2 * t;
    let dd = 1.630e-2 + 2.0 * 1.675e-7 * d - 3.0 * 7.139e-13 * t * d * d;
    (c, [dt, dsal, dd])
}

/// The depth term of Mackenzie's equation at `z` and its derivative dD/dz: D = z from the
/// surface (z = 0 included: a ray leaving the surface after a reflection feels the pressure
/// term's gradient like one a hair below it) to [`MACKENZIE_D`]; outside, the end value, held
/// constant (derivative 0).
fn mackenzie_depth(z: f64) -> (f64, f64) {
    let dd = if (0.0..MACKENZIE_D).contains(&z) {
        1.0
    } else {
        0.0
    };
    (z.clamp(0.0, MACKENZIE_D), dd)
}

/// Validity range of Mackenzie's equation (Mackenzie 1981): temperature, deg C.
pub const MACKENZIE_T: (f64, f64) = (-2.0, 30.0);
/// Validity range of Mackenzie's equation: salinity, ppt.
pub const MACKENZIE_S: (f64, f64) = (25.0, 40.0);
/// Validity range of Mackenzie's equation: depth, m.
pub const MACKENZIE_D: f64 = 8000.0;

/// Mackenzie's equation on temperature and salinity tables T(z), S(z).
#[derive(Clone, Debug, PartialEq)]
pub struct Mackenzie {
    /// Temperature, deg C, against depth.
    pub temperature: Table,
    /// Salinity, ppt, against depth.
    pub salinity: Table,
    interfaces: Vec<f64>,
}

impl Mackenzie {
    /// From the two tables (each validated against Mackenzie's range).
    pub fn new(temperature: Table, salinity: Table) -> Self {
        let mut interfaces: Vec<f64> = temperature
            .depths()
            .iter()
            .chain(salinity.depths())
            .copied()
            .collect();
        interfaces.sort_by(f64::total_cmp);
        interfaces.dedup();
        Mackenzie {
            temperature,
            salinity,
            interfaces,
        }
    }

    /// Reads `depth, temperature` rows and either `depth, salinity` rows or one constant
    /// salinity.
    pub fn parse(t_text: &str, s: SalinitySource<'_>) -> Result<Self, RaytraceError> {
        let t = Table::parse(
            "temperature table",
            t_text,
            (
                MACKENZIE_T.0,
                MACKENZIE_T.1,
                "deg C (Mackenzie 1981's range)",
            ),
        )?;
        let s_lim = (MACKENZIE_S.0, MACKENZIE_S.1, "ppt (Mackenzie 1981's range)");
        let s = match s {
            SalinitySource::Table(text) => Table::parse("salinity table", text, s_lim)?,
            SalinitySource::Constant(v) => {
                // (named as the one salinity it is, not as a table's row)
                super::check_range("salinity", v, s_lim.0, s_lim.1, s_lim.2)?;
                let last = t.last_depth().max(1.0);
                Table::new("salinity", vec![t.depths()[0], last], vec![v, v], s_lim)?
            }
        };
        Ok(Mackenzie::new(t, s))
    }
}

/// Where the salinity of a Mackenzie profile comes from.
#[derive(Clone, Copy, Debug)]
pub enum SalinitySource<'a> {
    /// Text of a `depth, salinity` table.
    Table(&'a str),
    /// One salinity at every depth, ppt.
    Constant(f64),
}

/// A sound-speed profile c(z).
#[derive(Clone, Debug, PartialEq)]
pub enum SoundSpeed {
    /// Constant speed, m/s.
    Isovelocity(f64),
    /// c = c0 + g z: `c0` (m/s) at the surface, gradient `g` (1/s).
    Linear {
        /// Speed at z = 0, m/s.
        c0: f64,
        /// dc/dz, 1/s.
        g: f64,
    },
    /// Munk (1974).
    Munk(Munk),
    /// Piecewise linear in depth, speeds in m/s.
    Table(Table),
    /// Mackenzie (1981) from T(z) and S(z).
    Mackenzie(Mackenzie),
}

/// Limits of a sound-speed table's speeds, m/s.
pub const SPEED_LIMITS: (f64, f64, &str) = (1.0, 1.0e5, "m/s");

impl SoundSpeed {
    /// A speed table from `depth, speed` text.
    pub fn parse_table(text: &str) -> Result<Self, RaytraceError> {
        Ok(SoundSpeed::Table(Table::parse(
            "profile table",
            text,
            SPEED_LIMITS,
        )?))
    }

    /// A short name: isovelocity, linear, munk, table or mackenzie.
    pub fn name(&self) -> &'static str {
        match self {
            SoundSpeed::Isovelocity(_) => "isovelocity",
            SoundSpeed::Linear { .. } => "linear",
            SoundSpeed::Munk(_) => "munk",
            SoundSpeed::Table(_) => "table",
            SoundSpeed::Mackenzie(_) => "mackenzie",
        }
    }

    /// A one-line description with the parameters.
    pub fn describe(&self) -> String {
        match self {
            SoundSpeed::Isovelocity(c) => format!("isovelocity c = {c} m/s"),
            SoundSpeed::Linear { c0, g } => format!("linear c = {c0} + {g} z m/s"),
            SoundSpeed::Munk(m) => format!(
                "Munk c_axis = {} m/s, z_axis = {} m, B = {} m, eps = {}",
                m.c_axis, m.z_axis, m.scale, m.eps
            ),
            SoundSpeed::Table(t) => format!(
                "table of {} rows, {} to {} m",
                t.depths().len(),
                t.depths()[0],
                t.last_depth()
            ),
            SoundSpeed::Mackenzie(m) => format!(
                "Mackenzie (1981) from {} temperature and {} salinity rows",
                m.temperature.depths().len(),
                m.salinity.depths().len()
            ),
        }
    }

    /// Speed (m/s) and gradient dc/dz (1/s) at depth `z` (m).
    pub fn eval(&self, z: f64) -> (f64, f64) {
        match self {
            SoundSpeed::Isovelocity(c) => (*c, 0.0),
            SoundSpeed::Linear { c0, g } => (c0 + g * z, *g),
            SoundSpeed::Munk(m) => {
                let zt = 2.0 * (z - m.z_axis) / m.scale;
                let e = (-zt).exp();
                (
                    m.c_axis * (1.0 + m.eps * (zt - 1.0 + e)),
                    m.c_axis * m.eps * (1.0 - e) * 2.0 / m.scale,
                )
            }
            SoundSpeed::Table(t) => t.eval(z),
            SoundSpeed::Mackenzie(m) => {
                let (t, dt) = m.temperature.eval(z);
                let (s, ds) = m.salinity.eval(z);
                let (d, dd) = mackenzie_depth(z);
                let (c, p) = mackenzie(t, s, d);
                (c, p[0] * dt + p[1] * ds + p[2] * dd)
            }
        }
    }

    /// [`SoundSpeed::eval`], but on a table row (within [`row_tol`]) the gradient of the layer
    /// entered when moving down (`down`) or up: the integrator's steps start on rows.
    pub fn eval_toward(&self, z: f64, down: bool) -> (f64, f64) {
        match self {
            SoundSpeed::Table(t) => t.eval_toward(z, down),
            SoundSpeed::Mackenzie(m) => {
                let (t, dt) = m.temperature.eval_toward(z, down);
                let (s, ds) = m.salinity.eval_toward(z, down);
                let (d, dd) = mackenzie_depth(z);
                let (c, p) = mackenzie(t, s, d);
                (c, p[0] * dt + p[1] * ds + p[2] * dd)
            }
            _ => self.eval(z),
        }
    }

    /// [`SoundSpeed::eval`] for the stages of a step that ends on the depth `row` (a table row
    /// or the sea surface), coming from above (`above`) or below: each table is evaluated on
    /// its piece that meets `row` on that side, extended past it ([`Table::eval_piece`]), and
    /// Mackenzie's depth term is not held at the surface, so that a stage overshooting `row`
    /// by a hair sees the smooth continuation of the layer the step comes through.
    pub fn eval_piece(&self, z: f64, row: f64, above: bool) -> (f64, f64) {
        match self {
            SoundSpeed::Table(t) => t.eval_piece(z, row, above),
            SoundSpeed::Mackenzie(m) => {
                let (t, dt) = m.temperature.eval_piece(z, row, above);
                let (s, ds) = m.salinity.eval_piece(z, row, above);
                let (d, dd) = if z < MACKENZIE_D {
                    (z, 1.0)
                } else {
                    (MACKENZIE_D, 0.0)
                };
                let (c, p) = mackenzie(t, s, d);
                (c, p[0] * dt + p[1] * ds + p[2] * dd)
            }
            _ => self.eval(z),
        }
    }

    /// Speed at depth `z`, m/s.
    pub fn speed(&self, z: f64) -> f64 {
        self.eval(z).0
    }

    /// Depths where the gradient jumps (table rows); the integrator lands its steps on them.
    pub fn interfaces(&self) -> &[f64] {
        match self {
            SoundSpeed::Table(t) => t.depths(),
            SoundSpeed::Mackenzie(m) => &m.interfaces,
            _ => &[],
        }
    }

    /// Checks the parameters and that the profile covers the water column `0..=z_max` with a
    /// positive, finite speed.
    pub fn check_depth(&self, z_max: f64) -> Result<(), RaytraceError> {
        check_range("deepest seafloor depth", z_max, 0.0, 12_000.0, "m")?;
        match self {
            SoundSpeed::Isovelocity(c) => check_range("c0", *c, 1.0, 1e5, "m/s")?,
            SoundSpeed::Linear { c0, g } => {
                check_range("c0", *c0, 1.0, 1e5, "m/s")?;
                check_range("gradient", *g, -1e4, 1e4, "1/s")?;
                let c_bot = c0 + g * z_max;
                if c_bot < 1.0 {
                    return Err(range_err(
                        "gradient",
                        g,
                        format!(
                            "a gradient that keeps c = c0 + g z >= 1 m/s down to the seafloor ({z_max} m); here c = {c_bot} m/s there"
                        ),
                    ));
                }
            }
            SoundSpeed::Munk(m) => {
                check_range("munk c_axis", m.c_axis, 1.0, 1e5, "m/s")?;
                check_range("munk z_axis", m.z_axis, 0.0, 12_000.0, "m")?;
                check_range("munk scale", m.scale, 1.0, 1e5, "m")?;
                check_range("munk eps", m.eps, 0.0, 0.1, "")?;
            }
            SoundSpeed::Table(t) => {
                if t.last_depth() < z_max {
                    return Err(range_err(
                        "profile table last depth",
                        t.last_depth(),
                        format!("at least the deepest seafloor depth {z_max} m (add a row)"),
                    ));
                }
            }
            SoundSpeed::Mackenzie(m) => {
                for (name, t) in [
                    ("temperature table last depth", &m.temperature),
                    ("salinity table last depth", &m.salinity),
                ] {
                    if t.last_depth() < z_max {
                        return Err(range_err(
                            name,
                            t.last_depth(),
                            format!("at least the deepest seafloor depth {z_max} m (add a row)"),
                        ));
                    }
                }
                check_range(
                    "deepest seafloor depth",
                    z_max,
                    0.0,
                    MACKENZIE_D,
                    "m (Mackenzie 1981's range)",
                )?;
            }
        }
        Ok(())
    }
}

/// The data rows of a small text table: `(line index, line, cells)`, cells separated by commas,
/// semicolons, tabs or spaces; `#` comments and blank lines skipped.
pub(crate) fn table_rows(text: &str) -> impl Iterator<Item = (usize, &str, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(n, line)| {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            return None;
        }
        let cols: Vec<&str> = line
            .split([',', ';', '\t', ' '])
            .filter(|s| !s.is_empty())
            .collect();
        Some((n, line, cols))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_row_of_more_than_two_numbers_is_refused() {
        let lim = (1400.0, 1700.0, "m/s");
        let ok = Table::parse("profile table", "depth,speed\n0,1500\n20,1490\n", lim).unwrap();
        assert_eq!(ok.values(), &[1500.0, 1490.0]);
        let e = Table::parse("profile table", "0,1500\n20,1500,7\n", lim)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2") && e.contains("3 columns"), "{e}");
    }

    #[test]
    fn munk_profile_values() {
        let m = SoundSpeed::Munk(Munk::default());
        for (z, c) in [(0.0, 1548.52), (1300.0, 1500.00), (5000.0, 1551.91)] {
            assert!((m.speed(z) - c).abs() < 0.005, "c({z}) = {}", m.speed(z));
        }
        // the gradient is the derivative of the speed
        for z in [10.0, 700.0, 1300.0, 3000.0] {
            let h = 1e-3;
            let num = (m.speed(z + h) - m.speed(z - h)) / (2.0 * h);
            assert!((m.eval(z).1 - num).abs() < 1e-7, "z = {z}");
        }
        assert!(m.eval(1300.0).1.abs() < 1e-12, "the axis is the minimum");
    }

    #[test]
    fn mackenzie_check_value() {
        let (c, _) = mackenzie(10.0, 35.0, 10.0);
        assert!((c - 1489.97).abs() < 0.005, "c = {c}");
        let t = Table::new("t", vec![0.0, 100.0], vec![10.0, 10.0], (-2.0, 30.0, "")).unwrap();
        let s = Table::new("s", vec![0.0, 100.0], vec![35.0, 35.0], (25.0, 40.0, "")).unwrap();
        let p = SoundSpeed::Mackenzie(Mackenzie::new(t, s));
        assert!((p.speed(10.0) - 1489.97).abs() < 0.005);
        // the chain-rule gradient matches a finite difference (T falling with depth)
        let t = Table::new("t", vec![0.0, 50.0], vec![20.0, 8.0], (-2.0, 30.0, "")).unwrap();
        let s = Table::new("s", vec![0.0, 50.0], vec![33.0, 35.0], (25.0, 40.0, "")).unwrap();
        let p = SoundSpeed::Mackenzie(Mackenzie::new(t, s));
        let h = 1e-4;
        let num = (p.speed(20.0 + h) - p.speed(20.0 - h)) / (2.0 * h);
        assert!((p.eval(20.0).1 - num).abs() < 1e-6);
    }

    #[test]
    fn table_is_validated_and_piecewise_linear() {
        let lim = SPEED_LIMITS;
        assert!(Table::new("p", vec![0.0, 10.0, 10.0], vec![1500.0; 3], lim).is_err());
        assert!(Table::new("p", vec![0.0, 10.0], vec![1500.0, -3.0], lim).is_err());
        assert!(Table::new("p", vec![0.0, 10.0], vec![1500.0, f64::NAN], lim).is_err());
        assert!(Table::new("p", vec![2.0, 10.0], vec![1500.0, 1510.0], lim).is_err());
        let t = Table::new(
            "p",
            vec![0.0, 10.0, 20.0],
            vec![1500.0, 1520.0, 1510.0],
            lim,
        )
        .unwrap();
        assert_eq!(t.eval(5.0), (1510.0, 2.0));
        assert_eq!(t.eval(15.0), (1515.0, -1.0));
        assert_eq!(t.eval(10.0), (1520.0, -1.0));
        assert_eq!(t.eval(30.0), (1510.0, 0.0));
        let p = SoundSpeed::Table(t);
        assert!(p.check_depth(20.0).is_ok());
        let e = p.check_depth(25.0).unwrap_err().to_string();
        assert!(
            e.contains("profile table last depth") && e.contains("25"),
            "{e}"
        );
        let parsed = SoundSpeed::parse_table("depth,c\n0, 1500\n# note\n10 1490\n").unwrap();
        assert_eq!(parsed.speed(5.0), 1495.0);
        assert!(SoundSpeed::parse_table("0,1500\nten,1490\n").is_err());
    }

    #[test]
    fn linear_profile_must_stay_positive() {
        let p = SoundSpeed::Linear {
            c0: 1500.0,
            g: -1.0,
        };
        assert!(p.check_depth(100.0).is_ok());
        assert!(p.check_depth(2000.0).is_err());
        assert!(SoundSpeed::Isovelocity(0.0).check_depth(10.0).is_err());
    }
}
