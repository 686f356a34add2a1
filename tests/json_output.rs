//! The JSON documents are a contract (docs/json.md): every document `eval`, `fit` and `check`
//! print opens with its `schema`, lists each map it read with the sha256 of the map's file —
//! computed here independently, with the sha2 crate, over the committed file the name stands
//! for — and its size, and never writes a number as a string (no string anywhere in the
//! document parses as a number, identities aside).

mod common;
use common::harness::{repo, run, stdout_ok};
use serde_json::Value;
use sha2::{Digest, Sha256};

/// The sha256 of a file's bytes, as lower-case hex.
fn sha256_of(path: &std::path::Path) -> String {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    Sha256::digest(&bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// Parses a document and checks what every document carries: its schema first, and each map
/// in `expected` (name → the committed file it must have been read from) with that file's
/// sha256, its path and its size.
fn document(text: &str, schema: &str, expected: &[(&str, &str)]) -> Value {
    let doc: Value = serde_json::from_str(text).expect("one JSON document");
    let obj = doc.as_object().expect("an object");
    assert_eq!(obj.keys().next().map(String::as_str), Some("schema"), "the schema comes first");
    assert_eq!(doc["schema"], schema);
    let maps = doc["maps"].as_array().expect("a list of maps");
    assert_eq!(maps.len(), expected.len(), "{}", doc["maps"]);
    for (name, file) in expected {
        let m = maps.iter().find(|m| m["name"] == *name).unwrap_or_else(|| panic!("map {name} not listed"));
        let file = repo().join(file);
        assert_eq!(m["sha256"].as_str(), Some(sha256_of(&file).as_str()), "{name}");
        let path = m["path"].as_str().expect("a path");
        assert_eq!(
            std::fs::canonicalize(repo().join(path)).unwrap(),
            std::fs::canonicalize(&file).unwrap(),
            "{name}: the file read"
        );
        let size: Vec<u64> = m["size"].as_array().unwrap().iter().map(|v| v.as_u64().expect("integers")).collect();
        assert_eq!(size.len(), 2);
        assert_eq!(size[0], 2 * size[1], "{name}: lat-long maps are 2:1");
        assert!(m["pixel_sha256"].as_str().is_some_and(|s| s.len() == 64));
    }
    no_numbers_as_strings(&doc, "");
    doc
}

/// Fails on a string that reads as a number (`"0.25"`, `"12"`), anywhere in `v`; the
/// identities (hex digests, commits) aside.
fn no_numbers_as_strings(v: &Value, at: &str) {
    match v {
        Value::String(s) => assert!(s.trim().parse::<f64>().is_err(), "{at}: the number {s:?} is a string"),
        Value::Array(a) => a.iter().enumerate().for_each(|(i, x)| no_numbers_as_strings(x, &format!("{at}[{i}]"))),
        Value::Object(o) => {
            for (k, x) in o {
                if !["sha256", "pixel_sha256", "baseline_commit"].contains(&k.as_str()) {
                    no_numbers_as_strings(x, &format!("{at}.{k}"));
                }
            }
        }
        _ => {}
    }
}

#[test]
fn the_checker_sees_a_number_written_as_a_string() {
    let bad = serde_json::json!({ "rows": [{ "rmse": "0.25" }] });
    assert!(std::panic::catch_unwind(|| no_numbers_as_strings(&bad, "")).is_err());
    no_numbers_as_strings(&serde_json::json!({ "rows": [{ "rmse": 0.25, "domain": "sphere" }] }), "");
}

#[test]
fn eval_documents_carry_the_schema_maps_and_numbers() {
    let text = stdout_ok(&run(&[
        "eval",
        "blender_city_256x128",
        "envmaps/gen_sky_sun.exr",
        "--encoders",
        "sh1,zh3_solved_shared",
        "--resolution",
        "16x8",
        "--format",
        "json",
    ]));
    let doc = document(
        &text,
        "probelab.eval/1",
        &[("blender_city_256x128", "envmaps/blender_city_256x128.exr"), ("gen_sky_sun", "envmaps/gen_sky_sun.exr")],
    );
    let given: Vec<&str> = doc["maps"].as_array().unwrap().iter().map(|m| m["given"].as_str().unwrap()).collect();
    assert_eq!(given, ["blender_city_256x128", "envmaps/gen_sky_sun.exr"], "the names as given");
    let rows = doc["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 4);
    for r in rows {
        for col in ["rmse", "rel_rmse", "rmse_r", "neg_frac", "max_abs_err", "stored_scalars"] {
            assert!(r[col].is_number(), "{col}: {}", r[col]);
        }
        let d = r["diagnostics"].as_object().expect("diagnostics are an object");
        assert!(d.values().all(Value::is_number), "{d:?}");
        if r["encoder"] == "zh3_solved_shared" {
            assert!(d["iters"].as_f64().is_some_and(|n| n >= 1.0), "the solver's iterations: {d:?}");
        }
    }
}

#[test]
fn fit_documents_carry_the_schema_maps_and_numbers() {
    let text = stdout_ok(&run(&["fit", "pmndrs_sunset_256x128", "--encoders", "sh2,zh3_solved_shared"]));
    let doc = document(&text, "probelab.fit/1", &[("pmndrs_sunset_256x128", "envmaps/pmndrs_sunset_256x128.exr")]);
    for f in doc["fits"].as_array().unwrap() {
        assert!(f["stored_scalars"].is_u64());
        assert!(f["diagnostics"].is_object());
        for e in f["entries"].as_array().unwrap() {
            assert!(e["value"].as_array().unwrap().iter().all(Value::is_number), "{e}");
        }
    }
}

/// On a copy of the committed baseline of an experiment whose maps are all committed.
#[test]
fn check_documents_carry_the_schema_maps_and_numbers() {
    let exp = "generated_scenes";
    let dir = tempfile::tempdir().unwrap();
    let base = repo().join("results").join(exp);
    std::fs::create_dir(dir.path().join(exp)).unwrap();
    for f in std::fs::read_dir(&base).unwrap() {
        let f = f.unwrap().path();
        if f.is_file() {
            std::fs::copy(&f, dir.path().join(exp).join(f.file_name().unwrap())).unwrap();
        }
    }
    let out = run(&["check", exp, "--out", dir.path().to_str().unwrap(), "--format", "json"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(out.status.code().is_some_and(|c| c <= 1), "{}", String::from_utf8_lossy(&out.stderr));
    // The experiment's maps, from its file, each a committed `envmaps/NAME.exr`.
    let file: toml::Table =
        toml::from_str(&std::fs::read_to_string(repo().join(format!("experiments/{exp}.toml"))).unwrap()).unwrap();
    let names: Vec<String> = file["maps"].as_array().unwrap().iter().map(|m| m.as_str().unwrap().to_string()).collect();
    let files: Vec<String> = names.iter().map(|n| format!("envmaps/{n}.exr")).collect();
    let expected: Vec<(&str, &str)> = names.iter().map(String::as_str).zip(files.iter().map(String::as_str)).collect();
    assert!(!expected.is_empty());
    let doc = document(&text, "probelab.check/1", &expected);
    let e = &doc["experiments"][0];
    for key in ["rows", "numbers", "moved"] {
        assert!(e[key].is_u64(), "{key}: {}", e[key]);
    }
    assert!(e["findings"].as_array().unwrap().iter().all(|f| f["kind"].is_string() && f["fails"].is_boolean()));
}

/// The claims' part of `check`'s document is structured: on a copy of the committed results
/// whose CLAIMS.csv has one verdict edited, and without the shared maps, `claims` says the
/// measurements were not taken and why, and lists that verdict as changed (its committed and
/// its present word), so `passed` is false, as the exit code 1 says.
#[test]
fn check_documents_give_the_claims_as_data() {
    let s = common::harness::Scratch::new();
    s.copy_from_repo("experiments");
    s.copy_from_repo("results");
    s.copy_from_repo("tolerances.toml");
    let csv = s.path().join("results/CLAIMS.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let judged = common::harness::parse_csv(&text);
    let first = &judged[0];
    let edited = text.replacen(
        &format!("{},{},{}", first["id"], first["kind"], first["verdict"]),
        &format!("{},{},edited", first["id"], first["kind"]),
        1,
    );
    assert_ne!(edited, text, "the first row's id, kind and verdict are its first three cells");
    std::fs::write(&csv, edited).unwrap();
    let out = s.run(&["check", "claims", "--format", "json"]);
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    let doc = document(&String::from_utf8(out.stdout).unwrap(), "probelab.check/1", &[]);
    let c = &doc["claims"];
    assert_eq!(c["passed"], false);
    assert_eq!(doc["passed"], false);
    assert_eq!(c["measured"], false);
    assert!(c["not_measured_because"].as_str().is_some_and(|w| w.contains("not on the search path")), "{c}");
    assert_eq!(c["moved"], serde_json::json!([]));
    assert_eq!(
        c["verdicts_changed"],
        serde_json::json!([{ "id": first["id"], "committed": "edited", "now": first["verdict"] }])
    );
}
