//! Parsing one declaration file: the paper, each claim's keys, its checks (exactly one
//! primary), every error naming the file and the claim.

use super::check::{CheckDecl, Test};
use super::file::PaperFile;
use super::kind::Kind;
use super::paper::{ClaimDecl, Paper, SAYS_MAX};
use super::threshold::{check_quantifier, check_threshold, ThresholdFrom};
use crate::math::echo::value as echo;
use anyhow::{bail, Context, Result};
use std::path::Path;

/// Refuses a `fixed` that is neither `before data` nor `after data: <reason>`.
fn check_fixed(fixed: &str) -> Result<()> {
    match fixed.strip_prefix("after data:") {
        _ if fixed == "before data" => Ok(()),
        Some(reason) if !reason.trim().is_empty() => Ok(()),
        _ => bail!("fixed '{fixed}' (expected \"before data\" or \"after data: <reason>\")", fixed = echo(fixed)),
    }
}

/// Refuses a claim without exactly one primary check, and a primary whose test does not fit
/// the kind: an anchor's primary only summarises (`ratio_summary`: it never holds or fails);
/// every other kind's primary has a criterion.
fn check_primary(kind: Kind, checks: &[CheckDecl]) -> Result<()> {
    let primaries: Vec<&CheckDecl> = checks.iter().filter(|k| k.primary).collect();
    let [p] = primaries.as_slice() else {
        bail!("{} checks have role = \"primary\" (exactly one decides the verdict)", primaries.len())
    };
    let summary = matches!(p.test, Test::RatioSummary);
    if kind == Kind::Anchor && !summary {
        bail!(
            "an anchor's primary check is test = \"ratio_summary\": an anchor is not comparable, never held or failed"
        );
    }
    if kind != Kind::Anchor && summary {
        bail!(
            "the primary check of a{} {} claim needs a criterion (ratio_summary has none)",
            if kind == Kind::Identity { "n" } else { "" },
            kind.as_str()
        );
    }
    Ok(())
}

/// Refuses a `table` whose name is not a plain identifier (`io::name`), as `FILE:LINE: key
/// 'table': …` at the first line of `text` that sets `table` to it.
fn table_name(table: &str, text: &str, origin: &Path) -> Result<()> {
    let Err(e) = crate::io::name::check(table.strip_prefix("measure:").unwrap_or(table)) else {
        return Ok(());
    };
    let line = text.lines().position(|l| {
        let l = l.trim_start();
        l.strip_prefix("table").is_some_and(|rest| {
            rest.trim_start().starts_with('=')
                && toml::from_str::<toml::Table>(l).ok().and_then(|t| t.get("table")?.as_str().map(|v| v == table))
                    == Some(true)
        })
    });
    match line {
        Some(n) => bail!("{}:{}: key 'table': {e}", origin.display(), n + 1),
        None => bail!("{}: key 'table': {e}", origin.display()),
    }
}

/// Refuses a declared map set that names a constructed scene: scenes are judged apart.
fn no_scene_in_map_sets(sets: &std::collections::BTreeMap<String, Vec<String>>, origin: &Path) -> Result<()> {
    for (set, maps) in sets {
        if let Some(m) = maps.iter().find(|m| crate::claims::population::is_constructed(m)) {
            bail!(
                "{}: [map_sets] {}: '{}' is a constructed scene; scenes are judged apart, in the set 'scenes'",
                origin.display(),
                echo(set),
                echo(m)
            );
        }
    }
    Ok(())
}

/// Parses one declaration file's text; `key` is its stem, `origin` names it in errors.
pub fn parse(key: &str, text: &str, origin: &Path) -> Result<Paper> {
    let f: PaperFile = crate::pipeline::experiment::parse_toml(text, origin)
        .map_err(|e| anyhow::anyhow!("{e:#} (not a claims declaration)"))?;
    let declared = f.measurements.is_some();
    let measurement_maps = f.measurements.map(|m| m.maps).unwrap_or_default();
    if declared && measurement_maps.is_empty() {
        bail!("{}: [measurements] maps = [] names no map", origin.display());
    }
    if let Some(m) = measurement_maps.iter().enumerate().find(|(i, m)| measurement_maps[..*i].contains(m)) {
        bail!("{}: [measurements] maps: '{}' appears twice", origin.display(), echo(m.1));
    }
    no_scene_in_map_sets(&f.map_sets, origin)?;
    let mut claims = Vec::new();
    for c in f.claim {
        let id = c.id.clone();
        let shown = echo(&id);
        let at = || format!("{}: claim {shown}", origin.display());
        if id.is_empty() || claims.iter().any(|d: &ClaimDecl| d.id == id) {
            bail!("{}: claim id '{shown}' is empty or declared twice", origin.display());
        }
        if c.says.chars().count() > SAYS_MAX {
            bail!("{}: 'says' has {} characters (at most {SAYS_MAX})", at(), c.says.chars().count());
        }
        if c.paper_figure.chars().count() > SAYS_MAX {
            bail!("{}: 'paper_figure' has {} characters (at most {SAYS_MAX})", at(), c.paper_figure.chars().count());
        }
        let Some(kind) = Kind::parse(&c.kind) else {
            bail!("{}: kind '{}' (expected identity, measured, example or anchor)", at(), echo(&c.kind))
        };
        check_fixed(&c.fixed).with_context(at)?;
        if c.differs.trim().is_empty() {
            bail!("{}: 'differs' is empty: say why our figure and the paper's may differ", at());
        }
        if c.check.is_empty() {
            bail!("{}: no [[claim.check]]: a claim is judged by its primary check", at());
        }
        for k in &c.check {
            table_name(&k.table, text, origin)?;
        }
        let checks = c.check.into_iter().map(|k| k.validate(&id, &f.map_sets)).collect::<Result<Vec<_>>>();
        let checks = checks.with_context(at)?;
        check_primary(kind, &checks).with_context(at)?;
        if c.quote.trim().is_empty() {
            bail!("{}: 'quote' is empty: quote the paper's sentence verbatim", at());
        }
        let threshold_from = ThresholdFrom::parse(&c.threshold_from).with_context(at)?;
        // Cannot fail: check_primary found exactly one.
        let primary = checks.iter().find(|k| k.primary).expect("one primary");
        check_threshold(kind, &threshold_from, &c.quote, primary).with_context(at)?;
        check_quantifier(kind, &c.quote, primary).with_context(at)?;
        let figures = super::figure::figures(c.figure).with_context(at)?;
        claims.push(ClaimDecl {
            figures,
            statement: c.statement.unwrap_or_else(|| c.says.clone()),
            id,
            says: c.says,
            paper_figure: c.paper_figure,
            criterion: c.criterion,
            quote: c.quote,
            threshold_from,
            kind,
            fixed: c.fixed,
            differs: c.differs,
            checks,
        });
    }
    Ok(Paper {
        key: key.to_string(),
        title: f.title,
        authors: f.authors,
        venue: f.venue,
        order: f.order,
        map_sets: f.map_sets,
        measurement_maps,
        claims,
    })
}
