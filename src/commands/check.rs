//! `probelab check`: re-runs experiments and compares every number with its baseline; exit 1
//! when anything moved (a map not on this machine leaves its rows unchecked, said once at the
//! end, unless `--require-all-maps`). Holds the results folder's shared lock, so no `bless` rewrites a
//! baseline while it is read. Text prints each experiment's report as it comes, then the
//! verdict; JSON prints one document at the end.

use super::output;
use super::terminal::{note, noteln, outln};
use anyhow::Result;
use probelab::ops::check as check_json;
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab check`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Experiment names or files (default: every experiment with `ci = true`).
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
    let out = env.results(a.out);
    let json = a.format == "json";
    let _lock = env.reading(&out)?;
    let claims = a.all || a.experiments.iter().any(|e| e == "claims");
    let names: Vec<String> = a.experiments.into_iter().filter(|e| e != "claims").collect();
    let mut code = 0;
    let mut checked = None;
    let mut claims_run = None;
    if a.all || !names.is_empty() || !claims {
        env.refuse_long_experiments(&probelab::regression::check::select(&env.root, &names, !a.all)?.0)?;
        let mut show = |c: &probelab::regression::check::ExperimentCheck, seconds: f64| -> Result<()> {
            if !json {
                output::write(c.report().as_bytes())?;
                noteln!("  ({}: {seconds:.1} s)", c.experiment);
            }
            Ok(())
        };
        let (c, summary) = probelab::regression::check::check_experiments(
            &env.root,
            &env.search,
            &out,
            &names,
            (a.all, !a.require_all_maps),
            &mut show,
        )?;
        code = c;
        note(&summary.notes);
        if !json {
            output::write(summary.text.as_bytes())?;
        }
        checked = Some(summary);
    }
    if claims {
        let run = probelab::regression::claims::run(&env.root, &env.search, &out, false, false)?;
        let (ok, text) = probelab::regression::claims::report(&run, true);
        if !json {
            output::write(text.as_bytes())?;
            outln!("claims: {}", if ok { "ok: no measurement moved, no verdict changed" } else { "FAILED" })?;
        }
        if !ok {
            code = code.max(1);
        }
        claims_run = Some(run);
    }
    if json {
        output::write(check_json::to_json(checked.as_ref(), claims_run.as_ref())?.as_bytes())?;
    }
    Ok(code)
}
