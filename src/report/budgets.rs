//! The table by storage budget that opens REPORT.md's landscape section: for each budget of
//! bytes a probe, the most accurate encoding that fits it (by the median over maps of its
//! relative RMSE), its error and evaluation cost, and the runner-up. Read from a committed
//! `table.csv` alone: an encoding's bytes are the `bytes` its quantised fit reports in
//! `diagnostics`, else [`HALF_BYTES`] per stored scalar (its `stored_scalars` column), as
//! [`Encoder::stored_bytes`](crate::encoders::encoder::Encoder::stored_bytes) defines them.

use super::csvfile::CsvTable;
use super::markdown::table;
use super::number::percent;
use crate::encoders::encoder::HALF_BYTES;
use anyhow::Result;
use std::collections::BTreeMap;

/// One encoding's standing in a table: its bytes a probe, and the medians over its rows.
#[derive(Clone, Debug, PartialEq)]
pub struct Standing {
    /// The encoder's name in the table.
    pub encoder: String,
    /// Bytes stored per probe.
    pub bytes: f64,
    /// The median over maps (rows) of `rel_rmse`: RMSE over the RMS of the reference E/π.
    pub rel_rmse: f64,
    /// The median over rows of `eval_ns`, ns per shaded normal; None without timing.
    pub eval_ns: Option<f64>,
    /// How many rows (maps) the medians are over.
    pub rows: usize,
}

/// The value of `key` in a `diagnostics` cell (`k=v;k=v`).
fn diagnostic(cell: &str, key: &str) -> Option<f64> {
    cell.split(';').filter_map(|kv| kv.split_once('=')).find(|(k, _)| k.trim() == key)?.1.trim().parse().ok()
}

/// The median of finite values (the lower middle of an even count); None when there are none.
fn median(mut v: Vec<f64>) -> Option<f64> {
    v.retain(|x| x.is_finite());
    v.sort_by(f64::total_cmp);
    (!v.is_empty()).then(|| v[(v.len() - 1) / 2])
}

/// Every encoder's standing over the table's `metric` rows, in first-appearance order; None
/// when the table lacks a column it needs.
pub fn standings(t: &CsvTable, metric: &str) -> Option<Vec<Standing>> {
    let cols = t.require(&["encoder", "metric", "rel_rmse", "stored_scalars", "diagnostics"]).ok()?;
    let [ec, mc, rc, sc, dc] = cols[..] else { return None };
    let tc = t.col("eval_ns");
    let mut order: Vec<String> = Vec::new();
    let mut rows: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (i, r) in t.rows.iter().enumerate().filter(|(_, r)| r[mc] == metric) {
        if !rows.contains_key(&r[ec]) {
            order.push(r[ec].clone());
        }
        rows.entry(r[ec].clone()).or_default().push(i);
    }
    let num = |i: usize, c: usize| t.num(i, c).ok().flatten();
    let out = order.into_iter().filter_map(|encoder| {
        let ix = &rows[&encoder];
        let bytes =
            diagnostic(&t.rows[ix[0]][dc], "bytes").or_else(|| num(ix[0], sc).map(|s| s * HALF_BYTES as f64))?;
        Some(Standing {
            bytes,
            rel_rmse: median(ix.iter().filter_map(|&i| num(i, rc)).collect())?,
            eval_ns: tc.and_then(|c| median(ix.iter().filter_map(|&i| num(i, c)).collect())),
            rows: ix.len(),
            encoder,
        })
    });
    Some(out.collect())
}

/// The two most accurate encodings within `budget` bytes (lowest median rel_rmse; a tie goes to
/// fewer bytes, then to the earlier in the table).
pub fn best_within(all: &[Standing], budget: f64) -> Vec<&Standing> {
    let mut fit: Vec<&Standing> = all.iter().filter(|s| s.bytes <= budget).collect();
    fit.sort_by(|a, b| a.rel_rmse.total_cmp(&b.rel_rmse).then(a.bytes.total_cmp(&b.bytes)));
    fit.truncate(2);
    fit
}

