//! The experiments' maps: which experiments name each, each as found on the search path now
//! (file and sha256), and the maps found in another file than the one their tables record.

use super::folders::Section;
use super::options::Options;
use super::provenance_page::RunRecord;
use crate::envmap::search::SearchPath;
use anyhow::Result;
use std::collections::BTreeMap;

/// One map file as found now (what the sheets are drawn from; compared with the records).
#[derive(Clone, Debug)]
pub(super) struct MapUse {
    file: String,
    sha256: String,
}

/// Every map the experiments name, with the experiments that name it (committed data only).
pub(super) fn named_maps(sections: &[Section]) -> BTreeMap<String, Vec<String>> {
    let mut named: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for s in sections {
        for m in s.exp.iter().flat_map(|e| &e.maps) {
            named.entry(m.clone()).or_default().push(s.name.clone());
        }
    }
    named
}

/// The maps found here in another file than the one a table was computed from, one sentence
/// each (the file's sha256 differs; `check` says whether the pixels are the same).
pub(super) fn mismatches(maps: &BTreeMap<String, Option<MapUse>>, records: &[RunRecord]) -> Vec<String> {
    let mut out = Vec::new();
    for (section, pr) in records {
        for r in &pr.maps {
            if let Some(Some(u)) = maps.get(&r.name) {
                if u.sha256 != r.sha256 {
                    out.push(format!(
                        "{section}: its table used a map {} with another file sha256 than {}",
                        r.name, u.file
                    ));
                }
            }
        }
    }
    out
}

/// Every map an experiment names, resolved on the search path and checksummed (`None` when it
/// is not found).
pub(super) fn map_uses(opts: &Options, sections: &[Section]) -> BTreeMap<String, Option<MapUse>> {
    let mut maps: BTreeMap<String, Option<MapUse>> = BTreeMap::new();
    for m in sections.iter().flat_map(|s| s.exp.iter().flat_map(|e| &e.maps)) {
        maps.entry(m.clone()).or_insert_with(|| map_use(opts.search, m).ok());
    }
    maps
}

pub(super) fn map_use(search: &SearchPath, name: &str) -> Result<MapUse> {
    let map = search.load(name)?;
    let path = map.path.clone().unwrap_or_default();
    Ok(MapUse {
        file: path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default(),
        sha256: map.sha256.clone().unwrap_or_default(),
    })
}
