//! Every lightmap measurement at once: the tables the declarations judge and the blending
//! strips the report draws ([`Study`]).

use crate::claims::lightmap::blend_tables::blend_measures;
use crate::claims::lightmap::bounce;
use crate::claims::lightmap::fig2_tables::fig2_measures;
use crate::claims::lightmap::leak;
use crate::claims::lightmap::roundtrip::hhd_roundtrip;
use crate::claims::lightmap::strip;
use crate::claims::measure::Measure;
use crate::envmap::search::SearchPath;
use crate::pipeline::experiment::Experiment;
use anyhow::Result;
use std::path::Path;

/// What [`measure`] returns: the measurement tables, and the blending strips for the report
/// layer to draw (one per pair, in `blend::pairs` order).
pub struct Study {
    /// The measurement tables: `fig2`, `fig2_curve`, `blend`, `blend_curve`, `hhd_roundtrip`,
    /// `probe_leak`, `self_bounce_quadrature`.
    pub measures: Vec<Measure>,
    /// The blending strips, one per pair in `blend::pairs` order.
    pub strips: Vec<strip::BlendStrip>,
}

/// The experiment whose maps, orientations, encoders and grid the probe leaks are measured on.
pub const LEAK_EXPERIMENT: &str = "probe_occlusion";

/// The experiment whose maps, cases, encoders and grid the self-bounce is checked on.
pub const BOUNCE_EXPERIMENT: &str = "lightmap_self_bounce";

/// Measures every table of the module (the paper probes of `blend::pairs` and the maps of the
/// [`LEAK_EXPERIMENT`] and [`BOUNCE_EXPERIMENT`] in `experiments` must be on the search path):
/// `fig2`, `fig2_curve`, `blend`, `blend_curve`, `hhd_roundtrip`, `probe_leak`,
/// `self_bounce_quadrature`, and the strips.
pub fn measure(search: &SearchPath, experiments: &Path) -> Result<Study> {
    let (fig2, fig2_curve) = fig2_measures();
    let (blend, blend_curve, strips) = blend_measures(search)?;
    let leaks = leak::measure(search, &Experiment::load(&experiments.join(format!("{LEAK_EXPERIMENT}.toml")))?)?;
    let bounce = bounce::measure(search, &Experiment::load(&experiments.join(format!("{BOUNCE_EXPERIMENT}.toml")))?)?;
    Ok(Study { measures: vec![fig2, fig2_curve, blend, blend_curve, hhd_roundtrip(), leaks, bounce], strips })
}
