//! Finding environment maps by name in a list of folders (docs/maps.md).
//!
//! The repository's `envmaps/` folder comes first, then every folder listed in the
//! environment variable `PROBELAB_ENVMAPS` (colon-separated on Unix; empty entries are
//! ignored). A name such as `grace_256x128` resolves to the first of
//! `<dir>/grace_256x128.exr`, `<dir>/grace_256x128.hdr` found, trying each folder in order;
//! then, for a known map ([`crate::envmap::known`]), to the first file under one of its aliases
//! (`<dir>/grace.exr`, `<dir>/grace.hdr`: the peer tool's `Data/Probes/grace.hdr`).
//!
//! [`SearchPath::open`] reads the map and applies the identity rule
//! ([`crate::envmap::identity`]): a known name only ever opens a file with that map's pixels (a
//! file that has other pixels is passed over, and the not-found error says which and why), and
//! a map whose pixels are a known map's is read as that map's half values, so that the peer's
//! `.hdr` gives the same texels, and the same numbers, as the `.exr` the baselines were
//! computed from.

use super::identity;
use super::known::{self, KnownMap};
use super::load::{self, LoadError};
use super::EnvMap;
use std::ffi::OsStr;
use std::path::{Path, PathBuf, MAIN_SEPARATOR};

/// Why a map is missing when no file has its name ([`SearchError::reason`], before any
/// suggestion).
pub const NO_FILE: &str = "no file of that name on the search path";

/// How a suggestion for a mistyped name starts ([`crate::math::nearest::did_you_mean`]).
const SUGGESTION: &str = " (did you mean";

/// The environment variable listing extra map folders.
pub const ENV_VAR: &str = "PROBELAB_ENVMAPS";

/// Why a map name could not be resolved to a file.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum SearchError {
    /// No candidate file exists in any folder, or none has the pixels of the known map named.
    #[error(
        "map '{name}' not found{after_name}; searched: {searched}{} (set PROBELAB_ENVMAPS to a \
         colon-separated list of folders; see docs/maps.md for where the paper probes come from)",
        why_suffix(.rejected, .get)
    )]
    NotFound {
        /// The name asked for.
        name: String,
        /// `" (no such file)"` when the name looked like a file path; `" (did you mean 'x'?)"`
        /// when an unknown name is close to a known map's or a map file's on the search path
        /// ([`crate::math::nearest`], [`SUGGESTION`]); else empty. One field for both, which never
        /// meet, keeps the error small.
        after_name: String,
        /// Every folder searched, in order, each marked `(missing)` if it does not exist.
        searched: String,
        /// Files found under the name or an alias of it but not taken, each with the reason.
        rejected: Vec<String>,
        /// For a known map: how to get it.
        get: Option<String>,
    },
    /// A path (a name with a folder in it), which is read as given and never looked up in the
    /// folders, names no file.
    #[error("map '{name}' not found ({NO_SUCH_FILE}; a path is read as given, not looked up in the map folders)")]
    NoSuchFile {
        /// The path asked for.
        name: String,
    },
    /// The name is empty.
    #[error("empty map name")]
    EmptyName,
}

/// Why a map given as a path is missing ([`SearchError::reason`]).
pub const NO_SUCH_FILE: &str = "no such file";

/// Whether a map name is looked up in the search path's folders (a plain name is; a path with
/// a folder in it is read as given): what decides whether a not-found message lists them.
pub fn looked_up(name: &str) -> bool {
    crate::io::name::is_plain(name)
}

/// One missing map with why, for a list of them: `name (why)`, a suggestion inside `why`
/// (`… (did you mean 'x'?)`) set after a semicolon, so the parentheses never nest.
pub fn missing_item(name: &str, why: &str) -> String {
    match why.find(SUGGESTION) {
        Some(i) => format!("{name} ({}; {})", &why[..i], why[i + 2..].trim_end_matches(')')),
        None => format!("{name} ({why})"),
    }
}

/// The part of the not-found message after the folders searched.
fn why_suffix(rejected: &[String], get: &Option<String>) -> String {
    let mut s = String::new();
    if !rejected.is_empty() {
        s += &format!("; not taken: {}", rejected.join("; "));
    }
    if let Some(g) = get {
        s += &format!("; it is a known map, {g}");
    }
    s
}

impl SearchError {
    /// Why the map is missing, in a few words (for one line of a report): the files passed
    /// over and how to get the map if it is known, else that no file has its name.
    pub fn reason(&self) -> String {
        match self {
            SearchError::NotFound { rejected, get, .. } if !rejected.is_empty() || get.is_some() => {
                why_suffix(rejected, get).trim_start_matches("; ").to_string()
            }
            SearchError::NotFound { after_name, .. } if after_name.starts_with(SUGGESTION) => {
                format!("{NO_FILE}{after_name}")
            }
            SearchError::NotFound { .. } => NO_FILE.to_string(),
            SearchError::NoSuchFile { .. } => NO_SUCH_FILE.to_string(),
            SearchError::EmptyName => "empty map name".to_string(),
        }
    }
}

