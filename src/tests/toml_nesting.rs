//! TOML nested deeper than 32 levels is refused with its file and line by every reader of a
//! TOML file (`pipeline::experiment::parse_toml`): claims declarations and report plans as
//! experiments (whose refusal `tests/user_values.rs` checks through the binary), and every
//! committed file is within the limit.

use std::fs;
use std::path::Path;

/// `depth` nested arrays around one number.
fn nested_arrays(depth: usize) -> String {
    format!("{}1{}", "[".repeat(depth), "]".repeat(depth))
}

#[test]
fn claims_and_report_plans_refuse_toml_nested_deeper_than_32() {
    // Claims declarations and report plans go through the same parser.
    let deep = format!("title = 'T'\nx = {}\n", nested_arrays(33));
    let e = crate::claims::declaration::parse::parse("p", &deep, Path::new("claims/p.toml")).err().unwrap();
    assert!(format!("{e:#}").starts_with("claims/p.toml:2: nested deeper than 32 levels"), "{e:#}");
    let e = crate::report::plans::parse_plans(&deep, Path::new("report/papers.toml")).err().unwrap();
    assert!(format!("{e:#}").starts_with("report/papers.toml:2: nested deeper than 32 levels"), "{e:#}");
}

#[test]
fn the_committed_toml_files_are_within_the_nesting_limit() {
    let mut seen = 0;
    let mut stack = vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments")];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "toml") {
                let text = fs::read_to_string(&p).unwrap();
                let parsed: anyhow::Result<toml::Table> = crate::pipeline::experiment::parse_toml(&text, &p);
                assert!(parsed.is_ok(), "{}: {:#}", p.display(), parsed.err().unwrap());
                seen += 1;
            }
        }
    }
    assert!(seen >= 10, "{seen} files");
}
