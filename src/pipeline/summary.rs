//! Summaries of a result table, generic over encoders (every encoder name comes from the
//! experiment file): statistics per orientation, per map and per orientation set (mean and
//! worst), with ratios to a baseline encoder; and declared claims checked on the rows.
//!
//! | key (experiment file)  | type   | meaning |
//! |------------------------|--------|---------|
//! | `[summary] baseline`   | string | optional encoder name; ratios are rmse / its rmse on the same map, domain, effects and metric |
//! | `[[claims]] id`        | string | claim id (e.g. `H8.hlsh`) |
//! | `claim`, `paper`       | string | the claim and the paper's figure for it, as text |
//! | `check`                | string | `ratio` (encoder / baseline on matched rows), `equal` (two encoders agree), `at_most` / `at_least` (the encoder's column against an absolute `bound`) |
//! | `encoder`, `baseline`  | string | the encoder names compared (`equal`: `encoder` vs `baseline`); `at_most`/`at_least` take no `baseline` |
//! | `column`               | string | `rmse` (default), `rel_rmse`, `max_abs_err`, `at_normal_abs_err` |
//! | `threshold`            | number | `ratio`: a row passes if ratio < threshold (default 1) |
//! | `statistic`            | string | `ratio`: `every` (default; holds yes/partly/no by rows) or `mean` (mean ratio < threshold) |
//! | `tolerance`            | number | `equal`: largest difference allowed relative to max(\|a\|, \|b\|, reference RMS) (default 1e-9) |
//! | `abs_tolerance`        | number | `equal`: a difference this small passes regardless (default 1e-12; for errors at rounding level) |
//! | `bound`                | number | `at_most`: a row passes if column ≤ bound; `at_least`: if column ≥ bound (required, finite, ≥ 0) |
//! | `effects`              | string | only rows with exactly this effects label |
//! | `maps`                 | [string] | only rows of these maps (each one of the experiment's `maps`, by name or file stem) |
//! | `note`                 | string | shown under the claims table |
//!
//! Output, beside `table.csv`: `summary.csv` when `[summary]` is present, `claims.csv` and
//! `CLAIMS.md` when claims are declared. Rows are visited in table order, so the files are
//! deterministic.

use crate::pipeline::table::{num, Row};
use anyhow::{bail, Result};
use serde::Deserialize;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

/// `[summary]` as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SummaryFile {
    pub baseline: Option<String>,
}

/// `[[claims]]` as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClaimFile {
    pub id: String,
    pub claim: String,
    #[serde(default)]
    pub paper: String,
    pub check: String,
    pub encoder: String,
    pub baseline: Option<String>,
    pub column: Option<String>,
    pub threshold: Option<f64>,
    pub statistic: Option<String>,
    pub tolerance: Option<f64>,
    pub abs_tolerance: Option<f64>,
    pub bound: Option<f64>,
    pub effects: Option<String>,
    pub maps: Option<Vec<String>>,
    pub note: Option<String>,
}

/// A numeric column of the table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Column {
    Rmse,
    RelRmse,
    MaxAbsErr,
    AtNormalAbsErr,
}

impl Column {
    fn parse(s: &str) -> Result<Self> {
        Ok(match s {
            "rmse" => Column::Rmse,
            "rel_rmse" => Column::RelRmse,
            "max_abs_err" => Column::MaxAbsErr,
            "at_normal_abs_err" => Column::AtNormalAbsErr,
            _ => bail!("column '{s}': expected rmse, rel_rmse, max_abs_err or at_normal_abs_err"),
        })
    }
    fn name(&self) -> &'static str {
        match self {
            Column::Rmse => "rmse",
            Column::RelRmse => "rel_rmse",
            Column::MaxAbsErr => "max_abs_err",
            Column::AtNormalAbsErr => "at_normal_abs_err",
        }
    }
    fn get(&self, r: &Row) -> Option<f64> {
        match self {
            Column::Rmse => Some(r.scores.rmse),
            Column::RelRmse => Some(r.scores.rel_rmse),
            Column::MaxAbsErr => Some(r.scores.max_abs),
            Column::AtNormalAbsErr => r.at_normal_abs_err,
        }
    }
}

/// How a claim is checked.
#[derive(Clone, Debug, PartialEq)]
pub enum Check {
    /// ratio = column(encoder) / column(baseline) per matched row; passes where < threshold.
    Ratio { threshold: f64, every: bool },
    /// column(encoder) and column(baseline) agree on every row: |a − b| ≤ tolerance ·
    /// max(|a|, |b|, RMS of the reference), or |a − b| ≤ abs_tolerance.
    Equal { tolerance: f64, abs_tolerance: f64 },
    /// column(encoder) ≤ bound on every matched row (no baseline).
    AtMost { bound: f64 },
    /// column(encoder) ≥ bound on every matched row (no baseline).
    AtLeast { bound: f64 },
}

/// A validated claim.
#[derive(Clone, Debug, PartialEq)]
pub struct Claim {
    pub id: String,
    pub claim: String,
    pub paper: String,
    pub check: Check,
    pub encoder: String,
    /// The encoder compared with (`ratio`, `equal`); empty for `at_most`/`at_least`.
    pub baseline: String,
    pub column: Column,
    pub effects: Option<String>,
    /// Only rows of these maps (table names: file stems); `None`: every map.
    pub maps: Option<Vec<String>>,
    pub note: Option<String>,
}

/// The name a map entry of an experiment gets in tables: its file stem (entries may be paths).
fn table_map_name(entry: &str) -> String {
    Path::new(entry).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| entry.to_string())
}

