//! RMSE per encoder and map as a dot plot on a log axis fitted to the values: a dot per
//! encoder per map, grouped by map, in the encoder's own colour and marker
//! ([`crate::report::style`]); encoders in panels of at most [`PANEL`]. A row exact to
//! rounding (rel_rmse under [`RATIO_FLOOR_REL_RMSE`] of the reference's RMS) would drag a log
//! axis down by decades: it is drawn hollow at the axis floor and its value given in the
//! caption. Many maps × many encoders (a plot taller than [`MAX_HEIGHT`]) become a heatmap of
//! RMSE relative to a named baseline ([`super::heatmap`]).

use super::super::csvfile::CsvTable;
use super::super::text::{text_width, BODY, FONT, HEADING, TITLE};
use super::axes::{fitted, grid, log_ticks, short};
use super::draw::{canvas, pe, Outcome};
use super::heatmap::{heatmap, Cells};
use super::marks::draw_marker;
use super::rows::{distinct, metric_rows, Measure};
use crate::encoders::encoder::Family;
use crate::pipeline::summary::RATIO_FLOOR_REL_RMSE;
use crate::report::style::style_of;
use anyhow::Result;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The most legend entries of one panel.
pub const PANEL: usize = 8;
/// The tallest dot plot; a taller one is drawn as a heatmap.
pub const MAX_HEIGHT: u32 = 2400;

/// Maps, encoders, mean rmse per (map, encoder), and the largest number of rows averaged.
pub(super) type MeanRmse = (Vec<String>, Vec<String>, Vec<Vec<Option<f64>>>, usize);

