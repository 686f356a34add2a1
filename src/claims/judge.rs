//! The one claims engine: judges each declared claim ([`crate::claims::declaration`]) on its
//! evidence tables — experiment tables and claims measurements alike, read as CSV — and rolls
//! its sub-checks up into exactly one verdict: `holds`, `partly` (saying which part),
//! `fails`, or `untestable` (saying why). Nothing here knows a claim, an encoder or a paper:
//! every criterion, threshold and roll-up rule comes from the declaration.
//!
//! Ratio statistics never divide by ~0: rows whose baseline value is at or below the check's
//! `floor` are excluded and counted, and the statistics are the ratio of means (Σa/Σb) and the
//! median of per-row ratios, never a mean of ratios.

use crate::claims::declaration::{CheckDecl, ClaimDecl, Paper, Rollup, Statistic, Test};
use anyhow::{bail, Context, Result};
use std::collections::HashMap;
use std::fmt::Write as _;

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
    /// The data to judge it is missing; the reason.
    Untestable(String),
}

/// One per-row value a check judged: the row's label (its key), the value (a ratio for ratio
/// tests) and whether the row passes on its own.
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

/// A claim's one verdict.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// The claim's roll-up rule is met: every required check passes on every set (`all`), or
    /// one check does (`any`).
    Holds,
    /// Some required checks pass and some fail; what held and what failed.
    Partly(String),
    /// No required check passes on any set; what failed.
    Fails(String),
    /// A required check cannot be judged (its evidence is missing); why.
    Untestable(String),
}

impl Verdict {
    /// `holds`, `partly`, `fails` or `untestable`.
    pub fn word(&self) -> &'static str {
        match self {
            Verdict::Holds => "holds",
            Verdict::Partly(_) => "partly",
            Verdict::Fails(_) => "fails",
            Verdict::Untestable(_) => "untestable",
        }
    }
    /// What part held, what failed, or why it cannot be judged.
    pub fn why(&self) -> &str {
        match self {
            Verdict::Holds => "",
            Verdict::Partly(s) | Verdict::Fails(s) | Verdict::Untestable(s) => s,
        }
    }
}

/// A judged claim.
#[derive(Clone, Debug)]
pub struct ClaimOutcome {
    /// The claim's id (`Z1`, `H3`, `D2`, …).
    pub id: String,
    /// The one verdict, rolled up from the checks.
    pub verdict: Verdict,
    /// Every check, judged.
    pub checks: Vec<CheckOutcome>,
}

impl ClaimOutcome {
    /// The headline: the first required check that does not pass (named), or else the first
    /// required check, as its phrase on each of its sets.
    pub fn our_figure(&self) -> String {
        let required = || self.checks.iter().filter(|c| !c.decl.anchor);
        let failing = required().find(|c| c.sets.iter().any(|s| s.status != Status::Pass));
        let Some(c) = failing.or_else(|| required().next()) else { return String::new() };
        let parts: Vec<String> = c
            .sets
            .iter()
            .map(|s| if c.sets.len() > 1 { format!("{}: {}", set_short(s), s.headline) } else { s.headline.clone() })
            .collect();
        let body = parts.join("; ");
        if failing.is_some() {
            format!("{} — {body}", c.decl.name)
        } else {
            body
        }
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

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(|a, b| a.total_cmp(b));
    let n = s.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
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
        let Some(val_col) = t.col(&k.column) else { bail!("the table has no column '{}'", k.column) };
        let map_col = t.col("map");
        let mut filters = Vec::new();
        for (name, allowed) in &k.filter {
            let Some(c) = t.col(name) else { bail!("where.{name}: the table has no column '{name}'") };
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
        return Ok(untestable(set, maps_judged, format!("no rows of '{}' in scope", k.encoder)));
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
            k.encoder,
            missing.iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", ")
        )
    })
}

