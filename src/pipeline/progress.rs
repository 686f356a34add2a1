//! Progress and logging. On a terminal: indicatif bars (cleared when done) and a plain log of
//! what was written; on a pipe or CI (`CI` set): no bars and a quiet log (only summaries and
//! warnings). Bars nest: one opened while another is running (a run's maps inside
//! `reproduce`'s experiments) is drawn below it, through one shared [`MultiProgress`].

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::OnceLock;
use std::time::Duration;

/// The one set of bars every [`Progress`] joins, so nested bars stack instead of overwriting
/// each other.
fn bars() -> &'static MultiProgress {
    static BARS: OnceLock<MultiProgress> = OnceLock::new();
    BARS.get_or_init(|| MultiProgress::with_draw_target(ProgressDrawTarget::stderr()))
}

/// Runs `f` (a write to stderr) with the bars hidden, so its lines land above them; just `f`
/// when no bar is drawn.
pub fn suspend<R>(f: impl FnOnce() -> R) -> R {
    if interactive() {
        bars().suspend(f)
    } else {
        f()
    }
}

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
    /// A bar over `len` steps, labelled `what`.
    pub fn new(len: u64, what: &str) -> Self {
        Self::with(Some(len), what, "{spinner} {prefix} [{bar:30}] {pos}/{len} {msg} ({elapsed})")
    }

    /// A counter for work of unknown length (a CSV probe file is not counted before it is
    /// read): steps done, rate and time so far.
    pub fn counter(what: &str) -> Self {
        Self::with(None, what, "{spinner} {prefix} {human_pos} {msg} ({per_sec}, {elapsed})")
    }

    fn with(len: Option<u64>, what: &str, template: &str) -> Self {
        let interactive = interactive();
        let bar = if interactive {
            bars().add(ProgressBar::with_draw_target(len, ProgressDrawTarget::hidden()))
        } else {
            ProgressBar::with_draw_target(len, ProgressDrawTarget::hidden())
        };
        bar.set_style(
            ProgressStyle::with_template(template)
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

    /// One step done.
    pub fn inc(&self) {
        self.bar.inc(1);
    }

    /// `n` steps done.
    pub fn inc_by(&self, n: u64) {
        self.bar.inc(n);
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
        if self.interactive {
            bars().remove(&self.bar);
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}
