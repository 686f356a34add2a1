//! A probe-set job, as `probelab probes` declares it (score encoders over a probe file or a
//! synthetic set, or one shard of it), and the merge of shards' statistics (`probelab merge`).
//! The binary parses the command line, prints and writes the statistics file; this module
//! reads the probes, scores them and returns what happened.

use crate::encoders::NamedEncoder;
use crate::io::progress::Progress;
use crate::math::sh::Sh9;
use crate::pipeline::probeset::format::{file_identity, write_probes, Format, ProbeReader};
use crate::pipeline::probeset::score::{score, SetStats, Source, SphereRule};
use crate::pipeline::probeset::shard::Shard;
use crate::pipeline::probeset::synth::{scene_palette, Synth};
use anyhow::{bail, Context, Result};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Where a job's probes come from.
#[derive(Clone, Debug)]
pub enum Input<'a> {
    /// A probe file, its format (`csv`, `f32`; `None`: from its extension).
    File(&'a Path, Option<&'a str>),
    /// `count` synthetic probes from `seed`, seeded by the maps of `palette` (comma-separated;
    /// `None`: every `*_256x128` map on the search path).
    Synth {
        /// Number of probes to synthesise.
        count: u64,
        /// Seed of the synthesis (the same seed gives the same probes).
        seed: u64,
        /// Comma-separated map names whose SH seed the probes (`None`: every `*_256x128` map on the
        /// search path).
        palette: Option<&'a str>,
    },
}

/// One `probelab probes` job: what to score, how, and what to save.
#[derive(Clone, Debug)]
pub struct Job<'a> {
    /// The probes.
    pub input: Input<'a>,
    /// Comma-separated encoder ids, or `all` ([`encoder_list`]).
    pub encoders: &'a str,
    /// `I/N`: this shard of the set.
    pub shard: &'a str,
    /// The quadrature rule `NZxNPHI` ([`SphereRule::parse`]).
    pub quadrature: &'a str,
    /// Probes per chunk (at least 1).
    pub chunk: usize,
    /// Where to save this shard's probes as well (`.csv` or `.f32`), if anywhere.
    pub save: Option<&'a Path>,
}

/// What a job did.
pub struct Done {
    /// The mergeable statistics.
    pub stats: SetStats,
    /// The shard that was scored.
    pub shard: Shard,
    /// Notes for the user (encoders left out of `all`, and why).
    pub notes: Vec<String>,
}

