//! The validation numbers that README.md and docs/ripple.md quote are those of the committed
//! study table, `figures/data/ripple_validation.csv` (written by `cellsurf converge
//! ripple_validation`, drawn into `ripple_validation.png` by `cellsurf figures`), and the
//! predicted values beside them are the predictors' (`cellsurf::ripple::predictors`); the
//! wavelengths that docs/ripple.md quotes from the error study against the bin are those of
//! `figures/data/ripple_error_vs_time.csv`, and the ray tracer's error table in
//! docs/raytrace.md is `figures/data/raytrace_error_vs_time.csv`, and the dunes' means and
//! standard errors in docs/dunes.md are `figures/data/dunes_error_vs_time.csv`'s, and the wind
//! ripples' in docs/windripples.md `figures/data/windripples_error_vs_time.csv`'s. The lit
//! shares that docs/raytrace.md quotes from Fig. 5's panel titles are recomputed as the figure
//! computes them.
//!
//! A rerun of the study that moves a mean, a standard error or a percentage derived from them
//! fails here, naming the file, the row and both numbers, until the docs follow. A written
//! number matches when it is the table's value rounded to the digits it is written with.

use std::collections::HashMap;
use std::path::Path;

use cellsurf::raytrace::figures::fig5_runs;
use cellsurf::raytrace::{Tracer, insonify};
use cellsurf::ripple::predictors::{soulsby_whitehouse, wiberg_harris};

/// The grain sizes of the current cases, mm (the x of the current charts).
const D50_MM: [f64; 3] = [0.1, 0.2, 0.4];
/// The orbital diameters of the wave cases, m (x of the wave charts in cm).
const D0_M: [f64; 3] = [0.2, 0.3, 0.4];
/// The wave cases' grain size, m.
const WAVE_D50_M: f64 = 0.3e-3;
/// A case may be written as having no ripples ("none", "no ripples yet") only where the study's
/// mean height is below this, cm: the initial roughness (0.16 cm), not a ripple.
const NO_RIPPLES_BELOW_CM: f64 = 0.25;

/// The study's points: `(chart, series)` to the `(x, y)` of its rows, in order.
struct Study(HashMap<(usize, usize), Vec<(f64, f64)>>);

impl Study {
    /// `figures/data/NAME.csv`.
    fn load(name: &str) -> Self {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("figures/data/{name}.csv"));
        let text = std::fs::read_to_string(&path).expect("the committed study table");
        let mut points: HashMap<(usize, usize), Vec<(f64, f64)>> = HashMap::new();
        for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
            let f: Vec<&str> = line.split(',').collect();
            assert_eq!(f.len(), 4, "a row of chart,series,x,y: {line}");
            let (x, y): (f64, f64) = (f[2].parse().unwrap(), f[3].parse().unwrap());
            if x.is_nan() {
                continue;
            }
            points
                .entry((f[0].parse().unwrap(), f[1].parse().unwrap()))
                .or_default()
                .push((x, y));
        }
        Study(points)
    }

    fn at(&self, chart: usize, series: usize, x: f64) -> Vec<f64> {
        let ys: Vec<f64> = self
            .0
            .get(&(chart, series))
            .unwrap_or_else(|| panic!("chart {chart} has no series {series}"))
            .iter()
            .filter(|p| (p.0 - x).abs() < 1e-9)
            .map(|p| p.1)
            .collect();
        assert!(
            !ys.is_empty(),
            "chart {chart}, series {series}: no point at x = {x}"
        );
        ys
    }

    /// A mean series' value at `x`.
    fn mean(&self, chart: usize, series: usize, x: f64) -> f64 {
        self.at(chart, series, x)[0]
    }

    /// The standard error of the mean series `series`: half its bar, drawn as the next series.
    fn se(&self, chart: usize, series: usize, x: f64) -> f64 {
        let bar = self.at(chart, series + 1, x);
        assert_eq!(
            bar.len(),
            2,
            "chart {chart}: the bar of series {series} at x = {x}"
        );
        (bar[1] - bar[0]).abs() / 2.0
    }
}

