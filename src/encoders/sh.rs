//! SH L0, L1 and L2 irradiance: least-squares projection with texel solid angles (exact cell
//! integrals, `projection.rs`), then the cosine band scales Â = (1, 2/3, 1/4) (FORMULAS §2–3).
//!
//! | id    | bands | stored scalars |
//! |-------|-------|----------------|
//! | `sh0` | 0     | 3  (the constant, DC-only encoder) |
//! | `sh1` | 0–1   | 12 |
//! | `sh2` | 0–2   | 27 |
//!
//! TOML keys: none. The fit uses the visible radiance (the map under the declared effects).
//! SH irradiance is not clamped: it can go negative, which the `neg_frac` column reports.
//!
//! Degenerate inputs need no fallback: the fit is a linear map of the coefficients (black in,
//! black out; a 1e-300 L1 band stays 1e-300), so every finite input gives a finite output.

use crate::encoders::encoder::{fit_each_unboxed, sq_errors_unboxed, Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::stored::{Role, Stored, Unit, SH_IRRADIANCE};
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use anyhow::Result;
use glam::DVec3;

/// SH irradiance truncated after band `max_band`.
pub struct ShEncoder {
    id: &'static str,
    max_band: usize,
}

impl ShEncoder {
    /// The encoder truncated after band `max_band` (0, 1 or 2; larger values act as 2).
    pub fn new(max_band: usize) -> Self {
        let id = ["sh0", "sh1", "sh2"][max_band.min(2)];
        ShEncoder { id, max_band: max_band.min(2) }
    }
}

impl ShEncoder {
    /// The fit of radiance SH `sh`: truncated, then convolved with the clamped cosine.
    fn fit_sh(&self, sh: &Sh9) -> ShIrradiance {
        ShIrradiance(sh.truncate(self.max_band).convolve_cosine(), self.max_band)
    }
}

/// The fitted E/π SH and the last band it stores (0, 1 or 2; higher bands are zero).
pub struct ShIrradiance(pub Sh9, pub usize);

/// The stored form of an E/π SH through band `max_band`: its (max_band + 1)² RGB
/// coefficients, named `L{l}_{m}` (FORMULAS §2–3).
pub fn stored_sh(sh: &Sh9, max_band: usize) -> Stored {
    let n = (max_band.min(2) + 1).pow(2);
    let mut s = Stored::new(SH_IRRADIANCE);
    s.sh(Role::Stored, Unit::Irradiance, &sh.0[..n]);
    s
}

impl Fitted for ShIrradiance {
    fn irradiance(&self, n: DVec3) -> Rgb {
        self.0.eval(n)
    }
    fn stored(&self) -> Stored {
        stored_sh(&self.0, self.1)
    }
    fn sh3(&self) -> Option<Sh9> {
        Some(self.0)
    }
}

impl Encoder for ShEncoder {
    fn id(&self) -> &str {
        self.id
    }
    fn family(&self) -> Family {
        Family::Sh
    }
    fn stored_scalars(&self) -> usize {
        3 * (self.max_band + 1) * (self.max_band + 1)
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        Box::new(self.fit_sh(input.visible_sh))
    }
    fn fit_sphere_each(&self, probes: &[Sh9], visit: &mut dyn FnMut(usize, &dyn Fitted)) {
        fit_each_unboxed(probes, visit, |p| self.fit_sh(p));
    }
    fn sphere_sq_errors(&self, probes: &[Sh9], irradiance: &[Sh9], out: &mut [f64]) -> bool {
        sq_errors_unboxed(probes, irradiance, out, |p| self.fit_sh(p))
    }
    /// Band 0 alone is the mean radiance, E/π = (1/4π)∫L dω ≥ 0. With band 1 a single light
    /// gives (1/4π)·e·(1 + 2 n·d), negative facing away from it.
    fn promises_non_negative(&self) -> bool {
        self.max_band == 0
    }
    /// Linear in the coefficients.
    fn is_scale_covariant(&self) -> bool {
        true
    }
    /// Each band is an irreducible representation of the rotation group.
    fn is_rotation_covariant(&self) -> bool {
        true
    }
    /// It is that projection (the basis is orthonormal and the cosine kernel diagonal in it).
    fn sphere_error_at_most_sh(&self) -> Option<usize> {
        Some(self.max_band)
    }
}

/// Builds the `sh0` encoder from its settings: SH band 0 only (constant). An unknown or
/// out-of-range setting is an error.
pub fn build_sh0(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("sh0")?;
    Ok(Box::new(ShEncoder::new(0)))
}
/// Builds the `sh1` encoder from its settings: SH L1 irradiance (bands 0-1). An unknown or
/// out-of-range setting is an error.
pub fn build_sh1(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("sh1")?;
    Ok(Box::new(ShEncoder::new(1)))
}
/// Builds the `sh2` encoder from its settings: SH L2 irradiance (bands 0-2). An unknown or
/// out-of-range setting is an error.
pub fn build_sh2(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("sh2")?;
    Ok(Box::new(ShEncoder::new(2)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::sh::{constant, delta_light};
    use std::f64::consts::PI;

    /// For a delta light of unit intensity along d, SH irradiance at n = d is the truncated
    /// Legendre expansion Σ_l Â_l (2l+1)/(4π) P_l(1): (1 + 2)/(4π) = 3/(4π) for L1 and
    /// (1 + 2 + 5/4)/(4π) = 17/(16π) for L2.
    #[test]
    fn delta_light_peak_matches_legendre_expansion() {
        let d = DVec3::new(0.3, 0.5, 0.81).normalize();
        let fit = ShEncoder::new(2).fit(&FitInput::sphere(&delta_light(d, Rgb::ONE)));
        let want = 17.0 / (16.0 * PI);
        assert!((fit.irradiance(d).x - want).abs() < 1e-14);
        let fit1 = ShEncoder::new(1).fit(&FitInput::sphere(&delta_light(d, Rgb::ONE)));
        assert!((fit1.irradiance(d).x - 3.0 / (4.0 * PI)).abs() < 1e-14);
    }

    #[test]
    fn constant_is_exact_for_every_order() {
        let sh = constant(Rgb::new(0.5, 1.0, 2.0));
        for b in 0..=2 {
            let f = ShEncoder::new(b).fit(&FitInput::sphere(&sh));
            assert!((f.irradiance(DVec3::NEG_Z) - Rgb::new(0.5, 1.0, 2.0)).abs().max_element() < 1e-15);
        }
        assert_eq!(ShEncoder::new(1).stored_scalars(), 12);
        assert_eq!(ShEncoder::new(2).stored_scalars(), 27);
    }
}
