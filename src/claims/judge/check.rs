//! One check judged on each map set it declares: its rows in scope, then a bound on every row
//! (`every_at_most`, `every_at_least`, `every_equal`) or a test against the baseline
//! ([`crate::claims::judge::baseline`]).

use crate::claims::declaration::{CheckDecl, Paper, Test};
use crate::claims::judge::baseline::judge_against_baseline;
use crate::claims::judge::outcome::{CheckOutcome, Evidence, RowValue, SetOutcome, Status};
use crate::claims::judge::scope::{Picked, Scope};
use crate::claims::judge::wording;
use crate::claims::population::{noun, Population, ALL};
use crate::claims::ratios;
use crate::math::echo::value as echo;
use anyhow::Result;

/// Judges one check on one set of a table.
fn judge_set(t: &Evidence, k: &CheckDecl, set: &str, population: Population) -> Result<SetOutcome> {
    let set_maps = population.named();
    let scope = Scope::new(t, k, population)?;
    if set != ALL && scope.map_col.is_none() {
        return Ok(SetOutcome::untestable(set, 0, format!("the table has no map column to select set '{set}'")));
    }
    let picked = scope.picked()?;
    let maps_judged = {
        let mut m: Vec<&str> = picked.iter().map(|p| p.map.as_str()).filter(|s| !s.is_empty()).collect();
        m.sort();
        m.dedup();
        m.len()
    };
    if picked.is_empty() {
        return Ok(SetOutcome::untestable(set, maps_judged, format!("no rows of '{}' in scope", echo(&k.encoder))));
    }
    if let Some(why) = set_maps.and_then(|s| missing_maps(k, set, s, &picked)) {
        return Ok(SetOutcome::untestable(set, maps_judged, why));
    }
    let excluded = picked.iter().filter(|p| p.value.is_none()).count();
    if !k.test.needs_baseline() {
        return Ok(judge_bound(k, set, maps_judged, &picked, excluded));
    }
    judge_against_baseline(&scope, set, maps_judged, &picked, excluded)
}

/// Why the set cannot be judged when some of its maps (those the check reads) have no rows.
fn missing_maps(k: &CheckDecl, set: &str, set_maps: &[String], picked: &[Picked]) -> Option<String> {
    let present: Vec<&str> = picked.iter().map(|p| p.map.as_str()).collect();
    let missing: Vec<&String> = set_maps
        .iter()
        .filter(|m| k.maps.as_ref().is_none_or(|l| l.contains(m)))
        .filter(|m| !present.contains(&m.as_str()))
        .collect();
    (!missing.is_empty()).then(|| {
        format!(
            "{} map(s) of set '{set}' have no rows of '{}': {}",
            missing.len(),
            echo(&k.encoder),
            missing.iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", ")
        )
    })
}

/// A bound on every row (`every_at_most`, `every_at_least`, `every_equal`): each value against
/// the bound.
fn judge_bound(k: &CheckDecl, set: &str, maps_judged: usize, picked: &[Picked], excluded: usize) -> SetOutcome {
    let col = &k.column;
    let vals: Vec<(&Picked, f64)> = picked.iter().filter_map(|p| p.value.map(|v| (p, v))).collect();
    if vals.is_empty() {
        let why = format!("every row of '{}' has an empty {col}", echo(&k.encoder));
        return SetOutcome::untestable(set, maps_judged, why);
    }
    let (upper, bound) = match k.test {
        Test::EveryAtMost { bound } => (true, bound),
        Test::EveryAtLeast { bound } => (false, bound),
        Test::EveryEqual { value } => return judge_exact(k, set, maps_judged, &vals, value, excluded),
        Test::MedianAtLeast { bound } => return judge_median(k, set, &vals, bound, excluded),
        _ => unreachable!("needs_baseline covers the other tests"),
    };
    let ok = |v: f64| if upper { v <= bound } else { v >= bound };
    let values: Vec<RowValue> =
        vals.iter().map(|(p, v)| RowValue { label: p.label.clone(), value: *v, pass: ok(*v) }).collect();
    // Cannot fail: `values` has one entry per `vals`, and an empty `vals` returned above.
    let worst = values
        .iter()
        .max_by(|a, b| if upper { a.value.total_cmp(&b.value) } else { b.value.total_cmp(&a.value) })
        .expect("non-empty");
    let passing = values.iter().filter(|v| v.pass).count();
    let (headline, figure) = wording::bound(&wording::BoundFigures {
        col,
        encoder: &k.encoder,
        upper,
        bound,
        worst: (worst.value, &worst.label),
        passing,
        rows: values.len(),
        excluded,
    });
    let status = Status::pass_if(passing == values.len());
    SetOutcome { set: set.into(), maps: maps_judged, only: None, status, headline, figure, values, excluded }
}

