//! Baselines: the committed tables under `results/<experiment>/`, the comparison of a fresh
//! table with one (the files are written together by `io::atomic::write_set`).
//!
//! Tables are compared as CSV text, column by column by name, so columns added later (timings,
//! new scores) are handled without code here knowing them. Rows are matched by their key
//! ([`KEY_COLUMNS`]); every other cell is compared under its [`Tolerance`]: numbers within
//! tolerance, text exactly. The `diagnostics` cell (`key=value;…`) is compared one key at a
//! time, as columns named `diagnostics.<key>`.

use crate::regression::tolerance::Tolerance;
use anyhow::{Context, Result};
use std::collections::HashMap;
use std::fmt;
use std::path::Path;

/// The table's file name inside `results/<experiment>/`.
pub const TABLE: &str = "table.csv";

/// The columns that identify a row (those present in a table are used).
pub const KEY_COLUMNS: &[&str] = &["map", "encoder", "domain", "effects", "metric"];

/// A baseline table: CSV as text, the header and the records
/// ([`CsvText`](crate::pipeline::table::CsvText), which parses it).
pub use crate::pipeline::table::CsvText as Table;

impl Table {
    /// Reads a table file.
    pub fn read(path: &Path) -> Result<Table> {
        let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
        Self::parse(&bytes, path)
    }

    /// The row keys, in row order; identical keys get ordinals 1, 2, … in order of appearance.
    pub fn keys(&self) -> Vec<RowKey> {
        let idx: Vec<Option<usize>> = KEY_COLUMNS.iter().map(|k| self.col(k)).collect();
        let mut seen: HashMap<[String; 5], usize> = HashMap::new();
        self.rows
            .iter()
            .map(|r| {
                let f: [String; 5] = std::array::from_fn(|i| idx[i].map(|c| r[c].clone()).unwrap_or_default());
                let n = seen.entry(f.clone()).or_insert(0);
                let ordinal = *n;
                *n += 1;
                let [map, encoder, domain, effects, metric] = f;
                RowKey { map, encoder, domain, effects, metric, ordinal }
            })
            .collect()
    }

    /// The comparable cells of row `i`: every non-key column, with `diagnostics` split into
    /// `diagnostics.<key>` cells.
    fn cells(&self, i: usize) -> Vec<(String, String)> {
        let mut out = Vec::new();
        for (c, v) in self.columns.iter().zip(&self.rows[i]) {
            if KEY_COLUMNS.contains(&c.as_str()) {
                continue;
            }
            if c == "diagnostics" {
                for item in v.split(';').filter(|s| !s.is_empty()) {
                    match item.split_once('=') {
                        Some((k, x)) => out.push((format!("diagnostics.{k}"), x.to_string())),
                        None => out.push((format!("diagnostics.{item}"), String::new())),
                    }
                }
            } else {
                out.push((c.clone(), v.clone()));
            }
        }
        out
    }
}

/// What identifies a row: map, encoder, domain, effects, metric (and an ordinal when a table
/// repeats a key).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct RowKey {
    /// The map's name.
    pub map: String,
    /// The encoder's name in the table.
    pub encoder: String,
    /// The domain label.
    pub domain: String,
    /// The effects label.
    pub effects: String,
    /// The metric's name.
    pub metric: String,
    /// 0 for the first row with this key, 1 for the second, and so on.
    pub ordinal: usize,
}

impl fmt::Display for RowKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}  {}  {}", self.map, self.encoder, self.domain)?;
        if !self.effects.is_empty() && self.effects != "none" {
            write!(f, " [{}]", self.effects)?;
        }
        write!(f, "  {}", self.metric)?;
        if self.ordinal > 0 {
            write!(f, " #{}", self.ordinal + 1)?;
        }
        Ok(())
    }
}

/// One difference between a baseline table and a fresh one.
#[derive(Clone, Debug, PartialEq)]
pub enum Change {
    /// A number moved beyond its tolerance. `rel` = (new − old)/|old| (infinite when old = 0).
    Moved {
        /// The row.
        key: RowKey,
        /// The column's name.
        column: String,
        /// The baseline's cell text.
        old: String,
        /// The fresh cell text.
        new: String,
        /// (new − old)/|old|; infinite when old = 0.
        rel: f64,
        /// The tolerance the move exceeded.
        tolerance: Tolerance,
    },
    /// A text cell (or a number that became text, or the reverse) changed.
    Text {
        /// The row.
        key: RowKey,
        /// The column's name.
        column: String,
        /// The baseline's cell text.
        old: String,
        /// The fresh cell text.
        new: String,
    },
    /// A row only the fresh table has.
    RowAdded(RowKey),
    /// A row only the baseline has.
    RowRemoved(RowKey),
    /// A column only the fresh table has.
    ColumnAdded(String),
    /// A column only the baseline has.
    ColumnRemoved(String),
}

