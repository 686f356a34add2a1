//! What the integration tests share: the harness (`harness.rs`: the binary, CSV rows, scratch
//! repositories, snapshots) and the shared maps (`shared_maps.rs`). The encoder tests, which
//! need the library's internals, live inside the crate with their helpers (`src/tests/`).
#![allow(dead_code, unused_imports)] // each test binary uses a different part

pub mod harness;
pub mod shared_maps;
