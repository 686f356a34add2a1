//! What the report is asked ([`Options`]: where it reads and writes, the sheets' scale) and
//! what a run returns ([`Generated`]: the files written, what this machine lacked).

use crate::envmap::search::SearchPath;
use crate::pipeline::reuse::ReferenceCache;
use std::path::{Path, PathBuf};

/// Where the report reads and writes.
pub struct Options<'a> {
    /// Repository root (holds `experiments/`).
    pub root: &'a Path,
    /// The results folder (`REPORT.md` is written here).
    pub out: &'a Path,
    /// Where the experiments' maps are looked up (for the sheets and the maps' checksums).
    pub search: &'a SearchPath,
    /// The comparison sheets' scale (`report --scale`, 1..=[`sheet::MAX_SCALE`]): every measure
    /// of a sheet times this; 1 is the standard sheet. Charts do not depend on it.
    pub sheet_scale: u32,
    /// Where the sheets' references are kept and looked up; its profile (`--profile`), if
    /// any, is where the report's phases are timed.
    pub references: &'a ReferenceCache<'a>,
}

/// What a report run produced. The pages written depend only on the committed files (results,
/// experiments, provenance), never on which maps this machine has: what it lacked is here.
pub struct Generated {
    /// The path of the `REPORT.md` written.
    pub report: PathBuf,
    /// The number of PNG pictures drawn: comparison sheets and charts (their SVGs not counted).
    pub pictures: usize,
    /// Experiments whose sheets were not redrawn (maps missing).
    pub kept: Vec<String>,
    /// The experiments' maps not found on the search path.
    pub missing: Vec<String>,
    /// Maps found in another file than the one their tables record (a sentence each).
    pub mismatches: Vec<String>,
    /// Files of the results viewer (`results/site/`) rewritten: 0 when nothing changed.
    pub site_rewritten: usize,
}
