//! Shared by `tests/hard_cases.rs` and `tests/properties.rs`: analytic lighting built from
//! ambient, delta lights and uniform caps, with its closed-form SH (whole and visible under a
//! surface's declared effects) and closed-form E/π; every registered encoder; and the error of
//! a fit on an output grid.
//!
//! Nothing here names an encoder: the encoders come from `probelab::encoders::REGISTRY`, so an
//! encoder added there joins every test that uses this module.
#![allow(dead_code)]

pub mod harness;
pub mod shared_maps;

use glam::{DQuat, DVec3};
use probelab::encoders::encoder::{Encoder, FitInput, Fitted, Params};
use probelab::encoders::REGISTRY;
use probelab::math::colour::Rgb;
use probelab::math::sh::{band_of, basis, constant, delta_light, Sh9};
use probelab::reference::domain::{Domain, OutputGrid};
use probelab::reference::metrics::score;
use probelab::reference::scenes::cap_irradiance;
use std::f64::consts::PI;

/// One light.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Radiance c from every direction.
    Ambient(Rgb),
    /// A directional (delta) light of radiant intensity `e` along `dir`: E/π facing it is e/π.
    Delta { dir: DVec3, e: Rgb },
    /// A uniform cap of radiance `radiance` and half-angle `half_angle` (radians) about `axis`.
    Cap { axis: DVec3, half_angle: f64, radiance: Rgb },
}

/// A visibility cap {ω : ω·axis ≥ cos}. Closed: a delta light exactly on its boundary (a light
/// exactly at the horizon) is visible, which is the case where the light's direction is
/// perpendicular to N (d_z = 0) yet it still counts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mask {
    pub axis: DVec3,
    pub cos: f64,
}

impl Mask {
    fn half_angle(&self) -> f64 {
        self.cos.clamp(-1.0, 1.0).acos()
    }
    /// Whether the cap of half-angle `half` about `axis` lies inside this mask.
    fn contains_cap(&self, axis: DVec3, half: f64) -> bool {
        angle(axis, self.axis) + half <= self.half_angle() + 1e-12
    }
    /// Whether the cap of half-angle `half` about `axis` lies outside this mask.
    fn excludes_cap(&self, axis: DVec3, half: f64) -> bool {
        angle(axis, self.axis) >= self.half_angle() + half - 1e-12
    }
}

