//! `probelab check`: re-runs experiments and compares every number with its baseline; exit 1
//! when anything moved. Holds the results folder's shared lock, so no `bless` rewrites a
//! baseline while it is read. Text prints each experiment's report as it comes, then the
//! verdict; JSON prints one document at the end.

use super::context::{reading, Env};
use super::terminal::{noteln, outln};
use anyhow::Result;
use probelab::front::check::{self as check_json, ClaimsCheck};
use probelab::io::output;
use std::path::PathBuf;

/// `probelab check`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Experiment names or files (default: every experiment with `ci = true`).
    experiments: Vec<String>,
    /// Also check the experiments marked `ci = false` (the full check).
    #[arg(long)]
    all: bool,
    /// Do not fail when a map is not on this machine (its rows are reported, not compared).
    #[arg(long)]
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
    let _lock = reading(&out)?;
    let claims = a.all || a.experiments.iter().any(|e| e == "claims");
    let names: Vec<String> = a.experiments.into_iter().filter(|e| e != "claims").collect();
    let mut code = 0;
    let mut checked = None;
    let mut claims_json = None;
    if a.all || !names.is_empty() || !claims {
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
            (a.all, a.allow_missing),
            &mut show,
        )?;
        code = c;
        if !json {
            output::write(summary.text.as_bytes())?;
        }
        checked = Some(summary);
    }
    if claims {
        let run = probelab::regression::claims::run(&env.root, &env.search, &out, false, false)?;
        let (ok, text) = probelab::regression::claims::report(&run, true);
        if json {
            claims_json = Some((ok, text));
        } else {
            output::write(text.as_bytes())?;
            outln!("claims: {}", if ok { "ok: no measurement moved, no verdict changed" } else { "FAILED" })?;
        }
        if !ok {
            code = code.max(1);
        }
    }
    if json {
        let claims = claims_json.as_ref().map(|(passed, text)| ClaimsCheck { passed: *passed, text });
        output::write(check_json::to_json(checked.as_ref(), claims)?.as_bytes())?;
    }
    Ok(code)
}
