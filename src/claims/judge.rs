//! The one claims engine: judges each declared claim ([`crate::claims::declaration`]) on its
//! evidence tables — experiment tables and claims measurements alike, read as CSV. Its one
//! primary check decides its one verdict, in the words its evidence kind allows
//! ([`crate::claims::declaration::Kind`]); its context checks are judged and shown, and never
//! change the verdict. A claim whose primary lacks its data is `untestable` (saying why).
//! Nothing here knows a claim, an encoder or a paper: every criterion and threshold comes from
//! the declaration.
//!
//! Ratios are taken per row (encoder / baseline, matched on the key columns), then per map —
//! a map's ratio is the geometric mean of its rows' ratios (its orientations, say) — and
//! summarised over maps by their median and geometric mean. Never a ratio of pooled means:
//! one map with large errors would decide it. Rows whose baseline value is at or below the
//! check's `floor` are excluded and counted, so no ratio divides by ~0.

use crate::claims::declaration::{CheckDecl, ClaimDecl, Kind, Paper, Statistic, Test};
use crate::claims::ratios;
use crate::math::echo::value as echo;
use anyhow::{bail, Context, Result};
use std::collections::HashMap;

/// The columns that identify a row besides its encoder (those present in a table are used).
pub const KEY_COLUMNS: &[&str] = &["map", "domain", "effects", "metric", "case"];

/// An evidence table: CSV text with a header (the same text table the baselines use).
pub use crate::pipeline::table::CsvText as Evidence;

/// Where a check, or a claim, stands.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    /// The criterion is met.
    Pass,
    /// The criterion is not met.
    Fail,
    /// A figure without a criterion (`ratio_summary`): shown, neither met nor missed.
    Shown,
    /// The data to judge it is missing; the reason.
    Untestable(String),
}

/// One value a check judged: the row's label (its key; the map for per-map ratios), the value
/// (a ratio for ratio tests) and whether it passes on its own.
#[derive(Clone, Debug)]
pub struct RowValue {
    /// The row's key as text (map, domain, effects, metric, case: those the table has).
    pub label: String,
    /// The row's map, for counting distinct maps.
    pub map: String,
    /// The value judged: the cell, or its ratio to the baseline encoder's for ratio tests.
    pub value: f64,
    /// Whether this row alone meets the criterion.
    pub pass: bool,
}

/// A check judged on one map set.
#[derive(Clone, Debug)]
pub struct SetOutcome {
    /// `all`, or a declared set name.
    pub set: String,
    /// Distinct maps judged.
    pub maps: usize,
    /// The check's status on this set.
    pub status: Status,
    /// One short phrase with the number.
    pub headline: String,
    /// The full figure.
    pub figure: String,
    /// Every row judged, in the table's order.
    pub values: Vec<RowValue>,
    /// Rows left out: baseline at or below the floor, or no value.
    pub excluded: usize,
}

/// A check judged on each set it declares.
#[derive(Clone, Debug)]
pub struct CheckOutcome {
    /// The check as declared in the claims file.
    pub decl: CheckDecl,
    /// Its outcome on each map set it names (or `all`).
    pub sets: Vec<SetOutcome>,
}

/// A claim's one verdict, in the words its kind allows.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// `measured`: the primary check passes on every set it is judged on.
    Holds,
    /// `identity`: the identity is met numerically, to rounding.
    HoldsIdentity,
    /// `measured`: the primary passes on some of its sets and not others; which.
    Partly(String),
    /// `measured` or `identity`: the primary check fails; where.
    Fails(String),
    /// `example`: the paper's case (or the closest we have) shows what the paper says.
    Reproduced,
    /// `example`: it does not; where.
    NotReproduced(String),
    /// `anchor`: the paper's figure comes from a population we do not have.
    NotComparable,
    /// The primary check cannot be judged (its evidence is missing); why.
    Untestable(String),
}

impl Verdict {
    /// The verdict word (one of its kind's [`Kind::verdict_words`], or `untestable`).
    pub fn word(&self) -> &'static str {
        match self {
            Verdict::Holds => "holds",
            Verdict::HoldsIdentity => "holds (identity)",
            Verdict::Partly(_) => "partly",
            Verdict::Fails(_) => "fails",
            Verdict::Reproduced => "reproduced",
            Verdict::NotReproduced(_) => "not reproduced",
            Verdict::NotComparable => "not comparable",
            Verdict::Untestable(_) => crate::claims::declaration::UNTESTABLE,
        }
    }
    /// What part held, what failed, or why it cannot be judged.
    pub fn why(&self) -> &str {
        match self {
            Verdict::Holds | Verdict::HoldsIdentity | Verdict::Reproduced | Verdict::NotComparable => "",
            Verdict::Partly(s) | Verdict::Fails(s) | Verdict::NotReproduced(s) | Verdict::Untestable(s) => s,
        }
    }
}

/// A judged claim.
#[derive(Clone, Debug)]
pub struct ClaimOutcome {
    /// The claim's id (`Z1`, `H3`, `D2`, …).
    pub id: String,
    /// The claim's evidence kind.
    pub kind: Kind,
    /// The one verdict, decided by the primary check.
    pub verdict: Verdict,
    /// Every check, judged (the primary among them).
    pub checks: Vec<CheckOutcome>,
}

