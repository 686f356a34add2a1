//! The exact reference's row convolution by FFT, for a grid whose columns are the map's
//! (W = w; FORMULAS §1; `row_convolution.rs` has the direct path and the problem).
//!
//! Output column i is centred on map cell i, and the input row's part of it is a circular
//! cross-correlation over the map's W cells: out[i] = Σₖ L[k]·κ[(k − i) mod W], with κ[m] the
//! clamped-cosine kernel integrated exactly over the cell m − ½ … m + ½ texels from the column
//! centre, summed over the row pair's polar nodes. κ is built from its primitive
//! F(u) = Σₙ wₙ·sign(u)·(aₙ sin min(|u|, Δₙ) + bₙ min(|u|, Δₙ)) at the cell edges
//! (a = sin φₒ sin φ, b = cos φₒ cos φ, cos Δ = −b/a), so every cell integral is exact, as in
//! the direct path; only the transforms round. The kernel is even (κ[m] = κ[W − m]: the cosine
//! is even about the column centre, which is a cell centre), so it is G(|u|) = F(|u|) at the
//! ⌊W/2⌋ edges below π, differenced, and mirrored; and its spectrum K̂ is real, so the
//! correlation's Ŷ = L̂·conj(K̂) is L̂·K̂, two real products a bin.
//!
//! Every input row's three channels' spectra are taken once, first. Then each pair of output
//! rows is one task: per input row, in order, the two output rows' kernels share one complex
//! transform (as real and imaginary parts, which are their two real spectra), and those multiply
//! the input row's into the pair's spectra, f = 0..W/2 (the rest is Hermitian); at the end the
//! task transforms its two rows back, two channels per inverse transform. A task's sums stay in
//! its own few kilobytes (no partial sums per chunk of input rows to allocate, fault in and
//! add up), and the order of every sum is fixed whatever the thread count. Cost per row pair:
//! ≈ W for the kernel, half a complex FFT of W and 3·(W/2 + 1) complex-by-real multiply-adds,
//! against 24·w per polar node directly (benches/README.md). The per-pair work is compiled
//! twice, for baseline x86-64 and with AVX2 (`row_pairs::has_avx2`).

use crate::envmap::moments::{RowMoments, RowPrefix};
use crate::envmap::{LatLong, PROGRESS_WIDTH};
use crate::io::progress::Progress;
use crate::math::colour::Rgb;
use crate::reference::row_pairs::for_each_node;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};
use std::f64::consts::{FRAC_1_PI, PI};
use std::sync::Arc;

/// Whether the FFT path computes a map of width `map_width` onto a grid of width `out_width`:
/// only at W = w. Elsewhere the columns either leave the map's lattice (one transform per gcd
/// class) or, at W = k·w, the transform of W costs more than w columns directly (benches/README.md).
pub(crate) fn applies(map_width: usize, out_width: usize) -> bool {
    out_width > 0 && map_width == out_width
}

/// The transforms and the kernel's edge geometry for one width W = w.
pub(crate) struct FftPlan {
    /// Map and grid width W.
    width: usize,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
    /// The cell edges' |u| below π, xₔ = (2d + 1)·π/W for d = 0..⌊W/2⌋, ascending.
    xs: Vec<f64>,
    /// Their sines.
    sins: Vec<f64>,
}

impl FftPlan {
    /// The plan for a map and grid of width `width`.
    pub(crate) fn new(width: usize) -> Self {
        let half = PI / width as f64;
        let xs: Vec<f64> = (0..width / 2).map(|d| (2 * d + 1) as f64 * half).collect();
        let sins = xs.iter().map(|x| x.sin()).collect();
        let mut planner = FftPlanner::new();
        let (forward, inverse) = (planner.plan_fft_forward(width), planner.plan_fft_inverse(width));
        FftPlan { width, forward, inverse, xs, sins }
    }

    /// Spectrum length kept per channel, W/2 + 1.
    fn bins(&self) -> usize {
        self.width / 2 + 1
    }

