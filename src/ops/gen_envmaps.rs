//! `probelab gen-envmaps`: writes the analytic scenes (`reference::scenes::generated`) as f32
//! EXR maps, each atomically, under the output folder's exclusive lock. The list of files
//! written is rendered from the outcome, after the last write, so a failing stdout never stops
//! the writes half way.

use super::context::Env;
use anyhow::{bail, Result};
use std::path::PathBuf;

/// The options of `probelab gen-envmaps`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GenEnvmapsOptions {
    /// The folder written (`--out`; `None`: `<root>/envmaps`).
    pub out: Option<PathBuf>,
    /// Width of the maps, even, 4 to 8192 (`--width`; the height is half).
    pub width: usize,
}

/// A map written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GeneratedMap {
    /// The file.
    pub path: PathBuf,
    /// The scene, in words.
    pub description: String,
}

/// What `probelab gen-envmaps` wrote.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Generated {
    /// Each map, in scene order.
    pub maps: Vec<GeneratedMap>,
}

/// `probelab gen-envmaps`: the width checked, the output folder's lock taken, every scene
/// written.
pub fn gen_envmaps(env: &Env, o: &GenEnvmapsOptions) -> Result<Generated> {
    let width = o.width;
    if width < 4 || !width.is_multiple_of(2) || width > 8192 {
        bail!("--width {width}: expected an even width from 4 to 8192");
    }
    let out = o.out.clone().unwrap_or_else(|| env.root.join("envmaps"));
    let _lock = env.writing(&out)?;
    let mut maps = Vec::new();
    for s in crate::reference::scenes::generated() {
        let path = out.join(format!("{}.exr", s.id));
        crate::envmap::load::write_exr(&path, &s.map(width))?;
        maps.push(GeneratedMap { path, description: s.description });
    }
    Ok(Generated { maps })
}

impl Generated {
    /// The files written, one line each with its scene.
    pub fn to_text(&self) -> String {
        self.maps.iter().map(|m| format!("{}  {}\n", m.path.display(), m.description)).collect()
    }
}
