//! Interrupted runs lose nothing: a run that fails halfway, by an error or a kill, leaves every
//! previous `results/` file byte-identical, and never a truncated or half-written one.
//!
//! The failure is injected with real bad input (the second map of a run, or the second
//! experiment of a reproduce, is a corrupt file from `tests/bad_inputs/`), so no test-only
//! hook lives in the program. The kill test spawns `probelab reproduce`, freezes it at every
//! moment its results change and kills it (SIGKILL) near its end, and checks each results file
//! is exactly its old bytes or exactly the bytes a complete run writes.

mod common;

use common::harness::{repo, Run, Scratch};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// The binary on the scratch repository `root`, finding the repository's maps (`envmaps/`).
fn probelab(root: &Scratch) -> Command {
    let mut c = root.probelab();
    // Timings differ between two complete runs; these tests compare files byte for byte.
    c.arg("--no-timing").env("PROBELAB_ENVMAPS", repo().join("envmaps"));
    c
}

fn run(root: &Scratch, args: &[&str]) -> Output {
    probelab(root).args(args).run()
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

/// The `results/` files of `root` with their bytes (hidden temporary files included), with the
/// run's dates blanked: they differ between two complete runs, and nothing else may.
fn results(root: &Scratch) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = root.snapshot("results");
    for (p, bytes) in files.iter_mut() {
        if p.file_name().is_some_and(|n| n == "provenance.toml") {
            let text = String::from_utf8(std::mem::take(bytes)).unwrap();
            *bytes = text.lines().filter(|l| !l.starts_with("date = ")).collect::<Vec<_>>().join("\n").into_bytes();
        }
        if p.file_name().is_some_and(|n| n == "REPORT.md" || n == "PROVENANCE.md") {
            // The report quotes those dates (from provenance.toml): blank them too, and the span
            // they make. Tables written within one second read "on <date>", across a second's
            // boundary "on <date> to <date>": which one depends on the machine's load, not on
            // whether the file is old or new.
            let text = blank_dates(&String::from_utf8(std::mem::take(bytes)).unwrap());
            *bytes = text.replace("<date> to <date>", "<date>").into_bytes();
        }
    }
    files
}

/// A scratch repository with experiments/ holding `experiments` (name, text) and results/
/// holding one unrelated table. (Experiments get no old table: an existing table is a baseline
/// that only `bless` may change, so a run with new numbers would refuse to write it.)
fn root_with(experiments: &[(&str, String)]) -> Scratch {
    let root = Scratch::new();
    root.copy_from_repo("tolerances.toml");
    for (name, text) in experiments {
        root.write(&format!("experiments/{name}.toml"), text);
    }
    root.write("results/unrelated/table.csv", "map,encoder\nkeep,me\n");
    root
}

/// Every registered encoder (`sphere`: those an experiment on the sphere accepts, i.e. all but
/// the ones that need a surface normal).
fn encoder_list(sphere: bool) -> String {
    probelab::encoders::REGISTRY
        .iter()
        .filter(|k| !sphere || !probelab::needs_surface_normal(k.id).unwrap())
        .map(|k| format!("'{}'", k.id))
        .collect::<Vec<_>>()
        .join(", ")
}

fn bad_map() -> String {
    repo().join("tests/bad_inputs/truncated_pixels.exr").display().to_string()
}

/// The maps of these runs: the repository's CC0 maps of 256×128 texels. What these tests check
/// (each results file is its old bytes or a complete run's, a failed run writes nothing) does
/// not depend on the maps' content or size; at a sixteenth of the generated scenes' texels a
/// `reproduce` costs less than half the CPU (most of it is the report's sheets), and the kill
/// test runs several.
const MAPS: [&str; 3] = ["blender_city_256x128", "pmndrs_dawn_256x128", "blender_studio_256x128"];

fn good_experiment() -> String {
    format!("maps = ['{}', '{}']\nencoders = [{}]\nresolution = [32, 16]\n", MAPS[0], MAPS[1], encoder_list(true))
}

