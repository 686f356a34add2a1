//! probelab: a research harness for compact diffuse-lighting encodings (SH, ZH3, Geomerics,
//! AHD/HHD in IrradZ, HLSH, the ambient cube and dice, SGs, the H-basis), each measured against
//! an exact reference over real HDR maps.
//!
//! # The library
//!
//! The public surface is small: load a map ([`Map::load`]), choose where its light is seen
//! from ([`Surface`]), compute the exact reference E/π at any normals
//! ([`Lighting::reference`]), fit any registered encoder by id with its settings
//! ([`Lighting::fit`], ids from [`encoder_ids`]), evaluate the fit ([`Fit::irradiance`]), get
//! its stored coefficients with names, units and basis ([`Fit::stored`], a [`Stored`]), and
//! score it ([`Lighting::score`]).
//!
//! ```no_run
//! use probelab::{DVec3, Map, Surface};
//! # fn main() -> probelab::Result<()> {
//! let map = Map::load("blender_city_256x128", ".")?;
//! let light = map.lighting(Surface::Sphere)?;
//! let fit = light.fit("zh3_solved_shared", "")?;
//! // The stored coefficients: each with its name, role, unit and value.
//! let stored = fit.stored();
//! let names: Vec<&str> = stored.entries.iter().map(|e| e.name.as_str()).collect();
//! // E/π at +Y from the fit, and the exact reference there.
//! let (fitted, exact) = (fit.irradiance(DVec3::Y), light.reference(&[DVec3::Y])[0]);
//! let error = (fitted - exact).length();
//! # Ok(())
//! # }
//! ```
//!
//! Units and directions are `docs/conventions.md` §1 (E/π; world directions, +Y up); SH
//! coefficients follow its §2. `docs/library.md` is the guide; `examples/fit_map.rs` and
//! `examples/compare.rs` use only this surface.
//!
//! # The surface
//!
//! - [`api`] (its types re-exported here): maps, the exact reference, fitting and evaluating
//!   any encoder by id, stored coefficients, scores, an experiment from its text.
//! - [`ops`]: the workflows, one function per command (`eval`, `fit`, `run`, `check`,
//!   `bless`, `claims`, `report`, `reproduce`, `probes`, `merge`, `sweep`, `maps`, ...), each
//!   taking an [`ops::Env`] and an options struct and returning a typed outcome with its
//!   renderings. The binary and the Python package are thin layers over these.
//! - [`encoders`]: the `Encoder` trait and the registry, for people who add an encoding.
//! - [`progress`]: the trait through which long work reports its steps.
//!
//! Everything else is internal (crate-private). The library never prints: long work reports
//! through [`progress`], the rest is returned. Every public item is documented
//! (`deny(missing_docs)` below). The layers, what each may use, and the module map are in
//! `ARCHITECTURE.md`, which `tests/architecture.rs` checks against the code.

#![deny(missing_docs)]

pub mod api;
/// The one error type of the library: every fallible function returns [`Result`], whose error
/// names the file, key or encoder and what is wrong (`{:#}` prints the whole chain, as the
/// command line does). It is `anyhow`'s, re-exported so that a program need not depend on it.
pub use anyhow::{Error, Result};
pub use api::{
    encoder_ids, needs_surface_normal, unit_normal, Entry, Experiment, Fit, Lighting, Map, Rgb, Role, Row, Score,
    Scores, Stored, Surface, Unit, Value, DEFAULT_RESOLUTION,
};
pub use glam::DVec3;

/// docs/library.md, whose Rust examples `cargo test --doc` compiles and runs.
#[cfg(doctest)]
#[doc = include_str!("../docs/library.md")]
pub mod library_guide {}

/// The `Encoder` trait and the registry, for people who add an encoding.
pub mod encoders;
/// The workflows, one function per command (what the binary and the Python package run).
pub mod ops;
/// Progress reporting: the trait a front end implements to show long work (the binary draws
/// terminal bars).
pub use io::progress;

// The internal layers (ARCHITECTURE.md): crate-private; the binary, the Python package, the
// examples and the tests under `tests/` use the surface above.
pub(crate) mod claims;
pub(crate) mod envmap;
pub(crate) mod io;
pub(crate) mod math;
pub(crate) mod pipeline;
pub(crate) mod reference;
pub(crate) mod regression;
pub(crate) mod report;

#[cfg(feature = "bench")]
pub mod bench;
#[cfg(test)]
mod tests;
