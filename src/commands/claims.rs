//! `probelab claims`: runs the claims measurements (when their maps are here) and judges every
//! declared claim, writing `results/CLAIMS.csv`, the per-paper pages, the measurement tables
//! and the blending strips. Takes the results folder's exclusive lock; exit 1 when a
//! measurement moved.

use super::output;
use super::terminal::noteln;
use anyhow::Result;
use probelab::ops::Env;
use probelab::regression::claims::ClaimsRun;
use std::path::{Path, PathBuf};

/// `probelab claims`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    env.checkout()?;
    let out = env.results(a.out);
    let _lock = env.writing(&out)?;
    let run = probelab::regression::claims::run(&env.root, &env.search, &out, false, true)?;
    let (ok, text) = probelab::regression::claims::report(&run, false);
    let strips = write_strips(&out, &run)?;
    output::write(text.as_bytes())?;
    noteln!("wrote {} file(s) and {strips} blending strip(s) under {}", run.written.len(), out.display());
    Ok(if ok { 0 } else { 1 })
}

/// Draws the lightmap study's blending strips (report layer) and writes them under
/// `results/claims/`, each atomically; returns how many.
pub fn write_strips(out: &Path, run: &ClaimsRun) -> Result<usize> {
    let strips = probelab::report::strip::pngs(&run.strips)?;
    for (name, bytes) in &strips {
        probelab::io::atomic::write(&out.join("claims").join(name), bytes)?;
    }
    Ok(strips.len())
}
