//! Log axes: decade bounds around positive values and short tick labels.

use super::super::number::sig;
use super::super::text::{text_width, BODY, FONT};
use super::draw::pe;
use anyhow::Result;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The height a tick label takes along a vertical axis, px.
const LABEL_LINE: i32 = 15;

/// The widest span a log axis is given: tables hold numbers within ±1e30
/// (`pipeline::table_cells`); a wider axis once made plotters' log coordinates hang.
const DRAWABLE: (f64, f64) = (1e-30, 1e30);

/// The smallest and largest finite positive values, if there is one, each clipped to
/// [`DRAWABLE`].
fn positive_span(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for v in values.filter(|v| *v > 0.0 && v.is_finite()).map(|v| v.clamp(DRAWABLE.0, DRAWABLE.1)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (hi > 0.0).then_some((lo, hi))
}

/// Decade bounds around positive values (at least one decade).
pub(super) fn decades(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = positive_span(values)?;
    let lo = 10f64.powf(lo.log10().floor());
    let mut hi = 10f64.powf(hi.log10().ceil());
    if hi <= lo {
        hi = lo * 10.0;
    }
    Some((lo, hi))
}

/// Tick label for log axes.
pub(super) fn tick(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let e = v.abs().log10();
    if (e - e.round()).abs() < 1e-9 && !(-3.0..=4.0).contains(&e.round()) {
        return format!("1e{}", e.round() as i32);
    }
    let s = sig(v, 2);
    let trim = |m: &str| {
        if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            m.to_string()
        }
    };
    match s.split_once('e') {
        // "5.0e7" reads "5e7".
        Some((m, e)) => format!("{}e{e}", trim(m)),
        None => trim(&s),
    }
}

/// Bounds of a log axis fitted to positive values: the data's span widened by 8% of its
/// decades on each side (at least 0.06 decade), so that no point sits on the frame.
pub(super) fn fitted(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = positive_span(values)?;
    let pad = ((hi / lo).log10() * 0.08).max(0.06);
    Some((lo / 10f64.powf(pad), hi * 10f64.powf(pad)))
}

/// Tick values of a log axis from `lo` to `hi`: the sparsest of the steps 1, then 1-2-5, then
/// 1-2-3-4-5-6-7-8-9, then with 1.2, 1.5 and 2.5 added, per decade that gives at least `min` ticks inside the bounds (the last
/// when none does).
pub(super) fn log_ticks(lo: f64, hi: f64, min: usize) -> Vec<f64> {
    let sets: [&[f64]; 4] = [
        &[1.0],
        &[1.0, 2.0, 5.0],
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
        &[1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
    ];
    let mut out = Vec::new();
    for set in sets {
        out.clear();
        let (e0, e1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
        for e in e0..=e1 {
            for m in set {
                let v = m * 10f64.powi(e);
                // Rounded to its own decimal digits, so that 0.3 is 0.3 and not 0.30000000000000004.
                let v = format!("{v:e}").parse::<f64>().unwrap_or(v);
                if v >= lo * (1.0 - 1e-12) && v <= hi * (1.0 + 1e-12) {
                    out.push(v);
                }
            }
        }
        if out.len() >= min {
            break;
        }
    }
    out
}

/// Grid lines and labelled ticks at `ticks` along x (`vertical`: lines across the plot, labels
/// under it) or y (labels left of it), `at` giving a value's pixel; a label that would touch
/// the one before it is left out (its grid line stays).
pub(super) fn grid<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    plot: (i32, i32, i32, i32),
    ticks: &[f64],
    at: impl Fn(f64) -> i32,
    vertical: bool,
) -> Result<()> {
    let (x0, y0, x1, y1) = plot;
    let light = RGBColor(225, 225, 225);
    let mut last: Option<i32> = None;
    for &v in ticks {
        let p = at(v);
        let label = tick(v);
        let (line, mark, pos, anchor) = if vertical {
            ([(p, y0), (p, y1)], [(p, y1), (p, y1 + 5)], (p, y1 + 8), Pos::new(HPos::Center, VPos::Top))
        } else {
            ([(x0, p), (x1, p)], [(x0 - 5, p), (x0, p)], (x0 - 8, p), Pos::new(HPos::Right, VPos::Center))
        };
        root.draw(&PathElement::new(line, light.stroke_width(1))).map_err(pe)?;
        root.draw(&PathElement::new(mark, BLACK.stroke_width(1))).map_err(pe)?;
        let w = text_width(&label, BODY, false) as i32;
        // The label's extent along the axis, and whether it clears the previous one by 6 px.
        let (from, to) = if vertical { (p - w / 2, p + w / 2) } else { (p - LABEL_LINE / 2, p + LABEL_LINE / 2) };
        let clear = match last {
            Some(l) if vertical => from >= l + 6,
            Some(l) => to <= l - 2,
            None => true,
        };
        if clear {
            root.draw_text(&label, &TextStyle::from((FONT, BODY)).pos(anchor), pos).map_err(pe)?;
            last = Some(if vertical { to } else { from });
        }
    }
    Ok(())
}
