//! Texel storage of an AHD/HHD model, including the IrradZ encodings of the 2018 brief
//! (eq. 4–7, FORMULAS §7): store I_z = I(N) instead of C_d and decode C_d = (I_z − C_a)/d_z,
//! optionally with the ambient as the luminance ratio L(C_a)/L(I_z) ∈ [0, 1].
//!
//! The direction is stored as its tangent-space xy about N (d_z = √(1 − x² − y²) ≥ 0 is
//! implied; N comes from the surface, so it is not stored). Both bases have I(N) = C_a + C_d d_z
//! (H(N) = 1), so the same decode serves AHD and HHD.
//!
//! | storage       | scalars                      | count |
//! |---------------|------------------------------|-------|
//! | `raw`         | C_a (3), C_d (3), d_xy (2)   | 8     |
//! | `irradz_rgb`  | C_a (3), I_z (3), d_xy (2)   | 8     |
//! | `irradz_luma` | L(C_a)/L(I_z), I_z (3), d_xy | 6     |
//!
//! Encoding with an IrradZ storage first puts d at least `MIN_DZ` above the horizon (keeping
//! its azimuth) so that the decode's division is bounded; `raw` keeps any d with d_z ≥ 0 and
//! mirrors a d below the horizon onto it (tangent xy cannot say "below").

use super::model::{Basis, Model};
use crate::math::colour::luminance as luma;
use crate::math::colour::Rgb;
use anyhow::{bail, Result};
use glam::DVec3;

/// Smallest d_z an IrradZ texel stores: cos 89.9°.
pub const MIN_DZ: f64 = 1.745_328_365_898_309e-3;

/// How a texel is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Storage {
    /// C_a, C_d and the direction's tangent xy: 8 scalars.
    Raw,
    /// C_a, I_z and the direction's tangent xy: 8 scalars (FORMULAS §7).
    IrradzRgb,
    /// The luminance ratio L(C_a)/L(I_z), I_z and the direction's tangent xy: 6 scalars (FORMULAS
    /// §7).
    IrradzLuma,
}

impl Storage {
    /// From the TOML value `raw`, `irradz_rgb` or `irradz_luma`.
    pub fn parse(s: &str) -> Result<Self> {
        Ok(match s {
            "raw" => Storage::Raw,
            "irradz_rgb" => Storage::IrradzRgb,
            "irradz_luma" => Storage::IrradzLuma,
            _ => bail!("unknown storage '{s}' (expected raw, irradz_rgb or irradz_luma)"),
        })
    }
    /// Scalars per texel (RGB counts 3).
    pub fn scalars(self) -> usize {
        match self {
            Storage::Raw | Storage::IrradzRgb => 8,
            Storage::IrradzLuma => 6,
        }
    }
}

/// A stored texel: the basis and N it belongs to (known from the encoder and the surface, not
/// stored), and its stored scalars (`storage.scalars()` of them are meaningful).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Texel {
    /// The model's ambient term (known from the encoder, not stored).
    pub basis: Basis,
    /// The surface normal N (known from the surface, not stored).
    pub normal: DVec3,
    /// Which layout `scalars` follows.
    pub storage: Storage,
    /// The stored scalars, in the layout of `storage` (only the first `storage.scalars()` are read).
    pub scalars: [f64; 8],
}

/// The tangent frame (t₁, t₂) of N (Duff et al.'s branchless ONB, glam).
pub fn tangent_frame(n: DVec3) -> (DVec3, DVec3) {
    n.any_orthonormal_pair()
}

impl Texel {
    /// Stores `m` (see the module table).
    pub fn encode(m: &Model, storage: Storage) -> Texel {
        let n = m.normal;
        let (t1, t2) = tangent_frame(n);
        let (mut x, mut y, mut z) = (m.d.dot(t1), m.d.dot(t2), m.d.dot(n).abs());
        if storage != Storage::Raw && z < MIN_DZ {
            let r = (x * x + y * y).sqrt();
            let s = (1.0 - MIN_DZ * MIN_DZ).sqrt();
            if r > 0.0 {
                (x, y) = (x / r * s, y / r * s);
            } else {
                (x, y) = (s, 0.0);
            }
            z = MIN_DZ;
        }
        let d = t1 * x + t2 * y + n * z;
        let fixed = Model { d, ..*m };
        let i_z = fixed.i_z();
        let mut s = [0.0; 8];
        let put = |s: &mut [f64; 8], at: usize, c: Rgb| s[at..at + 3].copy_from_slice(&c.to_array());
        match storage {
            Storage::Raw => {
                put(&mut s, 0, m.c_a);
                put(&mut s, 3, m.c_d);
                (s[6], s[7]) = (x, y);
            }
            Storage::IrradzRgb => {
                put(&mut s, 0, m.c_a);
                put(&mut s, 3, i_z);
                (s[6], s[7]) = (x, y);
            }
            Storage::IrradzLuma => {
                let l = luma(i_z);
                s[0] = if l > 0.0 { (luma(m.c_a) / l).clamp(0.0, 1.0) } else { 1.0 };
                put(&mut s, 1, i_z);
                (s[4], s[5]) = (x, y);
            }
        }
        Texel { basis: m.basis, normal: n, storage, scalars: s }
    }

