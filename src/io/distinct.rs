//! Outputs never overwrite inputs. A command that reads files and writes others refuses, before
//! any work, an output that is one of its inputs (`probes --input X --save X` once destroyed X
//! and exited 0) or another of its outputs. Two paths are the same file when they name the same
//! place once resolved — the canonical path of an existing file, or of the existing part of a
//! new file's path followed by the rest (`./`, `..` and symbolic links resolved) — or, for
//! files that exist, when they have the same device and inode (hard links).

use anyhow::{bail, Result};
use std::path::{Component, Path, PathBuf};

/// Where a path leads: its resolved path, and its device and inode when it exists.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileId {
    resolved: PathBuf,
    inode: Option<(u64, u64)>,
}

impl FileId {
    /// Whether two ids are the same file.
    pub fn same(&self, other: &FileId) -> bool {
        self.resolved == other.resolved || (self.inode.is_some() && self.inode == other.inode)
    }
}

/// The id of `path` (which need not exist).
pub fn identity(path: &Path) -> FileId {
    FileId { resolved: resolved(path), inode: inode(path) }
}

#[cfg(unix)]
fn inode(path: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn inode(_: &Path) -> Option<(u64, u64)> {
    None
}

/// `path` made absolute and resolved: the longest leading part that exists canonicalised
/// (links, `.` and `..` resolved by the file system), the rest appended with `.` dropped and
/// `..` taking a part off.
fn resolved(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let parts: Vec<Component> = absolute.components().collect();
    for keep in (1..=parts.len()).rev() {
        let head: PathBuf = parts[..keep].iter().collect();
        if let Ok(mut out) = std::fs::canonicalize(&head) {
            for c in &parts[keep..] {
                match c {
                    Component::CurDir => {}
                    Component::ParentDir => {
                        out.pop();
                    }
                    other => out.push(other),
                }
            }
            return out;
        }
    }
    lexical(&absolute)
}

/// `.` dropped and `..` taking off the part before it, without touching the disk.
fn lexical(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// A file a command names, with the option that names it (`--input`, `--out`, "experiment").
#[derive(Debug, Clone, Copy)]
pub struct Named<'a> {
    /// The option or role that names it, for the message.
    pub role: &'a str,
    /// The path as given.
    pub path: &'a Path,
}

/// Refuses an output that is one of `inputs` or another of `outputs`, naming both. Call it
/// before any work: nothing has been read or written yet when it refuses.
pub fn refuse_overwrite(outputs: &[Named], inputs: &[Named]) -> Result<()> {
    let ins: Vec<FileId> = inputs.iter().map(|i| identity(i.path)).collect();
    let outs: Vec<FileId> = outputs.iter().map(|o| identity(o.path)).collect();
    for (i, (o, oid)) in outputs.iter().zip(&outs).enumerate() {
        if let Some((input, _)) = inputs.iter().zip(&ins).find(|(_, id)| id.same(oid)) {
            bail!(
                "{}: {} is the input {} ({}): an output never overwrites an input; nothing done",
                o.path.display(),
                o.role,
                input.path.display(),
                input.role
            );
        }
        if let Some((other, _)) = outputs[..i].iter().zip(&outs).find(|(_, id)| id.same(oid)) {
            bail!(
                "{}: {} is the same file as {} ({}): two outputs cannot share a file; nothing done",
                o.path.display(),
                o.role,
                other.path.display(),
                other.role
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn named(role: &str, path: &Path) -> Named<'static> {
        Named { role: Box::<str>::leak(role.into()), path: Box::<Path>::leak(path.into()) }
    }

    /// The spellings of one file that must all be caught: itself, `./`, `..`, a symbolic link
    /// to it or to its folder, a hard link; and a new output beside it is not caught.
    #[test]
    fn every_spelling_of_an_input_is_caught() {
        let d = tempfile::tempdir().unwrap();
        let input = d.path().join("sub").join("in.csv");
        std::fs::create_dir(d.path().join("sub")).unwrap();
        std::fs::write(&input, b"x").unwrap();
        std::os::unix::fs::symlink(&input, d.path().join("link.csv")).unwrap();
        std::os::unix::fs::symlink(d.path().join("sub"), d.path().join("dirlink")).unwrap();
        std::fs::hard_link(&input, d.path().join("hard.csv")).unwrap();
        let spellings = [
            input.clone(),
            d.path().join("sub/./in.csv"),
            d.path().join("sub/../sub/in.csv"),
            d.path().join("link.csv"),
            d.path().join("dirlink/in.csv"),
            d.path().join("hard.csv"),
        ];
        for s in &spellings {
            let e = refuse_overwrite(&[named("--save", s)], &[named("--input", &input)]).unwrap_err().to_string();
            assert!(e.contains("--save") && e.contains("--input") && e.contains("in.csv"), "{}: {e}", s.display());
        }
        let beside = d.path().join("sub/out.csv");
        refuse_overwrite(&[named("--save", &beside)], &[named("--input", &input)]).unwrap();
        // A new file reached through a link to the folder and through `..` is one file.
        let via_link = d.path().join("dirlink/new.csv");
        let via_dots = d.path().join("x/../sub/new.csv");
        let e = refuse_overwrite(&[named("--out", &via_link), named("--save", &via_dots)], &[]).unwrap_err();
        assert!(e.to_string().contains("two outputs"), "{e}");
    }

    #[test]
    fn paths_resolve_without_the_file() {
        assert_eq!(lexical(Path::new("/a/./b/../c")), PathBuf::from("/a/c"));
        let d = tempfile::tempdir().unwrap();
        let real = std::fs::canonicalize(d.path()).unwrap();
        assert_eq!(resolved(&d.path().join("none/../x/./y")), real.join("x/y"));
    }
}