impl Claim {
    /// Validates a claim against the experiment's encoder names and map entries.
    pub fn from_file(f: ClaimFile, encoders: &[String], maps: &[String]) -> Result<Self> {
        let bounded = matches!(f.check.as_str(), "at_most" | "at_least");
        let baseline = match (&f.baseline, bounded) {
            (Some(_), true) => {
                bail!(
                    "claims: '{}': 'baseline' is not used by check = \"{}\" (it compares with 'bound')",
                    f.id,
                    f.check
                )
            }
            (None, true) => String::new(),
            (Some(b), false) => b.clone(),
            (None, false) => bail!("claims: '{}': check = \"{}\" needs 'baseline'", f.id, f.check),
        };
        for e in std::iter::once(&f.encoder).chain((!bounded).then_some(&baseline)) {
            if !encoders.contains(e) {
                bail!("claims: '{}' names encoder '{e}', which the experiment does not list", f.id);
            }
        }
        if !bounded && f.bound.is_some() {
            bail!("claims: '{}': 'bound' is for check = \"at_most\" or \"at_least\"", f.id);
        }
        let maps_filter = match f.maps {
            None => None,
            Some(list) => {
                if list.is_empty() {
                    bail!("claims: '{}': maps = [] matches no row; list at least one map or drop the key", f.id);
                }
                let mut names = Vec::new();
                for m in &list {
                    let name = table_map_name(m);
                    if !maps.iter().any(|e| e == m || table_map_name(e) == name) {
                        bail!("claims: '{}': maps names '{m}', which is not one of the experiment's maps", f.id);
                    }
                    if !names.contains(&name) {
                        names.push(name);
                    }
                }
                Some(names)
            }
        };
        let column = Column::parse(f.column.as_deref().unwrap_or("rmse"))?;
        let check = match f.check.as_str() {
            "at_most" | "at_least" => {
                if f.threshold.is_some() || f.statistic.is_some() || f.tolerance.is_some() || f.abs_tolerance.is_some()
                {
                    bail!(
                        "claims: '{}': check = \"{}\" takes 'bound' only ('threshold', 'statistic', 'tolerance' and \
                         'abs_tolerance' are for ratio/equal)",
                        f.id,
                        f.check
                    );
                }
                let Some(bound) = f.bound else {
                    bail!("claims: '{}': check = \"{}\" needs 'bound' (a number)", f.id, f.check)
                };
                if !(bound.is_finite() && bound >= 0.0) {
                    bail!("claims: '{}': bound must be a finite non-negative number, got {bound}", f.id);
                }
                if f.check == "at_most" {
                    Check::AtMost { bound }
                } else {
                    Check::AtLeast { bound }
                }
            }
            "ratio" => {
                if f.tolerance.is_some() || f.abs_tolerance.is_some() {
                    bail!("claims: '{}': 'tolerance'/'abs_tolerance' are for check = \"equal\"", f.id);
                }
                let threshold = f.threshold.unwrap_or(1.0);
                if !(threshold.is_finite() && threshold > 0.0) {
                    bail!("claims: '{}': threshold must be a positive number", f.id);
                }
                let every = match f.statistic.as_deref().unwrap_or("every") {
                    "every" => true,
                    "mean" => false,
                    s => bail!("claims: '{}': statistic '{s}' (expected every or mean)", f.id),
                };
                Check::Ratio { threshold, every }
            }
            "equal" => {
                if f.threshold.is_some() || f.statistic.is_some() {
                    bail!("claims: '{}': 'threshold'/'statistic' are for check = \"ratio\"", f.id);
                }
                let tolerance = f.tolerance.unwrap_or(1e-9);
                let abs_tolerance = f.abs_tolerance.unwrap_or(1e-12);
                if !(tolerance.is_finite() && tolerance >= 0.0 && abs_tolerance.is_finite() && abs_tolerance >= 0.0) {
                    bail!("claims: '{}': tolerance and abs_tolerance must be non-negative numbers", f.id);
                }
                Check::Equal { tolerance, abs_tolerance }
            }
            c => bail!("claims: '{}': check '{c}' (expected ratio, equal, at_most or at_least)", f.id),
        };
        Ok(Claim {
            id: f.id,
            claim: f.claim,
            paper: f.paper,
            check,
            encoder: f.encoder,
            baseline,
            column,
            effects: f.effects,
            maps: maps_filter,
            note: f.note,
        })
    }
}

/// Validates `[summary]`.
pub fn summary_baseline(f: SummaryFile, encoders: &[String]) -> Result<Option<String>> {
    if let Some(b) = &f.baseline {
        if !encoders.contains(b) {
            bail!("summary: baseline '{b}' is not one of the experiment's encoders");
        }
    }
    Ok(f.baseline)
}

/// The key rows are matched on across encoders.
fn key(r: &Row) -> (&str, &str, &str, &str) {
    (&r.map, &r.domain, &r.metric, &r.effects)
}

/// A pair of matched values (encoder, baseline) with the row they describe.
struct Pair<'a> {
    row: &'a Row,
    a: f64,
    b: f64,
}

impl Claim {
    /// Whether a row of the claim's encoder passes its effects and maps filters.
    fn selects(&self, r: &Row) -> bool {
        r.encoder == self.encoder
            && self.effects.as_deref().is_none_or(|e| r.effects == e)
            && self.maps.as_ref().is_none_or(|m| m.contains(&r.map))
    }
}

