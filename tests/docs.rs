//! The documentation says what the binary does: every command of `probelab --help` (and of
//! each command's own `--help`, for nested commands) and every option of each command has its
//! place in docs/commands.md, and nothing there is absent from the help; every relative link of
//! README.md, ARCHITECTURE.md and docs/*.md resolves; README.md stays short, opens with the two
//! commands, and `.ci/run` runs its test command; every command line of the ```` ```sh ````
//! blocks of README.md and docs/*.md runs on a fresh clone (a temporary copy of the checkout,
//! the release binary as `probelab`, `PROBELAB_ENVMAPS` unset), unless the manifest beside this
//! file, `tests/docs_commands.toml`, names it as long (with the file that runs it) or as needing
//! what a fresh clone lacks. The pages carry plain commands: the manifest, not they, holds what
//! only this test needs to know.
//!
//! docs/commands.md's layout, which this file parses: one `## `probelab CMD`` heading per
//! command (`## `probelab maps import`` for a nested one), a `## Global options` section for the
//! options of `probelab --help`, and in each section a table whose first cell names an option
//! in backticks (`` `--out <OUT>` ``; several may share a cell).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// What the documentation test does not run, and why: see its opening comment.
const MANIFEST: &str = "tests/docs_commands.toml";

fn read(rel: &str) -> String {
    std::fs::read_to_string(repo().join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// `probelab ARGS --help`, as text.
fn help(args: &[String]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_probelab")).args(args).arg("--help").output().unwrap();
    assert!(
        out.status.success(),
        "probelab {} --help failed: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The lines of the `TITLE:` block of a clap help text (up to the next blank line).
fn block<'a>(text: &'a str, title: &str) -> Vec<&'a str> {
    text.lines().skip_while(|l| l.trim_end() != title).skip(1).take_while(|l| !l.trim().is_empty()).collect()
}

/// The long option names (`--jobs`) of a help text's `Options:` block.
fn help_options(text: &str) -> BTreeSet<String> {
    block(text, "Options:").iter().filter_map(|l| long_option(l.trim_start())).collect()
}

/// The first `--name` in `s`, if `s` starts with an option (`-h, --help`, `--out <OUT>`).
fn long_option(s: &str) -> Option<String> {
    if !s.starts_with('-') {
        return None;
    }
    let at = s.find("--")?;
    let name: String = s[at..].chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '-').collect();
    (name.len() > 2).then_some(name)
}

/// The command names of a help text's `Commands:` block (without clap's `help`).
fn help_commands(text: &str) -> Vec<String> {
    block(text, "Commands:")
        .iter()
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(String::from)
        .collect()
}

/// Every command path (`["maps", "import"]`) with its options, from the binary's help,
/// depth first; `[]` is the top level (the global options).
fn commands_from_help() -> BTreeMap<Vec<String>, BTreeSet<String>> {
    let mut all = BTreeMap::new();
    let mut todo = vec![Vec::new()];
    while let Some(path) = todo.pop() {
        let text = help(&path);
        for c in help_commands(&text) {
            let mut sub = path.clone();
            sub.push(c);
            todo.push(sub);
        }
        all.insert(path, help_options(&text));
    }
    all
}

/// docs/commands.md's sections: command path → options named in its tables.
fn commands_from_doc(doc: &str) -> BTreeMap<Vec<String>, BTreeSet<String>> {
    let mut all: BTreeMap<Vec<String>, BTreeSet<String>> = BTreeMap::new();
    let mut current: Option<Vec<String>> = None;
    for line in doc.lines() {
        if let Some(h) = line.strip_prefix("## ") {
            let h = h.trim();
            current = if h == "Global options" {
                Some(Vec::new())
            } else {
                h.strip_prefix("`probelab ")
                    .and_then(|c| c.strip_suffix('`'))
                    .map(|cmd| cmd.split_whitespace().map(String::from).collect())
            };
            if let Some(c) = &current {
                all.entry(c.clone()).or_default();
            }
        } else if let (Some(c), Some(row)) = (&current, line.strip_prefix('|')) {
            let first = row.split('|').next().unwrap_or("");
            let names = first.split('`').skip(1).step_by(2).filter_map(long_option);
            all.get_mut(c).unwrap().extend(names);
        }
    }
    all
}

fn show(path: &[String]) -> String {
    if path.is_empty() {
        "probelab".into()
    } else {
        format!("probelab {}", path.join(" "))
    }
}

#[test]
fn command_table_matches_help_both_ways() {
    let doc = read("docs/commands.md");
    let from_help = commands_from_help();
    let from_doc = commands_from_doc(&doc);
    let global = from_help.get(&Vec::new()).cloned().unwrap_or_default();
    assert!(global.contains("--jobs"), "parsed no global options from `probelab --help`: {global:?}");
    assert!(from_help.len() > 10, "parsed too few commands from `probelab --help`: {:?}", from_help.keys());
    let mut faults = Vec::new();
    for (path, opts) in &from_help {
        let section = if path.is_empty() { "## Global options".to_string() } else { format!("## `{}`", show(path)) };
        let Some(documented) = from_doc.get(path) else {
            faults.push(format!(
                "docs/commands.md has no section '{section}' for the command `{}` (in its parent's --help)",
                show(path)
            ));
            continue;
        };
        for o in opts {
            // Global options are documented once, under "Global options".
            if !path.is_empty() && global.contains(o) {
                continue;
            }
            if !documented.contains(o) {
                faults.push(format!(
                    "docs/commands.md, section '{section}', lacks the option `{o}` (in `{} --help`)",
                    show(path)
                ));
            }
        }
    }
    for (path, documented) in &from_doc {
        let Some(opts) = from_help.get(path) else {
            faults.push(format!(
                "docs/commands.md documents `{}`, which is not a command of the binary's --help",
                show(path)
            ));
            continue;
        };
        for o in documented.difference(opts) {
            faults.push(format!(
                "docs/commands.md documents the option `{o}` under `{}`, but `{} --help` has no such option",
                show(path),
                show(path)
            ));
        }
    }
    assert!(faults.is_empty(), "docs/commands.md and --help disagree:\n  {}", faults.join("\n  "));
}

/// The relative link targets of a Markdown text, outside code blocks and code spans.
fn links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // Drop code spans: `[a](b)` inside backticks is not a link.
        let plain: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
        let mut rest = plain.as_str();
        while let Some(at) = rest.find("](") {
            rest = &rest[at + 2..];
            let Some(end) = rest.find(')') else { break };
            let target = rest[..end].split_whitespace().next().unwrap_or("").to_string();
            rest = &rest[end..];
            if target.is_empty() || target.starts_with('#') || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            out.push(target);
        }
    }
    out
}

