//! `probelab maps`: the search path, the `.exr` and `.hdr` files in each of its folders, and
//! the known maps (`envmaps/known.toml`) not on it, each with where to get it
//! (`docs/maps.md`). Nothing is written and no lock is taken.

use super::super::context::Env;
use crate::envmap::known::KnownMap;
use crate::envmap::search::{has_map_extension, ENV_VAR, NOT_UTF8};
use anyhow::Result;
use std::path::{Path, PathBuf};

/// A folder of the search path that could be listed, and its map files.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MapFolder {
    /// The folder.
    pub path: PathBuf,
    /// The names of its map files, sorted; one whose name is not UTF-8 is shown with its bad
    /// bytes replaced and `search::NOT_UTF8` beside it.
    pub files: Vec<String>,
}

/// What `probelab maps` found.
#[derive(Clone, Debug, PartialEq)]
pub struct MapsListing {
    /// The search path's folders, each marked `(missing)` when it is not there
    /// (`SearchPath::describe`).
    pub search: String,
    /// Each folder that could be listed, in search order.
    pub folders: Vec<MapFolder>,
    /// The known maps not on the search path.
    pub known_missing: Vec<&'static KnownMap>,
}

/// `probelab maps`: every folder of `env.search` listed (one that cannot be read is left
/// out), and the known maps it lacks.
pub fn list(env: &Env) -> Result<MapsListing> {
    let mut folders = Vec::new();
    for d in env.search.dirs() {
        let Ok(entries) = std::fs::read_dir(d) else {
            continue;
        };
        let mut files: Vec<String> = entries
            .filter_map(|e| e.ok())
            .filter(|e| is_map_file(&e.path()))
            .map(|e| match e.file_name().into_string() {
                Ok(name) => name,
                Err(name) => format!("{} ({NOT_UTF8})", name.to_string_lossy()),
            })
            .collect();
        files.sort();
        folders.push(MapFolder { path: d.clone(), files });
    }
    Ok(MapsListing { search: env.search.describe(), folders, known_missing: env.search.known_missing() })
}

/// Whether `path` is a map file to list or import from a folder: a regular file (after
/// symbolic links; not a FIFO, socket or a folder named `NAME.exr`) whose extension is `exr` or
/// `hdr` in any case (`X.EXR`).
pub fn is_map_file(path: &Path) -> bool {
    has_map_extension(path) && std::fs::metadata(path).is_ok_and(|m| m.is_file())
}

impl MapsListing {
    /// The listing as printed: the search path, each folder's map files, then the known maps
    /// missing with where to get them (or that none is).
    pub fn to_text(&self) -> String {
        let mut text = format!("search path: {}\n", self.search);
        for f in &self.folders {
            text += &format!("{}:\n", f.path.display());
            for n in &f.files {
                text += &format!("  {n}\n");
            }
        }
        if self.known_missing.is_empty() {
            return text + "every known map is on the search path\n";
        }
        text += &format!(
            "known maps not found ({}; put them in a folder and set {ENV_VAR}, docs/maps.md):\n",
            self.known_missing.len()
        );
        for k in &self.known_missing {
            text += &format!("  {} ({}x{}): {}\n", k.name, k.width, k.height, k.get);
        }
        text
    }
}