/// The angle between two unit vectors, accurate near 0 and π.
pub fn angle(a: DVec3, b: DVec3) -> f64 {
    2.0 * ((a - b).length() * 0.5).clamp(0.0, 1.0).asin()
}

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
    pub fn masks(&self) -> Vec<Mask> {
        let mut m = Vec::new();
        if self.hemisphere {
            m.push(Mask { axis: self.normal, cos: 0.0 });
        }
        if let Some((c, cos)) = self.cone {
            m.push(Mask { axis: c, cos });
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

/// Zonal SH of a function of ω·axis with zonal coefficients z_l: c_lm = z_l·√(4π/(2l+1))·Y_lm(axis).
fn zonal(axis: DVec3, z: [f64; 3], c: Rgb) -> Sh9 {
    let y = basis(axis);
    Sh9(std::array::from_fn(|i| {
        let l = band_of(i);
        c * (z[l] * (4.0 * PI / (2 * l + 1) as f64).sqrt() * y[i])
    }))
}

impl Light {
    /// Closed-form L2 SH of the radiance.
    pub fn sh(&self) -> Sh9 {
        match self {
            Light::Ambient(c) => constant(*c),
            Light::Delta { dir, e } => delta_light(*dir, *e),
            // ∫_{cap} Y_l0: 2π(1−c)·Y00, π√(3/4π)·sin²α, √(5/4π)·π·c·sin²α (as in
            // `scenes::Component::sh`), with 1 − c = 2 sin²(α/2) so tiny caps stay accurate.
            Light::Cap { axis, half_angle, radiance } => {
                let (s, c) = half_angle.sin_cos();
                let s2 = s * s;
                let one_minus_c = 2.0 * (0.5 * half_angle).sin().powi(2);
                zonal(
                    *axis,
                    [
                        2.0 * PI * one_minus_c * 0.5 * (1.0 / PI).sqrt(),
                        PI * (3.0 / (4.0 * PI)).sqrt() * s2,
                        (5.0 / (4.0 * PI)).sqrt() * PI * c * s2,
                    ],
                    *radiance,
                )
            }
        }
    }

    /// Closed-form E/π at unit normal n.
    pub fn irradiance(&self, n: DVec3) -> Rgb {
        match self {
            Light::Ambient(c) => *c,
            Light::Delta { dir, e } => *e * (n.dot(*dir).max(0.0) / PI),
            Light::Cap { axis, half_angle, radiance } => {
                *radiance * cap_irradiance(n.dot(*axis), half_angle.sin().powi(2))
            }
        }
    }

    /// The part of this light that passes every mask. Ambient light under nested masks becomes
    /// a cap (the innermost mask); a cap light must lie wholly inside or outside the masks.
    /// Panics on a configuration with no closed form (a test-construction error).
    pub fn visible(&self, masks: &[Mask]) -> Option<Light> {
        if masks.is_empty() {
            return Some(self.clone());
        }
        match self {
            Light::Delta { dir, .. } => masks.iter().all(|m| dir.dot(m.axis) >= m.cos).then(|| self.clone()),
            Light::Ambient(c) => {
                let inner = masks
                    .iter()
                    .find(|m| masks.iter().all(|o| o.contains_cap(m.axis, m.half_angle())))
                    .expect("ambient light under masks that are not nested has no closed form");
                Some(Light::Cap { axis: inner.axis, half_angle: inner.half_angle(), radiance: *c })
            }
            Light::Cap { axis, half_angle, .. } => {
                if masks.iter().any(|m| m.excludes_cap(*axis, *half_angle)) {
                    None
                } else {
                    assert!(
                        masks.iter().all(|m| m.contains_cap(*axis, *half_angle)),
                        "a cap light straddling a mask has no closed form"
                    );
                    Some(self.clone())
                }
            }
        }
    }

    pub fn rotated(&self, q: DQuat) -> Light {
        match self {
            Light::Ambient(c) => Light::Ambient(*c),
            Light::Delta { dir, e } => Light::Delta { dir: (q * *dir).normalize(), e: *e },
            Light::Cap { axis, half_angle, radiance } => {
                Light::Cap { axis: (q * *axis).normalize(), half_angle: *half_angle, radiance: *radiance }
            }
        }
    }

    pub fn scaled(&self, k: f64) -> Light {
        match self {
            Light::Ambient(c) => Light::Ambient(*c * k),
            Light::Delta { dir, e } => Light::Delta { dir: *dir, e: *e * k },
            Light::Cap { axis, half_angle, radiance } => {
                Light::Cap { axis: *axis, half_angle: *half_angle, radiance: *radiance * k }
            }
        }
    }
}

/// A sum of lights.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Lighting(pub Vec<Light>);

impl Lighting {
    pub fn sh(&self) -> Sh9 {
        self.0.iter().fold(Sh9::ZERO, |a, l| a + l.sh())
    }
    pub fn irradiance(&self, n: DVec3) -> Rgb {
        self.0.iter().map(|l| l.irradiance(n)).sum()
    }
    /// The light that passes the masks.
    pub fn visible(&self, masks: &[Mask]) -> Lighting {
        Lighting(self.0.iter().filter_map(|l| l.visible(masks)).collect())
    }
    pub fn rotated(&self, q: DQuat) -> Lighting {
        Lighting(self.0.iter().map(|l| l.rotated(q)).collect())
    }
    pub fn scaled(&self, k: f64) -> Lighting {
        Lighting(self.0.iter().map(|l| l.scaled(k)).collect())
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

/// Every registered encoder with its default settings, then every encoder configuration that
/// an experiment file in `experiments/` declares (settings included, so a variant used in a
/// table is tested too), each with a label ("sh1", or "zh3_shared in zh3.toml").
pub fn all_encoders() -> Vec<(String, Box<dyn Encoder>)> {
    let mut out = registry_encoders();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    for path in probelab::pipeline::experiment::list_experiments(&dir).expect("experiments/ lists") {
        let exp = probelab::pipeline::experiment::Experiment::load(&path).unwrap_or_else(|e| panic!("{e:#}"));
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        for named in exp.encoders {
            out.push((format!("{} in {file}", named.name), named.encoder));
        }
    }
    out
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
    probelab::math::convention::direction(azim_deg.to_radians(), (90.0 - elev_deg).to_radians())
}