    /// The model this texel decodes to. The stored tangent xy is renormalised if its length
    /// exceeds 1 (after blending); C_d is clamped at 0 (IrradZ: I_z below C_a in a channel).
    pub fn decode(&self) -> Model {
        let s = &self.scalars;
        let xy = match self.storage {
            Storage::IrradzLuma => (s[4], s[5]),
            _ => (s[6], s[7]),
        };
        let n = self.normal;
        let (t1, t2) = tangent_frame(n);
        let (mut x, mut y) = xy;
        let r2 = x * x + y * y;
        if r2 > 1.0 {
            let r = r2.sqrt();
            (x, y) = (x / r, y / r);
        }
        let z = (1.0 - x * x - y * y).max(0.0).sqrt();
        let d = t1 * x + t2 * y + n * z;
        let rgb = |at: usize| Rgb::new(s[at], s[at + 1], s[at + 2]);
        let (c_a, c_d) = match self.storage {
            Storage::Raw => (rgb(0), rgb(3)),
            Storage::IrradzRgb => {
                let (c_a, i_z) = (rgb(0), rgb(3));
                (c_a, ((i_z - c_a) / z.max(MIN_DZ)).max(Rgb::ZERO))
            }
            Storage::IrradzLuma => {
                let i_z = rgb(1);
                let c_a = i_z * s[0];
                (c_a, ((i_z - c_a) / z.max(MIN_DZ)).max(Rgb::ZERO))
            }
        };
        Model { basis: self.basis, normal: n, c_a, c_d, d }
    }

    /// The texel whose stored scalars are (1 − t)·a + t·b (what texture filtering does). The
    /// basis, N and storage are `a`'s; blending texels of different storages is meaningless and
    /// returns `a`'s layout applied to both scalar arrays.
    pub fn lerp(a: &Texel, b: &Texel, t: f64) -> Texel {
        let scalars = std::array::from_fn(|i| a.scalars[i] * (1.0 - t) + b.scalars[i] * t);
        Texel { scalars, ..*a }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::test_rng::Rng;

    fn random_model(r: &mut Rng, basis: Basis) -> Model {
        let n = r.unit();
        let mut d = r.unit();
        if d.dot(n) < 0.05 {
            d = (d - n * (d.dot(n) - 0.3)).normalize();
        }
        let col = |r: &mut Rng| Rgb::new(r.next().abs(), r.next().abs(), r.next().abs());
        Model { basis, normal: n, c_a: col(r), c_d: col(r), d }
    }

    #[test]
    fn raw_and_rgb_round_trip_exactly() {
        let mut r = Rng::new(8);
        for basis in [Basis::Ahd, Basis::Hhd] {
            for _ in 0..200 {
                let m = random_model(&mut r, basis);
                for st in [Storage::Raw, Storage::IrradzRgb] {
                    let back = Texel::encode(&m, st).decode();
                    assert!((back.c_a - m.c_a).abs().max_element() < 1e-12, "{st:?}");
                    assert!((back.c_d - m.c_d).abs().max_element() < 1e-10, "{st:?}");
                    assert!((back.d - m.d).length() < 1e-12);
                }
            }
        }
    }

    /// D1: the luminance-ratio texel decodes to I(N) = I_z exactly (C_a + (I_z − C_a) = I_z);
    /// its C_a is the stored ratio times I_z, so its chroma follows I_z's.
    #[test]
    fn luma_storage_keeps_i_z_exactly() {
        let mut r = Rng::new(9);
        for basis in [Basis::Ahd, Basis::Hhd] {
            for _ in 0..200 {
                let m = random_model(&mut r, basis);
                let t = Texel::encode(&m, Storage::IrradzLuma);
                let back = t.decode();
                let rel = ((back.i_z() - m.i_z()) / m.i_z()).abs().max_element();
                assert!(rel < 1e-14, "{rel}");
                assert!((0.0..=1.0).contains(&t.scalars[0]));
                let want_ratio = luma(m.c_a) / luma(m.i_z());
                assert!((t.scalars[0] - want_ratio.min(1.0)).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn irradz_moves_a_horizon_direction_up_and_raw_mirrors_below() {
        let n = DVec3::Y;
        let m = Model { basis: Basis::Ahd, normal: n, c_a: Rgb::ONE, c_d: Rgb::ONE, d: DVec3::X };
        let back = Texel::encode(&m, Storage::IrradzRgb).decode();
        assert!((back.d.dot(n) - MIN_DZ).abs() < 1e-12 && back.c_d.is_finite());
        let below = Model { d: DVec3::new(0.6, -0.8, 0.0), ..m };
        let back = Texel::encode(&below, Storage::Raw).decode();
        assert!((back.d - DVec3::new(0.6, 0.8, 0.0)).length() < 1e-15);
    }

    #[test]
    fn lerp_blends_the_stored_scalars() {
        let mut r = Rng::new(10);
        let (a, b) = (random_model(&mut r, Basis::Hhd), random_model(&mut r, Basis::Hhd));
        let b = Model { normal: a.normal, ..b };
        let (ta, tb) = (Texel::encode(&a, Storage::IrradzRgb), Texel::encode(&b, Storage::IrradzRgb));
        assert_eq!(Texel::lerp(&ta, &tb, 0.0), ta);
        let mid = Texel::lerp(&ta, &tb, 0.5);
        // IrradZ is linear in I_z: the blended texel's I(N) is the mean of the two.
        let want = (ta.decode().i_z() + tb.decode().i_z()) * 0.5;
        assert!((mid.decode().i_z() - want).abs().max_element() < 1e-12);
    }
}
