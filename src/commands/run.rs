//! `probelab run`: runs experiment files (or experiments by name) and writes each `results/<name>/table.csv` where none
//! exists; a table that exists is a baseline, left unchanged when nothing moved and refused
//! (exit 1) when something did (`ops::run`).

use super::context::refused_exit;
use anyhow::Result;
use probelab::ops::run::RunOptions;
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab run`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Experiment TOML files, or names of experiments in <root>/experiments/ (`sh_baseline`).
    #[arg(value_parser = super::args::file_name(), required = true)]
    experiments: Vec<String>,
    /// Output folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let outcome = probelab::ops::run::run(env, &RunOptions { experiments: a.experiments, out: a.out })?;
    Ok(refused_exit(&outcome.refused()))
}
