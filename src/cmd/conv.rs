//! The conventions every subcommand shares (written up in `docs/cli.md`).
//!
//! - Counts (`--steps`, `--events`, ...) accept scientific notation, and a count too large to
//!   hold is refused with the option's range: [`count_in`] (a [`CountRange`] the option's check
//!   shares).
//! - Grids are `--size WxH` (or `N` for a square): [`size_in`], [`parse_size`].
//! - `--out FILE` may be repeated; the extension picks the format: [`Outputs`]. A `.npy` output
//!   `NAME.npy` keeps its parameters in the sidecar `NAME.json`.
//! - `--json` prints one object: [`envelope`] (`model`, `version`, `parameters`, `elapsed_s`,
//!   `outputs`, then the model's own keys).
//! - `--scenario FILE.toml` starts from a scenario file, options typed on the command line
//!   override it; `--print-scenario` prints the run's scenario: [`merge_scenario`],
//!   [`scenario_text`].
//! - `--quiet`: no progress bar and no chatter; every file written is reported on stderr
//!   otherwise: [`wrote`], [`note`].
//! - Errors name the flag as the user typed it: [`typed_flag`], [`render_error`].

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, OnceLock};

use anyhow::{Context, Result, bail};
use clap::parser::ValueSource;
use clap::{ArgMatches, Command};
use serde::Serialize;
use serde::de::DeserializeOwned;

use cellsurf::engine::VERSION;
use cellsurf::engine::count::CountRange;

/// The subcommand as parsed: its definition, its matches and the words the user typed.
struct Invocation {
    command: Command,
    matches: ArgMatches,
    /// The words after the subcommand's name.
    words: Vec<String>,
}

static INVOCATION: OnceLock<Invocation> = OnceLock::new();
static QUIET: AtomicBool = AtomicBool::new(false);
static WRITTEN: Mutex<Vec<String>> = Mutex::new(Vec::new());
/// What to say on stderr if the run is interrupted now ([`say_on_interrupt`]).
static ON_INTERRUPT: Mutex<Vec<(u64, String)>> = Mutex::new(Vec::new());
/// Library parameter names that are not the flag's id (e.g. `width` for `--size`).
static SYNONYMS: Mutex<Vec<(&'static str, &'static str)>> = Mutex::new(Vec::new());

/// The top-level keys of the scenario file typed as `--scenario` (none without one, or where
/// it cannot be read as TOML: its own error says so).
pub fn scenario_keys() -> Vec<String> {
    let Some(inv) = INVOCATION.get() else {
        return Vec::new();
    };
    let Some(path) = inv
        .matches
        .try_get_one::<std::path::PathBuf>("scenario")
        .ok()
        .flatten()
    else {
        return Vec::new();
    };
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .map(|t| t.keys().cloned().collect())
        .unwrap_or_default()
}

/// Records the subcommand's definition and matches, for [`typed`] and [`typed_flag`].
pub fn init(command: Command, matches: ArgMatches, words: Vec<String>) {
    let _ = INVOCATION.set(Invocation {
        command,
        matches,
        words,
    });
}

/// Names that the library uses for a parameter whose flag has another id, e.g.
/// `("width", "size")`: an error about `width` then names `--size`.
pub fn synonyms(pairs: &[(&'static str, &'static str)]) {
    if let Ok(mut s) = SYNONYMS.lock() {
        s.extend_from_slice(pairs);
    }
}

/// Whether the option with this id (the field name) was given on the command line.
pub fn typed(id: &str) -> bool {
    INVOCATION.get().is_some_and(|inv| {
        inv.matches
            .try_contains_id(id)
            .unwrap_or(false)
            .then(|| inv.matches.value_source(id))
            .flatten()
            == Some(ValueSource::CommandLine)
    })
}

/// The flag with this id as the user typed it (`--grid`, `-g` or `--size`), or its long form
/// if it was not typed; `None` if the subcommand has no such option.
pub fn typed_flag(id: &str) -> Option<String> {
    let inv = INVOCATION.get()?;
    let arg = inv.command.get_arguments().find(|a| a.get_id() == id)?;
    spellings(arg, &inv.words)
        .into_iter()
        .next()
        .or_else(|| arg.get_long().map(|l| format!("--{l}")))
}

/// Whether the option `id` holds `value` (as the command line writes it) because a scenario
/// file set it away from the option's default: not typed, and not the default (numbers
/// compared as numbers). An option without a default counts as set when it holds a value.
pub fn set_by_scenario(id: &str, value: &str) -> bool {
    if typed(id) {
        return false;
    }
    let Some(inv) = INVOCATION.get() else {
        return false;
    };
    let Some(arg) = inv.command.get_arguments().find(|a| a.get_id() == id) else {
        return false;
    };
    let same = |d: &std::ffi::OsStr| {
        let d = d.to_string_lossy();
        match (d.trim().parse::<f64>(), value.trim().parse::<f64>()) {
            (Ok(x), Ok(y)) => x == y,
            _ => d == value,
        }
    };
    let defaults = arg.get_default_values();
    if defaults.is_empty() {
        // a flag (false by default) or an option without a default
        return value != "false";
    }
    !defaults.iter().any(|d| same(d))
}

/// The flags among `(id, long, given)` that were given, each as the user typed it (else its
/// long name), in the order listed.
pub fn given_flags(flags: &[(&str, &str, bool)]) -> Vec<String> {
    flags
        .iter()
        .filter(|&&(_, _, given)| given)
        .map(|&(id, long, _)| typed_flag(id).unwrap_or_else(|| long.into()))
        .collect()
}

/// A value outside the band `[lo, hi]` to as few digits (2 to 6 decimals) as show it outside:
/// `0.7996` against `[0.8, 1.2]` is `0.7996`, not `0.80`; `0.5` is `0.50`.
pub fn shown_outside(v: f64, lo: f64, hi: f64) -> String {
    (2..=6)
        .map(|d| format!("{v:.d$}"))
        .find(|s| s.parse::<f64>().is_ok_and(|r| !(lo..=hi).contains(&r)))
        .unwrap_or_else(|| v.to_string())
}

/// The command line with a negative value given as an option's value joined to it (`--n -inf`
/// read as `--n=-inf`, `-q -nan` as `-q=-nan`, `--snapshots -inf,5` as `--snapshots=-inf,5`,
/// `-w -5e-1` as `-w=-5e-1`, `--hop -1/64`, `--size -64x1`): a word that is `-inf`, `-nan` or
/// a minus sign followed by a digit or a point (no option of the command line is spelt so).
/// The parser takes such words for short flags otherwise (it knows only the plainest
/// negative numbers), and refuses them without naming the option, where a negative number is
/// the option's to refuse. Only an option that takes a value (`takes_value(word)`, the word
/// as typed: `--n`, `-w`) is joined to: after a switch (`--quiet -5`) the word is left to the
/// parser.
pub fn negative_words_joined(
    args: impl IntoIterator<Item = std::ffi::OsString>,
    takes_value: impl Fn(&str) -> bool,
) -> Vec<std::ffi::OsString> {
    let mut out: Vec<std::ffi::OsString> = Vec::new();
    for w in args {
        let word = w.to_string_lossy().to_ascii_lowercase();
        // (a list's first item too: `--snapshots -inf,5`)
        let first = word.split(',').next().unwrap_or("");
        let numeric = first
            .strip_prefix('-')
            .and_then(|r| r.chars().next())
            .is_some_and(|c| c.is_ascii_digit() || c == '.');
        let special = numeric || ["-inf", "-infinity", "-nan"].contains(&first);
        // a long option (`--n`) or a short one (`-q`), without a value joined to it
        let option = |p: &str| {
            !p.contains('=')
                && (p.len() > 2 && p.starts_with("--")
                    || p.len() == 2 && p.starts_with('-') && p != "--")
        };
        if special
            && let Some(prev) = out.last_mut()
            && let Some(p) = prev.to_str()
            && option(p)
            && takes_value(p)
        {
            let mut joined = std::ffi::OsString::from(format!("{p}="));
            joined.push(&w);
            *prev = joined;
            continue;
        }
        out.push(w);
    }
    out
}

