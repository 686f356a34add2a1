//! Error against a cost per encoder — everything an encoding stores, bytes, evaluation and fit
//! time — with the Pareto front drawn as a staircase, and the labels placed so none overlaps
//! another. y is the geometric mean over maps of the RMSE relative to a baseline encoder on the
//! same map (named on the axis), so no bright map dominates it. Every point keeps its
//! encoder's colour and marker ([`crate::report::style`]); the front's are ringed.

use super::super::csvfile::CsvTable;
use super::super::text::{text_width, BODY, FONT, TITLE};
use super::axes::{fitted, grid, log_ticks};
use super::dots::{exact_cells, mean_rmse};
use super::draw::{canvas, pe, Outcome};
use super::marks::{draw_marker, rgb};
use super::rows::{distinct, metric_rows, Measure};
use crate::pipeline::summary::RATIO_FLOOR_REL_RMSE;
use crate::report::style::style_of;
use anyhow::Result;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Indices of the Pareto-optimal points of (cost, error), sorted by cost: lower cost and lower
/// error are both better, and a point is on the front when no other point is at least as cheap
/// and at least as accurate while strictly better in one. Equal points are all on the front.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len()).collect();
    idx.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0).then(points[a].1.total_cmp(&points[b].1)));
    let mut front: Vec<usize> = Vec::new();
    let mut best = f64::INFINITY;
    for i in idx {
        let same_as_last = front.last().is_some_and(|&l| points[l] == points[i]);
        if points[i].1 < best || same_as_last {
            best = points[i].1;
            front.push(i);
        }
    }
    front
}

/// What an error-against-cost chart puts on x: a cost per encoder, read from the table by
/// column name (or the `bytes` key of `diagnostics`), the same for every encoder set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cost {
    /// `fit_ns`: the fit of one probe or texel (median over the table's rows).
    FitNs,
    /// `eval_ns`: one shaded normal (median over the table's rows).
    EvalNs,
    /// `stored_scalars` plus what the encoding keeps per shaded point (a cone, an AO term;
    /// `Encoder::storage`): everything it stores.
    StoredScalars,
    /// `bytes=` in `diagnostics`: the size of a quantised encoding (only quantised encoders
    /// report it, so only they are drawn).
    Bytes,
}

impl Cost {
    /// Every cost, in the order the pages show them.
    pub const ALL: [Cost; 4] = [Cost::StoredScalars, Cost::Bytes, Cost::EvalNs, Cost::FitNs];

    /// The chart's file name.
    pub fn file(self) -> &'static str {
        match self {
            Cost::FitNs => "chart_time.png",
            Cost::EvalNs => "chart_cost_eval.png",
            Cost::StoredScalars => "chart_cost_scalars.png",
            Cost::Bytes => "chart_cost_bytes.png",
        }
    }

    /// A phrase: "fit time", "stored scalars", …
    pub fn what(self) -> &'static str {
        match self {
            Cost::FitNs => "fit time",
            Cost::EvalNs => "evaluation time per shaded normal",
            Cost::StoredScalars => "stored scalars (per probe plus per point)",
            Cost::Bytes => "bytes (quantised encoders)",
        }
    }

    fn axis(self) -> &'static str {
        match self {
            Cost::FitNs => "fit time per probe or texel, ns (median over the rows; log scale)",
            Cost::EvalNs => "evaluation time per shaded normal, ns (median over the rows; log scale)",
            Cost::StoredScalars => "scalars stored per probe or texel plus per shaded point (log scale)",
            Cost::Bytes => "bytes per probe (quantised; log scale)",
        }
    }

    fn source(self) -> &'static str {
        match self {
            Cost::FitNs => "median `fit_ns`",
            Cost::EvalNs => "median `eval_ns`",
            Cost::StoredScalars => "`stored_scalars` plus the scalars kept per shaded point",
            Cost::Bytes => "`bytes` of `diagnostics`",
        }
    }

    /// This cost in row `i`, when the row has it.
    fn value(self, t: &CsvTable, i: usize) -> Result<Option<f64>> {
        let col = match self {
            Cost::FitNs => "fit_ns",
            Cost::EvalNs => "eval_ns",
            Cost::StoredScalars => "stored_scalars",
            Cost::Bytes => {
                let Some(c) = t.col("diagnostics") else { return Ok(None) };
                return Ok(diagnostic(&t.rows[i][c], "bytes"));
            }
        };
        match t.col(col) {
            Some(c) => t.num(i, c),
            None => Ok(None),
        }
    }

    /// Why nothing was drawn, when no row has this cost.
    fn missing(self, t: &CsvTable) -> String {
        match self {
            Cost::FitNs | Cost::EvalNs => {
                let col = if self == Cost::FitNs { "fit_ns" } else { "eval_ns" };
                if t.col(col).is_none() {
                    format!("not drawn: no {} in this table (it has no `{col}` column)", self.what())
                } else {
                    format!("not drawn: the `{col}` column is empty (the run had `--no-timing`)")
                }
            }
            Cost::StoredScalars => "not drawn: the table has no `stored_scalars` column".into(),
            Cost::Bytes => "not drawn: no encoder of this table is quantised (none reports `bytes`)".into(),
        }
    }
}

