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
//! scoring), then the measurements by topic — the zonal axis (`axis`: Z1–Z4), Geomerics
//! (`geomerics`: Z5), blending (`blending`: Z9) and quantisation (`quantisation`: Z10).

mod axis;
mod blending;
mod cases;
mod geomerics;
mod quantisation;

use crate::claims::declaration::Paper;
use crate::claims::measure::Measure;
use crate::envmap::search::SearchPath;
use anyhow::{bail, Result};

/// The paper whose declaration (`experiments/claims/zh3.toml`) names the maps these
/// measurements run on.
pub const PAPER: &str = "zh3";

/// The maps the ZH3 measurements run on, in the order of their tables' rows: the
/// `[measurements] maps` of the ZH3 talk's declaration (the five paper probes, then every usable
/// map of the search path's collection, at 256×128). An error when the declaration is absent or
/// names none.
pub fn maps(papers: &[Paper]) -> Result<&[String]> {
    match papers.iter().find(|p| p.key == PAPER) {
        Some(p) if !p.measurement_maps.is_empty() => Ok(&p.measurement_maps),
        Some(_) => bail!("experiments/claims/{PAPER}.toml names no [measurements] maps for the ZH3 measurements"),
        None => bail!("no experiments/claims/{PAPER}.toml: the maps of the ZH3 measurements are not declared"),
    }
}

/// The maps a measurement ran on: (name, sha256 and reference description).
pub type MapsUsed = Vec<(String, String)>;

/// Runs every ZH3 measurement on those of `maps` (in order; see [`maps`]) that the search path
/// has; returns the tables and the maps used.
pub fn measure(search: &SearchPath, maps: &[String]) -> Result<(Vec<Measure>, MapsUsed)> {
    let progress = crate::io::progress::Progress::new(8, "claims: ZH3 measurements");
    let grid = cases::grid();
    let (cases, maps) = cases::probes(search, &grid, maps)?;
    progress.inc();
    type Step<'a> = (&'static str, Box<dyn Fn() -> Result<Measure> + 'a>);
    let steps: Vec<Step> = vec![
        ("Z1", Box::new(|| axis::z1(&grid))),
        ("Z2", Box::new(|| axis::z2(&grid, &cases))),
        ("Z3", Box::new(|| axis::z3(&grid, &cases))),
        ("Z4", Box::new(|| axis::z4(&grid, &cases))),
        ("Z5", Box::new(|| geomerics::z5(&grid, &cases))),
        ("blending", Box::new(|| blending::zh3_blend(&grid))),
        ("quantisation", Box::new(|| quantisation::quantised_sizes(&grid, &cases))),
    ];
    let mut out = Vec::new();
    for (what, step) in steps {
        progress.message(what);
        out.push(step()?);
        progress.inc();
    }
    Ok((out, maps))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Z1 needs no maps. ZH3 of a zonal light is its SH3 (a zonal function's band-2 part is a
    /// multiple of the zonal harmonic about its axis), so every stored ZH3 must agree with SH3
    /// to rounding on every zonal light.
    #[test]
    fn zonal_lights_agree_with_sh3() {
        let grid = cases::grid();
        let m = axis::z1(&grid).unwrap();
        assert_eq!(m.rows.len(), 16);
        for r in &m.rows {
            let crate::claims::measure::Cell::Num(field) = r[2] else { panic!("a number") };
            assert!(field < 1e-9, "{r:?}");
        }
    }
}
