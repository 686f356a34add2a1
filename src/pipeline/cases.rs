//! What an experiment's work is made of: its cases (surface orientation × effects), the data
//! computed once per map ([`MapData`]) and per case ([`CaseData`]: the fit inputs, the exact
//! reference under the case's caps, the visible light). The runner (`runner.rs`) orders the
//! work over them; sweeps, claims and sheets build the same data, so everything scores the
//! same inputs.

use crate::encoders::encoder::FitInput;
use crate::envmap::moments::RowMoments;
use crate::envmap::{EnvMap, LatLong};
use crate::math::cap::Cap;
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use crate::pipeline::experiment::{DomainKind, Effect, Experiment};
use crate::pipeline::reuse::{cap_bits, Key, Path, ReferenceCache};
use crate::reference::domain::{frame_to, Domain, OutputGrid};
use crate::reference::exact::Reference;
use crate::reference::projection::{project, project_visible};
use crate::reference::radiance::{MapLight, RadianceSource};
use crate::reference::shared_kernel::irradiance_many_together;
use glam::DVec3;
use rayon::prelude::*;

/// One surface configuration to score: where n′ ranges and what light is visible.
#[derive(Clone, Debug)]
pub struct Case {
    /// Where the output normals n′ range (sphere or hemisphere about N).
    pub domain: Domain,
    /// `sphere` or `hemisphere:<orientation>` (or `sphere@<orientation>` for a sphere domain
    /// with effects about N).
    pub domain_label: String,
    /// The orientation set N was drawn from ("-" without one).
    pub orientation_set: String,
    /// The effects applied, joined with "+" ("none" without any).
    pub effects_label: String,
    /// The visibility caps the light is restricted to (hemisphere and cone effects).
    pub masks: Vec<Cap>,
    /// The surface normal N; None for the sphere probe case.
    pub normal: Option<DVec3>,
    /// The cone effect's (centre, cos α), if any.
    pub cone: Option<(DVec3, f64)>,
    /// The albedo ρ of the surface below the horizon under the `self_bounce` effect.
    pub albedo: Option<f64>,
}

impl Case {
    /// The whole sphere: no normal, no effect (a probe; an experiment without orientations).
    pub fn sphere() -> Case {
        Case {
            domain: Domain::Sphere,
            domain_label: "sphere".into(),
            orientation_set: "-".into(),
            effects_label: "none".into(),
            masks: vec![],
            normal: None,
            cone: None,
            albedo: None,
        }
    }
}

impl Case {
    /// A surface of unit normal `n` lit by the light above its horizon, normals n′ over the
    /// hemisphere about it, no other effect (what `eval --domain hemisphere:AXIS`, the API's
    /// `Surface::Normal` and the results viewer score), labelled `label`.
    pub fn hemisphere(n: DVec3, label: String) -> Case {
        Case {
            domain: Domain::Hemisphere { normal: n },
            domain_label: label,
            orientation_set: "-".into(),
            effects_label: "hemisphere".into(),
            masks: vec![Cap::hemisphere(n)],
            normal: Some(n),
            cone: None,
            albedo: None,
        }
    }
}

