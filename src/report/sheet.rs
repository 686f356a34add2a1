//! Comparison sheets (`sheet_<map>.png`): for one experiment on one map, a row per encoder
//! and, per view of the sphere of normals ([`View`]), three lit spheres: the reference, the
//! encoder and its signed relative error. All spheres of a sheet share one [`Tone`]; the error
//! sphere's colour scale is the sheet's [`ErrorScale`] (both in `tone.rs`). A sphere domain is
//! drawn front and top; a hemisphere domain as a disc looking down N.
//!
//! At scale N (`probelab report --scale N`, [`MAX_SCALE`] at most) every measure below is N
//! times larger: the sheet is laid out at scale 1 and each position and length multiplied by N,
//! the discs are evaluated at N·[`DISC`] pixels (every pixel at its own normal, not enlarged),
//! text is drawn at N times its even pixel size and the thumbnail is filtered at N·[`THUMB_W`].
//!
//! The rmse under each error sphere is the `exact` metric — solid-angle weighted over the
//! case's output domain at the experiment's resolution — read from the experiment's table, or
//! else scored here by the runner's one scoring step ([`score_fit`]) from the same
//! [`CaseData`] and fit the runner scores, so it equals the table's figure.

use super::canvas::{fill, paint_disc, CELL, PAPER};
use super::csvfile::CsvTable;
use super::number::{percent, sig};
use super::text::{draw_labels, even_px, fit_text, text_width, wrap, Label, BODY, HEADING, TITLE};
use super::tone::{diverging, experiment_error_range, nice_ceil, ErrorScale, ErrorScope, Tone};
use crate::encoders::encoder::Fitted;
use crate::envmap::EnvMap;
use crate::math::colour::luminance;
use crate::math::colour::Rgb;
use crate::pipeline::experiment::Experiment;
use crate::pipeline::runner::{cases, evaluate, score_fit, Case, CaseData, MapData};
use crate::reference::domain::Domain;
use crate::reference::metrics::{Metric, Scores};
use crate::reference::view::{Disc, View};
use anyhow::{ensure, Result};
use glam::DVec3;
use image::RgbImage;
use plotters::style::text_anchor::HPos;

/// A sphere's (disc's) diameter at scale 1, in pixels. Every measure below is in pixels at
/// scale 1.
pub const DISC: u32 = 96;
/// A sphere's cell width: the disc and 12 px.
pub const CELL_W: u32 = DISC + 12;
/// A sphere's cell height: the disc and 8 px.
pub const CELL_H: u32 = DISC + 8;
/// Two text lines under each row of spheres.
pub const ROW_H: u32 = CELL_H + 42;
/// The narrowest label column; wider when a name or storage note needs it ([`label_width`]).
pub const LABEL_W: u32 = 128;
/// Sizes of a row's name (bold) and storage note.
const NAME_PX: f64 = HEADING;
const NOTE_PX: f64 = BODY;
/// The margin around the sheet.
pub const MARGIN: u32 = 12;
/// The gap between two views' groups of three cells.
pub const VIEW_GAP: u32 = 16;
/// The most header lines drawn under the title (a line too wide for the sheet wraps).
pub const HEADER_LINES: u32 = 9;
/// The height of one header line.
pub const LINE_H: u32 = 18;
/// The map thumbnail's width (lat-long, so twice its height).
pub const THUMB_W: u32 = 256;
/// The map thumbnail's height.
pub const THUMB_H: u32 = 128;
/// Title, header lines, then the thumbnail with the colour bar beside it.
pub const HEADER_H: u32 = MARGIN + 26 + HEADER_LINES * LINE_H + 8 + THUMB_H + 22;
/// The view captions and column names above the rows.
pub const COLHEAD_H: u32 = 42;
/// The narrowest sheet: a narrower grid of cells is widened to this.
pub const MIN_W: u32 = 640;
/// The error colour bar's width.
pub const BAR_W: u32 = 256;
/// The error colour bar's height.
pub const BAR_H: u32 = 16;
/// The largest sheet scale (`--scale`): 8 draws a 96 px disc at 768 px.
pub const MAX_SCALE: u32 = 8;

/// The geometry of a comparison sheet: one row per encoder, three columns (reference, encoder,
/// relative error) per view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheetLayout {
    /// The rows of spheres: one per encoder.
    pub rows: u32,
    /// The views of the sphere of normals: 2 for the sphere (front, top), 1 for a hemisphere.
    pub views: u32,
    /// Width of the label column at scale 1 (names and storage notes in full).
    pub label_w: u32,
    /// Every measure is this many times its scale-1 value (1..=[`MAX_SCALE`]).
    pub scale: u32,
}

/// The label column's width: [`LABEL_W`], or the widest measured name (bold) or storage note
/// plus 14 px of gap when that is wider, so no name is shortened.
pub fn label_width<'a>(rows: impl IntoIterator<Item = (&'a str, &'a str)>) -> u32 {
    rows.into_iter()
        .map(|(name, note)| text_width(name, NAME_PX, true).max(text_width(note, NOTE_PX, false)) + 14)
        .fold(LABEL_W, u32::max)
}

