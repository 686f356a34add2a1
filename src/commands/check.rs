//! `probelab check`: re-runs experiments and compares every number with its baseline
//! (`ops::check`); exit 1 when anything moved (a map not on this machine leaves its rows
//! unchecked, said once at the end, unless `--require-all-maps`). Text prints each
//! experiment's report as it comes, then the verdict; JSON prints one document at the end.

use super::output;
use super::terminal::outln;
use anyhow::Result;
use probelab::ops::check::{self, text, CheckOptions};
use probelab::ops::check::{ExperimentCheck, MapPolicy, Selection};
use probelab::ops::{claims, Env};
use std::path::PathBuf;

/// `probelab check`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Experiment names or files (default: every experiment with `ci = true`).
    #[arg(value_parser = super::args::file_name())]
    experiments: Vec<String>,
    /// Also check the experiments marked `ci = false` (the full check).
    #[arg(long)]
    all: bool,
    /// Fail when a map is not on this machine (for CI that owns the maps). By default the
    /// rows of a missing map are not compared, and the maps missing are listed in one line.
    #[arg(long)]
    require_all_maps: bool,
    /// The old name of the default (missing maps allowed); accepted, not shown.
    #[arg(long, hide = true, conflicts_with = "require_all_maps")]
    allow_missing: bool,
    /// Baselines folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Output format: `text` (one line per finding and a verdict per experiment) or `json`
    /// (one object: the overall verdict, and per experiment its counts and findings).
    #[arg(long, default_value = "text", value_parser = ["text", "json"])]
    format: String,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let json = a.format == "json";
    let show = |c: &ExperimentCheck| -> Result<()> { Ok(output::write(text::experiment(c).as_bytes())?) };
    let opts = CheckOptions {
        experiments: a.experiments,
        selection: if a.all { Selection::All } else { Selection::Ci },
        maps: if a.require_all_maps { MapPolicy::RequireAll } else { MapPolicy::AllowMissing },
        out: a.out,
        on_checked: if json { None } else { Some(&show) },
    };
    let outcome = check::check(env, &opts)?;
    if json {
        output::write(check::json::document(&outcome)?.as_bytes())?;
    } else {
        if let Some(c) = &outcome.experiments {
            output::write(text::closing(c).as_bytes())?;
        }
        if let Some(run) = &outcome.claims {
            output::write(claims::text::report(run).as_bytes())?;
            outln!("{}", text::claims_verdict(run))?;
        }
    }
    Ok(if outcome.passed() { 0 } else { 1 })
}
