//! Cumulative azimuthal moments of each row of a map: the exact azimuth integrals
//! ∫ L(θ) e^{−imθ} dθ (m = 0, 1, 2) of the piecewise-constant radiance over any arc.
//!
//! The clamped cosine about a normal is a + b·cos(θ − θ_n) on a parallel, and every SH
//! function of bands 0–2 is a trigonometric polynomial of order ≤ 2 in θ; so an arc integral of
//! either is a combination of these moments, computed in O(1) from prefix sums. This is what
//! makes the exact reference cost O(rows) per normal instead of O(texels).

use crate::envmap::EnvMap;
use crate::math::cap::Arc;
use crate::math::colour::Rgb;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Exact azimuth integrals of one row over an arc: m0 = ∫L, and m1, m2 = ∫L e^{−imθ} as
/// (real, imaginary) parts, per channel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moments {
    /// ∫L dθ over the arc, per channel.
    pub m0: Rgb,
    /// ∫L e^{−iθ} dθ over the arc: (real, imaginary) parts.
    pub m1: [Rgb; 2],
    /// ∫L e^{−2iθ} dθ over the arc: (real, imaginary) parts.
    pub m2: [Rgb; 2],
}

impl std::ops::AddAssign for Moments {
    fn add_assign(&mut self, o: Moments) {
        self.m0 += o.m0;
        for k in 0..2 {
            self.m1[k] += o.m1[k];
            self.m2[k] += o.m2[k];
        }
    }
}
impl std::ops::Sub for Moments {
    type Output = Moments;
    fn sub(self, o: Moments) -> Moments {
        Moments {
            m0: self.m0 - o.m0,
            m1: [self.m1[0] - o.m1[0], self.m1[1] - o.m1[1]],
            m2: [self.m2[0] - o.m2[0], self.m2[1] - o.m2[1]],
        }
    }
}
impl std::ops::Mul<f64> for Moments {
    type Output = Moments;
    fn mul(self, s: f64) -> Moments {
        Moments { m0: self.m0 * s, m1: [self.m1[0] * s, self.m1[1] * s], m2: [self.m2[0] * s, self.m2[1] * s] }
    }
}

/// The azimuthal moments of every row of a map, for prefix sums built a row at a time.
///
/// What is kept for the whole map is O(W + H): each row's total moments and, per column, the
/// exact moments of a texel of unit radiance. A row's W+1 cumulative moments ([`RowPrefix`])
/// are rebuilt from the map's own f32 texels when a row is needed (O(W), the same sums in the
/// same order, so the same bits as keeping them): holding them for every row would cost 120
/// bytes per texel, ten times the map.
pub struct RowMoments<'m> {
    map: &'m EnvMap,
    width: usize,
    height: usize,
    dtheta: f64,
    /// (cos, sin) of mθ at the left edge of each column, m = 1, 2 (W+1 edges).
    edge_cis: Vec<[(f64, f64); 2]>,
    /// ∫ e^{−imθ} dθ over each column, m = 1, 2, as (real, imaginary) parts.
    weights: Vec<[(f64, f64); 2]>,
    /// Each row's total moments.
    totals: Vec<Moments>,
}

/// One row's cumulative moments at its W+1 texel edges (index k = left edge of texel k) and its
/// texels as f64: what [`RowMoments::cumulative`] and the other lookups read. Built by
/// [`RowMoments::fill`]; reused from row to row to keep allocations out of loops.
#[derive(Clone, Debug, Default)]
pub struct RowPrefix {
    j: usize,
    cum: Vec<Moments>,
    texels: Vec<Rgb>,
}

impl RowPrefix {
    /// An empty prefix, to be filled by [`RowMoments::fill`].
    pub fn new() -> Self {
        Self::default()
    }
    /// The row it holds.
    pub fn row(&self) -> usize {
        self.j
    }
    /// The W+1 cumulative moments at the texel edges.
    #[cfg(test)]
    pub fn cum(&self) -> &[Moments] {
        &self.cum
    }
    /// Texel k's radiance.
    #[inline]
    pub fn texel(&self, k: usize) -> Rgb {
        self.texels[k]
    }
}

/// Moments m0 and m1 only (what the clamped-cosine kernel needs): m0 = ∫L, m1 = ∫L e^{−iθ} as
/// (real, imaginary) parts, per channel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moments01 {
    /// ∫L dθ over the arc, per channel.
    pub m0: Rgb,
    /// ∫L e^{−iθ} dθ over the arc: (real, imaginary) parts.
    pub m1: [Rgb; 2],
}

