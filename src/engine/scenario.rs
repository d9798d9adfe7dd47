//! Scenario files of the subcommands whose options the library reads back (wind ripples,
//! dunes, cursor, ray tracing, tiling): the keys `cellsurf SUB --print-scenario` writes, one
//! a model parameter, named as the option (`steps`, `size`, `wind_field`, ...), after
//! `model = "SUB"`.
//!
//! [`read`] checks the model and hands the other keys to the model's own struct, which refuses
//! a key it does not know; [`GridSize`] is a grid size as those files write it. The published
//! figures read their scenario files (`scenarios/`) through these, so that a figure and the
//! command that reruns its scenario take the same parameters from the same file.

use std::fmt;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Deserializer};
use thiserror::Error;

/// A scenario file that cannot be read: not TOML, another model's, an unknown key, a value of
/// the wrong type or out of range.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{0}")]
pub struct ScenarioError(pub String);

impl ScenarioError {
    /// An error with this message.
    pub fn new(msg: impl fmt::Display) -> Self {
        ScenarioError(msg.to_string())
    }
}

/// What a scenario key takes, said from the TOML reader's message about a value it refused
/// (``invalid type: floating point `2.5`, expected usize``): the number kinds in words, any
/// other message (an unknown name's list of names) as it is.
pub fn what_a_key_takes(msg: &str) -> String {
    let first = msg.lines().next().unwrap_or(msg).trim();
    let expected = first.rsplit_once("expected ").map_or(first, |(_, e)| e);
    match expected.trim_end_matches(|c: char| c == '.' || c.is_whitespace()) {
        "usize" | "u64" | "u32" | "u16" | "u8" => "expected a whole number >= 0".into(),
        "i64" | "i32" => "expected a whole number".into(),
        "f64" | "f32" => "expected a number".into(),
        "a boolean" => "expected true or false".into(),
        "a string" => "expected a string".into(),
        _ if first.contains("expected") => format!("expected {expected}"),
        _ => first.to_string(),
    }
}

/// `base` with the key `k` set to `v`, read as a `T`; if it does not read, why, in words
/// ([`what_a_key_takes`]: a key of names given a value of another kind lists its names; an
/// unknown key is the reader's own message, which lists the keys).
pub fn key_reads_as<T: DeserializeOwned>(
    base: &toml::Table,
    k: &str,
    v: &toml::Value,
) -> Result<T, String> {
    let with = |v: &toml::Value| {
        let mut t = base.clone();
        t.insert(k.to_string(), v.clone());
        toml::Value::Table(t).try_into::<T>()
    };
    with(v).map_err(|e| {
        let e = e.to_string();
        if e.contains("unknown field") {
            return e;
        }
        match with(&toml::Value::String(String::new())) {
            Err(names) if e.contains("string only") => what_a_key_takes(&names.to_string()),
            _ => what_a_key_takes(&e),
        }
    })
}

/// Reads a scenario file of `model` (`model = "MODEL"` required) into `T`, whose fields are the
/// model's other keys (`T` refuses an unknown key with `#[serde(deny_unknown_fields)]`).
pub fn read<T: DeserializeOwned>(text: &str, model: &str) -> Result<T, ScenarioError> {
    let mut t: toml::Table = text
        .parse()
        .map_err(|e| ScenarioError::new(format!("not TOML: {e}")))?;
    match t.remove("model") {
        Some(toml::Value::String(m)) if m == model => {}
        Some(m) => {
            return Err(ScenarioError::new(format!(
                "model = {m} is not '{model}': run it with `cellsurf {}`",
                m.as_str().unwrap_or("?")
            )));
        }
        None => {
            return Err(ScenarioError::new(format!(
                "the file must name its model, `model = \"{model}\"`"
            )));
        }
    }
    toml::Value::Table(t)
        .try_into()
        .map_err(|e: toml::de::Error| ScenarioError::new(e.message()))
}

/// A grid size in cells as a scenario file writes it: a whole number `N` (a square) or a
/// string `"WxH"` (or `"N"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GridSize {
    /// Cells along x.
    pub w: usize,
    /// Cells along y.
    pub h: usize,
}

impl GridSize {
    /// The side of a square size; an error naming `key` otherwise.
    pub fn side(self, key: &str) -> Result<usize, ScenarioError> {
        if self.w == self.h {
            Ok(self.w)
        } else {
            Err(ScenarioError::new(format!(
                "{key} = {}x{} is out of range: this grid is square, give N or NxN",
                self.w, self.h
            )))
        }
    }
}

/// `"WxH"` or `"N"` as two whole numbers.
fn parse_size(s: &str) -> Option<GridSize> {
    let whole = |t: &str| t.trim().parse::<usize>().ok();
    match s.split_once(['x', 'X']) {
        Some((w, h)) => Some(GridSize {
            w: whole(w)?,
            h: whole(h)?,
        }),
        None => whole(s).map(|n| GridSize { w: n, h: n }),
    }
}

impl<'de> Deserialize<'de> for GridSize {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<GridSize, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            N(u64),
            S(String),
        }
        match Raw::deserialize(d)? {
            Raw::N(n) => Ok(GridSize {
                w: n as usize,
                h: n as usize,
            }),
            Raw::S(s) => parse_size(&s).ok_or_else(|| {
                serde::de::Error::custom(format!(
                    "size = \"{s}\" is not a grid size: expected N or WxH (whole numbers)"
                ))
            }),
        }
    }
}

/// Checks that `parse` refuses each of `cases`, a scenario of `model` with the keys `.0`, with a
/// message that names `.1` (the models' tests).
#[cfg(test)]
pub(crate) fn assert_refused<T: fmt::Debug>(
    model: &str,
    parse: impl Fn(&str) -> Result<T, ScenarioError>,
    cases: &[(&str, &str)],
) {
    for (keys, needle) in cases {
        let e = parse(&format!("model = \"{model}\"\n{keys}\n"))
            .expect_err(keys)
            .0;
        assert!(e.contains(needle), "{keys}: {e}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    struct T {
        size: Option<GridSize>,
        steps: Option<u64>,
    }

    #[test]
    fn reads_the_model_and_refuses_what_is_not_its_own() {
        let t: T = read("model = \"m\"\nsize = \"4x3\"\nsteps = 5\n", "m").unwrap();
        assert_eq!(t.size, Some(GridSize { w: 4, h: 3 }));
        assert_eq!(t.steps, Some(5));
        let t: T = read("model = \"m\"\nsize = 7\n", "m").unwrap();
        assert_eq!(t.size.unwrap().side("size"), Ok(7));
        assert!(
            read::<T>("size = 7\n", "m")
                .unwrap_err()
                .0
                .contains("model")
        );
        let e = read::<T>("model = \"other\"\n", "m").unwrap_err().0;
        assert!(e.contains("cellsurf other"), "{e}");
        let e = read::<T>("model = \"m\"\nsteep = 1\n", "m").unwrap_err().0;
        assert!(e.contains("steep"), "{e}");
        let e = read::<T>("model = \"m\"\nsize = \"4y3\"\n", "m")
            .unwrap_err()
            .0;
        assert!(e.contains("4y3"), "{e}");
        let e = GridSize { w: 4, h: 3 }.side("size").unwrap_err().0;
        assert!(e.contains("square"), "{e}");
    }
}