impl SheetLayout {
    /// Width × height in pixels: the scale-1 size times the scale.
    pub fn size(&self) -> (u32, u32) {
        let grid_w = 2 * MARGIN + self.label_w + self.views * 3 * CELL_W + self.views.saturating_sub(1) * VIEW_GAP;
        let s = self.scale;
        (s * grid_w.max(MIN_W), s * (HEADER_H + COLHEAD_H + self.rows * ROW_H + MARGIN))
    }
    /// Top-left pixel of the cell (row, view, column 0..3).
    pub fn cell(&self, row: u32, view: u32, col: u32) -> (u32, u32) {
        let x = MARGIN + self.label_w + view * (3 * CELL_W + VIEW_GAP) + col * CELL_W;
        (self.scale * x, self.scale * (HEADER_H + COLHEAD_H + row * ROW_H))
    }
    /// Top-left pixel of the disc in the cell (row, view, column 0..3), [`DISC`]·scale across.
    pub fn disc(&self, row: u32, view: u32, col: u32) -> (u32, u32) {
        let (x, y) = self.cell(row, view, col);
        (x + self.scale * ((CELL_W - DISC) / 2), y + self.scale * ((CELL_H - DISC) / 2))
    }
    /// Top-left pixel of the colour bar.
    pub fn colour_bar(&self) -> (u32, u32) {
        (self.scale * (MARGIN + THUMB_W + 28), self.scale * (MARGIN + 26 + HEADER_LINES * LINE_H + 8 + 44))
    }
}

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
    /// One row per encoder, in the experiment's order.
    pub rows: Vec<SheetRow>,
}

/// A text size at sheet scale `s`: the scale-1 size rounded to even pixels ([`even_px`]),
/// times `s`, so it stays even (plotters keeps glyphs on the baseline only at even sizes).
fn text_px(size: f64, s: u32) -> f64 {
    even_px(size) * s as f64
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
    /// The sheet's geometry; the label column measured at scale 1 (so every measure of a sheet
    /// at scale N is exactly N times its scale-1 value).
    pub fn layout(&self) -> SheetLayout {
        let label_w = label_width(self.rows.iter().map(|r| (r.name.as_str(), r.note.as_str())));
        SheetLayout { rows: self.rows.len() as u32, views: self.views.len() as u32, label_w, scale: self.scale }
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
        let (margin, cell_w, cell_h) = (s * MARGIN, s * CELL_W, s * CELL_H);
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

        let head_y = s * HEADER_H;
        for (v, view) in self.views.iter().enumerate() {
            let (x, _) = lay.cell(0, v as u32, 0);
            labels.push(Label::new(&view.caption, x, head_y, text_px(BODY, s)).bold());
            for (c, name) in ["reference", "encoder", "rel. error"].iter().enumerate() {
                let cx = x + c as u32 * cell_w + cell_w / 2;
                labels.push(Label::new(*name, cx, head_y + s * 20, text_px(BODY, s)).centre().grey());
            }
        }
        for (r, row) in self.rows.iter().enumerate() {
            let (_, y) = lay.cell(r as u32, 0, 0);
            labels.push(Label::new(&row.name, margin, y + s * (CELL_H / 2 - 18), text_px(NAME_PX, s)).bold());
            labels.push(Label::new(&row.note, margin, y + s * (CELL_H / 2 + 2), text_px(NOTE_PX, s)).grey());
            for (v, disc) in self.discs.iter().enumerate() {
                let refs = &self.reference[v];
                let vals = &row.values[v];
                for col in 0..3u32 {
                    let (x, y) = lay.cell(r as u32, v as u32, col);
                    fill(&mut img, x + s * 2, y, cell_w - s * 4, cell_h, CELL);
                    let (dx, dy) = lay.disc(r as u32, v as u32, col);
                    match col {
                        0 => paint_disc(&mut img, dx, dy, disc, CELL, |i| self.tone.map(refs[i])),
                        1 => paint_disc(&mut img, dx, dy, disc, CELL, |i| self.tone.map(vals[i])),
                        _ => paint_disc(&mut img, dx, dy, disc, CELL, |i| {
                            self.error.color(self.error.relative(refs[i], vals[i]))
                        }),
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
            }
        }
        draw_labels(&mut img, &labels)?;
        Ok((img, labels))
    }
}

/// A lat-long thumbnail of a map (box-filtered to `w`×`w/2`), with its own exposure (mean
/// luminance → 0.5, Reinhard with white at the 99th-percentile texel).
pub fn latlong_thumbnail(map: &EnvMap, w: u32) -> RgbImage {
    let h = w / 2;
    let (mw, mh) = (map.width(), map.height());
    let box_of = |o: u32, n: u32, m: usize| {
        let a = (o as usize * m) / n as usize;
        let b = (((o as usize + 1) * m) / n as usize).max(a + 1).min(m);
        (a.min(m - 1), b)
    };
    let mut px = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        let (j0, j1) = box_of(y, h, mh);
        for x in 0..w {
            let (i0, i1) = box_of(x, w, mw);
            let mut acc = Rgb::ZERO;
            for j in j0..j1 {
                for i in i0..i1 {
                    let t = map.texel(i, j);
                    acc += Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64);
                }
            }
            px.push(acc / ((j1 - j0) * (i1 - i0)) as f64);
        }
    }
    let mut lum: Vec<f64> = px.iter().map(|&c| luminance(c)).collect();
    let mean = lum.iter().sum::<f64>() / lum.len() as f64;
    lum.sort_by(f64::total_cmp);
    let p99 = lum[((lum.len() - 1) as f64 * 0.99) as usize];
    let exposure = if mean > 0.0 { 0.5 / mean } else { 1.0 };
    let tone = Tone { exposure, white: (p99 * exposure).max(1.0) };
    RgbImage::from_fn(w, h, |x, y| image::Rgb(tone.map(px[(y * w + x) as usize])))
}

