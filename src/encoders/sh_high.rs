//! SH irradiance beyond band 2 and windowed SH: the peer tool's `SHL3`, `SHL4` and `SHL2W`
//! (Probulator `ExperimentSH.h`, `SphericalHarmonics.h`: `shEvaluateDiffuse`,
//! `shFindWindowingLambda`, `shApplyWindowing`).
//!
//! | id | what | stored scalars |
//! |---|---|---|
//! | `sh3` | radiance SH through band 3, cosine band scales (Â₃ = 0) | 48 |
//! | `sh4` | radiance SH through band 4, Â₄ = −1/24 (Ramamoorthi–Hanrahan 2001, eq. 8) | 75 |
//! | `sh2_windowed` | L2 radiance SH windowed by 1/(1 + λ l²(l+1)²), λ for a target Laplacian | 27 |
//! | `sh2_windowed_peer` | the same with the peer's band energy (its indexing slip, below) | 27 |
//!
//! Bands 0–2 are the input's exact `visible_sh`; band 4 comes from the light's exact cell
//! integrals (`reference::radiance::project_sh4`). Band 3 is stored but adds nothing to
//! irradiance, so `sh3` equals `sh2` to rounding (as the peer's figures do).
//!
//! Windowing (Sloan, "Stupid SH Tricks", appendix A7): λ makes the squared Laplacian of the
//! windowed Rec.709-luminance radiance SH, Σ_l l²(l+1)² B_l /(1 + λ l²(l+1)²)², equal the target²
//! (the peer's target Laplacian is 10, "empirically chosen"), with B_l = Σ_m L_lm² the band energy;
//! λ = 0 if the unwindowed SH are already below it. The target is absolute, in radiance units,
//! so the window depends on the map's brightness (not scale covariant). The peer's band-energy
//! loop runs m from −1 to l instead of −l to l, so for band 2 it drops L₂,₋₂ (its λ is then too
//! small whenever L₂,₋₂ ≠ 0). `sh2_windowed` uses the whole band energy (rotation invariant);
//! `sh2_windowed_peer` reproduces the slip. λ is solved by Newton's method from 0 (the peer's),
//! kept inside a bracket by bisection, in f64.
//!
//! TOML keys: `target_laplacian` (windowed only; default 10, > 0).

