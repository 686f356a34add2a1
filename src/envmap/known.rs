//! The known maps: `envmaps/known.toml`, compiled into the program (docs/maps.md).
//!
//! Each entry names a map by its pixels ([`crate::envmap::identity`]): the name experiments use,
//! the other file stems it is shipped under (the peer tool's `Data/Probes/ennis.hdr` is
//! `ennis_256x128`), its pixel sha256 and size, the file digests known to hold those pixels
//! (what older `provenance.toml` files record), and where it comes from. The search path
//! ([`crate::envmap::search`]) lets a known name resolve only to a file with its pixels; `check`
//! takes a recorded file digest of a known map as satisfied by any file with its pixels.

use serde::Deserialize;
use std::sync::OnceLock;

/// The table's text, as committed.
const TABLE: &str = include_str!("../../envmaps/known.toml");

/// One known map.
#[derive(Clone, Debug, Deserialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct KnownMap {
    /// The map's name in experiments and tables.
    pub name: String,
    /// Other file stems it is shipped under.
    pub aliases: Vec<String>,
    /// Its pixel sha256 ([`crate::envmap::identity::pixel_sha256`]).
    pub pixel_sha256: String,
    /// Width of the map in texels.
    pub width: usize,
    /// Height of the map in texels.
    pub height: usize,
    /// sha256 of files known to hold exactly these pixels.
    pub files: Vec<String>,
    /// Where it comes from.
    pub source: String,
    /// Its terms of use.
    pub licence: String,
    /// How to get it.
    pub get: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Table {
    map: Vec<KnownMap>,
}

/// Parses and checks a table: every name, alias and pixel sha256 unique, digests 64 hex digits,
/// sizes 2:1. The committed table is checked by a unit test, so [`all`] cannot fail at run time.
fn parse(text: &str) -> Result<Vec<KnownMap>, String> {
    let t: Table = toml::from_str(text).map_err(|e| format!("envmaps/known.toml: {e}"))?;
    let hex = |s: &str| s.len() == 64 && s.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'));
    let mut names = std::collections::HashSet::new();
    let mut pixels = std::collections::HashSet::new();
    for m in &t.map {
        for n in std::iter::once(&m.name).chain(&m.aliases) {
            if n.is_empty() || n.contains(['/', '.']) {
                return Err(format!("envmaps/known.toml: '{n}' is not a plain map name"));
            }
        }
        if !names.insert(m.name.as_str()) {
            return Err(format!("envmaps/known.toml: map '{}' is listed twice", m.name));
        }
        if !hex(&m.pixel_sha256) || !m.files.iter().all(|f| hex(f)) {
            return Err(format!("envmaps/known.toml: map '{}': a digest is not 64 lower-case hex digits", m.name));
        }
        if !pixels.insert(m.pixel_sha256.as_str()) {
            return Err(format!("envmaps/known.toml: map '{}' has the pixels of another entry", m.name));
        }
        if m.height == 0 || m.width != 2 * m.height {
            return Err(format!("envmaps/known.toml: map '{}': {}x{} is not 2:1", m.name, m.width, m.height));
        }
    }
    let mut aliases = std::collections::HashSet::new();
    for m in &t.map {
        for a in &m.aliases {
            if !aliases.insert(a.as_str()) {
                return Err(format!("envmaps/known.toml: alias '{a}' belongs to two maps"));
            }
        }
    }
    Ok(t.map)
}

/// Every known map, in the table's order.
pub fn all() -> &'static [KnownMap] {
    static MAPS: OnceLock<Vec<KnownMap>> = OnceLock::new();
    // The committed table parses (unit test `committed_table_is_valid`); were it ever broken,
    // no map would be known, never a panic.
    MAPS.get_or_init(|| parse(TABLE).unwrap_or_default())
}

/// The known map of this name.
pub fn by_name(name: &str) -> Option<&'static KnownMap> {
    all().iter().find(|m| m.name == name)
}

/// The known map with these pixels.
pub fn by_pixels(pixel_sha256: &str) -> Option<&'static KnownMap> {
    all().iter().find(|m| m.pixel_sha256 == pixel_sha256)
}

impl KnownMap {
    /// Whether `file_sha256` is a file known to hold this map's pixels.
    pub fn has_file(&self, file_sha256: &str) -> bool {
        self.files.iter().any(|f| f == file_sha256)
    }

    /// The first 12 hex digits of the pixel sha256, as messages print it.
    pub fn short(&self) -> &str {
        &self.pixel_sha256[..12]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn committed_table_is_valid() {
        let maps = parse(TABLE).unwrap();
        assert_eq!(maps.len(), all().len());
        // The maps the committed experiments name on the shared folder, and the 14 CC0 maps.
        for n in ["ennis_256x128", "grace_256x128", "pisa_256x128", "uffizi_256x128", "wells_probulator"] {
            let m = by_name(n).unwrap_or_else(|| panic!("{n} is not known"));
            assert_eq!((m.width, m.height, m.files.len()), (256, 128, 2), "{n}: the .exr and the peer's .hdr");
        }
        assert_eq!(by_name("wells_probulator").unwrap().aliases, ["wells"]);
        assert!(by_name("wells_256x128").unwrap().aliases.is_empty(), "Probulator's wells is another map");
        assert_eq!(by_name("wells").map(|m| (m.width, m.height)), Some((1000, 500)));
        assert_eq!(all().iter().filter(|m| m.licence.starts_with("CC0")).count(), 14);
        let m = by_name("pisa_256x128").unwrap();
        assert_eq!(by_pixels(&m.pixel_sha256), Some(m));
        assert!(m.has_file("32234f0b85f54e859d54b9a7ae6717d2e5d72b0b074aeeca57def8c0dd5c89a0"));
    }

    #[test]
    fn bad_tables_are_refused() {
        let entry = |name: &str, alias: &str, px: char, w: usize| {
            format!(
                "[[map]]\nname = '{name}'\naliases = ['{alias}']\npixel_sha256 = '{}'\nwidth = {w}\nheight = 2\n\
                 files = []\nsource = ''\nlicence = ''\nget = ''\n",
                px.to_string().repeat(64)
            )
        };
        assert!(parse(&entry("a", "x", 'a', 4)).is_ok());
        let e = parse(&(entry("a", "x", 'a', 4) + &entry("a", "y", 'b', 4))).unwrap_err();
        assert!(e.contains("'a' is listed twice"), "{e}");
        let e = parse(&(entry("a", "x", 'a', 4) + &entry("b", "y", 'a', 4))).unwrap_err();
        assert!(e.contains("pixels of another"), "{e}");
        let e = parse(&(entry("a", "x", 'a', 4) + &entry("b", "x", 'b', 4))).unwrap_err();
        assert!(e.contains("alias 'x' belongs to two"), "{e}");
        assert!(parse(&entry("a", "x", 'A', 4)).unwrap_err().contains("hex"));
        assert!(parse(&entry("a", "x", 'a', 5)).unwrap_err().contains("not 2:1"));
        assert!(parse(&entry("a", "x.hdr", 'a', 4)).unwrap_err().contains("plain map name"));
    }
}