/// Whether `word` (`--long` or `-s`) is an option of some subcommand of `command` that takes
/// a value (for [`negative_words_joined`]).
pub fn takes_value(command: &Command, word: &str) -> bool {
    command
        .get_subcommands()
        .flat_map(|sc| sc.get_arguments())
        .any(|a| {
            a.get_action().takes_values()
                && match word.strip_prefix("--") {
                    Some(long) => a.get_long() == Some(long),
                    None => word.strip_prefix('-').and_then(|s| s.chars().next()) == a.get_short(),
                }
        })
}

/// Sets `--quiet` for [`wrote`] and [`note`].
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// Whether `--quiet` was given.
pub fn quiet() -> bool {
    QUIET.load(Ordering::Relaxed)
}

/// Lists a file written in the JSON `outputs`; [`finish`] reports it on stderr (unless
/// `--quiet`) once the run has succeeded and its outputs are in place, so that a file rolled
/// back by a later failure is never reported as written.
pub fn wrote(path: &Path) {
    if let Ok(mut w) = WRITTEN.lock() {
        w.push(path.display().to_string());
    }
}

/// Says `msg` on stderr (whatever `--quiet` says) if the run is interrupted (Ctrl-C, SIGTERM)
/// while the returned guard lives: for an output that an interrupt leaves in place, what was
/// left and how to finish it.
pub fn say_on_interrupt(msg: String) -> InterruptNote {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let id = NEXT.fetch_add(1, Ordering::Relaxed);
    if let Ok(mut n) = ON_INTERRUPT.lock() {
        n.push((id, msg));
    }
    InterruptNote(id)
}

/// The guard of [`say_on_interrupt`]: dropped, the message is no longer said.
#[must_use]
pub struct InterruptNote(u64);

impl Drop for InterruptNote {
    fn drop(&mut self) {
        if let Ok(mut n) = ON_INTERRUPT.lock() {
            n.retain(|(id, _)| *id != self.0);
        }
    }
}

/// On Ctrl-C or SIGTERM: removes the temporary outputs being written
/// ([`cellsurf::engine::io::remove_live_temporaries`]), says what [`say_on_interrupt`] asked,
/// and exits with status 130.
pub fn interrupted() -> ! {
    cellsurf::engine::io::remove_live_temporaries();
    if let Ok(n) = ON_INTERRUPT.lock() {
        for (_, msg) in n.iter() {
            err_line(format_args!("{msg}"));
        }
    }
    std::process::exit(130);
}

/// The notes held back until the run's inputs are all checked ([`hold_notes`], [`begin`]):
/// `Some` while they are held.
static HELD: Mutex<Option<Vec<String>>> = Mutex::new(None);

/// Holds the notes and warnings of [`note`] back until [`begin`] (or [`finish`]), so that a
/// run refused for a bad input says its error on the first line of stderr, and not the
/// warnings about the run it did not make; those already held stay held.
pub fn hold_notes() {
    if let Ok(mut h) = HELD.lock() {
        h.get_or_insert_with(Vec::new);
    }
}

/// The run's inputs are checked and its work begins: the notes held so far are said (before
/// any progress bar), and later ones at once.
pub fn begin() {
    let held = HELD.lock().ok().and_then(|mut h| h.take());
    for msg in held.into_iter().flatten() {
        err_line(msg);
    }
}

/// A line of chatter on stderr (not with `--quiet`); held back until [`begin`] where
/// [`hold_notes`] asked.
pub fn note(msg: impl std::fmt::Display) {
    if !quiet() {
        say(msg.to_string());
    }
}

/// A warning that the run changes a value it was given (a duration shorter than a step, more
/// frames or rows than the run has): said whatever `--quiet` says, as nothing is changed
/// silently; held back as [`note`] is.
pub fn changed(msg: impl std::fmt::Display) {
    say(msg.to_string());
}

/// A line on stderr now, or held until [`begin`].
fn say(msg: String) {
    if let Ok(mut h) = HELD.lock()
        && let Some(held) = h.as_mut()
    {
        held.push(msg);
        return;
    }
    err_line(msg);
}

/// A line on stderr, whatever `--quiet` says; a failed write (a reader that closed stderr,
/// as `cellsurf ... 2>&1 | head` does) is ignored, so that it never turns a run, or its exit
/// status, into a panic (the standard library's print macros panic there; the binary's
/// clippy lints forbid them).
pub fn err_line(msg: impl std::fmt::Display) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr().lock(), "{msg}");
}

/// The files reported by [`wrote`] so far.
pub fn written() -> Vec<String> {
    WRITTEN.lock().map(|w| w.clone()).unwrap_or_default()
}

/// The one `--json` envelope: `model`, `version`, `parameters` (typed, as in the scenario
/// file), `elapsed_s`, `outputs` (every file written), then the model's own keys.
pub fn envelope(
    model: &str,
    parameters: impl Serialize,
    elapsed_s: f64,
    own: serde_json::Value,
) -> Result<serde_json::Value> {
    let mut v = serde_json::Map::new();
    v.insert("model".into(), model.into());
    v.insert("version".into(), VERSION.into());
    v.insert("parameters".into(), serde_json::to_value(parameters)?);
    v.insert("elapsed_s".into(), elapsed_s.into());
    v.insert("outputs".into(), written().into());
    if let serde_json::Value::Object(o) = own {
        for (k, x) in o {
            if !v.contains_key(&k) {
                v.insert(k, x);
            }
        }
    }
    Ok(serde_json::Value::Object(v))
}

/// A value that is not a number where a number is expected, said in words with the form
/// expected (the standard library's "invalid digit found in string" names neither); the range
/// of a number that parses is checked by its option, which names it. Other errors pass as they
/// are.
pub fn plain_parse_error(command: &mut clap::Command, e: clap::Error) -> clap::Error {
    use clap::error::{ContextKind, ErrorKind};
    use std::error::Error as _;
    if e.kind() == ErrorKind::ArgumentConflict {
        return old_spelling_conflict(command, &e).unwrap_or(e);
    }
    if e.kind() != ErrorKind::ValueValidation {
        return e;
    }
    let expected = match e.source() {
        Some(s)
            if s.downcast_ref::<std::num::ParseIntError>()
                .is_some_and(|e| matches!(e.kind(), std::num::IntErrorKind::PosOverflow)) =>
        {
            "a smaller whole number (the option's range is in --help)"
        }
        Some(s) if s.is::<std::num::ParseIntError>() => "a whole number, 0 or more",
        Some(s) if s.is::<std::num::ParseFloatError>() => "a number (e.g. 0.5 or 1e-3)",
        _ => return e,
    };
    let (Some(arg), Some(value)) = (
        e.get(ContextKind::InvalidArg),
        e.get(ContextKind::InvalidValue),
    ) else {
        return e;
    };
    let msg = format!("invalid value '{value}' for '{arg}': expected {expected}");
    let name = std::env::args().nth(1).unwrap_or_default();
    match command.find_subcommand(&name) {
        Some(sc) => sc
            .clone()
            .bin_name(format!("cellsurf {name}"))
            .error(ErrorKind::ValueValidation, msg),
        None => command.error(ErrorKind::ValueValidation, msg),
    }
}

