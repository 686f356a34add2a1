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
//! So L1 = 4 + 9 = 13 bytes, ZH3 = 13 + 3 = 16 bytes, L2 = 13 + 15 = 28 bytes. The encoders
//! store exactly these bytes ([`encode_sh`]; ZH3: `zh3::encode_zh3`) and evaluate what their
//! decoder reads back ([`decode_sh`]; `zh3::decode_zh3`), so the sizes are counted, not assumed.
//!
//! | id       | what | bytes | stored scalars |
//! |----------|------|-------|----------------|
//! | `sh1_q13` | SH L1, quantised as above | 13 | 12 |
//! | `sh2_q28` | SH L2, quantised as above | 28 | 27 |
//! | `zh3_q16` | stored ZH3 (`zh3_solved_shared`), quantised as above | 16 | 15 |
//! | `zh3_hallucinate_q13` | hallucinated ZH3 (`zh3_hallucinate`): its L1 quantised as above | 13 | 12 |
//!
//! Every other encoding stores half floats: [`Encoder::stored_bytes`] is 2 bytes a scalar.
//!
//! TOML keys: none. ZH3 encoders take `quantise = "ratio8"` (see `zh3.rs`).

use crate::encoders::encoder::{Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::sh::ShIrradiance;
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use anyhow::{bail, Result};

/// Bytes of a quantised L1 probe (FORMULAS §11).
pub const BYTES_L1: usize = 13;
/// Bytes of a quantised ZH3 probe (FORMULAS §11).
pub const BYTES_ZH3: usize = 16;
/// Bytes of a quantised L2 probe (FORMULAS §11).
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

/// The ratio bound of radiance SH coefficient `i` (1..8): [`bound_l1`] for band 1,
/// [`bounds_l2`] for band 2.
fn bound_of(i: usize) -> f64 {
    if i < 4 {
        bound_l1()
    } else {
        bounds_l2()[i - 4]
    }
}

/// Serialises a radiance SH through band `max_band` (2 for L2, otherwise L1) as FORMULAS §11
/// (module doc): DC in RGB9E5 (4 bytes, little-endian), then one signed ratio byte per
/// coefficient i = 1.. and channel r, g, b, each a ratio to the *decoded* DC. 13 bytes for L1,
/// 28 for L2.
pub fn encode_sh(sh: &Sh9, max_band: usize) -> Vec<u8> {
    let packed = rgb9e5_encode(sh[0]);
    let dc = rgb9e5_decode(packed);
    let last = if max_band >= 2 { 9 } else { 4 };
    let mut out = Vec::with_capacity(if max_band >= 2 { BYTES_L2 } else { BYTES_L1 });
    out.extend_from_slice(&packed.to_le_bytes());
    for i in 1..last {
        for c in 0..3 {
            out.push(ratio8_encode(sh[i][c], dc[c], bound_of(i)) as u8);
        }
    }
    out
}

/// Decodes [`encode_sh`]'s bytes: the length decides the band (13: L1, 28: L2; higher bands
/// zero); any other length is an error.
pub fn decode_sh(bytes: &[u8]) -> Result<Sh9> {
    let last = match bytes.len() {
        BYTES_L1 => 4,
        BYTES_L2 => 9,
        n => bail!("quantised SH: {n} bytes; expected {BYTES_L1} (L1) or {BYTES_L2} (L2)"),
    };
    let dc = rgb9e5_decode(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]));
    let mut out = Sh9::ZERO;
    out[0] = dc;
    let mut q = bytes[4..].iter();
    for i in 1..last {
        for c in 0..3 {
            let b = *q.next().expect("the length was checked");
            out[i][c] = ratio8_decode(b as i8, dc[c], bound_of(i));
        }
    }
    Ok(out)
}

