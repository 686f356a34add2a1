//! `reproduce` run twice in a row changes no file: the second run finds its baselines, matches
//! them and writes nothing new, and the report it regenerates holds the same bytes, which the
//! atomic writer leaves untouched. The runs keep the timing pass on (as a user's `reproduce`
//! does): `fit_ns`/`eval_ns` differ between runs by nature, and must not rewrite a table. And
//! after a `bless`, a `reproduce` rewrites no baseline file: `bless` writes the summary with
//! the table it derives from (a stale summary beside a blessed table was rewritten by the next
//! `reproduce` on every fresh clone).

mod common;

use common::harness::{repo, Scratch};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// Every file under `dir` (recursively, hidden files included) with the sha256 of its bytes
/// and its modification time, keyed by its path relative to `dir`.
fn state(dir: &Path) -> BTreeMap<PathBuf, (String, SystemTime)> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let hash = common::harness::sha256_hex(&std::fs::read(&p).unwrap());
                let mtime = std::fs::metadata(&p).unwrap().modified().unwrap();
                out.insert(p.strip_prefix(dir).unwrap().to_path_buf(), (hash, mtime));
            }
        }
    }
    out
}

/// The files whose content or modification time differ between two states, or that one of
/// them lacks.
fn changed(a: &BTreeMap<PathBuf, (String, SystemTime)>, b: &BTreeMap<PathBuf, (String, SystemTime)>) -> Vec<String> {
    let names: std::collections::BTreeSet<&PathBuf> = a.keys().chain(b.keys()).collect();
    names
        .into_iter()
        .filter(|n| a.get(*n) != b.get(*n))
        .map(|n| {
            let what = match (a.get(n), b.get(n)) {
                (Some(x), Some(y)) if x.0 != y.0 => "content",
                (Some(_), Some(_)) => "mtime",
                (None, _) => "created",
                (_, None) => "removed",
            };
            format!("{} ({what})", n.display())
        })
        .collect()
}

#[test]
fn a_second_reproduce_changes_no_file() {
    let root = Scratch::new();
    root.copy_from_repo("tolerances.toml");
    root.copy_from_repo("experiments/report/papers.toml");
    // Two CC0 maps of the repository at 256x128, on the sphere and on a hemisphere: a table,
    // its provenance, sheets and charts per experiment, and the report's pages.
    for m in ["blender_city_256x128", "pmndrs_dawn_256x128"] {
        root.write(
            &format!("envmaps/{m}.exr"),
            std::fs::read(repo().join("envmaps").join(format!("{m}.exr"))).unwrap(),
        );
    }
    root.write(
        "experiments/sphere.toml",
        "maps = ['blender_city_256x128', 'pmndrs_dawn_256x128']\nencoders = ['sh1', 'sh2', 'geomerics']\n\
         resolution = [32, 16]\n[summary]\nbaseline = 'sh1'\n",
    );
    root.write(
        "experiments/floor.toml",
        "maps = ['pmndrs_dawn_256x128']\nencoders = ['sh1', 'sh2']\ndomain = 'hemisphere'\n\
         orientations = ['up']\neffects = ['hemisphere']\nresolution = [16, 8]\n",
    );
    let first = root.run(&["reproduce"]);
    assert!(first.status.success(), "{}", String::from_utf8_lossy(&first.stderr));
    let before = state(root.path());
    assert!(before.contains_key(Path::new("results/sphere/table.csv")), "{:?}", before.keys().collect::<Vec<_>>());
    assert!(before.contains_key(Path::new("results/REPORT.md")));
    assert!(before.keys().any(|p| p.starts_with("results/sphere") && p.extension().is_some_and(|e| e == "png")));
    // A later second, so a rewrite shows in the modification time on any file system.
    std::thread::sleep(std::time::Duration::from_millis(1100));
    let second = root.run(&["reproduce"]);
    assert!(second.status.success(), "{}", String::from_utf8_lossy(&second.stderr));
    assert_eq!(changed(&before, &state(root.path())), Vec::<String>::new(), "files the second reproduce changed");

    // A summary left from an older run beside the table: `bless` rewrites both together, and
    // the next `reproduce` finds nothing of the baseline to rewrite.
    let summary = root.path().join("results/sphere/summary.csv");
    assert!(summary.is_file());
    std::fs::write(&summary, "stale\n").unwrap();
    let bless = root.run(&["bless", "--force", "sphere", "floor"]);
    assert!(bless.status.success(), "{}", String::from_utf8_lossy(&bless.stderr));
    assert_ne!(std::fs::read(&summary).unwrap(), b"stale\n", "bless rewrote the summary with its table");
    let baseline = |s: &BTreeMap<PathBuf, (String, SystemTime)>| {
        let keep = |p: &PathBuf| ["table.csv", "provenance.toml", "summary.csv"].iter().any(|f| p.ends_with(f));
        s.iter().filter(|(p, _)| keep(p)).map(|(p, v)| (p.clone(), v.clone())).collect::<BTreeMap<_, _>>()
    };
    let blessed = baseline(&state(root.path()));
    assert_eq!(blessed.len(), 5, "{:?}", blessed.keys().collect::<Vec<_>>());
    std::thread::sleep(std::time::Duration::from_millis(1100));
    let third = root.run(&["reproduce"]);
    assert!(third.status.success(), "{}", String::from_utf8_lossy(&third.stderr));
    assert_eq!(changed(&blessed, &baseline(&state(root.path()))), Vec::<String>::new(), "after bless");
}