/// An old spelling given with the flag that replaced it, as clap refuses it: the same option
/// under two of its names (`dunes --grid 50 --size 60`, `-g` with `--size`), or a hidden old
/// option with the one it is part of (`ripple --nx 30 --size 24x12`, `conflicts_with`). The
/// message names both flags as typed and says which is the old spelling; `None` for other
/// conflicts, which clap's own message says well.
fn old_spelling_conflict(command: &clap::Command, e: &clap::Error) -> Option<clap::Error> {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    let name = std::env::args().nth(1)?;
    // (built, so that its arguments can be shown as clap shows them)
    let mut sc = command.find_subcommand(&name)?.clone();
    sc.build();
    let words: Vec<String> = std::env::args().skip(2).collect();
    let find = |shown: &str| sc.get_arguments().find(|a| a.to_string() == shown);
    let (ContextValue::String(first), ContextValue::String(other)) = (
        e.get(ContextKind::InvalidArg)?,
        e.get(ContextKind::PriorArg)?,
    ) else {
        return None;
    };
    let (a, b) = (find(first)?, find(other)?);
    let long = |a: &clap::Arg| format!("--{}", a.get_long().unwrap_or_default());
    let msg = if a.get_id() == b.get_id() {
        // one option under two names: an alias (an old spelling) or its short form
        let spelled = spellings(a, &words);
        let [x, y, ..] = spelled.as_slice() else {
            return None;
        };
        let what = |s: &str| {
            if s.len() == 2 {
                format!("{s} is its short form")
            } else {
                format!("{s} is its old spelling")
            }
        };
        let new = long(a);
        let notes: Vec<String> = [x, y]
            .into_iter()
            .filter(|s| **s != new)
            .map(|s| what(s))
            .collect();
        format!(
            "{x} and {y} both given: both set {new} ({}); give {new} once",
            notes.join(", ")
        )
    } else {
        // a hidden old option ("Old spelling of the x part of --size") with its successor
        let old_of = |a: &clap::Arg| {
            let help = a.get_help()?.to_string();
            a.is_hide_set()
                .then(|| help.strip_prefix("Old spelling of ").map(str::to_string))
                .flatten()
        };
        let (old, new, of) = match (old_of(a), old_of(b)) {
            (Some(of), _) => (a, b, of),
            (None, Some(of)) => (b, a, of),
            (None, None) => return None,
        };
        let typed = |a: &clap::Arg| spellings(a, &words).first().cloned().unwrap_or(long(a));
        let (o, n) = (typed(old), typed(new));
        format!(
            "{o} and {n} both given: {o} is the old spelling of {}; give {n} only",
            of.trim_end_matches('.')
        )
    };
    Some(
        sc.clone()
            .bin_name(format!("cellsurf {name}"))
            .error(ErrorKind::ArgumentConflict, msg),
    )
}

/// The names of option `a` among the `words` typed before any `--` (`--grid`, `-g`,
/// `--size`), each once, in the order typed.
fn spellings(a: &clap::Arg, words: &[String]) -> Vec<String> {
    let longs: Vec<&str> = a
        .get_long()
        .into_iter()
        .chain(a.get_all_aliases().unwrap_or_default())
        .collect();
    let shorts: Vec<char> = a
        .get_short()
        .into_iter()
        .chain(a.get_all_short_aliases().unwrap_or_default())
        .collect();
    let mut seen: Vec<String> = Vec::new();
    for w in words.iter().take_while(|w| *w != "--") {
        let spelled = if let Some(rest) = w.strip_prefix("--") {
            let name = rest.split('=').next().unwrap_or(rest);
            longs.contains(&name).then(|| format!("--{name}"))
        } else {
            w.strip_prefix('-')
                .and_then(|rest| rest.chars().next())
                .filter(|c| shorts.contains(c))
                .map(|c| format!("-{c}"))
        };
        if let Some(s) = spelled.filter(|s| !seen.contains(s)) {
            seen.push(s);
        }
    }
    seen
}

/// The words for a count above `max`, with the reason when `max` is the scenario file's limit.
fn too_large(s: &str, max: u64) -> String {
    if max >= MAX_SEED {
        format!(
            "'{s}' is out of range: expected at most {MAX_SEED} (2^63 - 1, the largest whole \
             number a scenario file holds)"
        )
    } else {
        format!("'{s}' is out of range: expected at most {max}")
    }
}

/// A whole number in decimal or scientific notation (`10000000`, `1e7`, `2.5e6`), up to the
/// largest `u64`; the option parsers below hold it to the option's type and to [`MAX_SEED`].
pub fn parse_whole(s: &str) -> Result<u64, String> {
    let t = s.trim();
    if let Ok(v) = t.parse::<u64>() {
        return Ok(v);
    }
    let bad = || format!("'{s}' is not a whole non-negative number (e.g. 100000 or 1e5)");
    let v: f64 = t.parse().map_err(|_| bad())?;
    if !v.is_finite() || v < 0.0 || v.fract() != 0.0 {
        return Err(bad());
    }
    if v > 1.8e19 {
        return Err(format!("'{s}' is too large: at most {}", u64::MAX));
    }
    Ok(v as u64)
}

/// [`parse_whole`] for an option held in `T`, refusing a count above `max` (and above
/// [`MAX_SEED`], what a scenario file holds).
fn parse_count_at_most<T: TryFrom<u64>>(s: &str, max: u64) -> Result<T, String> {
    let max = max.min(MAX_SEED);
    whole_at_most(s, max)?.ok_or_else(|| too_large(s, max))
}

/// `s` as a whole number in `T` at most `max`: `None` if it is one past that (`1e19`, `inf`
/// for a `u32`), an error if it is not a whole number at all.
fn whole_at_most<T: TryFrom<u64>>(s: &str, max: u64) -> Result<Option<T>, String> {
    let v = match parse_whole(s) {
        Ok(v) => v,
        // (a whole number past u64 is past the range too, which is what to say)
        Err(_) if s.trim().parse::<f64>().is_ok_and(|x| x > max as f64) => return Ok(None),
        Err(e) => return Err(e),
    };
    Ok(T::try_from(v).ok().filter(|_| v <= max))
}

/// A whole-number type an option is held in, with its largest value.
pub trait CountType: TryFrom<u64> + Clone + Send + Sync + 'static {
    /// The largest value of the type.
    const MAX: u64;
}

impl CountType for u32 {
    const MAX: u64 = u32::MAX as u64;
}
impl CountType for u64 {
    const MAX: u64 = u64::MAX;
}
impl CountType for usize {
    const MAX: u64 = usize::MAX as u64;
}

/// The parser of a whole-number option held in `T` whose valid values are `r`: a count as
/// [`parse_whole`] reads it, and one too large for `T` or for a scenario file (`1e19`, `1e30`,
/// `inf`) is refused with the option's own range, `'1e19' is out of range: expected 1 to
/// 2000`. A value that `T` holds is left to the option's check, which states the same range
/// (the check and the parser share `r`).
pub fn count_in<T: CountType>(
    r: CountRange,
) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static {
    count_within(r.expected)
}

/// [`count_in`] for an option whose range ends at another value (`--snapshots`, at most the
/// run's steps; `--blend`, at most the tiles' smaller side): `words` state that end, which the
/// option's check gives as a number once the other value is known.
pub fn count_within<T: CountType>(
    words: &'static str,
) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static {
    move |s| {
        whole_at_most(s, T::MAX.min(MAX_SEED))?
            .ok_or_else(|| format!("'{s}' is out of range: expected {words}"))
    }
}

/// A count in a `usize` option whose range has no end of its own (`raytrace --max-rays`, at
/// least `--rays`): [`parse_whole`], at most [`MAX_SEED`] = 2^63 - 1, the largest whole number
/// a scenario file holds (a larger one could be neither recorded nor read back).
pub fn parse_usize(s: &str) -> Result<usize, String> {
    parse_count_at_most(s, usize::MAX as u64)
}

/// [`parse_whole`] for a `u16` option whose range is the type's (a port).
pub fn parse_u16(s: &str) -> Result<u16, String> {
    parse_count_at_most(s, u64::from(u16::MAX)).map_err(|e| {
        if e.contains("not a whole") {
            format!("{e}: expected 0 to {}", u16::MAX)
        } else {
            e
        }
    })
}

