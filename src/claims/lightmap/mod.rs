//! The lightmap papers' measurements that no experiment table holds (`../shared/papers/CLAIMS.md`;
//! hemispherical-lighting talk 2024, directional-lightmap brief 2018), as measurement tables
//! that the declarations judge ([`measure`]):
//!
//! - **H7**, Fig. 2 of the brief in closed form (`fig2.rs`, tables in `fig2_tables.rs`): `fig2`
//!   (per tilt α and rule, the overshoot of I(N) beyond both endpoints) and `fig2_curve` (I(N)
//!   along t);
//! - **H5** and the real pairs of **H7**, the blending study (`blend.rs`, tables in
//!   `blend_tables.rs`): `blend` (per pair and method, RMSE against the blended reference and the
//!   overshoot at N) and `blend_curve` (the same along t, the blending charts' data);
//! - **H6**, the HHD ↔ linear-SH round trip (`roundtrip.rs`): `hhd_roundtrip`;
//! - **H8**, the light the probe occlusion operators let through from occluded directions
//!   (`leak.rs`): `probe_leak`, on the cases of `experiments/probe_occlusion.toml`;
//! - **H10**, the self-bounce term against a quadrature of the map's texels (`bounce.rs`):
//!   `self_bounce_quadrature`, on the cases of `experiments/lightmap_self_bounce.toml`.
//!
//! H1, H2, H4, H10, D1 and D2 are judged on experiment tables too (`lightmap_claims`,
//! `lightmap_table`, `lightmap_self_bounce`). `study.rs` measures them all at once. The blending strips (`strip.rs`), lit hemispheres
//! along t per method, are measured here as data and drawn by the report layer.
//!
//! Blending figures are E/π, the solid-angle RMSE over the hemisphere about N on 128×32
//! normals (the upper half of a 128×64 lat-long grid), against the exact occluded reference
//! (2 GL nodes per row piece), blended linearly. Fits go through the encoder registry's specs
//! (`blend.rs`). The timing pass is switched off: the tables are deterministic.

pub mod blend;
mod blend_tables;
pub mod bounce;
pub mod fig2;
mod fig2_tables;
pub mod leak;
mod roundtrip;
pub mod strip;
mod study;

pub use study::measure;
