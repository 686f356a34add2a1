//! The peer's six SG variants (kayru/Probulator, `addAllExperiments`) and its lobe set: 12 Vogel
//! lobes of sharpness 6, the constant lobe for the ambient variant, and their design on the
//! peer's sample directions, built once per process.

use crate::encoders::sg::fit::Design;
use crate::encoders::sg::lobes::{self, IrradianceRule, Lobe};
use crate::math::halton::{peer_sphere_directions, PEER_SAMPLE_COUNT};
use glam::DVec3;
use std::sync::OnceLock;

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
    /// The registered id.
    pub(super) fn id(self) -> &'static str {
        match self {
            Variant::Naive => "sg_naive",
            Variant::LeastSquares => "sg_ls",
            Variant::LeastSquaresAmbient => "sg_ls_ambient",
            Variant::NonNegativeLeastSquares => "sg_nnls",
            Variant::RunningAverage => "sg_ra",
            Variant::NonNegativeRunningAverage => "sg_nnra",
        }
    }

    /// Whether the constant lobe is fitted too.
    pub(super) fn ambient(self) -> bool {
        self == Variant::LeastSquaresAmbient
    }

    /// How the lobes give irradiance.
    pub(super) fn rule(self) -> IrradianceRule {
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
pub(super) fn peer_design(ambient: bool) -> &'static Design {
    static PLAIN: OnceLock<Design> = OnceLock::new();
    static AMBIENT: OnceLock<Design> = OnceLock::new();
    let cell = if ambient { &AMBIENT } else { &PLAIN };
    cell.get_or_init(|| Design::new(&peer_lobes(ambient), &peer_sphere_directions(PEER_SAMPLE_COUNT)))
}
