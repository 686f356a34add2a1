//! `probelab merge`: merges the statistics files of probe-set shards (`probes --out`,
//! `pipeline::probeset::job::merge`); with an output file, writes the merged statistics
//! atomically. The output may not overwrite a shard file (`io::distinct`).

use super::context::Env;
use crate::io::distinct::{refuse_overwrite, Named};
use crate::pipeline::probeset::score::SetStats;
use anyhow::Result;
use std::path::PathBuf;

/// The options of `probelab merge`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MergeOptions {
    /// The shards' statistics files.
    pub files: Vec<PathBuf>,
    /// Where to write the merged statistics (`--out`).
    pub out: Option<PathBuf>,
}

/// What `probelab merge` made.
pub struct Merged {
    /// The merged statistics.
    pub stats: SetStats,
}

/// `probelab merge`: the output checked distinct from the shard files, the shards merged (a
/// warning about them, then the file written, said through `env.notes`; before it, the
/// temporary files killed runs left beside it removed and noted).
pub fn merge(env: &Env, o: &MergeOptions) -> Result<Merged> {
    let inputs: Vec<Named> = o.files.iter().map(|p| Named { role: "a shard file", path: p }).collect();
    let outputs: Vec<Named> = o.out.iter().map(|p| Named { role: "--out", path: p }).collect();
    refuse_overwrite(&outputs, &inputs)?;
    let (stats, warning) = crate::pipeline::probeset::job::merge(&o.files)?;
    if let Some(w) = warning {
        env.notes.note(&w);
    }
    if let Some(out) = &o.out {
        env.remove_stale_beside(out);
        crate::io::atomic::write(out, stats.to_toml()?.as_bytes())?;
        env.notes.note(&format!("wrote {}", out.display()));
    }
    Ok(Merged { stats })
}

impl Merged {
    /// The summary CSV printed on stdout.
    pub fn summary_csv(&self) -> Result<Vec<u8>> {
        self.stats.summary_csv()
    }
}
