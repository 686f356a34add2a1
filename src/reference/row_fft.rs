//! The exact reference's row convolution by FFT, for a grid whose columns lie on the map's
//! lattice (FORMULAS §1; `row_convolution.rs` has the direct path and the problem).
//!
//! When the grid width w divides the map width W (p = W/w texels per column), output column i
//! is centred (i + ½)·p texels from θ = −π, and the input row's part of it is a circular
//! cross-correlation over the map's W cells: out[i] = Σₖ L[k]·κ[(k − i·p) mod W], with κ[m] the
//! clamped-cosine kernel integrated exactly over the cell m − p/2 … m + 1 − p/2 texels from the
//! column centre, summed over the row pair's polar nodes. κ is built from its primitive
//! F(u) = Σₙ wₙ·sign(u)·(aₙ sin min(|u|, Δₙ) + bₙ min(|u|, Δₙ)) at the W + 1 cell edges
//! (a = sin φₒ sin φ, b = cos φₒ cos φ, cos Δ = −b/a; F(u + 2π) = F(u) + F(π) − F(−π)), so every
//! cell integral is exact, as in the direct path; only the transforms round.
//!
//! Per input row its three channels' spectra are taken once; per row pair two kernels share one
//! complex transform (packed as real and imaginary parts), and their spectra multiply the row's
//! into the output rows' spectra, f = 0..W/2 (the rest is Hermitian). At the end each output
//! row's spectrum is folded to w frequencies (sampling every p-th lag: Σₗ Ŷ[f + l·w]) and
//! transformed back, two channels per inverse transform. Cost per row pair: ≈ 3W for the kernel,
//! half a complex FFT of W and 3·(W/2 + 1) complex multiply-adds, against 24·w per polar node
//! directly; so it is used only while W/w ≤ [`MAX_RATIO`] (benches/README.md).

use crate::envmap::moments::{RowMoments, RowPrefix};
use crate::envmap::LatLong;
use crate::math::colour::Rgb;
use crate::reference::row_pairs::{for_each_node, over_input_rows};
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};
use std::f64::consts::{FRAC_1_PI, PI};
use std::sync::Arc;

/// The largest W/w the FFT path takes. Its cost per row pair grows with W·log₂W, the direct
/// path's with w times the polar nodes (≈ 24·w·2.1 flops): by operation count the FFT is ahead
/// only at W = w (≈ 10k against 12.9k flops at 256; at W = 2w ≈ 21k), see benches/README.md.
pub(crate) const MAX_RATIO: usize = 1;

/// Whether the FFT path computes a map of width `map_width` onto a grid of width `out_width`.
pub(crate) fn applies(map_width: usize, out_width: usize) -> bool {
    out_width > 0 && map_width % out_width == 0 && map_width / out_width <= MAX_RATIO
}

/// One cell edge of the kernel's lattice: which distinct |u| it has, the sign of u, and
/// whether u was taken one turn back (then F gains one full-circle integral).
#[derive(Clone, Copy)]
struct Edge {
    at: usize,
    sign: f64,
    wraps: f64,
}

/// The transforms and the kernel's edge geometry for one map width against one grid width.
pub(crate) struct FftPlan {
    /// Map width W.
    width: usize,
    /// Grid width w.
    out_width: usize,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
    /// The W + 1 cell edges from the first column's centre.
    edges: Vec<Edge>,
    /// The distinct |u| of the edges, ascending, with their sines.
    offsets: Vec<(f64, f64)>,
}

impl FftPlan {
    /// The plan for W = `width` onto w = `out_width` ([`applies`] must hold).
    pub(crate) fn new(width: usize, out_width: usize) -> Self {
        let p = width / out_width;
        // Edge e is u = (2e − p)·π/W from the first column's centre: integers v = 2e − p in
        // half texels, taken into (−W, W] (one turn back beyond π).
        let half = PI / width as f64;
        let vs: Vec<(i64, bool)> = (0..=width as i64)
            .map(|e| {
                let v = 2 * e - p as i64;
                if v > width as i64 {
                    (v - 2 * width as i64, true)
                } else {
                    (v, false)
                }
            })
            .collect();
        let mut abs: Vec<i64> = vs.iter().map(|&(v, _)| v.abs()).collect();
        abs.sort_unstable();
        abs.dedup();
        let edges = vs
            .iter()
            .map(|&(v, wrapped)| Edge {
                at: abs.binary_search(&v.abs()).unwrap_or(0),
                sign: if v < 0 { -1.0 } else { 1.0 },
                wraps: if wrapped { 1.0 } else { 0.0 },
            })
            .collect();
        // |u| = π at v = W: its sine is 0 exactly, not sin(π) rounded.
        let offsets = abs
            .iter()
            .map(|&v| if v == width as i64 { (PI, 0.0) } else { (v as f64 * half, (v as f64 * half).sin()) })
            .collect();
        let mut planner = FftPlanner::new();
        let (forward, inverse) = (planner.plan_fft_forward(width), planner.plan_fft_inverse(out_width));
        FftPlan { width, out_width, forward, inverse, edges, offsets }
    }