/// Matched (encoder, baseline) values of the claim's column on every row of its encoder (in
/// table order) that passes its filters and has a baseline row.
fn pairs<'a>(rows: &'a [Row], c: &Claim) -> Vec<Pair<'a>> {
    let base: HashMap<_, &Row> = rows.iter().filter(|r| r.encoder == c.baseline).map(|r| (key(r), r)).collect();
    rows.iter()
        .filter(|r| c.selects(r))
        .filter_map(|r| {
            let b = base.get(&key(r))?;
            Some(Pair { row: r, a: c.column.get(r)?, b: c.column.get(b)? })
        })
        .collect()
}

/// A ratio that never prints as NaN/Inf: 0/0 is 1 (a tie), x/0 is reported as `None`.
fn ratio(a: f64, b: f64) -> Option<f64> {
    if b > 0.0 {
        Some(a / b)
    } else if a == 0.0 {
        Some(1.0)
    } else {
        None
    }
}

/// The median (mean of the two middle values for an even count).
fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(|a, b| a.total_cmp(b));
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

/// Mean and worst (largest) of values, with the index of the worst.
fn stats(v: &[f64]) -> (f64, f64, usize) {
    let mut worst = (f64::NEG_INFINITY, 0);
    for (i, &x) in v.iter().enumerate() {
        if x > worst.0 {
            worst = (x, i);
        }
    }
    (v.iter().sum::<f64>() / v.len() as f64, worst.0, worst.1)
}

/// Distinct values in first-appearance order.
fn distinct<'a>(it: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
    let mut out: Vec<&str> = Vec::new();
    for s in it {
        if !out.contains(&s) {
            out.push(s);
        }
    }
    out
}

/// One line of `summary.csv`: the rows of one encoder, effects, metric and orientation set,
/// restricted to one orientation (`domain`), one map, or neither ("*").
struct Group<'a> {
    encoder: &'a str,
    effects: &'a str,
    metric: &'a str,
    set: &'a str,
    domain: &'a str,
    map: &'a str,
    rows: Vec<&'a Row>,
}

fn groups(rows: &[Row]) -> Vec<Group<'_>> {
    let mut out = Vec::new();
    for enc in distinct(rows.iter().map(|r| r.encoder.as_str())) {
        let er: Vec<&Row> = rows.iter().filter(|r| r.encoder == enc).collect();
        for eff in distinct(er.iter().map(|r| r.effects.as_str())) {
            for metric in distinct(er.iter().map(|r| r.metric.as_str())) {
                for set in distinct(er.iter().map(|r| r.orientation_set.as_str())) {
                    let sr: Vec<&Row> = er
                        .iter()
                        .copied()
                        .filter(|r| r.effects == eff && r.metric == metric && r.orientation_set == set)
                        .collect();
                    if sr.is_empty() {
                        continue;
                    }
                    let mk = |domain, map, rows| Group { encoder: enc, effects: eff, metric, set, domain, map, rows };
                    for d in distinct(sr.iter().map(|r| r.domain.as_str())) {
                        out.push(mk(d, "*", sr.iter().copied().filter(|r| r.domain == d).collect()));
                    }
                    for m in distinct(sr.iter().map(|r| r.map.as_str())) {
                        out.push(mk("*", m, sr.iter().copied().filter(|r| r.map == m).collect()));
                    }
                    out.push(mk("*", "*", sr));
                }
            }
        }
    }
    out
}

/// `summary.csv`: per orientation, per map and per orientation set.
pub fn summary_csv(rows: &[Row], baseline: Option<&str>) -> Result<Vec<u8>> {
    let base: HashMap<_, &Row> =
        rows.iter().filter(|r| Some(r.encoder.as_str()) == baseline).map(|r| (key(r), r)).collect();
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "encoder",
        "effects",
        "metric",
        "orientation_set",
        "domain",
        "map",
        "n",
        "mean_rmse",
        "worst_rmse",
        "mean_rel_rmse",
        "worst_rel_rmse",
        "worst_rmse_at",
        "baseline",
        "n_ratio",
        "mean_ratio",
        "median_ratio",
        "worst_ratio",
        "frac_ratio_below_1",
        "worst_ratio_at",
    ])?;
    let at = |r: &Row| format!("{} {}", r.map, r.domain);
    for g in groups(rows) {
        let rmse: Vec<f64> = g.rows.iter().map(|r| r.scores.rmse).collect();
        let rel: Vec<f64> = g.rows.iter().map(|r| r.scores.rel_rmse).collect();
        let (mr, wr, wi) = stats(&rmse);
        let (mrel, wrel, _) = stats(&rel);
        let mut rec = vec![
            g.encoder.to_string(),
            g.effects.to_string(),
            g.metric.to_string(),
            g.set.to_string(),
            g.domain.to_string(),
            g.map.to_string(),
            g.rows.len().to_string(),
            num(mr),
            num(wr),
            num(mrel),
            num(wrel),
            at(g.rows[wi]),
        ];
        let ratios: Vec<(f64, &Row)> = g
            .rows
            .iter()
            .filter_map(|r| base.get(&key(r)).and_then(|b| ratio(r.scores.rmse, b.scores.rmse)).map(|x| (x, *r)))
            .collect();
        if let (Some(b), false) = (baseline, ratios.is_empty()) {
            let v: Vec<f64> = ratios.iter().map(|p| p.0).collect();
            let (m, wv, wi) = stats(&v);
            let below = v.iter().filter(|&&x| x < 1.0).count() as f64 / v.len() as f64;
            rec.extend([
                b.to_string(),
                v.len().to_string(),
                num(m),
                num(median(&v)),
                num(wv),
                num(below),
                at(ratios[wi].1),
            ]);
        } else {
            rec.extend(std::iter::repeat_n(String::new(), 7));
        }
        w.write_record(&rec)?;
    }
    w.into_inner().map_err(|e| anyhow::anyhow!("csv: {e}"))
}

