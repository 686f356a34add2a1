//! The one atomic writer: every file probelab writes is written to a temporary file beside its
//! target, synced, renamed over the target, and the folder synced, so a failure or a kill
//! leaves either the old file or the new one, never half of one. This is the only module that
//! renames temporary files into place.
//!
//! - [`Staged`]: a temporary file beside its target (`.NAME.tmp-PID-N`), removed when dropped
//!   unless [`Staged::commit`] moved it into place;
//! - [`write()`] (bytes), [`write_with`] (streamed through a buffer) and [`write_set`] (several
//!   files of one folder, all or none: a baseline's table and provenance) build on it.
//!
//! The writer removes nothing but its own temporary file, and remembers nothing between
//! writes. The temporary names are the ones [`crate::io::folder::remove_stale`] recognises: what
//! a killed writer leaves is removed by the workflow that writes the folder next, which is
//! handed the paths removed and reports them (`ops::Env::writing` for an output folder under
//! its lock, `ops::Env::remove_stale_beside` for a lone output file).

use anyhow::{bail, Context, Result};
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// A new temporary file beside a target path, not yet in place. Dropping it without
/// [`Staged::commit`] removes the temporary file.
#[derive(Debug)]
pub struct Staged {
    target: PathBuf,
    tmp: PathBuf,
    file: File,
}

impl Staged {
    /// Creates a uniquely named temporary file in the folder of `target` (`.NAME.tmp-PID-N`).
    /// The folder must exist.
    pub fn beside(target: &Path) -> std::io::Result<Staged> {
        // N, counted per process so two stages of one process never share a name: the one
        // static of the writer, which names files and remembers nothing about them.
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let dir = folder_of(target);
        let name = target.file_name().unwrap_or(target.as_os_str()).to_string_lossy();
        let mut last = None;
        for _ in 0..16 {
            let n = COUNTER.fetch_add(1, Ordering::Relaxed);
            let tmp = dir.join(format!(".{name}.tmp-{}-{n}", std::process::id()));
            match OpenOptions::new().write(true).create_new(true).open(&tmp) {
                Ok(file) => return Ok(Staged { target: target.to_path_buf(), tmp, file }),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
                Err(e) => return Err(named(target, "cannot create its temporary file", e)),
            }
        }
        let e = last.unwrap_or_else(|| std::io::Error::other("no free temporary name"));
        Err(named(target, "cannot create its temporary file", e))
    }

    /// The temporary file's path.
    pub fn tmp_path(&self) -> &Path {
        &self.tmp
    }

    /// The open temporary file, to write into (directly, or through a `BufWriter` that borrows
    /// it and is flushed before [`Staged::commit`]).
    pub fn file(&mut self) -> &mut File {
        &mut self.file
    }

    /// Syncs the temporary file and moves it over the target, then syncs the folder.
    pub fn commit(mut self) -> std::io::Result<()> {
        self.file.sync_all().map_err(|e| named(&self.target, "cannot sync its temporary file", e))?;
        std::fs::rename(&self.tmp, &self.target).map_err(|e| named(&self.target, "cannot move into place", e))?;
        // Renamed: nothing left to remove on drop.
        self.tmp = PathBuf::new();
        sync_folder(folder_of(&self.target));
        Ok(())
    }

    /// Writes all of `bytes` into the temporary file; the error names the target.
    fn write_all(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.file.write_all(bytes).map_err(|e| named(&self.target, "cannot write", e))
    }
}

/// An IO error whose message names the target file and the step that failed (the kind kept),
/// so every caller's message says which file, however it wraps it.
fn named(target: &Path, step: &str, e: std::io::Error) -> std::io::Error {
    std::io::Error::new(e.kind(), format!("{}: {step}: {e}", target.display()))
}

