//! probelab: a research harness for compact diffuse-lighting encodings.
//! See ARCHITECTURE.md for the module map.

pub mod atomic;
pub mod cap;
pub mod cli;
pub mod domain;
pub mod encoder;
pub mod encoders;
pub mod envmap;
pub mod experiment;
pub mod hallucination_fit;
pub mod metrics;
pub mod moments;
pub mod projection;
pub mod quadrature;
pub mod reference;
pub mod runner;
pub mod scenes;
pub mod sh;
pub mod table;
pub mod zh3_claims;