/// A check's headline on each of its sets (`paper 5: …; all 19: …`).
fn headlines(c: &CheckOutcome) -> String {
    let parts: Vec<String> = c
        .sets
        .iter()
        .map(|s| if c.sets.len() > 1 { format!("{}: {}", set_short(s), s.headline) } else { s.headline.clone() })
        .collect();
    parts.join("; ")
}

impl ClaimOutcome {
    /// Our figure: the primary check's headline on each of its sets, then the headline of
    /// each context check declared `beside` (named).
    pub fn our_figure(&self) -> String {
        let mut parts: Vec<String> = self.checks.iter().filter(|c| c.decl.primary).map(headlines).collect();
        for c in self.checks.iter().filter(|c| c.decl.beside) {
            parts.push(format!("{}: {}", c.decl.name, headlines(c)));
        }
        parts.join(" · ")
    }
    /// The map sets judged, with their map counts (e.g. `paper (5); all (19)`).
    pub fn maps(&self) -> String {
        let mut v: Vec<String> = Vec::new();
        for c in &self.checks {
            for s in &c.sets {
                let l = set_label(s);
                if !v.contains(&l) {
                    v.push(l);
                }
            }
        }
        v.join("; ")
    }
}

/// `paper (5 maps)`; a set without a map column is named alone.
pub fn set_label(s: &SetOutcome) -> String {
    if s.maps > 0 {
        format!("{} ({} map{})", s.set, s.maps, if s.maps == 1 { "" } else { "s" })
    } else {
        s.set.clone()
    }
}

/// `paper 5`: the set and its map count, short (for headlines).
fn set_short(s: &SetOutcome) -> String {
    if s.maps > 0 {
        format!("{} {}", s.set, s.maps)
    } else {
        s.set.clone()
    }
}

/// Three significant digits; scientific below 1e-3.
pub fn fmt3(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if !x.is_finite() {
        "non-finite".into()
    } else if x.abs() < 1e-3 || x.abs() >= 1e5 {
        format!("{x:.2e}")
    } else {
        let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    }
}

/// A row of the check: its label, map and value of the judged column (None: empty cell).
struct Picked<'a> {
    row: &'a [String],
    label: String,
    map: String,
    value: Option<f64>,
}

/// A cell of the judged column in a row in scope, as read.
enum Cell {
    /// An empty cell: the row has no value (left out and counted, not an error).
    Empty,
    /// A number as written (finite or not: the caller decides).
    Number(f64),
}

/// The rows a check reads in a table: the encoder and judged columns, the `where` filters,
/// the maps of the set and of the check, and the key columns that label and match rows.
struct Scope<'a> {
    t: &'a Evidence,
    k: &'a CheckDecl,
    set_maps: Option<&'a [String]>,
    enc_col: usize,
    val_col: usize,
    map_col: Option<usize>,
    filters: Vec<(usize, &'a Vec<String>)>,
    keys: Vec<usize>,
}

impl<'a> Scope<'a> {
    /// The check's columns in `t`; an error names a column the table lacks.
    fn new(t: &'a Evidence, k: &'a CheckDecl, set_maps: Option<&'a [String]>) -> Result<Self> {
        let enc_col = t.col("encoder").context("the table has no 'encoder' column")?;
        let Some(val_col) = t.col(&k.column) else { bail!("the table has no column '{}'", echo(&k.column)) };
        let map_col = t.col("map");
        let mut filters = Vec::new();
        for (name, allowed) in &k.filter {
            let Some(c) = t.col(name) else { bail!("where.{n}: the table has no column '{n}'", n = echo(name)) };
            filters.push((c, allowed));
        }
        let keys: Vec<usize> = KEY_COLUMNS.iter().filter_map(|c| t.col(c)).collect();
        Ok(Scope { t, k, set_maps, enc_col, val_col, map_col, filters, keys })
    }

    /// Whether a row passes the filters and lies on the set's and the check's maps.
    fn in_scope(&self, r: &[String]) -> bool {
        self.filters.iter().all(|(c, allowed)| allowed.contains(&r[*c]))
            && self.map_col.is_none_or(|m| {
                self.set_maps.is_none_or(|s| s.contains(&r[m]))
                    && self.k.maps.as_ref().is_none_or(|s| s.contains(&r[m]))
            })
    }

    /// The judged cell of a row of `encoder` (`*`: any) in scope; None for other rows, an
    /// error for a cell that is not a number.
    fn cell(&self, r: &[String], encoder: &str) -> Option<Result<Cell>> {
        if (encoder != "*" && r[self.enc_col] != encoder) || !self.in_scope(r) {
            return None;
        }
        let cell = r[self.val_col].trim();
        if cell.is_empty() {
            return Some(Ok(Cell::Empty));
        }
        Some(cell.parse::<f64>().map(Cell::Number).map_err(|_| anyhow::anyhow!("'{cell}' is not a number")))
    }

    /// A row's label: its non-empty key cells.
    fn label(&self, r: &[String]) -> String {
        self.keys.iter().map(|&c| r[c].as_str()).filter(|s| !s.is_empty()).collect::<Vec<_>>().join(" · ")
    }

