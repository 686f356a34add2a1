//! Gram matrices of SH bands 0–2 over the hemisphere and over cones, SH rotation, and the
//! world-space form of a visibility multiply that is symmetric about an axis.
//!
//! - **Gram matrices** (FORMULAS §9, derived there; every entry is re-derived by quadrature in
//!   the tests): G\[i,k\] = ∫_{ω·z > c} Y_i Y_k dω for the cone of cos α = c about +z. c = 0 is
//!   the hemisphere, c = −1 the sphere (identity).
//! - **Multiply** (FORMULAS §9): the L2 projection of (radiance × visibility) has coefficients
//!   out_k = Σ_i f_i·G\[i,k\], with G rotated to the visibility's axis.
//! - **Rotation**: band 1 is a vector, band 2 a traceless quadratic form ω·Mω, so rotating an
//!   SH is b → Rb, M → RMRᵀ (exact; no sampled inverse).
//! - **World-space multiply without rotation** (the hemispherical-lighting talk's quadratic-to-
//!   linear multiply, derived here): the Gram of a cap is invariant under rotations about its
//!   axis A, so it maps SH components of azimuthal order m about A to the same m. The band 0–1
//!   outputs need only the m = 0 parts of the input (f₀, b·A, the zonal band-2 part ∝ A·MA) and
//!   the m = ±1 parts, which are world vectors perpendicular to A: b⊥ and (MA)⊥. See
//!   [`AxialParts`] and [`multiply_to_linear`].

use crate::math::colour::Rgb;
use crate::math::sh::{k, Sh9, N_SH};
use glam::{DMat3, DQuat, DVec3};

/// A 9×9 matrix over the SH indices of FORMULAS §2.
pub type Mat9 = [[f64; N_SH]; N_SH];

/// The Gram matrix of SH bands 0–2 over the cone {ω·z > c} (FORMULAS §9). Symmetric; the
/// entries not listed there are zero (the cone is symmetric about z, so only equal |m| and
/// equal parity couple).
pub fn cone_gram(c: f64) -> Mat9 {
    let c = c.clamp(-1.0, 1.0);
    let (s3, s5, s15) = (3f64.sqrt(), 5f64.sqrt(), 15f64.sqrt());
    let u = 1.0 - c;
    let mut g = [[0.0; N_SH]; N_SH];
    let mut set = |i: usize, j: usize, v: f64| {
        g[i][j] = v;
        g[j][i] = v;
    };
    set(0, 0, u / 2.0);
    set(0, 2, s3 * (1.0 - c * c) / 4.0);
    set(0, 6, s5 * c * (1.0 - c * c) / 4.0);
    set(1, 1, u * u * (c + 2.0) / 4.0);
    set(3, 3, u * u * (c + 2.0) / 4.0);
    set(2, 2, u * (c * c + c + 1.0) / 2.0);
    let g15 = 3.0 * s5 * u * u * (1.0 + c) * (1.0 + c) / 16.0;
    set(1, 5, g15);
    set(3, 7, g15);
    set(2, 6, s15 * (1.0 - c * c) * (1.0 + 3.0 * c * c) / 16.0);
    let g44 = u * u * u * (3.0 * c * c + 9.0 * c + 8.0) / 16.0;
    set(4, 4, g44);
    set(8, 8, g44);
    let g55 = u * u * (3.0 * c * c * c + 6.0 * c * c + 4.0 * c + 2.0) / 4.0;
    set(5, 5, g55);
    set(7, 7, g55);
    set(6, 6, u * (9.0 * c.powi(4) + 9.0 * c * c * c - c * c - c + 4.0) / 8.0);
    g
}

/// The Gram matrix over the hemisphere z ≥ 0 (FORMULAS §9): ½·I plus G\[0,2\] = √3/4,
/// G\[1,5\] = G\[3,7\] = 3√5/16, G\[2,6\] = √15/16.
#[cfg(test)]
pub fn hemisphere_gram() -> Mat9 {
    cone_gram(0.0)
}

/// The traceless symmetric M with ω·Mω = Σ_{band 2} f_i·Y_i(ω) on the unit sphere, for one
/// channel (3z² − 1 = 2z² − x² − y² there).
pub(crate) fn quadratic_form(f: &Sh9, ch: usize) -> DMat3 {
    let [f4, f5, f6, f7, f8] = [f[4][ch], f[5][ch], f[6][ch], f[7][ch], f[8][ch]];
    let h = 0.5 * k::Y2_XY;
    let (xx, yy, zz) = (-k::Y20 * f6 + k::Y22 * f8, -k::Y20 * f6 - k::Y22 * f8, 2.0 * k::Y20 * f6);
    let (xy, yz, xz) = (h * f4, -h * f5, -h * f7);
    DMat3::from_cols(DVec3::new(xx, xy, xz), DVec3::new(xy, yy, yz), DVec3::new(xz, yz, zz))
}

