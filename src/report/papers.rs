//! The front of `results/REPORT.md`: the reproduction at a glance (one row per claim, from
//! `results/CLAIMS.csv` and the declarations `experiments/claims/*.toml`), and one section per
//! paper — the paper's own table or figure reproduced from the result CSVs, the sheets that
//! matter, what accuracy costs, and links to the per-experiment pages (`results/<name>/README.md`).
//!
//! Which result folders and figures belong to which paper section is data: the plans of
//! `experiments/report/papers.toml` ([`PLAN_FILE`], parsed by [`parse_plans`]).
//!
//! Everything here is handed data (tables, declarations, the plan file's text) and returns
//! Markdown or plans; `report` (mod.rs) reads the files. No encoder is named: tables are
//! pivoted over whatever encoders they hold.
//!
//! `CLAIMS.csv` (written by the claims engine, `claims::verdicts`): columns
//! `id,kind,verdict,paper_figure,our_figure,criterion,maps,detail`, `kind` one of
//! `identity|measured|example|anchor`, `verdict` one of the words its kind allows (or
//! `untestable`), `detail` a link relative to `results/`.

use super::csvfile::CsvTable;
use super::markdown::{href, table_with, text_cell};
use super::number::sig;
use crate::claims::declaration::{Kind, Paper, UNTESTABLE};
use crate::math::echo::value as echo;
use anyhow::{bail, Result};
use serde::Deserialize;
use std::fmt::Write as _;
use std::path::Path;

/// The columns `CLAIMS.csv` must have.
pub const CLAIMS_CSV_COLUMNS: [&str; 8] =
    ["id", "kind", "verdict", "paper_figure", "our_figure", "criterion", "maps", "detail"];

/// Where the paper sections' plans are declared, relative to `experiments/` (a subfolder, so
/// that no experiment listing takes it for an experiment).
pub const PLAN_FILE: &str = "report/papers.toml";

/// What the report shows of one paper, besides its declaration: the result folders that
/// belong to it (their pages are linked, in this order) and the figures reproduced inline.
/// The title is used only when the paper has no declaration file. Declared in
/// [`PLAN_FILE`] (one `[[section]]` each), read by [`parse_plans`].
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PaperPlan {
    /// The paper: its declaration's file stem (`experiments/claims/<key>.toml`), or a section
    /// without claims.
    pub key: String,
    /// The section's title when no declaration of `key` exists.
    pub title: String,
    /// The result folders of the section, in link order.
    #[serde(default)]
    pub pages: Vec<String>,
    /// The figures reproduced inline, in order (`[[section.figure]]`).
    #[serde(default, rename = "figure")]
    pub figures: Vec<Figure>,
}

/// A figure of a paper section, read from a result folder (`kind` in the plan file).
#[derive(Debug, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Figure {
    /// The folder's `table.csv` as a map × encoder rmse pivot per metric (`markdown::pivot`).
    Pivot {
        /// The result folder, relative to `results/`.
        folder: String,
        /// The text before the pivot.
        caption: String,
    },
    /// The folder's `summary.csv`: every encoder's ratio to the baseline, over all maps, per
    /// effects and orientation set ([`ratio_pivot`]).
    Ratios {
        /// The result folder, relative to `results/`.
        folder: String,
        /// The text before the ratios.
        caption: String,
    },
    /// A small CSV of the folder, shown whole.
    Csv {
        /// The result folder, relative to `results/`.
        folder: String,
        /// The CSV file in the folder.
        file: String,
        /// The text before the table.
        caption: String,
    },
    /// A picture of the folder, inline.
    Picture {
        /// The result folder, relative to `results/`.
        folder: String,
        /// The picture's file in the folder.
        file: String,
        /// The picture's alt text and the caption below it.
        caption: String,
    },
    /// The folder's error-against-cost charts (stored scalars, bytes, eval time), inline.
    Costs {
        /// The result folder, relative to `results/`.
        folder: String,
    },
}

/// The plan file as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlanFile {
    #[serde(default)]
    section: Vec<PaperPlan>,
}

