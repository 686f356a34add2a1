//! Real spherical harmonics of bands 0–2 and the cosine convolution.
//!
//! Basis and sign convention: FORMULAS §2 (Condon–Shortley phase, the authors' convention),
//! for a unit direction (x, y, z) in world space. The zonal axis of the basis is z; the maps'
//! up is y. Nothing here assumes which way is up.
//!
//! Band scales: FORMULAS §3, Â = (1, 2/3, 1/4) for E/π (Ramamoorthi–Hanrahan 2001).

use crate::math::colour::Rgb;
use glam::DVec3;
use std::f64::consts::PI;
use std::ops::{Add, Index, IndexMut, Mul, Sub};

/// Number of coefficients of SH through band 2.
pub const N_SH: usize = 9;

/// Normalised cosine-lobe band scales Â_l for l = 0, 1, 2: E/π = Σ Â_l L_lm Y_lm (FORMULAS §3).
pub const BAND_SCALE: [f64; 3] = [1.0, 2.0 / 3.0, 0.25];

/// The band l of coefficient index i.
pub const fn band_of(i: usize) -> usize {
    match i {
        0 => 0,
        1..=3 => 1,
        _ => 2,
    }
}

/// Normalisation constants of the basis (FORMULAS §2 table).
pub mod k {
    /// ½√(1/π)
    pub const Y00: f64 = 0.282_094_791_773_878_14;
    /// √(3/4π)
    pub const Y1: f64 = 0.488_602_511_902_919_9;
    /// ½√(15/π)
    pub const Y2_XY: f64 = 1.092_548_430_592_079_2;
    /// ¼√(5/π)
    pub const Y20: f64 = 0.315_391_565_252_520_05;
    /// ¼√(15/π)
    pub const Y22: f64 = 0.546_274_215_296_039_6;
}

/// The nine basis functions at unit direction `d` (FORMULAS §2), indices as in the table there.
#[inline]
pub fn basis(d: DVec3) -> [f64; N_SH] {
    let (x, y, z) = (d.x, d.y, d.z);
    [
        k::Y00,
        -k::Y1 * y,
        k::Y1 * z,
        -k::Y1 * x,
        k::Y2_XY * x * y,
        -k::Y2_XY * y * z,
        k::Y20 * (3.0 * z * z - 1.0),
        -k::Y2_XY * x * z,
        k::Y22 * (x * x - y * y),
    ]
}

/// RGB coefficients of SH through band 2. Whether it holds radiance or irradiance (E/π) is
/// the caller's convention; [`Sh9::convolve_cosine`] turns radiance into E/π.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Sh9(pub [Rgb; N_SH]);

impl Sh9 {
    /// All coefficients zero.
    pub const ZERO: Sh9 = Sh9([Rgb::ZERO; N_SH]);

    /// Evaluates Σ c_i Y_i(d).
    #[inline]
    pub fn eval(&self, d: DVec3) -> Rgb {
        let y = basis(d);
        let mut acc = Rgb::ZERO;
        for (c, yi) in self.0.iter().zip(y) {
            acc += *c * yi;
        }
        acc
    }

    /// Multiplies band l by Â_l (radiance SH → E/π SH), FORMULAS §3.
    pub fn convolve_cosine(&self) -> Sh9 {
        let mut out = *self;
        for (i, c) in out.0.iter_mut().enumerate() {
            *c *= BAND_SCALE[band_of(i)];
        }
        out
    }

    /// Keeps bands 0..=max_band and zeroes the rest.
    pub fn truncate(&self, max_band: usize) -> Sh9 {
        let mut out = *self;
        for (i, c) in out.0.iter_mut().enumerate() {
            if band_of(i) > max_band {
                *c = Rgb::ZERO;
            }
        }
        out
    }

    /// The L1 band of one channel as a vector in world xyz: (−L₁,₁, −L₁,₋₁, L₁,₀), the
    /// direction of the linear moment (FORMULAS §4), unnormalised.
    pub fn l1_vector(&self, channel: usize) -> DVec3 {
        DVec3::new(-self.0[3][channel], -self.0[1][channel], self.0[2][channel])
    }

    /// The L1 band as a vector in world xyz, with channels weighted by `w` (FORMULAS §4).
    pub fn l1_vector_weighted(&self, w: Rgb) -> DVec3 {
        (0..3).map(|c| self.l1_vector(c) * w[c]).sum()
    }

    /// One channel as nine scalars.
    pub fn channel(&self, c: usize) -> [f64; N_SH] {
        std::array::from_fn(|i| self.0[i][c])
    }

    /// Sets one channel from nine scalars.
    pub fn set_channel(&mut self, c: usize, v: &[f64; N_SH]) {
        for (coeff, &x) in self.0.iter_mut().zip(v) {
            coeff[c] = x;
        }
    }

    /// True if every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|c| c.is_finite())
    }
}

