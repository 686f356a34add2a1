//! The H-basis (Habel & Wimmer 2010, "Efficient Irradiance Normal Mapping", I3D, §4 and the
//! appendix): polynomials of degree ≤ 2 orthonormal over a hemisphere, made for storing a
//! lightmap texel's irradiance over the normals a normal map can give it. The peer tool's `H4`
//! and `H6` (Probulator `Source/Probulator/HBasis.h`, `ExperimentHBasis.h`).
//!
//! | id | functions | stored scalars |
//! |---|---|---|
//! | `hbasis4` | H1–H4 | 12 |
//! | `hbasis6` | H1–H6 | 18 |
//!
//! In the frame of the surface normal N, (x, y, z) = (n′·t, n′·s, n′·N), with t = R·X the image
//! of +X under the rotation R taking +Y to N (`reference::domain::frame_to`, the frame of the
//! hemisphere domain's output grid) and s = N × t:
//!
//! - H1 = 1/√(2π)
//! - H2 = √(3/(2π))·y, H3 = √(3/(2π))·(2z − 1), H4 = √(3/(2π))·x
//! - H5 = √(15/(2π))·x·y, H6 = ½√(15/(2π))·(x² − y²)
//!
//! These are the peer's functions with one correction: the peer's H1 is 1/(2√π) (the SH
//! Y₀₀), whose square integrates to ½ over the hemisphere, so its projection keeps half of the
//! constant term. (The peer also flips x and y, which changes no span.) The basis is
//! orthonormal over the hemisphere (tested by two quadratures); its span is {1, x, y, z} for
//! H4 and adds x·y and x² − y² for H6: any linear E/π (SH L1 light) is exact in both.
//!
//! **Irradiance, over the hemisphere about N.** The peer projects the radiance (its 20,000
//! Halton samples) over the world +Z hemisphere and scores the clamped radiance reconstruction
//! as if it were irradiance (PEER.md). Here, as in the paper, the coefficients hold the exact
//! irradiance E/π of the visible light over the hemisphere about N: c_k = ∫ E(n′) H_k(n′) dn′,
//! an orthogonal projection, so it is the least-squares fit over the hemisphere. The integral
//! is a product rule in N's frame: 16 Gauss–Legendre nodes in z ∈ [0, 1] by 32 equally spaced
//! azimuths, exact for polynomials up to degree 31 in z and 31 in the azimuth, so exact for an
//! L2 SH light, whose E/π is quadratic. Under a sun, whose terminator puts a kink in E/π, the
//! coefficients are within 1e-4 of the largest of a 64 × 128 rule's (tested).
//! The 512 values of E/π are input, cached per case
//! ([`crate::reference::radiance::RadianceSource::irradiance_set`]), like the ambient cube's
//! grid. Below N's horizon the fit evaluates the same polynomials (finite, not meaningful: no
//! hemisphere domain asks there).
//!
//! **Needs N.** The H-basis is defined over the hemisphere about a surface normal, so it
//! declares [`Encoder::needs_surface_normal`] and experiments refuse it on the sphere domain.
//! Without N (direct callers only) the fit is the SH L1 irradiance of the visible light
//! (`sh1`'s answer, 12 scalars too). Degenerate inputs: black in, black out; a target that is
//! not finite gives black; the target is divided by its largest magnitude before the sums.
//!
//! TOML keys: none.

