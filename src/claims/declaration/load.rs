//! Every declaration file of a repository (`experiments/claims/*.toml`), in report order, claim
//! ids unique across papers.

use super::paper::Paper;
use super::parse::parse;
use crate::math::echo::value as echo;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// The folder under `experiments/` that holds the declarations.
pub const DIR: &str = "claims";

/// Every declaration file in `experiments_dir/claims/`, in report order (by `order`, then
/// key). Claim ids are unique across papers. A repository without the folder declares no
/// claims.
pub fn load_papers(experiments_dir: &Path) -> Result<Vec<Paper>> {
    let dir = experiments_dir.join(DIR);
    if !dir.exists() {
        return Ok(Vec::new());
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .with_context(|| format!("{}: cannot list the claims declarations", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    let mut papers = Vec::new();
    for p in files {
        let text = std::fs::read_to_string(&p).with_context(|| format!("{}: cannot read", p.display()))?;
        let key = p.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        // The stem names results/claims/<key>.md: a plain identifier.
        if let Err(e) = crate::io::name::check(&key) {
            bail!("{}: the claims file's name {e}", p.display());
        }
        papers.push(parse(&key, &text, &p)?);
    }
    let mut seen: Vec<&str> = Vec::new();
    for p in &papers {
        for c in &p.claims {
            if seen.contains(&c.id.as_str()) {
                bail!("claim id '{}' is declared by two papers", echo(&c.id));
            }
            seen.push(&c.id);
        }
    }
    papers.sort_by(|a, b| a.order.cmp(&b.order).then(a.key.cmp(&b.key)));
    Ok(papers)
}
