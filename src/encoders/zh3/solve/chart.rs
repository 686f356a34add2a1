//! One axis group's reduced objective (FORMULAS §5, [`Target::eval_group_axis`]) in a gnomonic
//! chart about a unit axis a₀, with its analytic Hessian, as an argmin problem for Newton's
//! method.
//!
//! **Chart.** u(p) = a₀ + p₁e₁ + p₂e₂, with e₁, e₂ an orthonormal basis of the plane
//! perpendicular to a₀: every axis line within 90° of a₀ once, in 2 variables, so the Hessian is
//! not singular along u as it is in the 3 variables of u (the objective is even and homogeneous
//! of degree 0 in u). The chart is affine, so ∇ₚ = Eᵀ∇F(u) and ∇²ₚ = Eᵀ∇²F(u)E, E = [e₁ e₂].
//!
//! **Objective as forms of u.** On the sphere Y₂(a)·T₂ = aᵀQa, with Q the traceless symmetric
//! matrix of the band-2 coefficients (FORMULAS §2: 3z² − 1 = 2z² − x² − y² when |a| = 1). With
//! r = |u|², q_U = (u·U)² and q_c = uᵀQ_c u,
//!
//! F(u) = Σ_c w^err_c|T₂,c|² + |U|²/S − (1/S)·q_U/r − Σ_c κ_c·q_c²/r²,  κ_c = w^err_c·4π/5,
//!
//! (U, S as in [`Target::eval_axes`]), whose derivatives, with m = U(U·u) and s_c = Q_c u, are
//! - ∇(q_U/r) = 2m/r − 2q_U u/r²,
//!   ∇²(q_U/r) = 2UUᵀ/r − 4(muᵀ + umᵀ)/r² − 2q_U I/r² + 8q_U uuᵀ/r³;
//! - ∇(q²/r²) = 4q s/r² − 4q² u/r³,
//!   ∇²(q²/r²) = 8ssᵀ/r² + 4qQ/r² − 16q(suᵀ + usᵀ)/r³ − 4q² I/r³ + 24q² uuᵀ/r⁴.
//!
//! Tested against [`Target::eval_group_axis`]'s gradient and against finite differences.

use super::problem::{Group, Target};
use super::zonal::FOUR_PI_OVER_5;
use crate::math::sh::k as shk;
use argmin::core::{Error, Gradient, Hessian};
use glam::DVec3;
use nalgebra::{Matrix2, Matrix3, Matrix3x2, SVector, Vector2, Vector3};
use std::cell::Cell;

/// At most three channels share an axis.
const MAX_CHANNELS: usize = 3;

/// One group's reduced objective in the chart about `a0`, its constants gathered once.
pub(super) struct ChartProblem {
    /// The chart's origin (a unit axis) and its tangent basis, as the columns a₀, e₁, e₂.
    a0: Vector3<f64>,
    e: Matrix3x2<f64>,
    /// The group's weighted L1 direction U and 1/S.
    big_u: Vector3<f64>,
    inv_s: f64,
    /// Per channel of the group: κ_c and Q_c (unused rows are zero).
    kappa: [f64; MAX_CHANNELS],
    q: [Matrix3<f64>; MAX_CHANNELS],
    /// The last point and its gradient and Hessian (Newton asks for both at each point).
    cache: Cell<Option<(Vector2<f64>, Vector2<f64>, Matrix2<f64>)>>,
}

/// Q with uᵀQu = Y₂(u)·T₂ for unit u: the band-2 basis of FORMULAS §2 as a quadratic form.
fn band2_form(t2: &[f64; 5]) -> Matrix3<f64> {
    let (b, c0, c2) = (shk::Y2_XY, shk::Y20, shk::Y22);
    let (xy, yz, xz) = (0.5 * b * t2[0], -0.5 * b * t2[1], -0.5 * b * t2[3]);
    Matrix3::new(-c0 * t2[2] + c2 * t2[4], xy, xz, xy, -c0 * t2[2] - c2 * t2[4], yz, xz, yz, 2.0 * c0 * t2[2])
}

