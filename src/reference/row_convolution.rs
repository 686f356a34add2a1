//! The exact reference on a lat-long grid of normals with no caps: each input row's part is a
//! circular convolution, for any map width and any grid width (FORMULAS §1; `exact.rs`).
//!
//! On the parallel φ of an input row, the clamped cosine about the normal of output row φₒ and
//! azimuth θᵢ is a·cos(θ − θᵢ) + b on the arc [θᵢ − Δ, θᵢ + Δ] (a = sin φₒ sin φ,
//! b = cos φₒ cos φ, cos Δ = −b/a): one kernel for every column of the output row, shifted. Its
//! integral against the row is b·(C0(θᵢ+Δ) − C0(θᵢ−Δ)) + a·Re(e^{iθᵢ}(C1(θᵢ+Δ) − C1(θᵢ−Δ))), with
//! C0, C1 the row's cumulative moments (`envmap::moments`), exact for the piecewise-constant row.
//!
//! Grouped fractional shifts: with g = gcd(W, w) (map width W, grid width w), p = W/g and
//! q = w/g, columns i and i + q are exactly p texels apart. So the columns of each of the q
//! classes i mod q find their arc ends at one texel offset and one fraction: the coefficients
//! are formed once per class and end, without trigonometry (e^{∓iΔ} = t ∓ i√(1 − t²) with
//! t = cos Δ, and the partial texel's sine and versine by short series), and the class's g
//! columns are then four multiply-adds per channel over contiguous arrays (the row's moments
//! stored by phase mod p). The cost per input row is the grid's size times the polar nodes
//! whatever the two widths (a W that is a multiple of w is the case q = 1), and a grid finer
//! than the map works the same way.

use crate::envmap::moments::{sin_versin, sin_versin_series, Moments01, RowMoments, SERIES_MAX};
use crate::envmap::LatLong;
use crate::math::colour::Rgb;
use crate::reference::antipode;
use crate::reference::row_fft::{self, FftPlan};
use crate::reference::row_pairs::{for_each_node, has_avx2, over_input_rows};
use std::f64::consts::{FRAC_1_PI, PI};

/// A mirrored row where more than 1/`DENSE` of the values cancelled is convolved directly:
/// a normal on its own (`Reference::irradiance_many`) costs about four columns of a row.
const DENSE: usize = 8;

/// E/π at the centres of the lat-long grid `out` (row-major), for the map whose moments are
/// given, with no caps, integrating each row piece with the Gauss–Legendre `rule`; the lower
/// rows mirrored from the upper ones (`antipode`). A mirrored row where many values cancelled
/// ([`antipode::CANCELLED`], the dark side of a single light) is convolved directly instead;
/// the indices of the other cancelled values are returned, for the caller to compute those
/// normals on their own. `stop` is checked between the map's rows: once it says stop, the rest
/// is skipped and the values mean nothing (the caller that asked discards them).
pub(crate) fn irradiance_latlong(
    moments: &RowMoments,
    rule: &[(f64, f64)],
    out: LatLong,
    stop: &(dyn Fn() -> bool + Sync),
) -> (Vec<Rgb>, Vec<usize>) {
    let path = if row_fft::applies(moments.width(), out.width) {
        Path::Fft(FftPlan::new(out.width))
    } else {
        Path::Direct(Plan::new(moments.width(), moments.dtheta(), out.width))
    };
    let avx2 = has_avx2();
    let convolve = |rows: &[usize], values: &mut [Rgb]| match &path {
        Path::Fft(plan) => row_fft::convolve(moments, rule, out, plan, rows, values, stop, avx2),
        Path::Direct(plan) => convolve(moments, rule, out, plan, rows, values, stop, avx2),
    };
    let mut values = vec![Rgb::ZERO; out.height * out.width];
    let top: Vec<usize> = (0..antipode::direct_rows(out)).collect();
    convolve(&top, &mut values);
    let cancelled = antipode::mirror(moments, rule, out, &mut values);
    let w = out.width;
    let mut per_row = vec![0usize; out.height];
    for &k in &cancelled {
        per_row[k / w] += 1;
    }
    let dense = |j: usize| per_row[j] * DENSE > w;
    let redo: Vec<usize> = (0..out.height).filter(|&j| dense(j)).collect();
    if !redo.is_empty() {
        convolve(&redo, &mut values);
    }
    let rest = cancelled.into_iter().filter(|&k| !dense(k / w)).collect();
    (values, rest)
}

