//! `probelab maps`: shows the map search path, the maps it finds and the known maps it does not
//! (with where to get them); `probelab maps import`
//! makes the 256x128 maps of map files as the shared ones were made (`envmap::import`), named
//! through the known maps, each written atomically under the output folder's exclusive lock.

use super::context::describe_search;
use super::output;
use anyhow::{bail, Context, Result};
use probelab::envmap::import::Imported;
use probelab::envmap::EnvMap;
use probelab::io::distinct::{refuse_overwrite, Named};
use probelab::ops::Env;
use std::path::{Path, PathBuf};

/// `probelab maps`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    command: Option<MapsCommand>,
}

/// The subcommands of `probelab maps`.
#[derive(clap::Subcommand, Debug)]
enum MapsCommand {
    /// Make the 256x128 maps of map files as the shared ones were made (decode, half, solid-angle-
    /// weighted area average when larger), name them through the known maps (envmaps/known.toml)
    /// and write <name>.exr into --out; prints each with its pixel sha256 (docs/maps.md).
    Import {
        /// Map files (.exr, .hdr), or folders: every .exr and .hdr file directly in them.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// Folder to write the maps into (created if absent).
        #[arg(long)]
        out: PathBuf,
    },
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    match a.command {
        Some(MapsCommand::Import { inputs, out }) => import_maps(env, &inputs, &out),
        None => list(env),
    }
}

/// The search path, and the `.exr` and `.hdr` files in each of its folders.
fn list(env: &Env) -> Result<i32> {
    let mut text = format!("search path: {}\n", describe_search(&env.search));
    for d in env.search.dirs() {
        let Ok(entries) = std::fs::read_dir(d) else {
            continue;
        };
        let mut names: Vec<String> = entries
            .filter_map(|e| e.ok())
            .filter(|e| is_map_file(&e.path()))
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        text += &format!("{}:\n", d.display());
        for n in names {
            text += &format!("  {n}\n");
        }
    }
    text += &known_missing(env);
    output::write(text.as_bytes())?;
    Ok(0)
}

/// Whether `path` is a map file to list or import from a folder: a regular file (after
/// symbolic links; not a FIFO, socket or a folder named `NAME.exr`) whose extension is `exr` or
/// `hdr` in any case (`X.EXR`).
fn is_map_file(path: &Path) -> bool {
    probelab::envmap::search::has_map_extension(path) && std::fs::metadata(path).is_ok_and(|m| m.is_file())
}

/// The known maps (envmaps/known.toml) not on the search path, each with where to get it.
fn known_missing(env: &Env) -> String {
    let missing = env.search.known_missing();
    if missing.is_empty() {
        return "every known map is on the search path\n".to_string();
    }
    let mut text = format!(
        "known maps not found ({}; put them in a folder and set {}, docs/maps.md):\n",
        missing.len(),
        probelab::envmap::search::ENV_VAR
    );
    for k in missing {
        text += &format!("  {} ({}x{}): {}\n", k.name, k.width, k.height, k.get);
    }
    text
}

/// `probelab maps import` (`envmap::import`): every input is read and derived before anything
/// is written (a bad file writes nothing); a map whose file already exists in `out` with the
/// same pixels is left as it is, one with other pixels is refused; each is written atomically.
fn import_maps(env: &Env, inputs: &[PathBuf], out: &Path) -> Result<i32> {
    let files = input_files(inputs)?;
    // A target that is an input exists with that input's pixels (kept) or other pixels
    // (refused by `already_there`); the folder itself must not be an input file.
    let ins: Vec<Named> = files.iter().map(|p| Named { role: "an input map", path: p }).collect();
    refuse_overwrite(&[Named { role: "--out", path: out }], &ins)?;
    let made = derive_all(&files)?;
    let _lock = env.writing(out)?;
    let kept = already_there(&made, out)?;
    let mut lines = String::new();
    for ((f, source, d), &kept) in made.iter().zip(&kept) {
        let target = out.join(format!("{}.exr", d.name));
        if !kept {
            probelab::envmap::load::write_exr_half(&target, &d.map)?;
        }
        let how = if d.averaged {
            format!("{}x{} averaged to 256x128", source.width(), source.height())
        } else {
            "256x128, as is".to_string()
        };
        let known = match d.known {
            Some(k) => format!("known map {} ({}; {})", k.name, k.source, k.licence),
            None => "not a known map".to_string(),
        };
        lines += &format!(
            "{}{} <- {} ({how}): pixel sha256 {}, {known}\n",
            target.display(),
            if kept { " (already there, unchanged)" } else { "" },
            f.display(),
            d.pixel_sha256
        );
    }
    output::write(lines.as_bytes())?;
    Ok(0)
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
        let source = match probelab::envmap::load::load(f) {
            Ok(m) => m,
            Err(e) => {
                errors.push(e.to_string());
                continue;
            }
        };
        match probelab::envmap::import::derive(&source) {
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
            && probelab::envmap::identity::pixel_sha256(&probelab::envmap::load::load(&target)?) == d.pixel_sha256;
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
