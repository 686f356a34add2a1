//! A comparison sheet as drawn: [`Sheet`] and its [`SheetRow`]s, painted at the sheet's scale
//! (title, header lines, thumbnail, the error and chroma colour bars, the view captions, three
//! spheres per view per row — four with the chroma discs — and the figures under them).

use super::super::canvas::{fill, paint_disc, CELL, PAPER};
use super::super::number::{percent, sig};
use super::super::text::{draw_labels, fit_text, wrap, Label, BODY, TITLE};
use super::super::tone::{diverging, ErrorScale, Tone};
use super::chroma::{chroma_bar, disc_figure, sequential, Chroma};
use super::layout::{
    label_width, text_px, SheetLayout, BAR_H, BAR_W, CELL_H, CELL_W, DISC, HEADER_H, HEADER_LINES, LINE_H, MARGIN,
    MAX_SCALE, NAME_PX, NOTE_PX, THUMB_H,
};
use crate::math::colour::{xy_distance, Rgb};
use crate::reference::view::{Disc, View};
use anyhow::{ensure, Result};
use image::RgbImage;
use plotters::style::text_anchor::HPos;

/// One row of a sheet: an encoder's E/π at every view's disc normals and its labels.
#[derive(Clone, Debug)]
pub struct SheetRow {
    /// The encoder's name, printed bold in the label column.
    pub name: String,
    /// The encoder's storage note, printed under its name.
    pub note: String,
    /// Per view, E/π at that view's [`Disc::normals`].
    pub values: Vec<Vec<Rgb>>,
    /// Under the lit sphere (e.g. the negative fraction), may be empty.
    pub under_lit: String,
    /// Under the error sphere: two lines.
    pub under_err: [String; 2],
}

/// Everything a comparison sheet shows.
#[derive(Clone, Debug)]
pub struct Sheet {
    /// The title: `<experiment> - <map>`.
    pub title: String,
    /// Header lines (at most [`HEADER_LINES`]).
    pub lines: Vec<String>,
    /// The input map as a lat-long thumbnail, [`THUMB_W`]·scale × [`THUMB_H`]·scale pixels;
    /// `None` draws none.
    pub thumbnail: Option<RgbImage>,
    /// The line under the thumbnail.
    pub thumbnail_caption: String,
    /// The views of the sphere of normals, one group of three cells each.
    pub views: Vec<View>,
    /// Per view, the disc of normals drawn ([`DISC`]·scale pixels across).
    pub discs: Vec<Disc>,
    /// Per view, the reference E/π at the disc normals.
    pub reference: Vec<Vec<Rgb>>,
    /// The sheet's scale (1..=[`MAX_SCALE`]): the discs are [`DISC`]·scale across, the
    /// thumbnail [`THUMB_W`]·scale wide.
    pub scale: u32,
    /// The exposure and tone curve every lit sphere shares.
    pub tone: Tone,
    /// The error spheres' colour scale: the denominator's floor and the saturating range.
    pub error: ErrorScale,
    /// The chroma discs: drawn on their scale, or not and why ([`super::chroma`]).
    pub chroma: Chroma,
    /// One row per encoder, in the experiment's order.
    pub rows: Vec<SheetRow>,
}

/// Draws the horizontal colour bar of an error scale at (x0, y0), with its title, its meaning
/// and labelled values (−R, −R/2, 0, +R/2, +R in percent of the reference; the ends saturate),
/// at sheet scale `s` ([`BAR_W`]·s columns, each coloured at its own centre).
fn colour_bar(img: &mut RgbImage, labels: &mut Vec<Label>, x0: u32, y0: u32, scale: &ErrorScale, s: u32) {
    let (bar_w, bar_h) = (s * BAR_W, s * BAR_H);
    for x in 0..bar_w {
        let v = ((x as f64 + 0.5) / bar_w as f64) * 2.0 - 1.0;
        fill(img, x0 + x, y0, 1, bar_h, diverging(v));
    }
    labels.push(
        Label::new("relative error of luminance, % (saturates beyond)", x0, y0 - s * 40, text_px(BODY, s)).bold(),
    );
    labels.push(Label::new("(Y - Y_ref) / Y_ref: blue darker, red brighter", x0, y0 - s * 21, text_px(BODY, s)));
    let r = scale.range;
    for (frac, text) in [
        (0.0, format!("-{}", percent(r))),
        (0.25, format!("-{}", percent(r / 2.0))),
        (0.5, "0".to_string()),
        (0.75, format!("+{}", percent(r / 2.0))),
        (1.0, format!("+{}", percent(r))),
    ] {
        let x = x0 + (frac * bar_w as f64) as u32;
        fill(img, x.min(x0 + bar_w - s), y0 + bar_h, s, s * 4, [0, 0, 0]);
        let l = Label::new(text, x, y0 + bar_h + s * 5, text_px(BODY, s));
        labels.push(if frac == 0.0 {
            l
        } else if frac == 1.0 {
            Label { anchor: HPos::Right, ..l }
        } else {
            l.centre()
        });
    }
}

