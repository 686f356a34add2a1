//! The solver driving the axis problem (FORMULAS §5): argmin's L-BFGS with the More–Thuente
//! line search, run from the given L1 and the tetrahedron axes, or from the best of a screened
//! set of axis lines; the best end point per axis group wins.

use super::drive::{drive, LbfgsState};
use super::problem::*;
use super::zonal::*;
use argmin::core::State;
use argmin::solver::linesearch::condition::ArmijoCondition;
use argmin::solver::linesearch::{BacktrackingLineSearch, MoreThuenteLineSearch};
use argmin::solver::quasinewton::LBFGS;
use glam::DVec3;
use nalgebra::SVector;

/// Settings of the solve (TOML keys of the solved encoders).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverSettings {
    /// L-BFGS iteration cap per start.
    pub max_iters: u64,
    /// Stop when |∇| falls below this (the objective is normalised by the largest L0²).
    pub tol_grad: f64,
    /// Stop when the objective changes by less than this between iterations (normalised).
    pub tol_cost: f64,
    /// L-BFGS memory (number of correction pairs).
    pub memory: usize,
    /// Starts: 1 = the given L1 only; 5 = the given L1 and the four tetrahedron projections.
    pub starts: usize,
    /// The variables of stored solves (hallucinated solves always use [`Formulation::L1`]).
    pub formulation: Formulation,
    /// 0: L-BFGS from every start (FORMULAS §5). N > 0 (with [`Formulation::Axis`]; the
    /// default, 64): evaluate the reduced objective at the starts and at N more axis lines (a
    /// Fibonacci set), run L-BFGS from the best of them, then from the best one at least 45°
    /// from where that run ended (per axis). Tested to reach the same objective as the full
    /// multi-start (`screened_solve_matches_the_full_multistart`).
    pub screen: usize,
    /// The line search of each L-BFGS iteration.
    pub line_search: LineSearch,
    /// Screened solves: skip the second run where it provably cannot beat the first (see
    /// `MultiStart::second_run_futile`).
    pub skip_futile: bool,
}

/// The line search inside each L-BFGS iteration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineSearch {
    /// More–Thuente (strong Wolfe conditions).
    MoreThuente,
    /// Backtracking from the full step, halving until the Armijo condition holds (c = 1e-4).
    Backtracking,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            max_iters: 100,
            tol_grad: 1e-8,
            tol_cost: 1e-14,
            memory: 5,
            starts: 5,
            formulation: Formulation::Axis,
            screen: 64,
            line_search: LineSearch::MoreThuente,
            skip_futile: true,
        }
    }
}

/// Counts and figures of one solve (all starts).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveStats {
    /// L-BFGS runs, over all starts.
    pub runs: u32,
    /// Their iterations, summed.
    pub iters: u32,
    /// Calls argmin made to the cost.
    pub cost_evals: u32,
    /// Calls argmin made to the gradient.
    pub grad_evals: u32,
    /// Distinct points where cost and gradient were computed (cache misses), plus the
    /// screening evaluations.
    pub evals: u32,
    /// Runs that returned an argmin error (their start point was kept as a candidate).
    pub failures: u32,
    /// The objective at the solution ((E/π)² summed over the SH coefficients, weighted).
    pub objective: f64,
    /// The objective at the given L1 (the L1 axis), for comparison.
    pub objective_l1_axis: f64,
    /// Which start won (the largest index over the axes): 0 = the given L1, 1..4 =
    /// tetrahedron axes, 5.. = screening directions.
    pub best_start: u32,
}

/// The result of a solve: the L1 vectors (irradiance, xyz per channel) and the statistics.
#[derive(Clone, Copy, Debug)]
pub struct Solution {
    /// Each channel's solved L1 vector (irradiance, xyz); the zonal axis is their direction,
    /// weighted by `Target::axis_w` when the axis is shared.
    pub l1: [DVec3; 3],
    /// How the solve went.
    pub stats: SolveStats,
}

