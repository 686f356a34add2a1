//! Blending two lighting sets on one lightmap texel (claims H5 and H7; hemispherical-lighting
//! talk, 2018 brief Fig. 2). Each pair is two bakes of the same surface (normal N): two maps,
//! one map with a white delta light off and on, or one map and the same map turned 180° about
//! +Y. The two bakes are blended at t = 0, 0.1, …, 1 and reconstructed six ways:
//!
//! | method | what is blended | then |
//! |---|---|---|
//! | `ahd_params` | the stored AHD parameters (C_a, C_d, tangent d_xy) of `ahd_search_hemi` fits | decode (d_z = √(1 − \|d_xy\|²)) |
//! | `hhd_params` | the same for `hhd_search_hemi` fits | decode |
//! | `ahd_irradz` | the AHD fits stored as IrradZ (C_a, I_z, d_xy) | C_d = (I_z − C_a)/d_z |
//! | `hhd_irradz` | the HHD fits as IrradZ (the talk's texel) | C_d = (I_z − C_a)/d_z |
//! | `sh1_hhd` | the linear SH of the visible radiance | `hhd_from_linear_sh` (the talk's closed form) |
//! | `sh2` | the L2 SH of the visible radiance | its irradiance (linear in t; for scale) |
//!
//! The reference is the blended exact reference, (1 − t)·E₀ + t·E₁: the exact occluded E/π of
//! each bake (hemisphere about N), which is linear in t. Errors: solid-angle RMSE over the
//! hemisphere about N on 128×32 normals (the upper half of a 128×64 lat-long grid), E/π.
//! Overshoot at N: the largest Rec.709 luminance of a method's I(N) over t (101 steps) above
//! the larger of its two endpoint values, relative to that endpoint; undershoot likewise
//! below the smaller endpoint.
//!
//! The endpoint fits go through `lightmap::fit` with the `FitSpec`s of the registered
//! encoders (a test checks they reproduce the registry's fits bit for bit), because the study
//! needs the fitted parameters, which the `Fitted` trait does not expose.

use crate::encoders::encoder::FitInput;
use crate::encoders::lightmap::fit::{fit, Colours, Direction, FitSpec, Gram};
use crate::encoders::lightmap::{hhd_from_linear_sh, Basis, Model, Storage, Texel};
use crate::envmap::search::SearchPath;
use crate::envmap::EnvMap;
use crate::math::cap::Cap;
use crate::math::colour::Rgb;
use crate::math::sh::{delta_light, Sh9};
use crate::pipeline::runner::{Case, CaseData, MapData};
use crate::reference::domain::Domain;
use crate::reference::exact::DEFAULT_POLAR_NODES;
use crate::reference::metrics::score;
use anyhow::{Context, Result};
use glam::DVec3;
use std::f64::consts::PI;

/// The output grid (lat-long W×H; the hemisphere takes its upper H/2 rows).
pub const GRID: (usize, usize) = (128, 64);
use crate::math::colour::REC709;

/// One endpoint of a blending pair, as baked: a map (optionally turned 180° about +Y) and
/// optionally a white delta light.
#[derive(Clone, Debug)]
pub struct Endpoint {
    /// The map's name, loaded through the search path (e.g. `grace_256x128`).
    pub map: &'static str,
    /// Whether the map is turned 180° about +Y before baking ([`turned`]).
    pub turned: bool,
    /// (direction, k): a white delta light whose E/π at N is k × the map's L(I_z).
    pub light: Option<(DVec3, f64)>,
}

/// A blending pair on a surface of normal N.
#[derive(Clone, Debug)]
pub struct Pair {
    /// The pair's id, the `case` of the `blend` measure (e.g. `ennis_to_grace`).
    pub id: &'static str,
    /// A short human description of the two bakes and the surface.
    pub description: &'static str,
    /// The normal as a label (`+x`, `+y`, `+z`), used in domain labels and captions.
    pub normal_label: &'static str,
    /// The surface normal N (unit), about which both bakes are occluded.
    pub normal: DVec3,
    /// The bake at t = 0.
    pub a: Endpoint,
    /// The bake at t = 1.
    pub b: Endpoint,
}