#[test]
fn a_map_that_fails_second_writes_nothing() {
    let text = format!(
        "maps = ['{}', '{}']\nencoders = [{}]\nresolution = [32, 16]\n",
        MAPS[0],
        bad_map(),
        encoder_list(true)
    );
    let root = root_with(&[("first_good_then_bad", text)]);
    let before = results(&root);
    let out = run(&root, &["run", root.path().join("experiments/first_good_then_bad.toml").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("truncated_pixels.exr: file is truncated"));
    assert!(results(&root) == before, "results/ changed");
}

/// Two experiments on one command line, or in experiments/ for `reproduce`: the first
/// succeeds, the second fails while running; the first's results are not written either.
#[test]
fn an_experiment_that_fails_second_writes_nothing() {
    let bad = format!("maps = ['{}']\nencoders = ['sh1']\nresolution = [32, 16]\n", bad_map());
    let root = root_with(&[("a_good", good_experiment()), ("b_bad", bad)]);
    let before = results(&root);
    let exps = root.path().join("experiments");
    let out =
        run(&root, &["run", exps.join("a_good.toml").to_str().unwrap(), exps.join("b_bad.toml").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(results(&root) == before, "run: results/ changed");
    let out = run(&root, &["reproduce"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(results(&root) == before, "reproduce: results/ changed");
    // Without the bad experiment the same run writes a_good's table.
    std::fs::remove_file(exps.join("b_bad.toml")).unwrap();
    let out = run(&root, &["reproduce"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let after = results(&root);
    assert!(after[Path::new("a_good/table.csv")].starts_with(b"map,encoder,domain,metric"));
    assert_eq!(after[Path::new("unrelated/table.csv")], before[Path::new("unrelated/table.csv")]);
}

/// A `reproduce` killed at any moment leaves each results file either as it was or exactly
/// as a complete run writes it.
///
/// One run is frozen (SIGSTOP) each time its `results/` folder is seen to change (a file, a
/// hidden temporary file of an atomic write, or a size appears or goes), checked, and resumed;
/// near its end, when all but one of the complete run's files are there, it is killed (SIGKILL)
/// and checked once more. SIGKILL ends a process where it stands, without running anything of
/// it, so a frozen run's files are exactly what a kill at that moment leaves: the stops are
/// kills at every moment the files change, taken from one run instead of one run per kill,
/// and chosen by the run's own writes instead of by fractions of a measured duration.
#[test]
fn a_killed_reproduce_leaves_old_or_complete_files() {
    let (ids, all) = (encoder_list(true), encoder_list(false));
    let exps = [
        (
            "k1_sphere",
            format!("maps = ['{}', '{}']\nencoders = [{ids}]\nresolution = [32, 16]\n", MAPS[1], MAPS[0]),
        ),
        (
            "k2_walls",
            format!("maps = ['{}']\nencoders = [{all}]\ndomain = 'hemisphere'\norientations = ['axes6']\neffects = ['hemisphere']\nresolution = [16, 8]\n", MAPS[2]),
        ),
        ("k3_small", good_experiment()),
    ];
    // The bytes a complete run writes.
    let complete = root_with(&exps);
    let out = run(&complete, &["reproduce"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let new = results(&complete);
    let old = results(&root_with(&exps));
    let last = new.keys().filter(|n| !old.contains_key(*n)).count() - 1;

    let root = root_with(&exps);
    let child = probelab(&root).arg("reproduce").stdout(Stdio::null()).stderr(Stdio::null()).spawn().unwrap();
    let mut run = Frozen(child);
    let (mut seen, mut stops) = (listing(&root.path().join("results")), 0);
    let status = loop {
        if let Some(status) = run.0.try_wait().unwrap() {
            old_or_complete(&root, &old, &new, "finished");
            break status;
        }
        let now = listing(&root.path().join("results"));
        if now == seen {
            std::thread::sleep(std::time::Duration::from_millis(2));
            continue;
        }
        run.stop();
        stops += 1;
        let written = old_or_complete(&root, &old, &new, &format!("stop {stops}"));
        if written >= last {
            let _ = run.0.kill();
            let status = run.0.wait().unwrap();
            old_or_complete(&root, &old, &new, &format!("killed after stop {stops}"));
            break status;
        }
        seen = listing(&root.path().join("results"));
        run.resume();
    };
    println!("{stops} stops, the run then {status}");
    assert!(stops >= 3, "only {stops} moments seen: the run wrote its files faster than they were watched");
}

/// A run that is killed if the test ends first (a stopped run would wait forever).
struct Frozen(std::process::Child);

impl Frozen {
    /// Freezes the run and waits until every thread of it has stopped.
    fn stop(&self) {
        let pid = self.0.id();
        // SAFETY: a signal to our own child, which has not been waited for.
        unsafe { libc::kill(pid as i32, libc::SIGSTOP) };
        let tasks = PathBuf::from(format!("/proc/{pid}/task"));
        while std::fs::read_dir(&tasks).into_iter().flatten().flatten().any(|t| {
            let stat = std::fs::read_to_string(t.path().join("stat")).unwrap_or_default();
            let state = stat.rsplit(')').next().and_then(|r| r.split_whitespace().next()).unwrap_or("X");
            !matches!(state, "T" | "t" | "Z" | "X")
        }) {
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
    }

    fn resume(&self) {
        // SAFETY: as in `stop`.
        unsafe { libc::kill(self.0.id() as i32, libc::SIGCONT) };
    }
}

impl Drop for Frozen {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The files under `dir` with their sizes, tolerating files that go while it looks.
fn listing(dir: &Path) -> BTreeMap<PathBuf, u64> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            match e.metadata() {
                Ok(m) if m.is_dir() => stack.push(e.path()),
                Ok(m) => drop(out.insert(e.path(), m.len())),
                Err(_) => {}
            }
        }
    }
    out
}

/// Checks that each results file of `root` is its old bytes or the complete run's (a hidden
/// temporary file of an interrupted atomic write is never a results file), and that no old
/// file disappeared; returns how many non-hidden files are new.
fn old_or_complete(
    root: &Scratch,
    old: &BTreeMap<PathBuf, Vec<u8>>,
    new: &BTreeMap<PathBuf, Vec<u8>>,
    when: &str,
) -> usize {
    let after = results(root);
    let mut written = 0;
    for (name, bytes) in &after {
        if name.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.starts_with('.')) {
            continue;
        }
        let (as_old, as_new) = (old.get(name) == Some(bytes), new.get(name) == Some(bytes));
        assert!(as_old || as_new, "{when}: {} is neither old nor complete", name.display());
        written += usize::from(as_new && !as_old);
    }
    for name in old.keys() {
        assert!(after.contains_key(name), "{when}: {} disappeared", name.display());
    }
    written
}

/// A report is old or new whatever the clock did: one run's tables written within one second
/// and another's across a second's boundary give the same bytes once dates are blanked (the
/// comparison the kill test makes; a loaded machine spreads the writes over more seconds).
#[test]
fn the_comparison_of_reports_does_not_depend_on_the_seconds_the_tables_took() {
    let line =
        |dates: &str| format!("**How this run was made.** 3 tables, computed at commit `abc` on {dates} (UTC).\n");
    let (one, two) = (Scratch::new(), Scratch::new());
    one.write("results/REPORT.md", &line("2026-01-01T00:00:59Z"));
    two.write("results/REPORT.md", &line("2026-01-01T00:00:59Z to 2026-01-01T00:01:00Z"));
    assert!(results(&one) == results(&two));
    // A different report still differs.
    two.write("results/REPORT.md", &line("2026-01-01T00:00:59Z").replace("3 tables", "2 tables"));
    assert!(results(&one) != results(&two));
}