/// Minimises the objective of `target` from the multi-start of FORMULAS §5 (or its screened
/// variant, see [`SolverSettings::screen`]). A target with a coefficient that is not finite
/// keeps its given L1 with no descent (none could converge on it), so the fit is as non-finite
/// as its input and the solve ends.
pub fn solve(target: &Target, settings: &SolverSettings) -> Solution {
    if !target.is_finite() {
        let stats = SolveStats { objective: f64::NAN, objective_l1_axis: f64::NAN, ..SolveStats::default() };
        return Solution { l1: target.t1, stats };
    }
    let form = if settings.formulation == Formulation::Axis && target.zonal == Zonal::Stored {
        Formulation::Axis
    } else {
        Formulation::L1
    };
    let n = if form == Formulation::Axis { 3 * target.n_axes() } else { 3 * target.channels };
    if form == Formulation::L1 && target.channels == 3 && target.per_channel {
        // Separable, but in the L1 variables a channel whose best axis is near-perpendicular to
        // its L1 converges slowly, and one L-BFGS run on the sum stops on the sum's tolerance:
        // solve the channels one by one, as the authors do.
        let mut out = Solution { l1: [DVec3::ZERO; 3], stats: SolveStats::default() };
        let irr = target.to_sh();
        for c in 0..3 {
            let s = solve_n::<3>(&Target::channel(&irr, c, target.zonal), settings, form);
            out.l1[c] = s.l1[0];
            let (a, b) = (&mut out.stats, s.stats);
            a.runs += b.runs;
            a.iters += b.iters;
            a.cost_evals += b.cost_evals;
            a.grad_evals += b.grad_evals;
            a.evals += b.evals;
            a.failures += b.failures;
            a.objective += b.objective;
            a.objective_l1_axis += b.objective_l1_axis;
            a.best_start = a.best_start.max(b.best_start);
        }
        return out;
    }
    match n {
        3 => solve_n::<3>(target, settings, form),
        9 => solve_n::<9>(target, settings, form),
        _ => unreachable!("3 or 9 variables"),
    }
}

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
    let run = match settings.line_search {
        LineSearch::MoreThuente => LBFGS::new(MoreThuenteLineSearch::new(), memory)
            .with_tolerance_grad(settings.tol_grad)
            .and_then(|s| s.with_tolerance_cost(settings.tol_cost))
            .and_then(|solver| drive(solver, problem, state)),
        LineSearch::Backtracking => ArmijoCondition::new(ARMIJO_C)
            .and_then(|c| LBFGS::new(BacktrackingLineSearch::new(c), memory).with_tolerance_grad(settings.tol_grad))
            .and_then(|s| s.with_tolerance_cost(settings.tol_cost))
            .and_then(|solver| drive(solver, problem, state)),
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

/// Per axis group: the best objective, its L1 and the start it came from.
type Best = Vec<(f64, [DVec3; 3], u32)>;

/// Per axis group: the best screened value, its direction (None: the given L1's axis) and the
/// index of the start direction.
type Pick = Vec<(f64, Option<DVec3>, u32)>;

/// Minimises `target` in `N` variables: normalised by its largest L0, from the multi-start
/// directions or the screened start, keeping the best end point per axis group.
pub(super) fn solve_n<const N: usize>(target: &Target, settings: &SolverSettings, form: Formulation) -> Solution {
    let nc = target.channels;
    // Normalise so the tolerances are relative to the probe's brightness.
    let scale = target.l0[..nc].iter().fold(0.0f64, |m, &x| m.max(x.abs()));
    let scale = if scale > 0.0 && scale.is_finite() { scale } else { 1.0 };
    let t = target.scaled(scale);
    let given = t.t1;
    let run = MultiStart::<N> { t: &t, form, settings, groups: t.groups(), given, given_axes: t.axis_vectors(&given) };
    let mut stats = SolveStats::default();
    // The given L1 is a candidate in its own right.
    let mut best: Best = run.groups.iter().map(|g| (t.group_objective(g, &given), given, 0)).collect();
    stats.objective_l1_axis = best.iter().map(|b| b.0).sum();

    // Start directions: None = the given L1's axis; then the tetrahedron axes.
    let tetra = tetrahedron_axes();
    let dirs: Vec<Option<DVec3>> =
        std::iter::once(None).chain(tetra.iter().copied().map(Some)).take(settings.starts.clamp(1, 5)).collect();
    if settings.screen > 0 && form == Formulation::Axis {
        run.screened(dirs, &mut stats, &mut best);
    } else {
        run.run_every_start(&dirs, &mut stats, &mut best);
    }

    let mut l1 = [DVec3::ZERO; 3];
    for (i, g) in run.groups.iter().enumerate() {
        for &c in *g {
            l1[c] = best[i].1[c] * scale;
        }
    }
    stats.objective = best.iter().map(|b| b.0).sum::<f64>() * scale * scale;
    stats.objective_l1_axis *= scale * scale;
    stats.best_start = best.iter().map(|b| b.2).max().unwrap_or(0);
    Solution { l1, stats }
}

/// One solve of a normalised target in `N` variables: the groups of channels sharing an axis,
/// the given L1 and its axes, and how a start direction per group becomes a point.
struct MultiStart<'a, const N: usize> {
    t: &'a Target,
    form: Formulation,
    settings: &'a SolverSettings,
    groups: &'static [Group],
    given: [DVec3; 3],
    given_axes: [DVec3; 3],
}