/// Ends the program with the run's `result`: a write to a closed standard output (`| head`)
/// counts as success; the outputs held back are moved into place on success and removed on
/// failure, whose message is printed (naming the flag) with exit status 1.
pub fn finish(result: Result<()>) -> std::process::ExitCode {
    // An interrupt made the run's writes fail: the handler ([`interrupted`]) ends the process
    // (status 130) once it has removed the temporaries; no error of this run is reported.
    while cellsurf::engine::io::interrupted() {
        std::thread::park();
    }
    let result = match result {
        Err(e) if is_broken_pipe(&e) => Ok(()),
        r => r,
    };
    let result = result.and_then(|()| Ok(cellsurf::engine::io::publish_held()?));
    match result {
        Ok(()) => {
            begin();
            if !quiet() {
                for f in written() {
                    err_line(format_args!("wrote {f}"));
                }
                for f in cellsurf::engine::io::take_retired() {
                    err_line(format_args!(
                        "removed {} (written by an earlier run into the set this run replaced)",
                        f.display()
                    ));
                }
            }
            std::process::ExitCode::SUCCESS
        }
        Err(e) => {
            let dropped = cellsurf::engine::io::discard_held();
            err_line(format_args!("error: {}", render_error(&e)));
            // (the warnings held about a run that was refused are not said: they are said
            // once the inputs are right)
            if let Ok(mut h) = HELD.lock() {
                *h = None;
            }
            if dropped > 0 {
                err_line("(no output was written: the run failed)");
            }
            std::process::ExitCode::FAILURE
        }
    }
}

/// Whether `e` is a write to a closed pipe.
fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Refuses a run that would need more memory than this process may have (Linux: the
/// machine's `MemAvailable`, the memory limit of the process's cgroup, as a batch scheduler or
/// a container sets it, and its address-space and data ulimits; nothing is checked where none
/// can be read), naming `what` sets the size: an allocation that fails aborts the program,
/// with no message worth the name.
pub fn check_memory(what: &str, bytes: f64) -> Result<()> {
    let Some((avail, whose)) = available_memory() else {
        return Ok(());
    };
    if bytes > avail as f64 {
        bail!(
            "{what} needs about {:.1} GB of memory, more than the {:.1} GB available to this \
             run ({whose}): choose a smaller one",
            bytes / 1e9,
            avail as f64 / 1e9
        );
    }
    Ok(())
}

/// Bytes of memory a new allocation may take, and which limit gives it: the least of the
/// machine's `MemAvailable` (`/proc/meminfo`), the room left under the process's cgroup
/// memory limit (v2 `memory.max`, v1 `memory.limit_in_bytes`) and under its `ulimit -v`
/// (address space) and `ulimit -d` (data) soft limits.
fn available_memory() -> Option<(u64, &'static str)> {
    let kb_field = |text: &str, key: &str| -> Option<u64> {
        let line = text.lines().find(|l| l.starts_with(key))?;
        Some(line.split_whitespace().nth(1)?.parse::<u64>().ok()? * 1024)
    };
    let mut best: Option<(u64, &'static str)> = None;
    let mut offer = |room: Option<u64>, whose: &'static str| {
        if let Some(r) = room
            && best.is_none_or(|(b, _)| r < b)
        {
            best = Some((r, whose));
        }
    };
    let meminfo = std::fs::read_to_string("/proc/meminfo").unwrap_or_default();
    offer(
        kb_field(&meminfo, "MemAvailable:"),
        "the machine's free memory",
    );
    offer(cgroup_room(), "its cgroup's memory limit");
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let limits = std::fs::read_to_string("/proc/self/limits").unwrap_or_default();
    // "Max address space  <soft> <hard> bytes": a number, or "unlimited"
    let soft = |name: &str| -> Option<u64> {
        let line = limits.lines().find(|l| l.starts_with(name))?;
        line[name.len()..].split_whitespace().next()?.parse().ok()
    };
    let room = |limit: Option<u64>, used: Option<u64>| Some(limit?.saturating_sub(used?));
    offer(
        room(soft("Max address space"), kb_field(&status, "VmSize:")),
        "ulimit -v",
    );
    offer(
        room(soft("Max data size"), kb_field(&status, "VmData:")),
        "ulimit -d",
    );
    best
}

/// The room left under the memory limit of this process's cgroup (v2 or v1), if it has one.
fn cgroup_room() -> Option<u64> {
    let read = |p: &str| -> Option<u64> { std::fs::read_to_string(p).ok()?.trim().parse().ok() };
    let groups = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    for line in groups.lines() {
        let mut parts = line.splitn(3, ':');
        let (_, controllers, path) = (parts.next()?, parts.next()?, parts.next()?);
        // v2 ("0::/path"), then v1's memory controller; the path as mounted, or the root of
        // the mount where the namespace hides it
        let (dir, max, current) = if controllers.is_empty() {
            ("/sys/fs/cgroup", "memory.max", "memory.current")
        } else if controllers.split(',').any(|c| c == "memory") {
            (
                "/sys/fs/cgroup/memory",
                "memory.limit_in_bytes",
                "memory.usage_in_bytes",
            )
        } else {
            continue;
        };
        for base in [format!("{dir}{path}"), dir.to_string()] {
            let base = base.trim_end_matches('/');
            if let (Some(limit), Some(used)) = (
                read(&format!("{base}/{max}")),
                read(&format!("{base}/{current}")),
            ) {
                return Some(limit.saturating_sub(used));
            }
        }
    }
    None
}

/// The largest seed: a scenario file (TOML) holds whole numbers up to 2^63 - 1.
pub const MAX_SEED: u64 = i64::MAX as u64;

/// A seed: a whole number from 0 to [`MAX_SEED`] (`1e3` accepted).
pub fn parse_seed(s: &str) -> Result<u64, String> {
    let out_of_range = || {
        format!(
            "'{s}' is out of range: expected a seed, a whole number from 0 to {MAX_SEED} (2^63 - \
             1, the largest a scenario file holds)"
        )
    };
    let v = match parse_whole(s) {
        Ok(v) => v,
        // (a whole number past u64 is out of the seed's range too, which is what to say)
        Err(_) if s.trim().parse::<f64>().is_ok_and(|x| x > MAX_SEED as f64) => {
            return Err(out_of_range());
        }
        Err(e) => return Err(e),
    };
    if v > MAX_SEED {
        return Err(out_of_range());
    }
    Ok(v)
}

/// A duration in seconds: a number with an optional unit, `s`, `min`, `h` or `d` (`90s`,
/// `30min`, `2h`, `1.5e4`); finite and above 0.
pub fn parse_duration(s: &str) -> Result<f64, String> {
    let t = s.trim();
    let bad = || {
        format!(
            "'{s}' is not a duration: expected a number of seconds above 0, or one with a unit s, min, h or d (e.g. 90s, 30min, 2h)"
        )
    };
    let (num, scale) = [("min", 60.0), ("s", 1.0), ("h", 3600.0), ("d", 86400.0)]
        .iter()
        .find_map(|&(u, k)| t.strip_suffix(u).map(|n| (n.trim(), k)))
        .unwrap_or((t, 1.0));
    let v: f64 = num.parse().map_err(|_| bad())?;
    let secs = v * scale;
    if !(secs.is_finite() && secs > 0.0) {
        return Err(bad());
    }
    Ok(secs)
}

/// A grid size `WxH`, or `N` for `N x N`, in cells (whole numbers of at least 1).
pub fn parse_size(s: &str) -> Result<(usize, usize), String> {
    size_of(s, None)
}

/// The parser of a `--size` whose sides the model's checks hold to `sides` (words read after
/// "expected", `sides of 3 to 65536 cells`): as [`parse_size`], and a side of 0 or one too
/// large to hold (`0x4`, `1e30`) is refused with those words (`'0x4' is out of range: expected
/// sides of 3 to 65536 cells`); a side that a size holds is left to the model's checks.
pub fn size_in(
    sides: &'static str,
) -> impl Fn(&str) -> Result<Size, String> + Clone + Send + Sync + 'static {
    move |s| size_of(s, Some(sides)).map(|(w, h)| Size { w, h })
}

