//! No reference computed twice in one workflow: the exact reference a run, a comparison sheet
//! or a claim's cut-down sheet computes is kept, keyed by what it is a function of, and handed
//! to the next caller that asks for the same values. `reproduce` asks for the same values many
//! times: every `lightmap_self_bounce` albedo of a case has the same capped reference (the
//! bounce is added after), `landscape_hemi` and `lightmap_table` share the axes6 cases at 96×48,
//! `lightmap_self_bounce` and `probe_occlusion` those at 128×64, four experiments draw the same
//! +Y hemisphere disc of a map on their sheets, and the claims' sheets are cut from sheets the
//! report draws again.
//!
//! The key is everything the values depend on: the map's pixel sha256 (a map without one,
//! held only in memory, is never kept), the caps (each axis and cosine, bit for bit), the polar
//! nodes, which path evaluates them (the lat-long grid's or the per-normal one, which agree
//! only to rounding) and the sha256 of the normals' bits with their count (on the lat-long
//! path, the grid's size, which fixes its normals). So a value handed back is the very value
//! the caller would have computed, bit for bit.
//!
//! Memory stays bounded: at most [`BUDGET_BYTES`] of values are kept; past it the least
//! recently used are dropped first (a dropped value is computed again when asked for). The
//! cache is an object a workflow owns and lends to the work, never process-wide.

use crate::envmap::LatLong;
use crate::io::profile::{self, Profile};
use crate::math::cap::Cap;
use crate::math::colour::Rgb;
use glam::DVec3;
use sha2::{Digest, Sha256};
use std::collections::HashMap;
use std::sync::Mutex;

/// The most bytes of reference values a cache keeps (about 2.8 million normals' RGB). The
/// largest reuse distance in `reproduce` (the 128×64 axes6 cases of `lightmap_self_bounce`
/// asked for again by `probe_occlusion`, after `lightmap_table`'s 38 cases on every map) is
/// about 55 MiB on the 19 shared maps.
pub const BUDGET_BYTES: usize = 64 << 20;

/// The profile phase of a value handed back instead of computed (its calls count them).
pub const REUSED: &str = "reference reused (cache)";

/// Which evaluation of the reference produced the values: the lat-long grid's path or the
/// per-normal path (they agree only to rounding, so their values are never exchanged).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Path {
    /// `Reference::irradiance_latlong_until` on a lat-long output grid.
    LatLong,
    /// `Reference::irradiance_many` at each normal.
    PerNormal,
}

/// What a reference's values are a function of (see the module doc).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Key {
    map: String,
    caps: Vec<[u64; 4]>,
    polar_nodes: usize,
    path: Path,
    normals: [u8; 32],
    count: usize,
}

impl Key {
    /// The key of the reference of the map of pixel sha256 `map` under `caps` with
    /// `polar_nodes`, evaluated by `path` at `normals`.
    pub fn new(map: &str, caps: &[Cap], polar_nodes: usize, path: Path, normals: &[DVec3]) -> Key {
        let mut h = Sha256::new();
        // The bits go to the digest a block of normals at a time (a call per value costs more
        // than the digest of its eight bytes).
        let mut bytes = Vec::with_capacity(24 * NORMALS_PER_UPDATE);
        for block in normals.chunks(NORMALS_PER_UPDATE) {
            bytes.clear();
            bytes.extend(block.iter().flat_map(|n| n.to_array()).flat_map(|c| c.to_bits().to_le_bytes()));
            h.update(&bytes);
        }
        Key {
            map: map.to_string(),
            caps: cap_bits(caps),
            polar_nodes,
            path,
            normals: h.finalize().into(),
            count: normals.len(),
        }
    }

    /// This key with its caps replaced by `caps`: the key of another reference of the same
    /// map at the same normals (their digest taken once).
    pub fn for_caps(&self, caps: &[Cap]) -> Key {
        Key { caps: cap_bits(caps), ..self.clone() }
    }

    /// The key of the reference on the lat-long output grid `grid` (`Path::LatLong`): its
    /// values are a function of the grid's size, which fixes its normals, so the size stands
    /// for them (no digest of its normals' bits).
    pub fn latlong(map: &str, caps: &[Cap], polar_nodes: usize, grid: LatLong) -> Key {
        let mut normals = [0u8; 32];
        normals[..8].copy_from_slice(&(grid.width as u64).to_le_bytes());
        normals[8..16].copy_from_slice(&(grid.height as u64).to_le_bytes());
        Key {
            map: map.to_string(),
            caps: cap_bits(caps),
            polar_nodes,
            path: Path::LatLong,
            normals,
            count: grid.width * grid.height,
        }
    }
}