/// Parses the paper sections' plans ([`PLAN_FILE`]'s text; `origin` names it in errors), in
/// the file's order: the report's order for sections that no declaration orders. Keys are
/// unique and every folder and file stays inside `results/`.
pub fn parse_plans(text: &str, origin: &Path) -> Result<Vec<PaperPlan>> {
    let f: PlanFile = crate::pipeline::experiment::parse_toml(text, origin)
        .map_err(|e| anyhow::anyhow!("{e:#} (not a report plan)"))?;
    for (i, p) in f.section.iter().enumerate() {
        if p.key.is_empty() || f.section[..i].iter().any(|q| q.key == p.key) {
            bail!("{}: section key '{}' is empty or declared twice", origin.display(), echo(&p.key));
        }
        let files = p.figures.iter().flat_map(|g| match g {
            Figure::Csv { folder, file, .. } | Figure::Picture { folder, file, .. } => vec![folder, file],
            Figure::Pivot { folder, .. } | Figure::Ratios { folder, .. } | Figure::Costs { folder } => vec![folder],
        });
        for f in p.pages.iter().chain(files) {
            if relative_link(f) != Some(f.as_str()) {
                bail!("{}: section '{}': '{}' is not a path inside results/", origin.display(), echo(&p.key), echo(f));
            }
        }
    }
    Ok(f.section)
}

/// The papers' section titles, in report order: declared papers by `order`, then any plan
/// without a declaration, in the plans' order. Each with its plan, when the report has one.
pub fn section_titles<'a>(papers: &[Paper], plans: &'a [PaperPlan]) -> Vec<(String, Option<&'a PaperPlan>)> {
    let mut sorted: Vec<&Paper> = papers.iter().collect();
    sorted.sort_by_key(|p| (p.order, p.key.clone()));
    let mut out: Vec<(String, Option<&PaperPlan>)> = Vec::new();
    for p in sorted {
        out.push((p.title.clone(), plans.iter().find(|pl| pl.key == p.key)));
    }
    for pl in plans {
        if !papers.iter().any(|p| p.key == pl.key) {
            out.push((pl.title.clone(), Some(pl)));
        }
    }
    out
}

/// A link target that stays inside `results/`: relative, no scheme, no `..`, no backslash.
fn relative_link(l: &str) -> Option<&str> {
    let l = l.trim();
    let outside = l.is_empty()
        || l.starts_with('/')
        || l.contains("://")
        || l.contains('\\')
        || l.split('/').any(|p| p == "..")
        || (l.len() > 1 && l.as_bytes()[1] == b':');
    (!outside).then_some(l)
}

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
    let (id, kind, verdict, paper_fig, ours, detail) = (c[0], c[1], c[2], c[3], c[4], c[7]);
    check_rows(t, id, kind, verdict)?;
    let row_of = |cid: &str| t.rows.iter().find(|r| r[id] == cid);
    let cell = |s: &str| s.trim().to_string();
    let line = |cid: &str, says: &str, r: Option<&Vec<String>>| -> Vec<String> {
        let id_cell = match r.and_then(|r| relative_link(&r[detail])) {
            Some(l) => format!("[{cid}]({})", href(l)),
            None => cid.to_string(),
        };
        match r {
            Some(r) => vec![
                id_cell,
                r[kind].trim().to_string(),
                cell(says),
                cell(&r[paper_fig]),
                cell(&r[ours]),
                format!("**{}**", r[verdict].trim()),
            ],
            None => {
                vec![
                    id_cell,
                    "-".into(),
                    cell(says),
                    "-".into(),
                    "-".into(),
                    "not judged (no row in CLAIMS.csv)".into(),
                ]
            }
        }
    };
    let mut rows = Vec::new();
    let mut sorted: Vec<&Paper> = papers.iter().collect();
    sorted.sort_by_key(|p| (p.order, p.key.clone()));
    for p in &sorted {
        for d in &p.claims {
            rows.push(line(&d.id, &d.says, row_of(&d.id)));
        }
    }
    for r in &t.rows {
        if !papers.iter().flat_map(|p| &p.claims).any(|d| d.id == r[id]) {
            rows.push(line(&r[id], "(no declaration)", Some(r)));
        }
    }
    let mut words: Vec<&str> = Vec::new();
    for w in Kind::ALL.iter().flat_map(|k| k.verdict_words().iter().copied()).chain([UNTESTABLE]) {
        if !words.contains(&w) {
            words.push(w);
        }
    }
    let counts: Vec<String> = words
        .iter()
        .map(|w| (w, t.rows.iter().filter(|r| r[verdict].trim() == *w).count()))
        .filter(|(_, n)| *n > 0)
        .map(|(w, n)| format!("{n} {w}"))
        .collect();
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

