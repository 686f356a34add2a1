//! What a lightmap fit is fitted to: the tangent frame about N (with the search azimuth), the
//! target's inner products with the basis ([`FitTarget`]; the L2 SH irradiance as a quadratic
//! polynomial, [`QuadraticTarget`], whose moments are closed-form lune moments), and the
//! domain's constant moments.

use super::super::lune::{Angle, Moments};
use super::spec::Gram;
use crate::math::colour::Rgb;
use crate::math::gram::quadratic_form;
use crate::math::sh::{k, Sh9};
use glam::{DMat3, DVec3};
use std::sync::LazyLock;

/// The tangent frame: e3 = N, e1 the azimuth of the direction search.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// The tangent the direction search tilts towards (φ = 0).
    pub e1: DVec3,
    /// N × e1, the other tangent.
    pub e2: DVec3,
    /// The surface normal N.
    pub e3: DVec3,
}

impl Frame {
    /// The frame about unit `n` whose e1 is the tangent part of `towards` (or any tangent).
    pub fn new(n: DVec3, towards: DVec3) -> Self {
        let t = towards - n * towards.dot(n);
        let e1 = if t.length_squared() > 1e-24 * towards.length_squared().max(f64::MIN_POSITIVE) {
            t.normalize()
        } else {
            n.any_orthonormal_pair().0
        };
        let e1 = if e1.is_finite() { e1 } else { n.any_orthonormal_pair().0 };
        Frame { e1, e2: n.cross(e1), e3: n }
    }
    /// The frame turned by φ about N.
    pub fn turned(&self, phi: f64) -> Self {
        let (s, c) = phi.sin_cos();
        let e1 = self.e1 * c + self.e2 * s;
        Frame { e1, e2: self.e3.cross(e1), e3: self.e3 }
    }
    /// d at tilt θ from N towards e1.
    pub fn direction(&self, t: Angle) -> DVec3 {
        self.e1 * t.sin + self.e3 * t.cos
    }
    /// World → tangent coordinates.
    pub fn to_tangent(self, w: DVec3) -> DVec3 {
        DVec3::new(w.dot(self.e1), w.dot(self.e2), w.dot(self.e3))
    }
}

/// The fit target's inner products over the domain D, in the tangent frame.
#[cfg(test)]
pub trait FitTarget {
    /// (∫_D q, ∫_D z·q).
    fn plain(&self) -> [Rgb; 2];
    /// ∫_D max(0, n·d)·q for d = (sin θ, 0, cos θ); `m` holds the moments of D ∩ {n·d ≥ 0}.
    fn clamped(&self, t: Angle, m: &Moments) -> Rgb;
}

/// Monomials of degree ≤ 2 in tangent (x, y, z): 1, x, y, z, x², y², z², xy, xz, yz.
pub(super) const MONO: [(usize, usize, usize); 10] =
    [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (2, 0, 0), (0, 2, 0), (0, 0, 2), (1, 1, 0), (1, 0, 1), (0, 1, 1)];
/// The monomials that are even in y (the others integrate to zero against functions even in y).
pub(super) const EVEN_Y: [usize; 7] = [0, 1, 3, 4, 5, 6, 8];

/// The L2 SH irradiance as a quadratic polynomial in tangent coordinates.
#[derive(Clone, Copy, Debug)]
pub struct QuadraticTarget {
    /// Coefficients of the monomials `MONO`, RGB.
    pub coef: [Rgb; 10],
    pub(super) plain: [Rgb; 2],
}

impl QuadraticTarget {
    /// From E/π SH `e` (world space), in `frame`, over the domain with moments `domain`.
    pub fn new(e: &Sh9, frame: &Frame, domain: &Moments) -> Self {
        let r = DMat3::from_cols(frame.e1, frame.e2, frame.e3);
        let mut coef = [Rgb::ZERO; 10];
        for c in 0..3 {
            let p = r.transpose() * (e.l1_vector(c) * k::Y1);
            let m = r.transpose() * quadratic_form(e, c) * r;
            let v = [
                e[0][c] * k::Y00,
                p.x,
                p.y,
                p.z,
                m.x_axis.x,
                m.y_axis.y,
                m.z_axis.z,
                2.0 * m.y_axis.x,
                2.0 * m.z_axis.x,
                2.0 * m.z_axis.y,
            ];
            for (o, x) in coef.iter_mut().zip(v) {
                o[c] = x;
            }
        }
        let mut plain = [Rgb::ZERO; 2];
        for j in EVEN_Y {
            let (a, b, cc) = MONO[j];
            plain[0] += coef[j] * domain.get(a, b, cc);
            plain[1] += coef[j] * domain.get(a, b, cc + 1);
        }
        QuadraticTarget { coef, plain }
    }

    /// q at a tangent-space unit vector.
    #[cfg(test)]
    pub fn eval(&self, n: DVec3) -> Rgb {
        let v = [1.0, n.x, n.y, n.z, n.x * n.x, n.y * n.y, n.z * n.z, n.x * n.y, n.x * n.z, n.y * n.z];
        (0..10).map(|j| self.coef[j] * v[j]).sum()
    }
}

#[cfg(test)]
impl FitTarget for QuadraticTarget {
    fn plain(&self) -> [Rgb; 2] {
        self.plain
    }
    #[inline]
    fn clamped(&self, t: Angle, m: &Moments) -> Rgb {
        let (mut cx, mut cz) = (Rgb::ZERO, Rgb::ZERO);
        for j in EVEN_Y {
            let (a, b, c) = MONO[j];
            cx += self.coef[j] * m.get(a + 1, b, c);
            cz += self.coef[j] * m.get(a, b, c + 1);
        }
        cx * t.sin + cz * t.cos
    }
}

/// The fit domain's moments and its lune at a tilt.
#[derive(Clone, Copy, Debug)]
pub struct FitDomain {
    /// Which domain: the sphere or the hemisphere about N.
    pub gram: Gram,
    /// Its closed-form moments (computed once per process).
    pub moments: &'static Moments,
}

impl FitDomain {
    /// The domain of `gram`.
    pub fn new(gram: Gram) -> Self {
        // Computed once (they depend on nothing).
        static HEMISPHERE: LazyLock<Moments> = LazyLock::new(Moments::hemisphere);
        static SPHERE: LazyLock<Moments> = LazyLock::new(Moments::sphere);
        let moments = match gram {
            Gram::Hemisphere => &*HEMISPHERE,
            Gram::Sphere => &*SPHERE,
        };
        FitDomain { gram, moments }
    }
    /// The moments of the part of the domain where n·d ≥ 0, for d tilted by `t` from N.
    #[inline]
    #[cfg(test)]
    pub fn lune(&self, t: Angle) -> Moments {
        match self.gram {
            Gram::Hemisphere => Moments::hemisphere_lune(t),
            Gram::Sphere => Moments::sphere_half(t),
        }
    }
}
