//! The cost landscape's data: per row of the landscape tables (`results/landscape*/table.csv`)
//! under the `exact` metric, the map, encoder, domain, its family, RMSE and relative RMSE of
//! E/π (solid-angle weighted, the table's resolution), stored scalars and evaluation time (ns
//! per normal, as the table recorded it on the machine that made it). Rows as arrays under one
//! list of columns, numbers to 7 significant digits.

use super::encode::sig7;
use crate::report::csvfile::CsvTable;
use crate::report::style::style_of;
use serde_json::{json, Value};

/// The table columns each point carries, in order (then its family).
const COLUMNS: [&str; 7] = ["map", "encoder", "domain", "rmse", "rel_rmse", "stored_scalars", "eval_ns"];

/// The points of every table in `tables` (folder name, table): rows of the `exact` metric with
/// a finite RMSE.
pub(super) fn landscape_data(tables: &[(String, CsvTable)]) -> Value {
    let mut rows = Vec::new();
    let mut resolutions = serde_json::Map::new();
    for (folder, t) in tables {
        let cols: Vec<Option<usize>> = COLUMNS.iter().map(|c| t.col(c)).collect();
        let (metric, resolution) = (t.col("metric"), t.col("resolution"));
        for r in &t.rows {
            if metric.is_some_and(|c| r[c] != "exact") {
                continue;
            }
            let cell = |k: usize| cols[k].map(|c| r[c].as_str()).unwrap_or("");
            let num = |k: usize| cell(k).parse::<f64>().ok().filter(|v| v.is_finite()).map(sig7);
            let Some(rmse) = num(3) else { continue };
            if let Some(c) = resolution {
                resolutions.insert(folder.clone(), Value::String(r[c].clone()));
            }
            let family = style_of(cell(1)).family.label();
            rows.push(json!([folder, cell(0), cell(1), cell(2), rmse, num(4), num(5), num(6), family]));
        }
    }
    json!({
        "columns": ["table", "map", "encoder", "domain", "rmse", "rel_rmse", "stored_scalars", "eval_ns", "family"],
        "resolution": resolutions,
        "rows": rows,
    })
}
