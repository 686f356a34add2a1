//! `probelab fit-hallucination`: fits the ZH3 hallucination curve to the radiance SH of maps
//! and/or a probe file and prints it beside SH L1 and the paper's curve
//! (`pipeline::hallucination_fit`). Nothing is written and no lock is taken.

use super::output;
use anyhow::Result;
use probelab::ops::fit_hallucination::{fit_hallucination, FitHallucinationOptions};
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab fit-hallucination`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Map names (on the search path) or file paths.
    #[arg(value_parser = super::args::file_name())]
    maps: Vec<String>,
    /// A probe file in the format of `probes --input`/`--save`: L2 radiance SH, 27 numbers
    /// per probe, coefficient-major RGB (c0.r c0.g c0.b c1.r … c8.b; FORMULAS §2), as CSV
    /// (.csv) or raw little-endian f32 (.f32, .bin, .raw).
    #[arg(long)]
    probes: Option<PathBuf>,
    /// The probe file's format, csv or f32 (default: from its extension).
    #[arg(long, requires = "probes")]
    format: Option<String>,
    /// Also fit a cubic.
    #[arg(long)]
    cubic: bool,
    /// Zonal axis: rec709 (as zh3_hallucinate), equal, or channel.
    #[arg(long, default_value = "rec709")]
    axis: String,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let options =
        FitHallucinationOptions { maps: a.maps, probes: a.probes, format: a.format, cubic: a.cubic, axis: a.axis };
    output::write(fit_hallucination(env, &options)?.to_text().as_bytes())?;
    Ok(0)
}
