//! The exact reference: irradiance E/π of a map at any normal, under declared visibility caps.
//!
//! E/π(n) = (1/π) ∫ L(ω) max(0, n·ω) V(ω) dω, where L is the map read as piecewise-constant
//! radiance over its texel cells and V is the product of the declared effects' caps
//! (hemisphere about a surface normal N, cone about C). No Monte Carlo, f64 throughout.
//!
//! How: on the parallel of polar angle φ, n·ω = a cos(θ − θ_n) + b, and the support of the
//! clamped cosine and of every cap is an arc. The azimuth integral over those arcs is exact, from
//! the row's cumulative moments (`moments.rs`): O(1) per row instead of O(W). The polar
//! integral uses Gauss–Legendre nodes per row, with rows split where a cap boundary is tangent
//! to the parallel (the only places the integrand is not smooth in φ). Cost per normal:
//! O(H · nodes). `polar_nodes` is the one accuracy knob; see the convergence test.

use crate::envmap::moments::{Moments01, RowMoments, RowPrefix};
use crate::envmap::LatLong;
use crate::math::cap::{Arc, Arcs, Cap};
use crate::math::colour::Rgb;
use crate::math::quadrature::{for_each_polar_node, gauss_legendre};
use crate::reference::row_convolution;
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::{FRAC_1_PI, TAU};

/// Default Gauss–Legendre nodes per row piece. Chosen from the convergence study in the tests
/// and the polar-nodes sweep (`experiments/sweeps/polar_nodes.toml`): 2 nodes agree with 8 to better than 1e-7 relative on
/// the generated scenes at 256×128.
pub const DEFAULT_POLAR_NODES: usize = 2;

/// The exact irradiance of one map under a fixed set of visibility caps.
pub struct Reference<'a> {
    pub(super) moments: &'a RowMoments<'a>,
    masks: Vec<Cap>,
    pub(super) rule: Vec<(f64, f64)>,
    pub(super) grid: LatLong,
    /// Per row, everything that does not depend on the normal (see [`RowCache`]).
    pub(super) rows: Vec<RowCache>,
}

/// What one row contributes independently of the normal: its Gauss–Legendre nodes (split at
/// the masks' breakpoints inside it, if any) and, at each node, the masks' intersection as arc
/// pieces with the row's cumulative moments at their ends. The kernel's own breakpoints depend
/// on the normal; a row they split is integrated on the fly.
pub(super) struct RowCache {
    /// (sin φ, cos φ, w·sin φ) per node.
    pub(super) nodes: Vec<(f64, f64, f64)>,
    /// Whether a mask's breakpoint splits the row (`nodes` are then the split row's).
    pub(super) split: bool,
    /// Per node, the pieces of the masks' intersection on its parallel.
    pub(super) visible: Vec<Visible>,
    /// Unsplit, and some mask misses the parallel of every node: no mask breakpoint lies
    /// inside the row, so that mask misses the whole row and it adds nothing for any normal.
    pub(super) dark: bool,
}

/// The visible part of one parallel (the intersection of every mask's arc): up to four arc
/// pieces, each with the cumulative moments F at its ends, and their sum. A kernel arc then
/// needs F only at its own two ends: the ends it shares with a piece are looked up here.
#[derive(Clone, Copy)]
pub(super) struct Visible {
    /// The whole circle is visible (no masks, or every mask covers the parallel).
    full: bool,
    n: usize,
    pieces: [Piece; 4],
    /// Σ over pieces of F(hi) − F(lo): the moments of everything visible on the parallel.
    total: Moments01,
}

#[derive(Clone, Copy, Default)]
struct Piece {
    lo: f64,
    len: f64,
    f_lo: Moments01,
    f_hi: Moments01,
}

impl Visible {
    /// The masks' intersection on the parallel (s, c) of row j, with F at every piece end
    /// (`row`, row j's prefix, is read only when a mask cuts the parallel).
    fn new(moments: &RowMoments, j: usize, row: &RowPrefix, masks: &[Cap], s: f64, c: f64) -> Self {
        let mut arcs = Arcs::full();
        for m in masks {
            if arcs.is_empty() {
                break;
            }
            arcs = arcs.intersect(m.arc(s, c));
        }
        let mut v = Visible { full: false, n: 0, pieces: [Piece::default(); 4], total: Moments01::default() };
        match arcs.as_slice() {
            [a] if a.len >= TAU => {
                v.full = true;
                v.total = moments.row_total01(j);
            }
            pieces => {
                for a in pieces {
                    let (f_lo, f_hi) = (moments.cumulative01(row, a.lo), moments.cumulative01(row, a.hi()));
                    v.total += f_hi - f_lo;
                    v.pieces[v.n] = Piece { lo: a.lo, len: a.len, f_lo, f_hi };
                    v.n += 1;
                }
            }
        }
        v
    }

