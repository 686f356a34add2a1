//! Closed-form moments ∫ x^a y^b z^c dω (a + b + c ≤ 3) over the hemisphere z ≥ 0, the sphere,
//! and the lunes cut from them by a clamped cosine max(0, n·d) with d = (sin θ, 0, cos θ)
//! tilted by θ from N = z (the regions of every inner product of the AHD/HHD fits).
//!
//! Derivation (ours; checked against quadrature below). Parametrise the sphere about the y
//! axis: n = (r cos α, y, r sin α), r = √(1 − y²); then dω = dα dy. z ≥ 0 ⟺ α ∈ [0, π] and
//! n·d = r sin(α + θ) ≥ 0 ⟺ α ∈ [−θ, π − θ]. Every region here is α ∈ [α₀, α₁] × y ∈ [−1, 1]:
//!
//! | region                     | α₀  | α₁    |
//! |----------------------------|-----|-------|
//! | hemisphere                 | 0   | π     |
//! | sphere                     | 0   | 2π    |
//! | hemisphere ∩ {n·d ≥ 0}     | 0   | π − θ |
//! | sphere ∩ {n·d ≥ 0}         | −θ  | π − θ |
//!
//! so the moment separates: ∫ x^a y^b z^c = Y(a + c, b)·A(a, c) with
//! Y(k, b) = ∫₋₁¹ (1 − y²)^{k/2} y^b dy (0 for odd b; Y(0,0) = 2, Y(0,2) = 2/3, Y(1,0) = π/2,
//! Y(1,2) = π/8, Y(2,0) = 4/3, Y(3,0) = 3π/8) and A(a, c) = ∫_{α₀}^{α₁} cos^a α sin^c α dα from
//! the antiderivatives in `antiderivatives`.

use std::f64::consts::PI;

/// An angle with its sine and cosine (so tilts need one sin/cos each).
#[derive(Clone, Copy, Debug)]
pub struct Angle {
    /// The angle in radians.
    pub a: f64,
    /// Its sine.
    pub sin: f64,
    /// Its cosine.
    pub cos: f64,
}

impl Angle {
    /// An angle with its sine and cosine from `f64::sin_cos`.
    pub fn new(a: f64) -> Self {
        let (sin, cos) = a.sin_cos();
        Angle { a, sin, cos }
    }

    /// A tilt θ ∈ [0, π/2] with its sine and cosine by the fdlibm kernels (minimax polynomials
    /// on [−π/4, π/4], error below 1 ulp; θ > π/4 by the exact complement π/2 − θ), about
    /// three times cheaper than libm's general `sin_cos` (the golden section's inner loop).
    /// Each call is independent (no recurrence between calls, so no compounding rounding);
    /// outside [0, π/2] (or NaN) it is [`Angle::new`].
    #[inline]
    pub fn tilt(a: f64) -> Self {
        // π/2 = PIO2_HI + PIO2_LO (fdlibm's split: PIO2_HI is the f64 nearest π/2); PIO2_HI − a
        // is exact for a ∈ [π/4, π/2] (Sterbenz).
        const PIO2_HI: f64 = std::f64::consts::FRAC_PI_2;
        const PIO2_LO: f64 = 6.123_233_995_736_766e-17;
        if (0.0..=std::f64::consts::FRAC_PI_4).contains(&a) {
            Angle { a, sin: kernel_sin(a), cos: kernel_cos(a) }
        } else if a > std::f64::consts::FRAC_PI_4 && a <= PIO2_HI {
            let x = (PIO2_HI - a) + PIO2_LO;
            Angle { a, sin: kernel_cos(x), cos: kernel_sin(x) }
        } else {
            Angle::new(a)
        }
    }
}

/// sin x for |x| ≤ π/4 (fdlibm `__kernel_sin`, tail y = 0).
#[inline]
fn kernel_sin(x: f64) -> f64 {
    const S1: f64 = -1.666_666_666_666_663_2e-1;
    const S2: f64 = 8.333_333_333_322_49e-3;
    const S3: f64 = -1.984_126_982_985_795e-4;
    const S4: f64 = 2.755_731_370_707_006_8e-6;
    const S5: f64 = -2.505_076_025_340_686_3e-8;
    const S6: f64 = 1.589_690_995_211_55e-10;
    let z = x * x;
    let w = z * z;
    let r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let v = z * x;
    x + v * (S1 + z * r)
}

