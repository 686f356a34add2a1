//! The guard that keeps `run`/`reproduce` off a moved baseline: a run's table written where
//! none exists, left as it is when nothing moved, refused when something did ([`store`]); a
//! run on only some of its maps compared on those and never written ([`check_partial`]); and
//! the rows a table that stood is summarised from ([`rows_as_stored`]).

use crate::pipeline::experiment::Experiment;
use crate::pipeline::runner::RunReport;
use crate::regression::baseline::{Table, TABLE};
use crate::regression::bless::baseline_files;
use crate::regression::check::{compare_with_baseline, ExperimentCheck, MapPolicy};
use crate::regression::tolerance::Tolerances;
use anyhow::Result;
use std::path::Path;

/// What `run`/`reproduce` did with an experiment's table.
pub enum Stored {
    /// No baseline existed: table and provenance written.
    New,
    /// A baseline exists and nothing moved: left untouched.
    Unchanged(ExperimentCheck),
    /// A baseline exists and something moved: nothing written.
    Refused(ExperimentCheck),
}

impl Stored {
    /// Whether the table stands (written new, or unchanged); false when refused.
    pub fn stands(&self) -> bool {
        !matches!(self, Stored::Refused(_))
    }
}

/// The overwrite guard of `run`/`reproduce`: writes `<out>/<name>/` when it holds no table;
/// otherwise compares and writes nothing (see [`Stored`]). The run must have found every map.
pub fn store(out: &Path, root: &Path, exp: &Experiment, report: &RunReport) -> Result<Stored> {
    let dir = out.join(&exp.name);
    if !dir.join(TABLE).exists() {
        crate::io::atomic::write_set(&dir, &baseline_files(exp, report, root)?)?;
        return Ok(Stored::New);
    }
    let c = compare_with_baseline(&dir, exp, report, &Tolerances::load(root)?, MapPolicy::RequireAll)?;
    Ok(if c.passed() { Stored::Unchanged(c) } else { Stored::Refused(c) })
}

/// What `reproduce` did with an experiment run on only some of its maps: nothing is written
/// either way, since a baseline holds every map.
pub enum PartialCheck {
    /// No baseline to compare with (a note, not a failure).
    NoBaseline,
    /// The rows of the maps found compared with the baseline.
    Compared(Box<ExperimentCheck>),
}

impl PartialCheck {
    /// False when a number moved (or the baseline is unusable): `reproduce` then fails.
    pub fn passed(&self) -> bool {
        match self {
            PartialCheck::NoBaseline => true,
            PartialCheck::Compared(c) => c.passed(),
        }
    }

    /// The baseline's rows of the maps missing (not compared).
    pub fn unchecked_rows(&self) -> usize {
        match self {
            PartialCheck::NoBaseline => 0,
            PartialCheck::Compared(c) => c.unchecked_rows,
        }
    }
}

/// `reproduce` on an experiment some of whose maps are not on the search path: the rows of
/// the maps found are compared with the committed baseline in `<out>/<name>/` (the missing
/// maps' rows are not, [`compare_with_baseline`] with [`MapPolicy::AllowMissing`]); nothing is
/// written. The tolerances are read from `root` only when there is a baseline to compare with.
pub fn check_partial(out: &Path, root: &Path, exp: &Experiment, report: &RunReport) -> Result<PartialCheck> {
    let dir = out.join(&exp.name);
    if !dir.join(TABLE).exists() {
        return Ok(PartialCheck::NoBaseline);
    }
    let c = compare_with_baseline(&dir, exp, report, &Tolerances::load(root)?, MapPolicy::AllowMissing)?;
    Ok(PartialCheck::Compared(Box::new(c)))
}

/// The fresh rows with their scores replaced by the stored table's (`<dir>/table.csv`), for a
/// run whose table stood within tolerance: what the run writes next to the table (summaries,
/// claims) is then derived from the table actually kept, and does not drift in the last digits
/// when code changes move numbers below tolerance. Rows the table lacks, and cells that are
/// empty or not numbers, keep their fresh values.
pub fn rows_as_stored(dir: &Path, rows: &[crate::pipeline::table::Row]) -> Result<Vec<crate::pipeline::table::Row>> {
    let stored = Table::read(&dir.join(TABLE))?;
    let fresh = Table::parse(&crate::pipeline::table::to_csv(rows)?, &dir.join(TABLE))?;
    let index: std::collections::HashMap<_, usize> =
        stored.keys().into_iter().enumerate().map(|(i, k)| (k, i)).collect();
    let col = |name: &str| stored.columns.iter().position(|c| c == name);
    let cols =
        ["rmse_r", "rmse_g", "rmse_b", "rmse", "rel_rmse", "neg_frac", "max_abs_err", "at_normal_abs_err"].map(col);
    let mut out = rows.to_vec();
    for (row, key) in out.iter_mut().zip(fresh.keys()) {
        let Some(&i) = index.get(&key) else { continue };
        let cell = |c: Option<usize>| c.and_then(|c| stored.rows[i].get(c)).and_then(|v| v.parse::<f64>().ok());
        let s = &mut row.scores;
        let [r, g, b] = &mut s.rmse_rgb;
        let targets: [&mut f64; 7] = [r, g, b, &mut s.rmse, &mut s.rel_rmse, &mut s.neg_frac, &mut s.max_abs];
        for (t, c) in targets.into_iter().zip(cols) {
            if let Some(v) = cell(c) {
                *t = v;
            }
        }
        if row.at_normal_abs_err.is_some() {
            if let Some(v) = cell(cols[7]) {
                row.at_normal_abs_err = Some(v);
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A table that stood is what the summaries are computed from: the fresh rows' scores are
    /// replaced cell by cell (round-trip text, so exactly), unknown rows and empty cells kept.
    #[test]
    fn rows_as_stored_takes_the_kept_tables_numbers() {
        use crate::pipeline::table::Row;
        use crate::reference::metrics::Scores;
        let row = |map: &str, rmse: f64, at_n: Option<f64>| Row {
            map: map.into(),
            encoder: "sh1".into(),
            domain: "sphere".into(),
            metric: "exact".into(),
            scores: Scores { rmse_rgb: [rmse; 3], rmse, rel_rmse: 2.0 * rmse, neg_frac: 0.0, max_abs: 3.0 * rmse },
            stored_scalars: 12,
            orientation_set: String::new(),
            effects: String::new(),
            weighting: "solid_angle".into(),
            resolution: "8x4".into(),
            units: "E/pi".into(),
            reference: "exact".into(),
            diagnostics: String::new(),
            at_normal_abs_err: at_n,
            fit_ns: None,
            eval_ns: None,
        };
        let d = tempfile::tempdir().unwrap();
        let kept = vec![row("a", 0.1, Some(1e-3)), row("b", 0.2, None)];
        crate::pipeline::table::write_csv(&d.path().join(TABLE), &kept).unwrap();
        let nudged = |r: &Row| {
            let mut r = r.clone();
            r.scores.rmse *= 1.0 + 1e-13;
            r.scores.max_abs *= 1.0 + 1e-13;
            r.at_normal_abs_err = r.at_normal_abs_err.map(|v| v * 1.5);
            r
        };
        let fresh = vec![nudged(&kept[0]), nudged(&kept[1]), row("new", 0.3, None)];
        assert_ne!(fresh[0], kept[0]);
        let got = rows_as_stored(d.path(), &fresh).unwrap();
        assert_eq!(got[0], kept[0]);
        assert_eq!(got[1], kept[1]);
        assert_eq!(got[2], fresh[2]);
    }
}
