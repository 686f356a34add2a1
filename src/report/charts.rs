//! Charts (plotters, bundled font), each drawn twice from the same code: into a bitmap (the
//! PNG) and into an SVG string (for papers; text as `<text>` elements with the full labels,
//! laid out from the bitmap font's measured widths): rmse bars per encoder per map, error against fit
//! time with the Pareto front, convergence curves of sweeps, and the lightmap blending line
//! chart. Every chart reads its CSV by column name; a chart whose columns are absent is not
//! drawn and says why (the report prints the reason).
//!
//! File formats read here (also in docs/report.md):
//! - `table.csv` (the runner's): `map`, `encoder`, `rmse`; optional `metric` (rows of `exact`
//!   are charted when present), `fit_ns` (the error-against-time chart needs it).
//! - `sweep*.csv`: `knob,value,rmse,time_ns,label` — one chart per knob, one line per label;
//!   `time_ns` may be empty; an optional `reference` column says what rmse is measured against.
//! - `blend*.csv`: `t,method,irradiance_at_n_r,irradiance_at_n_g,irradiance_at_n_b,rmse` —
//!   `rmse` may be empty; an optional `set` column gives one chart per lighting set.

use super::csvfile::CsvTable;
use super::number::sig;
use super::text::{ensure_font, text_width, FONT};
use crate::math::colour::luminance;
use crate::math::colour::Rgb;
use anyhow::{anyhow, Result};
use image::RgbImage;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A drawn chart (the same drawing as pixels and as an SVG document of the same size), or the
/// reason it was not drawn.
#[derive(Debug)]
pub enum Outcome {
    Drawn { image: RgbImage, svg: String, caption: String },
    Skipped(String),
}

fn pe<E: std::fmt::Display>(e: E) -> anyhow::Error {
    anyhow!("drawing a chart: {e}")
}

/// Tableau 20 (the bold ten, then their light partners).
const PALETTE: [(u8, u8, u8); 20] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
    (174, 199, 232),
    (255, 187, 120),
    (152, 223, 138),
    (255, 152, 150),
    (197, 176, 213),
    (196, 156, 148),
    (247, 182, 210),
    (199, 199, 199),
    (219, 219, 141),
    (158, 218, 229),
];

fn colour(i: usize) -> RGBColor {
    let (r, g, b) = PALETTE[i % PALETTE.len()];
    RGBColor(r, g, b)
}

/// Draws a w×h chart twice with the same body, once on each backend: into a fresh bitmap
/// buffer (the PNG's pixels) and into an SVG string (`SVGBackend::with_string`). The body
/// sees `$root: &DrawingArea<DB, Shift>` for either backend, so every helper it calls is
/// generic over `DB: DrawingBackend`; it returns `Result<()>`. Evaluates to
/// `Result<(RgbImage, String)>`. (A macro, because a closure cannot be generic over the
/// backend.)
macro_rules! canvas {
    ($w:expr, $h:expr, |$root:ident| $body:block) => {{
        let (w, h): (u32, u32) = ($w, $h);
        ensure_font();
        (|| -> Result<(RgbImage, String)> {
            let mut buf = vec![255u8; (w * h * 3) as usize];
            {
                let area = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
                let $root = &area;
                (|| -> Result<()> { $body })()?;
                area.present().map_err(pe)?;
            }
            let image = RgbImage::from_raw(w, h, buf).ok_or_else(|| anyhow!("chart buffer size"))?;
            let mut svg = String::new();
            {
                let area = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
                let $root = &area;
                (|| -> Result<()> { $body })()?;
                area.present().map_err(pe)?;
            }
            Ok((image, svg))
        })()
    }};
}

