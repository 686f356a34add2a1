//! The crate's cross-layer tests: checks that need the internals of several layers at once (an
//! encoder against the exact reference on a generated map, a baseline comparison on a table
//! built in memory), which no public item shows. They were integration tests under `tests/`;
//! the library's public surface is small and deliberate, so they live here, compiled only for
//! `cargo test` (`#[cfg(test)]` in `lib.rs`). Tests that run the binary stay under `tests/` and
//! use the public surface alone. Each file names the concept it checks.

mod common;
mod encoder_hard_cases;
mod encoder_properties;
mod lightmap_exact_cases;
mod peer_hbasis;
mod reference_closed_forms;
mod reference_oracle;
mod shared_maps;
mod surface_encoders;
mod tilted_light_bound;
