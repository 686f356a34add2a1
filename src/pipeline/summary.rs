//! Summaries of a result table, generic over encoders (every encoder name comes from the
//! experiment file): statistics per orientation, per map and per orientation set (mean and
//! worst), with ratios to a baseline encoder. The claims are judged elsewhere
//! (`claims::judge`).
//!
//! | key (experiment file)  | type   | meaning |
//! |------------------------|--------|---------|
//! | `[summary] baseline`   | string | optional encoder name; ratios are rmse / its rmse on the same map, domain, effects and metric |
//!
//! Output, beside `table.csv`: `summary.csv` when `[summary]` is present. Rows are visited in
//! table order, so the file is deterministic.
//!
//! Ratio statistics ([`RatioStats`]): a row whose baseline error is below the floor
//! ([`RATIO_FLOOR_REL_RMSE`] of the reference's RMS, i.e. a baseline exact to rounding and
//! quadrature) is excluded and counted (`n_below_floor`), since a ratio to ~0 measures the
//! quadrature, not the encoder. Over the other rows the file gives the ratio of the means
//! (Σ rmse / Σ baseline rmse: no single row can dominate it by a division by ~0), the median
//! of the per-row ratios, the worst ratio and the fraction below 1. A mean of per-row ratios is
//! not printed: one near-exact baseline row made it 8·10⁵ on `generated_probe_occlusion`.

use crate::pipeline::table::{num, Row};
use anyhow::{bail, Result};
use serde::Deserialize;
use std::collections::HashMap;
use std::path::Path;

/// `[summary]` as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SummaryFile {
    /// Name of the encoder that ratios are taken against; None for no ratio columns.
    pub baseline: Option<String>,
}

/// Validates `[summary]`.
pub fn summary_baseline(f: SummaryFile, encoders: &[String]) -> Result<Option<String>> {
    if let Some(b) = &f.baseline {
        if !encoders.contains(b) {
            bail!("summary: baseline '{b}' is not one of the experiment's encoders");
        }
    }
    Ok(f.baseline)
}

/// The key rows are matched on across encoders: map, domain, metric and effects.
pub fn match_key(r: &Row) -> (&str, &str, &str, &str) {
    (&r.map, &r.domain, &r.metric, &r.effects)
}

/// The baseline floor: rows whose baseline `rel_rmse` (rmse / RMS of the reference) is below
/// this are left out of the ratio statistics and counted. 1e-6 = the baseline is exact to a
/// part per million, which only rounding and the polar quadrature reach (a constant map's
/// hemisphere, 3e-9); every real encoder error in the committed tables is above 8e-3.
pub const RATIO_FLOOR_REL_RMSE: f64 = 1e-6;

/// Ratio statistics of encoder rows against their baseline rows (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct RatioStats {
    /// Rows compared (baseline at or above the floor).
    pub n: usize,
    /// Rows left out because the baseline's rel_rmse is below [`RATIO_FLOOR_REL_RMSE`].
    pub n_below_floor: usize,
    /// Σ rmse / Σ baseline rmse over the compared rows.
    pub ratio_of_means: f64,
    /// Median of the per-row ratios.
    pub median_ratio: f64,
    /// Largest per-row ratio and its index in the compared pairs.
    pub worst_ratio: f64,
    /// Index of the worst ratio in the compared pairs.
    pub worst_at: usize,
    /// Fraction of compared rows whose ratio is below 1.
    pub frac_below_1: f64,
}

/// Ratio statistics of `(rmse, baseline rmse, baseline rel_rmse)` triples. `None` when every
/// row is below the floor (or there are none). `worst_at` indexes `pairs`.
pub fn ratio_stats(pairs: &[(f64, f64, f64)]) -> Option<RatioStats> {
    let kept: Vec<usize> =
        (0..pairs.len()).filter(|&i| pairs[i].2 >= RATIO_FLOOR_REL_RMSE && pairs[i].1 > 0.0).collect();
    if kept.is_empty() {
        return None;
    }
    let ratios: Vec<f64> = kept.iter().map(|&i| pairs[i].0 / pairs[i].1).collect();
    let (num, den) = kept.iter().fold((0.0, 0.0), |(a, b), &i| (a + pairs[i].0, b + pairs[i].1));
    let (_, worst, wi) = mean_worst(&ratios);
    Some(RatioStats {
        n: kept.len(),
        n_below_floor: pairs.len() - kept.len(),
        ratio_of_means: num / den,
        // Cannot be None: `kept`, one ratio each, was checked non-empty above.
        median_ratio: crate::math::stats::median(&ratios).unwrap_or(f64::NAN),
        worst_ratio: worst,
        worst_at: kept[wi],
        frac_below_1: ratios.iter().filter(|&&x| x < 1.0).count() as f64 / ratios.len() as f64,
    })
}

/// Mean and worst (largest) of values, with the index of the worst.
pub fn mean_worst(v: &[f64]) -> (f64, f64, usize) {
    let mut worst = (f64::NEG_INFINITY, 0);
    for (i, &x) in v.iter().enumerate() {
        if x > worst.0 {
            worst = (x, i);
        }
    }
    (v.iter().sum::<f64>() / v.len() as f64, worst.0, worst.1)
}