use crate::encoders::encoder::{Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::sh::ShIrradiance;
use crate::encoders::stored::{Role, Stored, Unit, Value};
use crate::math::colour::Rgb;
use crate::math::quadrature::gauss_legendre;
use crate::reference::domain::frame_to;
use anyhow::Result;
use glam::DVec3;
use std::f64::consts::TAU;
use std::sync::OnceLock;

/// The projection rule: Gauss–Legendre nodes in z = n′·N, and azimuths.
pub const RULE: (usize, usize) = (16, 32);

/// The six H-basis functions at local (x, y, z) (module docs; x, y, z in N's frame).
pub fn basis(x: f64, y: f64, z: f64) -> [f64; 6] {
    let c1 = 1.0 / TAU.sqrt();
    let c3 = (3.0 / TAU).sqrt();
    let c15 = (15.0 / TAU).sqrt();
    [c1, c3 * y, c3 * (2.0 * z - 1.0), c3 * x, c15 * x * y, 0.5 * c15 * (x * x - y * y)]
}

/// N's frame (t, s, N), module docs.
pub fn frame(n: DVec3) -> [DVec3; 3] {
    let n = n.normalize();
    let t = (frame_to(n) * DVec3::X).normalize();
    [t, n.cross(t), n]
}

/// The product rule over the hemisphere in local coordinates: (x, y, z) and weights (summing
/// to 2π), with `nz` Gauss–Legendre nodes in z and `na` azimuths.
pub fn local_rule(nz: usize, na: usize) -> Vec<([f64; 3], f64)> {
    let mut out = Vec::with_capacity(nz * na);
    for (t, w) in gauss_legendre(nz) {
        let z = 0.5 * (t + 1.0);
        let r = (1.0 - z * z).max(0.0).sqrt();
        for k in 0..na {
            let (s, c) = (TAU * (k as f64 + 0.5) / na as f64).sin_cos();
            out.push(([r * c, r * s, z], 0.5 * w * TAU / na as f64));
        }
    }
    out
}

/// [`local_rule`] at [`RULE`], built once.
fn rule() -> &'static [([f64; 3], f64)] {
    static R: OnceLock<Vec<([f64; 3], f64)>> = OnceLock::new();
    R.get_or_init(|| local_rule(RULE.0, RULE.1))
}

/// A fitted H-basis: N's frame and the coefficients (the last two are 0 for H4).
pub struct HBasisFit {
    frame: [DVec3; 3],
    coeffs: [Rgb; 6],
    count: usize,
}

impl HBasisFit {
    /// The projection of `target` (E/π at the rule's nodes about N) onto the first `count`
    /// functions, with the rule's local nodes and weights.
    fn project(frame: [DVec3; 3], count: usize, rule: &[([f64; 3], f64)], target: &[Rgb]) -> Self {
        let black = HBasisFit { frame, coeffs: [Rgb::ZERO; 6], count };
        let scale = target.iter().map(|e| e.abs().max_element()).fold(0.0, f64::max);
        if !(scale > 0.0 && scale.is_finite()) {
            return black;
        }
        let mut coeffs = [Rgb::ZERO; 6];
        for (&([x, y, z], w), e) in rule.iter().zip(target) {
            let h = basis(x, y, z);
            let e = *e / scale * w;
            for k in 0..count {
                coeffs[k] += e * h[k];
            }
        }
        HBasisFit { frame, coeffs: coeffs.map(|c| c * scale), count }
    }
}

impl Fitted for HBasisFit {
    /// The coefficients H1…H4 (or H6) of E/π, RGB each; N's frame (t, s, N) is derived.
    fn stored(&self) -> Stored {
        let mut out = Stored::new(
            "E/pi(n) = sum_k c_k*H_k(x, y, z), (x, y, z) = (n.t, n.s, n.N) in the frame of the surface normal N \
             (entries t, s, N: t the image of +X under the rotation taking +Y to N, s = N x t); H1 = 1/sqrt(2pi), \
             H2 = sqrt(3/2pi)*y, H3 = sqrt(3/2pi)*(2z - 1), H4 = sqrt(3/2pi)*x, H5 = sqrt(15/2pi)*xy, \
             H6 = sqrt(15/2pi)*(x^2 - y^2)/2 (Habel & Wimmer 2010, hbasis.rs); world directions, +Y up \
             (docs/conventions.md section 1)",
        );
        for k in 0..self.count {
            out.rgb(format!("H{}", k + 1), Unit::Irradiance, self.coeffs[k]);
        }
        for (name, v) in ["t", "s", "N"].into_iter().zip(self.frame) {
            out.push(Role::Derived, name, Unit::Direction, Value::Vector(v));
        }
        out
    }
    fn irradiance(&self, n: DVec3) -> Rgb {
        let [t, s, nn] = self.frame;
        let h = basis(n.dot(t), n.dot(s), n.dot(nn));
        (0..self.count).fold(Rgb::ZERO, |acc, k| acc + self.coeffs[k] * h[k])
    }
}

/// The H-basis encoder with 4 or 6 functions.
pub struct HBasisEncoder {
    count: usize,
}

