//! `probelab check --format json`'s document (`docs/json.md`, `probelab.check/1`): the
//! overall verdict, the maps the experiments read with their identities, each experiment's
//! counts and findings (`regression::check`), and the claims' verdict when they were checked.

use super::json::{self, MapEntry};
use crate::regression::check::CheckSummary;
use crate::regression::claims::ClaimsRun;
use anyhow::Result;
use serde_json::{json, Value};

/// The document: `summary` when experiments were checked, `claims` when the claims were.
pub fn to_json(summary: Option<&CheckSummary>, claims: Option<&ClaimsRun>) -> Result<String> {
    let mut doc = json!({
        "schema": json::CHECK,
        "passed": true,
        "maps": [],
        "experiments": [],
        "not_checked": [],
        "numbers": 0,
        "moved": 0,
        "unchecked_maps": 0,
        "seconds": 0.0,
    });
    if let Some(s) = summary {
        if let (Value::Object(doc), Value::Object(from)) = (&mut doc, &s.json) {
            doc.extend(from.iter().map(|(k, v)| (k.clone(), v.clone())));
        }
        let maps: Vec<MapEntry> = s.maps.iter().map(MapEntry::from_info).collect();
        doc["maps"] = json::maps(&maps);
    }
    if let Some(run) = claims {
        doc["claims"] = run.to_json(true);
        doc["passed"] = Value::Bool(doc["passed"].as_bool().unwrap_or(true) && run.passed(true));
    }
    json::text(&doc)
}
