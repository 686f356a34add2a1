//! The cells of every table read back (result tables, summaries, sweeps, claims measurements:
//! by `report`, `check`, `claims` and the regression baselines). A committed table may have
//! been edited: a cell "nan" once reached the report's pages and an rmse of 1e300 made a chart
//! hang. Every cell that reads as a number must be finite with |x| ≤ [`MAX_CELL`], except that
//! a relative-error column may hold the saturated value `reference::metrics` writes where the
//! reference is zero everywhere (`f64::MAX`, or a mean over at most 2²⁰ rows of values that
//! include it: at least [`SATURATED_MIN`]). A bad cell is refused as `FILE:LINE:COLUMN:`.
//! A cell that does not read as a number is text (names, descriptions; `nonfinite`, the loud
//! marker `pipeline::table::num` writes, stays text and is never drawn as a number).

use anyhow::{bail, Result};
use std::path::Path;

/// The largest magnitude a numeric cell may hold (the probe files' bound, `MAX_PROBE_VALUE`).
pub const MAX_CELL: f64 = 1e30;

/// The smallest saturated relative error: `f64::MAX` over 2²⁰ (a mean of up to 2²⁰ rows, one
/// of them saturated, is at least this).
pub const SATURATED_MIN: f64 = f64::MAX / 1_048_576.0;

/// Whether `column` is a relative error that may hold the saturated value (`rel_rmse`,
/// `mean_rel_rmse`, `worst_rel_rmse`).
fn may_saturate(column: &str) -> bool {
    column.ends_with("rel_rmse")
}

/// Why `cell` of `column` is not a cell a table may hold, or `None`.
pub fn fault(column: &str, cell: &str) -> Option<String> {
    let Ok(x) = cell.trim().parse::<f64>() else { return None };
    if !x.is_finite() {
        return Some(format!("'{cell}' is not a finite number"));
    }
    if x.abs() <= MAX_CELL || (may_saturate(column) && x >= SATURATED_MIN) {
        return None;
    }
    let allowed = if may_saturate(column) { " (or the saturated value, at least f64::MAX/2^20)" } else { "" };
    Some(format!("'{cell}' is out of range: a table's numbers lie within ±{MAX_CELL:e}{allowed}"))
}

/// Refuses the first bad cell of one record, at line `line` of `origin`: `FILE:LINE:COLUMN:
/// column 'NAME': …` (COLUMN counts from 1).
pub fn check_record<'a>(
    origin: &Path,
    line: u64,
    columns: &[String],
    cells: impl IntoIterator<Item = &'a str>,
) -> Result<()> {
    for (i, (name, cell)) in columns.iter().zip(cells).enumerate() {
        if let Some(why) = fault(name, cell) {
            bail!("{}:{line}:{}: column '{name}': {why}", origin.display(), i + 1);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cols(c: &[&str]) -> Vec<String> {
        c.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn numbers_are_finite_and_bounded() {
        for ok in ["0", "1e30", "-1e30", "0.25", "1e-300", "sh2", "", "nonfinite", "256x128"] {
            assert_eq!(fault("rmse", ok), None, "{ok}");
        }
        for bad in ["nan", "NaN", "inf", "-inf", "infinity", "1.000e300", "1.0000001e30", "-2e31"] {
            assert!(fault("rmse", bad).is_some(), "{bad}");
        }
    }

    /// The saturated relative error, as `reference::metrics` writes it and as a summary's mean
    /// over six rows holds it (both in the committed tables), and nothing between.
    #[test]
    fn only_the_saturated_relative_error_passes_the_bound() {
        let max = crate::pipeline::table::num(f64::MAX);
        let mean_of_six = crate::pipeline::table::num(f64::MAX / 6.0);
        for ok in [max.as_str(), mean_of_six.as_str(), "1.7976931348623157e308", "2.9961552247705263e307"] {
            assert_eq!(fault("rel_rmse", ok), None, "{ok}");
            assert_eq!(fault("mean_rel_rmse", ok), None, "{ok}");
            assert!(fault("rmse", ok).is_some(), "{ok}");
        }
        for bad in ["1e31", "1e300", "-1.7976931348623157e308", "inf"] {
            assert!(fault("rel_rmse", bad).is_some(), "{bad}");
        }
        let tiny = SATURATED_MIN / 2.0;
        assert!(fault("rel_rmse", &tiny.to_string()).is_some());
    }

    #[test]
    fn errors_give_file_line_and_column() {
        let c = cols(&["map", "encoder", "rmse"]);
        let e = check_record(Path::new("t.csv"), 7, &c, ["m", "sh2", "nan"]).unwrap_err().to_string();
        assert!(e.starts_with("t.csv:7:3: column 'rmse':"), "{e}");
    }
}
