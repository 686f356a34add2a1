//! `bless`: experiments re-run and the baselines that differ rewritten, each experiment's
//! files together (table, then the provenance that vouches for it:
//! [`crate::io::atomic::write_set`]). The only way a baseline changes.

use crate::envmap::search::SearchPath;
use crate::pipeline::experiment::Experiment;
use crate::pipeline::runner::{self, RunReport};
use crate::pipeline::settings::RunSettings;
use crate::pipeline::summary::SUMMARY;
use crate::regression::baseline::TABLE;
use crate::regression::check::{compare_with_baseline, select, ExperimentCheck, MapPolicy, Selection};
use crate::regression::provenance::{self, Provenance};
use crate::regression::tolerance::Tolerances;
use anyhow::{bail, Result};
use std::path::{Path, PathBuf};

/// Which baselines a bless rewrites.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rewrite {
    /// Those whose comparison failed.
    Moved,
    /// Every one (`--force`: refreshes the provenance and ignored columns such as timings).
    All,
}

/// What became of one experiment's baseline.
pub struct BlessedExperiment {
    /// The experiment's name.
    pub name: String,
    /// Its baseline folder.
    pub dir: PathBuf,
    /// Whether its comparison passed (nothing moved).
    pub passed: bool,
    /// The files written, in order; `None` when nothing moved and it was left unchanged.
    pub written: Option<Vec<String>>,
}

/// What a bless did.
pub struct Blessed {
    /// Each experiment blessed, in order.
    pub experiments: Vec<BlessedExperiment>,
    /// The experiments not blessed for want of maps (by default only): name and missing maps.
    pub skipped: Vec<(String, Vec<String>)>,
}

/// `probelab bless`: re-runs the experiments (by default all of them), hands each comparison
/// to `compared` (the same report as `check`'s), and rewrites the baselines that differ (all
/// of them under [`Rewrite::All`]). Every experiment is run and compared before anything is
/// written, so `compared` (which prints) can stop the command only before its first write. A
/// named experiment whose maps are missing is an error (nothing is written); by default such
/// experiments are skipped and listed.
pub fn bless(
    root: &Path,
    search: &SearchPath,
    out: &Path,
    (names, rewrite): (&[String], Rewrite),
    settings: &RunSettings,
    compared: &mut dyn FnMut(&ExperimentCheck) -> Result<()>,
) -> Result<Blessed> {
    let (exps, _) = select(root, names, Selection::All)?;
    let tolerances = Tolerances::load(root)?;
    let mut staged = Vec::new();
    let mut skipped = Vec::new();
    // The experiments' cases that are the same on a map share one reference.
    let cache = crate::pipeline::reuse::ReferenceCache::new(settings.profile);
    for exp in &exps {
        let report = runner::run(exp, search, settings, &cache)?;
        if !report.missing.is_empty() {
            if !names.is_empty() {
                bail!(
                    "{}: map(s) not found: {}; nothing blessed (a baseline needs every map)",
                    exp.name,
                    report.missing.join(", ")
                );
            }
            skipped.push((exp.name.clone(), report.missing.clone()));
            continue;
        }
        let c = compare_with_baseline(&out.join(&exp.name), exp, &report, &tolerances, MapPolicy::RequireAll)?;
        compared(&c)?;
        let files =
            if c.passed() && rewrite == Rewrite::Moved { None } else { Some(baseline_files(exp, &report, root)?) };
        staged.push((exp.name.clone(), c.passed(), files));
    }
    let mut experiments = Vec::new();
    for (name, passed, files) in staged {
        let dir = out.join(&name);
        if let Some(files) = &files {
            crate::io::atomic::write_set(&dir, files)?;
        }
        let written = files.map(|f| f.into_iter().map(|(n, _)| n).collect());
        experiments.push(BlessedExperiment { name, dir, passed, written });
    }
    Ok(Blessed { experiments, skipped })
}

/// The files of an experiment's baseline, in the order [`crate::io::atomic::write_set`] renames them:
/// the table, then the provenance that vouches for it, then (when the experiment declares a
/// `[summary]`) the summary derived from that table. Written with the table, the summary never
/// lags behind it: a `bless` that left the summary of an older run would have `run`/`reproduce`
/// rewrite it from the kept table on a fresh clone.
pub fn baseline_files(exp: &Experiment, report: &RunReport, root: &Path) -> Result<Vec<(String, Vec<u8>)>> {
    let table = crate::pipeline::table::to_csv(&report.rows)?;
    let prov = Provenance::new(exp, report, &table, root).to_toml()?;
    let mut files = vec![(TABLE.to_string(), table), (provenance::FILE_NAME.to_string(), prov.into_bytes())];
    if let Some(baseline) = &exp.summary {
        files.push((SUMMARY.to_string(), crate::pipeline::summary::summary_csv(&report.rows, baseline.as_deref())?));
    }
    Ok(files)
}