/// cos x for |x| ≤ π/4 (fdlibm `__kernel_cos`, tail y = 0).
#[inline]
fn kernel_cos(x: f64) -> f64 {
    const C1: f64 = 4.166_666_666_666_66e-2;
    const C2: f64 = -1.388_888_888_887_411e-3;
    const C3: f64 = 2.480_158_728_947_673e-5;
    const C4: f64 = -2.755_731_435_139_066_3e-7;
    const C5: f64 = 2.087_572_321_298_175e-9;
    const C6: f64 = -1.135_964_755_778_819_5e-11;
    let z = x * x;
    let w = z * z;
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + z * r)
}

/// Moments m\[a\]\[b\]\[c\] = ∫ x^a y^b z^c over a region α ∈ [α₀, α₁] (module docs), a + b + c ≤ 3.
#[derive(Clone, Copy, Debug, Default)]
pub struct Moments {
    /// The moments, indexed `m[a][b][c]` (zero where a + b + c > 3).
    pub m: [[[f64; 4]; 4]; 4],
}

/// The angular integrals A(a, c) = ∫_{α₀}^{α₁} cos^a α sin^c α dα (a + c ≤ 3, indexed \[a\]\[c\],
/// zero elsewhere) of a region (module docs): its moments are Y(a + c, b)·A(a, c). The fits'
/// inner loop needs only these ten numbers per tilt.
#[derive(Clone, Copy, Debug, Default)]
#[cfg(test)]
pub struct Angular(pub [[f64; 4]; 4]);

#[cfg(test)]
impl Angular {
    /// Hemisphere ∩ {n·d ≥ 0}, d tilted by θ ∈ [0, π]: α ∈ [0, β], β = π − θ, with
    /// sin β = sin θ, cos β = −cos θ, written out from `antiderivatives`.
    #[inline]
    #[cfg(test)]
    pub fn hemisphere_lune(theta: Angle) -> Self {
        const THIRD: f64 = 1.0 / 3.0;
        let (b, s, c) = (PI - theta.a, theta.sin, -theta.cos);
        let (s2, c2) = (s * s, c * c);
        let (s3, c3) = (s2 * s * THIRD, c2 * c * THIRD);
        let sc = s * c;
        Angular([
            [b, 1.0 - c, 0.5 * (b - sc), 2.0 * THIRD - c + c3],
            [s, 0.5 * s2, s3, 0.0],
            [0.5 * (b + sc), THIRD - c3, 0.0, 0.0],
            [s - s3, 0.0, 0.0, 0.0],
        ])
    }

    /// The half-sphere {n·d ≥ 0}: α ∈ [−θ, π − θ], where F(π − θ) − F(−θ) leaves (with
    /// s = sin θ, c = cos θ) A00 = π, A10 = 2s, A01 = 2c, A20 = A02 = π/2, A11 = 0,
    /// A30 = 2s − 2s³/3, A03 = 2c − 2c³/3, A21 = 2c³/3, A12 = 2s³/3.
    #[inline]
    #[cfg(test)]
    pub fn sphere_half(theta: Angle) -> Self {
        let (s, c) = (theta.sin, theta.cos);
        let (s3, c3) = (2.0 / 3.0 * (s * s * s), 2.0 / 3.0 * (c * c * c));
        let h = 0.5 * PI;
        Angular([
            [PI, 2.0 * c, h, 2.0 * c - c3],
            [2.0 * s, 0.0, s3, 0.0],
            [h, c3, 0.0, 0.0],
            [2.0 * s - s3, 0.0, 0.0, 0.0],
        ])
    }
}

/// The angular-integral pairs of the clamped-cosine integrals [`Clamped`]:
/// g_i = sin θ·A(CLAMPED_PAIRS\[i\].0) + cos θ·A(CLAMPED_PAIRS\[i\].1).
#[cfg(test)]
pub const CLAMPED_PAIRS: [((usize, usize), (usize, usize)); 6] =
    [((1, 0), (0, 1)), ((2, 0), (1, 1)), ((1, 1), (0, 2)), ((3, 0), (2, 1)), ((1, 2), (0, 3)), ((2, 1), (1, 2))];

/// The clamped-cosine integrals of a region cut by d = (sin θ, 0, cos θ): for x^a y^b z^c,
/// ∫ x^a y^b z^c·(n·d) over the region ∩ {n·d ≥ 0} = Y(a + c + 1, b)·g with
/// g = sin θ·A(a + 1, c) + cos θ·A(a, c + 1) ([`Angular`]), for the six (a, c) pairs of
/// [`CLAMPED_PAIRS`]. Simplified with sin²θ + cos²θ = 1 they are a few flops each (derived
/// from [`Angular`]'s entries; equal to that combination, tested).
#[derive(Clone, Copy, Debug)]
pub struct Clamped(pub [f64; 6]);