/// Whether `written` ("17.7", "+23", "151") is `value` rounded to the digits it is written with
/// (either neighbour at an exact tie).
/// ("8.5e-9": the digits of the mantissa at the exponent's scale).
fn rounds_to(written: &str, value: f64) -> bool {
    let Ok(w) = written.trim_start_matches('+').parse::<f64>() else {
        return false;
    };
    let (mantissa, exponent) = match written.split_once('e') {
        Some((m, e)) => (m, e.parse::<i32>().unwrap_or(0)),
        None => (written, 0),
    };
    let digits = mantissa.split('.').nth(1).map_or(0, str::len) as i32;
    let half = 0.5 * 10f64.powi(exponent - digits);
    (w - value).abs() <= half * (1.0 + 1e-9)
}

/// The checks of one file: each failure says where and what.
struct Checks<'a> {
    file: &'a str,
    text: String,
    /// The text as one line of single spaces: a sentence may wrap anywhere.
    flat: String,
    failures: Vec<String>,
}

impl<'a> Checks<'a> {
    fn of(file: &'a str) -> Self {
        let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(file))
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        let flat = text.split_whitespace().collect::<Vec<_>>().join(" ");
        Checks {
            file,
            text,
            flat,
            failures: Vec::new(),
        }
    }

    /// The cells of the table row that starts with `start` (`| case |`), trimmed.
    fn row(&mut self, start: &str) -> Option<Vec<String>> {
        let found = self.text.lines().find(|l| l.starts_with(start)).map(|l| {
            l.trim()
                .trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect()
        });
        if found.is_none() {
            self.failures
                .push(format!("{}: no table row starts with {start:?}", self.file));
        }
        found
    }

    fn expect(&mut self, what: &str, written: &str, value: f64) {
        if !rounds_to(written, value) {
            let source = if value.abs() >= 0.01 {
                format!("{value:.4}")
            } else {
                format!("{value:.3e}")
            };
            self.failures.push(format!(
                "{}: {what}: written {written}, its source gives {source}",
                self.file
            ));
        }
    }

    /// A case written as having no ripples: the study's mean height `height_cm` must be below
    /// [`NO_RIPPLES_BELOW_CM`].
    fn expect_no_ripples(&mut self, what: &str, height_cm: f64) {
        if height_cm >= NO_RIPPLES_BELOW_CM {
            self.failures.push(format!(
                "{}: {what}: written as no ripples, but the study's height is {height_cm:.2} cm",
                self.file
            ));
        }
    }

    /// A cell "MEAN +- SE ..." against the study's mean and standard error.
    fn expect_mean_se(&mut self, what: &str, cell: &str, mean: f64, se: f64) {
        let t: Vec<&str> = cell.split_whitespace().collect();
        self.expect(&format!("{what} (mean)"), t[0], mean);
        if t.get(1) == Some(&"+-") {
            self.expect(&format!("{what} (standard error)"), t[2], se);
        } else {
            self.failures.push(format!(
                "{}: {what}: {cell:?} has no standard error",
                self.file
            ));
        }
    }

    /// The `n` numbers of "+A / +B / +C %" (or "A / B / C cm", up to `unit`) written right
    /// after `lead`.
    fn after(&mut self, lead: &str, unit: &str, n: usize) -> Vec<String> {
        let flat = &self.flat;
        let Some(i) = flat.find(lead) else {
            self.failures
                .push(format!("{}: no sentence with {lead:?}", self.file));
            return Vec::new();
        };
        let rest = &flat[i + lead.len()..];
        let end = rest.find(unit).unwrap_or(rest.len());
        let numbers: Vec<String> = rest[..end]
            .split('/')
            .map(|s| s.split_whitespace().collect::<String>())
            .collect();
        if numbers.len() != n {
            self.failures.push(format!(
                "{}: after {lead:?}: {} numbers, not {n}",
                self.file,
                numbers.len()
            ));
        }
        numbers
    }

    /// The first `n` words of the prose right after `lead`.
    fn words_after(&mut self, lead: &str, n: usize) -> Vec<String> {
        match self.flat.find(lead) {
            Some(i) => self.flat[i + lead.len()..]
                .split_whitespace()
                .take(n)
                .map(|w| w.trim_end_matches([',', ';', ')']).to_string())
                .collect(),
            None => {
                self.failures
                    .push(format!("{}: no sentence with {lead:?}", self.file));
                vec![String::new(); n]
            }
        }
    }

    fn finish(self) -> Vec<String> {
        self.failures
    }
}