/// Normals whose bits [`Key::new`] hands the digest in one call.
const NORMALS_PER_UPDATE: usize = 256;

/// Each cap's axis and cosine, bit for bit: caps equal here bound the same light.
pub fn cap_bits(caps: &[Cap]) -> Vec<[u64; 4]> {
    caps.iter().map(|c| [c.axis.x.to_bits(), c.axis.y.to_bits(), c.axis.z.to_bits(), c.cos.to_bits()]).collect()
}

/// A kept value and when it was last handed out.
struct Entry {
    values: Vec<Rgb>,
    used: u64,
}

#[derive(Default)]
struct Kept {
    entries: HashMap<Key, Entry>,
    bytes: usize,
    tick: u64,
    computed: u64,
    reused: u64,
}

/// The references of one workflow (see the module doc).
pub struct ReferenceCache<'p> {
    kept: Mutex<Kept>,
    budget: usize,
    profile: Option<&'p Profile>,
}

impl<'p> ReferenceCache<'p> {
    /// An empty cache keeping at most [`BUDGET_BYTES`]; each computation it runs is timed on
    /// `profile` under the phase its caller names.
    pub fn new(profile: Option<&'p Profile>) -> Self {
        Self::with_budget(BUDGET_BYTES, profile)
    }

    /// [`ReferenceCache::new`] keeping at most `budget` bytes.
    pub fn with_budget(budget: usize, profile: Option<&'p Profile>) -> Self {
        ReferenceCache { kept: Mutex::new(Kept::default()), budget, profile }
    }

    /// The values of `key`: kept ones if there are, else `compute`'s, timed as phase `phase`
    /// and kept unless `compute` says they mean nothing (`None`: the work was cancelled) or the
    /// key is `None` (a map without a pixel sha256).
    pub fn values(
        &self,
        key: Option<Key>,
        phase: &'static str,
        compute: impl FnOnce() -> Option<Vec<Rgb>>,
    ) -> Option<Vec<Rgb>> {
        if let Some(k) = &key {
            let mut kept = self.lock();
            kept.tick += 1;
            let tick = kept.tick;
            if let Some(e) = kept.entries.get_mut(k) {
                let _s = profile::span(self.profile, REUSED);
                e.used = tick;
                let v = e.values.clone();
                kept.reused += 1;
                return Some(v);
            }
        }
        let values = {
            let _s = profile::span(self.profile, phase);
            compute()
        }?;
        let mut kept = self.lock();
        kept.computed += 1;
        if let Some(k) = key {
            self.keep(&mut kept, k, values.clone());
        }
        Some(values)
    }

    /// Keeps the values of every key of `keys` unless all are kept already: `compute` gives
    /// them all at once (`compute()[k]` is the value of `keys[k]`), timed as phase `phase` and
    /// counted as one computation.
    pub fn keep_together(&self, keys: Vec<Key>, phase: &'static str, compute: impl FnOnce() -> Vec<Vec<Rgb>>) {
        if keys.iter().all(|k| self.lock().entries.contains_key(k)) {
            return;
        }
        let values = {
            let _s = profile::span(self.profile, phase);
            compute()
        };
        let mut kept = self.lock();
        kept.computed += 1;
        for (k, v) in keys.into_iter().zip(values) {
            self.keep(&mut kept, k, v);
        }
    }

