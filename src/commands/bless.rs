//! `probelab bless`: re-runs experiments (and the claims measurements) and rewrites the
//! baselines that differ, printing the same report as `check`. Takes the results folder's
//! exclusive lock. Every write, then every line: a failing stdout never stops a bless between
//! two baselines.

use super::output;
use anyhow::Result;
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab bless`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Experiment names or files (default: every experiment).
    experiments: Vec<String>,
    /// Rewrite even when nothing moved (refreshes provenance and ignored columns).
    #[arg(long)]
    force: bool,
    /// Baselines folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    env.checkout()?;
    let out = env.results(a.out);
    let _lock = env.writing(&out)?;
    let claims = a.experiments.is_empty() || a.experiments.iter().any(|e| e == "claims");
    let names: Vec<String> = a.experiments.iter().filter(|e| *e != "claims").cloned().collect();
    let mut code = 0;
    let mut lines = String::new();
    if a.experiments.is_empty() || !names.is_empty() {
        env.refuse_long_experiments(&probelab::regression::check::select(&env.root, &names, false)?.0)?;
        // Each comparison is printed before anything is written (the library writes only after
        // every experiment was compared).
        let mut show = |c: &probelab::regression::check::ExperimentCheck| -> Result<()> {
            Ok(output::write(c.report().as_bytes())?)
        };
        let (c, text) = probelab::regression::check::bless(&env.root, &env.search, &out, (&names, a.force), &mut show)?;
        code = c;
        lines += &text;
    }
    if claims {
        let run = probelab::regression::claims::run(&env.root, &env.search, &out, true, true)?;
        let (_, text) = probelab::regression::claims::report(&run, false);
        super::claims::write_strips(&out, &run)?;
        lines += &text;
        lines += &format!("claims: wrote {} file(s)\n", run.written.len());
    }
    output::write(lines.as_bytes())?;
    Ok(code)
}
