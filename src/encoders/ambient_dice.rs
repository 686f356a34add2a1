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

use crate::encoders::encoder::{Encoder, FitInput, Fitted, Params};
use crate::encoders::stored::{Role, Stored, Unit, Value};
use crate::math::colour::Rgb;
use crate::math::sh::{basis as sh_basis, Sh9, N_SH};
use crate::reference::radiance::latlong_normals;
use anyhow::{bail, Result};
use glam::DVec3;
use nalgebra::{DMatrix, DVector};
use std::sync::OnceLock;

/// The fitting grid (lat-long pixel centres), the ambient cube's.
pub const FIT_GRID: (usize, usize) = crate::encoders::ambient_cube::FIT_GRID;

/// k = 1/φ = (√5 − 1)/2, the peer's `kT`.
const K: f64 = 0.618_033_988_749_894_9;

/// The dice's geometry: vertices, tangent frames, faces.
pub struct Geometry {
    /// The 12 unit vertices, in the peer's order.
    pub vertices: [DVec3; 12],
    /// Each vertex's tangent t and bitangent s (t × s = v).
    pub frames: [(DVec3, DVec3); 12],
    pub faces: Vec<Face>,
}

/// One face: its vertices, the rows that give its barycentrics, its centre, and the edge
/// factors D·(v_j − v_i)·t_i, D·(v_j − v_i)·s_i of its six edge control points.
pub struct Face {
    pub vertices: [usize; 3],
    /// b_i = dual[i]·n.
    dual: [DVec3; 3],
    centre: DVec3,
    /// For the edge points 0→1, 0→2, 1→0, 1→2, 2→0, 2→1: (tangent, bitangent) factors.
    edge: [(f64, f64); 6],
}

/// The edge points of a face as (from, to), in the order of [`Face::edge`].
const EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)];

impl Geometry {
    /// The peer's vertices with tangent frames turned by `twist` radians about each vertex from
    /// ours (0 in use; tests turn them to show the fit does not depend on the frame).
    pub fn new(twist: f64) -> Self {
        let raw = [
            (1.0, K, 0.0),
            (-1.0, K, 0.0),
            (1.0, -K, 0.0),
            (-1.0, -K, 0.0),
            (0.0, 1.0, K),
            (0.0, -1.0, K),
            (0.0, 1.0, -K),
            (0.0, -1.0, -K),
            (K, 0.0, 1.0),
            (-K, 0.0, 1.0),
            (K, 0.0, -1.0),
            (-K, 0.0, -1.0),
        ];
        let vertices: [DVec3; 12] = std::array::from_fn(|i| DVec3::new(raw[i].0, raw[i].1, raw[i].2).normalize());
        let frames = std::array::from_fn(|i| {
            let v = vertices[i];
            let t0 = DVec3::Y.cross(v).normalize();
            let s0 = v.cross(t0);
            let (s, c) = twist.sin_cos();
            (t0 * c + s0 * s, s0 * c - t0 * s)
        });
        let d = (5f64.sqrt() - 1.0) / 3.0;
        let mut faces = Vec::with_capacity(20);
        let near = |a: usize, b: usize| vertices[a].dot(vertices[b]) > 0.0;
        for a in 0..12 {
            for b in a + 1..12 {
                for c in b + 1..12 {
                    if !(near(a, b) && near(b, c) && near(a, c)) {
                        continue;
                    }
                    let ids = [a, b, c];
                    let v = ids.map(|i| vertices[i]);
                    let det = v[0].dot(v[1].cross(v[2]));
                    let dual = [v[1].cross(v[2]) / det, v[2].cross(v[0]) / det, v[0].cross(v[1]) / det];
                    let edge = EDGES.map(|(i, j)| {
                        let e = (v[j] - v[i]) * d;
                        let (t, s): (DVec3, DVec3) = frames[ids[i]];
                        (e.dot(t), e.dot(s))
                    });
                    faces.push(Face { vertices: ids, dual, centre: (v[0] + v[1] + v[2]).normalize(), edge });
                }
            }
        }
        Geometry { vertices, frames, faces }
    }

    /// The face holding unit direction `n` and its barycentrics (clamped at 0 against rounding
    /// on an edge).
    pub fn locate(&self, n: DVec3) -> (&Face, [f64; 3]) {
        let mut best = 0;
        let mut best_dot = f64::NEG_INFINITY;
        for (k, f) in self.faces.iter().enumerate() {
            let d = f.centre.dot(n);
            if d > best_dot {
                best_dot = d;
                best = k;
            }
        }
        let f = &self.faces[best];
        (f, f.dual.map(|r| r.dot(n).max(0.0)))
    }

    /// The Bézier basis at unit `n`: the face's vertices and, per vertex, the weights of its
    /// value and of its two derivatives. Every other coefficient has weight 0.
    pub fn bezier(&self, n: DVec3) -> ([usize; 3], [[f64; 3]; 3]) {
        let (face, b) = self.locate(n);
        (face.vertices, bezier_weights(face, b))
    }

    /// The linear basis at unit `n`: the face's vertices and their barycentrics.
    pub fn linear(&self, n: DVec3) -> ([usize; 3], [f64; 3]) {
        let (face, b) = self.locate(n);
        (face.vertices, b)
    }

