//! `probelab run`, the workflow: experiment files (or experiments by name) run and each
//! `results/<name>/table.csv` written where none exists; a table that exists is a baseline,
//! left unchanged when nothing moved and refused when something did (`regression::guard`).
//! Under the results folder's exclusive lock. What it says as it stores is `run/text.rs`.

pub mod text;

use super::context::experiment_outputs_distinct;
use super::Env;
use crate::pipeline::experiment::{self, Experiment};
use crate::pipeline::reuse::ReferenceCache;
use crate::pipeline::runner::{self, RunReport};
use crate::regression::guard::{self, Stored};
use anyhow::{bail, Result};
use std::path::{Path, PathBuf};

/// What `run` is asked to do.
pub struct RunOptions {
    /// Experiment TOML files, or names of experiments in `<root>/experiments/`.
    pub experiments: Vec<String>,
    /// The output folder (default: `<root>/results`).
    pub out: Option<PathBuf>,
}

/// What became of one experiment's table.
pub struct StoredTable {
    /// The experiment's name.
    pub experiment: String,
    /// How many maps it names.
    pub maps: usize,
    /// Written, matched, or refused.
    pub stored: Stored,
}

/// What `run` did.
pub struct RunOutcome {
    /// Each experiment's table, in order.
    pub tables: Vec<StoredTable>,
}

impl RunOutcome {
    /// The experiments whose baselines moved and were not written.
    pub fn refused(&self) -> Vec<String> {
        self.tables.iter().filter(|t| !t.stored.stands()).map(|t| t.experiment.clone()).collect()
    }
}

/// Losing nothing: every experiment is loaded and run before anything is written, so a
/// failure anywhere (a bad file, a map that cannot be read) leaves results/ as it was; each
/// file is then written atomically.
pub fn run(env: &Env, opts: &RunOptions) -> Result<RunOutcome> {
    let out = env.results(opts.out.clone());
    // Found and read before the lock creates the output folder: a typo writes nothing.
    let exps = opts
        .experiments
        .iter()
        .map(|e| Experiment::load(&experiment::resolve(&env.root, e)?))
        .collect::<Result<Vec<_>>>()?;
    let _lock = env.writing(&out)?;
    experiment_outputs_distinct(&out, &exps)?;
    env.refuse_long_experiments(&exps)?;
    let mut done = Vec::new();
    // The experiments' cases that are the same on a map share one reference.
    let cache = ReferenceCache::new(env.settings.profile);
    for exp in &exps {
        let report = runner::run(exp, &env.search, &env.settings, &cache)?;
        if !report.missing.is_empty() {
            bail!(
                "{}\nnothing written. Searched: {}",
                missing_maps(exp, &report.missing, &report.missing_why),
                env.search.describe()
            );
        }
        done.push(report);
    }
    let mut tables = Vec::new();
    for (exp, report) in exps.iter().zip(&done) {
        let stored = store(env, &out, exp, report)?;
        tables.push(StoredTable { experiment: exp.name.clone(), maps: exp.maps.len(), stored });
    }
    Ok(RunOutcome { tables })
}

/// "FILE:LINE: map 'x' not found" for each missing map (the line where the experiment file
/// names it).
fn missing_maps(exp: &Experiment, missing: &[String], why: &[String]) -> String {
    let file = exp.source.as_ref().map(|p| p.display().to_string()).unwrap_or_else(|| exp.name.clone());
    // A typo's suggestion (" (did you mean 'x'?)") is kept from the reason; the rest of it (how
    // to get a known map) is what the search path line after says.
    let hint =
        |k: usize| why.get(k).and_then(|w| w.find(" (did you mean").map(|i| w[i..].to_string())).unwrap_or_default();
    missing
        .iter()
        .zip(exp.source_lines(missing))
        .enumerate()
        .map(|(k, (m, line))| match line {
            Some(l) => format!("{file}:{l}: map '{m}' not found{}", hint(k)),
            None => format!("{file}: map '{m}' not found{}", hint(k)),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Writes `<out>/<name>/table.csv` and `provenance.toml` atomically when there is no table
/// yet; an existing table is a baseline and is never overwritten here (only `bless` does)
/// ([`guard::store`]). What became of the table is noted as it is known; when the table
/// stands, the summary derived from it is written too (`run`, `reproduce`).
pub(crate) fn store(env: &Env, out: &Path, exp: &Experiment, report: &RunReport) -> Result<Stored> {
    let _s = env.settings.span("write");
    let stored = guard::store(out, &env.root, exp, report)?;
    let dir = out.join(&exp.name);
    env.note_lines(&text::stored(&stored, &dir, report.rows.len()));
    if !stored.stands() {
        return Ok(stored);
    }
    if let Some(baseline) = &exp.summary {
        // A table that stood within tolerance is the one kept: summarise its numbers.
        let rows = match stored {
            Stored::Unchanged(_) => guard::rows_as_stored(&dir, &report.rows)?,
            _ => report.rows.clone(),
        };
        crate::pipeline::summary::write(&dir, baseline.as_deref(), &rows)?;
        env.notes.note(&format!("wrote {}", dir.join("summary.csv").display()));
    }
    Ok(stored)
}