/// Cells written "A / B / C unit" split into their parts, the unit dropped.
fn parts(cell: &str) -> Vec<String> {
    cell.trim_end_matches(" cm")
        .split(" / ")
        .map(|s| s.trim().to_string())
        .collect()
}

fn pct(ratio: f64) -> f64 {
    (ratio - 1.0) * 100.0
}

/// docs/ripple.md, "Checks against the ripple predictors": the two tables and the percentages
/// of the paragraph after them; and the error study's wavelengths against the bin (`e`,
/// `ripple_error_vs_time`: chart 0, series 2, bins of 2.5 / 5 / 10 mm in its rows' order).
fn ripple_md(s: &Study, e: &Study) -> Vec<String> {
    let mut c = Checks::of("docs/ripple.md");
    for &d50 in &D50_MM {
        let (sw_l, sw_h) = soulsby_whitehouse(d50 * 1e-3);
        for (t, series) in [(300, 0), (1800, 2)] {
            let case = format!("current, d50 = {d50} mm, {t} s");
            let Some(r) = c.row(&format!("| current 0.5 m/s, d50 = {d50} mm, {t} s |")) else {
                continue;
            };
            if r[1].starts_with("no ripples") {
                c.expect_no_ripples(&case, s.mean(1, series, d50));
            } else {
                let (m, e) = (s.mean(0, series, d50), s.se(0, series, d50));
                c.expect_mean_se(&format!("{case}, wavelength"), &r[1], m, e);
            }
            let first = |cell: &str| cell.split_whitespace().next().unwrap_or("").to_string();
            c.expect(
                &format!("{case}, predicted wavelength"),
                &first(&r[2]),
                sw_l * 100.0,
            );
            let (m, e) = (s.mean(1, series, d50), s.se(1, series, d50));
            c.expect_mean_se(&format!("{case}, height"), &r[3], m, e);
            c.expect(
                &format!("{case}, predicted height"),
                &first(&r[4]),
                sw_h * 100.0,
            );
            if t == 1800 {
                let (m, e) = (s.mean(4, 0, d50), s.se(4, 0, d50));
                c.expect_mean_se(&format!("{case}, ripple index"), &r[5], m, e);
                let (m, e) = (s.mean(4, 2, d50), s.se(4, 2, d50));
                c.expect_mean_se(&format!("{case}, symmetry index"), &r[6], m, e);
            }
        }
    }
    for &d50 in &D50_MM {
        // the opt-in recipe for mature current ripples: series 5 of the wavelength and height
        // charts, 6 (ripple index) and 8 (symmetry index) of the current shape chart
        let case = format!("current, d50 = {d50} mm, the recipe");
        let Some(r) = c.row(&format!(
            "| current 0.5 m/s, d50 = {d50} mm, the recipe, 6000 s |"
        )) else {
            continue;
        };
        let pairs = [(0, 5, 1), (1, 5, 3), (4, 6, 5), (4, 8, 6)];
        for (what, (chart, series, cell)) in
            ["wavelength", "height", "ripple index", "symmetry index"]
                .iter()
                .zip(pairs)
        {
            let (m, e) = (s.mean(chart, series, d50), s.se(chart, series, d50));
            c.expect_mean_se(&format!("{case}, {what}"), &r[cell], m, e);
        }
    }
    for &d0 in &D0_M {
        let x = d0 * 100.0;
        let (wh_l, wh_h, _) = wiberg_harris(d0, WAVE_D50_M);
        for (t, series) in [("16,000", 0), ("32,000", 2)] {
            let case = format!("waves, d0 = {d0} m, {t} s");
            let Some(r) = c.row(&format!("| waves, d50 = 0.3 mm, d0 = {d0} m, {t} s |")) else {
                continue;
            };
            let (m, e) = (s.mean(2, series, x), s.se(2, series, x));
            c.expect_mean_se(&format!("{case}, wavelength"), &r[1], m, e);
            let first = |cell: &str| cell.split_whitespace().next().unwrap_or("").to_string();
            c.expect(
                &format!("{case}, predicted wavelength"),
                &first(&r[2]),
                wh_l * 100.0,
            );
            c.expect(
                &format!("{case}, predicted height"),
                &first(&r[4]),
                wh_h * 100.0,
            );
            if series == 2 {
                let ri = s.mean(5, 0, x);
                c.expect(&format!("{case}, height"), &r[3], s.mean(2, 2, x) / ri);
                c.expect_mean_se(&format!("{case}, ripple index"), &r[5], ri, s.se(5, 0, x));
                let (m, e) = (s.mean(5, 2, x), s.se(5, 2, x));
                c.expect_mean_se(&format!("{case}, symmetry index"), &r[6], m, e);
            }
        }
    }
    for (start, series) in [
        ("| crest normal, grid frame, 64 x 64 cm (deg) |", 0),
        (
            "| crest normal, flow frame (default), 96 x 24 cm (deg) |",
            2,
        ),
    ] {
        let Some(r) = c.row(start) else { continue };
        if r.len() != 14 {
            c.failures.push(format!(
                "docs/ripple.md: {start} has {} cells, not 14",
                r.len()
            ));
            continue;
        }
        for (k, cell) in r[1..].iter().enumerate() {
            let angle = 15.0 * k as f64;
            let what = format!("{} at {angle} deg", r[0]);
            c.expect(&what, cell, s.mean(3, series, angle));
        }
    }
    let waves = |series: usize| -> Vec<f64> {
        D0_M.iter()
            .map(|&d0| s.mean(2, series, d0 * 100.0))
            .collect()
    };
    let (w16, w32) = (waves(0), waves(2));
    for (k, written) in c
        .after("but slower than 0.62 d0 (", "%", 3)
        .into_iter()
        .chain(c.after("for d0 = 0.2 / 0.3 / 0.4 m after 32,000 s (", "%", 3))
        .enumerate()
    {
        let k = k % 3;
        let predicted = wiberg_harris(D0_M[k], WAVE_D50_M).0 * 100.0;
        let what = format!(
            "32,000 s wave wavelength against 0.62 d0, d0 = {} m",
            D0_M[k]
        );
        c.expect(&what, &written, pct(w32[k] / predicted));
    }
    for (k, written) in c
        .after("but slower than 0.62 d0: ", " cm", 3)
        .into_iter()
        .enumerate()
    {
        let what = format!("32,000 s wave wavelength, d0 = {} m", D0_M[k % 3]);
        c.expect(&what, &written, w32[k % 3]);
    }
    for (k, written) in c
        .after("the mean wavelength grows by ", "%", 3)
        .into_iter()
        .enumerate()
    {
        let what = format!(
            "wave wavelength's growth from 16,000 to 32,000 s, d0 = {} m",
            D0_M[k]
        );
        c.expect(&what, &written, pct(w32[k] / w16[k]));
    }
    // the prose around the tables
    let ri = |x: f64| s.mean(5, 0, x);
    let si = |x: f64| s.mean(5, 2, x);
    let weak = c.words_after("The trend with grain size is weak: ", 3);
    let sw = c.words_after("mm against the predictor's ", 3);
    for (k, &d50) in D50_MM[..2].iter().enumerate() {
        let what = format!("current, d50 = {d50} mm, 300 s");
        c.expect(
            &format!("{what}, wavelength"),
            &weak[2 * k],
            s.mean(0, 0, d50),
        );
        let predicted = soulsby_whitehouse(d50 * 1e-3).0 * 100.0;
        c.expect(
            &format!("{what}, predicted wavelength"),
            &sw[2 * k],
            predicted,
        );
    }
    let (wl, wh, _) = wiberg_harris(0.4, WAVE_D50_M);
    let three = c.words_after("meet the first three (", 5);
    c.expect(
        "waves, d0 = 0.4 m, wavelength against 0.62 d0 (%)",
        &three[0],
        pct(w32[2] / (wl * 100.0)),
    );
    let height = w32[2] / ri(40.0);
    c.expect(
        "waves, d0 = 0.4 m, height against W&H (%)",
        &three[2],
        pct(height / (wh * 100.0)),
    );
    c.expect("waves, d0 = 0.4 m, ripple index", &three[4], ri(40.0));
    let range = |c: &mut Checks, what: &str, written: &str, values: &[f64]| {
        let w: Vec<&str> = written.trim_end_matches(',').split('-').collect();
        let lo = values.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = values.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        c.expect(&format!("{what}, lowest"), w[0], lo);
        c.expect(&format!("{what}, highest"), w.get(1).unwrap_or(&""), hi);
    };
    let xs: Vec<f64> = D0_M.iter().map(|d0| d0 * 100.0).collect();
    let sym = c.words_after("observed symmetry (", 1);
    range(
        &mut c,
        "waves, symmetry index",
        &sym[0],
        &xs.iter().map(|&x| si(x)).collect::<Vec<_>>(),
    );
    let steep = c.words_after("steepness (ripple index ", 2);
    range(
        &mut c,
        "waves, ripple index",
        &steep[0],
        &xs.iter().map(|&x| ri(x)).collect::<Vec<_>>(),
    );
    let predicted_ri = 100.0 * wl / (wh * 100.0);
    c.expect("waves, W&H ripple index", &steep[1], predicted_ri);
    let grows = c.words_after("hours of waves (by ", 1);
    let growth: Vec<f64> = (0..3).map(|k| pct(w32[k] / w16[k])).collect();
    range(
        &mut c,
        "waves, growth from 16,000 to 32,000 s (%)",
        &grows[0],
        &growth,
    );
    let study = c.words_after("the period exactly `pi d0 / U_w`): ", 11);
    for (k, &x) in xs.iter().enumerate() {
        let what = format!("waves, d0 = {} m, 32,000 s, the study's", D0_M[k]);
        c.expect(&format!("{what} wavelength"), &study[4 * k], w32[k]);
        c.expect(
            &format!("{what} standard error"),
            &study[4 * k + 2],
            s.se(2, 2, x),
        );
    }
    let bins: Vec<f64> = e.0[&(0, 2)].iter().map(|p| p.1).collect();
    for (k, written) in c
        .after("6 seeds) bins of 2.5 / 5 / 10 mm give ", " cm", 3)
        .into_iter()
        .enumerate()
    {
        let what = format!(
            "error study, wavelength in bins of {} mm",
            [2.5, 5.0, 10.0][k % 3]
        );
        c.expect(&what, &written, bins.get(k).copied().unwrap_or(f64::NAN));
    }
    c.finish()
}