    /// The cosine SRBF lobes at unit `n`, one per vertex.
    pub fn srbf(&self, n: DVec3) -> [f64; 12] {
        self.vertices.map(|v| {
            let c = v.dot(n).max(0.0);
            let c2 = c * c;
            0.7 * (0.5 * c2) + 0.3 * (5.0 / 6.0 * c2 * c2)
        })
    }
}

/// The Bézier weights of a face at barycentrics `b` (module docs; the peer's
/// `hybridCubicBezierWeights`): per face vertex, [value, tangent derivative, bitangent
/// derivative].
fn bezier_weights(face: &Face, b: [f64; 3]) -> [[f64; 3]; 3] {
    let s5 = 5f64.sqrt();
    let (a0, a1, a2) = ((s5 - 5.0) / 40.0, (11.0 * s5 - 15.0) / 40.0, s5 / 10.0);
    let [b0, b1, b2] = b;
    // Bernstein weights of the ten control points (cxyz: b0^x b1^y b2^z).
    let mut c300 = b0 * b0 * b0;
    let mut c030 = b1 * b1 * b1;
    let mut c003 = b2 * b2 * b2;
    let mut c210 = 3.0 * b0 * b0 * b1;
    let mut c201 = 3.0 * b0 * b0 * b2;
    let mut c120 = 3.0 * b0 * b1 * b1;
    let mut c021 = 3.0 * b1 * b1 * b2;
    let mut c102 = 3.0 * b0 * b2 * b2;
    let mut c012 = 3.0 * b1 * b2 * b2;
    // The centre point's three candidates, weighted w_i·6b0b1b2 (0 where two b's are 0).
    let denom = b1 * b2 + b0 * b2 + b0 * b1;
    let centre = 6.0 * b0 * b1 * b2;
    let (p0, p1, p2) = if denom > 0.0 {
        (centre * b1 * b2 / denom, centre * b0 * b2 / denom, centre * b0 * b1 / denom)
    } else {
        (0.0, 0.0, 0.0)
    };
    let mut value = [0.0; 3];
    // c⁽⁰⁾ = a0(f1 + f2) + a1(c021 + c012) + a2(c120 + c102).
    value[1] += a0 * p0;
    c003 += a0 * p0;
    c021 += a1 * p0;
    c012 += a1 * p0;
    c120 += a2 * p0;
    c102 += a2 * p0;
    // c⁽¹⁾ = a0(f2 + f0) + a1(c102 + c201) + a2(c012 + c210).
    value[2] += a0 * p1;
    c300 += a0 * p1;
    c102 += a1 * p1;
    c201 += a1 * p1;
    c012 += a2 * p1;
    c210 += a2 * p1;
    // c⁽²⁾ = a0(f0 + f1) + a1(c210 + c120) + a2(c201 + c021).
    value[0] += a0 * p2;
    c030 += a0 * p2;
    c210 += a1 * p2;
    c120 += a1 * p2;
    c201 += a2 * p2;
    c021 += a2 * p2;
    // Edge points: f_i/√5 plus the derivative terms; corners: f_i.
    let edge_weight = [c210, c201, c120, c021, c102, c012];
    let mut w = [[0.0; 3]; 3];
    for (k, &(i, _)) in EDGES.iter().enumerate() {
        let (ft, fs) = face.edge[k];
        value[i] += edge_weight[k] / s5;
        w[i][1] += ft * edge_weight[k];
        w[i][2] += fs * edge_weight[k];
    }
    value[0] += c300;
    value[1] += c030;
    value[2] += c003;
    for i in 0..3 {
        w[i][0] = value[i];
    }
    w
}

/// The dice's geometry with our tangent frames.
pub fn geometry() -> &'static Geometry {
    static G: OnceLock<Geometry> = OnceLock::new();
    G.get_or_init(|| Geometry::new(0.0))
}

/// A dice variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// `ambient_dice`: the Bézier basis in every channel.
    Bezier,
    /// `ambient_dice_ycocg`: Y in the Bézier basis, Co and Cg in the linear basis.
    BezierYCoCg,
    /// `ambient_dice_srbf`: the cosine SRBF lobes in every channel.
    Srbf,
}

impl Variant {
    fn id(self) -> &'static str {
        match self {
            Variant::Bezier => "ambient_dice",
            Variant::BezierYCoCg => "ambient_dice_ycocg",
            Variant::Srbf => "ambient_dice_srbf",
        }
    }

    /// The scalar basis functions whose moments a fit takes: 36 Bézier, 36 + 12 (Bézier then
    /// linear) or 12 SRBF.
    fn functions(self) -> usize {
        match self {
            Variant::Bezier => 36,
            Variant::BezierYCoCg => 48,
            Variant::Srbf => 12,
        }
    }

    /// The unknowns of the normal equations: per channel (36, 12), or joint for Y/Co/Cg
    /// (36 + 12 + 12).
    fn unknowns(self) -> usize {
        match self {
            Variant::Bezier => 36,
            Variant::BezierYCoCg => 60,
            Variant::Srbf => 12,
        }
    }

    /// The non-zero scalar basis values at `n`, as (index, value).
    fn row(self, g: &Geometry, n: DVec3, out: &mut Vec<(u16, f64)>) {
        match self {
            Variant::Bezier | Variant::BezierYCoCg => {
                let (face, b) = g.locate(n);
                let w = bezier_weights(face, b);
                for (i, &v) in face.vertices.iter().enumerate() {
                    for (slot, &x) in w[i].iter().enumerate() {
                        out.push(((3 * v + slot) as u16, x));
                    }
                }
                if self == Variant::BezierYCoCg {
                    for (i, &v) in face.vertices.iter().enumerate() {
                        out.push(((36 + v) as u16, b[i]));
                    }
                }
            }
            Variant::Srbf => {
                for (i, &x) in g.srbf(n).iter().enumerate() {
                    if x != 0.0 {
                        out.push((i as u16, x));
                    }
                }
            }
        }
    }
}