/// The case drawn for an experiment: the one whose surface normal is nearest +Y (the first
/// such), or the single sphere case.
pub fn representative_case(all: &[Case]) -> usize {
    let mut best = 0;
    let mut best_dot = f64::NEG_INFINITY;
    for (i, c) in all.iter().enumerate() {
        let d = c.normal.map(|n| n.dot(DVec3::Y)).unwrap_or(1.0);
        if d > best_dot + 1e-12 {
            best = i;
            best_dot = d;
        }
    }
    best
}

/// The figures printed under a row: the table's `exact` rmse, rel_rmse and neg_frac.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowFigures {
    /// The RMSE of E/π over the case's domain.
    pub rmse: f64,
    /// `rmse` divided by the RMS of the reference E/π (dimensionless).
    pub rel_rmse: f64,
    /// The weighted fraction of output normals where the encoder is negative in any channel.
    pub neg_frac: f64,
}

impl From<&Scores> for RowFigures {
    fn from(s: &Scores) -> Self {
        RowFigures { rmse: s.rmse, rel_rmse: s.rel_rmse, neg_frac: s.neg_frac }
    }
}

/// What a sheet drew: the case and each encoder's figures, and where they came from.
pub struct SheetScores {
    /// The case drawn: its domain label (`sphere`, `hemisphere:+y`).
    pub case_label: String,
    /// The case's effects label, as in the table's `effects` column.
    pub effects: String,
    /// Each encoder's name and figures, in the experiment's order.
    pub figures: Vec<(String, RowFigures)>,
    /// "table.csv" or "computed".
    pub source: &'static str,
}

/// The figures of every encoder for `case` on `map` from a results table (metric `exact`),
/// if the table has a row for each.
pub fn figures_from_table(t: &CsvTable, map: &str, case: &Case, names: &[String]) -> Option<Vec<RowFigures>> {
    let cols = t.require(&["map", "encoder", "domain", "effects", "metric", "rmse", "rel_rmse", "neg_frac"]).ok()?;
    let [mc, ec, dc, fc, xc, rc, lc, nc] = cols[..] else { return None };
    names
        .iter()
        .map(|name| {
            let i = (0..t.rows.len()).find(|&i| {
                let r = &t.rows[i];
                r[mc] == map
                    && r[ec] == *name
                    && r[dc] == case.domain_label
                    && r[fc] == case.effects_label
                    && r[xc] == "exact"
            })?;
            Some(RowFigures { rmse: t.num(i, rc).ok()??, rel_rmse: t.num(i, lc).ok()??, neg_frac: t.num(i, nc).ok()?? })
        })
        .collect()
}

