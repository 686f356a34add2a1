//! Experiment files: TOML in `experiments/` declaring maps, encoders, domain, effects and
//! metrics. An experiment is data; the runner (`runner.rs`) is the only code that executes it.
//!
//! | key            | type                      | default        | meaning |
//! |----------------|---------------------------|----------------|---------|
//! | `name`         | string                    | file stem      | results go to `results/<name>/` |
//! | `description`  | string                    | ""             | shown in the report |
//! | `maps`         | list of strings                  | required       | map names on the search path, or file paths |
//! | `encoders`     | list of strings or tables         | required       | `"sh2"` or `{ kind = "…", name = "…", <settings> }` |
//! | `metrics`      | list of strings                  | `["exact"]`    | `exact`, `probulator` |
//! | `domain`       | string                    | `"sphere"`     | `sphere` or `hemisphere` (n′ over the hemisphere about each N) |
//! | `orientations` | list of strings                  | `[]`           | surface normals N: `+x` … `-z`, `up`, `axes6`, `fibonacciN` |
//! | `effects`      | list of strings or tables         | `[]`           | `"hemisphere"`, `{ kind = "cone", cos_alpha = [..], tilt_deg = [..] }`, `{ kind = "self_bounce", albedo = [..] }` (needs `hemisphere`) |
//! | `resolution`   | [W, H]                    | `[256, 128]`   | output lat-long grid of normals for the `exact` metric |
//! | `polar_nodes`  | integer                   | 2              | Gauss–Legendre nodes per row piece of the reference |
//! | `ci`           | bool                      | true           | whether the CI check re-runs it |
//! | `summary`      | table                     | none           | `summary.csv` per orientation/map/set, ratios to `baseline` (`summary.rs`) |
//! | `sheets`       | list of strings           | every map      | the maps that get a comparison sheet in the report (each one of `maps`) |
//!
//! Unknown keys are errors that name the key and the line.
//!
//! The files: `file.rs` (the keys as written), `model.rs` (the validated experiment),
//! `read.rs` (reading a file, errors with their line), `validate.rs` and `effect.rs` (the
//! checks), `lines.rs` (where an error is), `toml_file.rs` (any TOML file of the project),
//! `catalog.rs` (finding experiment files), `resolution.rs` (`WxH`).

mod catalog;
mod effect;
mod file;
mod lines;
mod model;
mod read;
mod resolution;
mod toml_file;
mod validate;

pub use catalog::{list_experiments, resolve, NOT_A_CHECKOUT};
pub use file::ExperimentFile;
pub use model::{DomainKind, Effect, Experiment};
pub use resolution::parse_resolution;
pub use toml_file::parse_toml;
