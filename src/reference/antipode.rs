//! Half of a lat-long grid of exact irradiance from the other half (FORMULAS §1).
//!
//! The clamped cosine splits as max(0, x) = x + max(0, −x). With x = n·ω:
//!
//! E/π(−n) = (1/π) ∫ L(ω) max(0, −n·ω) dω = E/π(n) − n·M₁/π,  M₁ = ∫ L(ω) ω dω,
//!
//! M₁ being the map's first moment (radiance times direction over the sphere, so n·M₁/π is the
//! band-1 part of E/π scaled by 1; a constant map has M₁ = 0 and E/π = 1 on both sides).
//!
//! On a grid of even width w the antipode of the normal at (column i, row j) is the normal at
//! (i + w/2 mod w, H − 1 − j): φ → π − φ, θ → θ + π. The polar breakpoints of a normal at φₒ
//! (|φₒ − π/2| and π − |φₒ − π/2|, where its kernel is tangent to a parallel) are those of its
//! antipode, so both are integrated with the same polar nodes, and the identity holds node by
//! node: on each parallel the arc where x > 0 and its complement together make the circle,
//! whose integral of L·x is b·m₀ + a·Re(e^{iθₙ} m₁) with the row's total moments
//! (`envmap::moments`). n·M₁ is therefore integrated here with exactly those nodes, and the
//! mirrored half equals what the per-normal path gives to rounding (the rounding of a
//! difference: about 1e-16 of E/π(n), a relative 1e-16·E(n)/E(−n) on the darker side).

use crate::envmap::moments::RowMoments;
use crate::envmap::LatLong;
use crate::math::colour::Rgb;
use crate::math::quadrature::for_each_polar_node;
use std::f64::consts::{FRAC_1_PI, PI};

/// The output rows computed directly: all of them when the width is odd (an antipode is then
/// not a grid normal), else the upper ⌈H/2⌉ (a middle row, when H is odd, is its own mirror's
/// row and is computed).
pub(crate) fn direct_rows(out: LatLong) -> usize {
    if out.width % 2 == 0 {
        out.height.div_ceil(2)
    } else {
        out.height
    }
}

/// Each input row's polar nodes when no breakpoint splits it, (sin φ, cos φ, weight) each:
/// what [`linear_parts`] reads for every output row whose breakpoints miss the row (most of
/// them), instead of taking the same sines again.
fn unsplit_nodes(rule: &[(f64, f64)], rows: usize) -> Vec<Vec<(f64, f64, f64)>> {
    (0..rows)
        .map(|j| {
            let mut nodes = Vec::with_capacity(rule.len());
            let (p0, p1) = (PI * j as f64 / rows as f64, PI * (j + 1) as f64 / rows as f64);
            for_each_polar_node(p0, p1, &[], rule, |phi, wt| {
                let (s, c) = phi.sin_cos();
                nodes.push((s, c, wt));
            });
            nodes
        })
        .collect()
}

/// n·M₁ integrated with the polar nodes of output row `jo`, for the normals of that row, as
/// three parts: ∫∫ L n·ω = z + x·cos θₙ − y·sin θₙ (before the 1/π). `unsplit` are
/// [`unsplit_nodes`]; a row that one of the output row's breakpoints splits takes its own.
fn linear_parts(moments: &RowMoments, rule: &[(f64, f64)], unsplit: &[Vec<(f64, f64, f64)>], phi_o: f64) -> [Rgb; 3] {
    let (sin_o, cos_o) = phi_o.sin_cos();
    let half_pi = 0.5 * PI;
    let breaks = [(phi_o - half_pi).abs(), PI - (half_pi - phi_o).abs()];
    let rows = moments.height();
    let mut parts = [Rgb::ZERO; 3];
    for (j, nodes) in unsplit.iter().enumerate() {
        let total = moments.row_total(j);
        let (p0, p1) = (PI * j as f64 / rows as f64, PI * (j + 1) as f64 / rows as f64);
        let (mut sa, mut sb) = (0.0, 0.0);
        let mut add = |s: f64, c: f64, wt: f64| {
            sa += wt * s * sin_o * s;
            sb += wt * s * cos_o * c;
        };
        if breaks.iter().any(|&b| b > p0 && b < p1) {
            for_each_polar_node(p0, p1, &breaks, rule, |phi, wt| {
                let (s, c) = phi.sin_cos();
                add(s, c, wt);
            });
        } else {
            nodes.iter().for_each(|&(s, c, wt)| add(s, c, wt));
        }
        parts[0] += total.m0 * sb;
        parts[1] += total.m1[0] * sa;
        parts[2] += total.m1[1] * sa;
    }
    parts
}

/// Where the difference E/π(n) − n·M₁/π loses more digits than this fraction allows (a value
/// below `CANCELLED` of its antipode's, channel by channel), the mirrored value is not used: its
/// rounding, about 1e-16 of E/π(n), would be 1e-16/`CANCELLED` of the value itself. Such normals
/// face away from nearly all the light (under a single cone, the dark side).
pub(crate) const CANCELLED: f64 = 1e-3;

