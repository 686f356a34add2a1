//! The front of `results/REPORT.md`: the reproduction at a glance (one row per claim, from
//! `results/CLAIMS.csv` and the declarations `experiments/claims/*.toml`), and one section per
//! paper — the paper's own table or figure reproduced from the result CSVs, the sheets that
//! matter, what accuracy costs, and links to the per-experiment pages (`results/<name>/README.md`).
//!
//! Everything here is handed data (tables, declarations) and returns Markdown; `report` (mod.rs)
//! reads the files. No encoder is named: tables are pivoted over whatever encoders they hold.
//!
//! `CLAIMS.csv` (written by the claims engine, `claims::verdicts`): columns
//! `id,verdict,paper_figure,our_figure,criterion,maps,detail`, `verdict` one of
//! `holds|partly|fails|untestable`, `detail` a link relative to `results/`.

use super::csvfile::CsvTable;
use super::markdown::{href, table_with, text_cell};
use super::number::sig;
use crate::claims::declaration::Paper;
use anyhow::{bail, Result};
use std::fmt::Write as _;

/// The longest cell of the at-a-glance table, in characters (longer text is cut at a word
/// and ends in "…"; the full text is one click away in the claim's detail).
pub const CELL_MAX: usize = 150;

/// The columns `CLAIMS.csv` must have.
pub const CLAIMS_CSV_COLUMNS: [&str; 7] =
    ["id", "verdict", "paper_figure", "our_figure", "criterion", "maps", "detail"];

/// The verdicts a claim can get.
pub const VERDICTS: [&str; 4] = ["holds", "partly", "fails", "untestable"];

/// What the report shows of one paper, besides its declaration: the result folders that
/// belong to it (their pages are linked, in this order) and the figures reproduced inline.
/// The title is used only when the paper has no declaration file.
pub struct PaperPlan {
    pub key: &'static str,
    pub title: &'static str,
    pub pages: &'static [&'static str],
    pub figures: &'static [Figure],
}

