//! The command line end to end: `eval` (CSV columns, domains, timing columns, `--profile`),
//! `encoders`, `gen-envmaps`, and exit code 2 with a message for a missing map or bad
//! arguments.

mod common;

use common::harness::{parse_csv, probelab, repo, run, stdout_ok, Run};

#[test]
fn constant_map_is_exact_for_sh1_and_sh2() {
    let out = run(&["eval", "gen_constant", "--encoders", "sh1,sh2"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("map,encoder,domain,metric,rmse_r,rmse_g,rmse_b,rmse,rel_rmse"));
    let rows = parse_csv(&text);
    assert_eq!(rows.len(), 2);
    for r in rows {
        let rmse: f64 = r["rmse"].parse().unwrap();
        assert!(rmse <= 1e-6, "{}: {rmse}", r["encoder"]);
        assert_eq!(r["units"], "E/pi");
        assert_eq!(r["weighting"], "solid-angle");
    }
}

/// Under the hemisphere effect about a wall normal, a constant map is the hemisphere light
/// (1 + n·N)/2, which is linear: SH L1 of the occluded radiance represents it exactly.
#[test]
fn hemisphere_domain_on_a_wall() {
    let out = run(&["eval", "gen_constant", "--encoders", "sh0,sh1", "--domain", "hemisphere:+x"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = parse_csv(&String::from_utf8(out.stdout).unwrap());
    assert_eq!(rows[0]["domain"], "hemisphere:+x");
    let sh1: f64 = rows[1]["rmse"].parse().unwrap();
    assert!(sh1 < 1e-6, "{sh1}");
    // sh0 keeps only the mean over the sphere of the occluded radiance (½), so on the
    // hemisphere its error is the RMS of (1 + c)/2 − ½ = c/2 over c = n·N ∈ [0, 1]:
    // √(∫₀¹ c²/4 dc) = √(1/12).
    let sh0: f64 = rows[0]["rmse"].parse().unwrap();
    assert!((sh0 - (1.0f64 / 12.0).sqrt()).abs() < 1e-4, "{sh0}");
}

#[test]
fn missing_map_lists_searched_folders_and_exits_2() {
    let out = probelab()
        .args(["eval", "no_such_map", "--encoders", "sh1"])
        .env("PROBELAB_ENVMAPS", "/nonexistent/a:/nonexistent/b")
        .run();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no_such_map") && err.contains("/nonexistent/a") && err.contains("/nonexistent/b"), "{err}");
}

#[test]
fn bad_arguments_exit_2_with_a_message() {
    for args in [
        &["eval", "gen_constant", "--encoders", "sh7"][..],
        &["eval", "gen_constant", "--domain", "hemisphere:+w"][..],
        &["eval", "gen_constant", "--metric", "l1"][..],
        &["run", "experiments/does_not_exist.toml"][..],
    ] {
        let out = run(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(String::from_utf8_lossy(&out.stderr).starts_with("error: "), "{args:?}");
    }
}

/// `report --scale` takes a whole number from 1 to 8: anything else is refused by the argument
/// parser (exit 2, the option named) before anything is read or written.
#[test]
fn report_scale_outside_one_to_eight_exits_2() {
    let out_dir = std::env::temp_dir().join(format!("probelab_scale_refused_{}", std::process::id()));
    for bad in ["0", "9", "1.5", "two"] {
        let out = run(&["report", "--scale", bad, "--out", out_dir.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "--scale {bad}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.starts_with("error: ") && err.contains("--scale"), "--scale {bad}: {err}");
        assert!(!out_dir.exists(), "--scale {bad} wrote {}", out_dir.display());
    }
}

/// The committed generated maps are exactly what `gen-envmaps` writes today.
#[test]
fn committed_generated_maps_are_current() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(&["gen-envmaps", "--out", dir.path().to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let load = |p: &std::path::Path| probelab::Map::load(p.to_str().unwrap(), repo());
    let mut fresh: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().path()).collect();
    fresh.sort();
    assert!(!fresh.is_empty(), "gen-envmaps wrote no map");
    for path in fresh {
        let id = path.file_stem().unwrap().to_string_lossy().into_owned();
        let committed = load(&repo().join("envmaps").join(format!("{id}.exr")))
            .unwrap_or_else(|e| panic!("{e:#} (run `probelab gen-envmaps`)"));
        assert_eq!(load(&path).unwrap().texels(), committed.texels(), "{id} differs: run `probelab gen-envmaps`");
    }
}

/// Every lightmap encoder runs one-off on a hemisphere domain, with the same CSV
/// columns as on the sphere; on the constant map AHD with the hemispherical Gram is exact (H1).
#[test]
fn lightmap_encoders_run_on_a_hemisphere_domain() {
    let all = "ahd_linear_sphere,ahd_linear_hemi,ahd_search_sphere,ahd_search_hemi,ahd_irradz_2018,\
               hhd_linear_sphere,hhd_linear_hemi,hhd_search_sphere,hhd_search_hemi,hhd_from_sh1";
    let out = run(&["eval", "gen_constant", "--encoders", all, "--domain", "hemisphere:+y"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("map,encoder,domain,metric,rmse_r,rmse_g,rmse_b,rmse,rel_rmse"));
    let rows = parse_csv(&text);
    assert_eq!(rows.len(), 10);
    for r in &rows {
        assert_eq!(r["domain"], "hemisphere:+y");
        let rmse: f64 = r["rmse"].parse().unwrap();
        assert!(rmse.is_finite());
        if ["ahd_linear_hemi", "ahd_search_hemi", "ahd_irradz_2018"].contains(&r["encoder"].as_str()) {
            assert!(rmse < 1e-6, "{}: {rmse}", r["encoder"]);
        }
    }
}

/// The H-basis needs a surface normal: `eval` on the sphere and `probes` refuse it (exit 2,
/// naming it); on a wall under the hemisphere effect a constant map's E/π is (1 + n·N)/2, which
/// is linear in n, so H4 and H6 hold it exactly.
#[test]
fn the_hbasis_needs_a_surface_normal() {
    let out = run(&["eval", "gen_constant", "--encoders", "sh1,hbasis4"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(
            "'hbasis4' needs a surface normal N: it is defined only on the hemisphere about a surface normal N"
        ),
        "{err}"
    );
    let out = run(&["probes", "--synth", "10", "--encoders", "sh2,hbasis6"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("'hbasis6'"));
    let out = run(&["eval", "gen_constant", "--encoders", "hbasis4,hbasis6", "--domain", "hemisphere:+x"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for r in parse_csv(&String::from_utf8(out.stdout).unwrap()) {
        let rmse: f64 = r["rmse"].parse().unwrap();
        assert!(rmse < 1e-6, "{}: {rmse}", r["encoder"]);
    }
}

/// Tables carry the timing columns after the others; --no-timing leaves them empty; --profile
/// reports phases.
#[test]
fn tables_carry_timing_and_profile_reports_phases() {
    let out = run(&["--profile", "eval", "gen_constant", "--encoders", "sh1,sh2", "--resolution", "32x16"]);
    let text = stdout_ok(&out);
    assert!(text.lines().next().unwrap().ends_with(",fit_ns,eval_ns"));
    for r in parse_csv(&text) {
        let (f, e): (f64, f64) = (r["fit_ns"].parse().unwrap(), r["eval_ns"].parse().unwrap());
        assert!(f > 0.0 && e > 0.0 && f < 1e7 && e < 1e6, "{f} {e}");
    }
    let err = String::from_utf8_lossy(&out.stderr);
    for phase in ["decode", "reference", "fit", "render (encoder eval)", "timing pass"] {
        assert!(err.contains(phase), "{phase}: {err}");
    }
    let out = run(&["--no-timing", "eval", "gen_constant", "--encoders", "sh1", "--resolution", "32x16"]);
    let r = &parse_csv(&stdout_ok(&out))[0];
    assert_eq!((r["fit_ns"].as_str(), r["eval_ns"].as_str()), ("", ""));
}

/// `encoders` lists every registered encoder, one per line, id first.
#[test]
fn encoders_lists_the_registry() {
    let s = stdout_ok(&run(&["encoders"]));
    let ids: Vec<&str> = s.lines().filter_map(|l| l.split_whitespace().next()).collect();
    for k in probelab::encoders::REGISTRY {
        assert!(ids.contains(&k.id), "{} is not listed:\n{s}", k.id);
    }
}

/// Every encoder that needs a surface normal N or an occluded bake about N (the H-basis, every
/// AHD/HHD lightmap encoder, every probe-occlusion operator but the unoccluded leak baseline),
/// listed here by hand rather than read from the program.
const SURFACE_ONLY: &[&str] = &[
    "hbasis4",
    "hbasis6",
    "ahd_linear_sphere",
    "ahd_linear_hemi",
    "ahd_search_sphere",
    "ahd_search_hemi",
    "ahd_irradz_2018",
    "hhd_linear_sphere",
    "hhd_linear_hemi",
    "hhd_search_sphere",
    "hhd_search_hemi",
    "hhd_from_sh1",
    "probe_hemi_full",
    "probe_cone_full",
    "probe_hemi_q2l",
    "hlsh",
    "probe_hhd_lum",
    "cone_multiply",
    "ao_scale",
    "bent_normal",
];

/// On the sphere (no N) each surface-only encoder is refused by `eval` and `probes` with exit 2
/// and the reason; on a hemisphere domain every one of them runs. `probe_unoccluded` (the leak
/// baseline) and `with_self_bounce` around sh2 run on the sphere; `probes --encoders all` leaves
/// the surface-only ones out with a note naming them.
#[test]
fn surface_only_encoders_are_refused_on_the_sphere() {
    for id in SURFACE_ONLY {
        let want =
            format!("'{id}' needs a surface normal N: it is defined only on the hemisphere about a surface normal N");
        let out = run(&["eval", "gen_constant", "--encoders", &format!("sh1,{id}"), "--resolution", "16x8"]);
        assert_eq!(out.status.code(), Some(2), "eval {id}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(&want) && err.contains("--domain hemisphere:AXIS"), "eval {id}: {err}");
        assert!(out.stdout.is_empty(), "eval {id} printed a table");
        let out = run(&["probes", "--synth", "4", "--encoders", &format!("sh2,{id}")]);
        assert_eq!(out.status.code(), Some(2), "probes {id}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(&want) && err.contains("a probe is a sphere"), "probes {id}: {err}");
    }
    let list = SURFACE_ONLY.join(",");
    let out = run(&["eval", "gen_constant", "--encoders", &list, "--domain", "hemisphere:+z", "--resolution", "16x8"]);
    let rows = parse_csv(&stdout_ok(&out));
    assert_eq!(rows.len(), SURFACE_ONLY.len());
    for (r, id) in rows.iter().zip(SURFACE_ONLY) {
        assert_eq!(&r["encoder"], id);
        assert!(r["rmse"].parse::<f64>().unwrap().is_finite(), "{id}");
    }
    let out = run(&["eval", "gen_constant", "--encoders", "probe_unoccluded,with_self_bounce", "--resolution", "16x8"]);
    assert_eq!(parse_csv(&stdout_ok(&out)).len(), 2);

    let out = run(&["probes", "--synth", "4", "--encoders", "all"]);
    let table = stdout_ok(&out);
    let err = String::from_utf8_lossy(&out.stderr);
    for id in SURFACE_ONLY {
        assert!(err.contains(id), "the note does not name {id}: {err}");
        assert!(!table.lines().any(|l| l.starts_with(&format!("{id},"))), "probes all scored {id}");
    }
    assert!(table.lines().any(|l| l.starts_with("probe_unoccluded,")));
}

/// `with_self_bounce` needs N exactly when its inner encoder does: an experiment on the sphere
/// wrapping hlsh is refused naming the file and the reason; wrapping sh2 it loads.
#[test]
fn with_self_bounce_delegates_the_surface_refusal() {
    let root = common::harness::Scratch::new();
    root.copy_from_repo("envmaps/gen_constant.exr");
    let bad = root.write(
        "experiments/wrap.toml",
        "maps = ['gen_constant']\nresolution = [16, 8]\nencoders = [{ kind = 'with_self_bounce', inner = 'hlsh' }]\n",
    );
    let out = root.run(&["run", bad.to_str().unwrap(), "--out", root.path().join("out").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("wrap.toml")
            && err.contains("'with_self_bounce' needs a surface normal N")
            && err.contains("domain = \"hemisphere\""),
        "{err}"
    );
    let good = root.write(
        "experiments/wrap_sh2.toml",
        "maps = ['gen_constant']\nresolution = [16, 8]\nencoders = [{ kind = 'with_self_bounce', inner = 'sh2' }]\n",
    );
    let out = root.run(&["run", good.to_str().unwrap(), "--out", root.path().join("out").to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// `eval --format json`: the same rows as the CSV, keyed by the same columns in the same order,
/// each score a JSON number equal to the CSV's cell (both print f64 in shortest round-trip
/// form), empty cells `null`, the diagnostics an object of the CSV cell's `key=value` pairs; a
/// format other than csv or json is refused.
#[test]
fn eval_prints_json_with_the_csv_columns() {
    let args = ["eval", "blender_city_256x128", "--encoders", "sh1,zh3_solved_shared", "--resolution", "32x16"];
    let csv_text = stdout_ok(&run(&args));
    let csv = parse_csv(&csv_text);
    let columns: Vec<&str> = csv_text.lines().next().unwrap().split(',').collect();
    assert!(csv.iter().any(|r| r["diagnostics"].contains('=')), "an encoder with diagnostics");
    let json: serde_json::Value =
        serde_json::from_str(&stdout_ok(&run(&[&args[..], &["--format", "json"]].concat()))).unwrap();
    assert_eq!(json["schema"], "probelab.eval/1");
    let rows = json["rows"].as_array().expect("an array of rows");
    assert_eq!(rows.len(), csv.len());
    assert_eq!(rows.len(), 2);
    for (j, c) in rows.iter().zip(&csv) {
        let j = j.as_object().unwrap();
        assert_eq!(j.len(), c.len(), "the same columns");
        assert_eq!(j.keys().map(String::as_str).collect::<Vec<_>>(), columns, "the CSV's column order");
        for (col, cell) in c {
            let v = &j[col];
            if col == "diagnostics" {
                let pairs: Vec<(String, f64)> = cell
                    .split(';')
                    .filter(|p| !p.is_empty())
                    .map(|p| p.split_once('=').map(|(k, v)| (k.to_string(), v.parse().unwrap())).unwrap())
                    .collect();
                let obj = v.as_object().expect("diagnostics are an object");
                assert_eq!(obj.len(), pairs.len(), "{cell}");
                for (k, x) in pairs {
                    assert_eq!(obj[&k].as_f64(), Some(x), "diagnostics {k}");
                }
                continue;
            }
            match v {
                serde_json::Value::String(s) => assert_eq!(s, cell, "{col}"),
                serde_json::Value::Null => assert!(cell.is_empty(), "{col}: null for '{cell}'"),
                // Wall-clock columns differ between the two runs; only their type is compared.
                serde_json::Value::Number(_) if col.ends_with("_ns") => {}
                serde_json::Value::Number(n) => {
                    // serde_json's default parser may round the last bit; the printer does not.
                    let (a, b) = (n.as_f64().unwrap(), cell.parse::<f64>().unwrap());
                    assert!((a - b).abs() <= 1e-15 * a.abs().max(b.abs()), "{col}: {a} vs {b}")
                }
                other => panic!("{col}: {other}"),
            }
        }
        for col in ["rmse", "rel_rmse", "max_abs_err", "stored_scalars"] {
            assert!(j[col].is_number(), "{col} is a number");
        }
        assert!(j["units"].as_str().unwrap().contains("E/pi") || j["units"].as_str().unwrap().contains("E/π"));
    }
    let out = run(&[&args[..], &["--format", "xml"]].concat());
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("xml"));
}

/// `check --format json` says what the text format says: on a committed experiment whose
/// maps are all generated (in envmaps/ on every clone), the same verdict, the same counts, and one
/// finding object per finding line. The counts are read from the text independently.
#[test]
fn check_prints_json_with_the_text_counts() {
    let exp = "generated_scenes";
    // A copy of the baseline: a check holds a shared lock on its folder, which would make a
    // concurrent test's `run` on results/ wait.
    let dir = tempfile::tempdir().unwrap();
    let base = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("results").join(exp);
    std::fs::create_dir(dir.path().join(exp)).unwrap();
    for f in std::fs::read_dir(&base).unwrap() {
        let f = f.unwrap().path();
        if f.is_file() {
            std::fs::copy(&f, dir.path().join(exp).join(f.file_name().unwrap())).unwrap();
        }
    }
    let out_dir = dir.path().to_str().unwrap();
    let text_out = run(&["check", exp, "--out", out_dir]);
    let text = stdout_ok(&text_out);
    let json_out = run(&["check", exp, "--out", out_dir, "--format", "json"]);
    assert_eq!(json_out.status.code(), text_out.status.code(), "the same exit code");
    let doc: serde_json::Value = serde_json::from_str(&stdout_ok(&json_out)).expect("one JSON document");
    let e = &doc["experiments"][0];
    assert_eq!(e["experiment"], exp);
    assert_eq!(doc["passed"].as_bool(), Some(text.contains("check: ok")));
    assert_eq!(e["passed"], doc["passed"]);
    // "N rows, M numbers compared with the baseline …"
    let verdict = text.lines().find(|l| l.starts_with(&format!("{exp}: ok"))).expect("a verdict line");
    let n = |word: &str| -> u64 {
        let before = verdict.split(word).next().unwrap();
        before.split(|c: char| !c.is_ascii_digit()).rfind(|t| !t.is_empty()).unwrap().parse().unwrap()
    };
    assert_eq!(e["rows"].as_u64(), Some(n(" rows")));
    assert_eq!(e["numbers"].as_u64(), Some(n(" numbers compared")));
    assert_eq!(doc["numbers"], e["numbers"]);
    assert!(e["numbers"].as_u64().unwrap() > 0);
    let finding_lines = text.lines().filter(|l| l.starts_with(&format!("{exp}: ")) && *l != verdict).count();
    assert_eq!(e["findings"].as_array().unwrap().len(), finding_lines);
    assert!(e["baseline_commit"].is_string());
    let out = run(&["check", exp, "--format", "yaml"]);
    assert_eq!(out.status.code(), Some(2));
}
