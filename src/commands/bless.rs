//! `probelab bless`: re-runs experiments (and the claims measurements) and rewrites the
//! baselines that differ, printing the same report as `check` (`ops::bless`). Every write,
//! then every line: a failing stdout never stops a bless between two baselines.

use super::output;
use anyhow::Result;
use probelab::ops::bless::Rewrite;
use probelab::ops::bless::{self, BlessOptions};
use probelab::ops::check::text::experiment;
use probelab::ops::check::ExperimentCheck;
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab bless`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Experiment names or files (default: every experiment).
    #[arg(value_parser = super::args::file_name())]
    experiments: Vec<String>,
    /// Rewrite even when nothing moved (refreshes provenance and ignored columns).
    #[arg(long)]
    force: bool,
    /// Baselines folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    // Each comparison is printed before anything is written.
    let show = |c: &ExperimentCheck| -> Result<()> { Ok(output::write(experiment(c).as_bytes())?) };
    let opts = BlessOptions {
        experiments: a.experiments,
        rewrite: if a.force { Rewrite::All } else { Rewrite::Moved },
        out: a.out,
        on_compared: &show,
    };
    let outcome = bless::bless(env, &opts)?;
    output::write(bless::text::lines(&outcome).as_bytes())?;
    Ok(0)
}
