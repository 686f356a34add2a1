//! Convergence sweeps: rmse against a knob's value, and against time, one line per label.

use super::super::csvfile::CsvTable;
use super::draw::{canvas, pe, Outcome};
use super::lines::{draw_legend, legend_height, legend_width, line_panel, Series};
use super::rows::{distinct, Measure};
use anyhow::Result;
use plotters::prelude::*;

/// One chart per knob of a sweep CSV (`knob,value,rmse,time_ns,label`): rmse against the
/// knob's value, one line per label, and beside it rmse against time when `time_ns` is filled.
pub fn sweep_charts(t: &CsvTable) -> Result<Vec<(String, Outcome)>> {
    let [kc, vc, rc] = t.require(&["knob", "value", "rmse"])?[..] else { unreachable!() };
    // A series per `label`, or per map / encoder / domain where the file has those instead.
    let label_cols: Vec<usize> = match t.col("label") {
        Some(c) => vec![c],
        None => ["map", "encoder", "domain"].iter().filter_map(|h| t.col(h)).collect(),
    };
    let label_of = |i: usize| label_cols.iter().map(|&c| t.rows[i][c].as_str()).collect::<Vec<_>>().join(" / ");
    let tc = t.col("time_ns");
    let refc = t.col("reference");
    let all: Vec<usize> = (0..t.rows.len()).collect();
    let mut out = Vec::new();
    for knob in distinct(t, &all, kc) {
        let rows: Vec<usize> = all.iter().copied().filter(|&i| t.rows[i][kc] == knob).collect();
        let mut by_value = Vec::new();
        let mut by_time = Vec::new();
        let mut zero = 0;
        let mut labels: Vec<String> = Vec::new();
        for &i in &rows {
            let l = label_of(i);
            if !labels.contains(&l) {
                labels.push(l);
            }
        }
        let mut unplotted = 0;
        for (k, label) in labels.into_iter().enumerate() {
            let mut a = Vec::new();
            let mut b = Vec::new();
            for &i in rows.iter().filter(|&&i| label_of(i) == label) {
                let Some(v) = knob_value(&t.rows[i][vc]) else {
                    unplotted += 1;
                    continue;
                };
                let Some(r) = t.num(i, rc)? else { continue };
                if r <= 0.0 {
                    zero += 1;
                }
                a.push((v, r));
                if let Some(tn) = tc.map(|c| t.num(i, c)).transpose()?.flatten() {
                    b.push((tn, r));
                }
            }
            a.sort_by(|p, q| p.0.total_cmp(&q.0));
            b.sort_by(|p, q| p.0.total_cmp(&q.0));
            by_value.push(Series { label: label.clone(), colour: k, points: a });
            if !b.is_empty() {
                by_time.push(Series { label, colour: k, points: b });
            }
        }
        if by_value.iter().all(|s| s.points.is_empty()) {
            out.push((knob.clone(), Outcome::Skipped(format!("sweep '{knob}': no numeric rows"))));
            continue;
        }
        let two = !by_time.is_empty();
        let quantity = Measure::of(t, &rows).quantity();
        let w = if two { 1200 } else { 640 };
        let (image, svg, text) = canvas!(w + legend_width(&by_value), legend_height(&by_value), |root| {
            root.fill(&WHITE).map_err(pe)?;
            draw_legend(root, &by_value, w as i32)?;
            let root = &root.split_horizontally(w).0;
            let (a, b) = if two { root.split_horizontally(600) } else { (root.clone(), root.clone()) };
            line_panel(&a, &format!("{knob}: RMSE against value"), &knob, &quantity, &by_value, zero > 0)?;
            if two {
                line_panel(&b, &format!("{knob}: RMSE against time"), "time, ns", &quantity, &by_time, zero > 0)?;
            }
            Ok(())
        })?;
        let against = refc
            .and_then(|c| rows.iter().map(|&i| t.rows[i][c].clone()).find(|s| !s.is_empty()))
            .map(|s| format!("; rmse against {s}"))
            .unwrap_or_default();
        let caption = format!(
            "convergence sweep of `{knob}`: rmse against the knob's value (a W×H value is plotted at W){}{}{}",
            if two { " and against time_ns" } else { " (no time_ns in the file)" },
            against,
            if unplotted > 0 {
                format!("; {unplotted} row(s) with a non-numeric value (e.g. `full`) are in the CSV, not on the chart")
            } else {
                String::new()
            }
        );
        out.push((knob, Outcome::Drawn { image, svg, caption, text, marks: vec![] }));
    }
    Ok(out)
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
