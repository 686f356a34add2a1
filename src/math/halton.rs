//! The peer tool's fixed sample set on the sphere: Halton(2, 3) points mapped uniformly onto
//! the sphere (Probulator `Experiments.h`, `SharedData::generateSamples`, with `Math.h`'s
//! `sampleHalton` and `sampleUniformSphere`). Its SG and H-basis fits read the map's radiance
//! at these directions (the nearest texel), so a peer-compatible fit starts from the same set.
//!
//! Sample k (k = 0, 1, …) uses Halton index k + 1: u = h₂(k + 1), v = h₃(k + 1), then
//! z = 1 − 2u, r = √max(0, 1 − z²), ϕ = 2πv, direction (r cos ϕ, r sin ϕ, z) in world
//! coordinates (the peer's basis matrix is the identity). The peer computes in f32; this is
//! f64, so a direction within f32 rounding of a texel edge may read the neighbouring texel.

use glam::DVec3;
use std::f64::consts::TAU;

/// The peer's sample count (Probulator CLI `Main.cpp`: `sampleCount = 20000`).
pub const PEER_SAMPLE_COUNT: usize = 20_000;

/// The radical inverse of `index` in `base` (`sampleHalton`): digits of `index` mirrored about
/// the radix point.
pub fn halton(mut index: u32, base: u32) -> f64 {
    let (mut f, mut r) = (1.0, 0.0);
    let b = base as f64;
    while index > 0 {
        f /= b;
        r += f * (index % base) as f64;
        index /= base;
    }
    r
}

/// The k-th direction of the peer's set (k from 0), see the module doc.
pub fn peer_sphere_direction(k: usize) -> DVec3 {
    let i = k as u32 + 1;
    let (u, v) = (halton(i, 2), halton(i, 3));
    let z = 1.0 - 2.0 * u;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = (TAU * v).sin_cos();
    DVec3::new(r * c, r * s, z)
}

/// The first `count` directions of the peer's set, in its order.
pub fn peer_sphere_directions(count: usize) -> Vec<DVec3> {
    (0..count).map(peer_sphere_direction).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The radical inverse by hand: 1 → ½, 2 → ¼, 3 → ¾, 5 → 5/8 in base 2; 1 → ⅓, 2 → ⅔,
    /// 4 → 4/9 in base 3 (4 = 11₃ → 0.11₃ = 1/3 + 1/9).
    #[test]
    fn radical_inverse_by_hand() {
        for (i, b, want) in [
            (1, 2, 0.5),
            (2, 2, 0.25),
            (3, 2, 0.75),
            (5, 2, 0.625),
            (1, 3, 1.0 / 3.0),
            (2, 3, 2.0 / 3.0),
            (4, 3, 4.0 / 9.0),
        ] {
            assert!((halton(i, b) - want).abs() < 1e-15, "h_{b}({i})");
        }
        assert_eq!(halton(0, 2), 0.0);
    }

    /// The first direction by hand: u = ½, v = ⅓ → z = 0, ϕ = 2π/3. And the set is uniform:
    /// its mean direction and the mean of z² (⅓ for the uniform sphere) converge.
    #[test]
    fn directions_are_unit_and_uniform() {
        let d0 = peer_sphere_direction(0);
        let (s, c) = (TAU / 3.0).sin_cos();
        assert!((d0 - DVec3::new(c, s, 0.0)).length() < 1e-15);
        let dirs = peer_sphere_directions(PEER_SAMPLE_COUNT);
        assert!(dirs.iter().all(|d| (d.length() - 1.0).abs() < 1e-12));
        let n = dirs.len() as f64;
        let mean: DVec3 = dirs.iter().copied().sum::<DVec3>() / n;
        assert!(mean.length() < 2e-3, "{mean}");
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            let m2 = dirs.iter().map(|d| d.dot(axis).powi(2)).sum::<f64>() / n;
            assert!((m2 - 1.0 / 3.0).abs() < 2e-3, "{axis}: {m2}");
        }
    }
}