    /// Spectrum length kept per channel, W/2 + 1.
    fn bins(&self) -> usize {
        self.width / 2 + 1
    }
}

/// One polar node's kernel on a parallel: weight·(a cos u + b) over |u| < Δ.
#[derive(Clone, Copy)]
struct Node {
    delta: f64,
    sin: f64,
    wa: f64,
    wb: f64,
}

/// What a chunk of input rows keeps: the output rows' spectra and its work buffers.
struct Work {
    /// Per output row, per channel, the W/2 + 1 bins of Ŷ.
    acc: Vec<Complex64>,
    prefix: RowPrefix,
    /// The input row's three spectra, W/2 + 1 bins each.
    row: Vec<Complex64>,
    buf: Vec<Complex64>,
    scratch: Vec<Complex64>,
    nodes: Vec<Node>,
    g: Vec<f64>,
    kernels: [Vec<f64>; 2],
}

/// Convolves every input row into the output rows `rows_out` of `values` (E/π, row-major), by
/// FFT; `stop` as in `row_pairs::over_input_rows`.
pub(crate) fn convolve(
    moments: &RowMoments,
    rule: &[(f64, f64)],
    out: LatLong,
    plan: &FftPlan,
    rows_out: &[usize],
    values: &mut [Rgb],
    stop: &(dyn Fn() -> bool + Sync),
) {
    let (bins, w) = (plan.bins(), plan.width);
    let scratch_len = plan.forward.get_inplace_scratch_len().max(plan.inverse.get_inplace_scratch_len());
    let new = || Work {
        acc: vec![Complex64::default(); rows_out.len() * 3 * bins],
        prefix: RowPrefix::new(),
        row: vec![Complex64::default(); 3 * bins],
        buf: vec![Complex64::default(); w],
        scratch: vec![Complex64::default(); scratch_len],
        nodes: Vec::new(),
        g: vec![0.0; plan.offsets.len()],
        kernels: [vec![0.0; w], vec![0.0; w]],
    };
    let rows = moments.height();
    let add = |work: &mut Work, j: usize| {
        moments.fill(j, &mut work.prefix);
        row_spectra(plan, work);
        let polar = (PI * j as f64 / rows as f64, PI * (j + 1) as f64 / rows as f64);
        for (pair, acc) in rows_out.chunks(2).zip(work.acc.chunks_mut(2 * 3 * bins)) {
            let mut any = false;
            for (k, &jo) in pair.iter().enumerate() {
                work.nodes.clear();
                for_each_node(rule, out.phi_centre(jo), polar, |a, b, ws, t| work.nodes.push(node(a, b, ws, t)));
                any |= plan.kernel(&mut work.nodes, &mut work.g, &mut work.kernels[k]);
            }
            if any {
                add_pair(plan, work.buf.as_mut_slice(), &mut work.scratch, &work.kernels, pair.len(), &work.row, acc);
            }
        }
    };
    let partials = over_input_rows(moments, new, add, stop);
    let mut total = vec![Complex64::default(); rows_out.len() * 3 * bins];
    for p in &partials {
        for (t, v) in total.iter_mut().zip(&p.acc) {
            *t += v;
        }
    }
    let mut buf = vec![Complex64::default(); plan.out_width];
    let mut scratch = vec![Complex64::default(); scratch_len];
    for (&jo, spectra) in rows_out.iter().zip(total.chunks_exact(3 * bins)) {
        let row = &mut values[jo * out.width..][..out.width];
        back(plan, spectra, &mut buf, &mut scratch, row);
    }
}

