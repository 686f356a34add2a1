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

use crate::encoder::{Encoder, FitInput, Fitted, Params};
use crate::sh::{Rgb, Sh9};
use anyhow::Result;
use glam::DVec3;
use std::f64::consts::PI;

/// One channel's Geomerics parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeomericsChannel {
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

pub struct Geomerics {
    peer: bool,
}

struct GeomericsFit([GeomericsChannel; 3]);

impl Fitted for GeomericsFit {
    fn irradiance(&self, n: DVec3) -> Rgb {
        Rgb::new(self.0[0].eval(n), self.0[1].eval(n), self.0[2].eval(n))
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
    fn stored_scalars(&self) -> usize {
        12
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        let sh = input.visible_sh;
        Box::new(GeomericsFit(if self.peer { fit_peer(sh) } else { fit(sh) }))
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

pub fn build_geomerics(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("geomerics")?;
    Ok(Box::new(Geomerics { peer: false }))
}
pub fn build_geomerics_peer(p: &mut Params) -> Result<Box<dyn Encoder>> {
    p.finish("geomerics_peer")?;
    Ok(Box::new(Geomerics { peer: true }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::{constant, delta_light};

    fn enc(peer: bool, sh: &Sh9) -> Box<dyn Fitted> {
        Geomerics { peer }.fit(&FitInput::sphere(sh))
    }

    #[test]
    fn constant_environment_gives_exactly_one() {
        let f = enc(false, &constant(Rgb::ONE));
        for n in crate::domain::fibonacci_sphere(50) {
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
        let pts = crate::domain::fibonacci_sphere(200_000);
        let mean = pts.iter().map(|&n| ch.eval(n)).sum::<f64>() / pts.len() as f64;
        assert!((mean - e / (4.0 * PI)).abs() < 1e-5 * mean, "{mean}");
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
