//! `probelab probes`: scores encoders over a probe set (a file, or `--synth N`), in chunks and
//! optionally one shard of it (`pipeline::probeset::job`); prints the summary CSV on stdout and
//! the run's figures on stderr, and with `--out` writes the mergeable statistics atomically.

use super::output;
use super::terminal::noteln;
use anyhow::{bail, Result};
use probelab::ops::probes::{probes, ProbeInput, ProbesOptions, DEFAULT_CHUNK};
use probelab::ops::Env;
use std::path::PathBuf;

/// `probelab probes`: score encoders over a probe set (a file or synthetic).
#[derive(clap::Args, Debug)]
pub struct Args {
    /// A probe file: CSV (27 numbers a row, coefficient-major RGB) or raw little-endian f32
    /// (.f32/.bin/.raw, 27 per probe). See docs/scale.md.
    #[arg(long, conflicts_with = "synth", required_unless_present = "synth")]
    input: Option<PathBuf>,
    /// File format: csv or f32 (default: from the extension).
    #[arg(long)]
    format: Option<String>,
    /// Synthesise N probes instead (deterministic from --seed and the palette).
    #[arg(long)]
    synth: Option<u64>,
    /// Seed of the synthetic set.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Comma-separated maps whose SH3 seed synthetic probes (default: every *_256x128 map on
    /// the search path; the generated scenes when there is none).
    #[arg(long, value_parser = super::args::file_name())]
    palette: Option<String>,
    /// Comma-separated encoder ids, or `all` (sh1 is always added: it is the baseline).
    #[arg(long, default_value = probelab::ops::DEFAULT_ENCODERS)]
    encoders: String,
    /// Process shard I of N (contiguous probe ranges); merge the --out files with `probelab merge`.
    #[arg(long, default_value = "0/1")]
    shard: String,
    /// Write the mergeable statistics (TOML) to this file.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Quadrature rule NZxNPHI for encoders whose fit is not SH3 (6x12 is exact for outputs in SH
    /// bands <= 5; fewer nodes are faster and approximate; see docs/scale.md).
    #[arg(long, default_value = "6x12")]
    quadrature: String,
    /// Probes per chunk (memory in flight; results do not depend on it).
    #[arg(long, default_value_t = DEFAULT_CHUNK)]
    chunk: usize,
    /// Also write this shard's probes to FILE (.csv or .f32), e.g. to export a synthetic set.
    #[arg(long)]
    save: Option<PathBuf>,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let input = match (a.input, a.synth) {
        (Some(path), _) => ProbeInput::File { path, format: a.format },
        (None, Some(count)) => ProbeInput::Synth { count, seed: a.seed, palette: a.palette },
        (None, None) => bail!("give --input FILE or --synth N"),
    };
    let options = ProbesOptions {
        input,
        encoders: a.encoders,
        shard: a.shard,
        quadrature: a.quadrature,
        chunk: a.chunk,
        out: a.out,
        save: a.save,
    };
    let run = probes(env, &options)?;
    noteln!("{}", run.figures());
    output::write(&run.summary_csv()?)?;
    Ok(0)
}
