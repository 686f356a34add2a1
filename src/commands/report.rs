//! `probelab report`: draws the comparison sheets and charts and writes `results/REPORT.md`,
//! the folders' pages and `PROVENANCE.md` from the result CSVs (`ops::report`).

use super::terminal::note;
use anyhow::Result;
use probelab::ops::report::{self, ReportOptions};
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab report`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Results folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Draw the comparison sheets N times larger (1 to 8): discs evaluated at N times
    /// the pixels, text and thumbnail at N times their size. Charts are unchanged.
    #[arg(long, default_value_t = 1, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=probelab::ops::report::MAX_SCALE as i64))]
    scale: u32,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let generated = report::report(env, &ReportOptions { out: a.out, sheet_scale: a.scale })?;
    note(&report::text::lines(&generated));
    Ok(0)
}
