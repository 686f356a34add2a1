//! The result folders the report covers — every experiment of `experiments/`, then every
//! other folder of `results/` that holds a CSV or a picture — the files in a folder, and the
//! removal of a folder's stale pictures.

use crate::pipeline::experiment::{list_experiments, Experiment};
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// A report section: an experiment, or another folder of results.
pub(super) struct Section {
    pub(super) name: String,
    pub(super) exp: Option<Experiment>,
    pub(super) source_text: Option<String>,
    pub(super) source_file: Option<PathBuf>,
}

/// Files of `dir` (names only), sorted.
pub(super) fn files(dir: &Path) -> Vec<String> {
    let Ok(rd) = std::fs::read_dir(dir) else { return vec![] };
    let mut v: Vec<String> = rd
        .filter_map(|e| e.ok())
        .filter(|e| e.file_type().map(|t| t.is_file()).unwrap_or(false))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    v.sort();
    v
}

/// The report's sections: every experiment of `root/experiments/`, then every other folder of
/// `out` that holds a CSV or a picture, by name.
pub(super) fn sections(root: &Path, out: &Path) -> Result<Vec<Section>> {
    let mut sections = Vec::new();
    for path in list_experiments(&root.join("experiments"))? {
        let exp = Experiment::load(&path)?;
        let text = std::fs::read_to_string(&path).with_context(|| format!("{}: cannot read", path.display()))?;
        sections.push(Section {
            name: exp.name.clone(),
            exp: Some(exp),
            source_text: Some(text),
            source_file: Some(path),
        });
    }
    if let Ok(rd) = std::fs::read_dir(out) {
        let mut extra: Vec<String> = rd
            .filter_map(|e| e.ok())
            .filter(|e| e.file_type().map(|t| t.is_dir()).unwrap_or(false))
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| !n.starts_with('.') && !sections.iter().any(|s| s.name == *n))
            .filter(|n| files(&out.join(n)).iter().any(|f| f.ends_with(".csv") || f.ends_with(".png")))
            .collect();
        extra.sort();
        for name in extra {
            sections.push(Section { name, exp: None, source_text: None, source_file: None });
        }
    }
    Ok(sections)
}

/// Removes `prefix*.png` and `prefix*.svg` files of `dir` that are not in `keep`.
pub(super) fn remove_stale(dir: &Path, prefix: &str, keep: &[String]) -> Result<()> {
    for f in files(dir) {
        if f.starts_with(prefix) && (f.ends_with(".png") || f.ends_with(".svg")) && !keep.contains(&f) {
            let p = dir.join(&f);
            std::fs::remove_file(&p).with_context(|| format!("{}: cannot remove stale picture", p.display()))?;
        }
    }
    Ok(())
}
