//! HHD lightmap encoders (hemisphere + highlight direction, FORMULAS §8; the
//! hemispherical-lighting talk): I(n) = C_a·H(n) + C_d·max(0, n·d), H(n) = (1 + n·N)/2.
//!
//! | id | direction | colours | Gram | storage (scalars) |
//! |---|---|---|---|---|
//! | `hhd_linear_sphere` | linear (L1) | IrradZ: I_z fixed, ambient weight w_a ∈ [0, 1] by LS | sphere | irradz_rgb (8) |
//! | `hhd_linear_hemi` | linear | IrradZ, w_a by LS | hemisphere about N | irradz_rgb (8) |
//! | `hhd_search_sphere` | golden section in θ | IrradZ, w_a by LS | sphere | irradz_rgb (8) |
//! | `hhd_search_hemi` | golden section in θ | IrradZ, w_a by LS | hemisphere | irradz_rgb (8) |
//! | `hhd_from_sh1` | the talk's closed form from the linear SH | closed form | — | the linear SH (12) |
//!
//! The fitted encoders take the keys of `encoders/lightmap.rs`. `hhd_from_sh1` stores the
//! texel's linear SH (12 scalars) and solves the HHD at run time as the talk does
//! (`lightmap::hhd_from_linear_sh`, with I_z = b·N); key `storage` = `sh1` (default), or
//! `raw`/`irradz_rgb`/`irradz_luma` to store the solved HHD instead. With no surface normal
//! (a sphere probe) N is the Rec.709 L1 direction; with no usable direction either, the answer
//! is pure ambient (the band-0 irradiance), as for the fitted encoders (`lightmap::fit`).

use super::encoder::{build, Defaults, LightmapFit, TexelSource};
use crate::encoders::encoder::{Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::lightmap::fit::{Colours, Gram};
use crate::encoders::lightmap::{hhd_from_linear_sh, Basis, Model, Storage, Texel};
use crate::math::colour::Rgb;
use crate::math::colour::REC709;
use crate::math::sh::{k, Sh9};
use anyhow::Result;
use glam::DVec3;

fn hhd(gram: Gram, search: bool) -> Defaults {
    Defaults { basis: Basis::Hhd, gram, colours: Colours::IrradZ, search, storage: "irradz_rgb" }
}

/// Builds the `hhd_linear_sphere` encoder from its settings: HHD IrradZ, L1 direction, sphere Gram.
/// An unknown or out-of-range setting is an error.
pub fn build_linear_sphere(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build("hhd_linear_sphere", hhd(Gram::Sphere, false), p)
}
/// Builds the `hhd_linear_hemi` encoder from its settings: HHD IrradZ, L1 direction, hemisphere
/// Gram. An unknown or out-of-range setting is an error.
pub fn build_linear_hemi(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build("hhd_linear_hemi", hhd(Gram::Hemisphere, false), p)
}
/// Builds the `hhd_search_sphere` encoder from its settings: HHD IrradZ, golden-section tilt,
/// sphere Gram. An unknown or out-of-range setting is an error.
pub fn build_search_sphere(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build("hhd_search_sphere", hhd(Gram::Sphere, true), p)
}
/// Builds the `hhd_search_hemi` encoder from its settings: HHD IrradZ, golden-section tilt,
/// hemisphere Gram. An unknown or out-of-range setting is an error.
pub fn build_search_hemi(p: &mut Params) -> Result<Box<dyn Encoder>> {
    build("hhd_search_hemi", hhd(Gram::Hemisphere, true), p)
}

/// `hhd_from_sh1`: the talk's closed form.
pub struct HhdFromSh1 {
    /// `None`: the texel stores the linear SH.
    storage: Option<Storage>,
}

/// Builds the `hhd_from_sh1` encoder from its settings: HHD from linear SH, talk's closed form. An
/// unknown or out-of-range setting is an error.
pub fn build_from_sh1(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let s = p.str_or("storage", "sh1")?;
    let storage = if s == "sh1" { None } else { Some(Storage::parse(&s)?) };
    p.finish("hhd_from_sh1")?;
    Ok(Box::new(HhdFromSh1 { storage }))
}

impl Encoder for HhdFromSh1 {
    fn id(&self) -> &str {
        "hhd_from_sh1"
    }
    fn family(&self) -> Family {
        Family::Hhd
    }
    fn stored_scalars(&self) -> usize {
        self.storage.map_or(12, Storage::scalars)
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        // The stored texel: the linear SH of the bake (bands 0–1).
        let sh: Sh9 = input.visible_sh.truncate(1);
        let ok = sh.is_finite();
        let l1 = sh.l1_vector_weighted(REC709);
        let big = sh.0.iter().map(|c| c.abs().max_element()).fold(0.0, f64::max);
        let normal = input.surface_normal.and_then(|n| n.try_normalize()).filter(|n| n.is_finite());
        let usable = big > 0.0 && l1.length() > 1e-9 * big;
        let model = match (ok && big > 0.0, normal) {
            (false, n) => Model::black(Basis::Hhd, n.unwrap_or(DVec3::Z)),
            (true, Some(n)) => hhd_from_linear_sh(&sh, n),
            (true, None) if usable => hhd_from_linear_sh(&sh, l1.normalize()),
            (true, None) => Model {
                basis: Basis::Ahd,
                normal: DVec3::Z,
                c_a: (sh[0] * k::Y00).max(Rgb::ZERO),
                c_d: Rgb::ZERO,
                d: DVec3::Z,
            },
        };
        let (model, source) = match self.storage {
            Some(st) => {
                let t = Texel::encode(&model, st);
                (t.decode(), TexelSource::Texel(t))
            }
            None => (model, TexelSource::LinearSh(sh)),
        };
        Box::new(LightmapFit {
            model,
            source,
            diagnostics: vec![("theta_deg", model.d.dot(model.normal).clamp(-1.0, 1.0).acos().to_degrees())],
        })
    }
    /// C_a, C_d are clamped ≥ 0 and H ≥ 0.
    fn promises_non_negative(&self) -> bool {
        true
    }
    fn is_scale_covariant(&self) -> bool {
        true
    }
    fn is_rotation_covariant(&self) -> bool {
        true
    }
    /// The talk's closed form solves the HHD about N; without N it uses the L1 direction.
    fn needs_surface_normal(&self) -> bool {
        true
    }
}