#[test]
fn every_relative_link_resolves() {
    let mut pages: Vec<PathBuf> = vec![repo().join("README.md"), repo().join("ARCHITECTURE.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(repo().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    let mut broken = Vec::new();
    let mut count = 0;
    for page in &pages {
        let text = std::fs::read_to_string(page).unwrap();
        let dir = page.parent().unwrap();
        for target in links(&text) {
            count += 1;
            let file = target.split('#').next().unwrap();
            if !Path::new(dir).join(file).exists() {
                broken.push(format!(
                    "{}: link `{target}` does not resolve",
                    page.strip_prefix(repo()).unwrap().display()
                ));
            }
        }
    }
    assert!(count > 10, "found only {count} relative links: is the link parser broken?");
    assert!(broken.is_empty(), "broken links:\n  {}", broken.join("\n  "));
}

#[test]
fn links_parser_sees_links_and_skips_code() {
    let md = "see [a](docs/a.md#x) and [web](https://x.org) and `[no](c.md)`\n```\n[no](d.md)\n```\n[b](../b.md)\n";
    assert_eq!(links(md), ["docs/a.md#x", "../b.md"]);
}

#[test]
fn readme_is_short_and_opens_with_its_purpose_then_the_two_commands() {
    let readme = read("README.md");
    let opening = readme.split("```sh").next().unwrap_or("");
    let prose = opening.lines().filter(|l| !l.starts_with('#') && !l.trim().is_empty()).count();
    assert!(
        prose >= 2,
        "README.md must open with a paragraph on what probelab is for, and for whom, then the two commands"
    );
    assert!(
        readme.len() < 10 * 1024,
        "README.md is {} bytes; keep it under 10 KiB (details go in docs/)",
        readme.len()
    );
    let block = readme.split("```sh").nth(1).expect("README.md has no ```sh block").split("```").next().unwrap();
    let commands: Vec<&str> =
        block.lines().map(|l| l.split('#').next().unwrap().trim()).filter(|l| !l.is_empty()).collect();
    assert_eq!(
        commands.get(..2),
        Some(&["cargo run --release -- reproduce", TEST_COMMAND][..]),
        "README.md's first code block must open with the two commands"
    );
    for forbidden in ["FORMULAS.md", "CLAIMS.md", "SOURCES.md"] {
        // results/CLAIMS.md is not cited either; the claims are in docs/claims.md.
        assert!(!readme.contains(forbidden), "README.md cites {forbidden}, which is not in the repository");
    }
}

/// The README's test command, which `.ci/run` runs as it stands: `--no-fail-fast`, so one
/// failing test binary does not stop the others (cargo still exits non-zero).
const TEST_COMMAND: &str = "cargo test --release --no-fail-fast";

#[test]
fn ci_runs_the_readme_test_command() {
    let ci = read(".ci/run");
    let want: Vec<&str> = TEST_COMMAND.split_whitespace().collect();
    let cargo_tests: Vec<Vec<&str>> = ci
        .lines()
        .map(|l| l.split('#').next().unwrap())
        .map(|l| {
            l.split_whitespace()
                .skip_while(|w| *w != "cargo")
                .take_while(|w| !w.starts_with(['2', '|', '>']))
                .collect::<Vec<_>>()
        })
        .filter(|w| w.get(..2) == Some(&["cargo", "test"][..]))
        .collect();
    assert!(!cargo_tests.is_empty(), ".ci/run runs no `cargo test`");
    for words in cargo_tests {
        assert_eq!(words, want, ".ci/run runs `{}`, not the README's test command `{TEST_COMMAND}`", words.join(" "));
    }
    // A failure of the tests is the script's exit status (the summary after them must not hide it).
    assert!(
        ci.contains("status=${PIPESTATUS[0]}") && ci.trim_end().ends_with("exit \"$status\""),
        ".ci/run must exit with cargo's status"
    );
}

#[test]
fn help_parsers_read_clap_blocks() {
    let text =
        "Usage: x\n\nCommands:\n  run   Run\n  help  Print\n\nOptions:\n      --jobs <JOBS>  J\n  -h, --help     H\n";
    assert_eq!(help_commands(text), ["run"]);
    assert_eq!(help_options(text).into_iter().collect::<Vec<_>>(), ["--help", "--jobs"]);
    let doc = "## Global options\n| `--jobs <J>` | x |\n## `probelab maps import`\n| `--out <O>`, `-o` | y |\n## Other\n| `--no` | z |\n";
    let parsed = commands_from_doc(doc);
    assert_eq!(parsed[&Vec::new()].iter().collect::<Vec<_>>(), ["--jobs"]);
    assert_eq!(parsed[&vec!["maps".to_string(), "import".to_string()]].iter().collect::<Vec<_>>(), ["--out"]);
    assert_eq!(parsed.len(), 2);
}

/// A command line of a ```` ```sh ```` block: the page, its line number, the block (its
/// opening line) and the command (a continued line joined, trimmed).
#[derive(Debug, PartialEq)]
struct DocCommand {
    page: String,
    line: usize,
    block: usize,
    command: String,
}

impl DocCommand {
    /// The command without its trailing comment (`# …` after white space), trimmed: what a
    /// manifest entry names.
    fn text(&self) -> &str {
        let c = self.command.as_str();
        let cut = c.char_indices().find(|&(i, ch)| ch == '#' && i > 0 && c[..i].ends_with(char::is_whitespace));
        cut.map_or(c, |(i, _)| &c[..i]).trim()
    }
}

/// Every command line of the ```` ```sh ```` blocks of `text`: a trailing `\` joins the next
/// line; comment lines are not commands.
fn sh_commands(page: &str, text: &str) -> Vec<DocCommand> {
    let mut out = Vec::new();
    let lines: Vec<&str> = text.lines().collect();
    let mut i = 0;
    while i < lines.len() {
        if lines[i].trim_end() != "```sh" {
            i += 1;
            continue;
        }
        let start = i + 1;
        let end = (start..lines.len()).find(|&k| lines[k].trim_start().starts_with("```")).unwrap_or(lines.len());
        let block = &lines[start..end];
        let mut k = 0;
        while k < block.len() {
            let first = k;
            let mut command = block[k].trim_end().to_string();
            while command.ends_with('\\') && k + 1 < block.len() {
                command.pop();
                k += 1;
                command = format!("{} {}", command.trim_end(), block[k].trim());
            }
            k += 1;
            let trimmed = command.trim();
            if trimmed.is_empty() || trimmed.starts_with('#') {
                continue;
            }
            out.push(DocCommand {
                page: page.to_string(),
                line: start + first + 1,
                block: start,
                command: trimmed.to_string(),
            });
        }
        i = end + 1;
    }
    out
}

/// Why a documented command is not run: `long` names the file of the repository that runs it
/// (or its equivalent), `needs` what a fresh clone lacks; at least one is set.
#[derive(Debug, Clone, PartialEq)]
struct Skip {
    long: Option<String>,
    needs: Option<String>,
}

/// An entry of the manifest (tests/docs_commands.toml): on `page`, the command line `key`
/// names (its whole text, or a prefix of exactly one), or with `block` every line of its block.
#[derive(Debug, PartialEq)]
struct Entry {
    page: String,
    key: String,
    skip: Skip,
    block: bool,
}

/// The manifest's entries, or what is wrong with it.
fn manifest(text: &str) -> Result<Vec<Entry>, String> {
    let table: toml::Table = text.parse().map_err(|e| format!("{e}"))?;
    let mut out = Vec::new();
    for (page, lines) in &table {
        let lines = lines.as_table().ok_or(format!("[\"{page}\"] is not a table"))?;
        for (key, value) in lines {
            let at = format!("[\"{page}\"] \"{key}\"");
            let fields = value.as_table().ok_or(format!("{at}: not a table"))?;
            if let Some(unknown) = fields.keys().find(|k| !["long", "needs", "block"].contains(&k.as_str())) {
                return Err(format!("{at}: unknown field `{unknown}` (long, needs, block)"));
            }
            let text_of = |f: &str| -> Result<Option<String>, String> {
                match fields.get(f) {
                    None => Ok(None),
                    Some(v) => v
                        .as_str()
                        .filter(|s| !s.trim().is_empty())
                        .map(|s| Some(s.to_string()))
                        .ok_or(format!("{at}: `{f}` must be a non-empty string")),
                }
            };
            let skip = Skip { long: text_of("long")?, needs: text_of("needs")? };
            if skip.long.is_none() && skip.needs.is_none() {
                return Err(format!("{at}: says neither `long` nor `needs`"));
            }
            let block = match fields.get("block") {
                None => false,
                Some(v) => v.as_bool().ok_or(format!("{at}: `block` must be true or false"))?,
            };
            out.push(Entry { page: page.clone(), key: key.clone(), skip, block });
        }
    }
    Ok(out)
}

/// Which command (an index into `commands`) each entry skips, and the faults: an entry whose
/// page has no such line (stale) or several, a `long` file that does not exist (`exists`
/// says), a line two entries claim, and a line that still carries a marker comment of its own.
fn classify(
    commands: &[DocCommand],
    entries: &[Entry],
    exists: impl Fn(&str) -> bool,
) -> (BTreeMap<usize, Skip>, Vec<String>) {
    let mut skipped = BTreeMap::new();
    let mut faults = Vec::new();
    for e in entries {
        let at = format!("tests/docs_commands.toml, [\"{}\"] \"{}\"", e.page, e.key);
        let on_page: Vec<usize> = (0..commands.len()).filter(|&i| commands[i].page == e.page).collect();
        let exact: Vec<usize> = on_page.iter().copied().filter(|&i| commands[i].text() == e.key).collect();
        let matched = if exact.is_empty() {
            on_page.iter().copied().filter(|&i| commands[i].text().starts_with(e.key.as_str())).collect()
        } else {
            exact
        };
        if let Some(file) = e.skip.long.as_deref().filter(|f| !exists(f)) {
            faults.push(format!("{at}: long = \"{file}\", which is not a file of the repository"));
        }
        let hit = match matched[..] {
            [one] => one,
            [] => {
                faults.push(format!("{at}: stale, no command line of {} is or starts with it", e.page));
                continue;
            }
            _ => {
                let lines: Vec<String> = matched.iter().map(|&i| commands[i].line.to_string()).collect();
                faults.push(format!("{at}: names several lines of {} ({})", e.page, lines.join(", ")));
                continue;
            }
        };
        let block = commands[hit].block;
        let lines = on_page.into_iter().filter(|&i| if e.block { commands[i].block == block } else { i == hit });
        for i in lines {
            if skipped.insert(i, e.skip.clone()).is_some() {
                faults.push(format!("{at}: {}:{} is named twice", e.page, commands[i].line));
            }
        }
    }
    for c in commands {
        if ["# long:", "# needs:"].iter().any(|m| c.command.contains(m)) {
            faults.push(format!(
                "{}:{}: a `# long:`/`# needs:` marker; say it in tests/docs_commands.toml instead",
                c.page, c.line
            ));
        }
    }
    (skipped, faults)
}

#[test]
fn sh_commands_join_lines_and_strip_comments() {
    let md = "x\n```sh\n# a comment\nprobelab a \\\n  --b\nprobelab c   # the paper probes\n```\n\
              ```text\nnot a command\n```\n```sh\n#!/bin/bash\nN=4 # four\nprobelab d \"#x\"\n```\n";
    let got = sh_commands("p.md", md);
    let short: Vec<(usize, usize, &str, &str)> =
        got.iter().map(|c| (c.line, c.block, c.command.as_str(), c.text())).collect();
    assert_eq!(
        short,
        [
            (4, 2, "probelab a --b", "probelab a --b"),
            (6, 2, "probelab c   # the paper probes", "probelab c"),
            (13, 11, "N=4 # four", "N=4"),
            (14, 11, "probelab d \"#x\"", "probelab d \"#x\""),
        ]
    );
}

/// The manifest's checks see what they look for: a whole line wins over a prefix, a block entry
/// covers its block, and a stale entry, an ambiguous prefix, a missing `long` file, a line named
/// twice and a marker left in a page are faults.
#[test]
fn the_manifest_classifies_lines_and_finds_its_faults() {
    let md =
        "```sh\nprobelab check\nprobelab check one\n```\n```sh\nN=4\nrun $N\n```\n```sh\nx   # long: run by y\n```\n";
    let commands = sh_commands("p.md", md);
    let toml =
        "[\"p.md\"]\n\"probelab check\" = { needs = \"maps\" }\n\"N=4\" = { long = \"tests/t.rs\", block = true }\n";
    let entries = manifest(toml).unwrap();
    let (skipped, faults) = classify(&commands, &entries, |f| f == "tests/t.rs");
    assert_eq!(skipped.keys().copied().collect::<Vec<_>>(), [0, 2, 3]);
    assert_eq!(skipped[&0].needs.as_deref(), Some("maps"));
    assert_eq!(faults.len(), 1, "{faults:?}");
    assert!(faults[0].starts_with("p.md:10: a `# long:`"), "{faults:?}");
    let bad = "[\"p.md\"]\n\"probelab check o\" = { needs = \"a\" }\n\"gone\" = { needs = \"b\" }\n\
               \"probelab\" = { long = \"tests/none.rs\" }\n\"run $N\" = { needs = \"c\" }\n\"N=4\" = { needs = \"d\", block = true }\n";
    let (_, faults) = classify(&commands, &manifest(bad).unwrap(), |f| f == "tests/t.rs");
    let says = |what: &str| faults.iter().filter(|f| f.contains(what)).count();
    assert_eq!(says("\"gone\": stale"), 1, "{faults:?}");
    assert_eq!(says("\"probelab\": names several lines of p.md (2, 3)"), 1, "{faults:?}");
    assert_eq!(says("is named twice"), 1, "{faults:?}");
    assert_eq!(says("long = \"tests/none.rs\", which is not a file"), 1, "{faults:?}");
    assert_eq!(faults.len(), 5, "{faults:?}");
    assert!(manifest("[\"p.md\"]\n\"x\" = { block = true }\n").is_err());
    assert!(manifest("[\"p.md\"]\n\"x\" = { lnog = \"a\" }\n").is_err());
}

/// The files of the checkout (`git ls-files`), copied to `to`.
fn copy_checkout(to: &Path) {
    let out = Command::new("git").args(["ls-files", "-z"]).current_dir(repo()).output().expect("git ls-files");
    assert!(out.status.success(), "git ls-files: {}", String::from_utf8_lossy(&out.stderr));
    for rel in out.stdout.split(|b| *b == 0).filter(|r| !r.is_empty()) {
        let rel = Path::new(std::str::from_utf8(rel).unwrap());
        let (from, dest) = (repo().join(rel), to.join(rel));
        if !from.is_file() {
            continue; // deleted in the working tree
        }
        std::fs::create_dir_all(dest.parent().unwrap()).unwrap();
        std::fs::copy(&from, &dest).unwrap_or_else(|e| panic!("{}: {e}", rel.display()));
    }
}

/// Runs `command` with `sh` in `dir`, `bin` first on PATH and `PROBELAB_ENVMAPS` unset; the
/// exit status and output, or `None` after `limit`.
fn run_line(command: &str, dir: &Path, bin: &Path, limit: std::time::Duration) -> Option<std::process::Output> {
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let mut child = Command::new("sh")
        .args(["-c", command])
        .current_dir(dir)
        .env("PATH", path)
        .env_remove("PROBELAB_ENVMAPS")
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run sh");
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            child.kill().ok();
            child.wait().ok();
            return None;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    Some(child.wait_with_output().unwrap())
}

/// Every command of README.md's and docs/*.md's ```` ```sh ```` blocks runs on a fresh clone
/// (the committed maps only), in page order, in a copy of the checkout, with the binary as
/// `probelab`; or the manifest (tests/docs_commands.toml) says why not, each of its entries
/// naming a line that exists and each `long` a file of the repository.
#[test]
fn every_documented_command_runs_on_a_fresh_clone_or_is_in_the_manifest() {
    let mut pages = vec![PathBuf::from("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(repo().join("docs"))
        .unwrap()
        .map(|e| PathBuf::from("docs").join(e.unwrap().file_name()))
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    let commands: Vec<DocCommand> =
        pages.iter().flat_map(|p| sh_commands(&p.display().to_string(), &read(&p.display().to_string()))).collect();
    assert!(commands.len() > 20, "found only {} commands: is the block parser broken?", commands.len());
    let entries = manifest(&read(MANIFEST)).unwrap_or_else(|e| panic!("{MANIFEST}: {e}"));
    let (skipped, mut faults) = classify(&commands, &entries, |f| repo().join(f).is_file());
    for e in entries.iter().filter(|e| !pages.iter().any(|p| p.as_os_str() == e.page.as_str())) {
        faults.push(format!("{MANIFEST}: [\"{}\"] is not README.md or a page of docs/", e.page));
    }
    let checkout = tempfile::tempdir().unwrap();
    copy_checkout(checkout.path());
    let bin = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_probelab"), bin.path().join("probelab")).unwrap();
    let mut ran = 0;
    for (i, c) in commands.iter().enumerate() {
        if skipped.contains_key(&i) {
            continue;
        }
        ran += 1;
        let at = format!("{}:{}: `{}`", c.page, c.line, c.command);
        match run_line(&c.command, checkout.path(), bin.path(), std::time::Duration::from_secs(30)) {
            None => faults.push(format!("{at}: still running after 30 s (fix it, or say `long` in {MANIFEST})")),
            Some(out) if !out.status.success() => faults.push(format!(
                "{at}: exit {:?} on a fresh clone (fix it, or say `long` or `needs` in {MANIFEST}):\n    {}",
                out.status.code(),
                String::from_utf8_lossy(&out.stderr).trim().replace('\n', "\n    ")
            )),
            Some(_) => {}
        }
    }
    assert!(ran >= 5, "only {ran} documented commands ran");
    assert!(faults.is_empty(), "documented commands:\n  {}", faults.join("\n  "));
}