/// [`parse_size`], stating `sides` for a side out of every range.
fn size_of(s: &str, sides: Option<&str>) -> Result<(usize, usize), String> {
    let bad = || match sides {
        Some(r) => format!("'{s}' is not a size: expected N or WxH, e.g. 128 or 200x230, with {r}"),
        None => format!("'{s}' is not a size: expected N or WxH in cells, e.g. 128 or 200x230"),
    };
    let past = || match sides {
        Some(r) => format!("'{s}' is out of range: expected {r}"),
        None => format!("'{s}' has a zero side: each side is at least 1 cell"),
    };
    let (w, h) = match s.split_once(['x', 'X']) {
        Some((w, h)) => (w, h),
        None => (s, s),
    };
    // (each side a count: `1e3` accepted, as by every count option; `None` past every count)
    let side = |t: &str| -> Result<Option<usize>, String> {
        match whole_at_most::<usize>(t.trim(), MAX_SEED) {
            Ok(None) if sides.is_none() => Err(bad()),
            Ok(v) => Ok(v),
            Err(_) => Err(bad()),
        }
    };
    match (side(w)?, side(h)?) {
        (Some(w), Some(h)) if w > 0 && h > 0 => Ok((w, h)),
        _ => Err(past()),
    }
}

/// A grid size in cells, `WxH` (or `N` for a square), as typed and as written in scenario
/// files (a string, or a whole number for a square).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Size {
    /// Cells along x.
    pub w: usize,
    /// Cells along y.
    pub h: usize,
}

impl Size {
    /// A square of side `n`.
    pub const fn square(n: usize) -> Size {
        Size { w: n, h: n }
    }

    /// The side of a square size; an error naming `--size` (as typed) otherwise.
    pub fn side(self) -> Result<usize> {
        if self.w != self.h {
            let flag = typed_flag("size").unwrap_or_else(|| "--size".into());
            bail!("{flag} = {self} is out of range: this grid is square, give N or NxN");
        }
        Ok(self.w)
    }
}

impl std::fmt::Display for Size {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.w, self.h)
    }
}

impl std::str::FromStr for Size {
    type Err = String;
    fn from_str(s: &str) -> Result<Size, String> {
        parse_size(s).map(|(w, h)| Size { w, h })
    }
}

impl Serialize for Size {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.to_string())
    }
}

impl<'de> serde::Deserialize<'de> for Size {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Size, D::Error> {
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Raw {
            N(u64),
            S(String),
        }
        match Raw::deserialize(d)? {
            Raw::N(n) => Ok(Size::square(n as usize)),
            Raw::S(s) => s.parse().map_err(serde::de::Error::custom),
        }
    }
}

/// Serde for an optional value written as its name (`FromStr` and `Display`), for option
/// types that are not serde types themselves: `#[serde(with = "conv::opt_name")]`.
pub mod opt_name {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<T: std::fmt::Display, S: Serializer>(
        v: &Option<T>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        match v {
            Some(v) => s.serialize_str(&v.to_string()),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, T, D>(d: D) -> Result<Option<T>, D::Error>
    where
        T: std::str::FromStr,
        T::Err: std::fmt::Display,
        D: Deserializer<'de>,
    {
        match Option::<String>::deserialize(d)? {
            Some(s) => s.parse().map(Some).map_err(serde::de::Error::custom),
            None => Ok(None),
        }
    }
}

/// The output formats, picked by the extension of `--out`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    Gif,
    Csv,
    Nc,
    Npy,
    Bty,
    Zarr,
}

impl Format {
    /// The extension, without the dot.
    pub fn ext(self) -> &'static str {
        match self {
            Format::Png => "png",
            Format::Gif => "gif",
            Format::Csv => "csv",
            Format::Nc => "nc",
            Format::Npy => "npy",
            Format::Bty => "bty",
            Format::Zarr => "zarr",
        }
    }

    const ALL: [Format; 7] = [
        Format::Png,
        Format::Gif,
        Format::Csv,
        Format::Nc,
        Format::Npy,
        Format::Bty,
        Format::Zarr,
    ];

    /// The format of a path, from its extension (case-insensitive).
    pub fn of(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Format::ALL.into_iter().find(|f| f.ext() == ext)
    }
}

/// The files named by `--out` (repeatable), one per format.
#[derive(Debug, Default)]
pub struct Outputs {
    files: Vec<(Format, PathBuf)>,
}