/// The outcome of one claim.
pub struct Outcome {
    pub figure: String,
    pub holds: String,
    pub rows: usize,
}

/// Counts of failing rows by a label, largest first (ties in first-appearance order).
fn fail_counts<'a>(fails: &[&'a Row], label: impl Fn(&'a Row) -> &'a str) -> Vec<(&'a str, usize)> {
    let mut v: Vec<(&str, usize)> = Vec::new();
    for r in fails {
        let l = label(r);
        match v.iter_mut().find(|e| e.0 == l) {
            Some(e) => e.1 += 1,
            None => v.push((l, 1)),
        }
    }
    v.sort_by_key(|e| std::cmp::Reverse(e.1));
    v
}

fn top(v: &[(&str, usize)], n: usize) -> String {
    let mut s: Vec<String> = v.iter().take(n).map(|(l, c)| format!("{l} ({c})")).collect();
    if v.len() > n {
        s.push(format!("+{} more", v.len() - n));
    }
    s.join(", ")
}

/// Checks one claim on the rows.
pub fn check(c: &Claim, rows: &[Row]) -> Outcome {
    match c.check {
        Check::AtMost { bound } => check_bound(c, rows, bound, true),
        Check::AtLeast { bound } => check_bound(c, rows, bound, false),
        Check::Ratio { .. } | Check::Equal { .. } => check_pairs(c, rows),
    }
}

/// `ratio` and `equal`: the claim's encoder against its baseline on matched rows.
fn check_pairs(c: &Claim, rows: &[Row]) -> Outcome {
    let p = pairs(rows, c);
    if p.is_empty() {
        return Outcome {
            figure: format!("no rows of '{}' matched to '{}'", c.encoder, c.baseline),
            holds: "not measured".into(),
            rows: 0,
        };
    }
    let col = c.column.name();
    match c.check {
        Check::Equal { tolerance, abs_tolerance } => {
            // The worst relative difference among rows above the absolute floor.
            let (mut worst_rel, mut worst_abs, mut failing) = (None::<(f64, usize)>, 0.0f64, 0);
            for (i, q) in p.iter().enumerate() {
                let r = q.row;
                let ref_rms = if r.scores.rel_rmse > 0.0 { r.scores.rmse / r.scores.rel_rmse } else { 0.0 };
                let scale = q.a.abs().max(q.b.abs()).max(ref_rms);
                let d = (q.a - q.b).abs();
                worst_abs = worst_abs.max(d);
                if d <= abs_tolerance {
                    continue;
                }
                let rel = if scale > 0.0 { d / scale } else { f64::MAX };
                if worst_rel.is_none_or(|w| rel > w.0) {
                    worst_rel = Some((rel, i));
                }
                if rel > tolerance {
                    failing += 1;
                }
            }
            let rel_text = match worst_rel {
                Some((rel, i)) => {
                    let r = p[i].row;
                    format!(
                        "largest difference {} relative to max(|a|, |b|, reference RMS) (at {} {} {})",
                        num(rel),
                        r.map,
                        r.domain,
                        r.effects
                    )
                }
                None => "every difference is below the absolute floor".to_string(),
            };
            Outcome {
                figure: format!(
                    "{col}: {rel_text}, largest absolute {}, over {} rows; tolerance {} (absolute floor {}){}",
                    num(worst_abs),
                    p.len(),
                    num(tolerance),
                    num(abs_tolerance),
                    if failing > 0 { format!("; {failing} row(s) outside") } else { String::new() }
                ),
                holds: if failing == 0 { "yes".into() } else { "no".into() },
                rows: p.len(),
            }
        }
        // Not reached through `check`, which sends these to `check_bound`.
        Check::AtMost { .. } | Check::AtLeast { .. } => check(c, rows),
        Check::Ratio { threshold, every } => {
            let mut v = Vec::new();
            let mut fails: Vec<&Row> = Vec::new();
            let mut undefined = 0;
            for q in &p {
                match ratio(q.a, q.b) {
                    Some(x) => {
                        v.push(x);
                        if x >= threshold {
                            fails.push(q.row);
                        }
                    }
                    None => {
                        undefined += 1;
                        fails.push(q.row);
                    }
                }
            }
            let (mean, worst, wi) = if v.is_empty() { (0.0, 0.0, 0) } else { stats(&v) };
            let worst_row = p.iter().filter(|q| ratio(q.a, q.b).is_some()).nth(wi).map(|q| q.row);
            let pass = p.len() - fails.len();
            let mut figure = format!(
                "{col} ratio {} / {}: mean {}, median {}, worst {}{}; < {} in {}/{} rows",
                c.encoder,
                c.baseline,
                fmt3(mean),
                fmt3(if v.is_empty() { 0.0 } else { median(&v) }),
                fmt3(worst),
                worst_row.map(|r| format!(" ({} {} {})", r.map, r.domain, r.effects)).unwrap_or_default(),
                fmt3(threshold),
                pass,
                p.len()
            );
            if undefined > 0 {
                figure += &format!(" ({undefined} with a zero baseline counted as failing)");
            }
            if !fails.is_empty() && pass > 0 {
                figure += &format!(
                    "; fails at orientations {}; maps {}",
                    top(&fail_counts(&fails, |r| r.domain.as_str()), 6),
                    top(&fail_counts(&fails, |r| r.map.as_str()), 6)
                );
                if c.effects.is_none() && distinct(p.iter().map(|q| q.row.effects.as_str())).len() > 1 {
                    figure += &format!("; effects {}", top(&fail_counts(&fails, |r| r.effects.as_str()), 6));
                }
            }
            let holds = if every {
                if fails.is_empty() {
                    "yes".to_string()
                } else if pass == 0 {
                    "no".to_string()
                } else {
                    format!("partly ({pass}/{} rows)", p.len())
                }
            } else if mean < threshold && undefined == 0 {
                "yes".to_string()
            } else {
                "no".to_string()
            };
            Outcome { figure, holds, rows: p.len() }
        }
    }
}