impl fmt::Display for Change {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Change::Moved { key, column, old, new, rel, tolerance } => {
                let rel = if rel.is_finite() { format!("{rel:+.3e} relative") } else { "from 0".to_string() };
                write!(f, "moved    {key}  {column}  {old} -> {new}  ({rel}; tolerance {tolerance})")
            }
            Change::Text { key, column, old, new } => write!(f, "changed  {key}  {column}  '{old}' -> '{new}'"),
            Change::RowAdded(k) => write!(f, "row added    {k}"),
            Change::RowRemoved(k) => write!(f, "row removed  {k}"),
            Change::ColumnAdded(c) => write!(f, "column added    {c}"),
            Change::ColumnRemoved(c) => write!(f, "column removed  {c}"),
        }
    }
}

impl Change {
    /// The change as JSON (`check --format json`): `kind` (`moved`, `text`, `row_added`,
    /// `row_removed`, `column_added`, `column_removed`), the row and column where they apply,
    /// the old and new cell texts, the relative move (`null` from 0) and the tolerance, and
    /// `text`, the sentence the text format prints.
    pub fn to_json(&self) -> serde_json::Value {
        let mut v = match self {
            Change::Moved { key, column, old, new, rel, tolerance } => serde_json::json!({
                "kind": "moved", "row": key.to_string(), "column": column, "old": cell(old), "new": cell(new),
                "rel": rel.is_finite().then_some(*rel),
                "tolerance": match tolerance {
                    Tolerance::Within { rel, abs } => serde_json::json!({ "rel": rel, "abs": abs }),
                    Tolerance::Ignore => serde_json::Value::Null,
                },
            }),
            Change::Text { key, column, old, new } => serde_json::json!({
                "kind": "text", "row": key.to_string(), "column": column, "old": cell(old), "new": cell(new),
            }),
            Change::RowAdded(k) => serde_json::json!({ "kind": "row_added", "row": k.to_string() }),
            Change::RowRemoved(k) => serde_json::json!({ "kind": "row_removed", "row": k.to_string() }),
            Change::ColumnAdded(c) => serde_json::json!({ "kind": "column_added", "column": c }),
            Change::ColumnRemoved(c) => serde_json::json!({ "kind": "column_removed", "column": c }),
        };
        v["text"] = serde_json::Value::String(self.to_string());
        v
    }
}

/// A cell as JSON: a number when it reads as a finite one, else its text.
fn cell(text: &str) -> serde_json::Value {
    match text.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => serde_json::json!(x),
        _ => serde_json::Value::String(text.to_string()),
    }
}

/// The result of comparing two tables.
#[derive(Clone, Debug, Default)]
pub struct Comparison {
    /// Every difference found.
    pub changes: Vec<Change>,
    /// Rows present in both tables and compared.
    pub rows: usize,
    /// Numeric cells compared (equal, within tolerance, or moved).
    pub numbers: usize,
    /// Numbers that differ but within tolerance.
    pub within: usize,
    /// Cells not compared because their column is ignored.
    pub ignored: usize,
}

/// Compares a fresh table with its baseline. Rows whose map `skip` accepts (missing on this
/// machine, or with a changed checksum) are left out on both sides; `tolerance` gives the rule
/// for a cell of a row (by key and column).
pub fn compare(
    old: &Table,
    new: &Table,
    skip: &dyn Fn(&str) -> bool,
    tolerance: &dyn Fn(&RowKey, &str) -> Tolerance,
) -> Comparison {
    let mut out = Comparison::default();
    for c in &new.columns {
        if !old.columns.contains(c) {
            out.changes.push(Change::ColumnAdded(c.clone()));
        }
    }
    for c in &old.columns {
        if !new.columns.contains(c) {
            out.changes.push(Change::ColumnRemoved(c.clone()));
        }
    }
    // Cells are compared only in columns both tables have (others are reported above).
    let common = |name: &str| {
        let base = if name.starts_with("diagnostics.") { "diagnostics" } else { name };
        old.columns.iter().any(|c| c == base) && new.columns.iter().any(|c| c == base)
    };
    let old_keys = old.keys();
    let old_index: HashMap<&RowKey, usize> = old_keys.iter().enumerate().map(|(i, k)| (k, i)).collect();
    let mut matched = vec![false; old.rows.len()];
    for (ni, key) in new.keys().into_iter().enumerate() {
        if skip(&key.map) {
            continue;
        }
        let Some(&oi) = old_index.get(&key) else {
            out.changes.push(Change::RowAdded(key));
            continue;
        };
        matched[oi] = true;
        out.rows += 1;
        compare_cells(&mut out, &key, (&old.cells(oi), &new.cells(ni)), &common, tolerance);
    }
    for (k, m) in old_keys.into_iter().zip(matched) {
        if !m && !skip(&k.map) {
            out.changes.push(Change::RowRemoved(k));
        }
    }
    out
}