/// A variant's least-squares problem on the fitting grid: the basis at every grid normal
/// (sparse), the grid weights, and the factored normal matrix.
struct Design {
    /// Row p's entries are `entries[start[p]..start[p + 1]]`.
    start: Vec<usize>,
    entries: Vec<(u16, f64)>,
    weights: Vec<f64>,
    normal: nalgebra::Cholesky<f64, nalgebra::Dyn>,
    /// Per scalar basis function j, Σ_p w_p φ_j(n_p) Y_i(n_p) for the nine SH functions Y_i.
    sh_moments: Vec<[f64; N_SH]>,
}

impl Design {
    fn new(variant: Variant, pixel_weights: bool) -> Self {
        let g = geometry();
        let (w, h) = FIT_GRID;
        let normals = latlong_normals(w, h);
        let mut start = Vec::with_capacity(normals.len() + 1);
        let mut entries = Vec::new();
        let mut weights = Vec::with_capacity(normals.len());
        start.push(0);
        for (p, &n) in normals.iter().enumerate() {
            variant.row(g, n, &mut entries);
            start.push(entries.len());
            let j = p / w;
            // The exact solid angle of a pixel of row j: (2π/W)(cos φ_j − cos φ_{j+1}).
            let edge = |k: usize| (std::f64::consts::PI * k as f64 / h as f64).cos();
            weights.push(if pixel_weights { 1.0 } else { std::f64::consts::TAU / w as f64 * (edge(j) - edge(j + 1)) });
        }
        let m = variant.functions();
        let mut gram = DMatrix::<f64>::zeros(m, m);
        let mut sh_moments = vec![[0.0; N_SH]; m];
        for (p, &n) in normals.iter().enumerate() {
            let row = &entries[start[p]..start[p + 1]];
            let y = sh_basis(n);
            for &(a, x) in row {
                for &(b, z) in row {
                    gram[(a as usize, b as usize)] += weights[p] * x * z;
                }
                for (q, yi) in sh_moments[a as usize].iter_mut().zip(y) {
                    *q += weights[p] * x * yi;
                }
            }
        }
        let matrix = match variant {
            Variant::Bezier | Variant::Srbf => gram,
            Variant::BezierYCoCg => {
                // Unknowns (y, co, cg); RGB error 3e_Y² + 2e_Co² + 3e_Cg² − 2e_Y·e_Cg.
                let bb = gram.view((0, 0), (36, 36));
                let bl = gram.view((0, 36), (36, 12));
                let ll = gram.view((36, 36), (12, 12));
                let mut n = DMatrix::<f64>::zeros(60, 60);
                n.view_mut((0, 0), (36, 36)).copy_from(&(bb * 3.0));
                n.view_mut((0, 48), (36, 12)).copy_from(&(-bl));
                n.view_mut((48, 0), (12, 36)).copy_from(&(-bl.transpose()));
                n.view_mut((36, 36), (12, 12)).copy_from(&(ll * 2.0));
                n.view_mut((48, 48), (12, 12)).copy_from(&(ll * 3.0));
                n
            }
        };
        debug_assert_eq!(matrix.nrows(), variant.unknowns());
        let normal = nalgebra::Cholesky::new(matrix).expect("the dice's normal matrix is positive definite (tested)");
        Design { start, entries, weights, normal, sh_moments }
    }

    /// The design of `variant` with the given weighting, built on first use.
    fn get(variant: Variant, pixel_weights: bool) -> &'static Design {
        static D: [OnceLock<Design>; 6] = [const { OnceLock::new() }; 6];
        let k = variant as usize * 2 + usize::from(pixel_weights);
        D[k].get_or_init(|| Design::new(variant, pixel_weights))
    }

    /// Moments Σ_p w_p φ_j(n_p) E(n_p) of the target, per scalar basis function.
    fn moments(&self, m: usize, target: &[Rgb], scale: f64) -> Vec<Rgb> {
        let mut out = vec![Rgb::ZERO; m];
        for (p, e) in target.iter().enumerate() {
            let e = *e / scale * self.weights[p];
            for &(j, x) in &self.entries[self.start[p]..self.start[p + 1]] {
                out[j as usize] += e * x;
            }
        }
        out
    }
}

/// A fitted dice: per vertex, RGB value and derivatives (Bézier), Y value and derivatives
/// plus Co and Cg values (Y/Co/Cg), or RGB lobe amplitudes (SRBF).
pub struct DiceFit {
    variant: Variant,
    /// Bézier: 36 RGB coefficients (3 per vertex). Y/Co/Cg: 36 Y in `.x`, then 12 (Co, Cg, 0).
    /// SRBF: 12 RGB amplitudes.
    coeffs: Vec<Rgb>,
}

