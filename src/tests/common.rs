//! What the encoder tests share (`encoder_hard_cases.rs`, `encoder_properties.rs`,
//! `lightmap_exact_cases.rs`): surfaces with their declared effects, and fit inputs built from
//! the library's analytic lighting (`reference::lighting`: closed-form SH, whole and visible
//! under the effects, and closed-form E/π); every registered encoder; and the error of a fit on
//! an output grid.
//!
//! Nothing here names an encoder: the encoders come from `encoders::REGISTRY`, so an encoder
//! added there joins every test that uses this module.

use crate::encoders::encoder::{Encoder, FitInput, Fitted, Params};
use crate::encoders::REGISTRY;
use crate::math::cap::Cap;
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use crate::reference::domain::{Domain, OutputGrid};
pub use crate::reference::lighting::{Light, Lighting};
use crate::reference::metrics::score;
use glam::{DQuat, DVec3};

/// A surface: its normal N and the effects declared about it.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    pub normal: DVec3,
    /// The hemisphere effect about N: only light with ω·N ≥ 0 reaches the surface.
    pub hemisphere: bool,
    /// The cone effect: (centre, cos α).
    pub cone: Option<(DVec3, f64)>,
}

impl Surface {
    /// A surface with the hemisphere effect about `normal`.
    pub fn hemisphere(normal: DVec3) -> Self {
        Surface { normal: normal.normalize(), hemisphere: true, cone: None }
    }
    /// A surface normal with no effect (a hemisphere domain lit by the whole sphere).
    pub fn bare(normal: DVec3) -> Self {
        Surface { normal: normal.normalize(), hemisphere: false, cone: None }
    }
    /// The visibility caps of the declared effects (`Light::visible` takes them closed).
    pub fn masks(&self) -> Vec<Cap> {
        let mut m = Vec::new();
        if self.hemisphere {
            m.push(Cap::hemisphere(self.normal));
        }
        if let Some((c, cos)) = self.cone {
            m.push(Cap::new(c, cos));
        }
        m
    }
    pub fn rotated(&self, q: DQuat) -> Self {
        Surface {
            normal: (q * self.normal).normalize(),
            hemisphere: self.hemisphere,
            cone: self.cone.map(|(c, cos)| ((q * c).normalize(), cos)),
        }
    }
}

/// Everything a fit needs, owned, in closed form.
#[derive(Clone, Debug)]
pub struct Input {
    pub probe_sh: Sh9,
    pub visible_sh: Sh9,
    pub surface: Option<Surface>,
    pub exact_at_normal: Option<Rgb>,
    /// The lighting and the part of it that reaches the surface, for the closed-form E/π.
    pub probe: Lighting,
    pub visible: Lighting,
}

impl Input {
    pub fn new(lighting: &Lighting, surface: Option<&Surface>) -> Self {
        let visible = match surface {
            Some(s) => lighting.visible(&s.masks()),
            None => lighting.clone(),
        };
        Input {
            probe_sh: lighting.sh(),
            visible_sh: visible.sh(),
            surface: surface.cloned(),
            exact_at_normal: surface.map(|s| visible.irradiance(s.normal)),
            probe: lighting.clone(),
            visible,
        }
    }

    pub fn fit_input(&self) -> FitInput<'_> {
        FitInput {
            probe_sh: &self.probe_sh,
            visible_sh: &self.visible_sh,
            surface_normal: self.surface.as_ref().map(|s| s.normal),
            cone: self.surface.as_ref().and_then(|s| s.cone),
            exact_at_normal: self.exact_at_normal,
            surface_albedo: None,
            radiance: None,
        }
    }

    /// The same input with every coefficient, I_z and light scaled by k.
    pub fn scaled(&self, k: f64) -> Input {
        Input {
            probe_sh: self.probe_sh * k,
            visible_sh: self.visible_sh * k,
            surface: self.surface.clone(),
            exact_at_normal: self.exact_at_normal.map(|v| v * k),
            probe: self.probe.scaled(k),
            visible: self.visible.scaled(k),
        }
    }

    /// The domain the input is scored on: the sphere for a probe, the hemisphere about N for a
    /// surface.
    pub fn domain(&self) -> Domain {
        match &self.surface {
            Some(s) => Domain::Hemisphere { normal: s.normal },
            None => Domain::Sphere,
        }
    }
}

