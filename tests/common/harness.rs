//! The harness the integration tests share: the repository, the `probelab` binary run as a
//! child process, its CSV output as rows, scratch repositories in temporary folders, and byte
//! snapshots of folders.

use std::collections::{BTreeMap, HashMap};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository (the package root).
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The `probelab` binary, run from the repository root with `PROBELAB_ENVMAPS` unset, so that it
/// finds only the repository's `envmaps/` unless the test says otherwise.
pub fn probelab() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_probelab"));
    c.current_dir(repo()).env_remove("PROBELAB_ENVMAPS");
    c
}

/// Runs a command built by [`probelab`] (or [`Scratch::probelab`]) to completion.
pub trait Run {
    fn run(&mut self) -> Output;
}

impl Run for Command {
    fn run(&mut self) -> Output {
        self.output().expect("run probelab")
    }
}

/// `probelab ARGS` from the repository root, `PROBELAB_ENVMAPS` unset.
pub fn run(args: &[&str]) -> Output {
    probelab().args(args).run()
}

/// The stdout of a run that must have succeeded (else the test fails with its stderr).
pub fn stdout_ok(out: &Output) -> String {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout.clone()).expect("stdout is UTF-8")
}

/// The stderr of a run that must have succeeded (where `probelab` logs what it wrote).
pub fn stderr_ok(out: &Output) -> String {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Rows of CSV text as (header → value) maps.
pub fn parse_csv(text: &str) -> Vec<HashMap<String, String>> {
    // A leading `# …` line is a comment (the probe summary's source), as pandas' `comment="#"`.
    let mut r = csv::ReaderBuilder::new().comment(Some(b'#')).from_reader(text.as_bytes());
    let h: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    r.records().map(|rec| h.iter().cloned().zip(rec.unwrap().iter().map(String::from)).collect()).collect()
}

/// A scratch repository: a temporary folder the binary runs on with `--root`, holding what the
/// test writes into it or copies from the repository. Removed when dropped.
pub struct Scratch {
    dir: tempfile::TempDir,
}

impl Default for Scratch {
    fn default() -> Self {
        Self::new()
    }
}

impl Scratch {
    /// An empty scratch repository.
    pub fn new() -> Self {
        Scratch { dir: tempfile::tempdir().expect("create a temporary folder") }
    }

    /// Its root folder.
    pub fn path(&self) -> &Path {
        self.dir.path()
    }

    /// Writes `bytes` to `rel` (a path relative to the root), creating its folders.
    pub fn write(&self, rel: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
        let p = self.path().join(rel);
        fs::create_dir_all(p.parent().unwrap()).unwrap();
        fs::write(&p, bytes).unwrap();
        p
    }

    /// Copies the repository's `rel` (a file, or a folder with everything under it) to the
    /// same place in the scratch repository.
    pub fn copy_from_repo(&self, rel: &str) {
        copy_tree(&repo().join(rel), &self.path().join(rel));
    }

    /// The binary run on this root (`--root`), `PROBELAB_ENVMAPS` unset.
    pub fn probelab(&self) -> Command {
        let mut c = probelab();
        c.arg("--root").arg(self.path());
        c
    }

    /// `probelab --root ROOT ARGS`.
    pub fn run(&self, args: &[&str]) -> Output {
        self.probelab().args(args).run()
    }

    /// A [`snapshot`] of the folder `rel` of the root.
    pub fn snapshot(&self, rel: &str) -> BTreeMap<PathBuf, Vec<u8>> {
        snapshot(&self.path().join(rel))
    }
}

/// Copies a file, or a folder recursively, creating the destination's folders.
fn copy_tree(from: &Path, to: &Path) {
    if from.is_dir() {
        fs::create_dir_all(to).unwrap();
        for e in fs::read_dir(from).unwrap() {
            let e = e.unwrap();
            copy_tree(&e.path(), &to.join(e.file_name()));
        }
    } else {
        fs::create_dir_all(to.parent().unwrap()).unwrap();
        fs::copy(from, to).unwrap_or_else(|e| panic!("copy {}: {e}", from.display()));
    }
}

/// Every file under `dir` (recursively, hidden files included) with its bytes, keyed by its
/// path relative to `dir`; empty when `dir` does not exist.
pub fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = fs::read_dir(&d) else { continue };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let bytes = fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                out.insert(p.strip_prefix(dir).unwrap().to_path_buf(), bytes);
            }
        }
    }
    out
}

/// A `width` × `height` map whose texel at column `i`, row `j` (row 0 at the zenith) is
/// `f(i, j)`, built through the public surface ([`probelab::Map::from_texels`]).
pub fn map_from_fn(
    name: &str,
    width: usize,
    height: usize,
    mut f: impl FnMut(usize, usize) -> [f32; 3],
) -> probelab::Map {
    let texels = (0..height).flat_map(|j| (0..width).map(move |i| (i, j))).map(|(i, j)| f(i, j)).collect();
    probelab::Map::from_texels(name, width, height, texels).expect("a valid test map")
}

/// The lowercase hex sha256 of `bytes`, computed here rather than by the library, as provenance
/// files and JSON documents record a file's.
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// Makes the `provenance.toml` at `path` vouch for a table of bytes `table`, as if `bless`
/// had written them together: its `table_sha256` line, and nothing else, is rewritten.
pub fn vouch_for(path: &Path, table: &[u8]) {
    let text = fs::read_to_string(path).expect("provenance.toml");
    let key = "table_sha256 = ";
    assert_eq!(text.lines().filter(|l| l.starts_with(key)).count(), 1, "{}: one {key}line", path.display());
    let edited: String = text
        .split_inclusive('\n')
        .map(|l| if l.starts_with(key) { format!("{key}\"{}\"\n", sha256_hex(table)) } else { l.to_string() })
        .collect();
    fs::write(path, edited).expect("rewrite provenance.toml");
}
