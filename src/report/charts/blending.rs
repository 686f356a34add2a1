//! The lightmap blending study: E/π at N along t per method, its rmse, and the overshoot.

use super::super::csvfile::CsvTable;
use super::super::number::sig;
use super::draw::{canvas, pe, Outcome};
use super::lines::{draw_legend, legend_height, legend_width, line_panel, Scale, Series};
use super::rows::distinct;
use crate::math::colour::luminance;
use crate::math::colour::Rgb;
use crate::report::style::style_of;
use anyhow::Result;
use plotters::prelude::*;

/// Whether a CSV is a blending study: `t`, `method`, and E/π at N (`irradiance_at_n_r/_g/_b`
/// or `luma_at_normal`), whatever its name.
pub fn is_blend(t: &CsvTable) -> bool {
    ["t", "method"].iter().all(|h| t.col(h).is_some())
        && (t.col("luma_at_normal").is_some() || t.col("irradiance_at_n_r").is_some())
}

/// Irradiance at N along t per blending method, and its rmse along t (the lightmap blending
/// study; the 2018 brief's Fig. 2). One chart per `set` value when that column exists. The
/// caption gives each method's overshoot beyond both endpoints.
pub fn blend_charts(t: &CsvTable) -> Result<Vec<(String, Outcome)>> {
    let cols = BlendColumns::of(t)?;
    let sc = t.col("set").or(t.col("pair"));
    let all: Vec<usize> = (0..t.rows.len()).collect();
    let sets = match sc {
        Some(c) => distinct(t, &all, c),
        None => vec![String::new()],
    };
    let mut out = Vec::new();
    for set in sets {
        let rows: Vec<usize> = all.iter().copied().filter(|&i| sc.is_none_or(|c| t.rows[i][c] == set)).collect();
        let (irr, err, notes) = cols.series(t, &rows)?;
        let drawn = blend_chart(&set, &irr, &err, &notes)?;
        out.push((set, drawn));
    }
    Ok(out)
}

/// The columns a blending chart reads: `t`, `method`, E/π at N (RGB, or a luminance already),
/// the blended reference's luminance and the rmse when present.
struct BlendColumns {
    t: usize,
    method: usize,
    rgb: [Option<usize>; 3],
    luma: Option<usize>,
    reference: Option<usize>,
    rmse: Option<usize>,
}

impl BlendColumns {
    /// The columns of `t`; an error naming the RGB columns when neither form of E/π at N is there.
    fn of(t: &CsvTable) -> Result<Self> {
        let [tc, mc] = t.require(&["t", "method"])?[..] else { unreachable!() };
        // E/π at N as RGB (luminance taken here) or as a luminance already.
        let rgb = ["irradiance_at_n_r", "irradiance_at_n_g", "irradiance_at_n_b"].map(|h| t.col(h));
        let luma = t.col("luma_at_normal");
        if rgb.iter().any(|c| c.is_none()) && luma.is_none() {
            t.require(&["irradiance_at_n_r", "irradiance_at_n_g", "irradiance_at_n_b"])?;
        }
        // The blended reference: a method of its own, or a column beside every method's rows.
        let reference = t.col("reference_luma_at_normal");
        Ok(BlendColumns { t: tc, method: mc, rgb, luma, reference, rmse: t.col("rmse") })
    }

    /// E/π at N (luminance) of row `i`, `None` when a cell is empty.
    fn at_n(&self, t: &CsvTable, i: usize) -> Result<Option<f64>> {
        if let [Some(r), Some(g), Some(b)] = self.rgb {
            let (Some(x), Some(y), Some(z)) = (t.num(i, r)?, t.num(i, g)?, t.num(i, b)?) else { return Ok(None) };
            return Ok(Some(luminance(Rgb::new(x, y, z))));
        }
        // Cannot fail: without all three rgb columns, `of` refused a table without luma.
        t.num(i, self.luma.expect("checked"))
    }

    /// One set's lines: E/π at N along t per method (and the reference), the rmse along t per
    /// method that has it, and each method's overshoot note.
    fn series(&self, t: &CsvTable, rows: &[usize]) -> Result<(Vec<Series>, Vec<Series>, Vec<String>)> {
        let (mut irr, mut err, mut notes) = (Vec::new(), Vec::new(), Vec::new());
        let mut methods = distinct(t, rows, self.method);
        if self.reference.is_some() {
            methods.push("reference".into());
        }
        let first = methods.first().cloned().unwrap_or_default();
        for m in methods {
            let mut a = Vec::new();
            let mut e = Vec::new();
            let from_column = self.reference.is_some() && m == "reference";
            let picked = if from_column { &first } else { &m };
            for &i in rows.iter().filter(|&&i| t.rows[i][self.method] == *picked) {
                let Some(tv) = t.num(i, self.t)? else { continue };
                // Cannot fail: `from_column` implies `reference.is_some()`.
                let v = if from_column { t.num(i, self.reference.expect("checked"))? } else { self.at_n(t, i)? };
                let Some(v) = v else { continue };
                a.push((tv, v));
                if from_column {
                    continue;
                }
                if let Some(v) = self.rmse.map(|c| t.num(i, c)).transpose()?.flatten() {
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
            let style = style_of(&m);
            irr.push(Series { label: m.clone(), style, dashed: false, points: a });
            if !e.is_empty() {
                err.push(Series { label: m, style, dashed: false, points: e });
            }
        }
        Ok((irr, err, notes))
    }
}

/// One set's chart: E/π at N along t and, when any method has an rmse, the rmse along t
/// beside it; the caption with each method's overshoot.
fn blend_chart(set: &str, irr: &[Series], err: &[Series], notes: &[String]) -> Result<Outcome> {
    let two = !err.is_empty();
    let title = if set.is_empty() { String::new() } else { format!(" ({set})") };
    let w = if two { 1200 } else { 640 };
    let (image, svg, text) = canvas!(w + legend_width(irr), legend_height(irr), |root| {
        root.fill(&WHITE).map_err(pe)?;
        draw_legend(root, irr, w as i32)?;
        let root = &root.split_horizontally(w).0;
        let (a, b) = if two { root.split_horizontally(600) } else { (root.clone(), root.clone()) };
        let linear = Scale { linear_y: true, log2_x: false };
        let x = "blend parameter t (no unit)";
        line_panel(&a, &format!("irradiance at N along t{title}"), (x, "E/π at N (Rec.709 luminance)"), irr, linear)?;
        if two {
            let y = "RMSE of E/π (hemisphere about N, solid-angle)";
            line_panel(&b, &format!("RMSE along t{title}"), (x, y), err, linear)?;
        }
        Ok(())
    })?;
    let caption = format!(
        "blending{title}: E/π at N (luminance) along t per method{}; overshoot = largest excursion beyond both \
         endpoints' values: {}",
        if two { ", and the RMSE of E/π over the hemisphere about N along t" } else { "" },
        notes.join("; ")
    );
    Ok(Outcome::Drawn { image, svg, caption, text, marks: vec![] })
}