/// Writes the band-2 coefficients of one channel from its quadratic form (inverse of
/// [`quadratic_form`]; M must be traceless).
fn set_quadratic_form(out: &mut Sh9, ch: usize, m: &DMat3) {
    let h = 0.5 * k::Y2_XY;
    out[4][ch] = m.y_axis.x / h;
    out[5][ch] = -m.z_axis.y / h;
    out[6][ch] = m.z_axis.z / (2.0 * k::Y20);
    out[7][ch] = -m.z_axis.x / h;
    out[8][ch] = (m.x_axis.x - m.y_axis.y) / (2.0 * k::Y22);
}

/// The SH of the rotated function g(Rᵀω), i.e. the lighting turned by the rotation `r`:
/// band 0 is kept, the band-1 vector b becomes Rb and the band-2 form M becomes RMRᵀ.
pub fn rotate(f: &Sh9, r: DMat3) -> Sh9 {
    let mut out = Sh9::ZERO;
    out[0] = f[0];
    for ch in 0..3 {
        let b = r * f.l1_vector(ch);
        out[3][ch] = -b.x;
        out[1][ch] = -b.y;
        out[2][ch] = b.z;
        let m = r * quadratic_form(f, ch) * r.transpose();
        set_quadratic_form(&mut out, ch, &m);
    }
    out
}

/// The matrix D of [`rotate`]: rotate(f, r)_i = Σ_j D\[i\]\[j\]·f_j. Equivalently Y(Rω) = D·Y(ω);
/// D is orthogonal and block diagonal by band.
#[cfg(test)]
pub fn rotation_matrix(r: DMat3) -> Mat9 {
    let mut d = [[0.0; N_SH]; N_SH];
    for j in 0..N_SH {
        let mut e = Sh9::ZERO;
        e[j] = Rgb::ONE;
        let col = rotate(&e, r);
        for (i, row) in d.iter_mut().enumerate() {
            row[j] = col[i].x;
        }
    }
    d
}

/// A rotation taking +z to the unit vector `axis` (the tangent frame of a surface or cone).
/// Any twist about the axis gives the same multiply, since the caps are symmetric about it.
pub fn frame_from_z(axis: DVec3) -> DMat3 {
    DMat3::from_quat(DQuat::from_rotation_arc(DVec3::Z, axis.normalize()))
}

/// out_k = Σ_i f_i·G\[i,k\]: the L2 projection of (f × the cap whose Gram is G), FORMULAS §9.
pub fn multiply(f: &Sh9, g: &Mat9) -> Sh9 {
    let mut out = Sh9::ZERO;
    for (kk, o) in out.0.iter_mut().enumerate() {
        for (i, fi) in f.0.iter().enumerate() {
            if g[i][kk] != 0.0 {
                *o += *fi * g[i][kk];
            }
        }
    }
    out
}

/// The Gram of the cap of cos α = c about `axis`, in world space: D·G·Dᵀ with D the rotation
/// taking +z to the axis.
#[cfg(test)]
pub fn rotated_gram(c: f64, axis: DVec3) -> Mat9 {
    let d = rotation_matrix(frame_from_z(axis));
    let g = cone_gram(c);
    let mut out = [[0.0; N_SH]; N_SH];
    for i in 0..N_SH {
        for j in 0..N_SH {
            let mut s = 0.0;
            for a in 0..N_SH {
                for b in 0..N_SH {
                    s += d[i][a] * g[a][b] * d[j][b];
                }
            }
            out[i][j] = s;
        }
    }
    out
}

/// The full L2 multiply by the cap of cos α = c about `axis`: rotate the SH into the cap's
/// tangent frame, multiply by the (sparse) tangent-space Gram, rotate back. L2 output.
pub fn multiply_full(f: &Sh9, c: f64, axis: DVec3) -> Sh9 {
    let r = frame_from_z(axis);
    let tangent = rotate(f, r.transpose());
    rotate(&multiply(&tangent, &cone_gram(c)), r)
}

