//! `probelab view`: prints the results viewer's page (`ops::view`) and, where a desktop session
//! exists (a `DISPLAY` or `WAYLAND_DISPLAY`, or macOS), opens it in the default browser.

use super::terminal::note;
use anyhow::Result;
use probelab::ops::view::{self, ViewOptions};
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab view`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Results folder (default: <root>/results).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Only print the path, never open a browser.
    #[arg(long)]
    no_open: bool,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let viewed = view::view(env, &ViewOptions { out: a.out })?;
    println!("{}", viewed.index.display());
    let desktop = cfg!(target_os = "macos")
        || std::env::var_os("DISPLAY").is_some()
        || std::env::var_os("WAYLAND_DISPLAY").is_some();
    if desktop && !a.no_open {
        let opener = if cfg!(target_os = "macos") { "open" } else { "xdg-open" };
        if let Err(e) = std::process::Command::new(opener).arg(&viewed.index).spawn() {
            note(&format!("could not open a browser ({opener}: {e}); open the path above\n"));
        }
    }
    Ok(0)
}