/// A polar node from its kernel a·cos + b, weight `ws` and threshold t = cos Δ (t ≤ −1: the
/// whole circle).
fn node(a: f64, b: f64, ws: f64, t: f64) -> Node {
    let (delta, sin) = if t <= -1.0 { (PI, 0.0) } else { (t.acos(), ((1.0 - t) * (1.0 + t)).sqrt()) };
    Node { delta, sin, wa: ws * a, wb: ws * b }
}

impl FftPlan {
    /// Fills `kernel` with κ[m], m = 0..W, from the row pair's `nodes`; false (and `kernel`
    /// zero) when there are none. `g` is work space: G(|u|) at the distinct offsets.
    fn kernel(&self, nodes: &mut [Node], g: &mut [f64], kernel: &mut [f64]) -> bool {
        if nodes.is_empty() {
            kernel.fill(0.0);
            return false;
        }
        nodes.sort_by(|x, y| x.delta.total_cmp(&y.delta));
        // G(x) = Σ over nodes with Δ > x of (wa sin x + wb x), plus Σ over the others of
        // (wa sin Δ + wb Δ): sweep x upwards, nodes dropping out as x passes their Δ.
        let mut d = 0;
        let mut closed = 0.0;
        for (n, node) in nodes.iter().enumerate() {
            let (wa, wb) = nodes[n..].iter().fold((0.0, 0.0), |(a, b), o| (a + o.wa, b + o.wb));
            while d < g.len() && self.offsets[d].0 < node.delta {
                let (x, s) = self.offsets[d];
                g[d] = (wa * s + wb * x) + closed;
                d += 1;
            }
            closed += node.wa * node.sin + node.wb * node.delta;
        }
        g[d..].fill(closed);
        // F(π) − F(−π) = 2·closed: the whole circle.
        let turn = 2.0 * closed;
        let f = |e: &Edge| e.sign * g[e.at] + e.wraps * turn;
        let mut left = f(&self.edges[0]);
        for (k, e) in kernel.iter_mut().zip(&self.edges[1..]) {
            let right = f(e);
            *k = right - left;
            left = right;
        }
        true
    }
}

/// The three channels' spectra of the input row in `work.prefix`, into `work.row` (channels 0
/// and 1 packed in one transform).
fn row_spectra(plan: &FftPlan, work: &mut Work) {
    let (w, bins) = (plan.width, plan.bins());
    for (k, z) in work.buf.iter_mut().enumerate() {
        let t = work.prefix.texel(k);
        *z = Complex64::new(t.x, t.y);
    }
    plan.forward.process_with_scratch(&mut work.buf, &mut work.scratch);
    let (c01, c2) = work.row.split_at_mut(2 * bins);
    let (c0, c1) = c01.split_at_mut(bins);
    for f in 0..bins {
        let (x, y) = unpack(&work.buf, f, w);
        c0[f] = x;
        c1[f] = y;
    }
    for (k, z) in work.buf.iter_mut().enumerate() {
        *z = Complex64::new(work.prefix.texel(k).z, 0.0);
    }
    plan.forward.process_with_scratch(&mut work.buf, &mut work.scratch);
    c2.copy_from_slice(&work.buf[..bins]);
}

/// The spectra of the two real sequences packed as Z = x + i·y, at bin f of W.
#[inline]
fn unpack(z: &[Complex64], f: usize, w: usize) -> (Complex64, Complex64) {
    let (a, b) = (z[f], z[(w - f) % w].conj());
    ((a + b) * 0.5, (a - b) * Complex64::new(0.0, -0.5))
}

/// Transforms the pair's kernels (`count` of them, 1 or 2) together and adds the input row's
/// spectra times their conjugates to the pair's output rows in `acc`.
fn add_pair(
    plan: &FftPlan,
    buf: &mut [Complex64],
    scratch: &mut [Complex64],
    kernels: &[Vec<f64>; 2],
    count: usize,
    row: &[Complex64],
    acc: &mut [Complex64],
) {
    let (w, bins) = (plan.width, plan.bins());
    for (m, z) in buf.iter_mut().enumerate() {
        let im = if count == 2 { kernels[1][m] } else { 0.0 };
        *z = Complex64::new(kernels[0][m], im);
    }
    plan.forward.process_with_scratch(buf, scratch);
    let (acc0, acc1) = acc.split_at_mut((3 * bins).min(acc.len()));
    for f in 0..bins {
        let (k0, k1) = unpack(buf, f, w);
        let (k0, k1) = (k0.conj(), k1.conj());
        for ch in 0..3 {
            let l = row[ch * bins + f];
            acc0[ch * bins + f] += l * k0;
            if count == 2 {
                acc1[ch * bins + f] += l * k1;
            }
        }
    }
}

