//! What every workflow is given ([`Env`]): the repository root, the map search path,
//! `--allow-long`, and where the lines for the user go while it works ([`Notes`]); and what
//! every writing workflow does first: refuse a folder that is not a checkout, take the output
//! folder's lock, refuse outputs that would overwrite inputs, refuse work estimated too long,
//! remove (and note) the temporary files killed runs left where it writes.

use crate::envmap::search::SearchPath;
use crate::io::distinct::{refuse_overwrite, Named};
use crate::io::folder;
use crate::pipeline::estimate::{self, Estimate};
use crate::pipeline::experiment::Experiment;
use crate::pipeline::settings::RunSettings;
use anyhow::Result;
use std::path::{Path, PathBuf};

/// Where a workflow's lines for the user go while it works (a lock it waits for, a long
/// estimate, stale files it removed): the binary prints them on stderr; a program that does not
/// want them passes [`Quiet`]. The library never prints.
pub trait Notes: Sync {
    /// One line (no newline at its end).
    fn note(&self, line: &str);
}

/// [`Notes`] that drops every line.
pub struct Quiet;

impl Notes for Quiet {
    fn note(&self, _line: &str) {}
}

/// What every workflow is given.
pub struct Env<'a> {
    /// `--root`: the folder holding experiments/, results/ and envmaps/.
    pub root: PathBuf,
    /// `<root>/envmaps`, then `PROBELAB_ENVMAPS`.
    pub search: SearchPath,
    /// `--allow-long`: run work estimated above the bound (`pipeline::estimate::BOUND_S`).
    pub allow_long: bool,
    /// Where the lines for the user go.
    pub notes: &'a dyn Notes,
    /// How runs are carried out: the timing pass on or off, the profile their phases are timed on.
    pub settings: RunSettings<'a>,
}

/// An estimate at least this long (seconds) is announced when the run goes ahead.
const ANNOUNCE_S: f64 = 600.0;

impl Env<'_> {
    /// Every line of `text` (lines ending in newlines) as a note.
    pub fn note_lines(&self, text: &str) {
        for line in text.lines() {
            self.notes.note(line);
        }
    }

    /// The results folder: `out`, or `<root>/results`.
    pub fn results(&self, out: Option<PathBuf>) -> PathBuf {
        out.unwrap_or_else(|| self.root.join("results"))
    }

    /// Refuses work estimated above the bound unless `--allow-long` was given, naming `what`
    /// (the experiment file); announces a long wait that goes ahead (`pipeline::estimate`).
    pub fn refuse_long(&self, what: &str, estimate: &Estimate) -> Result<()> {
        estimate.refuse_if_long(what, self.allow_long)?;
        if estimate.seconds >= ANNOUNCE_S {
            self.notes.note(&format!("{what}: estimated {estimate}; progress shows the time left on a terminal"));
        }
        Ok(())
    }

    /// [`Env::refuse_long`] for experiments run together, their estimates added up: a
    /// refusal names the file of the longest.
    pub fn refuse_long_experiments(&self, exps: &[Experiment]) -> Result<()> {
        let parts: Vec<Estimate> =
            exps.iter().map(|e| estimate::experiment(e, &self.search, self.settings.timing)).collect();
        let longest = parts.iter().enumerate().max_by(|a, b| a.1.seconds.total_cmp(&b.1.seconds)).map(|(i, _)| i);
        let what = match longest.map(|i| &exps[i]) {
            Some(e) => {
                e.source.as_ref().map(|p| p.display().to_string()).unwrap_or_else(|| format!("probelab {}", e.name))
            }
            None => return Ok(()),
        };
        self.refuse_long(&what, &Estimate::total(&parts))
    }

    /// Refuses, before anything is written, a workflow that needs the experiments where there
    /// are none: the root is not a probelab checkout.
    pub fn checkout(&self) -> Result<()> {
        let dir = self.root.join("experiments");
        if !dir.is_dir() {
            anyhow::bail!(
                "{}: no experiments folder here: {}",
                dir.display(),
                crate::pipeline::experiment::NOT_A_CHECKOUT
            );
        }
        Ok(())
    }

    /// Takes the exclusive lock on an output folder for a writing workflow (waiting, with a
    /// note, while another probelab command holds it), then removes the temporary files that
    /// killed runs left there, saying so (`io::folder`).
    pub fn writing(&self, out: &Path) -> Result<folder::DirLock> {
        let lock = folder::lock(out, true, || self.waiting(out))?;
        self.removed(&folder::remove_stale(out)?);
        Ok(lock)
    }

    /// Before writing a lone output file that no locked output folder holds (`probes --out`,
    /// `--save`, `merge --out`): removes the temporary files that killed runs left in its folder,
    /// saying so (`io::folder::remove_stale_in`). Best effort: a folder that cannot be listed is
    /// the write's own error to report.
    pub fn remove_stale_beside(&self, target: &Path) {
        let dir = target.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        self.removed(&folder::remove_stale_in(dir).unwrap_or_default());
    }

    /// Notes each stale temporary file removed.
    fn removed(&self, paths: &[PathBuf]) {
        for p in paths {
            self.notes.note(&format!("removed {} (left by a killed run whose process is gone)", p.display()));
        }
    }

    /// The shared lock of a workflow that only reads an output folder (none when it does not
    /// exist yet).
    pub fn reading(&self, out: &Path) -> Result<Option<folder::DirLock>> {
        if !out.is_dir() {
            return Ok(None);
        }
        Ok(Some(folder::lock(out, false, || self.waiting(out))?))
    }

    fn waiting(&self, out: &Path) {
        self.notes.note(&format!("waiting for {}: another probelab command is using it", out.display()));
    }
}

/// Refuses, before anything runs, experiments whose result files under `out`
/// (`<name>/table.csv`, its provenance and summary) would overwrite one of their experiment
/// files (`io::distinct`).
pub fn experiment_outputs_distinct(out: &Path, exps: &[Experiment]) -> Result<()> {
    use crate::regression::{baseline::TABLE, provenance::FILE_NAME};
    let targets: Vec<PathBuf> =
        exps.iter().flat_map(|e| [TABLE, FILE_NAME, "summary.csv"].map(|f| out.join(&e.name).join(f))).collect();
    let outputs: Vec<Named> = targets.iter().map(|p| Named { role: "a result file", path: p }).collect();
    let inputs: Vec<Named> =
        exps.iter().filter_map(|e| Some(Named { role: "an experiment file", path: e.source.as_deref()? })).collect();
    refuse_overwrite(&outputs, &inputs)
}
