//! What the ZH3 claims are measured on, and how: the sphere output grid every figure uses
//! (256×128 lat-long normals, solid-angle weights), the five paper probes with their exact
//! cell-integrated reference, constructed scenes with their closed-form irradiance and SH, and
//! the encoders by registry name, scored through the pipeline's one scoring step
//! ([`crate::pipeline::runner::score_fit`]).

use crate::encoders::encoder::{Encoder, FitInput, Fitted};
use crate::envmap::moments::RowMoments;
use crate::envmap::search::SearchPath;
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use crate::pipeline::runner::{evaluate, score_fit};
use crate::reference::domain::{Domain, OutputGrid};
use crate::reference::exact::{Reference, DEFAULT_POLAR_NODES};
use crate::reference::lighting::{Light, Lighting};
use crate::reference::metrics::{Metric, Scores};
use crate::reference::scenes::Scene;
use anyhow::Result;
use glam::DVec3;

/// The lat-long resolution of the output grid of normals.
const RES: (usize, usize) = (256, 128);

/// A lighting case: its radiance SH and the reference E/π at each normal of the grid.
pub(super) struct Case {
    pub name: String,
    /// Radiance SH (exact projection of the map, or closed form).
    pub sh: Sh9,
    pub reference: Vec<Rgb>,
}

/// The sphere output grid shared by every case: 256×128 lat-long normals with their exact
/// solid angles.
pub(super) fn grid() -> OutputGrid {
    Domain::Sphere.output_grid(RES)
}

/// An encoder by kind with TOML settings.
pub(super) fn enc(kind: &str, settings: &[(&str, toml::Value)]) -> Result<Box<dyn Encoder>> {
    let t: toml::Table = settings.iter().map(|(k, v)| (k.to_string(), v.clone())).collect();
    Ok(crate::encoders::build(kind, None, t)?.encoder)
}

/// An RGB weight triple as a TOML setting.
pub(super) fn weights_value(w: [f64; 3]) -> toml::Value {
    toml::Value::Array(w.iter().map(|&x| toml::Value::Float(x)).collect())
}

/// The encoder's fit to radiance SH over the whole sphere.
pub(super) fn fit(e: &dyn Encoder, sh: &Sh9) -> Box<dyn Fitted> {
    e.fit(&FitInput::sphere(sh))
}

/// A fit evaluated at every normal of the grid.
pub(super) fn values(f: &dyn Fitted, grid: &OutputGrid) -> Vec<Rgb> {
    evaluate(f, &grid.normals)
}

/// The exact metric of an encoder on a case: solid-angle weighted, no clamp.
pub(super) fn exact(e: &dyn Encoder, case: &Case, grid: &OutputGrid) -> Scores {
    score_fit(e, fit(e, &case.sh).as_ref(), grid, &case.reference, Metric::Exact)
}

/// The peer-compatible metric (FORMULAS §10): per-pixel mean, clamped unless the encoder says
/// its peer counterpart is not.
pub(super) fn probulator(e: &dyn Encoder, case: &Case, grid: &OutputGrid) -> Scores {
    score_fit(e, fit(e, &case.sh).as_ref(), grid, &case.reference, Metric::Probulator)
}

/// The maps as cases, and (name, sha256 and reference description) for each.
pub(super) type Probes = (Vec<Case>, Vec<(String, String)>);

/// Every map of `names` (the declared ones, [`super::maps`]: the five paper probes, then every
/// map of the search path's collection that is not degraded), in order, as cases on the grid,
/// with a description of each map (named, with its sha256; never a machine path). The caller
/// runs the measurements only when every map is on the search path; one that is there but
/// cannot be read is an error naming it, never a silently absent row.
pub(super) fn probes(search: &SearchPath, grid: &OutputGrid, names: &[String]) -> Result<Probes> {
    let mut maps = Vec::new();
    let mut cases = Vec::new();
    for name in names {
        match map_case(search, name, grid) {
            Ok((c, desc)) => {
                maps.push((name.to_string(), desc));
                cases.push(c);
            }
            Err(e) => return Err(e.context(format!("claims: map {name} is on the search path but cannot be used"))),
        }
    }
    Ok((cases, maps))
}

/// One map on the search path: its exact SH projection and the exact cell-integrated reference
/// on the grid's lat-long normals.
fn map_case(search: &SearchPath, name: &str, grid: &OutputGrid) -> Result<(Case, String)> {
    let map = search.load(name).map_err(|e| anyhow::anyhow!("claims zh3: {e:#}"))?;
    let rm = RowMoments::new(&map);
    let reference = Reference::new(&rm, vec![], DEFAULT_POLAR_NODES);
    let values = reference.irradiance_latlong(grid.latlong.expect("the sphere grid is a lat-long grid"));
    let case = Case { name: name.to_string(), sh: crate::reference::projection::project(&map), reference: values };
    Ok((
        case,
        format!(
            "sha256 {} ({}x{}, {})",
            map.sha256.as_deref().unwrap_or("-"),
            map.width(),
            map.height(),
            reference.describe()
        ),
    ))
}

/// A constructed scene as a case: closed-form SH and irradiance.
pub(super) fn scene_case(scene: &Scene, grid: &OutputGrid) -> Case {
    Case {
        name: scene.id.clone(),
        sh: scene.sh(),
        reference: grid.normals.iter().map(|&n| scene.irradiance(n)).collect(),
    }
}

/// A scene of analytic lights.
pub(super) fn scene(id: &str, lights: Vec<Light>) -> Scene {
    Scene { id: id.into(), description: String::new(), lighting: Lighting(lights) }
}

/// A cap light of `half_angle` radians about `axis` (normalised).
pub(super) fn cap(axis: DVec3, half_angle: f64, radiance: Rgb) -> Light {
    Light::Cap { axis: axis.normalize(), half_angle, radiance }
}
