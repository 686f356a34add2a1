//! Geomerics' non-linear reconstruction of irradiance from linear SH (W. Joseph, "Reconstructing
//! diffuse lighting from spherical harmonic data", CEDEC 2015; discussed in the ZH3 talk,
//! "hallucinating coefficients"). Per channel, FORMULAS §6:
//!
//! - R0 = Y₀₀·L₀₀ (the mean radiance), R1 = (1/√(12π))·(−L₁,₁, −L₁,₋₁, L₁,₀) (the mean of ω·L);
//! - q = ½(1 + R̂1·n), p = 1 + 2|R1|/R0, a = (1 − |R1|/R0)/(1 + |R1|/R0);
//! - E/π(n) = R0·(a + (1 − a)(p + 1)·q^p).
//!
//! The normalisation is ours (derived): a constant environment of radiance 1 gives exactly 1,
//! and the mean over the sphere is R0 for any input (∮q^p dω = 4π/(p + 1)), so the DC term is
//! kept. |R1|/R0 ≤ 1 for non-negative radiance, with 1 for a delta light.
//!
//! | id               | what | stored scalars |
//! |------------------|------|----------------|
//! | `geomerics`      | as above | 12 |
//! | `geomerics_peer` | the peer tool's variant: R0 = L₀₀, R1 = ½·L1, result /π; unclamped when scored with `--metric probulator`. A constant environment gives 2/√π ≈ 1.128. Cross-checks only. | 12 |
//!
//! TOML keys: none. Degenerate inputs: R0 ≤ 0 gives 0; R1 = 0 gives the constant R0.

use crate::encoders::encoder::{fit_each_unboxed, sq_errors_unboxed, Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::stored::{Role, Stored, Unit, Value};
use crate::math::colour::Rgb;
use crate::math::sh::{basis, Sh9, N_SH};
use anyhow::Result;
use glam::DVec3;
use std::f64::consts::PI;

/// One channel's Geomerics parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeomericsChannel {
    /// R0: the mean radiance (or the peer's L₀₀), FORMULAS §6.
    pub r0: f64,
    /// R1 (the mean of ω·L over the sphere, or the peer's ½·L1).
    pub r1: DVec3,
    /// Overall factor on the result (1, or 1/π for the peer's variant).
    pub scale: f64,
}

impl GeomericsChannel {
    /// E/π at unit normal n (FORMULAS §6).
    pub fn eval(&self, n: DVec3) -> f64 {
        if self.r0.is_nan() || self.r0 <= 0.0 {
            return 0.0;
        }
        let len = self.r1.length();
        if len == 0.0 {
            return self.scale * self.r0;
        }
        let rho = len / self.r0;
        let q = (0.5 * (1.0 + self.r1.dot(n) / len)).clamp(0.0, 1.0);
        let p = 1.0 + 2.0 * rho;
        let a = (1.0 - rho) / (1.0 + rho);
        self.scale * self.r0 * (a + (1.0 - a) * (p + 1.0) * q.powf(p))
    }

    /// This channel's E/π split into its SH3 projection (the coefficients of Y₀…Y₈, FORMULAS
    /// §2) and the energy ∫(E − its SH3 projection)² dω of its bands ≥ 3, both in closed form.
    ///
    /// E/π = s·R0·(a + b·q^p) with b = (1 − a)(p + 1) is zonal about u = R̂1 in t = u·n, and
    /// q = (1 + t)/2. By Funk–Hecke its coefficients are 4π·s·R0·I_l·Y_lm(u), with
    /// I_l = ∫₀¹ (a + b q^p) P_l(2q − 1) dq: I₀ = a + b/(p + 1), I₁ = b·p/((p + 1)(p + 2)),
    /// I₂ = b·p(p − 1)/((p + 1)(p + 2)(p + 3)). The energy of bands ≥ 3 is
    /// ∫E² − Σ_l (2l + 1)·4π(sR0)²I_l² = 4π(sR0)²·b²·h(p), with
    /// h(p) = p²(p − 1)²(p − 2)² / ((p + 1)²(p + 2)²(p + 3)²(2p + 1)) (derived: the a-terms
    /// cancel exactly, and the factored form keeps full precision; h = 0 at p = 1 and 2, where
    /// q^p is a polynomial of degree ≤ 2 in t). Same degenerate answers as [`Self::eval`].
    pub fn sh3_projection(&self) -> ([f64; N_SH], f64) {
        let mut d = [0.0; N_SH];
        if self.r0.is_nan() || self.r0 <= 0.0 {
            return (d, 0.0);
        }
        let len = self.r1.length();
        let k = 4.0 * PI * self.scale * self.r0;
        // No R1: the constant s·R0 (ρ = 0 gives a = 1, b = 0, so any axis will do).
        let (rho, u) = if len == 0.0 { (0.0, DVec3::Z) } else { (len / self.r0, self.r1 / len) };
        let p = 1.0 + 2.0 * rho;
        let a = (1.0 - rho) / (1.0 + rho);
        let b = (1.0 - a) * (p + 1.0);
        let (p1, p2, p3) = (p + 1.0, p + 2.0, p + 3.0);
        let i = [a + b / p1, b * p / (p1 * p2), b * p * (p - 1.0) / (p1 * p2 * p3)];
        let y = basis(u);
        for (m, (dm, ym)) in d.iter_mut().zip(y).enumerate() {
            let l = if m == 0 {
                0
            } else if m < 4 {
                1
            } else {
                2
            };
            *dm = k * i[l] * ym;
        }
        let h = (p * (p - 1.0) * (p - 2.0) / (p1 * p2 * p3)).powi(2) / (2.0 * p + 1.0);
        (d, k * self.scale * self.r0 * b * b * h)
    }
}

