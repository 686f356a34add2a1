//! ZH3: linear SH plus the quadratic zonal harmonic about a zonal axis (ZH3 talk; FORMULAS §5).
//!
//! E/π(n) = L₀₀Y₀₀ + (2/3)·Σ L₁ₘY₁ₘ(n) + ¼·Σ_m k·Y₂ₘ(a)·Y₂ₘ(n), the last term being the
//! talk's ¼·f·√(5/16π)·(3(a·n)² − 1) with f = √(5/4π)·k. Every variant is expanded to an
//! irradiance SH3 and evaluated as one.
//!
//! | id | zonal axis | zonal coefficient | stored scalars |
//! |----|------------|-------------------|----------------|
//! | `zh3_hallucinate` | shared, from Rec.709-weighted L1 | curve f/L₀₀ = 0.08r + 0.6r², r per channel (the talk's shader) | 12 |
//! | `zh3_hallucinate_channel` | each channel's L1 | the same curve | 12 |
//! | `zh3_hallucinate_ambdir` | shared, Rec.709 | ambient + delta light model, f/L₀₀ = √(5/3)·r | 12 |
//! | `zh3_hallucinate_sphere` | shared, Rec.709 | sphere-light model, f/L₀₀ = (2√5/3)r² − √(5/3)r for r ≥ √3/2, else 0 | 12 |
//! | `zh3_stored_channel` | each channel's L1 | stored: least-squares zonal fit of L2 | 15 |
//! | `zh3_stored_shared` | shared, equal-weight L1 | stored | 15 |
//! | `zh3_solved_channel` | solved per channel (L-BFGS, `zh3_solve.rs`) | stored | 15 |
//! | `zh3_solved_shared` | solved, one shared axis, equal weights (the paper's solve) | stored | 15 |
//! | `zh3_hallucinate_solved` | the L1 is solved so that its hallucinated ZH3 best matches SH3; shared axis | curve | 12 |
//! | `zh3_q16` | as `zh3_solved_shared`, always `quantise = "ratio8"`: the talk's stored ZH3 in 16 bytes | stored | 15 |
//! | `zh3_hallucinate_q13` | as `zh3_hallucinate`, always `quantise = "ratio8"`: the talk's hallucinated ZH3 in 13 bytes | curve | 12 |
//!
//! The ratio r = |L1_c·a|/L₀₀,c of channel c is taken on radiance coefficients; it lies in
//! [0, √3] for non-negative radiance and equals √3 for one delta light. Solved variants store
//! the solved L1 (it replaces the projected one) and minimise the irradiance error of bands 1–2
//! (as the authors' solver does).
//!
//! TOML keys (each encoder reads only the keys that apply to it; others are rejected):
//!
//! | key | applies to | default | meaning |
//! |-----|------------|---------|---------|
//! | `axis_weights` | shared-axis encoders | `"rec709"` (hallucinate, ambdir, sphere), `"equal"` (stored_shared, solved_shared, hallucinate_solved) | channel weights of the shared axis: `"rec709"`, `"equal"` or `[r, g, b]` |
//! | `error_weights` | `zh3_solved_shared`, `zh3_hallucinate_solved` | `"equal"` | channel weights of the solve's objective; must match `axis_weights` (claim Z4) |
//! | `curve_c1`, `curve_c2`, `curve_c3` | curve encoders | 0.08, 0.6, 0 | f/L₀₀ = c1·r + c2·r² + c3·r³ |
//! | `max_iters` | solved | 100 | L-BFGS iterations per start |
//! | `tol_grad` | solved | 1e-8 | gradient-norm stop, objective normalised by max L₀₀² |
//! | `tol_cost` | solved | 1e-14 | objective-change stop (normalised) |
//! | `memory` | solved | 5 | L-BFGS memory |
//! | `starts` | solved | 5 | 1 = the given L1 only, up to 5 = plus the four tetrahedron projections |
//! | `screen` | `zh3_solved_*` | 64 | 0: L-BFGS from every start (FORMULAS §5); N: evaluate the reduced objective at those starts and N more axis lines, L-BFGS from the best and from the best one 45° away unless that second run provably cannot win (needs `formulation = "axis"`; tested to reach the same objective) |
//! | `line_search` | solved | `"more_thuente"` | the line search of each L-BFGS iteration: `"more_thuente"` or `"backtracking"` (Armijo) |
//! | `formulation` | `zh3_solved_*` | `"axis"` | `"axis"`: L-BFGS on the axis with the L1 in closed form (same minimum, faster); `"l1"`: on the L1 band itself, as the paper |
//! | `quantise` | all but `zh3_q16`, `zh3_hallucinate_q13` | `"none"` | `"ratio8"`: store as FORMULAS §11 (`quantise.rs`): 13 bytes, 16 with a stored coefficient |
//!
//! Settings are echoed in the `diagnostics` column, with the solver's iteration and evaluation
//! counts. Degenerate inputs: no L1 (or no weighted L1) gives no axis, so k = 0 (the result is SH
//! L1); a channel with L₀₀ ≤ 0 hallucinates k = 0.

mod build;
mod encoder;
pub(crate) mod model;
mod serialise;
pub mod solve;

pub use build::{
    build_hallucinate, build_hallucinate_ambdir, build_hallucinate_channel, build_hallucinate_q13,
    build_hallucinate_solved, build_hallucinate_sphere, build_q16, build_solved_channel, build_solved_shared,
    build_stored_channel, build_stored_shared, configured,
};
pub use model::{hallucinate, stored, AxisRule};

#[cfg(test)]
mod tests;
