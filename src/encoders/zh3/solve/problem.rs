//! The axis solve's problem (FORMULAS §5): the [`Target`] (one or three channels, weights,
//! stored or hallucinated zonal term), its objective with the analytic gradient in the L1
//! variables and in the reduced axis variables, and [`AxisProblem`], the objective as an argmin
//! cost function and gradient.

use super::zonal::*;
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use argmin::core::{CostFunction, Error, Gradient};
use glam::DVec3;
use nalgebra::SVector;
use std::cell::Cell;

/// Channels sharing one zonal axis.
pub(super) type Group = &'static [usize];
pub(super) const ONE: &[Group] = &[&[0]];
pub(super) const EACH: &[Group] = &[&[0], &[1], &[2]];
pub(super) const ALL: &[Group] = &[&[0, 1, 2]];

/// The target of a solve: irradiance SH (E/π) of one or three channels, with the weights.
#[derive(Clone, Debug)]
pub struct Target {
    /// Number of channels: 1, or 3.
    pub channels: usize,
    /// With three channels: each channel has its own axis (the objective is separable).
    pub per_channel: bool,
    /// Each channel's band-0 coefficient L0 (E/π).
    pub l0: [f64; 3],
    /// Each channel's band-1 target, as an xyz vector (E/π).
    pub t1: [DVec3; 3],
    /// Each channel's five band-2 coefficients (E/π; FORMULAS §2 order).
    pub t2: [[f64; 5]; 3],
    /// Weights of each channel's error in the objective.
    pub err_w: [f64; 3],
    /// Weights of each channel's L1 in a shared axis (a channel alone has weight 1).
    pub axis_w: [f64; 3],
    /// How the zonal coefficient follows from the axis: stored or hallucinated.
    pub zonal: Zonal,
}

impl Target {
    /// Every coefficient of the channels in use is finite.
    pub fn is_finite(&self) -> bool {
        let c = self.channels;
        self.l0[..c].iter().all(|x| x.is_finite())
            && self.t1[..c].iter().all(|v| v.is_finite())
            && self.t2[..c].iter().flatten().all(|x| x.is_finite())
    }

    /// One channel `c` of an irradiance SH.
    pub fn channel(irr: &Sh9, c: usize, zonal: Zonal) -> Self {
        Target {
            channels: 1,
            per_channel: true,
            l0: [irr[0][c], 0.0, 0.0],
            t1: [irr.l1_vector(c), DVec3::ZERO, DVec3::ZERO],
            t2: [l2_band(irr, c), [0.0; 5], [0.0; 5]],
            err_w: [1.0, 0.0, 0.0],
            axis_w: [1.0, 0.0, 0.0],
            zonal,
        }
    }

    /// All three channels, each with its own axis, equal error weights (a separable problem
    /// solved as one).
    pub fn per_channel(irr: &Sh9, zonal: Zonal) -> Self {
        Target { per_channel: true, ..Target::shared(irr, Rgb::ONE, Rgb::ONE, zonal) }
    }

    /// All three channels with one shared axis.
    pub fn shared(irr: &Sh9, axis_w: Rgb, err_w: Rgb, zonal: Zonal) -> Self {
        Target {
            channels: 3,
            per_channel: false,
            l0: [irr[0].x, irr[0].y, irr[0].z],
            t1: [irr.l1_vector(0), irr.l1_vector(1), irr.l1_vector(2)],
            t2: [l2_band(irr, 0), l2_band(irr, 1), l2_band(irr, 2)],
            err_w: err_w.to_array(),
            axis_w: axis_w.to_array(),
            zonal,
        }
    }

