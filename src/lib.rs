//! probelab: a research harness for compact diffuse-lighting encodings (SH, ZH3, Geomerics,
//! AHD/HHD in IrradZ, HLSH), each measured against an exact reference over real HDR maps.
//!
//! The crate is layered; each folder's `mod.rs` says what its layer is and what it may use,
//! and `ARCHITECTURE.md` holds the table that `tests/architecture.rs` checks every
//! `use crate::` line against. From the bottom up:
//!
//! | layer | what |
//! |---|---|
//! | [`math`] | SH basis and rotation, Gram matrices, quadrature, caps and arcs, the direction convention, exact statistics |
//! | [`envmap`] | lat-long maps, loading, the search path, row moments |
//! | [`reference`](mod@reference) | the exact reference, SH projection, analytic lighting and scenes, output domains and views, metrics |
//! | [`encoders`] | the `Encoder` trait, the registry, one file (or folder) per family |
//! | [`pipeline`] | experiments, the runner, timing, tables, summaries, sweeps, probe sets |
//! | [`claims`] | where the papers' claims are measured |
//! | [`regression`] | check, bless, baselines, provenance, tolerances |
//! | [`report`] | pictures, charts and `results/REPORT.md` |
//! | [`cli`] | the `probelab` command line |

pub mod claims;
pub mod cli;
pub mod encoders;
pub mod envmap;
pub mod math;
pub mod pipeline;
pub mod reference;
pub mod regression;
pub mod report;