/// The comparison sheet of an experiment on one map: its representative case, every encoder
/// of the experiment through the trait, fitted from the case's [`CaseData`] exactly as the
/// runner fits it. The figures under each row are the table's when `table` has them (the
/// runner's rows), else scored here by the runner's [`score_fit`] (the `exact` metric over the
/// case's output grid).
/// The reference on the discs is evaluated exactly at every pixel's normal. (Interpolating
/// it from the reference's fast lat-long path was tried: near the terminator of a small bright
/// source the bilinear error reached 2.7% of the local value at 256x128 and 0.66% at 512x256,
/// visible on the error spheres; so it is not done.)
/// At `scale` N the discs are [`DISC`]·N pixels across, each pixel's normal evaluated, and
/// the thumbnail is filtered at [`THUMB_W`]·N; the figures do not depend on the scale.
pub fn experiment_sheet(
    exp: &Experiment,
    map: &EnvMap,
    table: Option<&CsvTable>,
    scale: u32,
) -> Result<(Sheet, SheetScores)> {
    ensure!((1..=MAX_SCALE).contains(&scale), "sheet scale {scale}: must be 1 to {MAX_SCALE}");
    let data = MapData::new(map);
    let all = cases(exp);
    let ci = representative_case(&all);
    let case = &all[ci];
    let cd = CaseData::new(&data, case, exp.polar_nodes);
    let input = cd.fit_input();
    let fitted: Vec<Box<dyn Fitted>> = exp.encoders.iter().map(|e| e.encoder.fit(&input)).collect();
    let names: Vec<String> = exp.encoders.iter().map(|e| e.name.clone()).collect();

    let (figures, source) = match table.and_then(|t| figures_from_table(t, &map.name, case, &names)) {
        Some(f) => (f, "table.csv"),
        None => (computed_figures(exp, case, &cd, &fitted), "computed"),
    };

    let views = case_views(case);
    let discs: Vec<Disc> = views.iter().map(|v| Disc::new(v, (scale * DISC) as usize)).collect();
    let reference: Vec<Vec<Rgb>> = {
        let _s = crate::io::profile::span("report: reference (sheets)");
        discs.iter().map(|d| cd.reference_many(&d.normals)).collect()
    };
    let values: Vec<Vec<Vec<Rgb>>> = {
        let _s = crate::io::profile::span("report: encoder eval (sheets)");
        fitted.iter().map(|f| discs.iter().map(|d| evaluate(f.as_ref(), &d.normals)).collect()).collect()
    };
    let (tone, error) = sheet_scales(&reference, &figures, table.and_then(experiment_error_range));

    let rows: Vec<SheetRow> = exp
        .encoders
        .iter()
        .zip(values)
        .zip(&figures)
        .map(|((e, values), f)| sheet_row(e.name.clone(), e.encoder.storage(&input), values, f))
        .collect();

    let lines = header_lines(exp, case, all.len(), &cd.reference.describe(), source, &tone, &error);
    let sheet = Sheet {
        title: format!("{} - {}", exp.name, map.name),
        lines,
        thumbnail: Some(latlong_thumbnail(map, scale * THUMB_W)),
        thumbnail_caption: format!(
            "input map {}x{} (lat-long, +Y up, centre -Z; own exposure)",
            map.width(),
            map.height()
        ),
        views,
        discs,
        reference,
        scale,
        tone,
        error,
        rows,
    };
    let scores = SheetScores {
        case_label: case.domain_label.clone(),
        effects: case.effects_label.clone(),
        figures: names.into_iter().zip(figures).collect(),
        source,
    };
    Ok((sheet, scores))
}

/// Every encoder's figures scored here, as the runner scores them: the exact metric over the
/// case's domain at the experiment's resolution, through the runner's own step ([`score_fit`]).
fn computed_figures(exp: &Experiment, case: &Case, cd: &CaseData, fitted: &[Box<dyn Fitted>]) -> Vec<RowFigures> {
    let grid = case.domain.output_grid(exp.resolution);
    let ref_grid = cd.reference_on(&grid);
    exp.encoders
        .iter()
        .zip(fitted)
        .map(|(e, f)| RowFigures::from(&score_fit(e.encoder.as_ref(), f.as_ref(), &grid, &ref_grid, Metric::Exact)))
        .collect()
}

/// The views a case is drawn in: a hemisphere as a disc looking down its N (captioned with the
/// orientation of its domain label), the sphere front and top.
fn case_views(case: &Case) -> Vec<View> {
    match &case.domain {
        Domain::Hemisphere { normal } => {
            let label = case.domain_label.split(':').nth(1).unwrap_or("N").to_string();
            vec![View::down(*normal, &label)]
        }
        Domain::Sphere => vec![View::front(), View::top()],
    }
}

/// The sheet's tone (from the mean luminance and the brightest channel of the reference drawn)
/// and its error scale: the floor at 1% of that mean, the range the experiment's
/// (`experiment_range`, from its table) or else the median of this sheet's rows' finite
/// rel_rmse, rounded up to a 1-2-5 step.
fn sheet_scales(reference: &[Vec<Rgb>], figures: &[RowFigures], experiment_range: Option<f64>) -> (Tone, ErrorScale) {
    let drawn: Vec<Rgb> = reference.iter().flatten().copied().collect();
    let mean_lum = drawn.iter().map(|c| luminance(*c)).sum::<f64>() / drawn.len().max(1) as f64;
    let max_val = drawn.iter().map(|c| c.max_element()).fold(0.0, f64::max);
    let tone = Tone::from_reference(mean_lum, max_val);
    let floor = 0.01 * mean_lum.max(0.0);
    if let Some(range) = experiment_range {
        return (tone, ErrorScale { floor, range, scope: ErrorScope::Experiment });
    }
    let mut rel: Vec<f64> = figures.iter().map(|f| f.rel_rmse).filter(|v| v.is_finite()).collect();
    rel.sort_by(f64::total_cmp);
    let median = if rel.is_empty() { 0.0 } else { rel[(rel.len() - 1) / 2] };
    (tone, ErrorScale { floor, range: nice_ceil(median), scope: ErrorScope::Sheet })
}

/// An encoder's row: its name, storage note, values at the discs and the figures printed under
/// its spheres.
fn sheet_row(name: String, note: String, values: Vec<Vec<Rgb>>, f: &RowFigures) -> SheetRow {
    SheetRow {
        name,
        note,
        values,
        under_lit: if f.neg_frac > 0.0 { format!("negative on {}", percent(f.neg_frac)) } else { String::new() },
        under_err: [
            format!("RMSE {} E/π (exact, solid-angle)", sig(f.rmse, 3)),
            format!("relative RMSE {}", percent(f.rel_rmse)),
        ],
    }
}