/// The components of an L2 SH that a cap symmetric about the unit axis A can map to bands 0–1,
/// per channel. m = 0: `zonal` = (f₀, the band-1 coefficient along A = b·A, the zonal band-2
/// coefficient about A = √(4π/5)·A·MA). m = ±1: world vectors perpendicular to A, `b_perp`
/// = b⊥ (b the band-1 vector of [`Sh9::l1_vector`]) and `q_perp` = (2/K)(MA)⊥ with
/// K = ½√(15/π); in A's tangent frame they are −(f₃, f₁) and −(f₇, f₅).
#[derive(Clone, Copy, Debug)]
pub struct AxialParts {
    /// The unit symmetry axis A the parts are taken about.
    pub axis: DVec3,
    /// The m = 0 components (f₀, b·A, √(4π/5)·A·MA), each an RGB triple.
    pub zonal: [Rgb; 3],
    /// Per channel: the band-1 vector's component perpendicular to A (b⊥).
    pub b_perp: [DVec3; 3],
    /// Per channel: (2/K)(MA)⊥, the band-2 part that couples to band 1 perpendicular to A.
    pub q_perp: [DVec3; 3],
}

/// Splits `f` about `axis` (see [`AxialParts`]); no rotation, a few dot products per channel.
pub fn axial_parts(f: &Sh9, axis: DVec3) -> AxialParts {
    let a = axis;
    let mut zonal = [Rgb::ZERO; 3];
    let mut b_perp = [DVec3::ZERO; 3];
    let mut q_perp = [DVec3::ZERO; 3];
    let zonal2 = (4.0 * std::f64::consts::PI / 5.0).sqrt();
    for ch in 0..3 {
        let b = f.l1_vector(ch);
        let ma = quadratic_form(f, ch) * a;
        let (ba, ama) = (b.dot(a), a.dot(ma));
        zonal[0][ch] = f[0][ch];
        zonal[1][ch] = ba;
        zonal[2][ch] = zonal2 * ama;
        b_perp[ch] = b - a * ba;
        q_perp[ch] = (ma - a * ama) * (2.0 / k::Y2_XY);
    }
    AxialParts { axis, zonal, b_perp, q_perp }
}

/// The m = 0 block of a cap Gram on indices (0, 2, 6) and its m = ±1 block on (1, 5)
/// (= (3, 7)): everything [`multiply_to_linear`] and HLSH need.
#[derive(Clone, Copy, Debug)]
pub struct AxialGram {
    /// The m = 0 block: rows and columns for SH indices 0, 2 and 6.
    pub m0: [[f64; 3]; 3],
    /// The m = ±1 block: rows and columns for SH indices 1 and 5.
    pub m1: [[f64; 2]; 2],
}

impl AxialGram {
    /// Extracts the two axial blocks from a full 9×9 Gram matrix in the cap's tangent frame.
    pub fn of(g: &Mat9) -> Self {
        let z = [0, 2, 6];
        let p = [1, 5];
        AxialGram {
            m0: std::array::from_fn(|i| std::array::from_fn(|j| g[z[i]][z[j]])),
            m1: std::array::from_fn(|i| std::array::from_fn(|j| g[p[i]][p[j]])),
        }
    }

    /// The cone of cos α = c (the hemisphere for c = 0).
    pub fn cone(c: f64) -> Self {
        Self::of(&cone_gram(c))
    }
}

