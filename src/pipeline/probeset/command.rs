//! The probe-set commands: `probelab probes` (score encoders over a probe file or a synthetic
//! set, or one shard of it) and `probelab merge` (combine the shards' state files).

use crate::encoders::NamedEncoder;
use crate::math::sh::Sh9;
use crate::pipeline::output::noteln;
use crate::pipeline::probeset::format::{file_identity, write_probes, Format, ProbeReader, DEFAULT_CHUNK};
use crate::pipeline::probeset::score::{score, SetStats, Source, SphereRule};
use crate::pipeline::probeset::shard::Shard;
use crate::pipeline::probeset::synth::{scene_palette, Synth};
use crate::pipeline::progress::Progress;
use anyhow::{bail, Context, Result};
use rayon::prelude::*;
use std::path::PathBuf;

/// `probelab probes`: score encoders over a probe set (a file or synthetic).
#[derive(clap::Args, Debug)]
pub struct ProbesArgs {
    /// A probe file: CSV (27 numbers a row, coefficient-major RGB) or raw little-endian f32
    /// (.f32/.bin/.raw, 27 per probe). See docs/scale.md.
    #[arg(long, conflicts_with = "synth", required_unless_present = "synth")]
    pub input: Option<PathBuf>,
    /// File format: csv or f32 (default: from the extension).
    #[arg(long)]
    pub format: Option<String>,
    /// Synthesise N probes instead (deterministic from --seed and the palette).
    #[arg(long)]
    pub synth: Option<u64>,
    /// Seed of the synthetic set.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Comma-separated maps whose SH3 seed synthetic probes (default: every *_256x128 map on
    /// the search path; the generated scenes when there is none).
    #[arg(long)]
    pub palette: Option<String>,
    /// Comma-separated encoder ids, or `all` (sh1 is always added: it is the baseline).
    #[arg(long, default_value = "sh1,sh2")]
    pub encoders: String,
    /// Process shard I of N (contiguous probe ranges); merge the --out files with `probelab merge`.
    #[arg(long, default_value = "0/1")]
    pub shard: String,
    /// Write the mergeable statistics (TOML) to this file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Quadrature rule NZxNPHI for encoders whose fit is not SH3 (6x12 is exact for outputs in SH
    /// bands <= 5; fewer nodes are faster and approximate; see docs/scale.md).
    #[arg(long, default_value = "6x12")]
    pub quadrature: String,
    /// Probes per chunk (memory in flight; results do not depend on it).
    #[arg(long, default_value_t = DEFAULT_CHUNK)]
    pub chunk: usize,
    /// Also write this shard's probes to FILE (.csv or .f32), e.g. to export a synthetic set.
    #[arg(long)]
    pub save: Option<PathBuf>,
}

/// `probelab merge`: combine shard statistics.
#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// Statistics files written by `probelab probes --out`.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Write the merged statistics (TOML) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The encoders of `--encoders` (`all` = every registered encoder a probe can be scored with),
/// with sh1 first if it was not listed. Two kinds cannot be, and are refused by name: encoders
/// defined only about a surface normal ([`crate::encoders::encoder::Encoder::needs_surface_normal`]),
/// which a probe does not have, and encoders that fit the light beyond L2 SH
/// ([`crate::encoders::encoder::Encoder::reads_radiance`]), which a probe does not store.
pub fn encoder_list(list: &str) -> Result<Vec<NamedEncoder>> {
    let all = list.trim() == "all";
    let list = if all {
        crate::encoders::REGISTRY.iter().map(|k| k.id).collect::<Vec<_>>().join(",")
    } else {
        list.to_string()
    };
    let mut v = crate::encoders::build_list(&list)?;
    let beyond: Vec<String> = v.iter().filter(|e| e.encoder.reads_radiance()).map(|e| e.name.clone()).collect();
    let surface: Vec<String> = v.iter().filter(|e| e.encoder.needs_surface_normal()).map(|e| e.name.clone()).collect();
    if all {
        v.retain(|e| !e.encoder.needs_surface_normal() && !e.encoder.reads_radiance());
        noteln!(
            "--encoders all: left out {} (fitted from the light beyond L2 SH, which a probe does not store) and {} \
             (they need a surface normal N, which a probe does not have)",
            beyond.join(", "),
            surface.join(", ")
        );
    } else if let Some(e) = surface.first() {
        bail!(
            "--encoders: {}; a probe is a sphere of light with no surface: score it on a map with `eval --domain \
             hemisphere:AXIS` or an experiment with domain = \"hemisphere\"",
            crate::encoders::encoder::surface_normal_refusal(e)
        );
    } else if !beyond.is_empty() {
        bail!(
            "--encoders: {} fit(s) the light beyond L2 SH (bands 3-4, radiance samples or exact irradiance); a probe \
             stores L2 SH only, so a probe set cannot score them (use `eval` or an experiment on a map)",
            beyond.join(", ")
        );
    }
    if !v.iter().any(|e| e.name == crate::encoders::BASELINE) {
        v.insert(0, crate::encoders::build(crate::encoders::BASELINE, None, toml::Table::new())?);
    }
    Ok(v)
}

