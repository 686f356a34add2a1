//! Log axes: bounds around positive values, ticks (at least five labels: decades, 1-2-5 or
//! finer per decade, or linear 1-2-5 steps on an axis of less than a decade) and short tick
//! labels; a decade's label is never dropped, a minor one goes when labels would touch.

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

/// Tick label for log axes.
pub(super) fn tick(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let e = v.abs().log10();
    if (e - e.round()).abs() < 1e-9 && !(-3.0..=4.0).contains(&e.round()) {
        return format!("1e{}", e.round() as i32);
    }
    // The fewest significant digits (2 to 4) that give the value back: 0.052 and 0.0525 both
    // read as themselves.
    let s = (2..=4)
        .map(|d| sig(v, d))
        .find(|s| s.parse::<f64>().is_ok_and(|p| (p - v).abs() <= 1e-9 * v.abs()))
        .unwrap_or_else(|| sig(v, 4));
    trimmed(&s)
}

/// A number written with two significant digits, trailing zeros dropped ("2", "0.68",
/// "2e-12"): a value in a heatmap cell or a caption.
pub(super) fn short(v: f64) -> String {
    trimmed(&sig(v, 2))
}

/// `s` without trailing zeros after its decimal point, in the mantissa too ("5.0e7" is "5e7").
fn trimmed(s: &str) -> String {
    let trim = |m: &str| {
        if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            m.to_string()
        }
    };
    match s.split_once('e') {
        Some((m, e)) => format!("{}e{e}", trim(m)),
        None => trim(s),
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
/// 1-2-3-4-5-6-7-8-9, then with 1.2, 1.5 and 2.5 added, per decade that gives at least `min`
/// ticks inside the bounds; when none does (an axis of a fraction of a decade), evenly spaced
/// values of the largest 1-2-5 step that gives `min` ([`linear_ticks`]).
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
            return out;
        }
    }
    linear_ticks(lo, hi, min)
}

/// Multiples of the largest step 1, 2 or 5 × 10^k that puts at least `min` of them in
/// [`lo`, `hi`] (lo < hi), each rounded to its own decimal digits.
pub(super) fn linear_ticks(lo: f64, hi: f64, min: usize) -> Vec<f64> {
    let span = hi - lo;
    if !(span > 0.0) || !span.is_finite() {
        return vec![lo];
    }
    let mut e = span.log10().ceil() as i32;
    loop {
        for m in [5.0, 2.0, 1.0] {
            let step = m * 10f64.powi(e);
            let first = (lo / step).ceil() as i64;
            let last = (hi / step).floor() as i64;
            if last - first + 1 >= min as i64 || e < -300 {
                return (first..=last)
                    .map(|k| k as f64 * step)
                    .map(|v| format!("{v:.*e}", 6).parse::<f64>().unwrap_or(v))
                    .collect();
            }
        }
        e -= 1;
    }
}

/// Whether `v` is a power of ten (a decade's tick).
pub(super) fn is_decade(v: f64) -> bool {
    let e = v.abs().log10();
    v > 0.0 && (e - e.round()).abs() < 1e-9
}

/// Grid lines and labelled ticks at `ticks` along x (`vertical`: lines across the plot, labels
/// under it) or y (labels left of it), `at` giving a value's pixel. Decades' labels are placed
/// first and always; another label that would touch one already placed is left out (its grid
/// line stays).
pub(super) fn grid<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    plot: (i32, i32, i32, i32),
    ticks: &[f64],
    at: impl Fn(f64) -> i32,
    vertical: bool,
) -> Result<()> {
    let (x0, y0, x1, y1) = plot;
    let light = RGBColor(225, 225, 225);
    // Each label's extent along the axis, with a gap: 6 px between labels under x, 2 px on y.
    let extent = |v: f64| {
        let p = at(v);
        if vertical {
            let w = text_width(&tick(v), BODY, false) as i32;
            (p - w / 2 - 3, p + w / 2 + 3)
        } else {
            (p - LABEL_LINE / 2 - 1, p + LABEL_LINE / 2 + 1)
        }
    };
    let mut kept: Vec<(i32, i32)> = Vec::new();
    let mut show = vec![false; ticks.len()];
    for decades_first in [true, false] {
        for (k, &v) in ticks.iter().enumerate() {
            if is_decade(v) != decades_first {
                continue;
            }
            let (a, b) = extent(v);
            if decades_first || kept.iter().all(|&(c, d)| b <= c || a >= d) {
                kept.push((a, b));
                show[k] = true;
            }
        }
    }
    for (k, &v) in ticks.iter().enumerate() {
        let p = at(v);
        let (line, mark, pos, anchor) = if vertical {
            ([(p, y0), (p, y1)], [(p, y1), (p, y1 + 5)], (p, y1 + 8), Pos::new(HPos::Center, VPos::Top))
        } else {
            ([(x0, p), (x1, p)], [(x0 - 5, p), (x0, p)], (x0 - 8, p), Pos::new(HPos::Right, VPos::Center))
        };
        root.draw(&PathElement::new(line, light.stroke_width(1))).map_err(pe)?;
        root.draw(&PathElement::new(mark, BLACK.stroke_width(1))).map_err(pe)?;
        if show[k] {
            root.draw_text(&tick(v), &TextStyle::from((FONT, BODY)).pos(anchor), pos).map_err(pe)?;
        }
    }
    Ok(())
}
