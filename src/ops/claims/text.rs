//! The claims' text: what a claims run found (measurements not taken, moved, verdicts
//! changed), printed by `claims`, `check`, `bless` and `reproduce` alike, and what `claims`
//! wrote.

use super::ClaimsOutcome;
use crate::regression::claims::ClaimsRun;

/// The lines of a claims run's report (empty when nothing is to be said).
pub fn report(run: &ClaimsRun) -> String {
    let mut s = String::new();
    if let Some(why) = &run.skipped {
        s += &format!(
            "claims: measurements not taken ({why}); the committed measurement tables are judged as they stand\n"
        );
    }
    for (name, ch) in &run.moved {
        s += &format!("claims: measurement {name} moved ({} change(s)); not written:\n", ch.len());
        for c in ch.iter().take(20) {
            s += &format!("  {c}\n");
        }
    }
    for (id, old, new) in &run.verdicts_changed {
        s += &format!("claims: verdict of {id}: {old} -> {new}\n");
    }
    s
}

/// The line saying what `claims` wrote.
pub fn written(outcome: &ClaimsOutcome) -> String {
    format!(
        "wrote {} file(s) and {} blending strip(s) under {}\n",
        outcome.run.written.len(),
        outcome.strips,
        outcome.out.display()
    )
}