/// The cases an experiment declares.
pub fn cases(exp: &Experiment) -> Vec<Case> {
    if exp.orientations.is_empty() {
        return vec![Case::sphere()];
    }
    let mut out = Vec::new();
    for o in &exp.orientations {
        let n = o.normal;
        let (domain, domain_label) = match exp.domain {
            DomainKind::Sphere => (Domain::Sphere, format!("sphere@{}", o.label)),
            DomainKind::Hemisphere => (Domain::Hemisphere { normal: n }, format!("hemisphere:{}", o.label)),
        };
        // Effect variants: the cartesian product of every effect's parameter lists.
        let mut variants: Vec<Variant> = vec![(vec![], vec![], None, None)];
        for e in &exp.effects {
            let mut next = Vec::new();
            for (masks, labels, cone, albedo) in &variants {
                match e {
                    Effect::Hemisphere => {
                        let mut m = masks.clone();
                        m.push(Cap::hemisphere(n));
                        let mut l = labels.clone();
                        l.push("hemisphere".into());
                        next.push((m, l, *cone, *albedo));
                    }
                    Effect::SelfBounce { albedo: values } => {
                        for &a in values {
                            let mut l = labels.clone();
                            l.push(format!("self_bounce(albedo={a})"));
                            next.push((masks.clone(), l, *cone, Some(a)));
                        }
                    }
                    Effect::Cone { cos_alpha, tilt_deg } => {
                        for &t in tilt_deg {
                            let c = cone_centre(n, t);
                            for &ca in cos_alpha {
                                let mut m = masks.clone();
                                m.push(Cap::new(c, ca));
                                let mut l = labels.clone();
                                l.push(format!("cone(cos={ca},tilt={t}deg)"));
                                next.push((m, l, Some((c, ca)), *albedo));
                            }
                        }
                    }
                }
            }
            variants = next;
        }
        for (masks, labels, cone, albedo) in variants {
            out.push(Case {
                domain: domain.clone(),
                domain_label: domain_label.clone(),
                orientation_set: o.set.clone(),
                effects_label: if labels.is_empty() { "none".into() } else { labels.join("+") },
                masks,
                normal: Some(n),
                cone,
                albedo,
            });
        }
    }
    out
}

/// One effect combination while the cartesian product is built: caps, labels, cone, albedo.
type Variant = (Vec<Cap>, Vec<String>, Option<(DVec3, f64)>, Option<f64>);

/// The cone centre: N tilted by `tilt_deg` towards the tangent of N's frame (the image of +X
/// under the rotation taking +Y to N).
pub fn cone_centre(n: DVec3, tilt_deg: f64) -> DVec3 {
    let t = tilt_deg.to_radians();
    let tangent = frame_to(n) * DVec3::X;
    (n * t.cos() + tangent * t.sin()).normalize()
}

/// The profile phase of computing a case's exact reference on an output grid (a value handed
/// back by the [`ReferenceCache`] is not timed: the phase's calls count the computations).
pub const REFERENCE: &str = "reference";

/// Per-map data computed once and shared by every case: the row moments (for the reference
/// and masked projections) and the probe's L2 SH.
pub struct MapData<'m> {
    /// The map.
    pub map: &'m EnvMap,
    /// Prefix sums of the map's row moments.
    pub moments: RowMoments<'m>,
    /// The map's L2 radiance SH (the probe).
    pub probe_sh: Sh9,
}

impl<'m> MapData<'m> {
    /// Computes the moments and the probe SH of `map`.
    pub fn new(map: &'m EnvMap) -> Self {
        MapData { map, moments: RowMoments::new(map), probe_sh: project(map) }
    }
}

/// Evaluates together, and keeps in `cache`, the capped references of the cases that share a
/// hemisphere domain (the cone effect's cones about one surface normal N) on the experiment's
/// own grid of that domain (`reference::shared_kernel`: the kernel's arcs, F at their ends and
/// the row prefix sums once for all of a normal's caps). Each case's
/// [`CaseData::reference_on`] then finds its values there, bit for bit what it would have
/// computed. Nothing is done for a map without a pixel sha256 (nothing would be kept), for an
/// experiment none of whose metrics scores on its own grid, or for a domain with one set of caps.
pub fn references_together(exp: &Experiment, data: &MapData, cases: &[Case], cache: &ReferenceCache) {
    let Some(sha) = data.map.pixel_sha256.as_deref() else { return };
    if !exp.metrics.iter().any(|m| m.fixed_resolution().is_none()) {
        return;
    }
    // Per surface normal N (bit for bit), the distinct sets of caps of its capped cases.
    let mut groups: Vec<(DVec3, Vec<&[Cap]>)> = Vec::new();
    for c in cases.iter().filter(|c| !c.masks.is_empty()) {
        let Domain::Hemisphere { normal } = c.domain else { continue };
        let masks = c.masks.as_slice();
        match groups.iter_mut().find(|g| g.0.to_array().map(f64::to_bits) == normal.to_array().map(f64::to_bits)) {
            Some(g) if !g.1.iter().any(|m| cap_bits(m) == cap_bits(masks)) => g.1.push(masks),
            Some(_) => {}
            None => groups.push((normal, vec![masks])),
        }
    }
    groups.retain(|g| g.1.len() > 1);
    groups.par_iter().for_each(|(normal, sets)| {
        let grid = Domain::Hemisphere { normal: *normal }.output_grid(exp.resolution);
        let base = Key::new(sha, &[], exp.polar_nodes, Path::PerNormal, &grid.normals);
        let keys = sets.iter().map(|m| base.for_caps(m)).collect();
        cache.keep_together(keys, REFERENCE, || {
            let refs: Vec<Reference> =
                sets.iter().map(|m| Reference::new(&data.moments, m.to_vec(), exp.polar_nodes)).collect();
            irradiance_many_together(&refs.iter().collect::<Vec<_>>(), &grid.normals)
        });
    });
}