impl Sheet {
    /// The line under a row that states, per view, the share of its error sphere's pixels
    /// beyond ±R, where the colour saturates.
    fn saturation_line(&self, row: &SheetRow) -> String {
        let shares: Vec<String> = self
            .views
            .iter()
            .zip(row.values.iter().zip(&self.reference))
            .map(|(view, (vals, refs))| {
                let share = self.error.saturated(vals.iter().zip(refs).map(|(v, r)| self.error.relative(*r, *v)));
                let name = view.caption.split(':').next().unwrap_or("disc");
                format!("{name} {}", percent(share))
            })
            .collect();
        let chroma = self.chroma.range().map(|r| saturation(self, row, r)).unwrap_or_default();
        format!("error beyond ±{} (saturated): {} of the disc{chroma}", percent(self.error.range), shares.join(", "))
    }

    /// The sheet's geometry; the label column measured at scale 1 (so every measure of a sheet
    /// at scale N is exactly N times its scale-1 value).
    pub fn layout(&self) -> SheetLayout {
        let label_w = label_width(self.rows.iter().map(|r| (r.name.as_str(), r.note.as_str())));
        SheetLayout {
            rows: self.rows.len() as u32,
            views: self.views.len() as u32,
            label_w,
            scale: self.scale,
            chroma: self.chroma.range().is_some(),
        }
    }

    /// Draws the sheet at its scale: positions, lengths and text sizes are the scale-1 ones
    /// times [`Sheet::scale`]; the discs' pixels are the ones evaluated at [`Sheet::discs`].
    pub fn draw(&self) -> Result<RgbImage> {
        Ok(self.draw_with_labels()?.0)
    }

    /// [`Sheet::draw`], and the text labels it drew (for the layout checks).
    pub fn draw_with_labels(&self) -> Result<(RgbImage, Vec<Label>)> {
        let s = self.scale;
        ensure!((1..=MAX_SCALE).contains(&s), "sheet scale {s}: must be 1 to {MAX_SCALE}");
        for d in &self.discs {
            ensure!(d.d == (s * DISC) as usize, "sheet at scale {s}: a disc is {} px across, not {}", d.d, s * DISC);
        }
        let lay = self.layout();
        let (w, h) = lay.size();
        let (margin, cell_w) = (s * MARGIN, s * CELL_W);
        let mut img = RgbImage::from_pixel(w, h, image::Rgb(PAPER));
        let mut labels = Vec::new();
        labels.push(Label::new(&self.title, margin, margin, text_px(TITLE, s)).bold());
        let wrapped: Vec<String> = self.lines.iter().flat_map(|l| wrap(l, w - 2 * margin, text_px(BODY, s))).collect();
        for (i, line) in wrapped.iter().take(HEADER_LINES as usize).enumerate() {
            labels.push(Label::new(
                fit_text(line, w - 2 * margin, text_px(BODY, s)),
                margin,
                s * (MARGIN + 26 + i as u32 * LINE_H),
                text_px(BODY, s),
            ));
        }
        let thumb_y = s * (MARGIN + 26 + HEADER_LINES * LINE_H + 8);
        if let Some(t) = &self.thumbnail {
            image::imageops::replace(&mut img, t, margin as i64, thumb_y as i64);
            labels.push(
                Label::new(&self.thumbnail_caption, margin, thumb_y + s * (THUMB_H + 3), text_px(BODY, s)).grey(),
            );
        }
        let (bx, by) = lay.colour_bar();
        colour_bar(&mut img, &mut labels, bx, by, &self.error, s);
        chroma_bar(&mut img, &mut labels, lay.chroma_bar(), lay.chroma_text_width(), &self.chroma, s);

        let head_y = s * HEADER_H;
        for (v, view) in self.views.iter().enumerate() {
            let (x, _) = lay.cell(0, v as u32, 0);
            labels.push(Label::new(&view.caption, x, head_y, text_px(BODY, s)).bold());
            let names = ["reference", "encoder", "rel. error", "chroma err."];
            for (c, name) in names[..lay.columns() as usize].iter().enumerate() {
                let cx = x + c as u32 * cell_w + cell_w / 2;
                labels.push(Label::new(*name, cx, head_y + s * 20, text_px(BODY, s)).centre().grey());
            }
        }
        self.draw_rows(&mut img, &mut labels, &lay);
        draw_labels(&mut img, &labels)?;
        Ok((img, labels))
    }