impl Fitted for DiceFit {
    /// Per vertex i: the Bézier value f_i and derivatives g_i, h_i along its tangent t_i and
    /// bitangent s_i (RGB, or Y alone with linear Co_i, Cg_i), or the SRBF amplitude w_i; the
    /// vertices and frames are the dice's constants, listed derived (module docs).
    fn stored(&self) -> Stored {
        let g = geometry();
        let frame = "vertices v_i (derived entries vertex_i, the peer's icosahedron orientation) and, for the Bezier \
                     basis, the tangent t_i = normalize(Y x v_i) and bitangent s_i = v_i x t_i (entries t_i, s_i); \
                     the face of n is the one whose centre is nearest and its barycentrics b solve n = sum b_i v_i \
                     (ambient_dice.rs module docs, Iwanicki & Sloan 2017); world directions, +Y up (docs/conventions.md \
                     section 1)";
        let mut s = Stored::new(match self.variant {
            Variant::Bezier => format!(
                "E/pi(n) = the hybrid cubic Bezier triangle of n's face with corner values f_i and tangential \
                 derivatives g_i (along t_i), h_i (along s_i) per channel; {frame}"
            ),
            Variant::BezierYCoCg => format!(
                "Y(n) = the hybrid cubic Bezier triangle of n's face (corner values Y_f_i, derivatives Y_g_i, Y_h_i); \
                 Co(n) = sum b_i Co_i and Cg(n) = sum b_i Cg_i over the face; R = Y + Co - Cg, G = Y + Cg, \
                 B = Y - Co - Cg; {frame}"
            ),
            Variant::Srbf => format!(
                "E/pi(n) = sum_i w_i*(0.35*c_i^2 + 0.25*c_i^4), c_i = max(0, n.v_i) (the cosine SRBF lobes); {frame}"
            ),
        });
        match self.variant {
            Variant::Bezier => {
                for v in 0..12 {
                    for (slot, letter) in ["f", "g", "h"].into_iter().enumerate() {
                        s.rgb(format!("{letter}_{v}"), Unit::Irradiance, self.coeffs[3 * v + slot]);
                    }
                }
            }
            Variant::BezierYCoCg => {
                for v in 0..12 {
                    for (slot, letter) in ["f", "g", "h"].into_iter().enumerate() {
                        s.scalar(format!("Y_{letter}_{v}"), Unit::Irradiance, self.coeffs[3 * v + slot].x);
                    }
                }
                for v in 0..12 {
                    s.scalar(format!("Co_{v}"), Unit::Irradiance, self.coeffs[36 + v].x);
                }
                for v in 0..12 {
                    s.scalar(format!("Cg_{v}"), Unit::Irradiance, self.coeffs[36 + v].y);
                }
            }
            Variant::Srbf => {
                for v in 0..12 {
                    s.rgb(format!("w_{v}"), Unit::Irradiance, self.coeffs[v]);
                }
            }
        }
        for (v, p) in g.vertices.iter().enumerate() {
            s.push(Role::Derived, format!("vertex_{v}"), Unit::Direction, Value::Vector(*p));
        }
        if self.variant != Variant::Srbf {
            for (v, (t, b)) in g.frames.iter().enumerate() {
                s.push(Role::Derived, format!("t_{v}"), Unit::Direction, Value::Vector(*t));
                s.push(Role::Derived, format!("s_{v}"), Unit::Direction, Value::Vector(*b));
            }
        }
        s
    }
    fn irradiance(&self, n: DVec3) -> Rgb {
        let g = geometry();
        match self.variant {
            Variant::Bezier => {
                let (v, w) = g.bezier(n);
                let mut e = Rgb::ZERO;
                for (vi, wi) in v.iter().zip(&w) {
                    for (slot, ws) in wi.iter().enumerate() {
                        e += self.coeffs[3 * vi + slot] * *ws;
                    }
                }
                e
            }
            Variant::BezierYCoCg => {
                let (face, b) = g.locate(n);
                let w = bezier_weights(face, b);
                let (mut y, mut co, mut cg) = (0.0, 0.0, 0.0);
                for (i, &v) in face.vertices.iter().enumerate() {
                    for (slot, ws) in w[i].iter().enumerate() {
                        y += self.coeffs[3 * v + slot].x * ws;
                    }
                    co += self.coeffs[36 + v].x * b[i];
                    cg += self.coeffs[36 + v].y * b[i];
                }
                Rgb::new(y + co - cg, y + cg, y - co - cg)
            }
            Variant::Srbf => g.srbf(n).iter().zip(&self.coeffs).fold(Rgb::ZERO, |acc, (w, c)| acc + *c * *w),
        }
    }
}

/// The ambient dice encoder.
pub struct AmbientDiceEncoder {
    variant: Variant,
    pixel_weights: bool,
}

impl AmbientDiceEncoder {
    pub fn new(variant: Variant, pixel_weights: bool) -> Self {
        AmbientDiceEncoder { variant, pixel_weights }
    }

    /// The least-squares fit to E/π on the fitting grid (`target`, row-major, [`FIT_GRID`]).
    pub fn fit_target(&self, target: &[Rgb]) -> DiceFit {
        // Least squares is scale covariant: solve for the target divided by its largest
        // magnitude, so that a 1e-300 light does not underflow in the products below.
        let scale = target.iter().map(|e| e.abs().max_element()).fold(0.0, f64::max);
        if !(scale > 0.0 && scale.is_finite()) {
            return self.zero();
        }
        let design = Design::get(self.variant, self.pixel_weights);
        self.solve(design, &design.moments(self.variant.functions(), target, scale), scale)
    }