impl Outputs {
    /// Sorts the `--out` files by format; refuses an extension this subcommand does not write
    /// and two files of one format.
    pub fn new(paths: &[PathBuf], subcommand: &str, accepted: &[Format]) -> Result<Outputs> {
        let flag = typed_flag("out").unwrap_or_else(|| "--out".into());
        let list = || {
            accepted
                .iter()
                .map(|f| format!(".{}", f.ext()))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut files: Vec<(Format, PathBuf)> = Vec::new();
        for p in paths {
            let Some(f) = Format::of(p).filter(|f| accepted.contains(f)) else {
                bail!(
                    "{flag} {}: `cellsurf {subcommand}` writes {} (the extension picks the \
                     format)",
                    p.display(),
                    list()
                );
            };
            if let Some((_, q)) = files.iter().find(|(g, _)| *g == f) {
                bail!(
                    "{flag} {} and {flag} {}: one .{} output per run",
                    q.display(),
                    p.display(),
                    f.ext()
                );
            }
            // Before any work: a missing folder, or a path that is not a file (a Zarr store is
            // a folder: what an existing one holds is checked where it is written).
            if f == Format::Zarr {
                let dir = match p.parent() {
                    Some(d) if !d.as_os_str().is_empty() => d,
                    _ => Path::new("."),
                };
                if !dir.is_dir() {
                    bail!("{flag} {}: the folder does not exist", p.display());
                }
            } else {
                cellsurf::engine::io::check_output(&flag, p)?;
            }
            files.push((f, p.clone()));
        }
        Ok(Outputs { files })
    }

    /// Refuses `p` (given by `option`) when another output of this run has the same path:
    /// one would overwrite the other.
    pub fn check_distinct(&self, option: &str, p: &Path) -> Result<()> {
        if let Some((_, q)) = self.files.iter().find(|(_, q)| same_path(q, p)) {
            bail!(
                "{option} {}: the same file as the output {}; give each output its own name",
                p.display(),
                q.display()
            );
        }
        Ok(())
    }

    /// The file of this format, if one was asked for.
    pub fn get(&self, f: Format) -> Option<&Path> {
        self.files
            .iter()
            .find(|(g, _)| *g == f)
            .map(|(_, p)| p.as_path())
    }

    /// Why the option with this id (the field name), given on the command line, has no
    /// effect: it chooses `what` of the `format` output, and none was asked for.
    pub fn unused_option(&self, id: &str, format: Format, what: &str) -> Option<String> {
        (typed(id) && self.get(format).is_none()).then(|| {
            format!(
                "{} has no effect without a .{ext} output ({what}): give --out FILE.{ext}",
                typed_flag(id).unwrap_or_else(|| format!("--{}", id.replace('_', "-"))),
                ext = format.ext()
            )
        })
    }

    /// Adds a file given by an old spelling (`--gif FILE`, `--npy FILE`), if the format has
    /// none yet.
    pub fn add_legacy(&mut self, f: Format, p: Option<&PathBuf>) -> Result<()> {
        if let Some(p) = p {
            let option = format!("--{}", f.ext());
            if let Some(q) = self.get(f) {
                let out = typed_flag("out").unwrap_or_else(|| "--out".into());
                bail!(
                    "{option} {} and {out} {} both given: {option} is the old spelling of \
                     {out} FILE.{ext}, and a run writes one .{ext} output; give {out} only",
                    p.display(),
                    q.display(),
                    ext = f.ext()
                );
            }
            if Format::of(p) != Some(f) {
                bail!(
                    "{option} {}: the file name must end in .{} (or give it to --out, where the \
                     extension picks the format)",
                    p.display(),
                    f.ext()
                );
            }
            self.check_distinct(&option, p)?;
            cellsurf::engine::io::check_output(&option, p)?;
            self.files.push((f, p.clone()));
        }
        Ok(())
    }
}

/// The file of the old spelling `--format F --out STEM` (kept for one release): the stem with
/// the format's extension. A file name that already ends in another format's extension, or
/// more than one `--out`, is refused: the extension the user typed is never replaced silently.
pub fn legacy_format_path(f: Format, out: &[PathBuf]) -> Result<Option<PathBuf>> {
    if out.len() > 1 {
        bail!(
            "--format with {} --out files: give one --out, or leave --format out (the extension of each --out picks its format)",
            out.len()
        );
    }
    let Some(p) = out.first() else {
        return Ok(None);
    };
    if let Some(other) = Format::of(p).filter(|&g| g != f) {
        bail!(
            "--out {} names a .{} file but --format asks for .{}: give one (--out {}, without --format)",
            p.display(),
            other.ext(),
            f.ext(),
            p.with_extension(f.ext()).display()
        );
    }
    Ok(Some(p.with_extension(f.ext())))
}

/// Whether two output paths name the same file (as written, or once made absolute).
pub fn same_path(a: &Path, b: &Path) -> bool {
    if a == b {
        return true;
    }
    let abs = |p: &Path| {
        let dir = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        dir.canonicalize()
            .ok()
            .zip(p.file_name())
            .map(|(d, n)| d.join(n))
    };
    matches!((abs(a), abs(b)), (Some(x), Some(y)) if x == y)
}

/// Keys of the argument structure that are about input and output, not the model: never
/// read from nor written to a scenario file.
pub const IO_KEYS: [&str; 15] = [
    "scenario",
    "print_scenario",
    "out",
    "save_wind",
    "json",
    "quiet",
    "gif",
    "npy",
    "gif_frames",
    "threads",
    "part",
    "init",
    "check",
    "chunk_tiles",
    "dry_run",
];

fn is_io(key: &str) -> bool {
    IO_KEYS.contains(&key)
}

fn table<A: Serialize>(args: &A) -> Result<toml::Table> {
    match toml::Value::try_from(args).context("parameters as TOML")? {
        toml::Value::Table(t) => Ok(t),
        _ => bail!("parameters are not a table"),
    }
}

/// The model parameters of a run (the options except input/output ones), for the `--json`
/// envelope's `parameters`.
pub fn scenario_table<A: Serialize>(args: &A) -> Result<toml::Table> {
    let mut t = table(args)?;
    t.retain(|k, _| !is_io(k));
    Ok(t)
}

/// The scenario file of a run: `model = "..."`, then every model parameter (the options
/// except input/output ones).
pub fn scenario_text<A: Serialize>(args: &A, model: &str) -> Result<String> {
    let t = scenario_table(args)?;
    let mut s = format!("# cellsurf {VERSION} scenario: `cellsurf {model} --scenario FILE`\n");
    s.push_str(&format!("model = \"{model}\"\n"));
    s.push_str(&toml::to_string(&t).context("scenario as TOML")?);
    Ok(s)
}

/// The models whose scenario files name them (`model = "..."`), each a subcommand.
const MODELS: &[&str] = &[
    "ripple",
    "tile",
    "raytrace",
    "wind-ripples",
    "dunes",
    "cursor",
];

/// The options of a run from `--scenario FILE` (if given) and the command line: a value typed
/// on the command line wins, then the file's, then the option's default. The file must name
/// this model and only its parameters.
pub fn merge_scenario<A: Serialize + DeserializeOwned>(
    args: A,
    scenario: Option<&Path>,
    model: &str,
) -> Result<A> {
    let Some(path) = scenario else {
        return Ok(args);
    };
    let flag = typed_flag("scenario").unwrap_or_else(|| "--scenario".into());
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read {flag} {}", path.display()))?;
    let mut file: toml::Table = text
        .parse()
        .with_context(|| format!("{flag} {} is not TOML", path.display()))?;
    match file.remove("model") {
        Some(toml::Value::String(m)) if m == model => {}
        Some(toml::Value::String(m)) if MODELS.contains(&m.as_str()) => bail!(
            "{flag} {} is a '{m}' scenario, not '{model}': run `cellsurf {m} --scenario {}`",
            path.display(),
            path.display()
        ),
        Some(toml::Value::String(m)) => bail!(
            "{flag} {}: model = \"{m}\" is not a model of cellsurf: expected `model = \"{model}\"` \
             here (the models: {})",
            path.display(),
            MODELS.join(", ")
        ),
        _ => bail!(
            "{flag} {}: the file must name its model, `model = \"{model}\"`",
            path.display()
        ),
    }
    let defaults = table(&args)?;
    let mut merged = defaults.clone();
    let mut from_file = Vec::new();
    let folder = path.parent().unwrap_or(Path::new(""));
    for (k, v) in file {
        let v = if PATH_KEYS.contains(&k.as_str()) {
            beside(folder, v)
        } else {
            v
        };
        if is_io(&k) || !merged.contains_key(&k) && !known_option(&k) {
            bail!(
                "{flag} {}: '{k}' is not a parameter of `cellsurf {model}` (print one with \
                 --print-scenario)",
                path.display()
            );
        }
        if !typed(&k) {
            let v = whole_where_needed::<A>(&defaults, &k, v);
            from_file.push((k.clone(), v.clone()));
            merged.insert(k, v);
        }
    }
    match toml::Value::Table(merged).try_into() {
        Ok(a) => Ok(a),
        Err(e) => {
            // Name the key at fault, its value and what the option takes, in one line (the
            // parser's own message names Rust types).
            for (k, v) in &from_file {
                if !fits::<A>(&defaults, k, v) {
                    let expected = expected_by_option(k, v, kind_that_fits::<A>(&defaults, k));
                    // (a value the option's parser holds out of range, `1e30` or a size of
                    // "0": the key's range, the value as written)
                    if let Some((_, range)) = expected.split_once("' is out of range: ") {
                        let shown = match v {
                            toml::Value::Float(f) => cellsurf::ripple::params::shown(*f),
                            v => v.to_string(),
                        };
                        bail!(
                            "{flag} {}: {k} = {shown} is out of range: {range}",
                            path.display()
                        );
                    }
                    bail!(
                        "{flag} {}: {k} = {v} is not a valid value: {expected}",
                        path.display()
                    );
                }
            }
            Err(e).with_context(|| format!("in {flag} {}", path.display()))
        }
    }
}

/// Keys that name an input file (or a list of them): in a scenario file a relative path is
/// read from the scenario's folder, as a relative path on the command line is read from the
/// working directory.
pub const PATH_KEYS: [&str; 8] = [
    "tile",
    "ripple_scenario",
    "wind_image",
    "profile_table",
    "temperature_table",
    "salinity_table",
    "seafloor_csv",
    "seafloor",
];

/// A scenario's path value (a string, or an array of them) read from the scenario's `folder`:
/// a relative path is joined to it, an absolute one is kept; other values are kept as they are
/// (the option's own parser names them).
fn beside(folder: &Path, v: toml::Value) -> toml::Value {
    match v {
        toml::Value::String(s) if !s.is_empty() && Path::new(&s).is_relative() => {
            toml::Value::String(folder.join(&s).to_string_lossy().into_owned())
        }
        toml::Value::Array(a) => {
            toml::Value::Array(a.into_iter().map(|x| beside(folder, x)).collect())
        }
        other => other,
    }
}

/// Whether the options `defaults` with `k = v` read as an `A`.
fn fits<A: DeserializeOwned>(defaults: &toml::Table, k: &str, v: &toml::Value) -> bool {
    let mut t = defaults.clone();
    t.insert(k.to_string(), v.clone());
    toml::Value::Table(t).try_into::<A>().is_ok()
}

/// A whole number written as a float in a scenario (`steps = 2.0`, `1e4`, `1e17`) read as the
/// integer a whole-number option takes, as the command line reads `--steps 1e4` (and as the
/// ripple and growth scenarios read it), up to 2^63 - 1, the largest integer a scenario file
/// holds; any other value as it is.
fn whole_where_needed<A: DeserializeOwned>(
    defaults: &toml::Table,
    k: &str,
    v: toml::Value,
) -> toml::Value {
    if let toml::Value::Float(f) = v
        && f.is_finite()
        && f.fract() == 0.0
        && f.abs() < 9_223_372_036_854_775_808.0
        && !fits::<A>(defaults, k, &v)
    {
        let whole = toml::Value::Integer(f as i64);
        if fits::<A>(defaults, k, &whole) {
            return whole;
        }
    }
    v
}

/// Checks that the steps of the list option `key` (`snapshots`) are strictly increasing: a list
/// out of order or with a step twice is refused by name, never sorted.
pub fn strictly_increasing(key: &str, steps: &[u64]) -> Result<()> {
    if let Some(w) = steps.windows(2).find(|w| w[1] <= w[0]) {
        let list: Vec<String> = steps.iter().map(u64::to_string).collect();
        bail!(
            "{key} = {} is out of range: expected steps strictly increasing ({} is not after {})",
            list.join(","),
            w[1],
            w[0]
        );
    }
    Ok(())
}

/// A scenario value written as the command line writes it (`1,2` for an array).
pub fn cli_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => f.to_string(),
        toml::Value::Boolean(b) => b.to_string(),
        toml::Value::Array(a) => a.iter().map(cli_text).collect::<Vec<_>>().join(","),
        other => other.to_string(),
    }
}

