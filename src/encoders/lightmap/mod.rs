//! Lightmap encodings: the AHD and HHD models (FORMULAS §7, §8), their IrradZ
//! storage (2018 brief eq. 4–7), the talk's HHD-from-linear-SH closed form, and the fits
//! (hemispherical and spherical Gram, linear or golden-section direction) that
//! `encoders/ahd.rs` and `encoders/hhd.rs` wrap.
//!
//! One concept per file: `model` (the two models and their linear SH), `irradz` (texel
//! storage), `from_sh1` (HHD from linear SH), `lune` (closed-form moments over the hemisphere,
//! the sphere and their lunes).

pub mod ahd;
pub mod encoder;
pub mod fit;
pub mod from_sh1;
pub mod hhd;
pub mod irradz;
pub mod lune;
pub mod model;

pub use from_sh1::hhd_from_linear_sh;
pub use irradz::{Storage, Texel};
pub use model::{linear_sh_of, Basis, Model};
