//! A map's identity by its pixels, not its file bytes (docs/maps.md, "The identity rule").
//!
//! The paper probes reach users as Radiance `.hdr` files (the peer tool's `Data/Probes`) and
//! reached us as half-float OpenEXR files decoded from exactly those (`SOURCES.md`): two files,
//! different bytes, one map. What they share is their texels rounded to IEEE 754 binary16
//! ("half"), the precision every shared map is stored at. The *pixel sha256* is
//!
//! sha256( width as u32 LE ‖ height as u32 LE ‖ for each row from the top (row 0, +Y), each
//! column from the left, R, G, B: the half bits as u16 LE )
//!
//! with each value rounded to the nearest half, ties to even, and −0 written as +0. It can be
//! recomputed outside probelab, e.g. with numpy:
//! `sha256(struct.pack('<II', w, h) + np.maximum(a, 0).astype('<f2').tobytes())` for an
//! `(h, w, 3)` array `a` of non-negative values (`np.maximum` turns −0 into +0).

use super::{EnvMap, Texel};
use exr::prelude::f16;
use sha2::{Digest, Sha256};

/// The half-float bits of `v`, rounded to nearest (ties to even), −0 as +0.
pub fn half_bits(v: f32) -> u16 {
    let h = f16::from_f32(v).to_bits();
    if h == 0x8000 {
        0
    } else {
        h
    }
}

/// `v` rounded to the nearest half (ties to even), back as f32; −0 becomes +0.
pub fn to_half(v: f32) -> f32 {
    f16::from_bits(half_bits(v)).to_f32()
}

/// The half bits a stored half contributes to the pixel sha256: its own bits, −0 as +0. For
/// every half that is not NaN this is [`half_bits`] of its f32 value (a half converts to f32
/// exactly and back), so a decoder of half samples can form the digest's bytes without
/// converting back (a NaN is refused by [`EnvMap::new`] anyway).
pub(crate) fn stored_half_bits(h: f16) -> u16 {
    match h.to_bits() {
        0x8000 => 0,
        b => b,
    }
}

/// The pixel sha256 fed row by row: its size first, then the half bits of every row from the
/// top, in order (what [`pixel_sha256_of`] hashes, for a decoder that meets the rows in order).
pub(crate) struct PixelStream(Sha256);

impl PixelStream {
    /// A digest of a `width`×`height` map, its size already hashed.
    pub(crate) fn new(width: usize, height: usize) -> Self {
        let mut h = Sha256::new();
        h.update((width as u32).to_le_bytes());
        h.update((height as u32).to_le_bytes());
        PixelStream(h)
    }

    /// Adds the next rows' half bits (each value u16 LE, R, G, B per texel).
    pub(crate) fn update(&mut self, half_bytes: &[u8]) {
        self.0.update(half_bytes);
    }

    /// The digest in lower-case hex.
    pub(crate) fn finish(self) -> String {
        self.0.finalize().iter().map(|b| format!("{b:02x}")).collect()
    }
}

/// The pixel sha256 of a `width`×`height` grid of row-major texels (lower-case hex), as the
/// module documentation defines it. The half bits of a batch of rows are formed on the run's
/// threads while the previous batch is digested (two batches of at most [`HASH_BATCH_BYTES`]
/// alive at once); the digest sees the same bytes in the same order.
pub fn pixel_sha256_of(width: usize, height: usize, texels: &[Texel]) -> String {
    let mut h = PixelStream::new(width, height);
    let w = width.max(1);
    let rows_per_batch = (HASH_BATCH_BYTES / (6 * w)).max(1);
    let mut batches = texels.chunks(rows_per_batch * w);
    let mut ready = batches.next().map(half_bytes);
    while let Some(bytes) = ready.take() {
        let (_, next) = rayon::join(|| h.update(&bytes), || batches.next().map(half_bytes));
        ready = next;
    }
    h.finish()
}

/// The bytes one batch of texels adds to the pixel sha256 (each value's half bits, u16 LE).
const HASH_BATCH_BYTES: usize = 1 << 22;

/// The half bits of `texels`, R, G, B each as u16 LE, formed in parallel.
fn half_bytes(texels: &[Texel]) -> Vec<u8> {
    use rayon::prelude::*;
    let mut out = vec![0u8; texels.len() * 6];
    out.par_chunks_mut(6 << 12).zip(texels.par_chunks(1 << 12)).for_each(|(o, t)| {
        for (o, t) in o.chunks_exact_mut(6).zip(t) {
            for (o, &v) in o.chunks_exact_mut(2).zip(t) {
                o.copy_from_slice(&half_bits(v).to_le_bytes());
            }
        }
    });
    out
}

/// The pixel sha256 of a map.
pub fn pixel_sha256(map: &EnvMap) -> String {
    pixel_sha256_of(map.width(), map.height(), map.texels())
}

