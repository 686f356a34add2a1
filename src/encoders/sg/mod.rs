//! Spherical-Gaussian (SG) encodings of the peer tool (kayru/Probulator at ad916bd:
//! `ExperimentSG.h`, `SGBasis.cpp`, `SphericalGaussian.cpp`, `SGFitLeastSquares.cpp`; set up in
//! `Experiments.cpp`, `addAllExperiments`). SGs after Wang et al. 2009 (§4); the SG series of
//! M. Pettineo (2016) for the cosine-lobe and fitted irradiance; the running average after
//! T. Roughton (2018). The math is in [`lobes`], the fits in [`fit`].
//!
//! Every variant fits K = 12 lobes of sharpness λ = 6 (the peer's `0.5·lobeCount`) on the
//! peer's Vogel spiral about +Z ([`lobes::vogel_lobes`]) to the peer's radiance sample set:
//! 20,000 Halton(2, 3) directions, uniform on the sphere, each reading the map's nearest texel
//! ([`crate::reference::radiance::RadianceSource::samples`]; for an input with only L2 SH,
//! the band-limited radiance of those SH). Amplitudes are RGB.
//!
//! | id | peer | fit of the amplitudes | E/π from the lobes | stored scalars |
//! |----|------|-----------------------|--------------------|----------------|
//! | `sg_naive` | SG | scaled projection, f = 4λ²/((1 − e^{−2λ})K) | SG cosine lobe, λ_B = 8.5 | 36 |
//! | `sg_ls` | SGLS | least squares | SG cosine lobe, λ_B = 3 | 36 |
//! | `sg_ls_ambient` | SGLSA | least squares, plus a constant (λ = 0) lobe | SG cosine lobe, λ_B = 3 | 39 |
//! | `sg_nnls` | SGNNLS | non-negative least squares (Lawson–Hanson) | SG cosine lobe, λ_B = 3 | 36 |
//! | `sg_ra` | SGRA | running average in the sample order | Hill's fit | 36 |
//! | `sg_nnra` | SGNNRA | running average, clamped ≥ 0 after each update | Hill's fit | 36 |
//!
//! λ_B is the peer's ("chosen arbitrarily through experimentation"); the SG cosine lobe is
//! scaled to integrate to π, so a constant radiance c gives E/π = c.
//!
//! **Clamping.** The peer writes every SG irradiance image unclamped; [`Encoder::peer_clamps`]
//! is therefore false for all six (only the least-squares and plain running-average fits can
//! go negative on non-negative radiance).
//!
//! **Sample order.** Only the running averages depend on it; they use the peer's Halton order,
//! reproduced exactly ([`crate::math::halton`]). The fits are in f64 where the peer's are in
//! f32.
//!
//! **Cost.** The sample directions are fixed, so the sample matrix A, AᵀA and its
//! pseudo-inverse are built once per process for the peer's set (a fit then costs one pass
//! over the samples, Aᵀb, and a 12×12 product); a sample set with other directions gets its
//! own design, built in the fit.
//!
//! TOML keys: none. Degenerate inputs: black gives all amplitudes 0 (every fit is linear in
//! the radiance, or positively homogeneous for the non-negative ones).

pub mod fit;
pub mod lobes;

use crate::encoders::encoder::{Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::stored::{Role, Stored, Unit, Value};
use crate::math::colour::Rgb;
use crate::math::halton::{peer_sphere_directions, PEER_SAMPLE_COUNT};
use crate::reference::radiance::RadianceSample;
use anyhow::Result;
use fit::Design;
use glam::DVec3;
use lobes::{IrradianceRule, Lobe};
use std::sync::{Arc, OnceLock};

/// The peer's lobe count (`addAllExperiments`: `lobeCount = 12`).
pub const LOBE_COUNT: usize = 12;
/// The peer's lobe sharpness, `0.5·lobeCount`.
pub const LOBE_SHARPNESS: f64 = 0.5 * LOBE_COUNT as f64;
/// The cosine lobe's sharpness for the naive fit (the peer's `setBrdfLambda(8.5f)`).
pub const COSINE_SHARPNESS_NAIVE: f64 = 8.5;
/// The cosine lobe's sharpness for the least-squares fits (`setBrdfLambda(3.0f)`).
pub const COSINE_SHARPNESS_LS: f64 = 3.0;

/// Which of the peer's SG experiments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// `sg_naive`: scaled projection onto the lobes (peer SG).
    Naive,
    /// `sg_ls`: least squares (peer SGLS).
    LeastSquares,
    /// `sg_ls_ambient`: least squares plus a constant (λ = 0) lobe (peer SGLSA).
    LeastSquaresAmbient,
    /// `sg_nnls`: non-negative least squares, Lawson–Hanson (peer SGNNLS).
    NonNegativeLeastSquares,
    /// `sg_ra`: running average in the sample order (peer SGRA).
    RunningAverage,
    /// `sg_nnra`: running average clamped ≥ 0 after each update (peer SGNNRA).
    NonNegativeRunningAverage,
}