impl Moments01 {
    /// self += o·s.
    #[inline]
    pub fn add_scaled(&mut self, o: &Moments01, s: f64) {
        self.m0 += o.m0 * s;
        self.m1[0] += o.m1[0] * s;
        self.m1[1] += o.m1[1] * s;
    }
}

impl std::ops::Sub for Moments01 {
    type Output = Moments01;
    #[inline]
    fn sub(self, o: Moments01) -> Moments01 {
        Moments01 { m0: self.m0 - o.m0, m1: [self.m1[0] - o.m1[0], self.m1[1] - o.m1[1]] }
    }
}

impl std::ops::AddAssign for Moments01 {
    #[inline]
    fn add_assign(&mut self, o: Moments01) {
        self.m0 += o.m0;
        self.m1[0] += o.m1[0];
        self.m1[1] += o.m1[1];
    }
}

impl<'m> RowMoments<'m> {
    /// The per-column weights and every row's total moments of `map` (rows in parallel).
    pub fn new(map: &'m EnvMap) -> Self {
        let (w, h) = (map.width(), map.height());
        let grid = map.grid();
        let dtheta = grid.dtheta();
        let edge_cis: Vec<[(f64, f64); 2]> = (0..=w)
            .map(|k| {
                let t = grid.theta_edge(k);
                [t.cos_sin(), (2.0 * t).cos_sin()]
            })
            .collect();
        // ∫_{θk}^{θk+1} e^{−imθ} dθ = (e^{−imθk} − e^{−imθk+1})/(im)
        let texel_integral = |k: usize, m: usize| -> (f64, f64) {
            let (c0, s0) = edge_cis[k][m - 1];
            let (c1, s1) = edge_cis[k + 1][m - 1];
            // (e^{-ia} − e^{-ib})/(im) with e^{-ix} = (c, −s): numerator (c0−c1) + i(s1−s0)
            let (re, im) = (c0 - c1, s1 - s0);
            // divide by i m: (re + i im)/(i m) = im/m − i re/m
            (im / m as f64, -re / m as f64)
        };
        let weights: Vec<[(f64, f64); 2]> = (0..w).map(|k| [texel_integral(k, 1), texel_integral(k, 2)]).collect();
        let mut rm = Self { map, width: w, height: h, dtheta, edge_cis, weights, totals: Vec::new() };
        rm.totals = (0..h).into_par_iter().map(|j| rm.accumulate(j, |_, _| {})).collect();
        rm
    }

