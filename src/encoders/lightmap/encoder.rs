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

use crate::encoders::encoder::{named_weights, Encoder, Family, FitInput, Fitted, Params};
use crate::encoders::lightmap::fit::{fit, Colours, Direction, FitSpec, Gram, MAX_GOLDEN_STEPS};
use crate::encoders::lightmap::{Basis, Model, Storage, Texel};
use crate::encoders::stored::{Role, Stored, Unit, Value};
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use anyhow::{bail, Result};
use glam::DVec3;
use std::ops::Bound::{Excluded, Included};

/// An AHD/HHD lightmap encoder.
pub struct LightmapEncoder {
    /// The registry id it reports.
    pub id: &'static str,
    /// How texels are fitted.
    pub spec: FitSpec,
    /// How a fitted texel is stored.
    pub storage: Storage,
}

/// What a lightmap texel stores: an AHD/HHD texel, or the linear radiance SH the HHD is solved
/// from at run time (`hhd_from_sh1`).
#[derive(Clone, Copy, Debug)]
pub enum TexelSource {
    /// A texel of the layouts of `irradz.rs`.
    Texel(Texel),
    /// Linear radiance SH (bands 0–1; band 2 is not read).
    LinearSh(Sh9),
}

/// A fitted texel, decoded.
pub struct LightmapFit {
    /// The decoded model the texel evaluates.
    pub model: Model,
    /// What the texel stores (an AHD/HHD texel, or linear SH for `hhd_from_sh1`).
    pub source: TexelSource,
    /// Named figures of the fit (reported in the `diagnostics` column).
    pub diagnostics: Vec<(&'static str, f64)>,
}

/// The model's formula, FORMULAS §7 (AHD) or §8 (HHD).
fn model_formula(basis: Basis) -> &'static str {
    match basis {
        Basis::Ahd => "E/pi(n) = C_a + C_d*max(0, n.d) (AHD, docs/conventions.md section 7)",
        Basis::Hhd => "E/pi(n) = C_a*(1 + n.N)/2 + C_d*max(0, n.d) (HHD, docs/conventions.md section 8)",
    }
}

/// The stored form of a texel (module table of `irradz.rs`): its stored scalars, then N, the
/// tangent frame and the decoded model, derived.
fn texel_stored(t: &Texel, model: &Model) -> Stored {
    let s = &t.scalars;
    let rgb = |at: usize| Rgb::new(s[at], s[at + 1], s[at + 2]);
    let layout = match t.storage {
        Storage::Raw => "raw: C_a, C_d and d_x, d_y are stored",
        Storage::IrradzRgb => "irradz_rgb: C_a, I_z = E/pi(N) and d_x, d_y are stored; C_d = max(0, (I_z - C_a)/max(d_z, cos 89.9 deg)) (docs/conventions.md section 7)",
        Storage::IrradzLuma => "irradz_luma: ratio = L(C_a)/L(I_z) (Rec.709 luminance), I_z = E/pi(N) and d_x, d_y are \
                                stored; C_a = ratio*I_z, C_d = max(0, (I_z - C_a)/max(d_z, cos 89.9 deg)) \
                                (docs/conventions.md section 7)",
    };
    let mut out = Stored::new(format!(
        "{}; {layout}; d = d_x*t1 + d_y*t2 + d_z*N with d_z = sqrt(1 - d_x^2 - d_y^2) ((d_x, d_y) scaled to length 1 \
         if longer), (t1, t2) = glam's DVec3::any_orthonormal_pair(N) (Duff et al. 2017); N is the surface normal \
         (not stored); world directions, +Y up (section 1)",
        model_formula(t.basis)
    ));
    let (x, y) = match t.storage {
        Storage::Raw => {
            out.rgb("C_a", Unit::Irradiance, rgb(0)).rgb("C_d", Unit::Irradiance, rgb(3));
            (s[6], s[7])
        }
        Storage::IrradzRgb => {
            out.rgb("C_a", Unit::Irradiance, rgb(0)).rgb("I_z", Unit::Irradiance, rgb(3));
            (s[6], s[7])
        }
        Storage::IrradzLuma => {
            out.scalar("ratio", Unit::Unitless, s[0]).rgb("I_z", Unit::Irradiance, rgb(1));
            (s[4], s[5])
        }
    };
    out.scalar("d_x", Unit::Unitless, x).scalar("d_y", Unit::Unitless, y);
    let (t1, t2) = crate::encoders::lightmap::irradz::tangent_frame(t.normal);
    for (name, v) in [("N", t.normal), ("t1", t1), ("t2", t2)] {
        out.push(Role::Derived, name, Unit::Direction, Value::Vector(v));
    }
    model_entries(&mut out, model, false);
    out
}

/// The decoded model's colours and direction, as derived entries (N too when `with_normal`).
fn model_entries(out: &mut Stored, m: &Model, with_normal: bool) {
    if with_normal {
        out.push(Role::Derived, "N", Unit::Direction, Value::Vector(m.normal));
    }
    out.push(Role::Derived, "decoded_C_a", Unit::Irradiance, Value::Rgb(m.c_a));
    out.push(Role::Derived, "decoded_C_d", Unit::Irradiance, Value::Rgb(m.c_d));
    out.push(Role::Derived, "d", Unit::Direction, Value::Vector(m.d));
}

impl Fitted for LightmapFit {
    fn irradiance(&self, n: DVec3) -> Rgb {
        self.model.irradiance(n)
    }
    fn stored(&self) -> Stored {
        match &self.source {
            TexelSource::Texel(t) => texel_stored(t, &self.model),
            TexelSource::LinearSh(sh) => {
                let mut out = Stored::new(format!(
                    "the texel stores linear radiance SH (L0_0, L1_m; real orthonormal SH of docs/conventions.md \
                     section 2); at run time the HHD about the surface normal N is solved from it in closed form \
                     (section 8, 'HHD from linear SH', I_z = b.N): {}; the decoded C_a, C_d, d and N are listed, \
                     derived",
                    model_formula(self.model.basis)
                ));
                out.sh(Role::Stored, Unit::Radiance, &sh.0[..4]);
                model_entries(&mut out, &self.model, true);
                out
            }
        }
    }
    fn diagnostics(&self) -> Vec<(&'static str, f64)> {
        self.diagnostics.clone()
    }
}

/// The defaults of one encoder row.
pub struct Defaults {
    /// The ambient term of the model (AHD or HHD).
    pub basis: Basis,
    /// Default domain of the least squares (sphere or hemisphere).
    pub gram: Gram,
    /// Default colour fit (`colours` key): free or under the IrradZ constraint.
    pub colours: Colours,
    /// Whether the direction is searched (golden section) rather than taken from L1.
    pub search: bool,
    /// Default `storage` key: `raw`, `irradz_rgb` or `irradz_luma`.
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
    fn family(&self) -> Family {
        match self.spec.basis {
            Basis::Ahd => Family::Ahd,
            Basis::Hhd => Family::Hhd,
        }
    }
    fn stored_scalars(&self) -> usize {
        self.storage.scalars()
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        let r = fit(&self.spec, input);
        let texel = Texel::encode(&r.model, self.storage);
        let model = texel.decode();
        let mut diagnostics = vec![("theta_deg", r.theta.to_degrees())];
        if self.is_iterative() {
            diagnostics.push(("iters", r.iterations as f64));
            diagnostics.push(("evals", r.evaluations as f64));
        }
        if r.fallback {
            diagnostics.push(("fallback", 1.0));
        }
        Box::new(LightmapFit { model, source: TexelSource::Texel(texel), diagnostics })
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
