//! One claim's section of its paper's evidence page (`results/claims/<paper>.md`): the verdict
//! and the kind that allows its word; "What we found" in plain words (what the paper says, our
//! figure, the verdict, why the two may differ); the declaration; then the primary check,
//! which decides, and the context checks, which never change the verdict, each with its
//! figure per map set and its per-map or per-row values.

use crate::claims::declaration::{CheckDecl, ClaimDecl, Kind, Test, ThresholdFrom};
use crate::claims::judge::{fmt3, set_label, CheckOutcome, ClaimOutcome, Status};
use std::fmt::Write as _;

/// What a kind means, and the words it allows, in one sentence.
pub fn kind_text(kind: Kind) -> &'static str {
    match kind {
        Kind::Identity => {
            "identity: true by derivation or construction, checked numerically to rounding; `holds (identity)` or \
             `fails`"
        }
        Kind::Measured => {
            "measured: a general statement over maps or scenes; `holds`, `partly` (on some of the map sets judged) \
             or `fails`, decided by the primary check"
        }
        Kind::Example => {
            "example: stated for one case; `reproduced` or `not reproduced` on the paper's case or the closest we \
             have, the rate over the other maps shown as context"
        }
        Kind::Anchor => {
            "anchor: the paper's figure comes from a population we do not have; `not comparable`, our figure stands \
             beside theirs and never holds or fails"
        }
    }
}

/// The "What we found" paragraph: the paper's sentence verbatim, its figure, ours, the
/// verdict, every map that disagrees with its margin (or, when none does, the closest one),
/// where the threshold comes from and why the two may differ.
pub fn found_md(c: &ClaimDecl, o: &ClaimOutcome) -> String {
    let why = o.verdict.why();
    format!(
        "**What we found.** The paper says: \"{}\" (its figure: {}). We measure {}. Verdict: **{}**{} — {} {} \
         claim; its threshold: {}.{} Why the two may differ: {}\n",
        c.quote,
        c.paper_figure,
        o.our_figure(),
        o.verdict.word(),
        if why.is_empty() { String::new() } else { format!(" ({why})") },
        if c.kind == Kind::Measured { "a" } else { "an" },
        c.kind.as_str(),
        threshold_words(&c.threshold_from),
        margins(o),
        c.differs
    )
}

/// Where the threshold comes from, in words.
fn threshold_words(t: &ThresholdFrom) -> String {
    match t {
        ThresholdFrom::Paper(w) => format!("the paper's own number (\"{w}\")"),
        ThresholdFrom::Direction => "the direction the paper's words assert, its size shown".into(),
        ThresholdFrom::Rounding => "rounding (an identity)".into(),
        ThresholdFrom::None => "none (an anchor)".into(),
    }
}

/// The primary's threshold as (relation, value), when it has one.
fn threshold(t: &Test) -> Option<(&'static str, f64)> {
    match *t {
        Test::RatioEvery { below, .. } | Test::RatioSome { below, .. } => Some(("<", below)),
        Test::RatioStat { max: Some(m), .. } => Some(("≤", m)),
        Test::RatioStat { min: Some(m), .. } => Some(("≥", m)),
        Test::EveryAtLeast { bound } | Test::MedianAtLeast { bound } => Some(("≥", bound)),
        Test::EveryAtMost { bound } => Some(("≤", bound)),
        Test::EveryEqual { value } => Some(("=", value)),
        Test::Equal { tolerance, .. } => Some(("≤", tolerance)),
        _ => None,
    }
}

/// How far a value is from the threshold: relative to it (as a percentage) unless it is zero.
fn margin(v: f64, t: f64) -> String {
    if t == 0.0 || t.abs() <= 1e-6 {
        format!("by {}", fmt3((v - t).abs()))
    } else {
        format!("by {:.1}%", 100.0 * (v - t).abs() / t.abs())
    }
}

