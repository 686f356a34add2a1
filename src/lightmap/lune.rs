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
//! the antiderivatives in [`antiderivatives`].

use std::f64::consts::PI;

/// An angle with its sine and cosine (so tilts need one sin/cos each).
#[derive(Clone, Copy, Debug)]
pub struct Angle {
    pub a: f64,
    pub sin: f64,
    pub cos: f64,
}

impl Angle {
    pub fn new(a: f64) -> Self {
        let (sin, cos) = a.sin_cos();
        Angle { a, sin, cos }
    }
}

/// Moments m[a][b][c] = ∫ x^a y^b z^c over a region α ∈ [α₀, α₁] (module docs), a + b + c ≤ 3.
#[derive(Clone, Copy, Debug, Default)]
pub struct Moments {
    pub m: [[[f64; 4]; 4]; 4],
}

/// Antiderivatives F(a, c)(α) of cos^a α sin^c α for a + c ≤ 3, indexed [a][c].
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
const Y_INT: [[f64; 4]; 4] = [
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

    /// The hemisphere z ≥ 0 where n·d ≥ 0, d tilted by θ ∈ [0, π] towards +x: α ∈ [0, β],
    /// β = π − θ, written out (the fits' inner loop; equal to `of_range`, tested).
    #[inline]
    pub fn hemisphere_lune(theta: Angle) -> Self {
        let (b, s, c) = (PI - theta.a, theta.sin, -theta.cos);
        let (s2, c2) = (s * s, c * c);
        let (s3, c3) = (s2 * s, c2 * c);
        let a = |a00: f64, a10: f64, a01: f64, a20: f64, a02: f64, a11: f64, a30: f64, a03: f64, a21: f64, a12: f64| {
            [[a00, a01, a02, a03], [a10, a11, a12, 0.0], [a20, a21, 0.0, 0.0], [a30, 0.0, 0.0, 0.0]]
        };
        let sc = s * c;
        let t = a(
            b,
            s,
            1.0 - c,
            0.5 * (b + sc),
            0.5 * (b - sc),
            0.5 * s2,
            s - s3 / 3.0,
            2.0 / 3.0 - c + c3 / 3.0,
            (1.0 - c3) / 3.0,
            s3 / 3.0,
        );
        let mut m = [[[0.0; 4]; 4]; 4];
        for a in 0..4 {
            for c in 0..4 - a {
                m[a][0][c] = Y_INT[a + c][0] * t[a][c];
                if a + c <= 1 {
                    m[a][2][c] = Y_INT[a + c][2] * t[a][c];
                }
            }
        }
        Moments { m }
    }

    /// The half-sphere n·d ≥ 0, d tilted by θ towards +x.
    pub fn sphere_half(theta: Angle) -> Self {
        let a0 = Angle { a: -theta.a, sin: -theta.sin, cos: theta.cos };
        let a1 = Angle { a: PI - theta.a, sin: theta.sin, cos: -theta.cos };
        Self::of_range(a0, a1)
    }

    #[inline]
    pub fn get(&self, a: usize, b: usize, c: usize) -> f64 {
        self.m[a][b][c]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadrature::gauss_legendre;
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

    /// The written-out hemisphere lune equals the general range form.
    #[test]
    fn hemisphere_lune_equals_the_range_form() {
        for th in [0.0, 0.2, 0.9, 1.5, 2.0] {
            let t = Angle::new(th);
            let g = Moments::of_range(Angle::new(0.0), Angle { a: PI - th, sin: t.sin, cos: -t.cos });
            let h = Moments::hemisphere_lune(t);
            for a in 0..4 {
                for b in 0..4 {
                    for c in 0..4 {
                        assert!((g.m[a][b][c] - h.m[a][b][c]).abs() < 1e-14, "θ={th} [{a}{b}{c}]");
                    }
                }
            }
        }
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