    pub(super) fn is_empty(&self) -> bool {
        !self.full && self.n == 0
    }
}

/// What one normal needs for every row: its clamped-cosine cap, every breakpoint (the kernel's
/// first, then the masks'), and the azimuth of n.
pub(super) struct Kernel {
    pub(super) cap: Cap,
    pub(super) breaks: [f64; 8],
    pub(super) nb: usize,
    sin_t: f64,
    cos_t: f64,
}

impl Kernel {
    /// The kernel's own boundary is tangent inside the row (p0, p1): its arcs change shape there,
    /// so the row is split at every breakpoint and integrated on the fly.
    pub(super) fn splits_row(&self, p0: f64, p1: f64) -> bool {
        self.breaks[..2.min(self.nb)].iter().any(|&b| b > p0 && b < p1)
    }

    /// On a row no cap boundary is tangent inside, the arcs keep their shape, so a row the
    /// kernel misses at its first node is missed at all of them.
    pub(super) fn misses_unsplit_row(&self, nodes: &[(f64, f64, f64)]) -> bool {
        let (s, c, _) = nodes[0];
        self.cap.arc(s, c).is_none()
    }
}

/// F, the row's cumulative moments, at the two ends of one node's kernel arc: each computed at
/// most once, however many pieces (and, in `reference::shared_kernel`, mask sets) read it.
#[derive(Default)]
pub(super) struct KernelEnds {
    lo: Option<Moments01>,
    hi: Option<Moments01>,
}

impl KernelEnds {
    #[inline]
    fn lo(&mut self, moments: &RowMoments, row: &RowPrefix, ka: Arc) -> Moments01 {
        *self.lo.get_or_insert_with(|| moments.cumulative01(row, ka.lo))
    }
    #[inline]
    fn hi(&mut self, moments: &RowMoments, row: &RowPrefix, ka: Arc) -> Moments01 {
        *self.hi.get_or_insert_with(|| moments.cumulative01(row, ka.lo + ka.len))
    }
}

/// Fewest normals per batch of [`Reference::irradiance_many`]: each batch builds every row's
/// prefix sums once (O(W)) and streams them past all its normals, so a batch is made large
/// enough (two per thread) that the rebuilding costs little next to the normals' work.
pub(super) const BATCH: usize = 256;

impl<'a> Reference<'a> {
    /// A reference for the map whose moments are given, with light visible only inside every
    /// cap of `masks` (empty: the whole sphere), integrating each row piece with `polar_nodes`
    /// Gauss–Legendre nodes.
    pub fn new(moments: &'a RowMoments<'a>, masks: Vec<Cap>, polar_nodes: usize) -> Self {
        let rule = gauss_legendre(polar_nodes.max(1));
        let grid = LatLong::new(moments.width(), moments.height());
        let mut mask_breaks = [0.0f64; 8];
        let mut nm = 0;
        for c in &masks {
            for b in c.breakpoints() {
                // The kernel's two breakpoints come first in `Kernel::breaks`: room for 6.
                if nm < mask_breaks.len() - 2 {
                    mask_breaks[nm] = b;
                    nm += 1;
                }
            }
        }
        let mask_breaks = &mask_breaks[..nm];
        let mut prefix = RowPrefix::new();
        let rows = (0..grid.height)
            .map(|j| {
                // Only the masks' pieces read the row's prefix sums.
                if !masks.is_empty() {
                    moments.fill(j, &mut prefix);
                }
                let (p0, p1) = (grid.phi_edge(j), grid.phi_edge(j + 1));
                let split = mask_breaks.iter().any(|&b| b > p0 && b < p1);
                let mut nodes = Vec::with_capacity(rule.len());
                let mut visible = Vec::with_capacity(rule.len());
                let mut missed = vec![true; masks.len()];
                for_each_polar_node(p0, p1, if split { mask_breaks } else { &[] }, &rule, |phi, w| {
                    let (s, c) = phi.sin_cos();
                    nodes.push((s, c, w * s));
                    for (miss, m) in missed.iter_mut().zip(&masks) {
                        *miss &= m.arc(s, c).is_none();
                    }
                    visible.push(Visible::new(moments, j, &prefix, &masks, s, c));
                });
                let dark = !split && missed.iter().any(|&m| m);
                RowCache { nodes, split, visible, dark }
            })
            .collect();
        Self { moments, masks, rule, grid, rows }
    }