/// Every value of the primary (its widest set) that disagrees, with its margin; when none
/// does, the one closest to the threshold.
fn margins(o: &ClaimOutcome) -> String {
    let Some(p) = o.checks.iter().find(|k| k.decl.primary) else { return String::new() };
    let Some((rel, t)) = threshold(&p.decl.test) else { return String::new() };
    let Some(w) = p.sets.iter().max_by_key(|s| s.values.len()) else { return String::new() };
    if w.values.is_empty() || matches!(w.status, Status::Untestable(_)) {
        return String::new();
    }
    let failing: Vec<String> = w
        .values
        .iter()
        .filter(|v| !v.pass)
        .map(|v| format!("{} {} ({rel} {} missed {})", v.label, fmt3(v.value), fmt3(t), margin(v.value, t)))
        .collect();
    const SHOWN: usize = 20;
    if failing.is_empty() {
        // Cannot fail: `values` is non-empty.
        let closest =
            w.values.iter().min_by(|a, b| (a.value - t).abs().total_cmp(&(b.value - t).abs())).expect("non-empty");
        return format!(
            " Every value on {} meets {rel} {}; the closest is {} at {} ({}).",
            set_label(w),
            fmt3(t),
            closest.label,
            fmt3(closest.value),
            margin(closest.value, t)
        );
    }
    let more = if failing.len() > SHOWN {
        format!(", and {} more (listed below)", failing.len() - SHOWN)
    } else {
        String::new()
    };
    format!(
        " On {}, {} of {} disagree{}: {}{more}.",
        set_label(w),
        failing.len(),
        w.values.len(),
        if failing.len() == 1 { "s" } else { "" },
        failing.iter().take(SHOWN).cloned().collect::<Vec<_>>().join("; ")
    )
}

/// The detail of one claim, as Markdown (for the evidence pages).
pub fn detail_md(c: &ClaimDecl, o: &ClaimOutcome) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "**Verdict: {}**{}\n",
        o.verdict.word(),
        if o.verdict.why().is_empty() { String::new() } else { format!(" — {}", o.verdict.why()) }
    );
    let _ = writeln!(s, "{}", found_md(c, o));
    for f in &c.figures {
        let _ = writeln!(s, "![{}](../{})\n\n*Figure (ours):* {}\n", f.caption, f.image, f.caption);
    }
    let _ = writeln!(s, "- **Paper:** {}", c.statement);
    let _ = writeln!(s, "- **The paper's words:** \"{}\"", c.quote);
    let _ = writeln!(s, "- **Paper's figure:** {}", c.paper_figure);
    let _ = writeln!(s, "- **Evidence kind:** {}", kind_text(c.kind));
    let _ = writeln!(s, "- **Criterion:** {}", c.criterion);
    let _ = writeln!(s, "- **Threshold from:** {}", c.threshold_from.text());
    let _ = writeln!(s, "- **Criterion fixed:** {}\n", c.fixed);
    let ordered = o.checks.iter().filter(|k| k.decl.primary).chain(o.checks.iter().filter(|k| !k.decl.primary));
    for k in ordered {
        check_md(&mut s, k);
    }
    s
}

/// One check: its evidence, test, outcome per set and values.
fn check_md(s: &mut String, k: &CheckOutcome) {
    let d = &k.decl;
    let filter = if d.filter.is_empty() {
        String::new()
    } else {
        let f: Vec<String> = d.filter.iter().map(|(k, v)| format!("{k} = {}", v.join("|"))).collect();
        format!(", rows with {}", f.join(", "))
    };
    let _ = writeln!(
        s,
        "#### {} {}\n\nEvidence `{}`{filter}; test: {}\n",
        if d.primary { "Primary check (decides the verdict):" } else { "Context (never changes the verdict):" },
        d.name,
        d.source.path().display(),
        test_text(d)
    );
    for set in &k.sets {
        let status = match &set.status {
            Status::Pass => "passes".to_string(),
            Status::Fail => "fails".to_string(),
            Status::Shown => "shown".to_string(),
            Status::Untestable(w) => format!("untestable ({w})"),
        };
        let figure = if set.figure.is_empty() { &set.headline } else { &set.figure };
        let _ = writeln!(s, "- on {}: **{status}** — {figure}", set_label(set));
    }
    values_md(s, k);
    let _ = writeln!(s);
}