/// Geomerics from radiance SH, correctly normalised (FORMULAS §6).
pub fn fit(sh: &Sh9) -> [GeomericsChannel; 3] {
    // Y₀₀ = 1/√(4π); dividing (rather than multiplying by Y₀₀) keeps a constant exact.
    let (k0, k1) = ((4.0 * PI).sqrt(), (12.0 * PI).sqrt());
    std::array::from_fn(|c| GeomericsChannel { r0: sh[0][c] / k0, r1: sh.l1_vector(c) / k1, scale: 1.0 })
}

/// The peer tool's Geomerics: R0 = L₀₀, R1 = ½·L1, evaluated as E and divided by π.
pub fn fit_peer(sh: &Sh9) -> [GeomericsChannel; 3] {
    std::array::from_fn(|c| GeomericsChannel { r0: sh[0][c], r1: sh.l1_vector(c) * 0.5, scale: 1.0 / PI })
}

/// The Geomerics L1 encoder (`geomerics`, or `geomerics_peer` with the peer tool's normalisation).
pub struct Geomerics {
    peer: bool,
}

struct GeomericsFit([GeomericsChannel; 3]);

impl Fitted for GeomericsFit {
    fn irradiance(&self, n: DVec3) -> Rgb {
        Rgb::new(self.0[0].eval(n), self.0[1].eval(n), self.0[2].eval(n))
    }
    /// R0 (RGB) and the three components of R1 (RGB each), radiance units: 12 scalars; the
    /// overall factor (1, or the peer's 1/π) is the encoder's constant (FORMULAS §6).
    fn stored(&self) -> Stored {
        let ch = &self.0;
        let rgb = |f: &dyn Fn(&GeomericsChannel) -> f64| Rgb::new(f(&ch[0]), f(&ch[1]), f(&ch[2]));
        let mut s = Stored::new(
            "per channel E/pi(n) = scale*R0*(a + (1 - a)*(p + 1)*q^p), q = (1 + n.R1/|R1|)/2, p = 1 + 2|R1|/R0, \
             a = (1 - |R1|/R0)/(1 + |R1|/R0), R1 = (R1_x, R1_y, R1_z) of the channel; R0 <= 0 gives 0 and R1 = 0 \
             gives scale*R0 (docs/conventions.md section 6); n a world direction, +Y up (section 1)",
        );
        s.rgb("R0", Unit::Radiance, rgb(&|c| c.r0));
        s.rgb("R1_x", Unit::Radiance, rgb(&|c| c.r1.x));
        s.rgb("R1_y", Unit::Radiance, rgb(&|c| c.r1.y));
        s.rgb("R1_z", Unit::Radiance, rgb(&|c| c.r1.z));
        s.push(Role::Derived, "scale", Unit::Unitless, Value::Scalar(ch[0].scale));
        s
    }
    /// Exact (to rounding) by [`GeomericsChannel::sh3_projection`]: the in-band error is the
    /// coefficient difference (Parseval), the out-of-band energy is the reconstruction's own.
    fn sphere_sq_error(&self, reference: &Sh9) -> Option<f64> {
        let mut se = 0.0;
        for (c, ch) in self.0.iter().enumerate() {
            let (d, rest) = ch.sh3_projection();
            se += rest;
            for (i, di) in d.iter().enumerate() {
                se += (di - reference[i][c]).powi(2);
            }
        }
        Some(se)
    }
}

impl Geomerics {
    /// The fit of radiance SH `sh`, with this variant's normalisation.
    fn fit_geomerics(&self, sh: &Sh9) -> GeomericsFit {
        GeomericsFit(if self.peer { fit_peer(sh) } else { fit(sh) })
    }
}

