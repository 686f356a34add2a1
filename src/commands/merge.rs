//! `probelab merge`: merges the statistics files of probe-set shards (`probes --out`) and
//! prints the summary CSV; with `--out`, writes the merged statistics atomically.

use super::output;
use super::terminal::{note, noteln};
use anyhow::Result;
use probelab::io::distinct::{refuse_overwrite, Named};
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

pub fn run(a: Args) -> Result<i32> {
    let inputs: Vec<Named> = a.files.iter().map(|p| Named { role: "a shard file", path: p }).collect();
    let outputs: Vec<Named> = a.out.iter().map(|p| Named { role: "--out", path: p }).collect();
    refuse_overwrite(&outputs, &inputs)?;
    let (merged, warning) = probelab::pipeline::probeset::job::merge(&a.files)?;
    if let Some(w) = warning {
        note(&format!("{w}\n"));
    }
    if let Some(out) = &a.out {
        probelab::io::atomic::write(out, merged.to_toml()?.as_bytes())?;
        noteln!("wrote {}", out.display());
    }
    output::write(&merged.summary_csv()?)?;
    Ok(0)
}
