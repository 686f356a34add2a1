//! The standard output and standard error, for the binary (the library never prints). Command
//! code never uses `println!` or `eprintln!`, which panic (exit 101) when the stream fails: it
//! writes through the binary's `outln!` or [`write()`], whose errors are returned, and its
//! `noteln!` ([`note_fmt`]), which ignores them.
//!
//! - stdout fails because its reader went away (a closed pipe, `| head`): the error is a
//!   [`StdoutError`] and the command ends quietly with exit [`BROKEN_PIPE_EXIT`] (141, what a
//!   shell reports for a process ended by SIGPIPE, so `set -o pipefail` sees an incomplete run).
//! - stdout fails otherwise (`> /dev/full`): `error: cannot write to standard output: …`, exit 2.
//! - stdout was closed when the process started (`>&-`): the same, exit 2. The Rust runtime
//!   puts `/dev/null` on a closed standard stream before `main`, so every write would succeed
//!   and the results vanish with exit 0; on Linux a function in `.init_array`, which runs
//!   before the runtime, notes whether descriptor 1 was open ([`stdout_closed`]).
//! - stderr fails: the notes are lost, nothing else changes (there is nowhere to report it);
//!   the exit code still tells.
//!
//! Commands that write files print only before their first write or after their last
//! (`bless`, `gen-envmaps`), so a failing stdout never stops them half way.

use std::fmt;
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

/// Whether descriptor 1 was closed when the process started (set before `main`).
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// Run by the C runtime before Rust's (which would open `/dev/null` on a closed descriptor 1).
#[cfg(target_os = "linux")]
#[used]
#[link_section = ".init_array"]
static NOTE_CLOSED_STDOUT: extern "C" fn() = note_closed_stdout;

/// Notes whether descriptor 1 is closed: `/proc/self/fd` lists the open descriptors (when
/// `/proc` is not mounted nothing is noted).
#[cfg(target_os = "linux")]
extern "C" fn note_closed_stdout() {
    let fds = std::path::Path::new("/proc/self/fd");
    if fds.is_dir() && std::fs::symlink_metadata(fds.join("1")).is_err() {
        STDOUT_CLOSED.store(true, Ordering::Relaxed);
    }
}

/// Whether standard output was closed when the process started (`>&-`; noted on Linux only).
pub fn stdout_closed() -> bool {
    STDOUT_CLOSED.load(Ordering::Relaxed)
}

/// The error every write to a standard output closed at start gives.
pub fn closed_stdout_error() -> StdoutError {
    StdoutError(std::io::Error::other("it was closed when probelab started (>&-); the output would be lost"))
}

/// The exit code of a command whose stdout reader went away (128 + SIGPIPE).
pub const BROKEN_PIPE_EXIT: i32 = 141;

/// Standard output could not be written.
#[derive(Debug)]
pub struct StdoutError(pub std::io::Error);

impl StdoutError {
    /// True when the reader went away (a closed pipe), rather than a write error.
    pub fn is_broken_pipe(&self) -> bool {
        self.0.kind() == std::io::ErrorKind::BrokenPipe
    }
}

impl fmt::Display for StdoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "cannot write to standard output: {}", self.0)
    }
}

impl std::error::Error for StdoutError {}

/// Writes `bytes` to stdout and flushes them.
pub fn write(bytes: &[u8]) -> Result<(), StdoutError> {
    if stdout_closed() {
        return Err(closed_stdout_error());
    }
    let mut out = std::io::stdout().lock();
    out.write_all(bytes).and_then(|()| out.flush()).map_err(StdoutError)
}

/// Writes formatted text to stdout and flushes it (what `outln!` calls).
pub fn write_fmt(args: fmt::Arguments) -> Result<(), StdoutError> {
    write(args.to_string().as_bytes())
}

/// Writes formatted text to stderr, ignoring any error (what `noteln!` calls); above the
/// progress bars, when they are drawn ([`probelab::progress::suspend`]).
pub fn note_fmt(args: fmt::Arguments) {
    probelab::progress::suspend(|| {
        let _ = std::io::stderr().lock().write_fmt(args);
    });
}

/// The exit code and message of a failed command: a [`StdoutError`] anywhere in the chain
/// from a broken pipe gives ([`BROKEN_PIPE_EXIT`], no message); anything else gives
/// (2, `error: …`).
pub fn failure(e: &anyhow::Error) -> (i32, Option<String>) {
    let pipe = e.chain().any(|c| c.downcast_ref::<StdoutError>().is_some_and(StdoutError::is_broken_pipe));
    if pipe {
        (BROKEN_PIPE_EXIT, None)
    } else {
        (2, Some(format!("error: {e:#}\n")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_broken_stdout_pipe_is_quiet() {
        let pipe = anyhow::Error::from(StdoutError(std::io::ErrorKind::BrokenPipe.into()));
        assert_eq!(failure(&pipe.context("check")), (BROKEN_PIPE_EXIT, None));
        let full = anyhow::Error::from(StdoutError(std::io::Error::from_raw_os_error(28)));
        let (code, msg) = failure(&full);
        assert_eq!(code, 2);
        assert!(msg.unwrap().starts_with("error: cannot write to standard output: "));
        // A broken pipe elsewhere (not stdout) is an ordinary error.
        let other = anyhow::Error::from(std::io::Error::from(std::io::ErrorKind::BrokenPipe));
        assert_eq!(failure(&other).0, 2);
    }
}