/// Distinct values in first-appearance order.
pub fn distinct<'a>(it: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
    let mut out: Vec<&str> = Vec::new();
    for s in it {
        if !out.contains(&s) {
            out.push(s);
        }
    }
    out
}

/// One line of `summary.csv`: the rows of one encoder, effects, metric and orientation set,
/// restricted to one orientation (`domain`), one map, or neither ("*").
struct Group<'a> {
    encoder: &'a str,
    effects: &'a str,
    metric: &'a str,
    set: &'a str,
    domain: &'a str,
    map: &'a str,
    rows: Vec<&'a Row>,
}

fn groups(rows: &[Row]) -> Vec<Group<'_>> {
    let mut out = Vec::new();
    for enc in distinct(rows.iter().map(|r| r.encoder.as_str())) {
        let er: Vec<&Row> = rows.iter().filter(|r| r.encoder == enc).collect();
        for eff in distinct(er.iter().map(|r| r.effects.as_str())) {
            for metric in distinct(er.iter().map(|r| r.metric.as_str())) {
                for set in distinct(er.iter().map(|r| r.orientation_set.as_str())) {
                    let sr: Vec<&Row> = er
                        .iter()
                        .copied()
                        .filter(|r| r.effects == eff && r.metric == metric && r.orientation_set == set)
                        .collect();
                    if sr.is_empty() {
                        continue;
                    }
                    let mk = |domain, map, rows| Group { encoder: enc, effects: eff, metric, set, domain, map, rows };
                    for d in distinct(sr.iter().map(|r| r.domain.as_str())) {
                        out.push(mk(d, "*", sr.iter().copied().filter(|r| r.domain == d).collect()));
                    }
                    for m in distinct(sr.iter().map(|r| r.map.as_str())) {
                        out.push(mk("*", m, sr.iter().copied().filter(|r| r.map == m).collect()));
                    }
                    out.push(mk("*", "*", sr));
                }
            }
        }
    }
    out
}

/// The summary's file name, beside its experiment's table.
pub const SUMMARY: &str = "summary.csv";

/// `summary.csv`: per orientation, per map and per orientation set.
pub fn summary_csv(rows: &[Row], baseline: Option<&str>) -> Result<Vec<u8>> {
    let base: HashMap<_, &Row> =
        rows.iter().filter(|r| Some(r.encoder.as_str()) == baseline).map(|r| (match_key(r), r)).collect();
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "encoder",
        "effects",
        "metric",
        "orientation_set",
        "domain",
        "map",
        "n",
        "mean_rmse",
        "worst_rmse",
        "mean_rel_rmse",
        "worst_rel_rmse",
        "worst_rmse_at",
        "baseline",
        "n_ratio",
        "n_below_floor",
        "ratio_of_means",
        "median_ratio",
        "worst_ratio",
        "frac_ratio_below_1",
        "worst_ratio_at",
    ])?;
    let at = |r: &Row| format!("{} {}", r.map, r.domain);
    for g in groups(rows) {
        let rmse: Vec<f64> = g.rows.iter().map(|r| r.scores.rmse).collect();
        let rel: Vec<f64> = g.rows.iter().map(|r| r.scores.rel_rmse).collect();
        let (mr, wr, wi) = mean_worst(&rmse);
        let (mrel, wrel, _) = mean_worst(&rel);
        let mut rec = vec![
            g.encoder.to_string(),
            g.effects.to_string(),
            g.metric.to_string(),
            g.set.to_string(),
            g.domain.to_string(),
            g.map.to_string(),
            g.rows.len().to_string(),
            num(mr),
            num(wr),
            num(mrel),
            num(wrel),
            at(g.rows[wi]),
        ];
        let pairs: Vec<(&Row, &Row)> =
            g.rows.iter().filter_map(|r| base.get(&match_key(r)).map(|b| (*r, *b))).collect();
        let triples: Vec<(f64, f64, f64)> =
            pairs.iter().map(|(r, b)| (r.scores.rmse, b.scores.rmse, b.scores.rel_rmse)).collect();
        match (baseline, ratio_stats(&triples)) {
            (Some(b), Some(st)) => rec.extend([
                b.to_string(),
                st.n.to_string(),
                st.n_below_floor.to_string(),
                num(st.ratio_of_means),
                num(st.median_ratio),
                num(st.worst_ratio),
                num(st.frac_below_1),
                at(pairs[st.worst_at].0),
            ]),
            (Some(b), None) if !pairs.is_empty() => {
                rec.extend([b.to_string(), "0".into(), pairs.len().to_string()]);
                rec.extend(std::iter::repeat_n(String::new(), 5));
            }
            _ => rec.extend(std::iter::repeat_n(String::new(), 8)),
        }
        w.write_record(&rec)?;
    }
    w.into_inner().map_err(|e| anyhow::anyhow!("csv: {e}"))
}

