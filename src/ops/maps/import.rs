//! `probelab maps import` (`envmap::import`): the 256x128 maps of map files, made as the
//! shared ones were made and named through the known maps. Every input is read and derived
//! before anything is written (a bad file writes nothing); a map whose file already exists in
//! the output folder with the same pixels is left as it is, one with other pixels is refused;
//! each is written atomically under the output folder's exclusive lock.

use super::super::context::Env;
use super::list::is_map_file;
use crate::envmap::import::Imported;
use crate::envmap::known::KnownMap;
use crate::envmap::EnvMap;
use crate::io::distinct::{refuse_overwrite, Named};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// The options of `probelab maps import`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImportOptions {
    /// Map files (.exr, .hdr), or folders: every .exr and .hdr file directly in them.
    pub inputs: Vec<PathBuf>,
    /// The folder written (`--out`, created if absent).
    pub out: PathBuf,
}

/// One map made.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedMap {
    /// The input file.
    pub input: PathBuf,
    /// Its size in texels.
    pub input_size: (usize, usize),
    /// The file of the 256x128 map.
    pub target: PathBuf,
    /// True when the target was already there with the same pixels (left as it is).
    pub kept: bool,
    /// True when the input was averaged down (false: it was 256x128 already).
    pub averaged: bool,
    /// The map's pixel sha256.
    pub pixel_sha256: String,
    /// The known map it is, if any.
    pub known: Option<&'static KnownMap>,
}

/// What `probelab maps import` made, in input order.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedMaps {
    /// Each map.
    pub maps: Vec<ImportedMap>,
}

/// `probelab maps import`: `--out` checked not to be an input, every input derived, the lock
/// taken, the targets checked, then the maps not already there written.
pub fn import(env: &Env, o: &ImportOptions) -> Result<ImportedMaps> {
    let out = &o.out;
    let files = input_files(&o.inputs)?;
    // A target that is an input exists with that input's pixels (kept) or other pixels
    // (refused by `already_there`); the folder itself must not be an input file.
    let ins: Vec<Named> = files.iter().map(|p| Named { role: "an input map", path: p }).collect();
    refuse_overwrite(&[Named { role: "--out", path: out }], &ins)?;
    let made = derive_all(&files)?;
    let _lock = env.writing(out)?;
    let kept = already_there(&made, out)?;
    let mut maps = Vec::new();
    for ((f, source, d), kept) in made.into_iter().zip(kept) {
        let target = out.join(format!("{}.exr", d.name));
        if !kept {
            crate::envmap::load::write_exr_half(&target, &d.map)?;
        }
        maps.push(ImportedMap {
            input: f,
            input_size: (source.width(), source.height()),
            target,
            kept,
            averaged: d.averaged,
            pixel_sha256: d.pixel_sha256,
            known: d.known,
        });
    }
    Ok(ImportedMaps { maps })
}

/// The map files of the inputs: files as given, folders as every `.exr` and `.hdr` file
/// directly in them (sorted); a folder with none is an error.
fn input_files(inputs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for p in inputs {
        if !p.is_dir() {
            files.push(p.clone());
            continue;
        }
        let entries = std::fs::read_dir(p).with_context(|| format!("{}: cannot list the folder", p.display()))?;
        let mut found: Vec<PathBuf> =
            entries.filter_map(|e| e.ok().map(|e| e.path())).filter(|f| is_map_file(f)).collect();
        if found.is_empty() {
            bail!("{}: no .exr or .hdr file in this folder", p.display());
        }
        found.sort();
        files.extend(found);
    }
    Ok(files)
}

/// Every file read and its 256x128 map derived; every failure is reported together, and then
/// nothing is written.
fn derive_all(files: &[PathBuf]) -> Result<Vec<(PathBuf, EnvMap, Imported)>> {
    let mut made: Vec<(PathBuf, EnvMap, Imported)> = Vec::new();
    let mut errors = Vec::new();
    for f in files {
        let source = match crate::envmap::load::load(f) {
            Ok(m) => m,
            Err(e) => {
                errors.push(e.to_string());
                continue;
            }
        };
        match crate::envmap::import::derive(&source) {
            Ok(d) if made.iter().any(|m| m.2.name == d.name) => {
                errors.push(format!("{}: gives the map {}, as an earlier input does", f.display(), d.name))
            }
            Ok(d) => made.push((f.clone(), source, d)),
            Err(e) => errors.push(format!("{}: {e}", f.display())),
        }
    }
    if !errors.is_empty() {
        bail!("{}\nnothing written", errors.join("\n"));
    }
    Ok(made)
}

/// For each map made, whether its file is already in `out` with the same pixels (kept as it
/// is); a file there with other pixels is refused before anything is written.
fn already_there(made: &[(PathBuf, EnvMap, Imported)], out: &Path) -> Result<Vec<bool>> {
    let mut kept = Vec::new();
    for (f, _, d) in made {
        let target = out.join(format!("{}.exr", d.name));
        let same = target.exists()
            && crate::envmap::identity::pixel_sha256(&crate::envmap::load::load(&target)?) == d.pixel_sha256;
        if target.exists() && !same {
            bail!(
                "{}: exists with other pixels than the map made from {}; nothing written (remove it first)",
                target.display(),
                f.display()
            );
        }
        kept.push(same);
    }
    Ok(kept)
}

impl ImportedMaps {
    /// The maps as printed: one line each, its file, whether it was already there, the input
    /// and how it was made, its pixel sha256 and the known map it is.
    pub fn to_text(&self) -> String {
        let mut lines = String::new();
        for m in &self.maps {
            let how = if m.averaged {
                format!("{}x{} averaged to 256x128", m.input_size.0, m.input_size.1)
            } else {
                "256x128, as is".to_string()
            };
            let known = match m.known {
                Some(k) => format!("known map {} ({}; {})", k.name, k.source, k.licence),
                None => "not a known map".to_string(),
            };
            lines += &format!(
                "{}{} <- {} ({how}): pixel sha256 {}, {known}\n",
                m.target.display(),
                if m.kept { " (already there, unchanged)" } else { "" },
                m.input.display(),
                m.pixel_sha256
            );
        }
        lines
    }
}