/// `at_most` (`upper`) or `at_least`: the claim's column of its encoder against `bound` on
/// every selected row; a NaN fails either way.
fn check_bound(c: &Claim, rows: &[Row], bound: f64, upper: bool) -> Outcome {
    let v: Vec<(&Row, f64)> =
        rows.iter().filter(|r| c.selects(r)).filter_map(|r| Some((r, c.column.get(r)?))).collect();
    if v.is_empty() {
        return Outcome {
            figure: format!("no rows of '{}' with a {} value", c.encoder, c.column.name()),
            holds: "not measured".into(),
            rows: 0,
        };
    }
    let passes = |x: f64| if upper { x <= bound } else { x >= bound };
    let fails: Vec<&Row> = v.iter().filter(|(_, x)| !passes(*x)).map(|(r, _)| *r).collect();
    // The extreme towards failing: the largest value for at_most, the smallest for at_least
    // (a NaN is the most failing of all).
    let worse = |x: f64, y: f64| x.is_nan() || (!y.is_nan() && if upper { x > y } else { x < y });
    let (mut worst, mut best) = (v[0], v[0]);
    for &q in &v[1..] {
        if worse(q.1, worst.1) {
            worst = q;
        }
        if worse(best.1, q.1) {
            best = q;
        }
    }
    let at = |r: &Row| format!("{} {} {}", r.map, r.domain, r.effects);
    let (hi, lo) = if upper { ("largest", "smallest") } else { ("smallest", "largest") };
    let pass = v.len() - fails.len();
    let mut figure = format!(
        "{} of {}: {hi} {} ({}), {lo} {}; {} {} in {}/{} rows",
        c.column.name(),
        c.encoder,
        fmt3(worst.1),
        at(worst.0),
        fmt3(best.1),
        if upper { "<=" } else { ">=" },
        num(bound),
        pass,
        v.len()
    );
    if !fails.is_empty() && pass > 0 {
        figure += &format!(
            "; fails at orientations {}; maps {}",
            top(&fail_counts(&fails, |r| r.domain.as_str()), 6),
            top(&fail_counts(&fails, |r| r.map.as_str()), 6)
        );
    }
    let holds = if fails.is_empty() {
        "yes".to_string()
    } else if pass == 0 {
        "no".to_string()
    } else {
        format!("partly ({pass}/{} rows)", v.len())
    };
    Outcome { figure, holds, rows: v.len() }
}

/// Three significant digits.
fn fmt3(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return num(x);
    }
    let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    if digits > 6 {
        format!("{x:.2e}")
    } else {
        format!("{x:.digits$}")
    }
}

/// `claims.csv`.
pub fn claims_csv(experiment: &str, claims: &[Claim], outcomes: &[Outcome]) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["id", "claim", "paper_figure", "our_figure", "holds", "check", "experiment", "rows"])?;
    for (c, o) in claims.iter().zip(outcomes) {
        let mut check = match c.check {
            Check::Ratio { threshold, every } => {
                format!("ratio {} < {} ({})", c.column.name(), num(threshold), if every { "every row" } else { "mean" })
            }
            Check::Equal { tolerance, abs_tolerance } => {
                format!("equal {} (rel. tol. {}, abs. {})", c.column.name(), num(tolerance), num(abs_tolerance))
            }
            Check::AtMost { bound } => format!("{} <= {} (every row)", c.column.name(), num(bound)),
            Check::AtLeast { bound } => format!("{} >= {} (every row)", c.column.name(), num(bound)),
        };
        if let Some(e) = &c.effects {
            check += &format!("; effects {e}");
        }
        if let Some(m) = &c.maps {
            check += &format!("; maps {}", m.join(", "));
        }
        w.write_record([
            c.id.as_str(),
            &c.claim,
            &c.paper,
            &o.figure,
            &o.holds,
            &check,
            experiment,
            &o.rows.to_string(),
        ])?;
    }
    w.into_inner().map_err(|e| anyhow::anyhow!("csv: {e}"))
}

