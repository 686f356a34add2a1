//! The SG encoder: one of the peer's variants fitted to radiance samples, its fitted lobes and
//! amplitudes, the stored form, and the registry's builders.

use crate::encoders::encoder::{Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::sg::fit::{self, Design};
use crate::encoders::sg::lobes::{self, IrradianceRule, Lobe};
use crate::encoders::sg::variant::{peer_design, peer_lobes, Variant};
use crate::encoders::stored::{Role, Stored, Unit, Value};
use crate::math::colour::Rgb;
use crate::reference::radiance::RadianceSample;
use anyhow::Result;
use glam::DVec3;
use std::sync::Arc;

/// One of the peer's SG encodings.
#[derive(Clone, Copy, Debug)]
pub struct SphericalGaussians {
    /// Which variant.
    pub(super) variant: Variant,
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
    #[cfg(test)]
    pub fn amplitudes(&self) -> &[Rgb] {
        &self.amplitudes
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

/// The encoder of `variant`; it takes no settings.
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
