//! Rotation of SH bands 0–2 (FORMULAS §2 basis, Condon–Shortley phase).
//!
//! A rotation R turns the lighting: a light arriving from d arrives from R·d afterwards, so the
//! rotated radiance is g(ω) = f(Rᵀω). Each band rotates on its own:
//!
//! - band 0 is invariant;
//! - band 1 is a vector: Σ_m c₁ₘY₁ₘ(ω) = k₁·v·ω with v = (−c₁,₁, −c₁,₋₁, c₁,₀), and v′ = R·v;
//! - band 2 is a traceless quadratic form: Σ_m c₂ₘY₂ₘ(ω) = ωᵀQω on the sphere, and Q′ = R·Q·Rᵀ.
//!
//! Both follow from g(ω) = f(Rᵀω) (derived here, not quoted; the tests check them against
//! rotating light directions). This is exact, with no sampling: a 3×3 and a 5×5 matrix per
//! rotation, applied to all three channels.

use crate::math::colour::Rgb;
use crate::math::sh::{k, Sh9};
use glam::{DMat3, DQuat, DVec3};

/// The band-1 and band-2 matrices of one rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShRotation {
    /// c′[1 + a] = Σ_b band1[a][b]·c[1 + b].
    band1: [[f64; 3]; 3],
    /// c′[4 + a] = Σ_b band2[a][b]·c[4 + b].
    band2: [[f64; 5]; 5],
}

/// Band-2 coefficients (indices 4..=8) → symmetric traceless Q with ωᵀQω = Σ c·Y on the sphere.
/// On the sphere 3z² − 1 = 2z² − x² − y².
fn quadratic_form(c: [f64; 5]) -> DMat3 {
    let h = 0.5 * k::Y2_XY;
    let (qxy, qyz, qxz) = (h * c[0], -h * c[1], -h * c[3]);
    let qxx = -k::Y20 * c[2] + k::Y22 * c[4];
    let qyy = -k::Y20 * c[2] - k::Y22 * c[4];
    let qzz = 2.0 * k::Y20 * c[2];
    DMat3::from_cols(DVec3::new(qxx, qxy, qxz), DVec3::new(qxy, qyy, qyz), DVec3::new(qxz, qyz, qzz))
}

/// The inverse of [`quadratic_form`] for a symmetric traceless Q.
fn coefficients(q: DMat3) -> [f64; 5] {
    let h = 0.5 * k::Y2_XY;
    // Read the symmetric part, so rounding asymmetry does not leak in.
    let (qxy, qyz, qxz) =
        (0.5 * (q.x_axis.y + q.y_axis.x), 0.5 * (q.y_axis.z + q.z_axis.y), 0.5 * (q.x_axis.z + q.z_axis.x));
    [qxy / h, -qyz / h, q.z_axis.z / (2.0 * k::Y20), -qxz / h, (q.x_axis.x - q.y_axis.y) / (2.0 * k::Y22)]
}

impl ShRotation {
    /// The SH rotation of the rotation matrix `r` (orthonormal, det +1).
    pub fn new(r: DMat3) -> Self {
        // Band 1: v = (−c3, −c1, c2); v′ = R v. Column b of the matrix is the image of unit c[1+b].
        let to_v = |c: [f64; 3]| DVec3::new(-c[2], -c[0], c[1]);
        let from_v = |v: DVec3| [-v.y, v.z, -v.x];
        let mut band1 = [[0.0; 3]; 3];
        for b in 0..3 {
            let mut e = [0.0; 3];
            e[b] = 1.0;
            let out = from_v(r * to_v(e));
            for a in 0..3 {
                band1[a][b] = out[a];
            }
        }
        let mut band2 = [[0.0; 5]; 5];
        for b in 0..5 {
            let mut e = [0.0; 5];
            e[b] = 1.0;
            let out = coefficients(r * quadratic_form(e) * r.transpose());
            for a in 0..5 {
                band2[a][b] = out[a];
            }
        }
        ShRotation { band1, band2 }
    }

    /// The SH rotation of a unit quaternion.
    pub fn from_quat(q: DQuat) -> Self {
        Self::new(DMat3::from_quat(q.normalize()))
    }

    /// Rotates RGB SH through band 2: the result at ω equals `sh` at Rᵀω.
    pub fn apply(&self, sh: &Sh9) -> Sh9 {
        let mut out = Sh9::ZERO;
        out[0] = sh[0];
        for a in 0..3 {
            let mut acc = Rgb::ZERO;
            for b in 0..3 {
                acc += sh[1 + b] * self.band1[a][b];
            }
            out[1 + a] = acc;
        }
        for a in 0..5 {
            let mut acc = Rgb::ZERO;
            for b in 0..5 {
                acc += sh[4 + b] * self.band2[a][b];
            }
            out[4 + a] = acc;
        }
        out
    }
}