/// A row's cells: (column, value) pairs.
type Cells = [(String, String)];

/// The cells of one row both tables have, `(old, new)` as (column, value) pairs: each number
/// counted and judged against its column's tolerance, each text cell compared exactly.
fn compare_cells(
    out: &mut Comparison,
    key: &RowKey,
    (oc, nc): (&Cells, &Cells),
    common: &dyn Fn(&str) -> bool,
    tolerance: &dyn Fn(&RowKey, &str) -> Tolerance,
) {
    let mut names: Vec<&String> = nc.iter().map(|(n, _)| n).collect();
    names.extend(oc.iter().map(|(n, _)| n).filter(|n| !nc.iter().any(|(m, _)| m == *n)));
    for name in names {
        if !common(name) {
            continue;
        }
        let get = |cells: &[(String, String)]| cells.iter().find(|(n, _)| n == name).map(|(_, v)| v.clone());
        let (ov, nv) = (get(oc).unwrap_or_default(), get(nc).unwrap_or_default());
        let tol = tolerance(key, name);
        if tol == Tolerance::Ignore {
            out.ignored += 1;
            continue;
        }
        let parse = |s: &str| s.parse::<f64>().ok().filter(|v| v.is_finite());
        match (parse(&ov), parse(&nv)) {
            (Some(o), Some(n)) => {
                out.numbers += 1;
                if ov == nv || o == n {
                    continue;
                }
                if tol.accepts(o, n) {
                    out.within += 1;
                } else {
                    let rel = if o != 0.0 { (n - o) / o.abs() } else { f64::INFINITY };
                    out.changes.push(Change::Moved {
                        key: key.clone(),
                        column: name.clone(),
                        old: ov,
                        new: nv,
                        rel,
                        tolerance: tol,
                    });
                }
            }
            _ if ov != nv => {
                out.changes.push(Change::Text { key: key.clone(), column: name.clone(), old: ov, new: nv })
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regression::tolerance::Tolerance;

    const HEADER: &str = "map,encoder,domain,metric,rmse,label,diagnostics\n";

    fn table(rows: &[&str]) -> Table {
        let text = format!("{HEADER}{}", rows.iter().map(|r| format!("{r}\n")).collect::<String>());
        Table::parse(text.as_bytes(), Path::new("t.csv")).unwrap()
    }

    fn diff(old: &Table, new: &Table, tol: Tolerance) -> Comparison {
        compare(old, new, &|_| false, &|_, _| tol)
    }

    /// rel = 2⁻³⁰ about rmse = 1: 1 + 2⁻³⁰ passes, the next double up is reported with the
    /// row key, column, both values and the relative change.
    #[test]
    fn one_ulp_beyond_tolerance_is_reported() {
        let rel = 2f64.powi(-30);
        let tol = Tolerance::Within { rel, abs: 0.0 };
        let base = table(&["m,sh1,sphere,exact,1,a,"]);
        let edge = 1.0 + rel;
        let ok = diff(&base, &table(&[&format!("m,sh1,sphere,exact,{edge},a,")]), tol);
        assert!(ok.changes.is_empty(), "{:?}", ok.changes);
        assert_eq!((ok.numbers, ok.within, ok.rows), (1, 1, 1));
        let beyond = edge.next_up();
        let bad = diff(&base, &table(&[&format!("m,sh1,sphere,exact,{beyond},a,")]), tol);
        assert_eq!(bad.changes.len(), 1);
        match &bad.changes[0] {
            Change::Moved { key, column, old, new, rel: r, .. } => {
                assert_eq!((key.map.as_str(), key.encoder.as_str(), key.metric.as_str()), ("m", "sh1", "exact"));
                assert_eq!((column.as_str(), old.as_str()), ("rmse", "1"));
                assert_eq!(new.parse::<f64>().unwrap(), beyond);
                assert_eq!(*r, beyond - 1.0);
            }
            c => panic!("{c:?}"),
        }
        let line = bad.changes[0].to_string();
        assert!(line.contains("m  sh1  sphere  exact  rmse  1 -> 1.00000000093132"), "{line}");
    }

    #[test]
    fn text_rows_columns_and_diagnostics() {
        let base = table(&["m,sh1,sphere,exact,1,a,iters=3;res=0.5", "m,sh2,sphere,exact,2,a,"]);
        let new = table(&["m,sh1,sphere,exact,1,b,iters=4;res=0.5", "n,sh2,sphere,exact,2,a,"]);
        let c = diff(&base, &new, Tolerance::EXACT);
        let s: Vec<String> = c.changes.iter().map(|c| c.to_string()).collect();
        assert!(s[0].starts_with("changed  m  sh1  sphere  exact  label  'a' -> 'b'"), "{s:?}");
        assert!(s[1].starts_with("moved    m  sh1  sphere  exact  diagnostics.iters  3 -> 4"), "{s:?}");
        assert_eq!(s[2], "row added    n  sh2  sphere  exact");
        assert_eq!(s[3], "row removed  m  sh2  sphere  exact");
        assert_eq!(s.len(), 4);
        // A number that became non-numeric is a text change, whatever the tolerance.
        let nf = diff(&base, &table(&["m,sh1,sphere,exact,nonfinite,a,iters=3;res=0.5", "m,sh2,sphere,exact,2,a,"]), {
            Tolerance::Within { rel: 1.0, abs: 1.0 }
        });
        assert!(matches!(&nf.changes[..], [Change::Text { column, .. }] if column == "rmse"), "{:?}", nf.changes);
    }

    #[test]
    fn columns_added_removed_and_ignored() {
        let base = table(&["m,sh1,sphere,exact,1,a,"]);
        let text = "map,encoder,domain,metric,rmse,diagnostics,fit_ns\nm,sh1,sphere,exact,1,,123\n";
        let new = Table::parse(text.as_bytes(), Path::new("n.csv")).unwrap();
        let c = compare(&base, &new, &|_| false, &|_, col| {
            if col == "fit_ns" {
                Tolerance::Ignore
            } else {
                Tolerance::EXACT
            }
        });
        let s: Vec<String> = c.changes.iter().map(|c| c.to_string()).collect();
        assert_eq!(s, ["column added    fit_ns", "column removed  label"]);
        // Between two tables that both have it, an ignored column never moves.
        let c2 = compare(
            &new,
            &Table {
                rows: vec![vec![
                    "m".into(),
                    "sh1".into(),
                    "sphere".into(),
                    "exact".into(),
                    "1".into(),
                    "".into(),
                    "999".into(),
                ]],
                ..new.clone()
            },
            &|_| false,
            &|_, col| if col == "fit_ns" { Tolerance::Ignore } else { Tolerance::EXACT },
        );
        assert!(c2.changes.is_empty() && c2.ignored == 1, "{:?}", c2.changes);
    }

    #[test]
    fn skipped_maps_and_repeated_keys() {
        let base = table(&["m,sh1,sphere,exact,1,a,", "m,sh1,sphere,exact,2,a,", "gone,sh1,sphere,exact,1,a,"]);
        let new = table(&["m,sh1,sphere,exact,1,a,", "m,sh1,sphere,exact,3,a,"]);
        let c = compare(&base, &new, &|m| m == "gone", &|_, _| Tolerance::EXACT);
        assert_eq!(c.changes.len(), 1, "{:?}", c.changes);
        assert!(c.changes[0].to_string().contains("exact #2  rmse  2 -> 3"), "{}", c.changes[0]);
        // Old zero: the relative change is infinite and said so.
        let z = diff(&table(&["m,sh1,sphere,exact,0,a,"]), &table(&["m,sh1,sphere,exact,1e-300,a,"]), Tolerance::EXACT);
        assert!(z.changes[0].to_string().contains("(from 0;"), "{}", z.changes[0]);
    }

    #[test]
    fn malformed_tables_are_errors_naming_the_file() {
        let e = |s: &str| format!("{:#}", Table::parse(s.as_bytes(), Path::new("bad.csv")).err().unwrap());
        assert!(e("a,b\n1,2,3\n").contains("bad.csv"));
        assert!(e("a,a\n1,2\n").contains("twice"));
        assert!(e("").contains("bad.csv"));
    }
}