impl Clamped {
    /// Hemisphere lune, θ ∈ [0, π], β = π − θ, s = sin θ, c = cos θ: g = (1 + c, sβ/2,
    /// (s + cβ)/2, (1 + c)(2 − c)/3, (1 + c)²/3, s(1 + c)/3).
    #[inline]
    pub fn hemisphere_lune(theta: Angle) -> Self {
        const THIRD: f64 = 1.0 / 3.0;
        let (b, s, c) = (PI - theta.a, theta.sin, theta.cos);
        let p = 1.0 + c;
        Clamped([p, 0.5 * s * b, 0.5 * (s + c * b), p * (2.0 - c) * THIRD, p * p * THIRD, s * p * THIRD])
    }

    /// Half-sphere: g = (2, sπ/2, cπ/2, (2 + 2s²)/3, (2 + 2c²)/3, 2sc/3).
    #[inline]
    pub fn sphere_half(theta: Angle) -> Self {
        const TWO_THIRDS: f64 = 2.0 / 3.0;
        let (s, c) = (theta.sin, theta.cos);
        let h = 0.5 * PI;
        Clamped([2.0, h * s, h * c, TWO_THIRDS * (1.0 + s * s), TWO_THIRDS * (1.0 + c * c), TWO_THIRDS * s * c])
    }
}

/// Antiderivatives F(a, c)(α) of cos^a α sin^c α for a + c ≤ 3, indexed \[a\]\[c\].
fn antiderivatives(t: Angle) -> [[f64; 4]; 4] {
    let (a, s, c) = (t.a, t.sin, t.cos);
    let s2c = 2.0 * s * c; // sin 2α
    let mut f = [[0.0; 4]; 4];
    f[0][0] = a;
    f[1][0] = s;
    f[0][1] = -c;
    f[2][0] = 0.5 * a + 0.25 * s2c;
    f[0][2] = 0.5 * a - 0.25 * s2c;
    f[1][1] = 0.5 * s * s;
    f[3][0] = s - s * s * s / 3.0;
    f[0][3] = -c + c * c * c / 3.0;
    f[2][1] = -c * c * c / 3.0;
    f[1][2] = s * s * s / 3.0;
    f
}

/// Y(k, b) of the module docs for k = a + c ≤ 3 and b ≤ 3 (a + b + c ≤ 3).
pub const Y_INT: [[f64; 4]; 4] = [
    [2.0, 0.0, 2.0 / 3.0, 0.0],
    [PI / 2.0, 0.0, PI / 8.0, 0.0],
    [4.0 / 3.0, 0.0, 0.0, 0.0],
    [3.0 * PI / 8.0, 0.0, 0.0, 0.0],
];

impl Moments {
    /// The moments of the region α ∈ [α₀, α₁].
    pub fn of_range(a0: Angle, a1: Angle) -> Self {
        let (f0, f1) = (antiderivatives(a0), antiderivatives(a1));
        let mut m = [[[0.0; 4]; 4]; 4];
        for a in 0..4 {
            for c in 0..4 - a {
                let ac = f1[a][c] - f0[a][c];
                for b in (0..4 - a - c).step_by(2) {
                    m[a][b][c] = Y_INT[a + c][b] * ac;
                }
            }
        }
        Moments { m }
    }

    /// The hemisphere z ≥ 0.
    pub fn hemisphere() -> Self {
        Self::of_range(Angle { a: 0.0, sin: 0.0, cos: 1.0 }, Angle { a: PI, sin: 0.0, cos: -1.0 })
    }

    /// The whole sphere.
    pub fn sphere() -> Self {
        Self::of_range(Angle { a: 0.0, sin: 0.0, cos: 1.0 }, Angle { a: 2.0 * PI, sin: 0.0, cos: 1.0 })
    }

    /// The hemisphere z ≥ 0 where n·d ≥ 0, d tilted by θ ∈ [0, π] towards +x (equal to
    /// `of_range` over α ∈ [0, π − θ], tested).
    #[inline]
    #[cfg(test)]
    pub fn hemisphere_lune(theta: Angle) -> Self {
        Self::from_angular(&Angular::hemisphere_lune(theta))
    }

