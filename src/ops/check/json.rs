//! `probelab check --format json`'s document (`docs/json.md`, `probelab.check/1`): the
//! overall verdict, the maps the experiments read with their identities, each experiment's
//! counts and findings (`regression::check`), and the claims' verdict when they were checked.

use super::CheckOutcome;
use crate::ops::json::{self, MapEntry};
use crate::regression::baseline::Change;
use crate::regression::check::{Checked, ExperimentCheck};
use crate::regression::claims::ClaimsRun;
use anyhow::Result;
use serde_json::{json, Value};

/// The document: the experiments' part when they were checked, `claims` when the claims were.
pub fn document(outcome: &CheckOutcome) -> Result<String> {
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
    if let Some(c) = &outcome.experiments {
        if let (Value::Object(doc), Value::Object(from)) = (&mut doc, experiments(c)) {
            doc.extend(from);
        }
        let maps: Vec<MapEntry> = c.maps.iter().map(MapEntry::from_info).collect();
        doc["maps"] = json::maps(&maps);
    }
    if let Some(run) = &outcome.claims {
        doc["claims"] = claims(run);
        doc["passed"] = Value::Bool(doc["passed"].as_bool().unwrap_or(true) && run.passed());
    }
    json::text(&doc)
}

/// The experiments' part: `{ "passed", "experiments": [experiment…], "not_checked": […],
/// "numbers", "moved", "unchecked_maps", "missing_maps": […], "skipped_experiments",
/// "unchecked_rows", "seconds" }`.
fn experiments(c: &Checked) -> Value {
    json!({
        "passed": c.passed(),
        "experiments": c.experiments.iter().map(experiment).collect::<Vec<_>>(),
        "not_checked": c.left_out,
        "numbers": c.numbers,
        "moved": c.moved,
        "unchecked_maps": c.unchecked_maps,
        "missing_maps": c.missing.names(),
        "skipped_experiments": c.missing.skipped(),
        "unchecked_rows": c.missing.rows(),
        "seconds": (c.seconds * 10.0).round() / 10.0,
    })
}

/// One experiment: the counts of its report as numbers, the baseline's date and commit, and
/// each finding as its kind, whether it fails, and the sentence the text report prints.
fn experiment(c: &ExperimentCheck) -> Value {
    let n = &c.comparison;
    let findings: Vec<Value> =
        c.findings.iter().map(|f| json!({ "kind": f.kind(), "fails": f.fails(), "text": f.to_string() })).collect();
    json!({
        "experiment": c.experiment,
        "passed": c.passed(),
        "baseline_dir": c.dir.display().to_string(),
        "baseline_date": c.baseline.as_ref().map(|p| p.date.clone()),
        "baseline_commit": c.baseline.as_ref().map(|p| p.git_commit.clone()),
        "maps": c.maps,
        "unchecked_maps": c.unchecked_map_names(),
        "rows": n.rows,
        "numbers": n.numbers,
        "within_tolerance": n.within,
        "ignored": n.ignored,
        "moved": c.moved(),
        "findings": findings,
    })
}

/// The claims: `passed` ([`ClaimsRun::passed`]), whether the measurements were taken and why
/// not, each moved measurement with its changes ([`Change::to_json`]), and each changed verdict.
fn claims(run: &ClaimsRun) -> Value {
    let moved: Vec<Value> = run
        .moved
        .iter()
        .map(|(name, ch)| json!({ "measurement": name, "changes": ch.iter().map(Change::to_json).collect::<Vec<_>>() }))
        .collect();
    let verdicts: Vec<Value> =
        run.verdicts_changed.iter().map(|(id, old, new)| json!({ "id": id, "committed": old, "now": new })).collect();
    json!({
        "passed": run.passed(),
        "measured": run.skipped.is_none(),
        "not_measured_because": run.skipped,
        "moved": moved,
        "verdicts_changed": verdicts,
    })
}
