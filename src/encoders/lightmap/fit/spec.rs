//! What a lightmap fit is asked for (FORMULAS §7, §8): the Gram (hemisphere about N or
//! sphere), how the colours are found (free NNLS or I_z fixed), how the direction is chosen
//! (linear, or a golden-section search), and the basis.

use super::super::model::Basis;
use crate::math::colour::Rgb;

/// Which Gram (domain of the least squares).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gram {
    /// The whole sphere of normals.
    Sphere,
    /// The hemisphere about N.
    Hemisphere,
}

/// How the colours are fitted for a fixed direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Colours {
    /// C_a and C_d unconstrained but non-negative (a two-variable NNLS per channel).
    Free,
    /// The IrradZ constraint: the irradiance at N is I_z exactly, one free parameter left.
    IrradZ,
}

/// How the direction is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Direction {
    /// The optimal linear direction: d along the band-1 SH vector, channels weighted by
    /// `FitSpec::direction_weights`.
    Linear,
    /// Golden section in θ: at most `iterations` steps, stopping when the bracket is narrower
    /// than `tolerance` (radians).
    Search {
        /// The most golden-section steps.
        iterations: usize,
        /// The bracket width at which the search stops (radians).
        tolerance: f64,
    },
    /// The same in θ, then alternating golden sections in the azimuth φ (over ±90° about the
    /// current azimuth, at the current θ) and in θ, `rounds` times (a 2-D search).
    Search2d {
        /// The most golden-section steps of each 1-D search.
        iterations: usize,
        /// The bracket width at which each 1-D search stops (radians).
        tolerance: f64,
        /// How many φ-then-θ rounds follow the first θ search.
        rounds: usize,
    },
}

/// Everything that defines a fit.
#[derive(Clone, Copy, Debug)]
pub struct FitSpec {
    /// The model fitted: AHD or HHD.
    pub basis: Basis,
    /// The domain of normals the error is integrated over.
    pub gram: Gram,
    /// How the colours are fitted for a fixed direction.
    pub colours: Colours,
    /// How the direction is chosen.
    pub direction: Direction,
    /// Largest tilt of d from N (radians).
    pub max_tilt: f64,
    /// Channel weights of the search error (equal thirds: the tables' rmse).
    pub weights: Rgb,
    /// Channel weights of the linear (L1) direction (Rec.709, FORMULAS §4).
    pub direction_weights: Rgb,
    /// Take I_z from `FitInput::exact_at_normal` when present (else from the SH).
    pub exact_i_z: bool,
}
