//! Progress reporting, through a small trait. Long work in the library (a run's maps, a sweep,
//! the claims' measurements, the report's sheets, a probe set's chunks) opens a [`Progress`]
//! and reports steps on it; it never draws anything itself. What the steps become is the
//! installed [`Sink`]'s business: the binary installs one that draws nested terminal bars when
//! stderr is a terminal; with none installed (the library used alone, the tests) progress
//! costs a branch and shows nothing.
//!
//! The pattern is the `log` crate's: a process-wide sink set once by whoever owns the
//! terminal, so no signature in the library carries a progress argument.

use std::sync::OnceLock;

/// Where progress goes: the binary's terminal bars, or a test's recorder.
pub trait Sink: Send + Sync {
    /// A task of `len` steps (`None`: of unknown length, counted as it goes), labelled `what`.
    fn start(&self, len: Option<u64>, what: &str) -> Box<dyn Task>;

    /// Runs `f`, which writes to stderr, so that its lines land above whatever is drawn.
    fn suspend(&self, f: &mut dyn FnMut());
}

/// One task's progress, as a [`Sink`] shows it.
pub trait Task: Send + Sync {
    /// What is being worked on now.
    fn message(&self, msg: &str);
    /// `n` more steps done.
    fn advance(&self, n: u64);
    /// A line worth showing while the task runs (dropped where nothing is drawn).
    fn log(&self, line: &str);
    /// The task is over: remove it from the display.
    fn finish(&self);
}

static SINK: OnceLock<Box<dyn Sink>> = OnceLock::new();

/// Installs the process's progress sink; returns false (and keeps the first) if one was
/// already installed.
pub fn install(sink: Box<dyn Sink>) -> bool {
    SINK.set(sink).is_ok()
}

/// Runs `f` (a write to stderr) with the installed sink's display out of the way; just `f`
/// when there is none.
pub fn suspend(mut f: impl FnMut()) {
    match SINK.get() {
        Some(s) => s.suspend(&mut f),
        None => f(),
    }
}

/// A task's progress handle: reports go to the installed [`Sink`], or nowhere. Finished when
/// dropped.
pub struct Progress(Option<Box<dyn Task>>);

impl Progress {
    /// A task over `len` steps, labelled `what`.
    pub fn new(len: u64, what: &str) -> Self {
        Progress(SINK.get().map(|s| s.start(Some(len), what)))
    }

    /// A task of unknown length (a CSV probe file is not counted before it is read).
    pub fn counter(what: &str) -> Self {
        Progress(SINK.get().map(|s| s.start(None, what)))
    }

    /// What is being worked on now.
    pub fn message(&self, msg: impl Into<String>) {
        if let Some(t) = &self.0 {
            t.message(&msg.into());
        }
    }

    /// One step done.
    pub fn inc(&self) {
        self.inc_by(1);
    }

    /// `n` steps done.
    pub fn inc_by(&self, n: u64) {
        if let Some(t) = &self.0 {
            t.advance(n);
        }
    }

    /// A line worth showing while the task runs (what was written, say).
    pub fn log(&self, line: impl AsRef<str>) {
        if let Some(t) = &self.0 {
            t.log(line.as_ref());
        }
    }

    /// The task is over.
    pub fn finish(&self) {
        if let Some(t) = &self.0 {
            t.finish();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}
