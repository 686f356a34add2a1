//! Markdown pieces of `results/REPORT.md`: tables generated from CSVs (never by hand), claims
//! tables, links relative to the report so that it renders on a git host.

use super::csvfile::CsvTable;
use super::number::sig;
use anyhow::Result;

/// The columns of a claims file (`results/*/claims.csv`), in this order.
pub const CLAIMS_COLUMNS: &[&str] = &["id", "claim", "paper_figure", "our_figure", "holds"];

/// Per-channel columns left to the CSV (the report shows the combined `rmse`).
const DETAIL_COLUMNS: &[&str] = &["rmse_r", "rmse_g", "rmse_b"];

/// Full tables longer than this are linked, not inlined.
pub const MAX_INLINE_ROWS: usize = 300;

/// A cell: numbers to 4 significant digits, `|` escaped, newlines flattened.
pub fn cell(s: &str) -> String {
    let t = s.trim();
    if let Ok(v) = t.parse::<f64>() {
        if v.is_finite() && !t.is_empty() && t.chars().any(|c| c == '.' || c == 'e' || c == 'E') {
            return sig(v, 4);
        }
    }
    text_cell(t)
}

/// Text for a cell, as written (`|` escaped, newlines flattened).
pub fn text_cell(s: &str) -> String {
    s.trim().replace('|', "\\|").replace(['\n', '\r'], " ")
}

/// A Markdown pipe table; numbers to 4 significant digits.
pub fn table(headers: &[String], rows: &[Vec<String>]) -> String {
    table_with(headers, rows, cell)
}

/// A Markdown pipe table with cells formatted by `f`.
pub fn table_with(headers: &[String], rows: &[Vec<String>], f: fn(&str) -> String) -> String {
    let mut s = String::new();
    s.push_str(&format!("| {} |\n", headers.iter().map(|h| text_cell(h)).collect::<Vec<_>>().join(" | ")));
    s.push_str(&format!("|{}\n", headers.iter().map(|_| "---|").collect::<String>()));
    for r in rows {
        s.push_str(&format!("| {} |\n", r.iter().map(|c| f(c)).collect::<Vec<_>>().join(" | ")));
    }
    s
}

/// A relative link target: `/`-separated, spaces and parentheses percent-encoded.
pub fn href(rel: &str) -> String {
    rel.replace('\\', "/").replace(' ', "%20").replace('(', "%28").replace(')', "%29")
}

/// GitHub's heading anchor for simple headings: lower case, spaces to '-', other punctuation
/// except '-' and '_' dropped.
pub fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn distinct(t: &CsvTable, col: usize, rows: &[usize]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for &i in rows {
        if !out.contains(&t.rows[i][col]) {
            out.push(t.rows[i][col].clone());
        }
    }
    out
}

/// The rmse of every (map, encoder), one pivot per metric; a mean over the cases when the
/// table has several per (map, encoder). `None` when the table lacks map/encoder/rmse.
pub fn pivot(t: &CsvTable) -> Result<Option<String>> {
    let (Some(mc), Some(ec), Some(rc)) = (t.col("map"), t.col("encoder"), t.col("rmse")) else { return Ok(None) };
    let all: Vec<usize> = (0..t.rows.len()).collect();
    let metrics = match t.col("metric") {
        Some(c) => distinct(t, c, &all).into_iter().map(|m| Some((c, m))).collect(),
        None => vec![None],
    };
    let mut out = String::new();
    for metric in metrics {
        let rows: Vec<usize> =
            all.iter().copied().filter(|&i| metric.as_ref().is_none_or(|(c, m)| t.rows[i][*c] == *m)).collect();
        if rows.is_empty() {
            continue; // a header-only table: nothing to pivot (and no rows[0] to label it)
        }
        let maps = distinct(t, mc, &rows);
        let encs = distinct(t, ec, &rows);
        // (sum, count, worst) per (map, encoder).
        let mut cells = vec![vec![(0.0, 0usize, f64::NEG_INFINITY); encs.len()]; maps.len()];
        for &i in &rows {
            if let Some(v) = t.num(i, rc)? {
                // Cannot fail: `maps` and `encs` were collected from these very rows.
                let m = maps.iter().position(|x| *x == t.rows[i][mc]).expect("collected");
                let e = encs.iter().position(|x| *x == t.rows[i][ec]).expect("collected");
                let c = &mut cells[m][e];
                c.0 += v;
                c.1 += 1;
                c.2 = c.2.max(v);
            }
        }
        let k = cells.iter().flatten().map(|c| c.1).max().unwrap_or(0);
        let unit = t.col("units").map(|c| format!(" of {}", t.rows[rows[0]][c])).unwrap_or_default();
        let mut what = format!("rmse{unit}");
        if let Some((_, m)) = &metric {
            what.push_str(&format!(", metric `{m}`"));
            if let Some(wc) = t.col("weighting") {
                what.push_str(&format!(" ({})", t.rows[rows[0]][wc]));
            }
        }
        if k > 1 {
            let cases = t.col("domain").map(|c| distinct(t, c, &rows).len()).unwrap_or(k);
            what.push_str(&format!("; mean / worst over the {k} cases per map and encoder ({cases} domain label(s))"));
        }
        out.push_str(&format!("**{what}**, map × encoder:\n\n"));
        let mut headers = vec!["map".to_string()];
        headers.extend(encs.iter().cloned());
        let body: Vec<Vec<String>> = maps
            .iter()
            .zip(&cells)
            .map(|(m, row)| {
                std::iter::once(m.clone())
                    .chain(row.iter().map(|&(s, n, worst)| match n {
                        0 => "-".into(),
                        1 => sig(s, 4),
                        _ => format!("{} / {}", sig(s / n as f64, 4), sig(worst, 4)),
                    }))
                    .collect()
            })
            .collect();
        out.push_str(&table(&headers, &body));
        out.push('\n');
    }
    Ok(Some(out))
}

