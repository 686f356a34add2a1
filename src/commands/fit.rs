//! `probelab fit`: fits encoders to one map and prints each fit's stored coefficients (names,
//! units, roles and basis) and what it was fitted on, as JSON or CSV; everything is checked
//! before anything is printed. Nothing is written and no lock is taken. The checks, the fits and
//! the JSON document are `ops::fit`, shared with the Python package.

use super::output;
use anyhow::{bail, Result};
use probelab::api::Surface;
use probelab::ops::fit::{self, FitOptions};
use probelab::ops::{Env, MapSource};

/// `probelab fit`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Map name (on the search path) or file path.
    #[arg(value_parser = super::args::file_name())]
    map: String,
    /// Comma-separated encoder ids (see `probelab encoders`).
    #[arg(long)]
    encoders: String,
    /// The surface normal N as x,y,z (world space, +Y up; normalised): fit to the light above
    /// its horizon, about N. Without it the fit is a probe's, on the whole sphere.
    #[arg(long)]
    normal: Option<String>,
    /// `json` or `csv` (one row per stored or derived value).
    #[arg(long, default_value = "json")]
    format: String,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    if a.format != "json" && a.format != "csv" {
        bail!("--format '{}': expected json or csv", a.format);
    }
    let surface = match &a.normal {
        None => Surface::Sphere,
        Some(text) => Surface::Normal(fit::parse_normal(text)?),
    };
    let fitted = fit::fit(env, &FitOptions { map: MapSource::Named(a.map), encoders: a.encoders, surface })?;
    let text = if a.format == "json" { fitted.to_json()? } else { fitted.to_csv()? };
    output::write(text.as_bytes())?;
    Ok(0)
}
