//! Spherical Gaussians (SGs) and their irradiance: the functions the SG encodings share.
//!
//! An SG with axis p, sharpness λ and amplitude μ is G(v) = μ·e^{λ(p·v − 1)} (Wang et al.,
//! "All-Frequency Rendering of Dynamic, Spatially-Varying Reflectance", SIGGRAPH Asia 2009,
//! §4; the peer's `SphericalGaussian.cpp`). λ = 0 is the constant μ (the peer's ambient lobe).
//!
//! - ∫ G dω = 4π·(1 − e^{−2λ})/(2λ) (`sgIntegral`), 4π at λ = 0.
//! - ∫ G_a·G_b dω = 4π·μ_a·μ_b·sinh(d)/(d·e^{λ_a+λ_b}), d = |λ_a p_a + λ_b p_b| (`sgDot`).
//! - Irradiance with an SG cosine lobe (the peer's naive and least-squares experiments): the
//!   clamped cosine about n is replaced by an SG of sharpness λ_B about n whose integral is π
//!   (μ_B = π/∫e^{λ_B(p·v−1)}dω), and E/π(n) = Σ_k ∫G_k·B_n dω / π.
//! - Irradiance by Hill's fit (the peer's running averages; S. Hill 2016, in M. Pettineo, "SG
//!   Series Part 3: Diffuse Lighting From an SG Light Source"; the peer's `sgIrradianceFitted`).
//!
//! Lobe directions: the peer's Vogel spiral (`sampleVogelsSphere` in the peer's `Math.h`, after
//! marmakoide's "Spreading points on a disc and on a sphere"), about the world +Z axis.

use crate::math::colour::Rgb;
use glam::DVec3;
use std::f64::consts::PI;

/// An SG lobe without its amplitude: unit axis p and sharpness λ ≥ 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lobe {
    /// Unit axis p.
    pub axis: DVec3,
    /// Sharpness λ (≥ 0).
    pub sharpness: f64,
}

impl Lobe {
    /// e^{λ(p·v − 1)}: the lobe at unit direction v, with amplitude 1.
    pub fn weight(&self, v: DVec3) -> f64 {
        (self.sharpness * (self.axis.dot(v) - 1.0)).exp()
    }
}

/// Point i of n on the peer's Vogel spiral (`sampleVogelsSphere`): azimuth i·π(3 − √5) about
/// +Z, z from 1 − 1/n down to 1/n − 1 in equal steps (z = 0 for n = 1).
pub fn vogel_sphere(i: usize, n: usize) -> DVec3 {
    let golden_angle = PI * (3.0 - 5f64.sqrt());
    let theta = golden_angle * i as f64;
    let t = if n > 1 { i as f64 / (n - 1) as f64 } else { 0.5 };
    let (z0, z1) = (1.0 - 1.0 / n as f64, 1.0 / n as f64 - 1.0);
    let z = z0 + (z1 - z0) * t;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = theta.sin_cos();
    DVec3::new(r * c, r * s, z)
}

/// The peer's lobe set: `count` lobes of sharpness `sharpness` on the Vogel spiral.
pub fn vogel_lobes(count: usize, sharpness: f64) -> Vec<Lobe> {
    (0..count).map(|i| Lobe { axis: vogel_sphere(i, count), sharpness }).collect()
}

/// ∫ e^{λ(p·v − 1)} dω over the sphere = 2π(1 − e^{−2λ})/λ (`sgIntegral`); 4π at λ = 0.
pub fn sg_integral(lambda: f64) -> f64 {
    if lambda < 1e-8 {
        // 2π(2 − 2λ + …): the series keeps full precision near 0.
        return 4.0 * PI * (1.0 - lambda);
    }
    2.0 * PI * -(-2.0 * lambda).exp_m1() / lambda
}

/// ∫ G_a·G_b dω for unit amplitudes (`sgDot`): 4π·sinh(d)/(d·e^{λ_a+λ_b}),
/// d = |λ_a p_a + λ_b p_b|, written as 2π(e^{d−s} − e^{−d−s})/d (s = λ_a + λ_b ≥ d) so that
/// nothing overflows; d → 0 gives 4π·e^{−s}.
pub fn sg_inner(a: &Lobe, b: &Lobe) -> f64 {
    let s = a.sharpness + b.sharpness;
    let d = (a.sharpness * a.axis + b.sharpness * b.axis).length();
    if d < 1e-8 {
        return 4.0 * PI * (-s).exp() * (1.0 + d * d / 6.0);
    }
    2.0 * PI * ((d - s).exp() - (-d - s).exp()) / d
}

