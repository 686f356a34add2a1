//! Convergence sweeps: rmse against a knob's value, and against time, one line per label, in
//! the encoders' own styles; axes in words with units, sizes on a log2 axis, the sweep's name
//! (its variant, e.g. `polar_nodes_floor`) in the title.

use super::super::csvfile::CsvTable;
use super::convergence::convergence_charts;
use super::draw::Outcome;
use super::lines::{panels, Line, Panels, Scale, Series, MAX_LEGEND};
use super::rows::{distinct, Measure};
use crate::pipeline::sweep::Knob;
use crate::report::style::style_of;
use anyhow::Result;

/// One chart per knob of a sweep CSV (`knob,value,rmse,time_ns,label`): rmse against the
/// knob's value, one line per label, and beside it rmse against time when `time_ns` is filled.
/// A knob with more than [`MAX_LEGEND`] series gets the summary of [`convergence_charts`].
pub fn sweep_charts(t: &CsvTable) -> Result<Vec<(String, Outcome)>> {
    let [kc, _, _] = t.require(&["knob", "value", "rmse"])?[..] else { unreachable!() };
    let all: Vec<usize> = (0..t.rows.len()).collect();
    let mut out = Vec::new();
    for knob in distinct(t, &all, kc) {
        let rows: Vec<usize> = all.iter().copied().filter(|&i| t.rows[i][kc] == knob).collect();
        let (lines, unplotted) = lines_of(t, &rows)?;
        if lines.iter().all(|l| l.points.is_empty()) {
            out.push((knob.clone(), Outcome::Skipped(format!("sweep '{knob}': no numeric rows"))));
            continue;
        }
        let measure = Measure::of(t, &rows);
        let unplotted = if unplotted > 0 {
            format!("; {unplotted} row(s) with a non-numeric value (e.g. `full`) are in the CSV, not on the chart")
        } else {
            String::new()
        };
        let (p, timed) = describe(t, &rows, &knob, &measure, lines.iter().flat_map(|l| &l.points).any(|p| p.1 <= 0.0));
        let unplotted = format!("{timed}{unplotted}");
        if lines.len() <= MAX_LEGEND {
            out.push((knob.clone(), absolute_chart(&knob, &lines, &p, &measure, &unplotted)?));
        } else {
            out.extend(convergence_charts(&knob, &lines, &p, &measure, &unplotted)?);
        }
    }
    Ok(out)
}

/// The series of one knob's rows, in first-seen order, and how many rows have a value that is
/// not a number.
fn lines_of(t: &CsvTable, rows: &[usize]) -> Result<(Vec<Line>, usize)> {
    let [vc, rc] = t.require(&["value", "rmse"])?[..] else { unreachable!() };
    // A series per `label`, or per map / encoder / domain where the file has those instead.
    let label_cols: Vec<usize> = match t.col("label") {
        Some(c) => vec![c],
        None => ["map", "encoder", "domain"].iter().filter_map(|h| t.col(h)).collect(),
    };
    let group_col = if t.col("label").is_some() { None } else { t.col("encoder") };
    let label_of = |i: usize| label_cols.iter().map(|&c| t.rows[i][c].as_str()).collect::<Vec<_>>().join(" / ");
    let tc = t.col("time_ns");
    let mut lines: Vec<Line> = Vec::new();
    let mut unplotted = 0;
    for &i in rows {
        let label = label_of(i);
        let k = match lines.iter().position(|l| l.label == label) {
            Some(k) => k,
            None => {
                let group = group_col.map_or_else(|| label.clone(), |c| t.rows[i][c].clone());
                lines.push(Line { label, group, points: Vec::new() });
                lines.len() - 1
            }
        };
        let Some(v) = knob_value(&t.rows[i][vc]) else {
            unplotted += 1;
            continue;
        };
        let Some(r) = t.num(i, rc)? else { continue };
        let time = tc.map(|c| t.num(i, c)).transpose()?.flatten();
        lines[k].points.push((v, r, time));
    }
    for l in &mut lines {
        l.points.sort_by(|p, q| p.0.total_cmp(&q.0));
    }
    Ok((lines, unplotted))
}

