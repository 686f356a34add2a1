//! `reproduce` on a machine that has only some of an experiment's maps (a fresh clone has the
//! CC0 maps of `envmaps/` but not the paper probes): the experiment runs on the maps found,
//! those rows are compared with the committed baseline, the baseline is never rewritten from
//! the partial run, a moved number fails the command, and an experiment with no map found is
//! skipped and listed.

mod common;

use common::harness::{repo, vouch_for, Run, Scratch};
use std::process::Output;

fn text(o: &Output) -> (String, String) {
    (String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// `reproduce` on `root` (no timing pass: tables are compared byte for byte).
fn reproduce(root: &Scratch) -> Output {
    root.probelab().args(["--no-timing", "reproduce"]).run()
}

/// The summary line `reproduce` prints for experiment `x`.
fn summary_line(stdout: &str) -> String {
    stdout
        .lines()
        .map(str::trim)
        .find(|l| l.starts_with("x: "))
        .unwrap_or_else(|| panic!("no line for x:\n{stdout}"))
        .into()
}

/// The baseline files of experiment x (what only `bless` or a complete run may write; the
/// report step redraws the folder's README and sheets on every reproduce).
fn baseline(root: &Scratch) -> Vec<Vec<u8>> {
    ["table.csv", "provenance.toml"].map(|f| std::fs::read(root.path().join("results/x").join(f)).unwrap()).to_vec()
}

/// The count in "... N numbers compared ...".
fn numbers_compared(line: &str) -> usize {
    let before = line.split(" numbers compared").next().unwrap();
    before.rsplit(' ').next().unwrap().parse().unwrap_or_else(|_| panic!("no count in {line}"))
}

#[test]
fn an_experiment_missing_some_maps_is_checked_on_the_others_and_never_rewritten() {
    let root = Scratch::new();
    root.copy_from_repo("tolerances.toml");
    // Two maps under names of their own, so that removing one file removes one map.
    for (name, src) in [("a", "gen_sun_sky"), ("b", "gen_two_lights")] {
        let bytes = std::fs::read(repo().join("envmaps").join(format!("{src}.exr"))).unwrap();
        root.write(&format!("envmaps/{name}.exr"), bytes);
    }
    root.write("experiments/x.toml", "maps = ['a', 'b']\nencoders = ['sh1', 'sh2']\nresolution = [32, 16]\n");

    // Every map here: a new baseline, then a second run that matches it.
    let out = reproduce(&root);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stdout}{stderr}");
    assert_eq!(summary_line(&stdout), "x: 2 of 2 maps; no baseline yet: new baseline written");
    let out = reproduce(&root);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stdout}{stderr}");
    let full = summary_line(&stdout);
    assert!(full.starts_with("x: 2 of 2 maps; ") && full.contains("nothing moved"), "{full}");
    let all = numbers_compared(&full);
    let kept = baseline(&root);

    // Map b gone: a's rows are compared (the two maps have the same rows and columns, so half
    // the numbers), and the baseline, b's rows included, stays byte for byte.
    std::fs::remove_file(root.path().join("envmaps/b.exr")).unwrap();
    let out = reproduce(&root);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stdout}{stderr}");
    let line = summary_line(&stdout);
    assert!(line.starts_with("x: 1 of 2 maps (missing: b); "), "{line}");
    assert!(line.contains("nothing moved; baseline left unchanged"), "{line}");
    assert_eq!(2 * numbers_compared(&line), all, "{line} against {full}");
    assert!(baseline(&root) == kept, "a partial run rewrote the baseline");

    // A number of a's rows moved in the baseline (its provenance re-vouching for the edit):
    // the partial run fails and writes nothing.
    let table_path = root.path().join("results/x/table.csv");
    let table = std::fs::read_to_string(&table_path).unwrap();
    let mut reader = csv::Reader::from_reader(table.as_bytes());
    let header = reader.headers().unwrap().clone();
    let col = |n: &str| header.iter().position(|c| c == n).unwrap();
    let mut writer = csv::Writer::from_writer(Vec::new());
    writer.write_record(&header).unwrap();
    for r in reader.records() {
        let mut cells: Vec<String> = r.unwrap().iter().map(String::from).collect();
        if cells[col("map")] == "a" && cells[col("encoder")] == "sh1" {
            let v: f64 = cells[col("rmse")].parse().unwrap();
            cells[col("rmse")] = format!("{}", v * 1.5 + 1e-3);
        }
        writer.write_record(&cells).unwrap();
    }
    let edited = String::from_utf8(writer.into_inner().unwrap()).unwrap();
    assert_ne!(edited, table);
    std::fs::write(&table_path, &edited).unwrap();
    let prov_path = root.path().join("results/x/provenance.toml");
    vouch_for(&prov_path, edited.as_bytes());
    let before = baseline(&root);
    let out = reproduce(&root);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    let line = summary_line(&stdout);
    assert!(line.starts_with("x: 1 of 2 maps (missing: b); ") && line.contains("FAILED (1 moved)"), "{line}");
    assert!(stderr.contains("x: moved"), "{stderr}");
    assert!(baseline(&root) == before, "a failing partial run wrote");

    // No map at all: skipped and listed, nothing compared, exit 0.
    std::fs::remove_file(root.path().join("envmaps/a.exr")).unwrap();
    let out = reproduce(&root);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stdout}{stderr}");
    assert_eq!(summary_line(&stdout), "x: skipped, 0 of 2 maps (missing: a, b)");
    // Each missing map once, with the fix once; one closing line of what was not reproduced.
    assert!(stdout.contains("  a (read by 1 experiment(s))\n  b (read by 1 experiment(s))\n"), "{stdout}");
    assert_eq!(stdout.matches("PROBELAB_ENVMAPS").count(), 1, "{stdout}");
    // What it found is on stdout, ending with where the report is; stderr has no result line.
    assert!(stdout.trim_end().ends_with("REPORT.md"), "{stdout}");
    assert!(stdout.contains("claims: none declared"), "{stdout}");
    assert!(!stderr.contains("wrote ") && !stderr.contains("PROBELAB_ENVMAPS"), "{stderr}");
    assert!(
        stdout.contains("not reproduced here: 2 map(s) missing (a, b): 1 experiment(s) skipped, 0 run"),
        "{stdout}"
    );
    assert!(baseline(&root) == before);
}

/// A partial run with no baseline to compare with writes none (a baseline holds every map).
#[test]
fn a_partial_run_without_a_baseline_writes_nothing() {
    let root = Scratch::new();
    root.copy_from_repo("tolerances.toml");
    let bytes = std::fs::read(repo().join("envmaps/gen_constant.exr")).unwrap();
    root.write("envmaps/a.exr", bytes);
    root.write("experiments/x.toml", "maps = ['a', 'nowhere']\nencoders = ['sh1']\nresolution = [16, 8]\n");
    let out = reproduce(&root);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stdout}{stderr}");
    assert_eq!(
        summary_line(&stdout),
        "x: 1 of 2 maps (missing: nowhere); no baseline to compare with, nothing written"
    );
    assert!(!root.path().join("results/x/table.csv").exists());
}
