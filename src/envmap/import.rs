//! `probelab maps import`: a map file as the harness's 256×128 map, made the way the shared
//! `_256x128` maps were (`SOURCES.md`; docs/maps.md): decode, round to half, average down to
//! 256×128 with the solid-angle-weighted box filter ([`crate::envmap::resample`]) when larger,
//! round to half again; then name it through the known maps ([`crate::envmap::known`]).
//!
//! This module derives; the command line reads the files and writes the results.

use super::identity;
use super::known::{self, KnownMap};
use super::resample;
use super::EnvMap;

/// The size every imported map is made at (the experiments' maps).
pub const SIZE: (usize, usize) = (256, 128);

/// A map made ready for the search path.
pub struct Imported {
    /// The 256×128 map, its texels halves.
    pub map: EnvMap,
    /// The name it is written under (`<name>.exr`).
    pub name: String,
    /// Its pixel sha256.
    pub pixel_sha256: String,
    /// The known map it is, if any.
    pub known: Option<&'static KnownMap>,
    /// Whether it was averaged down (false: the source was already 256×128).
    pub averaged: bool,
}

/// Derives the 256×128 map of `source` (named after its file stem) and its name: the known
/// map's name when its pixels are a known map's, else `<stem>_256x128` (the stem itself when it
/// already ends in `_256x128`). Fails, saying why, when the source is smaller than 256×128,
/// holds a value above the largest half (65504), or would take the name of a known map whose
/// pixels it does not have (a different `ennis.hdr` never becomes `ennis_256x128`).
pub fn derive(source: &EnvMap) -> Result<Imported, String> {
    let halves = identity::halved(source)?;
    let (w, h) = SIZE;
    let averaged = (source.width(), source.height()) != SIZE;
    let small = resample::downsample(&halves, w, h)?;
    let map = identity::halved(&small)?;
    let pixel_sha256 = identity::pixel_sha256(&map);
    let found = known::by_pixels(&pixel_sha256);
    let name = match found {
        Some(k) => k.name.clone(),
        None => {
            let stem = &source.name;
            let name = if stem.ends_with("_256x128") { stem.clone() } else { format!("{stem}_256x128") };
            // The name becomes `<out>/<name>.exr`: a plain identifier, so it stays in --out.
            crate::io::name::check(&name).map_err(|e| format!("the map's name {e}; rename the file"))?;
            if let Some(k) = known::by_name(&name) {
                return Err(format!(
                    "its 256x128 pixels (pixel sha256 {}) are not those of the known map {name} (pixel sha256 {}, \
                     {}): not written under that name; rename the file if it is another map",
                    &pixel_sha256[..12],
                    k.short(),
                    k.source
                ));
            }
            name
        }
    };
    Ok(Imported { map, name, pixel_sha256, known: found, averaged })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An unknown map: named after its stem, averaged down when larger, refused when smaller.
    #[test]
    fn unknown_maps_are_named_after_their_stem() {
        let big = EnvMap::from_fn("mine", 512, 256, |i, j| [(i % 7) as f32, (j % 5) as f32, 0.5]).unwrap();
        let d = derive(&big).unwrap();
        assert_eq!((d.name.as_str(), d.averaged, d.known), ("mine_256x128", true, None));
        assert_eq!((d.map.width(), d.map.height()), SIZE);
        // 2x2 boxes of whole texels: the first target texel is the solid-angle-weighted mean of
        // rows 0 and 1 of columns 0 and 1, then rounded to half.
        let g = big.grid();
        let (w0, w1) = (g.solid_angle(0), g.solid_angle(1));
        let want = (w0 * 0.0 + w1 * 1.0) / (w0 + w1);
        assert_eq!(d.map.texel(0, 0)[1], identity::to_half(want as f32));
        assert_eq!(d.pixel_sha256, identity::pixel_sha256(&d.map));
        let already = EnvMap::from_fn("x_256x128", 256, 128, |_, _| [1.0; 3]).unwrap();
        assert_eq!(derive(&already).unwrap().name, "x_256x128");
        assert!(!derive(&already).unwrap().averaged);
        let small = EnvMap::from_fn("s", 128, 64, |_, _| [1.0; 3]).unwrap();
        assert!(derive(&small).err().unwrap().contains("never up"));
    }

    /// A map whose file stem is not a plain name (a leading dot, a space) is not written under
    /// it: `<out>/<name>.exr` must stay in `--out` and be no hidden file.
    #[test]
    fn an_imported_name_is_a_plain_name() {
        for stem in [".hidden", "a b"] {
            let m = EnvMap::from_fn(stem, 256, 128, |i, _| [(i % 3) as f32, 0.5, 0.25]).unwrap();
            let e = derive(&m).err().unwrap();
            assert!(e.contains("not a plain name") && e.contains(stem), "{e}");
        }
    }

    /// A file under a known map's stem with other pixels is not given that map's name.
    #[test]
    fn a_known_name_needs_the_known_pixels() {
        let fake = EnvMap::from_fn("ennis", 256, 128, |_, _| [1.0; 3]).unwrap();
        let e = derive(&fake).err().unwrap();
        assert!(e.contains("not those of the known map ennis_256x128"), "{e}");
        let big = EnvMap::from_fn("x", 512, 256, |_, _| [1e5, 0.0, 0.0]).unwrap();
        assert!(derive(&big).err().unwrap().contains("65504"));
    }
}
