//! HHD from linear SH: the talk's closed form (FORMULAS §8), per channel.
//!
//! With b_c = (2/√π)·l₀ and b = (2/√π)·(L1 vector)/√3, an HHD has b_c = 2C_a + C_d,
//! b = C_a N + C_d d, and I_z = b·N. From |b − C_a N|² = (b_c − 2C_a)²:
//! 3C_a² − 2(2b_c − I_z)C_a + (b_c² − |b|²) = 0, and C_a is the smaller root
//! ((2b_c − I_z) − √Δ)/3 (the larger one is C_a + (4 − 2 d·N)C_d/3 ≥ C_a).
//!
//! **The discriminant cannot be negative here.** With I_z = b·N (the talk's line), substituting
//! |b|² = I_z² + |b⊥|² gives Δ = (2b_c − I_z)² − 3(b_c² − |b|²) = (b_c − 2I_z)² + 3|b⊥|² ≥ 0
//! (tested below); rounding is clamped at 0. A bake's exact I_z that differs from b·N (SH of a
//! radiance that is not hemispherical) is not used: I_z is taken from the SH, as in the talk.
//!
//! **One direction for RGB.** The model has one d: the per-channel residuals b − C_a N are
//! summed with Rec.709 weights and normalised; each channel's C_d is its residual's component
//! along d, clamped ≥ 0. C_a is clamped ≥ 0 (a non-physical SH). For the SH of an HHD every
//! channel's residual is C_d·d, so the round trip is exact.
//!
//! **Degenerate.** If the summed residual vanishes (no directional part: the hemisphere light,
//! or black) d = N and C_d = 0.

use super::model::{Basis, Model};
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use glam::DVec3;
use std::f64::consts::PI;

use crate::math::colour::REC709;

/// The closed form on one channel, before any clamping: the smaller root C_a, and b and I_z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChannelSolve {
    /// ((2b_c − I_z) − √Δ)/3 with Δ = (b_c − 2I_z)² + 3|b⊥|² (rounding clamped at 0).
    pub c_a: f64,
    /// b = (2/√π)·(L1 vector)/√3 = C_a N + C_d d for an HHD.
    pub b: DVec3,
    /// I_z = b·N.
    pub i_z: f64,
}

/// The talk's closed form for one channel of linear radiance SH: l₀ and the band-1 vector
/// (−l₁,₁, −l₁,₋₁, l₁,₀), about the unit normal N. Every HHD-from-linear-SH fit in the crate
/// goes through here: [`hhd_from_linear_sh`] per RGB channel, and the probe path's luminance
/// HHD (`encoders::probe_occlusion`), which clamps C_a to [0, I_z].
pub fn solve_channel(l0: f64, l1: DVec3, n: DVec3) -> ChannelSolve {
    let s = 2.0 / PI.sqrt();
    let b_c = s * l0;
    let b = l1 * (s / 3f64.sqrt());
    let i_z = b.dot(n);
    let b_perp = b - n * i_z;
    let disc = ((b_c - 2.0 * i_z).powi(2) + 3.0 * b_perp.length_squared()).max(0.0);
    ChannelSolve { c_a: ((2.0 * b_c - i_z) - disc.sqrt()) / 3.0, b, i_z }
}

/// The HHD whose linear radiance SH is `sh` (bands 0–1 are read), about the unit normal N.
pub fn hhd_from_linear_sh(sh: &Sh9, normal: DVec3) -> Model {
    let n = normal.normalize();
    let mut c_a = Rgb::ZERO;
    let mut resid = [DVec3::ZERO; 3];
    let mut dir = DVec3::ZERO;
    for c in 0..3 {
        let ch = solve_channel(sh[0][c], sh.l1_vector(c), n);
        let ca = ch.c_a.max(0.0);
        c_a[c] = ca;
        resid[c] = ch.b - n * ca;
        dir += resid[c] * REC709[c];
    }
    let d = dir.try_normalize().filter(|d| d.is_finite()).unwrap_or(n);
    let c_d = Rgb::from_array(std::array::from_fn(|c| resid[c].dot(d).max(0.0)));
    Model { basis: Basis::Hhd, normal: n, c_a, c_d, d }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::encoders::lightmap::model::linear_sh_of;
    use crate::math::test_rng::Rng;

    /// The discriminant identity Δ = (b_c − 2I_z)² + 3|b⊥|² for I_z = b·N, on random data.
    #[test]
    fn discriminant_is_a_sum_of_squares() {
        let mut r = Rng::new(4);
        for _ in 0..200 {
            let (b_c, b, n) = (r.next() * 3.0, DVec3::new(r.next(), r.next(), r.next()), r.unit());
            let i_z = b.dot(n);
            let lhs = (2.0 * b_c - i_z).powi(2) - 3.0 * (b_c * b_c - b.length_squared());
            let rhs = (b_c - 2.0 * i_z).powi(2) + 3.0 * (b - n * i_z).length_squared();
            assert!((lhs - rhs).abs() < 1e-12 * (1.0 + lhs.abs()));
        }
    }

    /// H6: HHD → linear SH → HHD returns the input, for random HHDs with d above the horizon
    /// and below it.
    #[test]
    fn round_trip_returns_the_input() {
        let mut r = Rng::new(21);
        let mut worst = (0.0f64, 0.0f64);
        for _ in 0..2000 {
            let n = r.unit();
            let d = r.unit();
            let col = |r: &mut Rng| Rgb::new(r.next().abs(), r.next().abs(), r.next().abs()) * 3.0;
            let m = Model { basis: Basis::Hhd, normal: n, c_a: col(&mut r), c_d: col(&mut r) + Rgb::splat(0.01), d };
            let back = hhd_from_linear_sh(&linear_sh_of(&m), n);
            worst.0 = worst.0.max((back.c_a - m.c_a).abs().max_element()).max((back.c_d - m.c_d).abs().max_element());
            worst.1 = worst.1.max((back.d - d).length());
        }
        assert!(worst.0 < 1e-10 && worst.1 < 1e-10, "{worst:?}");
    }

    #[test]
    fn hemisphere_light_and_black_have_no_direction() {
        let n = DVec3::new(0.0, 1.0, 0.0);
        let m = Model { basis: Basis::Hhd, normal: n, c_a: Rgb::new(1.0, 2.0, 3.0), c_d: Rgb::ZERO, d: n };
        let back = hhd_from_linear_sh(&linear_sh_of(&m), n);
        assert!((back.c_a - m.c_a).abs().max_element() < 1e-14 && back.c_d.abs().max_element() < 1e-14);
        let z = hhd_from_linear_sh(&Sh9::ZERO, n);
        assert_eq!((z.c_a, z.c_d, z.d), (Rgb::ZERO, Rgb::ZERO, n));
    }
}
