//! The repository's files and maps for the crate's cross-layer tests: the package root, CSV
//! rows, and the shared maps (`PROBELAB_ENVMAPS`), as `tests/common/` gives the tests that run the binary.

use crate::envmap::search::SearchPath;
use std::collections::HashMap;
use std::path::PathBuf;

/// The repository (the package root).
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Rows of CSV text as (header → value) maps.
pub fn parse_csv(text: &str) -> Vec<HashMap<String, String>> {
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let h: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    r.records().map(|rec| h.iter().cloned().zip(rec.unwrap().iter().map(String::from)).collect()).collect()
}

/// The probes of the papers' tables (`experiments/sh_baseline.toml`, `zh3_table.toml`,
/// `probelab claims zh3`). The build script checks for the same five.
pub const PAPER_PROBES: [&str; 5] =
    ["ennis_256x128", "grace_256x128", "pisa_256x128", "uffizi_256x128", "wells_probulator"];

/// The value of `PROBELAB_ENVMAPS` after checking that its folders hold every map named (a test
/// that reads the shared maps carries `#[cfg_attr(not(shared_maps), ignore = "…")]`, so it runs
/// only when the variable was set at build time). Panics, saying what is missing and where it
/// looked, otherwise.
pub fn shared_envmaps(maps: &[&str]) -> String {
    let value = std::env::var("PROBELAB_ENVMAPS").unwrap_or_default();
    assert!(
        !value.is_empty(),
        "this test needs the shared maps (it runs because PROBELAB_ENVMAPS or CI was set when it was built): \
         set PROBELAB_ENVMAPS to the folder holding them"
    );
    let search = SearchPath::new(std::env::split_paths(&value).filter(|p| !p.as_os_str().is_empty()).collect());
    let missing: Vec<String> = maps.iter().filter_map(|m| search.resolve(m).err()).map(|e| e.to_string()).collect();
    assert!(missing.is_empty(), "PROBELAB_ENVMAPS is set but lacks maps this test needs:\n{}", missing.join("\n"));
    value
}
