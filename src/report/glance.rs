//! The reproduction at a glance, REPORT.md's first table: one row per claim, from
//! `results/CLAIMS.csv` and the declarations `experiments/claims/*.toml`, with the count of
//! each verdict.
//!
//! `CLAIMS.csv` (written by the claims engine, `claims::verdicts`): columns
//! `id,kind,verdict,paper_figure,our_figure,criterion,maps,detail`, `kind` one of
//! `identity|measured|example|anchor`, `verdict` one of the words its kind allows (or
//! `untestable`), `detail` a link relative to `results/`. No encoder is named.

use super::csvfile::CsvTable;
use super::markdown::{href, table_with, text_cell};
use super::plans::relative_link;
use crate::claims::declaration::{Kind, Paper, UNTESTABLE};
use crate::math::echo::value as echo;
use anyhow::{bail, Result};
use std::fmt::Write as _;

/// The columns `CLAIMS.csv` must have.
pub const CLAIMS_CSV_COLUMNS: [&str; 8] =
    ["id", "kind", "verdict", "paper_figure", "our_figure", "criterion", "maps", "detail"];

/// Refuses a row of `CLAIMS.csv` with an unknown kind, a verdict word its kind does not allow,
/// or an id seen twice (`id`, `kind`, `verdict`: the column indices).
fn check_rows(t: &CsvTable, id: usize, kind: usize, verdict: usize) -> Result<()> {
    let mut seen: Vec<&str> = Vec::new();
    for r in &t.rows {
        let Some(k) = Kind::parse(r[kind].trim()) else {
            bail!(
                "{}: claim {}: kind '{}' is not one of {}",
                t.path.display(),
                echo(&r[id]),
                echo(&r[kind]),
                Kind::ALL.map(|k| k.as_str()).join(", ")
            );
        };
        let v = r[verdict].trim();
        if v != UNTESTABLE && !k.verdict_words().contains(&v) {
            bail!(
                "{}: claim {}: verdict '{}' is not one a{} {} claim may get ({} or {UNTESTABLE})",
                t.path.display(),
                echo(&r[id]),
                echo(&r[verdict]),
                if k == Kind::Measured { "" } else { "n" },
                k.as_str(),
                k.verdict_words().join(", ")
            );
        }
        if seen.contains(&r[id].as_str()) {
            bail!("{}: claim {} has two rows (one verdict per claim)", t.path.display(), echo(&r[id]));
        }
        seen.push(&r[id]);
    }
    Ok(())
}

/// The columns of `CLAIMS.csv` the at-a-glance table reads (indices).
struct Columns {
    id: usize,
    kind: usize,
    verdict: usize,
    paper_fig: usize,
    ours: usize,
    detail: usize,
}

/// A claim's row of the at-a-glance table: its id (linked to its evidence when the row has a
/// link inside `results/`), kind, what the paper says, both figures and the verdict; or, with
/// no row in CLAIMS.csv, that it was not judged.
fn glance_row(c: &Columns, cid: &str, says: &str, r: Option<&Vec<String>>) -> Vec<String> {
    let cell = |s: &str| s.trim().to_string();
    let id_cell = match r.and_then(|r| relative_link(&r[c.detail])) {
        Some(l) => format!("[{cid}]({})", href(l)),
        None => cid.to_string(),
    };
    match r {
        Some(r) => vec![
            id_cell,
            r[c.kind].trim().to_string(),
            cell(says),
            cell(&r[c.paper_fig]),
            cell(&r[c.ours]),
            format!("**{}**", r[c.verdict].trim()),
        ],
        None => {
            vec![id_cell, "-".into(), cell(says), "-".into(), "-".into(), "not judged (no row in CLAIMS.csv)".into()]
        }
    }
}

/// How many claims got each verdict word (`n word`), in the kinds' order of words, then
/// `untestable`; words no claim got left out.
fn verdict_counts(t: &CsvTable, verdict: usize) -> Vec<String> {
    let mut words: Vec<&str> = Vec::new();
    for w in Kind::ALL.iter().flat_map(|k| k.verdict_words().iter().copied()).chain([UNTESTABLE]) {
        if !words.contains(&w) {
            words.push(w);
        }
    }
    words
        .iter()
        .map(|w| (w, t.rows.iter().filter(|r| r[verdict].trim() == *w).count()))
        .filter(|(_, n)| *n > 0)
        .map(|(w, n)| format!("{n} {w}"))
        .collect()
}

/// The at-a-glance table: one row per claim, in paper order (declarations), then claims of
/// the CSV that no declaration lists. No cell is ever cut: short text is written at the source
/// (the declarations' `says` and `paper_figure`, the engine's headlines). `claims` is
/// `None` when `results/CLAIMS.csv` does not exist: one line says so.
pub fn at_a_glance(papers: &[Paper], claims: Option<&CsvTable>) -> Result<String> {
    let mut md = String::from("## Reproduction at a glance\n\n");
    let Some(t) = claims else {
        md.push_str(
            "`results/CLAIMS.csv` is not there yet: the claims engine writes it (`probelab reproduce`), and this \
             table then lists every claim with its verdict.\n\n",
        );
        return Ok(md);
    };
    let c = t.require(&CLAIMS_CSV_COLUMNS)?;
    let cols = Columns { id: c[0], kind: c[1], verdict: c[2], paper_fig: c[3], ours: c[4], detail: c[7] };
    check_rows(t, cols.id, cols.kind, cols.verdict)?;
    let row_of = |cid: &str| t.rows.iter().find(|r| r[cols.id] == cid);
    let mut rows = Vec::new();
    let mut sorted: Vec<&Paper> = papers.iter().collect();
    sorted.sort_by_key(|p| (p.order, p.key.clone()));
    for p in &sorted {
        for d in &p.claims {
            rows.push(glance_row(&cols, &d.id, &d.says, row_of(&d.id)));
        }
    }
    for r in &t.rows {
        if !papers.iter().flat_map(|p| &p.claims).any(|d| d.id == r[cols.id]) {
            rows.push(glance_row(&cols, &r[cols.id], "(no declaration)", Some(r)));
        }
    }
    let counts = verdict_counts(t, cols.verdict);
    let _ = writeln!(
        md,
        "{} claims judged: {}. The kind of evidence decides the words a verdict may use: `identity` (true by \
         derivation, checked to rounding: holds (identity) or fails), `measured` (a general statement: holds, \
         partly or fails), `example` (one case, as the paper showed it: reproduced or not reproduced), `anchor` \
         (the paper's figure comes from a population we do not have: not comparable). One primary check decides \
         each verdict; ratios are summarised per map by median and geometric mean, as each figure says. Each id \
         links to its evidence; [CLAIMS.csv](CLAIMS.csv) has the criterion and maps of each.\n",
        t.rows.len(),
        counts.join(", ")
    );
    let headers: Vec<String> =
        ["id", "kind", "the paper says", "paper's figure", "ours", "verdict"].iter().map(|s| s.to_string()).collect();
    md.push_str(&table_with(&headers, &rows, text_cell));
    md.push('\n');
    Ok(md)
}
