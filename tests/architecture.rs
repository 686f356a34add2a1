//! The architecture, checked: every `crate::` path in `src/` against the layer table of
//! `ARCHITECTURE.md` ("## Layers": layer, what, may use), and the module files for import
//! cycles.
//!
//! - A layer is a row of the table: the folder `src/<layer>/` or the file `src/<layer>.rs`, plus
//!   the crate-root files its "what" cell names (`main.rs`). What a layer uses is every
//!   `crate::<layer>` path in its files' code (comments are not code; unit tests are), other
//!   than its own; the binary's files (`main.rs` and the modules it declares) say `probelab::`.
//! - The table must say exactly what the code does: a use the table does not allow fails, and
//!   so does an allowance the code does not use (the table may not overstate either).
//! - The table is ordered bottom-up: a layer may use only layers listed above it, so there is
//!   no upward import and no circle between layers.
//! - Between module files (e.g. `pipeline::runner` and `pipeline::timing`, or a `mod.rs` and
//!   its own children) there is no circle.
//! - Every file the "## Code map" tables name exists under `src/`.
//! - Outside `encoders/` and `claims/`, product code names no encoder: no string literal in
//!   code before a file's `#[cfg(test)]` (every literal of a line, an element of a list literal
//!   `["sh1", "sh2"]` as much as one alone) is a registered encoder id, or a comma-separated
//!   list of them (`"sh1,sh2"`); a unit-test file of its own, `tests.rs`, is test code
//!   throughout.
//! - The modules whose product code touches the disk — opens, reads, writes or lists files
//!   (`fs::`, `File::`, `OpenOptions`) or asks about a path (`.is_file()`, `.is_dir()`,
//!   `.exists()`, `try_exists(`, `fs::metadata`, `symlink_metadata`) — are exactly the ones
//!   ARCHITECTURE.md lists ("Only these modules touch the disk").

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn src_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            src_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The module path of a file under `src/` (`envmap/mod.rs` → `envmap`, `math/sh.rs` →
/// `math::sh`); `None` for the crate roots.
fn module_of(rel: &Path) -> Option<Vec<String>> {
    let mut parts: Vec<String> = rel.iter().map(|s| s.to_string_lossy().into_owned()).collect();
    let last = parts.pop()?;
    let stem = last.strip_suffix(".rs")?.to_string();
    if parts.is_empty() && (stem == "lib" || stem == "main") {
        return None;
    }
    if stem != "mod" {
        parts.push(stem);
    }
    Some(parts)
}

/// The code of a file: `//` comments removed (doc links are not imports).
fn code_of(text: &str) -> String {
    text.lines()
        .map(|l| {
            // A `//` inside a string literal is rare in this crate; cut at the first one.
            match l.find("//") {
                Some(i) => &l[..i],
                None => l,
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every `crate::a::b::…` path in `code`, as segments.
fn crate_paths(code: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        let before = rest[..i].chars().last();
        rest = &rest[i + "crate::".len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$') {
            continue; // e.g. `$crate::` or an identifier ending in "crate"
        }
        let mut segs = Vec::new();
        let mut s = rest;
        loop {
            let end = s.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(s.len());
            if end == 0 {
                break;
            }
            segs.push(s[..end].to_string());
            s = &s[end..];
            match s.strip_prefix("::") {
                Some(t) => s = t,
                None => break,
            }
        }
        if !segs.is_empty() {
            out.push(segs);
        }
    }
    out
}

/// The byte offset of the first inline module (`mod x {`, any visibility) in `code`, where
/// `super` stops meaning the file's parent.
fn inline_mod_start(code: &str) -> Option<usize> {
    let mut at = 0;
    for line in code.split_inclusive('\n') {
        let t = line.trim_start();
        let t = ["pub(crate) ", "pub(super) ", "pub "].iter().find_map(|v| t.strip_prefix(v)).unwrap_or(t);
        if let Some(rest) = t.strip_prefix("mod ") {
            let end = rest.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(rest.len());
            if end > 0 && rest[end..].trim_start().starts_with('{') {
                return Some(at);
            }
        }
        at += line.len();
    }
    None
}

/// `code` without its `#[cfg(test)] mod x { … }` blocks. A unit-test module is a leaf of the
/// module graph (nothing imports it), so what it uses cannot close a circle.
fn without_test_modules(code: &str) -> String {
    let mut out = String::new();
    let mut rest = code;
    while let Some(i) = rest.find("#[cfg(test)]") {
        let after = &rest[i + "#[cfg(test)]".len()..];
        // Other attributes may sit between `#[cfg(test)]` and the `mod` line.
        let between = |k: usize| after[..k].lines().all(|l| l.trim().is_empty() || l.trim().starts_with("#["));
        let Some(open) =
            inline_mod_start(after).filter(|&k| between(k)).and_then(|k| after[k..].find('{').map(|b| k + b))
        else {
            out.push_str(&rest[..i + "#[cfg(test)]".len()]);
            rest = after;
            continue;
        };
        out.push_str(&rest[..i]);
        // The matching brace; `'{'` and `'}'` char literals aside, braces in this crate balance.
        let body = &after[open..];
        let (mut depth, mut close) = (0usize, body.len());
        let bytes = body.as_bytes();
        for (k, &b) in bytes.iter().enumerate() {
            let quoted = k > 0 && bytes[k - 1] == b'\'' && bytes.get(k + 1) == Some(&b'\'');
            match b {
                b'{' if !quoted => depth += 1,
                b'}' if !quoted => {
                    depth -= 1;
                    if depth == 0 {
                        close = k + 1;
                        break;
                    }
                }
                _ => {}
            }
        }
        rest = &body[close..];
    }
    out.push_str(rest);
    out
}

/// `super::x` paths of a file's top level (before any inline `mod … {`, where `super` would
/// mean the file itself), resolved against the file's module; `super::super::x` climbs twice.
fn super_paths(code: &str, module: &[String]) -> Vec<Vec<String>> {
    let top = &code[..inline_mod_start(code).unwrap_or(code.len())];
    let mut out = Vec::new();
    let mut rest = top;
    while let Some(i) = rest.find("super::") {
        let preceded = top[..top.len() - rest.len() + i].chars().next_back();
        rest = &rest[i..];
        let mut ups = 0;
        while let Some(r) = rest.strip_prefix("super::") {
            rest = r;
            ups += 1;
        }
        // `x::super::` is not a path from this file (it does not occur in this crate).
        if preceded.is_some_and(|c| c == ':') {
            continue;
        }
        // `super` of `a/b.rs` (module `a::b`) is `a`; so is that of `a/b/mod.rs`.
        let mut p: Vec<String> = module[..module.len().saturating_sub(ups)].to_vec();
        let end = rest.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(rest.len());
        if end > 0 {
            p.push(rest[..end].to_string());
            out.push(p);
        }
    }
    out
}

/// A parent's uses of its own child modules by relative path: `child::x`, `self::child::x` or
/// `use child as y`, for each name in `children` (`mod child;` alone declares, it does not
/// use). Paths after `::` are someone else's (`crate::…` paths are read by [`crate_paths`]);
/// a method's turbofish (`.collect::<…>`) and a generic call (`fit::<T>`) are not modules.
fn child_paths(code: &str, module: &[String], children: &BTreeSet<String>) -> Vec<Vec<String>> {
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut out = Vec::new();
    for child in children {
        let mut from = 0;
        while let Some(k) = code[from..].find(child.as_str()) {
            let i = from + k;
            from = i + child.len();
            let (before, after) = (&code[..i], &code[i + child.len()..]);
            let outer = before.strip_suffix("self::").unwrap_or(before);
            let prev = outer.chars().last();
            if prev.is_some_and(|c| ident(c) || c == ':' || c == '.') || after.starts_with(ident) {
                continue;
            }
            if (after.starts_with("::") && !after.starts_with("::<")) || after.starts_with(" as ") {
                let mut p = module.to_vec();
                p.push(child.clone());
                out.push(p);
            }
        }
    }
    out
}

/// A row of ARCHITECTURE.md's layer table.
#[derive(Debug, PartialEq)]
struct Layer {
    /// The first cell, in backticks: the folder `src/<name>/` or the file `src/<name>.rs`.
    name: String,
    /// The crate-root files the row's "what" cell names in backticks (`main.rs`, `lib.rs`):
    /// files of `src/` that belong to this layer although they are not named after it.
    files: BTreeSet<String>,
    /// The last cell: the layers it may use, in backticks, comma-separated (`—` for none).
    uses: BTreeSet<String>,
}

/// The layer table of ARCHITECTURE.md ("## Layers", `| layer | what | may use |`), bottom-up:
/// one row per layer; rows whose first cell is not a name in backticks (the header and the
/// separator) are skipped, so adding a layer is adding a row.
fn layer_table(text: &str) -> Vec<Layer> {
    let section = text.split("\n## Layers").nth(1).expect("ARCHITECTURE.md has a '## Layers' section");
    let ticked = |cell: &str| -> Vec<String> { cell.split('`').skip(1).step_by(2).map(String::from).collect() };
    let mut rows = Vec::new();
    for line in section.lines().skip_while(|l| !l.starts_with('|')) {
        if !line.starts_with('|') {
            break;
        }
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        let Some(name) = cells.first().and_then(|c| c.strip_prefix('`')).and_then(|c| c.strip_suffix('`')) else {
            continue; // the header and the separator row
        };
        let files = match cells.len() {
            3.. => ticked(cells[1]).into_iter().filter(|f| f.ends_with(".rs") && !f.contains('/')).collect(),
            _ => BTreeSet::new(),
        };
        let uses = ticked(cells.last().unwrap()).into_iter().collect();
        rows.push(Layer { name: name.to_string(), files, uses });
    }
    assert!(!rows.is_empty(), "the '## Layers' table of ARCHITECTURE.md has no rows");
    rows
}

struct Crate {
    /// module path → (file, code), crate roots aside
    modules: BTreeMap<Vec<String>, (PathBuf, String)>,
    /// Every file of `src/` (crate roots included): (path relative to `src/`, code)
    files: Vec<(PathBuf, String)>,
}

/// The binary's files: `main.rs` and the modules it declares (`mod cli;` → `cli.rs` or
/// `cli/…`). They reach the library as `probelab::…`, read here as `crate::…`.
fn is_binary_file(rel: &Path, main_code: &str) -> bool {
    let first = rel.iter().next().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let stem = first.strip_suffix(".rs").unwrap_or(&first);
    rel == Path::new("main.rs")
        || main_code.lines().any(|l| {
            let l = l.trim();
            let l = l.strip_prefix("pub ").unwrap_or(l);
            l.strip_prefix("mod ").and_then(|m| m.strip_suffix(';')).is_some_and(|m| m.trim() == stem)
        })
}

fn read_crate() -> Crate {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut paths = Vec::new();
    src_files(&root, &mut paths);
    paths.sort();
    let main_code = code_of(&std::fs::read_to_string(root.join("main.rs")).unwrap_or_default());
    let mut modules = BTreeMap::new();
    let mut files = Vec::new();
    for f in paths {
        let rel = f.strip_prefix(&root).unwrap().to_path_buf();
        let mut code = code_of(&std::fs::read_to_string(&f).unwrap());
        if is_binary_file(&rel, &main_code) {
            code = code.replace("probelab::", "crate::");
        }
        if let Some(m) = module_of(&rel) {
            modules.insert(m, (rel.clone(), code.clone()));
        }
        files.push((rel, code));
    }
    Crate { modules, files }
}

/// The layer a file of `src/` belongs to: the row that names it (`main.rs`), else its first
/// component (`pipeline/runner.rs` → `pipeline`, `cli.rs` → `cli`); `None` for a crate root no
/// row names.
fn layer_of(rel: &Path, table: &[Layer]) -> Option<String> {
    let s = rel.to_string_lossy();
    if let Some(l) = table.iter().find(|l| l.files.contains(s.as_ref())) {
        return Some(l.name.clone());
    }
    let first = rel.iter().next()?.to_string_lossy().into_owned();
    match first.strip_suffix(".rs") {
        Some("lib" | "main") if rel.components().count() == 1 => None,
        Some(stem) => Some(stem.to_string()),
        None => Some(first),
    }
}

fn architecture_md() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md")).unwrap()
}

/// What the table says against what the code does: errors, one line each.
/// The crate root's re-exports of a layer's module (`pub use io::progress;` in `lib.rs`): the
/// name, and the layer it belongs to. A path through one is a use of that layer.
fn root_reexports() -> BTreeMap<String, String> {
    let lib = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/lib.rs")).unwrap();
    code_of(&lib)
        .lines()
        .filter_map(|l| l.trim().strip_prefix("pub use ")?.strip_suffix(';'))
        .filter_map(|p| {
            let segs: Vec<&str> = p.split("::").collect();
            (segs.len() == 2 && segs.iter().all(|s| s.chars().all(|c| c.is_alphanumeric() || c == '_')))
                .then(|| (segs[1].to_string(), segs[0].to_string()))
        })
        .collect()
}

fn layer_errors(table: &[Layer], krate: &Crate) -> Vec<String> {
    let mut errors = Vec::new();
    let aliases = root_reexports();
    // What each layer's code uses, with one example place per use.
    let mut used: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    for (file, code) in &krate.files {
        let Some(layer) = layer_of(file, table) else {
            errors.push(format!("src/{}: no row of ARCHITECTURE.md's layer table names it", file.display()));
            continue;
        };
        let uses = used.entry(layer.clone()).or_default();
        for p in crate_paths(code) {
            let used_layer = aliases.get(&p[0]).unwrap_or(&p[0]);
            if *used_layer != layer {
                uses.entry(used_layer.clone())
                    .or_insert_with(|| format!("src/{}: crate::{}", file.display(), p.join("::")));
            }
        }
    }
    let names: Vec<&String> = table.iter().map(|l| &l.name).collect();
    for layer in used.keys() {
        if !names.contains(&layer) {
            errors.push(format!("layer `{layer}` (src/{layer}) is not in ARCHITECTURE.md's layer table"));
        }
    }
    for (i, row) in table.iter().enumerate() {
        let layer = &row.name;
        if names[..i].contains(&layer) {
            errors.push(format!("ARCHITECTURE.md: layer `{layer}` has two rows"));
        }
        for f in &row.files {
            if !krate.files.iter().any(|(p, _)| p == Path::new(f)) {
                errors.push(format!("ARCHITECTURE.md: layer `{layer}` names `{f}`, which is not a file of src/"));
            }
            if let Some(other) = table[..i].iter().find(|o| o.files.contains(f)) {
                errors.push(format!("ARCHITECTURE.md: `{f}` is named by both `{}` and `{layer}`", other.name));
            }
        }
        for a in &row.uses {
            if !names[..i].contains(&a) {
                errors.push(format!("ARCHITECTURE.md: `{layer}` may use `{a}`, which is not a layer listed above it"));
            }
        }
        let actual = used.get(layer).cloned().unwrap_or_default();
        for (u, place) in &actual {
            if !row.uses.contains(u) {
                errors.push(format!("`{layer}` uses `{u}`, which ARCHITECTURE.md does not allow ({place})"));
            }
        }
        for a in &row.uses {
            if !actual.contains_key(a) {
                errors.push(format!("ARCHITECTURE.md says `{layer}` may use `{a}`, but no code of `{layer}` does"));
            }
        }
    }
    errors
}

#[test]
fn layers_use_exactly_what_architecture_md_allows() {
    let errors = layer_errors(&layer_table(&architecture_md()), &read_crate());
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

/// The file paths of the "## Code map" tables (the first cell of each row, in backticks,
/// relative to the folder of the `### \`folder/\`` heading above it, or to `src/`), and the
/// `.rs` files a folder's row lists in its second cell, relative to that folder.
fn code_map_paths(text: &str) -> Vec<String> {
    let section = text.split("\n## Code map").nth(1).expect("ARCHITECTURE.md has a '## Code map' section");
    let section = section.split("\n## ").next().unwrap();
    let ticked = |cell: &str| -> Vec<String> { cell.split('`').skip(1).step_by(2).map(String::from).collect() };
    let mut folder = String::new();
    let mut out = Vec::new();
    for line in section.lines() {
        if let Some(h) = line.strip_prefix("### ") {
            folder = ticked(h).into_iter().next().unwrap_or_default();
            continue;
        }
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        if !line.starts_with('|') || cells.len() < 2 {
            continue;
        }
        for f in ticked(cells[0]) {
            if f.ends_with('/') {
                let sub = format!("{folder}{f}");
                out.extend(ticked(cells[1]).into_iter().filter(|g| g.ends_with(".rs")).map(|g| format!("{sub}{g}")));
            }
            out.push(format!("{folder}{f}"));
        }
    }
    out
}

#[test]
fn the_code_map_names_only_files_that_exist() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let paths = code_map_paths(&architecture_md());
    assert!(paths.len() > 50, "the code map lists too few files to be read right: {paths:?}");
    let gone: Vec<&String> = paths.iter().filter(|p| !src.join(p).exists()).collect();
    assert!(gone.is_empty(), "ARCHITECTURE.md's code map names files that are not under src/: {gone:?}");
}

/// Module graph: module → the module files it imports. An import is a `crate::` path, a
/// `super::` path, or a parent's relative path to its own child (`child::x`), each resolved to
/// the longest module file it names (`crate::encoders::build` → `encoders`, the `mod.rs`), in
/// product code (unit-test modules aside).
type Edges = BTreeMap<Vec<String>, BTreeSet<Vec<String>>>;

fn import_edges(modules: &BTreeMap<Vec<String>, (PathBuf, String)>) -> Edges {
    let resolve = |p: &[String]| -> Option<Vec<String>> {
        (1..=p.len()).rev().map(|k| p[..k].to_vec()).find(|c| modules.contains_key(c))
    };
    let mut edges = Edges::new();
    for (m, (_, code)) in modules {
        let code = without_test_modules(code);
        let children: BTreeSet<String> =
            modules.keys().filter(|c| c.len() == m.len() + 1 && c.starts_with(m)).map(|c| c[m.len()].clone()).collect();
        let mut targets: Vec<Vec<String>> = crate_paths(&code);
        targets.extend(super_paths(&code, m));
        targets.extend(child_paths(&code, m, &children));
        for t in targets {
            if let Some(r) = resolve(&t) {
                if &r != m {
                    edges.entry(m.clone()).or_default().insert(r);
                }
            }
        }
    }
    edges
}

/// The circles of the graph: its strongly connected components of more than one module
/// (Tarjan), each as sorted `a::b` names.
fn cycles(nodes: impl IntoIterator<Item = Vec<String>>, edges: &Edges) -> Vec<Vec<String>> {
    struct Tarjan<'a> {
        edges: &'a Edges,
        index: BTreeMap<Vec<String>, usize>,
        low: BTreeMap<Vec<String>, usize>,
        stack: Vec<Vec<String>>,
        on: BTreeSet<Vec<String>>,
        cycles: Vec<Vec<String>>,
    }
    impl Tarjan<'_> {
        fn visit(&mut self, v: &Vec<String>) {
            let i = self.index.len();
            self.index.insert(v.clone(), i);
            self.low.insert(v.clone(), i);
            self.stack.push(v.clone());
            self.on.insert(v.clone());
            for w in self.edges.get(v).cloned().unwrap_or_default() {
                if !self.index.contains_key(&w) {
                    self.visit(&w);
                    let l = self.low[v].min(self.low[&w]);
                    self.low.insert(v.clone(), l);
                } else if self.on.contains(&w) {
                    let l = self.low[v].min(self.index[&w]);
                    self.low.insert(v.clone(), l);
                }
            }
            if self.low[v] == self.index[v] {
                let mut comp = Vec::new();
                loop {
                    let w = self.stack.pop().unwrap();
                    self.on.remove(&w);
                    comp.push(w.join("::"));
                    if &w == v {
                        break;
                    }
                }
                if comp.len() > 1 {
                    comp.sort();
                    self.cycles.push(comp);
                }
            }
        }
    }
    let mut t = Tarjan {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        cycles: Vec::new(),
    };
    for m in nodes {
        if !t.index.contains_key(&m) {
            t.visit(&m);
        }
    }
    t.cycles
}

#[test]
fn no_import_cycles_between_module_files() {
    let krate = read_crate();
    let found = cycles(krate.modules.keys().cloned(), &import_edges(&krate.modules));
    assert!(found.is_empty(), "import cycles between module files: {found:?}");
}

/// The cycle check on a small synthetic crate: a `mod.rs` and its child that import each
/// other — through `super::`, `crate::`, `child::` or `self::child::` — form a circle; a
/// `mod child;` declaration alone, a unit test reaching up, a sibling, or a grandchild's
/// `super::super::` reaching past its parent does not.
#[test]
fn the_cycle_check_sees_a_mod_rs_and_its_child() {
    let crate_of = |files: &[(&str, &str)]| -> BTreeMap<Vec<String>, (PathBuf, String)> {
        files
            .iter()
            .map(|(rel, code)| (module_of(Path::new(rel)).unwrap(), (PathBuf::from(rel), code_of(code))))
            .collect()
    };
    let circle = vec![vec!["enc".to_string(), "enc::wrap".to_string()]];
    let parents =
        ["pub mod wrap;\nuse wrap::W;\npub fn build() {}", "pub mod wrap;\npub use self::wrap::W;\npub fn build() {}"];
    let parents =
        parents.iter().copied().chain(["pub mod wrap;\nconst R: &[fn()] = &[crate::enc::wrap::w];\npub fn build() {}"]);
    for parent in parents {
        for child in ["pub fn w() { super::build() }", "pub fn w() { crate::enc::build() }"] {
            let k = crate_of(&[("enc/mod.rs", parent), ("enc/wrap.rs", child)]);
            assert_eq!(cycles(k.keys().cloned(), &import_edges(&k)), circle, "{parent} / {child}");
        }
    }
    let acyclic = [
        ("enc/mod.rs", "pub mod wrap;\npub mod sh;\npub fn build() { wrap::w() }\nfn f() -> Vec<u8> { x.sh::<u8>() }"),
        ("enc/wrap.rs", "pub fn w() { super::sh::s() }\n#[cfg(test)]\n#[allow(unused)]\nmod tests {\n fn t() { crate::enc::build(); let c = '{'; }\n}"),
        ("enc/sh.rs", "pub fn s() {}"),
    ];
    let k = crate_of(&acyclic);
    assert_eq!(cycles(k.keys().cloned(), &import_edges(&k)), Vec::<Vec<String>>::new());
    // `super::super::x` in a grandchild names its grandparent's `x`, not its parent.
    assert_eq!(
        super_paths("use super::super::lune::Angle;", &["enc".into(), "fit".into(), "a".into()]),
        [["enc".to_string(), "lune".to_string()]]
    );
    let nested = [
        (
            "enc/mod.rs",
            "pub mod fit;
pub mod lune;",
        ),
        ("enc/lune.rs", "pub struct Angle;"),
        (
            "enc/fit/mod.rs",
            "mod a;
pub use a::f;",
        ),
        (
            "enc/fit/a.rs",
            "use super::super::lune::Angle;
pub fn f() {}",
        ),
    ];
    let k = crate_of(&nested);
    assert_eq!(cycles(k.keys().cloned(), &import_edges(&k)), Vec::<Vec<String>>::new());
}

/// A module's product code: what comes before its `#[cfg(test)]`; nothing for a unit-test
/// module in a file of its own (`…/tests.rs`, declared `#[cfg(test)] mod tests;`) or for the
/// crate's cross-layer tests (`src/tests/`, declared `#[cfg(test)] mod tests;` in `lib.rs`).
fn product_code<'a>(module: &[String], code: &'a str) -> &'a str {
    if module.last().is_some_and(|m| m == "tests") || module.first().is_some_and(|m| m == "tests") {
        return "";
    }
    code.split("#[cfg(test)]").next().unwrap()
}