/// The value of `key` in a `k=v;k=v` diagnostics cell.
pub(super) fn diagnostic(cell: &str, key: &str) -> Option<f64> {
    cell.split(';')
        .filter_map(|kv| kv.split_once('='))
        .find(|(k, _)| k.trim() == key)
        .and_then(|(_, v)| v.trim().parse().ok())
}

/// A chart's points (cost, error), their encoders and the baseline the error is relative to.
pub type CostPoints = (Vec<(f64, f64)>, Vec<String>, String);

/// What a cost chart needs beside the table: the scalars each encoder keeps per shaded point
/// (0 for most), and the baselines to try in order (the first in the table is used; else its
/// first encoder).
pub struct CostContext<'a> {
    /// Scalars kept per shaded point by the encoder of this name.
    pub per_point: &'a dyn Fn(&str) -> usize,
    /// Candidate baselines, in order of preference.
    pub baseline: &'a [&'a str],
}

/// The geometric mean over maps of `e`'s mean rmse relative to the baseline's on the same map,
/// over the maps where both have a value and the baseline is not exact; a ratio under
/// [`RATIO_FLOOR_REL_RMSE`] counts as that floor (an exact row would send the mean to 0).
fn geomean_ratio(mean: &[Vec<Option<f64>>], exact: &[Vec<bool>], e: usize, base: usize) -> Option<f64> {
    let logs: Vec<f64> = (0..mean.len())
        .filter(|&m| !exact[m][base])
        .filter_map(|m| Some((mean[m][e]?, mean[m][base]?)))
        .filter(|&(_, b)| b > 0.0)
        .map(|(v, b)| (v / b).max(RATIO_FLOOR_REL_RMSE).ln())
        .collect();
    (!logs.is_empty()).then(|| (logs.iter().sum::<f64>() / logs.len() as f64).exp())
}

