//! The peer tool's five paper probes as the shared maps hold them: their `.hdr` names beside
//! our map names, and where to find them on `PROBELAB_ENVMAPS`. Plain `std` code, shared by
//! the binary's tests (`tests/map_identity.rs`) and the crate's (`src/tests/map_identity.rs`,
//! which includes this file by path: an integration test cannot import a unit-test module).

use std::path::PathBuf;

pub const PEER: [(&str, &str); 5] = [
    ("ennis", "ennis_256x128"),
    ("grace", "grace_256x128"),
    ("pisa", "pisa_256x128"),
    ("uffizi", "uffizi_256x128"),
    ("wells", "wells_probulator"),
];

/// The folders of `PROBELAB_ENVMAPS`.
pub fn shared_dirs() -> Vec<PathBuf> {
    let v = std::env::var_os("PROBELAB_ENVMAPS").unwrap_or_default();
    std::env::split_paths(&v).filter(|p| !p.as_os_str().is_empty()).collect()
}

/// The folder holding the peer's five `.hdr` probes: a `PROBELAB_ENVMAPS` folder, or its
/// `probulator_hdr/` (the layout of the shared maps). Panics when there is none: the test runs
/// because the shared maps were declared present.
pub fn peer_dir() -> PathBuf {
    shared_dirs()
        .into_iter()
        .flat_map(|d| [d.clone(), d.join("probulator_hdr")])
        .find(|d| PEER.iter().all(|(h, _)| d.join(format!("{h}.hdr")).is_file()))
        .expect("PROBELAB_ENVMAPS names no folder holding Probulator's ennis/grace/pisa/uffizi/wells.hdr")
}

/// A map file of the shared folders.
pub fn shared_file(name: &str) -> PathBuf {
    shared_dirs().into_iter().map(|d| d.join(name)).find(|p| p.is_file()).unwrap_or_else(|| panic!("{name} missing"))
}
