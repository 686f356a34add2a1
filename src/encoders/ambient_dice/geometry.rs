//! The ambient dice's geometry (the peer's orientation; Iwanicki & Sloan 2017): the 12
//! icosahedron vertices with their tangent frames, the 20 faces, the face and barycentrics of
//! a normal, and the weights of the hybrid cubic Bézier, linear and cosine SRBF bases there.

use glam::DVec3;
use std::sync::OnceLock;

/// k = 1/φ = (√5 − 1)/2, the peer's `kT`.
pub(super) const K: f64 = 0.618_033_988_749_894_9;

/// The dice's geometry: vertices, tangent frames, faces.
pub struct Geometry {
    /// The 12 unit vertices, in the peer's order.
    pub vertices: [DVec3; 12],
    /// Each vertex's tangent t and bitangent s (t × s = v).
    pub frames: [(DVec3, DVec3); 12],
    /// The 20 triangular faces.
    pub faces: Vec<Face>,
}

/// One face: its vertices, the rows that give its barycentrics, its centre, and the edge
/// factors D·(v_j − v_i)·t_i, D·(v_j − v_i)·s_i of its six edge control points.
pub struct Face {
    /// Its three vertices, as indices into [`Geometry::vertices`].
    pub vertices: [usize; 3],
    /// b_i = dual[i]·n.
    pub(super) dual: [DVec3; 3],
    pub(super) centre: DVec3,
    /// For the edge points 0→1, 0→2, 1→0, 1→2, 2→0, 2→1: (tangent, bitangent) factors.
    pub(super) edge: [(f64, f64); 6],
}

/// The edge points of a face as (from, to), in the order of [`Face::edge`].
pub(super) const EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)];

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
pub(super) fn bezier_weights(face: &Face, b: [f64; 3]) -> [[f64; 3]; 3] {
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
