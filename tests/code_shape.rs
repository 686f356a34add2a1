//! The shape of the code: short functions (at most 80 lines) and product files (at most 600
//! lines before a file's `#[cfg(test)]`; unit tests may live in a sibling `tests.rs`, and the
//! crate's cross-layer tests in `src/tests/`) under `src/`; no work inside a `mod.rs` (its
//! product code declares modules and re-exports, and defines no function); and things named by
//! their concept: no issue or item numbers in `src/`, `tests/`, `benches/`, `examples/` or
//! `docs/`.

use std::path::{Path, PathBuf};

const MAX_FUNCTION_LINES: usize = 80;
const MAX_FILE_LINES: usize = 600;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every file under `dir` whose name ends with one of `extensions`.
fn files(dir: &Path, extensions: &[&str], out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries {
        let p = e.unwrap().path();
        if p.is_dir() {
            files(&p, extensions, out);
        } else if extensions.iter().any(|x| p.to_string_lossy().ends_with(x)) {
            out.push(p);
        }
    }
}

/// A line with its comments and string and character literals blanked, so braces inside them
/// do not count.
fn code_only(line: &str) -> String {
    let mut out = String::new();
    let mut chars = line.chars().peekable();
    let mut in_str = false;
    while let Some(c) = chars.next() {
        match (in_str, c) {
            (false, '/') if chars.peek() == Some(&'/') => break,
            (false, '"') => in_str = true,
            (true, '\\') => {
                chars.next();
            }
            (true, '"') => in_str = false,
            (false, '\'') => {
                // A char literal ('{', '\n') is skipped whole; a lifetime ('a) is kept.
                let rest: String = chars.clone().take(3).collect();
                if rest.starts_with('\\') || rest.chars().nth(1) == Some('\'') {
                    for d in chars.by_ref() {
                        if d == '\'' {
                            break;
                        }
                    }
                }
            }
            (false, c) => out.push(c),
            (true, _) => {}
        }
    }
    out
}

/// The name of the function a line opens (`fn name`, after any qualifiers), if it opens one.
fn fn_name(line: &str) -> Option<String> {
    let code = code_only(line);
    let at = code.find("fn ")?;
    let before = code[..at].trim();
    let qualifiers = ["pub", "pub(crate)", "pub(super)", "const", "async", "unsafe", "extern", "\"C\""];
    if !before.split_whitespace().all(|w| qualifiers.contains(&w)) {
        return None;
    }
    let name: String = code[at + 3..].chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
    (!name.is_empty()).then_some(name)
}

/// Each function of `text` longer than `limit` lines: (line, name, length), counted from its
/// `fn` line to the line that closes its body.
fn long_functions(text: &str, limit: usize) -> Vec<(usize, String, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut found = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let Some(name) = fn_name(line) else { continue };
        let (mut depth, mut opened) = (0i64, false);
        for (j, l) in lines.iter().enumerate().skip(i) {
            let code = code_only(l);
            for c in code.chars() {
                depth += match c {
                    '{' => 1,
                    '}' => -1,
                    _ => 0,
                };
                opened |= c == '{';
            }
            if !opened && code.trim_end().ends_with(';') {
                break;
            }
            if opened && depth <= 0 {
                if j - i + 1 > limit {
                    found.push((i + 1, name.clone(), j - i + 1));
                }
                break;
            }
        }
    }
    found
}

#[test]
fn functions_and_files_are_short() {
    let mut paths = Vec::new();
    files(&repo().join("src"), &[".rs"], &mut paths);
    paths.sort();
    let mut long = Vec::new();
    for p in &paths {
        let text = std::fs::read_to_string(p).unwrap();
        let rel = p.strip_prefix(repo()).unwrap().display().to_string();
        let n = product_lines(&text);
        if n > MAX_FILE_LINES && !is_test_file(&rel) {
            long.push(format!("{rel}: {n} product lines (file)"));
        }
        for (line, name, len) in long_functions(&text, MAX_FUNCTION_LINES) {
            long.push(format!("{rel}:{line}: fn {name}: {len} lines"));
        }
    }
    assert!(long.is_empty(), "over {MAX_FUNCTION_LINES} lines a function or {MAX_FILE_LINES} a file: {long:#?}");
}

