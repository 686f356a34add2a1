//! The terminal, which only the binary touches: `outln!` (stdout, errors returned), `noteln!`
//! (stderr, errors ignored), the progress bars the library's progress is drawn as, and the
//! `--profile` report at the end.
//!
//! On a terminal (stderr is one, and `CI` is not set) progress is drawn as nested indicatif
//! bars, cleared when done, with notes printed above them; elsewhere (a pipe, CI) no bar is
//! installed and the log stays quiet.

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use probelab::progress::{Sink, Task};
use std::io::IsTerminal;
use std::time::Duration;

/// `println!` that returns `Result<(), StdoutError>` instead of panicking.
macro_rules! outln {
    ($($arg:tt)*) => {
        crate::commands::output::write_fmt(format_args!("{}\n", format_args!($($arg)*)))
    };
}
pub(crate) use outln;

/// `eprintln!` that ignores a failing stderr instead of panicking, printed above the bars.
macro_rules! noteln {
    ($($arg:tt)*) => {
        crate::commands::output::note_fmt(format_args!("{}\n", format_args!($($arg)*)))
    };
}
pub(crate) use noteln;

/// Prints `text` (lines already ending in newlines) to stderr, above the bars.
pub fn note(text: &str) {
    if !text.is_empty() {
        crate::commands::output::note_fmt(format_args!("{text}"));
    }
}

/// The workflows' notes ([`probelab::ops::Notes`]), each a line on stderr above the bars.
pub struct Stderr;

impl probelab::ops::Notes for Stderr {
    fn note(&self, line: &str) {
        crate::commands::output::note_fmt(format_args!("{line}\n"));
    }
}

/// Whether stderr is an interactive terminal (and not CI).
fn interactive() -> bool {
    std::io::stderr().is_terminal() && std::env::var_os("CI").is_none()
}

/// Installs the terminal bars as the library's progress sink, when stderr is a terminal.
pub fn install_progress() {
    if interactive() {
        probelab::progress::install(Box::new(Bars(MultiProgress::with_draw_target(ProgressDrawTarget::stderr()))));
    }
}

/// Every task's bar, in one [`MultiProgress`] so nested bars (a run's maps inside `reproduce`'s
/// experiments) stack instead of overwriting each other.
struct Bars(MultiProgress);

/// One task's bar.
struct Bar {
    bar: ProgressBar,
    bars: MultiProgress,
}

impl Sink for Bars {
    fn start(&self, len: Option<u64>, what: &str) -> Box<dyn Task> {
        let template = match len {
            // The time left ({eta}) from the rate so far: long runs say when they will end.
            Some(_) => "{spinner} {prefix} [{bar:30}] {pos}/{len} {msg} ({elapsed}, {eta} left)",
            // Work of unknown length: steps done, rate and time so far.
            None => "{spinner} {prefix} {human_pos} {msg} ({per_sec}, {elapsed})",
        };
        let bar = self.0.add(ProgressBar::with_draw_target(len, ProgressDrawTarget::hidden()));
        bar.set_style(
            ProgressStyle::with_template(template)
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        bar.set_prefix(what.to_string());
        bar.enable_steady_tick(Duration::from_millis(120));
        Box::new(Bar { bar, bars: self.0.clone() })
    }

    fn suspend(&self, f: &mut dyn FnMut()) {
        self.0.suspend(f)
    }
}

impl Task for Bar {
    fn message(&self, msg: &str) {
        self.bar.set_message(msg.to_string());
    }

    fn advance(&self, n: u64) {
        self.bar.inc(n);
    }

    fn log(&self, line: &str) {
        self.bar.println(line);
    }

    fn finish(&self) {
        self.bar.finish_and_clear();
        self.bars.remove(&self.bar);
    }
}