/// Decade bounds around positive values (at least one decade).
fn decades(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for v in values.filter(|v| *v > 0.0 && v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if hi <= 0.0 {
        return None;
    }
    let lo = 10f64.powf(lo.log10().floor());
    let mut hi = 10f64.powf(hi.log10().ceil());
    if hi <= lo {
        hi = lo * 10.0;
    }
    Some((lo, hi))
}

/// Tick label for log axes.
fn tick(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let e = v.abs().log10();
    if (e - e.round()).abs() < 1e-9 && !(-3.0..=4.0).contains(&e.round()) {
        return format!("1e{}", e.round() as i32);
    }
    let s = sig(v, 2);
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The rows a table chart uses: those of metric `exact` when a `metric` column exists and has
/// such rows, else those of the first metric listed. Returns the rows and the metric's name.
fn metric_rows(t: &CsvTable) -> (Vec<usize>, Option<String>) {
    let Some(mc) = t.col("metric") else { return ((0..t.rows.len()).collect(), None) };
    let pick = if t.rows.iter().any(|r| r[mc] == "exact") {
        "exact".to_string()
    } else {
        t.rows.first().map(|r| r[mc].clone()).unwrap_or_default()
    };
    ((0..t.rows.len()).filter(|&i| t.rows[i][mc] == pick).collect(), Some(pick))
}

/// Values first-seen order.
fn distinct(t: &CsvTable, rows: &[usize], col: usize) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for &i in rows {
        if !out.contains(&t.rows[i][col]) {
            out.push(t.rows[i][col].clone());
        }
    }
    out
}

/// Maps, encoders, mean rmse per (map, encoder), and the largest number of rows averaged.
type MeanRmse = (Vec<String>, Vec<String>, Vec<Vec<Option<f64>>>, usize);

/// Mean rmse per (map, encoder) and the largest number of rows averaged.
fn mean_rmse(t: &CsvTable, rows: &[usize]) -> Result<MeanRmse> {
    let [mc, ec, rc] = t.require(&["map", "encoder", "rmse"])?[..] else { unreachable!() };
    let maps = distinct(t, rows, mc);
    let encs = distinct(t, rows, ec);
    let mut sum = vec![vec![(0.0, 0usize); encs.len()]; maps.len()];
    for &i in rows {
        let Some(v) = t.num(i, rc)? else { continue };
        // Cannot fail: `maps` and `encs` were collected from these very rows.
        let m = maps.iter().position(|x| *x == t.rows[i][mc]).expect("collected");
        let e = encs.iter().position(|x| *x == t.rows[i][ec]).expect("collected");
        sum[m][e].0 += v;
        sum[m][e].1 += 1;
    }
    let k = sum.iter().flatten().map(|s| s.1).max().unwrap_or(0);
    let mean = sum.iter().map(|r| r.iter().map(|&(s, n)| (n > 0).then(|| s / n as f64)).collect()).collect();
    Ok((maps, encs, mean, k))
}

/// Horizontal bars of rmse per encoder, grouped by map, log scale.
pub fn rmse_bars(t: &CsvTable, title: &str) -> Result<Outcome> {
    if t.col("map").is_none() || t.col("encoder").is_none() || t.col("rmse").is_none() {
        return Ok(Outcome::Skipped("the table has no map, encoder and rmse columns".into()));
    }
    let (rows, metric) = metric_rows(t);
    let (maps, encs, mean, k) = mean_rmse(t, &rows)?;
    let Some((lo, hi)) = decades(mean.iter().flatten().flatten().copied()) else {
        return Ok(Outcome::Skipped("no positive rmse to draw on a log scale".into()));
    };
    let zeros = mean.iter().flatten().flatten().filter(|v| **v <= 0.0).count();
    let bar = if encs.len() > 6 { 7.0 } else { 11.0 };
    let group = encs.len() as f64 + 0.8;
    let slots = maps.len() as f64 * group;
    let (label_w, legend_w) = (190u32, 170u32);
    let plot_h = (slots * bar).ceil() as u32;
    let (w, h) = (980u32, plot_h + 110);
    let (image, svg) = canvas!(w, h, |root| {
        root.fill(&WHITE).map_err(pe)?;
        let (area, legend) = root.split_horizontally(w - legend_w);
        let mut chart = ChartBuilder::on(&area)
            .caption(title, (FONT, 16).into_font().style(FontStyle::Bold))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(label_w)
            .build_cartesian_2d((lo..hi).log_scale(), 0.0..slots)
            .map_err(pe)?;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .y_labels(0)
            .x_desc("rmse of E/pi (log scale)")
            .x_label_formatter(&|v| tick(*v))
            .label_style((FONT, 12))
            .axis_desc_style((FONT, 12))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(pe)?;
        for (e, _) in encs.iter().enumerate() {
            let bars = maps.iter().enumerate().filter_map(|(m, _)| {
                let v = mean[m][e]?;
                let y0 = slots - (m as f64 * group + e as f64 + 0.1);
                Some(Rectangle::new([(lo, y0), (v.max(lo), y0 - 0.85)], colour(e).filled()))
            });
            chart.draw_series(bars).map_err(pe)?;
        }
        let style = TextStyle::from((FONT, 12)).pos(Pos::new(HPos::Right, VPos::Center));
        for (m, name) in maps.iter().enumerate() {
            let y = slots - (m as f64 * group + encs.len() as f64 / 2.0);
            let (x, py) = chart.backend_coord(&(lo, y));
            area.draw_text(name, &style, (x - 8, py)).map_err(pe)?;
        }
        for (e, name) in encs.iter().enumerate() {
            let y = 50 + e as i32 * 18;
            legend.draw(&Rectangle::new([(6, y), (20, y + 12)], colour(e).filled())).map_err(pe)?;
            legend.draw_text(name, &TextStyle::from((FONT, 12)), (26, y)).map_err(pe)?;
        }
        Ok(())
    })?;
    let mut caption = format!(
        "rmse of E/pi per encoder per map, log scale{}",
        metric.map(|m| format!(", metric `{m}`")).unwrap_or_default()
    );
    if k > 1 {
        caption.push_str(&format!("; each bar is the mean over the {k} cases (orientations/effects) of the table"));
    }
    if zeros > 0 {
        caption.push_str(&format!("; {zeros} zero rmse value(s) drawn at the axis floor"));
    }
    Ok(Outcome::Drawn { image, svg, caption })
}

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
    /// `stored_scalars`: what the encoding stores per probe or texel.
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
            Cost::StoredScalars => "stored scalars",
            Cost::Bytes => "bytes (quantised encoders)",
        }
    }

    fn axis(self) -> &'static str {
        match self {
            Cost::FitNs => "fit time per probe or texel, ns (median; log scale)",
            Cost::EvalNs => "evaluation time per shaded normal, ns (median; log scale)",
            Cost::StoredScalars => "stored scalars per probe or texel (log scale)",
            Cost::Bytes => "bytes per probe (quantised; log scale)",
        }
    }

    fn source(self) -> &'static str {
        match self {
            Cost::FitNs => "median `fit_ns`",
            Cost::EvalNs => "median `eval_ns`",
            Cost::StoredScalars => "`stored_scalars`",
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
fn diagnostic(cell: &str, key: &str) -> Option<f64> {
    cell.split(';')
        .filter_map(|kv| kv.split_once('='))
        .find(|(k, _)| k.trim() == key)
        .and_then(|(_, v)| v.trim().parse().ok())
}

/// A chart's points, their encoders and the metric they are of.
pub type CostPoints = (Vec<(f64, f64)>, Vec<String>, Option<String>);

/// One point per encoder: (median cost over its rows, mean rmse), for the rows of the chart's
/// metric; encoders without the cost (or with a cost ≤ 0, which a log axis cannot show) are
/// left out. Returns the points, their encoders and the metric.
pub fn cost_points(t: &CsvTable, cost: Cost) -> Result<CostPoints> {
    let (Some(ec), Some(rc)) = (t.col("encoder"), t.col("rmse")) else { return Ok((vec![], vec![], None)) };
    let (rows, metric) = metric_rows(t);
    let mut pts = Vec::new();
    let mut names = Vec::new();
    for e in distinct(t, &rows, ec) {
        let mut costs = Vec::new();
        let (mut sum, mut n) = (0.0, 0usize);
        for &i in rows.iter().filter(|&&i| t.rows[i][ec] == e) {
            if let Some(v) = cost.value(t, i)? {
                costs.push(v);
            }
            if let Some(v) = t.num(i, rc)? {
                sum += v;
                n += 1;
            }
        }
        if costs.is_empty() || n == 0 {
            continue;
        }
        costs.sort_by(f64::total_cmp);
        let median = costs[costs.len() / 2];
        if median > 0.0 && median.is_finite() {
            pts.push((median, sum / n as f64));
            names.push(e);
        }
    }
    Ok((pts, names, metric))
}

/// Error against fit time (kept for callers of the first cost chart).
pub fn error_vs_time(t: &CsvTable, title: &str) -> Result<Outcome> {
    error_vs_cost(t, Cost::FitNs, title)
}

/// Error against a cost per encoder (x = the cost, y = mean rmse), log–log, with the Pareto
/// front (lower cost and lower error both better) drawn as a staircase and named in the caption.
pub fn error_vs_cost(t: &CsvTable, cost: Cost, title: &str) -> Result<Outcome> {
    if t.col("encoder").is_none() || t.col("rmse").is_none() {
        return Ok(Outcome::Skipped("not drawn: the table has no encoder and rmse columns".into()));
    }
    let (pts, names, metric) = cost_points(t, cost)?;
    if pts.is_empty() {
        return Ok(Outcome::Skipped(cost.missing(t)));
    }
    let front = pareto_front(&pts);
    // Cannot fail: `cost_points` keeps only finite costs > 0, and `pts` is not empty.
    let (xlo, xhi) = decades(pts.iter().map(|p| p.0)).expect("positive costs");
    let (ylo, yhi) = decades(pts.iter().map(|p| p.1)).unwrap_or((1e-3, 1.0));
    let h = 560u32;
    let (image, svg) = canvas!(820, h, |root| {
        root.fill(&WHITE).map_err(pe)?;
        let mut chart = ChartBuilder::on(root)
            .caption(title, (FONT, 16).into_font().style(FontStyle::Bold))
            .margin(14)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d((xlo..xhi).log_scale(), (ylo..yhi).log_scale())
            .map_err(pe)?;
        chart
            .configure_mesh()
            .x_desc(cost.axis())
            .y_desc("rmse of E/pi (mean over the table's rows; log scale)")
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .label_style((FONT, 12))
            .axis_desc_style((FONT, 12))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(pe)?;
        let red = RGBColor(200, 30, 30);
        // The front as a staircase: the best error reachable at a cost of at most x.
        let mut line: Vec<(f64, f64)> = Vec::new();
        for &i in &front {
            let p = (pts[i].0, pts[i].1.max(ylo));
            if let Some(&last) = line.last() {
                line.push((p.0, last.1));
            }
            line.push(p);
        }
        chart
            .draw_series(LineSeries::new(line, red.stroke_width(2)))
            .map_err(pe)?
            .label("Pareto front (none is both cheaper and more accurate)")
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], red.stroke_width(2)));
        // Labels from measured widths ([`place_labels`]): right of the point, or left of it
        // where the right would leave the plot, moved up or down past labels already placed,
        // with a leader line when moved off the point; never shortened.
        let grey = RGBColor(90, 90, 90);
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let plot = (xr.start, yr.start, xr.end, yr.end);
        let at: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, p.1.max(ylo))).collect();
        let px: Vec<(i32, i32)> = at.iter().map(|a| chart.backend_coord(a)).collect();
        let widths: Vec<u32> = names.iter().map(|n| text_width(n, 12.0, false)).collect();
        let boxes = place_labels(&px, &widths, 14, plot);
        for (i, name) in names.iter().enumerate() {
            let c = if front.contains(&i) { red } else { grey };
            chart.draw_series(std::iter::once(Circle::new(at[i], 5, c.filled()))).map_err(pe)?;
            let (bx0, by0, bx1, by1) = boxes[i];
            let (x, y) = px[i];
            let cy = (by0 + by1) / 2;
            if (cy - y).abs() > 7 {
                let ex = if bx0 >= x { bx0 - 2 } else { bx1 + 2 };
                root.draw(&PathElement::new([(x, y), (ex, cy)], grey.mix(0.6).stroke_width(1))).map_err(pe)?;
            }
            root.draw_text(name, &TextStyle::from((FONT, 12).into_font()).color(&c), (bx0, by0 + 1)).map_err(pe)?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font((FONT, 12))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(pe)?;
        Ok(())
    })?;
    let on: Vec<&str> = front.iter().map(|&i| names[i].as_str()).collect();
    let left_out = {
        let (rows, _) = metric_rows(t);
        let ec = t.col("encoder").expect("checked"); // cannot fail: checked on entry
        distinct(t, &rows, ec).len() - names.len()
    };
    Ok(Outcome::Drawn {
        image,
        svg,
        caption: format!(
            "error against {} per encoder: x = {} over the table's rows, y = mean rmse{}; Pareto front (lower cost \
             and lower error both better): {}{}",
            cost.what(),
            cost.source(),
            metric.map(|m| format!(" (metric `{m}`)")).unwrap_or_default(),
            on.join(", "),
            if left_out > 0 { format!("; {left_out} encoder(s) without this cost not drawn") } else { String::new() }
        ),
    })
}

