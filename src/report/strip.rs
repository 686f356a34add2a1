//! Drawing a blending strip (`blend_strip_<pair>.png` of the lightmap study): the data —
//! lit-hemisphere values along t per method, the disc, the titles — comes from the claims layer
//! ([`BlendStrip`]); this draws one row per method and one disc (looking down N) per t.
//! Exposure: the first row's pixel-mean luminance → 0.5 (the study puts the blended reference
//! first); the same [`Tone`] for every disc.

use super::canvas::{fill, paint_disc, CELL, PAPER};
use super::number::sig;
use super::png::png_bytes;
use super::sheet::{LINE_H, MARGIN};
use super::text::{draw_labels, text_width, Label, BODY, TITLE};
use super::tone::Tone;
use crate::claims::lightmap::strip::BlendStrip;
use crate::math::colour::luminance;
use crate::math::colour::Rgb;
use anyhow::Result;
use image::RgbImage;

/// Width of the method names' column, in pixels: at least this, wider when a name needs it.
const LABEL_W: u32 = 150;

/// Draws a blending strip (see the module doc); an error if a row lacks a reconstruction for
/// some t or a value for some normal of the disc.
pub fn draw(strip: &BlendStrip) -> Result<RgbImage> {
    let (title, ts, rows, disc) = (&strip.title, &strip.ts, &strip.rows, &strip.disc);
    let bad = |r: &crate::claims::lightmap::strip::StripRow| {
        r.values.len() != ts.len()
            || r.values.iter().any(|v| v.len() != disc.normals.len())
            || !(r.rmse.is_empty() || r.rmse.len() == ts.len())
    };
    if rows.iter().any(bad) {
        anyhow::bail!(
            "blend strip '{title}': every method needs one reconstruction per t ({} values) at the {} strip normals, \
             and one RMSE per t or none",
            ts.len(),
            disc.normals.len()
        );
    }
    let first: Vec<Rgb> = rows.first().map(|r| r.values.concat()).unwrap_or_default();
    let mean =
        if first.is_empty() { 0.0 } else { first.iter().map(|c| luminance(*c)).sum::<f64>() / first.len() as f64 };
    let max = first.iter().map(|c| c.max_element()).fold(0.0, f64::max);
    let tone = Tone::from_reference(mean, max);
    let cell = disc.d as u32 + 8;
    // Room under each disc for its RMSE, when the strip prints them.
    let numbers = rows.iter().any(|r| r.rmse.iter().any(Option::is_some));
    let text_h = if numbers { LINE_H } else { 0 };
    // The caption's lines: the view, the tone map, and what the numbers under the discs are.
    let mut caption = vec![
        format!("E/π, {}", strip.view.caption),
        format!("{}; exposure from the first row's mean", tone.describe()),
    ];
    if numbers {
        caption.push("under each disc: RMSE vs the blended reference (hemisphere)".to_string());
    }
    let head = MARGIN + 26 + caption.len() as u32 * LINE_H + 22;
    let label_w = rows.iter().map(|r| text_width(&r.method, BODY, true) + 14).fold(LABEL_W, u32::max);
    // Wide enough for the title and every caption line, so no text is cut at the right edge.
    let text_w = caption.iter().map(|c| text_width(c, BODY, false)).chain([text_width(title, TITLE, true)]).max();
    let w = (2 * MARGIN + label_w + ts.len() as u32 * cell).max(2 * MARGIN + text_w.unwrap_or(0));
    let h = head + rows.len() as u32 * (cell + 4 + text_h) + MARGIN;
    let mut img = RgbImage::from_pixel(w, h, image::Rgb(PAPER));
    let mut labels = vec![Label::new(title, MARGIN, MARGIN, TITLE).bold()];
    for (i, line) in caption.iter().enumerate() {
        labels.push(Label::new(line, MARGIN, MARGIN + 26 + i as u32 * LINE_H, BODY));
    }
    for (k, t) in ts.iter().enumerate() {
        let x = MARGIN + label_w + k as u32 * cell + cell / 2;
        labels.push(Label::new(format!("t = {}", sig(*t, 2)), x, head - 20, BODY).centre());
    }
    for (r, row) in rows.iter().enumerate() {
        let y = head + r as u32 * (cell + 4 + text_h);
        labels.push(Label::new(&row.method, MARGIN, y + cell / 2 - 8, BODY).bold());
        for (k, vals) in row.values.iter().enumerate() {
            let x = MARGIN + label_w + k as u32 * cell;
            fill(&mut img, x + 1, y, cell - 2, cell, CELL);
            paint_disc(&mut img, x + 4, y + 4, disc, CELL, |i| tone.map(vals[i]));
            if let Some(Some(e)) = row.rmse.get(k) {
                labels.push(Label::new(format!("RMSE {}", sig(*e, 3)), x + cell / 2, y + cell + 1, BODY).centre());
            }
        }
    }
    draw_labels(&mut img, &labels)?;
    Ok(img)
}

