//! The command line, owned by the binary: one file per subcommand, each holding that command's
//! clap arguments, the one `ops` workflow it calls, what it prints and its exit code. `cli`
//! holds the global options and the dispatch; `context` the exit code of a refused baseline; `args` the arguments that name files;
//! `terminal` and `output` the streams and bars.
//!
//! Exit codes: 0 done, 1 a check or a baseline guard failed (something moved), 2 an error
//! (bad input, a file that cannot be read or written), 141 stdout's reader went away.

// clap prints the argument docs as --help, where <root>, <name> and <out> are placeholders.
#![allow(rustdoc::invalid_html_tags)]

mod args;
mod bless;
mod check;
mod claims;
mod cli;
mod context;
mod encoders;
mod eval;
mod fit;
mod fit_hallucination;
mod gen_envmaps;
mod maps;
mod merge;
pub mod output;
mod probes;
mod report;
mod reproduce;
mod run;
mod sweep;
mod terminal;
mod view;

pub use cli::{main_with, Cli};