    /// Runs the prefix sums of row j from the left edge, handing `at(k, F(edge k + 1))` the
    /// cumulative moments after each texel; returns the row total. The one place the sums are
    /// formed, so totals and prefixes agree bit for bit.
    #[inline]
    fn accumulate(&self, j: usize, mut at: impl FnMut(usize, &Moments)) -> Moments {
        let mut acc = Moments::default();
        for (k, (t, &[(r1, i1), (r2, i2)])) in self.map.row(j).iter().zip(&self.weights).enumerate() {
            let l = Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64);
            acc.m0 += l * self.dtheta;
            acc.m1[0] += l * r1;
            acc.m1[1] += l * i1;
            acc.m2[0] += l * r2;
            acc.m2[1] += l * i2;
            at(k, &acc);
        }
        acc
    }

    /// Fills `row` with row j's cumulative moments and texels (O(W)).
    pub fn fill(&self, j: usize, row: &mut RowPrefix) {
        row.j = j;
        row.cum.clear();
        row.cum.reserve(self.width + 1);
        row.cum.push(Moments::default());
        let mut cum = std::mem::take(&mut row.cum);
        self.accumulate(j, |_, acc| cum.push(*acc));
        row.cum = cum;
        row.texels.clear();
        row.texels.extend(self.map.row(j).iter().map(|t| Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64)));
    }

    /// Walks row j's m0 and m1 prefix sums without storing them: `at(k, L, F)` for each texel k,
    /// with its radiance L and the cumulative moments F at its left edge (zero at k = 0). The
    /// same sums in the same order as [`Self::fill`], so the same bits as the prefix it fills; the
    /// row's last edge is [`Self::row_total01`].
    #[inline(always)]
    pub fn prefix01(&self, j: usize, mut at: impl FnMut(usize, Rgb, &Moments01)) {
        let mut acc = Moments01::default();
        for (k, (t, &[(r1, i1), _])) in self.map.row(j).iter().zip(&self.weights).enumerate() {
            let l = Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64);
            at(k, l, &acc);
            acc.m0 += l * self.dtheta;
            acc.m1[0] += l * r1;
            acc.m1[1] += l * i1;
        }
    }

    /// Row j's prefix, newly allocated (see [`Self::fill`] to reuse one).
    #[cfg(test)]
    pub fn prefix(&self, j: usize) -> RowPrefix {
        let mut row = RowPrefix::new();
        self.fill(j, &mut row);
        row
    }

    /// Width of the map in texels.
    pub fn width(&self) -> usize {
        self.width
    }
    /// Height of the map in texels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Moments of the whole row j.
    #[inline]
    pub fn row_total(&self, j: usize) -> Moments {
        self.totals[j]
    }

    /// (cos θ, sin θ) of the left edge of column k (k ≤ W).
    #[inline]
    pub fn edge_cis1(&self, k: usize) -> (f64, f64) {
        self.edge_cis[k][0]
    }

    /// The cumulative moments ∫_{−π}^{θ} on the prefix's row, for any real θ (periodic
    /// extension).
    #[inline]
    pub fn cumulative(&self, row: &RowPrefix, theta: f64) -> Moments {
        self.cumulative_to(row, theta, 2)
    }

    /// As [`Self::cumulative`], computing the partial texel only for m ≤ `max_m` (m2 is then
    /// left at the prefix value and must not be used).
    #[inline]
    fn cumulative_to(&self, row: &RowPrefix, theta: f64, max_m: usize) -> Moments {
        let w = self.width as f64;
        let u = (theta + PI) / self.dtheta;
        let wraps = (u / w).floor();
        let u_in = u - wraps * w;
        let k = (u_in.floor().max(0.0) as usize).min(self.width - 1);
        let mut out = row.cum[k];
        if wraps != 0.0 {
            out += row.cum[self.width] * wraps;
        }
        // Partial texel k from its left edge to θ.
        let delta = (u_in - k as f64) * self.dtheta;
        if delta != 0.0 {
            let l = row.texels[k];
            out.m0 += l * delta;
            for m in 1..=max_m {
                let x = m as f64 * delta;
                let (sx, half) = (x.sin(), (0.5 * x).sin());
                // (1 − e^{−ix})/(im) = sin x/m − i(1 − cos x)/m
                let (fr, fi) = (sx / m as f64, -2.0 * half * half / m as f64);
                // times e^{−imθk} = (c, −s)
                let (c, s) = self.edge_cis[k][m - 1];
                let (re, im) = (c * fr + s * fi, c * fi - s * fr);
                let target = if m == 1 { &mut out.m1 } else { &mut out.m2 };
                target[0] += l * re;
                target[1] += l * im;
            }
        }
        out
    }

    /// `cumulative_to` with `max_m` = 1, the clamped-cosine kernel's case, with less
    /// work: no wrap division inside the first period, truncation instead of `floor` for the
    /// (non-negative) texel index, no m = 2 terms, and the partial texel's sin x and 1 − cos x
    /// by `sin_versin` (the same values to an ulp or two).
    #[inline]
    pub fn cumulative01(&self, row: &RowPrefix, theta: f64) -> Moments01 {
        let w = self.width as f64;
        let u = (theta + PI) / self.dtheta;
        // (u / w).floor() is 0 exactly when 0 <= u < w (the quotient then rounds below 1).
        let (u_in, wrap) = if (0.0..w).contains(&u) {
            (u, None)
        } else {
            let wraps = (u / w).floor();
            (u - wraps * w, (wraps != 0.0).then_some(wraps))
        };
        // `as usize` truncates, which is floor for u_in >= 0 and saturates to 0 below it, as
        // floor().max(0.0) does.
        let k = (u_in as usize).min(self.width - 1);
        let cell = &row.cum[k];
        let mut out = Moments01 { m0: cell.m0, m1: cell.m1 };
        if let Some(wraps) = wrap {
            let t = &row.cum[self.width];
            out.add_scaled(&Moments01 { m0: t.m0, m1: t.m1 }, wraps);
        }
        let delta = (u_in - k as f64) * self.dtheta;
        if delta != 0.0 {
            let l = row.texels[k];
            out.m0 += l * delta;
            let (sx, versin) = sin_versin(delta);
            let (fr, fi) = (sx, -versin);
            let (c, s) = self.edge_cis[k][0];
            let (re, im) = (c * fr + s * fi, c * fi - s * fr);
            out.m1[0] += l * re;
            out.m1[1] += l * im;
        }
        out
    }

    /// m0 and m1 of the whole row j.
    #[inline]
    pub fn row_total01(&self, j: usize) -> Moments01 {
        let t = &self.totals[j];
        Moments01 { m0: t.m0, m1: t.m1 }
    }

    /// Azimuth width of a texel.
    pub fn dtheta(&self) -> f64 {
        self.dtheta
    }

    /// Moments of the prefix's row over an arc.
    #[inline]
    pub fn arc(&self, row: &RowPrefix, arc: Arc) -> Moments {
        if arc.len >= TAU {
            return self.row_total(row.j);
        }
        self.cumulative(row, arc.hi()) - self.cumulative(row, arc.lo)
    }
}