impl<const N: usize> MultiStart<'_, N> {
    /// The start point with each group's direction (None: the given L1's axis): the axis itself,
    /// or the given L1 projected onto it.
    fn start(&self, dir_of_group: &dyn Fn(usize) -> Option<DVec3>) -> SVector<f64, N> {
        let mut x = SVector::<f64, N>::zeros();
        match self.form {
            Formulation::Axis => {
                for (i, g) in self.groups.iter().enumerate() {
                    let u = dir_of_group(i).unwrap_or(self.given_axes[g[0]]);
                    x.fixed_rows_mut::<3>(3 * i).copy_from_slice(&u.to_array());
                }
            }
            Formulation::L1 => {
                for (i, g) in self.groups.iter().enumerate() {
                    for &c in *g {
                        let v = match dir_of_group(i) {
                            None => self.given[c],
                            Some(d) => d * d.dot(self.given[c]),
                        };
                        x.fixed_rows_mut::<3>(3 * c).copy_from_slice(&v.to_array());
                    }
                }
            }
        }
        x
    }

    /// The L1 band at a point.
    fn l1_of(&self, x: &SVector<f64, N>) -> [DVec3; 3] {
        match self.form {
            Formulation::Axis => self.t.l1_for_axes(x.as_slice()),
            Formulation::L1 => vectors::<N>(x),
        }
    }

    /// Whether a point has an axis at all (a start without one is evaluated, not optimised).
    fn has_axis(&self, x: &SVector<f64, N>) -> bool {
        match self.form {
            Formulation::Axis => (0..N / 3).any(|i| x.fixed_rows::<3>(3 * i).norm() > 1e-12),
            Formulation::L1 => self.groups.iter().any(|g| self.t.group_axis(g, &vectors::<N>(x)).length() > 1e-12),
        }
    }

    /// Keeps the point's L1 for each group where it beats the best so far.
    fn consider(&self, x: &SVector<f64, N>, start: u32, best: &mut Best) {
        let v = self.l1_of(x);
        for (i, g) in self.groups.iter().enumerate() {
            let f = self.t.group_objective(g, &v);
            if f.is_finite() && f < best[i].0 {
                best[i] = (f, v, start);
            }
        }
    }

    /// L-BFGS from `x0`, unless `x0` has no axis (then `x0` itself).
    fn run_if_axis(&self, x0: SVector<f64, N>, stats: &mut SolveStats) -> SVector<f64, N> {
        if self.has_axis(&x0) {
            run_lbfgs(self.t, self.form, x0, self.settings, stats)
        } else {
            x0
        }
    }

    /// The plain multi-start: one L-BFGS run from every start direction.
    fn run_every_start(&self, dirs: &[Option<DVec3>], stats: &mut SolveStats, best: &mut Best) {
        for (si, d) in dirs.iter().enumerate() {
            let x0 = self.start(&|_| *d);
            let end = self.run_if_axis(x0, stats);
            self.consider(&end, si as u32, best);
        }
    }

    /// Screened multi-start: the reduced objective at every candidate direction, per axis, computed
    /// once; one L-BFGS run from the best combination (the objective is separable across axes),
    /// and a second from the best candidate at least 45° from where the first one ended.
    fn screened(&self, dirs: Vec<Option<DVec3>>, stats: &mut SolveStats, best: &mut Best) {
        let screen = Screen::new(self, &dirs, stats);
        let pick = screen.best(|_, _| true);
        let x0 = self.start(&|i| pick[i].1);
        let start = pick.iter().map(|p| p.2).max().unwrap_or(0);
        let end = self.run_if_axis(x0, stats);
        self.consider(&end, start, best);
        // A second run, in case the grid's best point sat in the wrong basin: the best line at
        // least 45° from the axis the first run reached (per axis, as lines).
        let cos45 = std::f64::consts::FRAC_1_SQRT_2;
        let ends: Vec<DVec3> = (0..self.groups.len())
            .map(|i| DVec3::new(end[3 * i], end[3 * i + 1], end[3 * i + 2]).normalize_or_zero())
            .collect();
        let second = screen.best(|i, a| a.dot(ends[i]).abs() <= cos45);
        let second: Pick =
            second.into_iter().enumerate().map(|(i, (f, _, si))| (f, screen.unit_of(si, i), si)).collect();
        if second.iter().all(|s| s.1.is_some()) && !self.second_run_futile(&second, &screen.consts, &end) {
            let x1 = self.start(&|i| second[i].1);
            let start = second.iter().map(|p| p.2).max().unwrap_or(0);
            let end = run_lbfgs(self.t, self.form, x1, self.settings, stats);
            self.consider(&end, start, best);
        }
    }

    /// Whether no second run can beat the first (per group): every screened line at least 45°
    /// from the end lies above the end's objective by more than M·r²/2, where r is the
    /// screening set's covering radius and M bounds F's second derivative along great circles
    /// (M = 2|U|²/S + 16·Σ w|T₂|², from |Y₂(a)·T₂| ≤ √(5/4π)|T₂|). A better minimum a* would
    /// have a screened line within r with F ≤ F(a*) + M·r²/2 (∇F(a*) = 0), so none lies further
    /// than 45° + r from the end.
    fn second_run_futile(&self, second: &Pick, consts: &[(DVec3, f64)], end: &SVector<f64, N>) -> bool {
        let Some(r) = screen_cover(self.settings.screen).filter(|_| self.settings.skip_futile) else { return false };
        let v = self.l1_of(end);
        self.groups.iter().enumerate().all(|(i, g)| {
            let (big_u, inv_s) = consts[i];
            let t2sq: f64 = g.iter().map(|&c| self.t.err_w[c] * self.t.t2[c].iter().map(|x| x * x).sum::<f64>()).sum();
            let constant = inv_s * big_u.length_squared() + t2sq;
            let m = 2.0 * inv_s * big_u.length_squared() + 16.0 * t2sq;
            second[i].0 + constant >= self.t.group_objective(g, &v) + 0.5 * m * r * r
        })
    }

    /// Per group: its weighted L1 direction U and 1/S, S = Σ (w^axis_c)²/w^err_c.
    fn screen_constants(&self) -> Vec<(DVec3, f64)> {
        let t = self.t;
        self.groups
            .iter()
            .map(|g| {
                let s: f64 = g.iter().map(|&c| t.w_axis(g, c).powi(2) / t.err_w[c]).sum();
                (t.group_axis(g, &t.t1), if s > 0.0 { 1.0 / s } else { 0.0 })
            })
            .collect()
    }
}

