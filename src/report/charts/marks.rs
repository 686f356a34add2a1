//! An encoder's mark on a chart: its colour and marker shape from the one style table
//! ([`crate::report::style`]), drawn filled (a value) or as an outline (an exact row at the
//! axis floor).

use super::draw::pe;
use crate::report::style::{EncoderStyle, Marker};
use anyhow::Result;
use plotters::coord::Shift;
use plotters::prelude::*;

/// The style's colour for plotters.
pub(super) fn rgb(s: &EncoderStyle) -> RGBColor {
    RGBColor(s.rgb[0], s.rgb[1], s.rgb[2])
}

/// The outline of `marker` of radius `r` about `at` (a closed polygon; the cross and plus are
/// drawn as strokes instead, [`draw_marker`]).
fn outline(marker: Marker, (x, y): (i32, i32), r: i32) -> Vec<(i32, i32)> {
    match marker {
        Marker::Square => vec![(x - r, y - r), (x + r, y - r), (x + r, y + r), (x - r, y + r)],
        Marker::TriangleUp => vec![(x, y - r - 1), (x + r + 1, y + r), (x - r - 1, y + r)],
        Marker::TriangleDown => vec![(x, y + r + 1), (x + r + 1, y - r), (x - r - 1, y - r)],
        Marker::Diamond => vec![(x, y - r - 1), (x + r + 1, y), (x, y + r + 1), (x - r - 1, y)],
        Marker::Star => (0..10)
            .map(|k| {
                let a = std::f64::consts::PI * (k as f64 / 5.0 - 0.5);
                let rr = if k % 2 == 0 { r as f64 + 1.5 } else { (r as f64 + 1.5) * 0.45 };
                (x + (rr * a.cos()).round() as i32, y + (rr * a.sin()).round() as i32)
            })
            .collect(),
        // A circle as a 16-gon (only for outlines; filled circles use plotters' own).
        Marker::Circle | Marker::Cross | Marker::Plus => (0..16)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 16.0;
                (x + (r as f64 * a.cos()).round() as i32, y + (r as f64 * a.sin()).round() as i32)
            })
            .collect(),
    }
}

/// Draws `style`'s marker of radius `r` centred at `at` (pixels of `area`): filled in the
/// style's colour with a white edge, or (`filled` false) as a 2 px outline in that colour.
pub(super) fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    at: (i32, i32),
    style: &EncoderStyle,
    r: i32,
    filled: bool,
) -> Result<()> {
    let c = rgb(style);
    let (x, y) = at;
    if matches!(style.marker, Marker::Cross | Marker::Plus) {
        let (a, b) = if style.marker == Marker::Cross {
            ([(x - r, y - r), (x + r, y + r)], [(x - r, y + r), (x + r, y - r)])
        } else {
            ([(x - r - 1, y), (x + r + 1, y)], [(x, y - r - 1), (x, y + r + 1)])
        };
        let w = if filled { 3 } else { 1 };
        for seg in [a, b] {
            area.draw(&PathElement::new(seg, c.stroke_width(w))).map_err(pe)?;
        }
        return Ok(());
    }
    if style.marker == Marker::Circle && filled {
        area.draw(&Circle::new(at, r as u32, c.filled())).map_err(pe)?;
        return area.draw(&Circle::new(at, r as u32, WHITE.stroke_width(1))).map_err(pe);
    }
    let shape = outline(style.marker, at, r);
    let mut closed = shape.clone();
    closed.push(shape[0]);
    if filled {
        area.draw(&Polygon::new(shape, c.filled())).map_err(pe)?;
        area.draw(&PathElement::new(closed, WHITE.stroke_width(1))).map_err(pe)
    } else {
        area.draw(&Polygon::new(shape, WHITE.filled())).map_err(pe)?;
        area.draw(&PathElement::new(closed, c.stroke_width(2))).map_err(pe)
    }
}