/// Markdown-safe cell text.
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// `CLAIMS.md`: what the figures are, the claims table, then for each ratio claim its
/// breakdown by effects and orientation set, by orientation (sets of up to 8), and by map.
pub fn claims_md(
    name: &str,
    description: &str,
    rows: &[Row],
    claims: &[Claim],
    outcomes: &[Outcome],
) -> Result<String> {
    let mut s = String::new();
    writeln!(s, "# Claims checked by `{name}`\n")?;
    writeln!(s, "Generated by `probelab run experiments/{name}.toml`; do not edit. {description}\n")?;
    let list = |f: fn(&Row) -> &str| distinct(rows.iter().map(f)).join(", ");
    writeln!(
        s,
        "Every figure is an error of E/π (units `{}`), weighting `{}`, output grid `{}`, reference `{}`, \
         effects `{}`, domains `{}` (orientation sets `{}`), on maps {}.\n",
        list(|r| &r.units),
        list(|r| &r.weighting),
        list(|r| &r.resolution),
        list(|r| &r.reference),
        list(|r| &r.effects),
        if distinct(rows.iter().map(|r| r.domain.as_str())).len() > 8 {
            format!("{} distinct", distinct(rows.iter().map(|r| r.domain.as_str())).len())
        } else {
            list(|r| &r.domain)
        },
        list(|r| &r.orientation_set),
        list(|r| &r.map)
    )?;
    writeln!(s, "| id | claim | paper figure | our figure | holds |")?;
    writeln!(s, "|---|---|---|---|---|")?;
    for (c, o) in claims.iter().zip(outcomes) {
        writeln!(s, "| {} | {} | {} | {} | {} |", c.id, cell(&c.claim), cell(&c.paper), cell(&o.figure), o.holds)?;
    }
    for c in claims.iter().filter(|c| c.note.is_some()) {
        writeln!(s, "\n- **{}**: {}", c.id, c.note.as_deref().unwrap_or_default())?;
    }
    for c in claims {
        let Check::Ratio { threshold, .. } = c.check else { continue };
        let p = pairs(rows, c);
        if p.is_empty() {
            continue;
        }
        writeln!(
            s,
            "\n## {}: {} ratio {} / {} (passes below {})\n",
            c.id,
            c.column.name(),
            c.encoder,
            c.baseline,
            fmt3(threshold)
        )?;
        let table = |s: &mut String, title: &str, sel: &dyn Fn(&Row) -> String| -> Result<()> {
            let labels: Vec<String> = {
                let mut v: Vec<String> = Vec::new();
                for q in &p {
                    let l = sel(q.row);
                    if !v.contains(&l) {
                        v.push(l);
                    }
                }
                v
            };
            writeln!(
                s,
                "| {title} | rows | mean ratio | median | worst ratio | worst at | below {} |",
                fmt3(threshold)
            )?;
            writeln!(s, "|---|---|---|---|---|---|---|")?;
            for l in labels {
                let sub: Vec<(f64, &Row)> =
                    p.iter().filter(|q| sel(q.row) == l).filter_map(|q| ratio(q.a, q.b).map(|x| (x, q.row))).collect();
                if sub.is_empty() {
                    continue;
                }
                let v: Vec<f64> = sub.iter().map(|x| x.0).collect();
                let (m, wv, wi) = stats(&v);
                let below = v.iter().filter(|&&x| x < threshold).count();
                let wr = sub[wi].1;
                writeln!(
                    s,
                    "| {} | {} | {} | {} | {} | {} {} | {}/{} |",
                    cell(&l),
                    v.len(),
                    fmt3(m),
                    fmt3(median(&v)),
                    fmt3(wv),
                    wr.map,
                    wr.domain,
                    below,
                    v.len()
                )?;
            }
            writeln!(s)?;
            Ok(())
        };
        table(&mut s, "effects, orientation set", &|r| format!("{}, {}", r.effects, r.orientation_set))?;
        let small_sets: Vec<&str> = distinct(p.iter().map(|q| q.row.orientation_set.as_str()))
            .into_iter()
            .filter(|set| {
                distinct(p.iter().filter(|q| q.row.orientation_set == *set).map(|q| q.row.domain.as_str())).len() <= 8
            })
            .collect();
        if !small_sets.is_empty() {
            let sets = small_sets.clone();
            table(&mut s, "orientation (sets of up to 8)", &move |r| {
                if sets.contains(&r.orientation_set.as_str()) {
                    format!("{} ({})", r.domain, r.orientation_set)
                } else {
                    "other sets".into()
                }
            })?;
        }
        table(&mut s, "map", &|r| r.map.clone())?;
    }
    Ok(s)
}