    /// A row's key, to match it with a baseline row.
    fn key_of(&self, r: &[String]) -> Vec<String> {
        self.keys.iter().map(|&c| r[c].clone()).collect()
    }

    /// The value of a row of `encoder` in scope (None: an empty cell); an error for a cell
    /// that is not a finite number. `of` names the encoder in the error where it is a baseline.
    fn value(&self, r: &[String], encoder: &str, of: &str) -> Option<Result<Option<f64>>> {
        let cell = self.cell(r, encoder)?;
        let col = &self.k.column;
        Some(match cell {
            Ok(Cell::Number(x)) if x.is_finite() => Ok(Some(x)),
            Ok(Cell::Number(x)) => Err(anyhow::anyhow!("row {}: {col}{of} is {x}", self.label(r))),
            Ok(Cell::Empty) => Ok(None),
            Err(e) => Err(anyhow::anyhow!("row {}: {col}: {e}", self.label(r))),
        })
    }

    /// The rows of the check's encoder in scope, in table order.
    fn picked(&self) -> Result<Vec<Picked<'a>>> {
        let mut picked = Vec::new();
        for r in &self.t.rows {
            if let Some(value) = self.value(r, &self.k.encoder, "") {
                picked.push(Picked {
                    row: r,
                    label: self.label(r),
                    map: self.map_col.map(|m| r[m].clone()).unwrap_or_default(),
                    value: value?,
                });
            }
        }
        Ok(picked)
    }

    /// The baseline encoder's values in scope, by row key.
    fn baseline_rows(&self, base: &str) -> Result<HashMap<Vec<String>, Option<f64>>> {
        let mut rows = HashMap::new();
        for r in &self.t.rows {
            if let Some(value) = self.value(r, base, &format!(" of '{base}'")) {
                rows.insert(self.key_of(r), value?);
            }
        }
        Ok(rows)
    }
}

/// A set that could not be judged, and why.
fn untestable(set: &str, maps: usize, why: String) -> SetOutcome {
    SetOutcome {
        set: set.into(),
        maps,
        status: Status::Untestable(why),
        headline: "no data".into(),
        figure: String::new(),
        values: vec![],
        excluded: 0,
    }
}

/// Pass when every row passes.
fn pass_if(all: bool) -> Status {
    if all {
        Status::Pass
    } else {
        Status::Fail
    }
}

/// Judges one check on one set of a table.
fn judge_set(t: &Evidence, k: &CheckDecl, set: &str, set_maps: Option<&[String]>) -> Result<SetOutcome> {
    let scope = Scope::new(t, k, set_maps)?;
    if set_maps.is_some() && scope.map_col.is_none() {
        return Ok(untestable(set, 0, format!("the table has no map column to select set '{set}'")));
    }
    let picked = scope.picked()?;
    let maps_judged = {
        let mut m: Vec<&str> = picked.iter().map(|p| p.map.as_str()).filter(|s| !s.is_empty()).collect();
        m.sort();
        m.dedup();
        m.len()
    };
    if picked.is_empty() {
        return Ok(untestable(set, maps_judged, format!("no rows of '{}' in scope", echo(&k.encoder))));
    }
    if let Some(why) = set_maps.and_then(|s| missing_maps(k, set, s, &picked)) {
        return Ok(untestable(set, maps_judged, why));
    }
    let excluded = picked.iter().filter(|p| p.value.is_none()).count();
    if !k.test.needs_baseline() {
        return Ok(judge_bound(k, set, maps_judged, &picked, excluded));
    }
    judge_against_baseline(&scope, set, maps_judged, &picked, excluded)
}

/// Why the set cannot be judged when some of its maps (those the check reads) have no rows.
fn missing_maps(k: &CheckDecl, set: &str, set_maps: &[String], picked: &[Picked]) -> Option<String> {
    let present: Vec<&str> = picked.iter().map(|p| p.map.as_str()).collect();
    let missing: Vec<&String> = set_maps
        .iter()
        .filter(|m| k.maps.as_ref().is_none_or(|l| l.contains(m)))
        .filter(|m| !present.contains(&m.as_str()))
        .collect();
    (!missing.is_empty()).then(|| {
        format!(
            "{} map(s) of set '{set}' have no rows of '{}': {}",
            missing.len(),
            echo(&k.encoder),
            missing.iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", ")
        )
    })
}

