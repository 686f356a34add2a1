//! ZH3 end to end: `fit-hallucination` fits the hallucination curve to a probe file, and
//! `claims zh3` writes the table of the ZH3 claims and the measurement tables of Z9 and Z10
//! from the paper probes (the shared maps).

mod common;

use common::harness::{parse_csv, probelab, run, Run};
use common::shared_maps::{shared_envmaps, PAPER_PROBES};

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
    let out = run(&["fit-hallucination", "--probes", path.to_str().unwrap(), "--cubic"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let s = String::from_utf8(out.stdout).unwrap();
    assert!(s.contains("fitted quadratic") && s.contains("fitted cubic") && s.contains("curve_c1"), "{s}");
    assert!(s.contains("15 channel sample(s)"), "{s}");

    std::fs::write(&path, "1,2,3\n").unwrap();
    let out = run(&["fit-hallucination", "--probes", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("probes.csv:1") && err.contains("27"), "{err}");

    let out = run(&["fit-hallucination"]);
    assert_eq!(out.status.code(), Some(2));
}

/// `claims zh3` writes both files with the eight judged claims, and the measurement tables
/// of Z9 and Z10 under `claims/measures/`.
#[test]
#[cfg_attr(not(shared_maps), ignore = "needs the shared maps: set PROBELAB_ENVMAPS to the folder holding them")]
fn claims_zh3_writes_the_table() {
    let env = shared_envmaps(&PAPER_PROBES);
    let dir = tempfile::tempdir().unwrap();
    let out =
        probelab().args(["claims", "zh3", "--out", dir.path().to_str().unwrap()]).env("PROBELAB_ENVMAPS", env).run();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(dir.path().join("zh3_claims/claims.csv")).unwrap();
    let rows = parse_csv(&csv);
    let ids: Vec<&str> = rows.iter().map(|r| r["id"].as_str()).collect();
    assert_eq!(ids, ["Z1", "Z2", "Z3", "Z4", "Z5", "Z6", "Z7", "Z8"]);
    assert!(rows.iter().all(|r| !r["holds"].is_empty() && !r["our_figure"].contains("NaN")));
    let md = std::fs::read_to_string(dir.path().join("zh3_claims/CLAIMS.md")).unwrap();
    assert!(md.contains("## Z8"));
    // Z10: per paper probe, the serialised sizes of the talk (13 / 13 / 16 / 28 bytes), each
    // decoding to exactly what its quantised encoder evaluates.
    let sizes = parse_csv(&std::fs::read_to_string(dir.path().join("claims/measures/quantised_sizes.csv")).unwrap());
    assert_eq!(sizes.len(), 4 * PAPER_PROBES.len());
    for r in &sizes {
        let want = match r["encoder"].as_str() {
            "sh1" | "zh3_hallucinate" => "13",
            "zh3_solved_shared" => "16",
            "sh2" => "28",
            e => panic!("unexpected encoder {e}"),
        };
        assert_eq!((r["bytes"].as_str(), r["roundtrip_max_abs"].as_str()), (want, "0"), "{r:?}");
    }
    // Z9: the blend's own zonal coefficient is ¼ of an endpoint's (P₂(cos 45°)).
    let blend = parse_csv(&std::fs::read_to_string(dir.path().join("claims/measures/zh3_blend.csv")).unwrap());
    let own = blend.iter().find(|r| r["case"] == "deltas_x_y" && r["encoder"] == "sh3_blended").unwrap();
    assert!((own["zonal_scale"].parse::<f64>().unwrap() - 0.25).abs() < 1e-12, "{own:?}");
    assert!(dir.path().join("claims/measures/README.md").exists());
}

/// Without the paper probes, `claims zh3` fails with a clear error and exit code 2, and writes
/// nothing.
#[test]
fn claims_zh3_without_the_probes_exits_2() {
    let empty = tempfile::tempdir().unwrap();
    let out = run(&["claims", "zh3", "--out", empty.path().to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("PROBELAB_ENVMAPS"));
    assert!(!empty.path().join("zh3_claims").exists());
}
