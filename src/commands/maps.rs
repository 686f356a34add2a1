//! `probelab maps`: shows the map search path, the maps it finds and the known maps it does not
//! (with where to get them); `probelab maps import` makes the 256x128 maps of map files as the
//! shared ones were made, named through the known maps, each written atomically under the
//! output folder's exclusive lock (`ops::maps`).

use super::output;
use anyhow::Result;
use probelab::ops::maps::import::{import, ImportOptions};
use probelab::ops::maps::list::list;
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab maps`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    command: Option<MapsCommand>,
}

/// The subcommands of `probelab maps`.
#[derive(clap::Subcommand, Debug)]
enum MapsCommand {
    /// Make the 256x128 maps of map files as the shared ones were made (decode, half, solid-angle-
    /// weighted area average when larger), name them through the known maps (envmaps/known.toml)
    /// and write <name>.exr into --out; prints each with its pixel sha256 (docs/maps.md).
    Import {
        /// Map files (.exr, .hdr), or folders: every .exr and .hdr file directly in them.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// Folder to write the maps into (created if absent).
        #[arg(long)]
        out: PathBuf,
    },
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let text = match a.command {
        Some(MapsCommand::Import { inputs, out }) => import(env, &ImportOptions { inputs, out })?.to_text(),
        None => list(env)?.to_text(),
    };
    output::write(text.as_bytes())?;
    Ok(0)
}