    /// The visibility caps this reference integrates under (empty: the whole sphere).
    #[cfg(test)]
    pub fn caps(&self) -> &[Cap] {
        &self.masks
    }

    /// A human-readable description for tables and reports.
    pub fn describe(&self) -> String {
        let parts = crate::math::quadrature::polar_pieces(self.grid.phi_edge(1));
        let cut =
            if parts > 1 { format!(", each row cut into {parts} pieces of at most pi/128") } else { String::new() };
        format!(
            "exact cell-integrated ({}x{} map, {} GL node(s)/row piece{cut})",
            self.grid.width,
            self.grid.height,
            self.rule.len()
        )
    }

    pub(super) fn kernel(&self, n: DVec3) -> Kernel {
        let cap = Cap::hemisphere(n);
        let mut breaks = [0.0f64; 8];
        let mut nb = 0;
        for c in std::iter::once(&cap).chain(&self.masks) {
            for b in c.breakpoints() {
                if nb < breaks.len() {
                    breaks[nb] = b;
                    nb += 1;
                }
            }
        }
        let (sin_t, cos_t) = cap.theta().sin_cos();
        Kernel { cap, breaks, nb, sin_t, cos_t }
    }

    /// One node's contribution: the clamped cosine of `k` on the parallel (s, c) of row j,
    /// integrated exactly in azimuth over its arc inside the visible part `vis`.
    #[inline]
    fn add_node(&self, row: &RowPrefix, k: &Kernel, node: (f64, f64, f64), vis: &Visible, acc: &mut Rgb) {
        if vis.is_empty() {
            return;
        }
        let Some(ka) = k.cap.arc(node.0, node.1) else { return };
        self.add_arc(row, k, node, vis, ka, &mut KernelEnds::default(), acc);
    }

    /// [`Self::add_node`] given the kernel's arc `ka` on the node's parallel (non-empty) and a
    /// memo of F at its ends, which the references of one normal's other masks share
    /// (`reference::shared_kernel`): the same arithmetic in the same order, so the same bits.
    ///
    /// With F the row's cumulative moments (F(θ + 2π) = F(θ) + T, T the row total), the kernel
    /// arc K = [k0, k0 + kl] meets a piece P = [p0, p0 + pl] in at most two arcs; their ends are
    /// ends of K (F computed here, at most once each) or of P shifted by whole turns (F from
    /// the cache plus multiples of T). A piece inside K adds its cached moments; a kernel
    /// covering the whole parallel adds the cached total.
    #[inline]
    pub(super) fn add_arc(
        &self,
        row: &RowPrefix,
        k: &Kernel,
        (s, c, ws): (f64, f64, f64),
        vis: &Visible,
        ka: Arc,
        ends: &mut KernelEnds,
        acc: &mut Rgb,
    ) {
        let m = if ka.len >= TAU {
            vis.total
        } else if vis.full {
            ends.hi(self.moments, row, ka) - ends.lo(self.moments, row, ka)
        } else {
            let (k0, kl) = (ka.lo, ka.len);
            let total = self.moments.row_total01(row.row());
            let mut m = Moments01::default();
            for p in &vis.pieces[..vis.n] {
                // The piece's start in K's frame: d = p0 − k0 + 2π·turns, in [0, 2π).
                let mut d = p.lo - k0;
                let mut turns = 0.0;
                while d < 0.0 {
                    d += TAU;
                    turns += 1.0;
                }
                while d >= TAU {
                    d -= TAU;
                    turns -= 1.0;
                }
                // F(p0 + 2π·n) = F(p0) + n·T, and k0 + d = p0 + 2π·turns.
                let shifted = |f: &Moments01, n: f64| {
                    let mut v = *f;
                    if n != 0.0 {
                        v.add_scaled(&total, n);
                    }
                    v
                };
                if d < kl {
                    // [k0 + d, k0 + min(d + pl, kl)]
                    if d + p.len <= kl {
                        m += p.f_hi - p.f_lo;
                    } else {
                        m += ends.hi(self.moments, row, ka) - shifted(&p.f_lo, turns);
                    }
                }
                let wrapped = d + p.len - TAU;
                if wrapped > 0.0 {
                    // [k0, k0 + min(d + pl − 2π, kl)]
                    let hi = if wrapped < kl { shifted(&p.f_hi, turns - 1.0) } else { ends.hi(self.moments, row, ka) };
                    m += hi - ends.lo(self.moments, row, ka);
                }
            }
            m
        };
        let (a, b) = k.cap.dot_coefficients(s, c);
        // ∫ L (a cos(θ − θn) + b) dθ = b·m0 + a·Re(e^{iθn} m1)
        *acc += (m.m0 * b + (m.m1[0] * k.cos_t - m.m1[1] * k.sin_t) * a) * ws;
    }