/// Median of every `*_ns` column per encoder, when the table has any.
pub fn timing_summary(t: &CsvTable) -> Result<Option<String>> {
    let Some(ec) = t.col("encoder") else { return Ok(None) };
    let ns: Vec<usize> = (0..t.headers.len()).filter(|&c| t.headers[c].ends_with("_ns")).collect();
    if ns.is_empty() {
        return Ok(None);
    }
    let all: Vec<usize> = (0..t.rows.len()).collect();
    let mut headers = vec!["encoder".to_string()];
    headers.extend(ns.iter().map(|&c| format!("median {}", t.headers[c])));
    let mut body = Vec::new();
    for e in distinct(t, ec, &all) {
        let mut row = vec![e.clone()];
        for &c in &ns {
            let mut v = Vec::new();
            for &i in all.iter().filter(|&&i| t.rows[i][ec] == e) {
                if let Some(x) = t.num(i, c)? {
                    v.push(x);
                }
            }
            v.sort_by(f64::total_cmp);
            row.push(if v.is_empty() { "-".into() } else { sig(v[v.len() / 2], 3) });
        }
        body.push(row);
    }
    Ok(Some(format!("**Timing** (median over the table's rows):\n\n{}\n", table(&headers, &body))))
}

/// The whole table: columns whose value is the same in every row are stated once above it;
/// the per-channel rmse columns are left to the CSV. Long tables are not inlined.
pub fn full_table(t: &CsvTable, csv_link: &str) -> String {
    if t.rows.is_empty() {
        return "The table has no rows.\n".into();
    }
    let mut common = Vec::new();
    let mut shown = Vec::new();
    for (c, h) in t.headers.iter().enumerate() {
        if DETAIL_COLUMNS.contains(&h.as_str()) {
            continue;
        }
        if t.rows.len() > 1 && t.is_constant(c) {
            if !t.rows[0][c].is_empty() {
                common.push(format!("{h} = `{}`", t.rows[0][c].replace('`', "'")));
            }
        } else {
            shown.push(c);
        }
    }
    let mut s = String::new();
    if !common.is_empty() {
        s.push_str(&format!("Every row: {}.\n\n", common.join(", ")));
    }
    if t.rows.len() > MAX_INLINE_ROWS {
        s.push_str(&format!("{} rows: too many to show here; see [the CSV]({}).\n", t.rows.len(), href(csv_link)));
        return s;
    }
    let headers: Vec<String> = shown.iter().map(|&c| t.headers[c].clone()).collect();
    let rows: Vec<Vec<String>> = t.rows.iter().map(|r| shown.iter().map(|&c| r[c].clone()).collect()).collect();
    s.push_str(&table(&headers, &rows));
    s
}

