//! What `reproduce` says at its end: the closing summary, a line per experiment and the one
//! line of what this machine lacked.

use super::{ReproduceOutcome, Reproduced};
use crate::ops::run::text::summary as stored_summary;
use crate::regression::guard::PartialCheck;

/// The closing summary (stdout): the experiments, a line for each whose table stood, was
/// checked on some maps or was skipped, and what this machine lacked.
pub fn summary(outcome: &ReproduceOutcome) -> String {
    let mut s = format!("reproduce: {} experiment(s)\n", outcome.experiments);
    for r in &outcome.results {
        let n = r.maps.len();
        let line = match &r.outcome {
            Reproduced::Stored(stored) if stored.stands() => {
                format!("{}: {n} of {n} maps; {}", r.name, stored_summary(stored))
            }
            Reproduced::Stored(_) => continue,
            Reproduced::Partial(missing, check) => partial_line(&r.name, n, missing, check),
            Reproduced::Skipped => format!("{}: skipped, 0 of {n} maps (missing: {})", r.name, r.maps.join(", ")),
        };
        s += &format!("  {line}\n");
    }
    if let Some(line) = outcome.missing.line("reproduced") {
        s += &format!("{line}; their baselines were left unchanged\n");
    }
    s
}

/// The summary line of an experiment checked on some of its `n` maps: maps found of maps
/// named, the missing ones, and how many numbers were compared.
fn partial_line(name: &str, n: usize, missing: &[String], check: &PartialCheck) -> String {
    let head = format!("{name}: {} of {n} maps (missing: {})", n - missing.len(), missing.join(", "));
    match check {
        PartialCheck::NoBaseline => format!("{head}; no baseline to compare with, nothing written"),
        PartialCheck::Compared(c) if c.passed() => {
            format!("{head}; {} numbers compared, nothing moved; baseline left unchanged", c.comparison.numbers)
        }
        PartialCheck::Compared(c) => format!(
            "{head}; {} numbers compared, FAILED ({} moved); baseline left unchanged",
            c.comparison.numbers,
            c.moved()
        ),
    }
}
