//! Outputs and names, through the `probelab` binary, as a hostile user meets them: an output
//! that is an input (by any spelling), a write that fails, the temporary files a killed writer
//! left beside a target, a committed table edited to hold "nan" or 1e300, and names that leave
//! their folder. Each refusal exits 2 with a message naming the file, and leaves the files as
//! they were.

mod common;

use common::harness::{repo, Run, Scratch};
use std::process::{Command, Output};

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Exit 2 with a message that holds every one of `needles`.
fn refused(out: &Output, needles: &[&str]) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    for n in needles {
        assert!(err.contains(n), "expected {n:?} in: {err}");
    }
}

/// A process id that is surely gone: a child that has been waited for.
fn gone_pid() -> u32 {
    let mut child = Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    pid
}

/// A scratch folder holding a probe file `in.csv` of three synthetic probes.
fn with_probes() -> Scratch {
    let s = Scratch::new();
    let out = s.run(&["probes", "--synth", "3", "--save", s.path().join("in.csv").to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    s
}

/// `probes --input X --save X` (and `--out X`) replaced the input with exit 0. Every spelling
/// of the input is refused before any work: the path itself, `./`, `..`, a symbolic link to
/// it or to its folder, a hard link; and two outputs that are one file.
#[test]
fn outputs_never_overwrite_inputs() {
    let s = with_probes();
    let d = s.path();
    let input = d.join("in.csv");
    let before = std::fs::read(&input).unwrap();
    std::os::unix::fs::symlink(&input, d.join("link.csv")).unwrap();
    std::os::unix::fs::symlink(d, d.join("here")).unwrap();
    std::fs::hard_link(&input, d.join("hard.csv")).unwrap();
    std::fs::create_dir(d.join("sub")).unwrap();
    let spellings = ["in.csv", "./in.csv", "sub/../in.csv", "link.csv", "here/in.csv", "hard.csv"];
    for spelling in spellings {
        for option in ["--save", "--out"] {
            let out = s.probelab().current_dir(d).args(["probes", "--input", "in.csv", option, spelling]).run();
            refused(&out, &[spelling, option, "--input", "never overwrites an input"]);
            assert_eq!(std::fs::read(&input).unwrap(), before, "{option} {spelling} changed the input");
        }
    }
    let out = s.probelab().current_dir(d).args(["probes", "--synth", "2", "--save", "o.csv", "--out", "./o.csv"]).run();
    refused(&out, &["o.csv", "two outputs"]);
    assert!(!d.join("o.csv").exists());
    // merge: the merged statistics over one of the shards.
    let shard = d.join("s.toml");
    let out = s.probelab().current_dir(d).args(["probes", "--input", "in.csv", "--out", "s.toml"]).run();
    assert!(out.status.success(), "{}", stderr(&out));
    let shard_before = std::fs::read(&shard).unwrap();
    let out = s.probelab().current_dir(d).args(["merge", "s.toml", "--out", "sub/../s.toml"]).run();
    refused(&out, &["s.toml", "--out", "never overwrites an input"]);
    assert_eq!(std::fs::read(&shard).unwrap(), shard_before);
}

/// `run`: an experiment file where its own table would be written is refused before the run.
#[test]
fn a_run_never_writes_over_its_experiment_file() {
    let s = Scratch::new();
    s.copy_from_repo("tolerances.toml");
    let text = "name = 'small'\nmaps = ['gen_constant']\nencoders = ['sh1']\nresolution = [16, 8]\n";
    let exp = s.write("results/small/table.csv", text);
    let envmaps = repo().join("envmaps");
    let out = s.probelab().env("PROBELAB_ENVMAPS", &envmaps).args(["--no-timing", "run"]).arg(&exp).run();
    refused(&out, &["results/small/table.csv", "never overwrites an input"]);
    assert_eq!(std::fs::read_to_string(&exp).unwrap(), text);
}

/// A write that fails says which file: the file-size limit makes the probe file's write fail
/// (EFBIG), a folder in the way makes the rename fail, a file in the way of its folder makes
/// the folder fail. Exit 2, the target named, no temporary file left.
#[test]
fn writer_errors_name_their_target() {
    use std::os::unix::process::CommandExt;
    let s = Scratch::new();
    let d = s.path();
    let mut limited = s.probelab();
    limited.current_dir(d).args(["probes", "--synth", "2000", "--save", "big.csv"]);
    // SAFETY: only async-signal-safe libc calls between fork and exec.
    unsafe {
        limited.pre_exec(|| {
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            let lim = libc::rlimit { rlim_cur: 4096, rlim_max: 4096 };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &lim) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    refused(&limited.run(), &["big.csv: cannot write"]);
    std::fs::create_dir_all(d.join("busy.csv/inside")).unwrap();
    let out = s.probelab().current_dir(d).args(["probes", "--synth", "2", "--save", "busy.csv"]).run();
    refused(&out, &["busy.csv: cannot move into place"]);
    std::fs::write(d.join("file"), b"x").unwrap();
    let out = s.probelab().current_dir(d).args(["probes", "--synth", "2", "--save", "file/p.csv"]).run();
    refused(&out, &["file/p.csv: cannot create its folder"]);
    let left: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

/// A killed `probes --save` left `.NAME.tmp-PID` beside its target, outside any results
/// folder, for good. A lone output file's workflow now removes, before writing it, the
/// temporary files in its folder of writers no longer running, and says so; a running
/// writer's stays.
#[test]
fn stale_temporaries_beside_any_target_are_removed() {
    let s = Scratch::new();
    let d = s.path().join("anywhere");
    std::fs::create_dir(&d).unwrap();
    let gone = gone_pid();
    let mut alive = Command::new("sleep").arg("60").spawn().unwrap();
    let stale = [d.join(format!(".p.csv.tmp-{gone}")), d.join(format!(".other.csv.tmp-{gone}-2"))];
    let live = d.join(format!(".p.csv.tmp-{}", alive.id()));
    for f in stale.iter().chain([&live]) {
        std::fs::write(f, b"left over").unwrap();
    }
    let out = s.run(&["probes", "--synth", "2", "--save", d.join("p.csv").to_str().unwrap()]);
    let live_stays = live.exists();
    alive.kill().unwrap();
    alive.wait().unwrap();
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    for f in &stale {
        assert!(!f.exists(), "{} was not removed", f.display());
        assert!(err.contains(&format!("removed {}", f.display())), "no note for {}: {err}", f.display());
    }
    assert!(live_stays, "a running writer's temporary file was removed");
}

/// A committed table edited to hold "nan" or 1e300: `report` wrote "nan" into pages and a chart
/// of an rmse of 1e300 hung. Every table read is refused at its bad cell, FILE:LINE:COLUMN.
#[test]
fn corrupt_committed_tables_are_refused_at_their_cell() {
    let table = "map,encoder,domain,effects,metric,rmse,rel_rmse,neg_frac\n\
                 m,sh1,sphere,,exact,0.5,0.1,0\nm,sh2,sphere,,exact,BAD,0.1,0\n";
    for bad in ["nan", "1.000e300", "inf", "-2e31"] {
        let s = Scratch::new();
        s.copy_from_repo("tolerances.toml");
        std::fs::create_dir_all(s.path().join("experiments")).unwrap();
        s.write("results/exp/table.csv", table.replace("BAD", bad));
        let out = s.run(&["report"]);
        refused(&out, &["exp/table.csv:3:6: column 'rmse'", bad]);
    }
    // The saturated relative error the metrics write is a table's value, not a corruption
    // (`src/tests/table_values.rs`).
}

/// `table = "measure:../../x"` in a claims file read a table outside results/claims/measures.
/// A name that is not a plain identifier is refused naming the file, line and key; a claims
/// file whose own name is not one is refused too.
#[test]
fn names_never_leave_their_folder() {
    let s = Scratch::new();
    s.copy_from_repo("tolerances.toml");
    let claim = |table: &str| {
        format!(
            "title='T'\nauthors='A'\nvenue='V'\norder=1\n\
             [[claim]]\nid='X1'\nsays='s'\npaper_figure='p'\ncriterion='c'\n\
             kind='measured'\nfixed='before data'\ndiffers='d'\nquote='the paper states 0.5'\nthreshold_from='paper: 0.5'\n\
             [[claim.check]]\nname='n'\ntable='{table}'\nencoder='a'\ntest='every_at_most'\nbound=1\n\
             role='primary'\n"
        )
    };
    s.write("results/x.csv", "map,encoder,rmse\nm,a,0.5\n");
    for table in ["measure:../../x", "../x", "measure:.hidden"] {
        s.write("experiments/claims/t.toml", claim(table));
        let out = s.run(&["claims"]);
        refused(&out, &["experiments/claims/t.toml:17: key 'table'", "not a plain name"]);
    }
    std::fs::remove_file(s.path().join("experiments/claims/t.toml")).unwrap();
    s.write("experiments/claims/a b.toml", claim("exp"));
    refused(&s.run(&["claims"]), &["a b.toml", "not a plain name"]);
    // A map name that leaves the search path's folders is not looked up in them.
    let root = Scratch::new();
    std::fs::create_dir(root.path().join("envmaps")).unwrap();
    std::fs::copy(repo().join("envmaps/gen_constant.exr"), root.path().join("outside_zz.exr")).unwrap();
    let out = root.run(&["eval", "../outside_zz", "--resolution", "16x8"]);
    refused(&out, &["../outside_zz"]);
}
