//! `probelab gen-envmaps`: writes the analytic scenes (`reference::scenes::generated`) as f32
//! EXR maps, each atomically, under the output folder's exclusive lock; prints each file after
//! the last write, so a failing stdout never stops the writes half way.

use super::output;
use anyhow::{bail, Result};
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab gen-envmaps`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output folder (default: <root>/envmaps).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Width of the maps (height is half).
    #[arg(long, default_value_t = 1024)]
    width: usize,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let width = a.width;
    if width < 4 || !width.is_multiple_of(2) || width > 8192 {
        bail!("--width {width}: expected an even width from 4 to 8192");
    }
    let out = a.out.unwrap_or_else(|| env.root.join("envmaps"));
    let _lock = env.writing(&out)?;
    let mut lines = String::new();
    for s in probelab::reference::scenes::generated() {
        let path = out.join(format!("{}.exr", s.id));
        probelab::envmap::load::write_exr(&path, &s.map(width))?;
        lines += &format!("{}  {}\n", path.display(), s.description);
    }
    output::write(lines.as_bytes())?;
    Ok(0)
}