fn lit(map: &'static str) -> Endpoint {
    Endpoint { map, turned: false, light: None }
}

/// The five pairs (paper probes).
pub fn pairs() -> Vec<Pair> {
    let tilt = |n: DVec3, towards: DVec3, deg: f64| {
        let r = deg.to_radians();
        (n * r.cos() + towards * r.sin()).normalize()
    };
    vec![
        Pair {
            id: "ennis_to_grace",
            description: "two maps, floor",
            normal_label: "+y",
            normal: DVec3::Y,
            a: lit("ennis_256x128"),
            b: lit("grace_256x128"),
        },
        Pair {
            id: "uffizi_to_pisa_wall",
            description: "two maps, wall",
            normal_label: "+x",
            normal: DVec3::X,
            a: lit("uffizi_256x128"),
            b: lit("pisa_256x128"),
        },
        Pair {
            id: "grace_light_on",
            description: "grace, white delta light 60° off N (E/π at N = 2 L(I_z)) off -> on, floor",
            normal_label: "+y",
            normal: DVec3::Y,
            a: lit("grace_256x128"),
            b: Endpoint { light: Some((tilt(DVec3::Y, DVec3::X, 60.0), 2.0)), ..lit("grace_256x128") },
        },
        Pair {
            id: "wells_light_on_wall",
            description: "wells, white delta light 45° off N (E/π at N = 1 L(I_z)) off -> on, wall",
            normal_label: "+z",
            normal: DVec3::Z,
            a: lit("wells_probulator"),
            b: Endpoint { light: Some((tilt(DVec3::Z, DVec3::Y, 45.0), 1.0)), ..lit("wells_probulator") },
        },
        Pair {
            id: "ennis_turned_180",
            description: "ennis and ennis turned 180° about +Y, wall",
            normal_label: "+x",
            normal: DVec3::X,
            a: lit("ennis_256x128"),
            b: Endpoint { turned: true, ..lit("ennis_256x128") },
        },
    ]
}

/// A bake of one lighting on the surface: what the encoders see and the exact reference.
pub struct Bake {
    /// L2 SH of the unoccluded radiance (plus the delta light, if any).
    pub probe_sh: Sh9,
    /// L2 SH of the radiance in the hemisphere about N (plus the delta light, if any).
    pub visible_sh: Sh9,
    /// Exact occluded irradiance E/π at N (the bake's I_z).
    pub exact_at_normal: Rgb,
    /// Exact occluded E/π at the normals the bake was made for, in their order.
    pub reference: Vec<Rgb>,
}

impl Bake {
    /// The encoders' fit input for this bake on a surface of normal `normal` (no cone, no
    /// albedo, SH only).
    pub fn input(&self, normal: DVec3) -> FitInput<'_> {
        FitInput {
            probe_sh: &self.probe_sh,
            visible_sh: &self.visible_sh,
            surface_normal: Some(normal),
            cone: None,
            exact_at_normal: Some(self.exact_at_normal),
            surface_albedo: None,
            radiance: None,
        }
    }
}

/// The map turned 180° about +Y: θ → θ + π is a shift by half the width (exact).
pub fn turned(map: &EnvMap) -> Result<EnvMap> {
    let (w, h) = (map.width(), map.height());
    let texels = (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).map(|(i, j)| map.texel((i + w / 2) % w, j)).collect();
    Ok(EnvMap::new(format!("{}_turned", map.name), w, h, texels)?)
}

/// The hemisphere case about `n` (the runner's `hemisphere` effect).
pub fn hemisphere_case(n: DVec3, label: &str) -> Case {
    Case {
        domain: Domain::Hemisphere { normal: n },
        domain_label: format!("hemisphere:{label}"),
        orientation_set: label.to_string(),
        effects_label: "hemisphere".into(),
        masks: vec![Cap::hemisphere(n)],
        normal: Some(n),
        cone: None,
        albedo: None,
    }
}