/// The files passed over in a [`SearchError::reason`] (`"not taken: …"`), without how to get
/// the map: what a list that names each missing map once shows beside it.
pub fn passed_over_in(reason: &str) -> Option<String> {
    let rest = reason.strip_prefix("not taken: ")?;
    Some(format!("not taken: {}", rest.split("; it is a known map").next().unwrap_or(rest)))
}

/// Why [`SearchPath::open`] failed: the map is not here, or a file found cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// The name resolved to no usable file on the search path.
    #[error(transparent)]
    NotFound(#[from] SearchError),
    /// A file was found but could not be loaded.
    #[error(transparent)]
    Load(#[from] LoadError),
}

/// An ordered list of folders in which map names are looked up.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SearchPath {
    dirs: Vec<PathBuf>,
}

/// A file that may hold the map asked for.
struct Candidate {
    path: PathBuf,
    /// Found under an alias of a known map, not under the name itself.
    alias: bool,
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

    /// The folders searched, comma-separated, each marked `(missing)` when it is not there
    /// (what an error about a map not found prints).
    pub fn describe(&self) -> String {
        let shown: Vec<String> = self
            .dirs
            .iter()
            .map(|d| if d.is_dir() { d.display().to_string() } else { format!("{} (missing)", d.display()) })
            .collect();
        shown.join(", ")
    }

    /// Every file that may hold map `name`, in the order they are tried.
    ///
    /// If `name` looks like a file path (contains a path separator or has an extension) and
    /// something exists there (or cannot be inspected), that path alone, so the loader reports
    /// what is wrong with it (a directory, a FIFO, permission denied). Otherwise each folder in
    /// turn for `<dir>/<name>.exr`, `<dir>/<name>.hdr` and, if `name` has an extension,
    /// `<dir>/<name>`; then, for a known map, each folder for each alias `<dir>/<alias>.exr`,
    /// `<dir>/<alias>.hdr`. Only existing files are listed.
    fn candidates(&self, name: &str) -> Vec<Candidate> {
        let as_file = Path::new(name);
        let has_ext = as_file.extension().is_some();
        if looks_like_path(name) {
            // Anything at that path (a directory, a FIFO, a file that cannot be inspected)
            // goes to the loader, whose error says what is wrong with it; only a path that
            // does not exist falls through to the folders.
            match std::fs::metadata(as_file) {
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                _ => return vec![Candidate { path: as_file.to_path_buf(), alias: false }],
            }
        }
        let mut out = Vec::new();
        // Only a plain name is looked up in the folders: `../x` must not leave them.
        if !crate::io::name::is_plain(name) {
            return out;
        }
        let mut push = |stem: &str, alias: bool, with_name: bool| {
            for dir in &self.dirs {
                let mut files = map_files_named(dir, stem);
                if with_name {
                    files.push(dir.join(stem));
                }
                out.extend(files.into_iter().filter(|c| c.is_file()).map(|path| Candidate { path, alias }));
            }
        };
        push(name, false, has_ext);
        for alias in known::by_name(name).map(|k| k.aliases.as_slice()).unwrap_or_default() {
            push(alias, true, false);
        }
        out
    }

    /// The error for a map none of whose candidates was taken.
    fn not_found(&self, name: &str, rejected: Vec<String>) -> SearchError {
        if !looked_up(name) && rejected.is_empty() {
            return SearchError::NoSuchFile { name: name.to_string() };
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
        let path_like = looks_like_path(name);
        let get = known::by_name(name).map(|k| format!("{}x{}, {}; {}", k.width, k.height, k.source, k.get));
        let after_name = if path_like {
            " (no such file)".to_string()
        } else if get.is_some() {
            String::new()
        } else {
            crate::math::nearest::did_you_mean(name, &self.names())
        };
        SearchError::NotFound { name: name.to_string(), after_name, searched, rejected, get }
    }

    /// The known maps ([`crate::envmap::known`]) with no file on this search path under their
    /// name or an alias, in the table's order (by name only: no file is read).
    pub fn known_missing(&self) -> Vec<&'static KnownMap> {
        known::all().iter().filter(|k| self.candidates(&k.name).is_empty()).collect()
    }