impl Encoder for Geomerics {
    fn id(&self) -> &str {
        if self.peer {
            "geomerics_peer"
        } else {
            "geomerics"
        }
    }
    fn family(&self) -> Family {
        Family::Geomerics
    }
    fn stored_scalars(&self) -> usize {
        12
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        Box::new(self.fit_geomerics(input.visible_sh))
    }
    fn fit_sphere_each(&self, probes: &[Sh9], visit: &mut dyn FnMut(usize, &dyn Fitted)) {
        fit_each_unboxed(probes, visit, |p| self.fit_geomerics(p));
    }
    fn sphere_sq_errors(&self, probes: &[Sh9], irradiance: &[Sh9], out: &mut [f64]) -> bool {
        sq_errors_unboxed(probes, irradiance, out, |p| self.fit_geomerics(p))
    }
    /// The peer tool scores its Geomerics without clamping (FORMULAS §10).
    fn peer_clamps(&self) -> bool {
        !self.peer
    }
    /// The peer variant carries the 2/√π bias of FORMULAS §6 on purpose.
    fn degrades_input(&self) -> bool {
        self.peer
    }
}

/// Builds the `geomerics` encoder from its settings: Geomerics L1 reconstruction, normalised. An
/// unknown or out-of-range setting is an error.
pub fn build_geomerics(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("geomerics")?;
    Ok(Box::new(Geomerics { peer: false }))
}
/// Builds the `geomerics_peer` encoder from its settings: Geomerics as the peer tool (R0=L00,
/// R1=L1/2). An unknown or out-of-range setting is an error.
pub fn build_geomerics_peer(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("geomerics_peer")?;
    Ok(Box::new(Geomerics { peer: true }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::sh::{constant, delta_light};

    fn enc(peer: bool, sh: &Sh9) -> Box<dyn Fitted> {
        Geomerics { peer }.fit(&FitInput::sphere(sh))
    }

    #[test]
    fn constant_environment_gives_exactly_one() {
        let f = enc(false, &constant(Rgb::ONE));
        for n in crate::reference::domain::fibonacci_sphere(50) {
            assert_eq!(f.irradiance(n), Rgb::ONE * 1.0, "{n}");
        }
        // The peer's variant carries 2/√π.
        let g = enc(true, &constant(Rgb::ONE)).irradiance(DVec3::Y);
        assert!((g.x - 2.0 / PI.sqrt()).abs() < 1e-14);
    }

    /// |R1|/R0 = 1 for a delta light: a = 0, p = 3, so E/π = R0·4·q³ with R0 = e/(4π); at the
    /// light's direction q = 1. Independently, the mean over the sphere is R0 (DC kept), checked
    /// by quadrature over a Fibonacci set.
    #[test]
    fn delta_light_and_kept_dc() {
        let d = DVec3::new(0.2, -0.4, 0.89).normalize();
        let e = 2.5;
        let sh = delta_light(d, Rgb::splat(e));
        let ch = fit(&sh)[0];
        assert!((ch.r1.length() / ch.r0 - 1.0).abs() < 1e-14);
        assert!((ch.eval(d) - 4.0 * e / (4.0 * PI)).abs() < 1e-14);
        assert!(ch.eval(-d).abs() < 1e-14);
        let pts = crate::reference::domain::fibonacci_sphere(200_000);
        let mean = pts.iter().map(|&n| ch.eval(n)).sum::<f64>() / pts.len() as f64;
        assert!((mean - e / (4.0 * PI)).abs() < 1e-5 * mean, "{mean}");
    }

    /// ∫ over the sphere of `f(n)` by a rule aligned with `u`: t = u·n = 2s² − 1 (so the
    /// reconstruction's (1 + t)^p, singular in a derivative at t = −1, becomes the smooth
    /// s^(2p+1)), 64 Gauss–Legendre nodes in s, 16 azimuths (exact for the azimuthal
    /// trigonometric polynomials of degree ≤ 4 that products of SH3 with a zonal function are).
    fn aligned_integral(u: DVec3, f: impl Fn(DVec3) -> f64) -> f64 {
        let e1 = u.any_orthonormal_vector();
        let e2 = u.cross(e1);
        let mut sum = 0.0;
        for (x, w) in crate::math::quadrature::gauss_legendre(64) {
            let s = 0.5 * (x + 1.0);
            let t = 2.0 * s * s - 1.0;
            let r = (1.0 - t * t).max(0.0).sqrt();
            // dt = 4s ds, ds = dx/2; dω = dt dφ.
            let wt = w * 0.5 * 4.0 * s;
            for k in 0..16 {
                let (sp, cp) = (std::f64::consts::TAU * (k as f64 + 0.25) / 16.0).sin_cos();
                let n = u * t + (e1 * cp + e2 * sp) * r;
                sum += wt * (std::f64::consts::TAU / 16.0) * f(n);
            }
        }
        sum
    }

    /// The closed-form SH3 projection, out-of-band energy and squared error against an SH3
    /// agree with quadrature of the evaluated reconstruction (`powf`), to 1e-12, for ratios
    /// |R1|/R0 from 0 to 1 (p = 1…3, including p = 2 where the out-of-band energy vanishes),
    /// the peer variant and a ratio above 1 (possible for inputs with negative radiance).
    #[test]
    fn sh3_projection_and_error_match_quadrature() {
        let u = DVec3::new(0.3, -0.7, 0.5).normalize();
        let mut reference = Sh9::ZERO;
        for i in 0..N_SH {
            reference[i] = Rgb::new(0.3 - 0.07 * i as f64, 0.1 * (i as f64).sin(), 0.05 * i as f64 - 0.2);
        }
        for (rho, scale) in [(0.0, 1.0), (1e-3, 1.0), (0.2, 1.0), (0.5, 1.0), (0.77, 1.0 / PI), (1.0, 1.0), (1.4, 1.0)]
        {
            let ch = GeomericsChannel { r0: 0.8, r1: u * (0.8 * rho), scale };
            let (d, rest) = ch.sh3_projection();
            let axis = if rho == 0.0 { DVec3::Z } else { u };
            for (i, di) in d.iter().enumerate() {
                let want = aligned_integral(axis, |n| ch.eval(n) * basis(n)[i]);
                assert!((di - want).abs() < 1e-12 * ch.r0, "rho {rho} coefficient {i}: {di} vs {want}");
            }
            let energy = aligned_integral(axis, |n| ch.eval(n).powi(2));
            let in_band: f64 = d.iter().map(|x| x * x).sum();
            assert!((rest - (energy - in_band)).abs() < 1e-12 * energy, "rho {rho}: {rest} vs {}", energy - in_band);
            if rho == 0.0 || rho == 0.5 {
                assert!(rest.abs() < 1e-15 * energy, "rho {rho}: q^p is SH3, rest {rest}");
            } else if rho >= 0.2 {
                assert!(rest > 1e-9 * energy, "rho {rho}: rest {rest}");
            }
            let fit = GeomericsFit([ch; 3]);
            let se = fit.sphere_sq_error(&reference).unwrap();
            let want: f64 =
                (0..3).map(|c| aligned_integral(axis, |n| (ch.eval(n) - reference.eval(n)[c]).powi(2))).sum();
            assert!((se - want).abs() < 1e-12 * want, "rho {rho}: {se} vs {want}");
        }
        // Degenerate: black gives the reference's own energy (Parseval).
        let black = GeomericsFit([GeomericsChannel { r0: 0.0, r1: DVec3::X, scale: 1.0 }; 3]);
        let own: f64 = (0..N_SH).map(|i| reference[i].length_squared()).sum();
        assert_eq!(black.sphere_sq_error(&reference), Some(own));
    }

    /// Through the encoder on a real fit: error 0 for a constant environment (exactly SH3).
    #[test]
    fn closed_form_error_of_fits() {
        let sh = constant(Rgb::new(0.5, 1.0, 2.0));
        let f = enc(false, &sh);
        assert!(f.sphere_sq_error(&sh.convolve_cosine()).unwrap() < 1e-28);
        let sh =
            delta_light(DVec3::new(0.1, 0.9, -0.3).normalize(), Rgb::new(3.0, 2.0, 1.0)) + constant(Rgb::splat(0.2));
        for peer in [false, true] {
            let f = enc(peer, &sh);
            let reference = sh.convolve_cosine();
            let se = f.sphere_sq_error(&reference).unwrap();
            // An independent check by a dense Fibonacci set (equal-area points).
            let pts = crate::reference::domain::fibonacci_sphere(400_000);
            let mc = pts.iter().map(|&n| (f.irradiance(n) - reference.eval(n)).length_squared()).sum::<f64>()
                * (4.0 * PI / pts.len() as f64);
            assert!((se - mc).abs() < 1e-4 * mc, "peer {peer}: {se} vs {mc}");
        }
    }

    #[test]
    fn degenerate_inputs_are_finite() {
        let f = enc(false, &Sh9::ZERO);
        assert_eq!(f.irradiance(DVec3::X), Rgb::ZERO);
        let mut sh = constant(Rgb::ONE);
        sh[0].y = 0.0;
        let v = enc(false, &sh).irradiance(DVec3::X);
        assert!(v.is_finite() && v.y == 0.0);
        assert!(!Geomerics { peer: true }.peer_clamps() && Geomerics { peer: false }.peer_clamps());
    }
}
