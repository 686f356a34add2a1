//! Log axes: decade bounds around positive values and short tick labels.

use super::super::number::sig;

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
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
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