/// The PNG files of strips: (file name, PNG bytes), each drawn by [`draw`].
pub fn pngs(strips: &[BlendStrip]) -> Result<Vec<(String, Vec<u8>)>> {
    strips.iter().map(|s| Ok((s.file_name(), png_bytes(&draw(s)?)?))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::claims::lightmap::strip::{strip_disc, strip_normals, StripRow, STRIP_DISC};
    use crate::encoders::encoder::Fitted;
    use crate::reference::view::View;
    use glam::DVec3;

    /// A strip of SH L1 fits of two scenes blended in SH along t: one row per method, one disc
    /// per t; the ends show the two scenes' own fits.
    #[test]
    fn blend_strip_draws_one_disc_per_t() {
        let scene = |id: &str| crate::reference::scenes::generated().into_iter().find(|s| s.id == id).unwrap().map(32);
        let sh = |id: &str| crate::reference::projection::project(&scene(id));
        let (a, b) = (sh("gen_hemisphere"), sh("gen_two_lights"));
        let ts = vec![0.0, 0.5, 1.0];
        let blended: Vec<crate::math::sh::Sh9> = ts.iter().map(|&t| a * (1.0 - t) + b * t).collect();
        let enc = crate::encoders::build("sh1", None, toml::Table::new()).unwrap().encoder;
        let normals = strip_normals(DVec3::Y);
        let fits: Vec<Box<dyn Fitted>> =
            blended.iter().map(|s| enc.fit(&crate::encoders::encoder::FitInput::sphere(s))).collect();
        let values: Vec<Vec<Rgb>> = fits.iter().map(|f| normals.iter().map(|&m| f.irradiance(m)).collect()).collect();
        let view = View::down(DVec3::Y, "+y");
        let strip = |rows: Vec<StripRow>| BlendStrip {
            pair: "test".into(),
            title: "test".into(),
            disc: strip_disc(&view),
            view: view.clone(),
            ts: ts.clone(),
            rows,
        };
        let img =
            draw(&strip(vec![StripRow { method: "sh1 of blended SH".into(), values: values.clone(), rmse: vec![] }]))
                .unwrap();
        let (d, cell) = (STRIP_DISC as u32, STRIP_DISC as u32 + 8);
        // Three discs are narrower than the caption's tone line: the strip widens to its longest
        // line, so no text reaches (and is cut at) the right edge.
        assert!(img.width() > 2 * MARGIN + LABEL_W + 3 * cell, "the case tests the widening");
        let head = MARGIN + 26 + 2 * LINE_H + 22;
        for y in 0..head {
            for x in img.width() - MARGIN..img.width() {
                assert_eq!(img.get_pixel(x, y).0, PAPER, "text in the right margin at ({x}, {y})");
            }
        }
        assert_eq!(img.height(), head + (cell + 4) + MARGIN);
        let centre = |k: u32| img.get_pixel(MARGIN + LABEL_W + k * cell + 4 + d / 2, head + 4 + d / 2).0;
        assert_ne!(centre(0), centre(2), "the two ends differ");
        let bad = StripRow { method: "x".into(), values: vec![vec![Rgb::ZERO; normals.len()]], rmse: vec![] };
        assert!(draw(&strip(vec![bad])).is_err());
        let numbered = StripRow { method: "m".into(), values, rmse: vec![Some(0.1), None, Some(0.25)] };
        // Printing each cell's RMSE adds a line of text under every row's discs, and a caption
        // line saying what they are.
        assert_eq!(draw(&strip(vec![numbered])).unwrap().height(), head + LINE_H + (cell + 4 + LINE_H) + MARGIN);
    }
}