/// The naive fit's normalisation (`sgBasisNormalizationFactor`): 4λ²/((1 − e^{−2λ})·K). The
/// peer notes "there is no solid basis for this"; it makes a constant radiance c project to
/// amplitudes c·2λ/K (exactly c for the peer's λ = K/2, since the mean of one lobe over the
/// sphere is (1 − e^{−2λ})/(2λ)).
pub fn naive_normalisation(lambda: f64, count: usize) -> f64 {
    4.0 * lambda * lambda / (-(-2.0 * lambda).exp_m1() * count as f64)
}

/// The irradiance rule of a fitted SG basis (what turns the radiance lobes into E/π).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IrradianceRule {
    /// The clamped cosine replaced by an SG of this sharpness whose integral is π.
    CosineLobe(f64),
    /// Hill's curve fit of one SG's irradiance (`sgIrradianceFitted`).
    HillFit,
}

impl IrradianceRule {
    /// E/π at unit normal n of the lobe with amplitude 1 (a channel's E/π is Σ_k μ_k times this).
    pub fn lobe_irradiance(&self, lobe: &Lobe, n: DVec3) -> f64 {
        match *self {
            IrradianceRule::CosineLobe(lambda_b) => {
                // μ_B·∫G_k·e^{λ_B(n·v−1)}dω/π with μ_B = π/∫e^{λ_B(n·v−1)}dω.
                let b = Lobe { axis: n, sharpness: lambda_b };
                sg_inner(lobe, &b) / sg_integral(lambda_b)
            }
            IrradianceRule::HillFit => hill_irradiance(lobe, n) / PI,
        }
    }
}

/// Hill's fitted irradiance ∫ e^{λ(p·v−1)}·max(0, n·v) dω of a unit-amplitude SG (S. Hill 2016,
/// as the peer's `sgIrradianceFitted`): with c₀ = 0.36, c₁ = 1/(4c₀), t = p·n,
/// scale = 1 + 2e^{−2λ} − 1/λ, bias = (e^{−λ} − e^{−2λ})/λ − e^{−2λ}, x = √(1 − scale):
/// y = (c₀t + c₁x)²/x where |c₀t| ≤ c₁x, else max(t, 0); the result is
/// (scale·y + bias)·∫G dω. λ = 0 (a constant lobe) gives π, the exact value; the peer returns
/// μ there, a factor π short, but never builds a λ = 0 lobe with this rule (its running
/// averages have no ambient lobe).
pub fn hill_irradiance(lobe: &Lobe, n: DVec3) -> f64 {
    let lambda = lobe.sharpness;
    if lambda == 0.0 {
        return PI;
    }
    let t = lobe.axis.dot(n);
    let c0 = 0.36;
    let c1 = 1.0 / (4.0 * c0);
    let eml = (-lambda).exp();
    let em2l = eml * eml;
    let rl = 1.0 / lambda;
    let scale = 1.0 + 2.0 * em2l - rl;
    let bias = (eml - em2l) * rl - em2l;
    let x = (1.0 - scale).max(0.0).sqrt();
    let x0 = c0 * t;
    let x1 = c1 * x;
    let y = if x0.abs() <= x1 {
        let s = x0 + x1;
        s * s / x
    } else {
        t.clamp(0.0, 1.0)
    };
    (scale * y + bias) * sg_integral(lambda)
}

/// E/π at n of the lobes with their RGB amplitudes, under `rule`.
pub fn irradiance(lobes: &[Lobe], amplitudes: &[Rgb], rule: IrradianceRule, n: DVec3) -> Rgb {
    lobes.iter().zip(amplitudes).map(|(l, &mu)| mu * rule.lobe_irradiance(l, n)).sum()
}

