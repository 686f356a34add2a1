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
//! **Clamping.** The peer writes every SG irradiance image unclamped; [`crate::encoders::encoder::Encoder::peer_clamps`]
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

mod encoder;
pub mod fit;
pub mod lobes;
mod variant;

pub use encoder::{build_ls, build_ls_ambient, build_naive, build_nnls, build_nnra, build_ra};

#[cfg(test)]
mod tests;
