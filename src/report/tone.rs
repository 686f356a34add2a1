//! Tone mapping and the error colour scale of the pictures.
//!
//! Every sphere on a sheet uses one [`Tone`]: exposure puts the reference's solid-angle mean
//! Rec.709 luminance (over the scored domain) at 0.5, then an extended-Reinhard curve per
//! channel whose white is the reference's largest exposed value (so the reference never clips
//! and brighter values saturate), then the sRGB transfer curve. Negative E/π shows black.
//!
//! The error sphere shows the signed relative error of luminance,
//! (Y − Y_ref) / max(Y_ref, 1% of the reference's mean Y), through a diverging map (blue:
//! darker than the reference, red: brighter) over ±R ([`ErrorScale`]); R is shared by the
//! sheet: the median over rows of rel_rmse (rmse / RMS of the reference), rounded up to a
//! 1-2-5 step ([`nice_ceil`]). Dark regions, where a small absolute error is a large relative
//! one, may saturate.

use super::csvfile::CsvTable;
use super::number::sig;
use crate::math::colour::luminance;
use crate::math::colour::Rgb;

/// The sRGB transfer curve (IEC 61966-2-1) of a linear value in [0, 1].
pub fn srgb_encode(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.0031308 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// One exposure and tone curve for every sphere of a sheet (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tone {
    /// Multiplier applied to E/π.
    pub exposure: f64,
    /// Extended-Reinhard white point in exposed units (≥ 1; 1 means a plain clip at 1).
    pub white: f64,
}

impl Tone {
    /// Exposure from the reference's mean luminance (→ 0.5); white from its largest channel.
    pub fn from_reference(mean_luminance: f64, max_value: f64) -> Self {
        let exposure = if mean_luminance > 0.0 && mean_luminance.is_finite() { 0.5 / mean_luminance } else { 1.0 };
        let white = (max_value * exposure).max(1.0);
        Tone { exposure, white: if white.is_finite() { white } else { 1.0 } }
    }

    /// One channel: exposure, x(1 + x/w²)/(1 + x), clip to [0, 1]. With w = 1 this is x.
    pub fn curve(&self, v: f64) -> f64 {
        let x = (v * self.exposure).max(0.0);
        if !x.is_finite() {
            return if v > 0.0 { 1.0 } else { 0.0 };
        }
        (x * (1.0 + x / (self.white * self.white)) / (1.0 + x)).min(1.0)
    }

    /// Display colour (sRGB, 8 bit) of an E/π value.
    pub fn map(&self, c: Rgb) -> [u8; 3] {
        [c.x, c.y, c.z].map(|v| (srgb_encode(self.curve(v)) * 255.0).round() as u8)
    }

    /// A one-line statement of the curve for sheet headers.
    pub fn describe(&self) -> String {
        format!(
            "exposure x{} (reference mean Y -> 0.5), Reinhard white {}, sRGB; E/π < 0 black",
            sig(self.exposure, 3),
            sig(self.white, 3)
        )
    }
}

/// The signed relative-error scale of a sheet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorScale {
    /// Luminance below which the denominator is held (1% of the reference's mean luminance).
    pub floor: f64,
    /// R: the error shown at the ends of the colour bar.
    pub range: f64,
    /// Which sheets share R.
    pub scope: ErrorScope,
}

/// Which sheets share an error scale's range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorScope {
    /// Every sheet of the experiment (the range from its table).
    Experiment,
    /// This sheet alone (no table to take it from).
    Sheet,
}

impl ErrorScale {
    /// (Y − Y_ref) / max(Y_ref, floor); 0 where both vanish.
    pub fn relative(&self, reference: Rgb, test: Rgb) -> f64 {
        let (yr, yt) = (luminance(reference), luminance(test));
        let den = yr.max(self.floor);
        if den > 0.0 && den.is_finite() {
            let r = (yt - yr) / den;
            if r.is_finite() {
                r
            } else {
                0.0
            }
        } else {
            0.0
        }
    }

    /// The colour of a relative error.
    pub fn color(&self, rel: f64) -> [u8; 3] {
        diverging(rel / self.range)
    }
}

/// ColorBrewer RdBu (9 classes), blue at −1, white at 0, red at +1; the luminance of the
/// colour falls monotonically with |v| on each side, so "further from white" reads as "larger
/// error" in colour and in grey.
const RDBU: [[u8; 3]; 9] = [
    [33, 102, 172],
    [67, 147, 195],
    [146, 197, 222],
    [209, 229, 240],
    [247, 247, 247],
    [253, 219, 199],
    [244, 165, 130],
    [214, 96, 77],
    [178, 24, 43],
];

