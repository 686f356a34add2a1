//! `probelab probes`: scores encoders over a probe set (a file, or synthetic probes), in
//! chunks and optionally one shard of it (`pipeline::probeset::job`); with an output file,
//! writes the mergeable statistics atomically. No output may overwrite the input
//! (`io::distinct`). The summary CSV and the run's figures are rendered from the outcome.

use super::context::Env;
use crate::io::distinct::{refuse_overwrite, Named};
use crate::pipeline::probeset::job::{self, Input, Job};
use crate::pipeline::probeset::score::SetStats;
use crate::pipeline::probeset::shard::Shard;
use anyhow::Result;
use std::path::PathBuf;

pub use crate::pipeline::probeset::format::DEFAULT_CHUNK;

/// Where the probes come from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ProbeInput {
    /// A probe file (`--input`), its format (`csv`, `f32`; `None`: from its extension).
    File {
        /// The file.
        path: PathBuf,
        /// `--format`.
        format: Option<String>,
    },
    /// Synthetic probes (`--synth N`).
    Synth {
        /// Number of probes.
        count: u64,
        /// `--seed`.
        seed: u64,
        /// `--palette`: comma-separated maps whose SH3 seed the probes (`None`: every
        /// `*_256x128` map on the search path).
        palette: Option<String>,
    },
}

/// The options of `probelab probes`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProbesOptions {
    /// The probes.
    pub input: ProbeInput,
    /// Comma-separated encoder ids, or `all` (`--encoders`).
    pub encoders: String,
    /// `I/N`: this shard of the set (`--shard`).
    pub shard: String,
    /// The quadrature rule `NZxNPHI` (`--quadrature`).
    pub quadrature: String,
    /// Probes per chunk (`--chunk`).
    pub chunk: usize,
    /// Where to write the mergeable statistics (`--out`).
    pub out: Option<PathBuf>,
    /// Where to save this shard's probes as well (`--save`).
    pub save: Option<PathBuf>,
}

/// What `probelab probes` did.
pub struct ProbesRun {
    /// The mergeable statistics.
    pub stats: SetStats,
    /// The shard that was scored.
    pub shard: Shard,
}

/// `probelab probes`: outputs checked distinct from the input, the job run (its notes, then
/// the statistics file written, said through `env.notes`). Before each output file is written,
/// the temporary files killed runs left beside it are removed and noted.
pub fn probes(env: &Env, o: &ProbesOptions) -> Result<ProbesRun> {
    let outputs = [("--out", &o.out), ("--save", &o.save)];
    let outputs: Vec<Named> =
        outputs.iter().filter_map(|(r, p)| Some(Named { role: r, path: p.as_deref()? })).collect();
    let inputs: Vec<Named> = match &o.input {
        ProbeInput::File { path, .. } => vec![Named { role: "--input", path }],
        ProbeInput::Synth { .. } => vec![],
    };
    refuse_overwrite(&outputs, &inputs)?;
    let input = match &o.input {
        ProbeInput::File { path, format } => Input::File(path, format.as_deref()),
        ProbeInput::Synth { count, seed, palette } => {
            Input::Synth { count: *count, seed: *seed, palette: palette.as_deref() }
        }
    };
    let job = Job {
        input,
        encoders: &o.encoders,
        shard: &o.shard,
        quadrature: &o.quadrature,
        chunk: o.chunk,
        save: o.save.as_deref(),
    };
    if let Some(save) = &o.save {
        env.remove_stale_beside(save);
    }
    let done = job::run(&job, &env.search)?;
    for n in &done.notes {
        env.notes.note(n);
    }
    if let Some(out) = &o.out {
        env.remove_stale_beside(out);
        crate::io::atomic::write(out, done.stats.to_toml()?.as_bytes())?;
        env.notes.note(&format!("wrote {}", out.display()));
    }
    Ok(ProbesRun { stats: done.stats, shard: done.shard })
}

impl ProbesRun {
    /// The summary CSV printed on stdout.
    pub fn summary_csv(&self) -> Result<Vec<u8>> {
        self.stats.summary_csv()
    }

    /// The run's figures, the line printed on stderr at the end: probes, shard, wall and input
    /// time, peak memory, threads.
    pub fn figures(&self) -> String {
        let stats = &self.stats;
        format!(
            "probes: {} (shard {}/{}), wall {:.3} s, input {:.3} s, peak memory {:.1} MiB (VmHWM), {} thread(s)",
            stats.probes,
            self.shard.index,
            self.shard.count,
            stats.wall_s,
            stats.input_s,
            stats.peak_mem_bytes as f64 / (1024.0 * 1024.0),
            stats.threads
        )
    }
}
