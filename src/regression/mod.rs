//! The regression layer: guarding the committed numbers. Tables as text and the cell-by-cell
//! comparison (`baseline`), per-column tolerances (`tolerance`), the provenance written beside
//! each table (`provenance`), and the `check`/`bless` commands with the guard that keeps a run
//! off a moved baseline (`check`), and the maps a check could not find, each said once
//! (`missing`).
//!
//! What this layer may use: the layer table of ARCHITECTURE.md (checked by
//! `tests/architecture.rs`).

pub mod baseline;
pub mod check;
pub mod claims;
pub mod missing;
pub mod provenance;
pub mod tolerance;