/// Bakes a lighting on the surface of normal `n`, scored on `normals`.
pub fn bake(search: &SearchPath, l: &Endpoint, n: DVec3, label: &str, normals: &[DVec3]) -> Result<Bake> {
    let mut map = search.load(l.map).map_err(|e| anyhow::anyhow!("lightmap claims: {e:#}"))?;
    if l.turned {
        map = turned(&map).with_context(|| format!("turning {}", l.map))?;
    }
    let data = MapData::new(&map);
    let case = hemisphere_case(n, label);
    let cd = CaseData::new(&data, &case, DEFAULT_POLAR_NODES);
    let mut b = Bake {
        probe_sh: cd.inputs.probe_sh,
        visible_sh: cd.inputs.visible_sh,
        exact_at_normal: cd.inputs.exact_at_normal.expect("hemisphere case has N"),
        reference: cd.reference_many(normals),
    };
    if let Some((d, k)) = l.light {
        // E/π at N = k·L(I_z): sh::delta_light(d, e) has E/π = e·max(0, n·d)/π.
        let at_n = k * b.exact_at_normal.dot(REC709);
        let e = Rgb::splat(PI * at_n / d.dot(n));
        let sh = delta_light(d, e);
        b.probe_sh = b.probe_sh + sh;
        b.visible_sh = b.visible_sh + sh;
        b.exact_at_normal += e * (d.dot(n) / PI);
        for (r, np) in b.reference.iter_mut().zip(normals) {
            *r += e * (np.dot(d).max(0.0) / PI);
        }
    }
    Ok(b)
}

/// The `FitSpec` of a registered lightmap encoder and its storage (the defaults of
/// `encoders/ahd.rs` and `encoders/hhd.rs`; checked against the registry by a test).
pub fn spec(basis: Basis) -> (FitSpec, Storage) {
    let spec = FitSpec {
        basis,
        gram: Gram::Hemisphere,
        colours: if basis == Basis::Ahd { Colours::Free } else { Colours::IrradZ },
        direction: Direction::Search { iterations: 30, tolerance: 1e-6 },
        max_tilt: 89f64.to_radians(),
        weights: Rgb::splat(1.0 / 3.0),
        direction_weights: REC709,
        exact_i_z: true,
    };
    (spec, if basis == Basis::Ahd { Storage::Raw } else { Storage::IrradzRgb })
}

/// The model the registered `ahd_search_hemi` (Ahd) or `hhd_search_hemi` (Hhd) encoder
/// evaluates: its fit, stored and decoded.
pub fn fitted_model(basis: Basis, input: &FitInput) -> Model {
    let (s, storage) = spec(basis);
    Texel::encode(&fit(&s, input).model, storage).decode()
}

/// The methods, in table order.
pub const METHODS: [&str; 6] = ["ahd_params", "hhd_params", "ahd_irradz", "hhd_irradz", "sh1_hhd", "sh2"];

/// Everything one pair needs to reconstruct at any t.
pub struct Blend {
    /// The surface normal N of the pair.
    pub normal: DVec3,
    /// The bake at t = 0.
    pub a: Bake,
    /// The bake at t = 1.
    pub b: Bake,
    ahd: (Model, Model),
    hhd: (Model, Model),
}

impl Blend {
    /// Fits the AHD and HHD models of both bakes once (as the registered `ahd_search_hemi`
    /// and `hhd_search_hemi` encoders do); every t then blends these.
    pub fn new(normal: DVec3, a: Bake, b: Bake) -> Self {
        let ahd = (fitted_model(Basis::Ahd, &a.input(normal)), fitted_model(Basis::Ahd, &b.input(normal)));
        let hhd = (fitted_model(Basis::Hhd, &a.input(normal)), fitted_model(Basis::Hhd, &b.input(normal)));
        Blend { normal, a, b, ahd, hhd }
    }

    fn lerp_texels(m: &(Model, Model), storage: Storage, t: f64) -> Model {
        Texel::lerp(&Texel::encode(&m.0, storage), &Texel::encode(&m.1, storage), t).decode()
    }