/// An encoding's cell: its name and bytes.
fn named(s: &Standing) -> String {
    format!("`{}` ({:.0} B)", s.encoder, s.bytes)
}

/// The budget table of `t` (metric `exact`) as markdown with its caption, or None when the
/// table has no standing to rank.
pub fn budget_table(t: &CsvTable, budgets: &[u32], folder: &str, link: &str) -> Result<Option<String>> {
    let Some(all) = standings(t, "exact").filter(|a| !a.is_empty()) else { return Ok(None) };
    let maps = all.iter().map(|s| s.rows).max().unwrap_or(0);
    let headers: Vec<String> =
        ["budget, bytes a probe", "most accurate", "its relative RMSE", "its eval, ns a normal", "runner-up"]
            .map(String::from)
            .to_vec();
    let rows: Vec<Vec<String>> = budgets
        .iter()
        .map(|&b| {
            let best = best_within(&all, f64::from(b));
            let first = best.first();
            vec![
                b.to_string(),
                first.map_or("none fits".into(), |s| named(s)),
                first.map_or("-".into(), |s| percent(s.rel_rmse)),
                first.and_then(|s| s.eval_ns).map_or("-".into(), |v| format!("{v:.1}")),
                best.get(1).map_or("none".into(), |s| format!("{} at {}", named(s), percent(s.rel_rmse))),
            ]
        })
        .collect();
    Ok(Some(format!(
        "**Which encoding for a budget?** ({folder}) For each budget of bytes stored per probe, the encoding with the \
         lowest median over maps (up to {maps}) of relative RMSE (the exact metric: solid-angle weighted RMSE of E/π \
         over the RMS of the reference E/π, whole sphere, the table's resolution), and the runner-up. Bytes: the \
         quantised encodings' serialised length (FORMULAS §11), else {HALF_BYTES} bytes a stored scalar (half \
         floats). Evaluation: the median over maps of `eval_ns`, ns per shaded normal on this table's machine. From \
         [{folder}/table.csv]({link}).\n\n{}",
        table(&headers, &rows)
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// Three encoders on two maps: bytes from `diagnostics` or 2 a scalar; the medians are the
    /// lower middle; a budget keeps only what fits.
    #[test]
    fn budgets_rank_what_fits() {
        let csv = "map,encoder,metric,rel_rmse,stored_scalars,diagnostics,eval_ns\n\
                   m1,a,exact,0.5,3,,10\nm2,a,exact,0.7,3,,30\n\
                   m1,q,exact,0.2,12,bytes=13,20\nm2,q,exact,0.4,12,bytes=13,20\n\
                   m1,b,exact,0.1,12,,5\nm2,b,exact,0.3,12,,7\nm1,b,other,0.0,12,,5\n";
        let t = CsvTable::parse(Path::new("t.csv"), csv.as_bytes()).unwrap();
        let s = standings(&t, "exact").unwrap();
        let get = |n: &str| s.iter().find(|x| x.encoder == n).unwrap().clone();
        assert_eq!((get("a").bytes, get("q").bytes, get("b").bytes), (6.0, 13.0, 24.0));
        assert_eq!((get("a").rel_rmse, get("b").rel_rmse, get("b").rows), (0.5, 0.1, 2));
        assert_eq!(get("a").eval_ns, Some(10.0));
        let names = |b: f64| best_within(&s, b).iter().map(|x| x.encoder.clone()).collect::<Vec<_>>();
        assert_eq!(names(5.0), Vec::<String>::new());
        assert_eq!(names(8.0), ["a"]);
        assert_eq!(names(16.0), ["q", "a"]);
        assert_eq!(names(100.0), ["b", "q"]);
        let md = budget_table(&t, &[4, 16], "x", "x/table.csv").unwrap().unwrap();
        assert!(md.contains("| 4 | none fits |"), "{md}");
        assert!(md.contains("| 16 | `q` (13 B) | 20% | 20.00 | `a` (6 B) at 50% |"), "{md}");
    }
}
