//! What the command line's `eval` and `fit` compute, for every front end alike: the `probelab`
//! binary (`src/commands/`) and the Python package (`bindings/python/`) call these functions,
//! so the two print the same rows, the same coefficients and the same refusals. Messages name
//! the command line's options (`--encoders`, `--domain`, `--normal`), whose names the Python
//! package's keyword arguments share. Layers: `ARCHITECTURE.md`.

pub mod bless;
pub mod check;
pub mod claims;
pub mod context;
pub mod eval;
pub mod fit;
pub mod json;
pub mod report;
pub mod reproduce;
pub mod run;

pub use context::{Env, Notes, Quiet};