    /// Adds the polar integral of the prefix's row for kernel `k` to `acc` (before the 1/π).
    #[inline]
    pub(super) fn add_row(&self, prefix: &RowPrefix, k: &Kernel, acc: &mut Rgb) {
        let j = prefix.row();
        let (p0, p1) = (self.grid.phi_edge(j), self.grid.phi_edge(j + 1));
        let row = &self.rows[j];
        if row.dark {
            return;
        }
        if k.splits_row(p0, p1) {
            // The kernel's boundary is tangent inside the row: split at every breakpoint,
            // nodes and mask arcs computed here.
            for_each_polar_node(p0, p1, &k.breaks[..k.nb], &self.rule, |phi, w| {
                let (s, c) = phi.sin_cos();
                let vis = Visible::new(self.moments, j, prefix, &self.masks, s, c);
                self.add_node(prefix, k, (s, c, w * s), &vis, acc);
            });
        } else if row.split {
            for (&node, vis) in row.nodes.iter().zip(&row.visible) {
                self.add_node(prefix, k, node, vis, acc);
            }
        } else {
            if k.misses_unsplit_row(&row.nodes) {
                return;
            }
            for (&node, vis) in row.nodes.iter().zip(&row.visible) {
                self.add_node(prefix, k, node, vis, acc);
            }
        }
    }

    /// E/π at unit normal `n`.
    pub fn irradiance(&self, n: DVec3) -> Rgb {
        let k = self.kernel(n);
        let mut acc = Rgb::ZERO;
        let mut prefix = RowPrefix::new();
        for j in 0..self.grid.height {
            self.moments.fill(j, &mut prefix);
            self.add_row(&prefix, &k, &mut acc);
        }
        acc * FRAC_1_PI
    }

    /// E/π at many normals, in parallel batches. A batch runs row by row over all its normals
    /// (the row's moments stay in cache); each normal still adds its rows, nodes and arcs in
    /// the order of [`Self::irradiance`], so every value equals it bit for bit and does not
    /// depend on the thread count.
    pub fn irradiance_many(&self, normals: &[DVec3]) -> Vec<Rgb> {
        let mut out = vec![Rgb::ZERO; normals.len()];
        let batch = BATCH.max(normals.len().div_ceil(2 * rayon::current_num_threads()));
        out.par_chunks_mut(batch).zip(normals.par_chunks(batch)).for_each(|(acc, ns)| {
            let kernels: Vec<Kernel> = ns.iter().map(|&n| self.kernel(n)).collect();
            let mut prefix = RowPrefix::new();
            for j in 0..self.grid.height {
                self.moments.fill(j, &mut prefix);
                for (k, a) in kernels.iter().zip(acc.iter_mut()) {
                    self.add_row(&prefix, k, a);
                }
            }
            for a in acc.iter_mut() {
                *a *= FRAC_1_PI;
            }
        });
        out
    }

    /// E/π at the centres of a lat-long grid of normals (world orientation, row-major). With
    /// no caps every output row is a circular convolution of each input row
    /// ([`crate::reference::row_convolution`], any map and grid widths), the lower half mirrored
    /// from the upper (`reference::antipode`) except where that difference cancels, which is
    /// [`Self::irradiance_many`]; with caps this is [`Self::irradiance_many`].
    pub fn irradiance_latlong(&self, out: LatLong) -> Vec<Rgb> {
        self.irradiance_latlong_until(out, &|| false)
    }