    /// The reconstruction of `method` at t, as a function of the normal.
    pub fn method(&self, method: &str, t: f64) -> Box<dyn Fn(DVec3) -> Rgb + '_> {
        let lerp_sh = |x: &Sh9, y: &Sh9| *x * (1.0 - t) + *y * t;
        let texels = match method {
            "ahd_params" => Some((&self.ahd, Storage::Raw)),
            "hhd_params" => Some((&self.hhd, Storage::Raw)),
            "ahd_irradz" => Some((&self.ahd, Storage::IrradzRgb)),
            "hhd_irradz" => Some((&self.hhd, Storage::IrradzRgb)),
            _ => None,
        };
        if let Some((models, storage)) = texels {
            let m = Self::lerp_texels(models, storage, t);
            return Box::new(move |n| m.irradiance(n));
        }
        match method {
            "sh1_hhd" => {
                let m = hhd_from_linear_sh(&lerp_sh(&self.a.visible_sh, &self.b.visible_sh), self.normal);
                Box::new(move |n| m.irradiance(n))
            }
            "sh2" => {
                let e = lerp_sh(&self.a.visible_sh, &self.b.visible_sh).convolve_cosine();
                Box::new(move |n| e.eval(n))
            }
            _ => unreachable!("unknown blend method {method}"),
        }
    }

    /// The blended exact reference on the bakes' normals.
    pub fn reference(&self, t: f64) -> Vec<Rgb> {
        self.a.reference.iter().zip(&self.b.reference).map(|(x, y)| *x * (1.0 - t) + *y * t).collect()
    }
}

/// One point of the blending study along t: a row of the `blend_curve` measure.
#[derive(Clone, Debug)]
pub struct BlendRow {
    /// The pair's id ([`Pair::id`]).
    pub pair: String,
    /// The method, one of [`METHODS`].
    pub method: String,
    /// The blend weight, 0 (bake a) to 1 (bake b).
    pub t: f64,
    /// Solid-angle RMSE against the blended exact reference over the hemisphere about N, E/π.
    pub rmse: f64,
    /// `rmse` over the RMS of the blended reference (dimensionless).
    pub rel_rmse: f64,
    /// Rec.709 luminance of the method's E/π at N, and the reference's.
    pub at_normal: f64,
    /// Rec.709 luminance of the blended exact E/π at N.
    pub reference_at_normal: f64,
}

/// One pair and method of the blending study over all t: a row of the `blend` measure.
#[derive(Clone, Debug)]
pub struct BlendSummary {
    /// The pair's id ([`Pair::id`]).
    pub pair: String,
    /// The method, one of [`METHODS`].
    pub method: String,
    /// The mean of the RMSE (E/π) over t = 0, 0.1, …, 1.
    pub mean_rmse: f64,
    /// The mean of the RMSE (E/π) over the interior t = 0.1, …, 0.9 only: at t = 0 and 1 every
    /// method reconstructs one bake alone, so the endpoints say nothing about blending.
    pub mean_rmse_interior: f64,
    /// The largest RMSE (E/π) over those t.
    pub max_rmse: f64,
    /// The RMSE (E/π) at t = 0 (bake a alone).
    pub rmse_t0: f64,
    /// The RMSE (E/π) at t = ½.
    pub rmse_half: f64,
    /// The RMSE (E/π) at t = 1 (bake b alone).
    pub rmse_t1: f64,
    /// Relative overshoot of the luminance of I(N) above the larger endpoint ([`shoot`]).
    pub overshoot: f64,
    /// Relative undershoot of the luminance of I(N) below the smaller endpoint ([`shoot`]).
    pub undershoot: f64,
}

/// Over- and undershoot of the luminance of I(N) along t (module doc), relative to the larger
/// endpoint.
pub fn shoot(values: &[f64]) -> (f64, f64) {
    let (first, last) = (values[0], values[values.len() - 1]);
    let (hi, lo) = (first.max(last), first.min(last));
    let max = values.iter().copied().fold(f64::MIN, f64::max);
    let min = values.iter().copied().fold(f64::MAX, f64::min);
    if hi <= 0.0 {
        return (0.0, 0.0);
    }
    (((max - hi) / hi).max(0.0), ((lo - min) / hi).max(0.0))
}