/// The sheet's header lines: the description, the case drawn (of `n_cases`), the reference
/// (`reference`, its description), where the figures come from, the tone and the error scale.
fn header_lines(
    exp: &Experiment,
    case: &Case,
    n_cases: usize,
    reference: &str,
    source: &str,
    tone: &Tone,
    error: &ErrorScale,
) -> Vec<String> {
    let (res_w, res_h) = match case.domain {
        Domain::Sphere => exp.resolution,
        Domain::Hemisphere { .. } => (exp.resolution.0, exp.resolution.1 / 2),
    };
    let mut lines = vec![];
    if !exp.description.is_empty() {
        lines.push(exp.description.clone());
    }
    lines.push(format!(
        "case: {} (effects: {}){}",
        case.domain_label,
        case.effects_label,
        if n_cases > 1 {
            format!("; drawn: the case nearest N = +Y, 1 of {n_cases} in the table")
        } else {
            String::new()
        }
    ));
    lines.push(format!("E/π; reference: {reference}, at every pixel's normal"));
    lines.push(format!(
        "figures: exact metric, solid-angle weighted over {} at {}x{} ({})",
        if matches!(case.domain, Domain::Sphere) { "the sphere" } else { "the hemisphere about N" },
        res_w,
        res_h,
        if source == "table.csv" { "from table.csv" } else { "computed as the runner does" }
    ));
    lines.push(format!("every sphere: {}", tone.describe()));
    lines.push(match error.scope {
        ErrorScope::Experiment => format!(
            "error scale ±{}, the same on every sheet of this experiment: median rel_rmse of table.csv",
            percent(error.range)
        ),
        ErrorScope::Sheet => {
            format!(
                "error scale ±{}, this sheet's own (no table.csv): median rel_rmse of its rows",
                percent(error.range)
            )
        }
    });
    lines.push("(Y = Rec.709 luminance; the denominator is held at >= 1% of the reference's mean Y)".into());
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::experiment::ExperimentFile;
    use std::path::Path;

    fn experiment(toml: &str) -> Experiment {
        let f: ExperimentFile = toml::from_str(toml).unwrap();
        Experiment::from_file(f, "t").unwrap()
    }

    fn scene_map(id: &str, width: usize) -> EnvMap {
        crate::reference::scenes::generated().into_iter().find(|s| s.id == id).unwrap().map(width)
    }

    /// Independent sRGB of 0.5 (IEC 61966-2-1): 1.055 · 0.5^(1/2.4) − 0.055 = 0.73536 → 188.
    #[test]
    fn constant_map_reference_sphere_is_uniform() {
        let exp = experiment("maps = ['gen_constant']\nencoders = ['sh1']\nresolution = [32, 16]");
        let map = scene_map("gen_constant", 64);
        let (sheet, _) = experiment_sheet(&exp, &map, None, 1).unwrap();
        // The reference of a constant map of radiance 1 is E/π = 1 everywhere.
        let dev = sheet.reference.iter().flatten().map(|c| (*c - Rgb::ONE).abs().max_element()).fold(0.0, f64::max);
        assert!(dev < 1e-4, "reference deviates from 1 by {dev}");
        let img = sheet.draw().unwrap();
        let expected = (255.0 * (1.055 * 0.5f64.powf(1.0 / 2.4) - 0.055)).round() as u8;
        assert_eq!(expected, 188);
        let lay = sheet.layout();
        for v in 0..2 {
            let (x, y) = lay.cell(0, v, 0);
            let (dx, dy) = (x + (CELL_W - DISC) / 2, y + (CELL_H - DISC) / 2);
            let disc = &sheet.discs[v as usize];
            let mut full = 0;
            for py in 0..disc.d {
                for px in 0..disc.d {
                    let p = img.get_pixel(dx + px as u32, dy + py as u32).0;
                    let cov = disc.coverage[py * disc.d + px];
                    if cov == 1.0 {
                        assert_eq!(p, [expected; 3], "view {v} pixel ({px},{py})");
                        full += 1;
                    } else if cov == 0.0 {
                        assert_eq!(p, CELL, "outside the disc is the cell background");
                    }
                }
            }
            // A disc of diameter D covers about π/4 of its square.
            assert!((full as f64 / (DISC * DISC) as f64 - std::f64::consts::FRAC_PI_4).abs() < 0.03, "{full}");
        }
    }

    #[test]
    fn sheet_size_follows_rows_and_views() {
        let mk = |encoders: &str, hemi: bool| {
            let extra =
                if hemi { "domain = 'hemisphere'\norientations = ['up']\neffects = ['hemisphere']\n" } else { "" };
            let exp = experiment(&format!("maps = ['m']\nencoders = [{encoders}]\nresolution = [16, 8]\n{extra}"));
            let map = scene_map("gen_sun_sky", 32);
            experiment_sheet(&exp, &map, None, 1).unwrap().0.draw().unwrap().dimensions()
        };
        // Expected sizes from the published measures, derived here by hand.
        let h = |rows: u32| HEADER_H + COLHEAD_H + rows * ROW_H + MARGIN;
        let w2 = 2 * MARGIN + LABEL_W + 6 * CELL_W + VIEW_GAP;
        assert_eq!(mk("'sh1'", false), (w2, h(1)));
        assert_eq!(mk("'sh0','sh1','sh2'", false), (w2, h(3)));
        let w1 = (2 * MARGIN + LABEL_W + 3 * CELL_W).max(MIN_W);
        assert_eq!(mk("'sh0','sh2'", true), (w1, h(2)));
        assert_eq!(h(3) - h(1), 2 * ROW_H);
    }

    /// Long encoder names are printed in full: the label column grows to the widest name
    /// (measured), and every label of the row column ends before the first sphere.
    #[test]
    fn long_names_widen_the_label_column() {
        let exp = experiment(
            "maps = ['m']\nencoders = ['sh1', { kind = 'sh2', name = 'sh2_with_a_very_long_descriptive_name' }]\n\
             resolution = [16, 8]",
        );
        let (sheet, _) = experiment_sheet(&exp, &scene_map("gen_sun_sky", 32), None, 1).unwrap();
        let lay = sheet.layout();
        let name = "sh2_with_a_very_long_descriptive_name";
        let want = text_width(name, NAME_PX, true) + 14;
        assert!(want > LABEL_W, "the test name must be wider than the default column");
        assert_eq!(lay.label_w, want);
        let (w, _) = lay.size();
        assert_eq!(w, 2 * MARGIN + want + 6 * CELL_W + VIEW_GAP);
        // The name ends at least 14 px before the first cell.
        assert!(MARGIN + text_width(name, NAME_PX, true) + 14 <= lay.cell(0, 0, 0).0);
        assert_eq!(label_width([("sh1", "12 scalars")]), LABEL_W);
    }

    #[test]
    fn drawn_colour_bar_matches_the_map_left_to_right() {
        let exp = experiment("maps = ['m']\nencoders = ['sh1']\nresolution = [16, 8]");
        let (sheet, _) = experiment_sheet(&exp, &scene_map("gen_two_lights", 32), None, 1).unwrap();
        let img = sheet.draw().unwrap();
        let (bx, by) = sheet.layout().colour_bar();
        for x in 0..BAR_W {
            let v = ((x as f64 + 0.5) / BAR_W as f64) * 2.0 - 1.0;
            assert_eq!(img.get_pixel(bx + x, by + BAR_H / 2).0, diverging(v), "bar pixel {x}");
        }
        assert!(img.get_pixel(bx, by + 2).0[2] > 150, "left end blue (darker than the reference)");
        assert!(img.get_pixel(bx + BAR_W - 1, by + 2).0[0] > 150, "right end red (brighter)");
    }

    /// On the hemisphere light (radiance 1 above the horizon), the constant encoder sh0 is
    /// 0.5 everywhere while the reference is 1 at the top and 0 at the bottom: the lower half
    /// of its front sphere must be brighter than the reference's and its error red (brighter),
    /// the top blue (darker).
    #[test]
    fn over_brightening_is_brighter_and_red() {
        let exp = experiment("maps = ['m']\nencoders = ['sh0']\nresolution = [32, 16]");
        let (sheet, _) = experiment_sheet(&exp, &scene_map("gen_hemisphere", 64), None, 1).unwrap();
        let img = sheet.draw().unwrap();
        let lay = sheet.layout();
        let at = |col: u32, fy: f64| {
            let (x, y) = lay.cell(0, 0, col);
            let (dx, dy) = (x + (CELL_W - DISC) / 2, y + (CELL_H - DISC) / 2);
            img.get_pixel(dx + DISC / 2, dy + (fy * DISC as f64) as u32).0.map(i32::from)
        };
        let (ref_low, enc_low, err_low) = (at(0, 0.85), at(1, 0.85), at(2, 0.85));
        assert!(enc_low[1] > ref_low[1] + 40, "sh0 brighter near the bottom: {enc_low:?} vs {ref_low:?}");
        assert!(err_low[0] > err_low[2] + 60, "bottom error reads 'brighter' (red): {err_low:?}");
        let (ref_top, enc_top, err_top) = (at(0, 0.15), at(1, 0.15), at(2, 0.15));
        assert!(enc_top[1] + 20 < ref_top[1], "sh0 darker near the top: {enc_top:?} vs {ref_top:?}");
        assert!(err_top[2] > err_top[0] + 40, "top error reads 'darker' (blue): {err_top:?}");
    }

    #[test]
    fn sheet_figures_equal_the_runner_table() {
        let exp = experiment(
            "maps = ['m']\nencoders = ['sh0', 'sh1', 'sh2']\nresolution = [32, 16]\ndomain = 'hemisphere'\n\
             orientations = ['axes6']\neffects = ['hemisphere']",
        );
        let map = scene_map("gen_sky_sun", 64);
        let rows = crate::pipeline::runner::run_map(&exp, &map);
        let (sheet, s) = experiment_sheet(&exp, &map, None, 1).unwrap();
        assert_eq!((s.case_label.as_str(), s.source), ("hemisphere:+y", "computed"));
        assert_eq!(sheet.views.len(), 1);
        for (name, f) in &s.figures {
            let row = rows.iter().find(|r| &r.encoder == name && r.domain == s.case_label).unwrap();
            assert_eq!(RowFigures::from(&row.scores), *f, "{name}");
        }
        // Read back from the table's CSV: the same figures to the CSV's round-trip precision.
        let t = CsvTable::parse(Path::new("table.csv"), &crate::pipeline::table::to_csv(&rows).unwrap()).unwrap();
        let (sheet2, s2) = experiment_sheet(&exp, &map, Some(&t), 1).unwrap();
        assert_eq!(s2.source, "table.csv");
        assert_eq!(s2.figures, s.figures);
        assert_eq!(sheet2.rows[2].under_err, sheet.rows[2].under_err);
    }

    /// The same sheet at scales 1 and `s`.
    fn at_scales(toml: &str, map: &str, s: u32) -> (Sheet, Sheet) {
        let exp = experiment(toml);
        let map = scene_map(map, 32);
        (experiment_sheet(&exp, &map, None, 1).unwrap().0, experiment_sheet(&exp, &map, None, s).unwrap().0)
    }

    /// At scale 2 the sheet is exactly twice as wide and tall, from the layout and in the drawn
    /// image, with the hand-derived scale-1 measures doubled; the names still end before the
    /// first sphere at their doubled text size.
    #[test]
    fn scale_two_doubles_every_measure() {
        let long = "sh2_with_a_very_long_descriptive_name";
        let sphere =
            format!("maps = ['m']\nencoders = ['sh1', {{ kind = 'sh2', name = '{long}' }}]\nresolution = [16, 8]");
        let hemi = "maps = ['m']\nencoders = ['sh0','sh2']\nresolution = [16, 8]\ndomain = 'hemisphere'\n\
                    orientations = ['up']\neffects = ['hemisphere']";
        let h = |rows: u32| HEADER_H + COLHEAD_H + rows * ROW_H + MARGIN;
        let label = text_width(long, NAME_PX, true) + 14;
        for (toml, want1) in [
            (sphere.as_str(), (2 * MARGIN + label + 6 * CELL_W + VIEW_GAP, h(2))),
            (hemi, ((2 * MARGIN + LABEL_W + 3 * CELL_W).max(MIN_W), h(2))),
        ] {
            let (one, two) = at_scales(toml, "gen_sun_sky", 2);
            let (l1, l2) = (one.layout(), two.layout());
            assert_eq!(l1.size(), want1);
            assert_eq!(l2.size(), (2 * want1.0, 2 * want1.1));
            assert_eq!(one.draw().unwrap().dimensions(), want1);
            assert_eq!(two.draw().unwrap().dimensions(), (2 * want1.0, 2 * want1.1));
            for (r, v, c) in [(0, 0, 0), (1, 0, 2), (1, l1.views - 1, 1)] {
                let ((x1, y1), (x2, y2)) = (l1.cell(r, v, c), l2.cell(r, v, c));
                assert_eq!((x2, y2), (2 * x1, 2 * y1));
                let ((dx1, dy1), (dx2, dy2)) = (l1.disc(r, v, c), l2.disc(r, v, c));
                assert_eq!((dx2, dy2), (2 * dx1, 2 * dy1));
            }
            assert_eq!(l2.colour_bar(), (2 * l1.colour_bar().0, 2 * l1.colour_bar().1));
            assert!(two.discs.iter().all(|d| d.d == 2 * DISC as usize));
            assert_eq!(two.thumbnail.as_ref().unwrap().dimensions(), (2 * THUMB_W, 2 * THUMB_H));
            for row in &two.rows {
                let end = 2 * MARGIN + text_width(&row.name, 2.0 * NAME_PX, true);
                assert!(end < l2.cell(0, 0, 0).0, "{} ends at {end}", row.name);
            }
        }
        // The text sizes stay even at every scale.
        for s in 1..=MAX_SCALE {
            for size in [NAME_PX, NOTE_PX, 17.0, 11.5, 11.0, 10.0] {
                assert_eq!(text_px(size, s) % 2.0, 0.0, "size {size} at scale {s}");
            }
        }
    }

    /// The scale-2 discs are evaluated at 192 px, not enlarged from 96: averaging each 2×2
    /// block of a scale-2 lit disc (reference, encoder: smooth in the normal) gives the
    /// scale-1 disc to within a few sRGB levels — measured means 0.07 to 0.27, worst 1.5 to
    /// 11.5 levels (at sh2's clamp to black), where the front reference disc placed half a
    /// scale-1 pixel off gives a mean of 0.69, worst 44 — yet many blocks are not uniform, as a
    /// nearest-neighbour enlargement's all would be. The error disc (saturating scale, sharp
    /// at the sun) is checked only for that. The colour bar is coloured at each of its 2·BAR_W
    /// columns.
    #[test]
    fn scale_two_discs_are_rendered_at_twice_the_pixels() {
        let (one, two) = at_scales("maps = ['m']\nencoders = ['sh2']\nresolution = [16, 8]", "gen_sun_sky", 2);
        let (i1, i2) = (one.draw().unwrap(), two.draw().unwrap());
        let (l1, l2) = (one.layout(), two.layout());
        for v in 0..2u32 {
            for col in 0..3u32 {
                let ((x1, y1), (x2, y2)) = (l1.disc(0, v, col), l2.disc(0, v, col));
                let (d1, d2) = (&one.discs[v as usize], &two.discs[v as usize]);
                let (mut n, mut sum, mut worst, mut varied) = (0u32, 0.0, 0.0f64, 0u32);
                for py in 0..DISC as usize {
                    for px in 0..DISC as usize {
                        let sub = [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(a, b)| (2 * px + a, 2 * py + b));
                        let inside = d1.coverage[py * d1.d + px] == 1.0
                            && sub.iter().all(|&(qx, qy)| d2.coverage[qy * d2.d + qx] == 1.0);
                        if !inside {
                            continue;
                        }
                        let p1 = i1.get_pixel(x1 + px as u32, y1 + py as u32).0;
                        let q = sub.map(|(qx, qy)| i2.get_pixel(x2 + qx as u32, y2 + qy as u32).0);
                        if q.iter().any(|c| *c != q[0]) {
                            varied += 1;
                        }
                        for ch in 0..3 {
                            let mean = q.iter().map(|c| c[ch] as f64).sum::<f64>() / 4.0;
                            let e = (mean - p1[ch] as f64).abs();
                            sum += e;
                            worst = worst.max(e);
                        }
                        n += 1;
                    }
                }
                let mean = sum / (3 * n) as f64;
                let what = format!("view {v} col {col}: {n} blocks, mean {mean:.3}, worst {worst:.2}, varied {varied}");
                assert!(n as f64 > 0.7 * (DISC * DISC) as f64, "{what}");
                if col < 2 {
                    assert!(mean < 0.4 && worst <= 16.0, "{what}");
                    assert!(varied as f64 > 0.2 * n as f64, "{what}");
                } else {
                    assert!(varied as f64 > 0.05 * n as f64, "{what}");
                }
            }
        }
        let (bx, by) = l2.colour_bar();
        for x in 0..2 * BAR_W {
            let v = ((x as f64 + 0.5) / (2 * BAR_W) as f64) * 2.0 - 1.0;
            assert_eq!(i2.get_pixel(bx + x, by + BAR_H).0, diverging(v), "bar pixel {x}");
        }
    }

    /// Every label of a sheet — sphere and hemisphere, a long name, figures under each row —
    /// is inside the canvas, overlaps no other label and is drawn in full (no header line
    /// shortened), at scales 1 and 2.
    #[test]
    fn sheet_labels_stay_apart_and_on_the_canvas() {
        let long = "sh2_with_a_very_long_descriptive_name";
        let sphere = format!(
            "maps = ['m']\nencoders = ['sh0', 'sh1', {{ kind = 'sh2', name = '{long}' }}]\nresolution = [16, 8]"
        );
        let hemi = "maps = ['m']\nencoders = ['sh0','sh2','zh3_hallucinate']\nresolution = [16, 8]\n\
                    domain = 'hemisphere'\norientations = ['up']\neffects = ['hemisphere']";
        for toml in [sphere.as_str(), hemi] {
            for s in [1, 2] {
                let exp = experiment(toml);
                let (sheet, _) = experiment_sheet(&exp, &scene_map("gen_sun_sky", 32), None, s).unwrap();
                let (img, labels) = sheet.draw_with_labels().unwrap();
                let (w, h) = (img.width() as i32, img.height() as i32);
                let boxes: Vec<_> = labels.iter().map(|l| (l.text.clone(), l.bounds())).collect();
                for (i, (t, b)) in boxes.iter().enumerate() {
                    assert!(!t.ends_with("..."), "shortened: {t}");
                    assert!(b.0 >= 0 && b.1 >= 0 && b.2 <= w && b.3 <= h, "'{t}' {b:?} leaves the {w}x{h} sheet");
                    for (u, c) in &boxes[i + 1..] {
                        let overlap = b.0 < c.2 && c.0 < b.2 && b.1 < c.3 && c.1 < b.3;
                        assert!(!overlap, "'{t}' {b:?} overlaps '{u}' {c:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn scales_outside_one_to_eight_are_refused() {
        let exp = experiment("maps = ['m']\nencoders = ['sh1']\nresolution = [16, 8]");
        let map = scene_map("gen_constant", 16);
        for s in [0, MAX_SCALE + 1] {
            let e = experiment_sheet(&exp, &map, None, s).err().expect("refused").to_string();
            assert!(e.contains(&format!("sheet scale {s}")) && e.contains("1 to 8"), "{e}");
        }
        // A sheet whose discs do not match its scale is refused, not drawn misplaced.
        let (mut sheet, _) = experiment_sheet(&exp, &map, None, 1).unwrap();
        sheet.scale = 2;
        assert!(sheet.draw().unwrap_err().to_string().contains("96 px across, not 192"));
    }
}
