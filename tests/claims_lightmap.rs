//! `claims lightmap` end to end: from the paper probes (the shared maps) it writes the
//! measurement tables of H5–H7 under `claims/measures/` and the blending strips under
//! `claims/`, each value checked against what it must be independently of the program.

mod common;

use common::harness::{parse_csv, probelab, run, Run};
use common::shared_maps::{shared_envmaps, PAPER_PROBES};
use std::path::Path;

fn table(dir: &Path, name: &str) -> Vec<std::collections::HashMap<String, String>> {
    parse_csv(&std::fs::read_to_string(dir.join(format!("claims/measures/{name}.csv"))).unwrap())
}

fn num(r: &std::collections::HashMap<String, String>, col: &str) -> f64 {
    r[col].parse().unwrap_or_else(|_| panic!("{col}: {:?}", r[col]))
}

#[test]
#[cfg_attr(not(shared_maps), ignore = "needs the shared maps: set PROBELAB_ENVMAPS to the folder holding them")]
fn claims_lightmap_writes_the_tables_and_strips() {
    let env = shared_envmaps(&PAPER_PROBES);
    let dir = tempfile::tempdir().unwrap();
    let out = probelab()
        .args(["claims", "lightmap", "--out", dir.path().to_str().unwrap()])
        .env("PROBELAB_ENVMAPS", env)
        .run();
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
}

/// Without the paper probes, `claims lightmap` fails with a clear error and exit code 2, and
/// writes nothing.
#[test]
fn claims_lightmap_without_the_probes_exits_2() {
    let empty = tempfile::tempdir().unwrap();
    let out = run(&["claims", "lightmap", "--out", empty.path().to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!empty.path().join("claims").exists());
}
