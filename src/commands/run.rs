//! `probelab run`: runs experiment files (or experiments by name) and writes each `results/<name>/table.csv` where none
//! exists; a table that exists is a baseline, left unchanged when nothing moved and refused
//! (exit 1) when something did. Takes the results folder's exclusive lock.

use super::context::{describe_search, refused_exit};
use super::terminal::{note, noteln};
use anyhow::{bail, Result};
use probelab::ops::context::experiment_outputs_distinct;
use probelab::ops::Env;
use probelab::pipeline::experiment::{self, Experiment};
use probelab::pipeline::runner::{self, RunReport};
use probelab::regression::check::{self, Stored};
use std::path::{Path, PathBuf};

/// `probelab run`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Experiment TOML files, or names of experiments in <root>/experiments/ (`sh_baseline`).
    #[arg(required = true)]
    experiments: Vec<String>,
    /// Output folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Losing nothing: every experiment is loaded and run before anything is written, so a
/// failure anywhere (a bad file, a map that cannot be read) leaves results/ as it was; each
/// file is then written atomically.
pub fn run(a: Args, env: &Env) -> Result<i32> {
    let out = env.results(a.out);
    // Found and read before the lock creates the output folder: a typo writes nothing.
    let exps = a
        .experiments
        .iter()
        .map(|e| Experiment::load(&experiment::resolve(&env.root, e)?))
        .collect::<Result<Vec<_>>>()?;
    let _lock = env.writing(&out)?;
    experiment_outputs_distinct(&out, &exps)?;
    env.refuse_long_experiments(&exps)?;
    let mut done = Vec::new();
    for exp in &exps {
        let report = runner::run(exp, &env.search)?;
        if !report.missing.is_empty() {
            bail!(
                "{}\nnothing written. Searched: {}",
                missing_maps(exp, &report.missing, &report.missing_why),
                describe_search(&env.search)
            );
        }
        done.push(report);
    }
    let mut refused = Vec::new();
    for (exp, report) in exps.iter().zip(&done) {
        if store(&env.root, &out, exp, report)?.is_none() {
            refused.push(exp.name.clone());
        }
    }
    Ok(refused_exit(&refused))
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

/// Writes results/<name>/table.csv and provenance.toml atomically when there is no table yet;
/// an existing table is a baseline and is never overwritten here (only `bless` does): the
/// differences are printed and `None` returned if its numbers moved (`check::store`). When the
/// table stands, the summary derived from it is written too, and the phrase saying what became
/// of the table is returned.
pub fn store(root: &Path, out: &Path, exp: &Experiment, report: &RunReport) -> Result<Option<String>> {
    let _s = probelab::io::profile::span("write");
    let stored = check::store(out, root, exp, report)?;
    note(&stored.notes(exp, out, report.rows.len()));
    if !stored.stands() {
        return Ok(None);
    }
    if let Some(baseline) = &exp.summary {
        let dir = out.join(&exp.name);
        // A table that stood within tolerance is the one kept: summarise its numbers.
        let rows = match stored {
            Stored::Unchanged(_) => check::rows_as_stored(&dir, &report.rows)?,
            _ => report.rows.clone(),
        };
        probelab::pipeline::summary::write(&dir, baseline.as_deref(), &rows)?;
        noteln!("wrote {}", dir.join("summary.csv").display());
    }
    Ok(Some(stored.summary()))
}
