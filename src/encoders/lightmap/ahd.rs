//! AHD lightmap encoders (ambient + highlight direction, FORMULAS §7; 2018 brief): I(n) =
//! C_a + C_d·max(0, n·d), fitted to the bake's L2 SH irradiance (`lightmap::fit`).
//!
//! | id | direction | colours | Gram | storage (scalars) |
//! |---|---|---|---|---|
//! | `ahd_linear_sphere` | linear (L1) | free, non-negative LS | sphere | raw (8) |
//! | `ahd_linear_hemi` | linear | free | hemisphere about N | raw (8) |
//! | `ahd_search_sphere` | golden section in θ | free | sphere | raw (8) |
//! | `ahd_search_hemi` | golden section in θ | free | hemisphere | raw (8) |
//! | `ahd_irradz_2018` | linear | I_z fixed, min-norm + null space, non-negative | hemisphere | irradz_rgb (8) |
//!
//! Keys: `encoders/lightmap.rs`. Degenerate inputs: `lightmap::fit` (module docs).

use super::encoder::{build, Defaults};
use crate::encoders::encoder::{Encoder, Params};
use crate::encoders::lightmap::fit::{Colours, Gram};
use crate::encoders::lightmap::Basis;
use anyhow::Result;

fn ahd(gram: Gram, colours: Colours, search: bool) -> Defaults {
    let storage = if colours == Colours::IrradZ { "irradz_rgb" } else { "raw" };
    Defaults { basis: Basis::Ahd, gram, colours, search, storage }
}

/// Builds the `ahd_linear_sphere` encoder from its settings: AHD, L1 direction, sphere Gram. An
/// unknown or out-of-range setting is an error.
pub fn build_linear_sphere(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build("ahd_linear_sphere", ahd(Gram::Sphere, Colours::Free, false), p)
}
/// Builds the `ahd_linear_hemi` encoder from its settings: AHD, L1 direction, hemisphere Gram. An
/// unknown or out-of-range setting is an error.
pub fn build_linear_hemi(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build("ahd_linear_hemi", ahd(Gram::Hemisphere, Colours::Free, false), p)
}
/// Builds the `ahd_search_sphere` encoder from its settings: AHD, golden-section tilt, sphere Gram.
/// An unknown or out-of-range setting is an error.
pub fn build_search_sphere(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build("ahd_search_sphere", ahd(Gram::Sphere, Colours::Free, true), p)
}
/// Builds the `ahd_search_hemi` encoder from its settings: AHD, golden-section tilt, hemisphere
/// Gram. An unknown or out-of-range setting is an error.
pub fn build_search_hemi(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build("ahd_search_hemi", ahd(Gram::Hemisphere, Colours::Free, true), p)
}
/// Builds the `ahd_irradz_2018` encoder from its settings: AHD, I_z fixed, 2018 null-space fit. An
/// unknown or out-of-range setting is an error.
pub fn build_irradz_2018(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build("ahd_irradz_2018", ahd(Gram::Hemisphere, Colours::IrradZ, false), p)
}