/// Writes `summary.csv`, `claims.csv` and `CLAIMS.md` into `dir` as the experiment declares.
pub fn write(
    dir: &Path,
    name: &str,
    description: &str,
    summary: Option<Option<&str>>,
    claims: &[Claim],
    rows: &[Row],
) -> Result<Vec<String>> {
    let mut written = Vec::new();
    if let Some(baseline) = summary {
        crate::pipeline::atomic::write(&dir.join("summary.csv"), &summary_csv(rows, baseline)?)?;
        written.push("summary.csv".to_string());
    }
    if !claims.is_empty() {
        let outcomes: Vec<Outcome> = claims.iter().map(|c| check(c, rows)).collect();
        crate::pipeline::atomic::write(&dir.join("claims.csv"), &claims_csv(name, claims, &outcomes)?)?;
        crate::pipeline::atomic::write(
            &dir.join("CLAIMS.md"),
            claims_md(name, description, rows, claims, &outcomes)?.as_bytes(),
        )?;
        written.push("claims.csv".to_string());
        written.push("CLAIMS.md".to_string());
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::metrics::Scores;

    fn row(map: &str, enc: &str, domain: &str, rmse: f64) -> Row {
        Row {
            map: map.into(),
            encoder: enc.into(),
            domain: domain.into(),
            metric: "exact".into(),
            scores: Scores { rmse, rel_rmse: rmse, ..Default::default() },
            stored_scalars: 27,
            orientation_set: "axes6".into(),
            effects: "hemisphere".into(),
            weighting: "solid-angle".into(),
            resolution: "8x2".into(),
            units: "E/pi".into(),
            reference: "r".into(),
            diagnostics: String::new(),
            at_normal_abs_err: Some(rmse),
            fit_ns: None,
            eval_ns: None,
        }
    }

    fn rows() -> Vec<Row> {
        vec![
            row("m1", "base", "hemisphere:+x", 2.0),
            row("m1", "op", "hemisphere:+x", 1.0),
            row("m1", "base", "hemisphere:+y", 1.0),
            row("m1", "op", "hemisphere:+y", 1.5),
            row("m2", "base", "hemisphere:+x", 4.0),
            row("m2", "op", "hemisphere:+x", 1.0),
            row("m2", "base", "hemisphere:+y", 0.0),
            row("m2", "op", "hemisphere:+y", 0.0),
        ]
    }

    fn claim(check: &str, extra: &str) -> Claim {
        let f: ClaimFile =
            toml::from_str(&format!("id='c'\nclaim='x'\ncheck='{check}'\nencoder='op'\nbaseline='base'\n{extra}"))
                .unwrap();
        Claim::from_file(f, &["op".into(), "base".into()], &maps()).unwrap()
    }

    fn maps() -> Vec<String> {
        vec!["m1".into(), "dir/m2.exr".into()]
    }

    /// A claim without a baseline (`at_most`/`at_least`).
    fn bounded(check: &str, extra: &str) -> Claim {
        let f: ClaimFile =
            toml::from_str(&format!("id='b'\nclaim='x'\ncheck='{check}'\nencoder='op'\n{extra}")).unwrap();
        Claim::from_file(f, &["op".into(), "base".into()], &maps()).unwrap()
    }

    #[test]
    fn ratio_claims_count_rows_and_name_failures() {
        let o = check(&claim("ratio", ""), &rows());
        // Ratios: 0.5, 1.5, 0.25, 0/0 = 1 (a tie fails "< 1").
        assert_eq!(o.rows, 4);
        assert_eq!(o.holds, "partly (2/4 rows)");
        assert!(o.figure.contains("mean 0.812, median 0.750, worst 1.50 (m1 hemisphere:+y"), "{}", o.figure);
        assert!(o.figure.contains("fails at orientations hemisphere:+y (2)"), "{}", o.figure);
        let mean = check(&claim("ratio", "statistic='mean'\nthreshold=0.9"), &rows());
        assert_eq!(mean.holds, "yes");
        let all = check(&claim("ratio", "threshold=2"), &rows());
        assert_eq!(all.holds, "yes");
    }

    #[test]
    fn equal_claims_use_relative_tolerance() {
        assert_eq!(check(&claim("equal", ""), &rows()).holds, "no");
        // A copy of op under another name, off by 1e-13 relative: equal at 1e-12, not at 1e-14.
        let mut t = rows();
        t.extend(rows().into_iter().filter(|x| x.encoder == "op").map(|mut x| {
            x.encoder = "dup".into();
            x.scores.rmse *= 1.0 + 1e-13;
            x
        }));
        let enc = ["op".to_string(), "dup".to_string()];
        let c = |tol: &str| {
            let f: ClaimFile = toml::from_str(&format!(
                "id='e'\nclaim='x'\ncheck='equal'\nencoder='op'\nbaseline='dup'\ntolerance={tol}\nabs_tolerance=1e-15"
            ))
            .unwrap();
            Claim::from_file(f, &enc, &maps()).unwrap()
        };
        let o = check(&c("1e-12"), &t);
        assert_eq!((o.holds.as_str(), o.rows), ("yes", 4), "{}", o.figure);
        assert_eq!(check(&c("1e-14"), &t).holds, "no");
        // Differences below the absolute floor pass whatever their relative size (errors at
        // rounding level): op = 1e-16 vs dup = 2e-16.
        let tiny: Vec<Row> = t
            .iter()
            .cloned()
            .map(|mut x| {
                x.scores.rmse = if x.encoder == "dup" { 2e-16 } else { 1e-16 };
                x.scores.rel_rmse = 1.0;
                x
            })
            .collect();
        assert_eq!(check(&c("1e-14"), &tiny).holds, "yes");
    }

    #[test]
    fn bad_claims_are_rejected_with_the_key() {
        let enc = ["op".to_string(), "base".to_string()];
        let parse = |s: &str| -> String {
            let f: ClaimFile =
                toml::from_str(&format!("id='c'\nclaim='x'\nencoder='op'\nbaseline='base'\n{s}")).unwrap();
            format!("{:#}", Claim::from_file(f, &enc, &maps()).err().unwrap())
        };
        assert!(parse("check='nope'").contains("check 'nope'"));
        assert!(parse("check='ratio'\ncolumn='speed'").contains("column 'speed'"));
        assert!(parse("check='ratio'\nstatistic='median'").contains("statistic 'median'"));
        assert!(parse("check='equal'\nthreshold=1").contains("threshold"));
        assert!(parse("check='ratio'\nbound=1").contains("'bound' is for check"));
        assert!(parse("check='at_most'\nbound=1").contains("'baseline' is not used"));
        assert!(parse("check='ratio'\nmaps=['m3']").contains("maps names 'm3'"));
        assert!(parse("check='ratio'\nmaps=[]").contains("maps = [] matches no row"));
        let parse_nb = |s: &str| -> String {
            let f: ClaimFile = toml::from_str(&format!("id='c'\nclaim='x'\nencoder='op'\n{s}")).unwrap();
            format!("{:#}", Claim::from_file(f, &enc, &maps()).err().unwrap())
        };
        assert!(parse_nb("check='ratio'").contains("needs 'baseline'"));
        assert!(parse_nb("check='at_most'").contains("needs 'bound'"));
        assert!(parse_nb("check='at_least'\nbound=-1").contains("bound must be"));
        assert!(parse_nb("check='at_most'\nbound=nan").contains("bound must be"));
        assert!(parse_nb("check='at_most'\nbound=1\nthreshold=2").contains("takes 'bound' only"));
        // A map is matched by its entry or its table name (file stem).
        assert_eq!(bounded("at_most", "bound=1\nmaps=['m2', 'dir/m2.exr']").maps, Some(vec!["m2".to_string()]));
        let f: ClaimFile = toml::from_str("id='c'\nclaim='x'\ncheck='ratio'\nencoder='zz'\nbaseline='base'").unwrap();
        assert!(format!("{:#}", Claim::from_file(f, &enc, &maps()).err().unwrap()).contains("encoder 'zz'"));
        assert!(toml::from_str::<ClaimFile>("id='c'\nclaim='x'\ncheck='ratio'\nencoder='a'\nbaseline='b'\nbogus=1")
            .is_err());
    }

    #[test]
    fn bound_claims_compare_each_row_with_the_bound() {
        // op's rmse: 1.0, 1.5 (m1), 1.0, 0.0 (m2).
        let o = check(&bounded("at_most", "bound=1.5"), &rows());
        assert_eq!((o.holds.as_str(), o.rows), ("yes", 4), "{}", o.figure);
        assert!(
            o.figure.contains("rmse of op: largest 1.50 (m1 hemisphere:+y hemisphere), smallest 0"),
            "{}",
            o.figure
        );
        assert!(o.figure.contains("<= 1.5 in 4/4 rows"), "{}", o.figure);
        // Just below the largest value: that row fails.
        let o = check(&bounded("at_most", "bound=1.4999999"), &rows());
        assert_eq!(o.holds, "partly (3/4 rows)", "{}", o.figure);
        assert!(o.figure.contains("fails at orientations hemisphere:+y (1); maps m1 (1)"), "{}", o.figure);
        assert_eq!(check(&bounded("at_most", "bound=0"), &rows()).holds, "partly (1/4 rows)");
        // at_least: the zero row fails a positive bound and passes bound 0; the smallest value is named.
        let o = check(&bounded("at_least", "bound=1"), &rows());
        assert_eq!(o.holds, "partly (3/4 rows)", "{}", o.figure);
        assert!(o.figure.contains("smallest 0 (m2 hemisphere:+y hemisphere), largest 1.50"), "{}", o.figure);
        assert_eq!(check(&bounded("at_least", "bound=0"), &rows()).holds, "yes");
        assert_eq!(check(&bounded("at_least", "bound=2"), &rows()).holds, "no");
        // Another column.
        let mut t = rows();
        t[1].at_normal_abs_err = Some(3e-13);
        let o = check(&bounded("at_most", "bound=1e-12\ncolumn='at_normal_abs_err'\nmaps=['m1']"), &t);
        assert_eq!(o.holds, "partly (1/2 rows)", "{}", o.figure);
        // A NaN fails both checks.
        let mut t = rows();
        t[1].scores.rmse = f64::NAN;
        assert_eq!(check(&bounded("at_most", "bound=10"), &t).holds, "partly (3/4 rows)");
        assert_eq!(check(&bounded("at_least", "bound=0"), &t).holds, "partly (3/4 rows)");
    }

    #[test]
    fn maps_filter_selects_rows_by_table_name() {
        // m2 is listed as a path; rows name it by its stem. On m2 the ratios are 0.25 and the
        // 0/0 tie (1), so all pass below 1.01; on m1 they are 0.5 and 1.5.
        let on = |m: &str, thr: &str| check(&claim("ratio", &format!("maps=['{m}']\nthreshold={thr}")), &rows());
        let o = on("m2", "1.01");
        assert_eq!((o.holds.as_str(), o.rows), ("yes", 2), "{}", o.figure);
        let o = on("m1", "1");
        assert_eq!((o.holds.as_str(), o.rows), ("partly (1/2 rows)", 2), "{}", o.figure);
        // By its path as written in the experiment, too.
        assert_eq!(on("dir/m2.exr", "1.01").rows, 2);
        let o = check(&bounded("at_most", "bound=1\nmaps=['m2']"), &rows());
        assert_eq!((o.holds.as_str(), o.rows), ("yes", 2), "{}", o.figure);
        let c = claim("ratio", "maps=['m2']");
        let csv = String::from_utf8(claims_csv("e", std::slice::from_ref(&c), &[check(&c, &rows())]).unwrap()).unwrap();
        assert!(csv.contains("ratio rmse < 1 (every row); maps m2"), "{csv}");
        // CLAIMS.md breaks the claim down over the selected map only.
        let md = claims_md("e", "", &rows(), std::slice::from_ref(&c), &[check(&c, &rows())]).unwrap();
        let breakdown = &md[md.find("## c:").unwrap()..];
        assert!(breakdown.contains("| m2 |") && !breakdown.contains("| m1 |"), "{md}");
    }

    #[test]
    fn summary_has_orientation_map_and_set_lines() {
        let csv = String::from_utf8(summary_csv(&rows(), Some("base")).unwrap()).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        // Per encoder (2): 2 orientations + 2 maps + 1 set = 5 lines.
        assert_eq!(lines.len(), 1 + 10, "{csv}");
        // op over +x: ratios 0.5 and 0.25 → mean 0.375, worst 0.5 at m1.
        let x = lines.iter().find(|l| l.starts_with("op,hemisphere,exact,axes6,hemisphere:+x,*")).unwrap();
        assert!(x.contains(",base,2,0.375,0.375,0.5,1,m1 hemisphere:+x"), "{x}");
        let all = lines.iter().find(|l| l.starts_with("op,hemisphere,exact,axes6,*,*")).unwrap();
        assert!(all.contains(",4,"), "{all}");
        // No baseline: ratio fields empty.
        let plain = String::from_utf8(summary_csv(&rows(), None).unwrap()).unwrap();
        assert!(plain.lines().nth(1).unwrap().ends_with(",,,,,,,"));
    }
}
