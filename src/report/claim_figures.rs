//! The figures `probelab claims` draws for the claims pages (`results/claims/<paper>.md`):
//! each claim's sheet cut down to what it is about (the comparison sheet of one experiment on
//! one map with only the claim's encoders, composed by [`sheet::experiment_sheet`] as every
//! sheet is), and the blending study's RMSE along t per pair (claim H5, drawn by
//! [`charts::blend_charts`] from the committed `claims/measures/blend_curve.csv`).

use super::csvfile::CsvTable;
use super::names::file_safe;
use super::{charts, png, sheet};
use crate::claims::declaration::{load_papers, SheetCrop};
use crate::envmap::search::SearchPath;
use crate::pipeline::experiment::Experiment;
use crate::pipeline::reuse::ReferenceCache;
use anyhow::{anyhow, Context, Result};
use std::path::Path;

/// The claims' sheets (of the declarations under `root`'s `experiments/`), as (path under the
/// results folder, PNG bytes), in the declarations' order, their references kept in and read
/// from `cache`. A sheet whose map is not on the search path is not drawn (its committed picture
/// stands, like any figure of a map this machine lacks).
pub fn claim_sheets(
    root: &Path,
    search: &SearchPath,
    results: &Path,
    cache: &ReferenceCache,
) -> Result<Vec<(String, Vec<u8>)>> {
    let papers = load_papers(&root.join("experiments"))?;
    let mut out = Vec::new();
    for f in papers.iter().flat_map(|p| &p.claims).flat_map(|c| &c.figures) {
        let Some(crop) = &f.sheet else { continue };
        if search.resolve(&crop.map).is_err() {
            continue;
        }
        let bytes = draw_crop(root, search, results, crop, cache).with_context(|| format!("figure {}", f.image))?;
        out.push((f.image.clone(), bytes));
    }
    Ok(out)
}

/// One cut-down sheet: the experiment with only the crop's encoders, in the crop's order, on
/// its map, with the figures of the experiment's committed table when it has them.
fn draw_crop(
    root: &Path,
    search: &SearchPath,
    results: &Path,
    crop: &SheetCrop,
    cache: &ReferenceCache,
) -> Result<Vec<u8>> {
    let mut exp = Experiment::load(&root.join("experiments").join(format!("{}.toml", crop.experiment)))?;
    let mut kept = Vec::new();
    for name in &crop.encoders {
        let i = exp
            .encoders
            .iter()
            .position(|e| e.name == *name)
            .ok_or_else(|| anyhow!("experiment {} has no encoder '{name}'", crop.experiment))?;
        kept.push(exp.encoders.remove(i));
    }
    exp.encoders = kept;
    let table_path = results.join(&crop.experiment).join("table.csv");
    let table = if table_path.is_file() { Some(CsvTable::read(&table_path)?) } else { None };
    let map = search.load(&crop.map)?;
    let (sheet, _) = sheet::experiment_sheet(&exp, &map, table.as_ref(), 1, cache)?;
    png::png_bytes(&sheet.draw()?)
}

/// The blending study's charts from `claims/measures/blend_curve.csv` under `results`, one
/// per pair (E/π at N and the RMSE along t, each method in its style), as
/// (`claims/blend_chart_<pair>.png`, PNG bytes); none when the table is not there.
pub fn blend_charts(results: &Path) -> Result<Vec<(String, Vec<u8>)>> {
    let path = results.join("claims").join("measures").join("blend_curve.csv");
    if !path.is_file() {
        return Ok(vec![]);
    }
    let t = CsvTable::read(&path)?;
    let mut out = Vec::new();
    for (pair, o) in charts::blend_charts(&t)? {
        if let charts::Outcome::Drawn { image, .. } = o {
            out.push((format!("claims/blend_chart_{}.png", file_safe(&pair)), png::png_bytes(&image)?));
        }
    }
    Ok(out)
}