/// README.md, "Sand ripples against the predictors": the rows the study measures (the
/// 128,000 s row is from longer runs, and the ripple and symmetry indices at 300 s are not in
/// the study's table).
fn readme(s: &Study) -> Vec<String> {
    let mut c = Checks::of("README.md");
    for &d50 in &D50_MM {
        let case = format!("current, d50 {d50} mm");
        let Some(r) = c.row(&format!(
            "| the paper's rules{}, current 0.5 m/s, d50 {d50} mm, after 300 s / 1800 s |",
            if d50 == D50_MM[0] {
                " (`--recipe paper`)"
            } else {
                ""
            }
        )) else {
            continue;
        };
        let (sw_l, sw_h) = soulsby_whitehouse(d50 * 1e-3);
        for (k, (col, chart)) in [(1, 0), (3, 1)].into_iter().enumerate() {
            let name = ["wavelength", "height"][k];
            let p = parts(&r[col]);
            if p.len() != 2 {
                c.failures.push(format!(
                    "README.md: {case}, {name}: {:?} is not 'A / B'",
                    r[col]
                ));
                continue;
            }
            for (i, series) in [0, 2].into_iter().enumerate() {
                let what = format!("{case}, {name} at {} s", [300, 1800][i]);
                if p[i] == "none" {
                    c.expect_no_ripples(&what, s.mean(1, series, d50));
                } else {
                    c.expect(&what, &p[i], s.mean(chart, series, d50));
                }
            }
        }
        c.expect(
            &format!("{case}, predicted wavelength"),
            &parts(&r[2])[0],
            sw_l * 100.0,
        );
        c.expect(
            &format!("{case}, predicted height"),
            &parts(&r[4])[0],
            sw_h * 100.0,
        );
        for (col, series, name) in [(5, 0, "ripple index"), (6, 2, "symmetry index")] {
            match parts(&r[col]).get(1) {
                Some(w) => c.expect(
                    &format!("{case}, {name} at 1800 s"),
                    w,
                    s.mean(4, series, d50),
                ),
                None => c
                    .failures
                    .push(format!("README.md: {case}: no 1800 s {name}")),
            }
        }
    }
    for &d50 in &D50_MM {
        // the recipe for mature current ripples (the default's rules under a current) after
        // 6000 s: the study's series 5 (wavelength, height), 6 and 8 (ripple and symmetry
        // index)
        let case = format!("current, d50 {d50} mm, the default");
        let Some(r) = c.row(&format!(
            "| current 0.5 m/s, d50 {d50} mm, the recipe (the default's rules), after 6000 s |"
        )) else {
            continue;
        };
        for (what, chart, series, cell) in [
            ("wavelength", 0, 5, 1),
            ("height", 1, 5, 3),
            ("ripple index", 4, 6, 5),
            ("symmetry index", 4, 8, 6),
        ] {
            c.expect(
                &format!("{case}, {what}"),
                r[cell].split_whitespace().next().unwrap_or(""),
                s.mean(chart, series, d50),
            );
        }
    }
    let start = "| waves, d50 0.3 mm, d0 0.2 / 0.3 / 0.4 m, after 32,000 s (8.9 h) |";
    if let Some(r) = c.row(start) {
        let (wl, pred, h, pred_h) = (parts(&r[1]), parts(&r[2]), parts(&r[3]), parts(&r[4]));
        let mut ri = Vec::new();
        let mut si = Vec::new();
        for (k, &d0) in D0_M.iter().enumerate() {
            let x = d0 * 100.0;
            let (wh_l, wh_h, _) = wiberg_harris(d0, WAVE_D50_M);
            let case = format!("waves, d0 = {d0} m");
            c.expect(&format!("{case}, wavelength"), &wl[k], s.mean(2, 2, x));
            c.expect(
                &format!("{case}, predicted wavelength"),
                &pred[k],
                wh_l * 100.0,
            );
            let height = s.mean(2, 2, x) / s.mean(5, 0, x);
            c.expect(&format!("{case}, height"), &h[k], height);
            c.expect(
                &format!("{case}, predicted height"),
                &pred_h[k],
                wh_h * 100.0,
            );
            ri.push(s.mean(5, 0, x));
            si.push(s.mean(5, 2, x));
        }
        for (col, values, name) in [(5, ri, "ripple index"), (6, si, "symmetry index")] {
            let range: Vec<&str> = r[col].split('-').collect();
            let lo = values.iter().cloned().fold(f64::INFINITY, f64::min);
            let hi = values.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            c.expect(&format!("waves, lowest {name}"), range[0], lo);
            c.expect(
                &format!("waves, highest {name}"),
                range.get(1).unwrap_or(&""),
                hi,
            );
        }
    }
    c.finish()
}

