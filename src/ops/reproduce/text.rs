//! What `reproduce` says at its end: the closing summary, a line per experiment, the one
//! line of what this machine lacked, the verdicts counted (REPORT.md's at-a-glance table) with
//! which were re-measured here and which judged from committed tables, and where the report is.

use super::{ReproduceOutcome, Reproduced};
use crate::ops::run::text::summary as stored_summary;
use crate::regression::claims::Judged;
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
    // The evidence this run computed: the tables it stored (or found unmoved) and the claims'
    // measurements it wrote.
    let mut here: Vec<String> = outcome
        .results
        .iter()
        .filter(|r| matches!(&r.outcome, Reproduced::Stored(s) if s.stands()))
        .map(|r| format!("{}/table.csv", r.name))
        .collect();
    here.extend(outcome.claims.written.iter().cloned());
    s += &claims_summary(&outcome.claims.verdicts, &here);
    s += &format!("report: {}\n", outcome.report.report.display());
    s
}

/// The verdicts counted by word (in the order they first appear), then the claims whose every
/// evidence table is in `here` (re-measured by this run) and the others (judged from the
/// tables committed under results/, their maps not all on this machine).
fn claims_summary(verdicts: &[Judged], here: &[String]) -> String {
    if verdicts.is_empty() {
        return "claims: none declared (experiments/claims/)\n".into();
    }
    let mut counts: Vec<(&str, usize)> = Vec::new();
    for v in verdicts {
        match counts.iter_mut().find(|(w, _)| *w == v.verdict) {
            Some((_, n)) => *n += 1,
            None => counts.push((&v.verdict, 1)),
        }
    }
    let counted: Vec<String> = counts.iter().map(|(w, n)| format!("{n} {w}")).collect();
    let mut s = format!("claims: {} judged: {}\n", verdicts.len(), counted.join(", "));
    let (measured, committed): (Vec<&Judged>, Vec<&Judged>) =
        verdicts.iter().partition(|v| v.evidence.iter().all(|e| here.contains(e)));
    let ids = |vs: &[&Judged]| vs.iter().map(|v| v.id.as_str()).collect::<Vec<_>>().join(", ");
    if !measured.is_empty() {
        s += &format!("  re-measured here: {} ({})\n", measured.len(), ids(&measured));
    }
    if !committed.is_empty() {
        s += &format!(
            "  judged from the committed tables (not every table they read was computed here): {} ({})\n",
            committed.len(),
            ids(&committed)
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn judged(id: &str, verdict: &str, evidence: &[&str]) -> Judged {
        Judged { id: id.into(), verdict: verdict.into(), evidence: evidence.iter().map(|e| e.to_string()).collect() }
    }

    #[test]
    fn the_claims_summary_counts_verdicts_and_says_which_were_measured_here() {
        let verdicts = [
            judged("Z1", "reproduced", &["zh3_table/table.csv"]),
            judged("Z2", "not reproduced", &["zh3_table/table.csv", "claims/measures/axis.csv"]),
            judged("H1", "reproduced", &["hemi/table.csv"]),
        ];
        let here = ["zh3_table/table.csv".to_string(), "claims/measures/axis.csv".to_string()];
        let s = claims_summary(&verdicts, &here);
        assert_eq!(
            s,
            "claims: 3 judged: 2 reproduced, 1 not reproduced\n  re-measured here: 2 (Z1, Z2)\n  judged from the \
             committed tables (not every table they read was computed here): 1 (H1)\n"
        );
        assert_eq!(claims_summary(&[], &here), "claims: none declared (experiments/claims/)\n");
    }
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
