//! Ratio-based quantisation of SH and ZH3 (ZH3 talk, "storage"; FORMULAS §11): every
//! coefficient except DC is stored as a −1..1 ratio, which is possible because non-negative
//! lighting bounds each coefficient's ratio to DC.
//!
//! The talk gives the sizes (L1 13 bytes, ZH3 16, L2 28), not the layout. The layout here is
//! ours (derived), the one that gives exactly those sizes:
//! - DC (the three radiance L₀₀) in RGB9E5, the shared-exponent format of
//!   `EXT_texture_shared_exponent` (9-bit mantissas, one 5-bit exponent): 4 bytes. It
//!   saturates at 65408, far above any probe in this workplace.
//! - Every other coefficient of channel c as one signed byte q = round(127·(x/L₀₀,c)/B), with B
//!   the coefficient's bound for non-negative radiance, attained by a delta light: √3 for each
//!   L1 component; for L2 √15/2 (m = −2, −1, 1, 2) and √5 (m = 0); √5 for the ZH3 coefficient
//!   f/L₀₀ (its range is [−√5/2, √5]). Ratios are taken to the *decoded* DC, as a decoder sees it.
//!
//! So L1 = 4 + 9 = 13 bytes, ZH3 = 13 + 3 = 16 bytes, L2 = 13 + 15 = 28 bytes.
//!
//! | id       | what | bytes | stored scalars |
//! |----------|------|-------|----------------|
//! | `sh1_q13` | SH L1, quantised as above | 13 | 12 |
//! | `sh2_q28` | SH L2, quantised as above | 28 | 27 |
//!
//! TOML keys: none. ZH3 encoders take `quantise = "ratio8"` (see `zh3.rs`).

use crate::encoders::encoder::{Encoder, FitInput, Fitted, Params};
use crate::encoders::sh::ShIrradiance;
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use anyhow::Result;

/// Bytes of a quantised L1, ZH3 and L2 probe (FORMULAS §11).
pub const BYTES_L1: usize = 13;
pub const BYTES_ZH3: usize = 16;
pub const BYTES_L2: usize = 28;

/// Ratio bound of each L1 component, |x|/L₀₀ ≤ √3.
pub fn bound_l1() -> f64 {
    3f64.sqrt()
}

/// Ratio bounds of the L2 coefficients (indices 4..8: m = −2, −1, 0, 1, 2).
pub fn bounds_l2() -> [f64; 5] {
    let (a, b) = (0.5 * 15f64.sqrt(), 5f64.sqrt());
    [a, a, b, a, a]
}

/// Ratio bound of the ZH3 coefficient f/L₀₀ (f the radiance coefficient of the rotated Y₂₀).
pub fn bound_zh3() -> f64 {
    5f64.sqrt()
}

const MANTISSA_BITS: i32 = 9;
const EXP_BIAS: i32 = 15;
const MAX_EXP: i32 = 31;

/// Largest value RGB9E5 represents: (2⁹ − 1)/2⁹ · 2^(31 − 15) = 65408.
pub fn rgb9e5_max() -> f64 {
    ((1 << MANTISSA_BITS) - 1) as f64 / (1 << MANTISSA_BITS) as f64 * 2f64.powi(MAX_EXP - EXP_BIAS)
}

/// Encodes a non-negative RGB in RGB9E5 (the reference algorithm of
/// `EXT_texture_shared_exponent`); negative and non-finite inputs encode as 0.
pub fn rgb9e5_encode(c: Rgb) -> u32 {
    let max = rgb9e5_max();
    let cl = |x: f64| if x.is_finite() { x.clamp(0.0, max) } else { 0.0 };
    let (r, g, b) = (cl(c.x), cl(c.y), cl(c.z));
    let maxc = r.max(g).max(b);
    if maxc == 0.0 {
        return 0;
    }
    let mut exp = (maxc.log2().floor() as i32).max(-EXP_BIAS - 1) + 1 + EXP_BIAS;
    let step = |e: i32| 2f64.powi(e - EXP_BIAS - MANTISSA_BITS);
    if (maxc / step(exp) + 0.5).floor() as i32 == 1 << MANTISSA_BITS {
        exp += 1;
    }
    let s = step(exp);
    let q = |x: f64| ((x / s + 0.5).floor() as u32).min((1 << MANTISSA_BITS) - 1);
    q(r) | (q(g) << 9) | (q(b) << 18) | ((exp as u32) << 27)
}

/// Decodes RGB9E5.
pub fn rgb9e5_decode(p: u32) -> Rgb {
    let exp = (p >> 27) as i32;
    let s = 2f64.powi(exp - EXP_BIAS - MANTISSA_BITS);
    let m = |k: u32| ((p >> k) & 0x1ff) as f64 * s;
    Rgb::new(m(0), m(9), m(18))
}

/// A coefficient `x` of a channel with decoded DC `dc`, as a signed byte of x/(dc·bound).
pub fn ratio8_encode(x: f64, dc: f64, bound: f64) -> i8 {
    if dc.is_nan() || dc <= 0.0 || !x.is_finite() {
        return 0;
    }
    (127.0 * (x / (dc * bound)).clamp(-1.0, 1.0)).round() as i8
}