/// One point per encoder: (median cost over its rows, the geometric mean over maps of its
/// RMSE relative to the baseline), for the rows of the chart's metric; encoders without the
/// cost (or with a cost ≤ 0, which a log axis cannot show) or without a ratio are left out.
pub fn cost_points(t: &CsvTable, cost: Cost, cx: &CostContext) -> Result<CostPoints> {
    let (Some(ec), Some(_)) = (t.col("encoder"), t.col("rmse")) else { return Ok((vec![], vec![], String::new())) };
    let (rows, _) = metric_rows(t);
    let (_, encs, mean, _) = mean_rmse(t, &rows)?;
    let exact = exact_cells(t, &rows, &mean)?;
    let base = cx.baseline.iter().find_map(|b| encs.iter().position(|e| e == b)).unwrap_or(0);
    let mut pts = Vec::new();
    let mut names = Vec::new();
    for (k, e) in encs.iter().enumerate() {
        let mut costs = Vec::new();
        for &i in rows.iter().filter(|&&i| t.rows[i][ec] == *e) {
            if let Some(v) = cost.value(t, i)? {
                costs.push(v);
            }
        }
        let Some(y) = geomean_ratio(&mean, &exact, k, base) else { continue };
        if costs.is_empty() {
            continue;
        }
        costs.sort_by(f64::total_cmp);
        let mut median = costs[costs.len() / 2];
        if cost == Cost::StoredScalars {
            median += (cx.per_point)(e) as f64;
        }
        if median > 0.0 && median.is_finite() {
            pts.push((median, y));
            names.push(e.clone());
        }
    }
    Ok((pts, names, encs.get(base).cloned().unwrap_or_default()))
}

/// The chart's size.
const W: u32 = 820;
const H: u32 = 580;
/// A point's marker radius, and the line height labels are placed on.
const DOT: i32 = 5;
const LINE: i32 = 15;

/// Error against a cost per encoder (x = the cost, y = the geometric mean over maps of the
/// RMSE relative to the baseline), log–log on axes fitted to the points, with the Pareto front
/// (lower cost and lower error both better) drawn as a staircase and named in the caption;
/// every point labelled, no label over another or over a point ([`place_labels`]). Not drawn
/// when every encoder has the same cost: the page says so instead.
pub fn error_vs_cost(t: &CsvTable, cost: Cost, title: &str, cx: &CostContext) -> Result<Outcome> {
    if t.col("encoder").is_none() || t.col("rmse").is_none() {
        return Ok(Outcome::Skipped("not drawn: the table has no encoder and rmse columns".into()));
    }
    let (pts, names, base) = cost_points(t, cost, cx)?;
    if pts.is_empty() {
        return Ok(Outcome::Skipped(cost.missing(t)));
    }
    if pts.len() > 1 && pts.iter().all(|p| p.0 == pts[0].0) {
        return Ok(Outcome::Skipped(format!(
            "not drawn: every encoder here has the same {} ({}), so the chart would say nothing; the RMSE chart \
             compares them",
            cost.what(),
            super::axes::tick(pts[0].0)
        )));
    }
    let front = pareto_front(&pts);
    let (rows, _) = metric_rows(t);
    let measure = Measure::of(t, &rows);
    // Cannot fail: `cost_points` keeps only finite costs > 0, and `pts` is not empty.
    let (xlo, xhi) = fitted(pts.iter().map(|p| p.0)).expect("positive costs");
    let (ylo, yhi) = fitted(pts.iter().map(|p| p.1)).unwrap_or((1e-3, 1.0));
    let marks = std::cell::RefCell::new(Vec::new());
    let (image, svg, text) = canvas!(W, H, |root| {
        root.fill(&WHITE).map_err(pe)?;
        let red = RGBColor(60, 60, 60);
        title_and_key(root, title, red)?;
        let body = root.split_vertically(56).1;
        let mut chart = ChartBuilder::on(&body)
            .margin(14)
            .margin_top(6)
            .x_label_area_size(50)
            .y_label_area_size(76)
            .build_cartesian_2d((xlo..xhi).log_scale(), (ylo..yhi).log_scale())
            .map_err(pe)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(0)
            .y_labels(0)
            .x_label_formatter(&|_| String::new())
            .y_label_formatter(&|_| String::new())
            .x_desc(cost.axis())
            .y_desc(format!("RMSE / RMSE of {base}, geometric mean over maps (log)"))
            .label_style((FONT, BODY))
            .axis_desc_style((FONT, BODY))
            .draw()
            .map_err(pe)?;
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let plot = (xr.start, yr.start, xr.end, yr.end);
        grid(root, plot, &log_ticks(xlo, xhi, 5), |v| chart.backend_coord(&(v, ylo)).0, true)?;
        grid(root, plot, &log_ticks(ylo, yhi, 5), |v| chart.backend_coord(&(xlo, v)).1, false)?;
        let line = staircase(&pts, &front);
        // The staircase's segments, for labels to keep off.
        let steps: Vec<(i32, i32)> = line.iter().map(|p| chart.backend_coord(p)).collect();
        let segments: Vec<(i32, i32, i32, i32)> = steps
            .windows(2)
            .map(|w| (w[0].0.min(w[1].0) - 2, w[0].1.min(w[1].1) - 2, w[0].0.max(w[1].0) + 2, w[0].1.max(w[1].1) + 2))
            .collect();
        chart.draw_series(LineSeries::new(line, red.stroke_width(2))).map_err(pe)?;
        let px: Vec<(i32, i32)> = pts.iter().map(|a| chart.backend_coord(a)).collect();
        let dots = draw_points(root, &px, &names, &front, plot, &segments)?;
        *marks.borrow_mut() = dots;
        Ok(())
    })?;
    let on: Vec<&str> = front.iter().map(|&i| names[i].as_str()).collect();
    let left_out = {
        let ec = t.col("encoder").expect("checked"); // cannot fail: checked on entry
        distinct(t, &rows, ec).len() - names.len()
    };
    let caption = cost_caption(cost, &measure, &on, left_out, &base);
    Ok(Outcome::Drawn { image, svg, caption, text, marks: marks.into_inner() })
}

