//! Line charts: one panel of series (log axes where the range allows, log2 for sizes) and the
//! legend column beside the panels, so a legend never covers data. Each series is drawn in its
//! encoder's colour and marker ([`crate::report::style`]).

use super::super::text::{text_width, BODY, FONT, HEADING};
use super::axes::{grid, log_ticks, tick};
use super::draw::{canvas, pe, Outcome};
use super::marks::{draw_marker, rgb};
use crate::report::style::EncoderStyle;
use anyhow::Result;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Height of one legend entry, px.
pub(super) const LEGEND_LINE: i32 = 20;

/// Width of the legend column for these series: the widest measured label, the 24 px line
/// sample before it and 12 px of margin on each side.
pub(super) fn legend_width(series: &[Series]) -> u32 {
    series.iter().map(|s| text_width(&s.label, BODY, false)).max().unwrap_or(0) + 24 + 24
}

/// Boxes (x0, y0, x1, y1) of the legend entries in a column starting at `x0`, one line each
/// from the top margin down, each as wide as its measured label plus the line sample.
pub(super) fn legend_boxes(series: &[Series], x0: i32) -> Vec<(i32, i32, i32, i32)> {
    series
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let y0 = 40 + i as i32 * LEGEND_LINE;
            (x0 + 12, y0, x0 + 12 + 24 + text_width(&s.label, BODY, false) as i32, y0 + LEGEND_LINE)
        })
        .collect()
}

/// Image height: 460 px, or taller when the legend needs it.
pub(super) fn legend_height(series: &[Series]) -> u32 {
    460u32.max(40 + series.len() as u32 * LEGEND_LINE as u32 + 12)
}

/// Draws the legend in its own column right of the panels (`x0` = the panels' right edge),
/// so it never covers data: a line sample with the series' marker and the label per series.
pub(super) fn draw_legend<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, series: &[Series], x0: i32) -> Result<()> {
    for (s, b) in series.iter().zip(legend_boxes(series, x0)) {
        let c = rgb(&s.style);
        let y = (b.1 + b.3) / 2;
        if s.dashed {
            for x in [b.0, b.0 + 8, b.0 + 16] {
                root.draw(&PathElement::new([(x, y), (x + 4, y)], c.stroke_width(2))).map_err(pe)?;
            }
        } else {
            root.draw(&PathElement::new([(b.0, y), (b.0 + 18, y)], c.stroke_width(2))).map_err(pe)?;
        }
        draw_marker(root, (b.0 + 9, y), &s.style, 4, true)?;
        let style = TextStyle::from((FONT, BODY).into_font()).color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center));
        root.draw_text(&s.label, &style, (b.0 + 24, y)).map_err(pe)?;
    }
    Ok(())
}

/// One series of a line chart.
pub(super) struct Series {
    pub(super) label: String,
    /// The encoder's look ([`crate::report::style::style_of`]), the same in every chart.
    pub(super) style: EncoderStyle,
    /// Drawn dashed (a second statistic of the same group, beside its solid line).
    pub(super) dashed: bool,
    pub(super) points: Vec<(f64, f64)>,
}

/// The least and the greatest of `v` (infinite when `v` is empty).
fn span(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for x in v {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    (lo, hi)
}

/// A linear axis' range: the data's span widened by 6% each side (by a tenth of the value's size,
/// at least 0.1, when the span is a point).
fn pad(lo: f64, hi: f64) -> (f64, f64) {
    let d = if hi > lo { (hi - lo) * 0.06 } else { lo.abs().max(1.0) * 0.1 };
    (lo - d, hi + d)
}

/// How a panel's axes are scaled beyond the default (log where every value is positive and
/// spans a factor 20).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Scale {
    /// A linear y whatever the range (a value may be zero).
    pub(super) linear_y: bool,
    /// x is a size (a map or grid width): a log2 axis ticked at powers of two.
    pub(super) log2_x: bool,
}

/// The powers of two from `lo` to `hi`.
fn powers_of_two(lo: f64, hi: f64) -> Vec<f64> {
    let (a, b) = (lo.log2().ceil() as i32, hi.log2().floor() as i32);
    (a..=b).map(|e| 2f64.powi(e)).collect()
}

