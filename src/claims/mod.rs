//! The claims layer: where the papers' claims are measured. The ZH3 talk's claims (`zh3`),
//! the lightmap study of the 2018 brief and the hemispherical-lighting talk (`lightmap`:
//! Fig. 2 in closed form, the blending study), and the claims experiment files declare, judged
//! on their tables (`declared`: `claims.csv`, `CLAIMS.md` beside `table.csv`).
//!
//! May use: `math`, `envmap`, `reference`, `encoders`, `pipeline`. Never `report`.

pub mod declaration;
pub mod declared;
pub mod lightmap;
pub mod zh3;
