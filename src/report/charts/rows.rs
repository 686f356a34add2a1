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

/// What a chart's error is, read from the table's columns: the unit (`units`, E/π), the
/// reference (`metric` and `reference`), the weighting and the resolutions.
#[derive(Clone, Debug, PartialEq)]
pub struct Measure {
    /// The unit, `E/π` (the `units` column's `E/pi`, or E/π where the table has no such column).
    pub unit: String,
    /// The metric (`exact`, `probulator`), when the table has one.
    pub metric: Option<String>,
    /// The reference as the table states it.
    pub reference: Option<String>,
    /// The weighting (`solid-angle`), when stated.
    pub weighting: Option<String>,
    /// The output resolutions of the rows.
    pub resolution: Vec<String>,
}

impl Measure {
    /// The measure of `rows` of `t` (first non-empty value of each column).
    pub fn of(t: &CsvTable, rows: &[usize]) -> Measure {
        let first = |h: &str| -> Option<String> {
            let c = t.col(h)?;
            rows.iter().map(|&i| t.rows[i][c].clone()).find(|v| !v.is_empty() && v != "-")
        };
        let reference = first("reference").or_else(|| first("error_of"));
        let unit = first("units").unwrap_or_else(|| "E/pi".into()).replace("pi", "π");
        let resolution = t.col("resolution").map(|c| distinct(t, rows, c)).unwrap_or_default();
        Measure {
            unit,
            metric: first("metric"),
            reference,
            weighting: first("weighting"),
            resolution: resolution.into_iter().filter(|r| !r.is_empty() && r != "-").collect(),
        }
    }

    /// What is measured, for an axis: "RMSE of E/π (exact, solid-angle)". The reference is
    /// the `metric`, or where the table has none, its `reference` up to " reference" (a
    /// sweep's "converged reference (1024x512 map, 16 GL nodes)" gives "converged").
    pub fn quantity(&self) -> String {
        let kind =
            self.metric.as_deref().or_else(|| self.reference.as_deref()?.split_once(" reference").map(|(k, _)| k));
        let how: Vec<&str> = [kind, self.weighting.as_deref()].into_iter().flatten().collect();
        if how.is_empty() {
            format!("RMSE of {}", self.unit)
        } else {
            format!("RMSE of {} ({})", self.unit, how.join(", "))
        }
    }

    /// The axis title of a log axis: "RMSE of E/π (exact, solid-angle; log scale)".
    pub fn axis(&self) -> String {
        let q = self.quantity();
        match q.strip_suffix(')') {
            Some(open) => format!("{open}; log scale)"),
            None => format!("{q} (log scale)"),
        }
    }

    /// The caption's statement: "RMSE of E/π against the exact reference (…), solid-angle
    /// weighted, at 128x64".
    pub fn caption(&self) -> String {
        let mut s = format!("RMSE of {}", self.unit);
        match (&self.metric, &self.reference) {
            (Some(m), Some(r)) => s.push_str(&format!(" against the `{m}` reference, {r}")),
            (Some(m), None) => s.push_str(&format!(" against the `{m}` reference")),
            (None, Some(r)) => s.push_str(&format!(" against {r}")),
            (None, None) => {}
        }
        if let Some(w) = &self.weighting {
            s.push_str(&format!(", {w} weighted"));
        }
        if !self.resolution.is_empty() {
            s.push_str(&format!(", at {}", self.resolution.join(", ")));
        }
        s
    }
}
