//! `probelab reproduce`: every experiment of `experiments/` on the maps found, then the claims
//! and `results/REPORT.md` (`ops::reproduce`); exit 1 when a baseline or a claims measurement
//! moved.

use super::context::refused_exit;
use super::output;
use anyhow::Result;
use probelab::ops::reproduce::ReproduceOptions;
use probelab::ops::{claims, report, reproduce, Env};
use std::path::PathBuf;

/// `probelab reproduce`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// What it found goes to stdout, in one piece at the end: the claims' findings, the report
/// written, each missing map once (the committed pages never say it) and the closing summary.
/// Stderr carries only what happens while it runs: progress, and the notes of its steps.
pub fn run(a: Args, env: &Env) -> Result<i32> {
    let outcome = reproduce::reproduce(env, &ReproduceOptions { out: a.out })?;
    let mut text = claims::text::report(&outcome.claims);
    text += &report::text::lines(&outcome.report);
    text += &outcome.missing.notes(&env.search);
    text += &reproduce::text::summary(&outcome);
    output::write(text.as_bytes())?;
    Ok(refused_exit(&outcome.refused()))
}