    /// The half-sphere n·d ≥ 0, d tilted by θ towards +x (equal to `of_range` over
    /// α ∈ [−θ, π − θ], tested).
    #[cfg(test)]
    pub fn sphere_half(theta: Angle) -> Self {
        Self::from_angular(&Angular::sphere_half(theta))
    }

    /// The moments Y(a + c, b)·A(a, c) (module docs) of a region's angular integrals.
    #[inline]
    #[cfg(test)]
    pub fn from_angular(t: &Angular) -> Self {
        let mut m = [[[0.0; 4]; 4]; 4];
        for a in 0..4 {
            for c in 0..4 - a {
                m[a][0][c] = Y_INT[a + c][0] * t.0[a][c];
                if a + c <= 1 {
                    m[a][2][c] = Y_INT[a + c][2] * t.0[a][c];
                }
            }
        }
        Moments { m }
    }

    /// The moment ∫ x^a y^b z^c.
    #[inline]
    pub fn get(&self, a: usize, b: usize, c: usize) -> f64 {
        self.m[a][b][c]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quadrature::gauss_legendre;
    use glam::DVec3;

    /// Quadrature of x^a y^b z^c over {z ≥ z_min} ∩ {n·d ≥ 0}, independent of the α
    /// parametrisation: Gauss–Legendre in z between the breakpoints; on each ring z = t the
    /// condition n·d = r sin θ cos φ + t cos θ ≥ 0 is an arc cos φ ≥ κ, found from the ring and
    /// integrated by Gauss–Legendre in φ (the integrand is a trigonometric polynomial of degree
    /// ≤ 3, so 24 nodes are exact to rounding; in z the arc's √ edge limits it to ~1e-8 with 400
    /// nodes). `d = None`: no clamp.
    fn quad(z_min: f64, d: Option<f64>, a: i32, b: i32, c: i32) -> f64 {
        let (gl, gz) = (gauss_legendre(24), gauss_legendre(400));
        let mut s = 0.0;
        // Breakpoints of the ring integrals in z: 0 (the hemisphere) and ±sin θ (where the
        // arc becomes the whole ring or empty).
        let sd = d.map_or(0.0, |th: f64| th.sin().abs());
        let mut cuts = vec![z_min, 0.0, 1.0, sd, -sd];
        cuts.retain(|&c| c >= z_min && c <= 1.0);
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        for w2 in cuts.windows(2) {
            let (lo, hi) = (w2[0], w2[1]);
            for &(x, w) in &gz {
                let t = lo + (hi - lo) * 0.5 * (x + 1.0);
                let wt = (hi - lo) * 0.5 * w;
                let r = (1.0 - t * t).max(0.0).sqrt();
                let (p0, p1) = match d {
                    None => (-PI, PI),
                    Some(th) => {
                        let (st, ct) = th.sin_cos();
                        if st * r < 1e-300 {
                            if t * ct >= 0.0 {
                                (-PI, PI)
                            } else {
                                (0.0, 0.0)
                            }
                        } else {
                            let kappa = -t * ct / (r * st);
                            if kappa <= -1.0 {
                                (-PI, PI)
                            } else if kappa >= 1.0 {
                                (0.0, 0.0)
                            } else {
                                let h = kappa.acos();
                                (-h, h)
                            }
                        }
                    }
                };
                for &(y, wp) in &gl {
                    let phi = p0 + (p1 - p0) * 0.5 * (y + 1.0);
                    let wphi = (p1 - p0) * 0.5 * wp;
                    let n = DVec3::new(r * phi.cos(), r * phi.sin(), t);
                    s += wt * wphi * n.x.powi(a) * n.y.powi(b) * n.z.powi(c);
                }
            }
        }
        s
    }

    #[test]
    fn moments_match_quadrature() {
        for th in [0.0, 0.3, 1.0, PI / 2.0, 1.4, 2.5] {
            let t = Angle::new(th);
            let regions = [
                ("hemisphere", Moments::hemisphere(), 0.0, None),
                ("sphere", Moments::sphere(), -1.0, None),
                ("hemisphere lune", Moments::hemisphere_lune(t), 0.0, Some(th)),
                ("sphere half", Moments::sphere_half(t), -1.0, Some(th)),
            ];
            for (name, m, z_min, d) in regions {
                for a in 0..4 {
                    for b in 0..4 - a {
                        for c in 0..4 - a - b {
                            let q = quad(z_min, d, a as i32, b as i32, c as i32);
                            let v = m.get(a, b, c);
                            assert!((v - q).abs() < 1e-7, "{name} θ={th}: M[{a}{b}{c}] = {v}, quadrature {q}");
                        }
                    }
                }
            }
        }
    }

    /// The written-out hemisphere lune and half-sphere equal the general range form.
    #[test]
    fn written_out_regions_equal_the_range_form() {
        for th in [0.0, 0.2, 0.9, 1.5, 2.0] {
            let t = Angle::new(th);
            let lune = Moments::of_range(Angle::new(0.0), Angle { a: PI - th, sin: t.sin, cos: -t.cos });
            let half = Moments::of_range(
                Angle { a: -th, sin: -t.sin, cos: t.cos },
                Angle { a: PI - th, sin: t.sin, cos: -t.cos },
            );
            for (name, g, h) in [("lune", lune, Moments::hemisphere_lune(t)), ("half", half, Moments::sphere_half(t))] {
                for a in 0..4 {
                    for b in 0..4 {
                        for c in 0..4 {
                            assert!((g.m[a][b][c] - h.m[a][b][c]).abs() < 1e-14, "{name} θ={th} [{a}{b}{c}]");
                        }
                    }
                }
            }
        }
    }

    /// The simplified clamped-cosine integrals equal sin θ·A(a + 1, c) + cos θ·A(a, c + 1) of
    /// the angular integrals, and through them the quadrature-checked moments.
    #[test]
    fn clamped_equals_the_angular_combination() {
        for th in [0.0, 0.2, 0.9, std::f64::consts::FRAC_PI_2, 2.0, 3.1] {
            let t = Angle::new(th);
            for (name, g, a) in [
                ("lune", Clamped::hemisphere_lune(t), Angular::hemisphere_lune(t)),
                ("half", Clamped::sphere_half(t), Angular::sphere_half(t)),
            ] {
                for (i, ((a1, c1), (a2, c2))) in CLAMPED_PAIRS.into_iter().enumerate() {
                    let want = t.sin * a.0[a1][c1] + t.cos * a.0[a2][c2];
                    assert!((g.0[i] - want).abs() < 1e-14, "{name} θ={th} g{i}: {} vs {want}", g.0[i]);
                }
            }
        }
    }

    /// `Angle::tilt` against libm's sin/cos on a fine grid of [0, π/2] (both sides of the π/4
    /// switch and the end points): within 1.5 ulp of the libm value, and `Angle::new` outside.
    #[test]
    fn tilt_sin_cos_matches_libm() {
        let n = 200_000;
        let ulp = |x: f64| f64::EPSILON * x.abs().max(f64::MIN_POSITIVE);
        let mut pts: Vec<f64> = (0..=n).map(|i| std::f64::consts::FRAC_PI_2 * i as f64 / n as f64).collect();
        let q = std::f64::consts::FRAC_PI_4;
        pts.extend([q, q.next_up(), q.next_down(), 1e-300, 1e-8, std::f64::consts::FRAC_PI_2]);
        for a in pts {
            let t = Angle::tilt(a);
            let (s, c) = a.sin_cos();
            assert!((t.sin - s).abs() <= 1.5 * ulp(s), "sin {a}: {} vs {s}", t.sin);
            assert!((t.cos - c).abs() <= 1.5 * ulp(c).max(ulp(1e-17)), "cos {a}: {} vs {c}", t.cos);
            assert_eq!(t.a, a);
        }
        for a in [-0.1, 1.6, 3.0] {
            let (t, u) = (Angle::tilt(a), Angle::new(a));
            assert_eq!((t.sin, t.cos), (u.sin, u.cos));
        }
        assert!(Angle::tilt(f64::NAN).sin.is_nan());
    }

    /// Known values: the hemisphere's ∫1 = 2π, ∫z = π, ∫z² = 2π/3; the clamped cosine over
    /// the sphere integrates to π (∫max(0, n·d) dω).
    #[test]
    fn known_values() {
        let h = Moments::hemisphere();
        assert!((h.get(0, 0, 0) - 2.0 * PI).abs() < 1e-14);
        assert!((h.get(0, 0, 1) - PI).abs() < 1e-14);
        assert!((h.get(0, 0, 2) - 2.0 * PI / 3.0).abs() < 1e-14);
        let t = Angle::new(0.7);
        let half = Moments::sphere_half(t);
        let clamped = t.sin * half.get(1, 0, 0) + t.cos * half.get(0, 0, 1);
        assert!((clamped - PI).abs() < 1e-14);
    }
}
