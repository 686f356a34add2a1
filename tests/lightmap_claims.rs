//! The lightmap paper's claims measurements (with the ZH3 measurements `probelab claims` takes
//! beside them), end to end: from the shared maps, `probelab claims` writes the measurement
//! tables (H5–H8, H10, Z9, Z10 checked here) under `claims/measures/` and the blending strips
//! under `claims/`, each value checked against what it must be independently of the program.
//! Without the maps it takes no measurement. (The H2 bound of `experiments/lightmap_claims.toml`
//! is checked inside the crate: `src/tests/tilted_light_bound.rs`.)

mod common;

use common::harness::{parse_csv, probelab, repo, Run};
use common::shared_maps::shared_envmaps;
use std::path::Path;

/// The maps of the claims measurements, as `experiments/claims/zh3.toml` declares them
/// (`[measurements] maps`), in order.
fn measurement_maps() -> Vec<String> {
    let text = std::fs::read_to_string(repo().join("experiments/claims/zh3.toml")).unwrap();
    let file: toml::Table = toml::from_str(&text).unwrap();
    let maps = file["measurements"]["maps"].as_array().expect("[measurements] maps is a list");
    maps.iter().map(|m| m.as_str().expect("a map name").to_string()).collect()
}

/// The rows of `claims/measures/NAME.csv` under `dir`.
fn table(dir: &Path, name: &str) -> Vec<std::collections::HashMap<String, String>> {
    parse_csv(&std::fs::read_to_string(dir.join(format!("claims/measures/{name}.csv"))).unwrap())
}

fn num(r: &std::collections::HashMap<String, String>, col: &str) -> f64 {
    r[col].parse().unwrap_or_else(|_| panic!("{col}: {:?}", r[col]))
}

#[test]
#[cfg_attr(
    not(shared_maps),
    ignore = "needs the paper probes (not CC0, not in the repository): set PROBELAB_ENVMAPS to a folder holding them, see envmaps/README.md"
)]
fn claims_write_the_measurement_tables_and_strips() {
    let maps = measurement_maps();
    let env = shared_envmaps(&maps.iter().map(String::as_str).collect::<Vec<_>>());
    let dir = tempfile::tempdir().unwrap();
    let out = probelab().args(["claims", "--out", dir.path().to_str().unwrap()]).env("PROBELAB_ENVMAPS", env).run();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // Fig. 2: IrradZ is linear (no overshoot); at 60° the renormalised AHD peaks at 1/(2 sin α).
    let fig2 = table(dir.path(), "fig2");
    assert!(fig2.iter().filter(|r| r["encoder"] == "irradz").all(|r| num(r, "overshoot") == 0.0));
    let r = fig2.iter().find(|r| r["case"] == "alpha_60" && r["encoder"] == "ahd_renormalised").unwrap();
    let a = 60f64.to_radians();
    assert!((num(r, "overshoot") - (0.5 / a.sin() - a.cos())).abs() < 1e-12);
    // The blending study: five pairs × six methods, 11 values of t; IrradZ blends I_z linearly,
    // so I(N) never leaves the interval of its endpoints (luminance is linear too).
    let blend = table(dir.path(), "blend");
    assert_eq!(blend.len(), 30);
    for r in blend.iter().filter(|r| r["encoder"].ends_with("_irradz")) {
        assert!(num(r, "undershoot_rel") == 0.0 && num(r, "overshoot_rel") < 1e-12, "{r:?}");
    }
    assert_eq!(table(dir.path(), "blend_curve").len(), 30 * 11);
    // The HHD round trip is exact up to rounding.
    for r in table(dir.path(), "hhd_roundtrip") {
        assert!(num(&r, "max_error") < 1e-9, "{r:?}");
    }
    for pair in ["ennis_to_grace", "uffizi_to_pisa_wall", "grace_light_on", "wells_light_on_wall", "ennis_turned_180"] {
        assert!(dir.path().join(format!("claims/blend_strip_{pair}.png")).exists(), "{pair}");
    }
    let readme = std::fs::read_to_string(dir.path().join("claims/measures/README.md")).unwrap();
    assert!(readme.contains("`hhd_roundtrip.csv`"), "{readme}");
    // Z10: per map, the serialised sizes of the talk (13 / 13 / 16 / 28 bytes), each decoding to
    // exactly what its quantised encoder evaluates.
    let sizes = table(dir.path(), "quantised_sizes");
    assert_eq!(sizes.len(), 4 * maps.len());
    for r in &sizes {
        let want = match r["encoder"].as_str() {
            "sh1" | "zh3_hallucinate" => "13",
            "zh3_solved_shared" => "16",
            "sh2" => "28",
            e => panic!("unexpected encoder {e}"),
        };
        assert_eq!((r["bytes"].as_str(), r["roundtrip_max_abs"].as_str()), (want, "0"), "{r:?}");
    }
    // H8: an encoder fitted from the visible light alone (sh2_of_visible) lets nothing through
    // from occluded directions, by construction; a row per map, orientation (up and the +y of
    // axes6 once: 38) and encoder of probe_occlusion (8).
    let leak = table(dir.path(), "probe_leak");
    assert_eq!(leak.len(), maps.len() * 38 * 8);
    for r in leak.iter().filter(|r| r["encoder"] == "sh2_of_visible") {
        assert_eq!((num(r, "leak"), num(r, "leak_rms")), (0.0, 0.0), "{r:?}");
    }
    // H10: the reference's bounce and HHD's term agree with the texel quadrature of I_z to the
    // reference's polar quadrature (1e-6 where a horizon cuts the rows), on 19 maps × 6 axes × 3
    // albedos.
    let bounce = table(dir.path(), "self_bounce_quadrature");
    let exact: Vec<_> =
        bounce.iter().filter(|r| r["encoder"] == "reference" || r["encoder"] == "hhd_search_hemi+bounce").collect();
    assert_eq!(exact.len(), 2 * maps.len() * 6 * 3);
    for r in exact {
        assert!(num(r, "bounce_max_rel_err") < 1e-6 && num(r, "iz_rel_err") < 1e-6, "{r:?}");
    }
    // Z9: the blend's own zonal coefficient is ¼ of an endpoint's (P₂(cos 45°)).
    let blend = table(dir.path(), "zh3_blend");
    let own = blend.iter().find(|r| r["case"] == "deltas_x_y" && r["encoder"] == "sh3_blended").unwrap();
    assert!((num(own, "zonal_scale") - 0.25).abs() < 1e-12, "{own:?}");
}

/// Without the maps, `claims` takes no measurement and says so; it writes no measurement table
/// (the committed ones would be judged as they stand).
#[test]
fn claims_without_the_maps_take_no_measurement() {
    let empty = tempfile::tempdir().unwrap();
    let out = probelab()
        .args(["--root", env!("CARGO_MANIFEST_DIR"), "claims", "--out", empty.path().to_str().unwrap()])
        .env_remove("PROBELAB_ENVMAPS")
        .run();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("measurements not taken"));
    assert!(!empty.path().join("claims/measures").exists());
}