    /// [`Self::irradiance_latlong`], checking `stop` between the map's rows: once it says
    /// stop, the rest is skipped and the values mean nothing (the caller that asked discards
    /// them).
    pub fn irradiance_latlong_until(&self, out: LatLong, stop: &(dyn Fn() -> bool + Sync)) -> Vec<Rgb> {
        if !self.masks.is_empty() || out.width == 0 || out.height == 0 {
            let normals: Vec<DVec3> = (0..out.height)
                .flat_map(|j| (0..out.width).map(move |i| (i, j)))
                .map(|(i, j)| out.direction(i, j))
                .collect();
            return self.irradiance_many(&normals);
        }
        let (mut values, cancelled) = row_convolution::irradiance_latlong(self.moments, &self.rule, out, stop);
        let normals: Vec<DVec3> = cancelled.iter().map(|&k| out.direction(k % out.width, k / out.width)).collect();
        for (k, v) in cancelled.into_iter().zip(self.irradiance_many(&normals)) {
            values[k] = v;
        }
        values
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::envmap::EnvMap;
    use std::f64::consts::PI;

    fn test_map(w: usize) -> EnvMap {
        EnvMap::from_fn("t", w, w / 2, |i, j| {
            let v = ((i * 7 + j * 3) % 11) as f32 * 0.5 + 0.1;
            [v, v * 0.5 + j as f32, (i as f32).sqrt()]
        })
        .unwrap()
    }

    /// Brute-force cell integration by s×s sub-cells (second-order accurate).
    fn brute(map: &EnvMap, s: usize, n: DVec3, masks: &[Cap]) -> Rgb {
        let g = map.grid();
        let fine = LatLong::new(g.width * s, g.height * s);
        let mut acc = Rgb::ZERO;
        for j in 0..fine.height {
            let om = fine.solid_angle(j);
            for i in 0..fine.width {
                let d = fine.direction(i, j);
                if !masks.iter().all(|c| c.contains(d)) {
                    continue;
                }
                let t = map.texel(i / s, j / s);
                acc += Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64) * (n.dot(d).max(0.0) * om);
            }
        }
        acc / PI
    }

    /// A constant environment of radiance 1 gives E/π = 1 (FORMULAS §1). The error falls
    /// with the polar node count and the map resolution; the default meets 1e-6 at 256×128.
    #[test]
    fn constant_map_converges_to_one() {
        let normals =
            [DVec3::Y, DVec3::X, DVec3::new(0.3, 0.5, 0.81).normalize(), DVec3::new(-0.1, -0.99, 0.05).normalize()];
        let worst = |w: usize, q: usize| {
            let map = EnvMap::from_fn("c", w, w / 2, |_, _| [1.0; 3]).unwrap();
            let rm = RowMoments::new(&map);
            let r = Reference::new(&rm, vec![], q);
            normals.iter().map(|&n| (r.irradiance(n) - Rgb::ONE).abs().max_element()).fold(0.0, f64::max)
        };
        let by_q: Vec<f64> = (1..=4).map(|q| worst(256, q)).collect();
        assert!(by_q.windows(2).all(|p| p[1] < p[0]), "not converging in q: {by_q:?}");
        assert!(worst(512, 2) < worst(256, 2) / 4.0);
        assert!(worst(256, DEFAULT_POLAR_NODES) < 1e-6);
    }

