//! `probelab check`, the workflow: under the results folder's shared lock (no `bless` rewrites
//! a baseline while it is read), the selected experiments re-run and compared with their
//! baselines (`regression::check`), and the claims checked when asked for (`all`, or the name
//! `claims`). Its text is `check/text.rs`, its JSON document `check/json.rs`
//! ([docs/json.md](../../docs/json.md)).

pub mod json;
pub mod text;

use super::Env;
use crate::regression::check::{check_experiments, select, CheckRequest, Checked};
pub use crate::regression::check::{ExperimentCheck, MapPolicy, Selection};
use crate::regression::claims::{self, ClaimsMode, ClaimsRun};
use anyhow::Result;
use std::path::PathBuf;

/// What is handed each experiment's check as soon as it is known.
pub type OnChecked<'a> = &'a dyn Fn(&ExperimentCheck) -> Result<()>;

/// What `check` is asked to do.
pub struct CheckOptions<'a> {
    /// Experiment names or files, and `claims` for the claims (empty: the default selection).
    pub experiments: Vec<String>,
    /// The default selection; [`Selection::All`] (`--all`) checks the claims too.
    pub selection: Selection,
    /// What a map missing from this machine does (`--require-all-maps`).
    pub maps: MapPolicy,
    /// The baselines folder (default: `<root>/results`).
    pub out: Option<PathBuf>,
    /// Handed each experiment's check as soon as it is known (the text report prints it then),
    /// followed by a note of the seconds it took; `None`: neither (the JSON document says it
    /// all at the end).
    pub on_checked: Option<OnChecked<'a>>,
}

/// What `check` found.
pub struct CheckOutcome {
    /// The experiments checked, when any were.
    pub experiments: Option<Checked>,
    /// The claims checked, when they were.
    pub claims: Option<ClaimsRun>,
}

impl CheckOutcome {
    /// True when no experiment failed and the claims (when checked) passed.
    pub fn passed(&self) -> bool {
        self.experiments.as_ref().is_none_or(Checked::passed) && self.claims.as_ref().is_none_or(ClaimsRun::passed)
    }
}

/// Checks the experiments and the claims `opts` select against what is committed. The maps
/// not found are noted once, after the last experiment ([`crate::regression::missing`]).
pub fn check(env: &Env, opts: &CheckOptions) -> Result<CheckOutcome> {
    let out = env.results(opts.out.clone());
    let _lock = env.reading(&out)?;
    let claims = opts.selection == Selection::All || opts.experiments.iter().any(|e| e == "claims");
    let names: Vec<String> = opts.experiments.iter().filter(|e| *e != "claims").cloned().collect();
    let mut outcome = CheckOutcome { experiments: None, claims: None };
    if opts.selection == Selection::All || !names.is_empty() || !claims {
        env.refuse_long_experiments(&select(&env.root, &names, opts.selection)?.0)?;
        let mut show = |c: &ExperimentCheck, seconds: f64| -> Result<()> {
            if let Some(on_checked) = opts.on_checked {
                on_checked(c)?;
                env.notes.note(&format!("  ({}: {seconds:.1} s)", c.experiment));
            }
            Ok(())
        };
        let request =
            CheckRequest { names: &names, selection: opts.selection, policy: opts.maps, settings: env.settings };
        let checked = check_experiments(&env.root, &env.search, &out, &request, &mut show)?;
        env.note_lines(&checked.missing.notes(&env.search));
        outcome.experiments = Some(checked);
    }
    if claims {
        outcome.claims = Some(claims::run(&env.root, &env.search, &out, ClaimsMode::Check)?);
    }
    Ok(outcome)
}