impl Variant {
    fn id(self) -> &'static str {
        match self {
            Variant::Naive => "sg_naive",
            Variant::LeastSquares => "sg_ls",
            Variant::LeastSquaresAmbient => "sg_ls_ambient",
            Variant::NonNegativeLeastSquares => "sg_nnls",
            Variant::RunningAverage => "sg_ra",
            Variant::NonNegativeRunningAverage => "sg_nnra",
        }
    }

    fn ambient(self) -> bool {
        self == Variant::LeastSquaresAmbient
    }

    fn rule(self) -> IrradianceRule {
        match self {
            Variant::Naive => IrradianceRule::CosineLobe(COSINE_SHARPNESS_NAIVE),
            Variant::LeastSquares | Variant::LeastSquaresAmbient | Variant::NonNegativeLeastSquares => {
                IrradianceRule::CosineLobe(COSINE_SHARPNESS_LS)
            }
            Variant::RunningAverage | Variant::NonNegativeRunningAverage => IrradianceRule::HillFit,
        }
    }
}

/// The lobe set: the peer's 12 Vogel lobes, plus the constant lobe (axis +Z, λ = 0) when
/// `ambient`, last as the peer appends it.
pub fn peer_lobes(ambient: bool) -> Vec<Lobe> {
    let mut l = lobes::vogel_lobes(LOBE_COUNT, LOBE_SHARPNESS);
    if ambient {
        l.push(Lobe { axis: DVec3::Z, sharpness: 0.0 });
    }
    l
}

/// The design of the peer's lobe set on the peer's sample directions, built once.
fn peer_design(ambient: bool) -> &'static Design {
    static PLAIN: OnceLock<Design> = OnceLock::new();
    static AMBIENT: OnceLock<Design> = OnceLock::new();
    let cell = if ambient { &AMBIENT } else { &PLAIN };
    cell.get_or_init(|| Design::new(&peer_lobes(ambient), &peer_sphere_directions(PEER_SAMPLE_COUNT)))
}

/// One of the peer's SG encodings.
#[derive(Clone, Copy, Debug)]
pub struct SphericalGaussians {
    variant: Variant,
}

/// A fitted SG basis: lobes, RGB amplitudes and the irradiance rule.
#[derive(Clone, Debug)]
pub struct SgFit {
    lobes: Arc<[Lobe]>,
    amplitudes: Vec<Rgb>,
    rule: IrradianceRule,
    /// Lawson–Hanson outer iterations (NNLS only).
    iterations: Option<usize>,
}

impl SgFit {
    /// The RGB amplitude of each lobe, in the order of [`SgFit::lobes`].
    pub fn amplitudes(&self) -> &[Rgb] {
        &self.amplitudes
    }
    /// The lobes (axes and sharpness).
    pub fn lobes(&self) -> &[Lobe] {
        &self.lobes
    }
}