/// A figure of a paper section, read from a result folder.
pub enum Figure {
    /// The folder's `table.csv` as a map × encoder rmse pivot per metric (`markdown::pivot`).
    Pivot { folder: &'static str, caption: &'static str },
    /// The folder's `summary.csv`: every encoder's ratio to the baseline, over all maps, per
    /// effects and orientation set ([`ratio_pivot`]).
    Ratios { folder: &'static str, caption: &'static str },
    /// A small CSV of the folder, shown whole.
    Csv { folder: &'static str, file: &'static str, caption: &'static str },
    /// A picture of the folder, inline.
    Picture { folder: &'static str, file: &'static str, caption: &'static str },
    /// The folder's error-against-cost charts (stored scalars, bytes, eval time), inline.
    Costs { folder: &'static str },
}

/// The three papers, in the report's order when no declaration gives one, then the landscape of
/// every encoding (a section without claims).
pub const PLANS: &[PaperPlan] = &[
    PaperPlan {
        key: "zh3",
        title: "ZH3: Quadratic Zonal Harmonics (I3D 2024 talk)",
        pages: &["zh3_table", "sh_baseline"],
        figures: &[
            Figure::Pivot {
                folder: "zh3_table",
                caption: "The talk's comparison (linear SH, stored and hallucinated ZH3, quadratic SH on a few maps), \
                          whole sphere, every ZH3 variant; `probulator` is the talk's own metric, `exact` ours.",
            },
            Figure::Costs { folder: "zh3_table" },
            Figure::Picture {
                folder: "zh3_table",
                file: "sheet_grace_256x128.png",
                caption: "Grace: the talk says ZH3 comes very close to SH3 here.",
            },
        ],
    },
    PaperPlan {
        key: "hemi",
        title: "Hemispherical Lighting Insights (SIGGRAPH 2024 Advances talk)",
        pages: &[
            "lightmap_table",
            "lightmap_search2d",
            "lightmap_self_bounce",
            "lightmap_claims",
            "probe_occlusion",
            "generated_probe_occlusion",
            "cone_ao",
        ],
        figures: &[
            Figure::Ratios {
                folder: "lightmap_table",
                caption: "Lightmap encodings (AHD/HHD, linear or searched direction, spherical or hemispherical \
                          Gram; H3, H4) on every real map, error over the hemisphere about N.",
            },
            Figure::Ratios {
                folder: "probe_occlusion",
                caption: "Hemispherical occlusion of SH probes (H8) on every real map.",
            },
            Figure::Ratios {
                folder: "cone_ao",
                caption: "The cone multiply against AO (H9), per cone (cos α, tilt of the cone from N).",
            },
            Figure::Costs { folder: "lightmap_table" },
            Figure::Picture {
                folder: "lightmap_table",
                file: "sheet_ennis_256x128.png",
                caption: "Ennis, floor (N = +y): each lightmap encoding against the exact reference.",
            },
        ],
    },
    PaperPlan {
        key: "brief2018",
        title: "Directional Lightmap Encoding Insights (SIGGRAPH Asia 2018 brief)",
        pages: &["lightmap_claims", "lightmap_table"],
        figures: &[
            Figure::Csv {
                folder: "claims/measures",
                file: "fig2.csv",
                caption: "Fig. 2 in closed form: blending two AHD texels whose directions are α apart, per \
                          direction-blend rule — where E(N) peaks, by how much it overshoots, and AHD over IrradZ at \
                          t = ½.",
            },
            Figure::Picture {
                folder: "claims",
                file: "blend_strip_grace_light_on.png",
                caption: "Blending a light on (grace): parameter blends against the blended reference.",
            },
        ],
    },
    PaperPlan {
        key: "landscape",
        title: "The landscape: every encoding by what it stores",
        pages: &["landscape", "landscape_hemi", "probulator_parity"],
        figures: &[
            Figure::Costs { folder: "landscape" },
            Figure::Ratios {
                folder: "landscape",
                caption: "Every probe encoding (the papers' and the peer tool's) on every usable real map, whole \
                          sphere: its error as a ratio to SH L1's.",
            },
            Figure::Costs { folder: "landscape_hemi" },
            Figure::Ratios {
                folder: "landscape_hemi",
                caption: "Every encoding on the hemisphere about N (lightmap use: H-basis, AHD, HHD and SH at their \
                          real storage), the light above the surface only, on every usable real map, six normals.",
            },
            Figure::Pivot {
                folder: "probulator_parity",
                caption: "Parity with the peer tool (Probulator): every encoding it has, on the five paper probes, \
                          scored with its metric against our exact reference; its own figures are in \
                          docs/peer_encodings.md.",
            },
        ],
    },
];

/// `s` cut to at most `max` characters, at a word boundary where there is one, ending in "…".
pub fn shorten(s: &str, max: usize) -> String {
    let s = s.trim();
    if s.chars().count() <= max {
        return s.to_string();
    }
    let cut: String = s.chars().take(max.saturating_sub(1)).collect();
    let at = cut.rfind(' ').filter(|&i| i > max / 2).unwrap_or(cut.len());
    format!("{}…", cut[..at].trim_end_matches([' ', ',', ';', ':']))
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

/// The at-a-glance table: one row per claim, in paper order (declarations), then claims of
/// the CSV that no declaration lists. Cells are at most [`CELL_MAX`] characters. `claims` is
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
    let (id, verdict, paper_fig, ours, detail) = (c[0], c[1], c[2], c[3], c[6]);
    let mut seen: Vec<&str> = Vec::new();
    for r in &t.rows {
        if !VERDICTS.contains(&r[verdict].trim()) {
            bail!(
                "{}: claim {}: verdict '{}' is not one of {}",
                t.path.display(),
                r[id],
                r[verdict],
                VERDICTS.join(", ")
            );
        }
        if seen.contains(&r[id].as_str()) {
            bail!("{}: claim {} has two rows (one verdict per claim)", t.path.display(), r[id]);
        }
        seen.push(&r[id]);
    }
    let row_of = |cid: &str| t.rows.iter().find(|r| r[id] == cid);
    let cell = |s: &str| shorten(s, CELL_MAX);
    let line = |cid: &str, says: &str, r: Option<&Vec<String>>| -> Vec<String> {
        let id_cell = match r.and_then(|r| relative_link(&r[detail])) {
            Some(l) => format!("[{cid}]({})", href(l)),
            None => cid.to_string(),
        };
        match r {
            Some(r) => {
                vec![id_cell, cell(says), cell(&r[paper_fig]), cell(&r[ours]), format!("**{}**", r[verdict].trim())]
            }
            None => vec![id_cell, cell(says), "-".into(), "-".into(), "not judged (no row in CLAIMS.csv)".into()],
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
    let count = |v: &str| t.rows.iter().filter(|r| r[verdict].trim() == v).count();
    let _ = writeln!(
        md,
        "{} claims judged: {} hold, {} partly, {} fail, {} untestable. Each id links to its evidence; \
         [CLAIMS.csv](CLAIMS.csv) has the criterion and maps of each.\n",
        t.rows.len(),
        count("holds"),
        count("partly"),
        count("fails"),
        count("untestable")
    );
    let headers: Vec<String> =
        ["id", "the paper says", "paper's figure", "ours", "verdict"].iter().map(|s| s.to_string()).collect();
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
    use std::path::Path;

    fn csv(s: &str) -> CsvTable {
        CsvTable::parse(Path::new("s.csv"), s.as_bytes()).unwrap()
    }

    #[test]
    fn shorten_cuts_at_a_word() {
        assert_eq!(shorten("short", 150), "short");
        let s = shorten("alpha beta gamma delta", 12);
        assert_eq!(s, "alpha beta…");
        assert!(s.chars().count() <= 12);
        let long = "x".repeat(400);
        assert_eq!(shorten(&long, 150).chars().count(), 150);
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
