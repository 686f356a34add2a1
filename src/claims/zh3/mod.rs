//! The ZH3 talk's measurements that no experiment table row holds: zonal lights against SH3
//! (Z1), the chroma error of per-channel axes (Z2), the solved axis on a constructed scene
//! (Z3), mismatched axis weights per channel (Z4), the Geomerics moments (Z5), blending (Z9) and
//! the serialised quantised sizes (Z10). Z6–Z8 are
//! judged on the `zh3_table` experiment; the claims themselves, their criteria and verdicts
//! are data (`experiments/claims/zh3.toml`) judged by the one engine (`claims::judge`).
//!
//! Unless a table's `about` says otherwise the figure is the **exact** metric: E/π over the
//! **sphere**, **solid-angle** weighted, on the 256×128 lat-long grid of normals, against the
//! exact cell-integrated reference of the map (2 GL nodes per row piece). Constructed scenes
//! use their closed-form irradiance and SH instead.
//!
//! The folder, by concern: what is measured and how (`cases`: the grid, the maps and scenes,
//! scoring), then the measurements by topic — the zonal axis (`axis`: Z1–Z4; `fringe`: Z2's fringe and axis divergence), Geomerics
//! (`geomerics`: Z5), blending (`blending`: Z9) and quantisation (`quantisation`: Z10).

mod axis;
mod blending;
mod cases;
mod declared;
mod fringe;
mod geomerics;
mod quantisation;
mod run;

pub use declared::maps;
pub use run::measure;