/// The string literals of Rust source `src` (its comments skipped), each with its line; and the
/// line of its first `#[cfg(test)]` outside comments and literals, where product code ends.
/// Normal, byte, C and raw strings (`r#"…"#`) are read; char literals (`'"'`) and lifetimes
/// are stepped over. A literal's text is as written, escapes unread.
fn string_literals(src: &str) -> (Vec<(usize, String)>, Option<usize>) {
    let b = src.as_bytes();
    let ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let (mut out, mut test_line, mut line, mut i) = (Vec::new(), None, 1, 0);
    // Steps over `b[from..to]`, counting its newlines.
    let skip = |line: &mut usize, from: usize, to: usize| {
        *line += b[from..to.min(b.len())].iter().filter(|&&c| c == b'\n').count();
        to
    };
    while i < b.len() {
        let rest = &b[i..];
        if rest.starts_with(b"//") {
            i = rest.iter().position(|&c| c == b'\n').map_or(b.len(), |k| i + k);
        } else if rest.starts_with(b"/*") {
            let (mut depth, mut k) = (0usize, i);
            while k < b.len() {
                if b[k..].starts_with(b"/*") {
                    depth += 1;
                    k += 2;
                } else if b[k..].starts_with(b"*/") {
                    depth -= 1;
                    k += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    k += 1;
                }
            }
            i = skip(&mut line, i, k);
        } else if let Some((open, raw, hashes)) = string_start(b, i, ident) {
            let close = format!("\"{}", "#".repeat(hashes));
            let body = open + 1;
            let end = if raw {
                b[body..].windows(close.len()).position(|w| w == close.as_bytes()).map_or(b.len(), |k| body + k)
            } else {
                let mut k = body;
                while k < b.len() && b[k] != b'"' {
                    k += if b[k] == b'\\' { 2 } else { 1 };
                }
                k.min(b.len())
            };
            out.push((line, String::from_utf8_lossy(&b[body..end]).into_owned()));
            i = skip(&mut line, i, end + close.len());
        } else if b[i] == b'\'' {
            // A char literal ('x', '\'', '"') ends within a few bytes; a lifetime does not close.
            let close = (i + 2..(i + 12).min(b.len())).find(|&k| b[k] == b'\'' && (b[k - 1] != b'\\' || k == i + 3));
            i = match close {
                Some(k) if b[i + 1] == b'\\' || src[i + 1..k].chars().count() == 1 => k + 1,
                _ => i + 1,
            };
        } else if ident(b[i]) {
            i = (i..b.len()).find(|&k| !ident(b[k])).unwrap_or(b.len());
        } else {
            if rest.starts_with(b"#[cfg(test)]") && test_line.is_none() {
                test_line = Some(line);
            }
            line += usize::from(b[i] == b'\n');
            i += 1;
        }
    }
    (out, test_line)
}

