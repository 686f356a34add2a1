//! The rows a table chart reads: the chart's metric, and a column's values in first-seen order.

use super::super::csvfile::CsvTable;

/// The rows a table chart uses: those of metric `exact` when a `metric` column exists and has
/// such rows, else those of the first metric listed. Returns the rows and the metric's name.
pub(super) fn metric_rows(t: &CsvTable) -> (Vec<usize>, Option<String>) {
    let Some(mc) = t.col("metric") else { return ((0..t.rows.len()).collect(), None) };
    let pick = if t.rows.iter().any(|r| r[mc] == "exact") {
        "exact".to_string()
    } else {
        t.rows.first().map(|r| r[mc].clone()).unwrap_or_default()
    };
    ((0..t.rows.len()).filter(|&i| t.rows[i][mc] == pick).collect(), Some(pick))
}

/// Values first-seen order.
pub(super) fn distinct(t: &CsvTable, rows: &[usize], col: usize) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for &i in rows {
        if !out.contains(&t.rows[i][col]) {
            out.push(t.rows[i][col].clone());
        }
    }
    out
}
