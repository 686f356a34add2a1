//! Where a claim's threshold comes from, and the two rules that keep a verdict fair to the
//! paper's words:
//!
//! - **The threshold rule.** A number decides a verdict only when the paper states it
//!   (`threshold_from = "paper: <the quoted words>"`, words found in the claim's `quote` and
//!   naming a number: "more than halves" is 0.5, "13 bytes" is 13). A qualitative word
//!   ("clear", "dramatically", "much closer") decides only the direction it asserts
//!   (`"direction"`: a ratio below or above 1, a value above or below zero up to a rounding
//!   floor of 1e-6); its size is shown beside the verdict, never made a threshold. An identity
//!   holds to `"rounding"`; an anchor has no threshold (`"none"`).
//! - **The quantifier rule.** The sentence's own quantifier sets the population rule: "For
//!   example" or "In this case" makes the claim an `example`, decided on one case named in
//!   advance; "in every case" needs every case (`ratio_every` or an `every_*` bound); a hedge
//!   ("usually", "tends to", "sometimes", "most of") is decided by the direction on most maps,
//!   the per-map median (`ratio_stat` with `statistic = "median"`, or `median_at_least`).
//!   Identities and anchors are exempt: a derivation holds in every case, an anchor is never
//!   judged.

use super::check::{CheckDecl, Statistic, Test};
use super::kind::Kind;
use anyhow::{bail, Result};

/// Where a claim's threshold comes from (`threshold_from`).
#[derive(Clone, Debug, PartialEq)]
pub enum ThresholdFrom {
    /// `paper: <words>`: a number the paper states, in its own words.
    Paper(String),
    /// `direction`: a word decides only the direction it asserts.
    Direction,
    /// `rounding`: an identity, held to rounding (or a quadrature's accuracy).
    Rounding,
    /// `none`: an anchor, which is never held or failed.
    None,
}

/// Words that state a number without digits.
const NUMBER_WORDS: [&str; 11] =
    ["half", "halves", "quarter", "third", "twice", "double", "exact", "zero", "most", "¼", "½"];

/// Phrases that make a sentence one example.
const EXAMPLE: [&str; 4] = ["for example", "in this case", "in examples like this", "to give an example"];

/// Phrases that make a sentence hold in every case.
const EVERY: [&str; 2] = ["in every case", "always"];

/// Hedges: the direction on most maps decides.
const HEDGES: [&str; 7] = ["usually", "tends to", "tend to", "sometimes", "most of", "often", "generally"];

impl ThresholdFrom {
    /// Parses `threshold_from`.
    pub fn parse(s: &str) -> Result<ThresholdFrom> {
        Ok(match s {
            "direction" => ThresholdFrom::Direction,
            "rounding" => ThresholdFrom::Rounding,
            "none" => ThresholdFrom::None,
            _ => match s.strip_prefix("paper:").map(str::trim) {
                Some(w) if !w.is_empty() => ThresholdFrom::Paper(w.to_string()),
                _ => bail!(
                    "threshold_from '{}' (expected \"paper: <the quoted words>\", \"direction\", \"rounding\" or \"none\")",
                    crate::math::echo::value(s)
                ),
            },
        })
    }

    /// As written in the declaration and in `CLAIMS.csv`.
    pub fn text(&self) -> String {
        match self {
            ThresholdFrom::Paper(w) => format!("paper: {w}"),
            ThresholdFrom::Direction => "direction".into(),
            ThresholdFrom::Rounding => "rounding".into(),
            ThresholdFrom::None => "none".into(),
        }
    }
}

/// Whether the primary's criterion is a direction only: a ratio against 1, a sign up to a
/// rounding floor of 1e-6, or either way.
fn is_direction(t: &Test) -> bool {
    match *t {
        Test::RatioEvery { below, .. } | Test::RatioSome { below, .. } => below == 1.0,
        Test::RatioStat { min, max, .. } => matches!((min, max), (None, Some(1.0)) | (Some(1.0), None)),
        Test::RatioEither => true,
        Test::EveryAtLeast { bound } | Test::EveryAtMost { bound } | Test::MedianAtLeast { bound } => {
            bound.abs() <= 1e-6
        }
        _ => false,
    }
}

/// The threshold rule: the primary's threshold comes from where `from` says.
pub(super) fn check_threshold(kind: Kind, from: &ThresholdFrom, quote: &str, primary: &CheckDecl) -> Result<()> {
    match from {
        ThresholdFrom::None if kind != Kind::Anchor => bail!("threshold_from = \"none\" is for an anchor only"),
        _ if kind == Kind::Anchor && *from != ThresholdFrom::None => {
            bail!("an anchor has no threshold: threshold_from = \"none\"")
        }
        ThresholdFrom::Rounding if kind != Kind::Identity => {
            bail!("threshold_from = \"rounding\" is for an identity; a {} claim's threshold comes from the paper or is a direction", kind.as_str())
        }
        ThresholdFrom::Direction if !is_direction(&primary.test) => bail!(
            "threshold_from = \"direction\", but the primary's threshold is not a direction (a ratio against 1, or a \
             sign up to 1e-6): a threshold without a number the paper states may not decide a verdict"
        ),
        ThresholdFrom::Paper(w) if !quote.contains(w.as_str()) => {
            bail!("threshold_from quotes '{}', which the claim's quote does not contain", crate::math::echo::value(w))
        }
        ThresholdFrom::Paper(w) if !names_a_number(w) => bail!(
            "threshold_from quotes '{}', which states no number (a word decides only its direction: \
             threshold_from = \"direction\")",
            crate::math::echo::value(w)
        ),
        _ => Ok(()),
    }
}

/// Whether quoted words state a number: a digit, or a number word.
fn names_a_number(w: &str) -> bool {
    let lower = w.to_lowercase();
    lower.chars().any(|c| c.is_ascii_digit())
        || lower.split(|c: char| !c.is_alphanumeric() && c != '¼' && c != '½').any(|t| NUMBER_WORDS.contains(&t))
}

/// The quantifier rule: the sentence's quantifier sets the population rule of a measured or
/// example claim.
pub(super) fn check_quantifier(kind: Kind, quote: &str, primary: &CheckDecl) -> Result<()> {
    if matches!(kind, Kind::Identity | Kind::Anchor) {
        return Ok(());
    }
    let q = quote.to_lowercase();
    let has = |list: &[&'static str]| -> Option<&'static str> { list.iter().find(|p| q.contains(**p)).copied() };
    if let Some(p) = has(&EXAMPLE) {
        if kind != Kind::Example {
            bail!("the quote says \"{p}\": the claim is an example, decided on one case named in advance");
        }
        return Ok(());
    }
    if let Some(p) = has(&EVERY) {
        let every = matches!(
            primary.test,
            Test::RatioEvery { .. } | Test::EveryAtLeast { .. } | Test::EveryAtMost { .. } | Test::EveryEqual { .. }
        );
        if !every {
            bail!("the quote says \"{p}\": the primary must hold in every case (ratio_every or an every_* bound)");
        }
        return Ok(());
    }
    if let Some(p) = has(&HEDGES) {
        let median =
            matches!(primary.test, Test::RatioStat { statistic: Statistic::Median, .. } | Test::MedianAtLeast { .. });
        if !median {
            bail!(
                "the quote hedges (\"{p}\"): the direction on most maps decides (ratio_stat with statistic = \
                 \"median\", or median_at_least), with the count shown"
            );
        }
    }
    Ok(())
}