    /// The same fit when the target is the E/π of L2 SH `e` (the light of SH alone, where no
    /// radiance source is given): E/π = Σ_i e_i Y_i is linear in the nine coefficients, so the
    /// grid moments are `Design::sh_moments` times e, with no grid to evaluate (probe sets fit
    /// millions of these). Equal to [`AmbientDiceEncoder::fit_target`] of the grid to rounding
    /// (tested).
    pub fn fit_sh(&self, e: &Sh9) -> DiceFit {
        let scale = e.0.iter().map(|c| c.abs().max_element()).fold(0.0, f64::max);
        if !(scale > 0.0 && scale.is_finite()) {
            return self.zero();
        }
        let design = Design::get(self.variant, self.pixel_weights);
        let m: Vec<Rgb> = design
            .sh_moments
            .iter()
            .map(|q| q.iter().zip(&e.0).fold(Rgb::ZERO, |acc, (qi, ei)| acc + *ei / scale * *qi))
            .collect();
        self.solve(design, &m, scale)
    }

    fn zero(&self) -> DiceFit {
        DiceFit { variant: self.variant, coeffs: vec![Rgb::ZERO; self.variant.functions()] }
    }

    /// The coefficients from the moments of the target divided by `scale`.
    fn solve(&self, design: &Design, m: &[Rgb], scale: f64) -> DiceFit {
        let coeffs = match self.variant {
            Variant::Bezier | Variant::Srbf => {
                let mut out = vec![Rgb::ZERO; m.len()];
                for c in 0..3 {
                    let x = design.normal.solve(&DVector::from_iterator(m.len(), m.iter().map(|v| v[c])));
                    for (o, v) in out.iter_mut().zip(x.iter()) {
                        o[c] = v * scale;
                    }
                }
                out
            }
            Variant::BezierYCoCg => {
                // Right-hand side: Bᵀ(E_R + E_G + E_B), Lᵀ(E_R − E_B), Lᵀ(−E_R + E_G − E_B).
                let mut rhs = DVector::<f64>::zeros(60);
                for j in 0..36 {
                    rhs[j] = m[j].x + m[j].y + m[j].z;
                }
                for j in 0..12 {
                    let l = m[36 + j];
                    rhs[36 + j] = l.x - l.z;
                    rhs[48 + j] = -l.x + l.y - l.z;
                }
                let x = design.normal.solve(&rhs);
                let mut out = vec![Rgb::ZERO; 48];
                for j in 0..36 {
                    out[j] = Rgb::new(x[j] * scale, 0.0, 0.0);
                }
                for j in 0..12 {
                    out[36 + j] = Rgb::new(x[36 + j] * scale, x[48 + j] * scale, 0.0);
                }
                out
            }
        };
        if coeffs.iter().all(|c| c.is_finite()) {
            DiceFit { variant: self.variant, coeffs }
        } else {
            self.zero()
        }
    }
}

impl Encoder for AmbientDiceEncoder {
    fn id(&self) -> &str {
        self.variant.id()
    }
    fn stored_scalars(&self) -> usize {
        match self.variant {
            Variant::Bezier => 108,
            Variant::BezierYCoCg => 60,
            Variant::Srbf => 36,
        }
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        match input.radiance {
            Some(light) => {
                let (w, h) = FIT_GRID;
                Box::new(self.fit_target(&light.irradiance_latlong(w, h)))
            }
            // The fallback light of the visible SH alone (`FitInput::light`): its E/π is the
            // cosine-convolved SH, fitted in closed form.
            None => Box::new(self.fit_sh(&input.visible_sh.convolve_cosine())),
        }
    }
    /// The peer scores its dice unclamped (PEER.md).
    fn peer_clamps(&self) -> bool {
        false
    }
    /// Linear least squares of a target that scales with the input.
    fn is_scale_covariant(&self) -> bool {
        true
    }
    /// The Bézier basis (both variants using it) does not contain the constant, so with no
    /// usable direction it cannot match pure ambient: a constant is fitted to 4.1% at worst
    /// (module docs). The SRBF lobes sum to 1 and make no such exception.
    fn degrades_input(&self) -> bool {
        self.variant != Variant::Srbf
    }
}

fn weights_key(p: &mut Params) -> Result<bool> {
    let w = p.str_or("weights", "solid_angle")?;
    match w.as_str() {
        "solid_angle" => Ok(false),
        "pixel" => Ok(true),
        _ => bail!("key 'weights': expected 'solid_angle' or 'pixel', got '{w}'"),
    }
}