/// The kind of TOML value that key `k` of the scenario takes (`true or false`, `a number`, ...),
/// found by trying one of each; `None` where none fits.
fn kind_that_fits<A: DeserializeOwned>(defaults: &toml::Table, k: &str) -> Option<&'static str> {
    use toml::Value as V;
    let text = || V::String("x".into());
    let candidates = [
        (V::Boolean(true), "true or false"),
        (V::Float(0.5), "a number (e.g. 0.5 or 1e-3), not in quotes"),
        (V::Integer(1), "a whole number, not in quotes"),
        (text(), "a string in quotes"),
        (
            V::Array(vec![text()]),
            "a list of strings in brackets, e.g. [\"a\", \"b\"]",
        ),
        (
            V::Array(vec![V::Integer(1)]),
            "a list of whole numbers in brackets, e.g. [1, 2]",
        ),
        (
            V::Array(vec![V::Float(0.5)]),
            "a list of numbers in brackets, e.g. [0.5, 2]",
        ),
    ];
    candidates
        .into_iter()
        .find(|(v, _)| fits::<A>(defaults, k, v))
        .map(|(_, kind)| kind)
}

/// What the option `id` takes, said by its own parser of `v` written as on the command line
/// (`'16.5' is not a whole number ...`), by its list of values (`one of calm, uniform, ...`),
/// or by the `kind` of TOML value it takes where the command line would take `v` but the file
/// holds it as another kind (`straight = 1`, `hop = "1/64"`), else the first line of its help.
fn expected_by_option(id: &str, v: &toml::Value, kind: Option<&str>) -> String {
    use std::error::Error as _;
    let text = cli_text(v);
    let Some(inv) = INVOCATION.get() else {
        return "see --help".into();
    };
    let Some(arg) = inv.command.get_arguments().find(|a| a.get_id() == id) else {
        return "see --help".into();
    };
    let help = || {
        arg.get_help()
            .map(|h| h.to_string())
            .and_then(|h| h.lines().next().map(str::to_string))
            .map_or_else(|| "see --help".into(), |h| format!("expected {h}"))
    };
    let listed = || {
        let names: Vec<String> = arg
            .get_possible_values()
            .iter()
            .filter(|p| !p.is_hide_set())
            .map(|p| p.get_name().to_string())
            .collect();
        (!names.is_empty()).then(|| format!("expected one of {}", names.join(", ")))
    };
    let by_kind = || kind.map(|k| format!("expected {k}"));
    let Some(long) = arg.get_long() else {
        return listed().or_else(by_kind).unwrap_or_else(help);
    };
    // (the subcommand's own parser, on `--long=value` alone)
    let parsed = inv
        .command
        .clone()
        .no_binary_name(true)
        .try_get_matches_from([format!("--{long}={text}")]);
    match parsed {
        // accepted by the option, but a whole number past what a scenario file holds
        Ok(_) if whole_past_scenario(v) => format!(
            "expected a whole number from 0 to {MAX_SEED} (2^63 - 1, the largest a scenario \
             file holds)"
        ),
        Err(e) if e.kind() == clap::error::ErrorKind::ValueValidation => match e.source() {
            Some(s) if s.is::<std::num::ParseIntError>() => {
                "expected a whole number, 0 or more".into()
            }
            Some(s) if s.is::<std::num::ParseFloatError>() => {
                "expected a number (e.g. 0.5 or 1e-3)".into()
            }
            Some(s) => s.to_string(),
            None => listed().or_else(by_kind).unwrap_or_else(help),
        },
        // accepted as written on the command line: the file holds it as another kind
        Ok(_) => by_kind().unwrap_or_else(help),
        _ => listed().or_else(by_kind).unwrap_or_else(help),
    }
}

/// Whether `v` is a whole number above [`MAX_SEED`] (written as a float: TOML's integers stop
/// there).
fn whole_past_scenario(v: &toml::Value) -> bool {
    matches!(v, toml::Value::Float(f) if f.is_finite() && f.fract() == 0.0 && *f >= MAX_SEED as f64)
}

/// Whether the subcommand has an option with this id (an optional one may be absent from the
/// serialised arguments).
fn known_option(id: &str) -> bool {
    INVOCATION
        .get()
        .is_some_and(|inv| inv.command.get_arguments().any(|a| a.get_id() == id))
}

/// The error as printed: its chain joined by ": ", where the innermost message's leading
/// parameter name (`until_occupied = 2 is out of range ...`) becomes the flag as the user
/// typed it (`--until-occupied = 2 ...`) when that option was given on the command line.
pub fn render_error(e: &anyhow::Error) -> String {
    let mut parts: Vec<String> = e.chain().map(|c| c.to_string()).collect();
    // A typed error that prints its source as part of its own message: say it once.
    parts.dedup_by(|later, earlier| earlier.ends_with(later.as_str()));
    let n = parts.len();
    parts
        .into_iter()
        .enumerate()
        .map(|(i, p)| if i + 1 == n { flagged(&p) } else { p })
        .collect::<Vec<_>>()
        .join(": ")
}

fn flagged(msg: &str) -> String {
    let Some((name, rest)) = msg.split_once(" = ") else {
        return msg.to_string();
    };
    let key = name.trim_start_matches("--").replace(['-', ' '], "_");
    let synonyms = SYNONYMS.lock().map(|s| s.clone()).unwrap_or_default();
    let synonym = synonyms
        .iter()
        .find(|(from, _)| *from == key || *from == name);
    let id = synonym.map_or(key.as_str(), |(_, to)| to);
    if typed(id)
        && let Some(flag) = typed_flag(id)
    {
        return match synonym {
            Some(_) => format!("{flag} ({name}) = {rest}"),
            None => format!("{flag} = {rest}"),
        };
    }
    // a value named as its flag that the scenario file gave, not the command line: its key
    // a key the scenario file holds, not typed: its value is the file's (a message that says
    // where its value came from already is left as it is)
    let marked = rest.contains("(the default)") || rest.contains("scenario");
    if (name.starts_with("--") || synonym.is_some())
        && !typed(id)
        && !marked
        && scenario_keys().iter().any(|k| k == id)
    {
        return match synonym {
            Some(_) => format!("{id} ({name}) = {rest} (the scenario file's {id})"),
            None => format!("{id} = {rest} (the scenario file's {id})"),
        };
    }
    msg.to_string()
}

#[cfg(test)]
mod tests {

    /// A ratio just outside its band is shown with the digits that put it outside.
    #[test]
    fn values_outside_a_band_show_it() {
        use super::shown_outside;
        assert_eq!(shown_outside(0.7996, 0.8, 1.2), "0.7996");
        assert_eq!(shown_outside(1.2004, 0.8, 1.2), "1.2004");
        assert_eq!(shown_outside(0.5, 0.8, 1.2), "0.50");
        assert_eq!(shown_outside(1.8043, 0.8, 1.2), "1.80");
        assert_eq!(shown_outside(0.79999999, 0.8, 1.2), "0.79999999");
    }

