//! The probe synthesiser: deterministic synthetic L2 SH radiance probes at any scale, for
//! scoring encoders on far more lighting than the stored maps hold.
//!
//! ## Synthetic probes (`probelab probes --synth N --seed S`)
//!
//! Probe i depends only on (S, i, palette), never on chunking, threads or shards. Drawn from a
//! SplitMix64 stream seeded by (S, i):
//! - with probability 0.8, a palette map's SH3 (normalised to mean radiance luminance 1), under a
//!   uniformly random rotation (Shoemake) and an exposure 2^U(−3, 3);
//! - coloured ambient (always without a map, else with probability ½): constant radiance of
//!   luminance 2^U(−4, 0) · exposure;
//! - 0–3 lights (at least one without a map), each with a random colour and a uniformly random
//!   direction: directional (E/π facing it 2^U(−2, 3)), sphere (a cap of half-angle 0.5°–15°,
//!   E/π on its axis 2^U(−2, 3)) or cone (a cap of half-angle 15°–60°, E/π on its axis
//!   2^U(−3, 1)), all scaled by the exposure. Their SH are closed forms (`lighting::Light`).
//!
//! The palette is the SH3 of every `*_256x128` map on the search path (`PROBELAB_ENVMAPS`), or
//! the maps named with `--palette`; with none found, the generated analytic scenes' closed-form
//! SH. The palette's fingerprint is part of the set's identity (merging checks it).

use crate::math::colour::luminance;
use crate::math::colour::Rgb;
use crate::math::sh::{constant, delta_light, Sh9};
use crate::math::sh_rotation::{uniform_rotation, ShRotation};
use crate::reference::lighting::Light;
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny counter-based generator, seeded per probe.
/// Part of the product, not a test helper: every synthetic set is defined by its exact stream.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl SplitMix64 {
    /// The stream of probe `index` of the set seeded by `seed`.
    pub fn for_probe(seed: u64, index: u64) -> Self {
        SplitMix64(mix64(seed ^ mix64(index.wrapping_add(0x9e37_79b9_7f4a_7c15))))
    }
    /// The next 64 random bits of the stream.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        mix64(self.0)
    }
    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f64()
    }
    /// Uniform integer in [0, n).
    pub fn below(&mut self, n: usize) -> usize {
        (((self.next_u64() >> 32) * n as u64) >> 32) as usize
    }
    /// A uniformly random unit vector.
    pub fn direction(&mut self) -> DVec3 {
        let z = self.uniform(-1.0, 1.0);
        let (s, c) = (TAU * self.f64()).sin_cos();
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * c, r * s, z)
    }
    /// A random light colour of Rec.709 luminance 1 (saturation up to 0.6).
    pub fn colour(&mut self) -> Rgb {
        let s = self.uniform(0.0, 0.6);
        let c = Rgb::new(self.f64(), self.f64(), self.f64()).map(|u| (1.0 + s * (2.0 * u - 1.0)).max(0.05));
        c / luminance(c)
    }
}

/// The probe synthesiser (see the module doc).
#[derive(Clone, Debug)]
pub struct Synth {
    /// The seed every probe's stream is derived from.
    pub seed: u64,
    /// Palette SH3, each normalised to mean radiance luminance 1.
    palette: Vec<Sh9>,
    /// Names of the palette maps, in palette order.
    pub palette_names: Vec<String>,
}

impl Synth {
    /// A synthesiser over `palette` (name, radiance SH3); entries with no light are dropped.
    pub fn new(seed: u64, palette: Vec<(String, Sh9)>) -> Self {
        let mut names = Vec::new();
        let mut sh = Vec::new();
        for (n, s) in palette {
            let mean = luminance(s[0] * crate::math::sh::k::Y00);
            if mean > 0.0 && s.is_finite() {
                names.push(n);
                sh.push(s * (1.0 / mean));
            }
        }
        Synth { seed, palette: sh, palette_names: names }
    }

    /// A short fingerprint of the seed and palette (FNV-1a over their bits).
    pub fn fingerprint(&self) -> String {
        let mut h = 0xcbf2_9ce4_8422_2325u64;
        let mut eat = |x: u64| {
            for b in x.to_le_bytes() {
                h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
            }
        };
        eat(self.seed);
        // Coefficient-major, as in a probe file.
        for s in &self.palette {
            for v in s.0.iter().flat_map(|c| c.to_array()) {
                eat(v.to_bits());
            }
        }
        format!("{h:016x}")
    }

    /// Probe `i` of the set.
    pub fn probe(&self, i: u64) -> Sh9 {
        let mut rng = SplitMix64::for_probe(self.seed, i);
        let mut sh = Sh9::ZERO;
        let with_map = !self.palette.is_empty() && rng.f64() < 0.8;
        let exposure = 2f64.powf(rng.uniform(-3.0, 3.0));
        if with_map {
            let m = &self.palette[rng.below(self.palette.len())];
            let q = uniform_rotation(rng.f64(), rng.f64(), rng.f64());
            sh = ShRotation::from_quat(q).apply(m) * exposure;
        }
        if !with_map || rng.f64() < 0.5 {
            let c = rng.colour() * (2f64.powf(rng.uniform(-4.0, 0.0)) * exposure);
            sh = sh + constant(c);
        }
        let lights = (rng.below(4) + usize::from(!with_map)).min(3);
        for _ in 0..lights {
            let kind = rng.below(3);
            let d = rng.direction();
            let colour = rng.colour() * exposure;
            sh = sh
                + match kind {
                    // Directional: E/π facing it = e/π.
                    0 => delta_light(d, colour * (PI * 2f64.powf(rng.uniform(-2.0, 3.0)))),
                    // Sphere and cone lights: caps; on their axis E/π = L·sin²α (FORMULAS §1 units).
                    _ => {
                        let (lo, hi, e_lo, e_hi) =
                            if kind == 1 { (0.5, 15.0, -2.0, 3.0) } else { (15.0, 60.0, -3.0, 1.0) };
                        let alpha = rng.uniform(lo, hi).to_radians();
                        let e = 2f64.powf(rng.uniform(e_lo, e_hi));
                        Light::Cap { axis: d, half_angle: alpha, radiance: colour * (e / alpha.sin().powi(2)) }.sh()
                    }
                };
        }
        sh
    }

    /// Probes [start, end) in parallel (index order).
    pub fn probes(&self, start: u64, end: u64) -> Vec<Sh9> {
        (start..end).into_par_iter().map(|i| self.probe(i)).collect()
    }
}

/// The generated analytic scenes' closed-form SH (name, radiance SH3): the palette when no map
/// is found.
pub fn scene_palette() -> Vec<(String, Sh9)> {
    crate::reference::scenes::generated().into_iter().map(|s| (s.id.clone(), s.sh())).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn synthesis_is_deterministic_and_physical() {
        let s = Synth::new(7, scene_palette());
        assert_eq!(s.probe(12345), s.probe(12345));
        assert_ne!(s.probe(1), s.probe(2));
        assert_ne!(Synth::new(8, scene_palette()).probe(1), s.probe(1));
        assert_eq!(s.probes(10, 20)[3], s.probe(13));
        // Every probe is a sum of non-negative lights: its mean radiance is positive, and its
        // SH3 irradiance (a smoothed non-negative function) is mostly non-negative.
        for i in 0..2000 {
            let p = s.probe(i);
            assert!(p.is_finite() && p[0].min_element() > 0.0, "probe {i}: {:?}", p[0]);
        }
    }
}
