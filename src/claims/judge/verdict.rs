//! A claim's one verdict: every check judged on its evidence, the primary deciding in the
//! words its evidence kind allows ([`crate::claims::declaration::Kind`]); context checks are
//! shown and never change it.

use crate::claims::declaration::{ClaimDecl, Kind, Paper, Source};
use crate::claims::judge::check::judge_check;
use crate::claims::judge::outcome::{CheckOutcome, ClaimOutcome, Evidence, Status, Verdict};
use crate::claims::judge::wording;

/// The verdict of a claim of `kind`, from its primary check alone: context checks are shown
/// and never change it. A primary without its data makes the claim `untestable`; an anchor
/// with its data is `not comparable`, whatever the figure.
pub fn decide(kind: Kind, checks: &[CheckOutcome]) -> Verdict {
    let Some(p) = checks.iter().find(|c| c.decl.primary) else {
        return Verdict::Untestable("no primary check".into());
    };
    let (mut passing, mut failing, mut untestable) = (Vec::new(), Vec::new(), Vec::new());
    for s in &p.sets {
        match &s.status {
            Status::Untestable(why) => untestable.push(wording::untestable_on(s, why)),
            Status::Fail => failing.push(wording::set_label(s)),
            Status::Pass | Status::Shown => passing.push(wording::set_label(s)),
        }
    }
    let name = &p.decl.name;
    if !untestable.is_empty() {
        return Verdict::Untestable(wording::untestable_reason(name, &untestable));
    }
    match kind {
        Kind::Anchor => Verdict::NotComparable,
        Kind::Identity if failing.is_empty() => Verdict::HoldsIdentity,
        Kind::Example if failing.is_empty() => Verdict::Reproduced,
        Kind::Measured if failing.is_empty() => Verdict::Holds,
        Kind::Example => Verdict::NotReproduced(wording::not_met(name, &failing)),
        Kind::Measured if !passing.is_empty() => Verdict::Partly(wording::partly(name, &passing, &failing)),
        Kind::Identity | Kind::Measured => Verdict::Fails(wording::fails(name, &failing)),
    }
}

/// Judges a claim: every check on its evidence; the primary decides.
pub fn judge_claim(
    paper: &Paper,
    c: &ClaimDecl,
    evidence: &dyn Fn(&Source) -> std::result::Result<Evidence, String>,
) -> ClaimOutcome {
    let checks: Vec<CheckOutcome> = c.checks.iter().map(|k| judge_check(paper, k, &evidence(&k.source))).collect();
    let verdict = decide(c.kind, &checks);
    ClaimOutcome { id: c.id.clone(), kind: c.kind, verdict, checks }
}