/// The map with every texel rounded to half ([`to_half`]): the texels its pixel sha256 names.
/// Name, path and file sha256 are kept. Fails if a texel is above the largest half (65504),
/// which would round to infinity.
pub fn halved(map: &EnvMap) -> Result<EnvMap, String> {
    let texels: Vec<Texel> = map.texels().iter().map(|t| t.map(to_half)).collect();
    let mut out = EnvMap::new(map.name.clone(), map.width(), map.height(), texels)
        .map_err(|e| format!("{e} after rounding to half: a texel is above 65504, the largest half-float value"))?;
    out.path = map.path.clone();
    out.sha256 = map.sha256.clone();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Half bits from the IEEE 754 binary16 layout (1 sign, 5 exponent, 10 fraction bits),
    /// written out by hand: 1 = 0x3c00, 65504 = 0x7bff, 2^-24 (smallest subnormal) = 0x0001,
    /// 2^-14 (smallest normal) = 0x0400; 1 + 2^-11 lies half way between 1 and its successor
    /// 0x3c01 and goes to the even 0x3c00, 1 + 3·2^-11 goes to the even 0x3c02.
    #[test]
    fn half_bits_round_to_nearest_even() {
        assert_eq!(half_bits(1.0), 0x3c00);
        assert_eq!(half_bits(65504.0), 0x7bff);
        assert_eq!(half_bits(2f32.powi(-24)), 0x0001);
        assert_eq!(half_bits(2f32.powi(-14)), 0x0400);
        assert_eq!(half_bits(1.0 + 2f32.powi(-11)), 0x3c00);
        assert_eq!(half_bits(1.0 + 3.0 * 2f32.powi(-11)), 0x3c02);
        assert_eq!(half_bits(-0.0), 0);
        assert_eq!(half_bits(0.0), 0);
        // Below half the smallest subnormal: flushed to zero.
        assert_eq!(half_bits(2f32.powi(-26)), 0);
    }

    /// The digest of a 2x1 map, its bytes laid out by hand: 02 00 00 00 01 00 00 00, then
    /// texel (1, 0.5, 2) = 3c00 3800 4000 and (0, 1, 0) = 0000 3c00 0000, each little-endian.
    #[test]
    fn pixel_sha256_hashes_the_documented_bytes() {
        let map = EnvMap::new("m", 2, 1, vec![[1.0, 0.5, 2.0], [0.0, 1.0, 0.0]]).unwrap();
        let bytes: [u8; 20] = [2, 0, 0, 0, 1, 0, 0, 0, 0x00, 0x3c, 0x00, 0x38, 0x00, 0x40, 0, 0, 0x00, 0x3c, 0, 0];
        let want: String = Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect();
        assert_eq!(pixel_sha256(&map), want);
        // A value that rounds to the same half is the same map; one half step away is not.
        let near = EnvMap::new("n", 2, 1, vec![[1.0 + 1e-4, 0.5, 2.0], [0.0, 1.0, -0.0]]).unwrap();
        assert_eq!(pixel_sha256(&near), want);
        let off = EnvMap::new("o", 2, 1, vec![[1.0 + 2f32.powi(-10), 0.5, 2.0], [0.0, 1.0, 0.0]]).unwrap();
        assert_ne!(pixel_sha256(&off), want);
        // The size is part of the identity: the same 6 values as a 1x... grid cannot exist
        // (2:1 only), so compare against the same texels hashed with another width field.
        assert_ne!(pixel_sha256_of(1, 2, map.texels()), want);
    }

    /// Every half that is not NaN contributes its own bits (−0 as +0), as its f32 value would:
    /// all 65,536 bit patterns.
    #[test]
    fn stored_halves_hash_as_their_values() {
        for bits in 0..=u16::MAX {
            let h = f16::from_bits(bits);
            if !h.is_nan() {
                assert_eq!(stored_half_bits(h), half_bits(h.to_f32()), "{bits:#06x}");
            }
        }
        assert_eq!(stored_half_bits(f16::from_bits(0x8000)), 0);
    }

    #[test]
    fn halved_rounds_and_refuses_overflow() {
        let map = EnvMap::new("m", 2, 1, vec![[1.0 + 1e-4, 0.1, 2.0], [0.0, 1.0, 3.0]]).unwrap();
        let h = halved(&map).unwrap();
        assert_eq!(h.texel(0, 0), [1.0, f16::from_f32(0.1).to_f32(), 2.0]);
        assert_eq!(pixel_sha256(&h), pixel_sha256(&map));
        let big = EnvMap::new("b", 2, 1, vec![[70000.0, 0.0, 0.0], [0.0; 3]]).unwrap();
        let e = halved(&big).unwrap_err();
        assert!(e.contains("65504"), "{e}");
    }
}