/// Every registered encoder with its default settings, with its id.
pub fn registry_encoders() -> Vec<(String, Box<dyn Encoder>)> {
    REGISTRY
        .iter()
        .map(|k| {
            let e = (k.build)(&mut Params::new(toml::Table::new()))
                .unwrap_or_else(|e| panic!("encoder '{}' must build with default settings: {e:#}", k.id));
            (k.id.to_string(), e)
        })
        .collect()
}

/// Every registered encoder with its default settings, then every other encoder configuration
/// that an experiment file in `experiments/` declares (settings included, so a variant used in a
/// table is tested too), each with a label ("sh1", or "zh3_shared in zh3.toml"). A
/// configuration is its kind and settings (its `name` only labels it): one already listed, such
/// as `sh1` in seven files or `{ kind = "sh2" }`, builds the same encoder and is tested once,
/// under its first label. Every file's encoders are still built (`Experiment::load`).
pub fn all_encoders() -> Vec<(String, Box<dyn Encoder>)> {
    let mut out = registry_encoders();
    let mut seen: Vec<(String, toml::Table)> =
        REGISTRY.iter().map(|k| (k.id.to_string(), toml::Table::new())).collect();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    for path in crate::pipeline::experiment::list_experiments(&dir).expect("experiments/ lists") {
        let exp = crate::pipeline::experiment::Experiment::load(&path).unwrap_or_else(|e| panic!("{e:#}"));
        let configs = configurations(&path);
        assert_eq!(configs.len(), exp.encoders.len(), "{}: one encoder per entry", path.display());
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        for (named, config) in exp.encoders.into_iter().zip(configs) {
            if !seen.contains(&config) {
                seen.push(config);
                out.push((format!("{} in {file}", named.name), named.encoder));
            }
        }
    }
    out
}

/// The `encoders` entries of an experiment file as (kind, settings): `"sh2"` is ("sh2", {}),
/// `{ kind = "sh2", name = "x" }` is too.
fn configurations(path: &std::path::Path) -> Vec<(String, toml::Table)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let file: toml::Table = text.parse().unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let entries = file.get("encoders").and_then(toml::Value::as_array).expect("encoders = [..]");
    entries
        .iter()
        .map(|e| match e {
            toml::Value::String(kind) => (kind.clone(), toml::Table::new()),
            toml::Value::Table(t) => {
                let mut settings = t.clone();
                settings.remove("name");
                let kind = settings.remove("kind").and_then(|k| k.as_str().map(String::from)).expect("kind");
                (kind, settings)
            }
            other => panic!("{}: encoder entry {other}", path.display()),
        })
        .collect()
}

/// Values of `f` at the grid's normals.
pub fn eval(f: &dyn Fitted, grid: &OutputGrid) -> Vec<Rgb> {
    grid.normals.iter().map(|&n| f.irradiance(n)).collect()
}

/// Solid-angle-weighted RMSE (√ of the mean of the channel MSEs) of `test` against
/// `reference` on `grid`, computed on values divided by `scale` (so 1e-300 and 1e+300 lighting
/// neither underflow nor overflow when squared) and returned in units of `scale`.
pub fn rmse_scaled(reference: &[Rgb], test: &[Rgb], grid: &OutputGrid, scale: f64) -> f64 {
    let r: Vec<Rgb> = reference.iter().map(|v| *v / scale).collect();
    let t: Vec<Rgb> = test.iter().map(|v| *v / scale).collect();
    score(&r, &t, &grid.weights, false).rmse
}

/// Solid-angle-weighted RMS of `values` on `grid`, in units of `scale`.
pub fn rms_scaled(values: &[Rgb], grid: &OutputGrid, scale: f64) -> f64 {
    rmse_scaled(values, &vec![Rgb::ZERO; values.len()], grid, scale)
}

/// The largest |component| of a list of values.
pub fn max_abs(values: &[Rgb]) -> f64 {
    values.iter().map(|v| v.abs().max_element()).fold(0.0, f64::max)
}

/// The E/π of the SH projection of the visible radiance through band `l` (the SH L_l answer,
/// computed from its definition, not through any encoder).
pub fn sh_projection(input: &Input, l: usize) -> Sh9 {
    input.visible_sh.truncate(l).convolve_cosine()
}

/// A direction from elevation above the xz-plane and azimuth, in degrees (maps' convention: +Y up).
pub fn dir(elev_deg: f64, azim_deg: f64) -> DVec3 {
    crate::math::convention::direction(azim_deg.to_radians(), (90.0 - elev_deg).to_radians())
}