/// Fills rows [`direct_rows`]..H of `values` (E/π on the grid `out`, row-major) from their
/// antipodes in the rows above: E/π(−n) = E/π(n) − n·M₁/π. Returns the indices of the values
/// that cancelled (see [`CANCELLED`]), which the caller computes another way.
pub(crate) fn mirror(moments: &RowMoments, rule: &[(f64, f64)], out: LatLong, values: &mut [Rgb]) -> Vec<usize> {
    let (w, h) = (out.width, out.height);
    let top = direct_rows(out);
    let mut cancelled = Vec::new();
    let unsplit = unsplit_nodes(rule, moments.height());
    let columns: Vec<(f64, f64)> = (0..w).map(|i| out.theta_centre(i).sin_cos()).collect();
    for jo in top..h {
        let src = h - 1 - jo;
        let [z, x, y] = linear_parts(moments, rule, &unsplit, out.phi_centre(src));
        for (i, &(sin_t, cos_t)) in columns.iter().enumerate() {
            let linear = (z + x * cos_t - y * sin_t) * FRAC_1_PI;
            let e = values[src * w + i] - linear;
            let at = jo * w + (i + w / 2) % w;
            if e.cmplt(values[src * w + i] * CANCELLED).any() {
                cancelled.push(at);
            }
            values[at] = e.max(Rgb::ZERO);
        }
    }
    cancelled
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::envmap::EnvMap;
    use crate::reference::exact::Reference;
    use glam::DVec3;

    /// M₁ = ∫ L ω dω of a piecewise-constant map in closed form, cell by cell: with
    /// ω = (sin φ sin θ, cos φ, −sin φ cos θ) and dω = sin φ dφ dθ, ∫ sin²φ dφ = φ/2 − sin 2φ/4,
    /// ∫ sin φ cos φ dφ = sin²φ/2, ∫ sin θ dθ = −cos θ, ∫ cos θ dθ = sin θ.
    fn first_moment(map: &EnvMap) -> [DVec3; 3] {
        let g = map.grid();
        let mut m = [DVec3::ZERO; 3];
        for j in 0..g.height {
            let (p0, p1) = (g.phi_edge(j), g.phi_edge(j + 1));
            let s2 = (p1 - p0) / 2.0 - ((2.0 * p1).sin() - (2.0 * p0).sin()) / 4.0;
            let sc = (p1.sin().powi(2) - p0.sin().powi(2)) / 2.0;
            for i in 0..g.width {
                let (t0, t1) = (g.theta_edge(i), g.theta_edge(i + 1));
                let cell = DVec3::new(s2 * (t0.cos() - t1.cos()), sc * (t1 - t0), -s2 * (t1.sin() - t0.sin()));
                let t = map.texel(i, j);
                for (ch, m) in m.iter_mut().enumerate() {
                    *m += cell * t[ch] as f64;
                }
            }
        }
        m
    }

    /// The identity itself, by quadrature: E/π(n) − E/π(−n) from the per-normal path (8 polar
    /// nodes) against n·M₁/π with M₁ in closed form, for normals in every direction.
    #[test]
    fn difference_of_antipodes_is_the_first_moment() {
        let map = EnvMap::from_fn("t", 48, 24, |i, j| {
            let v = ((i * 7 + j * 3) % 11) as f32 * 0.5 + 0.1;
            [v, v * 0.5 + j as f32, (i as f32).sqrt()]
        })
        .unwrap();
        let rm = RowMoments::new(&map);
        let r = Reference::new(&rm, vec![], 8);
        let m1 = first_moment(&map);
        for n in crate::reference::domain::fibonacci_sphere(50) {
            let d = r.irradiance(n) - r.irradiance(-n);
            let want = Rgb::new(n.dot(m1[0]), n.dot(m1[1]), n.dot(m1[2])) * FRAC_1_PI;
            let scale = r.irradiance(n).max(r.irradiance(-n)).max_element();
            assert!((d - want).abs().max_element() < 1e-9 * scale, "{n}: {d} vs {want}");
        }
    }

    /// The mirrored half against the per-normal path, on grids of odd and even width and
    /// height (an odd width mirrors nothing; an odd height computes its middle row).
    #[test]
    fn mirrored_rows_equal_the_per_normal_path() {
        let map = EnvMap::from_fn("t", 40, 20, |i, j| [(i % 5) as f32 + 0.2, (j * j) as f32 * 0.1, 1.0]).unwrap();
        let rm = RowMoments::new(&map);
        let r = Reference::new(&rm, vec![], 2);
        for out in
            [LatLong::new(16, 9), LatLong::new(15, 8), LatLong::new(17, 7), LatLong::new(2, 1), LatLong::new(40, 20)]
        {
            assert_eq!(direct_rows(out) < out.height, out.width % 2 == 0 && out.height > 1);
            let fast = r.irradiance_latlong(out);
            for j in 0..out.height {
                for i in 0..out.width {
                    let want = r.irradiance(out.direction(i, j));
                    let d = (fast[j * out.width + i] - want).abs().max_element();
                    assert!(d < 1e-12 * want.max_element().max(1.0), "{out:?} ({i},{j}): {d}");
                }
            }
        }
    }
}
