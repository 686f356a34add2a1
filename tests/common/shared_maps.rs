//! The shared environment maps: the folders of `PROBELAB_ENVMAPS` (in CI `../shared/envmaps`),
//! which hold the papers' probes and the other real maps that cannot live in git.
//!
//! A test that reads them carries
//! `#[cfg_attr(not(shared_maps), ignore = "needs the paper probes (not CC0, not in the repository): set PROBELAB_ENVMAPS to a folder holding them, see envmaps/README.md")]`,
//! so without them cargo reports it as ignored. The build script sets `shared_maps` when the
//! variable (or `CI`) is set; the test then runs and asks [`shared_envmaps`] for the maps it
//! needs, which fails the test when one is missing: a set variable declares the maps present.

use probelab::ops::SearchPath;

/// The probes of the papers' tables (`experiments/sh_baseline.toml`, `zh3_table.toml`,
/// `probelab claims zh3`). The build script checks for the same five.
pub const PAPER_PROBES: [&str; 5] =
    ["ennis_256x128", "grace_256x128", "pisa_256x128", "uffizi_256x128", "wells_probulator"];

/// The value of `PROBELAB_ENVMAPS`, to pass on to the binary, after checking that its folders
/// hold every map named. Panics, saying what is missing and where it looked, otherwise.
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