/// Writes `summary.csv` into `dir`, ratios against `baseline` when one is declared.
pub fn write(dir: &Path, baseline: Option<&str>, rows: &[Row]) -> Result<()> {
    crate::io::atomic::write(&dir.join(SUMMARY), &summary_csv(rows, baseline)?)
}

/// The rows the summary and claims tests share: encoders `op` and `base` on maps `m1` and `m2`,
/// two orientations each; the rmse is also the rel_rmse and the at-normal error.
#[cfg(test)]
pub(crate) mod fixtures {
    use crate::pipeline::table::Row;
    use crate::reference::metrics::Scores;

    /// One row of `enc` on `map` at orientation `domain`.
    fn row(map: &str, enc: &str, domain: &str, rmse: f64) -> Row {
        Row {
            map: map.into(),
            encoder: enc.into(),
            domain: domain.into(),
            metric: "exact".into(),
            scores: Scores { rmse, rel_rmse: rmse, ..Default::default() },
            stored_scalars: 27,
            orientation_set: "axes6".into(),
            effects: "hemisphere".into(),
            weighting: "solid-angle".into(),
            resolution: "8x2".into(),
            units: "E/pi".into(),
            reference: "r".into(),
            diagnostics: String::new(),
            at_normal_abs_err: Some(rmse),
            fit_ns: None,
            eval_ns: None,
        }
    }

    /// Ratios op/base: m1 0.5 (+x), 1.5 (+y); m2 0.25 (+x), 0/0 (+y).
    pub fn rows() -> Vec<Row> {
        vec![
            row("m1", "base", "hemisphere:+x", 2.0),
            row("m1", "op", "hemisphere:+x", 1.0),
            row("m1", "base", "hemisphere:+y", 1.0),
            row("m1", "op", "hemisphere:+y", 1.5),
            row("m2", "base", "hemisphere:+x", 4.0),
            row("m2", "op", "hemisphere:+x", 1.0),
            row("m2", "base", "hemisphere:+y", 0.0),
            row("m2", "op", "hemisphere:+y", 0.0),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::fixtures::rows;
    use super::*;

    #[test]
    fn summary_has_orientation_map_and_set_lines() {
        let csv = String::from_utf8(summary_csv(&rows(), Some("base")).unwrap()).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        // Per encoder (2): 2 orientations + 2 maps + 1 set = 5 lines.
        assert_eq!(lines.len(), 1 + 10, "{csv}");
        // op over +x: ratios 0.5 and 0.25 → ratio of means (1 + 1)/(2 + 4) = 1/3, median 0.375,
        // worst 0.5 at m1, none below the floor.
        let x = lines.iter().find(|l| l.starts_with("op,hemisphere,exact,axes6,hemisphere:+x,*")).unwrap();
        assert!(x.contains(",base,2,0,0.3333333333333333,0.375,0.5,1,m1 hemisphere:+x"), "{x}");
        // The whole set: m2 +y has a baseline of 0 (below the floor): left out and counted.
        // The other three: (1 + 1.5 + 1)/(2 + 1 + 4) = 0.5, median of {0.5, 1.5, 0.25} = 0.5,
        // worst 1.5 at m1 +y, 2 of 3 below 1.
        let all = lines.iter().find(|l| l.starts_with("op,hemisphere,exact,axes6,*,*")).unwrap();
        assert!(all.ends_with(",base,3,1,0.5,0.5,1.5,0.6666666666666666,m1 hemisphere:+y"), "{all}");
        // m2: +x gives 0.25; +y is below the floor, left out and counted.
        let y2 = lines.iter().find(|l| l.starts_with("op,hemisphere,exact,axes6,*,m2")).unwrap();
        assert!(y2.ends_with(",base,1,1,0.25,0.25,0.25,1,m2 hemisphere:+x"), "{y2}");
        // No baseline: ratio fields empty.
        let plain = String::from_utf8(summary_csv(&rows(), None).unwrap()).unwrap();
        assert!(plain.lines().nth(1).unwrap().ends_with(",,,,,,,,"));
    }

    #[test]
    fn a_baseline_near_zero_cannot_dominate() {
        // Two ordinary rows (ratios 0.5 and 2) and one whose baseline is exact to 1e-12: a mean
        // of ratios would be ~3e11; the floor leaves that row out and counts it.
        let st = ratio_stats(&[(1.0, 2.0, 0.1), (2.0, 1.0, 0.1), (1.0, 1e-12, 1e-12)]).unwrap();
        assert_eq!((st.n, st.n_below_floor), (2, 1));
        assert_eq!(st.ratio_of_means, 1.0); // (1 + 2)/(2 + 1)
        assert_eq!(st.median_ratio, 1.25); // mean of the two middle values 0.5 and 2
        assert_eq!((st.worst_ratio, st.worst_at), (2.0, 1));
        assert_eq!(st.frac_below_1, 0.5);
        // Just above the floor counts; every row below it gives no statistic.
        assert_eq!(ratio_stats(&[(1.0, 1.0, RATIO_FLOOR_REL_RMSE)]).unwrap().n, 1);
        assert_eq!(ratio_stats(&[(1.0, 1e-9, 1e-9)]), None);
        assert_eq!(ratio_stats(&[]), None);
    }
}