/// The two ways of convolving the rows: by FFT where the grid's columns are the map's
/// ([`row_fft::applies`]), else directly.
enum Path {
    Direct(Plan),
    Fft(FftPlan),
}

/// Convolves every input row into the output rows `rows_out` of `values` (E/π, row-major); the
/// per-row work compiled for AVX2 when `avx2` (`row_pairs::has_avx2` must have said so).
#[allow(clippy::too_many_arguments)]
fn convolve(
    moments: &RowMoments,
    rule: &[(f64, f64)],
    out: LatLong,
    plan: &Plan,
    rows_out: &[usize],
    values: &mut [Rgb],
    stop: &(dyn Fn() -> bool + Sync),
    avx2: bool,
) {
    let n = rows_out.len() * plan.row_len();
    let new = || Sums {
        acc: vec![0.0f64; n],
        phased: Phased::new(plan),
        nodes: Vec::new(),
        ends: [ClassEnds::new(plan.q), ClassEnds::new(plan.q)],
    };
    let add = |sums: &mut Sums, j: usize| {
        let row = InputRow { moments, plan, rule, out, rows_out, j };
        #[cfg(target_arch = "x86_64")]
        if avx2 {
            // SAFETY: `avx2` is true only where the CPU has AVX2 (`row_pairs::has_avx2`).
            unsafe { add_input_row_avx2(&row, sums) };
            return;
        }
        let _ = avx2;
        add_input_row(&row, sums);
    };
    let partials = over_input_rows(moments, new, add, stop);
    let mut total = vec![0.0f64; n];
    for p in &partials {
        for (t, v) in total.iter_mut().zip(&p.acc) {
            *t += v;
        }
    }
    // From class-major order (class c, member t, channel; each class padded to `stride`) to
    // row-major columns i = c + q·t.
    for (&jo, classes) in rows_out.iter().zip(total.chunks_exact(plan.row_len())) {
        let row = &mut values[jo * out.width..][..out.width];
        for (c, class) in classes.chunks_exact(plan.stride).enumerate() {
            for (t, v) in class[..3 * plan.g].chunks_exact(3).enumerate() {
                row[c + plan.q * t] = Rgb::new(v[0], v[1], v[2]) * FRAC_1_PI;
            }
        }
    }
}

/// What a chunk of input rows keeps: the output rows' sums (class-major, each class padded to
/// [`Plan::stride`], as [`Plan::add_node`] writes them) and its work buffers.
struct Sums {
    acc: Vec<f64>,
    phased: Phased,
    /// One row pair's polar nodes: a, b, weight and cos Δ (`row_pairs::for_each_node`).
    nodes: Vec<(f64, f64, f64, f64)>,
    /// One polar node's upper and lower arc ends, every class's.
    ends: [ClassEnds; 2],
}

/// One input row j against the output rows `rows_out`.
struct InputRow<'a> {
    moments: &'a RowMoments<'a>,
    plan: &'a Plan,
    rule: &'a [(f64, f64)],
    out: LatLong,
    rows_out: &'a [usize],
    j: usize,
}

/// [`add_input_row`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn add_input_row_avx2(row: &InputRow, sums: &mut Sums) {
    add_input_row(row, sums);
}

/// Adds input row `row.j` to every output row: the row pair's polar nodes are listed first, so
/// that their arcs run here and not in a callback.
#[inline(always)]
fn add_input_row(row: &InputRow, sums: &mut Sums) {
    let (plan, rows) = (row.plan, row.moments.height());
    sums.phased.fill(row.moments, row.j, plan);
    let polar = (PI * row.j as f64 / rows as f64, PI * (row.j + 1) as f64 / rows as f64);
    for (&jo, acc) in row.rows_out.iter().zip(sums.acc.chunks_exact_mut(plan.row_len())) {
        sums.nodes.clear();
        for_each_node(row.rule, row.out.phi_centre(jo), polar, |a, b, ws, t| sums.nodes.push((a, b, ws, t)));
        for &(a, b, ws, t) in &sums.nodes {
            plan.add_node(&sums.phased, (a, b, ws), &plan.arc(t), &mut sums.ends, acc);
        }
    }
}

