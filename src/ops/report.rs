//! `probelab report`, the workflow: under the results folder's exclusive lock, the comparison
//! sheets and charts drawn and `results/REPORT.md`, the folders' pages and `PROVENANCE.md`
//! written from the result CSVs (`report::generate`; `reproduce` ends with the same). What it
//! says is `report/text.rs`.

pub mod text;

use super::Env;
use crate::pipeline::reuse::ReferenceCache;
/// The largest `--scale` of the comparison sheets.
pub use crate::report::sheet::MAX_SCALE;
use crate::report::Generated;
use anyhow::Result;
use std::path::{Path, PathBuf};

/// What `report` is asked to do.
pub struct ReportOptions {
    /// The results folder (default: `<root>/results`).
    pub out: Option<PathBuf>,
    /// The comparison sheets' scale, 1 to `report::sheet::MAX_SCALE` (1: the standard sheets).
    pub sheet_scale: u32,
}

/// Writes the report ([`Generated`]: what was drawn, and what this machine lacked).
pub fn report(env: &Env, opts: &ReportOptions) -> Result<Generated> {
    env.checkout()?;
    let out = env.results(opts.out.clone());
    let _lock = env.writing(&out)?;
    generate(env, &out, opts.sheet_scale, &ReferenceCache::new(env.settings.profile))
}

/// Writes `<out>/REPORT.md` with its pictures, the comparison sheets at `sheet_scale`, under a
/// lock the caller holds (`report`, `reproduce`), the sheets' references kept in and read from
/// `cache` (its profile times the report's phases).
pub(crate) fn generate(env: &Env, out: &Path, sheet_scale: u32, cache: &ReferenceCache) -> Result<Generated> {
    let options = crate::report::Options { root: &env.root, out, search: &env.search, sheet_scale, references: cache };
    crate::report::generate(&options)
}
