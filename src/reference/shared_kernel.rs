//! The capped references of one surface evaluated together: several [`Reference`]s of one map
//! (the cone effect's cones about one surface normal N, say) at the same output normals.
//!
//! What a normal needs on a row is partly its own and partly its masks': the clamped cosine's
//! arc on each node's parallel (an `acos`, `Cap::arc`) and F, the row's cumulative moments, at
//! that arc's two ends belong to the normal alone; the visible pieces belong to the masks. On
//! a row that neither the kernel's nor a reference's mask boundary splits, every reference
//! integrates at the same Gauss–Legendre nodes, so the kernel arc and F at its ends are
//! computed once a node for all of them, and each row's prefix sums once a batch for all of
//! them. Each reference still adds its rows, nodes and arcs in the order of
//! [`Reference::irradiance`] (a split row goes through its own path), so every value equals
//! the one-reference path bit for bit.

use crate::envmap::moments::RowPrefix;
use crate::math::colour::Rgb;
use crate::reference::exact::{Kernel, KernelEnds, Reference, BATCH};
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::FRAC_1_PI;

/// E/π at `normals` under each reference of `refs`: `out[r][i]` is
/// `refs[r].irradiance_many(normals)[i]`, bit for bit. References of different maps or polar
/// rules share nothing and are evaluated one by one.
pub fn irradiance_many_together(refs: &[&Reference], normals: &[DVec3]) -> Vec<Vec<Rgb>> {
    let Some(first) = refs.first() else { return Vec::new() };
    let shareable = refs.iter().all(|r| std::ptr::eq(r.moments, first.moments) && r.rule == first.rule);
    if !shareable || refs.len() == 1 {
        return refs.iter().map(|r| r.irradiance_many(normals)).collect();
    }
    let nr = refs.len();
    // Normal-major: the values of normal i are out[i·R .. i·R + R].
    let mut out = vec![Rgb::ZERO; normals.len() * nr];
    let batch = BATCH.max(normals.len().div_ceil(2 * rayon::current_num_threads()));
    out.par_chunks_mut(batch * nr).zip(normals.par_chunks(batch)).for_each(|(acc, ns)| {
        let kernels: Vec<Kernel> = ns.iter().flat_map(|&n| refs.iter().map(move |r| r.kernel(n))).collect();
        let mut prefix = RowPrefix::new();
        let mut shared = Vec::with_capacity(nr);
        for j in 0..first.grid.height {
            first.moments.fill(j, &mut prefix);
            for (ks, a) in kernels.chunks(nr).zip(acc.chunks_mut(nr)) {
                add_row_together(refs, &prefix, ks, a, &mut shared);
            }
        }
        for a in acc.iter_mut() {
            *a *= FRAC_1_PI;
        }
    });
    (0..nr).map(|r| out.iter().skip(r).step_by(nr).copied().collect()).collect()
}

/// Adds row `prefix.row()` for one normal to each reference's sum: `ks[r]` is the normal's
/// kernel under `refs[r]` (the same clamped-cosine cap in each, only the masks' breakpoints
/// differ) and `acc[r]` its sum. `shared` is scratch.
fn add_row_together(refs: &[&Reference], prefix: &RowPrefix, ks: &[Kernel], acc: &mut [Rgb], shared: &mut Vec<usize>) {
    let j = prefix.row();
    let grid = refs[0].grid;
    let (p0, p1) = (grid.phi_edge(j), grid.phi_edge(j + 1));
    let k = &ks[0];
    let kernel_splits = k.splits_row(p0, p1);
    shared.clear();
    for (r, reference) in refs.iter().enumerate() {
        let row = &reference.rows[j];
        if kernel_splits || row.split {
            // Nodes of this reference's own: its one-reference path.
            reference.add_row(prefix, &ks[r], &mut acc[r]);
        } else if !row.dark {
            shared.push(r);
        }
    }
    let Some(&r0) = shared.first() else { return };
    // Unsplit rows have the same nodes in every reference (the row's rule, nothing else).
    let nodes = &refs[r0].rows[j].nodes;
    if k.misses_unsplit_row(nodes) {
        return;
    }
    for (q, &node) in nodes.iter().enumerate() {
        let Some(ka) = k.cap.arc(node.0, node.1) else { continue };
        let mut ends = KernelEnds::default();
        for &r in shared.iter() {
            let vis = &refs[r].rows[j].visible[q];
            if !vis.is_empty() {
                refs[r].add_arc(prefix, &ks[r], node, vis, ka, &mut ends, &mut acc[r]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::envmap::moments::RowMoments;
    use crate::envmap::EnvMap;
    use crate::math::cap::Cap;
    use crate::reference::domain::{frame_to, Domain};

    /// Every reference evaluated together equals its own per-normal path bit for bit (so far
    /// below the 1e-9 relative the paths must agree to): cones about both poles and a tilted
    /// normal, at several openings and tilts (caps whose breakpoints split rows, cones that
    /// miss whole rows), with and without the hemisphere effect, at the hemisphere grid's
    /// normals about N.
    #[test]
    fn together_equals_one_by_one() {
        let map = EnvMap::from_fn("t", 64, 32, |i, j| {
            let v = ((i * 7 + j * 3) % 11) as f32 * 0.5 + 0.1;
            [v, v * 0.5 + j as f32, (i as f32).sqrt()]
        })
        .unwrap();
        let rm = RowMoments::new(&map);
        for n in [DVec3::Y, DVec3::NEG_Y, DVec3::new(0.3, 0.8, -0.5).normalize(), DVec3::X] {
            let mut sets = vec![vec![Cap::hemisphere(n)]];
            for tilt in [0.0, 30.0, 65.0] {
                for cos_alpha in [-0.3, 0.0, 0.5, 0.9] {
                    // N tilted by `tilt` degrees towards its frame's tangent (the cone effect's centre).
                    let t: f64 = f64::to_radians(tilt);
                    let centre = (n * t.cos() + frame_to(n) * DVec3::X * t.sin()).normalize();
                    let cone = Cap::new(centre, cos_alpha);
                    sets.push(vec![cone]);
                    sets.push(vec![Cap::hemisphere(n), cone]);
                }
            }
            let refs: Vec<Reference> = sets.into_iter().map(|m| Reference::new(&rm, m, 2)).collect();
            let by_ref: Vec<&Reference> = refs.iter().collect();
            let normals = Domain::Hemisphere { normal: n }.output_grid((24, 12)).normals;
            let together = irradiance_many_together(&by_ref, &normals);
            let split = refs.iter().any(|r| r.rows.iter().any(|row| row.split));
            assert!(split, "some cap must split a row for n {n}");
            for (r, values) in refs.iter().zip(&together) {
                assert_eq!(*values, r.irradiance_many(&normals), "n {n}, caps {:?}", r.caps());
            }
        }
    }
}