/// Greatest common divisor.
fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// The column classes of one map width against one grid width.
struct Plan {
    /// Map width W.
    width: usize,
    /// Azimuth width of a map texel, 2π/W.
    h: f64,
    /// Columns per class, gcd(W, w).
    g: usize,
    /// Texels between consecutive columns of a class, W/g.
    p: usize,
    /// Classes, w/g.
    q: usize,
    /// Values a class takes in the sums: its 3g (g columns, three channels) rounded up to a
    /// multiple of four, so that every class is whole blocks of lanes (the padding's sums
    /// are never read).
    stride: usize,
    /// Per class c, the centre of its first column in texels from θ = −π: (c + ½)·p/q.
    centre: Vec<f64>,
    /// [`Phased`] holds the edges k = −lo..W + lo, lo = ⌊W/2⌋ + 2: an arc end lies within half
    /// a turn (plus rounding) of a first column's centre, which is within the first p texels,
    /// and a class's last column is W − p texels past its first.
    lo: usize,
    /// Per stored edge e = k + lo, where its three channels start in [`Phased`]: phase e mod p,
    /// then e / p within the phase (a table: no division in the inner loops).
    at: Vec<usize>,
}

impl Plan {
    fn new(width: usize, h: f64, out_width: usize) -> Self {
        let g = gcd(width, out_width);
        let (p, q) = (width / g, out_width / g);
        let centre = (0..q).map(|c| ((2 * c + 1) * p) as f64 / (2 * q) as f64).collect();
        let lo = width / 2 + 2;
        let edges = width + 2 * lo;
        let len = edges.div_ceil(p);
        let at = (0..edges).map(|e| ((e % p) * len + e / p) * 3).collect();
        let stride = (3 * g).next_multiple_of(4);
        Plan { width, h, g, p, q, stride, centre, lo, at }
    }

    /// Values an output row takes in the sums: q classes of [`Self::stride`].
    fn row_len(&self) -> usize {
        self.q * self.stride
    }

    /// A polar node's half-arc from t = cos Δ (the whole circle when t ≤ −1).
    #[inline(always)]
    fn arc(&self, t: f64) -> Arc {
        if t <= -1.0 {
            Arc { delta: 0.5 * self.width as f64, cos: -1.0, sin: 0.0 }
        } else {
            Arc { delta: t.acos() / self.h, cos: t, sin: ((1.0 - t) * (1.0 + t)).sqrt() }
        }
    }

    /// One arc end of every class, into `out`: the texel k it lies in, and the factors of C0,
    /// Re C1″, Im C1″ and L there. `e` is +1 for the upper end, −1 for the lower, and `ws`
    /// carries the end's sign. A loop over the classes with no branch where the partial texel's
    /// sine and versine take the series (texels at most [`SERIES_MAX`] wide), so it runs four
    /// classes a step where the CPU has AVX2.
    #[inline(always)]
    fn ends(&self, arc: &Arc, e: f64, kernel: (f64, f64, f64), out: &mut ClassEnds) {
        if self.h <= SERIES_MAX {
            self.ends_with(arc, e, kernel, out, sin_versin_series);
        } else {
            self.ends_with(arc, e, kernel, out, sin_versin);
        }
    }

    /// [`Self::ends`] with the partial texel's (sin, versin) from `sv`.
    #[inline(always)]
    fn ends_with(
        &self,
        arc: &Arc,
        e: f64,
        (a, b, ws): (f64, f64, f64),
        out: &mut ClassEnds,
        sv: fn(f64) -> (f64, f64),
    ) {
        let q = self.q;
        let (centre, ks) = (&self.centre[..q], &mut out.k[..q]);
        let (x1, x2, x3) = (&mut out.x1[..q], &mut out.x2[..q], &mut out.x3[..q]);
        out.x0 = ws * b;
        for c in 0..q {
            // The end at u = centre ± Δ texels lies in texel k, a fraction f·h into it.
            let u = centre[c] + e * arc.delta;
            let k = u.floor();
            let f = (u - k) * self.h;
            let (sf, vf) = sv(f);
            // z = e^{i(u_centre − k)h} = e^{i(f ∓ Δ)}, the column centre seen from the edge.
            let cf = 1.0 - vf;
            let (zc, zs) = (arc.cos * cf + e * arc.sin * sf, arc.cos * sf - e * arc.sin * cf);
            // The partial texel: L·z·(sin f − i(1 − cos f)); κ is its real part over L.
            let kappa = zc * sf + zs * vf;
            ks[c] = k;
            x1[c] = ws * a * zc;
            x2[c] = -ws * a * zs;
            x3[c] = ws * (b * f + a * kappa);
        }
    }