    /// The profile the computations are timed on, if any.
    pub fn profile(&self) -> Option<&'p Profile> {
        self.profile
    }

    /// How many values were computed and how many handed back from the cache.
    #[cfg(test)]
    pub fn counts(&self) -> (u64, u64) {
        let kept = self.lock();
        (kept.computed, kept.reused)
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Kept> {
        // A panic while the lock was held leaves only counters and complete entries behind.
        self.kept.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Keeps `values` under `key`, dropping the least recently used beyond the budget (a value
    /// larger than the whole budget is not kept).
    fn keep(&self, kept: &mut Kept, key: Key, values: Vec<Rgb>) {
        let size = std::mem::size_of_val(values.as_slice());
        if size > self.budget || kept.entries.contains_key(&key) {
            return;
        }
        while kept.bytes + size > self.budget {
            // Cannot fail: the budget is exceeded only while something is kept.
            let oldest = kept.entries.iter().min_by_key(|(_, e)| e.used).map(|(k, _)| k.clone()).expect("kept");
            if let Some(e) = kept.entries.remove(&oldest) {
                kept.bytes -= std::mem::size_of_val(e.values.as_slice());
            }
        }
        kept.tick += 1;
        let used = kept.tick;
        kept.bytes += size;
        kept.entries.insert(key, Entry { values, used });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(map: &str, caps: &[Cap], path: Path, normals: &[DVec3]) -> Option<Key> {
        Some(Key::new(map, caps, 2, path, normals))
    }

    /// The same key computes once; any difference in map, cap, path or normals computes again;
    /// no key, or cancelled work, is never kept.
    #[test]
    fn computes_each_key_once() {
        let cache = ReferenceCache::new(None);
        let normals = vec![DVec3::Y, DVec3::X];
        let one = |v: f64| Some(vec![Rgb::splat(v); 2]);
        let hemi = [Cap::hemisphere(DVec3::Y)];
        assert_eq!(cache.values(key("a", &hemi, Path::PerNormal, &normals), "t", || one(1.0)), one(1.0));
        assert_eq!(cache.values(key("a", &hemi, Path::PerNormal, &normals), "t", || one(2.0)), one(1.0));
        assert_eq!(cache.counts(), (1, 1));
        let other_normals = vec![DVec3::Y, DVec3::NEG_X];
        let tilted = [Cap::hemisphere(DVec3::new(0.0, 1.0, 1e-300).normalize())];
        for k in [
            key("b", &hemi, Path::PerNormal, &normals),
            key("a", &[], Path::PerNormal, &normals),
            key("a", &[Cap::new(DVec3::Y, 1e-17)], Path::PerNormal, &normals),
            key("a", &tilted, Path::PerNormal, &normals),
            key("a", &hemi, Path::LatLong, &normals),
            key("a", &hemi, Path::PerNormal, &other_normals),
            key("a", &hemi, Path::PerNormal, &normals[..1]),
        ] {
            assert_eq!(cache.values(k, "t", || one(3.0)), one(3.0));
        }
        assert_eq!(cache.counts(), (8, 1));
        assert_eq!(cache.values(None, "t", || one(4.0)), one(4.0));
        assert_eq!(cache.values(None, "t", || one(5.0)), one(5.0));
        assert_eq!(cache.values(key("c", &[], Path::LatLong, &normals), "t", || None), None);
        assert_eq!(cache.values(key("c", &[], Path::LatLong, &normals), "t", || one(6.0)), one(6.0));
        assert_eq!(cache.counts(), (11, 1));
    }

    /// A lat-long grid's key is its size's: grids of other sizes, the per-normal path at the
    /// same normals, another map or other caps are other keys.
    #[test]
    fn a_latlong_key_is_the_grid_size() {
        let grid = LatLong::new(4, 2);
        let normals: Vec<DVec3> = (0..2).flat_map(|j| (0..4).map(move |i| grid.direction(i, j))).collect();
        let k = Key::latlong("a", &[], 2, grid);
        assert_eq!(k, Key::latlong("a", &[], 2, LatLong::new(4, 2)));
        for other in [
            Key::latlong("a", &[], 2, LatLong::new(2, 4)),
            Key::latlong("a", &[], 2, LatLong::new(8, 1)),
            Key::latlong("b", &[], 2, grid),
            Key::latlong("a", &[Cap::hemisphere(DVec3::Y)], 2, grid),
            Key::latlong("a", &[], 3, grid),
            Key::new("a", &[], 2, Path::PerNormal, &normals),
        ] {
            assert_ne!(k, other);
        }
    }

    /// Past the budget the least recently used value goes first; a value over the whole budget
    /// is never kept.
    #[test]
    fn keeps_at_most_the_budget_least_recently_used_first() {
        let per = std::mem::size_of::<Rgb>() * 4;
        let cache = ReferenceCache::with_budget(2 * per, None);
        let v = |x: f64| Some(vec![Rgb::splat(x); 4]);
        let k = |m: &str| key(m, &[], Path::LatLong, &[DVec3::Y]);
        cache.values(k("a"), "t", || v(1.0));
        cache.values(k("b"), "t", || v(2.0));
        cache.values(k("a"), "t", || v(9.0)); // a is now the most recent
        cache.values(k("c"), "t", || v(3.0)); // b goes
        assert_eq!(cache.counts(), (3, 1));
        assert_eq!(cache.values(k("a"), "t", || v(9.0)), v(1.0));
        assert_eq!(cache.values(k("c"), "t", || v(9.0)), v(3.0));
        assert_eq!(cache.values(k("b"), "t", || v(2.5)), v(2.5));
        assert_eq!(cache.counts(), (4, 3));
        let huge = Some(vec![Rgb::ZERO; 9]);
        cache.values(k("h"), "t", || huge.clone());
        assert_eq!(cache.values(k("h"), "t", || v(7.0)), v(7.0));
    }
}
