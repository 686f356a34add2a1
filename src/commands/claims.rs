//! `probelab claims`: runs the claims measurements (when their maps are here) and judges every
//! declared claim, writing `results/CLAIMS.csv`, the per-paper pages, the measurement tables
//! and the blending strips (`ops::claims`); exit 1 when a measurement moved.

use super::output;
use super::terminal::note;
use anyhow::Result;
use probelab::ops::claims::{self, ClaimsOptions};
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab claims`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let outcome = claims::claims(env, &ClaimsOptions { out: a.out })?;
    output::write(claims::text::report(&outcome.run).as_bytes())?;
    note(&claims::text::written(&outcome));
    Ok(if outcome.passed() { 0 } else { 1 })
}
