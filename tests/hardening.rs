//! Hardening, through the `probelab` binary: each section reproduces one way user input or the
//! environment broke the program (settings out of range, coarse maps, a hang, a failing
//! stdout, concurrent writers, the leftovers of killed runs, and the small things) as it was
//! reported, and checks what the fixed program does instead. Every test here fails on the code
//! before the fixes (commit c18cedd); each test's doc comment says what the old code did.
//!
//! Failures whose home is elsewhere:
//! - chunks that do not store every pixel once: `tests/bad_inputs.rs`, the corpus files
//!   `chunk_*.exr` and `tile_duplicated.exr` through `eval` and `run`;
//! - probe values that overflow, files without probes: `tests/probe_sets.rs`
//!   `bad_probe_corpus_fails_cleanly` on the corpus `tests/bad_probes/`;
//! - `merge` of mismatched or corrupt shards: `tests/probe_sets.rs`
//!   `merge_refuses_mismatched_or_corrupt_shards`.
//!
//! Each writing command here runs on a scratch repository ([`Scratch`]) whose maps are the
//! repository's generated ones (`envmaps/`), on a 16×8 output grid, so each run is cheap.

mod common;

use common::harness::{parse_csv, repo, Run, Scratch};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

// ---------------------------------------------------------------------------------------------
// The scratch repository and its commands.

/// A scratch repository holding `tolerances.toml` and the experiments `(name, text)`.
fn root_with(experiments: &[(&str, &str)]) -> Scratch {
    let root = Scratch::new();
    root.copy_from_repo("tolerances.toml");
    std::fs::create_dir_all(root.path().join("experiments")).unwrap();
    for (name, text) in experiments {
        root.write(&format!("experiments/{name}.toml"), text);
    }
    root
}

/// `probelab --root ROOT --no-timing`, finding the repository's generated maps (timings differ
/// between runs; these tests compare tables byte for byte).
fn probelab(root: &Scratch) -> Command {
    let mut c = root.probelab();
    c.arg("--no-timing").env("PROBELAB_ENVMAPS", repo().join("envmaps"));
    c
}

fn run(root: &Scratch, args: &[&str]) -> Output {
    probelab(root).args(args).run()
}

/// `probelab run` of the scratch repository's experiments `names` (`run` takes files).
fn run_experiments(root: &Scratch, names: &[&str]) -> Output {
    let files: Vec<String> =
        names.iter().map(|n| root.path().join(format!("experiments/{n}.toml")).display().to_string()).collect();
    probelab(root).arg("run").args(&files).run()
}

/// A small experiment: the constant and the sun-and-sky maps, SH L1 and L2, a 16×8 grid.
const SMALL: &str = "maps = ['gen_constant', 'gen_sun_sky']\nencoders = ['sh1', 'sh2']\nresolution = [16, 8]\n";

/// An experiment on `gen_sun_sky` whose line 5 is the encoder entry `entry`.
fn with_encoder(entry: &str) -> String {
    format!("maps = ['gen_sun_sky']\nresolution = [16, 8]\nencoders = [\n  'sh1',\n  {entry},\n]\n")
}

/// The same, on the hemisphere about +Y with its effect (what the lightmap encoders fit).
fn with_lightmap_encoder(entry: &str) -> String {
    format!(
        "maps = ['gen_sun_sky']\nresolution = [16, 8]\nencoders = [\n  'sh1',\n  {entry},\n]\n\
         domain = 'hemisphere'\norientations = ['up']\neffects = ['hemisphere']\n"
    )
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Exit 2 with one `error:` holding every word of `want`, no panic, nothing on stdout.
fn assert_refused(out: &Output, want: &[&str], what: &str) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{what}: exit {:?}: {err}", out.status);
    assert!(err.starts_with("error: "), "{what}: {err}");
    assert!(!err.contains("panicked"), "{what}: a panic: {err}");
    for w in want {
        assert!(err.contains(w), "{what}: the error lacks '{w}': {err}");
    }
    assert!(out.stdout.is_empty(), "{what}: output on stdout");
}