/// A uniformly distributed random rotation from three uniforms in [0, 1) (Shoemake 1992,
/// "Uniform random rotations", Graphics Gems III).
pub fn uniform_rotation(u1: f64, u2: f64, u3: f64) -> DQuat {
    use std::f64::consts::TAU;
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let (s2, c2) = (TAU * u2).sin_cos();
    let (s3, c3) = (TAU * u3).sin_cos();
    DQuat::from_xyzw(a * s2, a * c2, b * s3, b * c3)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::sh::delta_light;

    fn rotations() -> Vec<DMat3> {
        let mut v = vec![
            DMat3::IDENTITY,
            DMat3::from_rotation_x(0.7),
            DMat3::from_rotation_y(-1.9),
            DMat3::from_rotation_z(2.4),
            DMat3::from_axis_angle(DVec3::new(0.2, -0.5, 0.84).normalize(), 1.234),
        ];
        for i in 0..8 {
            let f = |k: u32| ((i * 7 + k as usize) as f64 * 0.618_033_988_749_895).fract();
            v.push(DMat3::from_quat(uniform_rotation(f(1), f(2), f(3))));
        }
        v
    }

    fn max_diff(a: &Sh9, b: &Sh9) -> f64 {
        (0..9).map(|i| (a[i] - b[i]).abs().max_element()).fold(0.0, f64::max)
    }

    /// Rotating the SH of a delta light equals the SH of the light at the rotated direction
    /// (exact: both are closed forms).
    #[test]
    fn rotating_a_delta_light_moves_its_direction() {
        let e = Rgb::new(1.0, 0.5, 2.0);
        for r in rotations() {
            let rot = ShRotation::new(r);
            for d in [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(0.3, -0.5, 0.81).normalize()] {
                let got = rot.apply(&delta_light(d, e));
                let want = delta_light(r * d, e);
                assert!(max_diff(&got, &want) < 1e-14, "{r:?} {d}: {}", max_diff(&got, &want));
            }
        }
    }

    /// g(ω) = f(Rᵀω) for an arbitrary (non-physical) coefficient set, and the band norms are
    /// preserved.
    #[test]
    fn rotated_function_is_the_function_at_the_inverse_direction() {
        let f = Sh9(std::array::from_fn(|i| Rgb::new(0.3 * i as f64 - 1.0, (i as f64).sin(), 1.0 / (1.0 + i as f64))));
        for r in rotations() {
            let g = ShRotation::new(r).apply(&f);
            for w in [DVec3::new(0.1, 0.2, 0.97).normalize(), DVec3::NEG_X, DVec3::new(-0.6, -0.7, 0.2).normalize()] {
                assert!((g.eval(w) - f.eval(r.transpose() * w)).abs().max_element() < 1e-13);
            }
            for (lo, hi) in [(1, 4), (4, 9)] {
                let n = |s: &Sh9| (lo..hi).map(|i| s[i] * s[i]).sum::<Rgb>();
                assert!((n(&g) - n(&f)).abs().max_element() < 1e-13);
            }
        }
    }

    #[test]
    fn composition_and_quaternion_form() {
        let rs = rotations();
        let f = delta_light(DVec3::new(0.5, 0.6, 0.7).normalize(), Rgb::ONE);
        let (a, b) = (rs[5], rs[9]);
        let two = ShRotation::new(b).apply(&ShRotation::new(a).apply(&f));
        assert!(max_diff(&two, &ShRotation::new(b * a).apply(&f)) < 1e-14);
        let q = uniform_rotation(0.3, 0.6, 0.9);
        assert!((q.length() - 1.0).abs() < 1e-15);
        assert!(max_diff(&ShRotation::from_quat(q).apply(&f), &ShRotation::new(DMat3::from_quat(q)).apply(&f)) < 1e-15);
    }

    /// Uniform rotations: the image of a fixed axis is uniform on the sphere, so its mean is 0
    /// and the mean of y² is 1/3 (to Monte Carlo precision over a low-discrepancy set).
    #[test]
    fn uniform_rotation_is_isotropic() {
        let n = 4096;
        let (mut mean, mut yy) = (DVec3::ZERO, 0.0);
        for i in 0..n {
            let f = |k: f64| ((i as f64 + 0.5) * k).fract();
            let q = uniform_rotation(f(0.754_877_666_246_692_7), f(0.569_840_290_998_053_3), f(0.438_670_462_424_268));
            let v = q * DVec3::Z;
            mean += v;
            yy += v.y * v.y;
        }
        assert!((mean / n as f64).length() < 0.02, "{}", mean / n as f64);
        assert!((yy / n as f64 - 1.0 / 3.0).abs() < 0.01);
    }
}
