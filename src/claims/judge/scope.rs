//! The rows a check reads in an evidence table: its encoder's and its baseline's, those in
//! scope of its `where` filters and maps, labelled and matched on the key columns.

use crate::claims::declaration::CheckDecl;
use crate::claims::judge::outcome::Evidence;
use crate::claims::population::Population;
use crate::math::echo::value as echo;
use anyhow::{bail, Context, Result};
use std::collections::HashMap;

/// The columns that identify a row besides its encoder (those present in a table are used).
pub const KEY_COLUMNS: &[&str] = &["map", "domain", "effects", "metric", "case"];

/// A row of the check: its label, map and value of the judged column (None: empty cell).
pub(super) struct Picked<'a> {
    /// The row's cells.
    pub(super) row: &'a [String],
    /// Its key as text.
    pub(super) label: String,
    /// Its map (empty in a table without maps).
    pub(super) map: String,
    /// The judged cell (None: empty).
    pub(super) value: Option<f64>,
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
pub(super) struct Scope<'a> {
    t: &'a Evidence,
    /// The check.
    pub(super) k: &'a CheckDecl,
    population: Population<'a>,
    enc_col: usize,
    val_col: usize,
    /// The map column, if the table has one.
    pub(super) map_col: Option<usize>,
    filters: Vec<(usize, &'a Vec<String>)>,
    keys: Vec<usize>,
}

impl<'a> Scope<'a> {
    /// The check's columns in `t`; an error names a column the table lacks.
    pub(super) fn new(t: &'a Evidence, k: &'a CheckDecl, population: Population<'a>) -> Result<Self> {
        let enc_col = t.col("encoder").context("the table has no 'encoder' column")?;
        let Some(val_col) = t.col(&k.column) else { bail!("the table has no column '{}'", echo(&k.column)) };
        let map_col = t.col("map");
        let mut filters = Vec::new();
        for (name, allowed) in &k.filter {
            let Some(c) = t.col(name) else { bail!("where.{n}: the table has no column '{n}'", n = echo(name)) };
            filters.push((c, allowed));
        }
        let keys: Vec<usize> = KEY_COLUMNS.iter().filter_map(|c| t.col(c)).collect();
        Ok(Scope { t, k, population, enc_col, val_col, map_col, filters, keys })
    }

    /// Whether a row passes the filters and lies on the set's and the check's maps. A
    /// baseline row is not held to a filter on the encoder column (which picks the judged
    /// encoders, as in `encoder = "*"` with `where = { encoder = [...] }`).
    fn in_scope(&self, r: &[String], baseline: bool) -> bool {
        self.filters.iter().all(|(c, allowed)| (baseline && *c == self.enc_col) || allowed.contains(&r[*c]))
            && self
                .map_col
                .is_none_or(|m| self.population.holds(&r[m]) && self.k.maps.as_ref().is_none_or(|s| s.contains(&r[m])))
    }

    /// The judged cell of a row of `encoder` (`*`: any) in scope; None for other rows, an
    /// error for a cell that is not a number.
    fn cell(&self, r: &[String], encoder: &str) -> Option<Result<Cell>> {
        let baseline = encoder != self.k.encoder;
        if (encoder != "*" && r[self.enc_col] != encoder) || !self.in_scope(r, baseline) {
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
    pub(super) fn key_of(&self, r: &[String]) -> Vec<String> {
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
    pub(super) fn picked(&self) -> Result<Vec<Picked<'a>>> {
        let mut picked = Vec::new();
        for r in &self.t.rows {
            if let Some(value) = self.value(r, &self.k.encoder, "") {
                let label = match self.k.encoder.as_str() {
                    "*" => format!("{} · {}", r[self.enc_col], self.label(r)),
                    _ => self.label(r),
                };
                picked.push(Picked {
                    row: r,
                    label,
                    map: self.map_col.map(|m| r[m].clone()).unwrap_or_default(),
                    value: value?,
                });
            }
        }
        Ok(picked)
    }

    /// The baseline encoder's values in scope, by row key.
    pub(super) fn baseline_rows(&self, base: &str) -> Result<HashMap<Vec<String>, Option<f64>>> {
        let mut rows = HashMap::new();
        for r in &self.t.rows {
            if let Some(value) = self.value(r, base, &format!(" of '{base}'")) {
                rows.insert(self.key_of(r), value?);
            }
        }
        Ok(rows)
    }
}