/// Decodes a ratio byte.
pub fn ratio8_decode(q: i8, dc: f64, bound: f64) -> f64 {
    q as f64 / 127.0 * bound * dc
}

/// Quantises a radiance SH through band `max_band` (1 or 2): DC in RGB9E5, the rest as ratio
/// bytes. Returns the decoded radiance SH (higher bands zero).
pub fn quantise_sh(sh: &Sh9, max_band: usize) -> Sh9 {
    let dc = rgb9e5_decode(rgb9e5_encode(sh[0]));
    let mut out = Sh9::ZERO;
    out[0] = dc;
    let b2 = bounds_l2();
    let last = if max_band >= 2 { 9 } else { 4 };
    for i in 1..last {
        let bound = if i < 4 { bound_l1() } else { b2[i - 4] };
        for c in 0..3 {
            out[i][c] = ratio8_decode(ratio8_encode(sh[i][c], dc[c], bound), dc[c], bound);
        }
    }
    out
}

/// SH L1 or L2 quantised to 13 or 28 bytes.
pub struct ShQuantised {
    id: &'static str,
    max_band: usize,
}

impl Encoder for ShQuantised {
    fn id(&self) -> &str {
        self.id
    }
    /// Ratio quantisation loses precision by design (and cannot hold 1e-300 lights).
    fn degrades_input(&self) -> bool {
        true
    }
    fn stored_scalars(&self) -> usize {
        3 * (self.max_band + 1) * (self.max_band + 1)
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        let q = quantise_sh(input.visible_sh, self.max_band);
        Box::new(Quantised(ShIrradiance(q.convolve_cosine()), if self.max_band == 1 { BYTES_L1 } else { BYTES_L2 }))
    }
}

struct Quantised(ShIrradiance, usize);

impl Fitted for Quantised {
    fn irradiance(&self, n: glam::DVec3) -> Rgb {
        self.0.irradiance(n)
    }
    fn diagnostics(&self) -> Vec<(&'static str, f64)> {
        vec![("bytes", self.1 as f64)]
    }
    /// The decoded coefficients are an SH irradiance, evaluated as one.
    fn sh3(&self) -> Option<Sh9> {
        self.0.sh3()
    }
}

pub fn build_sh1_q13(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("sh1_q13")?;
    Ok(Box::new(ShQuantised { id: "sh1_q13", max_band: 1 }))
}
pub fn build_sh2_q28(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("sh2_q28")?;
    Ok(Box::new(ShQuantised { id: "sh2_q28", max_band: 2 }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::sh::{basis, delta_light};
    use glam::DVec3;

    /// The bounds are the largest |Y_lm(d)|/Y₀₀ over directions (a delta light), found by a
    /// dense search, independently of the closed forms.
    #[test]
    fn bounds_are_attained_by_delta_lights() {
        let mut best = [0.0f64; 9];
        for d in crate::reference::domain::fibonacci_sphere(200_000) {
            let y = basis(d);
            for i in 1..9 {
                best[i] = best[i].max((y[i] / y[0]).abs());
            }
        }
        let want: Vec<f64> = (1..9).map(|i| if i < 4 { bound_l1() } else { bounds_l2()[i - 4] }).collect();
        for i in 1..9 {
            assert!(best[i] <= want[i - 1] + 1e-12 && best[i] > want[i - 1] * (1.0 - 1e-4), "{i}: {}", best[i]);
        }
    }

    #[test]
    fn rgb9e5_round_trip() {
        assert_eq!(rgb9e5_decode(rgb9e5_encode(Rgb::ZERO)), Rgb::ZERO);
        assert_eq!(rgb9e5_max(), 65408.0);
        for c in [Rgb::new(1.0, 0.5, 0.25), Rgb::new(123.4, 5.6, 0.078), Rgb::new(1e-3, 2e-3, 0.0)] {
            let d = rgb9e5_decode(rgb9e5_encode(c));
            let m = c.max_element();
            // Half a step of a 9-bit mantissa relative to the largest channel.
            assert!((d - c).abs().max_element() <= m / 512.0 * 1.0001, "{c} -> {d}");
        }
        // Exactly representable values survive.
        assert_eq!(rgb9e5_decode(rgb9e5_encode(Rgb::new(256.0, 128.0, 1.0))), Rgb::new(256.0, 128.0, 1.0));
    }

    /// A delta light's ratios sit on the bounds, so quantisation keeps them to the byte step.
    #[test]
    fn quantised_delta_light_is_close() {
        let d = DVec3::new(0.3, 0.8, -0.52).normalize();
        let sh = delta_light(d, Rgb::new(3.0, 2.0, 1.0));
        let q = quantise_sh(&sh, 2);
        for i in 0..9 {
            for c in 0..3 {
                assert!((q[i][c] - sh[i][c]).abs() <= 0.01 * sh[0][c] * 2.0, "{i} {c}");
            }
        }
        assert_eq!(quantise_sh(&sh, 1)[6], Rgb::ZERO);
    }
}
