//! `probelab bless`, the workflow: under the results folder's exclusive lock, experiments (and
//! the claims measurements) re-run and the baselines that differ rewritten
//! (`regression::bless`), each comparison handed over before anything is written. Its text is
//! `bless/text.rs`: every write, then every line, so a failing stdout never stops a bless
//! between two baselines.

pub mod text;

use super::Env;
pub use crate::regression::bless::Rewrite;
use crate::regression::bless::{self, Blessed};
use crate::regression::check::{select, ExperimentCheck, Selection};
use crate::regression::claims::{self, ClaimsMode, ClaimsRun};
use anyhow::Result;
use std::path::PathBuf;

/// What `bless` is asked to do.
pub struct BlessOptions<'a> {
    /// Experiment names or files, and `claims` for the claims (empty: every experiment and the
    /// claims).
    pub experiments: Vec<String>,
    /// Which baselines are rewritten (`--force`: all of them).
    pub rewrite: Rewrite,
    /// The baselines folder (default: `<root>/results`).
    pub out: Option<PathBuf>,
    /// Handed each experiment's comparison (the report `check` prints), before anything is
    /// written; an error stops the bless before its first write.
    pub on_compared: &'a dyn Fn(&ExperimentCheck) -> Result<()>,
}

/// What `bless` did.
pub struct BlessOutcome {
    /// The experiments blessed, when any were asked for.
    pub experiments: Option<Blessed>,
    /// The claims blessed, when they were asked for.
    pub claims: Option<ClaimsRun>,
}

/// Blesses the experiments and the claims `opts` name.
pub fn bless(env: &Env, opts: &BlessOptions) -> Result<BlessOutcome> {
    env.checkout()?;
    let out = env.results(opts.out.clone());
    let _lock = env.writing(&out)?;
    let all = opts.experiments.is_empty();
    let names: Vec<String> = opts.experiments.iter().filter(|e| *e != "claims").cloned().collect();
    let mut outcome = BlessOutcome { experiments: None, claims: None };
    if all || !names.is_empty() {
        env.refuse_long_experiments(&select(&env.root, &names, Selection::All)?.0)?;
        let mut show = |c: &ExperimentCheck| (opts.on_compared)(c);
        let blessed = bless::bless(&env.root, &env.search, &out, (&names, opts.rewrite), &env.settings, &mut show)?;
        outcome.experiments = Some(blessed);
    }
    if all || opts.experiments.iter().any(|e| e == "claims") {
        let run = claims::run(&env.root, &env.search, &out, ClaimsMode::Bless)?;
        super::claims::write_strips(
            env,
            &out,
            &run,
            &crate::pipeline::reuse::ReferenceCache::new(env.settings.profile),
        )?;
        outcome.claims = Some(run);
    }
    Ok(outcome)
}