    /// Every map name this search path knows of: the known maps and their aliases, then the
    /// stem of every `.exr` and `.hdr` file in its folders (what a typo is compared with).
    pub fn names(&self) -> Vec<String> {
        let mut names: Vec<String> =
            known::all().iter().flat_map(|k| std::iter::once(&k.name).chain(&k.aliases)).cloned().collect();
        for dir in &self.dirs {
            let Ok(entries) = std::fs::read_dir(dir) else { continue };
            let mut stems: Vec<String> = entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| has_map_extension(p))
                .filter_map(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
                .collect();
            stems.sort();
            names.extend(stems.into_iter().filter(|s| !names.contains(s)).collect::<Vec<_>>());
        }
        names
    }

    /// The file [`SearchPath::open`] would try first for `name` (see `candidates`),
    /// without reading it: for a known map found under an alias, whether its pixels are that
    /// map's is only known once it is opened. If no file exists the error lists every folder
    /// searched, marking those that do not exist.
    pub fn resolve(&self, name: &str) -> Result<PathBuf, SearchError> {
        if name.is_empty() {
            return Err(SearchError::EmptyName);
        }
        match self.candidates(name).into_iter().next() {
            Some(c) => Ok(c.path),
            None => Err(self.not_found(name, Vec::new())),
        }
    }

    /// Finds and reads map `name` under the identity rule (module documentation): each
    /// candidate in turn is loaded with [`load::load`]; for a known map the first whose pixel
    /// sha256 is the map's is taken, the others are passed over and named in the not-found
    /// error. A map whose pixels are a known map's is read as its halves
    /// ([`identity::halved`]). The map is named `name` when `name` is a known map (so a file
    /// found under an alias gives the rows of the map asked for), else after its file stem;
    /// it carries its pixel sha256. A candidate that cannot be read is an error.
    pub fn open(&self, name: &str) -> Result<EnvMap, OpenError> {
        if name.is_empty() {
            return Err(SearchError::EmptyName.into());
        }
        let wanted = known::by_name(name);
        let mut rejected = Vec::new();
        for c in self.candidates(name) {
            let mut map = load::load(&c.path)?;
            let pixels = map.pixel_sha256.clone().unwrap_or_else(|| identity::pixel_sha256(&map));
            if let Some(k) = wanted.filter(|k| k.pixel_sha256 != pixels) {
                rejected.push(passed_over(&c.path, &map, &pixels, k));
                continue;
            }
            if known::by_pixels(&pixels).is_some() {
                // A known map's halves are finite, so this cannot fail; were it to, the
                // texels as read are kept.
                if let Ok(h) = identity::halved(&map) {
                    map = h;
                }
            }
            if wanted.is_some() || c.alias {
                map.name = name.to_string();
            }
            map.pixel_sha256 = Some(pixels);
            return Ok(map);
        }
        Err(self.not_found(name, rejected).into())
    }

    /// The maps not found, each with why ([`missing_item`]), then the folders searched
    /// (`\nSearched: …`) when one of them was looked up there: a path is read as given.
    pub fn missing_maps(&self, missing: &[String], why: &[String]) -> String {
        let list: Vec<String> = missing.iter().zip(why).map(|(m, w)| missing_item(m, w)).collect();
        let searched = if missing.iter().any(|m| looked_up(m)) {
            format!("\nSearched: {}", self.describe())
        } else {
            String::new()
        };
        format!("{}{searched}", list.join(", "))
    }

    /// [`SearchPath::open`], with any error as an `anyhow` error.
    pub fn load(&self, name: &str) -> anyhow::Result<EnvMap> {
        Ok(self.open(name)?)
    }
}

/// Whether a map name is meant as a file path: it has a path separator or an extension.
fn looks_like_path(name: &str) -> bool {
    Path::new(name).extension().is_some() || name.contains('/') || name.contains(MAIN_SEPARATOR)
}

/// The name a map found at `path` for `name` gets in tables (what [`SearchPath::open`] names
/// it): `name` itself for a known map, else the file stem.
pub fn table_name(name: &str, path: &Path) -> String {
    if known::by_name(name).is_some() {
        return name.to_string();
    }
    path.file_stem().unwrap_or(path.as_os_str()).to_string_lossy().into_owned()
}

/// Why the file at `path` is not known map `k`: its size and pixel sha256, and the known map
/// its pixels are, if any.
fn passed_over(path: &Path, map: &EnvMap, pixels: &str, k: &KnownMap) -> String {
    let what = match known::by_pixels(pixels) {
        Some(other) => format!("its pixels are the known map {}, not {}", other.name, k.name),
        None => {
            format!("its pixels are not those of {} ({}x{}, pixel sha256 {})", k.name, k.width, k.height, k.short())
        }
    };
    format!("{} ({}x{}, pixel sha256 {}: {what})", path.display(), map.width(), map.height(), &pixels[..12])
}