/// docs/raytrace.md, "Error against step size and run time": its table is the study's
/// (`raytrace_error_vs_time`: chart 0 the three errors against ds, chart 1 the same errors
/// against the CPU seconds per ray), one row per step size of the study, with the linear ray's
/// steps over its 30 km.
fn raytrace_md(t: &Study) -> Vec<String> {
    let mut c = Checks::of("docs/raytrace.md");
    let header = "| ds (m) | steps | arc radius error |";
    let lines: Vec<String> = c
        .text
        .lines()
        .skip_while(|l| !l.starts_with(header))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(str::to_string)
        .collect();
    let studied = &t.0[&(0, 0)];
    if lines.len() != studied.len() {
        c.failures.push(format!(
            "docs/raytrace.md: the error table has {} rows, the study {} step sizes",
            lines.len(),
            studied.len()
        ));
    }
    for line in lines {
        let r: Vec<&str> = line
            .trim()
            .trim_matches('|')
            .split('|')
            .map(str::trim)
            .collect();
        let Some(ds) = r[0]
            .parse::<f64>()
            .ok()
            .filter(|ds| studied.iter().any(|p| p.0 == *ds))
        else {
            c.failures.push(format!(
                "docs/raytrace.md: {line:?}: not a step size of the study"
            ));
            continue;
        };
        let case = format!("ds {ds} m");
        c.expect(&format!("{case}, steps"), r[1], (30_000.0 / ds).ceil());
        for (col, series, name) in [
            (2, 0, "arc radius error"),
            (3, 1, "Snell drift, linear"),
            (4, 2, "Snell drift, Munk"),
        ] {
            c.expect(&format!("{case}, {name}"), r[col], t.mean(0, series, ds));
        }
        // the CPU time is the x of chart 1's point with this step size's error
        let error = t.mean(0, 0, ds);
        let cpu = t.0[&(1, 0)]
            .iter()
            .find(|p| p.1 == error)
            .map_or(f64::NAN, |p| p.0);
        c.expect(&format!("{case}, CPU us/ray"), r[5], cpu * 1e6);
    }
    c.finish()
}

