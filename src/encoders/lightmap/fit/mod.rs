//! The AHD/HHD least-squares fits (2018 brief; hemispherical-lighting talk;
//! FORMULAS §7, §8): colours by least squares over the hemisphere about N (hemispherical Gram)
//! or over the sphere (spherical Gram), for a direction d that is the optimal linear one (the
//! Rec.709-weighted L1 vector, FORMULAS §4) or found by a golden-section search in its tilt θ
//! from N at the L1 azimuth.
//!
//! **FitTarget.** The L2 SH irradiance q (E/π) of the bake's visible radiance, a quadratic
//! polynomial; every inner product of q and of the basis functions 1, H(n) = (1 + n·N)/2 and
//! max(0, n·d) over the domain is a moment of degree ≤ 3 over the domain or its lune
//! (`lune.rs`), so the fit has no quadrature. Any other target (e.g. an exact irradiance by
//! quadrature, for the claims) enters through [`FitTarget`].
//!
//! **Colours** for a fixed d, per channel:
//! - `Free`: (C_a, C_d) minimising the error with C_a, C_d ≥ 0 (a two-variable NNLS: the
//!   unconstrained solution if non-negative, else the better one-variable solution).
//! - `IrradZ`: I(N) = I_z fixed; I(n) = I_z·[w·f_a(n) + (1 − w)·max(0, n·d)/d_z], w ∈ [0, 1]
//!   by linear least squares (the talk's ambient weight w_a for HHD; for AHD the same line is
//!   the 2018 brief's minimum-norm solution I_z/(d_z² + 1)·(1, d_z) plus the null space
//!   t·(−d_z, 1), searched over the t that keep both colours non-negative — solved in closed
//!   form, since the error is quadratic in t). C_a = w·I_z, C_d = (1 − w)·I_z/d_z.
//!
//! **Direction search.** Golden section over θ ∈ [0, θ_max] (θ_max = 89° by default, so that
//! d_z > 0 for IrradZ), with the channel errors summed with `weights`; the endpoint θ = 0
//! (d = N: the H1 optimum, which a bracket never reaches exactly) and the linear θ are also
//! evaluated and the best of the three is kept, so the search is never worse than the linear
//! direction in the fit's own error.
//!
//! **Degenerate inputs (documented fallbacks).**
//! - Black (every coefficient and I_z zero): the zero model.
//! - No surface normal (a probe on the sphere): the fit is over the sphere and N is taken to be
//!   the linear direction, d = N (with no surface there is no tilt to search, so searched
//!   encoders use the linear direction). I_z (IrradZ) is then q(N).
//! - No surface normal and no usable direction (|L1| ≤ 1e-9 of the largest coefficient, after
//!   scaling the input to order one): pure ambient, the band-0 answer — an AHD with C_a = the
//!   mean E/π and C_d = 0, whatever the encoder's basis (HHD cannot represent a constant on the
//!   sphere, so its own best fit would be worse than pure ambient).
//! - A surface normal and no usable direction: d = N (θ = 0), and the search azimuth is the
//!   frame's first tangent.
//!
//! The input is scaled by a power of two to order one before fitting (so 1e-300 and 1e+300
//! inputs neither underflow nor overflow when squared) and the colours scaled back.
//!
//! One concept per file: `spec.rs` (what a fit is asked for), `target.rs` (the frame about N,
//! the target and its domain), `least_squares.rs` (the colours for a fixed direction),
//! `search.rs` (the golden-section direction search), `bake.rs` (the fit of one bake: scaling,
//! fallbacks, the searches) and `tests.rs`.

mod bake;
mod least_squares;
pub(crate) mod search;
mod spec;
pub(crate) mod target;
#[cfg(test)]
mod tests;

pub use bake::fit;
pub use search::MAX_GOLDEN_STEPS;
pub use spec::{Colours, Direction, FitSpec, Gram};