/// Scores every method along t for one pair.
pub fn study(pair: &Pair, blend: &Blend, normals: &[DVec3], weights: &[f64]) -> (Vec<BlendRow>, Vec<BlendSummary>) {
    let mut rows = Vec::new();
    let mut sums = Vec::new();
    let n = blend.normal;
    for method in METHODS {
        let mut rmse = Vec::new();
        for i in 0..=10 {
            let t = i as f64 / 10.0;
            let f = blend.method(method, t);
            let test: Vec<Rgb> = normals.iter().map(|&w| f(w)).collect();
            let reference = blend.reference(t);
            let s = score(&reference, &test, weights, false);
            let ref_n = (blend.a.exact_at_normal * (1.0 - t) + blend.b.exact_at_normal * t).dot(REC709);
            rows.push(BlendRow {
                pair: pair.id.into(),
                method: method.into(),
                t,
                rmse: s.rmse,
                rel_rmse: s.rel_rmse,
                at_normal: f(n).dot(REC709),
                reference_at_normal: ref_n,
            });
            rmse.push(s.rmse);
        }
        let at_n: Vec<f64> = (0..=100).map(|i| blend.method(method, i as f64 / 100.0)(n).dot(REC709)).collect();
        let (overshoot, undershoot) = shoot(&at_n);
        sums.push(BlendSummary {
            pair: pair.id.into(),
            method: method.into(),
            mean_rmse: rmse.iter().sum::<f64>() / rmse.len() as f64,
            mean_rmse_interior: rmse[1..10].iter().sum::<f64>() / 9.0,
            max_rmse: rmse.iter().copied().fold(0.0, f64::max),
            rmse_t0: rmse[0],
            rmse_half: rmse[5],
            rmse_t1: rmse[10],
            overshoot,
            undershoot,
        });
    }
    (rows, sums)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::sh::constant;

    /// The specs reproduce the registered encoders' fits exactly.
    #[test]
    fn specs_match_the_registered_encoders() {
        let n = DVec3::new(0.2, 0.9, 0.1).normalize();
        let d = DVec3::new(0.6, 0.5, -0.2).normalize();
        let visible = crate::math::gram::multiply_full(&constant(Rgb::new(0.3, 0.4, 0.5)), 0.0, n)
            + delta_light(d, Rgb::new(2.0, 1.0, 0.5))
            + delta_light(DVec3::new(-0.3, 0.8, 0.4).normalize(), Rgb::new(0.2, 0.9, 0.1));
        let iz = visible.convolve_cosine().eval(n);
        let input = FitInput {
            probe_sh: &visible,
            visible_sh: &visible,
            surface_normal: Some(n),
            cone: None,
            exact_at_normal: Some(iz),
            surface_albedo: None,
            radiance: None,
        };
        for (basis, id) in [(Basis::Ahd, "ahd_search_hemi"), (Basis::Hhd, "hhd_search_hemi")] {
            let m = fitted_model(basis, &input);
            let f = crate::encoders::build(id, None, toml::Table::new()).unwrap().encoder.fit(&input);
            for w in Domain::Sphere.output_grid((16, 8)).normals {
                assert_eq!(m.irradiance(w), f.irradiance(w), "{id} at {w}");
            }
        }
    }

    #[test]
    fn turning_is_a_rotation_about_y() {
        let (w, h) = (8, 4);
        let texels: Vec<[f32; 3]> = (0..w * h).map(|i| [i as f32, 0.0, 1.0]).collect();
        let m = EnvMap::new("m", w, h, texels).unwrap();
        let t = turned(&m).unwrap();
        let g = crate::envmap::LatLong::new(w, h);
        for j in 0..h {
            for i in 0..w {
                let d = g.direction(i, j);
                let rotated = DVec3::new(-d.x, d.y, -d.z);
                // The texel of t at direction d is m's texel at d turned 180° about +Y.
                let at = (0..w).flat_map(|a| (0..h).map(move |b| (a, b)));
                let (ii, jj) = at.clone().find(|&(a, b)| (g.direction(a, b) - rotated).length() < 1e-9).unwrap();
                assert_eq!(t.texel(i, j), m.texel(ii, jj));
            }
        }
    }

    #[test]
    fn shoot_measures_beyond_both_endpoints() {
        assert_eq!(shoot(&[1.0, 0.5, 0.0]), (0.0, 0.0));
        assert_eq!(shoot(&[1.0, 1.5, 0.5]), (0.5, 0.0));
        assert_eq!(shoot(&[1.0, 0.25, 0.5]), (0.0, 0.25));
    }
}