pub fn build_ambient_dice(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let pixel = weights_key(p)?;
    p.finish("ambient_dice")?;
    Ok(Box::new(AmbientDiceEncoder::new(Variant::Bezier, pixel)))
}
pub fn build_ambient_dice_ycocg(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let pixel = weights_key(p)?;
    p.finish("ambient_dice_ycocg")?;
    Ok(Box::new(AmbientDiceEncoder::new(Variant::BezierYCoCg, pixel)))
}
pub fn build_ambient_dice_srbf(p: &mut Params) -> Result<Box<dyn Encoder>> {
    let pixel = weights_key(p)?;
    p.finish("ambient_dice_srbf")?;
    Ok(Box::new(AmbientDiceEncoder::new(Variant::Srbf, pixel)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::sh::constant;
    use crate::math::test_rng::Rng;

    /// The icosahedron: 12 unit vertices, each with 5 neighbours at cos 1/√5; 20 faces, each
    /// vertex in 5; antipodal pairs (the peer's list holds each vertex's opposite).
    #[test]
    fn the_dice_is_an_icosahedron() {
        let g = geometry();
        assert_eq!(g.faces.len(), 20);
        for (i, v) in g.vertices.iter().enumerate() {
            assert!((v.length() - 1.0).abs() < 1e-15);
            let near = g.vertices.iter().filter(|w| (w.dot(*v) - 1.0 / 5f64.sqrt()).abs() < 1e-12).count();
            assert_eq!(near, 5, "vertex {i}");
            assert_eq!(g.faces.iter().filter(|f| f.vertices.contains(&i)).count(), 5);
            assert!(g.vertices.iter().any(|w| (*w + *v).length() < 1e-15));
            let (t, s) = g.frames[i];
            assert!(t.dot(*v).abs() < 1e-15 && (t.cross(s) - *v).length() < 1e-15);
        }
    }

    /// The face found for a direction is the one whose barycentrics are all ≥ 0 (independent
    /// criterion: n inside the cone of the face's vertices), and n = Σ b_i v_i; Σ b_i = 1 at a
    /// vertex and (1 + 2/√5)^(−1/2)·3 = 1.258 at a face centre.
    #[test]
    fn barycentrics_locate_and_reconstruct() {
        let g = geometry();
        let mut rng = Rng::new(3);
        for _ in 0..2000 {
            let n = rng.unit();
            let (face, b) = g.locate(n);
            let back: DVec3 = (0..3).map(|i| g.vertices[face.vertices[i]] * b[i]).sum();
            assert!((back - n).length() < 1e-14, "{n}");
            for f in &g.faces {
                let raw = f.dual.map(|r| r.dot(n));
                if raw.iter().all(|&x| x > 1e-12) {
                    assert_eq!(f.vertices, face.vertices, "{n}");
                }
            }
        }
        let (_, b) = g.locate(g.vertices[4]);
        assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        let f = &g.faces[7];
        let (_, b) = g.locate(f.centre);
        let want = 3.0 / (3.0 + 6.0 / 5f64.sqrt()).sqrt();
        assert!((b.iter().sum::<f64>() - want).abs() < 1e-14, "{b:?}");
    }

    /// D = (√5 − 1)/3 equals the peer's factor: its table gives 0.3504874 for the edge point of
    /// face {0, 4, 8} next to vertex 4 towards vertex 0, whose tangent in the peer is +X
    /// (`triDerivativeTangentFactors[0][2]`).
    #[test]
    fn edge_factor_is_the_peers() {
        let g = geometry();
        let d = (5f64.sqrt() - 1.0) / 3.0;
        assert!(((g.vertices[0] - g.vertices[4]).dot(DVec3::X) * d - 0.350_487_4).abs() < 1e-7);
        // And 0.2981424 for vertex 8 towards 0 along the peer's tangent (0.8506508, 0, −0.5257311).
        let t8 = DVec3::new(0.850_650_8, 0.0, -0.525_731_1);
        assert!(((g.vertices[0] - g.vertices[8]).dot(t8) * d - 0.298_142_4).abs() < 1e-7);
    }

    /// The Bézier basis interpolates: at vertex i it is 1 on f_i and 0 on every other
    /// coefficient (value and derivatives alike).
    #[test]
    fn bezier_interpolates_the_vertex_values() {
        let g = geometry();
        for (i, &v) in g.vertices.iter().enumerate() {
            let (ids, w) = g.bezier(v);
            for k in 0..3 {
                let want = if ids[k] == i { [1.0, 0.0, 0.0] } else { [0.0; 3] };
                for s in 0..3 {
                    assert!((w[k][s] - want[s]).abs() < 1e-14, "vertex {i}: {w:?}");
                }
            }
        }
    }

    /// The Bézier dice is continuous across edges: on a shared edge both faces give the same
    /// weights to the same coefficients (the opposite vertex gets 0).
    #[test]
    fn bezier_is_continuous_across_edges() {
        let g = geometry();
        let mut rng = Rng::new(9);
        let coeffs: Vec<f64> = (0..36).map(|_| rng.next()).collect();
        let value = |f: &Face, n: DVec3| {
            let b = f.dual.map(|r| r.dot(n).max(0.0));
            let w = bezier_weights(f, b);
            (0..3)
                .flat_map(|i| (0..3).map(move |s| (i, s)))
                .map(|(i, s)| coeffs[3 * f.vertices[i] + s] * w[i][s])
                .sum::<f64>()
        };
        let mut edges = 0;
        for (a, fa) in g.faces.iter().enumerate() {
            for fb in &g.faces[a + 1..] {
                let shared: Vec<usize> = fa.vertices.iter().copied().filter(|v| fb.vertices.contains(v)).collect();
                if shared.len() != 2 {
                    continue;
                }
                edges += 1;
                for t in [0.1, 0.37, 0.5, 0.9] {
                    let n = (g.vertices[shared[0]] * (1.0 - t) + g.vertices[shared[1]] * t).normalize();
                    let (x, y) = (value(fa, n), value(fb, n));
                    assert!((x - y).abs() < 1e-13, "edge {shared:?} at {t}: {x} vs {y}");
                }
            }
        }
        assert_eq!(edges, 30);
    }

    /// The SRBF lobes are a partition of unity (module docs: Σ(n·a)² = 2 and Σ(n·a)⁴ = 6/5 over
    /// the six vertex axes, a spherical 5-design).
    #[test]
    fn srbf_lobes_sum_to_one() {
        let g = geometry();
        let mut rng = Rng::new(5);
        for _ in 0..1000 {
            let n = rng.unit();
            let axes = &g.vertices[..];
            let s2: f64 = axes.iter().map(|a| a.dot(n).powi(2)).sum::<f64>() / 2.0;
            let s4: f64 = axes.iter().map(|a| a.dot(n).powi(4)).sum::<f64>() / 2.0;
            assert!((s2 - 2.0).abs() < 1e-13 && (s4 - 1.2).abs() < 1e-13, "{s2} {s4}");
            assert!((g.srbf(n).iter().sum::<f64>() - 1.0).abs() < 1e-14);
        }
    }

    /// The normal matrices of all three bases, both weightings, are positive definite (the
    /// Cholesky factorisation succeeds).
    #[test]
    fn normal_matrices_factor() {
        for v in [Variant::Bezier, Variant::BezierYCoCg, Variant::Srbf] {
            for pixel in [false, true] {
                let d = Design::get(v, pixel);
                assert_eq!(d.normal.l().nrows(), v.unknowns());
            }
        }
    }

    /// A target in the span is reproduced exactly: random coefficients' E/π on the grid, fitted,
    /// give the same function at random normals (to rounding), for all three variants and
    /// both weightings.
    #[test]
    fn functions_in_the_span_are_reproduced() {
        let mut rng = Rng::new(11);
        let normals = latlong_normals(FIT_GRID.0, FIT_GRID.1);
        for variant in [Variant::Bezier, Variant::BezierYCoCg, Variant::Srbf] {
            let m = variant.functions();
            let coeffs: Vec<Rgb> = (0..m)
                .map(|j| {
                    let c = Rgb::new(rng.next(), rng.next(), rng.next());
                    // Y/Co/Cg stores Y in x, then (Co, Cg, 0).
                    match variant {
                        Variant::BezierYCoCg if j < 36 => Rgb::new(c.x, 0.0, 0.0),
                        Variant::BezierYCoCg => Rgb::new(c.x, c.y, 0.0),
                        _ => c,
                    }
                })
                .collect();
            let truth = DiceFit { variant, coeffs };
            let target: Vec<Rgb> = normals.iter().map(|&n| truth.irradiance(n)).collect();
            for pixel in [false, true] {
                let fit = AmbientDiceEncoder::new(variant, pixel).fit_target(&target);
                for _ in 0..200 {
                    let n = rng.unit();
                    let (a, b) = (fit.irradiance(n), truth.irradiance(n));
                    assert!((a - b).abs().max_element() < 1e-10, "{variant:?} pixel={pixel} at {n}: {a} vs {b}");
                }
            }
        }
    }

    /// Constant light: the SRBF dice is exact (a partition of unity). The Bézier basis does not
    /// contain the constant: with every value 1 and every derivative 0 it is 1 at the vertices,
    /// 2b³(1 + 3/√5) = 0.951 at an edge's midpoint (b = (2 + 2/√5)^(−1/2)) and
    /// b³(3 + 18/√5 + 12a0 + 12(a1 + a2)/√5) = 0.938 at a face's centre (b = (3 + 6/√5)^(−1/2)),
    /// closed forms of the definition; so the least-squares fit of a constant misses by a few
    /// per cent (measured: 4.1% at worst, 1.65% RMS; the Y/Co/Cg variant on grey 1.68% RMS). The
    /// linear basis of Co and Cg misses a coloured constant by far more (measured: 28.7% at
    /// worst, 9.0% RMS on (0.5, 1, 2)). Errors relative, per channel, on a 256×128 grid.
    #[test]
    fn constant_light() {
        let g = geometry();
        let ones = DiceFit {
            variant: Variant::Bezier,
            coeffs: (0..36).map(|j| Rgb::splat(if j % 3 == 0 { 1.0 } else { 0.0 })).collect(),
        };
        let s5 = 5f64.sqrt();
        let b = 1.0 / (2.0 + 2.0 / s5).sqrt();
        let mid = (g.vertices[0] + g.vertices[4]).normalize();
        assert!((ones.irradiance(mid).x - 2.0 * b.powi(3) * (1.0 + 3.0 / s5)).abs() < 1e-14);
        let b = 1.0 / (3.0 + 6.0 / s5).sqrt();
        let (a0, a1, a2) = ((s5 - 5.0) / 40.0, (11.0 * s5 - 15.0) / 40.0, s5 / 10.0);
        let want = b.powi(3) * (3.0 + 18.0 / s5 + 12.0 * a0 + 12.0 * (a1 + a2) / s5);
        assert!((ones.irradiance(g.faces[3].centre).x - want).abs() < 1e-14, "{want}");
        assert!((want - 0.938).abs() < 5e-4, "{want}");

        let normals = latlong_normals(256, 128);
        let grid = crate::reference::domain::Domain::Sphere.output_grid((256, 128));
        // (variant, constant, worst and RMS relative error at most); a grey and a coloured one.
        let (grey, colour) = (Rgb::splat(0.7), Rgb::new(0.5, 1.0, 2.0));
        for (variant, a, worst_at_most, rms_at_most) in [
            (Variant::Srbf, colour, 1e-12, 1e-12),
            (Variant::Bezier, colour, 0.042, 0.017),
            (Variant::BezierYCoCg, grey, 0.042, 0.017),
            (Variant::BezierYCoCg, colour, 0.29, 0.091),
        ] {
            let f = AmbientDiceEncoder::new(variant, false).fit(&FitInput::sphere(&constant(a)));
            let rel: Vec<f64> = normals.iter().map(|&n| ((f.irradiance(n) - a) / a).abs().max_element()).collect();
            let worst = rel.iter().copied().fold(0.0, f64::max);
            let rms = (rel.iter().zip(&grid.weights).map(|(r, w)| r * r * w).sum::<f64>()
                / (4.0 * std::f64::consts::PI))
                .sqrt();
            eprintln!("{variant:?}: the constant {a} is fitted to {worst:e} at worst, {rms:e} RMS");
            assert!(worst < worst_at_most && rms < rms_at_most, "{variant:?} {a}: {worst} {rms}");
        }
    }

    /// Without a radiance source the target is the E/π of the visible SH, fitted in closed form
    /// from the nine coefficients: the same fit as from that light's E/π grid, to rounding.
    #[test]
    fn the_sh_path_equals_the_grid_path() {
        let mut rng = Rng::new(21);
        for variant in [Variant::Bezier, Variant::BezierYCoCg, Variant::Srbf] {
            for pixel in [false, true] {
                let e = AmbientDiceEncoder::new(variant, pixel);
                let sh = rng.sh();
                let light = crate::reference::radiance::ShLight::new(&sh);
                let grid = e.fit(&FitInput { radiance: Some(&light), ..FitInput::sphere(&sh) });
                let closed = e.fit(&FitInput::sphere(&sh));
                for _ in 0..100 {
                    let n = rng.unit();
                    let (a, b) = (grid.irradiance(n), closed.irradiance(n));
                    assert!((a - b).abs().max_element() < 1e-12, "{variant:?} {pixel}: {a} vs {b}");
                }
            }
        }
        let e = AmbientDiceEncoder::new(Variant::Bezier, false);
        assert_eq!(e.fit(&FitInput::sphere(&Sh9::ZERO)).irradiance(DVec3::X), Rgb::ZERO);
    }

    /// Black in, black out; a non-finite target gives black; k·target gives k·fit.
    #[test]
    fn degenerate_and_scaled_targets() {
        let n = latlong_normals(FIT_GRID.0, FIT_GRID.1).len();
        let mut rng = Rng::new(4);
        let target: Vec<Rgb> = (0..n).map(|_| Rgb::new(rng.uniform01(), rng.uniform01(), rng.uniform01())).collect();
        for variant in [Variant::Bezier, Variant::BezierYCoCg, Variant::Srbf] {
            let e = AmbientDiceEncoder::new(variant, false);
            let d = rng.unit();
            assert_eq!(e.fit_target(&vec![Rgb::ZERO; n]).irradiance(d), Rgb::ZERO);
            let mut bad = target.clone();
            bad[17] = Rgb::new(f64::NAN, 0.0, 0.0);
            assert_eq!(e.fit_target(&bad).irradiance(d), Rgb::ZERO);
            let one = e.fit_target(&target).irradiance(d);
            let scaled: Vec<Rgb> = target.iter().map(|v| *v * 1e-300).collect();
            let tiny = e.fit_target(&scaled).irradiance(d) / 1e-300;
            assert!((tiny - one).abs().max_element() < 1e-12 * one.abs().max_element(), "{variant:?}");
        }
    }

    /// The fitted E/π does not depend on the tangent frames: the same least-squares problem
    /// with every frame turned by 0.7 rad gives the same function (a small grid, solved here
    /// with nalgebra's SVD, independently of [`Design`]).
    #[test]
    fn tangent_frames_do_not_matter() {
        let normals = latlong_normals(32, 16);
        let target = |n: DVec3| (3.0 * n.x).sin() + n.y * n.z + 0.5;
        let fit = |g: &Geometry| {
            let rows: Vec<Vec<(u16, f64)>> = normals
                .iter()
                .map(|&n| {
                    let mut r = Vec::new();
                    Variant::Bezier.row(g, n, &mut r);
                    r
                })
                .collect();
            let mut a = DMatrix::<f64>::zeros(normals.len(), 36);
            for (p, r) in rows.iter().enumerate() {
                for &(j, x) in r {
                    a[(p, j as usize)] = x;
                }
            }
            let b = DVector::from_iterator(normals.len(), normals.iter().map(|&n| target(n)));
            let x = a.svd(true, true).solve(&b, 1e-12).unwrap();
            move |g: &Geometry, n: DVec3| {
                let mut r = Vec::new();
                Variant::Bezier.row(g, n, &mut r);
                r.iter().map(|&(j, w)| x[j as usize] * w).sum::<f64>()
            }
        };
        let (g0, g1) = (Geometry::new(0.0), Geometry::new(0.7));
        let (f0, f1) = (fit(&g0), fit(&g1));
        let mut rng = Rng::new(8);
        for _ in 0..200 {
            let n = rng.unit();
            assert!((f0(&g0, n) - f1(&g1, n)).abs() < 1e-9, "{n}");
        }
    }
}