/// Mean of column `col` per (map, encoder) over `rows`, and the largest number of rows averaged.
fn mean_of(t: &CsvTable, rows: &[usize], col: usize) -> Result<MeanRmse> {
    let [mc, ec] = t.require(&["map", "encoder"])?[..] else { unreachable!() };
    let maps = distinct(t, rows, mc);
    let encs = distinct(t, rows, ec);
    let mut sum = vec![vec![(0.0, 0usize); encs.len()]; maps.len()];
    for &i in rows {
        let Some(v) = t.num(i, col)? else { continue };
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

/// Mean rmse per (map, encoder) and the largest number of rows averaged.
pub(super) fn mean_rmse(t: &CsvTable, rows: &[usize]) -> Result<MeanRmse> {
    let rc = t.require(&["rmse"])?[0];
    mean_of(t, rows, rc)
}

/// Per (map, encoder), whether its mean is exact to rounding: mean rel_rmse below
/// [`RATIO_FLOOR_REL_RMSE`] where the table has `rel_rmse`, else an rmse below that share of
/// the table's largest mean rmse (or not positive).
pub(super) fn exact_cells(t: &CsvTable, rows: &[usize], mean: &[Vec<Option<f64>>]) -> Result<Vec<Vec<bool>>> {
    if let Some(rc) = t.col("rel_rmse") {
        let (_, _, rel, _) = mean_of(t, rows, rc)?;
        return Ok(rel
            .iter()
            .map(|r| r.iter().map(|v| v.is_some_and(|v| v < RATIO_FLOOR_REL_RMSE)).collect())
            .collect());
    }
    let top = mean.iter().flatten().flatten().fold(0.0f64, |a, &b| a.max(b));
    Ok(mean
        .iter()
        .map(|r| r.iter().map(|v| v.is_some_and(|v| v <= 0.0 || v < RATIO_FLOOR_REL_RMSE * top)).collect())
        .collect())
}

/// The encoders in panels: in family order ([`Family::ALL`], members in the table's order), a
/// family of more than [`PANEL`] cut into near-equal runs, the runs packed in order into panels
/// of at most [`PANEL`] entries. Returns encoder indices per panel.
pub fn panels(encoders: &[String]) -> Vec<Vec<usize>> {
    let mut runs: Vec<Vec<usize>> = Vec::new();
    for f in Family::ALL {
        let members: Vec<usize> = (0..encoders.len()).filter(|&e| style_of(&encoders[e]).family == f).collect();
        let n = members.len().div_ceil(PANEL).max(1);
        runs.extend(members.chunks(members.len().div_ceil(n).max(1)).map(<[usize]>::to_vec));
    }
    let mut out: Vec<Vec<usize>> = Vec::new();
    for run in runs {
        match out.last_mut() {
            Some(p) if p.len() + run.len() <= PANEL => p.extend(run),
            _ => out.push(run),
        }
    }
    out
}

/// Pixels per encoder slot, and a panel's margin above and below the dots (title, x axis).
const SLOT: f64 = 12.0;
const PANEL_EXTRA: u32 = 110;

/// A panel's height for `maps` maps and `n` encoders.
fn panel_height(maps: usize, n: usize) -> u32 {
    (maps as f64 * (n as f64 + 0.8) * SLOT).ceil() as u32 + PANEL_EXTRA
}

/// RMSE per encoder and map: a dot plot (see the module doc), or when it would be taller than
/// [`MAX_HEIGHT`], the heatmap of RMSE relative to `baseline` (the experiment's summary
/// baseline, else the program's; the table's first encoder when it lacks both).
pub fn rmse_dots(t: &CsvTable, title: &str, baseline: &[&str]) -> Result<Outcome> {
    if t.col("map").is_none() || t.col("encoder").is_none() || t.col("rmse").is_none() {
        return Ok(Outcome::Skipped("the table has no map, encoder and rmse columns".into()));
    }
    let (rows, _) = metric_rows(t);
    let (maps, encs, mean, k) = mean_rmse(t, &rows)?;
    let exact = exact_cells(t, &rows, &mean)?;
    let measure = Measure::of(t, &rows);
    let groups = panels(&encs);
    let heights: Vec<u32> = groups.iter().map(|g| panel_height(maps.len(), g.len())).collect();
    let h = 44 + heights.iter().sum::<u32>();
    if h > MAX_HEIGHT {
        let base = baseline.iter().find_map(|b| encs.iter().position(|e| e == b)).unwrap_or(0);
        let cells = Cells { maps: &maps, encs: &encs, mean: &mean, exact: &exact, order: groups.concat() };
        return heatmap(&cells, base, title, &measure, k);
    }
    let inexact =
        mean.iter().zip(&exact).flat_map(|(r, x)| r.iter().zip(x).filter(|(_, x)| !**x).filter_map(|(v, _)| *v));
    let Some((lo, hi)) = fitted(inexact).or_else(|| fitted(mean.iter().flatten().flatten().copied())) else {
        return Ok(Outcome::Skipped("no positive rmse to draw on a log scale".into()));
    };
    let label_w = maps.iter().map(|m| text_width(m, BODY, false)).max().unwrap_or(0) + 24;
    let legend_w = encs.iter().map(|e| text_width(e, BODY, false)).max().unwrap_or(0).max(150) + 48;
    let w = 560 + label_w + legend_w;
    let axis = measure.axis();
    let any_exact = exact.iter().flatten().any(|x| *x);
    let (image, svg, text) = canvas!(w, h, |root| {
        root.fill(&WHITE).map_err(pe)?;
        let mut rest = root.titled(title, (FONT, TITLE).into_font().style(FontStyle::Bold)).map_err(pe)?;
        for (g, group) in groups.iter().enumerate() {
            let (area, below) = rest.split_vertically(heights[g]);
            rest = below;
            let dots = Dots { maps: &maps, encs: &encs, mean: &mean, exact: &exact, lo, hi, label_w, axis: &axis };
            dots.panel(&area, group, w - legend_w, any_exact)?;
        }
        Ok(())
    })?;
    let caption = dots_caption(&measure, (&maps, &encs, &mean, &exact), groups.len(), k);
    Ok(Outcome::Drawn { image, svg, caption, text, marks: vec![] })
}

/// The dot plot's caption, with every exact row's value.
fn dots_caption(
    measure: &Measure,
    (maps, encs, mean, exact): (&[String], &[String], &[Vec<Option<f64>>], &[Vec<bool>]),
    panels: usize,
    k: usize,
) -> String {
    let mut caption = format!(
        "{}; a dot per encoder per map on a log axis fitted to the values; each encoder in its own colour and \
         marker (a hue per family); {panels} panel(s) of at most {PANEL} encoders, all on one scale",
        measure.caption()
    );
    if k > 1 {
        caption.push_str(&format!("; each dot is the mean over the {k} cases (orientations/effects) of the table"));
    }
    let mut exact_rows = Vec::new();
    for (m, row) in mean.iter().enumerate() {
        for (e, v) in row.iter().enumerate() {
            if let (Some(v), true) = (v, exact[m][e]) {
                exact_rows.push(format!("{} on {} {}", encs[e], maps[m], short(*v)));
            }
        }
    }
    if !exact_rows.is_empty() {
        let n = exact_rows.len();
        let shown = exact_rows.iter().take(12).cloned().collect::<Vec<_>>().join(", ");
        let more = if n > 12 { format!(" and {} more (table.csv)", n - 12) } else { String::new() };
        caption.push_str(&format!(
            "; {n} exact row(s) (rel_rmse < {RATIO_FLOOR_REL_RMSE:e} of the reference's RMS), drawn hollow at the \
             axis floor: {shown}{more}"
        ));
    }
    caption
}

/// What every panel of one chart shares.
struct Dots<'a> {
    maps: &'a [String],
    encs: &'a [String],
    mean: &'a [Vec<Option<f64>>],
    exact: &'a [Vec<bool>],
    lo: f64,
    hi: f64,
    label_w: u32,
    axis: &'a str,
}

impl Dots<'_> {
    /// One panel on `area`: its encoders' dots per map (plot `plot_w` wide) and its legend.
    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        group: &[usize],
        plot_w: u32,
        any_exact: bool,
    ) -> Result<()> {
        let (lo, n) = (self.lo, group.len());
        let group_h = n as f64 + 0.8;
        let slots = self.maps.len() as f64 * group_h;
        let (plot, legend) = area.split_horizontally(plot_w);
        let mut fams: Vec<&str> = group.iter().map(|&e| style_of(&self.encs[e]).family.label()).collect();
        fams.dedup();
        let mut chart = ChartBuilder::on(&plot)
            .caption(fams.join(", "), (FONT, HEADING).into_font().style(FontStyle::Bold))
            .margin(10)
            .x_label_area_size(48)
            .y_label_area_size(self.label_w)
            .build_cartesian_2d((lo..self.hi).log_scale(), 0.0..slots)
            .map_err(pe)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(0)
            .y_labels(0)
            .x_label_formatter(&|_| String::new())
            .x_desc(self.axis)
            .label_style((FONT, BODY))
            .axis_desc_style((FONT, BODY))
            .draw()
            .map_err(pe)?;
        let base = plot.get_base_pixel();
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let frame = (xr.start - base.0, yr.start - base.1, xr.end - base.0, yr.end - base.1);
        let ticks = log_ticks(lo, self.hi, 5);
        grid(&plot, frame, &ticks, |v| chart.backend_coord(&(v, 0.0)).0 - base.0, true)?;
        let sep = RGBColor(215, 215, 215);
        for m in 1..self.maps.len() {
            let y = chart.backend_coord(&(lo, slots - m as f64 * group_h + 0.4)).1 - base.1;
            plot.draw(&PathElement::new([(frame.0, y), (frame.2, y)], sep.stroke_width(1))).map_err(pe)?;
        }
        for (k, &e) in group.iter().enumerate() {
            let style = style_of(&self.encs[e]);
            for m in 0..self.maps.len() {
                let Some(v) = self.mean[m][e] else { continue };
                let exact = self.exact[m][e] || v < lo;
                let y = slots - (m as f64 * group_h + k as f64 + 0.5);
                let at = chart.backend_coord(&(if exact { lo } else { v.min(self.hi) }, y));
                let x = if exact { at.0 + 6 } else { at.0 };
                draw_marker(&plot, (x - base.0, at.1 - base.1), &style, 4, !exact)?;
            }
        }
        let style = TextStyle::from((FONT, BODY)).pos(Pos::new(HPos::Right, VPos::Center));
        for (m, name) in self.maps.iter().enumerate() {
            let y = slots - (m as f64 * group_h + n as f64 / 2.0);
            let (x, py) = chart.backend_coord(&(lo, y));
            plot.draw_text(name, &style, (x - 8 - base.0, py - base.1)).map_err(pe)?;
        }
        let left = TextStyle::from((FONT, BODY)).pos(Pos::new(HPos::Left, VPos::Center));
        for (k, &e) in group.iter().enumerate() {
            let y = 40 + k as i32 * 20;
            draw_marker(&legend, (18, y + 7), &style_of(&self.encs[e]), 5, true)?;
            legend.draw_text(&self.encs[e], &left, (36, y + 7)).map_err(pe)?;
        }
        if any_exact {
            let y = 40 + n as i32 * 20 + 8;
            legend.draw(&Circle::new((18, y + 7), 4, BLACK.stroke_width(2))).map_err(pe)?;
            legend.draw_text("hollow: exact,", &left, (36, y + 7)).map_err(pe)?;
            legend.draw_text("at the axis floor", &left, (36, y + 27)).map_err(pe)?;
        }
        Ok(())
    }
}
