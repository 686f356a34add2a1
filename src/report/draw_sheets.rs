//! The comparison sheets of every experiment whose maps are all on the search path: drawn (in
//! parallel per experiment), written as `sheet_<map>.png` (or, split into pages,
//! `sheet_<map>_p<k>.png`), and the stale ones removed.

use super::csvfile::CsvTable;
use super::folders::{remove_stale, Section};
use super::maps::MapUse;
use super::options::Options;
use super::{png, sheet};
use crate::io::profile;
use crate::io::progress::Progress;
use crate::pipeline::experiment::Experiment;
use anyhow::Result;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;

/// Draws the comparison sheets of every experiment whose maps are all found, removing its
/// stale ones: the number of sheets drawn and, per experiment drawn, its sheets' file names.
pub(super) fn draw_sheets(
    opts: &Options,
    sections: &[Section],
    maps: &BTreeMap<String, Option<MapUse>>,
) -> Result<(usize, BTreeMap<String, Vec<String>>)> {
    let drawable: Vec<&Section> = sections
        .iter()
        .filter(|s| s.exp.as_ref().is_some_and(|e| e.maps.iter().all(|m| maps.get(m).is_some_and(|u| u.is_some()))))
        .collect();
    let total: usize = drawable.iter().map(|s| s.exp.as_ref().map_or(0, |e| e.sheet_maps().len())).sum();
    let progress = Progress::new(total as u64, "sheets");
    let mut pictures = 0;
    let mut drawn_sheets: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for s in &drawable {
        // Cannot fail: `drawable` holds only the sections that have an experiment.
        let exp = s.exp.as_ref().expect("drawable sections are experiments");
        let dir = opts.out.join(&s.name);
        progress.message(s.name.clone());
        let names = experiment_sheets(opts, exp, &dir, &progress)?;
        pictures += names.len();
        remove_stale(&dir, "sheet_", &names)?;
        drawn_sheets.insert(s.name.clone(), names);
    }
    progress.finish();
    Ok((pictures, drawn_sheets))
}

/// Draws and writes the sheets of one experiment into `dir`, with the figures of its
/// `table.csv` when there is one; their file names, in the experiment's map order. Every sheet
/// shares one error scale: the high percentile of |relative error| over all their error
/// spheres ([`sheet::share_error_scale`]), so the sheets are composed first and drawn after.
pub(super) fn experiment_sheets(
    opts: &Options,
    exp: &Experiment,
    dir: &Path,
    progress: &Progress,
) -> Result<Vec<String>> {
    let table_path = dir.join("table.csv");
    let table = if table_path.is_file() { Some(CsvTable::read(&table_path)?) } else { None };
    // The sheets of one experiment are independent files: composed and drawn in parallel (each
    // one's pixels do not depend on the thread count), named in the experiment's map order.
    let mut sheets = exp
        .sheet_maps()
        .par_iter()
        .map(|m| -> Result<(String, sheet::Sheet)> {
            let map = {
                let _s = profile::span(opts.references.profile(), "report: decode");
                opts.search.load(m)?
            };
            let (sheet, _) = sheet::experiment_sheet(exp, &map, table.as_ref(), opts.sheet_scale, opts.references)?;
            Ok((m.clone(), sheet))
        })
        .collect::<Result<Vec<_>>>()?;
    sheet::share_error_scale(sheets.iter_mut().map(|(_, s)| s));
    // Each sheet as its pages (one, when it fits), each page its own file.
    let pages: Vec<(String, sheet::Sheet)> = sheets
        .iter()
        .flat_map(|(m, s)| {
            let pages = s.pages();
            let n = pages.len();
            pages.into_iter().enumerate().map(move |(i, p)| (sheet::page_file(m, i + 1, n), p))
        })
        .collect();
    pages
        .par_iter()
        .map(|(name, sheet)| -> Result<String> {
            let image = {
                let _s = profile::span(opts.references.profile(), "report: draw");
                sheet.draw()?
            };
            {
                let _s = profile::span(opts.references.profile(), "report: PNG encode");
                png::write_png(&dir.join(name), &image)?;
            }
            progress.log(format!("wrote {}", dir.join(name).display()));
            progress.inc();
            Ok(name.clone())
        })
        .collect::<Result<Vec<String>>>()
}
