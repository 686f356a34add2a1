//! The architecture, checked: every `crate::` path in `src/` against the layer table of
//! `ARCHITECTURE.md` ("## Layers": layer, what, may use), and the module files for import
//! cycles.
//!
//! - A layer is a folder of `src/` (or `cli.rs`). What a layer uses is every `crate::<layer>`
//!   path in its files' code (comments are not code; unit tests are), other than its own.
//! - The table must say exactly what the code does: a use the table does not allow fails, and
//!   so does an allowance the code does not use (the table may not overstate either).
//! - The table is ordered bottom-up: a layer may use only layers listed above it, so there is
//!   no upward import and no circle between layers.
//! - Between module files (e.g. `pipeline::runner` and `pipeline::timing`) there is no circle.
//! - Outside `encoders/` and `claims/`, product code names no encoder: no string literal in
//!   code before a file's `#[cfg(test)]` is a registered encoder id (a unit-test file of its
//!   own, `tests.rs`, is test code throughout).
//! - The modules whose product code touches the disk (`fs::`, `File::`, `OpenOptions`) are
//!   exactly the ones ARCHITECTURE.md lists ("Only these modules touch the disk").

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

/// `super::x` paths of a file's top level (before any inline `mod … {`, where `super` would
/// mean the file itself), resolved against the file's module.
fn super_paths(code: &str, module: &[String], is_mod_rs: bool) -> Vec<Vec<String>> {
    let top = match code.find("\nmod ").or_else(|| code.find("\npub(crate) mod tests")) {
        Some(i) => &code[..i],
        None => code,
    };
    let parent: Vec<String> =
        if is_mod_rs { module[..module.len().saturating_sub(1)].to_vec() } else { module[..module.len() - 1].to_vec() };
    let mut out = Vec::new();
    let mut rest = top;
    while let Some(i) = rest.find("super::") {
        rest = &rest[i + "super::".len()..];
        let end = rest.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(rest.len());
        if end > 0 {
            let mut p = parent.clone();
            p.push(rest[..end].to_string());
            out.push(p);
        }
    }
    out
}

/// The layer table of ARCHITECTURE.md: (layer, may use), in table order.
fn layer_table(text: &str) -> Vec<(String, BTreeSet<String>)> {
    let section = text.split("\n## Layers").nth(1).expect("ARCHITECTURE.md has a '## Layers' section");
    let mut rows = Vec::new();
    for line in section.lines().skip_while(|l| !l.starts_with('|')) {
        if !line.starts_with('|') {
            break;
        }
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        let Some(name) = cells.first().and_then(|c| c.strip_prefix('`')).and_then(|c| c.strip_suffix('`')) else {
            continue; // the header and the separator row
        };
        let uses = cells
            .last()
            .unwrap()
            .split(',')
            .filter_map(|c| c.trim().strip_prefix('`').and_then(|c| c.strip_suffix('`')))
            .map(String::from)
            .collect();
        rows.push((name.to_string(), uses));
    }
    assert!(!rows.is_empty(), "the '## Layers' table of ARCHITECTURE.md has no rows");
    rows
}

struct Crate {
    /// module path → (file, code)
    modules: BTreeMap<Vec<String>, (PathBuf, String)>,
}

fn read_crate() -> Crate {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    src_files(&root, &mut files);
    let mut modules = BTreeMap::new();
    for f in files {
        let rel = f.strip_prefix(&root).unwrap().to_path_buf();
        if let Some(m) = module_of(&rel) {
            let mut code = code_of(&std::fs::read_to_string(&f).unwrap());
            // The command line is a module of the binary: it reaches the layers as `probelab::`.
            if rel == Path::new("cli.rs") {
                code = code.replace("probelab::", "crate::");
            }
            modules.insert(m, (rel, code));
        }
    }
    Crate { modules }
}

