//! The reference layer: what an encoder is scored against. The exact irradiance of a
//! piecewise-constant map at any normal, optionally under caps (`exact`); the exact SH
//! projection of a map (`projection`); analytic lighting with closed-form irradiance and SH, its
//! visible part under caps and its rotation (`lighting`); named analytic scenes and their exact
//! cell-average maps (`scenes`); the output grids a score is taken over (`domain`); the error
//! metrics (`metrics`); the light an encoder may read beyond L2 SH — SH through band 4,
//! radiance samples, exact E/π at any normal (`radiance`); and the views of the sphere of normals that pictures evaluate at (`view`).
//!
//! What this layer may use: the layer table of ARCHITECTURE.md (checked by
//! `tests/architecture.rs`).

pub(crate) mod antipode;
pub mod domain;
pub mod exact;
pub mod lighting;
pub mod metrics;
pub mod projection;
pub mod radiance;
pub mod row_convolution;
pub(crate) mod row_fft;
pub(crate) mod row_pairs;
pub mod scenes;
pub(crate) mod shared_kernel;
pub mod view;