/// A bound on every row (`every_at_most`, `every_at_least`): each value against the bound.
fn judge_bound(k: &CheckDecl, set: &str, maps_judged: usize, picked: &[Picked], excluded: usize) -> SetOutcome {
    let col = &k.column;
    let vals: Vec<(&Picked, f64)> = picked.iter().filter_map(|p| p.value.map(|v| (p, v))).collect();
    if vals.is_empty() {
        return untestable(set, maps_judged, format!("every row of '{}' has an empty {col}", k.encoder));
    }
    let (upper, bound) = match k.test {
        Test::EveryAtMost { bound } => (true, bound),
        Test::EveryAtLeast { bound } => (false, bound),
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
        return Ok(untestable(set, maps_judged, format!("no rows of '{}' match rows of '{base}'", k.encoder)));
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

/// Ratio tests (`ratio_every`, `ratio_some`, `ratio_stat`) on the per-row ratios to the
/// baseline, with the ratio of means and the median ratio in the figure.
fn judge_ratio(k: &CheckDecl, base: &str, pairs: &Pairs, left_out: &str) -> Judged {
    let col = &k.column;
    let ratios: Vec<f64> = pairs.iter().map(|(_, a, b)| a / b).collect();
    let sum_a: f64 = pairs.iter().map(|p| p.1).sum();
    let sum_b: f64 = pairs.iter().map(|p| p.2).sum();
    let rom = sum_a / sum_b;
    let med = median(&ratios);
    let (lo, hi) = ratios.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| (l.min(x), h.max(x)));
    let name = format!("{}/{base} {col}", k.encoder);
    let n = ratios.len();
    let row_values = |pass: &dyn Fn(f64) -> bool| -> Vec<RowValue> {
        pairs
            .iter()
            .zip(&ratios)
            .map(|((p, _, _), &r)| RowValue { label: p.label.clone(), map: p.map.clone(), value: r, pass: pass(r) })
            .collect()
    };
    let (ok, values, headline) = match k.test {
        Test::RatioEvery { below } | Test::RatioSome { below } => {
            let values = row_values(&|r| r < below);
            let passing = values.iter().filter(|v| v.pass).count();
            let every = matches!(k.test, Test::RatioEvery { .. });
            let ok = if every { passing == n } else { passing > 0 };
            let headline =
                format!("ratio median {} ({}–{}), {passing}/{n} < {}", fmt3(med), fmt3(lo), fmt3(hi), fmt3(below));
            (ok, values, headline)
        }
        Test::RatioStat { statistic, min, max } => {
            let (stat, sname) = match statistic {
                Statistic::RatioOfMeans => (rom, "ratio of means"),
                Statistic::MedianRatio => (med, "median ratio"),
            };
            let ok = min.is_none_or(|m| stat >= m) && max.is_none_or(|m| stat <= m);
            let band = match (min, max) {
                (Some(a), Some(b)) => format!("[{}, {}]", fmt3(a), fmt3(b)),
                (Some(a), None) => format!("[{}, ∞)", fmt3(a)),
                (None, Some(b)) => format!("[0, {}]", fmt3(b)),
                (None, None) => unreachable!("validated: a band"),
            };
            let values = row_values(&|_| ok);
            let headline = format!("{sname} {}, {} {band}", fmt3(stat), if ok { "within" } else { "outside" });
            (ok, values, headline)
        }
        _ => unreachable!("the other tests returned above"),
    };
    let figure = format!(
        "{name}: {headline}; ratio of means {}, median {}, range {}–{} over {n} rows{left_out}",
        fmt3(rom),
        fmt3(med),
        fmt3(lo),
        fmt3(hi)
    );
    (pass_if(ok), values, headline, figure)
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

/// Rolls a claim's checks up into its verdict, by the claim's rule.
pub fn roll_up(rule: Rollup, checks: &[CheckOutcome]) -> Verdict {
    let required: Vec<&CheckOutcome> = checks.iter().filter(|c| !c.decl.anchor).collect();
    let mut untestable = Vec::new();
    let mut failing = Vec::new();
    let mut passing = Vec::new();
    for c in &required {
        for s in &c.sets {
            let what = format!("'{}' on {}", c.decl.name, set_label(s));
            match &s.status {
                Status::Untestable(why) => untestable.push(format!("{what}: {why}")),
                Status::Fail => failing.push(what),
                Status::Pass => passing.push(what),
            }
        }
    }
    if !untestable.is_empty() {
        return Verdict::Untestable(untestable.join("; "));
    }
    let check_holds = |c: &CheckOutcome| c.sets.iter().all(|s| s.status == Status::Pass);
    match rule {
        Rollup::All if failing.is_empty() => Verdict::Holds,
        Rollup::Any if required.iter().any(|c| check_holds(c)) => Verdict::Holds,
        _ if passing.is_empty() => Verdict::Fails(format!("fails: {}", failing.join("; "))),
        _ => {
            // Name the part that held on a narrower set only.
            let mut s = format!("holds: {}; fails: {}", passing.join("; "), failing.join("; "));
            let paper_only: Vec<&str> = required
                .iter()
                .filter(|c| {
                    c.sets.iter().any(|s| s.set != "all" && s.status == Status::Pass)
                        && c.sets.iter().any(|s| s.set == "all" && s.status == Status::Fail)
                })
                .map(|c| c.decl.name.as_str())
                .collect();
            if !paper_only.is_empty() {
                s = format!("held only on the narrower map set for {}; {s}", paper_only.join(", "));
            }
            Verdict::Partly(s)
        }
    }
}

/// Judges a claim: every check on its evidence, rolled up.
pub fn judge_claim(
    paper: &Paper,
    c: &ClaimDecl,
    evidence: &dyn Fn(&crate::claims::declaration::Source) -> std::result::Result<Evidence, String>,
) -> ClaimOutcome {
    let checks: Vec<CheckOutcome> = c.checks.iter().map(|k| judge_check(paper, k, &evidence(&k.source))).collect();
    let verdict = roll_up(c.rollup, &checks);
    ClaimOutcome { id: c.id.clone(), verdict, checks }
}

/// The detail of one claim, as Markdown (for the evidence pages).
pub fn detail_md(c: &ClaimDecl, o: &ClaimOutcome) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "**Verdict: {}**{}\n",
        o.verdict.word(),
        if o.verdict.why().is_empty() { String::new() } else { format!(" — {}", o.verdict.why()) }
    );
    let _ = writeln!(s, "- **Paper:** {}", c.statement);
    let _ = writeln!(s, "- **Paper's figure:** {}", c.paper_figure);
    let _ = writeln!(s, "- **Criterion:** {}", c.criterion);
    let _ = writeln!(s, "- **Roll-up:** {}\n", match c.rollup {
        Rollup::All => "holds if every required check passes on every set it is judged on; fails if none passes anywhere; otherwise partly",
        Rollup::Any => "holds if some required check passes on every set it is judged on",
    });
    for k in &o.checks {
        let d = &k.decl;
        let _ = writeln!(
            s,
            "#### {} {}\n\nEvidence `{}`{}; test: {}\n",
            if d.anchor { "Anchor (not counted):" } else { "Check:" },
            d.name,
            d.source.path().display(),
            if d.filter.is_empty() {
                String::new()
            } else {
                format!(
                    ", rows with {}",
                    d.filter.iter().map(|(k, v)| format!("{k} = {}", v.join("|"))).collect::<Vec<_>>().join(", ")
                )
            },
            test_text(d)
        );
        for set in &k.sets {
            let status = match &set.status {
                Status::Pass => "passes".to_string(),
                Status::Fail => "fails".to_string(),
                Status::Untestable(w) => format!("untestable ({w})"),
            };
            let _ = writeln!(
                s,
                "- on {}: **{status}** — {}",
                set_label(set),
                if set.figure.is_empty() { &set.headline } else { &set.figure }
            );
        }
        // The per-row values of the widest set.
        if let Some(w) = k.sets.iter().max_by_key(|s| s.values.len()) {
            if !w.values.is_empty() && w.values.len() <= 60 {
                let what = if d.test.needs_baseline() {
                    if matches!(d.test, Test::Equal { .. }) {
                        "relative difference"
                    } else {
                        "ratio"
                    }
                } else {
                    d.column.as_str()
                };
                let _ = writeln!(s, "\n| row | {what} | passes alone |\n|---|---|---|");
                for v in &w.values {
                    let _ = writeln!(s, "| {} | {} | {} |", v.label, fmt3(v.value), if v.pass { "yes" } else { "no" });
                }
            } else if w.values.len() > 60 {
                let _ = writeln!(s, "\n({} rows; per-row values in the evidence table)", w.values.len());
            }
        }
        let _ = writeln!(s);
    }
    s
}