impl HBasisEncoder {
    /// An H-basis encoder with `count` functions (4 or 6).
    pub fn new(count: usize) -> Self {
        HBasisEncoder { count }
    }

    /// The fit about unit `normal` with a `nz` × `na` rule.
    fn fit_about(&self, input: &FitInput, normal: DVec3, nz: usize, na: usize) -> HBasisFit {
        let frame = frame(normal);
        let own;
        let rule = if (nz, na) == RULE {
            rule()
        } else {
            own = local_rule(nz, na);
            &own
        };
        let [t, s, n] = frame;
        let nodes: Vec<DVec3> = rule.iter().map(|&([x, y, z], _)| (t * x + s * y + n * z).normalize()).collect();
        let target = input.light().irradiance_set(&nodes);
        HBasisFit::project(frame, self.count, rule, &target)
    }
}

impl Encoder for HBasisEncoder {
    fn id(&self) -> &str {
        if self.count == 4 {
            "hbasis4"
        } else {
            "hbasis6"
        }
    }
    fn family(&self) -> Family {
        Family::HBasis
    }
    fn stored_scalars(&self) -> usize {
        3 * self.count
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        match input.surface_normal.and_then(|n| n.try_normalize()).filter(|n| n.is_finite()) {
            Some(n) => Box::new(self.fit_about(input, n, RULE.0, RULE.1)),
            None => Box::new(ShIrradiance(input.visible_sh.truncate(1).convolve_cosine(), 1)),
        }
    }
    fn needs_surface_normal(&self) -> bool {
        true
    }
    /// A projection of a target that scales with the input.
    fn is_scale_covariant(&self) -> bool {
        true
    }
}

