//! A variant's least-squares problem on the fitting grid (the ambient cube's 128×64 lat-long
//! pixel centres): the sparse basis rows, solid-angle or pixel weights, the normal matrix
//! Cholesky-factored once per process, and the moments of a target (or of the nine SH
//! functions, for fits from L2 SH alone).

use super::geometry::geometry;
use super::variant::Variant;
use crate::math::colour::Rgb;
use crate::math::sh::{basis as sh_basis, N_SH};
use crate::reference::radiance::latlong_normals;
use nalgebra::DMatrix;
use std::sync::OnceLock;

/// The fitting grid (lat-long pixel centres), the ambient cube's.
pub const FIT_GRID: (usize, usize) = crate::encoders::ambient_cube::FIT_GRID;

/// A variant's least-squares problem on the fitting grid: the basis at every grid normal
/// (sparse), the grid weights, and the factored normal matrix.
pub(super) struct Design {
    /// Row p's entries are `entries[start[p]..start[p + 1]]`.
    pub(super) start: Vec<usize>,
    pub(super) entries: Vec<(u16, f64)>,
    pub(super) weights: Vec<f64>,
    pub(super) normal: nalgebra::Cholesky<f64, nalgebra::Dyn>,
    /// Per scalar basis function j, Σ_p w_p φ_j(n_p) Y_i(n_p) for the nine SH functions Y_i.
    pub(super) sh_moments: Vec<[f64; N_SH]>,
}

impl Design {
    pub(super) fn new(variant: Variant, pixel_weights: bool) -> Self {
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
    pub(super) fn get(variant: Variant, pixel_weights: bool) -> &'static Design {
        static D: [OnceLock<Design>; 6] = [const { OnceLock::new() }; 6];
        let k = variant as usize * 2 + usize::from(pixel_weights);
        D[k].get_or_init(|| Design::new(variant, pixel_weights))
    }

    /// Moments Σ_p w_p φ_j(n_p) E(n_p) of the target, per scalar basis function.
    pub(super) fn moments(&self, m: usize, target: &[Rgb], scale: f64) -> Vec<Rgb> {
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