/// The diverging colour map at v (clamped to [−1, 1]), linearly interpolated between classes.
pub fn diverging(v: f64) -> [u8; 3] {
    diverging_exact(v).map(|c| c.round() as u8)
}

/// [`diverging`] before rounding to 8 bits.
fn diverging_exact(v: f64) -> [f64; 3] {
    let v = if v.is_finite() { v.clamp(-1.0, 1.0) } else { 0.0 };
    let s = (v + 1.0) * 4.0;
    let i = (s.floor() as usize).min(7);
    let f = s - i as f64;
    let (a, b) = (RDBU[i], RDBU[i + 1]);
    [0, 1, 2].map(|k| a[k] as f64 + (b[k] as f64 - a[k] as f64) * f)
}

/// The smallest 1-2-5 step (0.1% … 500%) at or above x.
pub fn nice_ceil(x: f64) -> f64 {
    let steps = [1.0, 2.0, 5.0];
    for e in -3..=0 {
        for s in steps {
            let v = s * 10f64.powi(e);
            if x <= v * (1.0 + 1e-9) {
                return v;
            }
        }
    }
    5.0
}

/// The error range every sheet of an experiment shares: the median `rel_rmse` of the table's
/// rows (metric `exact` where the table has a `metric` column; every map and case), rounded up
/// to a 1-2-5 step; None when the table has no finite `rel_rmse`.
pub fn experiment_error_range(t: &CsvTable) -> Option<f64> {
    let rc = t.col("rel_rmse")?;
    let mc = t.col("metric");
    let mut rel: Vec<f64> = (0..t.rows.len())
        .filter(|&i| mc.is_none_or(|c| t.rows[i][c] == "exact"))
        .filter_map(|i| t.num(i, rc).ok().flatten())
        .filter(|v| v.is_finite())
        .collect();
    if rel.is_empty() {
        return None;
    }
    rel.sort_by(f64::total_cmp);
    Some(nice_ceil(rel[(rel.len() - 1) / 2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_map_is_monotone_and_signed() {
        let lum = |c: [f64; 3]| luminance(Rgb::from_array(c));
        let lum8 = |c: [u8; 3]| lum(c.map(f64::from));
        assert_eq!(diverging(0.0), [247, 247, 247]);
        let mut prev_pos = lum(diverging_exact(0.0));
        let mut prev_neg = prev_pos;
        for k in 1..=400 {
            let v = k as f64 / 400.0;
            let (p, n) = (diverging_exact(v), diverging_exact(-v));
            assert!(lum(p) < prev_pos && lum(n) < prev_neg, "luminance falls strictly with |v| at {v}");
            // After rounding to 8 bits, within half a level per channel.
            assert!((lum8(diverging(v)) - lum(p)).abs() <= 0.5 && (lum8(diverging(-v)) - lum(n)).abs() <= 0.5);
            let (p, n) = (diverging_exact(v), diverging_exact(-v));
            assert!(p[0] > p[2] && n[2] > n[0], "positive is red, negative blue at {v}");
            prev_pos = lum(diverging_exact(v));
            prev_neg = lum(diverging_exact(-v));
        }
        assert!(prev_pos < 100.0 && prev_neg < 100.0, "the ends are dark");
        assert_eq!(diverging(7.0), diverging(1.0));
        assert_eq!(diverging(f64::NAN), diverging(0.0));
    }

    #[test]
    fn tone_curve_and_error_steps() {
        let t = Tone::from_reference(2.0, 2.0);
        assert_eq!(t.exposure, 0.25);
        assert_eq!(t.white, 1.0);
        assert_eq!(t.curve(2.0), 0.5);
        assert_eq!(t.curve(-1.0), 0.0);
        let t = Tone::from_reference(1.0, 10.0);
        assert!((t.curve(10.0) - 1.0).abs() < 1e-12, "the reference's max maps to white");
        assert_eq!(nice_ceil(0.0), 0.001);
        assert_eq!(nice_ceil(0.03), 0.05);
        assert_eq!(nice_ceil(0.1), 0.1);
        assert_eq!(nice_ceil(40.0), 5.0);
    }
}