/// A bound on every row (`every_at_most`, `every_at_least`, `every_equal`): each value against
/// the bound.
fn judge_bound(k: &CheckDecl, set: &str, maps_judged: usize, picked: &[Picked], excluded: usize) -> SetOutcome {
    let col = &k.column;
    let vals: Vec<(&Picked, f64)> = picked.iter().filter_map(|p| p.value.map(|v| (p, v))).collect();
    if vals.is_empty() {
        return untestable(set, maps_judged, format!("every row of '{}' has an empty {col}", echo(&k.encoder)));
    }
    let (upper, bound) = match k.test {
        Test::EveryAtMost { bound } => (true, bound),
        Test::EveryAtLeast { bound } => (false, bound),
        Test::EveryEqual { value } => return judge_exact(k, set, maps_judged, &vals, value, excluded),
        _ => unreachable!("needs_baseline covers the other tests"),
    };
    let ok = |v: f64| if upper { v <= bound } else { v >= bound };
    let values: Vec<RowValue> = vals
        .iter()
        .map(|(p, v)| RowValue { label: p.label.clone(), map: p.map.clone(), value: *v, pass: ok(*v) })
        .collect();
    // Cannot fail: `values` has one entry per `vals`, and an empty `vals` returned above.
    let worst = values
        .iter()
        .max_by(|a, b| if upper { a.value.total_cmp(&b.value) } else { b.value.total_cmp(&a.value) })
        .expect("non-empty");
    let passing = values.iter().filter(|v| v.pass).count();
    let op = if upper { "≤" } else { "≥" };
    let headline = format!(
        "{} {col} {} {op} {} ({passing}/{})",
        if upper { "max" } else { "min" },
        fmt3(worst.value),
        fmt3(bound),
        values.len()
    );
    let figure = format!(
        "{col} of {}: {} {} at {}; {op} {} in {passing}/{} rows{}",
        k.encoder,
        if upper { "largest" } else { "smallest" },
        fmt3(worst.value),
        worst.label,
        fmt3(bound),
        values.len(),
        if excluded > 0 { format!(" ({excluded} row(s) without a value left out)") } else { String::new() }
    );
    let status = pass_if(passing == values.len());
    SetOutcome { set: set.into(), maps: maps_judged, status, headline, figure, values, excluded }
}

/// `every_equal`: every value is exactly `value`.
fn judge_exact(
    k: &CheckDecl,
    set: &str,
    maps_judged: usize,
    vals: &[(&Picked, f64)],
    value: f64,
    excluded: usize,
) -> SetOutcome {
    let col = &k.column;
    let values: Vec<RowValue> = vals
        .iter()
        .map(|(p, v)| RowValue { label: p.label.clone(), map: p.map.clone(), value: *v, pass: *v == value })
        .collect();
    let passing = values.iter().filter(|v| v.pass).count();
    let off: Vec<&str> = values.iter().filter(|v| !v.pass).map(|v| v.label.as_str()).collect();
    let headline = format!("{col} = {} in {passing}/{}", fmt3(value), values.len());
    let figure = format!(
        "{col} of {}: {headline} rows{}{}",
        k.encoder,
        if off.is_empty() { String::new() } else { format!("; differs at {}", off.join(", ")) },
        if excluded > 0 { format!(" ({excluded} row(s) without a value left out)") } else { String::new() }
    );
    let status = pass_if(passing == values.len());
    SetOutcome { set: set.into(), maps: maps_judged, status, headline, figure, values, excluded }
}

/// The rows of a check paired with its baseline's on the key columns: (row, value, baseline).
type Pairs<'p, 'a> = Vec<(&'p Picked<'a>, f64, f64)>;

/// Tests against a baseline (`equal`, ratio tests): rows matched on the key columns, those
/// whose baseline is at or below the floor, unmatched or empty left out and counted.
fn judge_against_baseline(
    scope: &Scope,
    set: &str,
    maps_judged: usize,
    picked: &[Picked],
    mut excluded: usize,
) -> Result<SetOutcome> {
    let k = scope.k;
    let col = &k.column;
    // Cannot fail: `declaration` refuses a test that needs a baseline without one.
    let base = k.baseline.as_deref().expect("validated: the test needs a baseline");
    let base_rows = scope.baseline_rows(base)?;
    let mut pairs: Pairs = Vec::new();
    let mut unmatched = 0;
    let mut below_floor = 0;
    for p in picked {
        let Some(a) = p.value else { continue };
        match base_rows.get(&scope.key_of(p.row)) {
            None => unmatched += 1,
            Some(None) => excluded += 1,
            Some(Some(b)) => {
                if matches!(k.test, Test::Equal { .. }) || *b > k.floor {
                    pairs.push((p, a, *b));
                } else {
                    below_floor += 1;
                }
            }
        }
    }
    if unmatched > 0 && pairs.is_empty() {
        return Ok(untestable(set, maps_judged, format!("no rows of '{}' match rows of '{base}'", echo(&k.encoder))));
    }
    if pairs.is_empty() {
        let why = format!("every row of '{base}' is at or below the floor {} ({below_floor} row(s))", fmt3(k.floor));
        return Ok(untestable(set, maps_judged, why));
    }
    excluded += below_floor + unmatched;
    let left_out = {
        let mut v = Vec::new();
        if below_floor > 0 {
            v.push(format!("{below_floor} with {base} {col} ≤ floor {}", fmt3(k.floor)));
        }
        if unmatched > 0 {
            v.push(format!("{unmatched} without a {base} row"));
        }
        if excluded > below_floor + unmatched {
            v.push(format!("{} without a value", excluded - below_floor - unmatched));
        }
        if v.is_empty() {
            String::new()
        } else {
            format!("; left out: {}", v.join(", "))
        }
    };
    let (status, values, headline, figure) = match k.test {
        Test::Equal { tolerance, abs_tolerance } => judge_equal(&pairs, tolerance, abs_tolerance, &left_out),
        _ => judge_ratio(k, base, &pairs, &left_out),
    };
    Ok(SetOutcome { set: set.into(), maps: maps_judged, status, headline, figure, values, excluded })
}

