//! Losing nothing (issue 8): a run that fails halfway, by an error or a kill, leaves every
//! previous `results/` file byte-identical, and never a truncated or half-written one.
//!
//! The failure is injected with real bad input (the second map of a run, or the second
//! experiment of a reproduce, is a corrupt file from `tests/bad_inputs/`), so no test-only
//! hook lives in the program. The kill test spawns `probelab reproduce`, kills it (SIGKILL) at
//! several moments spread over its run time, and checks each results file is exactly its old
//! bytes or exactly the bytes a complete run writes.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Instant;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn probelab(root: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_probelab"));
    // Timings differ between two complete runs; these tests compare files byte for byte.
    c.arg("--no-timing").arg("--root").arg(root).env("PROBELAB_ENVMAPS", repo().join("envmaps"));
    c
}

fn run(root: &Path, args: &[&str]) -> Output {
    probelab(root).args(args).output().expect("run probelab")
}

/// `text` with every ISO 8601 UTC time `YYYY-MM-DDThh:mm:ssZ` replaced by `<date>`.
fn blank_dates(text: &str) -> String {
    let shape = |w: &[u8]| {
        w.len() == 20
            && w.iter().enumerate().all(|(i, &c)| match i {
                4 | 7 => c == b'-',
                10 => c == b'T',
                13 | 16 => c == b':',
                19 => c == b'Z',
                _ => c.is_ascii_digit(),
            })
    };
    let b = text.as_bytes();
    let (mut out, mut i) = (String::new(), 0);
    while i < b.len() {
        if i + 20 <= b.len() && shape(&b[i..i + 20]) {
            out.push_str("<date>");
            i += 20;
        } else {
            let ch = text[i..].chars().next().unwrap();
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    out
}

/// Every file under `dir` with its bytes (hidden temporary files included).
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = fs::read_dir(&d) else { continue };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let mut bytes = fs::read(&p).unwrap();
                if p.file_name().is_some_and(|n| n == "provenance.toml") {
                    // The run's date differs between two complete runs; everything else must not.
                    let text = String::from_utf8(bytes).unwrap();
                    bytes =
                        text.lines().filter(|l| !l.starts_with("date = ")).collect::<Vec<_>>().join("\n").into_bytes();
                }
                if p.file_name().is_some_and(|n| n == "REPORT.md") {
                    // The report quotes those dates (from provenance.toml): blank them too.
                    bytes = blank_dates(&String::from_utf8(bytes).unwrap()).into_bytes();
                }
                out.insert(p.strip_prefix(dir).unwrap().to_path_buf(), bytes);
            }
        }
    }
    out
}

/// A root with experiments/ holding `experiments` (name, text) and results/ holding one
/// unrelated table. (Experiments get no old table: an existing table is a baseline that only
/// `bless` may change, so a run with new numbers would refuse to write it.)
fn root_with(experiments: &[(&str, String)]) -> tempfile::TempDir {
    let root = tempfile::tempdir().unwrap();
    fs::create_dir_all(root.path().join("experiments")).unwrap();
    fs::copy(repo().join("tolerances.toml"), root.path().join("tolerances.toml")).unwrap();
    for (name, text) in experiments {
        fs::write(root.path().join("experiments").join(format!("{name}.toml")), text).unwrap();
    }
    let other = root.path().join("results/unrelated");
    fs::create_dir_all(&other).unwrap();
    fs::write(other.join("table.csv"), "map,encoder\nkeep,me\n").unwrap();
    root
}

fn encoder_list() -> String {
    probelab::encoders::REGISTRY.iter().map(|k| format!("'{}'", k.id)).collect::<Vec<_>>().join(", ")
}

fn bad_map() -> String {
    repo().join("tests/bad_inputs/truncated_pixels.exr").display().to_string()
}

fn good_experiment() -> String {
    format!("maps = ['gen_constant', 'gen_sun_sky']\nencoders = [{}]\nresolution = [32, 16]\n", encoder_list())
}