/// Every encoder's ratio to the summary's baseline over all maps, from a `summary.csv`: one
/// row per encoder, one column per (effects, orientation set) — either left out of the label
/// when it has one value — each cell "ratio of means (median ratio)". Rows of metric `exact`
/// when there are any. `None` when the file has no ratio columns or no rows.
pub fn ratio_pivot(t: &CsvTable) -> Result<Option<String>> {
    let need = ["encoder", "effects", "metric", "orientation_set", "domain", "map", "baseline", "ratio_of_means"];
    if need.iter().any(|c| t.col(c).is_none()) || t.rows.is_empty() {
        return Ok(None);
    }
    let c = t.require(&need)?;
    let (ec, fc, mc, sc, dc, pc, bc, rc) = (c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]);
    let medc = t.col("median_ratio");
    let nc = t.col("n_ratio");
    let exc = t.col("n_below_floor");
    let metric = if t.rows.iter().any(|r| r[mc] == "exact") { "exact".to_string() } else { t.rows[0][mc].clone() };
    let rows: Vec<usize> = (0..t.rows.len())
        .filter(|&i| t.rows[i][dc] == "*" && t.rows[i][pc] == "*" && t.rows[i][mc] == metric)
        .collect();
    if rows.is_empty() {
        return Ok(None);
    }
    let distinct = |col: usize| {
        let mut v: Vec<String> = Vec::new();
        for &i in &rows {
            if !v.contains(&t.rows[i][col]) {
                v.push(t.rows[i][col].clone());
            }
        }
        v
    };
    let (encs, effects, sets) = (distinct(ec), distinct(fc), distinct(sc));
    let mut cols: Vec<(String, String)> = Vec::new();
    for e in &effects {
        for s in &sets {
            if rows.iter().any(|&i| t.rows[i][fc] == *e && t.rows[i][sc] == *s) {
                cols.push((e.clone(), s.clone()));
            }
        }
    }
    let label = |(e, s): &(String, String)| match (effects.len() > 1, sets.len() > 1) {
        (true, true) => format!("{e}, {s}"),
        (true, false) => e.clone(),
        _ => s.clone(),
    };
    let baselines = distinct(bc);
    let mut headers = vec!["encoder".to_string()];
    headers.extend(cols.iter().map(label));
    let (mut n_max, mut excluded) = (0usize, 0usize);
    let mut body = Vec::new();
    for e in &encs {
        let mut row = vec![e.clone()];
        for (fx, st) in &cols {
            let i = rows.iter().copied().find(|&i| t.rows[i][ec] == *e && t.rows[i][fc] == *fx && t.rows[i][sc] == *st);
            row.push(match i {
                Some(i) => {
                    if let Some(n) = nc.and_then(|c| t.rows[i][c].parse::<usize>().ok()) {
                        n_max = n_max.max(n);
                    }
                    excluded += exc.and_then(|c| t.rows[i][c].parse::<usize>().ok()).unwrap_or(0);
                    match (t.num(i, rc)?, medc.map(|c| t.num(i, c)).transpose()?.flatten()) {
                        (Some(r), Some(m)) => format!("{} ({})", sig(r, 3), sig(m, 3)),
                        (Some(r), None) => sig(r, 3),
                        _ => "-".into(),
                    }
                }
                None => "-".into(),
            });
        }
        body.push(row);
    }
    let mut md = format!(
        "rmse ratio to `{}` (metric `{metric}`): **ratio of means** Σ rmse / Σ baseline rmse, and in brackets the \
         median of the per-row ratios, over up to {n_max} rows (maps × orientations) per cell; below 1 = lower error \
         than the baseline.",
        baselines.join("`, `")
    );
    if excluded > 0 {
        let _ = write!(md, " {excluded} row(s) left out: their baseline is exact to the floor (see summary.csv).");
    }
    md.push_str("\n\n");
    md.push_str(&table_with(&headers, &body, text_cell));
    md.push('\n');
    Ok(Some(md))
}

