//! The library's public surface is small and deliberate, and the binary is thin:
//!
//! - `cargo doc --no-deps --lib` writes at most [`MAX_ITEM_PAGES`] item pages (structs, enums,
//!   traits, functions, constants, types, statics, macros): the surface is `api` (and its
//!   re-exports at the crate root), `ops` (one function per workflow), `encoders` (the trait and
//!   the registry, for people who add encoders) and `progress` (the trait the binary draws
//!   bars through). Every public item is documented (`#![deny(missing_docs)]` in `src/lib.rs`).
//! - The binary (`src/main.rs`, `src/commands/`) and the Python package
//!   (`bindings/python/src/`) reach the library only through that surface.
//! - `api` has no hidden hatch (`#[doc(hidden)]`).
//! - Exit codes are the binary's: no library file names one.
//! - A command file never imports another command's file: shared parts live in
//!   `commands/{terminal,output,context,args}.rs`.
//! - Only `benches/` names the `bench` feature's re-exports.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The most item pages the public surface may have.
const MAX_ITEM_PAGES: usize = 300;

/// The surface's top-level names: what code outside the crate may write after `probelab::`.
const SURFACE: &[&str] = &[
    "api",
    "ops",
    "encoders",
    "progress",
    "Error",
    "Result",
    "DVec3",
    "Map",
    "Lighting",
    "Fit",
    "Stored",
    "Entry",
    "Role",
    "Unit",
    "Value",
    "Surface",
    "Rgb",
    "Row",
    "Score",
    "Scores",
    "Experiment",
    "encoder_ids",
    "needs_surface_normal",
    "unit_normal",
    "DEFAULT_RESOLUTION",
];

/// The binary's files that every command may share.
const SHARED_COMMAND_FILES: &[&str] = &["terminal", "output", "context", "args", "mod"];

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// A file's code with `//` comments removed (doc text is not code).
fn code_of(text: &str) -> String {
    text.lines().map(|l| l.find("//").map_or(l, |i| &l[..i])).collect::<Vec<_>>().join("\n")
}

/// The name after each `probelab::` in `code` (`probelab::ops::eval` → `ops`; a braced list
/// `probelab::{Map, ops}` gives each of its first-level names).
fn surface_names(code: &str) -> Vec<String> {
    let mut names = Vec::new();
    let ident = |s: &str| s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect::<String>();
    for (at, _) in code.match_indices("probelab::") {
        let rest = &code[at + "probelab::".len()..];
        if let Some(list) = rest.strip_prefix('{') {
            let mut depth = 0;
            let mut item = String::new();
            for c in list.chars() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        names.push(ident(item.trim()));
                        item.clear();
                        continue;
                    }
                    _ => {}
                }
                item.push(c);
            }
            names.push(ident(item.trim()));
        } else {
            names.push(ident(rest));
        }
    }
    names.retain(|n| !n.is_empty());
    names
}

/// The files outside the crate's library that must use the surface alone.
fn front_end_files() -> Vec<PathBuf> {
    let mut files = vec![repo().join("src/main.rs")];
    rust_files(&repo().join("src/commands"), &mut files);
    rust_files(&repo().join("bindings/python/src"), &mut files);
    files
}

#[test]
fn the_binary_and_python_use_only_the_surface() {
    let mut found = Vec::new();
    for p in front_end_files() {
        let code = code_of(&std::fs::read_to_string(&p).unwrap());
        for n in surface_names(&code) {
            if !SURFACE.contains(&n.as_str()) {
                found.push(format!("{}: probelab::{n}", p.strip_prefix(repo()).unwrap().display()));
            }
        }
    }
    assert!(found.is_empty(), "front ends reaching past the public surface: {found:#?}");
}

/// The library's files: everything under `src/` but the binary's.
fn library_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    rust_files(&repo().join("src"), &mut files);
    files.retain(|p| !p.starts_with(repo().join("src/commands")) && !p.ends_with("src/main.rs"));
    files
}

#[test]
fn exit_codes_are_the_binarys() {
    let words = ["process::exit", "ExitCode", "exit_code", "Result<i32>", "Result<(i32", "-> i32 {"];
    let mut found = Vec::new();
    for p in library_files() {
        let code = code_of(&std::fs::read_to_string(&p).unwrap());
        for w in words.iter().filter(|w| code.contains(*w)) {
            found.push(format!("{}: {w}", p.strip_prefix(repo()).unwrap().display()));
        }
    }
    assert!(found.is_empty(), "exit codes in the library: {found:#?}");
}