    /// The groups of channels that share an axis.
    pub(super) fn groups(&self) -> &'static [Group] {
        match (self.channels, self.per_channel) {
            (1, _) => ONE,
            (_, true) => EACH,
            _ => ALL,
        }
    }

    /// Number of zonal axes.
    pub fn n_axes(&self) -> usize {
        self.groups().len()
    }

    /// Weight of channel c in its group's axis.
    #[inline]
    pub(super) fn w_axis(&self, g: Group, c: usize) -> f64 {
        if g.len() == 1 {
            1.0
        } else {
            self.axis_w[c]
        }
    }

    /// The (unnormalised) axis vector of group `g` for L1 vectors `v`.
    #[inline]
    pub(super) fn group_axis(&self, g: Group, v: &[DVec3; 3]) -> DVec3 {
        g.iter().map(|&c| v[c] * self.w_axis(g, c)).sum()
    }

    /// The axis vector of each channel's group for L1 vectors `v` (unnormalised).
    pub fn axis_vectors(&self, v: &[DVec3; 3]) -> [DVec3; 3] {
        let mut out = [DVec3::ZERO; 3];
        for g in self.groups() {
            let u = self.group_axis(g, v);
            for &c in *g {
                out[c] = u;
            }
        }
        out
    }

    /// The objective at L1 vectors `x` (3 numbers per channel, xyz), and its gradient when
    /// `grad` is given (same layout).
    pub fn eval(&self, x: &[f64], grad: Option<&mut [f64]>) -> f64 {
        let nc = self.channels;
        debug_assert_eq!(x.len(), 3 * nc);
        let mut v = [DVec3::ZERO; 3];
        for c in 0..nc {
            v[c] = DVec3::new(x[3 * c], x[3 * c + 1], x[3 * c + 2]);
        }
        let mut gv = [DVec3::ZERO; 3];
        let cost = self.groups().iter().map(|g| self.eval_group(g, &v, &mut gv)).sum();
        if let Some(g) = grad {
            for c in 0..nc {
                g[3 * c..3 * c + 3].copy_from_slice(&gv[c].to_array());
            }
        }
        cost
    }

    /// The full objective of the channels of one group at L1 vectors `v`.
    pub fn group_objective(&self, g: Group, v: &[DVec3; 3]) -> f64 {
        self.eval_group(g, v, &mut [DVec3::ZERO; 3])
    }

    /// One group's part of [`Target::eval`]; adds its gradient into `gv`.
    pub(super) fn eval_group(&self, g: Group, v: &[DVec3; 3], gv: &mut [DVec3; 3]) -> f64 {
        let u = self.group_axis(g, v);
        let len = u.length();
        let mut cost = 0.0;
        if len.is_nan() || len <= 1e-300 {
            // No axis: k = 0.
            for &c in g {
                let d1 = v[c] - self.t1[c];
                let t2sq: f64 = self.t2[c].iter().map(|t| t * t).sum();
                cost += self.err_w[c] * (d1.length_squared() + t2sq);
                gv[c] = d1 * (2.0 * self.err_w[c]);
            }
            return cost;
        }
        let a = u / len;
        let (y, jac) = band2_with_jacobian(a);
        let jt = |r: &[f64; 5]| -> DVec3 {
            let mut o = DVec3::ZERO;
            for m in 0..5 {
                o += DVec3::from_array(jac[m]) * r[m];
            }
            o
        };
        let mut ga = DVec3::ZERO;
        for &c in g {
            let w = self.err_w[c];
            let d1 = v[c] - self.t1[c];
            let t2 = &self.t2[c];
            // k and its derivatives with respect to v_c and a.
            let (k, dk_dv, dk_da) = match self.zonal {
                Zonal::Stored => {
                    let yt: f64 = (0..5).map(|m| y[m] * t2[m]).sum();
                    (FOUR_PI_OVER_5 * yt, DVec3::ZERO, jt(t2) * FOUR_PI_OVER_5)
                }
                Zonal::Hallucinated(curve) => {
                    let l0 = self.l0[c];
                    if l0 <= 0.0 {
                        (0.0, DVec3::ZERO, DVec3::ZERO)
                    } else {
                        let s = v[c].dot(a);
                        let sign = if s < 0.0 { -1.0 } else { 1.0 };
                        let r = RATIO_SCALE * s.abs() / l0;
                        let (gr, dg) = curve.eval(r);
                        let dk_dr = K_HALLUCINATE * l0 * dg;
                        let dr = RATIO_SCALE * sign / l0;
                        (K_HALLUCINATE * l0 * gr, a * (dk_dr * dr), v[c] * (dk_dr * dr))
                    }
                }
            };
            let r: [f64; 5] = std::array::from_fn(|m| k * y[m] - t2[m]);
            let ry: f64 = (0..5).map(|m| r[m] * y[m]).sum();
            let rr: f64 = r.iter().map(|q| q * q).sum();
            cost += w * (d1.length_squared() + rr);
            gv[c] = (d1 + dk_dv * ry) * (2.0 * w);
            ga += (dk_da * ry + jt(&r) * k) * (2.0 * w);
        }
        // Through the normalisation a = u/|u|.
        let gu = (ga - a * a.dot(ga)) / len;
        for &c in g {
            gv[c] += gu * self.w_axis(g, c);
        }
        cost
    }

    /// The reduced objective of a **stored** solve (variable projection): for a fixed axis line
    /// a = ±u/|u| of a group the best L1 has a closed form ([`Target::l1_for_axes`]), which
    /// leaves, per group,
    ///
    /// F(a) = |P⊥U|²/S + Σ_c w^err_c·(|T₂,c|² − (4π/5)(Y₂(a)·T₂,c)²),
    ///
    /// with U = Σ_c w^axis_c·t_c, S = Σ_c (w^axis_c)²/w^err_c and P⊥ = I − aaᵀ (Lagrange
    /// multipliers on Σ w^axis_c v_c ∥ a). min F equals the minimum of [`Target::eval`]. `x`
    /// holds one axis vector u per group (3 numbers each); the gradient with respect to them is
    /// written to `grad`. Requires positive error weights.
    pub fn eval_axes(&self, x: &[f64], grad: Option<&mut [f64]>) -> f64 {
        let groups = self.groups();
        debug_assert_eq!(x.len(), 3 * groups.len());
        let mut f = 0.0;
        let mut gbuf = [0.0; 9];
        for (i, g) in groups.iter().enumerate() {
            let u = DVec3::new(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
            let (fg, gu) = self.eval_group_axis(g, u);
            f += fg;
            gbuf[3 * i..3 * i + 3].copy_from_slice(&gu.to_array());
        }
        if let Some(out) = grad {
            out.copy_from_slice(&gbuf[..out.len()]);
        }
        f
    }

    /// One group's reduced objective at axis vector `u`, and its gradient.
    pub(super) fn eval_group_axis(&self, g: Group, u: DVec3) -> (f64, DVec3) {
        let big_u = self.group_axis(g, &self.t1);
        let s: f64 = g.iter().map(|&c| self.w_axis(g, c).powi(2) / self.err_w[c]).sum();
        let inv_s = if s > 0.0 { 1.0 / s } else { 0.0 };
        let mut f: f64 = g.iter().map(|&c| self.err_w[c] * self.t2[c].iter().map(|x| x * x).sum::<f64>()).sum();
        let len = u.length();
        if len.is_nan() || len <= 1e-300 {
            // No axis: k = 0, and the L1 is left as it is.
            return (f, DVec3::ZERO);
        }
        let a = u / len;
        let (y, jac) = band2_with_jacobian(a);
        let au = a.dot(big_u);
        f += inv_s * (big_u.length_squared() - au * au);
        let mut ga = big_u * (-2.0 * inv_s * au);
        for &c in g {
            let t2 = &self.t2[c];
            let yt: f64 = (0..5).map(|m| y[m] * t2[m]).sum();
            f -= self.err_w[c] * FOUR_PI_OVER_5 * yt * yt;
            let coef = -2.0 * self.err_w[c] * FOUR_PI_OVER_5 * yt;
            for m in 0..5 {
                ga += DVec3::from_array(jac[m]) * (coef * t2[m]);
            }
        }
        (f, (ga - a * a.dot(ga)) / len)
    }

    /// The L1 vectors that minimise the objective for the axis lines in `x` (one u per group;
    /// see [`Target::eval_axes`]): v_c = t_c − (w^axis_c/w^err_c)·P⊥U/S.
    pub fn l1_for_axes(&self, x: &[f64]) -> [DVec3; 3] {
        let mut v = self.t1;
        for (i, g) in self.groups().iter().enumerate() {
            let u = DVec3::new(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
            let len = u.length();
            if len.is_nan() || len <= 1e-300 {
                continue;
            }
            let a = u / len;
            let big_u = self.group_axis(g, &self.t1);
            let s: f64 = g.iter().map(|&c| self.w_axis(g, c).powi(2) / self.err_w[c]).sum();
            if s > 0.0 {
                let perp = (big_u - a * a.dot(big_u)) / s;
                for &c in *g {
                    v[c] -= perp * (self.w_axis(g, c) / self.err_w[c]);
                }
            }
        }
        v
    }

    /// The target as an irradiance SH (L0, L1, L2 of its channels).
    pub(super) fn to_sh(&self) -> Sh9 {
        let mut s = Sh9::ZERO;
        for c in 0..self.channels {
            s[0][c] = self.l0[c];
            s[1][c] = -self.t1[c].y;
            s[2][c] = self.t1[c].z;
            s[3][c] = -self.t1[c].x;
            for m in 0..5 {
                s[4 + m][c] = self.t2[c][m];
            }
        }
        s
    }

    /// A copy with every coefficient divided by `s` (the objective scales by 1/s²).
    pub(super) fn scaled(&self, s: f64) -> Self {
        let mut t = self.clone();
        for c in 0..3 {
            t.l0[c] /= s;
            t.t1[c] /= s;
            for m in 0..5 {
                t.t2[c][m] /= s;
            }
        }
        t
    }
}

/// The L2 band of channel c (indices 4..8).
pub fn l2_band(sh: &Sh9, c: usize) -> [f64; 5] {
    std::array::from_fn(|m| sh[4 + m][c])
}

/// The variables the solver works on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formulation {
    /// The L1 band itself (3 variables per channel), the paper's formulation.
    L1,
    /// One unnormalised axis u per zonal axis (3 variables each) of the reduced objective
    /// [`Target::eval_axes`]; the L1 follows in closed form. Same minimum; stored solves only.
    Axis,
}