/// A small CSV shown whole (numbers to 4 significant digits).
pub fn whole_csv(t: &CsvTable) -> String {
    let rows: Vec<Vec<String>> = t.rows.clone();
    super::markdown::table(&t.headers, &rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv(s: &str) -> CsvTable {
        CsvTable::parse(Path::new("s.csv"), s.as_bytes()).unwrap()
    }

    #[test]
    fn plans_parse_in_order_and_stay_inside_results() {
        let text = "[[section]]\nkey = 'b'\ntitle = 'B'\npages = ['x', 'y']\n\
                    [[section.figure]]\nkind = 'picture'\nfolder = 'x'\nfile = 'p.png'\ncaption = 'c'\n\
                    [[section.figure]]\nkind = 'costs'\nfolder = 'y'\n\
                    [[section]]\nkey = 'a'\ntitle = 'A'\n";
        let plans = parse_plans(text, Path::new("p.toml")).unwrap();
        assert_eq!(plans.iter().map(|p| p.key.as_str()).collect::<Vec<_>>(), ["b", "a"]);
        assert_eq!(plans[0].pages, ["x", "y"]);
        assert_eq!(
            plans[0].figures,
            [
                Figure::Picture { folder: "x".into(), file: "p.png".into(), caption: "c".into() },
                Figure::Costs { folder: "y".into() }
            ]
        );
        assert!(plans[1].pages.is_empty() && plans[1].figures.is_empty());
        let err = |t: &str| format!("{:#}", parse_plans(t, Path::new("p.toml")).unwrap_err());
        assert!(err("[[section]]\nkey = 'a'\ntitle = 'A'\n[[section]]\nkey = 'a'\ntitle = 'B'\n").contains("twice"));
        assert!(err("[[section]]\nkey = 'a'\ntitle = 'A'\npages = ['../x']\n").contains("inside results/"));
        assert!(err(
            "[[section]]\nkey = 'a'\ntitle = 'A'\n[[section.figure]]\nkind = 'costs'\nfolder = 'x'\ncaption = 'c'\n"
        )
        .contains("p.toml"));
        assert!(err("[[section]]\nkey = 'a'\ntitle = 'A'\n[[section.figure]]\nkind = 'chart'\nfolder = 'x'\n")
            .contains("p.toml"));
    }

    #[test]
    fn links_stay_inside_results() {
        assert_eq!(relative_link("claims/zh3.md#z6"), Some("claims/zh3.md#z6"));
        for bad in ["/abs/x.md", "../x.md", "https://x.org", "C:\\x", "a\\b", ""] {
            assert_eq!(relative_link(bad), None, "{bad}");
        }
    }

    #[test]
    fn ratio_pivot_reads_the_summary() {
        let t = csv(
            "encoder,effects,metric,orientation_set,domain,map,n,baseline,n_ratio,n_below_floor,ratio_of_means,median_ratio\n\
             a,hemisphere,exact,up,*,*,2,b,2,0,0.5,0.25\n\
             a,hemisphere,exact,up,*,m1,1,b,1,0,0.5,0.5\n\
             a,hemisphere,exact,axes6,*,*,12,b,11,1,0.8,0.7\n\
             b,hemisphere,exact,up,*,*,2,b,2,0,1,1\n",
        );
        let md = ratio_pivot(&t).unwrap().unwrap();
        assert!(md.contains("| encoder | up | axes6 |"), "{md}");
        assert!(md.contains("| a | 0.500 (0.250) | 0.800 (0.700) |"), "{md}");
        assert!(md.contains("| b | 1.00 (1.00) | - |"), "{md}");
        // The per-map line (n_ratio 1) is not a cell; the largest cell has 11 rows compared.
        assert!(md.contains("up to 11 rows"), "{md}");
        assert!(md.contains("1 row(s) left out"), "{md}");
        // An old summary without the ratio-of-means column gives nothing rather than a wrong figure.
        assert!(ratio_pivot(&csv("encoder,mean_ratio\na,804795\n")).unwrap().is_none());
    }
}