/// What every encoder is fitted from in one case, owned (the timing pass keeps it after the
/// case's reference is gone): the probe's SH, the SH of the light visible under the case's
/// caps, and the exact E/π at N.
#[derive(Clone, Copy, Debug)]
pub struct CaseInputs {
    /// The probe's L2 radiance SH (the whole map).
    pub probe_sh: Sh9,
    /// L2 radiance SH of the light visible under the case's caps.
    pub visible_sh: Sh9,
    /// Exact E/π at N; None without a surface normal.
    pub exact_at_normal: Option<Rgb>,
}

impl CaseInputs {
    /// The fit input of `case` (its surface normal, cone and albedo) from these inputs and the
    /// case's visible light (`None`: encoders fall back to the light of the visible SH).
    pub fn fit_input<'s>(&'s self, case: &Case, light: Option<&'s dyn RadianceSource>) -> FitInput<'s> {
        FitInput {
            probe_sh: &self.probe_sh,
            visible_sh: &self.visible_sh,
            surface_normal: case.normal,
            cone: case.cone,
            exact_at_normal: self.exact_at_normal,
            surface_albedo: case.albedo,
            radiance: light,
        }
    }
}

/// Per-case data: the fit inputs, the exact reference under the case's caps, and the visible
/// light itself (lazy: nothing is computed unless an encoder asks). Sweeps, claims and sheets
/// build it too, so everything scores the same inputs.
pub struct CaseData<'a> {
    /// The case scored.
    pub case: &'a Case,
    /// What the encoders are fitted from.
    pub inputs: CaseInputs,
    /// The exact reference under the case's caps.
    pub reference: Reference<'a>,
    /// The visible light (lazy).
    pub light: MapLight<'a>,
    /// The map's pixel sha256 (None: a map held only in memory) and the polar nodes: with the
    /// case's caps, what a reference kept in `cache` is keyed by.
    map_sha256: Option<&'a str>,
    polar_nodes: usize,
    /// Where references are kept and looked up ([`CaseData::reusing`]); None: computed each time.
    cache: Option<&'a ReferenceCache<'a>>,
}

impl<'a> CaseData<'a> {
    /// Only the declared effects are simulated: with no caps the visible SH is the probe SH.
    pub fn new(data: &'a MapData, case: &'a Case, polar_nodes: usize) -> Self {
        let visible_sh = if case.masks.is_empty() {
            data.probe_sh
        } else {
            project_visible(&data.moments, &case.masks, polar_nodes)
        };
        let reference = Reference::new(&data.moments, case.masks.clone(), polar_nodes);
        let exact_at_normal = case.normal.map(|n| reference.irradiance(n));
        let light = MapLight::new(data.map, &data.moments, case.masks.clone(), polar_nodes);
        CaseData {
            case,
            inputs: CaseInputs { probe_sh: data.probe_sh, visible_sh, exact_at_normal },
            reference,
            light,
            map_sha256: data.map.pixel_sha256.as_deref(),
            polar_nodes,
            cache: None,
        }
    }

    /// The same case, its references kept in and read from `cache`, each computation timed
    /// there as [`REFERENCE`] (on a grid) or as the phase the caller names.
    pub fn reusing(self, cache: &'a ReferenceCache<'a>) -> Self {
        CaseData { cache: Some(cache), ..self }
    }

