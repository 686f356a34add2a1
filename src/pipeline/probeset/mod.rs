//! Probe sets at production scale: L2 SH radiance probes read from files or synthesised, scored
//! by any registered encoder in fixed-size chunks (memory does not grow with the set), with
//! mergeable statistics so a set can be split into shards on a batch engine.
//!
//! Shards (`shard`), probe files (`format`), the probe synthesiser (`synth`), the error of one
//! probe and the scoring of a set (`score`), the mergeable state file (`state`), and a whole
//! job as `probelab probes` declares it, and the merge of shards (`job`).
//!
//! What this layer may use: the layer table of ARCHITECTURE.md (checked by
//! `tests/architecture.rs`).

pub mod format;
pub mod job;
pub mod score;
pub mod shard;
pub mod state;
pub mod synth;