/// docs/dunes.md, "Error against run time": the means after 12 seeds at 500 iterations
/// (`dunes_error_vs_time`: charts 2 and 3, the bare fraction and the bodies against iterations,
/// Q = 1 and Q = 3) and their standard errors (charts 0 and 1 at the longest run time).
fn dunes_md(t: &Study) -> Vec<String> {
    let mut c = Checks::of("docs/dunes.md");
    let last = |chart: usize, series: usize| t.0[&(chart, series)].last().map_or(f64::NAN, |p| p.1);
    let bare = c.words_after("After 12 seeds the bare fraction is ", 10);
    let bodies = c.words_after("and the number of bodies ", 7);
    for (what, written, value) in [
        ("bare fraction, Q = 1", &bare[0], last(2, 0)),
        (
            "bare fraction's standard error, Q = 1",
            &bare[2],
            last(0, 0),
        ),
        ("bare fraction, Q = 3", &bare[7], last(2, 1)),
        (
            "bare fraction's standard error, Q = 3",
            &bare[9],
            last(0, 2),
        ),
        ("bodies, Q = 1", &bodies[0], last(3, 0)),
        ("bodies' standard error, Q = 1", &bodies[2], last(1, 0)),
        ("bodies, Q = 3", &bodies[4], last(3, 1)),
        ("bodies' standard error, Q = 3", &bodies[6], last(1, 2)),
    ] {
        c.expect(what, written, value);
    }
    c.finish()
}