/// The screened values of one solve: per group and per candidate direction (the starts, then
/// the screening lines), the unit axis line and the reduced objective there up to a constant
/// (+∞ where there is no axis). Computed once and read by both picks of
/// [`MultiStart::screened`].
struct Screen {
    /// Per group: U and 1/S (see [`MultiStart::screen_constants`]).
    consts: Vec<(DVec3, f64)>,
    /// The candidate directions (None: the given L1's axis).
    dirs: Vec<Option<DVec3>>,
    /// Unit axis line per group and candidate (index `i * dirs.len() + si`; zero where there is
    /// none).
    units: Vec<DVec3>,
    /// The screened value per group and candidate (same index).
    values: Vec<f64>,
}

impl Screen {
    /// The screened values at the start directions `starts` and the screening lines, per group
    /// (each one counted as an evaluation).
    fn new<const N: usize>(run: &MultiStart<'_, N>, starts: &[Option<DVec3>], stats: &mut SolveStats) -> Self {
        let consts = run.screen_constants();
        let (lines, bases) = (screen_lines(run.settings.screen), screen_bases(run.settings.screen));
        let dirs: Vec<Option<DVec3>> = starts.iter().copied().chain(lines.iter().copied().map(Some)).collect();
        let n = dirs.len() * run.groups.len();
        let mut s = Screen { consts, dirs, units: Vec::with_capacity(n), values: Vec::with_capacity(n) };
        for (i, g) in run.groups.iter().enumerate() {
            let kernel = ScreenKernel::new(run.t, s.consts[i], g);
            for d in starts {
                let a = d.unwrap_or(run.given_axes[g[0]]).normalize_or_zero();
                let y = match d {
                    Some(d) => band2(d.normalize()),
                    None => band2(a),
                };
                s.units.push(a);
                s.values.push(if a == DVec3::ZERO { f64::INFINITY } else { kernel.value(a, &y) });
            }
            s.units.extend(bases.iter().map(|b| b.0));
            s.values.extend(bases.iter().map(|(a, y)| kernel.value(*a, y)));
        }
        stats.evals += s.values.iter().filter(|f| **f != f64::INFINITY).count() as u32;
        s
    }

