//! One L-BFGS run of the axis problem (FORMULAS §5): argmin's L-BFGS solver stepped through
//! its `Solver` trait (`init`, `next_iter`, `terminate_internal`) in the loop argmin's
//! `Executor::run` performs, without the executor's per-run set-up (its interrupt flag, observer
//! and checkpoint checks, and the moves of the whole executor and its state), and with the
//! stop on the objective's relative change ([`SolverSettings::tol_cost_rel`]). The L-BFGS update
//! and the line searches are argmin's, unchanged; without the relative stop a run is bit for bit
//! the executor's (`driver_matches_the_executor`). The relative stop applies to one-axis reduced
//! problems only (`zh3_solved_shared`'s).

use super::problem::*;
use super::solver::{LineSearch, SolveStats, SolverSettings};
use argmin::core::{Error, IterState, Problem, Solver, State, TerminationReason, TerminationStatus};
use argmin::solver::linesearch::condition::ArmijoCondition;
use argmin::solver::linesearch::{BacktrackingLineSearch, MoreThuenteLineSearch};
use argmin::solver::quasinewton::LBFGS;
use nalgebra::SVector;

/// argmin's state of an L-BFGS run in `N` variables.
pub(super) type LbfgsState<const N: usize> = IterState<SVector<f64, N>, SVector<f64, N>, (), (), (), f64>;

/// The sufficient-decrease constant of the backtracking line search (Nocedal & Wright's usual
/// choice).
const ARMIJO_C: f64 = 1e-4;

/// Runs L-BFGS from `x0` with the line search of `settings`; returns the best point seen (the
/// start point when argmin returns an error).
pub(super) fn run_lbfgs<const N: usize>(
    t: &Target,
    form: Formulation,
    x0: SVector<f64, N>,
    settings: &SolverSettings,
    stats: &mut SolveStats,
) -> SVector<f64, N> {
    let problem = AxisProblem::<N>::new(t, form);
    let state = LbfgsState::<N>::new().param(x0).max_iters(settings.max_iters);
    let memory = settings.memory.max(1);
    // The relative stop only where the objective is one axis's reduced error: on a sum over
    // separately solved axes it stops on the sum and leaves a dim channel short, and in the L1
    // variables it moved errors by up to 1e-7 relative (docs/decisions.md).
    let rel = if form == Formulation::Axis && t.n_axes() == 1 { settings.tol_cost_rel } else { 0.0 };
    let run = match settings.line_search {
        LineSearch::MoreThuente => LBFGS::new(MoreThuenteLineSearch::new(), memory)
            .with_tolerance_grad(settings.tol_grad)
            .and_then(|s| s.with_tolerance_cost(settings.tol_cost))
            .and_then(|solver| drive(solver, problem, state, rel)),
        LineSearch::Backtracking => ArmijoCondition::new(ARMIJO_C)
            .and_then(|c| LBFGS::new(BacktrackingLineSearch::new(c), memory).with_tolerance_grad(settings.tol_grad))
            .and_then(|s| s.with_tolerance_cost(settings.tol_cost))
            .and_then(|solver| drive(solver, problem, state, rel)),
    };
    stats.runs += 1;
    match run {
        Ok((p, mut state)) => {
            stats.cost_evals += p.cost_calls.get();
            stats.grad_evals += p.grad_calls.get();
            stats.evals += p.evals.get();
            stats.iters += state.get_iter() as u32;
            state.take_best_param().unwrap_or(x0)
        }
        Err(_) => {
            stats.failures += 1;
            x0
        }
    }
}

/// argmin's executor loop for `solver` on `problem` from `state`: `init`, then, until the state
/// is terminated, the solver's own stops (`terminate_internal`: its tolerances, the iteration
/// cap), the stop on the relative change |Δf| < `tol_rel`·|f| (0: off), and one `next_iter`,
/// each followed by the best-point update and the iteration count, as `Executor::run` does.
pub(super) fn drive<'t, const N: usize, S>(
    mut solver: S,
    problem: AxisProblem<'t, N>,
    state: LbfgsState<N>,
    tol_rel: f64,
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
            } else if (state.get_prev_cost() - state.get_cost()).abs() < tol_rel * state.get_cost().abs() {
                state = state.terminate_with(TerminationReason::SolverConverged);
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
