//! Horizontal bars of rmse per encoder, grouped by map, on a log axis; the encoders in panels
//! of at most [`PANEL`] legend entries, a hue per encoder family ([`Family`], declared by each
//! encoder) and within a family a lightness and a marker per member.

use super::super::csvfile::CsvTable;
use super::super::text::{text_width, BODY, FONT, HEADING, TITLE};
use super::axes::{decades, tick};
use super::draw::{canvas, pe, Outcome};
use super::rows::{distinct, metric_rows, Measure};
use crate::encoders::encoder::Family;
use anyhow::Result;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The most legend entries of one panel.
pub const PANEL: usize = 8;
/// The lightness levels within a family's hue (each with a marker shape as well).
pub const SHADES: usize = 4;

/// Maps, encoders, mean rmse per (map, encoder), and the largest number of rows averaged.
pub(super) type MeanRmse = (Vec<String>, Vec<String>, Vec<Vec<Option<f64>>>, usize);

/// Mean rmse per (map, encoder) and the largest number of rows averaged.
pub(super) fn mean_rmse(t: &CsvTable, rows: &[usize]) -> Result<MeanRmse> {
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

/// The Tableau 10 hues, one per family in [`Family::ALL`] order.
const HUES: [(u8, u8, u8); 10] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (188, 189, 34),
    (23, 190, 207),
    (127, 127, 127),
];

/// One bar series: an encoder, its family and its place within its family's members.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// Column of the encoder in the mean table.
    pub encoder: usize,
    /// Its family.
    pub family: Family,
    /// Its place among its family's members in the panel (0..[`PANEL`]).
    pub member: usize,
}

/// The colour of a family's member: the family's hue, darker or lighter by member (members
/// 4 apart share a lightness and differ in marker, [`marker_shape`]).
pub fn entry_colour(family: Family, member: usize) -> RGBColor {
    let (r, g, b) = HUES[family.index() % HUES.len()];
    // Member 0 the hue darkened, then the hue, then two lighter tints.
    let t = [-0.35, 0.0, 0.4, 0.65][member % SHADES];
    let mix = |c: u8| -> u8 {
        let c = c as f64;
        (if t < 0.0 { c * (1.0 + t) } else { c + (255.0 - c) * t }).round() as u8
    };
    RGBColor(mix(r), mix(g), mix(b))
}

/// The encoders in panels: sorted by family (in [`Family::ALL`] order, members in the table's
/// order), a family of more than [`PANEL`] cut into near-equal runs of at most [`PANEL`], the
/// runs packed in order into panels of at most [`PANEL`] entries (a panel never holds two runs
/// of one family, so each member's lightness and marker are its own in its panel).
pub fn panels(encoders: &[String], family: &dyn Fn(&str) -> Family) -> Vec<Vec<Entry>> {
    let mut runs: Vec<Vec<Entry>> = Vec::new();
    for f in Family::ALL {
        let members: Vec<usize> = (0..encoders.len()).filter(|&e| family(&encoders[e]) == f).collect();
        let n = members.len().div_ceil(PANEL).max(1);
        for run in members.chunks(members.len().div_ceil(n).max(1)) {
            runs.push(run.iter().enumerate().map(|(m, &e)| Entry { encoder: e, family: f, member: m }).collect());
        }
    }
    let mut out: Vec<Vec<Entry>> = Vec::new();
    for run in runs {
        match out.last_mut() {
            Some(p) if p.len() + run.len() <= PANEL && p.iter().all(|e| e.family != run[0].family) => p.extend(run),
            _ => out.push(run),
        }
    }
    out
}

/// Pixels per bar slot, and the plot's margin above and below the bars (title, x axis).
const BAR: f64 = 10.0;
const PANEL_EXTRA: u32 = 96;

/// Horizontal bars of rmse per encoder, grouped by map, log scale, in panels of at most
/// [`PANEL`] encoders (see [`panels`]); `family` gives each encoder's family.
pub fn rmse_bars(t: &CsvTable, title: &str, family: &dyn Fn(&str) -> Family) -> Result<Outcome> {
    if t.col("map").is_none() || t.col("encoder").is_none() || t.col("rmse").is_none() {
        return Ok(Outcome::Skipped("the table has no map, encoder and rmse columns".into()));
    }
    let (rows, _) = metric_rows(t);
    let (maps, encs, mean, k) = mean_rmse(t, &rows)?;
    let Some((lo, hi)) = decades(mean.iter().flatten().flatten().copied()) else {
        return Ok(Outcome::Skipped("no positive rmse to draw on a log scale".into()));
    };
    let measure = Measure::of(t, &rows);
    let zeros = mean.iter().flatten().flatten().filter(|v| **v <= 0.0).count();
    let groups = panels(&encs, family);
    let label_w = maps.iter().map(|m| text_width(m, BODY, false)).max().unwrap_or(0) + 24;
    let legend_w = encs.iter().map(|e| text_width(e, BODY, false)).max().unwrap_or(0) + 48;
    let heights: Vec<u32> = groups.iter().map(|g| panel_height(maps.len(), g.len())).collect();
    let w = 560 + label_w + legend_w;
    let h = 40 + heights.iter().sum::<u32>();
    let axis = measure.axis();
    let (image, svg, text) = canvas!(w, h, |root| {
        root.fill(&WHITE).map_err(pe)?;
        let mut rest = root.titled(title, (FONT, TITLE).into_font().style(FontStyle::Bold)).map_err(pe)?;
        for (g, group) in groups.iter().enumerate() {
            let (area, below) = rest.split_vertically(heights[g]);
            rest = below;
            let bars = Bars { maps: &maps, encs: &encs, mean: &mean, lo, hi, label_w, axis: &axis };
            bars.panel(&area, group, w - legend_w)?;
        }
        Ok(())
    })?;
    let mut caption = format!(
        "{}; per encoder per map, log scale; a hue per encoder family, a lightness and marker per member; \
         {} panel(s) of at most {PANEL} encoders, all on one scale",
        measure.caption(),
        groups.len()
    );
    if k > 1 {
        caption.push_str(&format!("; each bar is the mean over the {k} cases (orientations/effects) of the table"));
    }
    if zeros > 0 {
        caption.push_str(&format!("; {zeros} zero rmse value(s) drawn at the axis floor"));
    }
    Ok(Outcome::Drawn { image, svg, caption, text, marks: vec![] })
}