/// The encoders of `--encoders` (`all` = every registered encoder a probe can be scored with),
/// with sh1 first if it was not listed. Two kinds cannot be, and are refused by name: encoders
/// defined only about a surface normal ([`crate::encoders::encoder::Encoder::needs_surface_normal`]),
/// which a probe does not have, and encoders that fit the light beyond L2 SH
/// ([`crate::encoders::encoder::Encoder::reads_radiance`]), which a probe does not store.
/// Returns them, and the note saying what `all` left out (`None` without `all`).
pub fn encoder_list(list: &str) -> Result<(Vec<NamedEncoder>, Option<String>)> {
    let all = list.trim() == "all";
    let list = if all {
        crate::encoders::REGISTRY.iter().map(|k| k.id).collect::<Vec<_>>().join(",")
    } else {
        list.to_string()
    };
    let mut v = crate::encoders::build_list(&list)?;
    let beyond: Vec<String> = v.iter().filter(|e| e.encoder.reads_radiance()).map(|e| e.name.clone()).collect();
    let surface: Vec<String> = v.iter().filter(|e| e.encoder.needs_surface_normal()).map(|e| e.name.clone()).collect();
    let mut note = None;
    if all {
        v.retain(|e| !e.encoder.needs_surface_normal() && !e.encoder.reads_radiance());
        note = Some(format!(
            "--encoders all: left out {} (fitted from the light beyond L2 SH, which a probe does not store) and {} \
             (they need a surface normal N, which a probe does not have)",
            beyond.join(", "),
            surface.join(", ")
        ));
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
    Ok((v, note))
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
                    let ext_ok = crate::envmap::search::has_map_extension(&p);
                    let stem = p.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
                    if ext_ok && stem.ends_with("_256x128") && p.file_name().and_then(|n| n.to_str()).is_none() {
                        bail!("{}: {}", p.display(), crate::envmap::search::NOT_UTF8);
                    }
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

/// The source of a job's probes and its identity (the file's, or the synthesis's parameters).
fn open_source(input: &Input, shard: Shard, search: &crate::envmap::search::SearchPath) -> Result<(Source, String)> {
    Ok(match *input {
        Input::File(path, format) => {
            let format = Format::resolve(path, format)?;
            let reader = ProbeReader::open(path, format, shard)?;
            (Source::File(reader), file_identity(path)?)
        }
        Input::Synth { count: 0, .. } => bail!("--synth 0: a probe set needs at least one probe"),
        Input::Synth { count, seed, palette: names } => {
            let synth = Synth::new(seed, palette(search, names)?);
            let id = format!(
                "synth n={count} seed={seed} palette={} [{}] fingerprint={}",
                synth.palette_names.len(),
                synth.palette_names.join(" "),
                synth.fingerprint()
            );
            let (start, end) = shard.range(count);
            (Source::Synth { synth, start, end, next: start }, id)
        }
    })
}

/// Runs a probe-set job: reads or synthesises the shard's probes chunk by chunk, scores every
/// encoder on them (saving the probes too with [`Job::save`]), and returns the statistics.
pub fn run(job: &Job, search: &crate::envmap::search::SearchPath) -> Result<Done> {
    let shard = Shard::parse(job.shard)?;
    let (encoders, note) = encoder_list(job.encoders)?;
    let rule = SphereRule::parse(job.quadrature)?;
    if job.chunk == 0 {
        bail!("--chunk must be at least 1");
    }
    let (mut source, source_id) = open_source(&job.input, shard, search)?;
    // Probes read so far (the bar advances as each chunk arrives); a synthetic shard's length
    // is known, a file's is not counted ahead.
    let progress = match &source {
        Source::Synth { start, end, .. } => Progress::new(end - start, "probes"),
        _ => Progress::counter("probes"),
    };
    let stats = match job.save {
        Some(path) => {
            let format = Format::resolve(path, None)?;
            let mut first = true;
            crate::io::atomic::write_with(path, |w| {
                score(&mut source, &source_id, shard, &encoders, &rule, job.chunk, |c| {
                    progress.inc_by(c.len() as u64);
                    write_probes(w, format, c, std::mem::take(&mut first))
                })
            })?
        }
        None => score(&mut source, &source_id, shard, &encoders, &rule, job.chunk, |c| {
            progress.inc_by(c.len() as u64);
            Ok(())
        })?,
    };
    progress.finish();
    Ok(Done { stats, shard, notes: note.into_iter().collect() })
}

/// Merges the statistics files of shards (`probelab merge`); returns the merged statistics and
/// a warning naming the shards missing, if any. `files` must not be empty.
pub fn merge(files: &[PathBuf]) -> Result<(SetStats, Option<String>)> {
    let mut merged: Option<SetStats> = None;
    for f in files {
        let s = SetStats::load(f)?;
        match &mut merged {
            None => merged = Some(s),
            Some(m) => m.merge(&s).with_context(|| format!("merging {}", f.display()))?,
        }
    }
    let Some(merged) = merged else { bail!("no statistics files to merge") };
    let warning = (!merged.complete()).then(|| {
        let missing: Vec<usize> = (0..merged.shard_count).filter(|s| !merged.shards.contains(s)).collect();
        format!("warning: partial merge: shard(s) {missing:?} of {} missing", merged.shard_count)
    });
    Ok((merged, warning))
}
