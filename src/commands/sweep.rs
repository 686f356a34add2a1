//! `probelab sweep`: varies one accuracy knob and records error against time
//! (`experiments/sweeps/*.toml`, `pipeline::sweep`), writing `results/sweeps/<name>.csv`
//! atomically under the results folder's exclusive lock.

use anyhow::Result;
use probelab::ops::sweep::{sweep, SweepOptions};
use probelab::ops::Env;
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
    sweep(env, &SweepOptions { files: a.files, out: a.out })?;
    Ok(0)
}
