//! The pipeline layer: the order of work from an experiment file to a table. Experiment
//! files and their validation (`experiment`), the estimate of a run's time (`estimate`), the runner (`runner`: per map, per case, per
//! encoder, scoring; its cases and their data in `cases`), a run's settings (`settings`: timing on or off, the profile), the timing pass (`timing`), the references a workflow computes once (`reuse`), result rows and CSV (`table`), summaries
//! (`summary`), one-knob sweeps (`sweep`), probe sets at scale (`probeset`) and the ZH3
//! hallucination-curve fit (`hallucination_fit`).
//!
//! What this layer may use: the layer table of ARCHITECTURE.md (checked by
//! `tests/architecture.rs`).

pub mod cases;
pub mod estimate;
pub mod experiment;
pub mod hallucination_fit;
pub mod probeset;
pub mod reuse;
pub mod runner;
pub mod settings;
pub mod summary;
pub mod sweep;
pub mod table;
pub mod table_cells;
pub mod timing;