    /// The reference on coarse maps: "exact" holds to its stated 1e-6 on every accepted map size, the
    /// coarsest included (a 2×1 map's one row gave E/π 9% off before rows were cut into pieces
    /// of at most π/128). Expected values are closed forms: 1 for a constant map; with the
    /// hemisphere cap about N, (1 + n·N)/2 (the cosine lobe's visible fraction); and for a map
    /// constant along each row, E/π(+Y) = Σ_j L_j (sin²φ_{j+1} − sin²φ_j) over the upper rows
    /// (∫ cos φ sin φ dφ = ½ sin²φ, times 2π/π).
    #[test]
    fn exact_on_every_map_size() {
        let normals = [DVec3::Y, DVec3::X, DVec3::new(0.3, 0.5, 0.81).normalize(), -DVec3::Y];
        for (w, h) in [(2, 1), (4, 2), (6, 3), (8, 4), (16, 8), (64, 32), (100, 50), (256, 128)] {
            let map = EnvMap::from_fn("c", w, h, |_, _| [1.0; 3]).unwrap();
            let rm = RowMoments::new(&map);
            let r = Reference::new(&rm, vec![], DEFAULT_POLAR_NODES);
            for &n in &normals {
                let e = r.irradiance(n);
                assert!((e - Rgb::ONE).abs().max_element() < 1e-6, "{w}x{h} n={n}: {e}");
            }
            let lat = r.irradiance_latlong(LatLong::new(w, h));
            assert!(lat.iter().all(|e| (*e - Rgb::ONE).abs().max_element() < 1e-6), "{w}x{h} lat-long path");
            let hemi = Reference::new(&rm, vec![Cap::hemisphere(DVec3::Y)], DEFAULT_POLAR_NODES);
            for &n in &normals {
                let want = 0.5 * (1.0 + n.dot(DVec3::Y));
                let e = hemi.irradiance(n);
                assert!((e - Rgb::splat(want)).abs().max_element() < 1e-6, "{w}x{h} hemisphere n={n}: {e}");
            }
            // Rows of different radiance, constant along each row.
            let rows = EnvMap::from_fn("r", w, h, |_, j| [1.0 + j as f32, 2.0, 0.5 * (j % 3) as f32]).unwrap();
            let rm = RowMoments::new(&rows);
            let r = Reference::new(&rm, vec![], DEFAULT_POLAR_NODES);
            let mut want = Rgb::ZERO;
            for j in 0..h {
                let (p0, p1) = (PI * j as f64 / h as f64, (PI * (j + 1) as f64 / h as f64).min(0.5 * PI));
                if p1 > p0 {
                    let t = rows.texel(0, j);
                    want += Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64) * (p1.sin().powi(2) - p0.sin().powi(2));
                }
            }
            let e = r.irradiance(DVec3::Y);
            assert!((e - want).abs().max_element() < 1e-6 * want.max_element(), "{w}x{h} rows: {e} vs {want}");
        }
    }

    #[test]
    fn matches_brute_force_cell_integration() {
        let map = test_map(32);
        let rm = RowMoments::new(&map);
        let mask = [Cap::hemisphere(DVec3::new(0.8, 0.1, -0.59).normalize())];
        for masks in [&[][..], &mask[..]] {
            let r = Reference::new(&rm, masks.to_vec(), 4);
            for n in [DVec3::new(0.3, 0.5, 0.81).normalize(), DVec3::new(0.9, -0.2, 0.1).normalize()] {
                let ours = r.irradiance(n);
                let b1 = brute(&map, 8, n, masks);
                let b2 = brute(&map, 32, n, masks);
                let (e1, e2) = ((ours - b1).abs().max_element(), (ours - b2).abs().max_element());
                assert!(e2 < e1 && e2 < 2e-4 * ours.max_element(), "{n}: {e1} {e2} {ours}");
            }
        }
    }

    /// The cached visible pieces give what intersecting every arc afresh at every node gives
    /// (the direct method: kernel arc ∩ each mask's arc, moments of each resulting arc), here
    /// for two masks whose visible part straddles the ±π seam and splits into two arcs on some
    /// parallels, and normals whose kernel arcs wrap. Same nodes, so equal to rounding; and both
    /// converge to brute-force cell integration.
    #[test]
    fn cached_pieces_equal_direct_arc_intersection() {
        let map = test_map(64);
        let rm = RowMoments::new(&map);
        let grid = map.grid();
        // Two hemispheres tilted apart: just above the equator each covers more than half of
        // the parallel about opposite azimuths, so their intersection is two arcs; a wide
        // cone about −x puts piece ends near the seam.
        let masks = vec![
            Cap::hemisphere(DVec3::new(0.45, 0.85, 0.1).normalize()),
            Cap::hemisphere(DVec3::new(-0.45, 0.85, 0.05).normalize()),
            Cap::new(DVec3::new(-0.9, 0.3, 0.05).normalize(), -0.6),
        ];
        let q = 3;
        let r = Reference::new(&rm, masks.clone(), q);
        let rule = gauss_legendre(q);
        let direct = |n: DVec3| {
            let k = Cap::hemisphere(n);
            let breaks: Vec<f64> = std::iter::once(&k).chain(&masks).flat_map(|c| c.breakpoints()).collect();
            let (st, ct) = k.theta().sin_cos();
            let mut acc = Rgb::ZERO;
            for j in 0..grid.height {
                let row = rm.prefix(j);
                for_each_polar_node(grid.phi_edge(j), grid.phi_edge(j + 1), &breaks, &rule, |phi, w| {
                    let (s, c) = phi.sin_cos();
                    let arcs = masks.iter().fold(Arcs::full().intersect(k.arc(s, c)), |a, m| a.intersect(m.arc(s, c)));
                    let (a, b) = k.dot_coefficients(s, c);
                    for arc in arcs.as_slice() {
                        let m = rm.arc(&row, *arc);
                        acc += (m.m0 * b + (m.m1[0] * ct - m.m1[1] * st) * a) * (w * s);
                    }
                });
            }
            acc / PI
        };
        let (mut two_pieces, mut seam) = (false, false);
        for j in 0..grid.height {
            let phi = 0.5 * (grid.phi_edge(j) + grid.phi_edge(j + 1));
            let (s, c) = phi.sin_cos();
            let arcs = masks.iter().fold(Arcs::full(), |a, m| a.intersect(m.arc(s, c)));
            two_pieces |= arcs.as_slice().len() == 2;
            seam |= arcs.as_slice().iter().any(|a| a.len < TAU && (a.lo < -PI || a.hi() > PI));
        }
        assert!(two_pieces && seam, "the masks must leave two pieces on a parallel, and one across the seam");
        for n in crate::reference::domain::fibonacci_sphere(200) {
            let (ours, want) = (r.irradiance(n), direct(n));
            let scale = want.max_element().max(1e-3);
            assert!((ours - want).abs().max_element() <= 1e-12 * scale, "{n}: {ours} vs {want}");
        }
        let n = DVec3::new(0.2, 0.9, -0.3).normalize();
        let ours = r.irradiance(n);
        let (e1, e2) = (
            (ours - brute(&map, 4, n, &masks)).abs().max_element(),
            (ours - brute(&map, 16, n, &masks)).abs().max_element(),
        );
        assert!(ours.max_element() > 0.01 && e2 < e1, "{n}: {e1} {e2} {ours}");
    }

    /// The batched row-by-row path equals the per-normal one bit for bit, with no caps, with
    /// caps whose breakpoints split rows, and with more masks than the on-the-fly buffer holds.
    #[test]
    fn batched_path_equals_per_normal_path() {
        let map = test_map(64);
        let rm = RowMoments::new(&map);
        let c = |x: f64, y: f64, z: f64, cos: f64| Cap::new(DVec3::new(x, y, z).normalize(), cos);
        let sets = [
            vec![],
            vec![c(0.0, 1.0, 0.0, 0.0)],
            vec![c(0.3, 0.8, -0.2, 0.0), c(0.5, 0.7, 0.1, 0.6)],
            vec![
                c(0.3, 0.8, -0.2, 0.0),
                c(0.5, 0.7, 0.1, -0.3),
                c(0.1, 0.9, 0.0, 0.2),
                c(0.0, 1.0, 0.2, 0.1),
                c(0.2, 1.0, 0.0, 0.3),
            ],
        ];
        let normals = crate::reference::domain::fibonacci_sphere(600);
        for masks in sets {
            let r = Reference::new(&rm, masks.clone(), 2);
            let many = r.irradiance_many(&normals);
            for (n, v) in normals.iter().zip(&many) {
                assert_eq!(*v, r.irradiance(*n), "{} masks, n {n}", masks.len());
            }
        }
    }

    #[test]
    fn fast_latlong_path_equals_general_path() {
        let map = test_map(64);
        let rm = RowMoments::new(&map);
        let r = Reference::new(&rm, vec![], 2);
        // 18 and 27 columns: classes of two columns and of one, padded to whole blocks of four.
        for out in
            [LatLong::new(64, 20), LatLong::new(32, 16), LatLong::new(16, 9), LatLong::new(18, 9), LatLong::new(27, 8)]
        {
            let fast = r.irradiance_latlong(out);
            for j in 0..out.height {
                for i in 0..out.width {
                    let g = r.irradiance(out.direction(i, j));
                    let d = (fast[j * out.width + i] - g).abs().max_element();
                    assert!(d < 1e-11 * g.max_element().max(1.0), "{out:?} ({i},{j}) {d}");
                }
            }
        }
    }
}