use crate::encoders::encoder::{Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::sh::stored_sh;
use crate::encoders::stored::{Role, Stored, Unit, Value, SH_IRRADIANCE};
use crate::math::colour::{luminance, Rgb};
use crate::math::sh::{Sh9, N_SH};
use crate::math::sh4::{basis4, BAND_SCALE4};
use anyhow::Result;
use glam::DVec3;

/// SH irradiance through band 3 (bands 0–2 and a zero band 3 after the cosine convolution).
pub struct Sh3Encoder;
/// SH irradiance through band 4.
pub struct Sh4Encoder;

/// E/π as bands 0–2 plus, optionally, band 4 (nine coefficients, index 16..25).
pub struct ShHighIrradiance {
    low: Sh9,
    band4: Option<[Rgb; 9]>,
}

impl Fitted for ShHighIrradiance {
    /// The E/π SH through band 3 (16 RGB: band 3 is stored, and zero after the cosine
    /// convolution) or band 4 (25 RGB), FORMULAS §2–3 (`math::sh4` extends §2's convention).
    fn stored(&self) -> Stored {
        let mut c: Vec<Rgb> = self.low.0.to_vec();
        c.resize(16, Rgb::ZERO);
        if let Some(b4) = &self.band4 {
            c.extend_from_slice(b4);
        }
        let mut s = Stored::new(SH_IRRADIANCE);
        s.sh(Role::Stored, Unit::Irradiance, &c);
        s
    }
    fn irradiance(&self, n: DVec3) -> Rgb {
        let mut e = self.low.eval(n);
        if let Some(b4) = &self.band4 {
            let y = basis4(n);
            for (c, yi) in b4.iter().zip(&y[16..]) {
                e += *c * *yi;
            }
        }
        e
    }
    fn sh3(&self) -> Option<Sh9> {
        match self.band4 {
            None => Some(self.low),
            Some(_) => None,
        }
    }
    /// Parseval over bands 0–4: the reference has bands 0–2 only, so band 4 adds its energy.
    fn sphere_sq_error(&self, reference: &Sh9) -> Option<f64> {
        let low: f64 = (0..N_SH).map(|i| (self.low[i] - reference[i]).length_squared()).sum();
        let high: f64 = self.band4.iter().flatten().map(|c| c.length_squared()).sum();
        Some(low + high)
    }
}

impl Encoder for Sh3Encoder {
    fn reads_radiance(&self) -> bool {
        true
    }

    fn id(&self) -> &str {
        "sh3"
    }
    fn family(&self) -> Family {
        Family::Sh
    }
    fn stored_scalars(&self) -> usize {
        48
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        Box::new(ShHighIrradiance { low: input.visible_sh.convolve_cosine(), band4: None })
    }
    fn is_scale_covariant(&self) -> bool {
        true
    }
    fn is_rotation_covariant(&self) -> bool {
        true
    }
    fn sphere_error_at_most_sh(&self) -> Option<usize> {
        Some(2)
    }
}

impl Encoder for Sh4Encoder {
    fn reads_radiance(&self) -> bool {
        true
    }

    fn id(&self) -> &str {
        "sh4"
    }
    fn family(&self) -> Family {
        Family::Sh
    }
    fn stored_scalars(&self) -> usize {
        75
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        let light = input.light();
        let sh = light.sh4();
        let band4 = std::array::from_fn(|k| sh.0[16 + k] * BAND_SCALE4[4]);
        Box::new(ShHighIrradiance { low: input.visible_sh.convolve_cosine(), band4: Some(band4) })
    }
    fn is_scale_covariant(&self) -> bool {
        true
    }
    fn is_rotation_covariant(&self) -> bool {
        true
    }
    /// The projection through band 4 contains the one through band 2 (orthogonal bands).
    fn sphere_error_at_most_sh(&self) -> Option<usize> {
        Some(2)
    }
}

/// L2 SH irradiance with the peer's Laplacian window.
pub struct WindowedSh {
    target_laplacian: f64,
    peer_band_energy: bool,
}

/// l²(l + 1)² for l = 0, 1, 2.
const LAPLACIAN: [f64; 3] = [0.0, 4.0, 36.0];

impl WindowedSh {
    /// Band energies B₁, B₂ of the luminance radiance SH (the peer's, with its slip, if asked).
    fn band_energy(&self, lum: &[f64; N_SH]) -> [f64; 3] {
        let b1 = lum[1] * lum[1] + lum[2] * lum[2] + lum[3] * lum[3];
        let first = if self.peer_band_energy { 5 } else { 4 };
        let b2 = lum[first..9].iter().map(|c| c * c).sum();
        [0.0, b1, b2]
    }

    /// The window strength λ ≥ 0: the root of Σ L_l B_l/(1 + λL_l)² = T², or 0.
    pub fn lambda(&self, lum: &[f64; N_SH]) -> f64 {
        let b = self.band_energy(lum);
        // Scaled by the largest energy so that no square overflows (hard cases reach 1e150).
        let scale = b[1].max(b[2]);
        if !(scale > 0.0 && scale.is_finite()) {
            return 0.0;
        }
        let bs = [0.0, b[1] / scale, b[2] / scale];
        let target = self.target_laplacian * self.target_laplacian / scale;
        let s = |lam: f64| (1..3).map(|l| LAPLACIAN[l] * bs[l] / (1.0 + lam * LAPLACIAN[l]).powi(2)).sum::<f64>();
        if s(0.0) <= target {
            return 0.0;
        }
        // S(λ) ≤ Σ B_l/(λ² L_l), so S(hi) ≤ target at hi = √(Σ B_l/L_l / target).
        let (mut lo, mut hi) = (0.0f64, ((bs[1] / 4.0 + bs[2] / 36.0) / target).sqrt());
        let mut lam = 0.0;
        for _ in 0..500 {
            let f = s(lam) - target;
            if f > 0.0 {
                lo = lam;
            } else {
                hi = lam;
            }
            let fd: f64 =
                (1..3).map(|l| -2.0 * LAPLACIAN[l].powi(2) * bs[l] / (1.0 + lam * LAPLACIAN[l]).powi(3)).sum();
            let mut next = lam - f / fd;
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (next - lam).abs() <= 1e-15 * next.abs() || hi - lo <= 1e-15 * hi {
                return next;
            }
            lam = next;
        }
        lam
    }
}

/// The windowed fit: E/π SH and its λ.
struct WindowedFit {
    sh: Sh9,
    lambda: f64,
}

impl Fitted for WindowedFit {
    fn irradiance(&self, n: DVec3) -> Rgb {
        self.sh.eval(n)
    }
    fn sh3(&self) -> Option<Sh9> {
        Some(self.sh)
    }
    fn diagnostics(&self) -> Vec<(&'static str, f64)> {
        vec![("lambda", self.lambda)]
    }
    /// The windowed E/π SH (27 scalars) and the window's λ, derived.
    fn stored(&self) -> Stored {
        let mut s = stored_sh(&self.sh, 2);
        s.basis = format!("{}; the radiance SH were windowed by 1/(1 + lambda*l^2(l+1)^2) first", s.basis);
        s.push(Role::Derived, "lambda", Unit::Unitless, Value::Scalar(self.lambda));
        s
    }
}

impl Encoder for WindowedSh {
    fn id(&self) -> &str {
        if self.peer_band_energy {
            "sh2_windowed_peer"
        } else {
            "sh2_windowed"
        }
    }
    fn family(&self) -> Family {
        Family::Sh
    }
    fn stored_scalars(&self) -> usize {
        27
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        let sh = input.visible_sh;
        let lum: [f64; N_SH] = std::array::from_fn(|i| luminance(sh[i]));
        let lambda = self.lambda(&lum);
        let mut out = *sh;
        for (i, c) in out.0.iter_mut().enumerate() {
            let l = crate::math::sh::band_of(i);
            *c *= 1.0 / (1.0 + lambda * LAPLACIAN[l]);
        }
        Box::new(WindowedFit { sh: out.convolve_cosine(), lambda })
    }
    /// The whole band energy is rotation invariant; the peer's partial one is not.
    fn is_rotation_covariant(&self) -> bool {
        !self.peer_band_energy
    }
    fn degrades_input(&self) -> bool {
        self.peer_band_energy
    }
}

/// Builds the `sh3` encoder from its settings: SH L3 irradiance (bands 0-3; peer SHL3). An unknown
/// or out-of-range setting is an error.
pub fn build_sh3(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("sh3")?;
    Ok(Box::new(Sh3Encoder))
}
/// Builds the `sh4` encoder from its settings: SH L4 irradiance (bands 0-4; peer SHL4). An unknown
/// or out-of-range setting is an error.
pub fn build_sh4(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("sh4")?;
    Ok(Box::new(Sh4Encoder))
}
fn windowed(p: &mut Params, peer: bool, id: &str) -> Result<Box<dyn Encoder>> {
    use std::ops::Bound::{Excluded, Included};
    let target_laplacian = p.f64_in("target_laplacian", 10.0, (Excluded(0.0), Included(1e6)))?;
    p.finish(id)?;
    Ok(Box::new(WindowedSh { target_laplacian, peer_band_energy: peer }))
}
/// Builds the `sh2_windowed` encoder from its settings: SH L2, Laplacian window (peer SHL2W, full
/// band energy). An unknown or out-of-range setting is an error.
pub fn build_sh2_windowed(p: &mut Params) -> Result<Box<dyn Encoder>> {
    windowed(p, false, "sh2_windowed")
}
/// Builds the `sh2_windowed_peer` encoder from its settings: SH L2 windowed as the peer (its
/// band-energy slip). An unknown or out-of-range setting is an error.
pub fn build_sh2_windowed_peer(p: &mut Params) -> Result<Box<dyn Encoder>> {
    windowed(p, true, "sh2_windowed_peer")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::sh::delta_light;
    use crate::math::sh4::Sh25;
    use crate::reference::radiance::{RadianceSample, RadianceSource};
    use std::f64::consts::PI;
    use std::sync::Arc;

    /// A source that only knows SH through band 4 (what sh4 reads).
    #[derive(Debug)]
    struct Band4(Sh25);
    impl RadianceSource for Band4 {
        fn sh4(&self) -> &Sh25 {
            &self.0
        }
        fn radiance(&self, _: DVec3) -> Rgb {
            unreachable!()
        }
        fn samples(&self) -> &[RadianceSample] {
            unreachable!()
        }
        fn irradiance(&self, _: DVec3) -> Rgb {
            unreachable!()
        }
        fn irradiance_latlong(&self, _: usize, _: usize) -> Arc<Vec<Rgb>> {
            unreachable!()
        }
    }

    /// A delta light of unit intensity along d: SH irradiance at n = d is the truncated Legendre
    /// series Σ_l Â_l (2l+1)/(4π): (1 + 2 + 5/4 + 0 − 9/24)/(4π) through band 4.
    #[test]
    fn delta_light_peak_is_the_legendre_series() {
        let d = DVec3::new(0.3, 0.5, 0.81).normalize();
        let mut full = Sh25::ZERO;
        for (c, y) in full.0.iter_mut().zip(basis4(d)) {
            *c = Rgb::splat(y);
        }
        let sh9 = delta_light(d, Rgb::ONE);
        let src = Band4(full);
        let input = FitInput { radiance: Some(&src), ..FitInput::sphere(&sh9) };
        let want = (1.0 + 2.0 + 1.25 - 9.0 / 24.0) / (4.0 * PI);
        assert!((Sh4Encoder.fit(&input).irradiance(d).x - want).abs() < 1e-14);
        let want3 = (1.0 + 2.0 + 1.25) / (4.0 * PI);
        assert!((Sh3Encoder.fit(&input).irradiance(d).x - want3).abs() < 1e-14);
    }

    /// λ by hand: luminance SH with B₁ = 0 and one band-2 coefficient c: 36c²/(1 + 36λ)² = T²
    /// gives λ = (6|c|/T − 1)/36. The peer's slip drops c when it is L₂,₋₂ (index 4): λ = 0.
    #[test]
    fn window_strength_by_hand() {
        let e = WindowedSh { target_laplacian: 10.0, peer_band_energy: false };
        let p = WindowedSh { target_laplacian: 10.0, peer_band_energy: true };
        let mut lum = [0.0; N_SH];
        lum[0] = 3.0;
        lum[6] = 20.0;
        let want = (6.0 * 20.0 / 10.0 - 1.0) / 36.0;
        assert!((e.lambda(&lum) - want).abs() < 1e-14 * want, "{}", e.lambda(&lum));
        assert!((p.lambda(&lum) - want).abs() < 1e-14 * want);
        lum[6] = 0.0;
        lum[4] = 20.0;
        assert!((e.lambda(&lum) - want).abs() < 1e-14 * want);
        assert_eq!(p.lambda(&lum), 0.0);
        lum[4] = 1.0; // 36 < 100: below the target
        assert_eq!(e.lambda(&lum), 0.0);
        lum[4] = 1e150;
        assert!(e.lambda(&lum).is_finite() && e.lambda(&lum) > 0.0);
    }
}
