//! The output folder's discipline. Writing commands hold an exclusive advisory lock on the
//! folder they write ([`lock`], `flock` on the folder itself; `check` holds a shared one), so
//! two `bless` runs cannot interleave their tables and provenance. A killed writer leaves hidden
//! files behind: `.NAME.tmp-PID-N` (a [`crate::io::atomic::Staged`] file), `.NAME.tmp-PID` (the
//! same, as older versions named them) and `.NAME.old-PID` (the previous version a
//! [`crate::io::atomic::write_set`] keeps until every rename is done). Under the lock
//! [`remove_stale`] deletes those whose process is gone; beside a lone output file no lock
//! covers, [`remove_stale_in`] does the same in its folder. Both return what they removed, for
//! the workflow to report.

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// An advisory lock on an output folder, released when dropped (or when the process ends,
/// however it ends).
#[derive(Debug)]
pub struct DirLock {
    _dir: std::fs::File,
}

/// Locks the folder `dir` (created if missing) itself, with `flock` on the folder, so no lock
/// file is left in it: exclusively for a command that writes there, shared for one that only
/// reads. If another probelab command holds it, `waiting` is called once and the call blocks
/// until that command ends.
pub fn lock(dir: &Path, exclusive: bool, waiting: impl FnOnce()) -> Result<DirLock> {
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create folder", dir.display()))?;
    let file =
        std::fs::File::open(dir).with_context(|| format!("{}: cannot open the folder to lock it", dir.display()))?;
    let path = dir;
    let tried = if exclusive { file.try_lock() } else { file.try_lock_shared() };
    match tried {
        Ok(()) => {}
        Err(std::fs::TryLockError::WouldBlock) => {
            waiting();
            let r = if exclusive { file.lock() } else { file.lock_shared() };
            r.with_context(|| format!("{}: cannot lock", path.display()))?;
        }
        Err(std::fs::TryLockError::Error(e)) => {
            return Err(e).with_context(|| format!("{}: cannot lock", path.display()));
        }
    }
    Ok(DirLock { _dir: file })
}

/// The process id in a temporary file's name `.NAME.tmp-PID`, `.NAME.tmp-PID-N` or
/// `.NAME.old-PID`; None for any other name.
pub fn temp_file_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?;
    let (_, tail) = rest.rsplit_once(".tmp-").or_else(|| rest.rsplit_once(".old-"))?;
    let mut parts = tail.split('-');
    let pid = parts.next()?;
    let n = parts.next();
    if parts.next().is_some() || n.is_some_and(|n| n.is_empty() || !n.bytes().all(|b| b.is_ascii_digit())) {
        return None;
    }
    if pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pid.parse().ok()
}

/// Whether process `pid` is running. Where `/proc` is not mounted every process counts as
/// gone: the exclusive lock already keeps other probelab writers out.
fn process_alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    proc.join("self").exists() && proc.join(pid.to_string()).exists()
}

/// Deletes the temporary files killed runs left in `dir` and its subfolders (see the module
/// doc) whose process is gone, and returns them. Call it while holding the exclusive
/// [`lock`]. Symbolic links are not followed; nothing else is touched.
pub fn remove_stale(dir: &Path) -> Result<Vec<std::path::PathBuf>> {
    let mut removed = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(d) = pending.pop() {
        let (gone, subfolders) = remove_stale_here(&d)?;
        removed.extend(gone);
        pending.extend(subfolders);
    }
    removed.sort();
    Ok(removed)
}

/// [`remove_stale`] in `dir` alone (not its subfolders): for the folder of an output file that
/// no locked output folder holds (`probes --out`, `--save`, `merge --out`), so any folder
/// written into is cleaned, not only `results/`. Call it before the write.
pub fn remove_stale_in(dir: &Path) -> Result<Vec<std::path::PathBuf>> {
    let (mut removed, _) = remove_stale_here(dir)?;
    removed.sort();
    Ok(removed)
}

/// The stale temporary files removed from `dir`, and its subfolders (not followed).
fn remove_stale_here(d: &Path) -> Result<(Vec<PathBuf>, Vec<PathBuf>)> {
    let own = std::process::id();
    let (mut removed, mut subfolders) = (Vec::new(), Vec::new());
    let entries = match std::fs::read_dir(d) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok((removed, subfolders)),
        Err(e) => return Err(e).with_context(|| format!("{}: cannot list", d.display())),
    };
    for e in entries.flatten() {
        let Ok(kind) = e.file_type() else { continue };
        let path = e.path();
        if kind.is_dir() {
            subfolders.push(path);
        } else if kind.is_file() {
            let name = e.file_name();
            let Some(pid) = name.to_str().and_then(temp_file_pid) else { continue };
            if pid != own && !process_alive(pid) {
                std::fs::remove_file(&path)
                    .with_context(|| format!("{}: cannot remove a stale temporary file", path.display()))?;
                removed.push(path);
            }
        }
    }
    Ok((removed, subfolders))
}

