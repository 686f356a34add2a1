//! The crate's cross-layer tests: checks that need the internals of several layers at once (an
//! encoder against the exact reference on a generated map, a baseline comparison on a table
//! built in memory), which no public item shows. They were integration tests under `tests/`;
//! the library's public surface is small and deliberate, so they live here, compiled only for
//! `cargo test` (`#[cfg(test)]` in `lib.rs`). Tests that run the binary stay under `tests/` and
//! use the public surface alone. Each file names the concept it checks.

mod band_scale_check;
mod claim_ids;
mod common;
mod effects_cost;
mod encoder_hard_cases;
mod encoder_properties;
mod envmap_load;
mod hard_case_catalogue;
mod hdr_exposure;
mod lightmap_exact_cases;
mod map_identity;
mod peer_hbasis;
mod reference_closed_forms;
mod reference_oracle;
mod repository;
mod run_estimates;
mod surface_encoders;
mod table_values;
mod tilted_light_bound;
mod toml_nesting;