/// The lines of a file before its first `#[cfg(test)]`: its product code.
fn product_lines(text: &str) -> usize {
    text.lines().take_while(|l| l.trim() != "#[cfg(test)]").count()
}

/// A file of unit tests: a `tests.rs`, or anything under `src/tests/`.
fn is_test_file(rel: &str) -> bool {
    rel.ends_with("/tests.rs") || rel.starts_with("src/tests/")
}

/// A `mod.rs` declares its modules, documents them and re-exports; the work is in files named
/// by what it is (no function in a `mod.rs`'s product code).
#[test]
fn mod_files_hold_no_work() {
    let mut paths = Vec::new();
    files(&repo().join("src"), &["mod.rs"], &mut paths);
    paths.sort();
    let mut busy = Vec::new();
    for p in &paths {
        let text = std::fs::read_to_string(p).unwrap();
        let product: Vec<&str> = text.lines().take_while(|l| l.trim() != "#[cfg(test)]").collect();
        let fns: Vec<String> = product.iter().filter_map(|l| fn_name(l)).collect();
        if !fns.is_empty() {
            busy.push(format!("{}: fn {}", p.strip_prefix(repo()).unwrap().display(), fns.join(", fn ")));
        }
    }
    assert!(busy.is_empty(), "mod.rs files that do work (move it to a file named by its concept): {busy:#?}");
}

/// Where `text` cites an issue or an item by its number (the word, then digits, with or
/// without a space or underscore between), as (line, text); one finding per line.
fn numbered_references(text: &str) -> Vec<(usize, String)> {
    let words = [["iss", "ue"].concat(), ["it", "em"].concat()];
    let mut found = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let lower = line.to_lowercase();
        for w in &words {
            for (at, _) in lower.match_indices(w.as_str()) {
                let before = lower[..at].chars().next_back();
                let rest = lower[at + w.len()..].trim_start_matches([' ', '_', '#']);
                let word_start = before.is_none_or(|c| !c.is_alphanumeric());
                if word_start
                    && rest.starts_with(|c: char| c.is_ascii_digit())
                    && found.last().is_none_or(|f: &(usize, String)| f.0 != i + 1)
                {
                    found.push((i + 1, line.trim().to_string()));
                }
            }
        }
    }
    found
}

#[test]
fn nothing_is_named_by_an_issue_number() {
    let mut paths = Vec::new();
    for dir in ["src", "tests", "benches", "examples", "docs"] {
        files(&repo().join(dir), &[".rs", ".md", ".toml"], &mut paths);
    }
    for top in ["README.md", "ARCHITECTURE.md"] {
        paths.push(repo().join(top));
    }
    let mut found = Vec::new();
    for p in &paths {
        let text = std::fs::read_to_string(p).unwrap();
        for (line, what) in numbered_references(&text) {
            found.push(format!("{}:{line}: {what}", p.strip_prefix(repo()).unwrap().display()));
        }
    }
    assert!(found.is_empty(), "named by number, not by concept: {found:#?}");
}

/// The checkers themselves: they see what they look for, and only that.
#[test]
fn the_shape_checkers_see_what_they_look_for() {
    let body = |n: usize| (0..n).map(|i| format!("    let x{i} = '{{';\n")).collect::<String>();
    let text = format!("pub(crate) fn long() {{\n{}}}\nfn short() {{ }}\nfn decl();\n", body(100));
    assert_eq!(long_functions(&text, 100), [(1, "long".to_string(), 102)]);
    assert!(long_functions(&text, 102).is_empty());
    assert_eq!(product_lines("a\nb\n#[cfg(test)]\nmod tests {}\n"), 2);
    assert!(is_test_file("src/envmap/load/tests.rs") && is_test_file("src/tests/common.rs"));
    assert!(!is_test_file("src/envmap/load.rs"));
    let cited =
        format!("// {} 17\nlet {}8_x = 1;\nlet items = [0];\nreissue 3", ["Iss", "ue"].concat(), ["it", "em"].concat());
    assert_eq!(numbered_references(&cited).iter().map(|f| f.0).collect::<Vec<_>>(), [1, 2]);
}
