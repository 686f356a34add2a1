//! The direction search: golden section over the tilt θ of d from N (and the best of the
//! bracket's end point, θ = 0 and the linear θ), or the linear direction alone.

#[cfg(test)]
use super::super::lune::Angle;
#[cfg(test)]
use crate::math::colour::Rgb;

use super::least_squares::*;
use super::spec::*;
#[cfg(test)]
use super::target::*;

/// The solved direction and colours in the frame.
#[derive(Clone, Copy, Debug)]
pub struct Solved {
    /// The tilt of d from N (radians).
    pub theta: f64,
    /// The colours and objective at that tilt.
    pub colour: Colour,
    /// Golden-section steps taken.
    pub iterations: usize,
    /// Objective evaluations.
    pub evaluations: usize,
}

/// 1/φ = (√5 − 1)/2.
pub(super) const INV_PHI: f64 = 0.618_033_988_749_894_9;

/// Chooses θ (linear or golden section, module docs) and solves the colours, for any target
/// (each θ by [`colours_at`]).
#[cfg(test)]
pub fn solve(spec: &FitSpec, domain: &FitDomain, target: &dyn FitTarget, i_z: Rgb, theta_lin: f64) -> Solved {
    let at = |th: f64| colours_at(spec, domain, target, i_z, Angle::new(th));
    solve_by(spec, theta_lin, |th| at(th).objective, at)
}

/// [`solve`] with the objective at θ given by `objective` (the search compares only these)
/// and the colours by `colours`, called once at the chosen θ (not counted as an evaluation:
/// it repeats the winner's).
pub(super) fn solve_by(
    spec: &FitSpec,
    theta_lin: f64,
    objective: impl Fn(f64) -> f64,
    colours: impl Fn(f64) -> Colour,
) -> Solved {
    let theta_lin = theta_lin.clamp(0.0, spec.max_tilt);
    let mut evals = 0usize;
    let mut eval = |th: f64| {
        evals += 1;
        objective(th)
    };
    match spec.direction {
        Direction::Linear => Solved { theta: theta_lin, colour: colours(theta_lin), iterations: 0, evaluations: 1 },
        Direction::Search { iterations, tolerance } | Direction::Search2d { iterations, tolerance, .. } => {
            let (x, f, iters) = golden_section(0.0, spec.max_tilt, iterations, tolerance, &mut eval);
            let mut best = (x, f);
            for th in [0.0, theta_lin] {
                let f = eval(th);
                if f < best.1 {
                    best = (th, f);
                }
            }
            Solved { theta: best.0, colour: colours(best.0), iterations: iters, evaluations: evals }
        }
    }
}

/// The most golden-section steps any search takes, whatever its settings: the bracket shrinks
/// by 0.618 a step, so 200 steps take [0, π] far below one ulp.
pub const MAX_GOLDEN_STEPS: usize = 200;

/// Golden-section search for the minimum of `f` on [a, b]: at most `iterations` steps (and
/// never more than [`MAX_GOLDEN_STEPS`]), stopping when the bracket is narrower than
/// `tolerance` or stops shrinking (it cannot narrow below one ulp, so a tolerance under that
/// must not keep it going). Returns the better of the last two points, its value, and the
/// number of steps (each costs one evaluation, after the first two).
pub(super) fn golden_section(
    mut a: f64,
    mut b: f64,
    iterations: usize,
    tolerance: f64,
    mut f: impl FnMut(f64) -> f64,
) -> (f64, f64, usize) {
    let mut x1 = b - INV_PHI * (b - a);
    let mut x2 = a + INV_PHI * (b - a);
    let (mut f1, mut f2) = (f(x1), f(x2));
    let mut iters = 0;
    while iters < iterations.min(MAX_GOLDEN_STEPS) && b - a > tolerance {
        let width = b - a;
        iters += 1;
        if f1 <= f2 {
            b = x2;
            (x2, f2) = (x1, f1);
            x1 = b - INV_PHI * (b - a);
            f1 = f(x1);
        } else {
            a = x1;
            (x1, f1) = (x2, f2);
            x2 = a + INV_PHI * (b - a);
            f2 = f(x2);
        }
        if b - a >= width {
            break;
        }
    }
    if f1 <= f2 {
        (x1, f1, iters)
    } else {
        (x2, f2, iters)
    }
}