/// A point, the objective there and its gradient.
pub(super) type Evaluation<const N: usize> = (SVector<f64, N>, f64, SVector<f64, N>);

/// The objective as an argmin problem with `N` variables. Cost and gradient are computed
/// together and the pair is cached, since the line search asks for both at each trial point.
/// Counts argmin's calls and the distinct evaluations.
pub struct AxisProblem<'t, const N: usize> {
    /// What is fitted.
    pub target: &'t Target,
    /// What the `N` variables are.
    pub formulation: Formulation,
    /// Calls argmin made to the cost.
    pub cost_calls: Cell<u32>,
    /// Calls argmin made to the gradient.
    pub grad_calls: Cell<u32>,
    /// Distinct points where cost and gradient were computed (cache misses).
    pub evals: Cell<u32>,
    cache: Cell<Option<Evaluation<N>>>,
}

impl<'t, const N: usize> AxisProblem<'t, N> {
    /// The problem of `target` in `formulation`; `N` must be its variable count (3 per axis,
    /// or 3 per channel), which is asserted.
    pub fn new(target: &'t Target, formulation: Formulation) -> Self {
        let want = if formulation == Formulation::Axis { 3 * target.n_axes() } else { 3 * target.channels };
        assert_eq!(N, want, "variable count for {formulation:?}");
        AxisProblem {
            target,
            formulation,
            cost_calls: Cell::new(0),
            grad_calls: Cell::new(0),
            evals: Cell::new(0),
            cache: Cell::new(None),
        }
    }

