//! Real spherical harmonics through band 4 (25 coefficients), for the encodings that need more
//! than [`crate::math::sh`]'s bands 0–2 (SH L3/L4 irradiance, the peer tool's `SHL3`/`SHL4`).
//!
//! Same convention as FORMULAS §2 and `sh.rs`, extended: index l² + l + m, zonal axis z,
//! Condon–Shortley phase, Y_lm = √2 K_lm P_l^|m|(z) cos(mϕ) for m > 0, √2 K_lm P_l^|m|(z)
//! sin(|m|ϕ) for m < 0, K_l0 P_l(z) for m = 0, with K_lm = √((2l+1)/4π · (l−|m|)!/(l+|m|)!)
//! and ϕ the azimuth about z. Bands 0–2 equal [`crate::math::sh::basis`] (tested).
//!
//! Band scales for E/π (Ramamoorthi–Hanrahan 2001, eq. 8 divided by π): Â = (1, 2/3, 1/4, 0,
//! −1/24). The clamped cosine has no odd bands above 1, so band 3 adds nothing to irradiance.

use crate::math::colour::Rgb;
use crate::math::sh::{Sh9, N_SH};
use glam::DVec3;
use std::f64::consts::PI;

/// Number of coefficients through band 4.
pub const N_SH4: usize = 25;

/// Normalised cosine-lobe band scales Â_l for l = 0..4 (E/π), see the module doc.
pub const BAND_SCALE4: [f64; 5] = [1.0, 2.0 / 3.0, 0.25, 0.0, -1.0 / 24.0];

/// The band l of coefficient index i (i < 25).
pub const fn band_of4(i: usize) -> usize {
    match i {
        0 => 0,
        1..=3 => 1,
        4..=8 => 2,
        9..=15 => 3,
        _ => 4,
    }
}

/// The 25 basis functions at unit direction `d`, index l² + l + m.
pub fn basis4(d: DVec3) -> [f64; N_SH4] {
    let (x, y, z) = (d.x, d.y, d.z);
    // Re and Im of (x + iy)^m = sin^m θ · (cos mϕ, sin mϕ).
    let mut cm = [1.0f64; 5];
    let mut sm = [0.0f64; 5];
    for m in 1..5 {
        cm[m] = cm[m - 1] * x - sm[m - 1] * y;
        sm[m] = sm[m - 1] * x + cm[m - 1] * y;
    }
    let mut out = [0.0; N_SH4];
    for m in 0..5usize {
        // P̃_l^m(z) = P_l^m(z) / sin^m θ, by the upward recurrence in l (Condon–Shortley phase in
        // P̃_m^m = (−1)^m (2m − 1)!!).
        let mut pmm = 1.0;
        for k in 0..m {
            pmm *= -((2 * k + 1) as f64);
        }
        let (mut p_prev, mut p) = (0.0, pmm);
        for l in m..5usize {
            if l == m + 1 {
                p_prev = p;
                p = z * (2 * m + 1) as f64 * pmm;
            } else if l > m + 1 {
                let next = ((2 * l - 1) as f64 * z * p - (l + m - 1) as f64 * p_prev) / (l - m) as f64;
                p_prev = p;
                p = next;
            }
            let ratio: f64 = ((l - m + 1)..=(l + m)).map(|v| v as f64).product();
            let k = ((2 * l + 1) as f64 / (4.0 * PI) / ratio).sqrt();
            let c = l * l + l;
            if m == 0 {
                out[c] = k * p;
            } else {
                let s2 = std::f64::consts::SQRT_2 * k * p;
                out[c + m] = s2 * cm[m];
                out[c - m] = s2 * sm[m];
            }
        }
    }
    out
}

/// RGB coefficients of SH through band 4 (radiance or E/π, as the caller says).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sh25(pub [Rgb; N_SH4]);

impl Default for Sh25 {
    fn default() -> Self {
        Sh25::ZERO
    }
}

impl Sh25 {
    /// All coefficients zero.
    pub const ZERO: Sh25 = Sh25([Rgb::ZERO; N_SH4]);