/// One output row from its three channels' spectra Ŷ (W/2 + 1 bins each): folded to the grid's
/// w bins (out[i] = Y[i·p]), transformed back (channels 0 and 1 together), scaled by 1/(W·π).
fn back(plan: &FftPlan, spectra: &[Complex64], buf: &mut [Complex64], scratch: &mut [Complex64], row: &mut [Rgb]) {
    let (w, bins, n) = (plan.width, plan.bins(), plan.out_width);
    // Ŷ at any bin of W, from the kept half by Hermitian symmetry.
    let full = |ch: usize, f: usize| {
        let s = &spectra[ch * bins..][..bins];
        if f < bins {
            s[f]
        } else {
            s[w - f].conj()
        }
    };
    let fold = |ch: usize, f: usize| (0..w / n).map(|l| full(ch, f + l * n)).sum::<Complex64>();
    let scale = FRAC_1_PI / w as f64;
    for (f, z) in buf.iter_mut().enumerate() {
        *z = fold(0, f) + fold(1, f) * Complex64::new(0.0, 1.0);
    }
    plan.inverse.process_with_scratch(buf, scratch);
    for (v, z) in row.iter_mut().zip(buf.iter()) {
        v.x = (z.re * scale).max(0.0);
        v.y = (z.im * scale).max(0.0);
    }
    for (f, z) in buf.iter_mut().enumerate() {
        *z = fold(2, f);
    }
    plan.inverse.process_with_scratch(buf, scratch);
    for (v, z) in row.iter_mut().zip(buf.iter()) {
        v.z = (z.re * scale).max(0.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::envmap::EnvMap;
    use crate::math::quadrature::gauss_legendre;
    use crate::reference::exact::Reference;

    /// Every output row by FFT against the per-normal path (each normal integrated on its own
    /// from the row moments, no transform), at W/w = 1 to 6 (column centres on cell centres and
    /// on cell edges; odd and even grid widths; a one-column grid), whether or not
    /// [`applies`] would pick the FFT for that size.
    #[test]
    fn fft_rows_equal_the_per_normal_path() {
        let map_of = |w: usize, h: usize| {
            EnvMap::from_fn("t", w, h, move |i, j| {
                let v = ((i * 7 + j * 3) % 11) as f32 * 0.5 + 0.1;
                [v, if i == w / 3 && j == h / 4 { 900.0 } else { 0.0 }, (j as f32 + 1.0).recip()]
            })
            .unwrap()
        };
        for (mw, mh, ow, oh) in [
            (48, 24, 48, 24),
            (48, 24, 24, 13),
            (42, 21, 14, 8),
            (40, 20, 10, 9),
            (30, 15, 6, 4),
            (42, 21, 7, 4),
            (10, 5, 10, 5),
            (6, 3, 1, 3),
        ] {
            let map = map_of(mw, mh);
            let rm = RowMoments::new(&map);
            let rule = gauss_legendre(2);
            let out = LatLong::new(ow, oh);
            let plan = FftPlan::new(mw, ow);
            let mut fast = vec![Rgb::ZERO; ow * oh];
            let rows: Vec<usize> = (0..oh).collect();
            convolve(&rm, &rule, out, &plan, &rows, &mut fast, &|| false);
            let r = Reference::new(&rm, vec![], 2);
            let top = fast.iter().map(|v| v.max_element()).fold(0.0, f64::max);
            for j in 0..oh {
                for i in 0..ow {
                    let want = r.irradiance(out.direction(i, j));
                    let d = (fast[j * ow + i] - want).abs().max_element();
                    assert!(d <= 1e-12 * top, "{mw}x{mh} onto {ow}x{oh} ({i},{j}): {} vs {want}", fast[j * ow + i]);
                }
            }
        }
    }

    /// The rule: the FFT where the grid width divides the map's at most [`MAX_RATIO`] times.
    #[test]
    fn applies_where_the_columns_are_on_the_lattice() {
        assert!(applies(256, 256) && applies(7, 7) && applies(256 * MAX_RATIO, 256));
        assert!(!applies(1000, 256) && !applies(256, 512) && !applies(256 * (MAX_RATIO + 1), 256) && !applies(4, 0));
    }
}
