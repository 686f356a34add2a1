//! Scoring sets of probes end to end: `probelab probes` on synthetic and saved sets, shards
//! merged by `probelab merge` equal one run (also through the GNU parallel recipe of docs/scale.md),
//! and bad probe files exit 2 naming the file.

mod common;

use common::harness::{parse_csv, probelab, repo, stdout_ok, Run};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `probelab ARGS` run in `dir` (relative paths in ARGS are in `dir`), `PROBELAB_ENVMAPS` unset.
fn run_in(args: &[&str], dir: &Path) -> Output {
    probelab().args(args).current_dir(dir).run()
}

/// The summary without the run-dependent columns (timings, memory, shard list) and without its
/// `# source:` comment.
fn figures(csv: &str) -> Vec<Vec<(String, String)>> {
    // The summary's timing and run figures (docs/scale.md), listed here by hand.
    let run_dependent = ["probes_per_s", "encoder_s", "wall_s", "peak_mem_mib", "shards"];
    parse_csv(csv)
        .into_iter()
        .map(|r| {
            let mut v: Vec<_> = r.into_iter().filter(|(k, _)| !run_dependent.contains(&k.as_str())).collect();
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
    assert!(csv.starts_with("# source: file set.csv"), "{csv}");
}

/// The summary reads in a terminal: the probe set's provenance (a palette of every map on the
/// search path, hundreds of characters) is said once, in the `# source:` line above the table,
/// and no cell of the table runs long.
#[test]
fn the_summary_keeps_its_source_in_one_comment_line() {
    let dir = tempfile::tempdir().unwrap();
    let csv = stdout_ok(&run_in(&["probes", "--synth", "50", "--encoders", "sh1,sh2"], dir.path()));
    let mut lines = csv.lines();
    let source = lines.next().unwrap();
    assert!(source.starts_with("# source: synth n=50 seed=1 palette="), "{source}");
    assert!(lines.all(|l| !l.starts_with('#') && !l.contains("palette=")), "{csv}");
    let rows = parse_csv(&csv);
    assert_eq!(rows.len(), 2);
    for r in &rows {
        assert!(!r.contains_key("source"), "{r:?}");
        for (k, v) in r {
            assert!(v.chars().count() <= 80, "{k} = '{v}' ({} characters)", v.chars().count());
        }
    }
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

/// The GNU parallel recipe of docs/scale.md, run as written (with a smaller set); its merge
/// equals one run.
#[test]
#[cfg_attr(
    not(gnu_parallel),
    ignore = "needs GNU parallel on PATH (Debian package `parallel`; once installed, `touch build.rs`)"
)]
fn docs_gnu_parallel_recipe() {
    let doc = std::fs::read_to_string(repo().join("docs/scale.md")).unwrap();
    let block = doc.split("<!-- recipe:parallel -->").nth(1).unwrap().split("<!-- /recipe -->").next().unwrap();
    let script: String = block.lines().filter(|l| !l.starts_with("```")).collect::<Vec<_>>().join("\n");
    assert!(script.contains("3000000"));
    // 2000 probes: with every encoder (the SG fits cost tens of ms a probe) 20,000 took 18 min.
    let script = script.replace("3000000", "2000");
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
    assert!(
        out.status.success(),
        "the recipe failed ({}):\nstdout:\n{}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let merged = std::fs::read_to_string(dir.path().join("summary.csv")).unwrap();
    let whole = stdout_ok(&run_in(&["probes", "--synth", "2000", "--seed", "7", "--encoders", "all"], dir.path()));
    assert_eq!(figures(&merged), figures(&whole));
}

/// The bad-probe corpus `tests/bad_probes/`: one small file per kind of bad probe file, written
/// by [`probe_kinds`] (regenerate with `PROBELAB_REGEN_BAD_INPUTS=1 cargo test --test
/// probe_sets`). Each is a probe file that broke the scoring, or a member of its class: values that would overflow
/// the scoring (refused with the line or probe index and field), and files without a single
/// probe (refused, where they used to print `rmse_mean 0` and exit 0).
fn probe_kinds() -> Vec<(&'static str, Vec<u8>, &'static [&'static str])> {
    let row = |v: &str| format!("{}\n", vec![v; 27].join(","));
    let f32s = |v: f32| (0..27).flat_map(|_| v.to_le_bytes()).collect::<Vec<u8>>();
    vec![
        ("overflow_1e160.csv", row("1e160").into_bytes(), &[":1: field 1 ('1e160') is out of range", "1e30"]),
        (
            "overflow_line_5.csv",
            format!("# probes\n{}\n{}{}", row("0.5"), row("1"), row("-2e31")).into_bytes(),
            &[":5: field 1 ('-2e31') is out of range"],
        ),
        (
            "overflow_f32_max.f32",
            [f32s(1.0), f32s(3.0e38)].concat(),
            &[": probe 1 (byte 108), value 1", "out of range"],
        ),
        ("header_only.csv", b"c0_r,c0_g,c0_b\n".to_vec(), &["no probes"]),
        ("comment_only.csv", b"# a comment\n# and another\n".to_vec(), &["no probes"]),
        ("blank_lines.csv", b"\n \n\t\n".to_vec(), &["no probes"]),
        ("empty.csv", Vec::new(), &["no probes"]),
        ("empty.f32", Vec::new(), &["empty probe file (0 bytes)"]),
    ]
}

fn bad_probe_dir() -> PathBuf {
    repo().join("tests").join("bad_probes")
}

#[test]
fn bad_probe_corpus_is_current() {
    if std::env::var_os("PROBELAB_REGEN_BAD_INPUTS").is_some() {
        std::fs::create_dir_all(bad_probe_dir()).unwrap();
        for (file, bytes, _) in probe_kinds() {
            std::fs::write(bad_probe_dir().join(file), bytes).unwrap();
        }
    }
    let kinds = probe_kinds();
    for (file, bytes, _) in &kinds {
        let committed = std::fs::read(bad_probe_dir().join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(committed == *bytes, "{file} differs from its generator");
    }
    for e in std::fs::read_dir(bad_probe_dir()).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        assert!(kinds.iter().any(|k| k.0 == name) || name == "fuzz", "{name} is not made by the generator");
    }
}

/// Every bad probe file: exit 2, an error naming the file (and line or probe) and the fault,
/// nothing on stdout, for every registered encoder, whole and as a shard.
#[test]
fn bad_probe_corpus_fails_cleanly() {
    let dir = bad_probe_dir();
    for (file, _, words) in probe_kinds() {
        for shard in ["0/1", "1/2"] {
            let out = run_in(&["probes", "--input", file, "--encoders", "all", "--shard", shard], &dir);
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{file} {shard}: {err}");
            // `--encoders all` first notes on stderr which encoders a probe cannot score.
            assert!(err.lines().any(|l| l.starts_with(&format!("error: {file}"))), "{file} {shard}: {err}");
            for w in words {
                assert!(err.contains(w), "{file} {shard}: lacks '{w}': {err}");
            }
            assert!(!err.contains("panicked"), "{err}");
            assert!(out.stdout.is_empty(), "{file} {shard}: output on stdout");
        }
    }
}

/// At the range's edge every registered encoder still scores finitely; and a shard holding no
/// probe (shard 1 of 2 of a one-probe file) prints empty statistics, never 0.
#[test]
fn edge_of_the_range_and_empty_shards() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let big: Vec<String> =
        (0..27).map(|k| if k % 4 == 0 { "-1e30".into() } else { format!("{}e29", k % 9 + 1) }).collect();
    std::fs::write(d.join("edge.csv"), format!("{}\n{}\n", big.join(","), vec!["1e-300"; 27].join(","))).unwrap();
    let csv = stdout_ok(&run_in(&["probes", "--input", "edge.csv", "--encoders", "all"], d));
    for r in parse_csv(&csv) {
        for col in ["rmse_mean", "rmse_max", "rel_rmse_mean", "rel_rmse_max"] {
            let v: f64 = r[col].parse().unwrap_or_else(|_| panic!("{}: {col} = '{}'", r["encoder"], r[col]));
            assert!(v.is_finite(), "{}: {col} = {v}", r["encoder"]);
        }
        assert_eq!(r["invalid"], "0");
    }
    std::fs::write(d.join("one.csv"), format!("{}\n", vec!["1"; 27].join(","))).unwrap();
    let csv = stdout_ok(&run_in(&["probes", "--input", "one.csv", "--shard", "0/2", "--encoders", "sh1,sh2"], d));
    for r in parse_csv(&csv) {
        assert_eq!(r["probes"], "0");
        for col in ["rmse_mean", "rmse_p50", "rmse_max", "rel_rmse_mean", "rel_rmse_max", "reduction_vs_sh1"] {
            assert_eq!(r[col], "", "{}: {col} of no probes", r["encoder"]);
        }
    }
}

/// Merging shards: `merge` refuses shards of different sets, repeated shards, counts that
/// overflow or do not add up, and corrupt exact-sum digits; each names the file.
#[test]
fn merge_refuses_mismatched_or_corrupt_shards() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Two different .f32 sets with one name and one size, in two folders.
    for (sub, seed) in [("a", "1"), ("b", "2")] {
        std::fs::create_dir_all(d.join(sub)).unwrap();
        let save = format!("{sub}/set.f32");
        stdout_ok(&run_in(&["probes", "--synth", "40", "--seed", seed, "--encoders", "sh1", "--save", &save], d));
    }
    let shard = |set: &str, i: usize| {
        let (input, out) = (format!("{set}/set.f32"), format!("{set}{i}.toml"));
        let s = format!("{i}/2");
        stdout_ok(&run_in(&["probes", "--input", &input, "--encoders", "sh1", "--shard", &s, "--out", &out], d));
        out
    };
    let (a0, b1, a1) = (shard("a", 0), shard("b", 1), shard("a", 1));
    stdout_ok(&run_in(&["merge", &a0, &a1], d));
    let text = std::fs::read_to_string(d.join(&a0)).unwrap();
    let edited = |name: &str, from: &str, to: &str| {
        assert!(text.contains(from), "{from} not in the state");
        std::fs::write(d.join(name), text.replacen(from, to, 1)).unwrap();
        name.to_string()
    };
    let dup = edited("dup.toml", "shards = [0]", "shards = [0, 0]");
    let wrap = edited("wrap.toml", "probes = 20", "probes = 18446744073709551615");
    let digits = text.split("sum_digits = [[").nth(1).unwrap();
    let digit = digits.split(']').next().unwrap().split(", ").nth(1).unwrap().to_string();
    let corrupt = edited("digit.toml", &format!(", {digit}]"), ", 99999999999]");
    for (files, want) in [
        (vec![a0.as_str(), b1.as_str()], "different probe sets"),
        (vec![dup.as_str(), a1.as_str()], "dup.toml: shards [0, 0] must be strictly increasing"),
        (vec![wrap.as_str(), a1.as_str()], "wrap.toml: corrupt statistics: encoder sh1: counts do not add up"),
        (vec![corrupt.as_str(), a1.as_str()], "digit.toml: corrupt statistics"),
        (vec![a0.as_str(), a0.as_str()], "appears twice"),
    ] {
        let mut args = vec!["merge"];
        args.extend(&files);
        let out = run_in(&args, d);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{files:?}: {err}");
        assert!(err.contains(want), "{files:?}: {err}");
        assert!(out.stdout.is_empty());
    }
}