/// The synthesis palette: the named maps, or every `*_256x128` map on the search path, or (with
/// none) the generated scenes' closed-form SH.
pub fn palette(search: &crate::envmap::search::SearchPath, names: Option<&str>) -> Result<Vec<(String, Sh9)>> {
    let paths: Vec<PathBuf> = match names {
        Some(list) => list
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(|n| search.resolve(n).map_err(anyhow::Error::from))
            .collect::<Result<_>>()?,
        None => {
            let mut found: Vec<(String, PathBuf)> = Vec::new();
            for d in search.dirs() {
                let Ok(entries) = std::fs::read_dir(d) else { continue };
                for p in entries.filter_map(|e| e.ok().map(|e| e.path())) {
                    let ext_ok = p.extension().is_some_and(|x| x == "exr" || x == "hdr");
                    let stem = p.file_stem().and_then(|s| s.to_str()).unwrap_or("").to_string();
                    if ext_ok && stem.ends_with("_256x128") && !found.iter().any(|f| f.0 == stem) {
                        found.push((stem, p));
                    }
                }
            }
            found.sort();
            found.into_iter().map(|f| f.1).collect()
        }
    };
    if paths.is_empty() {
        return Ok(scene_palette());
    }
    paths
        .par_iter()
        .map(|p| {
            let map = crate::envmap::load::load(p)?;
            Ok((map.name.clone(), crate::reference::projection::project(&map)))
        })
        .collect()
}

/// Runs `probelab probes`; prints the summary CSV on stdout and run figures on stderr.
pub fn command(a: ProbesArgs, search: &crate::envmap::search::SearchPath) -> Result<i32> {
    let shard = Shard::parse(&a.shard)?;
    let encoders = encoder_list(&a.encoders)?;
    let rule = SphereRule::parse(&a.quadrature)?;
    if a.chunk == 0 {
        bail!("--chunk must be at least 1");
    }
    let (mut source, source_id) = match (&a.input, a.synth) {
        (Some(path), _) => {
            let format = Format::resolve(path, a.format.as_deref())?;
            let reader = ProbeReader::open(path, format, shard)?;
            (Source::File(reader), file_identity(path)?)
        }
        (None, Some(0)) => bail!("--synth 0: a probe set needs at least one probe"),
        (None, Some(n)) => {
            let synth = Synth::new(a.seed, palette(search, a.palette.as_deref())?);
            let id = format!(
                "synth n={n} seed={} palette={} [{}] fingerprint={}",
                a.seed,
                synth.palette_names.len(),
                synth.palette_names.join(" "),
                synth.fingerprint()
            );
            let (start, end) = shard.range(n);
            (Source::Synth { synth, start, end, next: start }, id)
        }
        (None, None) => bail!("give --input FILE or --synth N"),
    };
    // Probes read so far (the bar advances as each chunk arrives); a synthetic shard's length
    // is known, a file's is not counted ahead.
    let progress = match &source {
        Source::Synth { start, end, .. } => Progress::new(end - start, "probes"),
        _ => Progress::counter("probes"),
    };
    let stats = match &a.save {
        Some(path) => {
            let format = Format::resolve(path, None)?;
            let mut first = true;
            crate::pipeline::atomic::write_with(path, |w| {
                score(&mut source, &source_id, shard, &encoders, &rule, a.chunk, |c| {
                    progress.inc_by(c.len() as u64);
                    write_probes(w, format, c, std::mem::take(&mut first))
                })
            })?
        }
        None => score(&mut source, &source_id, shard, &encoders, &rule, a.chunk, |c| {
            progress.inc_by(c.len() as u64);
            Ok(())
        })?,
    };
    progress.finish();
    if let Some(out) = &a.out {
        crate::pipeline::atomic::write(out, stats.to_toml()?.as_bytes())?;
        noteln!("wrote {}", out.display());
    }
    noteln!(
        "probes: {} (shard {}/{}), wall {:.3} s, input {:.3} s, peak memory {:.1} MiB (VmHWM), {} thread(s)",
        stats.probes,
        shard.index,
        shard.count,
        stats.wall_s,
        stats.input_s,
        stats.peak_mem_bytes as f64 / (1024.0 * 1024.0),
        stats.threads
    );
    crate::pipeline::output::write(&stats.summary_csv()?)?;
    Ok(0)
}

/// Runs `probelab merge`.
pub fn merge_command(a: MergeArgs) -> Result<i32> {
    let mut merged: Option<SetStats> = None;
    for f in &a.files {
        let s = SetStats::load(f)?;
        match &mut merged {
            None => merged = Some(s),
            Some(m) => m.merge(&s).with_context(|| format!("merging {}", f.display()))?,
        }
    }
    // Cannot fail: `files` is `required = true`, so the loop ran at least once.
    let merged = merged.expect("clap requires at least one file");
    if !merged.complete() {
        let missing: Vec<usize> = (0..merged.shard_count).filter(|s| !merged.shards.contains(s)).collect();
        noteln!("warning: partial merge: shard(s) {missing:?} of {} missing", merged.shard_count);
    }
    if let Some(out) = &a.out {
        crate::pipeline::atomic::write(out, merged.to_toml()?.as_bytes())?;
        noteln!("wrote {}", out.display());
    }
    crate::pipeline::output::write(&merged.summary_csv()?)?;
    Ok(0)
}