/// Builds the `hbasis4` encoder from its settings: H-basis 4, E/pi over the hemisphere about N
/// (peer H4). An unknown or out-of-range setting is an error.
pub fn build_hbasis4(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("hbasis4")?;
    Ok(Box::new(HBasisEncoder::new(4)))
}
/// Builds the `hbasis6` encoder from its settings: H-basis 6, E/pi over the hemisphere about N
/// (peer H6). An unknown or out-of-range setting is an error.
pub fn build_hbasis6(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("hbasis6")?;
    Ok(Box::new(HBasisEncoder::new(6)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::cap::Cap;
    use crate::math::sh::{basis as sh_basis, Sh9};
    use crate::math::sh4::Sh25;
    use crate::math::test_rng::Rng;
    use crate::reference::lighting::{Light, Lighting};
    use crate::reference::radiance::{RadianceSample, RadianceSource};
    use std::f64::consts::PI;
    use std::sync::Arc;

    /// Orthonormal over the hemisphere: by the product rule (exact for these degree-4
    /// products) and, independently, by a midpoint rule in (θ, φ) with sin θ dθ dφ.
    #[test]
    fn orthonormal_on_the_hemisphere() {
        let gram = |pts: &[([f64; 3], f64)]| {
            let mut g = [[0.0; 6]; 6];
            for &([x, y, z], w) in pts {
                let h = basis(x, y, z);
                for i in 0..6 {
                    for j in 0..6 {
                        g[i][j] += w * h[i] * h[j];
                    }
                }
            }
            g
        };
        let (nt, np) = (400, 800);
        let mut mid = Vec::with_capacity(nt * np);
        for i in 0..nt {
            let th = (i as f64 + 0.5) / nt as f64 * PI / 2.0;
            for j in 0..np {
                let ph = (j as f64 + 0.5) / np as f64 * TAU;
                let w = th.sin() * (PI / 2.0 / nt as f64) * (TAU / np as f64);
                mid.push(([th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()], w));
            }
        }
        for (g, tol) in [(gram(&local_rule(3, 5)), 1e-14), (gram(&mid), 1e-5)] {
            for (i, row) in g.iter().enumerate() {
                for (j, v) in row.iter().enumerate() {
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((v - want).abs() < tol, "<H{}, H{}> = {v}", i + 1, j + 1);
                }
            }
        }
        // The peer's H1, 1/(2√π), has ∫H1² = 2π/(4π) = ½ over the hemisphere.
        assert!((TAU * (0.5 / PI.sqrt()).powi(2) - 0.5).abs() < 1e-15);
    }

    /// The frame is right-handed with N as its pole, and t is the hemisphere grid's +X image.
    #[test]
    fn frame_is_orthonormal() {
        let mut rng = Rng::new(1);
        for n in [DVec3::Y, DVec3::NEG_Y, DVec3::X, rng.unit(), rng.unit()] {
            let [t, s, nn] = frame(n);
            assert!((t.cross(s) - nn).length() < 1e-14 && t.dot(nn).abs() < 1e-14 && (nn - n).length() < 1e-14);
        }
        assert!((frame(DVec3::Y)[0] - DVec3::X).length() < 1e-15);
    }

    /// An SH L1 light's E/π, a + (2/3)·b·n′, is linear: in the span of H1–H4, so both encoders
    /// reproduce it over the hemisphere about any N to rounding.
    #[test]
    fn linear_irradiance_is_exact() {
        let mut rng = Rng::new(7);
        for _ in 0..20 {
            let sh = rng.sh().truncate(1);
            let n = rng.unit();
            let input = FitInput { surface_normal: Some(n), ..FitInput::sphere(&sh) };
            let want = sh.convolve_cosine();
            for count in [4, 6] {
                let fit = HBasisEncoder::new(count).fit(&input);
                for _ in 0..50 {
                    let mut d = rng.unit();
                    if d.dot(n) < 0.0 {
                        d = -d;
                    }
                    let (a, b) = (fit.irradiance(d), want.eval(d));
                    assert!((a - b).abs().max_element() < 1e-13, "H{count} at {d}: {a} vs {b}");
                }
            }
        }
    }

    /// A light whose E/π adds x·y in N's frame (N = +Y: t = +X, s = −Z, so x·y = −X·Z, the SH
    /// function −Y₂₁ ∝ x z up to its constant): H6 reproduces it exactly, H4 cannot (its
    /// error is the x·y term's norm, by orthonormality).
    #[test]
    fn the_xy_term_needs_h6() {
        let mut sh = Sh9::ZERO;
        sh.0[0] = Rgb::splat(2.0);
        sh.0[7] = Rgb::new(1.0, 0.5, 0.25); // Y₂₁ = −½√(15/π)·x·z
        let input = FitInput { surface_normal: Some(DVec3::Y), ..FitInput::sphere(&sh) };
        let want = sh.convolve_cosine();
        let h6 = HBasisEncoder::new(6).fit(&input);
        let h4 = HBasisEncoder::new(4).fit(&input);
        let mut rng = Rng::new(3);
        let mut worst4 = 0.0f64;
        for _ in 0..200 {
            let mut d = rng.unit();
            if d.y < 0.0 {
                d = -d;
            }
            assert!((h6.irradiance(d) - want.eval(d)).abs().max_element() < 1e-13);
            worst4 = worst4.max((h4.irradiance(d) - want.eval(d)).abs().max_element());
        }
        assert!(worst4 > 0.01, "{worst4}");
        let y21 = sh_basis(DVec3::new(1.0, 0.0, 1.0).normalize())[7];
        assert!((y21 + 0.25 * (15.0 / PI).sqrt()).abs() < 1e-15, "{y21}");
    }

    /// Without a surface normal the fit is sh1's: SH L1 irradiance of the visible light.
    #[test]
    fn without_n_it_is_sh1() {
        let sh = Rng::new(5).sh();
        let fit = HBasisEncoder::new(6).fit(&FitInput::sphere(&sh));
        let want = sh.truncate(1).convolve_cosine();
        for d in [DVec3::X, DVec3::NEG_Y, DVec3::new(0.3, 0.4, -0.866).normalize()] {
            assert!((fit.irradiance(d) - want.eval(d)).abs().max_element() < 1e-15);
        }
    }

    /// The lighting's exact E/π as a [`RadianceSource`] (only `irradiance` is read here).
    #[derive(Debug)]
    struct Analytic(Lighting, Sh25);

    impl RadianceSource for Analytic {
        fn sh4(&self) -> &Sh25 {
            &self.1
        }
        fn radiance(&self, _: DVec3) -> Rgb {
            Rgb::ZERO
        }
        fn samples(&self) -> &[RadianceSample] {
            &[]
        }
        fn irradiance(&self, n: DVec3) -> Rgb {
            self.0.irradiance(n)
        }
        fn irradiance_latlong(&self, _: usize, _: usize) -> Arc<Vec<Rgb>> {
            Arc::new(Vec::new())
        }
    }

    /// H4 is the least-squares fit over the hemisphere within span{1, x, y, z}, which holds
    /// the SH L1 irradiance of the visible light, and H6 contains H4: so on a sun and sky under
    /// the hemisphere effect, the hemisphere RMSE (measured by a 64 × 128 rule, not the fit's)
    /// goes sh1 ≥ H4 ≥ H6, and H4 is strictly better than sh1 here.
    #[test]
    fn h4_beats_the_sh1_irradiance_and_h6_beats_h4() {
        let n = DVec3::new(-0.2, 0.9, 0.4).normalize();
        let sun = (n + frame(n)[1] * 1.3).normalize();
        let lighting = Lighting(vec![
            Light::Ambient(Rgb::new(0.3, 0.35, 0.5)),
            Light::Cap { axis: sun, half_angle: 3f64.to_radians(), radiance: Rgb::new(300.0, 250.0, 200.0) },
        ])
        .visible(&[Cap::hemisphere(n)]);
        let sh = lighting.sh();
        let light = Analytic(lighting.clone(), Sh25::from_sh9(&sh));
        let input = FitInput { surface_normal: Some(n), radiance: Some(&light), ..FitInput::sphere(&sh) };
        let [t, s, nn] = frame(n);
        let err = |f: &dyn Fn(DVec3) -> Rgb| {
            let sum: f64 = local_rule(64, 128)
                .iter()
                .map(|&([x, y, z], w)| {
                    let d = t * x + s * y + nn * z;
                    w * (f(d) - lighting.irradiance(d)).length_squared()
                })
                .sum();
            (sum / TAU).sqrt()
        };
        let sh1 = sh.truncate(1).convolve_cosine();
        let (h4, h6) = (HBasisEncoder::new(4).fit(&input), HBasisEncoder::new(6).fit(&input));
        let (e1, e4, e6) = (err(&|d| sh1.eval(d)), err(&|d| h4.irradiance(d)), err(&|d| h6.irradiance(d)));
        assert!(e4 < 0.9 * e1 && e6 <= e4 * (1.0 + 1e-9), "hemisphere RMSE: sh1 {e1:.5}, H4 {e4:.5}, H6 {e6:.5}");
    }

    /// Under a sun (a small cap 500 times the sky's radiance, 50° from a tilted N, so its
    /// terminator crosses the hemisphere and puts a kink in E/π) and a sky, visible under the
    /// hemisphere effect, the 16 × 32 rule's coefficients are within 1e-4 of the largest of a
    /// 64 × 128 rule's (the product rule converges only as the square of its spacing across a
    /// kink).
    #[test]
    fn the_rule_has_converged_on_a_sun() {
        let n = DVec3::new(0.3, 0.8, -0.2).normalize();
        let sun = (n * 50f64.to_radians().cos() + frame(n)[0] * 50f64.to_radians().sin()).normalize();
        let lighting = Lighting(vec![
            Light::Ambient(Rgb::new(0.2, 0.3, 0.5)),
            Light::Cap { axis: sun, half_angle: 2f64.to_radians(), radiance: Rgb::new(500.0, 400.0, 300.0) },
        ])
        .visible(&[Cap::hemisphere(n)]);
        let light = Analytic(lighting.clone(), Sh25::from_sh9(&lighting.sh()));
        let sh = Sh9::ZERO;
        let input = FitInput { surface_normal: Some(n), radiance: Some(&light), ..FitInput::sphere(&sh) };
        let e = HBasisEncoder::new(6);
        let (a, b) = (e.fit_about(&input, n, RULE.0, RULE.1), e.fit_about(&input, n, 64, 128));
        let big = b.coeffs.iter().map(|c| c.abs().max_element()).fold(0.0, f64::max);
        let worst = (0..6).map(|k| (a.coeffs[k] - b.coeffs[k]).abs().max_element()).fold(0.0, f64::max) / big;
        assert!(worst < 1e-4, "16 x 32 against 64 x 128: {worst:e} of the largest coefficient");
    }
}