    /// Per group, the candidate of least value among those `admit` lets through (given the
    /// group and the unit line): the value, the candidate's direction and its index.
    fn best(&self, admit: impl Fn(usize, DVec3) -> bool) -> Pick {
        let n = self.dirs.len();
        (0..self.values.len() / n.max(1))
            .map(|i| {
                let mut p = (f64::INFINITY, None, 0);
                for (si, (&f, &a)) in
                    self.values[i * n..(i + 1) * n].iter().zip(&self.units[i * n..(i + 1) * n]).enumerate()
                {
                    if f < p.0 && admit(i, a) {
                        p = (f, self.dirs[si], si as u32);
                    }
                }
                p
            })
            .collect()
    }

    /// The unit line of candidate `si` for group `i` (None where there is no axis), as the
    /// second pick starts from it.
    fn unit_of(&self, si: u32, i: usize) -> Option<DVec3> {
        let u = self.units[i * self.dirs.len() + si as usize];
        (u != DVec3::ZERO).then_some(u)
    }
}

/// One group's screened value, F(a) up to a constant: −(a·U)²/S − Σ w^err (4π/5)(Y₂(a)·T₂)²,
/// with the group's constants gathered once.
struct ScreenKernel<'t> {
    big_u: DVec3,
    inv_s: f64,
    /// Per channel of the group: w^err·4π/5 and its L2 band.
    channels: Vec<(f64, &'t [f64; 5])>,
}

impl<'t> ScreenKernel<'t> {
    fn new(t: &'t Target, (big_u, inv_s): (DVec3, f64), g: Group) -> Self {
        ScreenKernel { big_u, inv_s, channels: g.iter().map(|&c| (t.err_w[c] * FOUR_PI_OVER_5, &t.t2[c])).collect() }
    }

    /// The value at unit line `a` with band-2 basis `y`.
    #[inline]
    fn value(&self, a: DVec3, y: &[f64; 5]) -> f64 {
        let mut f = -self.inv_s * a.dot(self.big_u).powi(2);
        for &(wk, t2) in &self.channels {
            let yt: f64 = (0..5).map(|m| y[m] * t2[m]).sum();
            f -= wk * yt * yt;
        }
        f
    }
}

/// `n` axis lines for screening: the upper half (y > 0) of a Fibonacci set of 2n points (the
/// objective is even in the axis, so a and −a are the same line). Cached for the default n.
pub(super) fn screen_lines(n: usize) -> std::borrow::Cow<'static, [DVec3]> {
    static DEFAULT: std::sync::OnceLock<Vec<DVec3>> = std::sync::OnceLock::new();
    let make = |n: usize| -> Vec<DVec3> {
        crate::reference::domain::fibonacci_sphere(2 * n).into_iter().filter(|d| d.y > 0.0).collect()
    };
    if n == SolverSettings::default().screen {
        std::borrow::Cow::Borrowed(DEFAULT.get_or_init(|| make(n)).as_slice())
    } else {
        std::borrow::Cow::Owned(make(n))
    }
}

/// Each of [`screen_lines`] as a unit vector, with the band-2 basis there (of the line
/// normalised first). Cached for the default n.
fn screen_bases(n: usize) -> std::borrow::Cow<'static, [(DVec3, [f64; 5])]> {
    static DEFAULT: std::sync::OnceLock<Vec<(DVec3, [f64; 5])>> = std::sync::OnceLock::new();
    let make = |n: usize| -> Vec<(DVec3, [f64; 5])> {
        screen_lines(n).iter().map(|d| (d.normalize_or_zero(), band2(d.normalize()))).collect()
    };
    if n == SolverSettings::default().screen {
        std::borrow::Cow::Borrowed(DEFAULT.get_or_init(|| make(n)).as_slice())
    } else {
        std::borrow::Cow::Owned(make(n))
    }
}

/// A covering radius (radians) of the default screening lines taken with their antipodes:
/// every axis line lies within it of one of them. A dense search finds 0.2494; 0.27 leaves more
/// than the dense set's own spacing as margin (`screen_cover_bounds_every_line`). None for
/// other screening sets.
pub(super) fn screen_cover(n: usize) -> Option<f64> {
    (n == SolverSettings::default().screen).then_some(SCREEN_COVER_64)
}

/// See [`screen_cover`].
pub(super) const SCREEN_COVER_64: f64 = 0.27;

pub(super) fn vectors<const N: usize>(x: &SVector<f64, N>) -> [DVec3; 3] {
    let mut v = [DVec3::ZERO; 3];
    for c in 0..N / 3 {
        v[c] = DVec3::new(x[3 * c], x[3 * c + 1], x[3 * c + 2]);
    }
    v
}
