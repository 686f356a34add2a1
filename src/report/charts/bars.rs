//! Horizontal bars of rmse per encoder, grouped by map, on a log axis.

use super::super::csvfile::CsvTable;
use super::super::text::FONT;
use super::axes::{decades, tick};
use super::draw::{canvas, colour, pe, Outcome};
use super::rows::{distinct, metric_rows};
use anyhow::Result;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

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