/// Whether a string literal opens at `i` (`"`, `b"`, `c"`, `r"`, `r#"`, `br#"`…, not inside
/// an identifier): the offset of its opening quote, whether it is raw, and its number of `#`.
fn string_start(b: &[u8], i: usize, ident: impl Fn(u8) -> bool) -> Option<(usize, bool, usize)> {
    if i > 0 && ident(b[i - 1]) {
        return None;
    }
    let mut k = i;
    if k < b.len() && (b[k] == b'b' || b[k] == b'c') {
        k += 1;
    }
    if k < b.len() && b[k] == b'r' {
        k += 1;
        let hashes = b[k..].iter().take_while(|&&c| c == b'#').count();
        return (b.get(k + hashes) == Some(&b'"')).then_some((k + hashes, true, hashes));
    }
    (b.get(k) == Some(&b'"')).then_some((k, false, 0))
}

/// The encoder ids a string literal names: itself, if it is one, or every part of a
/// comma-separated list (`"sh1,sh2"`, `"sh1, zh3_hallucinate"`) whose parts all are.
fn named_encoders(lit: &str, ids: &BTreeSet<String>) -> Vec<String> {
    if ids.contains(lit) {
        return vec![lit.to_string()];
    }
    let parts: Vec<&str> = lit.split(',').map(str::trim).collect();
    if parts.len() > 1 && parts.iter().all(|p| ids.contains(*p)) {
        return parts.into_iter().map(String::from).collect();
    }
    Vec::new()
}

