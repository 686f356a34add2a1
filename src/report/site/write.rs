//! The site run: every experiment map found on the search path gets its data recomputed; a map
//! this machine lacks keeps its committed data file (the paper probes are never in a fresh
//! clone); then the index, the claims (with each claim's figure and explorer preset from its
//! declaration), the landscape and the pages. A file whose bytes would
//! not change is not rewritten, so a regeneration with unchanged data touches nothing.

use super::assets::ASSETS;
use super::claims_data::claims_data;
use super::claims_evidence::claims_evidence;
use super::encode::script;
use super::index_data::index_data;
use super::landscape_data::landscape_data;
use super::map_data::map_data;
use crate::encoders::NamedEncoder;
use crate::report::csvfile::CsvTable;
use crate::report::folders::Section;
use crate::report::maps::MapUse;
use crate::report::names::{file_safe, CLAIMS_CSV};
use crate::report::options::Options;
use anyhow::{Context, Result};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The site's folder under the results folder.
pub(crate) const SITE_DIR: &str = "site";

/// What the site run did: files rewritten, and the maps whose committed data were kept.
#[derive(Clone, Debug, Default)]
pub(crate) struct SiteWritten {
    /// Files whose bytes changed (or were new).
    pub(crate) rewritten: usize,
    /// Maps absent here whose committed data file was kept.
    pub(crate) kept: Vec<String>,
}

/// Writes `results/site/` (see the module doc).
pub(crate) fn write_site(
    opts: &Options,
    sections: &[Section],
    maps: &BTreeMap<String, Option<MapUse>>,
) -> Result<SiteWritten> {
    let site = opts.out.join(SITE_DIR);
    let data_dir = site.join("data");
    std::fs::create_dir_all(&data_dir).with_context(|| format!("{}: cannot create folder", data_dir.display()))?;
    let shown = encoders_by_map(sections);
    let outcomes: Vec<(String, bool, bool)> = shown
        .par_iter()
        .map(|(m, encoders)| -> Result<(String, bool, bool)> {
            let path = data_dir.join(map_file(m));
            if maps.get(m).is_some_and(|u| u.is_some()) {
                let map = opts.search.load(m)?;
                let value = map_data(&map, encoders)?;
                let changed = write_if_changed(&path, script("PROBELAB_MAPS", Some(m), &value).as_bytes())?;
                Ok((m.to_string(), true, changed))
            } else {
                Ok((m.to_string(), path.is_file(), false))
            }
        })
        .collect::<Result<_>>()?;
    let mut written = SiteWritten::default();
    let mut listed = Vec::new();
    for (m, present, changed) in outcomes {
        written.rewritten += usize::from(changed);
        if present {
            listed.push(m.clone());
        }
        if present && maps.get(&m).is_none_or(|u| u.is_none()) {
            written.kept.push(m);
        }
    }
    let names: Vec<String> = shown.values().flatten().map(|e| e.name.clone()).collect();
    let mut names_once = Vec::new();
    for n in names {
        if !names_once.contains(&n) {
            names_once.push(n);
        }
    }
    let papers = crate::claims::declaration::load_papers(&opts.root.join("experiments"))?;
    let experiment_maps: BTreeMap<String, Vec<String>> =
        sections.iter().filter_map(|s| s.exp.as_ref()).map(|e| (e.name.clone(), e.maps.clone())).collect();
    let exists = |rel: &str| opts.out.join(rel).is_file();
    let evidence = claims_evidence(&papers, &shown, &experiment_maps, &listed, &exists);
    let mut files: Vec<(PathBuf, String)> = vec![
        (data_dir.join("index.js"), script("PROBELAB_INDEX", None, &index_data(&listed, &names_once))),
        (
            data_dir.join("claims.js"),
            script("PROBELAB_CLAIMS", None, &claims_data(read_claims(opts.out)?.as_ref(), evidence)),
        ),
        (
            data_dir.join("landscape.js"),
            script("PROBELAB_LANDSCAPE", None, &landscape_data(&landscape_tables(opts.out)?)),
        ),
    ];
    files.extend(ASSETS.iter().map(|(name, text)| (site.join(name), text.to_string())));
    for (path, text) in files {
        written.rewritten += usize::from(write_if_changed(&path, text.as_bytes())?);
    }
    Ok(written)
}

/// A map's data file name: `map_<name>.js`.
pub(crate) fn map_file(map: &str) -> String {
    format!("map_{}.js", file_safe(map))
}

/// Per map of the experiments (by name), the encoders its tables show, each name once, in the
/// experiments' order.
fn encoders_by_map(sections: &[Section]) -> BTreeMap<String, Vec<&NamedEncoder>> {
    let mut out: BTreeMap<String, Vec<&NamedEncoder>> = BTreeMap::new();
    for e in sections.iter().filter_map(|s| s.exp.as_ref()) {
        for m in &e.maps {
            let list = out.entry(m.clone()).or_default();
            for enc in &e.encoders {
                if !list.iter().any(|x| x.name == enc.name) {
                    list.push(enc);
                }
            }
        }
    }
    out
}

/// CLAIMS.csv, when the claims engine has written it.
fn read_claims(out: &Path) -> Result<Option<CsvTable>> {
    let p = out.join(CLAIMS_CSV);
    Ok(if p.is_file() { Some(CsvTable::read(&p)?) } else { None })
}

/// The landscape tables: `table.csv` of the results folders `landscape` (sphere) and
/// `landscape_hemi` (hemispheres), when present.
fn landscape_tables(out: &Path) -> Result<Vec<(String, CsvTable)>> {
    let mut v = Vec::new();
    for name in ["landscape", "landscape_hemi"] {
        let p = out.join(name).join("table.csv");
        if p.is_file() {
            v.push((name.to_string(), CsvTable::read(&p)?));
        }
    }
    Ok(v)
}

/// Writes `bytes` to `path` atomically unless the file already holds exactly them: whether it
/// wrote.
fn write_if_changed(path: &Path, bytes: &[u8]) -> Result<bool> {
    if std::fs::read(path).is_ok_and(|old| old == bytes) {
        return Ok(false);
    }
    crate::io::atomic::write(path, bytes)?;
    Ok(true)
}
