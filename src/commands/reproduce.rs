//! `probelab reproduce`: every experiment of `experiments/` on the maps found, then the claims
//! and `results/REPORT.md`. An experiment with every map is run and stored as `run` stores it;
//! one with some maps is checked against its baseline on those (never rewritten); one with none
//! is skipped and listed. Takes the results folder's exclusive lock; exit 1 when a baseline or
//! a claims measurement moved.

use super::context::refused_exit;
use super::output;
use super::terminal::{note, noteln, outln};
use anyhow::Result;
use probelab::io::progress::Progress;
use probelab::ops::context::experiment_outputs_distinct;
use probelab::ops::Env;
use probelab::pipeline::experiment::{list_experiments, Experiment};
use probelab::pipeline::runner::{self, RunReport};
use probelab::regression::missing::{self, MissingMaps};
use std::path::PathBuf;

/// `probelab reproduce`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// The experiments' runs, by how many of their maps were found.
#[derive(Default)]
struct Runs<'a> {
    done: Vec<(&'a Experiment, RunReport)>,
    partial: Vec<(&'a Experiment, RunReport)>,
    skipped: Vec<(&'a Experiment, RunReport)>,
}

/// Runs every experiment before anything is written (a failing run writes nothing).
fn run_all<'a>(exps: &'a [Experiment], env: &Env) -> Result<Runs<'a>> {
    let mut runs = Runs::default();
    let progress = Progress::new(exps.len() as u64, "experiments");
    for exp in exps {
        progress.message(exp.name.clone());
        let report = runner::run(exp, &env.search)?;
        if report.missing.is_empty() {
            runs.done.push((exp, report));
        } else if report.missing.len() == exp.maps.len() {
            runs.skipped.push((exp, report));
        } else {
            runs.partial.push((exp, report));
        }
        progress.inc();
    }
    progress.finish();
    Ok(runs)
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    env.checkout()?;
    let out = env.results(a.out);
    let _lock = env.writing(&out)?;
    let dir = env.root.join("experiments");
    let exps = list_experiments(&dir)?.iter().map(|p| Experiment::load(p)).collect::<Result<Vec<_>>>()?;
    experiment_outputs_distinct(&out, &exps)?;
    env.refuse_long_experiments(&exps)?;
    let runs = run_all(&exps, env)?;
    let mut refused = Vec::new();
    let mut summary = Vec::new();
    let mut missing = MissingMaps::default();
    for (exp, report) in &runs.done {
        match super::run::store(&env.root, &out, exp, report)? {
            Some(told) => summary.push(format!("{}: {n} of {n} maps; {told}", exp.name, n = exp.maps.len())),
            None => refused.push(exp.name.clone()),
        }
    }
    // Some maps found: those maps' rows are compared with the committed baseline, which is
    // never rewritten from a partial run.
    for (exp, report) in &runs.partial {
        let line = probelab::regression::check::check_partial(&out, &env.root, exp, report)?;
        note(&line.notes);
        missing.add(exp.maps.len(), &report.missing, &report.missing_why, line.unchecked_rows);
        if !line.passed {
            refused.push(exp.name.clone());
        }
        summary.push(line.text);
    }
    for (exp, report) in &runs.skipped {
        let n = exp.maps.len();
        let rows = missing::baseline_rows(&out.join(&exp.name), &report.missing)?;
        missing.add(n, &report.missing, &report.missing_why, rows);
        summary.push(format!("{}: skipped, 0 of {n} maps (missing: {})", exp.name, exp.maps.join(", ")));
    }
    noteln!("sweeps (experiments/sweeps/) are not re-run by reproduce: `probelab sweep` runs them");
    // The claims, judged on the tables just written (and the measurements, when their maps are
    // here), before the report that presents them.
    let claims = probelab::regression::claims::run(&env.root, &env.search, &out, false, true)?;
    let (claims_ok, text) = probelab::regression::claims::report(&claims, false);
    super::claims::write_strips(&out, &claims)?;
    output::write(text.as_bytes())?;
    if !claims_ok {
        refused.push("claims".into());
    }
    super::report::write_report(env, &out, 1)?;
    // What this machine lacked: each missing map once, then one line in the summary (the
    // committed pages never say it).
    note(&missing.notes(&env.search));
    outln!("reproduce: {} experiment(s)", exps.len())?;
    for line in &summary {
        outln!("  {line}")?;
    }
    if let Some(line) = missing.line("reproduced") {
        outln!("{line}; their baselines were left unchanged")?;
    }
    Ok(refused_exit(&refused))
}
