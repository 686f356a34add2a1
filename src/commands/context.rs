//! What every command shares: the repository root and the map search path ([`Env`]), the
//! results folder, the output folder's locks (exclusive for a writer, shared for `check`),
//! the refusal of work estimated too long (`--allow-long`), and the lines about the search path
//! and refused baselines.

use super::terminal::{note, noteln};
use anyhow::Result;
use probelab::envmap::search::SearchPath;
use probelab::io::distinct::{refuse_overwrite, Named};
use probelab::io::folder;
use probelab::pipeline::estimate::{self, Estimate};
use probelab::pipeline::experiment::Experiment;
use std::path::{Path, PathBuf};

/// What every command is given: the repository root and the map search path.
pub struct Env {
    /// `--root`: the folder holding experiments/, results/ and envmaps/.
    pub root: PathBuf,
    /// `<root>/envmaps`, then `PROBELAB_ENVMAPS`.
    pub search: SearchPath,
    /// `--allow-long`: run work estimated above the bound (`pipeline::estimate::BOUND_S`).
    pub allow_long: bool,
}

impl Env {
    /// The results folder: `out`, or `<root>/results`.
    pub fn results(&self, out: Option<PathBuf>) -> PathBuf {
        out.unwrap_or_else(|| self.root.join("results"))
    }

    /// Refuses work estimated above the bound unless `--allow-long` was given, naming `what`
    /// (the experiment file); announces a long wait that goes ahead (`pipeline::estimate`).
    pub fn refuse_long(&self, what: &str, estimate: &Estimate) -> Result<()> {
        estimate.refuse_if_long(what, self.allow_long)?;
        if estimate.seconds >= ANNOUNCE_S {
            noteln!("{what}: estimated {estimate}; progress shows the time left on a terminal");
        }
        Ok(())
    }

    /// [`Env::refuse_long`] for experiments run together, their estimates added up: a refusal
    /// names the file of the longest.
    pub fn refuse_long_experiments(&self, exps: &[Experiment]) -> Result<()> {
        let parts: Vec<Estimate> = exps.iter().map(|e| estimate::experiment(e, &self.search)).collect();
        let longest = parts.iter().enumerate().max_by(|a, b| a.1.seconds.total_cmp(&b.1.seconds)).map(|(i, _)| i);
        let what = match longest.map(|i| &exps[i]) {
            Some(e) => {
                e.source.as_ref().map(|p| p.display().to_string()).unwrap_or_else(|| format!("probelab {}", e.name))
            }
            None => return Ok(()),
        };
        self.refuse_long(&what, &Estimate::total(&parts))
    }
}

/// An estimate at least this long (seconds) is announced on stderr when the run goes ahead.
const ANNOUNCE_S: f64 = 600.0;

/// Refuses, before anything is written, a command that needs the experiments where there are
/// none: `--root` (by default the current folder) is not a probelab checkout.
pub fn checkout(env: &Env) -> Result<()> {
    let dir = env.root.join("experiments");
    if !dir.is_dir() {
        anyhow::bail!(
            "{}: no experiments folder here: {}",
            dir.display(),
            probelab::pipeline::experiment::NOT_A_CHECKOUT
        );
    }
    Ok(())
}

/// Takes the exclusive lock on an output folder for a writing command (waiting, with a note,
/// while another probelab command holds it), then removes the temporary files that killed
/// runs left there, saying so (`io::folder`).
pub fn writing(out: &Path) -> Result<folder::DirLock> {
    let lock = folder::lock(out, true, || waiting(out))?;
    for p in folder::remove_stale(out)? {
        noteln!("removed {} (left by a killed run whose process is gone)", p.display());
    }
    Ok(lock)
}

/// The shared lock of a command that only reads an output folder (none when it does not
/// exist yet).
pub fn reading(out: &Path) -> Result<Option<folder::DirLock>> {
    if !out.is_dir() {
        return Ok(None);
    }
    Ok(Some(folder::lock(out, false, || waiting(out))?))
}

/// Refuses, before anything runs, experiments whose result files under `out`
/// (`<name>/table.csv`, its provenance and summary) would overwrite one of their experiment
/// files (`io::distinct`).
pub fn experiment_outputs_distinct(out: &Path, exps: &[Experiment]) -> Result<()> {
    use probelab::regression::{baseline::TABLE, provenance::FILE_NAME};
    let targets: Vec<PathBuf> =
        exps.iter().flat_map(|e| [TABLE, FILE_NAME, "summary.csv"].map(|f| out.join(&e.name).join(f))).collect();
    let outputs: Vec<Named> = targets.iter().map(|p| Named { role: "a result file", path: p }).collect();
    let inputs: Vec<Named> =
        exps.iter().filter_map(|e| Some(Named { role: "an experiment file", path: e.source.as_deref()? })).collect();
    refuse_overwrite(&outputs, &inputs)
}

fn waiting(out: &Path) {
    noteln!("waiting for {}: another probelab command is using it", out.display());
}

/// The search path's folders, each marked `(missing)` when it is not there.
pub fn describe_search(s: &SearchPath) -> String {
    s.describe()
}

/// The exit code of `run`/`reproduce` with the baselines of `refused` not written: 1, with the
/// advice on stderr, when any was refused.
pub fn refused_exit(refused: &[String]) -> i32 {
    match probelab::regression::check::refusal_advice(refused) {
        Some(advice) => {
            note(&advice);
            1
        }
        None => 0,
    }
}