/// Places one label per point: boxes (x0, y0, x1, y1) of width `widths[i]` and height
/// `line`, inside `plot`, none overlapping another. Each label goes right of its point (12 px
/// gap) or, when that leaves the plot, left of it; then at the point's height or the nearest
/// free height, trying steps of a line up and down. Points are placed in order of x, then y.
pub fn place_labels(
    points: &[(i32, i32)],
    widths: &[u32],
    line: i32,
    plot: (i32, i32, i32, i32),
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
        let x0 = if x + 12 + w <= px1 { x + 12 } else { (x - 12 - w).max(px0) };
        let mut best = None;
        for k in 0..200 {
            let step = if k % 2 == 0 { k / 2 } else { -(k / 2 + 1) };
            let y0 = y - line / 2 + step * line;
            let b = (x0, y0, x0 + w, y0 + line);
            if y0 < py0 || y0 + line > py1 {
                continue;
            }
            if done.iter().all(|&j| !overlaps(b, placed[j])) {
                best = Some(b);
                break;
            }
        }
        placed[i] = best.unwrap_or((
            x0,
            (y - line / 2).clamp(py0, py1 - line),
            x0 + w,
            (y - line / 2).clamp(py0, py1 - line) + line,
        ));
        done.push(i);
    }
    placed
}

/// Height of one legend entry, px.
const LEGEND_LINE: i32 = 16;

/// Width of the legend column for these series: the widest measured label, the 24 px line
/// sample before it and 12 px of margin on each side.
fn legend_width(series: &[Series]) -> u32 {
    series.iter().map(|s| text_width(&s.label, 12.0, false)).max().unwrap_or(0) + 24 + 24
}

/// Boxes (x0, y0, x1, y1) of the legend entries in a column starting at `x0`, one line each
/// from the top margin down, each as wide as its measured label plus the line sample.
fn legend_boxes(series: &[Series], x0: i32) -> Vec<(i32, i32, i32, i32)> {
    series
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let y0 = 40 + i as i32 * LEGEND_LINE;
            (x0 + 12, y0, x0 + 12 + 24 + text_width(&s.label, 12.0, false) as i32, y0 + LEGEND_LINE)
        })
        .collect()
}

