//! The claims layer: the papers' claims, measured and judged by one engine. The claims are
//! data (`experiments/claims/<paper>.toml`, parsed by `declaration`); `judge` decides each
//! one's verdict by its primary check on its evidence (experiment tables and the measurements
//! here), in the words its evidence kind allows, aggregating ratios per map (`ratios`), maps
//! and constructed scenes apart (`population`);
//! `verdicts` writes `results/CLAIMS.csv` and the per-paper evidence pages (`page`). The measurements
//! are what no table row holds yet: the ZH3 talk's (`zh3`) and the lightmap papers'
//! (`lightmap`: Fig. 2 in closed form, the blending study), written as `measure` tables.
//!
//! What this layer may use: the layer table of ARCHITECTURE.md (checked by
//! `tests/architecture.rs`).

pub mod declaration;
pub mod judge;
pub mod lightmap;
pub mod measure;
pub mod page;
pub mod population;
pub mod ratios;
pub mod verdicts;
pub mod zh3;
