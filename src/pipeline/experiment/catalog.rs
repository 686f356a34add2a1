//! Finding experiment files: every one in a folder, and one by path, file stem or name (with
//! "did you mean" for a typo).

use super::model::Experiment;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// What a command that needs the experiments says where there are none.
pub const NOT_A_CHECKOUT: &str = "run inside a probelab checkout or pass `--root`";

/// Every `*.toml` in a folder, sorted by name. A folder that is not there is an error saying
/// where to run ([`NOT_A_CHECKOUT`]).
pub fn list_experiments(dir: &Path) -> Result<Vec<PathBuf>> {
    if !dir.is_dir() {
        bail!("{}: no experiments folder here: {NOT_A_CHECKOUT}", dir.display());
    }
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("{}: cannot list experiments", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    out.sort();
    Ok(out)
}

/// Finds an experiment file by path, by file stem in `<root>/experiments/` (`run
/// sh_baseline` is `experiments/sh_baseline.toml`), or by its `name`. An unknown name is an
/// error naming the nearest experiment ([`crate::math::nearest`]) and every one there; outside
/// a checkout it says where to run.
pub fn resolve(root: &Path, name: &str) -> Result<PathBuf> {
    let p = Path::new(name);
    if p.is_file() {
        return Ok(p.to_path_buf());
    }
    let dir = root.join("experiments");
    if !dir.is_dir() {
        bail!("experiment '{name}': no such file, and no experiments folder at {}: {NOT_A_CHECKOUT}", dir.display());
    }
    let by_stem = dir.join(format!("{name}.toml"));
    if by_stem.is_file() {
        return Ok(by_stem);
    }
    let all = list_experiments(&dir)?;
    let mut names = Vec::new();
    for f in &all {
        if let Ok(e) = Experiment::load(f) {
            if e.name == name {
                return Ok(f.clone());
            }
            names.push(e.name);
        }
    }
    let known: Vec<String> =
        all.iter().filter_map(|f| f.file_stem().map(|s| s.to_string_lossy().into_owned())).collect();
    let stem = p.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| name.to_string());
    let hint = match crate::math::nearest::nearest(&stem, known.iter().chain(&names)) {
        Some(n) => format!("; did you mean '{n}'?"),
        None => String::new(),
    };
    bail!(
        "experiment '{name}': no such file, and no experiment of that name in {}{hint} (known: {})",
        dir.display(),
        known.join(", ")
    )
}