#[test]
fn layers_use_exactly_what_architecture_md_allows() {
    let arch = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md")).unwrap();
    let table = layer_table(&arch);
    let krate = read_crate();
    // What each layer's code uses, with one example place per use.
    let mut used: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    for (m, (file, code)) in &krate.modules {
        let layer = &m[0];
        used.entry(layer.clone()).or_default();
        for p in crate_paths(code) {
            if &p[0] != layer {
                used.get_mut(layer)
                    .unwrap()
                    .entry(p[0].clone())
                    .or_insert_with(|| format!("src/{}: crate::{}", file.display(), p.join("::")));
            }
        }
    }
    let mut errors = Vec::new();
    let names: Vec<&String> = table.iter().map(|(n, _)| n).collect();
    for layer in used.keys() {
        if !names.contains(&layer) {
            errors.push(format!("layer `{layer}` (src/{layer}) is not in ARCHITECTURE.md's layer table"));
        }
    }
    for (i, (layer, allowed)) in table.iter().enumerate() {
        let below: BTreeSet<&String> = names[..i].iter().copied().collect();
        for a in allowed {
            if !below.contains(a) {
                errors.push(format!("ARCHITECTURE.md: `{layer}` may use `{a}`, which is not a layer listed above it"));
            }
        }
        let actual = used.get(layer).cloned().unwrap_or_default();
        for (u, place) in &actual {
            if !allowed.contains(u) {
                errors.push(format!("`{layer}` uses `{u}`, which ARCHITECTURE.md does not allow ({place})"));
            }
        }
        for a in allowed {
            if !actual.contains_key(a) {
                errors.push(format!("ARCHITECTURE.md says `{layer}` may use `{a}`, but no code of `{layer}` does"));
            }
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn no_import_cycles_between_module_files() {
    let krate = read_crate();
    let resolve = |p: &[String]| -> Option<Vec<String>> {
        (1..=p.len()).rev().map(|k| p[..k].to_vec()).find(|c| krate.modules.contains_key(c))
    };
    let mut edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    for (m, (file, code)) in &krate.modules {
        let is_mod_rs = file.file_name().is_some_and(|f| f == "mod.rs");
        let mut targets: Vec<Vec<String>> = crate_paths(code);
        targets.extend(super_paths(code, m, is_mod_rs));
        for t in targets {
            if let Some(r) = resolve(&t) {
                if &r != m {
                    edges.entry(m.clone()).or_default().insert(r);
                }
            }
        }
    }
    // Tarjan's strongly connected components.
    struct Tarjan<'a> {
        edges: &'a BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
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
        edges: &edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        cycles: Vec::new(),
    };
    for m in krate.modules.keys() {
        if !t.index.contains_key(m) {
            t.visit(m);
        }
    }
    assert!(t.cycles.is_empty(), "import cycles between module files: {:?}", t.cycles);
}

/// A module's product code: what comes before its `#[cfg(test)]`; nothing for a unit-test
/// module in a file of its own (`…/tests.rs`, declared `#[cfg(test)] mod tests;`).
fn product_code<'a>(module: &[String], code: &'a str) -> &'a str {
    if module.last().is_some_and(|m| m == "tests") {
        return "";
    }
    code.split("#[cfg(test)]").next().unwrap()
}

#[test]
fn only_encoders_and_claims_name_an_encoder() {
    let ids: BTreeSet<String> = probelab::encoders::REGISTRY.iter().map(|k| k.id.to_string()).collect();
    let krate = read_crate();
    let mut errors = Vec::new();
    for (m, (file, code)) in &krate.modules {
        if m[0] == "encoders" || m[0] == "claims" {
            continue;
        }
        let product = product_code(m, code);
        for (n, line) in product.lines().enumerate() {
            for (i, lit) in line.split('"').enumerate() {
                if i % 2 == 1 && ids.contains(lit) {
                    errors.push(format!("src/{}:{}: names encoder \"{lit}\"", file.display(), n + 1));
                }
            }
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn only_the_listed_modules_touch_the_disk() {
    let arch = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md")).unwrap();
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
    let mut touching = BTreeSet::new();
    for (m, (_, code)) in &krate.modules {
        let product = product_code(m, code);
        if ["fs::", "File::", "OpenOptions"].iter().any(|p| product.contains(p)) {
            touching.insert(m.join("::"));
        }
    }
    let unlisted: Vec<_> = touching.difference(&listed).collect();
    let idle: Vec<_> = listed.difference(&touching).collect();
    assert!(
        unlisted.is_empty() && idle.is_empty(),
        "touch the disk but are not listed in ARCHITECTURE.md: {unlisted:?}; listed but touch no file: {idle:?}"
    );
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
    assert_eq!(super_paths("use super::load;\nmod tests {\n use super::*;", &m, false), vec![vec!["envmap", "load"]]);
    let t = layer_table(
        "x\n## Layers\n\n| layer | what | may use |\n|---|---|---|\n| `a` | a | — |\n| `b` | b | `a` |\n\nafter",
    );
    assert_eq!(t, vec![("a".into(), BTreeSet::new()), ("b".into(), BTreeSet::from(["a".to_string()]))]);
}