/// Where product code (before the first `#[cfg(test)]`) names an encoder in a string literal,
/// alone, as an element of a list literal or joined by commas: (line, literal).
fn encoder_literals(src: &str, ids: &BTreeSet<String>) -> Vec<(usize, String)> {
    let (literals, test_line) = string_literals(src);
    literals
        .into_iter()
        .filter(|(line, lit)| test_line.is_none_or(|t| *line < t) && !named_encoders(lit, ids).is_empty())
        .collect()
}

#[test]
fn only_encoders_and_claims_name_an_encoder() {
    let ids: BTreeSet<String> = probelab::encoders::REGISTRY.iter().map(|k| k.id.to_string()).collect();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut errors = Vec::new();
    for (m, (file, _)) in &read_crate().modules {
        // A unit-test file of its own (`…/tests.rs`) and the cross-layer tests (`src/tests/`) are
        // test code throughout.
        if m[0] == "encoders" || m[0] == "claims" || m[0] == "tests" || m.last().is_some_and(|x| x == "tests") {
            continue;
        }
        let text = std::fs::read_to_string(src.join(file)).unwrap();
        for (line, lit) in encoder_literals(&text, &ids) {
            errors.push(format!("src/{}:{line}: names encoder \"{lit}\"", file.display()));
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

/// What, in a module's product code, touches the disk: opening, reading, writing or listing
/// files (`fs::`, `File::`, `OpenOptions`), and asking whether or what a path is.
const DISK: [&str; 9] = [
    "fs::",
    "File::",
    "OpenOptions",
    ".is_file()",
    ".is_dir()",
    ".exists()",
    "try_exists(",
    "fs::metadata",
    "symlink_metadata",
];

/// The marks of [`DISK`] that `product` holds.
fn disk_touches(product: &str) -> Vec<&'static str> {
    DISK.iter().copied().filter(|p| product.contains(p)).collect()
}

#[test]
fn only_the_listed_modules_touch_the_disk() {
    let arch = architecture_md();
    let start = arch
        .find("**Only these modules touch the disk**")
        .expect("ARCHITECTURE.md states which modules touch the disk");
    let rest = &arch[start..];
    let end = rest[2..].find("\n- **").map(|i| i + 2).unwrap_or(rest.len());
    let listed: BTreeSet<String> = rest[..end]
        .split('`')
        .skip(1)
        .step_by(2)
        .filter(|s| s.chars().all(|c| c.is_alphanumeric() || c == '_' || c == ':'))
        .map(String::from)
        .collect();
    let krate = read_crate();
    let mut touching = BTreeMap::new();
    for (m, (_, code)) in &krate.modules {
        let marks = disk_touches(product_code(m, code));
        if !marks.is_empty() {
            touching.insert(m.join("::"), marks);
        }
    }
    let unlisted: Vec<_> = touching.iter().filter(|(m, _)| !listed.contains(*m)).collect();
    let idle: Vec<_> = listed.iter().filter(|m| !touching.contains_key(*m)).collect();
    assert!(
        unlisted.is_empty() && idle.is_empty(),
        "touch the disk but are not listed in ARCHITECTURE.md: {unlisted:?}; listed but touch no file: {idle:?}"
    );
}

/// The encoder rule sees every literal of a line, a list literal's elements, comma-joined ids,
/// raw and multi-line strings; not comments, char literals, partial lists or unit tests.
#[test]
fn the_encoder_rule_sees_literals_lists_and_joined_ids() {
    let ids: BTreeSet<String> = ["sh1", "sh2", "zh3_x"].iter().map(|s| s.to_string()).collect();
    let src = concat!(
        "let a = (\"x\", \"sh2\"); let q = '\"'; let l: &'static str = \"sh1\";\n",
        "const E: [&str; 2] = [\"sh1\", \"zh3_x\"]; // \"sh2\"\n",
        "let j = \"sh1,sh2\"; let k = \"sh1, zh3_x\"; let no = \"sh1,all\"; let s = \"--encoders sh1\";\n",
        "/* \"sh1\" */ let r = r#\"zh3_x\"#; let m = \"a\n\\\"b\"; let esc = \"say \\\"sh9\\\"\";\n",
        "let after = \"sh2\";\n",
        "#[cfg(test)]\nmod tests { const T: &str = \"sh1\"; }\n",
    );
    let found: Vec<(usize, String)> = encoder_literals(src, &ids);
    let want: Vec<(usize, String)> =
        [(1, "sh2"), (1, "sh1"), (2, "sh1"), (2, "zh3_x"), (3, "sh1,sh2"), (3, "sh1, zh3_x"), (4, "zh3_x"), (6, "sh2")]
            .iter()
            .map(|(l, s)| (*l, s.to_string()))
            .collect();
    assert_eq!(found, want);
    assert_eq!(named_encoders("sh1, zh3_x", &ids), ["sh1", "zh3_x"]);
}

/// The disk rule sees file checks and metadata as well as reads and writes.
#[test]
fn the_disk_rule_sees_file_checks() {
    let cases = [
        ("if path.is_file() {", ".is_file()"),
        ("if dir.is_dir() {", ".is_dir()"),
        ("let here = p.exists();", ".exists()"),
        ("let here = p.try_exists()?;", "try_exists("),
        ("let m = std::fs::metadata(p)?;", "fs::metadata"),
        ("let m = p.symlink_metadata()?;", "symlink_metadata"),
        ("let f = File::open(p)?;", "File::"),
        ("let o = OpenOptions::new();", "OpenOptions"),
    ];
    for (code, mark) in cases {
        assert!(disk_touches(code).contains(&mark), "{code}: {:?}", disk_touches(code));
    }
    assert!(disk_touches("let n = p.file_name(); let e = path.extension();").is_empty());
}

/// The checker itself: paths, modules and the table parse as intended.
#[test]
fn the_checker_reads_paths_modules_and_the_table() {
    assert_eq!(
        crate_paths("use crate::math::sh::{Sh9, k};\nlet x = crate::envmap::load::load(p); $crate::no"),
        vec![vec!["math", "sh"], vec!["envmap", "load", "load"]]
    );
    assert_eq!(module_of(Path::new("envmap/mod.rs")), Some(vec!["envmap".to_string()]));
    assert_eq!(module_of(Path::new("math/sh.rs")), Some(vec!["math".to_string(), "sh".to_string()]));
    assert_eq!(module_of(Path::new("lib.rs")), None);
    assert_eq!(code_of("let a = 1; // crate::x\n/// [`crate::y`]\nb"), "let a = 1; \n\nb");
    let m = vec!["envmap".to_string(), "search".to_string()];
    assert_eq!(super_paths("use super::load;\nmod tests {\n use super::*;", &m), vec![vec!["envmap", "load"]]);
    let t = layer_table(
        "x\n## Layers\n\n| layer | what | may use |\n|---|---|---|\n| `a` | a | — |\n| `b` | b (`main.rs`, `b/x.rs`) | `a` |\n\nafter",
    );
    let row = |name: &str, files: &[&str], uses: &[&str]| Layer {
        name: name.into(),
        files: files.iter().map(|s| s.to_string()).collect(),
        uses: uses.iter().map(|s| s.to_string()).collect(),
    };
    assert_eq!(t, vec![row("a", &[], &[]), row("b", &["main.rs"], &["a"])]);
    assert_eq!(layer_of(Path::new("main.rs"), &t), Some("b".into()));
    assert_eq!(layer_of(Path::new("lib.rs"), &t), None);
    assert_eq!(layer_of(Path::new("commands/run.rs"), &t), Some("commands".into()));
    assert_eq!(layer_of(Path::new("cli.rs"), &t), Some("cli".into()));
    assert!(is_binary_file(Path::new("commands/run.rs"), "mod cli;\nmod commands;\n"));
    assert!(!is_binary_file(Path::new("pipeline/run.rs"), "mod cli;\nmod commands;\n"));
    let map = "x\n## Code map\n\n### `math/`\n| file | what |\n|---|---|\n| `sh.rs`, `gram.rs` | x |\n\
               | `sg/` | `lobes.rs` (x), `mod.rs` |\n\n`api.rs`: y\n\n## Next\n| `z.rs` | no |";
    assert_eq!(code_map_paths(map), ["math/sh.rs", "math/gram.rs", "math/sg/lobes.rs", "math/sg/mod.rs", "math/sg/"]);
}

/// The library never prints: only the binary (`main.rs` and the modules it declares) and the
/// stream primitives it calls (`io/output.rs`) reach stdout or stderr. Everything else returns
/// values or reports progress through `io::progress`. Unit tests are held to it too: what a
/// test wants to say goes into its assertion's message.
#[test]
fn the_library_never_prints() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let main_code = code_of(&std::fs::read_to_string(root.join("main.rs")).unwrap());
    let printing = ["println!", "eprintln!", "print!(", "eprint!(", "dbg!(", "stdout()", "stderr()"];
    let mut found = Vec::new();
    for (rel, code) in &read_crate().files {
        if is_binary_file(rel, &main_code) {
            continue;
        }
        for p in printing.iter().filter(|p| code.contains(*p)) {
            found.push(format!("{}: {p}", rel.display()));
        }
    }
    assert!(found.is_empty(), "library code that prints: {found:?}");
}

/// One atomic writer: only `io/atomic.rs` renames a file into place.
#[test]
fn only_the_atomic_writer_renames_files() {
    let renaming: Vec<String> = read_crate()
        .files
        .iter()
        .filter(|(rel, code)| code.contains("rename(") && rel != Path::new("io/atomic.rs"))
        .map(|(rel, _)| rel.display().to_string())
        .collect();
    assert!(renaming.is_empty(), "files that rename outside io/atomic.rs: {renaming:?}");
}
