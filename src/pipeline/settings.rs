//! How a run is carried out beyond what its experiment declares, handed down by whoever runs
//! it (the command line's `--no-timing` and `--profile`, the Python package's Ctrl-C): whether
//! the timing pass runs ([`crate::pipeline::timing`]), the profile its phases are timed on
//! ([`crate::io::profile`]), and the [`Cancel`] it checks between chunks of work. Nothing of it
//! is kept process-wide.

use crate::io::profile::{self, Profile, Span};
use std::sync::atomic::{AtomicBool, Ordering};

/// A request to stop, set by whoever runs the work (the Python package, when Ctrl-C arrives)
/// from another thread, and read by the work between chunks: the reference's input rows, the
/// cases of a map, the timing pass. Work that sees it stops early and leaves values that mean
/// nothing; the workflow that was handed it then fails with [`Cancelled`] instead of returning
/// them. The library never sets it.
#[derive(Debug, Default)]
pub struct Cancel(AtomicBool);

impl Cancel {
    /// Asks the work to stop.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether the work was asked to stop.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// The error of work stopped by its [`Cancel`].
#[derive(Debug, thiserror::Error)]
#[error("cancelled")]
pub struct Cancelled;

/// The settings of a run.
#[derive(Clone, Copy)]
pub struct RunSettings<'p> {
    /// Whether the timing pass fills the `fit_ns` and `eval_ns` columns (`--no-timing`: not).
    pub timing: bool,
    /// Where the run's phases are timed (`--profile`), if anywhere.
    pub profile: Option<&'p Profile>,
    /// Checked between chunks of work, if given (the command line gives none: its Ctrl-C ends
    /// the process).
    pub cancel: Option<&'p Cancel>,
}

impl Default for RunSettings<'_> {
    /// Timing on, no profile: what a run is without options.
    fn default() -> Self {
        RunSettings { timing: true, profile: None, cancel: None }
    }
}

impl<'p> RunSettings<'p> {
    /// Starts timing phase `name` on the run's profile (a no-op without one).
    pub fn span(&self, name: &'static str) -> Span<'p> {
        profile::span(self.profile, name)
    }

    /// Whether the run was asked to stop.
    pub fn cancelled(&self) -> bool {
        self.cancel.is_some_and(Cancel::is_cancelled)
    }

    /// [`Cancelled`] when the run was asked to stop: what a workflow checks before returning
    /// values that work stopped early may have left meaningless.
    pub fn check_cancelled(&self) -> Result<(), Cancelled> {
        if self.cancelled() {
            Err(Cancelled)
        } else {
            Ok(())
        }
    }

    /// The same settings without the timing pass (work whose tables carry no timing columns).
    pub fn untimed(self) -> Self {
        RunSettings { timing: false, ..self }
    }
}
