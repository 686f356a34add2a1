//! `probelab report`: draws the comparison sheets and charts and writes `results/REPORT.md`,
//! the folders' pages and `PROVENANCE.md` from the result CSVs (`report::generate`). Takes the
//! results folder's exclusive lock.

use super::terminal::noteln;
use anyhow::Result;
use probelab::ops::Env;
use std::path::{Path, PathBuf};

/// `probelab report`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Results folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Draw the comparison sheets N times larger (1 to 8): discs evaluated at N times
    /// the pixels, text and thumbnail at N times their size. Charts are unchanged.
    #[arg(long, default_value_t = 1, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=probelab::report::sheet::MAX_SCALE as i64))]
    scale: u32,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    env.checkout()?;
    let out = env.results(a.out);
    let _lock = env.writing(&out)?;
    write_report(env, &out, a.scale)?;
    Ok(0)
}

/// Writes results/REPORT.md with its pictures (`report::generate`), the comparison sheets at
/// `sheet_scale` (1 for the standard sheets), and says what was drawn.
pub fn write_report(env: &Env, out: &Path, sheet_scale: u32) -> Result<()> {
    let options = probelab::report::Options { root: &env.root, out, search: &env.search, sheet_scale };
    let g = probelab::report::generate(&options)?;
    noteln!("wrote {} ({} picture(s) drawn)", g.report.display(), g.pictures);
    if !g.kept.is_empty() {
        noteln!(
            "sheets not redrawn, the committed ones kept ({} map(s) not on the search path): {}",
            g.missing.len(),
            g.kept.join(", ")
        );
    }
    for m in &g.mismatches {
        noteln!("warning: {m}");
    }
    Ok(())
}
