//! The state file of a scored probe set or shard (`probelab probes --out`, `probelab merge`):
//! TOML holding the exact statistics (sums as big-integer digits, quantile sketches as bucket
//! counts), so shards scored apart merge bit-for-bit into the one-pass result.

use crate::math::stats::SummaryState;
use crate::pipeline::probeset::score::{EncoderStats, SetStats, REFERENCE};
use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The state file's format tag.
pub const STATE_FORMAT: &str = "probelab-probe-stats/1";

#[derive(Serialize, Deserialize)]
struct EncoderState {
    name: String,
    stored_scalars: usize,
    closed_form: u64,
    quadrature: u64,
    seconds: f64,
    rmse: SummaryState,
    rel_rmse: SummaryState,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct StateFile {
    format: String,
    source: String,
    reference: String,
    shard_count: usize,
    shards: Vec<usize>,
    quadrature: String,
    probes: u64,
    wall_s: f64,
    input_s: f64,
    peak_mem_bytes: u64,
    threads: usize,
    encoders: Vec<EncoderState>,
}

impl SetStats {
    /// The state as TOML (exact: sums as big-integer digits, sketches as bucket counts).
    pub fn to_toml(&self) -> Result<String> {
        let f = StateFile {
            format: STATE_FORMAT.into(),
            source: self.source.clone(),
            reference: REFERENCE.into(),
            shard_count: self.shard_count,
            shards: self.shards.clone(),
            quadrature: self.quadrature.clone(),
            probes: self.probes,
            wall_s: self.wall_s,
            input_s: self.input_s,
            peak_mem_bytes: self.peak_mem_bytes,
            threads: self.threads,
            encoders: self
                .encoders
                .iter()
                .map(|e| EncoderState {
                    name: e.name.clone(),
                    stored_scalars: e.stored_scalars,
                    closed_form: e.closed_form,
                    quadrature: e.quadrature,
                    seconds: e.seconds,
                    rmse: (&e.rmse).into(),
                    rel_rmse: (&e.rel_rmse).into(),
                })
                .collect(),
        };
        Ok(toml::to_string(&f)?)
    }

    /// Reads a state file written by [`Self::to_toml`]; errors name the file.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("{}: cannot read probe statistics", path.display()))?;
        let f: StateFile = toml::from_str(&text)
            .map_err(|e| anyhow::anyhow!("{}: not a probe statistics file: {e}", path.display()))?;
        if f.format != STATE_FORMAT {
            bail!("{}: format '{}', expected '{STATE_FORMAT}'", path.display(), f.format);
        }
        if f.reference != REFERENCE {
            bail!("{}: errors measured against '{}', expected '{REFERENCE}'", path.display(), f.reference);
        }
        if f.shard_count == 0 || f.shards.is_empty() || f.shards.iter().any(|&s| s >= f.shard_count) {
            bail!("{}: shards {:?} do not fit shard_count {}", path.display(), f.shards, f.shard_count);
        }
        if f.shards.windows(2).any(|w| w[0] >= w[1]) {
            bail!("{}: shards {:?} must be strictly increasing (each shard once)", path.display(), f.shards);
        }
        check_fields(&f).map_err(|e| anyhow::anyhow!("{}: corrupt statistics: {e}", path.display()))?;
        let encoders = f
            .encoders
            .into_iter()
            .map(|e| {
                Ok(EncoderStats {
                    name: e.name,
                    stored_scalars: e.stored_scalars,
                    closed_form: e.closed_form,
                    quadrature: e.quadrature,
                    seconds: e.seconds,
                    rmse: e.rmse.to_summary()?,
                    rel_rmse: e.rel_rmse.to_summary()?,
                })
            })
            .collect::<Result<Vec<_>>>()
            .map_err(|e: anyhow::Error| anyhow::anyhow!("{}: corrupt statistics: {e:#}", path.display()))?;
        Ok(SetStats {
            source: f.source,
            shard_count: f.shard_count,
            shards: f.shards,
            quadrature: f.quadrature,
            probes: f.probes,
            wall_s: f.wall_s,
            input_s: f.input_s,
            peak_mem_bytes: f.peak_mem_bytes,
            threads: f.threads,
            encoders,
        })
    }
}

/// The consistency of a state's fields, beyond what each type checks: a known quadrature rule,
/// a source, at least one thread; finite non-negative times; distinct, non-empty encoder names;
/// and every encoder scored exactly `probes` probes (closed-form + quadrature counts, and each
/// statistic's valid + invalid counts, added with checked arithmetic).
fn check_fields(f: &StateFile) -> Result<()> {
    crate::pipeline::probeset::score::SphereRule::parse(&f.quadrature)?;
    if f.source.trim().is_empty() {
        bail!("empty source");
    }
    if f.threads == 0 {
        bail!("threads = 0");
    }
    let time_ok = |t: f64| t.is_finite() && t >= 0.0;
    if !time_ok(f.wall_s) || !time_ok(f.input_s) {
        bail!("wall_s {} and input_s {} must be finite and non-negative", f.wall_s, f.input_s);
    }
    if f.encoders.is_empty() {
        bail!("no encoders");
    }
    for (k, e) in f.encoders.iter().enumerate() {
        if e.name.trim().is_empty() || f.encoders[..k].iter().any(|o| o.name == e.name) {
            bail!("encoder name '{}' is empty or repeated", e.name);
        }
        if !time_ok(e.seconds) {
            bail!("encoder {}: seconds {} must be finite and non-negative", e.name, e.seconds);
        }
        let scored = e.closed_form.checked_add(e.quadrature);
        let rmse = e.rmse.count.checked_add(e.rmse.invalid);
        let rel = e.rel_rmse.count.checked_add(e.rel_rmse.invalid);
        if [scored, rmse, rel].iter().any(|&n| n != Some(f.probes)) {
            bail!(
                "encoder {}: counts do not add up to probes = {} (closed_form {} + quadrature {}, rmse {} + {} invalid, rel_rmse {} + {} invalid)",
                e.name,
                f.probes,
                e.closed_form,
                e.quadrature,
                e.rmse.count,
                e.rmse.invalid,
                e.rel_rmse.count,
                e.rel_rmse.invalid
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::probeset::score::tests::{score_synth, strip_timing};
    use crate::pipeline::probeset::shard::Shard;
    use crate::pipeline::probeset::synth::{scene_palette, Synth};

    /// Splitting a set in two (here: unevenly, with different chunk sizes) and merging the two
    /// shard states gives exactly the one-pass state, through the TOML files.
    #[test]
    fn shards_merge_exactly() {
        let synth = Synth::new(11, scene_palette());
        let n = 5003;
        let whole = strip_timing(score_synth(&synth, n, Shard::ALL, 1000));
        let dir = tempfile::tempdir().unwrap();
        let mut parts = Vec::new();
        for (i, chunk) in [(0, 333), (1, 4096)] {
            let s = score_synth(&synth, n, Shard { index: i, count: 2 }, chunk);
            let p = dir.path().join(format!("s{i}.toml"));
            std::fs::write(&p, s.to_toml().unwrap()).unwrap();
            parts.push(SetStats::load(&p).unwrap());
        }
        let mut merged = parts[0].clone();
        merged.merge(&parts[1]).unwrap();
        let mut merged = strip_timing(merged);
        assert_eq!(merged.shards, vec![0, 1]);
        merged.shard_count = 1;
        merged.shards = vec![0];
        assert_eq!(merged, whole);
        let e = parts[0].clone().merge(&parts[0]).err().unwrap().to_string();
        assert!(e.contains("twice"), "{e}");
    }
}