impl Fitted for SgFit {
    fn irradiance(&self, n: DVec3) -> Rgb {
        lobes::irradiance(&self.lobes, &self.amplitudes, self.rule, n)
    }
    /// The RGB radiance amplitude μ_k of each lobe (3 per lobe); the lobes' axes and
    /// sharpnesses are the encoder's constants (the peer's Vogel set), listed derived.
    fn stored(&self) -> Stored {
        let rule = match self.rule {
            IrradianceRule::CosineLobe(l) => format!(
                "the clamped cosine about n replaced by an SG of sharpness {l} about n whose integral is pi: \
                 E/pi(n) = sum_k mu_k * integral(G_k B_n)/pi"
            ),
            IrradianceRule::HillFit => "E/pi(n) = sum_k mu_k * Hill's fitted SG irradiance of lobe k at n".to_string(),
        };
        let mut s = Stored::new(format!(
            "radiance L(v) = sum_k mu_k*exp(lambda_k*(p_k.v - 1)) (lobe k: mu_k stored, axis p_k and sharpness \
             lambda_k the encoder's constants, sg/lobes.rs); {rule}; world directions, +Y up (docs/conventions.md \
             section 1)"
        ));
        for (k, mu) in self.amplitudes.iter().enumerate() {
            s.rgb(format!("mu_{k}"), Unit::Radiance, *mu);
        }
        for (k, l) in self.lobes.iter().enumerate() {
            s.push(Role::Derived, format!("axis_{k}"), Unit::Direction, Value::Vector(l.axis));
            s.push(Role::Derived, format!("sharpness_{k}"), Unit::Unitless, Value::Scalar(l.sharpness));
        }
        s
    }
    fn diagnostics(&self) -> Vec<(&'static str, f64)> {
        match self.iterations {
            Some(i) => vec![("iters", i as f64)],
            None => Vec::new(),
        }
    }
}

impl SphericalGaussians {
    /// Fits the amplitudes to radiance samples (any directions; the peer's set uses the cached
    /// design).
    pub fn fit_samples(&self, samples: &[RadianceSample]) -> SgFit {
        let ambient = self.variant.ambient();
        let cached = peer_design(ambient);
        let own;
        let same = cached.samples() == samples.len()
            && samples.iter().zip(cached.directions()).all(|(s, d)| s.direction == *d);
        let design = if same {
            cached
        } else {
            let dirs: Vec<DVec3> = samples.iter().map(|s| s.direction).collect();
            own = Design::new(&peer_lobes(ambient), &dirs);
            &own
        };
        let values: Vec<Rgb> = samples.iter().map(|s| s.radiance).collect();
        let mut iterations = None;
        let amplitudes = match self.variant {
            Variant::Naive => fit::naive(design, &values),
            Variant::LeastSquares | Variant::LeastSquaresAmbient => fit::least_squares(design, &values),
            Variant::NonNegativeLeastSquares => {
                let f = fit::non_negative_least_squares(design, &values);
                iterations = Some(f.iterations);
                f.amplitudes
            }
            Variant::RunningAverage => fit::running_average(design, &values, false),
            Variant::NonNegativeRunningAverage => fit::running_average(design, &values, true),
        };
        // A non-finite sample (impossible from a validated map) must not leak NaN into output.
        let amplitudes = amplitudes.into_iter().map(|a| if a.is_finite() { a } else { Rgb::ZERO }).collect();
        SgFit { lobes: design.lobes().into(), amplitudes, rule: self.variant.rule(), iterations }
    }
}

impl Encoder for SphericalGaussians {
    fn reads_radiance(&self) -> bool {
        true
    }

    fn id(&self) -> &str {
        self.variant.id()
    }
    fn family(&self) -> Family {
        Family::SphericalGaussians
    }
    fn stored_scalars(&self) -> usize {
        3 * peer_lobes(self.variant.ambient()).len()
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        let light = input.light();
        Box::new(self.fit_samples(light.samples()))
    }
    /// The peer writes its SG irradiance images unclamped (`ExperimentSGBase::
    /// generateIrradianceImage`).
    fn peer_clamps(&self) -> bool {
        false
    }
    fn is_iterative(&self) -> bool {
        self.variant == Variant::NonNegativeLeastSquares
    }
    /// A fixed set of 12 lobes cannot represent a constant, so on a light with no direction
    /// these fits can be worse than the band-0 answer; they are kept for parity with the peer.
    fn degrades_input(&self) -> bool {
        true
    }
    fn promises_non_negative(&self) -> bool {
        matches!(self.variant, Variant::NonNegativeLeastSquares | Variant::NonNegativeRunningAverage)
    }
    fn is_scale_covariant(&self) -> bool {
        true
    }
}

fn build(p: &mut Params, variant: Variant) -> Result<Box<dyn Encoder>> {
    p.finish(variant.id())?;
    Ok(Box::new(SphericalGaussians { variant }))
}