    /// Scratch length of both transforms.
    fn scratch_len(&self) -> usize {
        self.forward.get_inplace_scratch_len().max(self.inverse.get_inplace_scratch_len())
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

/// A task's work buffers (one task: an output row pair against every input row). Spectra of
/// real sequences are kept as bins f = 0..W/2, real and imaginary parts interleaved.
struct Work {
    /// Per output row of the pair, per channel, the spectrum Ŷ.
    acc: Vec<f64>,
    buf: Vec<Complex64>,
    scratch: Vec<Complex64>,
    nodes: Vec<Node>,
    /// G at the edges below π and one beyond.
    g: Vec<f64>,
    /// The pair's two half-kernels κ[0..=⌊W/2⌋].
    halves: [Vec<f64>; 2],
    /// The pair's two real kernel spectra, each value twice (for a bin's real and imaginary parts).
    spectra: [Vec<f64>; 2],
}

impl Work {
    fn new(plan: &FftPlan) -> Self {
        let (bins, edges) = (plan.bins(), plan.xs.len() + 1);
        Work {
            acc: vec![0.0; 2 * ROW * bins],
            buf: vec![Complex64::default(); plan.width],
            scratch: vec![Complex64::default(); plan.scratch_len()],
            nodes: Vec::new(),
            g: vec![0.0; edges],
            halves: [vec![0.0; edges], vec![0.0; edges]],
            spectra: [vec![0.0; 2 * bins], vec![0.0; 2 * bins]],
        }
    }
}

/// Reals a row's three spectra take, per bin: 3 channels × (real, imaginary).
const ROW: usize = 3 * 2;

/// Convolves every input row into the output rows `rows_out` of `values` (E/π, row-major), by
/// FFT: the input rows' spectra are taken once, then each pair of output rows is one task on
/// the thread pool, which sums its spectra over the input rows in order (so the values do not
/// depend on the thread count) and transforms them back. `stop` is checked before each input
/// row: once it says stop, the values mean nothing (the caller discards them). The per-pair work
/// is compiled for AVX2 when `avx2` (`row_pairs::has_avx2` must have said so).
#[allow(clippy::too_many_arguments)]
pub(crate) fn convolve(
    moments: &RowMoments,
    rule: &[(f64, f64)],
    out: LatLong,
    plan: &FftPlan,
    rows_out: &[usize],
    values: &mut [Rgb],
    stop: &(dyn Fn() -> bool + Sync),
    avx2: bool,
) {
    let inputs = input_spectra(moments, plan, stop);
    let w = plan.width;
    let pairs = rows_out.chunks(2).len();
    let progress = (w >= PROGRESS_WIDTH).then(|| Progress::new(pairs as u64, "exact reference"));
    let rows: Vec<Vec<Rgb>> = rows_out
        .par_chunks(2)
        .map_init(
            || Work::new(plan),
            |work, rows| {
                let pair = OutputPair { plan, rule, out, rows, inputs: &inputs, height: moments.height() };
                add_input_rows(&pair, work, stop, avx2);
                let mut values = vec![Rgb::ZERO; rows.len() * w];
                for (row, spectra) in values.chunks_exact_mut(w).zip(work.acc.chunks_exact(ROW * plan.bins())) {
                    back(plan, spectra, &mut work.buf, &mut work.scratch, row);
                }
                if let Some(p) = &progress {
                    p.inc();
                }
                values
            },
        )
        .collect();
    for (&jo, row) in rows_out.iter().zip(rows.iter().flat_map(|r| r.chunks_exact(w))) {
        values[jo * out.width..][..out.width].copy_from_slice(row);
    }
}

/// Every input row's three spectra ([`row_spectra`]), row after row, `ROW`·(W/2 + 1) reals a
/// row, taken in parallel; left zero from where `stop` said stop.
fn input_spectra(moments: &RowMoments, plan: &FftPlan, stop: &(dyn Fn() -> bool + Sync)) -> Vec<f64> {
    let len = ROW * plan.bins();
    let mut spectra = vec![0.0; moments.height() * len];
    let init =
        || (RowPrefix::new(), vec![Complex64::default(); plan.width], vec![Complex64::default(); plan.scratch_len()]);
    spectra.par_chunks_mut(len).enumerate().for_each_init(init, |(prefix, buf, scratch), (j, row)| {
        if !stop() {
            moments.fill(j, prefix);
            row_spectra(plan, prefix, buf, scratch, row);
        }
    });
    spectra
}

/// One or two output rows against every input row.
struct OutputPair<'a> {
    plan: &'a FftPlan,
    rule: &'a [(f64, f64)],
    out: LatLong,
    /// The output rows (one or two).
    rows: &'a [usize],
    /// Every input row's spectra ([`input_spectra`]).
    inputs: &'a [f64],
    /// The map's rows.
    height: usize,
}

/// [`add_input_rows`], its loops compiled for AVX2 when `avx2`.
fn add_input_rows(pair: &OutputPair, work: &mut Work, stop: &(dyn Fn() -> bool + Sync), avx2: bool) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` is true only where the CPU has AVX2 (`row_pairs::has_avx2`).
        unsafe { add_input_rows_avx2(pair, work, stop) };
        return;
    }
    let _ = avx2;
    add_input_rows_portable(pair, work, stop);
}

/// [`add_input_rows_portable`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn add_input_rows_avx2(pair: &OutputPair, work: &mut Work, stop: &(dyn Fn() -> bool + Sync)) {
    add_input_rows_portable(pair, work, stop);
}

/// Sets `work.acc` to the pair's output spectra: Σ over the input rows j, in order, of
/// L̂ⱼ·K̂ⱼ,ⱼₒ for each output row jₒ of the pair.
#[inline(always)]
fn add_input_rows_portable(pair: &OutputPair, work: &mut Work, stop: &(dyn Fn() -> bool + Sync)) {
    let plan = pair.plan;
    let row_len = ROW * plan.bins();
    work.acc.fill(0.0);
    for (j, row) in pair.inputs.chunks_exact(row_len).enumerate() {
        if stop() {
            break;
        }
        let polar = (PI * j as f64 / pair.height as f64, PI * (j + 1) as f64 / pair.height as f64);
        let mut any = false;
        for (k, &jo) in pair.rows.iter().enumerate() {
            work.nodes.clear();
            for_each_node(pair.rule, pair.out.phi_centre(jo), polar, |a, b, ws, t| work.nodes.push(node(a, b, ws, t)));
            any |= plan.kernel(&mut work.nodes, &mut work.g, &mut work.halves[k]);
        }
        if any {
            pair_spectra(plan, &mut work.buf, &mut work.scratch, &work.halves, pair.rows.len(), &mut work.spectra);
            let (acc0, acc1) = work.acc.split_at_mut(row_len);
            multiply_add(row, &work.spectra[0], acc0);
            if pair.rows.len() == 2 {
                multiply_add(row, &work.spectra[1], acc1);
            }
        }
    }
}

/// A polar node from its kernel a·cos + b, weight `ws` and threshold t = cos Δ (t ≤ −1: the
/// whole circle).
#[inline(always)]
fn node(a: f64, b: f64, ws: f64, t: f64) -> Node {
    let (delta, sin) = if t <= -1.0 { (PI, 0.0) } else { (t.acos(), ((1.0 - t) * (1.0 + t)).sqrt()) };
    Node { delta, sin, wa: ws * a, wb: ws * b }
}

impl FftPlan {
    /// Fills `half` with κ[m], m = 0..=⌊W/2⌋ (κ[W − m] = κ[m]), from the row pair's `nodes`;
    /// false (and `half` zero) when there are none. `g` is work space: G(xₔ) at the edges below
    /// π, and one beyond.
    #[inline(always)]
    fn kernel(&self, nodes: &mut [Node], g: &mut [f64], half: &mut [f64]) -> bool {
        if nodes.is_empty() {
            half.fill(0.0);
            return false;
        }
        nodes.sort_by(|x, y| x.delta.total_cmp(&y.delta));
        // G(x) = Σ over nodes with Δ > x of (wa sin x + wb x), plus Σ over the others of
        // (wa sin Δ + wb Δ): x upwards, nodes dropping out as x passes their Δ.
        let n = self.xs.len();
        let mut d = 0;
        let mut closed = 0.0;
        for (k, node) in nodes.iter().enumerate() {
            let (wa, wb) = nodes[k..].iter().fold((0.0, 0.0), |(a, b), o| (a + o.wa, b + o.wb));
            let end = d + self.xs[d..].partition_point(|&x| x < node.delta);
            for ((g, &x), &s) in g[d..end].iter_mut().zip(&self.xs[d..end]).zip(&self.sins[d..end]) {
                *g = (wa * s + wb * x) + closed;
            }
            d = end;
            closed += node.wa * node.sin + node.wb * node.delta;
        }
        g[d..n].fill(closed);
        // The edge after the last one below π: π itself (W odd, F(π) = closed), or π + π/W
        // (W even: F(π + y) = F(π) + F(π) − F(π − y), the whole circle's integral being 2·closed).
        g[n] = if self.width % 2 == 1 { closed } else { 2.0 * closed - g[n - 1] };
        // κ[0] spans −x₀ … x₀: G(x₀) − (−G(x₀)); κ[m] spans xₘ₋₁ … xₘ.
        half[0] = 2.0 * g[0];
        for ((h, &hi), &lo) in half[1..=n].iter_mut().zip(&g[1..=n]).zip(&g[..n]) {
            *h = hi - lo;
        }
        true
    }
}

/// The three channels' spectra of the input row in `prefix`, into `row` (`ROW`·(W/2 + 1)
/// reals; channels 0 and 1 packed in one transform).
fn row_spectra(plan: &FftPlan, prefix: &RowPrefix, buf: &mut [Complex64], scratch: &mut [Complex64], row: &mut [f64]) {
    let (w, bins) = (plan.width, plan.bins());
    for (k, z) in buf.iter_mut().enumerate() {
        let t = prefix.texel(k);
        *z = Complex64::new(t.x, t.y);
    }
    plan.forward.process_with_scratch(buf, scratch);
    let (c01, c2) = row.split_at_mut(4 * bins);
    let (c0, c1) = c01.split_at_mut(2 * bins);
    for f in 0..bins {
        let (x, y) = unpack(buf, f, w);
        (c0[2 * f], c0[2 * f + 1]) = (x.re, x.im);
        (c1[2 * f], c1[2 * f + 1]) = (y.re, y.im);
    }
    for (k, z) in buf.iter_mut().enumerate() {
        *z = Complex64::new(prefix.texel(k).z, 0.0);
    }
    plan.forward.process_with_scratch(buf, scratch);
    for (c, z) in c2.chunks_exact_mut(2).zip(&buf[..bins]) {
        (c[0], c[1]) = (z.re, z.im);
    }
}

/// The spectra of the two real sequences packed as Z = x + i·y, at bin f of W.
#[inline(always)]
fn unpack(z: &[Complex64], f: usize, w: usize) -> (Complex64, Complex64) {
    let (a, b) = (z[f], z[(w - f) % w].conj());
    ((a + b) * 0.5, (a - b) * Complex64::new(0.0, -0.5))
}

/// The real spectra of the pair's kernels (`count` of them, 1 or 2) from their halves, both in
/// one transform (κ₀ + i·κ₁: both spectra are real, so they are its real and imaginary parts),
/// into `spectra`, each value twice.
#[inline(always)]
fn pair_spectra(
    plan: &FftPlan,
    buf: &mut [Complex64],
    scratch: &mut [Complex64],
    halves: &[Vec<f64>; 2],
    count: usize,
    spectra: &mut [Vec<f64>; 2],
) {
    // κ[m] for m ≤ W/2, then κ[W − m] mirrored: straight loops, no index folding per value.
    let (low, high) = buf.split_at_mut(plan.width / 2 + 1);
    let n = high.len();
    let [h0, h1] = halves;
    if count == 2 {
        for ((z, &re), &im) in low.iter_mut().zip(h0).zip(h1) {
            *z = Complex64::new(re, im);
        }
        for ((z, &re), &im) in high.iter_mut().zip(h0[1..=n].iter().rev()).zip(h1[1..=n].iter().rev()) {
            *z = Complex64::new(re, im);
        }
    } else {
        for (z, &re) in low.iter_mut().zip(h0) {
            *z = Complex64::new(re, 0.0);
        }
        for (z, &re) in high.iter_mut().zip(h0[1..=n].iter().rev()) {
            *z = Complex64::new(re, 0.0);
        }
    }
    plan.forward.process_with_scratch(buf, scratch);
    let [s0, s1] = spectra;
    for ((k0, k1), z) in s0.chunks_exact_mut(2).zip(s1.chunks_exact_mut(2)).zip(buf.iter()) {
        (k0[0], k0[1]) = (z.re, z.re);
        (k1[0], k1[1]) = (z.im, z.im);
    }
}

/// Ŷ += L̂·K̂ for each of the row's three channel spectra (`row`) against one real kernel
/// spectrum (`spectrum`, each value twice): one multiply-add per real number.
#[inline(always)]
fn multiply_add(row: &[f64], spectrum: &[f64], acc: &mut [f64]) {
    for (l, a) in row.chunks_exact(spectrum.len()).zip(acc.chunks_exact_mut(spectrum.len())) {
        for ((a, l), k) in a.iter_mut().zip(l).zip(spectrum) {
            *a += l * k;
        }
    }
}

/// One output row from its three channels' spectra Ŷ (W/2 + 1 bins each, interleaved),
/// transformed back (channels 0 and 1 together) and scaled by 1/(W·π).
fn back(plan: &FftPlan, spectra: &[f64], buf: &mut [Complex64], scratch: &mut [Complex64], row: &mut [Rgb]) {
    let (w, bins) = (plan.width, plan.bins());
    // Ŷ at any bin of W, from the kept half by Hermitian symmetry.
    let full = |ch: usize, f: usize| {
        let s = &spectra[ch * 2 * bins..][..2 * bins];
        if f < bins {
            Complex64::new(s[2 * f], s[2 * f + 1])
        } else {
            Complex64::new(s[2 * (w - f)], -s[2 * (w - f) + 1])
        }
    };
    let scale = FRAC_1_PI / w as f64;
    for (f, z) in buf.iter_mut().enumerate() {
        *z = full(0, f) + full(1, f) * Complex64::new(0.0, 1.0);
    }
    plan.inverse.process_with_scratch(buf, scratch);
    for (v, z) in row.iter_mut().zip(buf.iter()) {
        v.x = (z.re * scale).max(0.0);
        v.y = (z.im * scale).max(0.0);
    }
    for (f, z) in buf.iter_mut().enumerate() {
        *z = full(2, f);
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
    use crate::reference::row_pairs::has_avx2;

    fn map_of(w: usize, h: usize) -> EnvMap {
        EnvMap::from_fn("t", w, h, move |i, j| {
            let v = ((i * 7 + j * 3) % 11) as f32 * 0.5 + 0.1;
            [v, if i == w / 3 && j == h / 4 { 900.0 } else { 0.0 }, (j as f32 + 1.0).recip()]
        })
        .unwrap()
    }

    /// Rows `0..oh` of a `ow`-wide grid by FFT from `map`, the per-row work portable or AVX2.
    fn fft_rows(map: &EnvMap, ow: usize, oh: usize, avx2: bool) -> Vec<Rgb> {
        let rm = RowMoments::new(map);
        let plan = FftPlan::new(ow);
        let mut fast = vec![Rgb::ZERO; ow * oh];
        let rows: Vec<usize> = (0..oh).collect();
        convolve(&rm, &gauss_legendre(2), LatLong::new(ow, oh), &plan, &rows, &mut fast, &|| false, avx2);
        fast
    }

    /// Every output row by FFT against the per-normal path (each normal integrated on its own
    /// from the row moments, no transform): widths whose half is even and odd, two columns,
    /// odd and even grid heights (a map is twice as wide as high, so W is even).
    #[test]
    fn fft_rows_equal_the_per_normal_path() {
        for (mw, mh, oh) in [(48, 24, 24), (48, 24, 13), (10, 5, 5), (10, 5, 8), (6, 3, 3), (2, 1, 2), (2, 1, 3)] {
            let map = map_of(mw, mh);
            let fast = fft_rows(&map, mw, oh, false);
            let rm = RowMoments::new(&map);
            let r = Reference::new(&rm, vec![], 2);
            let out = LatLong::new(mw, oh);
            let top = fast.iter().map(|v| v.max_element()).fold(0.0, f64::max);
            for j in 0..oh {
                for i in 0..mw {
                    let want = r.irradiance(out.direction(i, j));
                    let d = (fast[j * mw + i] - want).abs().max_element();
                    assert!(d <= 1e-12 * top, "{mw}x{mh} onto {mw}x{oh} ({i},{j}): {} vs {want}", fast[j * mw + i]);
                }
            }
        }
    }

    /// The AVX2 copy of the per-row work does the same operations four wide, so its values are
    /// the portable copy's to the bit (nothing to compare where the CPU has no AVX2).
    #[test]
    fn avx2_rows_equal_the_portable_rows() {
        if !has_avx2() {
            return; // Nothing to compare: this CPU runs the portable copy only.
        }
        for (mw, mh, oh) in [(48, 24, 24), (10, 5, 7), (256, 128, 64)] {
            let map = map_of(mw, mh);
            assert_eq!(fft_rows(&map, mw, oh, true), fft_rows(&map, mw, oh, false), "{mw}x{mh}");
        }
    }

    /// The rule: the FFT exactly where the grid's width is the map's.
    #[test]
    fn applies_where_the_columns_are_the_maps() {
        assert!(applies(256, 256) && applies(7, 7) && applies(1, 1));
        assert!(!applies(1000, 256) && !applies(256, 512) && !applies(512, 256) && !applies(4, 0));
    }
}
