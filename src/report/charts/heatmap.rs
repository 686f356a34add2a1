//! Many maps × many encoders as a heatmap of RMSE relative to a named baseline on the same
//! map, the ratio written in every cell: a row per encoder (in family order, its name in its
//! own colour), a column per map. Blue is better than the baseline, red worse, on a log2 scale
//! saturating at 8× either way ([`crate::report::tone::diverging`]). The baseline's own row
//! gives its absolute RMSE, so every cell can be turned back into an RMSE.

use super::super::text::{text_width, BODY, FONT, TITLE};
use super::axes::short;
use super::draw::{canvas, pe, Outcome};
use super::marks::rgb;
use super::rows::Measure;
use crate::report::style::style_of;
use crate::report::tone::diverging;
use anyhow::Result;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A cell's height, px; its width is set by the map names (two staggered header lines).
const ROW: i32 = 22;
/// The ratio at which the colour saturates, as a power of two (2³ = 8×).
const SATURATE_LOG2: f64 = 3.0;

/// One cell's text and colour: the ratio to the baseline (or the baseline's own RMSE, or
/// "exact", or "—" where the baseline is exact on that map).
fn cell(v: Option<f64>, base: Option<f64>, exact: bool, base_exact: bool, is_base: bool) -> (String, [u8; 3]) {
    let white = [255, 255, 255];
    match (v, base) {
        (None, _) => (String::new(), white),
        (Some(_), _) if exact => ("exact".into(), [235, 235, 235]),
        (Some(v), _) if is_base => (short(v), white),
        (Some(_), _) if base_exact => ("—".into(), [235, 235, 235]),
        (Some(v), Some(b)) if b > 0.0 => (short(v / b), diverging((v / b).log2() / SATURATE_LOG2)),
        _ => (String::new(), white),
    }
}

/// What a heatmap shows: the maps, the encoders, the mean rmse per map per encoder, which of
/// those are exact to rounding, and the encoders' row order.
pub(super) struct Cells<'a> {
    pub(super) maps: &'a [String],
    pub(super) encs: &'a [String],
    pub(super) mean: &'a [Vec<Option<f64>>],
    pub(super) exact: &'a [Vec<bool>],
    pub(super) order: Vec<usize>,
}

/// The heatmap of `c` relative to encoder `base`; `k` is the most cases a cell averages.
pub(super) fn heatmap(c: &Cells, base: usize, title: &str, measure: &Measure, k: usize) -> Result<Outcome> {
    let Cells { maps, encs, mean, exact, order } = c;
    let name_w = encs.iter().map(|e| text_width(e, BODY, false)).max().unwrap_or(0) as i32 + 24;
    let head_w = maps.iter().map(|m| text_width(m, BODY, false)).max().unwrap_or(0) as i32;
    let col = (head_w / 2 + 10).max(text_width("0.00e-0", BODY, false) as i32 + 10);
    let top = 44 + 2 * ROW + 8;
    let (w, h) =
        ((name_w + col * maps.len() as i32 + col / 2 + 20) as u32, (top + ROW * order.len() as i32 + 20) as u32);
    let (image, svg, text) = canvas!(w, h, |root| {
        root.fill(&WHITE).map_err(pe)?;
        let centre =
            TextStyle::from((FONT, TITLE).into_font().style(FontStyle::Bold)).pos(Pos::new(HPos::Center, VPos::Top));
        root.draw_text(&format!("{title}, as a ratio to {}", encs[base]), &centre, (w as i32 / 2, 8)).map_err(pe)?;
        let mid = TextStyle::from((FONT, BODY)).pos(Pos::new(HPos::Center, VPos::Center));
        for (m, name) in maps.iter().enumerate() {
            let x = name_w + col * m as i32 + col / 2;
            let y = 44 + (m as i32 % 2) * ROW + ROW / 2;
            root.draw_text(name, &mid, (x, y)).map_err(pe)?;
            root.draw(&PathElement::new([(x, y + ROW / 2 - 2), (x, top - 2)], RGBColor(190, 190, 190))).map_err(pe)?;
        }
        for (r, &e) in order.iter().enumerate() {
            let y = top + r as i32 * ROW;
            let ink = rgb(&style_of(&encs[e]));
            let label = TextStyle::from((FONT, BODY).into_font()).color(&ink).pos(Pos::new(HPos::Right, VPos::Center));
            root.draw_text(&encs[e], &label, (name_w - 10, y + ROW / 2)).map_err(pe)?;
            for m in 0..maps.len() {
                let x = name_w + col * m as i32;
                let (t, c) = cell(mean[m][e], mean[m][base], exact[m][e], exact[m][base], e == base);
                root.draw(&Rectangle::new([(x, y), (x + col - 1, y + ROW - 1)], RGBColor(c[0], c[1], c[2]).filled()))
                    .map_err(pe)?;
                let dark = c.iter().map(|&v| v as u32).sum::<u32>() < 330;
                let ink = if dark { WHITE } else { RGBColor(20, 20, 20) };
                let style =
                    TextStyle::from((FONT, BODY).into_font()).color(&ink).pos(Pos::new(HPos::Center, VPos::Center));
                root.draw_text(&t, &style, (x + col / 2, y + ROW / 2)).map_err(pe)?;
            }
        }
        let y = top + order.iter().position(|&e| e == base).unwrap_or(0) as i32 * ROW;
        let frame = [(name_w, y), (name_w + col * maps.len() as i32 - 1, y + ROW - 1)];
        root.draw(&Rectangle::new(frame, BLACK.stroke_width(2))).map_err(pe)?;
        Ok(())
    })?;
    let mut caption = format!(
        "{}; as a ratio to `{b}` on the same map (the ratio in each cell; `{b}`'s own row gives its RMSE); blue is \
         better than `{b}`, red worse, on a log2 scale saturating at {}× either way; \"exact\": rel_rmse under 1e-6 \
         of the reference's RMS; \"—\": `{b}` exact there, no ratio; a row per encoder in family order, a column \
         per map ({} maps × {} encoders, too many for a dot plot)",
        measure.caption(),
        2f64.powf(SATURATE_LOG2),
        maps.len(),
        encs.len(),
        b = encs[base],
    );
    if k > 1 {
        caption.push_str(&format!("; each cell is the mean over the {k} cases (orientations/effects) of the table"));
    }
    Ok(Outcome::Drawn { image, svg, caption, text, marks: vec![] })
}
