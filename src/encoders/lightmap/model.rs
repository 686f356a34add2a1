//! The AHD and HHD lightmap models (FORMULAS §7, §8; 2018 brief, hemispherical-lighting talk).
//!
//! - AHD: I(n) = C_a + C_d·max(0, n·d).
//! - HHD: I(n) = C_a·H(n) + C_d·max(0, n·d), with the hemisphere light H(n) = (1 + n·N)/2.
//!
//! I is irradiance as E/π. `normal` is the surface normal N (HHD's hemisphere axis and the
//! IrradZ axis, I_z = I(N)); on a sphere probe with no surface it is the axis the encoder chose
//! (see `fit`).

use crate::math::colour::Rgb;
use crate::math::sh::{delta_light, k, Sh9};
use glam::DVec3;
use std::f64::consts::PI;

/// Which ambient term the model has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Basis {
    /// Ambient + highlight direction: a constant C_a.
    Ahd,
    /// Hemisphere + highlight direction: C_a·H(n), H(n) = (1 + n·N)/2.
    Hhd,
}

/// One fitted texel: basis, surface normal N, ambient colour C_a, directional colour C_d and
/// the highlight direction d (unit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Model {
    /// The ambient term: constant (AHD) or hemisphere (HHD).
    pub basis: Basis,
    /// The surface normal N (unit).
    pub normal: DVec3,
    /// Ambient colour C_a (E/π).
    pub c_a: Rgb,
    /// Directional colour C_d (E/π facing d).
    pub c_d: Rgb,
    /// Unit highlight direction d.
    pub d: DVec3,
}

impl Model {
    /// The all-zero model (black in, black out).
    pub fn black(basis: Basis, normal: DVec3) -> Self {
        Model { basis, normal, c_a: Rgb::ZERO, c_d: Rgb::ZERO, d: normal }
    }

    /// The ambient basis function at n: 1 (AHD) or H(n) = (1 + n·N)/2 (HHD).
    #[inline]
    pub fn ambient_basis(&self, n: DVec3) -> f64 {
        match self.basis {
            Basis::Ahd => 1.0,
            Basis::Hhd => 0.5 * (1.0 + n.dot(self.normal)),
        }
    }

    /// E/π at unit normal n (FORMULAS §7, §8).
    #[inline]
    pub fn irradiance(&self, n: DVec3) -> Rgb {
        self.c_a * self.ambient_basis(n) + self.c_d * n.dot(self.d).max(0.0)
    }

    /// I_z = I(N), the irradiance at the surface normal (both bases have value C_a there).
    pub fn i_z(&self) -> Rgb {
        self.irradiance(self.normal)
    }
}

/// The model's linear radiance SH (bands 0–1, band 2 zero), FORMULAS §8: the radiance whose
/// irradiance is the model. HHD: a hemisphere light of radiance C_a over {ω·N ≥ 0} plus a
/// delta light of intensity π·C_d along d. AHD: a uniform sphere of radiance C_a plus the same
/// delta light. Hemisphere of radiance C_a: l₀ = C_a·2π·Y₀₀ = C_a√π, L1 vector = C_a·π·Y₁·N
/// (∫_{z≥0} z dω = π); so b_c = (2/√π)l₀ = 2C_a + C_d and b = C_a N + C_d d.
pub fn linear_sh_of(model: &Model) -> Sh9 {
    let mut out = delta_light(model.d, model.c_d * PI).truncate(1);
    match model.basis {
        Basis::Ahd => out[0] += model.c_a * (4.0 * PI).sqrt(),
        Basis::Hhd => {
            out[0] += model.c_a * PI.sqrt();
            let v = model.normal * (PI * k::Y1);
            // The L1 vector (−l₁₁, −l₁₋₁, l₁₀) = v.
            out[3] -= model.c_a * v.x;
            out[1] -= model.c_a * v.y;
            out[2] += model.c_a * v.z;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quadrature::gauss_legendre;

    /// ∫ f Y_i over the sphere by Gauss–Legendre in t = ω·axis, split at t = 0 (where the
    /// hemisphere light about `axis` steps), × the trapezoid rule in azimuth.
    fn project(axis: DVec3, f: impl Fn(DVec3) -> f64) -> [f64; 9] {
        let mut out = [0.0; 9];
        let nphi = 64;
        let (u, v) = axis.any_orthonormal_pair();
        let half: Vec<(f64, f64)> = gauss_legendre(16).into_iter().map(|(x, w)| (0.5 * x + 0.5, 0.5 * w)).collect();
        for (x, w) in half.iter().map(|&(x, w)| (x, w)).chain(half.iter().map(|&(x, w)| (-x, w))) {
            let s = (1.0 - x * x).sqrt();
            for p in 0..nphi {
                let phi = 2.0 * PI * p as f64 / nphi as f64;
                let d = axis * x + (u * phi.cos() + v * phi.sin()) * s;
                let y = crate::math::sh::basis(d);
                let v = f(d) * w * 2.0 * PI / nphi as f64;
                for i in 0..9 {
                    out[i] += v * y[i];
                }
            }
        }
        out
    }

    /// The hemisphere light's SH from its definition (quadrature of the step function), and the
    /// identity b_c = 2C_a + C_d, b = C_a N + C_d d of FORMULAS §8.
    #[test]
    fn linear_sh_of_hhd_is_hemisphere_plus_delta() {
        let n = DVec3::new(0.3, 0.9, -0.2).normalize();
        let d = DVec3::new(0.7, 0.5, 0.3).normalize();
        let m = Model { basis: Basis::Hhd, normal: n, c_a: Rgb::new(1.0, 2.0, 0.5), c_d: Rgb::new(0.3, 0.1, 2.0), d };
        let sh = linear_sh_of(&m);
        let hemi = project(n, |w| if w.dot(n) >= 0.0 { 1.0 } else { 0.0 });
        let y = crate::math::sh::basis(d);
        for i in 0..4 {
            let want = m.c_a * hemi[i] + m.c_d * (PI * y[i]);
            assert!((sh[i] - want).abs().max_element() < 1e-13, "{i}: {} vs {want}", sh[i]);
        }
        for i in 4..9 {
            assert_eq!(sh[i], Rgb::ZERO);
        }
        let b_c = sh[0] * (2.0 / PI.sqrt());
        assert!((b_c - (m.c_a * 2.0 + m.c_d)).abs().max_element() < 1e-14);
        for c in 0..3 {
            let b = sh.l1_vector(c) * (2.0 / PI.sqrt() / 3f64.sqrt());
            assert!((b - (n * m.c_a[c] + d * m.c_d[c])).length() < 1e-14);
        }
    }

    /// The model's irradiance equals the cosine convolution of its radiance: for the hemisphere
    /// light, E/π = (1 + n·N)/2 exactly (bands 0–1 only), so the linear SH reproduces it.
    #[test]
    fn irradiance_of_linear_sh_matches_the_model_for_hemisphere_light() {
        let n = DVec3::new(-0.4, 0.2, 0.8).normalize();
        let m = Model { basis: Basis::Hhd, normal: n, c_a: Rgb::ONE, c_d: Rgb::ZERO, d: n };
        let e = linear_sh_of(&m).convolve_cosine();
        for w in [n, -n, DVec3::X, DVec3::new(0.3, -0.3, 0.9).normalize()] {
            assert!((e.eval(w) - m.irradiance(w)).abs().max_element() < 1e-14);
        }
        assert!((m.i_z() - Rgb::ONE).abs().max_element() < 1e-15);
    }
}
