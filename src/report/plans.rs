//! The paper sections' plans: what REPORT.md shows of each paper besides its declaration — the
//! result folders that belong to it and the figures reproduced inline — declared in
//! `experiments/report/papers.toml` ([`PLAN_FILE`], parsed by [`parse_plans`]); and the
//! sections' titles in report order. Every folder and file a plan names stays inside
//! `results/` ([`relative_link`]).

use crate::claims::declaration::Paper;
use crate::math::echo::value as echo;
use anyhow::{bail, Result};
use serde::Deserialize;
use std::path::Path;

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
    /// The folder's `table.csv` by storage budget: for each budget of bytes a probe, the most
    /// accurate encoding that fits and the runner-up ([`super::budgets`]).
    Budgets {
        /// The result folder, relative to `results/`.
        folder: String,
        /// The budgets, bytes a probe, in the table's order.
        budgets: Vec<u32>,
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
            Figure::Pivot { folder, .. }
            | Figure::Ratios { folder, .. }
            | Figure::Budgets { folder, .. }
            | Figure::Costs { folder } => vec![folder],
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
pub(super) fn relative_link(l: &str) -> Option<&str> {
    let l = l.trim();
    let outside = l.is_empty()
        || l.starts_with('/')
        || l.contains("://")
        || l.contains('\\')
        || l.split('/').any(|p| p == "..")
        || (l.len() > 1 && l.as_bytes()[1] == b':');
    (!outside).then_some(l)
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
