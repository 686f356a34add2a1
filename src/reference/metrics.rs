//! Error metrics of E/π against the exact reference.
//!
//! - `exact`: solid-angle-weighted RMSE over the output domain (sphere or hemisphere), per
//!   channel; `rmse` = √(mean of the three channel MSEs); `rel_rmse` = rmse / RMS(reference).
//! - `probulator`: the peer tool's scoring (FORMULAS §10) — a plain per-pixel mean over the
//!   256×128 lat-long output pixels at pixel centres, equal-thirds channels, test values clamped
//!   at ≥ 0 (unless the encoder says its peer counterpart is unclamped) — but computed against
//!   our exact reference, not Monte Carlo.

use crate::math::colour::Rgb;
use anyhow::{bail, Result};

/// Which scoring rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    /// Solid-angle-weighted RMSE over the output domain, against the exact reference.
    Exact,
    /// The peer tool's per-pixel mean over its 256×128 lat-long output (FORMULAS §10), still
    /// against the exact reference.
    Probulator,
}

impl Metric {
    /// Parses a metric name, `exact` or `probulator`; any other name is an error.
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "exact" => Ok(Metric::Exact),
            "probulator" => Ok(Metric::Probulator),
            _ => bail!("unknown metric '{s}' (expected exact or probulator)"),
        }
    }
    /// The metric's name as [`Metric::parse`] accepts it.
    pub fn name(&self) -> &'static str {
        match self {
            Metric::Exact => "exact",
            Metric::Probulator => "probulator",
        }
    }
    /// The weighting this metric applies, for table labels.
    pub fn weighting(&self) -> &'static str {
        match self {
            Metric::Exact => "solid-angle",
            Metric::Probulator => "per-pixel",
        }
    }
    /// The fixed output resolution of the metric, if it has one.
    pub fn fixed_resolution(&self) -> Option<(usize, usize)> {
        match self {
            Metric::Exact => None,
            Metric::Probulator => Some((256, 128)),
        }
    }
}

/// The scores of one encoder against the reference over one output grid.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Scores {
    /// Weighted RMSE of E/π per channel (R, G, B).
    pub rmse_rgb: [f64; 3],
    /// √(mean of the three channel MSEs), in E/π.
    pub rmse: f64,
    /// `rmse` divided by the RMS of the reference E/π (dimensionless).
    pub rel_rmse: f64,
    /// Weighted fraction of output normals where any channel of the test value is negative.
    pub neg_frac: f64,
    /// Largest absolute error of any channel.
    pub max_abs: f64,
}

/// Weighted RMSE of `test` against `reference` with weights `w` (any positive scale). When
/// `clamp` is set the test values are clamped at ≥ 0 first (the peer tool's rule). Sums run in
/// index order, so the result is deterministic.
pub fn score(reference: &[Rgb], test: &[Rgb], w: &[f64], clamp: bool) -> Scores {
    assert_eq!(reference.len(), test.len());
    assert_eq!(reference.len(), w.len());
    // Values beyond ~1e150 (or below ~1e-150) would overflow (underflow) when squared: such
    // inputs are scaled by an exact power of two first, which leaves ordinary inputs untouched
    // and every result exact up to that power.
    let big = reference.iter().chain(test).map(|v| v.abs().max_element()).filter(|v| v.is_finite()).fold(0.0, f64::max);
    let scale = if big > 1e150 || (big > 0.0 && big < 1e-150) { 2f64.powi(-(big.log2().round() as i32)) } else { 1.0 };
    let mut se = Rgb::ZERO;
    let mut sr = Rgb::ZERO;
    let (mut wsum, mut neg, mut max_abs) = (0.0, 0.0, 0.0f64);
    for ((r, t), &wi) in reference.iter().zip(test).zip(w) {
        if t.min_element() < 0.0 {
            neg += wi;
        }
        let t = if clamp { t.max(Rgb::ZERO) } else { *t };
        let d = (t - *r) * scale;
        let r = *r * scale;
        max_abs = max_abs.max(d.abs().max_element());
        se += d * d * wi;
        sr += r * r * wi;
        wsum += wi;
    }
    let mse = se / wsum;
    let rmse = (mse.element_sum() / 3.0).sqrt();
    let rms_ref = (sr.element_sum() / (3.0 * wsum)).sqrt();
    let (rmse, max_abs, mse) = (rmse / scale, max_abs / scale, mse);
    let unscale = |v: f64| v.sqrt() / scale;
    Scores {
        rmse_rgb: [unscale(mse.x), unscale(mse.y), unscale(mse.z)],
        rmse,
        // A reference that is zero everywhere (e.g. a cone that sees no light) has no relative
        // error; a non-zero test value there saturates at f64::MAX rather than printing Inf.
        rel_rmse: if rms_ref > 0.0 {
            (rmse * scale / rms_ref).min(f64::MAX)
        } else if rmse == 0.0 {
            0.0
        } else {
            f64::MAX
        },
        neg_frac: neg / wsum,
        max_abs,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rmse_of_known_differences() {
        let r = vec![Rgb::ONE; 4];
        let t = vec![Rgb::new(1.0, 2.0, 1.0), Rgb::new(1.0, 0.0, 1.0), Rgb::ONE, Rgb::ONE];
        let s = score(&r, &t, &[1.0; 4], false);
        // G errors: +1, −1, 0, 0 → MSE_g = 0.5; R, B zero.
        assert!((s.rmse_rgb[1] - 0.5f64.sqrt()).abs() < 1e-15);
        assert!((s.rmse - (0.5f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!((s.rel_rmse - s.rmse).abs() < 1e-15);
        assert_eq!(s.max_abs, 1.0);
    }

    #[test]
    fn weights_and_clamping() {
        let r = vec![Rgb::ZERO, Rgb::ZERO];
        let t = vec![Rgb::splat(-1.0), Rgb::splat(2.0)];
        let s = score(&r, &t, &[3.0, 1.0], false);
        assert!((s.rmse - ((3.0 + 4.0) / 4.0f64).sqrt()).abs() < 1e-15);
        assert!((s.neg_frac - 0.75).abs() < 1e-15);
        let c = score(&r, &t, &[3.0, 1.0], true);
        assert!((c.rmse - 1.0).abs() < 1e-15, "clamped −1 → 0, only 2 counts: √(4/4)");
    }
}
