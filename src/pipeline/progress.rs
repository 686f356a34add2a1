//! Progress and logging. On a terminal: indicatif bars (cleared when done) and a plain log of
//! what was written; on a pipe or CI (`CI` set): no bars and a quiet log (only summaries and
//! warnings).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::Duration;

/// Whether stderr is an interactive terminal (and not CI).
pub fn interactive() -> bool {
    std::io::stderr().is_terminal() && std::env::var_os("CI").is_none()
}

/// A progress bar over `len` steps; hidden unless [`interactive`].
pub struct Progress {
    bar: ProgressBar,
    interactive: bool,
}

impl Progress {
    pub fn new(len: u64, what: &str) -> Self {
        let interactive = interactive();
        let bar = ProgressBar::with_draw_target(
            Some(len),
            if interactive { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() },
        );
        bar.set_style(
            ProgressStyle::with_template("{spinner} {prefix} [{bar:30}] {pos}/{len} {msg} ({elapsed})")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        bar.set_prefix(what.to_string());
        if interactive {
            bar.enable_steady_tick(Duration::from_millis(120));
        }
        Progress { bar, interactive }
    }

    /// What is being worked on now.
    pub fn message(&self, msg: impl Into<String>) {
        self.bar.set_message(msg.into());
    }

    pub fn inc(&self) {
        self.bar.inc(1);
    }

    /// A log line: printed above the bar on a terminal, dropped in the quiet log.
    pub fn log(&self, line: impl AsRef<str>) {
        if self.interactive {
            self.bar.println(line.as_ref());
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}