/// What a baseline test gives a set: status, per-row values, headline and figure.
type Judged = (Status, Vec<RowValue>, String, String);

/// `equal`: every row's relative difference from its baseline within the tolerance
/// (differences up to `abs_tolerance` count as none).
fn judge_equal(pairs: &Pairs, tolerance: f64, abs_tolerance: f64, left_out: &str) -> Judged {
    let values: Vec<RowValue> = pairs
        .iter()
        .map(|(p, a, b)| {
            let d = (a - b).abs();
            let scale = a.abs().max(b.abs());
            let rel = if d <= abs_tolerance {
                0.0
            } else if scale > 0.0 {
                d / scale
            } else {
                f64::INFINITY
            };
            RowValue { label: p.label.clone(), map: p.map.clone(), value: rel, pass: rel <= tolerance }
        })
        .collect();
    // Cannot fail: `values` has one entry per pair, and no pairs returned above.
    let worst = values.iter().max_by(|a, b| a.value.total_cmp(&b.value)).expect("non-empty");
    let passing = values.iter().filter(|v| v.pass).count();
    let headline =
        format!("largest relative difference {} ≤ {} ({passing}/{})", fmt3(worst.value), fmt3(tolerance), values.len());
    let figure =
        format!("{headline}; worst at {}; differences ≤ {} count as equal{left_out}", worst.label, fmt3(abs_tolerance));
    let status = pass_if(passing == values.len());
    (status, values, headline, figure)
}

/// How many maps (or, in a table without maps, cases) a summary holds, as a phrase (`19 maps`).
fn n_maps(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}

/// Ratio tests (`ratio_every`, `ratio_some`, `ratio_stat`, `ratio_summary`) on the ratios to
/// the baseline: per row, then per map (the geometric mean of a map's rows), summarised over
/// maps by median and geometric mean ([`crate::claims::ratios`]). Every figure names its
/// aggregation.
fn judge_ratio(k: &CheckDecl, base: &str, pairs: &Pairs, left_out: &str) -> Judged {
    let col = &k.column;
    let ratios: Vec<f64> = pairs.iter().map(|(_, a, b)| a / b).collect();
    let group = |p: &Picked| if p.map.is_empty() { p.label.clone() } else { p.map.clone() };
    let keyed: Vec<(String, f64)> = pairs.iter().zip(&ratios).map(|((p, _, _), &r)| (group(p), r)).collect();
    let refs: Vec<(&str, f64)> = keyed.iter().map(|(m, r)| (m.as_str(), *r)).collect();
    // Cannot fail: the caller returns untestable when there are no pairs.
    let sum = ratios::per_map(&refs).expect("non-empty pairs");
    let (lo, hi) = ratios.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| (l.min(x), h.max(x)));
    let n = ratios.len();
    let m = sum.maps.len();
    let (med, gm) = (fmt3(sum.median), fmt3(sum.geomean));
    let noun = if pairs.iter().all(|(p, _, _)| p.map.is_empty()) { "case" } else { "map" };
    let row_values = |pass: &dyn Fn(f64) -> bool| -> Vec<RowValue> {
        pairs
            .iter()
            .zip(&ratios)
            .map(|((p, _, _), &r)| RowValue { label: p.label.clone(), map: p.map.clone(), value: r, pass: pass(r) })
            .collect()
    };
    let map_values = |pass: &dyn Fn(f64) -> bool| -> Vec<RowValue> {
        sum.maps
            .iter()
            .map(|g| RowValue {
                label: format!("{} ({} row{})", g.map, g.rows, if g.rows == 1 { "" } else { "s" }),
                map: g.map.clone(),
                value: g.ratio,
                pass: pass(g.ratio),
            })
            .collect()
    };
    let (status, values, headline) = match k.test {
        Test::RatioEvery { below, per_map } | Test::RatioSome { below, per_map } => {
            let values = if per_map { map_values(&|r| r < below) } else { row_values(&|r| r < below) };
            let passing = values.iter().filter(|v| v.pass).count();
            let every = matches!(k.test, Test::RatioEvery { .. });
            let ok = if every { passing == values.len() } else { passing > 0 };
            let unit = if per_map || n == m { format!("{noun}s") } else { "rows".to_string() };
            let headline =
                format!("{passing}/{} {unit} < {} (per-map median {med}, geomean {gm})", values.len(), fmt3(below));
            (pass_if(ok), values, headline)
        }
        Test::RatioStat { statistic, min, max } => {
            let stat = match statistic {
                Statistic::Median => sum.median,
                Statistic::GeoMean => sum.geomean,
            };
            let ok = min.is_none_or(|m| stat >= m) && max.is_none_or(|m| stat <= m);
            let band = match (min, max) {
                (Some(a), Some(b)) => format!("in [{}, {}]", fmt3(a), fmt3(b)),
                (Some(a), None) => format!("≥ {}", fmt3(a)),
                (None, Some(b)) => format!("≤ {}", fmt3(b)),
                (None, None) => unreachable!("validated: a band"),
            };
            let other = match statistic {
                Statistic::Median => format!("geomean {gm}"),
                Statistic::GeoMean => format!("median {med}"),
            };
            let headline = format!(
                "per-map {} {}{} {band} ({other}, {})",
                if statistic == Statistic::Median { "median" } else { "geomean" },
                fmt3(stat),
                if ok { "" } else { ", not" },
                n_maps(m, noun)
            );
            (pass_if(ok), map_values(&|_| ok), headline)
        }
        Test::RatioSummary => {
            let headline = format!("per-map median {med}, geomean {gm} ({})", n_maps(m, noun));
            (Status::Shown, map_values(&|_| true), headline)
        }
        _ => unreachable!("the other tests returned above"),
    };
    let figure = format!(
        "{}/{base} {col}: {headline}; per-map ratios (each the geometric mean of its rows' ratios) over {}: median \
         {med}, geometric mean {gm}, range {}–{}; per-row ratios over {n} rows: range {}–{}{left_out}",
        k.encoder,
        n_maps(m, noun),
        fmt3(sum.min),
        fmt3(sum.max),
        fmt3(lo),
        fmt3(hi)
    );
    (status, values, headline, figure)
}

