//! What the commands share beyond `ops::Env`: the exit code of a run whose baselines were
//! refused.

use super::terminal::note;

/// The exit code of `run`/`reproduce` with the baselines of `refused` not written: 1, with the
/// advice on stderr, when any was refused.
pub fn refused_exit(refused: &[String]) -> i32 {
    match probelab::ops::run::text::refusal_advice(refused) {
        Some(advice) => {
            note(&advice);
            1
        }
        None => 0,
    }
}
