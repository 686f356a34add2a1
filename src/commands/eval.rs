//! `probelab eval`: scores encoders on maps, once, and prints the table (CSV or JSON) on
//! stdout; nothing is written and no lock is taken. Exit 2 when a map is not found. What it
//! computes is `ops::eval`, shared with the Python package.

use super::output;
use anyhow::Result;
use probelab::ops::eval::{self, EvalMaps, EvalOptions};
use probelab::ops::Env;

/// `probelab eval`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Map names (on the search path) or file paths.
    #[arg(value_parser = super::args::file_name(), required = true)]
    maps: Vec<String>,
    /// Comma-separated encoder ids (see `probelab encoders`).
    #[arg(long, default_value = probelab::ops::DEFAULT_ENCODERS)]
    encoders: String,
    /// `sphere`, or `hemisphere:AXIS` with AXIS one of +x -x +y -y +z -z (the surface normal
    /// N; the hemisphere effect about N is applied and n′ ranges over its hemisphere).
    #[arg(long, default_value = "sphere")]
    domain: String,
    /// `exact` (solid-angle weighted) or `probulator` (the peer tool's per-pixel mean).
    #[arg(long, default_value = "exact")]
    metric: String,
    /// Output lat-long resolution WxH for the exact metric.
    #[arg(long, default_value = "256x128")]
    resolution: String,
    /// Gauss–Legendre nodes per row piece of the reference.
    #[arg(long, default_value_t = eval::DEFAULT_POLAR_NODES)]
    polar_nodes: usize,
    /// Output format: `csv` (the table's columns) or `json` (one object: `schema`, the maps
    /// read with their sha256, and the rows keyed by the same columns, scores as numbers;
    /// docs/json.md).
    #[arg(long, default_value = "csv", value_parser = ["csv", "json"])]
    format: String,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let options = EvalOptions {
        maps: EvalMaps::Named(a.maps),
        encoders: a.encoders,
        domain: a.domain,
        metric: a.metric,
        resolution: a.resolution,
        polar_nodes: a.polar_nodes,
    };
    let evaluated = eval::eval(env, &options)?;
    output::write(&if a.format == "json" { evaluated.to_json()?.into_bytes() } else { evaluated.to_csv()? })?;
    Ok(0)
}
