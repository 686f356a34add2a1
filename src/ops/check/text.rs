//! `check`'s text: each experiment's report (one line per finding, each starting with the
//! experiment's name, then its verdict line; `bless`, `run` and `reproduce` print the same
//! report), and the closing lines (the experiments left out, the verdict, what went unchecked
//! for want of maps, the claims' verdict).

use crate::regression::baseline::Change as C;
use crate::regression::check::{Checked, ExperimentCheck, Finding};
use crate::regression::claims::ClaimsRun;

/// One experiment's report: a line per finding (a map missing where that is allowed is in the
/// verdict line, not a line of its own: which map, and why, is said once for the whole check),
/// then the verdict line.
pub fn experiment(c: &ExperimentCheck) -> String {
    let mut s = String::new();
    for f in c.findings.iter().filter(|f| !matches!(f, Finding::MapMissing { allowed: true, .. })) {
        s += &format!("{}: {f}\n", c.experiment);
    }
    let unchecked = c.unchecked_maps();
    let counts = counts(c);
    if c.passed() && unchecked >= c.maps {
        s += &format!("{}: skipped: none of its {} map(s) is on this machine\n", c.experiment, c.maps);
    } else if c.passed() && unchecked > 0 {
        s += &format!(
            "{}: ok on the maps here ({} of {}; {} row(s) of the {unchecked} missing not checked) ({counts})\n",
            c.experiment,
            c.maps - unchecked,
            c.maps,
            c.unchecked_rows
        );
    } else if c.passed() {
        s += &format!("{}: ok, nothing moved ({counts})\n", c.experiment);
    } else {
        s += &format!("{}: FAILED: {} ({counts})\n", c.experiment, failures(c).join(", "));
    }
    s
}

/// The counts of a verdict line: rows and numbers compared, with which baseline, how many of
/// those differ within tolerance, and how many more cells were not compared at all (columns
/// the tolerances ignore, such as timings: never counted among the numbers compared).
fn counts(c: &ExperimentCheck) -> String {
    let from = match &c.baseline {
        Some(p) => format!(
            "baseline of {} from {}{}",
            p.date,
            &p.git_commit[..p.git_commit.len().min(12)],
            if p.git_dirty == Some(true) { " (uncommitted changes)" } else { "" }
        ),
        None => "baseline".to_string(),
    };
    let n = &c.comparison;
    format!(
        "{} rows, {} numbers compared with the {from} in {}, {} of them different but within tolerance; {} \
         cells of ignored columns (timings) not compared",
        n.rows,
        n.numbers,
        c.dir.display(),
        n.within,
        n.ignored
    )
}

/// What failed, counted by kind ("2 number(s) moved", …), the kinds absent left out.
fn failures(c: &ExperimentCheck) -> Vec<String> {
    let map_problem = |f: &Finding| {
        matches!(f, Finding::MapChanged { .. } | Finding::MapUnrecorded { .. } | Finding::MapMissing { .. })
            && f.fails()
    };
    let baseline_problem =
        |f: &Finding| matches!(f, Finding::NoBaseline | Finding::NoProvenance(_) | Finding::TableEdited { .. });
    [
        (c.moved(), "number(s) moved"),
        (c.count(|f| matches!(f, Finding::Change(C::Text { .. }))), "text cell(s) changed"),
        (c.count(|f| matches!(f, Finding::Change(C::RowAdded(_)))), "row(s) added"),
        (c.count(|f| matches!(f, Finding::Change(C::RowRemoved(_)))), "row(s) removed"),
        (
            c.count(|f| matches!(f, Finding::Change(C::ColumnAdded(_) | C::ColumnRemoved(_)))),
            "column(s) added or removed",
        ),
        (c.count(map_problem), "map(s) changed, unrecorded or missing"),
        (c.count(baseline_problem), "baseline problem(s)"),
    ]
    .into_iter()
    .filter(|(n, _)| *n > 0)
    .map(|(n, what)| format!("{n} {what}"))
    .collect()
}