impl Drop for Staged {
    fn drop(&mut self) {
        if !self.tmp.as_os_str().is_empty() {
            // Best effort: the error that stopped the write is the one worth reporting.
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// The folder a path lives in (`.` for a bare file name).
fn folder_of(path: &Path) -> &Path {
    path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."))
}

/// Syncs a folder, so a rename in it survives a crash (best effort: not every file system
/// lets a folder be opened for that).
fn sync_folder(dir: &Path) {
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
}

/// Whether `path` is a regular file whose content is exactly `bytes` (read only when the sizes
/// agree, so never more than `bytes.len()`; any error reading it counts as "no").
fn holds(path: &Path, bytes: &[u8]) -> bool {
    let same_size = std::fs::symlink_metadata(path).is_ok_and(|m| m.is_file() && m.len() == bytes.len() as u64);
    same_size && std::fs::read(path).is_ok_and(|old| old == bytes)
}

/// Creates the folder of `path` and stages a temporary file beside it, errors naming the path.
fn stage(path: &Path) -> Result<Staged> {
    let dir = folder_of(path);
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create its folder {}", path.display(), dir.display()))?;
    Ok(Staged::beside(path)?)
}

/// Writes `bytes` to `path` atomically, creating parent folders. A regular file that already
/// holds exactly `bytes` is left untouched (not rewritten, its modification time kept), so a
/// regeneration whose data did not change changes no file.
pub fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    if holds(path, bytes) {
        return Ok(());
    }
    let mut staged = stage(path)?;
    staged.write_all(bytes)?;
    Ok(staged.commit()?)
}

/// Streams a file atomically: `f` writes into a buffered temporary file beside `path`, which
/// replaces `path` only if `f` succeeds (for outputs too large to hold in memory).
pub fn write_with<T>(path: &Path, f: impl FnOnce(&mut std::io::BufWriter<&mut File>) -> Result<T>) -> Result<T> {
    let mut staged = stage(path)?;
    let mut w = std::io::BufWriter::with_capacity(1 << 20, staged.file());
    let out = f(&mut w).with_context(|| format!("{}: not written", path.display()))?;
    w.into_inner().map_err(|e| anyhow::anyhow!("{}: cannot write: {}", path.display(), e.error()))?;
    staged.commit()?;
    Ok(out)
}

/// Writes several files into `dir` as one set (a baseline): every file is first staged and
/// synced; only then are they renamed into place, in the order given (put the file that
/// vouches for the others, the provenance, last). If a rename fails, the files already renamed
/// are restored from hard-linked copies of their old versions (`.NAME.old-PID`), so the old set
/// stays whole. A kill between two renames cannot be rolled back; the provenance's table
/// checksum then exposes the mismatch to `probelab check`.
pub fn write_set(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<()> {
    write_set_failing_after(dir, files, None)
}

/// [`write_set`], with a failure injected before rename number `fail_at` (for tests).
fn write_set_failing_after(dir: &Path, files: &[(String, Vec<u8>)], fail_at: Option<usize>) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create folder", dir.display()))?;
    let mut staged = Vec::new();
    for (name, bytes) in files {
        let target = dir.join(name);
        let mut s = Staged::beside(&target)?;
        s.write_all(bytes)?;
        // Every file synced before the first rename (the commit's own sync is then free).
        s.file().sync_all().map_err(|e| named(&target, "cannot sync its temporary file", e))?;
        staged.push(s);
    }
    let backups = Backups::keep(dir, files)?;
    for (i, s) in staged.into_iter().enumerate() {
        let target = dir.join(&files[i].0);
        let result =
            if fail_at == Some(i) { Err(std::io::Error::other("injected failure (test)")) } else { s.commit() };
        if let Err(e) = result {
            backups.restore(&files[..i]);
            return Err(e).with_context(|| {
                format!("{}: not written; the previous versions of the set were kept", target.display())
            });
        }
    }
    Ok(())
}

/// Hard-linked copies (`.NAME.old-PID`) of the files a [`write_set`] replaces, removed when
/// dropped.
struct Backups {
    dir: PathBuf,
    names: Vec<String>,
}

impl Backups {
    fn path(dir: &Path, name: &str) -> PathBuf {
        dir.join(format!(".{name}.old-{}", std::process::id()))
    }

    /// Links (or copies) every existing target; refuses a target that is not a regular file.
    fn keep(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<Backups> {
        let mut kept = Backups { dir: dir.to_path_buf(), names: Vec::new() };
        for (name, _) in files {
            let target = dir.join(name);
            match std::fs::symlink_metadata(&target) {
                Err(_) => {}
                Ok(m) if m.is_file() => {
                    let bak = Self::path(dir, name);
                    let _ = std::fs::remove_file(&bak);
                    std::fs::hard_link(&target, &bak)
                        .or_else(|_| std::fs::copy(&target, &bak).map(|_| ()))
                        .with_context(|| format!("{}: cannot keep the old version", target.display()))?;
                    kept.names.push(name.clone());
                }
                Ok(_) => bail!("{}: exists and is not a regular file", target.display()),
            }
        }
        Ok(kept)
    }

    /// Puts back the old versions of `done` (removing those that had none).
    fn restore(&self, done: &[(String, Vec<u8>)]) {
        for (name, _) in done {
            let target = self.dir.join(name);
            if self.names.contains(name) {
                let _ = std::fs::rename(Self::path(&self.dir, name), &target);
            } else {
                let _ = std::fs::remove_file(&target);
            }
        }
    }
}

impl Drop for Backups {
    fn drop(&mut self) {
        for name in &self.names {
            let _ = std::fs::remove_file(Self::path(&self.dir, name));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same bytes again leave the file itself in place (a rename would give a new inode);
    /// different bytes of the same length replace it.
    #[cfg(unix)]
    #[test]
    fn same_bytes_leave_the_file_untouched() {
        use std::os::unix::fs::MetadataExt;
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("t.png");
        write(&p, b"same").unwrap();
        let ino = std::fs::metadata(&p).unwrap().ino();
        write(&p, b"same").unwrap();
        assert_eq!(std::fs::metadata(&p).unwrap().ino(), ino, "identical bytes: not rewritten");
        write(&p, b"diff").unwrap();
        assert_ne!(std::fs::metadata(&p).unwrap().ino(), ino, "new bytes: replaced");
        assert_eq!(std::fs::read(&p).unwrap(), b"diff");
    }

    #[test]
    fn writes_and_replaces() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("a/b/t.csv");
        write(&p, b"one").unwrap();
        write(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        assert_eq!(std::fs::read_dir(p.parent().unwrap()).unwrap().count(), 1, "no temp file left");
    }

    #[test]
    fn streaming_write_replaces_only_on_success() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("s.bin");
        write_with(&p, |w| Ok(w.write_all(b"abc")?)).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"abc");
        let e: Result<()> = write_with(&p, |w| {
            w.write_all(b"partial")?;
            anyhow::bail!("stopped")
        });
        assert!(e.is_err());
        assert_eq!(std::fs::read(&p).unwrap(), b"abc");
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 1, "no temp file left");
    }

    #[test]
    fn staged_names_are_the_ones_stale_cleanup_knows() {
        let d = tempfile::tempdir().unwrap();
        let s = Staged::beside(&d.path().join("t.csv")).unwrap();
        let name = s.tmp_path().file_name().unwrap().to_str().unwrap().to_string();
        assert_eq!(crate::io::folder::temp_file_pid(&name), Some(std::process::id()), "{name}");
        drop(s);
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 0, "a dropped stage leaves nothing");
    }

    #[test]
    fn failure_leaves_old_file() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("t.csv");
        write(&p, b"old").unwrap();
        // Renaming a file over a non-empty directory fails: the old content stays.
        let q = d.path().join("dir");
        std::fs::create_dir(&q).unwrap();
        std::fs::write(q.join("x"), b"x").unwrap();
        assert!(write(&q, b"new").is_err());
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 2, "no temp file left");
    }

    /// Every step that can fail says which target: the folder cannot be made, the temporary
    /// file cannot be created, the rename fails (a non-empty folder in the way), the set's
    /// rename fails.
    #[test]
    fn writer_errors_name_their_target() {
        let d = tempfile::tempdir().unwrap();
        std::fs::write(d.path().join("file"), b"x").unwrap();
        let under_a_file = d.path().join("file/t.csv");
        let e = format!("{:#}", write(&under_a_file, b"x").unwrap_err());
        assert!(e.starts_with(&format!("{}: cannot create its folder", under_a_file.display())), "{e}");
        let e = Staged::beside(&under_a_file).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{}: cannot create its temporary file", under_a_file.display())), "{e}");
        let busy = d.path().join("busy");
        std::fs::create_dir_all(busy.join("inside")).unwrap();
        let e = format!("{:#}", write(&busy, b"x").unwrap_err());
        assert!(e.starts_with(&format!("{}: cannot move into place", busy.display())), "{e}");
        let e = format!("{:#}", write_with(&busy, |w| Ok(w.write_all(b"x")?)).unwrap_err());
        assert!(e.starts_with(&format!("{}: cannot move into place", busy.display())), "{e}");
        let e = format!("{:#}", write_set(d.path(), &[("busy".into(), b"x".to_vec())]).unwrap_err());
        assert!(e.contains(&busy.display().to_string()), "{e}");
    }

    /// A write removes nothing but its own temporary file: another writer's, even one whose
    /// process is gone, stays for the workflow to remove (`io::folder::remove_stale`).
    #[test]
    fn a_write_leaves_other_temporaries_alone() {
        let d = tempfile::tempdir().unwrap();
        let gone = crate::io::folder::pid_of_a_finished_process();
        let stale = d.path().join(format!(".t.csv.tmp-{gone}"));
        std::fs::write(&stale, b"x").unwrap();
        write(&d.path().join("t.csv"), b"new").unwrap();
        assert!(stale.exists());
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 2, "the target and the stale file");
    }

    #[test]
    fn a_set_replaces_every_file_or_none() {
        let d = tempfile::tempdir().unwrap();
        let files = |t: &str| vec![("table.csv".to_string(), t.as_bytes().to_vec()), ("p.toml".into(), t.into())];
        write_set(d.path(), &files("old")).unwrap();
        // A failure after the first rename: the first file is restored, the second untouched.
        assert!(write_set_failing_after(d.path(), &files("new"), Some(1)).is_err());
        for n in ["table.csv", "p.toml"] {
            assert_eq!(std::fs::read_to_string(d.path().join(n)).unwrap(), "old", "{n}");
        }
        // A target that cannot be replaced is found before anything is renamed.
        std::fs::remove_file(d.path().join("p.toml")).unwrap();
        std::fs::create_dir(d.path().join("p.toml")).unwrap();
        assert!(write_set(d.path(), &files("new")).is_err());
        assert_eq!(std::fs::read_to_string(d.path().join("table.csv")).unwrap(), "old");
        std::fs::remove_dir(d.path().join("p.toml")).unwrap();
        // No temporary or backup file is left behind by the failures.
        let left: Vec<_> = std::fs::read_dir(d.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left, ["table.csv"], "{left:?}");
        write_set(d.path(), &files("new")).unwrap();
        for n in ["table.csv", "p.toml"] {
            assert_eq!(std::fs::read_to_string(d.path().join(n)).unwrap(), "new", "{n}");
        }
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 2);
    }
}
