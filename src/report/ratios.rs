//! Every encoder's ratio to the baseline from a `summary.csv`, as a Markdown table: shown on a
//! result folder's page and in the paper sections. Tables are pivoted over whatever encoders
//! they hold.

use super::csvfile::CsvTable;
use super::markdown::{table_with, text_cell};
use super::number::sig;
use anyhow::Result;
use std::fmt::Write as _;

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
    let distinct = |col: usize| distinct(t, &rows, col);
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

/// The values of column `col` over `rows`, each once, in first-seen order.
fn distinct(t: &CsvTable, rows: &[usize], col: usize) -> Vec<String> {
    let mut v: Vec<String> = Vec::new();
    for &i in rows {
        if !v.contains(&t.rows[i][col]) {
            v.push(t.rows[i][col].clone());
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn csv(s: &str) -> CsvTable {
        CsvTable::parse(Path::new("s.csv"), s.as_bytes()).unwrap()
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
