//! Newton's method on one axis group's reduced objective (FORMULAS §5) in the gnomonic chart
//! about a screened axis line (`chart.rs`): argmin's `Newton` (full steps, the analytic Hessian)
//! stepped by `drive::drive_until` until a step is shorter than [`STEP_TOL`]. Newton converges
//! quadratically near a minimum, so the point after such a step is at the objective's rounding;
//! but from a poor start it may head for a saddle or a maximum, so its end is kept only where it
//! is a local minimum near the start (`solver::MultiStart::descend` otherwise runs L-BFGS).

use super::chart::ChartProblem;
use super::drive::drive_until;
use super::problem::{Group, Target};
use argmin::core::{IterState, State};
use argmin::solver::newton::Newton;
use glam::DVec3;
use nalgebra::{Matrix2, Vector2};

/// argmin's state of a Newton run in the chart's 2 variables.
type NewtonState = IterState<Vector2<f64>, Vector2<f64>, (), Matrix2<f64>, (), f64>;

/// The stop: a step (in the chart, radians near its origin) shorter than this. The error after
/// it is of order its square, far below the objective's rounding.
pub(super) const STEP_TOL: f64 = 1e-8;

/// The cap on Newton iterations from one start (it takes about five from a screened line).
const MAX_NEWTON_ITERS: u64 = 12;

/// The end of a Newton run, with its iteration count.
pub(super) struct NewtonEnd {
    /// The axis vector (not unit) of the local minimum reached; None where the run did not end
    /// at one: not finite, more than 45° from the start, the gradient's norm not below
    /// `tol_grad` (L-BFGS's own gradient stop) or the Hessian not positive definite.
    pub axis: Option<DVec3>,
    /// Newton iterations taken.
    pub iters: u32,
}

/// Newton's method for group `g` of `target` from the unit axis `a0`.
pub(super) fn newton_axis(target: &Target, g: Group, a0: DVec3, tol_grad: f64) -> NewtonEnd {
    let problem = ChartProblem::new(target, g, a0);
    let state = NewtonState::new().param(Vector2::zeros()).max_iters(MAX_NEWTON_ITERS);
    // argmin's Newton takes the parameter out of the state before setting the next one, so the
    // state keeps no previous parameter: the stop keeps its own.
    let last = std::cell::Cell::new(Vector2::zeros());
    let short_step = |s: &NewtonState| s.get_param().is_some_and(|p| (p - last.replace(*p)).norm() < STEP_TOL);
    let Ok((problem, state)) = drive_until(Newton::new(), problem, state, short_step) else {
        return NewtonEnd { axis: None, iters: 0 };
    };
    let iters = state.get_iter() as u32;
    let axis =
        state.get_param().copied().filter(|p| p.iter().all(|x| x.is_finite()) && p.norm() <= 1.0).and_then(|p| {
            let (grad, h) = problem.derivatives(&p);
            let minimum = grad.norm() < tol_grad && h[(0, 0)] > 0.0 && h.determinant() > 0.0;
            minimum.then(|| problem.axis(&p))
        });
    NewtonEnd { axis, iters }
}
