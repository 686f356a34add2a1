//! `probelab merge`: merges the statistics files of probe-set shards (`probes --out`) and
//! prints the summary CSV; with `--out`, writes the merged statistics atomically.

use super::output;
use anyhow::Result;
use probelab::ops::merge::{merge, MergeOptions};
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab merge`: combine shard statistics.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Statistics files written by `probelab probes --out`.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Write the merged statistics (TOML) here.
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let merged = merge(env, &MergeOptions { files: a.files, out: a.out })?;
    output::write(&merged.summary_csv()?)?;
    Ok(0)
}