    /// Each encoding's row: its name and note, its discs per view, and the figures under the
    /// first view's discs.
    fn draw_rows(&self, img: &mut RgbImage, labels: &mut Vec<Label>, lay: &SheetLayout) {
        let s = self.scale;
        let (margin, cell_w, cell_h) = (s * MARGIN, s * CELL_W, s * CELL_H);
        for (r, row) in self.rows.iter().enumerate() {
            let (_, y) = lay.cell(r as u32, 0, 0);
            labels.push(Label::new(&row.name, margin, y + s * (CELL_H / 2 - 18), text_px(NAME_PX, s)).bold());
            labels.push(Label::new(&row.note, margin, y + s * (CELL_H / 2 + 2), text_px(NOTE_PX, s)).grey());
            for (v, disc) in self.discs.iter().enumerate() {
                let refs = &self.reference[v];
                let vals = &row.values[v];
                for col in 0..lay.columns() {
                    let (x, y) = lay.cell(r as u32, v as u32, col);
                    fill(img, x + s * 2, y, cell_w - s * 4, cell_h, CELL);
                    let (dx, dy) = lay.disc(r as u32, v as u32, col);
                    match col {
                        0 => paint_disc(img, dx, dy, disc, CELL, |i| self.tone.map(refs[i])),
                        1 => paint_disc(img, dx, dy, disc, CELL, |i| self.tone.map(vals[i])),
                        2 => paint_disc(img, dx, dy, disc, CELL, |i| {
                            self.error.color(self.error.relative(refs[i], vals[i]))
                        }),
                        _ => {
                            let range = self.chroma.range().unwrap_or(1.0);
                            paint_disc(img, dx, dy, disc, CELL, |i| sequential(xy_distance(vals[i], refs[i]) / range));
                            let (cx, cy) = lay.cell(r as u32, v as u32, col);
                            let at = (cx + cell_w / 2, cy + cell_h + s * 4);
                            labels.push(Label::new(disc_figure(vals, refs), at.0, at.1, text_px(BODY, s)).centre());
                        }
                    }
                }
                // The figures are the whole domain's: print them once, under the first view.
                if v > 0 {
                    continue;
                }
                let (x0, y0) = lay.cell(r as u32, v as u32, 0);
                let (line1, line2) = (y0 + cell_h + s * 4, y0 + cell_h + s * 22);
                let x = x0 + s * 2;
                labels.push(Label::new(&row.under_err[0], x, line1, text_px(BODY, s)));
                let second = if row.under_lit.is_empty() {
                    row.under_err[1].clone()
                } else {
                    format!("{}; {}", row.under_err[1], row.under_lit)
                };
                labels.push(Label::new(second, x, line2, text_px(BODY, s)));
                labels.push(Label::new(self.saturation_line(row), x, y0 + cell_h + s * 40, text_px(BODY, s)));
            }
        }
    }
}

/// The share of a row's chroma pixels beyond R, per view, for the row's saturation line.
fn saturation(sheet: &Sheet, row: &SheetRow, range: f64) -> String {
    let shares: Vec<String> = sheet
        .views
        .iter()
        .zip(row.values.iter().zip(&sheet.reference))
        .map(|(view, (vals, refs))| {
            let n = vals.len().max(1);
            let beyond = vals.iter().zip(refs).filter(|(v, r)| xy_distance(**v, **r) > range).count();
            let name = view.caption.split(':').next().unwrap_or("disc");
            format!("{name} {}", percent(beyond as f64 / n as f64))
        })
        .collect();
    format!("; xy beyond {}: {}", sig(range, 2), shares.join(", "))
}