#[test]
fn no_command_imports_another_commands_file() {
    let mut files = Vec::new();
    rust_files(&repo().join("src/commands"), &mut files);
    let commands: Vec<String> = files.iter().map(|p| p.file_stem().unwrap().to_string_lossy().into_owned()).collect();
    let mut found = Vec::new();
    for p in &files {
        let me = p.file_stem().unwrap().to_string_lossy().into_owned();
        if me == "mod" {
            continue;
        }
        let code = code_of(&std::fs::read_to_string(p).unwrap());
        for other in commands.iter().filter(|c| **c != me && !SHARED_COMMAND_FILES.contains(&c.as_str())) {
            for prefix in ["super::", "crate::commands::"] {
                if code.contains(&format!("{prefix}{other}::")) || code.contains(&format!("{prefix}{{{other}")) {
                    found.push(format!("commands/{me}.rs uses commands/{other}.rs"));
                }
            }
        }
    }
    assert!(found.is_empty(), "command files importing each other: {found:#?}");
}

#[test]
fn api_has_no_hidden_hatch() {
    let api = std::fs::read_to_string(repo().join("src/api.rs")).unwrap();
    assert!(!code_of(&api).contains("doc(hidden)"), "src/api.rs hides a public item (#[doc(hidden)])");
}

#[test]
fn only_the_benches_use_the_bench_reexports() {
    let mut files = Vec::new();
    for dir in ["src", "tests", "examples", "bindings/python/src"] {
        rust_files(&repo().join(dir), &mut files);
    }
    let found: Vec<String> = files
        .iter()
        .filter(|p| !p.ends_with("src/lib.rs") && !p.ends_with("src/bench.rs") && !p.ends_with("tests/surface.rs"))
        .filter(|p| {
            let code = code_of(&std::fs::read_to_string(p).unwrap());
            code.contains("probelab::bench") || code.contains("crate::bench")
        })
        .map(|p| p.strip_prefix(repo()).unwrap().display().to_string())
        .collect();
    assert!(found.is_empty(), "outside benches/, the bench re-exports are used by: {found:?}");
}

/// The item pages under a rustdoc output folder: one HTML file per struct, enum, trait,
/// function, constant, type alias, static or macro.
fn item_pages(dir: &Path, out: &mut Vec<String>) {
    let kinds = ["struct.", "enum.", "trait.", "fn.", "constant.", "type.", "static.", "macro.", "union."];
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if p.is_dir() {
            item_pages(&p, out);
        } else if name.ends_with(".html") && kinds.iter().any(|k| name.starts_with(k)) {
            out.push(p.display().to_string());
        }
    }
}

/// `cargo doc --no-deps --lib` into its own folder under `target/`, and the item pages it
/// writes. The first run also checks the dependencies' metadata, without the dev profile's
/// `opt-level = 3` for dependencies and without debug information: rustdoc reads only the
/// dependencies' metadata, but the build scripts and proc macros it needs are compiled in full,
/// and optimised they cost 2.4 times as much CPU (every page written is byte-identical).
#[test]
fn the_public_surface_is_small() {
    let exe = std::env::current_exe().expect("the test binary's path");
    let target = exe.ancestors().nth(3).expect("target/<profile>/deps/<test>").join("surface-doc");
    let status = Command::new(env!("CARGO"))
        .args(["doc", "--quiet", "--no-deps", "--lib", "--target-dir"])
        .arg(&target)
        .args(["--config", "profile.dev.package.\"*\".opt-level = 0", "--config", "profile.dev.debug = false"])
        .current_dir(repo())
        .status()
        .expect("run cargo doc");
    assert!(status.success(), "cargo doc --no-deps --lib failed");
    let mut pages = Vec::new();
    item_pages(&target.join("doc").join("probelab"), &mut pages);
    pages.sort();
    assert!(!pages.is_empty(), "cargo doc wrote no item page under {}", target.display());
    assert!(
        pages.len() <= MAX_ITEM_PAGES,
        "{} public item pages, more than {MAX_ITEM_PAGES}: {:#?}",
        pages.len(),
        pages.iter().map(|p| p.rsplit("doc/probelab/").next().unwrap_or(p)).collect::<Vec<_>>()
    );
}

/// The checkers see what they look for.
#[test]
fn the_surface_checkers_see_what_they_look_for() {
    let code = "use probelab::{Map, ops::Env, envmap::{a, b}};\nlet x = probelab::pipeline::run();";
    assert_eq!(surface_names(code), ["Map", "ops", "envmap", "pipeline"]);
    assert_eq!(code_of("let a = 1; // probelab::x"), "let a = 1; ");
}
