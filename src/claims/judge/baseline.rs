//! The tests against a baseline encoder: `equal` (relative differences within a tolerance)
//! and the ratio tests (`ratio_every`, `ratio_some`, `ratio_stat`, `ratio_summary`), rows
//! matched on the key columns. Ratios are taken per row, then per map (the geometric mean of
//! a map's rows), and summarised over maps by median and geometric mean
//! ([`crate::claims::ratios`]); never a ratio of pooled means.

use crate::claims::declaration::{CheckDecl, Statistic, Test};
use crate::claims::judge::outcome::{RowValue, SetOutcome, Status};
use crate::claims::judge::scope::{Picked, Scope};
use crate::claims::judge::wording;
use crate::claims::population::noun;
use crate::claims::ratios::{self, Summary};
use crate::math::echo::value as echo;
use anyhow::Result;

/// The rows of a check paired with its baseline's on the key columns: (row, value, baseline).
type Pairs<'p, 'a> = Vec<(&'p Picked<'a>, f64, f64)>;

/// Tests against a baseline (`equal`, ratio tests): rows matched on the key columns, those
/// whose baseline is at or below the floor, unmatched or empty left out and counted.
pub(super) fn judge_against_baseline(
    scope: &Scope,
    set: &str,
    maps_judged: usize,
    picked: &[Picked],
    mut excluded: usize,
) -> Result<SetOutcome> {
    let k = scope.k;
    // Cannot fail: `declaration` refuses a test that needs a baseline without one.
    let base = k.baseline.as_deref().expect("validated: the test needs a baseline");
    let base_rows = scope.baseline_rows(base)?;
    let mut pairs: Pairs = Vec::new();
    let mut unmatched = 0;
    let mut below_floor = 0;
    for p in picked {
        let Some(a) = p.value else { continue };
        match base_rows.get(&scope.key_of(p.row)) {
            None => unmatched += 1,
            Some(None) => excluded += 1,
            Some(Some(b)) => {
                if matches!(k.test, Test::Equal { .. }) || *b > k.floor {
                    pairs.push((p, a, *b));
                } else {
                    below_floor += 1;
                }
            }
        }
    }
    if unmatched > 0 && pairs.is_empty() {
        let why = format!("no rows of '{}' match rows of '{base}'", echo(&k.encoder));
        return Ok(SetOutcome::untestable(set, maps_judged, why));
    }
    if pairs.is_empty() {
        let why =
            format!("every row of '{base}' is at or below the floor {} ({below_floor} row(s))", wording::fmt3(k.floor));
        return Ok(SetOutcome::untestable(set, maps_judged, why));
    }
    let left_out = wording::left_out(base, &k.column, k.floor, below_floor, unmatched, excluded);
    excluded += below_floor + unmatched;
    let (status, values, headline, figure) = match k.test {
        Test::Equal { tolerance, abs_tolerance } => judge_equal(&pairs, tolerance, abs_tolerance, &left_out),
        _ => judge_ratio(k, (set, base), &pairs, &left_out),
    };
    Ok(SetOutcome { set: set.into(), maps: maps_judged, only: None, status, headline, figure, values, excluded })
}

/// What a baseline test gives a set: status, per-row values, headline and figure.
type Judged = (Status, Vec<RowValue>, String, String);

/// `equal`: every row's relative difference from its baseline within the tolerance
/// (differences up to `abs_tolerance` count as none).
fn judge_equal(pairs: &Pairs, tolerance: f64, abs_tolerance: f64, left_out: &str) -> Judged {
    let values: Vec<RowValue> = pairs
        .iter()
        .map(|(p, a, b)| {
            let d = (a - b).abs();
            let scale = a.abs().max(b.abs());
            let rel = if d <= abs_tolerance {
                0.0
            } else if scale > 0.0 {
                d / scale
            } else {
                f64::INFINITY
            };
            RowValue { label: p.label.clone(), value: rel, pass: rel <= tolerance }
        })
        .collect();
    // Cannot fail: `values` has one entry per pair, and no pairs returned above.
    let worst = values.iter().max_by(|a, b| a.value.total_cmp(&b.value)).expect("non-empty");
    let passing = values.iter().filter(|v| v.pass).count();
    let counts = (passing, values.len());
    let (headline, figure) = wording::equal((worst.value, &worst.label), tolerance, abs_tolerance, counts, left_out);
    (Status::pass_if(passing == values.len()), values, headline, figure)
}