    /// The capped reference (no self-bounce) at `normals`, on the lat-long path when `grid`
    /// (`normals` are then that grid's), else per normal: `compute`'s values, or the cache's
    /// when it has this key; None only when `compute` was stopped.
    fn capped(
        &self,
        grid: Option<LatLong>,
        normals: &[DVec3],
        phase: &'static str,
        compute: impl FnOnce() -> Option<Vec<Rgb>>,
    ) -> Option<Vec<Rgb>> {
        match self.cache {
            Some(cache) => {
                let (masks, nodes) = (&self.case.masks, self.polar_nodes);
                let key = self.map_sha256.map(|m| match grid {
                    Some(grid) => Key::latlong(m, masks, nodes, grid),
                    None => Key::new(m, masks, nodes, Path::PerNormal, normals),
                });
                cache.values(key, phase, compute)
            }
            None => compute(),
        }
    }

    /// What every encoder is fitted from.
    pub fn fit_input(&self) -> FitInput<'_> {
        self.inputs.fit_input(self.case, Some(&self.light))
    }

    /// The reference E/π at `normals`: the exact irradiance under the case's caps plus, under
    /// the `self_bounce` effect, the light of the surface below the horizon.
    pub fn reference_many(&self, normals: &[DVec3]) -> Vec<Rgb> {
        self.reference_many_as(normals, REFERENCE)
    }

    /// [`CaseData::reference_many`], a computation timed on the cache as `phase`.
    pub fn reference_many_as(&self, normals: &[DVec3], phase: &'static str) -> Vec<Rgb> {
        let compute = || Some(self.reference.irradiance_many(normals));
        // Cannot fail: the per-normal path is never stopped.
        let mut v = self.capped(None, normals, phase, compute).expect("never stopped");
        self.add_self_bounce(normals, &mut v);
        v
    }

    /// The reference E/π on an output grid (the fast lat-long path where it applies), with the
    /// self-bounce as in [`CaseData::reference_many`].
    pub fn reference_on(&self, grid: &OutputGrid) -> Vec<Rgb> {
        self.reference_on_until(grid, &|| false)
    }

    /// [`Self::reference_on`], checking `stop` between the map's rows (on the lat-long path):
    /// once it says stop, the values mean nothing.
    pub fn reference_on_until(&self, grid: &OutputGrid, stop: &(dyn Fn() -> bool + Sync)) -> Vec<Rgb> {
        let compute: Box<dyn FnOnce() -> Vec<Rgb>> = match grid.latlong {
            Some(ll) => Box::new(move || self.reference.irradiance_latlong_until(ll, stop)),
            None => Box::new(|| self.reference.irradiance_many(&grid.normals)),
        };
        // Stopped values are handed back (they mean nothing) but never kept.
        let mut stopped = None;
        let kept = self.capped(grid.latlong, &grid.normals, REFERENCE, || {
            let v = compute();
            if stop() {
                stopped = Some(v);
                None
            } else {
                Some(v)
            }
        });
        let mut v = kept.or(stopped).unwrap_or_default();
        self.add_self_bounce(&grid.normals, &mut v);
        v
    }

    /// Self-bounce (hemispherical-lighting talk; `Effect::SelfBounce`). The model: the surface
    /// below the horizon is an infinite Lambertian plane of albedo ρ, lit by the exact
    /// irradiance at N (I_z, E/π units, so the plane's irradiance is π·I_z); it reflects the
    /// uniform radiance ρ·I_z into every direction below the horizon. A uniform radiance L
    /// over the half-space ω·N < 0 gives E/π = L·(1 − H(n′)) at a normal n′, with
    /// H(n′) = (1 + n′·N)/2 the hemisphere light; so the reference gains
    /// ρ·I_z·(1 − H(n′)). Nothing is added without the effect.
    fn add_self_bounce(&self, normals: &[DVec3], values: &mut [Rgb]) {
        let (Some(rho), Some(n), Some(iz)) = (self.case.albedo, self.case.normal, self.inputs.exact_at_normal) else {
            return;
        };
        for (v, &np) in values.iter_mut().zip(normals) {
            *v += iz * (rho * (1.0 - np.dot(n)) * 0.5);
        }
    }
}
