//! The identity rule (docs/maps.md) on real files: the peer tool's `Data/Probes/*.hdr` are the
//! maps our `.exr` copies hold (same pixel sha256), `check` of the experiments on those five
//! probes passes from the `.hdr` files alone, a wrong file under a known map's alias is passed
//! over with the reason, and `maps import` remakes the shared `_256x128` maps exactly.

mod common;

use common::harness::{repo, Run};
use common::peer_probes::{peer_dir, shared_file, PEER};
use std::path::Path;

/// Maps read from the peer's `.hdr` files: with only the peer's folder on the search path, `check` of the
/// two experiments that use exactly the five probes passes, reading every map from a `.hdr`.
#[test]
#[cfg_attr(not(shared_maps), ignore = "needs PROBELAB_ENVMAPS with the paper probes (Probulator's Data/Probes/*.hdr)")]
fn check_passes_on_the_peer_hdr_files_alone() {
    let out = common::harness::probelab()
        .args(["--no-timing", "check", "--require-all-maps", "sh_baseline", "probulator_parity"])
        .env("PROBELAB_ENVMAPS", peer_dir())
        .run();
    let (so, se) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "{so}{se}");
    for exp in ["sh_baseline", "probulator_parity"] {
        assert!(so.contains(&format!("{exp}: ok, nothing moved")), "{so}");
        for (hdr, name) in PEER {
            assert!(so.contains(&format!("{exp}: map {name} read from ")), "{so}");
            assert!(so.contains(&format!("{hdr}.hdr, not the baseline's file but the same pixels")), "{so}");
        }
    }
}

/// A file under a known map's alias with other pixels is not taken: here a CC0 map copied to
/// `wells.exr` (the loader reads content, not extensions), asked for as `wells_probulator`.
#[test]
fn a_wrong_file_under_an_alias_is_passed_over_with_the_reason() {
    let t = tempfile::tempdir().unwrap();
    std::fs::copy(repo().join("envmaps/blender_city_256x128.exr"), t.path().join("wells.exr")).unwrap();
    let out = common::harness::probelab()
        .args(["eval", "wells_probulator", "--encoders", "sh1"])
        .env("PROBELAB_ENVMAPS", t.path())
        .run();
    let se = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{se}");
    assert!(se.contains("wells_probulator"), "{se}");
    assert!(se.contains("not taken:") && se.contains("wells.exr"), "{se}");
    assert!(se.contains("its pixels are the known map blender_city_256x128, not wells_probulator"), "{se}");
    // check names the map, why it is missing (once, on stderr), and fails when every map is required.
    let out = common::harness::probelab()
        .args(["--no-timing", "check", "--require-all-maps", "sh_baseline"])
        .env("PROBELAB_ENVMAPS", t.path())
        .run();
    let (so, se) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert_eq!(out.status.code(), Some(1), "{so}");
    assert!(so.contains("sh_baseline: map wells_probulator not found on this machine"), "{so}");
    assert!(se.contains("  wells_probulator (read by 1 experiment(s)): not taken: "), "{se}");
}

/// `maps import` of a 1000x500 and a 1024x512 source remakes the shared 256x128 maps pixel for
/// pixel, naming them through the known table.
#[test]
#[cfg_attr(
    not(shared_maps),
    ignore = "needs PROBELAB_ENVMAPS with the shared maps (wells.exr 1000x500, blender_city.exr 1024x512)"
)]
fn import_remakes_the_shared_256x128_maps() {
    let t = tempfile::tempdir().unwrap();
    let out_dir = t.path().join("out");
    let out = common::harness::probelab()
        .arg("maps")
        .arg("import")
        .arg(shared_file("wells.exr"))
        .arg(shared_file("blender_city.exr"))
        .arg("--out")
        .arg(&out_dir)
        .run();
    let so = common::harness::stdout_ok(&out);
    for (name, want) in [
        ("wells_256x128", shared_file("wells_256x128.exr")),
        ("blender_city_256x128", repo().join("envmaps/blender_city_256x128.exr")),
    ] {
        let load = |p: &Path| probelab::Map::load(p.to_str().unwrap(), repo()).unwrap();
        let (made, want) = (load(&out_dir.join(format!("{name}.exr"))), load(&want));
        // The same size and the same halves: the same pixel sha256.
        assert_eq!(made.size(), want.size(), "{name}");
        assert_eq!(made.texels(), want.texels(), "{name}: the halves themselves");
        assert!(so.contains(&format!("known map {name}")), "{so}");
    }
    // The peer's folder: the five probes under the experiments' names, as they are.
    let out = common::harness::probelab().arg("maps").arg("import").arg(peer_dir()).arg("--out").arg(&out_dir).run();
    let so = common::harness::stdout_ok(&out);
    for (_, name) in PEER {
        assert!(Path::new(&out_dir.join(format!("{name}.exr"))).is_file(), "{so}");
        assert!(so.contains(&format!("known map {name}")), "{so}");
    }
}