    /// Bands 0–2 from an [`Sh9`], bands 3–4 zero.
    pub fn from_sh9(s: &Sh9) -> Self {
        let mut out = Sh25::ZERO;
        out.0[..N_SH].copy_from_slice(&s.0);
        out
    }

    /// Bands 0–2 as an [`Sh9`].
    pub fn to_sh9(self) -> Sh9 {
        Sh9(std::array::from_fn(|i| self.0[i]))
    }

    /// Σ c_i Y_i(d) over bands 0..=`max_band`.
    pub fn eval(&self, d: DVec3, max_band: usize) -> Rgb {
        let y = basis4(d);
        let n = (max_band.min(4) + 1).pow(2);
        let mut acc = Rgb::ZERO;
        for (c, yi) in self.0[..n].iter().zip(y) {
            acc += *c * yi;
        }
        acc
    }

    /// Multiplies band l by Â_l (radiance SH → E/π SH) and zeroes the bands above `max_band`.
    pub fn convolve_cosine(&self, max_band: usize) -> Sh25 {
        let mut out = *self;
        for (i, c) in out.0.iter_mut().enumerate() {
            let l = band_of4(i);
            *c *= if l <= max_band { BAND_SCALE4[l] } else { 0.0 };
        }
        out
    }

    /// True if every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|c| c.is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quadrature::gauss_legendre;
    use crate::math::sh::basis;

    #[test]
    fn bands_0_to_2_equal_the_l2_basis() {
        for d in [DVec3::new(0.3, -0.5, 0.81), DVec3::new(-0.9, 0.1, 0.2), DVec3::Z, DVec3::NEG_X] {
            let d = d.normalize();
            let (a, b) = (basis4(d), basis(d));
            for i in 0..N_SH {
                assert!((a[i] - b[i]).abs() < 1e-14, "{i}: {} vs {}", a[i], b[i]);
            }
        }
    }

    /// Orthonormality by a product rule exact for polynomials of degree ≤ 8 on the sphere
    /// (Gauss–Legendre in z, equal steps in ϕ).
    #[test]
    fn basis_is_orthonormal() {
        let gl = gauss_legendre(10);
        let nphi = 20;
        let mut g = [[0.0f64; N_SH4]; N_SH4];
        for &(z, w) in &gl {
            for k in 0..nphi {
                let ph = 2.0 * PI * k as f64 / nphi as f64;
                let r = (1.0 - z * z).sqrt();
                let y = basis4(DVec3::new(r * ph.cos(), r * ph.sin(), z));
                let wt = w * 2.0 * PI / nphi as f64;
                for i in 0..N_SH4 {
                    for j in 0..N_SH4 {
                        g[i][j] += wt * y[i] * y[j];
                    }
                }
            }
        }
        for (i, row) in g.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 1e-12, "G[{i}][{j}] = {v}");
            }
        }
    }

    /// Funk–Hecke check of Â_4: E/π of a delta light at the pole is max(0, z)/π; its band-4
    /// coefficient Â_4·Y_40(z-axis) must equal (1/π)∫ max(0, z) Y_40 dω = ∫₀¹ z P₄(z) dz · 2K₄₀,
    /// and ∫₀¹ z P₄(z) dz = −1/48 (closed form: P₄ = (35z⁴ − 30z² + 3)/8).
    #[test]
    fn band_4_scale_is_funk_hecke() {
        let k40 = (9.0 / (4.0 * PI)).sqrt();
        let y40_pole = k40; // P₄(1) = 1
        let projected = 2.0 * k40 * (-1.0 / 48.0);
        assert!((BAND_SCALE4[4] * y40_pole - projected).abs() < 1e-15);
        // and by quadrature of the polynomial
        let gl = gauss_legendre(8);
        let q: f64 = gl
            .iter()
            .map(|&(t, w)| {
                let z = 0.5 * (t + 1.0);
                0.5 * w * z * (35.0 * z.powi(4) - 30.0 * z * z + 3.0) / 8.0
            })
            .sum();
        assert!((q + 1.0 / 48.0).abs() < 1e-15, "{q}");
    }
}