/// The quadratic-to-linear multiply in world space: bands 0–1 of the L2 multiply by the cap
/// whose axial Gram is `g`, about `parts.axis`, with no SH rotation. Equals
/// [`multiply_full`] truncated to the linear band (tested to 1e-9).
///
/// out₀ = Σ_j G⁰\[0\]\[j\]·zonal_j; the output band-1 vector is
/// (Σ_j G⁰\[1\]\[j\]·zonal_j)·A + G¹\[0\]\[0\]·b⊥ + G¹\[0\]\[1\]·q⊥.
pub fn multiply_to_linear(parts: &AxialParts, g: &AxialGram) -> Sh9 {
    let mut out = Sh9::ZERO;
    let z = &parts.zonal;
    let dc = z[0] * g.m0[0][0] + z[1] * g.m0[0][1] + z[2] * g.m0[0][2];
    let along = z[0] * g.m0[1][0] + z[1] * g.m0[1][1] + z[2] * g.m0[1][2];
    out[0] = dc;
    for ch in 0..3 {
        let b = parts.axis * along[ch] + parts.b_perp[ch] * g.m1[0][0] + parts.q_perp[ch] * g.m1[0][1];
        out[3][ch] = -b.x;
        out[1][ch] = -b.y;
        out[2][ch] = b.z;
    }
    out
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // matrices are indexed by (i, j) as in FORMULAS §9
mod tests {
    use super::*;
    use crate::math::quadrature::gauss_legendre;
    use crate::math::sh::basis;
    use crate::math::test_rng::Rng;
    use std::f64::consts::PI;

    /// ∫ over the cap {ω·axis > c} of Y_i·Y_k, by Gauss–Legendre in t = ω·axis on [c, 1] and the
    /// trapezoid rule in azimuth (exact for the degree-4 polynomials involved), in an orthonormal
    /// frame built by Gram–Schmidt (independent of `frame_from_z` and of the closed forms).
    fn quadrature_gram(c: f64, axis: DVec3) -> Mat9 {
        let helper = if axis.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
        let u = (helper - axis * helper.dot(axis)).normalize();
        let v = axis.cross(u);
        let (nt, nphi) = (12, 24);
        let mut g = [[0.0; N_SH]; N_SH];
        for (x, w) in gauss_legendre(nt) {
            let t = 0.5 * (1.0 - c) * x + 0.5 * (1.0 + c);
            let wt = 0.5 * (1.0 - c) * w;
            let s = (1.0 - t * t).max(0.0).sqrt();
            for p in 0..nphi {
                let phi = 2.0 * PI * p as f64 / nphi as f64;
                let d = axis * t + (u * phi.cos() + v * phi.sin()) * s;
                let y = basis(d);
                let wp = wt * 2.0 * PI / nphi as f64;
                for i in 0..N_SH {
                    for kk in 0..N_SH {
                        g[i][kk] += wp * y[i] * y[kk];
                    }
                }
            }
        }
        g
    }

    fn max_diff(a: &Mat9, b: &Mat9) -> (f64, usize, usize) {
        let mut worst = (0.0, 0, 0);
        for i in 0..N_SH {
            for j in 0..N_SH {
                let d = (a[i][j] - b[i][j]).abs();
                if d > worst.0 {
                    worst = (d, i, j);
                }
            }
        }
        worst
    }

    /// FORMULAS §9 is derived, not quoted: every entry of the hemisphere Gram (the listed
    /// off-diagonals and the ½ diagonal) and of the cone Gram at several cos α, and every
    /// entry claimed to be zero, against quadrature.
    #[test]
    fn gram_matrices_match_quadrature() {
        for c in [-1.0, -0.5, 0.0, 0.25, 0.5, 0.75, 0.9, 0.99] {
            let (d, i, j) = max_diff(&cone_gram(c), &quadrature_gram(c, DVec3::Z));
            assert!(d < 1e-13, "cos α = {c}: G[{i},{j}] off by {d}");
        }
        let h = hemisphere_gram();
        let (s3, s5, s15) = (3f64.sqrt(), 5f64.sqrt(), 15f64.sqrt());
        for i in 0..N_SH {
            assert_eq!(h[i][i], 0.5, "hemisphere diagonal {i}");
        }
        for (i, j, v) in [(0, 2, s3 / 4.0), (1, 5, 3.0 * s5 / 16.0), (3, 7, 3.0 * s5 / 16.0), (2, 6, s15 / 16.0)] {
            assert!((h[i][j] - v).abs() < 1e-16 && h[j][i] == h[i][j]);
        }
        let nonzero_off = [(0, 2), (1, 5), (3, 7), (2, 6)];
        for i in 0..N_SH {
            for j in 0..N_SH {
                if i != j && !nonzero_off.contains(&(i.min(j), i.max(j))) {
                    assert_eq!(h[i][j], 0.0, "hemisphere G[{i},{j}]");
                }
            }
        }
        // c = −1 is the sphere: the identity (orthonormality).
        let s = cone_gram(-1.0);
        for i in 0..N_SH {
            for j in 0..N_SH {
                assert!((s[i][j] - if i == j { 1.0 } else { 0.0 }).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn cone_narrows_as_cos_alpha_grows() {
        // The visible solid angle 4π·G[0,0] = 2π(1 − c) and every diagonal entry fall
        // monotonically with c, reaching 0 at c = 1 (finite throughout).
        let cs: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
        for w in cs.windows(2) {
            let (a, b) = (cone_gram(w[0]), cone_gram(w[1]));
            for i in 0..N_SH {
                assert!(b[i][i] <= a[i][i] + 1e-15, "G[{i},{i}] grows from c={} to {}", w[0], w[1]);
            }
        }
        let one = cone_gram(1.0);
        assert!(one.iter().flatten().all(|v| v.abs() < 1e-15));
        assert!(cone_gram(1.0 - 1e-12).iter().flatten().all(|v| v.is_finite()));
    }

    #[test]
    fn rotation_turns_the_function() {
        let mut rng = Rng::new(7);
        for _ in 0..20 {
            let (f, r) = (rng.sh(), rng.rotation());
            let g = rotate(&f, r);
            for _ in 0..5 {
                let w = rng.unit();
                // g(ω) = f(Rᵀω)
                let d = (g.eval(w) - f.eval(r.transpose() * w)).abs().max_element();
                assert!(d < 1e-13, "{d}");
            }
            // D is orthogonal.
            let d = rotation_matrix(r);
            for i in 0..N_SH {
                for j in 0..N_SH {
                    let dot: f64 = (0..N_SH).map(|a| d[i][a] * d[j][a]).sum();
                    assert!((dot - if i == j { 1.0 } else { 0.0 }).abs() < 1e-13);
                }
            }
        }
    }

    /// The Gram rotated to N (D·G·Dᵀ) equals quadrature over the cap about N directly, and the
    /// full multiply is the projection of f × cap.
    #[test]
    fn rotated_gram_matches_quadrature_about_any_axis() {
        let mut rng = Rng::new(11);
        for c in [0.0, 0.5, 0.9] {
            for _ in 0..6 {
                let n = rng.unit();
                let (d, i, j) = max_diff(&rotated_gram(c, n), &quadrature_gram(c, n));
                assert!(d < 1e-13, "c={c} N={n}: [{i},{j}] {d}");
                let f = rng.sh();
                let full = multiply_full(&f, c, n);
                let direct = multiply(&f, &quadrature_gram(c, n));
                for i in 0..N_SH {
                    assert!((full[i] - direct[i]).abs().max_element() < 1e-12);
                }
            }
        }
    }

    /// The world-space quadratic-to-linear multiply equals the full L2 multiply truncated to
    /// bands 0–1, for random SH, random axes, and hemisphere and cones (to
    /// 1e-9).
    #[test]
    fn quadratic_to_linear_equals_truncated_full_multiply() {
        let mut rng = Rng::new(3);
        let mut worst = 0.0f64;
        for c in [0.0, 0.25, 0.5, 0.75, 0.9] {
            let g = AxialGram::cone(c);
            for _ in 0..50 {
                let (f, n) = (rng.sh(), rng.rotation() * rng.unit());
                let full = multiply_full(&f, c, n).truncate(1);
                let q2l = multiply_to_linear(&axial_parts(&f, n), &g);
                for i in 0..N_SH {
                    worst = worst.max((full[i] - q2l[i]).abs().max_element());
                }
            }
        }
        assert!(worst < 1e-9, "{worst}");
        assert!(worst < 1e-13, "expected rounding only, got {worst}");
    }

    /// The twist of the tangent frame about the axis does not matter (the cap is symmetric).
    #[test]
    fn full_multiply_ignores_the_twist() {
        let mut rng = Rng::new(5);
        let f = rng.sh();
        let n = rng.unit();
        let base = multiply_full(&f, 0.3, n);
        let twist = DMat3::from_quat(DQuat::from_axis_angle(n, 1.234)) * frame_from_z(n);
        let other = rotate(&multiply(&rotate(&f, twist.transpose()), &cone_gram(0.3)), twist);
        for i in 0..N_SH {
            assert!((base[i] - other[i]).abs().max_element() < 1e-13);
        }
    }

    /// The zonal parts are the tangent-frame coefficients: about +z they are f₀, f₂, f₆ and the
    /// m = ±1 vectors are −(f₃, f₁) and −(f₇, f₅).
    #[test]
    fn axial_parts_about_z_are_the_tangent_coefficients() {
        let f = Rng::new(9).sh();
        let p = axial_parts(&f, DVec3::Z);
        for ch in 0..3 {
            assert!((p.zonal[0][ch] - f[0][ch]).abs() < 1e-15);
            assert!((p.zonal[1][ch] - f[2][ch]).abs() < 1e-15);
            assert!((p.zonal[2][ch] - f[6][ch]).abs() < 1e-14);
            assert!((p.b_perp[ch] - DVec3::new(-f[3][ch], -f[1][ch], 0.0)).length() < 1e-15);
            assert!((p.q_perp[ch] - DVec3::new(-f[7][ch], -f[5][ch], 0.0)).length() < 1e-14);
        }
    }
}