/// The chart's title, centred, and the front's key at the top right.
fn title_and_key<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    red: RGBColor,
) -> Result<()> {
    let centre =
        TextStyle::from((FONT, TITLE).into_font().style(FontStyle::Bold)).pos(Pos::new(HPos::Center, VPos::Top));
    root.draw_text(title, &centre, (W as i32 / 2, 8)).map_err(pe)?;
    let key = "Pareto front, ringed (none is both cheaper and more accurate)";
    let kx = W as i32 - 14 - text_width(key, BODY, false) as i32;
    root.draw(&PathElement::new([(kx - 30, 42), (kx - 6, 42)], red.stroke_width(2))).map_err(pe)?;
    root.draw_text(key, &TextStyle::from((FONT, BODY)).pos(Pos::new(HPos::Left, VPos::Center)), (kx, 42))
        .map_err(pe)?;
    Ok(())
}

/// The front as a staircase: the best error reachable at a cost of at most x.
fn staircase(pts: &[(f64, f64)], front: &[usize]) -> Vec<(f64, f64)> {
    let mut line: Vec<(f64, f64)> = Vec::new();
    for &i in front {
        if let Some(&last) = line.last() {
            line.push((pts[i].0, last.1));
        }
        line.push(pts[i]);
    }
    line
}

/// The chart's caption: what x and y are, the encoders on the front (`on`), and how many
/// encoders had no such cost.
fn cost_caption(cost: Cost, measure: &Measure, on: &[&str], left_out: usize, base: &str) -> String {
    format!(
        "error against {} per encoder: x = {} over the table's rows, y = the geometric mean over maps of its \
         mean {} divided by `{base}`'s on the same map (maps where `{base}` is exact left out; a ratio under 1e-6 \
         counts as 1e-6); each point in its encoder's colour and marker; Pareto front (lower cost and lower error \
         both better): {}{}",
        cost.what(),
        cost.source(),
        measure.caption(),
        on.join(", "),
        if left_out > 0 { format!("; {left_out} encoder(s) without this cost not drawn") } else { String::new() }
    )
}