#[test]
fn a_map_that_fails_second_writes_nothing() {
    let text =
        format!("maps = ['gen_constant', '{}']\nencoders = [{}]\nresolution = [32, 16]\n", bad_map(), encoder_list());
    let root = root_with(&[("first_good_then_bad", text)]);
    let before = snapshot(&root.path().join("results"));
    let out = run(root.path(), &["run", root.path().join("experiments/first_good_then_bad.toml").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("truncated_pixels.exr: file is truncated"));
    assert!(snapshot(&root.path().join("results")) == before, "results/ changed");
}

/// Two experiments on one command line, or in experiments/ for `reproduce`: the first
/// succeeds, the second fails while running; the first's results are not written either.
#[test]
fn an_experiment_that_fails_second_writes_nothing() {
    let bad = format!("maps = ['{}']\nencoders = ['sh1']\nresolution = [32, 16]\n", bad_map());
    let root = root_with(&[("a_good", good_experiment()), ("b_bad", bad)]);
    let results = root.path().join("results");
    let before = snapshot(&results);
    let exps = root.path().join("experiments");
    let out = run(
        root.path(),
        &["run", exps.join("a_good.toml").to_str().unwrap(), exps.join("b_bad.toml").to_str().unwrap()],
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(snapshot(&results) == before, "run: results/ changed");
    let out = run(root.path(), &["reproduce"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(snapshot(&results) == before, "reproduce: results/ changed");
    // Without the bad experiment the same run writes a_good's table.
    fs::remove_file(exps.join("b_bad.toml")).unwrap();
    let out = run(root.path(), &["reproduce"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let after = snapshot(&results);
    assert!(after[Path::new("a_good/table.csv")].starts_with(b"map,encoder,domain,metric"));
    assert_eq!(after[Path::new("unrelated/table.csv")], before[Path::new("unrelated/table.csv")]);
}

/// A `reproduce` killed at any moment leaves each results file either as it was or exactly
/// as a complete run writes it.
#[test]
fn a_killed_reproduce_leaves_old_or_complete_files() {
    let ids = encoder_list();
    let exps = [
        (
            "k1_sphere",
            format!("maps = ['gen_sun_sky', 'gen_two_lights']\nencoders = [{ids}]\nresolution = [32, 16]\n"),
        ),
        (
            "k2_walls",
            format!("maps = ['gen_cone']\nencoders = [{ids}]\ndomain = 'hemisphere'\norientations = ['axes6']\neffects = ['hemisphere']\nresolution = [16, 8]\n"),
        ),
        ("k3_small", good_experiment()),
    ];
    // The bytes a complete run writes, and how long it takes.
    let complete = root_with(&exps);
    let t0 = Instant::now();
    let out = run(complete.path(), &["reproduce"]);
    let full = t0.elapsed();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let new = snapshot(&complete.path().join("results"));
    let old = snapshot(&root_with(&exps).path().join("results"));
    println!("a complete reproduce takes {full:?}");

    // Two early kills, then kills creeping up on the end of the run (where the files are
    // written) until one run finishes before its kill.
    let mut fracs = vec![0.2, 0.6];
    fracs.extend((0..10).map(|k| 0.85 + 0.06 * k as f64));
    for frac in fracs {
        let mut outcomes = BTreeMap::new();
        let root = root_with(&exps);
        let mut child =
            probelab(root.path()).arg("reproduce").stdout(Stdio::null()).stderr(Stdio::null()).spawn().unwrap();
        std::thread::sleep(full.mul_f64(frac));
        let _ = child.kill();
        let status = child.wait().unwrap();
        let after = snapshot(&root.path().join("results"));
        for (name, bytes) in &after {
            let hidden = name.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.starts_with('.'));
            if hidden {
                // A temporary file of an interrupted atomic write: never a results file.
                *outcomes.entry("temporary").or_insert(0) += 1;
                continue;
            }
            let as_old = old.get(name) == Some(bytes);
            let as_new = new.get(name) == Some(bytes);
            assert!(as_old || as_new, "killed at {frac:.2} of the run: {} is neither old nor complete", name.display());
            *outcomes.entry(if as_new && !as_old { "new" } else { "old" }).or_insert(0) += 1;
        }
        for name in old.keys() {
            assert!(after.contains_key(name), "killed at {frac:.2}: {} disappeared", name.display());
        }
        println!("killed at {frac:.2} of the run ({status}): {outcomes:?}");
        if status.success() {
            break;
        }
    }
}