impl Index<usize> for Sh9 {
    type Output = Rgb;
    fn index(&self, i: usize) -> &Rgb {
        &self.0[i]
    }
}
impl IndexMut<usize> for Sh9 {
    fn index_mut(&mut self, i: usize) -> &mut Rgb {
        &mut self.0[i]
    }
}
impl Add for Sh9 {
    type Output = Sh9;
    fn add(self, o: Sh9) -> Sh9 {
        Sh9(std::array::from_fn(|i| self.0[i] + o.0[i]))
    }
}
impl Sub for Sh9 {
    type Output = Sh9;
    fn sub(self, o: Sh9) -> Sh9 {
        Sh9(std::array::from_fn(|i| self.0[i] - o.0[i]))
    }
}
impl Mul<f64> for Sh9 {
    type Output = Sh9;
    fn mul(self, s: f64) -> Sh9 {
        Sh9(std::array::from_fn(|i| self.0[i] * s))
    }
}

/// The SH projection of a single directional (delta) light of radiant intensity `e`
/// (so that E/π at n facing it is e·(n·d)/π), i.e. c_i = e·Y_i(d).
pub fn delta_light(d: DVec3, e: Rgb) -> Sh9 {
    let y = basis(d);
    Sh9(std::array::from_fn(|i| e * y[i]))
}

/// The SH projection of a constant environment of radiance `c`: only L₀₀ = c·√(4π).
pub fn constant(c: Rgb) -> Sh9 {
    let mut s = Sh9::ZERO;
    s.0[0] = c * (4.0 * PI).sqrt();
    s
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // Gram matrices are indexed by (a, b)
mod tests {
    use super::*;
    use crate::math::convention::direction;

    /// Fibonacci-free brute quadrature over (θ, φ) midpoint grid: orthonormality of the basis.
    #[test]
    fn basis_is_orthonormal() {
        let (nt, np) = (400, 200);
        let mut g = [[0.0f64; N_SH]; N_SH];
        for j in 0..np {
            let (p0, p1) = (PI * j as f64 / np as f64, PI * (j + 1) as f64 / np as f64);
            let w = (2.0 * PI / nt as f64) * (p0.cos() - p1.cos());
            for i in 0..nt {
                let t = 2.0 * PI * ((i as f64 + 0.5) / nt as f64 - 0.5);
                let y = basis(direction(t, 0.5 * (p0 + p1)));
                for a in 0..N_SH {
                    for b in 0..N_SH {
                        g[a][b] += w * y[a] * y[b];
                    }
                }
            }
        }
        for a in 0..N_SH {
            for b in 0..N_SH {
                let want = if a == b { 1.0 } else { 0.0 };
                assert!((g[a][b] - want).abs() < 1e-3, "G[{a}][{b}] = {}", g[a][b]);
            }
        }
    }

    #[test]
    fn constants_match_closed_forms() {
        assert!((k::Y00 - 0.5 * (1.0 / PI).sqrt()).abs() < 1e-16);
        assert!((k::Y1 - (3.0 / (4.0 * PI)).sqrt()).abs() < 1e-16);
        assert!((k::Y2_XY - 0.5 * (15.0 / PI).sqrt()).abs() < 1e-15);
        assert!((k::Y20 - 0.25 * (5.0 / PI).sqrt()).abs() < 1e-16);
        assert!((k::Y22 - 0.25 * (15.0 / PI).sqrt()).abs() < 1e-16);
    }

    /// A constant environment of radiance 1 gives E/π = 1 everywhere (FORMULAS §1).
    #[test]
    fn constant_environment_gives_one() {
        let e = constant(Rgb::ONE).convolve_cosine();
        for d in [DVec3::X, DVec3::NEG_Y, DVec3::new(0.6, 0.0, 0.8)] {
            assert!((e.eval(d) - Rgb::ONE).abs().max_element() < 1e-15);
        }
    }

    /// Addition theorem: Σ_m Y_lm(a)Y_lm(b) = (2l+1)/(4π)·P_l(a·b); checks signs and constants
    /// of every band independently of the table.
    #[test]
    fn addition_theorem() {
        let a = DVec3::new(0.3, -0.5, 0.81).normalize();
        let b = DVec3::new(-0.7, 0.2, 0.4).normalize();
        let (ya, yb) = (basis(a), basis(b));
        let t = a.dot(b);
        let p = [1.0, t, 0.5 * (3.0 * t * t - 1.0)];
        for l in 0..3 {
            let s: f64 = (0..N_SH).filter(|&i| band_of(i) == l).map(|i| ya[i] * yb[i]).sum();
            let want = (2 * l + 1) as f64 / (4.0 * PI) * p[l];
            assert!((s - want).abs() < 1e-14, "band {l}");
        }
    }

    #[test]
    fn l1_vector_points_at_a_delta_light() {
        let d = DVec3::new(0.2, 0.9, -0.3).normalize();
        let s = delta_light(d, Rgb::new(1.0, 2.0, 3.0));
        for c in 0..3 {
            assert!((s.l1_vector(c).normalize() - d).length() < 1e-14);
        }
    }
}