/// The closing lines after every experiment's report: the experiments left out for
/// `ci = false`, the verdict line, and the one line of what could not be checked for want of
/// maps.
pub fn closing(c: &Checked) -> String {
    let mut text = String::new();
    if !c.left_out.is_empty() {
        text += &format!("not checked (ci = false): {}; `probelab check --all` includes them\n", c.left_out.join(", "));
    }
    text += &verdict(c);
    if let Some(line) = c.missing.line("checked") {
        text += &format!("{line}\n");
    }
    text
}

/// `check`'s verdict line: ok, or the experiments that failed and what to do (`bless` when
/// numbers moved; the maps when only maps were missing, under `--require-all-maps`).
fn verdict(c: &Checked) -> String {
    let (n, elapsed, failed) = (c.experiments.len(), c.seconds, &c.failed);
    if failed.is_empty() {
        return format!(
            "check: ok: {n} experiment(s), {} numbers compared, nothing moved ({elapsed:.1} s)\n",
            c.numbers
        );
    }
    let advice = if c.maps_only {
        "Only maps are missing: put them on the map search path (see the maps listed on stderr).".to_string()
    } else {
        format!("If intended, run `probelab bless {}` and quote its output in the commit message.", failed.join(" "))
    };
    format!(
        "check: FAILED: {} of {n} experiment(s) differ from their baselines ({}); {} number(s) moved. {advice} \
         ({elapsed:.1} s)\n",
        failed.len(),
        failed.join(", "),
        c.moved
    )
}

/// The claims' verdict line (no newline), after their report (`claims/text.rs`).
pub fn claims_verdict(run: &ClaimsRun) -> String {
    let verdict = if run.passed() { "ok: no measurement moved, no verdict changed" } else { "FAILED" };
    format!("claims: {verdict}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regression::baseline::Comparison;
    use std::path::PathBuf;

    #[test]
    fn allowed_missing_maps_are_counted_in_the_verdict_and_fail_only_when_required() {
        let c = ExperimentCheck {
            experiment: "x".into(),
            dir: PathBuf::from("results/x"),
            findings: vec![Finding::MapMissing { map: "m".into(), why: "gone".into(), allowed: true }],
            comparison: Comparison::default(),
            baseline: None,
            maps: 3,
            unchecked_rows: 7,
        };
        assert!(c.passed());
        let report = experiment(&c);
        assert!(report.contains("x: ok on the maps here (2 of 3; 7 row(s) of the 1 missing not checked)"), "{report}");
        // Which map, and why, is said once for the whole check, not in each experiment's report.
        assert!(!report.contains("map m"), "{report}");
        let strict = ExperimentCheck {
            findings: vec![Finding::MapMissing { map: "m".into(), why: "gone".into(), allowed: false }],
            ..c
        };
        assert!(!strict.passed());
        let report = experiment(&strict);
        assert!(report.contains("x: FAILED: 1 map(s) changed, unrecorded or missing"), "{report}");
        assert!(report.contains("x: map m not found on this machine: its rows were not checked"));
    }

    #[test]
    fn the_counts_never_call_a_cell_both_compared_and_ignored() {
        let comparison = Comparison { rows: 2, numbers: 6, within: 1, ignored: 4, ..Default::default() };
        let c = ExperimentCheck {
            experiment: "x".into(),
            dir: PathBuf::from("results/x"),
            findings: vec![],
            comparison,
            baseline: None,
            maps: 1,
            unchecked_rows: 0,
        };
        let line = counts(&c);
        assert!(line.starts_with("2 rows, 6 numbers compared with the baseline in results/x"), "{line}");
        assert!(line.contains("1 of them different but within tolerance; 4 cells of ignored columns"), "{line}");
        assert!(!line.contains("4 ignored"), "{line}");
    }
}