/// The widest partial texel (radians) for which [`sin_versin`] uses its series: maps at least
/// 63 texels wide.
pub(crate) const SERIES_MAX: f64 = 0.1;

/// (sin x, 1 − cos x) of a partial texel, 0 ≤ x ≤ one texel width. For x ≤ 0.1 by the Taylor
/// series through x⁹ and x¹⁰ (the first omitted terms, x¹¹/11! and x¹²/12!, are below 3e-18
/// of the result, so this is exact to rounding, and cancellation-free like 2 sin²(x/2));
/// otherwise by libm as `cumulative_to` does.
#[inline]
pub(crate) fn sin_versin(x: f64) -> (f64, f64) {
    if x.abs() <= SERIES_MAX {
        sin_versin_series(x)
    } else {
        let half = (0.5 * x).sin();
        (x.sin(), 2.0 * half * half)
    }
}

/// [`sin_versin`]'s series branch alone, for |x| ≤ [`SERIES_MAX`]: no branch, so a loop of
/// it vectorises (the same operations, so the same bits as [`sin_versin`] there).
#[inline(always)]
pub(crate) fn sin_versin_series(x: f64) -> (f64, f64) {
    let z = x * x;
    let s = x * (1.0 + z * (-1.0 / 6.0 + z * (1.0 / 120.0 + z * (-1.0 / 5040.0 + z * (1.0 / 362_880.0)))));
    let v = z * (0.5 + z * (-1.0 / 24.0 + z * (1.0 / 720.0 + z * (-1.0 / 40_320.0 + z * (1.0 / 3_628_800.0)))));
    (s, v)
}

