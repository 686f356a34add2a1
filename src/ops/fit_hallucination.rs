//! `probelab fit-hallucination`: fits the ZH3 hallucination curve to the radiance SH of maps
//! (their exact projection) and/or a probe file (read as `probes --input` reads it) and scores
//! it beside SH L1 and the paper's curve (`pipeline::hallucination_fit`; ZH3 talk, FORMULAS
//! §5). Nothing is written and no lock is taken.

use super::context::Env;
use crate::pipeline::hallucination_fit::{self, Report};
use anyhow::{bail, Result};
use std::path::PathBuf;

/// The options of `probelab fit-hallucination`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FitHallucinationOptions {
    /// Map names (on the search path) or file paths.
    pub maps: Vec<String>,
    /// A probe file (`--probes`).
    pub probes: Option<PathBuf>,
    /// The probe file's format, `csv` or `f32` (`--format`; `None`: from its extension).
    pub format: Option<String>,
    /// Also fit a cubic (`--cubic`).
    pub cubic: bool,
    /// The zonal axis: `rec709`, `equal` or `channel` (`--axis`).
    pub axis: String,
}

/// What `probelab fit-hallucination` computed.
#[derive(Clone, Debug, PartialEq)]
pub struct HallucinationFit {
    /// The maps named, as given.
    pub maps: Vec<String>,
    /// The curves fitted and scored.
    pub report: Report,
}

/// `probelab fit-hallucination`: the axis checked, the maps projected and the probe file read,
/// then the curves fitted (`hallucination_fit::report`).
pub fn fit_hallucination(env: &Env, o: &FitHallucinationOptions) -> Result<HallucinationFit> {
    let rule = hallucination_fit::parse_axis(&o.axis)?;
    let mut probes = Vec::new();
    for m in &o.maps {
        probes.push(crate::reference::projection::project(&env.search.load(m)?));
    }
    if let Some(path) = &o.probes {
        probes.extend(crate::pipeline::probeset::format::read_all(path, o.format.as_deref())?);
    }
    if probes.is_empty() {
        bail!("fit-hallucination: give map names and/or --probes FILE");
    }
    let report = hallucination_fit::report(&probes, rule, &o.axis, o.cubic)?;
    Ok(HallucinationFit { maps: o.maps.clone(), report })
}

impl HallucinationFit {
    /// The report as printed: the maps read, then the curves (`hallucination_fit::format_report`).
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        if !self.maps.is_empty() {
            out += &format!("maps: {}\n", self.maps.join(", "));
        }
        out + &hallucination_fit::format_report(&self.report)
    }
}