/// A check's test in words.
pub fn test_text(d: &CheckDecl) -> String {
    let base = d.baseline.as_deref().unwrap_or("");
    let col = &d.column;
    let floor =
        if d.floor > 0.0 { format!(" (rows with {base} {col} ≤ {} left out)", fmt3(d.floor)) } else { String::new() };
    match &d.test {
        Test::RatioEvery { below } => format!("every {} / {base} {col} ratio < {}{floor}", d.encoder, fmt3(*below)),
        Test::RatioSome { below } => format!("some {} / {base} {col} ratio < {}{floor}", d.encoder, fmt3(*below)),
        Test::RatioStat { statistic, min, max } => format!(
            "{} of {} / {base} {col} {}{floor}",
            match statistic {
                Statistic::RatioOfMeans => "ratio of means",
                Statistic::MedianRatio => "median ratio",
            },
            d.encoder,
            match (min, max) {
                (Some(a), Some(b)) => format!("in [{}, {}]", fmt3(*a), fmt3(*b)),
                (Some(a), None) => format!("≥ {}", fmt3(*a)),
                (None, Some(b)) => format!("≤ {}", fmt3(*b)),
                (None, None) => String::new(),
            }
        ),
        Test::EveryAtMost { bound } => format!("every {col} of {} ≤ {}", d.encoder, fmt3(*bound)),
        Test::EveryAtLeast { bound } => format!("every {col} of {} ≥ {}", d.encoder, fmt3(*bound)),
        Test::Equal { tolerance, abs_tolerance } => format!(
            "{} and {base} {col} agree within {} relative (differences ≤ {} count as equal)",
            d.encoder,
            fmt3(*tolerance),
            fmt3(*abs_tolerance)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::claims::declaration::parse;
    use std::path::Path;

    /// A paper with one claim of the given checks, and a table with maps m1..m3 (m1, m2 the
    /// "paper" set): encoder `a` against `b`.
    fn paper(checks: &str, rollup: &str) -> Paper {
        let text = format!(
            "title='T'\nauthors='A'\nvenue='V'\norder=1\n[map_sets]\npaper=['m1','m2']\n[[claim]]\nid='X1'\nsays='s'\n\
             paper_figure='p'\ncriterion='c'\nrollup='{rollup}'\n{checks}"
        );
        parse("t", &text, Path::new("t.toml")).unwrap()
    }

    fn table() -> Evidence {
        // a/b ratios: m1 0.5, m2 0.8, m3 1.5; m4 baseline 1e-9 (ratio 1e6).
        let csv = "map,encoder,metric,rmse\nm1,a,exact,0.5\nm1,b,exact,1\nm2,a,exact,0.8\nm2,b,exact,1\n\
                   m3,a,exact,3\nm3,b,exact,2\nm4,a,exact,0.001\nm4,b,exact,1e-9\nm1,a,peer,9\nm1,b,peer,1\n";
        Evidence::parse(csv.as_bytes(), Path::new("t.csv")).unwrap()
    }

    fn judge(checks: &str, rollup: &str) -> ClaimOutcome {
        let p = paper(checks, rollup);
        let t = table();
        judge_claim(&p, &p.claims[0], &|_| Ok(t.clone()))
    }

    const CHECK: &str = "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nbaseline='b'\nwhere={metric='exact'}\n";

    #[test]
    fn every_ratio_on_two_sets_gives_partly_when_only_the_paper_set_holds() {
        let o = judge(&format!("{CHECK}test='ratio_every'\nfloor=1e-6\non=['paper','all']"), "all");
        assert_eq!(o.verdict.word(), "partly", "{:?}", o.verdict);
        assert!(o.verdict.why().contains("held only on the narrower map set"), "{}", o.verdict.why());
        let all = &o.checks[0].sets[1];
        // m4 is left out by the floor and counted.
        assert_eq!(all.values.len(), 3);
        assert_eq!(all.excluded, 1);
        assert!(all.figure.contains("1 with b rmse ≤ floor"), "{}", all.figure);
        assert_eq!(o.checks[0].sets[0].status, Status::Pass);
    }

    #[test]
    fn a_claim_fails_on_a_constructed_table() {
        let o = judge(&format!("{CHECK}test='ratio_every'\nbelow=0.4\nfloor=1e-6"), "all");
        assert_eq!(o.verdict.word(), "fails");
        assert_eq!(o.checks[0].sets[0].values.iter().filter(|v| v.pass).count(), 0);
    }

    #[test]
    fn ratio_statistics_are_never_a_mean_of_ratios() {
        // Ratio of means over m1..m3: (0.5 + 0.8 + 3) / (1 + 1 + 2) = 1.075; median 0.8.
        let rom = judge(
            &format!("{CHECK}test='ratio_stat'\nstatistic='ratio_of_means'\nmin=1.07\nmax=1.08\nfloor=1e-6"),
            "all",
        );
        assert_eq!(rom.verdict, Verdict::Holds, "{}", rom.checks[0].sets[0].figure);
        let med = judge(&format!("{CHECK}test='ratio_stat'\nstatistic='median_ratio'\nmax=0.8\nfloor=1e-6"), "all");
        assert_eq!(med.verdict, Verdict::Holds);
        // Without the floor, m4 (1e6) joins: the median moves to (0.8 + 1.5)/2, the ratio of
        // means stays ≈ 1.075 — a near-zero baseline cannot dominate it.
        let nf = judge(&format!("{CHECK}test='ratio_stat'\nstatistic='ratio_of_means'\nmax=1.1"), "all");
        assert_eq!(nf.verdict, Verdict::Holds, "{}", nf.checks[0].sets[0].figure);
        let nm = judge(&format!("{CHECK}test='ratio_stat'\nstatistic='median_ratio'\nmax=0.8"), "all");
        assert_eq!(nm.verdict.word(), "fails");
    }

    #[test]
    fn bounds_some_equal_and_anchors() {
        let at = "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nwhere={metric='exact'}\n";
        assert_eq!(judge(&format!("{at}test='every_at_most'\nbound=3"), "all").verdict, Verdict::Holds);
        assert_eq!(judge(&format!("{at}test='every_at_most'\nbound=2"), "all").verdict.word(), "fails");
        assert_eq!(judge(&format!("{at}test='every_at_least'\nbound=0.5"), "all").verdict.word(), "fails");
        assert_eq!(judge(&format!("{CHECK}test='ratio_some'\nbelow=0.6"), "all").verdict, Verdict::Holds);
        assert_eq!(judge(&format!("{CHECK}test='equal'\ntolerance=0.01"), "all").verdict.word(), "fails");
        // An anchor that fails does not count; a required check that passes decides.
        let o = judge(
            &format!("{CHECK}test='ratio_some'\nbelow=0.6\n{CHECK}test='ratio_every'\nbelow=0.1\nrole='anchor'"),
            "all",
        );
        assert_eq!(o.verdict, Verdict::Holds);
        // Two required checks, one failing: partly under `all`, holds under `any`.
        let two = format!("{CHECK}test='ratio_some'\nbelow=0.6\n{CHECK}test='ratio_every'\nbelow=0.1");
        assert_eq!(judge(&two, "all").verdict.word(), "partly");
        assert_eq!(judge(&two, "any").verdict, Verdict::Holds);
    }

    #[test]
    fn missing_data_is_untestable_never_passed() {
        let p = paper(&format!("{CHECK}test='ratio_every'"), "all");
        let o = judge_claim(&p, &p.claims[0], &|_| Err("results/e/table.csv: not found".into()));
        assert_eq!(o.verdict.word(), "untestable");
        assert!(o.verdict.why().contains("not found"));
        // A set whose maps are absent from the table.
        let p = paper(&format!("{CHECK}test='ratio_every'\non=['paper']\nmaps=['m1','m2']"), "all");
        let t = Evidence::parse(b"map,encoder,metric,rmse\nm1,a,exact,1\nm1,b,exact,2\n", Path::new("t")).unwrap();
        let o = judge_claim(&p, &p.claims[0], &|_| Ok(t.clone()));
        assert_eq!(o.verdict.word(), "untestable");
        assert!(o.verdict.why().contains("m2"), "{}", o.verdict.why());
        // A column the table does not have.
        let o = judge(&format!("{CHECK}test='ratio_every'\ncolumn='speed'"), "all");
        assert!(o.verdict.why().contains("no column 'speed'"), "{}", o.verdict.why());
    }
}
