//! `probelab reproduce`: every experiment of `experiments/` on the maps found, then the claims
//! and `results/REPORT.md` (`ops::reproduce`); exit 1 when a baseline or a claims measurement
//! moved.

use super::context::refused_exit;
use super::output;
use super::terminal::note;
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

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let outcome = reproduce::reproduce(env, &ReproduceOptions { out: a.out })?;
    output::write(claims::text::report(&outcome.claims).as_bytes())?;
    note(&report::text::lines(&outcome.report));
    // What this machine lacked: each missing map once, then one line in the summary (the
    // committed pages never say it).
    note(&outcome.missing.notes(&env.search));
    output::write(reproduce::text::summary(&outcome).as_bytes())?;
    Ok(refused_exit(&outcome.refused()))
}