/// `median_at_least`: a map's value is the median of its rows; the median of the maps' values
/// is at least `bound` (the direction on most maps). Each map is listed, with whether it alone
/// meets the bound, and the count is shown.
fn judge_median(k: &CheckDecl, set: &str, vals: &[(&Picked, f64)], bound: f64, excluded: usize) -> SetOutcome {
    let mut maps: Vec<(String, Vec<f64>)> = Vec::new();
    for (p, v) in vals {
        let m = if p.map.is_empty() { p.label.clone() } else { p.map.clone() };
        match maps.iter_mut().find(|(n, _)| *n == m) {
            Some((_, list)) => list.push(*v),
            None => maps.push((m, vec![*v])),
        }
    }
    let values: Vec<RowValue> = maps
        .iter()
        .map(|(m, list)| {
            let v = ratios::median(list);
            RowValue { label: wording::map_label(m, list.len()), value: v, pass: v >= bound }
        })
        .collect();
    let per_map: Vec<f64> = values.iter().map(|v| v.value).collect();
    let median = ratios::median(&per_map);
    let passing = values.iter().filter(|v| v.pass).count();
    let headline = wording::median_bound(&k.column, (median, bound), (passing, values.len()), noun(set));
    let figure = format!("{} of {}: {headline}", k.column, k.encoder);
    let status = Status::pass_if(median >= bound);
    SetOutcome { set: set.into(), maps: values.len(), only: None, status, headline, figure, values, excluded }
}

/// `every_equal`: every value is exactly `value`.
fn judge_exact(
    k: &CheckDecl,
    set: &str,
    maps_judged: usize,
    vals: &[(&Picked, f64)],
    value: f64,
    excluded: usize,
) -> SetOutcome {
    let values: Vec<RowValue> =
        vals.iter().map(|(p, v)| RowValue { label: p.label.clone(), value: *v, pass: *v == value }).collect();
    let passing = values.iter().filter(|v| v.pass).count();
    let off: Vec<&str> = values.iter().filter(|v| !v.pass).map(|v| v.label.as_str()).collect();
    let (headline, figure) = wording::exact(&k.column, &k.encoder, value, (passing, values.len()), &off, excluded);
    let status = Status::pass_if(passing == values.len());
    SetOutcome { set: set.into(), maps: maps_judged, only: None, status, headline, figure, values, excluded }
}

/// Judges one check on every set it declares. `table` is its evidence, or why there is none.
pub fn judge_check(paper: &Paper, k: &CheckDecl, table: &std::result::Result<Evidence, String>) -> CheckOutcome {
    let sets =
        k.on.iter()
            .map(|set| {
                let population = Population::of(set, paper.map_sets.get(set).map(|v| v.as_slice()));
                let out = match table {
                    Err(why) => Err(why.clone()),
                    Ok(t) => judge_set(t, k, set, population).map_err(|e| format!("{}: {e:#}", k.source.label())),
                };
                let mut out = out.unwrap_or_else(|why| SetOutcome::untestable(set, 0, why));
                out.only = k.maps.clone();
                out
            })
            .collect();
    CheckOutcome { decl: k.clone(), sets }
}
