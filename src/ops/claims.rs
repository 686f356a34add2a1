//! `probelab claims`, the workflow: under the results folder's exclusive lock, the claims
//! measurements run (when their maps are here) and every declared claim judged
//! (`regression::claims`), writing `results/CLAIMS.csv`, the per-paper pages, the measurement
//! tables and the lightmap study's blending strips (drawn by the report layer). Its text is
//! `claims/text.rs`.

pub mod text;

use super::Env;
use crate::pipeline::reuse::ReferenceCache;
use crate::regression::claims::{self, ClaimsMode, ClaimsRun};
use anyhow::Result;
use std::path::{Path, PathBuf};

/// What `claims` is asked to do.
pub struct ClaimsOptions {
    /// The output folder (default: `<root>/results`).
    pub out: Option<PathBuf>,
}

/// What `claims` did.
pub struct ClaimsOutcome {
    /// The claims run: what was written, what moved, the verdicts that changed.
    pub run: ClaimsRun,
    /// How many blending strips were written.
    pub strips: usize,
    /// The output folder.
    pub out: PathBuf,
}

impl ClaimsOutcome {
    /// True when no measurement moved.
    pub fn passed(&self) -> bool {
        self.run.passed()
    }
}

/// Runs and judges the claims, writing what is new or unmoved ([`ClaimsMode::Write`]) and the
/// blending strips.
pub fn claims(env: &Env, opts: &ClaimsOptions) -> Result<ClaimsOutcome> {
    env.checkout()?;
    let out = env.results(opts.out.clone());
    let _lock = env.writing(&out)?;
    let run = claims::run(&env.root, &env.search, &out, ClaimsMode::Write)?;
    let strips = write_strips(env, &out, &run, &ReferenceCache::new(env.settings.profile))?;
    Ok(ClaimsOutcome { run, strips, out })
}

/// Draws the lightmap study's blending strips and the claims pages' own figures (the claims'
/// cut-down sheets, the blending charts; report layer) and writes them under `<out>/claims/`,
/// each atomically; returns how many strips (`claims`, `bless`, `reproduce`). The sheets'
/// references are kept in and read from `cache`.
pub(crate) fn write_strips(env: &Env, out: &Path, run: &ClaimsRun, cache: &ReferenceCache) -> Result<usize> {
    let strips = crate::report::strip::pngs(&run.strips)?;
    for (name, bytes) in &strips {
        crate::io::atomic::write(&out.join("claims").join(name), bytes)?;
    }
    let sheets = crate::report::claim_figures::claim_sheets(&env.root, &env.search, out, cache)?;
    for (name, bytes) in sheets.iter().chain(&crate::report::claim_figures::blend_charts(out)?) {
        crate::io::atomic::write(&out.join(name), bytes)?;
    }
    Ok(strips.len())
}