/// Exit 0; the stdout.
fn assert_ok(out: &Output, what: &str) -> String {
    assert!(out.status.success(), "{what}: exit {:?}: {}", out.status, stderr(out));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Waits for `child`, killing it and failing the test if it is still running after ten
/// minutes. Not a speed check (every command here takes well under a second when it works):
/// it turns a hang, what unbounded golden-section settings once caused, into a failure instead of a test run that never ends.
fn wait_or_fail_on_hang(mut child: Child, what: &str) -> Output {
    let limit = std::time::Duration::from_secs(600);
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: still running after {limit:?}: a hang");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// A stdout whose reader has gone away: the write end of a pipe whose read end is closed
/// before the command starts, so its first write fails with EPIPE (what `| head -1` does to
/// the writes after the first line, without the race).
fn closed_pipe() -> Stdio {
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    Stdio::from(writer)
}

/// The identity of every file under `results/` (its inode): a file rewritten by an atomic
/// rename gets a new one, a file left alone keeps its own.
#[cfg(unix)]
fn inodes(root: &Scratch) -> BTreeMap<PathBuf, u64> {
    use std::os::unix::fs::MetadataExt;
    root.snapshot("results")
        .into_keys()
        .map(|p| {
            let ino = std::fs::metadata(root.path().join("results").join(&p)).unwrap().ino();
            (p, ino)
        })
        .collect()
}

/// The hidden temporary files (`.NAME.tmp-…`, `.NAME.old-…`) under `results/`.
fn hidden_temporaries(root: &Scratch) -> Vec<PathBuf> {
    root.snapshot("results")
        .into_keys()
        .filter(|p| p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.starts_with('.')))
        .collect()
}

/// Whether `results/NAME/provenance.toml` describes `results/NAME/table.csv` (its
/// `table_sha256` is the table's): the pair comes from one run.
fn pair_is_consistent(out: &Path, name: &str) -> bool {
    let table = std::fs::read(out.join(name).join("table.csv")).unwrap();
    let prov: toml::Table =
        std::fs::read_to_string(out.join(name).join("provenance.toml")).unwrap().parse().expect("provenance parses");
    prov["table_sha256"].as_str() == Some(common::harness::sha256_hex(&table).as_str())
}

// ---------------------------------------------------------------------------------------------
// Settings out of range: NaN/Inf settings were accepted and written into a baseline.

/// Non-finite and absurd settings in an experiment file are refused with
/// exit 2 and `FILE:LINE: configuring encoder 'KIND': key 'KEY': expected … RANGE, got VALUE`,
/// by `run` and by `bless`, and no baseline is written. The old code wrote a baseline for each
/// (`weights = [nan, …]` gave `nonfinite` cells; the 1e308 curve gave rmse 3.8e291).
#[test]
fn nonfinite_settings_are_refused_naming_file_line_key_and_range() {
    let cases = [
        ("nan_weights", "{ kind = 'probe_hhd_lum', weights = [nan, 1.0, 1.0] }", "weights", "[0, 1e6]", "[NaN, 1, 1]"),
        ("inf_weights", "{ kind = 'probe_hhd_lum', weights = [inf, 1.0, 1.0] }", "weights", "[0, 1e6]", "[inf, 1, 1]"),
        (
            "huge_curve",
            "{ kind = 'zh3_hallucinate', curve_c1 = 1e308, curve_c2 = 1e308 }",
            "curve_c1",
            "[-100, 100]",
            "1e308",
        ),
        ("nan_curve", "{ kind = 'zh3_hallucinate', curve_c2 = nan }", "curve_c2", "[-100, 100]", "NaN"),
        ("inf_tilt", "{ kind = 'ahd_search_hemi', max_tilt_deg = inf }", "max_tilt_deg", "(0, 90)", "inf"),
    ];
    let root = root_with(&[]);
    for (name, entry, key, range, value) in cases {
        let file = format!("experiments/{name}.toml");
        let path = root.write(&file, with_encoder(entry));
        let kind = entry.split('\'').nth(1).unwrap();
        let (at, key, got) =
            (format!("{name}.toml:5: configuring encoder '{kind}'"), format!("key '{key}'"), format!("got {value}"));
        let want = [at.as_str(), key.as_str(), range, got.as_str()];
        assert_refused(&run(&root, &["run", path.to_str().unwrap()]), &want, &format!("run {name}"));
        assert_refused(&run(&root, &["bless", name]), &want, &format!("bless {name}"));
        assert!(!root.path().join("results").join(name).exists(), "{name}: a baseline was written");
    }
}

// ---------------------------------------------------------------------------------------------
// Coarse maps: they got an inaccurate reference labelled "exact".

/// The reference on coarse maps, through `eval`: on a constant map of radiance 1, E/π is 1 at every
/// normal and SH L0 holds it exactly, so the whole error is the reference's. The old reference
/// integrated each row's polar extent with two Gauss–Legendre nodes, wrong by 8.7% on a 2×1
/// map (0.49% at 4×2). On the hemisphere about +X, E/π is (1 + n·X)/2 (the light above the
/// wall), linear in n, so SH L1 of the visible light holds it exactly too (the cut polar
/// pieces also meet the hemisphere's boundary).
#[test]
fn coarse_maps_get_an_exact_reference() {
    let dir = tempfile::tempdir().unwrap();
    for (w, h) in [(2, 1), (4, 2), (8, 4)] {
        let path = dir.path().join(format!("constant_{w}x{h}.exr"));
        let map = common::harness::map_from_fn("c", w, h, |_, _| [1.0; 3]);
        map.write_exr(&path).unwrap();
        let p = path.to_str().unwrap();
        for (domain, encoder) in [("sphere", "sh0"), ("hemisphere:+x", "sh1")] {
            let csv = assert_ok(
                &common::harness::run(&["eval", p, "--encoders", encoder, "--domain", domain, "--resolution", "32x16"]),
                p,
            );
            let row = &parse_csv(&csv)[0];
            let rmse: f64 = row["rmse"].parse().unwrap();
            assert!(rmse <= 1e-6, "{w}x{h} {domain} {encoder}: rmse {rmse} (E/pi)");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Solver settings: unchecked, they panicked (101) or aborted (134).

/// `memory = 1e18` made the L-BFGS history allocation panic with "capacity
/// overflow" (exit 101) and `memory = 1e12` abort for lack of memory (exit 134). Both, and the
/// other solver settings' extremes, are now refused with the key and its range.
#[test]
fn solver_settings_out_of_range_exit_2() {
    let root = root_with(&[]);
    for (name, entry, key, range) in [
        ("memory_1e18", "{ kind = 'zh3_solved_shared', memory = 1000000000000000000 }", "memory", "[1, 64]"),
        ("memory_1e12", "{ kind = 'zh3_solved_shared', memory = 1000000000000 }", "memory", "[1, 64]"),
        ("max_iters", "{ kind = 'zh3_solved_channel', max_iters = 1000000000000000000 }", "max_iters", "[1, 10000]"),
        ("starts", "{ kind = 'zh3_solved_shared', starts = 100000000 }", "starts", "[1, 5]"),
        ("tol_grad", "{ kind = 'zh3_solved_shared', tol_grad = -inf }", "tol_grad", "[0, 1]"),
        ("screen", "{ kind = 'zh3_solved_shared', screen = 1000000000000 }", "screen", "[0, 10000]"),
    ] {
        let path = root.write(&format!("experiments/{name}.toml"), with_encoder(entry));
        let out = run(&root, &["run", path.to_str().unwrap()]);
        assert_refused(&out, &[&format!("{name}.toml:5:"), &format!("key '{key}'"), range], name);
        assert!(!root.path().join("results").join(name).exists(), "{name}: a baseline was written");
    }
}

// ---------------------------------------------------------------------------------------------
// Golden-section settings: a hang.

/// `iterations = 1e18, tolerance_rad = 1e-300` ran forever in the old code:
/// the golden-section bracket cannot shrink below one ulp, so the tolerance was never met and
/// the step count was the user's. The step count is now refused above its bound (200); and the
/// tolerance alone, at the most steps allowed, no longer matters: the search stops when its
/// bracket stops shrinking. Both searches (θ only, and alternating θ/φ with the most rounds)
/// of both lightmap models finish, with the error of the same search at its default settings
/// (30 steps, 1e-6 rad) to 1%. (No timing: that the test ends is the proof; the guard only
/// turns a hang into a failure.)
#[test]
fn golden_section_settings_cannot_hang() {
    let root = root_with(&[]);
    let path = root.write(
        "experiments/hang.toml",
        with_lightmap_encoder("{ kind = 'ahd_search_hemi', iterations = 1000000000000000000, tolerance_rad = 1e-300 }"),
    );
    let out = wait_or_fail_on_hang(spawn(probelab(&root).args(["run", path.to_str().unwrap()])), "iterations = 1e18");
    assert_refused(&out, &["hang.toml:5:", "key 'iterations': expected an integer in [0, 200]"], "iterations = 1e18");

    for (i, kind) in ["ahd_search_hemi", "hhd_search_hemi"].iter().enumerate() {
        for (search, rounds) in [("theta", ""), ("theta_phi", ", rounds = 16")] {
            let name = format!("tiny_tolerance_{i}_{search}");
            let text = format!(
                "maps = ['gen_sun_sky']\nresolution = [16, 8]\nencoders = [\n  \
                 {{ kind = '{kind}', name = 'tiny', iterations = 200, tolerance_rad = 1e-300, search = '{search}'{rounds} }},\n  \
                 {{ kind = '{kind}', name = 'default', search = '{search}' }},\n]\n\
                 domain = 'hemisphere'\norientations = ['up']\neffects = ['hemisphere']\n"
            );
            let path = root.write(&format!("experiments/{name}.toml"), text);
            let out = wait_or_fail_on_hang(spawn(probelab(&root).args(["run", path.to_str().unwrap()])), &name);
            assert_ok(&out, &name);
            let table = std::fs::read_to_string(root.path().join("results").join(&name).join("table.csv")).unwrap();
            let rmse: BTreeMap<String, f64> =
                parse_csv(&table).into_iter().map(|r| (r["encoder"].clone(), r["rmse"].parse().unwrap())).collect();
            // The search at the default settings (30 steps, 1e-6 rad) finds the same minimum.
            let (tiny, default) = (rmse["tiny"], rmse["default"]);
            assert!(tiny.is_finite() && (tiny - default).abs() <= 1e-2 * default, "{name}: rmse {tiny} vs {default}");
        }
    }
}

/// Starts `cmd` with its stdout and stderr captured.
fn spawn(cmd: &mut Command) -> Child {
    cmd.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("spawn probelab")
}

// ---------------------------------------------------------------------------------------------
// A failing stdout: it panicked.

/// Every command that prints, with what it needs on the scratch repository `root` (which has a
/// baseline for `small`, and a saved shard state `shard.toml`).
fn printing_commands() -> Vec<Vec<&'static str>> {
    vec![
        vec!["encoders"],
        vec!["maps"],
        vec!["eval", "gen_constant", "--encoders", "sh1", "--resolution", "16x8"],
        vec!["check", "small"],
        vec!["bless", "small", "--force"],
        vec!["fit-hallucination", "gen_sun_sky"],
        vec!["probes", "--synth", "20", "--encoders", "sh1"],
        vec!["merge", "shard.toml"],
    ]
}

fn root_for_printing() -> Scratch {
    let root = root_with(&[("small", SMALL)]);
    assert_ok(&run_experiments(&root, &["small"]), "run small");
    let shard = root.path().join("shard.toml");
    assert_ok(
        &run(&root, &["probes", "--synth", "20", "--encoders", "sh1", "--out", shard.to_str().unwrap()]),
        "probes --out",
    );
    root
}

/// `probelab encoders > /dev/full` exited 101 (the panic of `println!`).
/// Every printing command now exits 2 with `error: cannot write to standard output: …`.
#[cfg(target_os = "linux")]
#[test]
fn stdout_to_dev_full_exits_2() {
    let root = root_for_printing();
    for args in printing_commands() {
        let full = std::fs::File::options().write(true).open("/dev/full").expect("/dev/full");
        let mut cmd = probelab(&root);
        cmd.args(&args).current_dir(root.path()).stdout(Stdio::from(full)).stderr(Stdio::piped());
        let out = cmd.output().unwrap();
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?} > /dev/full: exit {:?}: {err}", out.status);
        assert!(err.contains("error: cannot write to standard output: "), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

/// `encoders`, `check`, `bless`, `maps` and `fit-hallucination` into a
/// closed pipe exited 101. Every printing command now ends quietly with 141 (128 + SIGPIPE,
/// what a shell reports for a process that SIGPIPE ended), with nothing on stderr.
#[test]
fn stdout_into_a_closed_pipe_exits_141_quietly() {
    let root = root_for_printing();
    for args in printing_commands() {
        let mut cmd = probelab(&root);
        cmd.args(&args).current_dir(root.path()).stdout(closed_pipe()).stderr(Stdio::piped());
        let out = cmd.output().unwrap();
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(141), "{args:?} | (closed): exit {:?}: {err}", out.status);
        assert!(!err.contains("error:") && !err.contains("panicked"), "{args:?}: {err}");
    }
}

/// `bless --force a b c | head -1` exited 101 after rewriting two of the
/// three baselines (it printed a line after each). A bless now writes every baseline or none,
/// whatever happens to its stdout, and leaves no temporary file. (Today it prints each
/// experiment's comparison before its first write and the "wrote" lines after its last, so a
/// stdout closed from the start stops it before any write, and `| head -1` before any write or
/// after the last, depending on when the reader goes.) A bless with a working stdout, first,
/// shows that the test sees a rewrite: each file replaced by a rename gets a new inode.
#[cfg(unix)]
#[test]
fn bless_into_a_closed_pipe_writes_all_or_none() {
    let root = root_with(&[("a", SMALL), ("b", SMALL), ("c", SMALL)]);
    assert_ok(&run_experiments(&root, &["a", "b", "c"]), "run a b c");
    let force = ["bless", "--force", "a", "b", "c"];
    // How many of the six baseline files a command replaced; fails unless all or none.
    let all_or_none = |before: &BTreeMap<PathBuf, u64>, what: &str| -> usize {
        let after = inodes(&root);
        assert_eq!(after.keys().collect::<Vec<_>>(), before.keys().collect::<Vec<_>>(), "{what}");
        let replaced = after.iter().filter(|(p, ino)| before[*p] != **ino).count();
        assert!(replaced == 0 || replaced == 6, "{what}: replaced {replaced} of the 6 baseline files");
        for name in ["a", "b", "c"] {
            assert!(pair_is_consistent(&root.path().join("results"), name), "{what}: {name}");
        }
        assert!(hidden_temporaries(&root).is_empty(), "{what}: {:?}", hidden_temporaries(&root));
        replaced
    };

    let before = inodes(&root);
    assert_eq!(before.len(), 6, "{before:?}");
    let out = probelab(&root).args(force).stdout(Stdio::null()).stderr(Stdio::piped()).output().unwrap();
    assert_ok(&out, "bless --force");
    assert_eq!(all_or_none(&before, "bless --force > /dev/null"), 6);

    let before = inodes(&root);
    let out = probelab(&root).args(force).stdout(closed_pipe()).stderr(Stdio::piped()).output().unwrap();
    assert_eq!(out.status.code(), Some(141), "{}", stderr(&out));
    all_or_none(&before, "bless --force into a closed pipe");

    // `| head -1`: the reader takes one line and goes.
    let before = inodes(&root);
    let mut child = probelab(&root).args(force).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut first).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(matches!(out.status.code(), Some(0 | 141)), "{:?}: {}", out.status, stderr(&out));
    assert!(!stderr(&out).contains("panicked"), "{}", stderr(&out));
    all_or_none(&before, "bless --force | head -1");

    // Moved numbers (the sh2 rmse of gen_sun_sky doubled in each table), into a closed pipe:
    // each table is restored, or none is.
    let mut moved = BTreeMap::new();
    for name in ["a", "b", "c"] {
        let p = root.path().join("results").join(name).join("table.csv");
        let text = std::fs::read_to_string(&p).unwrap();
        let rows = parse_csv(&text);
        let r = rows.iter().find(|r| r["map"] == "gen_sun_sky" && r["encoder"] == "sh2").unwrap();
        let doubled = format!("{}", r["rmse"].parse::<f64>().unwrap() * 2.0);
        let edited = text.replacen(&format!(",{},", r["rmse"]), &format!(",{doubled},"), 1);
        assert_ne!(edited, text);
        std::fs::write(&p, &edited).unwrap();
        moved.insert(name, edited);
    }
    let before = root.snapshot("results");
    let out =
        probelab(&root).args(["bless", "a", "b", "c"]).stdout(closed_pipe()).stderr(Stdio::piped()).output().unwrap();
    assert_eq!(out.status.code(), Some(141), "{}", stderr(&out));
    let restored: Vec<&str> = ["a", "b", "c"]
        .into_iter()
        .filter(|n| std::fs::read_to_string(root.path().join("results").join(n).join("table.csv")).unwrap() != moved[n])
        .collect();
    assert!(restored.is_empty() || restored.len() == 3, "bless rewrote only {restored:?} of a, b, c");
    if restored.is_empty() {
        assert!(root.snapshot("results") == before, "results/ changed although no baseline was blessed");
    }
    assert!(hidden_temporaries(&root).is_empty(), "{:?}", hidden_temporaries(&root));
}

// ---------------------------------------------------------------------------------------------
// Concurrent writers: two bless runs at once.

/// The lock on `results/`, deterministically: while another process holds the lock on `results/`,
/// `bless` says it is waiting and writes nothing; once the lock is released it finishes. The
/// old code took no lock: it wrote at once. (`check` takes the lock shared, so it does not
/// wait for another `check`, but does for a `bless`.)
#[test]
fn a_writing_command_waits_for_the_lock_on_results() {
    let root = root_with(&[("small", SMALL)]);
    let results = root.path().join("results");
    std::fs::create_dir_all(&results).unwrap();
    let held = std::fs::File::open(&results).unwrap();
    held.lock().unwrap();

    let mut child =
        probelab(&root).args(["bless", "small"]).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut first = String::new();
    err.read_line(&mut first).unwrap();
    assert!(
        first.starts_with("waiting for ") && first.contains("another probelab command is using it"),
        "bless did not wait for the lock: {first:?}"
    );
    // It waits: nothing written while the lock is held (give it the time to do the run).
    std::thread::sleep(std::time::Duration::from_millis(500));
    assert!(root.snapshot("results").is_empty(), "bless wrote while another command held the lock");
    assert!(child.try_wait().unwrap().is_none(), "bless ended while another command held the lock");
    drop(held);
    let status = child.wait().unwrap();
    assert!(status.success());
    assert!(pair_is_consistent(&results, "small"));

    // A shared holder (a `check`) lets another check through, and holds off a bless.
    let held = std::fs::File::open(&results).unwrap();
    held.lock_shared().unwrap();
    let out = run(&root, &["check", "small"]);
    assert_ok(&out, "check under a shared lock");
    assert!(!stderr(&out).contains("waiting for"), "{}", stderr(&out));
    let mut child =
        probelab(&root).args(["bless", "small"]).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut first = String::new();
    err.read_line(&mut first).unwrap();
    assert!(first.starts_with("waiting for "), "bless did not wait for a check: {first:?}");
    drop(held);
    assert!(child.wait().unwrap().success());
}

/// Concurrent writers, end to end: two `bless` runs of one experiment name, from two
/// repositories whose experiment files differ (SH L1 in one, SH L2 in the other), into one
/// results folder, started together, several times. Each time, `table.csv` and
/// `provenance.toml` come from one run (the provenance's `table_sha256` is the table's), and
/// no temporary file is left. Without the lock the two runs' renames can interleave; whether
/// they do in a given round is a matter of timing, which is why the test above shows the lock
/// itself.
#[test]
fn two_concurrent_blesses_leave_a_consistent_pair() {
    let sh1 = "maps = ['gen_constant', 'gen_sun_sky']\nencoders = ['sh1']\nresolution = [16, 8]\n";
    let sh2 = "maps = ['gen_constant', 'gen_sun_sky']\nencoders = ['sh2']\nresolution = [16, 8]\n";
    let (one, two) = (root_with(&[("x", sh1)]), root_with(&[("x", sh2)]));
    let shared = tempfile::tempdir().unwrap();
    let out = shared.path().join("results");
    let bless = |root: &Scratch| {
        probelab(root)
            .args(["bless", "x", "--force", "--out", out.to_str().unwrap()])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let mut winners = std::collections::BTreeSet::new();
    for round in 0..8 {
        let (a, b) = (bless(&one), bless(&two));
        for c in [a, b] {
            let o = c.wait_with_output().unwrap();
            assert!(o.status.success(), "round {round}: {}", stderr(&o));
        }
        assert!(pair_is_consistent(&out, "x"), "round {round}: table.csv and provenance.toml from different runs");
        let table = std::fs::read_to_string(out.join("x/table.csv")).unwrap();
        winners.insert(parse_csv(&table)[0]["encoder"].clone());
        let left: Vec<_> = std::fs::read_dir(out.join("x")).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left.len(), 2, "round {round}: {left:?}");
    }
    assert!(!winners.is_empty());
}

// ---------------------------------------------------------------------------------------------
// Leftovers: a killed run left hidden temporary files.

/// The hidden files a killed run leaves (`.NAME.tmp-PID`,
/// `.NAME.tmp-PID-N`, `.NAME.old-PID`) were never removed. The next writing command removes
/// those whose process is gone, in subfolders too, and names each on stderr; a live process's
/// temporary file and every other file stay. The old code left them all.
#[test]
fn stale_temporaries_are_removed_with_a_note() {
    let root = root_with(&[("small", SMALL)]);
    // A process id that is surely gone: a child that has been waited for.
    let mut child = Command::new("true").spawn().unwrap();
    let gone = child.id();
    child.wait().unwrap();
    let live = std::process::id();
    let stale = [
        format!("small/.table.csv.tmp-{gone}"),
        format!("small/.provenance.toml.tmp-{gone}"),
        format!("small/.table.csv.old-{gone}"),
        format!("small/.provenance.toml.old-{gone}"),
        format!(".REPORT.md.tmp-{gone}"),
        format!("deep/er/.gen_sky.exr.tmp-{gone}-3"),
    ];
    let kept = [format!("small/.table.csv.tmp-{live}"), ".notes.tmp-abc".to_string(), "other/table.csv".to_string()];
    for f in stale.iter().chain(&kept) {
        root.write(&format!("results/{f}"), "left over");
    }
    let out = run_experiments(&root, &["small"]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    for f in &stale {
        assert!(!root.path().join("results").join(f).exists(), "{f} was not removed");
        let note = format!(
            "removed {} (left by a killed run whose process is gone)",
            root.path().join("results").join(f).display()
        );
        assert!(err.contains(&note), "no note for {f}: {err}");
    }
    for f in &kept {
        assert!(root.path().join("results").join(f).exists(), "{f} was removed");
    }
    assert!(pair_is_consistent(&root.path().join("results"), "small"));
}

// ---------------------------------------------------------------------------------------------
// The small things.

/// `--encoders ""` exited 0 with a header-only CSV, and `--encoders sh1,sh1` gave duplicate
/// rows. Both are errors, as they are in experiment files.
#[test]
fn small_encoder_lists_empty_or_repeated() {
    for (list, want) in [("", "--encoders '': list at least one encoder"), ("sh1,sh1", "'sh1' appears twice")] {
        let out = common::harness::run(&["eval", "gen_constant", "--encoders", list]);
        assert_refused(&out, &[want], &format!("--encoders '{list}'"));
    }
    let root = root_with(&[("empty", "maps = ['gen_constant']\nencoders = []\n")]);
    assert_refused(
        &run_experiments(&root, &["empty"]),
        &["empty.toml", "encoders: list at least one encoder"],
        "encoders = []",
    );
}

/// A map listed twice, or two maps with one file stem (rows are keyed by the stem), gave rows
/// with identical keys. Both are errors on the command line; in an experiment file the error
/// names the file and the line of the second map; nothing is written.
#[test]
fn small_repeated_maps_and_one_stem_twice() {
    let copy = tempfile::tempdir().unwrap();
    let other = copy.path().join("gen_constant.exr");
    std::fs::copy(repo().join("envmaps/gen_constant.exr"), &other).unwrap();
    let other = other.to_str().unwrap();
    for maps in [["gen_constant", "gen_constant"], ["gen_constant", other]] {
        let out = common::harness::run(&["eval", maps[0], maps[1], "--encoders", "sh1"]);
        assert_refused(&out, &["are both the map 'gen_constant'"], &format!("eval {maps:?}"));
    }
    let twice = "maps = ['gen_constant',\n  'gen_constant']\nencoders = ['sh1']\nresolution = [16, 8]\n".to_string();
    let stem = format!("maps = ['gen_constant',\n  '{other}']\nencoders = ['sh1']\nresolution = [16, 8]\n");
    let root = root_with(&[("twice", &twice), ("stem", &stem)]);
    assert_refused(&run_experiments(&root, &["twice"]), &["twice.toml:1: maps: 'gen_constant' appears twice"], "twice");
    assert_refused(
        &run_experiments(&root, &["stem"]),
        &["stem.toml:2: maps", "are both the map 'gen_constant'"],
        "stem",
    );
    assert!(root.snapshot("results").is_empty());
}

/// `--resolution axb` said only "invalid digit found in string", without naming the option.
#[test]
fn small_bad_resolution_names_the_option() {
    for bad in ["axb", "16x", "x8", "0x0", "99999999999999999999x1", "32x8"] {
        let out = common::harness::run(&["eval", "gen_constant", "--resolution", bad]);
        assert_refused(&out, &["--resolution", &format!("'{bad}'")], bad);
    }
}

/// An experiment listing 300,000 missing maps took more than 120 s: each missing map's line
/// was found by reading the file again (quadratic). Here 30,000, so the test stays cheap: each
/// is reported as `FILE:LINE: map 'NAME' not found`, in order, and nothing is written. (No
/// timing: a quadratic search would still pass, only slowly; the figure for 300,000 is in
/// docs/robustness.md.)
#[test]
fn small_many_missing_maps_are_each_located() {
    let n = 30_000;
    let mut text = String::from("encoders = ['sh1']\nmaps = [\n");
    for k in 0..n {
        text += &format!("  'missing_{k}',\n");
    }
    text += "]\n";
    let root = root_with(&[("many", &text)]);
    let out = run_experiments(&root, &["many"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{}", &err[..err.len().min(2000)]);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("not found")).collect();
    assert_eq!(lines.len(), n);
    for k in [0, 1, n / 2, n - 1] {
        assert!(lines[k].ends_with(&format!("many.toml:{}: map 'missing_{k}' not found", k + 3)), "{}", lines[k]);
    }
    assert!(root.snapshot("results").is_empty());
}

// ---------------------------------------------------------------------------------------------
// Beyond the list: what the audit of user-data paths found.

/// A result table or summary that holds only its header (a user's edit, or a table emptied by
/// hand) made `probelab report` panic (exit 101): the pivot of REPORT.md labelled its units
/// from the first row, and the summary's ratio pivot picked its metric from it. The report is
/// now written, without those pivots.
#[test]
fn audit_header_only_tables_do_not_stop_the_report() {
    let text = format!("{SMALL}\n[summary]\nbaseline = 'sh1'\n");
    let root = root_with(&[("x", &text)]);
    assert_ok(&run_experiments(&root, &["x"]), "run x");
    for file in ["table.csv", "summary.csv"] {
        let p = root.path().join("results/x").join(file);
        let header = std::fs::read_to_string(&p).unwrap().lines().next().unwrap().to_string();
        std::fs::write(&p, format!("{header}\n")).unwrap();
    }
    let out = run(&root, &["report"]);
    assert_ok(&out, "report on header-only tables");
    assert!(root.path().join("results/REPORT.md").is_file());
}

/// `--jobs 1000000` spent minutes creating a million threads before doing anything (a hang to
/// the user), and `--jobs 0` was quietly taken as 1. Both are refused, naming the option and
/// its range.
#[test]
fn audit_jobs_is_bounded() {
    for jobs in ["0", "1000000", "18446744073709551615"] {
        let out = common::harness::run(&["--jobs", jobs, "encoders"]);
        assert_refused(&out, &[&format!("--jobs {jobs}: expected 1 to 1024")], &format!("--jobs {jobs}"));
    }
    assert_ok(&common::harness::run(&["--jobs", "1024", "encoders"]), "--jobs 1024");
}

// ---------------------------------------------------------------------------------------------
// The third round of hostile input: huge texels, a closed stdout, file names that are not text.

/// An 8x4 Radiance file stored flat (no run-length coding) whose every texel is the RGBE bytes
/// `px`.
fn flat_hdr(px: [u8; 4]) -> Vec<u8> {
    [&b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n"[..], &px.repeat(32)].concat()
}

/// A map of 3e38 texels (finite, below f32::MAX) ran once, wrote a baseline with rmse 3.47e31,
/// and every later `run` or `check` failed at "(fresh table):2:5", naming no file. A `.hdr`
/// texel with exponent byte 255 (0.5·2^127 = 8.5e37) did the same. Both are refused at load,
/// naming the file and the texel; a map at the bound, 1e24, runs and checks clean with every
/// encoder.
#[test]
fn texels_above_the_bound_are_refused_at_load_and_the_bound_fits_every_table() {
    let root = root_with(&[]);
    let exr = root.path().join("huge.exr");
    exr::prelude::write_rgb_file(
        &exr,
        8,
        4,
        |x, y| if (x, y) == (3, 1) { (1.0, 3e38f32, 1.0) } else { (1.0, 1.0, 1.0) },
    )
    .unwrap();
    let hdr = root.write("huge.hdr", flat_hdr([128, 128, 128, 255]));
    for (path, at) in [(&exr, "x=3, y=1, channel G"), (&hdr, "x=0, y=0, channel R")] {
        let out = run(&root, &["eval", path.to_str().unwrap(), "--encoders", "sh1"]);
        let file = path.display().to_string();
        assert_refused(&out, &[&file, "above the bound 1e24", at], &file);
    }
    // Every encoder on a map at the bound (on a hemisphere, where every encoder is defined):
    // the tables hold every number, and check reads them.
    let ids = assert_ok(&common::harness::run(&["encoders"]), "encoders");
    let ids: Vec<&str> = ids.lines().filter_map(|l| l.split_whitespace().next()).collect();
    let at = root.path().join("at_bound.exr");
    exr::prelude::write_rgb_file(
        &at,
        16,
        8,
        |x, y| if x < 4 && y < 2 { (1e24f32, 1e24, 1e24) } else { (1e20, 1e22, 0.0) },
    )
    .unwrap();
    let list = ids.iter().map(|i| format!("'{i}'")).collect::<Vec<_>>().join(", ");
    root.write(
        "experiments/at_bound.toml",
        format!(
            "maps = ['{}']\nencoders = [{list}]\nresolution = [16, 8]\n\
             domain = 'hemisphere'\norientations = ['up']\neffects = ['hemisphere']\n",
            at.display()
        ),
    );
    assert_ok(&run_experiments(&root, &["at_bound"]), "run at the bound");
    assert_ok(&run(&root, &["check", "at_bound"]), "check at the bound");
}

/// With stdout closed (`>&-`) the Rust runtime put /dev/null in its place: results vanished and
/// the exit code was 0. Now: exit 2 and "cannot write to standard output" (on Linux, where the
/// closed descriptor is noted before the runtime starts). `> /dev/null` still succeeds.
#[cfg(target_os = "linux")]
#[test]
fn a_closed_stdout_exits_2() {
    for args in
        [vec!["encoders"], vec!["--help"], vec!["eval", "gen_constant", "--encoders", "sh1", "--resolution", "16x8"]]
    {
        let out = Command::new("sh")
            .arg("-c")
            .arg("exec \"$@\" >&-")
            .arg("sh")
            .arg(env!("CARGO_BIN_EXE_probelab"))
            .args(&args)
            .env("PROBELAB_ENVMAPS", repo().join("envmaps"))
            .output()
            .unwrap();
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?} >&-: {err}");
        assert!(err.contains("error: cannot write to standard output: it was closed"), "{args:?}: {err}");
        let out = common::harness::probelab().args(&args).stdout(Stdio::null()).output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{args:?} > /dev/null: {}", stderr(&out));
    }
}

/// A file name that is not UTF-8 could not be passed at all (clap's "invalid UTF-8 was
/// detected", naming no argument), `maps` listed it, and the `--synth` palette skipped it
/// silently. Each now says the same: refused naming the argument, listed as unusable, and the
/// palette refuses it naming the file.
#[cfg(unix)]
#[test]
fn file_names_that_are_not_utf8_are_named_everywhere() {
    use std::os::unix::ffi::OsStrExt;
    let root = root_with(&[]);
    let maps = root.path().join("maps");
    std::fs::create_dir_all(&maps).unwrap();
    let name = std::ffi::OsStr::from_bytes(b"caf\xe9_256x128.exr");
    let path = maps.join(name);
    std::fs::copy(repo().join("envmaps/gen_constant.exr"), &path).unwrap();
    let out = common::harness::probelab().arg("eval").arg(&path).args(["--encoders", "sh1"]).output().unwrap();
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("<MAPS>") && err.contains("is not valid UTF-8") && err.contains("rename the file"), "{err}");
    let out = common::harness::probelab().arg("run").arg(maps.join(std::ffi::OsStr::from_bytes(b"\xff.toml"))).output();
    let err = stderr(&out.unwrap());
    assert!(err.contains("<EXPERIMENTS>") && err.contains("is not valid UTF-8"), "{err}");
    let listed = common::harness::probelab().arg("maps").env("PROBELAB_ENVMAPS", &maps).output().unwrap();
    let text = assert_ok(&listed, "maps");
    assert!(text.contains("caf\u{fffd}_256x128.exr (its name is not valid UTF-8"), "{text}");
    let synth = ["probes", "--synth", "4", "--encoders", "sh1"];
    let out = common::harness::probelab().args(synth).env("PROBELAB_ENVMAPS", &maps).output().unwrap();
    assert_refused(&out, &["caf\u{fffd}_256x128.exr: its name is not valid UTF-8"], "probes --synth");
}