/// A claims file as a table (columns `id,claim,paper_figure,our_figure,holds`; any other
/// columns, such as `notes` or `check`, follow). A file without those five is an error naming
/// the file.
pub fn claims_table(t: &CsvTable) -> Result<String> {
    let cols = t.require(CLAIMS_COLUMNS)?;
    let extra: Vec<usize> = (0..t.headers.len()).filter(|c| !cols.contains(c)).collect();
    let order: Vec<usize> = cols.iter().chain(&extra).copied().collect();
    let headers: Vec<String> = order.iter().map(|&c| t.headers[c].clone()).collect();
    let hc = cols[4];
    let rows: Vec<Vec<String>> = t
        .rows
        .iter()
        .map(|r| {
            order
                .iter()
                .map(|&c| {
                    if c == hc {
                        match r[c].trim().to_lowercase().as_str() {
                            "yes" | "true" | "holds" => "**yes**".to_string(),
                            "no" | "false" => "**no**".to_string(),
                            _ => r[c].clone(),
                        }
                    } else {
                        r[c].clone()
                    }
                })
                .collect()
        })
        .collect();
    Ok(table_with(&headers, &rows, text_cell))
}

/// Relative file links and image sources in Markdown text (`](target)` and `src="target"`),
/// without anchors and external URLs.
#[cfg(test)]
pub fn local_links(md: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = md;
    while let Some(i) = rest.find("](") {
        rest = &rest[i + 2..];
        if let Some(j) = rest.find(')') {
            out.push(rest[..j].to_string());
        }
    }
    for attr in ["src=\"", "href=\""] {
        let mut rest = md;
        while let Some(i) = rest.find(attr) {
            rest = &rest[i + attr.len()..];
            if let Some(j) = rest.find('"') {
                out.push(rest[..j].to_string());
            }
        }
    }
    out.into_iter()
        .filter(|l| !l.starts_with('#') && !l.contains("://") && !l.starts_with("mailto:"))
        .map(|l| l.split('#').next().unwrap_or("").replace("%20", " ").replace("%28", "(").replace("%29", ")"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn csv(s: &str) -> CsvTable {
        CsvTable::parse(Path::new("t.csv"), s.as_bytes()).unwrap()
    }

    #[test]
    fn pivot_means_cases_per_metric() {
        let t = csv(
            "map,encoder,domain,metric,rmse,units\na,sh1,hemisphere:+x,exact,0.5,E/pi\na,sh1,hemisphere:-x,exact,0.25,E/pi\n\
             a,sh2,hemisphere:+x,exact,0.1,E/pi\na,sh2,hemisphere:-x,exact,0.1,E/pi\n",
        );
        let p = pivot(&t).unwrap().unwrap();
        assert!(p.contains("| a | 0.3750 / 0.5000 | 0.1000 / 0.1000 |"), "{p}");
        assert!(p.contains("mean / worst over the 2 cases"), "{p}");
        assert!(p.contains("rmse of E/pi, metric `exact`"), "{p}");
    }

    #[test]
    fn full_table_factors_constant_columns() {
        let t = csv("map,encoder,rmse,rmse_r,units\na,sh1,0.5,0.4,E/pi\nb,sh1,0.25,0.2,E/pi\n");
        let s = full_table(&t, "x/table.csv");
        assert!(s.contains("Every row: encoder = `sh1`, units = `E/pi`."), "{s}");
        assert!(s.contains("| map | rmse |") && !s.contains("rmse_r"), "{s}");
    }

    #[test]
    fn claims_need_their_columns_and_mark_holds() {
        let t = csv("id,claim,paper_figure,our_figure,holds,notes\nH3,more than halves,0.45,0.41,yes,a|b\n");
        let s = claims_table(&t).unwrap();
        assert!(s.contains("| H3 | more than halves | 0.45 | 0.41 | **yes** | a\\|b |"), "{s}");
        let bad = csv("id,claim\nH1,x\n");
        assert!(claims_table(&bad).unwrap_err().to_string().contains("missing column(s) paper_figure"));
    }

    #[test]
    fn links_are_found_and_decoded() {
        let md = "![a](x/sheet%20a.png) [b](y.csv#L2) [c](#anchor) [d](https://x.org) <img src=\"z.png\"> <a href=\"../e.toml\">";
        assert_eq!(local_links(md), vec!["x/sheet a.png", "y.csv", "z.png", "../e.toml"]);
        assert_eq!(anchor("sh_baseline"), "sh_baseline");
        assert_eq!(anchor("How this run was made"), "how-this-run-was-made");
    }
}
