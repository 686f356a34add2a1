//! `probelab fit` end to end on the committed CC0 maps (no shared maps needed): JSON and CSV
//! parse, carry the names, units, roles and basis of each fit and what it was fitted on, and
//! hold the values the closed forms give; bad input exits 2 with a clear message.
//!
//! Expected values are derived here: `gen_constant` is radiance 1 everywhere, so its E/π is 1
//! at every normal and SH L1's band-0 coefficient is 1/Y00 = 2√π with no band 1; seen from a
//! surface with normal N = +Y the visible light is radiance 1 over the hemisphere about N, so
//! I_z = E/π(N) = 1.

mod common;
use common::harness::{parse_csv, run, stdout_ok};
use std::f64::consts::PI;

fn values(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().expect("a value is a list").iter().map(|x| x.as_f64().expect("a number")).collect()
}

#[test]
fn json_carries_names_units_basis_and_the_closed_form_values() {
    let out = run(&["fit", "gen_constant", "--encoders", "sh1,zh3_solved_shared", "--format", "json"]);
    let doc: serde_json::Value = serde_json::from_str(&stdout_ok(&out)).expect("JSON");
    assert_eq!(doc["schema"], "probelab.fit/1");
    assert_eq!(doc["maps"][0]["name"], "gen_constant");
    assert_eq!(doc["domain"], "sphere");
    assert!(doc["normal"].is_null());
    assert!(doc["fitted_on"].as_str().unwrap().contains("sphere"), "{}", doc["fitted_on"]);
    let fits = doc["fits"].as_array().unwrap();
    assert_eq!(fits.len(), 2);
    assert_eq!(fits[0]["encoder"], "sh1");
    assert_eq!(fits[1]["encoder"], "zh3_solved_shared");
    for f in fits {
        assert!(f["basis"].as_str().unwrap().contains("section 2"), "the basis cites the SH convention");
        let stored: usize = f["entries"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|e| e["role"] == "stored")
            .map(|e| values(&e["value"]).len())
            .sum();
        assert_eq!(stored as u64, f["stored_scalars"].as_u64().unwrap(), "{}", f["encoder"]);
    }
    let sh1 = fits[0]["entries"].as_array().unwrap();
    let names: Vec<&str> = sh1.iter().map(|e| e["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["L0_0", "L1_-1", "L1_0", "L1_1"]);
    assert!(sh1.iter().all(|e| e["unit"] == "E/pi" && e["role"] == "stored"));
    let dc = values(&sh1[0]["value"]);
    for c in dc {
        assert!((c - 2.0 * PI.sqrt()).abs() < 1e-6, "L0_0 = {c}, want 2 sqrt(pi)");
    }
    for e in &sh1[1..] {
        assert!(values(&e["value"]).iter().all(|v| v.abs() < 1e-9), "{e}: a constant has no band 1");
    }
}

#[test]
fn csv_about_a_normal_has_one_row_per_value() {
    let out = run(&["fit", "gen_constant", "--encoders", "hhd_linear_hemi", "--normal", "0,2,0", "--format", "csv"]);
    let rows = parse_csv(&stdout_ok(&out));
    let names: Vec<&str> = rows.iter().map(|r| r["entry"].as_str()).collect();
    assert_eq!(&names[..4], ["C_a", "I_z", "d_x", "d_y"]);
    for r in &rows {
        assert_eq!(r["map"], "gen_constant");
        assert_eq!(r["domain"], "hemisphere");
        assert_eq!(r["normal"], "0 1 0", "N is normalised");
        assert_eq!(r["encoder"], "hhd_linear_hemi");
        assert!(r["basis"].contains("HHD"), "{}", r["basis"]);
        assert!(["stored", "derived"].contains(&r["role"].as_str()));
    }
    let iz = &rows[1];
    assert_eq!((iz["role"].as_str(), iz["unit"].as_str(), iz["kind"].as_str()), ("stored", "E/pi", "rgb"));
    for c in ["v0", "v1", "v2"] {
        let v: f64 = iz[c].parse().unwrap();
        assert!((v - 1.0).abs() < 1e-6, "I_z {c} = {v}, want 1");
    }
    assert_eq!(rows[2]["kind"], "scalar");
    assert_eq!(rows[2]["v1"], "", "a scalar fills one value column");
    let stored: usize = rows
        .iter()
        .filter(|r| r["role"] == "stored")
        .map(|r| ["v0", "v1", "v2"].iter().filter(|c| !r[**c].is_empty()).count())
        .sum();
    assert_eq!(stored, 8, "irradz_rgb stores 8 scalars");
}

#[test]
fn bad_input_exits_2_with_the_reason() {
    let cases: [(&[&str], &[&str]); 7] = [
        (&["fit", "gen_constant", "--encoders", "sh9"], &["unknown encoder 'sh9'", "sh1"]),
        (&["fit", "gen_constant", "--encoders", "sh1", "--normal", "1,2"], &["--normal '1,2'", "x,y,z"]),
        (&["fit", "gen_constant", "--encoders", "sh1", "--normal", "0,0,0"], &["--normal '0,0,0'"]),
        (&["fit", "gen_constant", "--encoders", "sh1", "--normal", "1,nan,0"], &["--normal '1,nan,0'"]),
        (&["fit", "gen_constant", "--encoders", "hbasis4"], &["needs a surface normal", "--normal x,y,z"]),
        (&["fit", "gen_constant", "--encoders", "sh1", "--format", "xml"], &["--format 'xml'", "json or csv"]),
        (&["fit", "no_such_map", "--encoders", "sh1"], &["no_such_map"]),
    ];
    for (args, want) in cases {
        let out = run(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(out.stdout.is_empty(), "{args:?}: nothing printed on error");
        let err = String::from_utf8_lossy(&out.stderr);
        for w in want {
            assert!(err.contains(w), "{args:?}: '{w}' not in {err}");
        }
    }
}
