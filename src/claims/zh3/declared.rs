//! The maps the ZH3 measurements run on, as the ZH3 talk's declaration names them
//! (`[measurements] maps` in `experiments/claims/zh3.toml`).

use crate::claims::declaration::Paper;
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