trait CosSin {
    fn cos_sin(self) -> (f64, f64);
}
impl CosSin for f64 {
    fn cos_sin(self) -> (f64, f64) {
        let (s, c) = self.sin_cos();
        (c, s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::envmap::EnvMap;

    fn test_map() -> EnvMap {
        EnvMap::from_fn("t", 16, 8, |i, j| {
            let v = ((i * 7 + j * 3) % 11) as f32 * 0.5 + 0.1;
            [v, v * 0.5 + j as f32, (i as f32).sqrt()]
        })
        .unwrap()
    }

    /// Brute-force ∫ L e^{−imθ} over an arc by fine midpoint sampling of the piecewise-constant row.
    fn brute(map: &EnvMap, j: usize, lo: f64, hi: f64) -> Moments {
        // Midpoint sampling of a step function errs by O(step·L) at each texel edge.
        let n = 200_000;
        let h = (hi - lo) / n as f64;
        let mut out = Moments::default();
        for s in 0..n {
            let t = lo + (s as f64 + 0.5) * h;
            let u = ((t + PI) / TAU).rem_euclid(1.0);
            let i = ((u * map.width() as f64) as usize).min(map.width() - 1);
            let p = map.texel(i, j);
            let l = Rgb::new(p[0] as f64, p[1] as f64, p[2] as f64) * h;
            out.m0 += l;
            out.m1[0] += l * t.cos();
            out.m1[1] -= l * t.sin();
            out.m2[0] += l * (2.0 * t).cos();
            out.m2[1] -= l * (2.0 * t).sin();
        }
        out
    }

    /// The series agree with libm to 2 ulps on every partial-texel width the series covers.
    #[test]
    fn sin_versin_matches_libm() {
        for i in 0..=100_000 {
            let x = SERIES_MAX * i as f64 / 100_000.0;
            let (s, v) = sin_versin(x);
            let half = (0.5 * x).sin();
            let (ws, wv) = (x.sin(), 2.0 * half * half);
            assert!((s - ws).abs() <= 2.0 * f64::EPSILON * ws, "sin {x}: {s} vs {ws}");
            assert!((v - wv).abs() <= 2.0 * f64::EPSILON * wv, "1 - cos {x}: {v} vs {wv}");
        }
        assert_eq!(sin_versin(0.3), (0.3f64.sin(), 2.0 * 0.15f64.sin().powi(2)));
    }

    /// The kernel's m0/m1 arc moments (differences of [`RowMoments::cumulative01`], as the
    /// reference takes them) equal the general ones (to rounding) over arcs that wrap, start
    /// before −π, cover whole periods and end on texel edges.
    #[test]
    fn cumulative01_differences_equal_arc() {
        for w in [16, 64, 256] {
            let map = EnvMap::from_fn("t", w, w / 2, |i, j| [(i * 3 % 7) as f32 + 0.5, j as f32, 1.0]).unwrap();
            let rm = RowMoments::new(&map);
            let row = rm.prefix(3);
            let h = TAU / w as f64;
            for &(lo, len) in
                &[(-1.0, 0.5), (2.9, 1.0), (-4.0, 3.0), (0.123, 6.0), (-PI, 3.0 * h), (7.0, 2.0), (-9.5, 6.2)]
            {
                let (a, b) =
                    (rm.arc(&row, Arc { lo, len }), rm.cumulative01(&row, lo + len) - rm.cumulative01(&row, lo));
                let scale = a.m0.max_element();
                let d = [a.m0 - b.m0, a.m1[0] - b.m1[0], a.m1[1] - b.m1[1]];
                assert!(d.iter().all(|v| v.abs().max_element() <= 1e-14 * scale), "w {w} arc ({lo},{len}): {d:?}");
            }
        }
    }

    /// A row's prefix, rebuilt on demand, ends at the row total kept for the whole map, bit for
    /// bit, and its steps are the texels' exact moments: m0 steps by L·Δθ, and m1 over a texel
    /// is L·(e^{−iθk} − e^{−iθk+1})/i, checked here against that closed form directly.
    #[test]
    fn prefix_rebuilds_agree_with_the_totals() {
        let map = test_map();
        let rm = RowMoments::new(&map);
        let mut row = RowPrefix::new();
        for j in 0..map.height() {
            rm.fill(j, &mut row);
            assert_eq!(row.row(), j);
            assert_eq!(row.cum().len(), map.width() + 1);
            assert_eq!(row.cum()[map.width()], rm.row_total(j));
            let h = TAU / map.width() as f64;
            for k in 0..map.width() {
                let step = row.cum()[k + 1] - row.cum()[k];
                let l = row.texel(k);
                let (a, b) = (-PI + k as f64 * h, -PI + (k + 1) as f64 * h);
                // (e^{−ia} − e^{−ib})/i = (sin b − sin a) + i(cos b − cos a)
                let (re, im) = (b.sin() - a.sin(), b.cos() - a.cos());
                assert!((step.m0 - l * h).abs().max_element() <= 1e-12);
                assert!((step.m1[0] - l * re).abs().max_element() <= 1e-12, "row {j} texel {k}");
                assert!((step.m1[1] - l * im).abs().max_element() <= 1e-12, "row {j} texel {k}");
            }
            // The streamed m0, m1 prefix (the direct row convolution's) is the stored one's, bit
            // for bit, texel by texel.
            let mut seen = 0;
            rm.prefix01(j, |k, l, m| {
                assert_eq!((k, l), (seen, row.texel(k)));
                assert_eq!((m.m0, m.m1), (row.cum()[k].m0, row.cum()[k].m1), "row {j} edge {k}");
                seen += 1;
            });
            assert_eq!(seen, map.width());
            let t = rm.row_total01(j);
            assert_eq!((t.m0, t.m1), (row.cum()[map.width()].m0, row.cum()[map.width()].m1));
        }
    }

    #[test]
    fn arc_moments_match_brute_force() {
        let map = test_map();
        let rm = RowMoments::new(&map);
        for &(lo, len) in &[(-1.0, 0.5), (2.9, 1.0), (-4.0, 3.0), (0.123, 6.0), (-PI, TAU)] {
            let got = rm.arc(&rm.prefix(3), Arc { lo, len });
            let want = brute(&map, 3, lo, lo + len);
            let d = got - want;
            let err =
                [d.m0, d.m1[0], d.m1[1], d.m2[0], d.m2[1]].iter().map(|v| v.abs().max_element()).fold(0.0, f64::max);
            assert!(err < 5e-5, "arc ({lo},{len}): err {err}");
        }
    }
}
