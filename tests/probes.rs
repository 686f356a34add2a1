//! End-to-end checks of `probelab probes`, `merge` and the timing columns (issue 7).

use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn probelab(args: &[&str], dir: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_probelab"))
        .args(args)
        .current_dir(dir)
        .env_remove("PROBELAB_ENVMAPS")
        .output()
        .expect("run probelab")
}

fn ok(out: &std::process::Output) -> String {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// Rows of CSV text as (header → value) maps.
fn parse_csv(text: &str) -> Vec<std::collections::HashMap<String, String>> {
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let h: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    r.records().map(|rec| h.iter().cloned().zip(rec.unwrap().iter().map(String::from)).collect()).collect()
}

/// The summary without the run-dependent columns (timings, memory, shard list, source).
fn figures(csv: &str) -> Vec<Vec<(String, String)>> {
    let skip = probelab::pipeline::probeset::SUMMARY_TIMING_COLUMNS;
    parse_csv(csv)
        .into_iter()
        .map(|r| {
            let mut v: Vec<_> = r.into_iter().filter(|(k, _)| !skip.contains(&k.as_str()) && k != "source").collect();
            v.sort();
            v
        })
        .collect()
}

#[test]
fn shards_merged_by_the_cli_equal_one_run() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let whole = ok(&probelab(&["probes", "--synth", "4001", "--seed", "3", "--encoders", "sh0,sh2"], d));
    for i in 0..3 {
        let shard = format!("{i}/3");
        let out = format!("s{i}.toml");
        ok(&probelab(
            &[
                "probes",
                "--synth",
                "4001",
                "--seed",
                "3",
                "--encoders",
                "sh0,sh2",
                "--shard",
                &shard,
                "--out",
                &out,
                "--chunk",
                "500",
            ],
            d,
        ));
    }
    let merged = ok(&probelab(&["merge", "s0.toml", "s1.toml", "s2.toml", "--out", "m.toml"], d));
    assert_eq!(figures(&merged), figures(&whole));
    let rows = parse_csv(&merged);
    assert_eq!(
        rows.iter().map(|r| r["encoder"].as_str()).collect::<Vec<_>>(),
        ["sh1", "sh0", "sh2"],
        "sh1 added as the baseline"
    );
    assert_eq!(rows[0]["reduction_vs_sh1"], "0");
    assert_eq!(rows[2]["reduction_vs_sh1"], "1");
    assert_eq!(rows[0]["shards"], "all 3");
    // A partial merge warns; a shard twice is an error (exit 2).
    let partial = probelab(&["merge", "s0.toml", "s2.toml"], d);
    assert!(String::from_utf8_lossy(&partial.stderr).contains("partial merge"));
    let twice = probelab(&["merge", "s0.toml", "s0.toml"], d);
    assert_eq!(twice.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&twice.stderr).contains("twice"));
}

/// A synthetic set saved as CSV and as f32 and read back scores like the set itself (CSV
/// exactly: shortest round-trip decimals).
#[test]
fn saved_sets_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let synth = ok(&probelab(&["probes", "--synth", "1500", "--encoders", "sh2", "--save", "set.csv"], d));
    ok(&probelab(&["probes", "--synth", "1500", "--encoders", "sh2", "--save", "set.f32"], d));
    let csv = ok(&probelab(&["probes", "--input", "set.csv", "--encoders", "sh2"], d));
    assert_eq!(figures(&csv), figures(&synth));
    let f32 = ok(&probelab(&["probes", "--input", "set.f32", "--encoders", "sh2", "--shard", "1/2"], d));
    let r = parse_csv(&f32);
    assert_eq!(r[0]["probes"], "750");
    assert!(parse_csv(&csv)[0]["source"].starts_with("file set.csv"));
}

#[test]
fn bad_probe_files_exit_2_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("bad.csv"), "1,2,3\n").unwrap();
    std::fs::write(d.join("bad.f32"), [0u8; 100]).unwrap();
    for (args, want) in [
        (&["probes", "--input", "bad.csv"][..], "bad.csv:1: expected 27 numbers"),
        (&["probes", "--input", "bad.f32"][..], "bad.f32: size 100 bytes"),
        (&["probes", "--input", "missing.csv"][..], "missing.csv"),
        (&["probes", "--input", "x.txt"][..], "unknown probe file format"),
        (&["probes", "--synth", "10", "--shard", "2/2"][..], "--shard '2/2'"),
        (&["probes"][..], "--input"),
        (&["merge", "bad.csv"][..], "bad.csv"),
    ] {
        let out = probelab(args, d);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(want), "{args:?}: {err}");
    }
}

/// The GNU parallel recipe of the README, run as written (with a smaller set), when
/// `parallel` is installed; its merge equals one run.
#[test]
fn readme_gnu_parallel_recipe() {
    if Command::new("parallel").arg("--version").output().map(|o| !o.status.success()).unwrap_or(true) {
        eprintln!("skipped: GNU parallel is not installed (Debian package `parallel`)");
        return;
    }
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let block = readme.split("<!-- recipe:parallel -->").nth(1).unwrap().split("<!-- /recipe -->").next().unwrap();
    let script: String = block.lines().filter(|l| !l.starts_with("```")).collect::<Vec<_>>().join("\n");
    assert!(script.contains("3000000"));
    let script = script.replace("3000000", "20000");
    let dir = tempfile::tempdir().unwrap();
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_probelab"));
    let path = format!("{}:{}", bin.parent().unwrap().display(), std::env::var("PATH").unwrap_or_default());
    let out = Command::new("bash")
        .args(["-euo", "pipefail", "-c", &script])
        .current_dir(dir.path())
        .env("PATH", path)
        .env_remove("PROBELAB_ENVMAPS")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let merged = std::fs::read_to_string(dir.path().join("summary.csv")).unwrap();
    let whole = ok(&probelab(&["probes", "--synth", "20000", "--seed", "7", "--encoders", "all"], dir.path()));
    assert_eq!(figures(&merged), figures(&whole));
}

/// Tables carry the timing columns after the others; --no-timing leaves them empty; --profile
/// reports phases.
#[test]
fn tables_carry_timing_and_profile_reports_phases() {
    let out = Command::new(env!("CARGO_BIN_EXE_probelab"))
        .args(["--profile", "eval", "gen_constant", "--encoders", "sh1,sh2", "--resolution", "32x16"])
        .current_dir(repo())
        .output()
        .unwrap();
    let text = ok(&out);
    assert!(text.lines().next().unwrap().ends_with(",fit_ns,eval_ns"));
    for r in parse_csv(&text) {
        let (f, e): (f64, f64) = (r["fit_ns"].parse().unwrap(), r["eval_ns"].parse().unwrap());
        assert!(f > 0.0 && e > 0.0 && f < 1e7 && e < 1e6, "{f} {e}");
    }
    let err = String::from_utf8_lossy(&out.stderr);
    for phase in ["decode", "reference", "fit", "render (encoder eval)", "timing pass"] {
        assert!(err.contains(phase), "{phase}: {err}");
    }
    let out = Command::new(env!("CARGO_BIN_EXE_probelab"))
        .args(["--no-timing", "eval", "gen_constant", "--encoders", "sh1", "--resolution", "32x16"])
        .current_dir(repo())
        .output()
        .unwrap();
    let r = &parse_csv(&ok(&out))[0];
    assert_eq!((r["fit_ns"].as_str(), r["eval_ns"].as_str()), ("", ""));
}
