//! What every command shares: the repository root and the map search path ([`Env`]), the
//! results folder, the output folder's locks (exclusive for a writer, shared for `check`),
//! and the lines about the search path and refused baselines.

use super::terminal::{note, noteln};
use anyhow::Result;
use probelab::envmap::search::SearchPath;
use probelab::io::folder;
use std::path::{Path, PathBuf};

/// What every command is given: the repository root and the map search path.
pub struct Env {
    /// `--root`: the folder holding experiments/, results/ and envmaps/.
    pub root: PathBuf,
    /// `<root>/envmaps`, then `PROBELAB_ENVMAPS`.
    pub search: SearchPath,
}

impl Env {
    /// The results folder: `out`, or `<root>/results`.
    pub fn results(&self, out: Option<PathBuf>) -> PathBuf {
        out.unwrap_or_else(|| self.root.join("results"))
    }
}

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
