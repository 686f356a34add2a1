//! What a user wrote, said back in an error they can act on: a value is echoed cut to 40
//! characters and a quoted line to 120 (`math::echo`), never whole (a 300-digit number); TOML
//! nested deeper than 32 levels is refused with its file and line in experiment, sweep, claims
//! and report-plan files; a normal must be finite and at least 1e-6 long (`api::unit_normal`).

mod common;

use common::harness::{probelab, repo};
use std::fs;
use std::path::Path;
use std::process::Output;

/// 300 digits: no error may carry them whole.
fn digits() -> String {
    "1234567890".repeat(30)
}

/// The run exits 2, names `file`, says every one of `words`, and echoes no run of 41 or more
/// of the 300 digits.
fn refused(out: &Output, file: &str, words: &[&str]) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains(file), "the error does not name {file}: {err}");
    for w in words {
        assert!(err.contains(w), "the error lacks '{w}': {err}");
    }
    assert!(!err.contains(&digits()), "a value echoed whole: {err}");
    // Outside a quoted line (`  N | …`, up to 120 characters), a value is at most 40.
    for line in err.lines().filter(|l| l.trim_start().split(" | ").next().is_none_or(|n| n.parse::<usize>().is_err())) {
        assert!(!line.contains(&digits()[..41]), "a value echoed past 40 characters: {line}");
    }
    err
}

/// `depth` nested arrays around one number.
fn nested_arrays(depth: usize) -> String {
    format!("{}1{}", "[".repeat(depth), "]".repeat(depth))
}

#[test]
fn experiment_values_and_lines_are_echoed_cut() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("long.toml");
    let text = format!("maps = ['gen_constant']\nencoders = ['sh1']\norientations = ['{}']\n", digits());
    fs::write(&path, text).unwrap();
    let out = probelab().args(["run", path.to_str().unwrap()]).output().unwrap();
    let err = refused(&out, "long.toml:3:", &["unknown orientation '1234567890", "…'"]);
    let quoted = err.lines().find(|l| l.starts_with("  3 | orientations = ['1234567890")).expect(&err);
    assert_eq!(quoted.chars().count(), 6 + 120, "{quoted}");
    // A parser's message that quotes the value: cut there too, its words kept.
    let path = dir.path().join("typed.toml");
    fs::write(&path, format!("maps = ['gen_constant']\nencoders = ['sh1']\nresolution = '{}'\n", digits())).unwrap();
    let out = probelab().args(["run", path.to_str().unwrap()]).output().unwrap();
    refused(&out, "typed.toml:3:", &["invalid type: string \"1234567890", "…\", expected"]);
    // An unknown encoder with a 300-character name.
    let path = dir.path().join("encoder.toml");
    fs::write(&path, format!("maps = ['gen_constant']\nencoders = ['{}']\n", digits())).unwrap();
    let out = probelab().args(["run", path.to_str().unwrap()]).output().unwrap();
    refused(&out, "encoder.toml:2:", &["unknown encoder '1234567890", "…'"]);
}

#[test]
fn command_line_values_are_echoed_cut() {
    let domain = format!("hemisphere:{}", digits());
    let out = probelab().args(["eval", "gen_constant", "--domain", &domain]).output().unwrap();
    refused(&out, "--domain", &["…"]);
    let out = probelab().args(["eval", "gen_constant", "--encoders", &digits()]).output().unwrap();
    refused(&out, "unknown encoder", &["'1234567890", "…'"]);
    let normal = format!("{}x,0,0", digits());
    let out = probelab().args(["fit", "gen_constant", "--encoders", "sh1", "--normal", &normal]).output().unwrap();
    refused(&out, "--normal", &["…"]);
}

