//! `probelab gen-envmaps`: writes the analytic scenes (`reference::scenes::generated`) as f32
//! EXR maps, each atomically, under the output folder's exclusive lock; prints each file after
//! the last write, so a failing stdout never stops the writes half way.

use super::output;
use anyhow::Result;
use probelab::ops::gen_envmaps::{gen_envmaps, GenEnvmapsOptions};
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
    let generated = gen_envmaps(env, &GenEnvmapsOptions { out: a.out, width: a.width })?;
    output::write(generated.to_text().as_bytes())?;
    Ok(0)
}
