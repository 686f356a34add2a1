//! What the integration tests share: the harness (`harness.rs`: the binary, CSV rows, scratch
//! repositories, snapshots), the shared maps (`shared_maps.rs`) and the peer's probes among them
//! (`peer_probes.rs`). The encoder tests, which
//! need the library's internals, live inside the crate with their helpers (`src/tests/`).
#![allow(dead_code, unused_imports)] // each test binary uses a different part

pub mod harness;
pub mod hdr_files;
pub mod peer_probes;
pub mod shared_maps;
