//! `probelab sweep`: varies one accuracy knob and records error against time
//! (`experiments/sweeps/*.toml`, `pipeline::sweep`), writing `results/sweeps/<name>.csv`
//! atomically under the results folder's exclusive lock.

use super::terminal::noteln;
use anyhow::{bail, Result};
use probelab::io::distinct::{refuse_overwrite, Named};
use probelab::ops::Env;
use probelab::pipeline::sweep::{self, Sweep};
use std::path::PathBuf;

/// `probelab sweep`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Sweep files (default: every experiments/sweeps/*.toml, skipping those with missing maps).
    files: Vec<PathBuf>,
    /// Output folder (default: <root>/results); CSVs go to <out>/sweeps/<name>.csv.
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let results = env.results(a.out);
    let _lock = env.writing(&results)?;
    let out = results.join("sweeps");
    let all = a.files.is_empty();
    let files = if all {
        probelab::pipeline::experiment::list_experiments(&env.root.join("experiments").join("sweeps"))?
    } else {
        a.files
    };
    // Every sweep file read before any runs, and no table may overwrite one (`io::distinct`).
    let sweeps = files.iter().map(|p| Sweep::load(p)).collect::<Result<Vec<_>>>()?;
    let targets: Vec<PathBuf> = sweeps.iter().map(|s| out.join(format!("{}.csv", s.name))).collect();
    let outputs: Vec<Named> = targets.iter().map(|p| Named { role: "a sweep table", path: p }).collect();
    let inputs: Vec<Named> = files.iter().map(|p| Named { role: "a sweep file", path: p }).collect();
    refuse_overwrite(&outputs, &inputs)?;
    for (path, sweep) in files.iter().zip(&sweeps) {
        env.refuse_long(&path.display().to_string(), &probelab::pipeline::estimate::sweep(sweep, &env.search))?;
    }
    for ((path, sweep), file) in files.iter().zip(&sweeps).zip(&targets) {
        let (rows, missing) = sweep::run(sweep, &env.search)?;
        if !missing.is_empty() {
            if all {
                noteln!("skipped sweep {}: map(s) not found: {}", sweep.name, missing.join(", "));
                continue;
            }
            bail!("{}: map(s) not found: {}; nothing written", path.display(), missing.join(", "));
        }
        probelab::io::atomic::write(file, &sweep::to_csv(sweep, &rows)?)?;
        noteln!("wrote {} ({} rows)", file.display(), rows.len());
    }
    Ok(0)
}
