//! A validated experiment, as the runner takes it: maps, encoders, metrics, the domain of
//! output normals, the surface normals and the visibility effects.

use crate::encoders::NamedEncoder;
use crate::reference::domain::Orientation;
use crate::reference::metrics::Metric;
use std::path::PathBuf;

/// The most cases (surface normals × effect parameter combinations) one experiment may declare.
pub const MAX_CASES: usize = 1 << 20;

/// A visibility effect applied to the radiance before it reaches the surface.
#[derive(Clone, Debug, PartialEq)]
pub enum Effect {
    /// Only light with ω·N > 0 counts.
    Hemisphere,
    /// Only light inside the cone of cos α about C counts, C being N tilted by `tilt_deg`
    /// towards the tangent of N's frame (the image of +X under the rotation taking +Y to N).
    Cone {
        /// The cone's half-angle cosines cos α, each in [-1, 1); one case per value.
        cos_alpha: Vec<f64>,
        /// The tilts of C from N, in degrees; one case per value (default `[0]`).
        tilt_deg: Vec<f64>,
    },
    /// Self-bounce (hemispherical-lighting talk): the surface below the horizon is an infinite
    /// Lambertian plane of albedo ρ lit by the exact I_z, so it reflects the uniform radiance
    /// ρ·I_z (E/π units) from every direction below the horizon, and the reference gains
    /// ρ·I_z·(1 − H(n′)), H(n′) = (1 + n′·N)/2 (`runner::CaseData`). One case per albedo;
    /// needs the `hemisphere` effect.
    SelfBounce {
        /// The plane's albedos ρ, each in [0, 1].
        albedo: Vec<f64>,
    },
}

/// The domain of output normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DomainKind {
    /// Every normal of the sphere.
    Sphere,
    /// The normals n′ of the hemisphere about each surface normal N.
    Hemisphere,
}

/// A validated experiment.
pub struct Experiment {
    /// The name: results go to `results/<name>/` (letters, digits, `_`, `-`).
    pub name: String,
    /// Shown in the report; may be empty.
    pub description: String,
    /// The file it was read from (`None` when built from a parsed file).
    pub source: Option<PathBuf>,
    /// The map names, each once, in the file's order.
    pub maps: Vec<String>,
    /// The encoders, built through the registry, with distinct names.
    pub encoders: Vec<NamedEncoder>,
    /// The metrics scored, in the file's order (`exact` when it names none).
    pub metrics: Vec<Metric>,
    /// The domain of output normals.
    pub domain: DomainKind,
    /// The surface normals N, expanded from the file's orientation names.
    pub orientations: Vec<Orientation>,
    /// The visibility effects, in the file's order.
    pub effects: Vec<Effect>,
    /// The `exact` metric's output grid (W, H) in pixels, W = 2H.
    pub resolution: (usize, usize),
    /// Gauss–Legendre nodes per row piece of the reference (1..=16).
    pub polar_nodes: usize,
    /// Whether the CI check re-runs it.
    pub ci: bool,
    /// `Some(baseline)` when a per-orientation summary is declared.
    pub summary: Option<Option<String>>,
    /// The maps that get a comparison sheet in the report (`sheets = [...]`; `None`: every
    /// map). Each is one of `maps`.
    pub sheets: Option<Vec<String>>,
}

impl Experiment {
    /// The maps that get a comparison sheet, in the experiment's map order.
    pub fn sheet_maps(&self) -> Vec<String> {
        match &self.sheets {
            None => self.maps.clone(),
            Some(s) => self.maps.iter().filter(|m| s.contains(m)).cloned().collect(),
        }
    }
}