    /// One polar node: the kernel a·cos + b with weight `ws` over the arc ±Δ; `ends` is work
    /// space for its two ends.
    #[inline(always)]
    fn add_node(&self, row: &Phased, kernel: (f64, f64, f64), arc: &Arc, ends: &mut [ClassEnds; 2], acc: &mut [f64]) {
        let (a, b, ws) = kernel;
        let [up, down] = ends;
        self.ends(arc, 1.0, kernel, up);
        self.ends(arc, -1.0, (a, b, -ws), down);
        let at = |k: f64| self.at[(k as i64 + self.lo as i64) as usize];
        for (c, o) in acc.chunks_exact_mut(self.stride).enumerate() {
            let (h, l) = ([up.x0, up.x1[c], up.x2[c], up.x3[c]], [down.x0, down.x1[c], down.x2[c], down.x3[c]]);
            add_class(o, row.from(at(up.k[c])), row.from(at(down.k[c])), h, l);
        }
    }
}

/// One class's sums at one polar node, o[x] += (Σₘ hₘ·Aₘ[x]) + (Σₘ lₘ·Bₘ[x]) for x < `o.len()`:
/// A₀..A₃ and B₀..B₃ are C0, Re C1″, Im C1″ and L from the class's first column on at the arc's
/// upper and lower ends ([`Phased::from`]), h and l their factors ([`ClassEnds`]). Each array is
/// its own argument so that the compiler knows the sums are apart from the table: the loop runs
/// vectorised with no overlap check and one length check per array, per class.
#[inline(always)]
fn add_class(o: &mut [f64], [a0, a1, a2, a3]: [&[f64]; 4], [b0, b1, b2, b3]: [&[f64]; 4], h: [f64; 4], l: [f64; 4]) {
    let n = o.len();
    let (a0, a1, a2, a3) = (&a0[..n], &a1[..n], &a2[..n], &a3[..n]);
    let (b0, b1, b2, b3) = (&b0[..n], &b1[..n], &b2[..n], &b3[..n]);
    for x in 0..n {
        o[x] += (h[0] * a0[x] + h[1] * a1[x] + h[2] * a2[x] + h[3] * a3[x])
            + (l[0] * b0[x] + l[1] * b1[x] + l[2] * b2[x] + l[3] * b3[x]);
    }
}

/// One arc end of every class of a polar node (structure of arrays, one entry a class): the
/// texel k the end lies in, and the factors of C0 (`x0`, the same for every class), Re C1″,
/// Im C1″ and L there.
struct ClassEnds {
    k: Vec<f64>,
    x0: f64,
    x1: Vec<f64>,
    x2: Vec<f64>,
    x3: Vec<f64>,
}

impl ClassEnds {
    fn new(q: usize) -> Self {
        ClassEnds { k: vec![0.0; q], x0: 0.0, x1: vec![0.0; q], x2: vec![0.0; q], x3: vec![0.0; q] }
    }
}

/// The kernel's half-arc on one parallel: Δ in texels, cos Δ and sin Δ.
struct Arc {
    delta: f64,
    cos: f64,
    sin: f64,
}

/// One input row's cumulative moments at its texel edges k = −lo..W + lo ([`Plan::lo`]; whole
/// turns' totals added past the row's ends), with C1 rotated by e^{iθ_edge}, and the texel
/// right of each edge; stored phase by phase (edge k at [`Plan::at`]: phase (k + lo) mod p,
/// then (k + lo) / p) so a class's columns read consecutive values, the three channels of an
/// edge side by side.
struct Phased {
    c0: Vec<f64>,
    c1r: Vec<f64>,
    c1i: Vec<f64>,
    l: Vec<f64>,
    /// The row's W left edges in order: cumulative m0 and m1, the texel, e^{iθ_edge}.
    edges: Vec<(Moments01, Rgb, (f64, f64))>,
}

impl Phased {
    /// The table for `plan`, with room past its last phase for a class's padding
    /// ([`Plan::stride`]): a class's last block reads up to stride − 3g values past its last
    /// column, into the next phase or these zeros, for sums that are never read.
    fn new(plan: &Plan) -> Self {
        let n = plan.p * plan.at.len().div_ceil(plan.p) * 3 + plan.stride - 3 * plan.g;
        let edges = Vec::with_capacity(plan.width);
        Phased { c0: vec![0.0; n], c1r: vec![0.0; n], c1i: vec![0.0; n], l: vec![0.0; n], edges }
    }

