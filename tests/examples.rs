//! The examples (examples/fit_map.rs, examples/compare.rs) run and print what they say. `cargo
//! test` builds them next to the test binaries (target/<profile>/examples/); this test runs
//! those binaries and parses a line of their output. Expected values: the stored-scalar count
//! of ZH3 with a stored coefficient is 3 + 9 + 3 = 15 (L0, L1, k; ZH3 talk), and on the sphere
//! SH L2 is the least-squares projection through band 2, which contains SH L1, so its
//! solid-angle RMSE is no larger than SH L1's. `compare` says which grid it scored on, and its
//! scores are `probelab eval`'s with the command line's defaults (the binary run beside it).

use std::path::PathBuf;
use std::process::Command;

/// The example binary `name`, built by cargo (with this test's profile) into
/// `target/<profile>/examples/<name>`. A plain `cargo test` builds the examples under hashed
/// names, and `cargo test --test examples` not at all, so the test asks cargo for them.
fn example(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let profile = exe.parent().and_then(|deps| deps.parent()).expect("target/<profile>/deps/<test>");
    let mut build = Command::new(env!("CARGO"));
    build.args(["build", "--quiet", "--example", name]).current_dir(env!("CARGO_MANIFEST_DIR"));
    if !cfg!(debug_assertions) {
        build.arg("--release");
    }
    let status = build.status().expect("run cargo");
    assert!(status.success(), "cargo build --example {name} failed");
    let p = profile.join("examples").join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(p.is_file(), "{} not built", p.display());
    p
}

fn run(name: &str, args: &[&str]) -> String {
    let out = Command::new(example(name)).args(args).output().expect("run the example");
    assert!(out.status.success(), "{name} {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).expect("UTF-8")
}

#[test]
fn fit_map_prints_the_stored_coefficients() {
    let text = run("fit_map", &[]);
    let line = text.lines().find_map(|l| l.strip_prefix("stored scalars: ")).expect("a 'stored scalars:' line");
    assert_eq!(line.trim().parse::<usize>().unwrap(), 15, "{text}");
    assert!(text.lines().any(|l| l.trim_start().starts_with("stored  k ")), "{text}");
    // An encoder that needs N, with settings.
    let text = run("fit_map", &["gen_sky_sun", "hhd_linear_hemi", "storage = 'irradz_luma'"]);
    let line = text.lines().find_map(|l| l.strip_prefix("stored scalars: ")).unwrap();
    assert_eq!(line.trim(), "6", "{text}");
    assert!(text.contains("hemisphere about N = (0, 1, 0)"), "{text}");
}

#[test]
fn compare_scores_two_encoders() {
    let text = run("compare", &["sh1", "sh2"]);
    let score = |id: &str| -> f64 {
        let line = text.lines().find(|l| l.starts_with(&format!("{id} rmse="))).expect("a line per encoder");
        let v: f64 = line.split_whitespace().nth(1).unwrap()["rmse=".len()..].parse().unwrap();
        assert!(v.is_finite() && v > 0.0, "{line}");
        v
    };
    let (sh1, sh2) = (score("sh1"), score("sh2"));
    assert!(sh2 <= sh1, "sh2 {sh2} > sh1 {sh1}\n{text}");
}

#[test]
fn compare_says_its_grid_and_gives_the_command_lines_numbers() {
    let text = run("compare", &["sh1", "zh3_hallucinate"]);
    assert!(text.lines().any(|l| l.starts_with("scored over 256x128 normals")), "the grid is not said:\n{text}");
    let out = Command::new(env!("CARGO_BIN_EXE_probelab"))
        .args(["--no-timing", "eval", "blender_city_256x128", "--encoders", "sh1,zh3_hallucinate"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("run probelab eval");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut table = csv::Reader::from_reader(out.stdout.as_slice());
    let header = table.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|c| c == name).unwrap();
    let rows: Vec<csv::StringRecord> = table.records().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), 2);
    for cells in &rows {
        let (id, rmse) = (&cells[col("encoder")], &cells[col("rmse")]);
        assert_eq!(&cells[col("resolution")], "256x128");
        let printed = text.lines().find(|l| l.starts_with(&format!("{id} rmse="))).expect("a line per encoder");
        let theirs: f64 = printed.split_whitespace().nth(1).unwrap()["rmse=".len()..].parse().unwrap();
        let ours: f64 = rmse.parse().unwrap();
        assert!((ours - theirs).abs() <= 1e-12 * ours, "{id}: eval {ours}, compare {theirs}");
    }
}
