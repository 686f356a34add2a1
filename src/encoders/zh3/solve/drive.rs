//! The loop of one L-BFGS run of the axis problem (FORMULAS §5): argmin's L-BFGS solver stepped
//! through its `Solver` trait (`init`, `next_iter`, `terminate_internal`) in the loop argmin's
//! `Executor::run` performs, without the executor's per-run set-up (its interrupt flag, observer
//! and checkpoint checks, and the moves of the whole executor and its state), so a run is bit
//! for bit the executor's (`driver_matches_the_executor`). The L-BFGS update and the line
//! searches are argmin's, unchanged; `solver::run_lbfgs` builds the solver.

use super::problem::AxisProblem;
use argmin::core::{Error, IterState, Problem, Solver, State, TerminationStatus};
use nalgebra::SVector;

/// argmin's state of an L-BFGS run in `N` variables.
pub(super) type LbfgsState<const N: usize> = IterState<SVector<f64, N>, SVector<f64, N>, (), (), (), f64>;

/// argmin's executor loop for `solver` on `problem` from `state`: `init`, then, until the state
/// is terminated, the solver's own stops (`terminate_internal`: its tolerances, the iteration
/// cap) and one `next_iter`, each followed by the best-point update and the iteration count, as
/// `Executor::run` does.
pub(super) fn drive<'t, const N: usize, S>(
    mut solver: S,
    problem: AxisProblem<'t, N>,
    state: LbfgsState<N>,
) -> Result<(AxisProblem<'t, N>, LbfgsState<N>), Error>
where
    S: Solver<AxisProblem<'t, N>, LbfgsState<N>>,
{
    let mut problem = Problem::new(problem);
    let (mut state, _) = solver.init(&mut problem, state)?;
    state.update();
    loop {
        if !state.terminated() {
            if let TerminationStatus::Terminated(reason) = solver.terminate_internal(&state) {
                state = state.terminate_with(reason);
            }
        }
        if state.terminated() {
            break;
        }
        state = solver.next_iter(&mut problem, state)?.0;
        state.update();
        state.increment_iter();
    }
    let problem = problem.take_problem().ok_or_else(|| Error::msg("the solver kept the problem"))?;
    Ok((problem, state))
}