/// Quantises a radiance SH through band `max_band` (1 or 2): its serialised form
/// ([`encode_sh`]), decoded ([`decode_sh`]). Returns the decoded radiance SH (higher bands
/// zero).
#[cfg(test)]
pub fn quantise_sh(sh: &Sh9, max_band: usize) -> Sh9 {
    decode_sh(&encode_sh(sh, max_band)).expect("encode_sh writes 13 or 28 bytes")
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
    fn family(&self) -> Family {
        Family::Sh
    }
    /// Ratio quantisation loses precision by design (and cannot hold 1e-300 lights).
    fn degrades_input(&self) -> bool {
        true
    }
    fn stored_scalars(&self) -> usize {
        3 * (self.max_band + 1) * (self.max_band + 1)
    }
    fn stored_bytes(&self) -> usize {
        if self.max_band == 1 {
            BYTES_L1
        } else {
            BYTES_L2
        }
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        // The stored bytes, decoded: what a shader would read.
        let bytes = encode_sh(input.visible_sh, self.max_band);
        let q = decode_sh(&bytes).expect("encode_sh writes 13 or 28 bytes");
        Box::new(Quantised(ShIrradiance(q.convolve_cosine(), self.max_band), bytes.len()))
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
    /// The decoded coefficients a shader reads (E/π SH), from the 13 or 28 stored bytes.
    fn stored(&self) -> crate::encoders::stored::Stored {
        let mut s = self.0.stored();
        s.basis = format!(
            "{}; the values are those decoded from the {} stored bytes (DC in RGB9E5, every other radiance \
             coefficient a signed byte ratio to the decoded DC: docs/conventions.md section 11, quantise.rs)",
            s.basis, self.1
        );
        s
    }
    /// The decoded coefficients are an SH irradiance, evaluated as one.
    fn sh3(&self) -> Option<Sh9> {
        self.0.sh3()
    }
}

/// Builds the `sh1_q13` encoder from its settings: SH L1, ratio-quantised to 13 bytes. An unknown
/// or out-of-range setting is an error.
pub fn build_sh1_q13(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("sh1_q13")?;
    Ok(Box::new(ShQuantised { id: "sh1_q13", max_band: 1 }))
}
/// Builds the `sh2_q28` encoder from its settings: SH L2, ratio-quantised to 28 bytes. An unknown
/// or out-of-range setting is an error.
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

    /// The quantisation as it was specified scalar by scalar (DC through RGB9E5, each other
    /// coefficient through a ratio byte to the decoded DC), independently of the byte layout.
    fn per_scalar(sh: &Sh9, max_band: usize) -> Sh9 {
        let dc = rgb9e5_decode(rgb9e5_encode(sh[0]));
        let mut out = Sh9::ZERO;
        out[0] = dc;
        for i in 1..if max_band >= 2 { 9 } else { 4 } {
            let b = if i < 4 { bound_l1() } else { bounds_l2()[i - 4] };
            for c in 0..3 {
                out[i][c] = ratio8_decode(ratio8_encode(sh[i][c], dc[c], b), dc[c], b);
            }
        }
        out
    }

    /// Serialising and decoding is the scalar-by-scalar quantisation, bit for bit, has the
    /// talk's sizes, and is idempotent (decoded values re-encode to the same values).
    #[test]
    fn serialised_round_trip() {
        let mut rng = crate::math::test_rng::Rng::new(7);
        for k in 0..300 {
            // Non-negative lighting (three delta lights, some ambient), and every fourth an
            // arbitrary SH (negative DC, ratios beyond the bounds: clamped).
            let mut sh = Sh9::ZERO;
            for _ in 0..3 {
                sh = sh + delta_light(rng.unit(), Rgb::new(rng.uniform01(), rng.uniform01(), rng.uniform01()) * 3.0);
            }
            sh[0] += Rgb::splat(0.1 * (k % 3) as f64);
            if k % 4 == 3 {
                sh = rng.sh();
            }
            for (band, len) in [(1, BYTES_L1), (2, BYTES_L2)] {
                let bytes = encode_sh(&sh, band);
                assert_eq!(bytes.len(), len);
                let d = decode_sh(&bytes).unwrap();
                assert_eq!(d, per_scalar(&sh, band), "{k} band {band}");
                assert_eq!(quantise_sh(&sh, band), d);
                assert_eq!(decode_sh(&encode_sh(&d, band)).unwrap(), d, "{k} band {band}: not idempotent");
            }
        }
    }

    /// Hand-made bytes decode to the values the layout defines: RGB9E5 (256, 256, 256, exponent
    /// 16) is 1.0 per channel, and ratio bytes ±127 are ±bound × DC.
    #[test]
    fn bytes_decode_by_the_layout() {
        let dc: u32 = 256 | (256 << 9) | (256 << 18) | (16 << 27);
        let mut b = dc.to_le_bytes().to_vec();
        b.extend_from_slice(&[127, 0, 129, 0, 0, 0, 0, 0, 0]); // L1₋₁: r = √3, b = −√3
        let sh = decode_sh(&b).unwrap();
        assert_eq!(sh[0], Rgb::ONE);
        assert_eq!(sh[1], Rgb::new(3f64.sqrt(), 0.0, -(3f64.sqrt())));
        assert_eq!(encode_sh(&sh, 1), b);
        b.extend_from_slice(&[0; 15]);
        b[4 + 9 + 6] = 127; // L2₀, red: √5
        let sh = decode_sh(&b).unwrap();
        assert_eq!(sh[6], Rgb::new(5f64.sqrt(), 0.0, 0.0));
        assert_eq!(encode_sh(&sh, 2), b);
    }

    #[test]
    fn wrong_lengths_are_refused() {
        for n in [0, 4, 12, 14, 16, 27, 29] {
            let e = decode_sh(&vec![0u8; n]).unwrap_err().to_string();
            assert!(e.contains(&format!("{n} bytes")) && e.contains("13") && e.contains("28"), "{e}");
        }
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