/// Builds the `sg_naive` encoder from its settings: 12 SGs, naive projection (peer SG). An unknown
/// or out-of-range setting is an error.
pub fn build_naive(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build(p, Variant::Naive)
}
/// Builds the `sg_ls` encoder from its settings: 12 SGs, least squares (peer SGLS). An unknown or
/// out-of-range setting is an error.
pub fn build_ls(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build(p, Variant::LeastSquares)
}
/// Builds the `sg_ls_ambient` encoder from its settings: 12 SGs + ambient, least squares (peer
/// SGLSA). An unknown or out-of-range setting is an error.
pub fn build_ls_ambient(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build(p, Variant::LeastSquaresAmbient)
}
/// Builds the `sg_nnls` encoder from its settings: 12 SGs, non-negative least squares (peer
/// SGNNLS). An unknown or out-of-range setting is an error.
pub fn build_nnls(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build(p, Variant::NonNegativeLeastSquares)
}
/// Builds the `sg_ra` encoder from its settings: 12 SGs, running average (peer SGRA). An unknown or
/// out-of-range setting is an error.
pub fn build_ra(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build(p, Variant::RunningAverage)
}
/// Builds the `sg_nnra` encoder from its settings: 12 SGs, non-negative running average (peer
/// SGNNRA). An unknown or out-of-range setting is an error.
pub fn build_nnra(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build(p, Variant::NonNegativeRunningAverage)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples_of(f: impl Fn(DVec3) -> Rgb) -> Vec<RadianceSample> {
        peer_sphere_directions(PEER_SAMPLE_COUNT)
            .into_iter()
            .map(|d| RadianceSample { direction: d, radiance: f(d) })
            .collect()
    }

    const ALL: [Variant; 6] = [
        Variant::Naive,
        Variant::LeastSquares,
        Variant::LeastSquaresAmbient,
        Variant::NonNegativeLeastSquares,
        Variant::RunningAverage,
        Variant::NonNegativeRunningAverage,
    ];

    #[test]
    fn stored_scalars_are_the_lobes_rgb() {
        for v in ALL {
            let want = if v == Variant::LeastSquaresAmbient { 39 } else { 36 };
            assert_eq!(SphericalGaussians { variant: v }.stored_scalars(), want, "{v:?}");
        }
    }

    #[test]
    fn ls_ambient_reproduces_a_constant_and_the_others_come_close() {
        // A constant c: the ambient lobe takes it exactly (E/π = c); the 12 lobes alone
        // approximate it (the naive projection gives amplitudes ≈ c, whose sum over the lobes
        // is not flat), all within 15%.
        let c = Rgb::new(0.5, 1.0, 2.0);
        let samples = samples_of(|_| c);
        for v in ALL {
            let fit = SphericalGaussians { variant: v }.fit_samples(&samples);
            for n in [DVec3::X, DVec3::Y, DVec3::NEG_Z, DVec3::new(0.3, -0.5, 0.81).normalize()] {
                let e = fit.irradiance(n);
                let rel = ((e - c) / c).abs().max_element();
                if v == Variant::LeastSquaresAmbient {
                    assert!(rel < 1e-9, "{v:?} at {n}: {e}");
                } else {
                    assert!(rel < 0.15, "{v:?} at {n}: {e} vs {c}");
                }
            }
        }
    }

    #[test]
    fn other_sample_directions_get_their_own_design() {
        // The same radiance sampled at a different set of directions fits through a fresh
        // design: a lobe-shaped radiance is recovered by least squares either way.
        let lobes = peer_lobes(false);
        let truth: Vec<Rgb> = (0..12).map(|k| Rgb::splat(k as f64 * 0.1)).collect();
        let f = |d: DVec3| lobes::radiance(&lobes, &truth, d);
        let enc = SphericalGaussians { variant: Variant::LeastSquares };
        let peer = enc.fit_samples(&samples_of(f));
        let other: Vec<RadianceSample> = peer_sphere_directions(5000)
            .into_iter()
            .map(|d| DVec3::new(d.y, d.z, d.x))
            .map(|d| RadianceSample { direction: d, radiance: f(d) })
            .collect();
        let own = enc.fit_samples(&other);
        for ((a, b), t) in peer.amplitudes().iter().zip(own.amplitudes()).zip(&truth) {
            assert!((*a - *t).abs().max_element() < 1e-9 && (*b - *t).abs().max_element() < 1e-9);
        }
    }
}