/// The per-map ratios as judged values: each map's ratio (the geometric mean of its rows'),
/// labelled with its row count.
fn map_values(sum: &Summary, pass: &dyn Fn(f64) -> bool) -> Vec<RowValue> {
    sum.maps
        .iter()
        .map(|g| RowValue { label: wording::map_label(&g.map, g.rows), value: g.ratio, pass: pass(g.ratio) })
        .collect()
}

/// Ratio tests (`ratio_every`, `ratio_some`, `ratio_stat`, `ratio_summary`) on the ratios to
/// the baseline: per row, then per map (the geometric mean of a map's rows), summarised over
/// maps by median and geometric mean ([`crate::claims::ratios`]). Every figure names its
/// aggregation.
fn judge_ratio(k: &CheckDecl, (set, base): (&str, &str), pairs: &Pairs, left_out: &str) -> Judged {
    let ratios: Vec<f64> = pairs.iter().map(|(_, a, b)| a / b).collect();
    let group = |p: &Picked| if p.map.is_empty() { p.label.clone() } else { p.map.clone() };
    let keyed: Vec<(String, f64)> = pairs.iter().zip(&ratios).map(|((p, _, _), &r)| (group(p), r)).collect();
    let refs: Vec<(&str, f64)> = keyed.iter().map(|(m, r)| (m.as_str(), *r)).collect();
    // Cannot fail: the caller returns untestable when there are no pairs.
    let sum = ratios::per_map(&refs).expect("non-empty pairs");
    let (lo, hi) = ratios.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| (l.min(x), h.max(x)));
    let (n, m) = (ratios.len(), sum.maps.len());
    let noun = if pairs.iter().all(|(p, _, _)| p.map.is_empty()) { "case" } else { noun(set) };
    let row_values = |pass: &dyn Fn(f64) -> bool| -> Vec<RowValue> {
        pairs
            .iter()
            .zip(&ratios)
            .map(|((p, _, _), &r)| RowValue { label: p.label.clone(), value: r, pass: pass(r) })
            .collect()
    };
    let (status, values, headline) = match k.test {
        Test::RatioEvery { below, per_map } | Test::RatioSome { below, per_map } => {
            let values = if per_map { map_values(&sum, &|r| r < below) } else { row_values(&|r| r < below) };
            let passing = values.iter().filter(|v| v.pass).count();
            let every = matches!(k.test, Test::RatioEvery { .. });
            let ok = if every { passing == values.len() } else { passing > 0 };
            let unit = if per_map || n == m { format!("{noun}s") } else { "rows".to_string() };
            let headline = wording::ratio_count(passing, values.len(), &unit, below, &sum);
            (Status::pass_if(ok), values, headline)
        }
        Test::RatioStat { statistic, min, max } => {
            let stat = match statistic {
                Statistic::Median => sum.median,
                Statistic::GeoMean => sum.geomean,
            };
            let in_band = |r: f64| min.is_none_or(|m| r >= m) && max.is_none_or(|m| r <= m);
            let ok = in_band(stat);
            let values = map_values(&sum, &in_band);
            let count = values.iter().filter(|v| v.pass).count();
            let headline = wording::ratio_stat(statistic, (stat, ok), (min, max), &sum, (noun, count));
            (Status::pass_if(ok), values, headline)
        }
        Test::RatioEither => {
            let values = map_values(&sum, &|r| r != 1.0);
            let below = sum.maps.iter().filter(|g| g.ratio < 1.0).count();
            let above = sum.maps.iter().filter(|g| g.ratio > 1.0).count();
            let headline = wording::ratio_either((below, above), &sum, noun);
            (Status::pass_if(below > 0 && above > 0), values, headline)
        }
        Test::RatioSummary => (Status::Shown, map_values(&sum, &|_| true), wording::ratio_summary(&sum, noun)),
        _ => unreachable!("the other tests returned above"),
    };
    let figure = wording::ratio_figure((&k.encoder, base, &k.column), &headline, &sum, noun, (n, lo, hi), left_out);
    (status, values, headline, figure)
}
