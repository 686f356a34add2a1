//! Tone mapping and the error colour scale of the pictures.
//!
//! Every sphere on a sheet uses one [`Tone`]: exposure puts the reference's solid-angle mean
//! Rec.709 luminance (over the scored domain) at 0.5, then an extended-Reinhard curve per
//! channel whose white is the reference's largest exposed value (so the reference never clips
//! and brighter values saturate), then the sRGB transfer curve. Negative E/π shows black.
//!
//! The error sphere shows the signed relative error of luminance,
//! (Y − Y_ref) / max(Y_ref, 1% of the reference's mean Y), through a diverging map (blue:
//! darker than the reference, red: brighter) over ±R ([`ErrorScale`]). R is shared by every
//! sheet of an experiment: the [`SCALE_PERCENTILE`] of |relative error| over the pixels of
//! an experiment's error spheres, taken per row (encoder) and then the median over the rows
//! of all its sheets, rounded up to a 1-2-5 step ([`range_of`], [`nice_ceil`]); so a typical
//! row saturates on about one pixel in twenty, a worse one on more, and each error sphere
//! states the share of its own pixels beyond ±R ([`ErrorScale::saturated`]).

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

    /// The share of relative errors beyond ±range, where the colour saturates (0 for none).
    pub fn saturated(&self, rel: impl IntoIterator<Item = f64>) -> f64 {
        let (mut n, mut beyond) = (0usize, 0usize);
        for r in rel {
            n += 1;
            beyond += (r.abs() > self.range) as usize;
        }
        if n == 0 {
            0.0
        } else {
            beyond as f64 / n as f64
        }
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
    ramp(&RDBU, (v + 1.0) * 0.5)
}

/// A 9-class colour table at t in [0, 1] (clamped; a value not finite reads 0), linearly
/// interpolated between its classes, before rounding to 8 bits: the one ramp behind the
/// diverging error map and the sheets' sequential chroma map.
pub fn ramp(classes: &[[u8; 3]; 9], t: f64) -> [f64; 3] {
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let s = t * 8.0;
    let i = (s.floor() as usize).min(7);
    let f = s - i as f64;
    let (a, b) = (classes[i], classes[i + 1]);
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

/// The percentile of |relative error| over an error sphere's pixels that the error range is
/// taken from: the error is shown, not saturated, on 95% of a typical row's pixels.
pub const SCALE_PERCENTILE: f64 = 0.95;

/// The [`SCALE_PERCENTILE`] (nearest rank) of one row's |relative error| values (the pixels of
/// its error spheres); non-finite values are left out; 0 for none.
pub fn row_percentile(mut abs_errors: Vec<f32>) -> f64 {
    abs_errors.retain(|v| v.is_finite());
    if abs_errors.is_empty() {
        return 0.0;
    }
    let rank = ((SCALE_PERCENTILE * abs_errors.len() as f64).ceil() as usize).clamp(1, abs_errors.len());
    let (_, v, _) = abs_errors.select_nth_unstable_by(rank - 1, f32::total_cmp);
    f64::from(*v)
}

/// The error range of the rows drawn with one scale: the median (lower middle) over the rows of
/// their [`row_percentile`]s, rounded up to a 1-2-5 step. A typical row then saturates on about
/// 5% of its pixels; a row far worse than the typical one saturates more, and says so.
pub fn range_of(mut row_percentiles: Vec<f64>) -> f64 {
    row_percentiles.retain(|v| v.is_finite());
    row_percentiles.sort_by(f64::total_cmp);
    nice_ceil(if row_percentiles.is_empty() { 0.0 } else { row_percentiles[(row_percentiles.len() - 1) / 2] })
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

    /// A row's percentile is the 95th by nearest rank: of 1..=100 (in %) 95%; of 1..=20 (in
    /// ‰, NaN left out) the 19th, 1.9%. The range is the median row's, rounded up to 1-2-5.
    #[test]
    fn range_is_a_high_percentile() {
        let p = row_percentile((1..=100).map(|k| k as f32 / 100.0).collect());
        assert!((p - 0.95).abs() < 1e-6, "{p}");
        let q = row_percentile((1..=20).rev().map(|k| k as f32 / 1000.0).chain([f32::NAN]).collect());
        assert!((q - 0.019).abs() < 1e-6, "{q}");
        assert_eq!(row_percentile(Vec::new()), 0.0);
        assert_eq!(range_of(vec![q, 40.0, p]), 1.0, "the median row's, not the worst's");
        assert_eq!(range_of(vec![q]), 0.02);
        assert_eq!(range_of(Vec::new()), 0.001);
        let e = ErrorScale { floor: 0.0, range: 0.1, scope: ErrorScope::Experiment };
        assert_eq!(e.saturated([0.05, -0.2, 0.1, 0.3]), 0.5, "beyond ±R, not at it");
        assert_eq!(e.saturated([]), 0.0);
    }
}
