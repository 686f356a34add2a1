//! Finding environment maps by name in a list of folders.
//!
//! The repository's `envmaps/` folder comes first, then every folder listed in the
//! environment variable `PROBELAB_ENVMAPS` (colon-separated on Unix; empty entries are
//! ignored). A name such as `grace_256x128` resolves to the first of
//! `<dir>/grace_256x128.exr`, `<dir>/grace_256x128.hdr` found, trying each folder in order.

use super::load;
use super::EnvMap;
use std::ffi::OsStr;
use std::path::{Path, PathBuf, MAIN_SEPARATOR};

/// The environment variable listing extra map folders.
pub const ENV_VAR: &str = "PROBELAB_ENVMAPS";

/// Why a map name could not be resolved to a file.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum SearchError {
    /// No candidate file exists in any folder.
    #[error(
        "map '{name}' not found{as_path}; searched: {searched} (set PROBELAB_ENVMAPS to a \
         colon-separated list of folders; see README for where the paper probes come from)"
    )]
    NotFound {
        /// The name asked for.
        name: String,
        /// `" (no such file)"` when the name looked like a file path, else empty.
        as_path: String,
        /// Every folder searched, in order, each marked `(missing)` if it does not exist.
        searched: String,
    },
    /// The name is empty.
    #[error("empty map name")]
    EmptyName,
}

/// An ordered list of folders in which map names are looked up.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SearchPath {
    dirs: Vec<PathBuf>,
}

impl SearchPath {
    /// A search path of exactly these folders, in this order.
    pub fn new(dirs: Vec<PathBuf>) -> Self {
        Self { dirs }
    }

    /// The standard search path: `repo_envmaps` (the repository's `envmaps/` folder)
    /// first, then each folder of the `PROBELAB_ENVMAPS` environment variable.
    pub fn from_env(repo_envmaps: PathBuf) -> Self {
        Self::from_list(repo_envmaps, std::env::var_os(ENV_VAR).as_deref())
    }

    /// Like [`SearchPath::from_env`], with the variable's value passed in (`None` = unset).
    /// Entries are separated by the platform's path-list separator (`:` on Unix); empty
    /// entries are ignored, and a folder already in the list is not added again.
    pub fn from_list(repo_envmaps: PathBuf, list: Option<&OsStr>) -> Self {
        let mut dirs = vec![repo_envmaps];
        for dir in list.map(std::env::split_paths).into_iter().flatten() {
            if !dir.as_os_str().is_empty() && !dirs.contains(&dir) {
                dirs.push(dir);
            }
        }
        Self { dirs }
    }

    /// The folders searched, in order.
    pub fn dirs(&self) -> &[PathBuf] {
        &self.dirs
    }

    /// Resolves a map name to a file.
    ///
    /// If `name` looks like a file path (contains a path separator or has an extension)
    /// and something exists there (or cannot be inspected), that path is returned, so the
    /// loader reports what is wrong with it (a directory, a FIFO, permission denied). Otherwise each folder in turn is
    /// tried for `<dir>/<name>.exr`, `<dir>/<name>.hdr` and, if `name` has an extension,
    /// `<dir>/<name>`; the first existing file wins. If none exists the error lists every
    /// folder searched, marking those that do not exist.
    pub fn resolve(&self, name: &str) -> Result<PathBuf, SearchError> {
        if name.is_empty() {
            return Err(SearchError::EmptyName);
        }
        let as_file = Path::new(name);
        let has_ext = as_file.extension().is_some();
        let looks_like_path = has_ext || name.contains('/') || name.contains(MAIN_SEPARATOR);
        if looks_like_path {
            // Anything at that path (a directory, a FIFO, a file that cannot be inspected)
            // goes to the loader, whose error says what is wrong with it; only a path that
            // does not exist falls through to the folders.
            match std::fs::metadata(as_file) {
                Ok(_) => return Ok(as_file.to_path_buf()),
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Ok(as_file.to_path_buf()),
                Err(_) => {}
            }
        }
        for dir in &self.dirs {
            let mut candidates = vec![dir.join(format!("{name}.exr")), dir.join(format!("{name}.hdr"))];
            if has_ext {
                candidates.push(dir.join(name));
            }
            if let Some(found) = candidates.into_iter().find(|c| c.is_file()) {
                return Ok(found);
            }
        }
        let searched = if self.dirs.is_empty() {
            "(no folders)".to_string()
        } else {
            self.dirs
                .iter()
                .map(|d| if d.is_dir() { d.display().to_string() } else { format!("{} (missing)", d.display()) })
                .collect::<Vec<_>>()
                .join(", ")
        };
        let as_path = if looks_like_path { " (no such file)".to_string() } else { String::new() };
        Err(SearchError::NotFound { name: name.to_string(), as_path, searched })
    }

