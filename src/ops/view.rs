//! `probelab view`, the workflow: where the results viewer is (`results/site/index.html`, which
//! `report` and `reproduce` write), refused with what to run when it has not been written.

use super::Env;
use anyhow::{bail, Result};
use std::path::PathBuf;

/// What `view` is asked: the results folder (default `<root>/results`).
pub struct ViewOptions {
    /// The results folder.
    pub out: Option<PathBuf>,
}

/// The viewer's page.
pub struct Viewed {
    /// `<results>/site/index.html`, absolute when the root could be resolved.
    pub index: PathBuf,
}

/// Finds the viewer's index page; an error naming the path and `probelab report` when absent.
pub fn view(env: &Env, opts: &ViewOptions) -> Result<Viewed> {
    let out = env.results(opts.out.clone());
    let index = out.join("site").join("index.html");
    if !index.is_file() {
        bail!("{}: no results viewer here; `probelab report` writes it", index.display());
    }
    Ok(Viewed { index: std::path::absolute(&index).unwrap_or(index) })
}