/// docs/windripples.md, the error figure's row: the standard errors of the two wavelengths
/// after 8 seeds (`windripples_error_vs_time`: chart 1, series 0 the dominant peak, 1 the
/// spectrum-weighted mean, at the longest run time).
fn windripples_md(t: &Study) -> Vec<String> {
    let mut c = Checks::of("docs/windripples.md");
    let last = |series: usize| t.0[&(1, series)].last().map_or(f64::NAN, |p| p.1);
    let mean = c.words_after("pinned about 10 times more tightly (", 1);
    let peak = c.words_after("bins after 8 seeds) than the dominant peak (", 1);
    c.expect("the mean wavelength's standard error", &mean[0], last(1));
    c.expect(
        "the dominant wavelength's standard error",
        &peak[0],
        last(0),
    );
    c.finish()
}

/// docs/raytrace.md, "Fig. 5": the lit shares that the figure prints in its panel titles (the
/// floor beyond 5 m, and the tile at 40-40.64 m), computed as the figure computes them from its
/// scenarios ([`fig5_runs`]): isovelocity, the thermocline, the table with the inversion.
fn raytrace_fig5_md() -> Vec<String> {
    let mut c = Checks::of("docs/raytrace.md");
    let runs = fig5_runs().expect("the Fig. 5 scenarios");
    let floor = runs[0].floor().expect("the Fig. 5 floor");
    let xs = floor.xs();
    let beyond = xs.partition_point(|&x| x < 5.0)..xs.partition_point(|&x| x <= floor.x_range().1);
    let tile = xs.partition_point(|&x| x < 40.0)..xs.partition_point(|&x| x <= 40.64);
    let shares: Vec<(f64, f64)> = runs
        .iter()
        .map(|r| {
            let t = Tracer::new(&r.profile, &floor).expect("a tracer");
            let ins = insonify(&t, &r.fan(), &r.options(&floor)).expect("the fan");
            (
                100.0 * ins.lit_fraction(beyond.clone()),
                100.0 * ins.lit_fraction(tile.clone()),
            )
        })
        .collect();
    assert_eq!(shares.len(), 3, "Fig. 5 has three rows");
    let iso = c.words_after("Isovelocity insonifies ", 1);
    let iso_tile = c.words_after("far out only the stoss faces (", 1);
    let thermo = c.words_after("nothing beyond 35 m is reached (", 3);
    let inversion = c.words_after("m in shadow (", 3);
    let none = |w: &str| {
        if w == "none" {
            "0".to_string()
        } else {
            w.to_string()
        }
    };
    for (what, written, value) in [
        (
            "isovelocity, the floor beyond 5 m",
            iso[0].clone(),
            shares[0].0,
        ),
        (
            "isovelocity, the tile at 40 m",
            iso_tile[0].clone(),
            shares[0].1,
        ),
        (
            "thermocline, the floor beyond 5 m",
            thermo[0].clone(),
            shares[1].0,
        ),
        (
            "thermocline, the tile at 40 m",
            none(&thermo[2]),
            shares[1].1,
        ),
        (
            "inversion, the floor beyond 5 m",
            inversion[0].clone(),
            shares[2].0,
        ),
        (
            "inversion, the tile at 40 m",
            none(&inversion[2]),
            shares[2].1,
        ),
    ] {
        c.expect(&format!("Fig. 5, {what} (%)"), &written, value);
    }
    c.finish()
}