    /// Objective and gradient at x (from the cache when x was the last point).
    pub fn eval(&self, x: &SVector<f64, N>) -> (f64, SVector<f64, N>) {
        if let Some((cx, f, g)) = self.cache.get() {
            if cx == *x {
                return (f, g);
            }
        }
        self.evals.set(self.evals.get() + 1);
        let mut g = SVector::<f64, N>::zeros();
        let f = match self.formulation {
            Formulation::L1 => self.target.eval(x.as_slice(), Some(g.as_mut_slice())),
            Formulation::Axis => self.target.eval_axes(x.as_slice(), Some(g.as_mut_slice())),
        };
        self.cache.set(Some((*x, f, g)));
        (f, g)
    }
}

impl<const N: usize> CostFunction for AxisProblem<'_, N> {
    type Param = SVector<f64, N>;
    type Output = f64;
    fn cost(&self, x: &Self::Param) -> Result<f64, Error> {
        self.cost_calls.set(self.cost_calls.get() + 1);
        Ok(self.eval(x).0)
    }
}

impl<const N: usize> Gradient for AxisProblem<'_, N> {
    type Param = SVector<f64, N>;
    type Gradient = SVector<f64, N>;
    fn gradient(&self, x: &Self::Param) -> Result<Self::Gradient, Error> {
        self.grad_calls.set(self.grad_calls.get() + 1);
        Ok(self.eval(x).1)
    }
}
