//! The identity rule (docs/maps.md, `envmap::identity`) on real files: the peer tool's
//! `Data/Probes/*.hdr` have the pixels of our `.exr` copies and of the known table, and every
//! map the committed experiments and claims name is committed or one of the peer's probes. The
//! rule through the binary (`check`, aliases, `maps import`) is `tests/map_identity.rs`.

use super::repository::repo;
use crate::envmap::{identity, known, load};
#[path = "../../tests/common/peer_probes.rs"]
mod peer_probes;

use peer_probes::{peer_dir, shared_file, PEER};

/// Each `.hdr` has the pixel sha256 of the `.exr` it was decoded into, and that of the known
/// table; the files themselves differ.
#[test]
#[cfg_attr(
    not(shared_maps),
    ignore = "needs PROBELAB_ENVMAPS with the paper probes (Probulator's Data/Probes/*.hdr and the shared .exr copies)"
)]
fn peer_hdr_files_have_the_pixels_of_our_exr_copies() {
    let dir = peer_dir();
    for (hdr, name) in PEER {
        let h = load::load(&dir.join(format!("{hdr}.hdr"))).unwrap();
        let e = load::load(&shared_file(&format!("{name}.exr"))).unwrap();
        assert_ne!(h.sha256, e.sha256, "{hdr}: the same file?");
        assert_eq!(identity::pixel_sha256(&h), identity::pixel_sha256(&e), "{hdr}.hdr against {name}.exr");
        assert_eq!(identity::pixel_sha256(&e), known::by_name(name).unwrap().pixel_sha256, "{name}");
    }
}

/// Every map an experiment, a claims map set or the claims measurements name is committed in `envmaps/` or is one of
/// the peer's five probes, so that `check --all` can pass on a clone plus Probulator's
/// `Data/Probes` alone. Runs everywhere: it reads only the committed files.
#[test]
fn every_experiment_map_is_committed_or_in_the_peer_folder() {
    let root = repo();
    let committed =
        |name: &str| ["exr", "hdr"].iter().any(|x| root.join("envmaps").join(format!("{name}.{x}")).is_file());
    let peer = |name: &str| PEER.iter().any(|(_, n)| *n == name);
    let mut seen = 0;
    for file in crate::pipeline::experiment::list_experiments(&root.join("experiments")).unwrap() {
        let exp = crate::pipeline::experiment::Experiment::load(&file).unwrap();
        for m in &exp.maps {
            assert!(
                committed(m) || peer(m),
                "{}: map {m} is neither in envmaps/ nor in Probulator's Data/Probes",
                file.display()
            );
            seen += 1;
        }
    }
    for e in std::fs::read_dir(root.join("experiments/claims")).unwrap() {
        let file = e.unwrap().path();
        if file.extension().is_none_or(|x| x != "toml") {
            continue;
        }
        let doc: toml::Table = std::fs::read_to_string(&file).unwrap().parse().unwrap();
        let mut sets = doc.get("map_sets").and_then(|s| s.as_table()).cloned().unwrap_or_default();
        // The maps the measurements run on are a set too.
        if let Some(maps) = doc.get("measurements").and_then(|m| m.get("maps")) {
            sets.insert("measurements".into(), maps.clone());
        }
        for (set, maps) in &sets {
            for m in maps.as_array().unwrap() {
                let m = m.as_str().unwrap();
                assert!(
                    committed(m) || peer(m),
                    "{}: map set {set}: {m} is neither in envmaps/ nor in Data/Probes",
                    file.display()
                );
                seen += 1;
            }
        }
    }
    assert!(seen > 50, "only {seen} map names read: the experiment files were not found");
}
