//! The ambient dice (Iwanicki & Sloan 2017, "Ambient Dice", JCGT 6(2)): colours and tangential
//! derivatives stored at the 12 vertices of an icosahedron, blended over each face. The peer
//! tool's `AD`, `ADYCoCg` and `ADRBF` (Probulator `Source/Probulator/ExperimentAmbientDice.h`,
//! `.cpp`). The definitions below are the peer's; the paper was not at hand to check them.
//!
//! | id | basis | stored scalars |
//! |---|---|---|
//! | `ambient_dice` | hybrid cubic Bézier per channel: a value and two tangential derivatives per vertex (36) | 108 |
//! | `ambient_dice_ycocg` | Y: the Bézier basis (36); Co, Cg: the linear basis (12 each) | 60 |
//! | `ambient_dice_srbf` | 12 cosine SRBF lobes per channel, one per vertex | 36 |
//!
//! **Vertices**, as the peer orients them: the cyclic permutations of (±1, ±k, 0), k = 1/φ =
//! (√5 − 1)/2, normalised (neighbours are 63.4° apart, cos = 1/√5). **Faces**: the 20 triples of
//! mutually neighbouring vertices. A normal n lies in the face whose centre is nearest (the
//! icosahedron is face-transitive, so a face's central projection is the spherical Voronoi cell
//! of its centre). Its barycentrics are the coordinates of n in the basis of the face's three
//! unit vertices, n = Σ b_i v_i (the peer's `triangleBarycentricNormals`); they are not affine:
//! Σ b_i ≥ 1, with equality only at the vertices.
//!
//! **Bézier basis** (the peer's `hybridCubicBezierWeights`): the cubic Bézier triangle in
//! (b0, b1, b2) whose corner control points are the vertex values f_i; the edge point next to
//! vertex i on the edge towards j is f_i/√5 + D·(v_j − v_i)·(g_i t_i + h_i s_i), with g_i, h_i
//! the derivatives along the vertex's tangent t_i and bitangent s_i and D = (√5 − 1)/3 (the
//! peer's "1/(3α) times the projection of the edge vectors", α = sin 72°, on its unnormalised
//! vertices of length √(1 + k²)); the centre point is Σ_i w_i c⁽ⁱ⁾, w_i = b_j b_k/(b1b2 + b0b2 +
//! b0b1) for {i, j, k} = {0, 1, 2}, where c⁽⁰⁾ = a0(f1 + f2) + a1(c021 + c012) + a2(c120 +
//! c102) (and likewise c⁽¹⁾, c⁽²⁾), a0 = (√5 − 5)/40, a1 = (11√5 − 15)/40, a2 = √5/10. The
//! tangent frames are ours (t_i ∝ Y × v_i, s_i = v_i × t_i); any orthonormal frame spans the
//! same functions, so the fitted E/π does not depend on it (tested). The basis does not
//! contain the constant function: with unit values and zero derivatives it is 1 at the
//! vertices, 0.951 at edge midpoints and 0.938 at face centres (the barycentrics are not
//! affine), so a constant E/π is fitted to 4.1% at worst, 1.7% RMS (tested), not exactly.
//!
//! **Linear basis** (Co and Cg of the Y/Co/Cg variant, the peer's `evaluateLinear`): Σ b_i c_i
//! over the face's vertices. With Σ b_i between 1 and 1.258 it cannot hold a constant either:
//! a strongly coloured constant, (0.5, 1, 2), is fitted to 29% at worst, 9% RMS (tested). The
//! colour transform is the peer's: Y = R/4 + G/2 + B/4, Co = (R − B)/2, Cg = −R/4 + G/2 − B/4,
//! so R = Y + Co − Cg, G = Y + Cg, B = Y − Co − Cg.
//!
//! **Cosine SRBF** (the peer's `srbfWeights`): lobe i is 0.7·c²/2 + 0.3·5c⁴/6 with
//! c = max(n·v_i, 0). The lobes sum to 1 at every n (the six vertex axes a form a spherical
//! 5-design: Σ(n·a)² = 2, Σ(n·a)⁴ = 6/5), so a constant is fitted exactly.
//!
//! **Fit**: least squares of E/π over the sphere of normals, at the pixel centres of a 128×64
//! lat-long grid ([`FIT_GRID`], the ambient cube's, so the exact E/π grid is computed once per
//! case) weighted by their exact solid angles (`weights = "solid_angle"`, the default: the
//! `exact` metric's weighting and the peer's objective, whose moments are weighted by texel
//! areas and whose Gram matrix is a uniform Hammersley sum); `weights = "pixel"` weights every
//! pixel alike (the `probulator` metric's weighting). The normal matrix depends only on the
//! basis and the grid, so it is built and Cholesky-factored once per process; a fit is the
//! moments of the target and two triangular solves. Without a radiance source (probe sets:
//! L2 SH only) the target is the E/π of the SH, and its moments are a 9-column product, the
//! same fit without evaluating the grid. The Y/Co/Cg variant minimises the RGB error, which
//! couples Y and Cg (the RGB error is 3e_Y² + 2e_Co² + 3e_Cg² − 2e_Y·e_Cg); the peer fits Y,
//! Co and Cg each on its own.
//!
//! The peer fits its dice to its own Monte Carlo irradiance image and keeps the output
//! unclamped; here the target is the exact E/π of the visible light
//! ([`crate::reference::radiance::RadianceSource`]). On a hemisphere domain the dice is fitted
//! over the whole sphere of normals, like the ambient cube. Degenerate inputs: black in, black
//! out; a target that is not finite gives black; the target is divided by its largest
//! magnitude before the solve (a 1e-300 light must not underflow) and the answer scaled back.
//!
//! TOML keys: `weights` (`solid_angle`, default, or `pixel`).
//!
//! One concept per file: `geometry.rs` (the icosahedron, faces, barycentrics and the basis
//! weights), `variant.rs` (the three variants' bases), `design.rs` (the least-squares problem
//! on the fitting grid, factored once), `encoder.rs` (the fit and the encoders) and `tests.rs`.

mod design;
mod encoder;
mod geometry;
#[cfg(test)]
mod tests;
mod variant;

pub use encoder::{build_ambient_dice, build_ambient_dice_srbf, build_ambient_dice_ycocg};
