//! Scoring sets of probes end to end: `probelab probes` on synthetic and saved sets, shards
//! merged by `probelab merge` equal one run (also through the README's GNU parallel recipe),
//! and bad probe files exit 2 naming the file.

mod common;

use common::harness::{parse_csv, probelab, repo, stdout_ok, Run};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `probelab ARGS` run in `dir` (relative paths in ARGS are in `dir`), `PROBELAB_ENVMAPS` unset.
fn run_in(args: &[&str], dir: &Path) -> Output {
    probelab().args(args).current_dir(dir).run()
}

/// The summary without the run-dependent columns (timings, memory, shard list, source).
fn figures(csv: &str) -> Vec<Vec<(String, String)>> {
    let run_dependent = probelab::pipeline::probeset::SUMMARY_TIMING_COLUMNS;
    parse_csv(csv)
        .into_iter()
        .map(|r| {
            let mut v: Vec<_> =
                r.into_iter().filter(|(k, _)| !run_dependent.contains(&k.as_str()) && k != "source").collect();
            v.sort();
            v
        })
        .collect()
}

#[test]
fn shards_merged_by_the_cli_equal_one_run() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let whole = stdout_ok(&run_in(&["probes", "--synth", "4001", "--seed", "3", "--encoders", "sh0,sh2"], d));
    for i in 0..3 {
        let shard = format!("{i}/3");
        let out = format!("s{i}.toml");
        stdout_ok(&run_in(
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
    let merged = stdout_ok(&run_in(&["merge", "s0.toml", "s1.toml", "s2.toml", "--out", "m.toml"], d));
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
    let partial = run_in(&["merge", "s0.toml", "s2.toml"], d);
    assert!(String::from_utf8_lossy(&partial.stderr).contains("partial merge"));
    let twice = run_in(&["merge", "s0.toml", "s0.toml"], d);
    assert_eq!(twice.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&twice.stderr).contains("twice"));
}

/// A synthetic set saved as CSV and as f32 and read back scores like the set itself (CSV
/// exactly: shortest round-trip decimals).
#[test]
fn saved_sets_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let synth = stdout_ok(&run_in(&["probes", "--synth", "1500", "--encoders", "sh2", "--save", "set.csv"], d));
    stdout_ok(&run_in(&["probes", "--synth", "1500", "--encoders", "sh2", "--save", "set.f32"], d));
    let csv = stdout_ok(&run_in(&["probes", "--input", "set.csv", "--encoders", "sh2"], d));
    assert_eq!(figures(&csv), figures(&synth));
    let f32 = stdout_ok(&run_in(&["probes", "--input", "set.f32", "--encoders", "sh2", "--shard", "1/2"], d));
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
        let out = run_in(args, d);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(want), "{args:?}: {err}");
    }
}

/// The GNU parallel recipe of the README, run as written (with a smaller set); its merge
/// equals one run.
#[test]
#[cfg_attr(
    not(gnu_parallel),
    ignore = "needs GNU parallel on PATH (Debian package `parallel`; once installed, `touch build.rs`)"
)]
fn readme_gnu_parallel_recipe() {
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
    let whole = stdout_ok(&run_in(&["probes", "--synth", "20000", "--seed", "7", "--encoders", "all"], dir.path()));
    assert_eq!(figures(&merged), figures(&whole));
}
