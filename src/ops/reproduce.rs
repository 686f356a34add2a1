//! `probelab reproduce`, the workflow: every experiment of `experiments/` on the maps found,
//! then the claims and `results/REPORT.md`. An experiment with every map is run and stored as
//! `run` stores it; one with some maps is checked against its baseline on those (never
//! rewritten); one with none is skipped. Under the results folder's exclusive lock. Its text
//! is `reproduce/text.rs`.

pub mod text;

use super::context::experiment_outputs_distinct;
use super::Env;
use crate::io::progress::Progress;
use crate::pipeline::experiment::{list_experiments, Experiment};
use crate::pipeline::reuse::ReferenceCache;
use crate::pipeline::runner::{self, RunReport};
use crate::regression::claims::{self, ClaimsMode, ClaimsRun};
use crate::regression::guard::{self, PartialCheck, Stored};
use crate::regression::missing::{self, MissingMaps};
use crate::report::Generated;
use anyhow::Result;
use std::path::PathBuf;

/// What `reproduce` is asked to do.
pub struct ReproduceOptions {
    /// The output folder (default: `<root>/results`).
    pub out: Option<PathBuf>,
}

/// What became of one experiment, by how many of its maps were found.
pub enum Reproduced {
    /// Every map: its table stored as `run` stores it.
    Stored(Box<Stored>),
    /// Some maps (the missing ones named): checked on those, never written.
    Partial(Vec<String>, PartialCheck),
    /// No map: skipped.
    Skipped,
}

/// One experiment's part of a reproduction.
pub struct ExperimentOutcome {
    /// The experiment's name.
    pub name: String,
    /// The maps it names.
    pub maps: Vec<String>,
    /// What became of it.
    pub outcome: Reproduced,
}

/// What `reproduce` did.
pub struct ReproduceOutcome {
    /// How many experiments there were.
    pub experiments: usize,
    /// Each experiment: those with every map first, then those with some, then those with none.
    pub results: Vec<ExperimentOutcome>,
    /// The claims, judged on the tables just written.
    pub claims: ClaimsRun,
    /// The report written.
    pub report: Generated,
    /// The maps this machine lacked, each once.
    pub missing: MissingMaps,
}

impl ReproduceOutcome {
    /// What failed: the experiments whose baselines moved, and `claims` when a measurement did.
    pub fn refused(&self) -> Vec<String> {
        let mut refused: Vec<String> = self
            .results
            .iter()
            .filter(|r| match &r.outcome {
                Reproduced::Stored(s) => !s.stands(),
                Reproduced::Partial(_, p) => !p.passed(),
                Reproduced::Skipped => false,
            })
            .map(|r| r.name.clone())
            .collect();
        if !self.claims.passed() {
            refused.push("claims".into());
        }
        refused
    }
}

/// The experiments' runs, by how many of their maps were found.
#[derive(Default)]
struct Runs<'a> {
    done: Vec<(&'a Experiment, RunReport)>,
    partial: Vec<(&'a Experiment, RunReport)>,
    skipped: Vec<(&'a Experiment, RunReport)>,
}

/// Runs every experiment before anything is written (a failing run writes nothing).
fn run_all<'a>(exps: &'a [Experiment], env: &Env, cache: &ReferenceCache) -> Result<Runs<'a>> {
    let mut runs = Runs::default();
    let progress = Progress::new(exps.len() as u64, "experiments");
    for exp in exps {
        progress.message(exp.name.clone());
        let report = runner::run(exp, &env.search, &env.settings, cache)?;
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

/// Reproduces every experiment, the claims and the report.
pub fn reproduce(env: &Env, opts: &ReproduceOptions) -> Result<ReproduceOutcome> {
    env.checkout()?;
    let out = env.results(opts.out.clone());
    let _lock = env.writing(&out)?;
    let dir = env.root.join("experiments");
    let exps = list_experiments(&dir)?.iter().map(|p| Experiment::load(p)).collect::<Result<Vec<_>>>()?;
    experiment_outputs_distinct(&out, &exps)?;
    env.refuse_long_experiments(&exps)?;
    // One cache for the runs, the claims' sheets and the report's: no reference computed twice.
    let cache = ReferenceCache::new(env.settings.profile);
    let runs = run_all(&exps, env, &cache)?;
    let mut results = Vec::new();
    let mut missing = MissingMaps::default();
    let entry = |exp: &Experiment, outcome: Reproduced| ExperimentOutcome {
        name: exp.name.clone(),
        maps: exp.maps.clone(),
        outcome,
    };
    for (exp, report) in &runs.done {
        results.push(entry(exp, Reproduced::Stored(Box::new(super::run::store(env, &out, exp, report)?))));
    }
    // Some maps found: those maps' rows are compared with the committed baseline, which is
    // never rewritten from a partial run.
    for (exp, report) in &runs.partial {
        let check = guard::check_partial(&out, &env.root, exp, report)?;
        env.note_lines(&super::run::text::partial_notes(&check, &out.join(&exp.name)));
        missing.add(exp.maps.len(), &report.missing, &report.missing_why, check.unchecked_rows());
        results.push(entry(exp, Reproduced::Partial(report.missing.clone(), check)));
    }
    for (exp, report) in &runs.skipped {
        let rows = missing::baseline_rows(&out.join(&exp.name), &report.missing)?;
        missing.add(exp.maps.len(), &report.missing, &report.missing_why, rows);
        results.push(entry(exp, Reproduced::Skipped));
    }
    env.notes.note("sweeps (experiments/sweeps/) are not re-run by reproduce: `probelab sweep` runs them");
    // The claims, judged on the tables just written (and the measurements, when their maps are
    // here), before the report that presents them.
    let claims = claims::run(&env.root, &env.search, &out, ClaimsMode::Write)?;
    super::claims::write_strips(env, &out, &claims, &cache)?;
    let report = super::report::generate(env, &out, 1, &cache)?;
    Ok(ReproduceOutcome { experiments: exps.len(), results, claims, report, missing })
}