#[test]
fn numbers_the_docs_quote_are_their_sources() {
    let s = Study::load("ripple_validation");
    let e = Study::load("ripple_error_vs_time");
    let r = Study::load("raytrace_error_vs_time");
    let d = Study::load("dunes_error_vs_time");
    let w = Study::load("windripples_error_vs_time");
    let failures: Vec<String> = ripple_md(&s, &e)
        .into_iter()
        .chain(readme(&s))
        .chain(raytrace_md(&r))
        .chain(dunes_md(&d))
        .chain(windripples_md(&w))
        .chain(raytrace_fig5_md())
        .collect();
    assert!(
        failures.is_empty(),
        "{} documented number(s) differ from their source, a study table in figures/data/ \
         (rerun by `cellsurf converge STUDY`), a predictor or Fig. 5; update the docs:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn a_written_number_matches_only_its_rounding() {
    assert!(rounds_to("17.7", 17.688));
    assert!(rounds_to("+23", 23.06));
    assert!(rounds_to("151", 151.276));
    assert!(rounds_to("0.00", 0.0049));
    assert!(!rounds_to("17.7", 17.64));
    assert!(!rounds_to("0.97", 0.9649));
    assert!(!rounds_to("18", 18.6));
    assert!(!rounds_to("none", 1.0));
    assert!(rounds_to("8.5e-9", 8.49e-9));
    assert!(!rounds_to("8.5e-9", 8.44e-9));
    assert!(rounds_to("9.0e-10", 9.002e-10));
    assert_eq!(parts("17.7 / 39.1 cm"), ["17.7", "39.1"]);
}