fn v3(d: DVec3) -> Vector3<f64> {
    Vector3::new(d.x, d.y, d.z)
}

impl ChartProblem {
    /// The chart of group `g` of `target` about the unit axis `a0`.
    pub(super) fn new(target: &Target, g: Group, a0: DVec3) -> Self {
        let (e1, e2) = a0.any_orthonormal_pair();
        let s: f64 = g.iter().map(|&c| target.w_axis(g, c).powi(2) / target.err_w[c]).sum();
        let mut kappa = [0.0; MAX_CHANNELS];
        let mut q = [Matrix3::zeros(); MAX_CHANNELS];
        for (i, &c) in g.iter().enumerate() {
            kappa[i] = target.err_w[c] * FOUR_PI_OVER_5;
            q[i] = band2_form(&target.t2[c]);
        }
        ChartProblem {
            a0: v3(a0),
            e: Matrix3x2::from_columns(&[v3(e1), v3(e2)]),
            big_u: v3(target.group_axis(g, &target.t1)),
            inv_s: if s > 0.0 { 1.0 / s } else { 0.0 },
            kappa,
            q,
            cache: Cell::new(None),
        }
    }

    /// The axis vector u at chart point `p` (not unit).
    pub(super) fn axis(&self, p: &Vector2<f64>) -> DVec3 {
        let u = self.a0 + self.e * p;
        DVec3::new(u.x, u.y, u.z)
    }

    /// ∇F and ∇²F at u, in 3 variables (the module's formulas).
    fn derivatives3(&self, u: &Vector3<f64>) -> (Vector3<f64>, Matrix3<f64>) {
        let r = u.norm_squared();
        let uu = u * u.transpose();
        let eye = Matrix3::identity();
        let ud = self.big_u.dot(u);
        let (m, q_u) = (self.big_u * ud, ud * ud);
        let mut g = -self.inv_s * (2.0 * m / r - 2.0 * q_u * u / (r * r));
        let mut h = -self.inv_s
            * (2.0 * self.big_u * self.big_u.transpose() / r
                - 4.0 * (m * u.transpose() + u * m.transpose()) / (r * r)
                - 2.0 * q_u * eye / (r * r)
                + 8.0 * q_u * uu / (r * r * r));
        for (&kappa, q) in self.kappa.iter().zip(&self.q) {
            if kappa == 0.0 {
                continue;
            }
            let s = q * u;
            let qf = u.dot(&s);
            g -= kappa * (4.0 * qf * s / (r * r) - 4.0 * qf * qf * u / (r * r * r));
            h -= kappa
                * (8.0 * s * s.transpose() / (r * r) + 4.0 * qf * q / (r * r)
                    - 16.0 * qf * (s * u.transpose() + u * s.transpose()) / (r * r * r)
                    - 4.0 * qf * qf * eye / (r * r * r)
                    + 24.0 * qf * qf * uu / (r * r * r * r));
        }
        (g, h)
    }

    /// The gradient and Hessian in the chart at `p` (from the cache when `p` was the last point).
    pub(super) fn derivatives(&self, p: &Vector2<f64>) -> (Vector2<f64>, Matrix2<f64>) {
        if let Some((cp, g, h)) = self.cache.get() {
            if cp == *p {
                return (g, h);
            }
        }
        let (g3, h3) = self.derivatives3(&(self.a0 + self.e * p));
        let (g, h) = (self.e.transpose() * g3, self.e.transpose() * h3 * self.e);
        self.cache.set(Some((*p, g, h)));
        (g, h)
    }
}

impl Gradient for ChartProblem {
    type Param = SVector<f64, 2>;
    type Gradient = SVector<f64, 2>;
    fn gradient(&self, p: &Self::Param) -> Result<Self::Gradient, Error> {
        Ok(self.derivatives(p).0)
    }
}

impl Hessian for ChartProblem {
    type Param = SVector<f64, 2>;
    type Hessian = Matrix2<f64>;
    fn hessian(&self, p: &Self::Param) -> Result<Self::Hessian, Error> {
        Ok(self.derivatives(p).1)
    }
}