/// A panel's height for `maps` maps and `n` encoders.
fn panel_height(maps: usize, n: usize) -> u32 {
    (maps as f64 * (n as f64 + 0.8) * BAR).ceil() as u32 + PANEL_EXTRA
}

/// What every panel of one chart shares.
struct Bars<'a> {
    maps: &'a [String],
    encs: &'a [String],
    mean: &'a [Vec<Option<f64>>],
    lo: f64,
    hi: f64,
    label_w: u32,
    axis: &'a str,
}

impl Bars<'_> {
    /// One panel on `area`: its encoders' bars per map (plot `plot_w` wide) and its legend.
    fn panel<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, group: &[Entry], plot_w: u32) -> Result<()> {
        let (lo, n) = (self.lo, group.len());
        let group_h = n as f64 + 0.8;
        let slots = self.maps.len() as f64 * group_h;
        let (plot, legend) = area.split_horizontally(plot_w);
        let mut fams: Vec<&str> = group.iter().map(|e| e.family.label()).collect();
        fams.dedup();
        let mut chart = ChartBuilder::on(&plot)
            .caption(fams.join(", "), (FONT, HEADING).into_font().style(FontStyle::Bold))
            .margin(10)
            .x_label_area_size(44)
            .y_label_area_size(self.label_w)
            .build_cartesian_2d((lo..self.hi).log_scale(), 0.0..slots)
            .map_err(pe)?;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .y_labels(0)
            .x_desc(self.axis)
            .x_label_formatter(&|v| tick(*v))
            .label_style((FONT, BODY))
            .axis_desc_style((FONT, BODY))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(pe)?;
        for (k, e) in group.iter().enumerate() {
            let c = entry_colour(e.family, e.member);
            let bars = (0..self.maps.len()).filter_map(|m| {
                let v = self.mean[m][e.encoder]?;
                let y0 = slots - (m as f64 * group_h + k as f64 + 0.1);
                Some(Rectangle::new([(lo, y0), (v.max(lo), y0 - 0.85)], c.filled()))
            });
            chart.draw_series(bars).map_err(pe)?;
            for m in 0..self.maps.len() {
                let Some(v) = self.mean[m][e.encoder] else { continue };
                let y = slots - (m as f64 * group_h + k as f64 + 0.525);
                let at = chart.backend_coord(&(v.max(lo), y));
                let base = plot.get_base_pixel();
                marker(&plot, (at.0 - 6 - base.0, at.1 - base.1), e.member)?;
            }
        }
        let style = TextStyle::from((FONT, BODY)).pos(Pos::new(HPos::Right, VPos::Center));
        for (m, name) in self.maps.iter().enumerate() {
            let y = slots - (m as f64 * group_h + n as f64 / 2.0);
            let (x, py) = chart.backend_coord(&(lo, y));
            let base = plot.get_base_pixel();
            plot.draw_text(name, &style, (x - 8 - base.0, py - base.1)).map_err(pe)?;
        }
        for (k, e) in group.iter().enumerate() {
            let y = 40 + k as i32 * 20;
            legend
                .draw(&Rectangle::new([(6, y), (30, y + 14)], entry_colour(e.family, e.member).filled()))
                .map_err(pe)?;
            marker(&legend, (18, y + 7), e.member)?;
            let name = &self.encs[e.encoder];
            legend
                .draw_text(name, &TextStyle::from((FONT, BODY)).pos(Pos::new(HPos::Left, VPos::Center)), (36, y + 7))
                .map_err(pe)?;
        }
        Ok(())
    }
}

/// A member's marker shape (0 circle, 1 square, 2 triangle, 3 diamond): with its lightness
/// (`member % SHADES`), distinct for the [`PANEL`] members a panel may hold of one family.
pub fn marker_shape(member: usize) -> usize {
    (member + member / SHADES) % 4
}

/// A member's marker centred at `at` ([`marker_shape`]), dark and white-edged.
fn marker<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, at: (i32, i32), member: usize) -> Result<()> {
    let ink = RGBColor(30, 30, 30).filled();
    let edge = WHITE.stroke_width(1);
    let (x, y) = at;
    let shape: Vec<(i32, i32)> = match marker_shape(member) {
        0 => {
            area.draw(&Circle::new(at, 4, ink)).map_err(pe)?;
            return area.draw(&Circle::new(at, 4, edge)).map_err(pe);
        }
        1 => vec![(x - 4, y - 4), (x + 4, y - 4), (x + 4, y + 4), (x - 4, y + 4)],
        2 => vec![(x, y - 5), (x + 5, y + 4), (x - 5, y + 4)],
        _ => vec![(x, y - 5), (x + 5, y), (x, y + 5), (x - 5, y)],
    };
    area.draw(&Polygon::new(shape.clone(), ink)).map_err(pe)?;
    let mut closed = shape.clone();
    closed.push(shape[0]);
    area.draw(&PathElement::new(closed, edge)).map_err(pe)
}