/// Whether `path` ends in a map extension, `.exr` or `.hdr`, in any case (`X.EXR`): what the
/// search path, `maps` and `maps import` take for a map file.
pub fn has_map_extension(path: &Path) -> bool {
    path.extension().is_some_and(|x| x.eq_ignore_ascii_case("exr") || x.eq_ignore_ascii_case("hdr"))
}

/// What is said of a map file whose name is not UTF-8, wherever one is met (`maps`, the
/// `--synth` palette, the command line): map names are text in tables, so no command uses it.
pub const NOT_UTF8: &str =
    "its name is not valid UTF-8: maps are named in tables by their file names, which must be text; rename the file";

/// The files of `dir` named `stem` with a map extension: `STEM.exr`, then `STEM.hdr`, then the
/// same extensions in any other case (`STEM.EXR`, as `maps` lists them), each in name order.
fn map_files_named(dir: &Path, stem: &str) -> Vec<PathBuf> {
    let mut files = vec![dir.join(format!("{stem}.exr")), dir.join(format!("{stem}.hdr"))];
    let Ok(entries) = std::fs::read_dir(dir) else { return files };
    let mut other_case: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.file_stem().is_some_and(|s| s == stem))
        .filter(|p| has_map_extension(p) && p.extension().is_some_and(|x| x != "exr" && x != "hdr"))
        .collect();
    other_case.sort();
    files.extend(other_case);
    files
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

    /// `maps` lists `X.EXR` as map `X`, so the name finds it too; the lower-case file wins.
    #[test]
    fn a_map_extension_in_any_case_is_found_by_name() {
        let t = tempfile::tempdir().unwrap();
        let a = t.path().join("a");
        touch(&a.join("Loud.EXR"));
        touch(&a.join("mixed.Hdr"));
        let sp = SearchPath::new(vec![a.clone()]);
        assert_eq!(sp.resolve("Loud").unwrap(), a.join("Loud.EXR"));
        assert_eq!(sp.resolve("mixed").unwrap(), a.join("mixed.Hdr"));
        assert!(sp.resolve("loud").is_err() || cfg!(not(target_os = "linux")));
        touch(&a.join("Loud.exr"));
        assert_eq!(sp.resolve("Loud").unwrap(), a.join("Loud.exr"));
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
        assert!(msg.contains("not found (no such file;"), "{msg}");
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
        assert!(msg.contains("docs/maps.md"), "{msg}");
        // A path that does not exist says so, and lists no folder: it was not looked up there.
        let msg = sp.resolve("sub/nope.exr").unwrap_err().to_string();
        assert!(msg.contains("'sub/nope.exr' not found (no such file; a path is read as given"), "{msg}");
        assert!(!msg.contains("searched") && !msg.contains(&a.display().to_string()), "{msg}");
        // A file name without a folder is looked up, and the folders are listed.
        let msg = sp.resolve("nope.exr").unwrap_err().to_string();
        assert!(msg.contains("'nope.exr' not found (no such file); searched: "), "{msg}");
        assert!(msg.contains(&format!("{} (missing)", gone.display())), "{msg}");
        assert_eq!(sp.resolve(""), Err(SearchError::EmptyName));
    }

    #[test]
    fn an_unknown_name_near_a_map_file_gets_a_suggestion() {
        let t = tempfile::tempdir().unwrap();
        touch(&t.path().join("gen_sky_sun.exr"));
        touch(&t.path().join("gen_sun_sky.exr"));
        let sp = SearchPath::new(vec![t.path().to_path_buf()]);
        let e = sp.resolve("gen_sky_su").unwrap_err();
        assert!(e.to_string().starts_with("map 'gen_sky_su' not found (did you mean 'gen_sky_sun'?); searched"), "{e}");
        assert!(e.reason().ends_with(" (did you mean 'gen_sky_sun'?)"), "{}", e.reason());
        // A known map that is not here is no typo, and a name near nothing gets no suggestion.
        assert!(!sp.resolve("ennis_256x128").unwrap_err().to_string().contains("did you mean"));
        assert!(!sp.resolve("landscape").unwrap_err().to_string().contains("did you mean"));
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

    #[test]
    fn a_list_of_missing_maps_never_nests_parentheses() {
        let why = format!("{NO_FILE} (did you mean 'gen_cone'?)");
        assert_eq!(missing_item("gen_cnoe", &why), format!("gen_cnoe ({NO_FILE}; did you mean 'gen_cone'?)"));
        assert_eq!(missing_item("a", NO_SUCH_FILE), "a (no such file)");
        assert!(looked_up("nope.exr") && looked_up("nope") && !looked_up("envmaps/nope.exr"));
    }
}
