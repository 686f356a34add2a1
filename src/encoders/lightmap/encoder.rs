//! The encoder shared by the AHD (`ahd.rs`) and HHD (`hhd.rs`) lightmap encodings: a fit of
//! `lightmap::fit`, stored as a `lightmap::Texel` and decoded before evaluating.
//!
//! TOML keys (every one optional; defaults are each encoder's row in ahd.rs/hhd.rs):
//!
//! | key | values | meaning |
//! |---|---|---|
//! | `storage` | `raw`, `irradz_rgb`, `irradz_luma` | texel layout (8, 8, 6 scalars) |
//! | `colours` | `free`, `irradz` | non-negative least squares, or I_z fixed with the ambient weight in [0, 1] |
//! | `iz` | `exact`, `sh` | I_z from the bake's exact irradiance at N, or from the L2 SH at N |
//! | `max_tilt_deg` | (0, 90) | largest tilt of d from N (default 89) |
//! | `weights` | `equal`, `rec709`, [r, g, b] (each in [0, 1e6], not all 0) | channel weights of the search error (default equal: the tables' rmse) |
//! | `direction_weights` | as `weights` | channel weights of the linear L1 direction (default rec709, FORMULAS §4) |
//! | `iterations` | 0 to 200 | golden-section iterations, searched encoders (default 30) |
//! | `tolerance_rad` | (0, π] | stop when the θ bracket is narrower (default 1e-6) |
//! | `search` | `theta`, `theta_phi` | searched encoders: golden section in θ at the L1 azimuth (default), or alternating θ and φ (2-D) |
//! | `rounds` | 0 to 16 | `theta_phi`: alternations of φ and θ (default 2) |
//!
//! Diagnostics: `theta_deg` (tilt of d from N), and for searched encoders `iters`, `evals`;
//! `fallback` = 1 when the pure-ambient fallback was used (see `lightmap::fit`).

use crate::encoders::encoder::{named_weights, Encoder, FitInput, Fitted, Params};
use crate::encoders::lightmap::fit::{fit, Colours, Direction, FitSpec, Gram, MAX_GOLDEN_STEPS};
use crate::encoders::lightmap::{Basis, Model, Storage, Texel};
use crate::math::colour::Rgb;
use anyhow::{bail, Result};
use glam::DVec3;
use std::ops::Bound::{Excluded, Included};

/// An AHD/HHD lightmap encoder.
pub struct LightmapEncoder {
    pub id: &'static str,
    pub spec: FitSpec,
    pub storage: Storage,
}

/// A fitted texel, decoded.
pub struct LightmapFit {
    pub model: Model,
    pub diagnostics: Vec<(&'static str, f64)>,
}

impl Fitted for LightmapFit {
    fn irradiance(&self, n: DVec3) -> Rgb {
        self.model.irradiance(n)
    }
    fn diagnostics(&self) -> Vec<(&'static str, f64)> {
        self.diagnostics.clone()
    }
}

/// The defaults of one encoder row.
pub struct Defaults {
    pub basis: Basis,
    pub gram: Gram,
    pub colours: Colours,
    pub search: bool,
    pub storage: &'static str,
}

/// Builds an encoder from its defaults and the TOML keys of the module docs.
pub fn build(id: &'static str, def: Defaults, p: &mut Params) -> Result<Box<dyn Encoder>> {
    let storage = Storage::parse(&p.str_or("storage", def.storage)?)?;
    let colours = match p.str_or("colours", if def.colours == Colours::Free { "free" } else { "irradz" })?.as_str() {
        "free" => Colours::Free,
        "irradz" => Colours::IrradZ,
        s => bail!("key 'colours': expected 'free' or 'irradz', got '{s}'"),
    };
    let exact_i_z = match p.str_or("iz", "exact")?.as_str() {
        "exact" => true,
        "sh" => false,
        s => bail!("key 'iz': expected 'exact' or 'sh', got '{s}'"),
    };
    let max_tilt = p.f64_in("max_tilt_deg", 89.0, (Excluded(0.0), Excluded(90.0)))?;
    let weights = p.weights_or("weights", named_weights("equal")?)?;
    let direction_weights = p.weights_or("direction_weights", named_weights("rec709")?)?;
    let direction = if def.search {
        let iterations = p.usize_in("iterations", 30, 0..=MAX_GOLDEN_STEPS)?;
        let tolerance = p.f64_in("tolerance_rad", 1e-6, (Excluded(0.0), Included(std::f64::consts::PI)))?;
        match p.str_or("search", "theta")?.as_str() {
            "theta" => Direction::Search { iterations, tolerance },
            "theta_phi" => Direction::Search2d { iterations, tolerance, rounds: p.usize_in("rounds", 2, 0..=16)? },
            s => bail!("key 'search': expected 'theta' or 'theta_phi', got '{s}'"),
        }
    } else {
        Direction::Linear
    };
    p.finish(id)?;
    let spec = FitSpec {
        basis: def.basis,
        gram: def.gram,
        colours,
        direction,
        max_tilt: max_tilt.to_radians(),
        weights,
        direction_weights,
        exact_i_z,
    };
    Ok(Box::new(LightmapEncoder { id, spec, storage }))
}

impl Encoder for LightmapEncoder {
    fn id(&self) -> &str {
        self.id
    }
    fn stored_scalars(&self) -> usize {
        self.storage.scalars()
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        let r = fit(&self.spec, input);
        let model = Texel::encode(&r.model, self.storage).decode();
        let mut diagnostics = vec![("theta_deg", r.theta.to_degrees())];
        if self.is_iterative() {
            diagnostics.push(("iters", r.iterations as f64));
            diagnostics.push(("evals", r.evaluations as f64));
        }
        if r.fallback {
            diagnostics.push(("fallback", 1.0));
        }
        Box::new(LightmapFit { model, diagnostics })
    }
    fn is_iterative(&self) -> bool {
        matches!(self.spec.direction, Direction::Search { .. } | Direction::Search2d { .. })
    }
    /// AHD/HHD texels are fitted over the hemisphere about N (the HHD basis is H(n) = ½(1 + n·N));
    /// without N every variant falls back to the same direction of its own.
    fn needs_surface_normal(&self) -> bool {
        true
    }
    /// Colours are clamped non-negative and both basis functions are ≥ 0 on the sphere.
    fn promises_non_negative(&self) -> bool {
        true
    }
    /// Closed forms with relative thresholds (the input is scaled to order one first); the
    /// golden section's comparisons can flip between scales, so searched fits do not promise.
    fn is_scale_covariant(&self) -> bool {
        !self.is_iterative()
    }
    /// The linear direction, N and the Grams are geometric (the tangent frame's twist does
    /// not enter a fit with fixed d).
    fn is_rotation_covariant(&self) -> bool {
        !self.is_iterative()
    }
}