    /// `-inf`, `-infinity`, `-nan` and a minus sign before a digit or a point after an option
    /// are joined to it; after anything else, and every other word, are left as they are.
    #[test]
    fn negative_words_join_their_option() {
        let words = |v: &[&str]| v.iter().map(std::ffi::OsString::from).collect::<Vec<_>>();
        let joined = |v: &[&str]| negative_words_joined(words(v), |o| o != "--quiet");
        assert_eq!(
            joined(&["cellsurf", "grow", "--n", "-inf", "--steps", "-NaN"]),
            words(&["cellsurf", "grow", "--n=-inf", "--steps=-NaN"])
        );
        assert_eq!(
            joined(&["x", "--a", "-Infinity"]),
            words(&["x", "--a=-Infinity"])
        );
        assert_eq!(joined(&["x", "-q", "-inf"]), words(&["x", "-q=-inf"]));
        assert_eq!(joined(&["x", "--s", "-inf,5"]), words(&["x", "--s=-inf,5"]));
        // the forms the parser's own test of a negative number misses
        for v in ["-5e-1", "-.5", "-1e-3", "-1,5", "-1/64", "-64x1", "-1"] {
            assert_eq!(
                joined(&["x", "-w", v]),
                words(&["x", &format!("-w={v}")]),
                "{v}"
            );
        }
        for kept in [
            &["x", "--a=1", "-inf"][..],
            &["x", "--", "-inf"],
            &["x", "-dq", "-inf"],
            &["x", "--a", "-infx"],
            &["x", "--a", "-q"],
            &["x", "--a", "-"],
            // a switch takes no value: the word is the parser's
            &["x", "--quiet", "-5"],
            &["x", "--a", "5,-inf"],
        ] {
            assert_eq!(joined(kept), words(kept), "{kept:?}");
        }
    }

    use super::*;

    #[test]
    fn counts_accept_scientific_notation() {
        assert_eq!(parse_usize("1e7"), Ok(10_000_000));
        assert_eq!(parse_usize("2.5e6"), Ok(2_500_000));
        assert_eq!(parse_usize("42"), Ok(42));
        assert!(parse_usize("-1").is_err());
        assert!(parse_usize("1.5").is_err());
        assert!(parse_usize("1e30").is_err());
        // past what a scenario file holds: refused with that limit
        for s in ["9223372036854775808", "1e19", "1e30"] {
            let e = parse_usize(s).unwrap_err();
            assert!(
                e.contains(s) && e.contains("at most 9223372036854775807 (2^63 - 1"),
                "{e}"
            );
        }
        assert_eq!(parse_usize("9223372036854775807"), Ok(MAX_SEED as usize));
        assert_eq!(parse_whole("1e19"), Ok(10_000_000_000_000_000_000));
        assert_eq!(parse_u16("65535"), Ok(u16::MAX));
        assert!(parse_u16("65536").unwrap_err().contains("at most 65535"));
        assert!(parse_u16("-1").unwrap_err().contains("expected 0 to 65535"));
    }

    #[test]
    fn a_count_too_large_to_hold_is_refused_with_the_options_range() {
        const R: CountRange = CountRange::new(1, 2000, "1 to 2000");
        let frames = count_in::<usize>(R);
        let small = count_in::<u32>(CountRange::new(0, 12, "0 to 12"));
        // past the type, or past what a scenario file holds: the option's range
        for s in [
            "1e19",
            "1e30",
            "inf",
            "18446744073709551616",
            "9223372036854775808",
        ] {
            assert_eq!(
                frames(s),
                Err(format!("'{s}' is out of range: expected 1 to 2000")),
                "{s}"
            );
        }
        assert_eq!(
            small("4294967296"),
            Err("'4294967296' is out of range: expected 0 to 12".to_string())
        );
        // a value the type holds is left to the option's check, which states the same range
        assert_eq!(frames("2001"), Ok(2001));
        assert_eq!(frames("0"), Ok(0));
        assert_eq!(small("4294967295"), Ok(u32::MAX));
        assert_eq!(frames("1e3"), Ok(1000));
        // not a whole number: said as such, not as out of range
        for s in ["-1", "1.5", "nan", "", "two"] {
            let e = frames(s).unwrap_err();
            assert!(e.contains("not a whole non-negative number"), "{s}: {e}");
        }
    }

    #[test]
    fn a_size_side_of_zero_or_too_large_to_hold_is_refused_with_the_models_sides() {
        let sides = "sides of 3 to 65536 bins";
        let size = size_in(sides);
        for s in ["0", "0x4", "4x0", "1e30", "4xinf", "18446744073709551616x4"] {
            assert_eq!(
                size(s),
                Err(format!("'{s}' is out of range: expected {sides}")),
                "{s}"
            );
        }
        // sides the model's check refuses are left to it
        assert_eq!(size("2x1e5"), Ok(Size { w: 2, h: 100_000 }));
        let e = size("nan").unwrap_err();
        assert!(e.contains("not a size") && e.ends_with(sides), "{e}");
        // without a model's sides, a zero side is said as such
        assert!(parse_size("0x4").unwrap_err().contains("zero side"));
    }

    #[test]
    fn parse_size_square_and_rectangle() {
        assert_eq!(parse_size("128"), Ok((128, 128)));
        assert_eq!(parse_size("200x230"), Ok((200, 230)));
        assert!(parse_size("0x4").unwrap_err().contains("zero side"));
        assert!(parse_size("ax4").is_err());
        // sides in the counts' notation, as every count option takes them
        assert_eq!(parse_size("1e2"), Ok((100, 100)));
        assert_eq!(parse_size("64x1e2"), Ok((64, 100)));
        assert!(parse_size("1.5e0").unwrap_err().contains("not a size"));
        assert!(parse_size("-3").is_err());
    }

    #[test]
    fn a_seed_past_u64_is_out_of_the_seeds_range() {
        for s in ["18446744073709551616", "1e20", "9223372036854775808"] {
            let e = parse_seed(s).unwrap_err();
            assert!(e.contains("2^63 - 1") && e.contains(s), "{e}");
        }
        assert!(parse_seed("abc").unwrap_err().contains("not a whole"));
        assert_eq!(parse_seed("1e3"), Ok(1000));
    }

    #[test]
    fn format_from_extension() {
        assert_eq!(Format::of(Path::new("a/b.PNG")), Some(Format::Png));
        assert_eq!(Format::of(Path::new("s.zarr")), Some(Format::Zarr));
        assert_eq!(Format::of(Path::new("noext")), None);
        let o = Outputs::new(
            &[PathBuf::from("x.png"), PathBuf::from("y.gif")],
            "dunes",
            &[Format::Png, Format::Gif],
        )
        .unwrap();
        assert_eq!(o.get(Format::Gif), Some(Path::new("y.gif")));
        let e = Outputs::new(&[PathBuf::from("x.nc")], "dunes", &[Format::Png]).unwrap_err();
        assert!(e.to_string().contains("--out x.nc"), "{e}");
        let e = Outputs::new(
            &[PathBuf::from("x.png"), PathBuf::from("y.png")],
            "dunes",
            &[Format::Png],
        )
        .unwrap_err();
        assert!(e.to_string().contains("one .png output"), "{e}");
    }

    #[test]
    fn durations_with_units() {
        assert_eq!(parse_duration("90s"), Ok(90.0));
        assert_eq!(parse_duration("30min"), Ok(1800.0));
        assert_eq!(parse_duration("2h"), Ok(7200.0));
        assert_eq!(parse_duration("1.5e4"), Ok(15000.0));
        assert_eq!(parse_duration("1d"), Ok(86400.0));
        for bad in ["0", "-5s", "nan", "1e400", "2 weeks", "", "h"] {
            assert!(parse_duration(bad).is_err(), "{bad}");
        }
    }
}
