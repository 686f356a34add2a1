//! The claims view's data: CLAIMS.csv as the claims engine wrote it (id, kind, verdict, the
//! paper's figure and ours, the criterion, the maps, the evidence page), one object per claim,
//! and per claim id its figure and explorer preset (`claims_evidence`).

use crate::report::csvfile::CsvTable;
use serde_json::{json, Value};

/// The claims of `table` (CLAIMS.csv), each as an object keyed by the table's columns, and
/// `evidence` (per claim id: `figure` and `preset`).
pub(super) fn claims_data(table: Option<&CsvTable>, evidence: Value) -> Value {
    let Some(t) = table else { return json!({ "claims": [], "evidence": evidence }) };
    let claims: Vec<Value> = t
        .rows
        .iter()
        .map(|r| {
            let o: serde_json::Map<String, Value> =
                t.headers.iter().zip(r).map(|(h, v)| (h.clone(), Value::String(v.clone()))).collect();
            Value::Object(o)
        })
        .collect();
    json!({ "claims": claims, "evidence": evidence })
}
