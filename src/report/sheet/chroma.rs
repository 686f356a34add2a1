//! The chroma discs of a comparison sheet: per view, a fourth disc in each encoding's row
//! showing the per-pixel CIE 1931 xy distance from the encoding to the reference
//! ([`xy_distance`], the distance claim Z2 weighs), through a sequential colour map from 0
//! (white) to R (dark green), with its own colour bar.
//!
//! Whether they are drawn is computed ([`CHROMA_FLOOR`]): where no encoding's xy distance
//! exceeds the floor on any lit pixel (reference luminance at or above the error scale's floor,
//! 1% of the reference's mean), the encodings do not differ in colour, the discs are left out
//! and the sheet says why. R is chosen as the error scale's range is: per row, the
//! [`SCALE_PERCENTILE`](crate::report::tone::SCALE_PERCENTILE) of the xy distance over its lit
//! pixels; the median over the rows of every sheet of the experiment, rounded up to 1-2-5
//! ([`range_of`](super::super::tone::range_of)). Under each chroma disc: the RMS xy distance over the disc's pixels, each
//! weighted by the reference's luminance Y ([`xy_error`], weight 1 per pixel); each row
//! states the share of its chroma pixels beyond R.

use super::super::canvas::fill;
use super::super::number::sig;
use super::super::text::{wrap, Label, BODY};
use super::super::tone::{ramp, ErrorScope};
use super::layout::text_px;
use super::layout::{BAR_H, BAR_W};
use crate::math::colour::{xy_error, Rgb};
use image::RgbImage;
use plotters::style::text_anchor::HPos;

/// The xy distance below which two chromaticities are taken as one: MacAdam's ellipses (the
/// just-noticeable differences of chromaticity) have semi-axes of 0.001 to 0.01 in xy, so a
/// smaller distance is invisible.
pub const CHROMA_FLOOR: f64 = 0.001;

/// The chroma discs of a sheet: drawn on a scale, or not drawn and why.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Chroma {
    /// Drawn: xy distances 0..`range` coloured, beyond saturated; `scope` says which sheets
    /// share the range.
    Drawn { range: f64, scope: ErrorScope },
    /// Not drawn: no encoding exceeds [`CHROMA_FLOOR`] on a lit pixel; `largest` is the largest
    /// distance found there.
    NotDrawn { largest: f64 },
}

impl Chroma {
    /// The range when drawn.
    pub fn range(&self) -> Option<f64> {
        match self {
            Chroma::Drawn { range, .. } => Some(*range),
            Chroma::NotDrawn { .. } => None,
        }
    }
}

/// ColorBrewer Greens (9 classes), white at 0 to dark green at 1; the luminance falls
/// monotonically, so "darker" reads as "larger distance" in colour and in grey, and no colour
/// of it is one of the diverging error map's.
const GREENS: [[u8; 3]; 9] = [
    [247, 252, 245],
    [229, 245, 224],
    [199, 233, 192],
    [161, 217, 155],
    [116, 196, 118],
    [65, 171, 93],
    [35, 139, 69],
    [0, 109, 44],
    [0, 68, 27],
];

/// The sequential colour map at v (clamped to [0, 1]), linearly interpolated between classes.
pub fn sequential(v: f64) -> [u8; 3] {
    ramp(&GREENS, v).map(|c| c.round() as u8)
}

/// The RMS xy distance over a disc's pixels, weighted by the reference's luminance Y.
pub fn disc_figure(vals: &[Rgb], refs: &[Rgb]) -> String {
    format!("xy RMS {}", sig(xy_error(vals, refs, &vec![1.0; vals.len()]), 2))
}

/// Draws the chroma colour bar at (x0, y0) — its title, meaning, ticks 0, R/2, R and how R was
/// chosen, wrapped to `span` pixels — or, when not drawn, says why there; sheet scale `s`.
pub fn chroma_bar(img: &mut RgbImage, labels: &mut Vec<Label>, (x0, y0): (u32, u32), span: u32, c: &Chroma, s: u32) {
    let px = text_px(BODY, s);
    let note = |labels: &mut Vec<Label>, x: u32, y: u32, text: &str| {
        for (i, line) in wrap(text, span, px).into_iter().enumerate() {
            labels.push(Label::new(line, x, y + i as u32 * s * 18, px).grey());
        }
    };
    let Chroma::Drawn { range, scope } = *c else {
        let largest = if let Chroma::NotDrawn { largest } = c { *largest } else { 0.0 };
        let why = format!(
            "chroma error (CIE 1931 xy distance to the reference) not drawn: no encoding's exceeds {CHROMA_FLOOR} on a \
             lit pixel (largest {})",
            sig(largest, 2)
        );
        return note(labels, x0, y0 - s * 40, &why);
    };
    let (bar_w, bar_h) = (s * BAR_W, s * BAR_H);
    for x in 0..bar_w {
        fill(img, x0 + x, y0, 1, bar_h, sequential((x as f64 + 0.5) / bar_w as f64));
    }
    labels.push(Label::new("chroma error: CIE 1931 xy distance", x0, y0 - s * 40, px).bold());
    labels.push(Label::new("to the reference (Rec.709, D65, as displayed)", x0, y0 - s * 21, px));
    for (frac, text) in
        [(0.0, "0".to_string()), (0.5, sig(range / 2.0, 2)), (1.0, format!("{} (saturates)", sig(range, 2)))]
    {
        let x = x0 + (frac * bar_w as f64) as u32;
        fill(img, x.min(x0 + bar_w - s), y0 + bar_h, s, s * 4, [0, 0, 0]);
        let l = Label::new(text, x, y0 + bar_h + s * 5, px);
        labels.push(if frac == 0.0 {
            l
        } else if frac == 1.0 {
            Label { anchor: HPos::Right, ..l }
        } else {
            l.centre()
        });
    }
    let whose = match scope {
        ErrorScope::Experiment => "the experiment's scale",
        ErrorScope::Sheet => "this sheet's scale",
    };
    let how = format!(
        "{whose}: median of the rows' 95th percentiles on lit pixels (Y_ref >= 1% of its mean) over \
         the rows above {CHROMA_FLOOR}, up to 1-2-5; drawn as an encoding exceeds {CHROMA_FLOOR} there"
    );
    note(labels, x0, y0 + bar_h + s * 24, &how);
}
