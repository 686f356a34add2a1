//! The regression layer: guarding the committed numbers. Tables as text and the cell-by-cell
//! comparison (`baseline`), per-column tolerances (`tolerance`), the provenance written beside
//! each table (`provenance`); `check` and what it finds (`check`, `finding`), `bless`, the guard
//! that keeps a run off a moved baseline (`guard`), the maps a check could not find, each said
//! once (`missing`), and the claims under regression (`claims`).
//!
//! What this layer may use: the layer table of ARCHITECTURE.md (checked by
//! `tests/architecture.rs`).

pub mod baseline;
pub mod bless;
pub mod check;
pub mod claims;
pub mod finding;
pub mod guard;
pub mod missing;
pub mod provenance;
pub mod tolerance;
