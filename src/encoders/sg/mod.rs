//! Spherical Gaussians (placeholder module header, replaced when the encoders land).

pub mod fit;
pub mod lobes;
