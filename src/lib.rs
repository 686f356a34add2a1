//! probelab: a research harness for compact diffuse-lighting encodings.
//! See ARCHITECTURE.md for the module map.

pub mod atomic;
pub mod baseline;
pub mod cap;
pub mod check;
pub mod cli;
pub mod domain;
pub mod encoder;
pub mod encoders;
pub mod envmap;
pub mod experiment;
pub mod gram;
pub mod hallucination_fit;
pub mod lightmap;
pub mod lightmap_claims;
pub mod metrics;
pub mod moments;
pub mod probeset;
pub mod profile;
pub mod progress;
pub mod projection;
pub mod provenance;
pub mod quadrature;
pub mod reference;
pub mod report;
pub mod runner;
pub mod scenes;
pub mod sh;
pub mod sh_rotation;
pub mod stats;
pub mod summary;
pub mod sweep;
pub mod table;
pub mod timing;
pub mod tolerance;
pub mod zh3_claims;