/// The radiance Σ_k μ_k·e^{λ_k(p_k·v−1)} of the lobes at unit direction v.
#[cfg(test)]
pub fn radiance(lobes: &[Lobe], amplitudes: &[Rgb], v: DVec3) -> Rgb {
    lobes.iter().zip(amplitudes).map(|(l, &mu)| mu * l.weight(v)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quadrature::gauss_legendre;
    use crate::math::test_rng::Rng;

    /// ∫ f dω over the sphere by a product rule in (z = cos θ, φ) about +Z: Gauss–Legendre in
    /// z split at `breaks`, the trapezoid rule (exact for trigonometric polynomials) in φ.
    fn sphere_integral(f: impl Fn(DVec3) -> f64, breaks: &[f64]) -> f64 {
        let gl = gauss_legendre(24);
        let mut edges = vec![-1.0];
        edges.extend(breaks.iter().copied().filter(|b| b.abs() < 1.0));
        edges.push(1.0);
        edges.sort_by(f64::total_cmp);
        let nphi = 256;
        let mut sum = 0.0;
        for w in edges.windows(2) {
            let (a, b) = (w[0], w[1]);
            for &(x, wx) in &gl {
                let z = 0.5 * (a + b) + 0.5 * (b - a) * x;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let mut row = 0.0;
                for k in 0..nphi {
                    let phi = 2.0 * PI * (k as f64 + 0.5) / nphi as f64;
                    row += f(DVec3::new(r * phi.cos(), r * phi.sin(), z));
                }
                sum += 0.5 * (b - a) * wx * row * 2.0 * PI / nphi as f64;
            }
        }
        sum
    }

    #[test]
    fn vogel_points_are_unit_and_spread_in_z() {
        // z runs linearly from 1 − 1/n to 1/n − 1; point 0 sits at azimuth 0.
        let n = 12;
        for i in 0..n {
            let p = vogel_sphere(i, n);
            assert!((p.length() - 1.0).abs() < 1e-15);
            let z = (1.0 - 1.0 / 12.0) - i as f64 * (2.0 - 2.0 / 12.0) / 11.0;
            assert!((p.z - z).abs() < 1e-15, "{i}: {} vs {z}", p.z);
        }
        let p0 = vogel_sphere(0, n);
        assert!(p0.y.abs() < 1e-15 && p0.x > 0.0);
        // Successive points turn by the golden angle, 137.5°.
        let (a1, a2) = (vogel_sphere(1, n), vogel_sphere(2, n));
        let turn = (a2.y.atan2(a2.x) - a1.y.atan2(a1.x)).rem_euclid(2.0 * PI);
        assert!((turn - PI * (3.0 - 5f64.sqrt())).abs() < 1e-12);
        assert_eq!(vogel_sphere(0, 1), DVec3::X);
    }

    #[test]
    fn sg_integral_and_inner_match_quadrature() {
        let mut rng = Rng::new(7);
        for &lambda in &[0.0, 1e-9, 0.5, 3.0, 6.0, 8.5] {
            let l = Lobe { axis: DVec3::Z, sharpness: lambda };
            let q = sphere_integral(|v| l.weight(v), &[]);
            assert!((sg_integral(lambda) - q).abs() < 1e-10 * q, "λ={lambda}: {} vs {q}", sg_integral(lambda));
        }
        for _ in 0..6 {
            let a = Lobe { axis: DVec3::Z, sharpness: 6.0 };
            let b = Lobe { axis: rng.unit(), sharpness: 3.0 * (rng.next() + 1.0) };
            let q = sphere_integral(|v| a.weight(v) * b.weight(v), &[]);
            let c = sg_inner(&a, &b);
            assert!((c - q).abs() < 1e-9 * q, "{c} vs {q}");
            assert!((sg_inner(&b, &a) - c).abs() < 1e-15 * c);
        }
        // d = 0: equal and opposite lobes, e^{−2λ}·4π.
        let a = Lobe { axis: DVec3::Z, sharpness: 2.0 };
        let b = Lobe { axis: DVec3::NEG_Z, sharpness: 2.0 };
        let q = sphere_integral(|v| a.weight(v) * b.weight(v), &[]);
        assert!((sg_inner(&a, &b) - q).abs() < 1e-12 * q);
    }

    #[test]
    fn naive_normalisation_maps_a_constant_to_its_value() {
        // c·normalisation·mean(lobe) = c·2λ/K; for λ = K/2 that is c.
        let f = naive_normalisation(6.0, 12);
        let mean = sg_integral(6.0) / (4.0 * PI);
        assert!((f * mean - 1.0).abs() < 1e-15);
    }

    #[test]
    fn cosine_lobe_rule_integrates_to_pi_and_maps_a_constant_to_itself() {
        // The SG cosine lobe has integral π, so a constant radiance c (a λ = 0 lobe of
        // amplitude c) gives E/π = c exactly, as the clamped cosine does.
        for lambda_b in [3.0, 8.5] {
            let rule = IrradianceRule::CosineLobe(lambda_b);
            let ambient = Lobe { axis: DVec3::Z, sharpness: 0.0 };
            for n in [DVec3::X, DVec3::NEG_Z, DVec3::new(0.6, 0.0, 0.8)] {
                assert!((rule.lobe_irradiance(&ambient, n) - 1.0).abs() < 1e-13);
            }
        }
        // And a lobe's E/π is ∫ G·B_n dω/π, computed by quadrature of the product.
        let lobe = Lobe { axis: vogel_sphere(3, 12), sharpness: 6.0 };
        let n = DVec3::new(0.3, -0.4, 0.866).normalize();
        let mu_b = PI / sg_integral(3.0);
        let b = Lobe { axis: n, sharpness: 3.0 };
        let q = sphere_integral(|v| lobe.weight(v) * mu_b * b.weight(v), &[]) / PI;
        let c = IrradianceRule::CosineLobe(3.0).lobe_irradiance(&lobe, n);
        assert!((c - q).abs() < 1e-10 * q, "{c} vs {q}");
    }

    #[test]
    fn hill_fit_is_close_to_the_exact_irradiance_of_a_lobe() {
        // Hill's fit against ∫ G·max(0, n·v) dω by quadrature (split at the terminator z = 0
        // about n): within 2% of the lobe's peak irradiance at every angle, for the peer's
        // λ = 6 and for a wider and a sharper lobe (measured: 0.3%, 1.5%, 1.4%; the fit is
        // poorer for wide lobes, 9.6% at λ = 1).
        for lambda in [3.0, 6.0, 30.0] {
            let mut peak = 0.0f64;
            let mut worst = 0.0f64;
            for k in 0..=36 {
                let angle = PI * k as f64 / 36.0;
                // Lobe along +Z, normal tilted by `angle`; integrate in the normal's frame.
                let n = DVec3::new(angle.sin(), 0.0, angle.cos());
                let lobe = Lobe { axis: DVec3::Z, sharpness: lambda };
                let (t1, t2) = (DVec3::new(angle.cos(), 0.0, -angle.sin()), DVec3::Y);
                let exact = sphere_integral(
                    |v| {
                        let world = v.x * t1 + v.y * t2 + v.z * n;
                        lobe.weight(world) * v.z.max(0.0)
                    },
                    &[0.0],
                );
                let fit = hill_irradiance(&lobe, n);
                peak = peak.max(exact);
                worst = worst.max((fit - exact).abs());
            }
            assert!(worst < 0.02 * peak, "λ={lambda}: worst {worst} of peak {peak}");
        }
    }

    #[test]
    fn irradiance_sums_the_lobes() {
        let lobes = vogel_lobes(12, 6.0);
        let amps: Vec<Rgb> = (0..12).map(|k| Rgb::new(k as f64, 1.0, -0.5)).collect();
        let n = DVec3::new(0.2, 0.9, -0.1).normalize();
        for rule in [IrradianceRule::CosineLobe(8.5), IrradianceRule::HillFit] {
            let e = irradiance(&lobes, &amps, rule, n);
            let by_hand: Rgb = (0..12).map(|k| amps[k] * rule.lobe_irradiance(&lobes[k], n)).sum();
            assert!((e - by_hand).abs().max_element() < 1e-12);
        }
        let v = DVec3::Y;
        let r = radiance(&lobes, &amps, v);
        let by_hand: Rgb = (0..12).map(|k| amps[k] * (6.0 * (lobes[k].axis.y - 1.0)).exp()).sum();
        assert!((r - by_hand).abs().max_element() < 1e-12);
    }
}
