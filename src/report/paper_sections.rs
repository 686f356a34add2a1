//! REPORT.md's paper sections (one per paper, in the order of [`super::plans::section_titles`]:
//! its claims, the figures its plan reproduces with their tables and charts, links to its pages)
//! and the list of other results.

use super::budgets;
use super::charts;
use super::csvfile::CsvTable;
use super::markdown::{self, href};
use super::names::{rel, PAGE, PROVENANCE_PAGE};
use super::page::Page;
use super::plans::{section_titles, Figure, PaperPlan};
use super::ratios::ratio_pivot;
use anyhow::Result;
use std::fmt::Write as _;
use std::path::Path;

/// One section per paper: its claims' ids, the paper's figures reproduced, and its pages.
pub(super) fn paper_sections(
    out: &Path,
    decls: &[crate::claims::declaration::Paper],
    plans: &[PaperPlan],
    pages: &[Page],
) -> Result<String> {
    let evidence = |key: &str| {
        let f = format!("claims/{key}.md");
        if out.join(&f).is_file() {
            format!(", evidence in [{f}]({})", href(&f))
        } else {
            String::new()
        }
    };
    let mut md = String::new();
    for (title, plan) in section_titles(decls, plans) {
        let _ = writeln!(md, "## {title}\n");
        let decl = decls.iter().find(|p| p.title == title);
        if let Some(p) = decl {
            let ids: Vec<String> = p.claims.iter().map(|c| c.id.clone()).collect();
            let _ = writeln!(
                md,
                "{}. {}. Claims {}: verdicts above{}.\n",
                p.authors,
                p.venue,
                ids.join(", "),
                evidence(&p.key)
            );
        }
        let Some(plan) = plan else { continue };
        for f in &plan.figures {
            md.push_str(&figure(out, f)?);
        }
        let links: Vec<String> = plan
            .pages
            .iter()
            .filter(|n| pages.iter().any(|p| p.name == **n && p.has_page))
            .map(|n| format!("[{n}]({})", href(&rel(n, PAGE))))
            .collect();
        if !links.is_empty() {
            let _ = writeln!(md, "Full pages (tables, every chart and sheet): {}.\n", links.join(" · "));
        }
    }
    Ok(md)
}

/// One figure of a paper section, or nothing when its file is absent.
pub(super) fn figure(out: &Path, f: &Figure) -> Result<String> {
    let mut md = String::new();
    match f {
        Figure::Pivot { folder, caption } => {
            let p = out.join(folder).join("table.csv");
            if p.is_file() {
                if let Some(pv) = markdown::pivot(&CsvTable::read(&p)?)? {
                    let _ = writeln!(
                        md,
                        "{caption} From [{folder}/table.csv]({}).\n\n{pv}",
                        href(&rel(folder, "table.csv"))
                    );
                }
            }
        }
        Figure::Ratios { folder, caption } => {
            let p = out.join(folder).join("summary.csv");
            if p.is_file() {
                if let Some(pv) = ratio_pivot(&CsvTable::read(&p)?)? {
                    let _ = writeln!(
                        md,
                        "{caption} From [{folder}/summary.csv]({}): {pv}",
                        href(&rel(folder, "summary.csv"))
                    );
                }
            }
        }
        Figure::Budgets { folder, budgets } => {
            let p = out.join(folder).join("table.csv");
            if p.is_file() {
                let link = href(&rel(folder, "table.csv"));
                if let Some(t) = budgets::budget_table(&CsvTable::read(&p)?, budgets, folder, &link)? {
                    let _ = writeln!(md, "{t}");
                }
            }
        }
        Figure::Csv { folder, file, caption } => {
            let p = out.join(folder).join(file);
            if p.is_file() {
                let t = CsvTable::read(&p)?;
                let _ = writeln!(
                    md,
                    "{caption} From [{folder}/{file}]({}):\n\n{}",
                    href(&rel(folder, file)),
                    whole_csv(&t)
                );
            }
        }
        Figure::Picture { folder, file, caption } => {
            if out.join(folder).join(file).is_file() {
                let _ = writeln!(
                    md,
                    "![{caption}]({})\n\n*{caption}* ([{folder}]({}))\n",
                    href(&rel(folder, file)),
                    href(&rel(folder, PAGE))
                );
            }
        }
        Figure::Costs { folder } => {
            let drawn: Vec<charts::Cost> = charts::Cost::ALL
                .into_iter()
                .filter(|c| *c != charts::Cost::FitNs && out.join(folder).join(c.file()).is_file())
                .collect();
            if !drawn.is_empty() {
                let _ = writeln!(
                    md,
                    "**What accuracy costs** ({folder}): error against {}; the red staircase is the Pareto front (lower \
                     cost and lower error both better). Fit time and the captions: [{folder}]({}).\n",
                    drawn.iter().map(|c| c.what()).collect::<Vec<_>>().join(", "),
                    href(&rel(folder, PAGE))
                );
                for c in drawn {
                    let _ = writeln!(md, "![error against {}]({})\n", c.what(), href(&rel(folder, c.file())));
                }
            }
        }
    }
    Ok(md)
}

/// Links to the pages no paper section lists.
pub(super) fn other_results(pages: &[Page], in_papers: &[&str]) -> String {
    let mut md = String::from("## Other results\n\n");
    let rest: Vec<&Page> = pages.iter().filter(|p| !in_papers.contains(&p.name.as_str())).collect();
    if rest.is_empty() {
        md.push_str("Every result folder is linked from a paper's section above.\n\n");
    }
    for p in rest {
        let what = p.description.as_deref().filter(|d| !d.is_empty()).unwrap_or("results without an experiment file");
        if p.has_page {
            let _ = writeln!(md, "- [{}]({}): {what}", p.name, href(&rel(&p.name, PAGE)));
        } else {
            let _ = writeln!(md, "- {}: no results yet (`probelab run experiments/{}.toml`): {what}", p.name, p.name);
        }
    }
    let _ = writeln!(
        md,
        "\nHow every table was made (commit, date, settings, maps with sha256): [{PROVENANCE_PAGE}]({PROVENANCE_PAGE}).\n"
    );
    md
}

/// A small CSV shown whole (numbers to 4 significant digits).
fn whole_csv(t: &CsvTable) -> String {
    let rows: Vec<Vec<String>> = t.rows.clone();
    markdown::table(&t.headers, &rows)
}