/// Judges one check on every set it declares. `table` is its evidence, or why there is none.
pub fn judge_check(paper: &Paper, k: &CheckDecl, table: &std::result::Result<Evidence, String>) -> CheckOutcome {
    let sets =
        k.on.iter()
            .map(|set| {
                let set_maps = (set != "all").then(|| paper.map_sets.get(set).map(|v| v.as_slice()).unwrap_or(&[]));
                let out = match table {
                    Err(why) => Err(why.clone()),
                    Ok(t) => judge_set(t, k, set, set_maps).map_err(|e| format!("{}: {e:#}", k.source.label())),
                };
                out.unwrap_or_else(|why| SetOutcome {
                    set: set.clone(),
                    maps: 0,
                    status: Status::Untestable(why),
                    headline: "no data".into(),
                    figure: String::new(),
                    values: vec![],
                    excluded: 0,
                })
            })
            .collect();
    CheckOutcome { decl: k.clone(), sets }
}

/// The verdict of a claim of `kind`, from its primary check alone: context checks are shown
/// and never change it. A primary without its data makes the claim `untestable`; an anchor
/// with its data is `not comparable`, whatever the figure.
pub fn decide(kind: Kind, checks: &[CheckOutcome]) -> Verdict {
    let Some(p) = checks.iter().find(|c| c.decl.primary) else {
        return Verdict::Untestable("no primary check".into());
    };
    let (mut passing, mut failing, mut untestable) = (Vec::new(), Vec::new(), Vec::new());
    for s in &p.sets {
        match &s.status {
            Status::Untestable(why) => untestable.push(format!("on {}: {why}", set_label(s))),
            Status::Fail => failing.push(set_label(s)),
            Status::Pass | Status::Shown => passing.push(set_label(s)),
        }
    }
    if !untestable.is_empty() {
        return Verdict::Untestable(format!("'{}' {}", p.decl.name, untestable.join("; ")));
    }
    let on = |v: &[String]| v.join(" and ");
    match kind {
        Kind::Anchor => Verdict::NotComparable,
        Kind::Identity if failing.is_empty() => Verdict::HoldsIdentity,
        Kind::Example if failing.is_empty() => Verdict::Reproduced,
        Kind::Measured if failing.is_empty() => Verdict::Holds,
        Kind::Example => Verdict::NotReproduced(format!("'{}' not met on {}", p.decl.name, on(&failing))),
        Kind::Measured if !passing.is_empty() => {
            Verdict::Partly(format!("'{}' holds on {}, not on {}", p.decl.name, on(&passing), on(&failing)))
        }
        Kind::Identity | Kind::Measured => Verdict::Fails(format!("'{}' fails on {}", p.decl.name, on(&failing))),
    }
}

