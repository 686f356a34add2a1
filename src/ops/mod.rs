//! The workflows, one per command, for every front end alike: the `probelab` binary
//! (`src/commands/`) and the Python package (`bindings/python/`) call these functions, so the
//! two print the same rows, the same coefficients and the same refusals. Each workflow takes
//! an [`Env`] and its options and returns a typed outcome, rendered by functions beside it;
//! the binary decides the exit code. Messages name the command line's options (`--encoders`,
//! `--domain`, `--normal`), whose names the Python package's keyword arguments share. Layers:
//! `ARCHITECTURE.md`.

pub mod bless;
pub mod check;
pub mod claims;
pub mod context;
pub mod encoders;
pub mod eval;
pub mod fit;
pub mod fit_hallucination;
pub mod gen_envmaps;
pub mod json;
pub mod maps;
pub mod merge;
pub mod probes;
pub mod report;
pub mod reproduce;
pub mod run;
pub mod source;
pub mod sweep;
pub mod view;

pub use crate::encoders::DEFAULT_IDS as DEFAULT_ENCODERS;
pub use crate::envmap::load::in_guarded_decoder;
/// The map search path every workflow reads maps from (`<root>/envmaps`, then `PROBELAB_ENVMAPS`).
pub use crate::envmap::search::SearchPath;
pub use crate::io::profile::Profile;
pub use crate::pipeline::settings::{Cancel, Cancelled, RunSettings};
pub use context::{Env, Notes, Quiet};
pub use source::{MapSource, Texels};
