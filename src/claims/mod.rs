//! The claims layer: where the papers' claims are measured. The ZH3 talk's claims (`zh3`)
//! and the lightmap study of the 2018 brief and the hemispherical-lighting talk (`lightmap`:
//! Fig. 2 in closed form, the blending study).
//!
//! May use: `math`, `envmap`, `reference`, `encoders`, `pipeline`. Never `report`.

pub mod lightmap;
pub mod zh3;
