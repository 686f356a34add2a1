//! End-to-end checks of issue 3: the peer cross-check, `fit-hallucination`, `claims zh3`.
//! Tests that need the shared probes read them from PROBELAB_ENVMAPS and print a skip note
//! without them.

use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn probelab(args: &[&str], envmaps: Option<&str>) -> std::process::Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_probelab"));
    c.args(args).current_dir(repo());
    match envmaps {
        Some(e) => c.env("PROBELAB_ENVMAPS", e),
        None => c.env_remove("PROBELAB_ENVMAPS"),
    };
    c.output().expect("run probelab")
}

fn parse_csv(text: &str) -> Vec<std::collections::HashMap<String, String>> {
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let h: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    r.records().map(|rec| h.iter().cloned().zip(rec.unwrap().iter().map(String::from)).collect()).collect()
}

/// PROBELAB_ENVMAPS if it holds every map named.
fn shared_envmaps(maps: &[&str]) -> Option<String> {
    let v = std::env::var("PROBELAB_ENVMAPS").ok()?;
    let has = |m: &str| v.split(':').any(|d| Path::new(d).join(format!("{m}.exr")).is_file());
    maps.iter().all(|m| has(m)).then_some(v)
}

/// Acceptance (issue 3): the peer tool reports 0.04191 (zh3_hallucinate) and 0.01395
/// (zh3_solved_shared) on grace with its Monte Carlo reference; ours must agree within 4%.
#[test]
fn grace_matches_the_peer_tool() {
    let Some(env) = shared_envmaps(&["grace_256x128"]) else {
        eprintln!("skipped: PROBELAB_ENVMAPS does not hold grace_256x128");
        return;
    };
    let out = probelab(
        &["eval", "grace_256x128", "--encoders", "zh3_hallucinate,zh3_solved_shared", "--metric", "probulator"],
        Some(&env),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = parse_csv(&String::from_utf8(out.stdout).unwrap());
    for (row, peer) in rows.iter().zip([0.04191, 0.01395]) {
        let rmse: f64 = row["rmse"].parse().unwrap();
        assert!((rmse / peer - 1.0).abs() < 0.04, "{}: {rmse} vs peer {peer}", row["encoder"]);
        assert_eq!(row["weighting"], "per-pixel");
    }
    assert!(rows[1]["diagnostics"].contains("iters="), "{}", rows[1]["diagnostics"]);
}

/// A probe file of cap lights over a constant: the fit runs, prints its coefficients and beats
/// SH L1; a malformed file is refused with the file, the line and exit code 2.
#[test]
fn fit_hallucination_from_a_probe_file() {
    use glam::DVec3;
    use probelab::math::colour::Rgb;
    use probelab::math::sh::constant;
    use probelab::reference::lighting::Light;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("probes.csv");
    let mut text = String::from("# caps of several sizes and colours\n");
    for (i, half) in [0.1f64, 0.3, 0.6, 0.9, 1.2].iter().enumerate() {
        let axis = DVec3::new(1.0, i as f64, 0.5).normalize();
        let sh = Light::Cap { axis, half_angle: *half, radiance: Rgb::new(3.0, 2.0, 1.0) }.sh()
            + constant(Rgb::splat(0.05 * i as f64));
        let nums: Vec<String> =
            (0..3).flat_map(|c| (0..9).map(move |k| (c, k))).map(|(c, k)| sh[k][c].to_string()).collect();
        text += &nums.join(",");
        text += "\n";
    }
    std::fs::write(&path, &text).unwrap();
    let out = probelab(&["fit-hallucination", "--probes", path.to_str().unwrap(), "--cubic"], None);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let s = String::from_utf8(out.stdout).unwrap();
    assert!(s.contains("fitted quadratic") && s.contains("fitted cubic") && s.contains("curve_c1"), "{s}");
    assert!(s.contains("15 channel sample(s)"), "{s}");

    std::fs::write(&path, "1,2,3\n").unwrap();
    let out = probelab(&["fit-hallucination", "--probes", path.to_str().unwrap()], None);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("probes.csv:1") && err.contains("27"), "{err}");

    let out = probelab(&["fit-hallucination"], None);
    assert_eq!(out.status.code(), Some(2));
}

/// `claims zh3` writes both files with the ten claims (needs the five probes).
#[test]
fn claims_zh3_writes_the_table() {
    let maps = ["ennis_256x128", "grace_256x128", "pisa_256x128", "uffizi_256x128", "wells_probulator"];
    let Some(env) = shared_envmaps(&maps) else {
        eprintln!("skipped: PROBELAB_ENVMAPS does not hold the five paper probes");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = probelab(&["claims", "zh3", "--out", dir.path().to_str().unwrap()], Some(&env));
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(dir.path().join("zh3_claims/claims.csv")).unwrap();
    let rows = parse_csv(&csv);
    let ids: Vec<&str> = rows.iter().map(|r| r["id"].as_str()).collect();
    assert_eq!(ids, ["Z1", "Z2", "Z3", "Z4", "Z5", "Z6", "Z7", "Z8", "Z9", "Z10"]);
    assert!(rows.iter().all(|r| !r["holds"].is_empty() && !r["our_figure"].contains("NaN")));
    let md = std::fs::read_to_string(dir.path().join("zh3_claims/CLAIMS.md")).unwrap();
    assert!(md.contains("## Z10"));
    // Without the maps: a clear error, exit 2, nothing written.
    let empty = tempfile::tempdir().unwrap();
    let out = probelab(&["claims", "zh3", "--out", empty.path().to_str().unwrap()], None);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("PROBELAB_ENVMAPS"));
    assert!(!empty.path().join("zh3_claims").exists());
}

#[test]
fn new_encoders_are_listed() {
    let out = probelab(&["encoders"], None);
    let s = String::from_utf8(out.stdout).unwrap();
    for id in ["geomerics_peer", "zh3_solved_shared", "zh3_hallucinate_solved", "sh2_q28"] {
        assert!(s.contains(id), "{id}");
    }
}
