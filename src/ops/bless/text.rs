//! What `bless` says after its last write: each experiment's baseline written or left, the
//! experiments not blessed for want of maps, the claims' report and the files they wrote.

use super::BlessOutcome;
use crate::ops::claims::text::report as claims_report;

/// The lines (each ending in a newline).
pub fn lines(outcome: &BlessOutcome) -> String {
    let mut s = String::new();
    if let Some(blessed) = &outcome.experiments {
        for e in &blessed.experiments {
            let (name, dir) = (&e.name, e.dir.display());
            s += &match &e.written {
                None => format!("bless {name}: nothing moved; {dir} left unchanged\n"),
                Some(files) => {
                    let why = if e.passed { " (nothing moved; rewritten because of --force)" } else { "" };
                    format!("bless {name}: wrote {} in {dir}{why}\n", files.join(", "))
                }
            };
        }
        if !blessed.skipped.is_empty() {
            let skipped: Vec<String> =
                blessed.skipped.iter().map(|(name, maps)| format!("{name} (missing {})", maps.join(", "))).collect();
            s += &format!("not blessed, maps not found on this machine: {}\n", skipped.join("; "));
        }
    }
    if let Some(run) = &outcome.claims {
        s += &claims_report(run);
        s += &format!("claims: wrote {} file(s)\n", run.written.len());
    }
    s
}
