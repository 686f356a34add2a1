//! `probelab sweep`: varies one accuracy knob and records error against time
//! (`experiments/sweeps/*.toml`, `pipeline::sweep`), writing `<results>/sweeps/<name>.csv`
//! atomically under the results folder's exclusive lock. Every sweep file is read, and no
//! table may overwrite one (`io::distinct`), before any runs.

use super::context::Env;
use crate::io::distinct::{refuse_overwrite, Named};
use crate::pipeline::sweep::{self, Sweep};
use anyhow::{bail, Result};
use std::path::PathBuf;

/// The options of `probelab sweep`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SweepOptions {
    /// Sweep files; none: every `experiments/sweeps/*.toml`, skipping those with missing maps.
    pub files: Vec<PathBuf>,
    /// The results folder (`--out`; `None`: `<root>/results`).
    pub out: Option<PathBuf>,
}

/// A sweep that ran and the table it wrote.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SweepTable {
    /// The sweep's name.
    pub name: String,
    /// The table written.
    pub file: PathBuf,
    /// Its number of rows.
    pub rows: usize,
}

/// A sweep skipped because maps it names are not on the search path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SweepSkipped {
    /// The sweep's name.
    pub name: String,
    /// The maps not found.
    pub missing: Vec<String>,
}

/// What `probelab sweep` did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Swept {
    /// The tables written, in file order.
    pub written: Vec<SweepTable>,
    /// The sweeps skipped (only when every sweep file ran).
    pub skipped: Vec<SweepSkipped>,
}

/// `probelab sweep`: the lock taken, the sweep files read and checked, work estimated above
/// the bound refused, then each sweep run and its table written (each said through
/// `env.notes`). A sweep named on the command line whose maps are missing is an error; of
/// every sweep file, it is skipped.
pub fn sweep(env: &Env, o: &SweepOptions) -> Result<Swept> {
    let results = env.results(o.out.clone());
    let _lock = env.writing(&results)?;
    let out = results.join("sweeps");
    let all = o.files.is_empty();
    let files = if all {
        crate::pipeline::experiment::list_experiments(&env.root.join("experiments").join("sweeps"))?
    } else {
        o.files.clone()
    };
    let sweeps = files.iter().map(|p| Sweep::load(p)).collect::<Result<Vec<_>>>()?;
    let targets: Vec<PathBuf> = sweeps.iter().map(|s| out.join(format!("{}.csv", s.name))).collect();
    let outputs: Vec<Named> = targets.iter().map(|p| Named { role: "a sweep table", path: p }).collect();
    let inputs: Vec<Named> = files.iter().map(|p| Named { role: "a sweep file", path: p }).collect();
    refuse_overwrite(&outputs, &inputs)?;
    for (path, sweep) in files.iter().zip(&sweeps) {
        env.refuse_long(&path.display().to_string(), &crate::pipeline::estimate::sweep(sweep, &env.search))?;
    }
    let mut swept = Swept::default();
    for ((path, sweep), file) in files.iter().zip(&sweeps).zip(targets) {
        let (rows, missing) = sweep::run(sweep, &env.search, env.settings.profile)?;
        if !missing.is_empty() {
            if all {
                env.notes.note(&format!("skipped sweep {}: map(s) not found: {}", sweep.name, missing.join(", ")));
                swept.skipped.push(SweepSkipped { name: sweep.name.clone(), missing });
                continue;
            }
            bail!("{}: map(s) not found: {}; nothing written", path.display(), missing.join(", "));
        }
        crate::io::atomic::write(&file, &sweep::to_csv(sweep, &rows)?)?;
        env.notes.note(&format!("wrote {} ({} rows)", file.display(), rows.len()));
        swept.written.push(SweepTable { name: sweep.name.clone(), file, rows: rows.len() });
    }
    Ok(swept)
}