/// Judges a claim: every check on its evidence; the primary decides.
pub fn judge_claim(
    paper: &Paper,
    c: &ClaimDecl,
    evidence: &dyn Fn(&crate::claims::declaration::Source) -> std::result::Result<Evidence, String>,
) -> ClaimOutcome {
    let checks: Vec<CheckOutcome> = c.checks.iter().map(|k| judge_check(paper, k, &evidence(&k.source))).collect();
    let verdict = decide(c.kind, &checks);
    ClaimOutcome { id: c.id.clone(), kind: c.kind, verdict, checks }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::claims::declaration::parse;
    use std::path::Path;

    /// A paper with one claim of `kind` and the given checks; maps m1..m4 (m1, m2 the "paper"
    /// set).
    fn paper(checks: &str, kind: &str) -> Paper {
        let text = format!(
            "title='T'\nauthors='A'\nvenue='V'\norder=1\n[map_sets]\npaper=['m1','m2']\n[[claim]]\nid='X1'\nsays='s'\n\
             paper_figure='p'\ncriterion='c'\nkind='{kind}'\nfixed='before data'\ndiffers='d'\n{checks}"
        );
        parse("t", &text, Path::new("t.toml")).unwrap()
    }

    fn table() -> Evidence {
        // a/b ratios: m1 0.5, m2 0.8, m3 1.5; m4 baseline 1e-9 (ratio 1e6).
        let csv = "map,encoder,metric,rmse\nm1,a,exact,0.5\nm1,b,exact,1\nm2,a,exact,0.8\nm2,b,exact,1\n\
                   m3,a,exact,3\nm3,b,exact,2\nm4,a,exact,0.001\nm4,b,exact,1e-9\nm1,a,peer,9\nm1,b,peer,1\n";
        Evidence::parse(csv.as_bytes(), Path::new("t.csv")).unwrap()
    }

    fn judge_on(checks: &str, kind: &str, t: &Evidence) -> ClaimOutcome {
        let p = paper(checks, kind);
        judge_claim(&p, &p.claims[0], &|_| Ok(t.clone()))
    }

    fn judge(checks: &str, kind: &str) -> ClaimOutcome {
        judge_on(checks, kind, &table())
    }

    const CHECK: &str = "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nbaseline='b'\nwhere={metric='exact'}\n";
    const PRIMARY: &str =
        "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nbaseline='b'\nwhere={metric='exact'}\nrole='primary'\n";

    #[test]
    fn measured_is_partly_when_the_primary_holds_on_one_set_only() {
        let o = judge(&format!("{PRIMARY}test='ratio_every'\nfloor=1e-6\non=['paper','all']"), "measured");
        assert_eq!(o.verdict.word(), "partly", "{:?}", o.verdict);
        assert!(o.verdict.why().contains("holds on paper (2 maps), not on all (4 maps)"), "{}", o.verdict.why());
        let all = &o.checks[0].sets[1];
        // m4 is left out by the floor and counted.
        assert_eq!(all.values.len(), 3);
        assert_eq!(all.excluded, 1);
        assert!(all.figure.contains("1 with b rmse ≤ floor"), "{}", all.figure);
        let o = judge(&format!("{PRIMARY}test='ratio_every'\nbelow=0.4\nfloor=1e-6"), "measured");
        assert_eq!(o.verdict.word(), "fails");
        assert_eq!(judge(&format!("{PRIMARY}test='ratio_some'\nbelow=0.6"), "measured").verdict, Verdict::Holds);
    }

    /// Each kind has its own words: the same passing and failing primaries give them.
    #[test]
    fn each_kind_gets_its_own_words() {
        let pass = format!("{PRIMARY}test='ratio_some'\nbelow=0.6");
        let fail = format!("{PRIMARY}test='ratio_every'\nbelow=0.4\nfloor=1e-6");
        assert_eq!(judge(&pass, "identity").verdict, Verdict::HoldsIdentity);
        assert_eq!(judge(&fail, "identity").verdict.word(), "fails");
        assert_eq!(judge(&pass, "example").verdict, Verdict::Reproduced);
        assert_eq!(judge(&fail, "example").verdict.word(), "not reproduced");
        // An anchor's figure is shown (median of the per-map ratios 0.8 over m1..m3) and never
        // holds or fails.
        let o = judge(&format!("{PRIMARY}test='ratio_summary'\nfloor=1e-6"), "anchor");
        assert_eq!(o.verdict, Verdict::NotComparable);
        assert_eq!(o.checks[0].sets[0].status, Status::Shown);
        assert!(o.our_figure().contains("per-map median 0.800"), "{}", o.our_figure());
        for k in [Kind::Identity, Kind::Measured, Kind::Example] {
            assert!(k.verdict_words().contains(&judge(&pass, k.as_str()).verdict.word()));
            assert!(k.verdict_words().contains(&judge(&fail, k.as_str()).verdict.word()));
        }
        // Missing evidence is untestable for every kind, never passed.
        for k in Kind::ALL {
            let check = if k == Kind::Anchor { "test='ratio_summary'" } else { "test='ratio_every'" };
            let p = paper(&format!("{PRIMARY}{check}"), k.as_str());
            let o = judge_claim(&p, &p.claims[0], &|_| Err("results/e/table.csv: not found".into()));
            assert_eq!(o.verdict.word(), "untestable");
            assert!(o.verdict.why().contains("not found"));
        }
    }

    /// A context check is shown and judged, and never changes the verdict, whether it passes
    /// or fails, however many there are.
    #[test]
    fn context_checks_never_change_the_verdict() {
        let primary = format!("{PRIMARY}test='ratio_some'\nbelow=0.6");
        let failing_context = format!("{CHECK}test='ratio_every'\nbelow=0.1\n");
        let passing_context = format!("{CHECK}test='ratio_some'\nbelow=2\n");
        let alone = judge(&primary, "measured");
        for extra in [&failing_context, &passing_context] {
            for n in 1..4 {
                let o = judge(&format!("{primary}\n{}", extra.repeat(n).replace("name='n'", "name='c'")), "measured");
                assert_eq!(o.verdict, alone.verdict);
                assert_eq!(o.checks.len(), n + 1);
            }
        }
        // A context check declared `beside` stands beside the primary's figure.
        let beside = format!("{primary}\n{}beside=true\n", failing_context.replace("name='n'", "name='cost'"));
        let o = judge(&beside, "measured");
        assert_eq!(o.verdict, Verdict::Holds);
        assert!(o.our_figure().contains(" · cost: 0/"), "{}", o.our_figure());
    }

    /// The aggregation rule: ratios per map (the geometric mean of a map's rows), summarised by
    /// median and geometric mean; never a ratio of pooled means. On this table one map with
    /// large errors (big) makes the pooled ratio Σa/Σb = (0.4 + 0.3 + 0.45 + 20 + 20) / (1 + 1 +
    /// 1 + 10 + 40) = 0.776, while the per-map ratios are 0.4, 0.3, 0.45 and 1: median 0.425, geometric
    /// mean (0.054)^(1/4) = 0.4821. "Below 0.5" holds by the median and the geometric mean,
    /// and would fail by the pooled ratio.
    #[test]
    fn per_map_median_and_geomean_decide_where_the_pooled_ratio_disagrees() {
        const PRIMARY: &str = "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nbaseline='b'\nrole='primary'\n";
        let t = Evidence::parse(
            b"map,encoder,case,rmse\ns1,a,up,0.4\ns1,b,up,1\ns2,a,up,0.3\ns2,b,up,1\ns3,a,up,0.45\ns3,b,up,1\n\
              big,a,up,20\nbig,b,up,10\nbig,a,down,20\nbig,b,down,40\n",
            Path::new("t.csv"),
        )
        .unwrap();
        // The pooled ratio, by hand from the table: 41.15 / 53 = 0.776 over rows, not below 0.5.
        let (sa, sb) = (0.4 + 0.3 + 0.45 + 20.0 + 20.0, 1.0 + 1.0 + 1.0 + 10.0 + 40.0);
        assert!(sa / sb > 0.5);
        // big: rows 2 and 0.5, per-map ratio (2 · 0.5)^(1/2) = 1.
        let med = judge_on(&format!("{PRIMARY}test='ratio_stat'\nstatistic='median'\nmax=0.5"), "measured", &t);
        assert_eq!(med.verdict, Verdict::Holds, "{}", med.checks[0].sets[0].figure);
        assert!(
            med.our_figure().starts_with("per-map median 0.425 ≤ 0.500 (geomean 0.482, 4 maps)"),
            "{}",
            med.our_figure()
        );
        let gm = judge_on(&format!("{PRIMARY}test='ratio_stat'\nstatistic='geomean'\nmax=0.5"), "measured", &t);
        assert_eq!(gm.verdict, Verdict::Holds);
        let gm_tight = judge_on(&format!("{PRIMARY}test='ratio_stat'\nstatistic='geomean'\nmax=0.48"), "measured", &t);
        assert_eq!(gm_tight.verdict.word(), "fails");
        // The per-map values are what the page lists: one per map, big at 1.
        let v = &med.checks[0].sets[0].values;
        assert_eq!(v.len(), 4);
        assert!(v[3].label.starts_with("big (2 rows)") && (v[3].value - 1.0).abs() < 1e-15, "{:?}", v[3]);
        // Per map, 3 of 4 maps are below 0.5; per row, 3 of 5 rows.
        let pm = judge_on(&format!("{PRIMARY}test='ratio_some'\nbelow=0.5\nper_map=true"), "measured", &t);
        assert!(pm.our_figure().starts_with("3/4 maps < 0.500"), "{}", pm.our_figure());
        let pr = judge_on(&format!("{PRIMARY}test='ratio_some'\nbelow=0.5"), "measured", &t);
        assert!(pr.our_figure().starts_with("3/5 rows < 0.500"), "{}", pr.our_figure());
        // No figure names a ratio of means.
        for o in [&med, &gm, &pm, &pr] {
            assert!(!o.checks[0].sets[0].figure.contains("of means"), "{}", o.checks[0].sets[0].figure);
        }
    }

    #[test]
    fn bounds_and_equality() {
        let at = "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nwhere={metric='exact'}\nrole='primary'\n";
        assert_eq!(judge(&format!("{at}test='every_at_most'\nbound=3"), "measured").verdict, Verdict::Holds);
        assert_eq!(judge(&format!("{at}test='every_at_most'\nbound=2"), "measured").verdict.word(), "fails");
        assert_eq!(judge(&format!("{at}test='every_at_least'\nbound=0.5"), "measured").verdict.word(), "fails");
        assert_eq!(judge(&format!("{PRIMARY}test='equal'\ntolerance=0.01"), "identity").verdict.word(), "fails");
        let same = Evidence::parse(b"map,encoder,rmse\nm1,a,0.5\nm1,b,0.5000000000001\n", Path::new("t")).unwrap();
        let p = "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nbaseline='b'\nrole='primary'\ntest='equal'\n";
        assert_eq!(judge_on(p, "identity", &same).verdict, Verdict::HoldsIdentity);
    }

    #[test]
    fn missing_maps_and_columns_are_untestable() {
        let p = paper(&format!("{PRIMARY}test='ratio_every'\non=['paper']\nmaps=['m1','m2']"), "measured");
        let t = Evidence::parse(b"map,encoder,metric,rmse\nm1,a,exact,1\nm1,b,exact,2\n", Path::new("t")).unwrap();
        let o = judge_claim(&p, &p.claims[0], &|_| Ok(t.clone()));
        assert_eq!(o.verdict.word(), "untestable");
        assert!(o.verdict.why().contains("m2"), "{}", o.verdict.why());
        let o = judge(&format!("{PRIMARY}test='ratio_every'\ncolumn='speed'"), "measured");
        assert!(o.verdict.why().contains("no column 'speed'"), "{}", o.verdict.why());
    }
}
