//! The ZH3 axis solve (ZH3 talk, "solving for the zonal axis"; FORMULAS §5) as an argmin
//! problem, kept apart from the solver that minimises it.
//!
//! **Variables.** The L1 band, as one xyz vector per channel, v_c = (−L₁,₁, −L₁,₋₁, L₁,₀) in
//! irradiance units (E/π SH, band scale 2/3 applied): 3 numbers for one channel, 9 for three
//! channels sharing one axis. L0 stays fixed.
//!
//! **Zonal axis.** a = u/|u| with u = v (one channel) or u = Σ_c w^axis_c·v_c (shared axis).
//!
//! **Objective** (squared error in SH coefficient space of bands 1–2 of the irradiance SH, equal
//! to the sphere-integrated squared error because the basis is orthonormal):
//!
//! Σ_c w^err_c·( |v_c − t_c|² + |k_c·Y₂(a) − T₂,c|² )
//!
//! with t_c, T₂,c the target's L1 vector and L2 band, and k_c the zonal coefficient about a:
//! - **stored**: the least-squares zonal fit k_c = (4π/5)·Y₂(a)·T₂,c (FORMULAS §5);
//! - **hallucinated**: k_c = √(4π/5)·¼·L₀,c·g(r_c) with r_c = 1.5·|v_c·a|/L₀,c the radiance
//!   ratio (1.5 undoes the band scale 2/3) and g the hallucination curve (FORMULAS §5,
//!   "f_irr = ¼·f_rad(1.5·r)").
//!
//! The gradient is analytic ([`AxisProblem::eval`]) and is tested against finite differences.
//!
//! **Solver.** argmin's L-BFGS with the More–Thuente line search on static nalgebra vectors
//! (`SVector<f64, 3>` per channel, `SVector<f64, 9>` shared), run from several starts
//! (FORMULAS §5): the given L1, then the L1 projected onto each of the four tetrahedron axes
//! (±1, ±1, ±1)/√3 with an even number of minus signs. The best end point wins. By default the
//! starts are screened with 64 more axis lines; L-BFGS runs from the best, and again from the
//! best line ≥ 45° away only when a curvature bound cannot rule out a better minimum there
//! (`solver.rs`). The target is
//! divided by its largest L0 first, so the tolerances are relative to the probe's brightness.
//!
//! **Degenerate input.** Where u = 0 there is no axis: the zonal term is dropped (k = 0) and the
//! gradient of the L2 part is taken as 0. A start with u = 0 is evaluated but not optimised.
//!
//! The problem (`zonal.rs`: the zonal term about an axis; `problem.rs`: the target, its
//! objective and gradient, and the argmin problem) is kept apart from the solver driving it
//! (`solver.rs`: the multi-start and the screened start, L-BFGS runs; `drive.rs`: the loop
//! stepping argmin's L-BFGS).

mod drive;
mod problem;
mod solver;
#[cfg(test)]
mod tests;
mod zonal;

pub use problem::{l2_band, Formulation, Target};
pub use solver::{solve, LineSearch, SolveStats, SolverSettings};
pub use zonal::{band2, hallucinated_k, zonal_fit, zonal_fit_at, Curve, Zonal};