/// Image height: 460 px, or taller when the legend needs it.
fn legend_height(series: &[Series]) -> u32 {
    460u32.max(40 + series.len() as u32 * LEGEND_LINE as u32 + 12)
}

/// Draws the legend in its own column right of the panels (`x0` = the panels' right edge),
/// so it never covers data: a line sample with a point and the label per series.
fn draw_legend<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, series: &[Series], x0: i32) -> Result<()> {
    for (s, b) in series.iter().zip(legend_boxes(series, x0)) {
        let c = colour(s.colour);
        let y = (b.1 + b.3) / 2;
        root.draw(&PathElement::new([(b.0, y), (b.0 + 18, y)], c.stroke_width(2))).map_err(pe)?;
        root.draw(&Circle::new((b.0 + 9, y), 3, c.filled())).map_err(pe)?;
        root.draw_text(&s.label, &TextStyle::from((FONT, 12).into_font()).color(&BLACK), (b.0 + 24, b.1 + 1))
            .map_err(pe)?;
    }
    Ok(())
}

/// One series of a line chart.
struct Series {
    label: String,
    /// Palette index, so a label keeps its colour across panels.
    colour: usize,
    points: Vec<(f64, f64)>,
}

/// Draws one panel of line series on `area`: log axes where every value is positive and the
/// range spans at least a factor 20.
fn line_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    xdesc: &str,
    ydesc: &str,
    series: &[Series],
    force_linear_y: bool,
) -> Result<()> {
    let xs = || series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let ys = || series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
    let span = |v: &mut dyn Iterator<Item = f64>| {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for x in v {
            lo = lo.min(x);
            hi = hi.max(x);
        }
        (lo, hi)
    };
    let (xl, xh) = span(&mut xs());
    let (yl, yh) = span(&mut ys());
    if !xl.is_finite() {
        return Ok(());
    }
    let pad = |lo: f64, hi: f64| {
        let d = if hi > lo { (hi - lo) * 0.06 } else { lo.abs().max(1.0) * 0.1 };
        (lo - d, hi + d)
    };
    let xlog = xl > 0.0 && xh / xl >= 20.0;
    let ylog = !force_linear_y && yl > 0.0 && yh / yl >= 20.0;
    macro_rules! draw {
        ($x:expr, $y:expr) => {{
            let mut chart = ChartBuilder::on(area)
                .caption(title, (FONT, 14).into_font().style(FontStyle::Bold))
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(62)
                .build_cartesian_2d($x, $y)
                .map_err(pe)?;
            chart
                .configure_mesh()
                .x_desc(xdesc)
                .y_desc(ydesc)
                .x_label_formatter(&|v| tick(*v))
                .y_label_formatter(&|v| tick(*v))
                .label_style((FONT, 12))
                .axis_desc_style((FONT, 12))
                .light_line_style(RGBColor(238, 238, 238))
                .draw()
                .map_err(pe)?;
            for s in series {
                let c = colour(s.colour);
                chart.draw_series(LineSeries::new(s.points.clone(), c.stroke_width(2))).map_err(pe)?;
                chart.draw_series(s.points.iter().map(|p| Circle::new(*p, 3, c.filled()))).map_err(pe)?;
            }
        }};
    }
    let (xp, yp) = (pad(xl, xh), pad(yl, yh));
    match (xlog, ylog) {
        (true, true) => draw!((xl * 0.8..xh * 1.25).log_scale(), (yl * 0.8..yh * 1.25).log_scale()),
        (true, false) => draw!((xl * 0.8..xh * 1.25).log_scale(), yp.0..yp.1),
        (false, true) => draw!(xp.0..xp.1, (yl * 0.8..yh * 1.25).log_scale()),
        (false, false) => draw!(xp.0..xp.1, yp.0..yp.1),
    }
    Ok(())
}

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
        let w = if two { 1200 } else { 640 };
        let (image, svg) = canvas!(w + legend_width(&by_value), legend_height(&by_value), |root| {
            root.fill(&WHITE).map_err(pe)?;
            draw_legend(root, &by_value, w as i32)?;
            let root = &root.split_horizontally(w).0;
            let (a, b) = if two { root.split_horizontally(600) } else { (root.clone(), root.clone()) };
            line_panel(&a, &format!("{knob}: rmse against value"), &knob, "rmse of E/pi", &by_value, zero > 0)?;
            if two {
                line_panel(&b, &format!("{knob}: rmse against time"), "time, ns", "rmse of E/pi", &by_time, zero > 0)?;
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
        out.push((knob, Outcome::Drawn { image, svg, caption }));
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

/// Whether a CSV is a blending study: `t`, `method`, and E/π at N (`irradiance_at_n_r/_g/_b`
/// or `luma_at_normal`), whatever its name.
pub fn is_blend(t: &CsvTable) -> bool {
    ["t", "method"].iter().all(|h| t.col(h).is_some())
        && (t.col("luma_at_normal").is_some() || t.col("irradiance_at_n_r").is_some())
}

/// Whether a CSV is a sweep (it has `knob`, `value` and `rmse` columns), whatever its name.
pub fn is_sweep(t: &CsvTable) -> bool {
    ["knob", "value", "rmse"].iter().all(|h| t.col(h).is_some())
}

/// Irradiance at N along t per blending method, and its rmse along t (the lightmap blending
/// study; the 2018 brief's Fig. 2). One chart per `set` value when that column exists. The
/// caption gives each method's overshoot beyond both endpoints.
pub fn blend_charts(t: &CsvTable) -> Result<Vec<(String, Outcome)>> {
    let [tc, mc] = t.require(&["t", "method"])?[..] else { unreachable!() };
    // E/π at N as RGB (luminance taken here) or as a luminance already.
    let rgb = ["irradiance_at_n_r", "irradiance_at_n_g", "irradiance_at_n_b"].map(|h| t.col(h));
    let luma = t.col("luma_at_normal");
    if rgb.iter().any(|c| c.is_none()) && luma.is_none() {
        t.require(&["irradiance_at_n_r", "irradiance_at_n_g", "irradiance_at_n_b"])?;
    }
    let at_n = |i: usize| -> Result<Option<f64>> {
        if let [Some(r), Some(g), Some(b)] = rgb {
            let (Some(x), Some(y), Some(z)) = (t.num(i, r)?, t.num(i, g)?, t.num(i, b)?) else { return Ok(None) };
            return Ok(Some(luminance(Rgb::new(x, y, z))));
        }
        // Cannot fail: without all three rgb columns, `require` above refused a table without luma.
        t.num(i, luma.expect("checked"))
    };
    // The blended reference: a method of its own, or a column beside every method's rows.
    let refc = t.col("reference_luma_at_normal");
    let rc = t.col("rmse");
    let sc = t.col("set").or(t.col("pair"));
    let all: Vec<usize> = (0..t.rows.len()).collect();
    let sets = match sc {
        Some(c) => distinct(t, &all, c),
        None => vec![String::new()],
    };
    let mut out = Vec::new();
    for set in sets {
        let rows: Vec<usize> = all.iter().copied().filter(|&i| sc.is_none_or(|c| t.rows[i][c] == set)).collect();
        let mut irr = Vec::new();
        let mut err = Vec::new();
        let mut notes = Vec::new();
        let mut methods = distinct(t, &rows, mc);
        if refc.is_some() {
            methods.push("reference".into());
        }
        let first = methods.first().cloned().unwrap_or_default();
        for (k, m) in methods.into_iter().enumerate() {
            let mut a = Vec::new();
            let mut e = Vec::new();
            let from_column = refc.is_some() && m == "reference";
            let picked = if from_column { &first } else { &m };
            for &i in rows.iter().filter(|&&i| t.rows[i][mc] == *picked) {
                let Some(tv) = t.num(i, tc)? else { continue };
                // Cannot fail: `from_column` implies `refc.is_some()`.
                let v = if from_column { t.num(i, refc.expect("checked"))? } else { at_n(i)? };
                let Some(v) = v else { continue };
                a.push((tv, v));
                if from_column {
                    continue;
                }
                if let Some(v) = rc.map(|c| t.num(i, c)).transpose()?.flatten() {
                    e.push((tv, v));
                }
            }
            a.sort_by(|p, q| p.0.total_cmp(&q.0));
            e.sort_by(|p, q| p.0.total_cmp(&q.0));
            if let (Some(first), Some(last)) = (a.first(), a.last()) {
                let (lo, hi) = (first.1.min(last.1), first.1.max(last.1));
                let over = a.iter().map(|p| (p.1 - hi).max(lo - p.1).max(0.0)).fold(0.0, f64::max);
                notes.push(format!("{m}: overshoot {}", sig(over, 3)));
            }
            irr.push(Series { label: m.clone(), colour: k, points: a });
            if !e.is_empty() {
                err.push(Series { label: m, colour: k, points: e });
            }
        }
        let two = !err.is_empty();
        let title = if set.is_empty() { String::new() } else { format!(" ({set})") };
        let w = if two { 1200 } else { 640 };
        let (image, svg) = canvas!(w + legend_width(&irr), legend_height(&irr), |root| {
            root.fill(&WHITE).map_err(pe)?;
            draw_legend(root, &irr, w as i32)?;
            let root = &root.split_horizontally(w).0;
            let (a, b) = if two { root.split_horizontally(600) } else { (root.clone(), root.clone()) };
            line_panel(
                &a,
                &format!("irradiance at N along t{title}"),
                "t",
                "E/pi at N (Rec.709 luminance)",
                &irr,
                true,
            )?;
            if two {
                line_panel(&b, &format!("rmse along t{title}"), "t", "rmse of E/pi", &err, true)?;
            }
            Ok(())
        })?;
        let caption = format!(
            "blending{title}: E/pi at N (luminance) along t per method{}; overshoot = largest excursion beyond both \
             endpoints' values: {}",
            if two { ", and rmse along t" } else { "" },
            notes.join("; ")
        );
        out.push((set, Outcome::Drawn { image, svg, caption }));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn csv(s: &str) -> CsvTable {
        CsvTable::parse(Path::new("t.csv"), s.as_bytes()).unwrap()
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick(0.01), "0.01");
        assert_eq!(tick(1.0), "1");
        assert_eq!(tick(2.5), "2.5");
        assert_eq!(tick(1e-6), "1e-6");
        assert_eq!(tick(1e5), "1e5");
    }

    #[test]
    fn pareto_front_by_hand() {
        // (time, error): b dominates d; a is fastest; c is the most accurate.
        let p = [(1.0, 5.0), (2.0, 3.0), (10.0, 1.0), (3.0, 4.0), (20.0, 1.0)];
        assert_eq!(pareto_front(&p), vec![0, 1, 2]);
        assert_eq!(pareto_front(&[]), Vec::<usize>::new());
    }

    #[test]
    fn pareto_front_of_a_constructed_storage_set() {
        // (stored scalars, error), as an encoder landscape would give, worked by hand:
        //  0 (3, 0.9)   cheapest: on the front
        //  1 (12, 0.5)  dominated by 2 (same cost, lower error)
        //  2 (12, 0.3)  on: nothing at ≤ 12 scalars is below 0.3
        //  3 (12, 0.3)  equal to 2: both on (neither is strictly better)
        //  4 (15, 0.35) dominated by 2 (cheaper and more accurate)
        //  5 (15, 0.2)  on
        //  6 (27, 0.2)  dominated by 5 (same error, cheaper)
        //  7 (27, 0.05) on
        //  8 (75, 0.06) dominated by 7
        // Expected front by cost: 0, 2, 3, 5, 7 (1 is dominated by 2).
        let p = [
            (3.0, 0.9),
            (12.0, 0.5),
            (12.0, 0.3),
            (12.0, 0.3),
            (15.0, 0.35),
            (15.0, 0.2),
            (27.0, 0.2),
            (27.0, 0.05),
            (75.0, 0.06),
        ];
        assert_eq!(pareto_front(&p), vec![0, 2, 3, 5, 7]);
        // Brute force agrees: a point is on the front iff no other dominates it.
        let dominated = |i: usize| {
            p.iter()
                .enumerate()
                .any(|(j, q)| j != i && q.0 <= p[i].0 && q.1 <= p[i].1 && (q.0 < p[i].0 || q.1 < p[i].1))
        };
        let brute: Vec<usize> = (0..p.len()).filter(|&i| !dominated(i)).collect();
        assert_eq!(brute, vec![0, 2, 3, 5, 7]);
    }

    #[test]
    fn cost_charts_read_any_encoder_set() {
        // Encoders with made-up names: costs by column name, bytes only where `diagnostics`
        // has them, eval time per encoder the median of its rows.
        let t = csv("map,encoder,metric,rmse,stored_scalars,diagnostics,fit_ns,eval_ns\n\
             a,p,exact,0.5,12,,10,4\nb,p,exact,0.7,12,,10,6\na,q,exact,0.2,27,,20,9\nb,q,exact,0.2,27,,20,9\n\
             a,r,exact,0.6,12,bytes=13;x=1,30,3\nb,r,exact,0.6,12,bytes=13;x=1,30,3\n\
             a,s,exact,0.3,27,bytes=28,30,3\nb,s,exact,0.3,27,bytes=28,30,3\n");
        let (pts, names, metric) = cost_points(&t, Cost::StoredScalars).unwrap();
        assert_eq!(names, ["p", "q", "r", "s"]);
        assert_eq!(metric.as_deref(), Some("exact"));
        // p: 12 scalars, mean (0.5 + 0.7)/2 = 0.6; r: 12, 0.6 — equal points, both on the front.
        assert_eq!(pts, vec![(12.0, 0.6), (27.0, 0.2), (12.0, 0.6), (27.0, 0.3)]);
        assert_eq!(pareto_front(&pts), vec![0, 2, 1]);
        let (pts, names, _) = cost_points(&t, Cost::Bytes).unwrap();
        assert_eq!((pts, names), (vec![(13.0, 0.6), (28.0, 0.3)], vec!["r".to_string(), "s".to_string()]));
        // Eval: p's median of {4, 6} is the upper middle (6); r and s share 3 ns, s is better.
        let (pts, _, _) = cost_points(&t, Cost::EvalNs).unwrap();
        assert_eq!(pts[0], (6.0, 0.6));
        assert_eq!(pareto_front(&pts), vec![3, 1]);
        for c in Cost::ALL {
            match error_vs_cost(&t, c, "x").unwrap() {
                Outcome::Drawn { caption, .. } => assert!(caption.contains("Pareto front"), "{caption}"),
                Outcome::Skipped(s) => panic!("{c:?}: {s}"),
            }
        }
        match error_vs_cost(&t, Cost::Bytes, "x").unwrap() {
            Outcome::Drawn { caption, .. } => assert!(caption.contains("2 encoder(s) without this cost"), "{caption}"),
            Outcome::Skipped(s) => panic!("{s}"),
        }
        let plain = csv("map,encoder,metric,rmse,stored_scalars,diagnostics\na,p,exact,0.5,12,\n");
        assert!(
            matches!(error_vs_cost(&plain, Cost::Bytes, "x").unwrap(), Outcome::Skipped(s) if s.contains("quantised"))
        );
        assert!(
            matches!(error_vs_cost(&plain, Cost::EvalNs, "x").unwrap(), Outcome::Skipped(s) if s.contains("eval_ns"))
        );
    }

    #[test]
    fn time_chart_skips_without_fit_ns_and_draws_with_it() {
        let t = csv("map,encoder,metric,rmse\na,sh1,exact,0.5\na,sh2,exact,0.1\n");
        assert!(matches!(error_vs_time(&t, "x").unwrap(), Outcome::Skipped(s) if s.contains("fit_ns")));
        let t = csv("map,encoder,metric,rmse,fit_ns\na,sh1,exact,0.5,10\na,sh2,exact,0.1,40\na,zz,exact,0.3,50\n");
        match error_vs_time(&t, "x").unwrap() {
            Outcome::Drawn { caption, image, .. } => {
                assert!(caption.contains("both better): sh1, sh2"), "{caption}");
                assert_eq!(image.dimensions(), (820, 560));
            }
            Outcome::Skipped(s) => panic!("{s}"),
        }
    }

    /// A cluster of points as the ZH3 table's time chart has (eight encoders within 40 px, one
    /// at the right edge): every box is inside the plot and no two overlap (checked pairwise from
    /// the returned layout), and the right-edge label went left of its point.
    #[test]
    fn labels_never_overlap_or_leave_the_plot() {
        let plot = (70, 40, 800, 500);
        let pts = [
            (290, 215),
            (295, 232),
            (300, 245),
            (305, 240),
            (310, 250),
            (288, 262),
            (292, 268),
            (297, 230),
            (760, 250),
            (680, 283),
            (720, 290),
            (150, 245),
            (190, 365),
            (200, 195),
        ];
        let widths: Vec<u32> = (0..pts.len()).map(|i| 100 + 10 * i as u32).collect();
        let boxes = place_labels(&pts, &widths, 14, plot);
        for (i, b) in boxes.iter().enumerate() {
            assert!(
                b.0 >= plot.0 && b.1 >= plot.1 && b.2 <= plot.2 && b.3 <= plot.3,
                "label {i} {b:?} leaves the plot"
            );
            assert_eq!((b.2 - b.0) as u32, widths[i], "label {i} shortened");
            for (j, c) in boxes.iter().enumerate().skip(i + 1) {
                let overlap = b.0 < c.2 && c.0 < b.2 && b.1 < c.3 && c.1 < b.3;
                assert!(!overlap, "labels {i} {b:?} and {j} {c:?} overlap");
            }
        }
        assert!(boxes[8].2 <= pts[8].0, "the label of the right-edge point is left of it: {:?}", boxes[8]);
    }

    #[test]
    fn bars_average_cases_and_read_columns_by_name() {
        let t =
            csv("rmse,encoder,map,metric\n0.5,sh1,a,exact\n0.25,sh1,a,exact\n9,sh1,a,probulator\n0.1,sh2,a,exact\n");
        let (rows, m) = metric_rows(&t);
        assert_eq!(m.as_deref(), Some("exact"));
        let (_, encs, mean, k) = mean_rmse(&t, &rows).unwrap();
        assert_eq!(encs, vec!["sh1", "sh2"]);
        assert_eq!(mean[0][0], Some(0.375));
        assert_eq!(k, 2);
        assert!(
            matches!(rmse_bars(&t, "x").unwrap(), Outcome::Drawn { caption, .. } if caption.contains("mean over the 2"))
        );
    }

    #[test]
    fn blend_csv_of_the_lightmap_study() {
        // Luminance at N per method, the reference in its own column, sets by `pair`.
        let b =
            csv("pair,method,t,rmse,luma_at_normal,reference_luma_at_normal\np,ahd,0,0,1,1\np,ahd,0.5,0.1,1.5,1.1\n\
             p,ahd,1,0,1.2,1.2\np,sh2,0,0,1,1\np,sh2,0.5,0.05,1.1,1.1\np,sh2,1,0,1.2,1.2\n");
        let charts = blend_charts(&b).unwrap();
        assert_eq!(charts.len(), 1);
        assert_eq!(charts[0].0, "p");
        match &charts[0].1 {
            Outcome::Drawn { caption, .. } => {
                assert!(caption.contains("ahd: overshoot 0.300"), "{caption}");
                assert!(
                    caption.contains("sh2: overshoot 0") && caption.contains("reference: overshoot 0"),
                    "{caption}"
                );
            }
            Outcome::Skipped(w) => panic!("{w}"),
        }
        assert!(blend_charts(&csv("t,method\n0,a\n")).unwrap_err().to_string().contains("irradiance_at_n_r"));
    }

    #[test]
    fn knob_values_and_sweeps_without_a_label_column() {
        assert_eq!(knob_value("12"), Some(12.0));
        assert_eq!(knob_value("256x128"), Some(256.0));
        assert_eq!(knob_value("full"), None);
        assert_eq!(knob_value("NaN"), None);
        // The committed sweep format: series by map / encoder, W×H values, a `full` row.
        let s = csv("sweep,knob,value,map,encoder,rmse,time_ns\nr,res,32x16,m,sh1,0.2,10\nr,res,64x32,m,sh1,0.1,40\n\
             r,res,full,m,sh1,0.05,90\nr,res,32x16,m,reference,0.01,5\n");
        assert!(is_sweep(&s) && !is_sweep(&csv("knob,rmse\na,1\n")));
        let charts = sweep_charts(&s).unwrap();
        assert_eq!(charts.len(), 1);
        match &charts[0].1 {
            Outcome::Drawn { caption, .. } => {
                assert!(caption.contains("1 row(s) with a non-numeric value"), "{caption}")
            }
            Outcome::Skipped(w) => panic!("{w}"),
        }
    }

    /// The legend is in its own column right of the panels, so it cannot cover data: every
    /// entry's box starts right of the panels and stays inside the image, no two overlap, and
    /// the pixels right of the panels in a series' colour all lie inside the legend boxes (the
    /// data, which fills the panels' upper right corner here, is drawn left of them).
    #[test]
    fn legends_are_beside_the_data() {
        let s = csv("knob,value,rmse,time_ns,label\nk,1,0.001,10,a_long_series_name_one\nk,100,0.5,1000,a_long_series_name_one\n\
             k,1,0.002,10,two\nk,100,0.4,1000,two\n");
        let charts = sweep_charts(&s).unwrap();
        let Outcome::Drawn { image, .. } = &charts[0].1 else { panic!("not drawn") };
        let series: Vec<Series> = ["a_long_series_name_one", "two"]
            .iter()
            .enumerate()
            .map(|(k, l)| Series { label: l.to_string(), colour: k, points: vec![] })
            .collect();
        let boxes = legend_boxes(&series, 1200);
        for (i, b) in boxes.iter().enumerate() {
            assert!(b.0 >= 1200 && b.2 <= image.width() as i32 && b.3 <= image.height() as i32, "entry {i} {b:?}");
            for c in &boxes[i + 1..] {
                assert!(!(b.0 < c.2 && c.0 < b.2 && b.1 < c.3 && c.1 < b.3), "entries overlap: {b:?} {c:?}");
            }
        }
        let c0 = colour(0);
        let (mut inside, mut outside, mut left) = (0, 0, 0);
        for (x, y, p) in image.enumerate_pixels() {
            if p.0 != [c0.0, c0.1, c0.2] {
                continue;
            }
            let (x, y) = (x as i32, y as i32);
            if x < 1200 {
                left += 1;
            } else if boxes.iter().any(|b| x >= b.0 && x < b.2 && y >= b.1 && y < b.3) {
                inside += 1;
            } else {
                outside += 1;
            }
        }
        assert!(
            left > 0 && inside > 0 && outside == 0,
            "series colour: {left} in panels, {inside} in legend, {outside} elsewhere"
        );
    }

    /// Same CSV, same bytes: drawing a sweep twice gives identical images (series in file
    /// order, legend and labels from measured widths; nothing depends on hashing or threads).
    #[test]
    fn sweep_charts_are_deterministic() {
        let text = "knob,value,rmse,time_ns,label\nk,32,0.1,100,b\nk,64,0.02,400,b\nk,32,0.2,90,a\nk,64,0.05,300,a\n";
        let draw = || match sweep_charts(&csv(text)).unwrap().remove(0).1 {
            Outcome::Drawn { image, .. } => image.into_raw(),
            Outcome::Skipped(w) => panic!("{w}"),
        };
        assert!(draw() == draw());
    }

    /// Checks that `svg` is well-formed XML (every tag closed in order, attribute values
    /// quoted, only the five predefined entities) and returns its root's `width`/`height`
    /// and the text of every `<text>` element, unescaped.
    fn parse_svg(svg: &str) -> ((u32, u32), Vec<String>) {
        let unescape = |t: &str| -> String {
            let mut out = String::new();
            let mut rest = t;
            while let Some(i) = rest.find('&') {
                out.push_str(&rest[..i]);
                let j = rest[i..].find(';').unwrap_or_else(|| panic!("unterminated entity in {t:?}"));
                out.push(match &rest[i..i + j + 1] {
                    "&amp;" => '&',
                    "&lt;" => '<',
                    "&gt;" => '>',
                    "&quot;" => '"',
                    "&apos;" => '\'',
                    e => panic!("unknown entity {e}"),
                });
                rest = &rest[i + j + 1..];
            }
            out + rest
        };
        let mut stack: Vec<String> = Vec::new();
        let (mut size, mut texts) = (None, Vec::new());
        let mut rest = svg.trim_start();
        if rest.starts_with("<?xml") {
            rest = &rest[rest.find("?>").expect("xml declaration closed") + 2..];
        }
        while let Some(lt) = rest.find('<') {
            let content = &rest[..lt];
            assert!(!content.contains('>'), "stray '>' in {content:?}");
            if stack.last().is_some_and(|t| t == "text") {
                // plotters writes the text on its own line; SVG's default whitespace handling
                // drops the newlines around it.
                texts.push(unescape(content.trim()));
            } else {
                let _ = unescape(content);
            }
            let gt = rest[lt..].find('>').expect("tag closed") + lt;
            let tag = &rest[lt + 1..gt];
            rest = &rest[gt + 1..];
            if let Some(name) = tag.strip_prefix('/') {
                assert_eq!(stack.pop().as_deref(), Some(name.trim()), "closing tag out of order");
                continue;
            }
            let self_closing = tag.ends_with('/');
            let tag = tag.trim_end_matches('/');
            let name = tag.split_whitespace().next().expect("tag name").to_string();
            // Attributes: name="value" pairs, values without '<' or a bare '&'.
            let mut attrs = tag[name.len()..].trim();
            let mut found = Vec::new();
            while !attrs.is_empty() {
                let eq = attrs.find("=\"").unwrap_or_else(|| panic!("attribute without =\"…\" in <{tag}>"));
                let key = attrs[..eq].trim().to_string();
                let end = attrs[eq + 2..].find('"').expect("attribute value closed") + eq + 2;
                let value = &attrs[eq + 2..end];
                assert!(!value.contains('<'), "'<' in attribute {key}");
                found.push((key, unescape(value)));
                attrs = attrs[end + 1..].trim_start();
            }
            if name == "svg" && stack.is_empty() {
                let get = |k: &str| found.iter().find(|a| a.0 == k).map(|a| a.1.parse::<u32>().unwrap());
                size = Some((get("width").expect("width"), get("height").expect("height")));
            }
            if !self_closing {
                stack.push(name);
            }
        }
        assert!(stack.is_empty(), "unclosed tags {stack:?}");
        assert!(rest.trim().is_empty(), "text after the root element");
        (size.expect("an <svg> root"), texts)
    }

    #[test]
    fn svg_checker_refuses_broken_documents() {
        let ok = r#"<svg width="3" height="2" viewBox="0 0 3 2"><text x="1">a &amp; b</text><rect x="0"/></svg>"#;
        assert_eq!(parse_svg(ok), ((3, 2), vec!["a & b".to_string()]));
        assert_eq!(parse_svg("<svg width=\"1\" height=\"1\"><text>\nx\n</text></svg>").1, ["x"]);
        for bad in [
            r#"<svg width="3" height="2"><text>a</svg>"#,
            r#"<svg width="3" height="2"><text>a & b</text></svg>"#,
            r#"<svg width="3" height="2"><g></text></g></svg>"#,
            r#"<svg width="3" height=2></svg>"#,
        ] {
            assert!(std::panic::catch_unwind(|| parse_svg(bad)).is_err(), "accepted {bad}");
        }
    }

    /// Every chart is also an SVG: well-formed, the same width and height as its PNG, with a
    /// `<text>` element holding each encoder's (or series') full name — long ones and names
    /// with XML's special characters included.
    #[test]
    fn every_chart_is_also_an_svg_with_the_full_names() {
        let names = ["zh3_hallucinate_sun_sky_windowed_long_name", "sh<2>&co", "hlsh"];
        let mut table = String::from("map,encoder,metric,rmse,stored_scalars,fit_ns,eval_ns\n");
        for (k, n) in names.iter().enumerate() {
            let n = format!("\"{n}\"");
            table += &format!("m1,{n},exact,{},{},{},{}\n", 0.1 / (k + 1) as f64, 9 * (k + 1), 10 * (k + 1), 3 + k);
            table += &format!("m2,{n},exact,{},{},{},{}\n", 0.2 / (k + 1) as f64, 9 * (k + 1), 10 * (k + 1), 3 + k);
        }
        let t = csv(&table);
        let mut drawn = vec![("bars".to_string(), rmse_bars(&t, "bars").unwrap())];
        for c in [Cost::StoredScalars, Cost::EvalNs, Cost::FitNs] {
            drawn.push((format!("{c:?}"), error_vs_cost(&t, c, "cost").unwrap()));
        }
        let mut sweep = String::from("knob,value,rmse,time_ns,label\n");
        let mut blend = String::from("t,method,irradiance_at_n_r,irradiance_at_n_g,irradiance_at_n_b,rmse\n");
        for n in names {
            sweep += &format!("k,1,0.5,10,\"{n}\"\nk,10,0.05,100,\"{n}\"\n");
            blend += &format!("0,\"{n}\",1,1,1,0\n0.5,\"{n}\",1.3,1.3,1.3,0.1\n1,\"{n}\",1.2,1.2,1.2,0\n");
        }
        drawn.extend(sweep_charts(&csv(&sweep)).unwrap());
        drawn.extend(blend_charts(&csv(&blend)).unwrap());
        assert_eq!(drawn.len(), 6);
        for (what, o) in drawn {
            let Outcome::Drawn { image, svg, .. } = o else { panic!("{what}: not drawn") };
            let (size, texts) = parse_svg(&svg);
            assert_eq!(size, image.dimensions(), "{what}: SVG size");
            for n in names {
                assert!(texts.iter().any(|t| t == n), "{what}: no <text> with the full name {n:?}: {texts:?}");
            }
        }
    }

    #[test]
    fn sweep_and_blend_formats() {
        let s = csv("knob,value,rmse,time_ns,label\nref_res,32,0.1,100,grace\nref_res,64,0.02,400,grace\n\
             ref_res,128,0.004,1600,grace\niters,1,0.5,,hhd\niters,2,0.2,,hhd\n");
        let charts = sweep_charts(&s).unwrap();
        assert_eq!(charts.len(), 2);
        // The panels (1200 px for two, 640 for one) plus the legend column for "grace" / "hhd".
        let lw = |l: &str| text_width(l, 12.0, false) + 48;
        assert!(matches!(&charts[0].1, Outcome::Drawn { image, .. } if image.width() == 1200 + lw("grace")));
        assert!(matches!(&charts[1].1, Outcome::Drawn { image, .. } if image.width() == 640 + lw("hhd")));
        assert!(sweep_charts(&csv("knob,value\na,1\n")).unwrap_err().to_string().contains("missing column"));
        let b = csv(
            "t,method,irradiance_at_n_r,irradiance_at_n_g,irradiance_at_n_b,rmse\n0,ahd,1,1,1,0\n0.5,ahd,1.5,1.5,1.5,0.1\n\
             1,ahd,1.2,1.2,1.2,0\n0,reference,1,1,1,\n0.5,reference,1.1,1.1,1.1,\n1,reference,1.2,1.2,1.2,\n",
        );
        let charts = blend_charts(&b).unwrap();
        match &charts[0].1 {
            Outcome::Drawn { caption, .. } => {
                assert!(
                    caption.contains("ahd: overshoot 0.300") && caption.contains("reference: overshoot 0"),
                    "{caption}"
                )
            }
            Outcome::Skipped(s) => panic!("{s}"),
        }
    }
}
