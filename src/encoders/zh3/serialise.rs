//! A ZH3's serialised form (FORMULAS §11, `quantise.rs`): SH L1's 13 bytes, then one signed
//! byte per channel for a stored zonal coefficient (16); a hallucinated ZH3 is rebuilt from the
//! decoded L1.

use crate::encoders::quantise;
use crate::encoders::zh3::model::{finish_hallucinated, AxisRule, Zh3};
use crate::encoders::zh3::solve::Curve;
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use anyhow::{bail, Result};
use glam::DVec3;

/// f_rad/k_irr: the radiance coefficient of the rotated Y₂₀ per irradiance zonal coefficient,
/// f_rad = 4·f_irr = 4·√(5/4π)·k_irr.
fn f_of_k() -> f64 {
    4.0 * (5.0 / (4.0 * std::f64::consts::PI)).sqrt()
}

/// Serialises a ZH3 as FORMULAS §11 (`quantise.rs`): the radiance L0 and L1 as SH L1's 13
/// bytes ([`quantise::encode_sh`]), then, if `store_k`, the ratio f/L₀₀ of each channel as one
/// signed byte (bound [`quantise::bound_zh3`]): 16 bytes. Without it (hallucinated ZH3) the
/// decoder hallucinates k from the decoded L1: 13 bytes.
pub fn encode_zh3(z: &Zh3, store_k: bool) -> Vec<u8> {
    // Radiance SH of L0 and L1: L₀₀ = irradiance L0 (E/π), L1 = 1.5 × irradiance L1.
    let mut rad = Sh9::ZERO;
    rad[0] = z.l0;
    for c in 0..3 {
        let v = z.l1[c] * 1.5;
        (rad[1][c], rad[2][c], rad[3][c]) = (-v.y, v.z, -v.x);
    }
    let mut out = quantise::encode_sh(&rad, 1);
    if store_k {
        let dc = quantise::rgb9e5_decode(quantise::rgb9e5_encode(z.l0));
        let bz = quantise::bound_zh3();
        out.extend((0..3).map(|c| quantise::ratio8_encode(z.k[c] * f_of_k(), dc[c], bz) as u8));
    }
    out
}

/// Decodes [`encode_zh3`]'s bytes: 13 (hallucinated: k from the decoded L1 with `curve`) or 16
/// (stored k); the axes come from the decoded L1 by `rule`. Any other length is an error.
pub fn decode_zh3(bytes: &[u8], rule: AxisRule, curve: Curve) -> Result<Zh3> {
    if bytes.len() != quantise::BYTES_L1 && bytes.len() != quantise::BYTES_ZH3 {
        bail!(
            "quantised ZH3: {} bytes; expected {} (hallucinated) or {} (stored zonal coefficient)",
            bytes.len(),
            quantise::BYTES_L1,
            quantise::BYTES_ZH3
        );
    }
    let rad = quantise::decode_sh(&bytes[..quantise::BYTES_L1])?;
    let dc = rad[0];
    let l1: [DVec3; 3] = std::array::from_fn(|c| rad.l1_vector(c) / 1.5);
    let Some(kb) = bytes.get(quantise::BYTES_L1..).filter(|k| !k.is_empty()) else {
        return Ok(finish_hallucinated(dc, l1, rule, curve));
    };
    let bz = quantise::bound_zh3();
    let k = Rgb::from_array(std::array::from_fn(|c| quantise::ratio8_decode(kb[c] as i8, dc[c], bz) / f_of_k()));
    Ok(Zh3 { l0: dc, l1, axes: rule.axes(&l1), k })
}