#[test]
fn toml_nested_deeper_than_32_is_refused_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, command: &str, text: String, line: usize| {
        let path = dir.path().join(name);
        fs::write(&path, text).unwrap();
        let out = probelab().args([command, path.to_str().unwrap()]).output().unwrap();
        let err = refused(&out, &format!("{name}:{line}: nested deeper than 32 levels"), &[]);
        assert!(!err.contains("recursion"), "{err}");
    };
    let head = "maps = ['gen_constant']\nencoders = ['sh1']\n";
    run("arrays.toml", "run", format!("{head}x = {}\n", nested_arrays(100_000)), 3);
    run("inline.toml", "run", format!("{head}\nx = {}1{}\n", "{a = ".repeat(40), "}".repeat(40)), 4);
    run("dotted.toml", "run", format!("{head}{} = 1\n", vec!["a"; 40].join(".")), 3);
    run("header.toml", "run", format!("{head}[{}]\n", vec!["t"; 40].join(".")), 3);
    run("sweep.toml", "sweep", format!("knob = 'polar_nodes'\n{head}x = {}\n", nested_arrays(33)), 4);
    // 32 levels are within the limit: the file is read on, to its unknown key.
    let path = dir.path().join("within.toml");
    fs::write(&path, format!("{head}x = {}\n", nested_arrays(32))).unwrap();
    let out = probelab().args(["run", path.to_str().unwrap()]).output().unwrap();
    refused(&out, "within.toml:3:", &["unknown field `x`"]);
    // Claims declarations and report plans go through the same parser.
    let deep = format!("title = 'T'\nx = {}\n", nested_arrays(33));
    let e = probelab::claims::declaration::parse("p", &deep, Path::new("claims/p.toml")).err().unwrap();
    assert!(format!("{e:#}").starts_with("claims/p.toml:2: nested deeper than 32 levels"), "{e:#}");
    let e = probelab::report::plans::parse_plans(&deep, Path::new("report/papers.toml")).err().unwrap();
    assert!(format!("{e:#}").starts_with("report/papers.toml:2: nested deeper than 32 levels"), "{e:#}");
}

#[test]
fn the_committed_toml_files_are_within_the_nesting_limit() {
    let mut seen = 0;
    let mut stack = vec![repo().join("experiments")];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "toml") {
                let text = fs::read_to_string(&p).unwrap();
                let parsed: anyhow::Result<toml::Table> = probelab::pipeline::experiment::parse_toml(&text, &p);
                assert!(parsed.is_ok(), "{}: {:#}", p.display(), parsed.err().unwrap());
                seen += 1;
            }
        }
    }
    assert!(seen >= 10, "{seen} files");
}

#[test]
fn a_normal_must_be_finite_and_not_too_short() {
    for (text, said) in [
        ("0,0,0", "length at least 1e-6"),
        ("0,1e-7,0", "length at least 1e-6"),
        ("nan,1,0", "three finite numbers"),
        ("inf,1,0", "three finite numbers"),
    ] {
        let out = probelab().args(["fit", "gen_constant", "--encoders", "sh1", "--normal", text]).output().unwrap();
        refused(&out, "--normal", &[said]);
    }
    use probelab::DVec3;
    let n = probelab::unit_normal(DVec3::new(0.0, 1e-6, 0.0)).unwrap();
    assert_eq!(n, DVec3::Y);
    // Huge and tiny components are scaled before their length is taken.
    let n = probelab::unit_normal(DVec3::new(1e300, 1e300, 0.0)).unwrap();
    assert!((n - DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-15, "{n}");
    assert!(probelab::unit_normal(DVec3::new(3e-7, 4e-7, 0.0)).is_err());
    assert!(probelab::unit_normal(DVec3::new(6e-7, 8e-7, 0.0)).is_ok());
    let e = probelab::Map::from_texels("c", 8, 4, vec![[1.0; 3]; 32])
        .unwrap()
        .lighting(probelab::Surface::Normal(DVec3::ZERO))
        .err()
        .unwrap();
    assert!(format!("{e:#}").starts_with("surface normal: (0, 0, 0): a normal must be"), "{e:#}");
}