/// Draws one panel of line series on `area`, each a line through its points with its marker
/// on each: log axes where every value is positive and the range spans at least a factor 20,
/// and a log2 x ticked at powers of two for sizes ([`Scale`]).
pub(super) fn line_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    (xdesc, ydesc): (&str, &str),
    series: &[Series],
    scale: Scale,
) -> Result<()> {
    let (xl, xh) = span(series.iter().flat_map(|s| s.points.iter().map(|p| p.0)));
    let (yl, yh) = span(series.iter().flat_map(|s| s.points.iter().map(|p| p.1)));
    if !xl.is_finite() {
        return Ok(());
    }
    let xlog = xl > 0.0 && (xh / xl >= 20.0 || (scale.log2_x && xh > xl));
    let ylog = !scale.linear_y && yl > 0.0 && yh / yl >= 20.0;
    let (xp, yp) = (pad(xl, xh), pad(yl, yh));
    let (xb, yb) = ((xl * 0.8, xh * 1.25), (yl * 0.8, yh * 1.25));
    // A log axis gets the ticks of `axes::log_ticks`, drawn by `axes::grid` (plotters' own
    // key points put a label at every 1..9 of a decade, which overlap on a tall range).
    let xt = match (xlog, scale.log2_x) {
        (true, true) => powers_of_two(xb.0, xb.1),
        (true, false) => log_ticks(xb.0, xb.1, 5),
        _ => Vec::new(),
    };
    let yt = if ylog { log_ticks(yb.0, yb.1, 5) } else { Vec::new() };
    macro_rules! draw {
        ($x:expr, $y:expr) => {{
            let mut chart = ChartBuilder::on(area)
                .caption(title, (FONT, HEADING).into_font().style(FontStyle::Bold))
                .margin(12)
                .x_label_area_size(46)
                .y_label_area_size(72)
                .build_cartesian_2d($x, $y)
                .map_err(pe)?;
            chart
                .configure_mesh()
                .x_desc(xdesc)
                .y_desc(ydesc)
                .x_labels(if xlog { 0 } else { 10 })
                .y_labels(if ylog { 0 } else { 10 })
                .x_label_formatter(&|v| if xlog { String::new() } else { tick(*v) })
                .y_label_formatter(&|v| if ylog { String::new() } else { tick(*v) })
                .label_style((FONT, BODY))
                .axis_desc_style((FONT, BODY))
                .light_line_style(RGBColor(238, 238, 238))
                .draw()
                .map_err(pe)?;
            let (xr, yr) = chart.plotting_area().get_pixel_range();
            let base = area.get_base_pixel();
            let plot = (xr.start - base.0, yr.start - base.1, xr.end - base.0, yr.end - base.1);
            grid(area, plot, &xt, |v| chart.backend_coord(&(v, yl)).0 - base.0, true)?;
            grid(area, plot, &yt, |v| chart.backend_coord(&(xl, v)).1 - base.1, false)?;
            for s in series {
                let c = rgb(&s.style);
                if s.dashed {
                    chart.draw_series(DashedLineSeries::new(s.points.clone(), 5, 4, c.stroke_width(2))).map_err(pe)?;
                } else {
                    chart.draw_series(LineSeries::new(s.points.clone(), c.stroke_width(2))).map_err(pe)?;
                }
                for p in &s.points {
                    let (x, y) = chart.backend_coord(p);
                    draw_marker(area, (x - base.0, y - base.1), &s.style, 4, !s.dashed)?;
                }
            }
        }};
    }
    match (xlog, ylog) {
        (true, true) => draw!((xb.0..xb.1).log_scale(), (yb.0..yb.1).log_scale()),
        (true, false) => draw!((xb.0..xb.1).log_scale(), yp.0..yp.1),
        (false, true) => draw!(xp.0..xp.1, (yb.0..yb.1).log_scale()),
        (false, false) => draw!(xp.0..xp.1, yp.0..yp.1),
    }
    Ok(())
}

/// Most entries a sweep chart's legend holds. A knob with more series is drawn as their
/// convergence, summarised per encoder (two entries each), split into charts of at most this
/// many entries.
pub const MAX_LEGEND: usize = 8;

/// One series of a sweep: its label (map / encoder / domain, or `label`), the group it is
/// summarised in (its encoder, or the label where the file has none), and its points
/// (knob value, rmse, time_ns), in value order.
pub(super) struct Line {
    pub(super) label: String,
    pub(super) group: String,
    pub(super) points: Vec<(f64, f64, Option<f64>)>,
}

/// What a sweep chart's two panels say: their titles and axes in words, and the scales.
pub(super) struct Panels {
    /// The value panel's title ("polar_nodes_floor: RMSE against GL nodes").
    pub(super) title: String,
    /// The knob's axis in words with its unit.
    pub(super) x_value: String,
    /// The time axis in words: the time of what, and its unit.
    pub(super) x_time: String,
    /// The y axis (what is measured, against what).
    pub(super) y: String,
    pub(super) scale: Scale,
}

/// Draws the value panel and, when any series has times, the time panel (each series' points
/// sorted by time, so a line never doubles back), with the legend column beside them.
pub(super) fn panels(p: &Panels, (by_value, by_time): (&[Series], &[Series])) -> Result<Outcome> {
    let two = !by_time.is_empty();
    let w = if two { 1200 } else { 640 };
    let by_time: Vec<Series> = by_time
        .iter()
        .map(|s| {
            let mut points = s.points.clone();
            points.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
            Series { label: s.label.clone(), style: s.style, dashed: s.dashed, points }
        })
        .collect();
    let (image, svg, text) = canvas!(w + legend_width(by_value), legend_height(by_value), |root| {
        root.fill(&WHITE).map_err(pe)?;
        draw_legend(root, by_value, w as i32)?;
        let root = &root.split_horizontally(w).0;
        let (a, b) = if two { root.split_horizontally(600) } else { (root.clone(), root.clone()) };
        line_panel(&a, &p.title, (&p.x_value, &p.y), by_value, p.scale)?;
        if two {
            let time = Scale { log2_x: false, ..p.scale };
            line_panel(&b, "the same RMSE against time", (&p.x_time, &p.y), &by_time, time)?;
        }
        Ok(())
    })?;
    Ok(Outcome::Drawn { image, svg, caption: String::new(), text, marks: vec![] })
}