/// The panels' words for one knob's `rows`: the title names the sweep (the `sweep` column, a
/// variant such as `polar_nodes_floor`, else the knob), the x axis the knob in words with its
/// unit ([`Knob::axis`]; sizes on a log2 axis), the time axis the time of what (the `timed`
/// column). Returns them and the caption's sentence on what was timed.
fn describe(t: &CsvTable, rows: &[usize], knob: &str, measure: &Measure, zero: bool) -> (Panels, String) {
    let first = |h: &str| t.col(h).and_then(|c| rows.iter().map(|&i| t.rows[i][c].clone()).find(|v| !v.is_empty()));
    let sweep = first("sweep").unwrap_or_else(|| knob.to_string());
    let (x_value, log2_x) = Knob::axis_of(knob).unwrap_or_else(|| (format!("{knob} (as the file names it)"), false));
    let timed = t.col("timed").map(|c| distinct(t, rows, c)).unwrap_or_default();
    let timed: Vec<String> = timed.into_iter().filter(|v| !v.is_empty()).collect();
    let (x_time, said) = match timed.as_slice() {
        [] => ("time_ns of each row, ns".to_string(), String::new()),
        [one] if one == "fit" => ("fit time per probe or texel (median), ns".to_string(), String::new()),
        many => {
            let shown: Vec<&str> = many.iter().take(4).map(String::as_str).collect();
            let more = if many.len() > 4 { format!(" and {} more", many.len() - 4) } else { String::new() };
            (
                "time of each row's timed step (caption), ns".to_string(),
                format!("; timed steps: {}{more}", shown.join("; ")),
            )
        }
    };
    let title = format!("{sweep}: RMSE against {knob}");
    let scale = Scale { linear_y: zero, log2_x };
    (Panels { title, x_value, x_time, y: measure.quantity(), scale }, said)
}

/// Every series' rmse, one line each, against the knob's value and against time; a series in
/// its encoder's style, dashed when an earlier series has the same encoder.
fn absolute_chart(knob: &str, lines: &[Line], p: &Panels, measure: &Measure, unplotted: &str) -> Result<Outcome> {
    let series = |k: usize, l: &Line, time: bool| Series {
        label: l.label.clone(),
        style: style_of(&l.group),
        dashed: lines[..k].iter().any(|o| o.group == l.group),
        points: l.points.iter().filter_map(|p| if time { p.2.map(|t| (t, p.1)) } else { Some((p.0, p.1)) }).collect(),
    };
    let by_value: Vec<Series> = lines.iter().enumerate().map(|(k, l)| series(k, l, false)).collect();
    let by_time: Vec<Series> =
        lines.iter().enumerate().map(|(k, l)| series(k, l, true)).filter(|s| !s.points.is_empty()).collect();
    let two = !by_time.is_empty();
    let mut o = panels(p, (&by_value, &by_time))?;
    if let Outcome::Drawn { caption, .. } = &mut o {
        *caption = format!(
            "convergence sweep of `{knob}`: {} against the knob's value (a W×H value is plotted at W){}; a series \
             in its encoder's colour and marker, dashed when another series of that encoder came first{unplotted}",
            measure.caption(),
            if two { " and against time_ns (a scatter joined in order of time)" } else { " (no time_ns in the file)" },
        );
    }
    Ok(o)
}

/// A sweep knob's value as a number: a plain number, or the width W of a `W×H` resolution
/// (`WxH`); None for anything else (e.g. `full`).
pub fn knob_value(s: &str) -> Option<f64> {
    let s = s.trim();
    let v = match s.parse::<f64>() {
        Ok(v) => v,
        Err(_) => s.split_once(['x', '×']).and_then(|(w, h)| h.parse::<f64>().ok().and(w.parse::<f64>().ok()))?,
    };
    v.is_finite().then_some(v)
}

/// Whether a CSV is a sweep (it has `knob`, `value` and `rmse` columns), whatever its name.
pub fn is_sweep(t: &CsvTable) -> bool {
    ["knob", "value", "rmse"].iter().all(|h| t.col(h).is_some())
}
