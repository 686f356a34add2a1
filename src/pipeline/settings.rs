//! How a run is carried out beyond what its experiment declares, handed down by whoever runs
//! it (the command line's `--no-timing` and `--profile`): whether the timing pass runs
//! ([`crate::pipeline::timing`]), and the profile its phases are timed on
//! ([`crate::io::profile`]). Nothing of it is kept process-wide.

use crate::io::profile::{self, Profile, Span};

/// The settings of a run.
#[derive(Clone, Copy)]
pub struct RunSettings<'p> {
    /// Whether the timing pass fills the `fit_ns` and `eval_ns` columns (`--no-timing`: not).
    pub timing: bool,
    /// Where the run's phases are timed (`--profile`), if anywhere.
    pub profile: Option<&'p Profile>,
}

impl Default for RunSettings<'_> {
    /// Timing on, no profile: what a run is without options.
    fn default() -> Self {
        RunSettings { timing: true, profile: None }
    }
}

impl<'p> RunSettings<'p> {
    /// Starts timing phase `name` on the run's profile (a no-op without one).
    pub fn span(&self, name: &'static str) -> Span<'p> {
        profile::span(self.profile, name)
    }

    /// The same settings without the timing pass (work whose tables carry no timing columns).
    pub fn untimed(self) -> Self {
        RunSettings { timing: false, ..self }
    }
}
