//! The figures printed under a sheet's rows (the table's `exact` rmse, rel_rmse, neg_frac),
//! read from the experiment's table or scored, and what a sheet drew ([`SheetScores`]).

use super::super::csvfile::CsvTable;
use crate::pipeline::runner::Case;
use crate::reference::metrics::Scores;

/// The figures printed under a row: the table's `exact` rmse, rel_rmse and neg_frac.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowFigures {
    /// The RMSE of E/π over the case's domain.
    pub rmse: f64,
    /// `rmse` divided by the RMS of the reference E/π (dimensionless).
    pub rel_rmse: f64,
    /// The weighted fraction of output normals where the encoder is negative in any channel.
    pub neg_frac: f64,
}

impl From<&Scores> for RowFigures {
    fn from(s: &Scores) -> Self {
        RowFigures { rmse: s.rmse, rel_rmse: s.rel_rmse, neg_frac: s.neg_frac }
    }
}

/// What a sheet drew: the case and each encoder's figures, and where they came from.
#[cfg_attr(not(test), allow(dead_code, reason = "the unit tests read what each sheet figure came from"))]
pub struct SheetScores {
    /// The case drawn: its domain label (`sphere`, `hemisphere:+y`).
    pub case_label: String,
    /// Each encoder's name and figures, in the experiment's order.
    pub figures: Vec<(String, RowFigures)>,
    /// "table.csv" or "computed".
    pub source: &'static str,
}

/// The figures of every encoder for `case` on `map` from a results table, in `metric` (its
/// `metric` column), if the table has a row for each.
pub fn figures_from_table(
    t: &CsvTable,
    map: &str,
    case: &Case,
    names: &[String],
    metric: &str,
) -> Option<Vec<RowFigures>> {
    let cols = t.require(&["map", "encoder", "domain", "effects", "metric", "rmse", "rel_rmse", "neg_frac"]).ok()?;
    let [mc, ec, dc, fc, xc, rc, lc, nc] = cols[..] else { return None };
    names
        .iter()
        .map(|name| {
            let i = (0..t.rows.len()).find(|&i| {
                let r = &t.rows[i];
                r[mc] == map
                    && r[ec] == *name
                    && r[dc] == case.domain_label
                    && r[fc] == case.effects_label
                    && r[xc] == metric
            })?;
            Some(RowFigures { rmse: t.num(i, rc).ok()??, rel_rmse: t.num(i, lc).ok()??, neg_frac: t.num(i, nc).ok()?? })
        })
        .collect()
}