/// The values of the widest set: per map for per-map tests, per row otherwise.
fn values_md(s: &mut String, k: &CheckOutcome) {
    let d = &k.decl;
    let Some(w) = k.sets.iter().max_by_key(|s| s.values.len()) else { return };
    if w.values.is_empty() {
        return;
    }
    if w.values.len() > 60 {
        let _ = writeln!(s, "\n({} rows; per-row values in the evidence table)", w.values.len());
        return;
    }
    let per_map = matches!(
        d.test,
        Test::RatioStat { .. }
            | Test::RatioSummary
            | Test::RatioEither
            | Test::MedianAtLeast { .. }
            | Test::RatioEvery { per_map: true, .. }
            | Test::RatioSome { per_map: true, .. }
    );
    let what = match d.test {
        Test::Equal { .. } => "relative difference".to_string(),
        Test::MedianAtLeast { .. } => format!("per-map median {}", d.column),
        _ if per_map => "per-map ratio (geometric mean of its rows)".to_string(),
        _ if d.test.needs_baseline() => "ratio".to_string(),
        _ => d.column.clone(),
    };
    let _ = writeln!(s, "\n| {} | {what} | passes alone |\n|---|---|---|", if per_map { "map" } else { "row" });
    for v in &w.values {
        let pass = if matches!(d.test, Test::RatioSummary) {
            "-"
        } else if v.pass {
            "yes"
        } else {
            "no"
        };
        let _ = writeln!(s, "| {} | {} | {pass} |", v.label, fmt3(v.value));
    }
}

/// A check's test in words, naming its aggregation.
pub fn test_text(d: &CheckDecl) -> String {
    let base = d.baseline.as_deref().unwrap_or("");
    let col = &d.column;
    let floor =
        if d.floor > 0.0 { format!(" (rows with {base} {col} ≤ {} left out)", fmt3(d.floor)) } else { String::new() };
    let each = |per_map: bool| if per_map { "map's (geometric mean of its rows)" } else { "row's" };
    match &d.test {
        Test::RatioEvery { below, per_map } => {
            format!("every {} {} / {base} {col} ratio < {}{floor}", each(*per_map), d.encoder, fmt3(*below))
        }
        Test::RatioSome { below, per_map } => {
            format!("some {} {} / {base} {col} ratio < {}{floor}", each(*per_map), d.encoder, fmt3(*below))
        }
        Test::RatioStat { statistic, min, max } => format!(
            "{} (each the geometric mean of its rows' ratios) of {} / {base} {col} {}{floor}",
            statistic.words(),
            d.encoder,
            match (min, max) {
                (Some(a), Some(b)) => format!("in [{}, {}]", fmt3(*a), fmt3(*b)),
                (Some(a), None) => format!("≥ {}", fmt3(*a)),
                (None, Some(b)) => format!("≤ {}", fmt3(*b)),
                (None, None) => String::new(),
            }
        ),
        Test::RatioSummary => format!(
            "{} / {base} {col} per map (geometric mean of its rows' ratios), summarised by median and geometric mean; \
             no criterion{floor}",
            d.encoder
        ),
        Test::RatioEither => format!(
            "some map's {} / {base} {col} ratio (geometric mean of its rows) < 1 and some > 1 (either wins \
             somewhere){floor}",
            d.encoder
        ),
        Test::MedianAtLeast { bound } => {
            format!("median over maps of each map's median {col} of {} ≥ {}", d.encoder, fmt3(*bound))
        }
        Test::EveryAtMost { bound } => format!("every {col} of {} ≤ {}", d.encoder, fmt3(*bound)),
        Test::EveryAtLeast { bound } => format!("every {col} of {} ≥ {}", d.encoder, fmt3(*bound)),
        Test::EveryEqual { value } => format!("every {col} of {} = {}", d.encoder, fmt3(*value)),
        Test::Equal { tolerance, abs_tolerance } => format!(
            "{} and {base} {col} agree within {} relative (differences ≤ {} count as equal)",
            d.encoder,
            fmt3(*tolerance),
            fmt3(*abs_tolerance)
        ),
    }
}