    /// Resolves `name` (see [`SearchPath::resolve`]) and loads the map with [`load::load`].
    pub fn load(&self, name: &str) -> anyhow::Result<EnvMap> {
        let path = self.resolve(name)?;
        Ok(load::load(&path)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    fn touch(p: &Path) {
        if let Some(d) = p.parent() {
            fs::create_dir_all(d).unwrap();
        }
        fs::write(p, b"x").unwrap();
    }

    #[test]
    fn earlier_folder_and_exr_win() {
        let t = tempfile::tempdir().unwrap();
        let (a, b) = (t.path().join("a"), t.path().join("b"));
        touch(&b.join("m.exr"));
        touch(&a.join("m.hdr"));
        touch(&b.join("n.exr"));
        touch(&b.join("n.hdr"));
        let sp = SearchPath::new(vec![a.clone(), b.clone()]);
        // The first folder wins even though the second has the preferred extension.
        assert_eq!(sp.resolve("m").unwrap(), a.join("m.hdr"));
        // Within one folder .exr comes before .hdr.
        assert_eq!(sp.resolve("n").unwrap(), b.join("n.exr"));
        // Adding the .exr to the first folder makes it win.
        touch(&a.join("m.exr"));
        assert_eq!(sp.resolve("m").unwrap(), a.join("m.exr"));
    }

    #[test]
    fn name_with_extension_is_found_in_folders() {
        let t = tempfile::tempdir().unwrap();
        let a = t.path().join("a");
        touch(&a.join("probe.v2.exr"));
        touch(&a.join("q.pfm"));
        let sp = SearchPath::new(vec![a.clone()]);
        // "probe.v2" has an extension ("v2") but is not a file here: <name>.exr is tried.
        assert_eq!(sp.resolve("probe.v2").unwrap(), a.join("probe.v2.exr"));
        // A full file name inside a folder.
        assert_eq!(sp.resolve("q.pfm").unwrap(), a.join("q.pfm"));
        assert_eq!(sp.resolve("probe.v2.exr").unwrap(), a.join("probe.v2.exr"));
    }

    #[test]
    fn file_path_is_used_directly() {
        let t = tempfile::tempdir().unwrap();
        let f = t.path().join("elsewhere").join("x.exr");
        touch(&f);
        // An empty search path: the name is a path to an existing file.
        let sp = SearchPath::new(vec![]);
        let name = f.to_str().unwrap();
        assert_eq!(sp.resolve(name).unwrap(), f);
        // A folder given as a path reaches the loader, which says what is wrong with it.
        let dir_name = t.path().join("elsewhere");
        let msg = format!("{:#}", sp.load(dir_name.to_str().unwrap()).unwrap_err());
        assert!(msg.contains("is a directory"), "{msg}");
        // So does a path through a file (ENOTDIR); a path to nothing is "not found".
        let through = f.join("inner.exr");
        let msg = format!("{:#}", sp.load(through.to_str().unwrap()).unwrap_err());
        assert!(msg.contains("inner.exr: cannot"), "{msg}");
        let msg = sp.resolve(t.path().join("nothing.exr").to_str().unwrap()).unwrap_err().to_string();
        assert!(msg.contains("not found (no such file)"), "{msg}");
    }

    #[test]
    fn not_found_lists_every_folder() {
        let t = tempfile::tempdir().unwrap();
        let a = t.path().join("a");
        let gone = t.path().join("gone");
        let b = t.path().join("b");
        fs::create_dir_all(&a).unwrap();
        fs::create_dir_all(&b).unwrap();
        let sp = SearchPath::new(vec![a.clone(), gone.clone(), b.clone()]);
        let msg = sp.resolve("nope").unwrap_err().to_string();
        let expected = format!(
            "map 'nope' not found; searched: {}, {} (missing), {} (set PROBELAB_ENVMAPS",
            a.display(),
            gone.display(),
            b.display()
        );
        assert!(msg.starts_with(&expected), "{msg}");
        assert!(msg.contains("README"), "{msg}");
        // A path-like name that does not exist says so, and still lists the folders.
        let msg = sp.resolve("sub/nope.exr").unwrap_err().to_string();
        assert!(msg.contains("'sub/nope.exr' not found (no such file)"), "{msg}");
        assert!(msg.contains(&format!("{} (missing)", gone.display())), "{msg}");
        assert_eq!(sp.resolve(""), Err(SearchError::EmptyName));
    }

    #[cfg(unix)]
    #[test]
    fn from_list_puts_repo_first_and_skips_empty_entries() {
        let sp = SearchPath::from_list(PathBuf::from("repo/envmaps"), Some(OsStr::new(":/x/maps::/y:repo/envmaps:")));
        let want: Vec<PathBuf> = ["repo/envmaps", "/x/maps", "/y"].iter().map(PathBuf::from).collect();
        assert_eq!(sp.dirs(), want.as_slice());
        assert_eq!(SearchPath::from_list(PathBuf::from("r"), None).dirs(), [PathBuf::from("r")]);
    }

    #[test]
    fn load_resolves_then_reports_load_errors_with_the_path() {
        let t = tempfile::tempdir().unwrap();
        let f = t.path().join("bad.exr");
        fs::write(&f, b"not an image").unwrap();
        let sp = SearchPath::new(vec![t.path().to_path_buf()]);
        let msg = format!("{:#}", sp.load("bad").unwrap_err());
        assert!(msg.starts_with(&f.display().to_string()), "{msg}");
        assert!(msg.contains("magic"), "{msg}");
        let msg = format!("{:#}", sp.load("missing").unwrap_err());
        assert!(msg.contains("map 'missing' not found"), "{msg}");
    }
}