/// Draws the points (each in its encoder's colour and marker, ringed on the front) and their
/// labels (in the same colour), placed by
/// [`place_labels`] off every point and off the front's `segments`, with a leader line when a
/// label moved off its point's height; returns the points' marker boxes.
fn draw_points<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    px: &[(i32, i32)],
    names: &[String],
    front: &[usize],
    plot: (i32, i32, i32, i32),
    segments: &[(i32, i32, i32, i32)],
) -> Result<Vec<(i32, i32, i32, i32)>> {
    let grey = RGBColor(90, 90, 90);
    let r = DOT + 5;
    let dots: Vec<_> = px.iter().map(|&(x, y)| (x - r, y - r, x + r, y + r)).collect();
    let widths: Vec<u32> = names.iter().map(|n| text_width(n, BODY, false)).collect();
    let avoid: Vec<_> = dots.iter().chain(segments).copied().collect();
    let boxes = place_labels(px, &widths, LINE, plot, &avoid);
    for (i, name) in names.iter().enumerate() {
        let style = style_of(name);
        let c = rgb(&style);
        if front.contains(&i) {
            root.draw(&Circle::new(px[i], DOT as u32 + 4, BLACK.stroke_width(2))).map_err(pe)?;
        }
        draw_marker(root, px[i], &style, DOT, true)?;
        let (bx0, by0, bx1, by1) = boxes[i];
        let (x, y) = px[i];
        let cy = (by0 + by1) / 2;
        if (cy - y).abs() > DOT {
            let ex = if bx0 >= x { bx0 - 2 } else { bx1 + 2 };
            root.draw(&PathElement::new([(x, y), (ex, cy)], grey.mix(0.6).stroke_width(1))).map_err(pe)?;
        }
        let style = TextStyle::from((FONT, BODY).into_font()).color(&c).pos(Pos::new(HPos::Left, VPos::Center));
        root.draw_text(name, &style, (bx0, cy)).map_err(pe)?;
    }
    Ok(dots)
}

/// Places one label per point: boxes (x0, y0, x1, y1) of width `widths[i]` and height `line`,
/// inside `plot`, none overlapping another label or any box of `avoid` (the points' markers).
/// Each label goes right of its point (10 px gap) or left of it, at the point's height or the
/// nearest free height in steps of a line up and down (nearest first, right before left);
/// points are placed in order of x, then y. When no free place exists the label stays at its
/// point's height, right or left, inside the plot.
pub fn place_labels(
    points: &[(i32, i32)],
    widths: &[u32],
    line: i32,
    plot: (i32, i32, i32, i32),
    avoid: &[(i32, i32, i32, i32)],
) -> Vec<(i32, i32, i32, i32)> {
    let (px0, py0, px1, py1) = plot;
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by_key(|&i| (points[i].0, points[i].1));
    let mut placed: Vec<(i32, i32, i32, i32)> = vec![(0, 0, 0, 0); points.len()];
    let mut done: Vec<usize> = Vec::new();
    let overlaps = |a: (i32, i32, i32, i32), b: (i32, i32, i32, i32)| a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3;
    for i in order {
        let (x, y) = points[i];
        let w = widths[i] as i32;
        let sides = [x + 10, x - 10 - w];
        let inside = |b: (i32, i32, i32, i32)| b.0 >= px0 && b.2 <= px1 && b.1 >= py0 && b.3 <= py1;
        let free = |b: (i32, i32, i32, i32)| {
            inside(b) && done.iter().all(|&j| !overlaps(b, placed[j])) && avoid.iter().all(|&a| !overlaps(b, a))
        };
        let candidate = (0..120).flat_map(|k: i32| {
            let step = if k % 2 == 0 { k / 2 } else { -(k / 2 + 1) };
            sides.map(|x0| (x0, y - line / 2 + step * line, x0 + w, y - line / 2 + step * line + line))
        });
        let fallback = {
            let x0 = if sides[0] + w <= px1 { sides[0] } else { sides[1].max(px0) };
            let y0 = (y - line / 2).clamp(py0, py1 - line);
            (x0, y0, x0 + w, y0 + line)
        };
        placed[i] = candidate.into_iter().find(|&b| free(b)).unwrap_or(fallback);
        done.push(i);
    }
    placed
}