/// A process id that is surely gone: a child that has been waited for (for the tests of the
/// removal of stale temporary files, here and in `io::atomic`).
#[cfg(test)]
pub(crate) fn pid_of_a_finished_process() -> u32 {
    let mut child = std::process::Command::new("true").spawn().expect("spawn `true`");
    let gone = child.id();
    child.wait().expect("wait for `true`");
    gone
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temp_file_names_give_their_pid() {
        assert_eq!(temp_file_pid(".table.csv.tmp-123"), Some(123));
        assert_eq!(temp_file_pid(".provenance.toml.old-77"), Some(77));
        assert_eq!(temp_file_pid(".gen_sky.tmp-9-2"), Some(9));
        for other in
            ["table.csv", ".table.csv", ".a.tmp-", ".a.tmp-x", ".a.tmp-1-", ".a.tmp-1-2-3", "a.tmp-1", ".a.old-1x"]
        {
            assert_eq!(temp_file_pid(other), None, "{other}");
        }
    }

    /// Leftovers of a process that is gone are removed, in subfolders too; this process's own
    /// and ordinary files stay.
    #[test]
    fn stale_temporary_files_are_removed() {
        let d = tempfile::tempdir().unwrap();
        let gone = pid_of_a_finished_process();
        let own = std::process::id();
        std::fs::create_dir(d.path().join("x")).unwrap();
        let stale =
            [format!("x/.table.csv.tmp-{gone}"), format!("x/.provenance.toml.old-{gone}"), format!(".a.tmp-{gone}-3")];
        let kept = [format!("x/.table.csv.tmp-{own}"), "x/table.csv".to_string(), ".a.tmp-zz".to_string()];
        for f in stale.iter().chain(&kept) {
            std::fs::write(d.path().join(f), b"x").unwrap();
        }
        let removed = remove_stale(d.path()).unwrap();
        let mut want: Vec<_> = stale.iter().map(|f| d.path().join(f)).collect();
        want.sort();
        assert_eq!(removed, want);
        for f in &kept {
            assert!(d.path().join(f).exists(), "{f}");
        }
    }

    /// In one folder alone: the leftovers of a process that is gone are removed and returned; a
    /// running process's temporary file and the subfolders stay.
    #[test]
    fn stale_temporary_files_beside_a_target_are_removed() {
        let d = tempfile::tempdir().unwrap();
        let gone = pid_of_a_finished_process();
        let mut alive = std::process::Command::new("sleep").arg("30").spawn().unwrap();
        let stale = [d.path().join(format!(".t.csv.tmp-{gone}")), d.path().join(format!(".u.csv.tmp-{gone}-7"))];
        let live = d.path().join(format!(".t.csv.tmp-{}", alive.id()));
        let below = d.path().join(format!("x/.t.csv.tmp-{gone}"));
        std::fs::create_dir(d.path().join("x")).unwrap();
        for f in stale.iter().chain([&live, &below]) {
            std::fs::write(f, b"x").unwrap();
        }
        let removed = remove_stale_in(d.path()).unwrap();
        let live_stays = live.exists();
        alive.kill().unwrap();
        alive.wait().unwrap();
        assert_eq!(removed, stale);
        assert!(stale.iter().all(|f| !f.exists()));
        assert!(live_stays, "a running writer's temporary file stays");
        assert!(below.exists(), "a subfolder is not this folder");
    }

    #[test]
    fn a_second_exclusive_lock_waits() {
        let d = tempfile::tempdir().unwrap();
        let held = lock(d.path(), true, || panic!("free")).unwrap();
        let shared_waited = std::sync::atomic::AtomicBool::new(false);
        std::thread::scope(|s| {
            let t =
                s.spawn(|| lock(d.path(), false, || shared_waited.store(true, std::sync::atomic::Ordering::SeqCst)));
            std::thread::sleep(std::time::Duration::from_millis(100));
            drop(held);
            t.join().unwrap().unwrap();
        });
        assert!(shared_waited.load(std::sync::atomic::Ordering::SeqCst));
        let a = lock(d.path(), false, || panic!("shared locks share")).unwrap();
        let _b = lock(d.path(), false, || panic!("shared locks share")).unwrap();
        drop(a);
    }
}
