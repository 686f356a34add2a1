//! The claims as data: one declaration file per paper, `experiments/claims/<paper>.toml`,
//! parsed and validated here. Every claim of the papers (`CLAIMS.md` of the paper texts) is
//! declared once, with the paper's statement and figure, its evidence kind (which decides the
//! verdict words it may get), the criterion and when it was fixed, the one primary check that
//! decides the verdict and the context checks shown under it. Judging is
//! [`crate::claims::judge`]; nothing in Rust writes a verdict.
//!
//! | key (top level)  | type   | meaning |
//! |------------------|--------|---------|
//! | `title`, `authors`, `venue` | string | the paper, as cited in the report |
//! | `order`          | integer | the paper's place in the report (ZH3 talk 1, hemispherical talk 2, 2018 brief 3) |
//! | `[map_sets]`     | table of string lists | named map sets a check may be judged on besides `all` (e.g. `paper` = the five paper probes) |
//! | `[measurements]` | table  | optional: `maps` = the maps the paper's claims measurements run on, in the order of their tables' rows (non-empty, each once) |
//! | `[[claim]]`      | tables | the claims, in report order |
//!
//! | key (`[[claim]]`) | type | meaning |
//! |-------------------|------|---------|
//! | `id`              | string | the claim id of CLAIMS.md (`Z6`, `H3`, `D1`) |
//! | `says`            | string | what the paper says, in a phrase (≤ 110 characters) |
//! | `statement`       | string | the claim in full (optional; defaults to `says`) |
//! | `paper_figure`    | string | the paper's own figure for it, as text (≤ 110 characters, like `says`: the report never cuts a cell) |
//! | `kind`            | string | the evidence kind ([`Kind`]): `identity` (true by derivation or construction: `holds (identity)` or `fails`), `measured` (a general statement over maps or scenes: `holds`, `partly`, `fails`), `example` (stated for one case: `reproduced` or `not reproduced`), `anchor` (the paper's figure comes from a population we do not have: `not comparable`) |
//! | `criterion`       | string | when it counts as holding, in words that mirror the paper's; for an `anchor`, why it is not comparable |
//! | `quote`           | string | the paper's sentence, verbatim, hedges included (fragments joined by " … ") |
//! | `threshold_from`  | string | where the primary's threshold comes from: `paper: <words of the quote that state the number>`, `direction` (a word decides only its direction: a ratio against 1, a sign), `rounding` (an identity) or `none` (an anchor); see `threshold.rs` for the rule, and the quantifier rule the quote sets |
//! | `fixed`           | string | when the criterion was fixed: `before data`, or `after data: <reason>` |
//! | `differs`         | string | why our figure and the paper's may differ (population, metric, maps, resolution), for the page's "What we found" |
//! | `figure`          | table or list | optional: `image` (a `.png` under `results/`, plain names), `caption` (what to look at) and, for a figure `claims` draws itself, `sheet = { experiment, map, encoders }` (that experiment's comparison sheet on one map, only those encoders, written as `claims/<name>.png`): the figures of ours beside the paragraph, for a claim whose paper evidence is an image |
//! | `[[claim.check]]` | tables | the checks: exactly one with `role = "primary"`, which alone decides the verdict; the others are context, shown under it |
//!
//! | key (`[[claim.check]]`) | type | meaning |
//! |-------------------------|------|---------|
//! | `name`      | string | what the check shows, in a phrase |
//! | `table`     | string | the evidence: an experiment name (its `results/<name>/table.csv`) or `measure:<name>` (`results/claims/measures/<name>.csv`, written by a claims measurement) |
//! | `where`     | table  | only rows whose text columns equal these values (a value may be a list of allowed values) |
//! | `encoder`   | string | the rows judged (the `encoder` column) |
//! | `baseline`  | string | for ratio tests: the rows compared with, matched on the key columns (`map`, `domain`, `effects`, `metric`, `case` where present) |
//! | `column`    | string | the numeric column judged (default `rmse`) |
//! | `test`      | string | `ratio_every` (every matched ratio < `below`), `ratio_some` (at least one ratio < `below`), `ratio_stat` (the statistic of the per-map ratios in [`min`, `max`]), `ratio_summary` (the per-map ratios summarised, no criterion: an anchor's figure or context), `every_at_most` / `every_at_least` (every value against `bound`), `every_equal` (every value exactly `bound`), `equal` (every pair agrees within `tolerance` relative to max(\|a\|, \|b\|), or within `abs_tolerance`) |
//! | `below`     | number | the ratio threshold of `ratio_every`/`ratio_some` (default 1) |
//! | `per_map`   | bool   | `ratio_every`/`ratio_some`: judge each map's ratio (the geometric mean of its rows' ratios) instead of each row (default false) |
//! | `statistic` | string | `ratio_stat`: `median` or `geomean` of the per-map ratios (a map's ratio: the geometric mean of its rows' ratios). Never a ratio of pooled means. |
//! | `min`, `max`| number | `ratio_stat`: the band (either may be omitted) |
//! | `bound`     | number | `every_at_most` / `every_at_least` / `every_equal` |
//! | `tolerance`, `abs_tolerance` | number | `equal` (defaults 1e-9, 1e-12) |
//! | `floor`     | number | ratio tests: rows whose baseline value is below this are excluded and counted (default 0: only an exactly zero baseline) |
//! | `on`        | list   | the map sets judged: `all` and/or names of `[map_sets]` (default `["all"]`; a set absent from the table makes the check untestable on it) |
//! | `maps`      | list   | only rows of these maps (within every set) |
//! | `role`      | string | `primary` (exactly one per claim: decides the verdict) or `context` (default: shown under it, never changes it) |
//! | `beside`    | bool   | a context check whose headline stands beside the verdict in `CLAIMS.csv` and the report (e.g. a cost the verdict does not count; default false) |

//!
//! The files: `kind.rs` (the evidence kinds), `paper.rs` (`Paper`, `ClaimDecl`), `check.rs`
//! (`CheckDecl` and its `Test`), `figure.rs` (a claim's figures), `file.rs` (the keys as
//! written), `parse.rs` (one file),
//! `validate_check.rs` (one check), `load.rs` (every file of a repository).

mod check;
mod figure;
mod file;
mod kind;
mod load;
mod paper;
pub(crate) mod parse;
mod threshold;
mod validate_check;

pub use check::{CheckDecl, Source, Statistic, Test};
pub use figure::SheetCrop;
pub use kind::{Kind, UNTESTABLE};
pub use load::{load_papers, DIR};
pub use paper::{ClaimDecl, Paper};
pub use threshold::ThresholdFrom;

#[cfg(test)]
mod tests;