    /// The four arrays from value `at` on (a class's first column at one arc end).
    #[inline(always)]
    fn from(&self, at: usize) -> [&[f64]; 4] {
        [&self.c0[at..], &self.c1r[at..], &self.c1i[at..], &self.l[at..]]
    }

    /// Row j's values: its prefix sums in order (`RowMoments::prefix01`), then written phase by
    /// phase, so that the writes run along the arrays (written edge by edge, every store would
    /// land on another cache line of a table larger than the cache at 16k).
    #[inline(always)]
    fn fill(&mut self, moments: &RowMoments, j: usize, plan: &Plan) {
        self.edges.clear();
        moments.prefix01(j, |kk, l, m| self.edges.push((*m, l, moments.edge_cis1(kk))));
        let total = moments.row_total01(j);
        let (w, p, lo, edges) = (plan.width, plan.p, plan.lo as i64, plan.at.len());
        let slots = edges.div_ceil(p);
        for ph in 0..p.min(edges) {
            // Edge e = ph + p·s is k = e − lo = kk + wraps·W, stepping p texels a slot.
            let k = ph as i64 - lo;
            let mut wraps = k.div_euclid(w as i64);
            let mut kk = (k - wraps * w as i64) as usize;
            let base = ph * slots * 3;
            for at in (0..slots).take_while(|s| ph + p * s < edges).map(|s| base + 3 * s) {
                let (m, l, (ct, st)) = &self.edges[kk];
                let wr = wraps as f64;
                for ch in 0..3 {
                    let (r, i) = (m.m1[0][ch] + wr * total.m1[0][ch], m.m1[1][ch] + wr * total.m1[1][ch]);
                    self.c0[at + ch] = m.m0[ch] + wr * total.m0[ch];
                    self.c1r[at + ch] = r * ct - i * st;
                    self.c1i[at + ch] = r * st + i * ct;
                    self.l[at + ch] = l[ch];
                }
                kk += p;
                while kk >= w {
                    kk -= w;
                    wraps += 1;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_cover_every_column_once() {
        for (w, out) in [(1000, 256), (1024, 256), (999, 256), (256, 256), (2, 256), (64, 20), (6, 4)] {
            let plan = Plan::new(w, std::f64::consts::TAU / w as f64, out);
            assert_eq!(plan.q * plan.g, out);
            // A class's sums are whole blocks of four, at most three values of padding.
            assert!(plan.stride % 4 == 0 && (3 * plan.g..3 * plan.g + 4).contains(&plan.stride), "{w} onto {out}");
            let mut seen = vec![0; out];
            for c in 0..plan.q {
                for t in 0..plan.g {
                    seen[c + plan.q * t] += 1;
                    // Column i's centre (i + ½)·W/w texels from −π is its class's plus t·p.
                    let i = c + plan.q * t;
                    let want = (i as f64 + 0.5) * w as f64 / out as f64;
                    assert!((plan.centre[c] + (plan.p * t) as f64 - want).abs() < 1e-9 * want.max(1.0));
                }
            }
            assert!(seen.iter().all(|&n| n == 1), "{w} onto {out}");
        }
    }

    /// The AVX2 copy of the per-row work does the same operations four wide, so its values are
    /// the portable copy's to the bit (nothing to compare where the CPU has no AVX2): classes of one and
    /// of several columns, a grid finer than the map, classes padded to whole blocks of four (one
    /// column, ten columns).
    #[test]
    fn avx2_rows_equal_the_portable_rows() {
        if !has_avx2() {
            return; // Nothing to compare: this CPU runs the portable copy only.
        }
        for (mw, ow, oh) in [(100, 24, 13), (64, 16, 8), (20, 64, 9), (22, 9, 5), (30, 20, 7)] {
            let map = crate::envmap::EnvMap::from_fn("t", mw, mw / 2, |i, j| {
                [((i * 7 + j * 3) % 11) as f32 + 0.1, if i == 3 && j == 2 { 900.0 } else { 0.0 }, 1.0]
            })
            .unwrap();
            let rm = RowMoments::new(&map);
            let plan = Plan::new(mw, rm.dtheta(), ow);
            let rule = crate::math::quadrature::gauss_legendre(2);
            let rows: Vec<usize> = (0..oh).collect();
            let run = |avx2: bool| {
                let mut v = vec![Rgb::ZERO; ow * oh];
                convolve(&rm, &rule, LatLong::new(ow, oh), &plan, &rows, &mut v, &|| false, avx2);
                v
            };
            assert_eq!(run(true), run(false), "{mw} onto {ow}x{oh}");
        }
    }
}
