//! The command line: a thin layer over the library. IO happens here and in `runner`/`atomic`.

// clap prints the argument docs as --help, where <root>, <name> and <out> are placeholders.
#![allow(rustdoc::invalid_html_tags)]

use probelab::encoders;
use probelab::envmap::search::SearchPath;
use probelab::pipeline::experiment::{list_experiments, DomainKind, Effect, Experiment};
use probelab::pipeline::output;

/// `println!` that returns `Result<(), StdoutError>` instead of panicking (as the library's
/// `pipeline::output::outln`, which is crate-private).
macro_rules! outln {
    ($($arg:tt)*) => {
        probelab::pipeline::output::write_fmt(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `eprintln!` that ignores a failing stderr instead of panicking.
macro_rules! noteln {
    ($($arg:tt)*) => {
        probelab::pipeline::output::note_fmt(format_args!("{}\n", format_args!($($arg)*)))
    };
}
use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use probelab::pipeline::{atomic, runner, table};
use probelab::reference::domain::parse_axis;
use probelab::reference::metrics::Metric;
use std::path::{Path, PathBuf};

/// The `probelab` command line (its global options and the command).
#[derive(Parser, Debug)]
#[command(name = "probelab", version, about = "Measure compact diffuse-lighting encodings against an exact reference")]
pub struct Cli {
    /// Worker threads, 1 to 1024 (default: all cores). Results do not depend on it.
    #[arg(long, global = true)]
    pub jobs: Option<usize>,
    /// Repository root holding experiments/, results/ and envmaps/.
    #[arg(long, global = true, default_value = ".")]
    pub root: PathBuf,
    /// Print where the time went (decode, reference, fits, rendering, …) to stderr at the end.
    #[arg(long, global = true)]
    pub profile: bool,
    /// Skip the timing pass: the fit_ns and eval_ns columns stay empty.
    #[arg(long, global = true)]
    pub no_timing: bool,
    /// The command to run.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands (docs/commands.md).
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run experiment files and write results/<name>/table.csv (a table that exists is a
    /// baseline: left unchanged if nothing moved, refused if something did; see `bless`).
    Run {
        /// Experiment TOML files.
        #[arg(required = true)]
        experiments: Vec<PathBuf>,
        /// Output folder (default: <root>/results).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Run every experiment in experiments/ on the maps found; an experiment missing some maps is
    /// checked against its baseline on the others, one missing all of them is skipped and listed.
    Reproduce {
        /// Output folder (default: <root>/results).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Draw the comparison sheets and charts and write results/REPORT.md from the result CSVs.
    Report {
        /// Results folder (default: <root>/results).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Draw the comparison sheets N times larger (1 to 8): discs evaluated at N times
        /// the pixels, text and thumbnail at N times their size. Charts are unchanged.
        #[arg(long, default_value_t = 1, value_name = "N",
              value_parser = clap::value_parser!(u32).range(1..=probelab::report::sheet::MAX_SCALE as i64))]
        scale: u32,
    },
    /// Score encoders on maps and print CSV to stdout.
    Eval {
        /// Map names (on the search path) or file paths.
        #[arg(required = true)]
        maps: Vec<String>,
        /// Comma-separated encoder ids (see `probelab encoders`).
        #[arg(long, default_value = "sh1,sh2")]
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
        #[arg(long, default_value_t = probelab::reference::exact::DEFAULT_POLAR_NODES)]
        polar_nodes: usize,
        /// Output format: `csv` (the table's columns) or `json` (an array of objects keyed by
        /// the same columns, scores as numbers).
        #[arg(long, default_value = "csv", value_parser = ["csv", "json"])]
        format: String,
    },
    /// Fit encoders to one map and print each fit's stored coefficients (names, units, basis)
    /// and what it was fitted on.
    Fit {
        /// Map name (on the search path) or file path.
        map: String,
        /// Comma-separated encoder ids (see `probelab encoders`).
        #[arg(long)]
        encoders: String,
        /// The surface normal N as x,y,z (world space, +Y up; normalised): fit to the light above
        /// its horizon, about N. Without it the fit is a probe's, on the whole sphere.
        #[arg(long)]
        normal: Option<String>,
        /// `json` or `csv` (one row per stored or derived value).
        #[arg(long, default_value = "json")]
        format: String,
    },
    /// Write the analytic scenes into envmaps/ as f32 EXR.
    GenEnvmaps {
        /// Output folder (default: <root>/envmaps).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Width of the maps (height is half).
        #[arg(long, default_value_t = 1024)]
        width: usize,
    },
    /// Re-run experiments and compare every number with its baseline in results/ (exit 1 if
    /// anything moved).
    Check {
        /// Experiment names or files (default: every experiment with `ci = true`).
        experiments: Vec<String>,
        /// Also check the experiments marked `ci = false` (the full check).
        #[arg(long)]
        all: bool,
        /// Do not fail when a map is not on this machine (its rows are reported, not compared).
        #[arg(long)]
        allow_missing: bool,
        /// Baselines folder (default: <root>/results).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Output format: `text` (one line per finding and a verdict per experiment) or `json`
        /// (one object: the overall verdict, and per experiment its counts and findings).
        #[arg(long, default_value = "text", value_parser = ["text", "json"])]
        format: String,
    },
    /// Re-run experiments and rewrite the baselines that differ, printing the differences.
    Bless {
        /// Experiment names or files (default: every experiment).
        experiments: Vec<String>,
        /// Rewrite even when nothing moved (refreshes provenance and ignored columns).
        #[arg(long)]
        force: bool,
        /// Baselines folder (default: <root>/results).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Fit the ZH3 hallucination curve f/L00 = c1 r + c2 r² (+ c3 r³) to maps and/or a probe
    /// file, and print it next to SH L1 and the paper's curve.
    FitHallucination {
        /// Map names (on the search path) or file paths.
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
    },
    /// Run the claims measurements and judge every claim of experiments/claims/*.toml: writes
    /// results/CLAIMS.csv, results/claims/<paper>.md and results/claims/measures/*.csv (a
    /// measurement whose numbers moved is not rewritten; `bless claims` does that).
    Claims {
        /// Output folder (default: <root>/results).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// List the encoders.
    Encoders,
    /// Show the map search path and which maps it finds; `maps import` makes 256x128 maps.
    Maps {
        #[command(subcommand)]
        command: Option<MapsCommand>,
    },
    /// Score encoders over a probe set (a file, or --synth N), in chunks and optionally sharded.
    Probes(probelab::pipeline::probeset::ProbesArgs),
    /// Merge shard statistics written by `probes --out`.
    Merge(probelab::pipeline::probeset::MergeArgs),
    /// Vary one accuracy knob and record error against time (experiments/sweeps/*.toml).
    Sweep(probelab::pipeline::sweep::SweepArgs),
}

/// The subcommands of `probelab maps`.
#[derive(Subcommand, Debug)]
pub enum MapsCommand {
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

/// The most worker threads `--jobs` may ask for.
pub const MAX_JOBS: usize = 1024;

/// Runs the command line; returns the process exit code.
pub fn main_with(cli: Cli) -> Result<i32> {
    if let Some(j) = cli.jobs {
        // A bound not from user input alone: `--jobs 1000000` once spent minutes creating threads.
        if !(1..=MAX_JOBS).contains(&j) {
            bail!("--jobs {j}: expected 1 to {MAX_JOBS} worker threads");
        }
        rayon::ThreadPoolBuilder::new().num_threads(j).build_global().context("--jobs")?;
    }
    if cli.profile {
        probelab::pipeline::profile::enable();
    }
    probelab::pipeline::timing::set_enabled(!cli.no_timing);
    let _profile_report = probelab::pipeline::profile::ReportOnDrop(std::time::Instant::now());
    let root = cli.root.clone();
    let search = SearchPath::from_env(root.join("envmaps"));
    let results = |out: Option<PathBuf>| out.unwrap_or_else(|| root.join("results"));
    match cli.command {
        // Losing nothing: every experiment is loaded and run before anything is written, so a
        // failure anywhere (a bad file, a map that cannot be read) leaves results/ as it was;
        // each file is then written atomically.
        Command::Run { experiments, out } => {
            let out = results(out);
            let _lock = writing(&out)?;
            let exps = experiments.iter().map(|p| Experiment::load(p)).collect::<Result<Vec<_>>>()?;
            // Run everything first, write only then: a failure leaves results/ untouched.
            let mut done = Vec::new();
            for exp in &exps {
                let report = runner::run(exp, &search)?;
                if !report.missing.is_empty() {
                    bail!(
                        "{}\nnothing written. Searched: {}",
                        missing_maps(exp, &report.missing),
                        describe_search(&search)
                    );
                }
                done.push(report);
            }
            let mut refused = Vec::new();
            for (exp, report) in exps.iter().zip(&done) {
                if !write_results(&root, &out, exp, report)? {
                    refused.push(exp.name.clone());
                }
            }
            Ok(probelab::regression::check::refused_exit(&refused))
        }
        Command::Reproduce { out } => {
            let out = results(out);
            let _lock = writing(&out)?;
            let dir = root.join("experiments");
            let exps = list_experiments(&dir)?.iter().map(|p| Experiment::load(p)).collect::<Result<Vec<_>>>()?;
            let (mut skipped, mut refused) = (Vec::new(), Vec::new());
            let (mut done, mut partial) = (Vec::new(), Vec::new());
            let progress = probelab::pipeline::progress::Progress::new(exps.len() as u64, "experiments");
            for exp in &exps {
                progress.message(exp.name.clone());
                let report = runner::run(exp, &search)?;
                if report.missing.is_empty() {
                    done.push((exp, report));
                } else if report.missing.len() == exp.maps.len() {
                    noteln!("skipped {}: map(s) not found: {}", exp.name, report.missing.join(", "));
                    skipped.push(exp.name.clone());
                } else {
                    partial.push((exp, report));
                }
                progress.inc();
            }
            progress.finish();
            // Every run is done before anything is written (a failing run writes nothing).
            let mut summary = Vec::new();
            for (exp, report) in &done {
                if let Some(told) = write_results_told(&root, &out, exp, report)? {
                    let n = exp.maps.len();
                    summary.push(format!("{}: {n} of {n} maps; {told}", exp.name));
                } else {
                    refused.push(exp.name.clone());
                }
            }
            // Some maps found: those maps' rows are compared with the committed baseline, which
            // is never rewritten from a partial run.
            for (exp, report) in &partial {
                let line = probelab::regression::check::check_partial(&out, &root, exp, report)?;
                if !line.passed {
                    refused.push(exp.name.clone());
                }
                summary.push(line.text);
            }
            for name in &skipped {
                let exp = exps.iter().find(|e| &e.name == name).expect("a skipped experiment was listed");
                summary.push(format!(
                    "{name}: skipped, 0 of {n} maps (missing: {})",
                    exp.maps.join(", "),
                    n = exp.maps.len()
                ));
            }
            if !skipped.is_empty() || !partial.is_empty() {
                noteln!(
                    "{} experiment(s) skipped and {} run on part of their maps, for missing maps; their \
                     baselines were left unchanged.\nSearched: {}\nSet PROBELAB_ENVMAPS to the folder of the \
                     paper probes (see envmaps/README.md).",
                    skipped.len(),
                    partial.len(),
                    describe_search(&search)
                );
            }
            noteln!("sweeps (experiments/sweeps/) are not re-run by reproduce: `probelab sweep` runs them");
            // The claims, judged on the tables just written (and the measurements, when their
            // maps are here), before the report that presents them.
            let run = probelab::regression::claims::run(&root, &search, &out, false, true)?;
            let (claims_ok, text) = probelab::regression::claims::report(&run, false);
            write_strips(&out, &run)?;
            output::write(text.as_bytes())?;
            if !claims_ok {
                refused.push("claims".into());
            }
            write_report(&root, &out, &search, 1)?;
            outln!("reproduce: {} experiment(s)", exps.len())?;
            for line in &summary {
                outln!("  {line}")?;
            }
            Ok(probelab::regression::check::refused_exit(&refused))
        }
        Command::Report { out, scale } => {
            let out = results(out);
            let _lock = writing(&out)?;
            write_report(&root, &out, &search, scale)?;
            Ok(0)
        }
        Command::Check { experiments, all, allow_missing, out, format } => {
            let out = results(out);
            let json = format == "json";
            // A shared lock: no bless rewrites a baseline while it is read.
            let _lock = if out.is_dir() { Some(atomic::lock(&out, false, || waiting(&out))?) } else { None };
            let claims = all || experiments.iter().any(|e| e == "claims");
            let names: Vec<String> = experiments.into_iter().filter(|e| e != "claims").collect();
            let mut code = 0;
            let mut doc = serde_json::json!({ "passed": true });
            if all || !names.is_empty() || !claims {
                let (c, summary) = probelab::regression::check::check_experiments(
                    &root,
                    &search,
                    &out,
                    &names,
                    all,
                    allow_missing,
                    json,
                )?;
                code = c;
                if json {
                    doc = summary.json;
                } else {
                    output::write(summary.text.as_bytes())?;
                }
            }
            if claims {
                let run = probelab::regression::claims::run(&root, &search, &out, false, false)?;
                let (ok, text) = probelab::regression::claims::report(&run, true);
                if json {
                    doc["claims"] = serde_json::json!({
                        "passed": ok,
                        "lines": text.lines().collect::<Vec<_>>(),
                    });
                    doc["passed"] = serde_json::Value::Bool(doc["passed"].as_bool().unwrap_or(true) && ok);
                } else {
                    output::write(text.as_bytes())?;
                    outln!("claims: {}", if ok { "ok: no measurement moved, no verdict changed" } else { "FAILED" })?;
                }
                if !ok {
                    code = code.max(1);
                }
            }
            if json {
                let mut text = serde_json::to_string_pretty(&doc)?;
                text.push('\n');
                output::write(text.as_bytes())?;
            }
            Ok(code)
        }
        Command::Bless { experiments, force, out } => {
            let out = results(out);
            let _lock = writing(&out)?;
            let claims = experiments.is_empty() || experiments.iter().any(|e| e == "claims");
            let names: Vec<String> = experiments.iter().filter(|e| *e != "claims").cloned().collect();
            let mut code = 0;
            // Every write, then every line (pipeline::output): a failing stdout never stops a
            // bless between two baselines.
            let mut lines = String::new();
            if experiments.is_empty() || !names.is_empty() {
                let (c, text) = probelab::regression::check::bless_command(&root, &search, &out, &names, force)?;
                code = c;
                lines += &text;
            }
            if claims {
                let run = probelab::regression::claims::run(&root, &search, &out, true, true)?;
                let (_, text) = probelab::regression::claims::report(&run, false);
                write_strips(&out, &run)?;
                lines += &text;
                lines += &format!("claims: wrote {} file(s)\n", run.written.len());
            }
            output::write(lines.as_bytes())?;
            Ok(code)
        }
        Command::Eval { maps, encoders: list, domain, metric, resolution, polar_nodes, format } => {
            let exp = eval_experiment(maps, &list, &domain, &metric, &resolution, polar_nodes)?;
            let report = runner::run(&exp, &search)?;
            if !report.missing.is_empty() {
                let why: Vec<String> =
                    report.missing.iter().zip(&report.missing_why).map(|(m, w)| format!("{m} ({w})")).collect();
                bail!("map(s) not found: {}\nSearched: {}", why.join(", "), describe_search(&search));
            }
            output::write(&if format == "json" {
                table::to_json(&report.rows)?
            } else {
                table::to_csv(&report.rows)?
            })?;
            Ok(0)
        }
        Command::Fit { map, encoders: list, normal, format } => {
            output::write(fit_command(&search, &map, &list, normal.as_deref(), &format)?.as_bytes())?;
            Ok(0)
        }
        Command::GenEnvmaps { out, width } => {
            if width < 4 || width % 2 != 0 || width > 8192 {
                bail!("--width {width}: expected an even width from 4 to 8192");
            }
            let out = out.unwrap_or_else(|| root.join("envmaps"));
            let _lock = writing(&out)?;
            // Every map, then every line (a failing stdout never stops the writes half way).
            let mut lines = String::new();
            for s in probelab::reference::scenes::generated() {
                let path = out.join(format!("{}.exr", s.id));
                probelab::envmap::load::write_exr(&path, &s.map(width))?;
                lines += &format!("{}  {}\n", path.display(), s.description);
            }
            output::write(lines.as_bytes())?;
            Ok(0)
        }
        Command::FitHallucination { maps, probes, format, cubic, axis } => {
            let report = probelab::pipeline::hallucination_fit::run(
                &search,
                &maps,
                probes.as_deref(),
                format.as_deref(),
                &axis,
                cubic,
            )?;
            output::write(report.as_bytes())?;
            Ok(0)
        }
        Command::Claims { out } => {
            let out = results(out);
            let _lock = writing(&out)?;
            let run = probelab::regression::claims::run(&root, &search, &out, false, true)?;
            let (ok, text) = probelab::regression::claims::report(&run, false);
            let strips = write_strips(&out, &run)?;
            output::write(text.as_bytes())?;
            noteln!("wrote {} file(s) and {strips} blending strip(s) under {}", run.written.len(), out.display());
            Ok(if ok { 0 } else { 1 })
        }
        Command::Encoders => {
            let text: String = encoders::REGISTRY.iter().map(|k| format!("{:28} {}\n", k.id, k.summary)).collect();
            output::write(text.as_bytes())?;
            Ok(0)
        }
        Command::Maps { command: Some(MapsCommand::Import { inputs, out }) } => import_maps(&inputs, &out),
        Command::Maps { command: None } => {
            let mut text = format!("search path: {}\n", describe_search(&search));
            for d in search.dirs() {
                let Ok(entries) = std::fs::read_dir(d) else {
                    continue;
                };
                let mut names: Vec<String> = entries
                    .filter_map(|e| e.ok())
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .filter(|n| n.ends_with(".exr") || n.ends_with(".hdr"))
                    .collect();
                names.sort();
                text += &format!("{}:\n", d.display());
                for n in names {
                    text += &format!("  {n}\n");
                }
            }
            output::write(text.as_bytes())?;
            Ok(0)
        }
        Command::Probes(args) => probelab::pipeline::probeset::command(args, &search),
        Command::Merge(args) => probelab::pipeline::probeset::merge_command(args),
        Command::Sweep(args) => {
            let _lock = writing(&results(args.out.clone()))?;
            probelab::pipeline::sweep::command(args, &root, &search)
        }
    }
}

/// `probelab maps import` (`envmap::import`): every input is read and derived before anything
/// is written (a bad file writes nothing); a map whose file already exists in `out` with the
/// same pixels is left as it is, one with other pixels is refused; each is written atomically.
fn import_maps(inputs: &[PathBuf], out: &Path) -> Result<i32> {
    let mut files = Vec::new();
    for p in inputs {
        if p.is_dir() {
            let entries = std::fs::read_dir(p).with_context(|| format!("{}: cannot list the folder", p.display()))?;
            let mut found: Vec<PathBuf> = entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| f.is_file() && f.extension().is_some_and(|x| x == "exr" || x == "hdr"))
                .collect();
            if found.is_empty() {
                bail!("{}: no .exr or .hdr file in this folder", p.display());
            }
            found.sort();
            files.extend(found);
        } else {
            files.push(p.clone());
        }
    }
    let mut made: Vec<(PathBuf, probelab::envmap::EnvMap, probelab::envmap::import::Imported)> = Vec::new();
    let mut errors = Vec::new();
    for f in &files {
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
        bail!(
            "{}
nothing written",
            errors.join("\n")
        );
    }
    let _lock = writing(out)?;
    // A file already there is kept when it has the pixels made, and refused otherwise, before
    // anything is written.
    let mut kept = Vec::new();
    for (f, _, d) in &made {
        let target = out.join(format!("{}.exr", d.name));
        let same = match target.exists() {
            false => false,
            true if probelab::envmap::identity::pixel_sha256(&probelab::envmap::load::load(&target)?)
                == d.pixel_sha256 =>
            {
                true
            }
            true => bail!(
                "{}: exists with other pixels than the map made from {}; nothing written (remove it first)",
                target.display(),
                f.display()
            ),
        };
        kept.push(same);
    }
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

/// Takes the exclusive lock on an output folder for a writing command (waiting, with a note,
/// while another probelab command holds it), then removes the temporary files that killed
/// runs left there, saying so (`pipeline::atomic`).
fn writing(out: &Path) -> Result<atomic::DirLock> {
    let lock = atomic::lock(out, true, || waiting(out))?;
    for p in atomic::remove_stale(out)? {
        noteln!("removed {} (left by a killed run whose process is gone)", p.display());
    }
    Ok(lock)
}

fn waiting(out: &Path) {
    noteln!("waiting for {}: another probelab command is using it", out.display());
}

/// "FILE:LINE: map 'x' not found" for each missing map (the line where the experiment file
/// names it).
fn missing_maps(exp: &Experiment, missing: &[String]) -> String {
    let file = exp.source.as_ref().map(|p| p.display().to_string()).unwrap_or_else(|| exp.name.clone());
    missing
        .iter()
        .zip(exp.source_lines(missing))
        .map(|(m, line)| match line {
            Some(l) => format!("{file}:{l}: map '{m}' not found"),
            None => format!("{file}: map '{m}' not found"),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn describe_search(s: &SearchPath) -> String {
    s.dirs()
        .iter()
        .map(|d| if d.is_dir() { d.display().to_string() } else { format!("{} (missing)", d.display()) })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Draws the lightmap study's blending strips (report layer) and writes them under
/// `results/claims/`, each atomically; returns how many.
fn write_strips(out: &Path, run: &probelab::regression::claims::ClaimsRun) -> Result<usize> {
    let strips = probelab::report::strip::pngs(&run.strips)?;
    for (name, bytes) in &strips {
        probelab::pipeline::atomic::write(&out.join("claims").join(name), bytes)?;
    }
    Ok(strips.len())
}

/// Writes results/REPORT.md with its pictures (`report::generate`), the comparison sheets at
/// `sheet_scale` (1 for the standard sheets).
fn write_report(root: &Path, out: &Path, search: &SearchPath, sheet_scale: u32) -> Result<()> {
    let g = probelab::report::generate(&probelab::report::Options { root, out, search, sheet_scale })?;
    noteln!("wrote {} ({} picture(s) drawn)", g.report.display(), g.pictures);
    if !g.kept.is_empty() {
        noteln!("sheets not redrawn (maps not on the search path): {}", g.kept.join(", "));
    }
    Ok(())
}

/// Writes results/<name>/table.csv and provenance.toml atomically when there is no table
/// yet; an existing table is a baseline and is never overwritten here (only `bless` does):
/// returns false, printing the differences, if its numbers moved (`check::store`). When the
/// table stands, the summary files derived from it (summary.csv, claims) are written too.
pub fn write_results(root: &Path, out: &Path, exp: &Experiment, report: &runner::RunReport) -> Result<bool> {
    Ok(write_results_told(root, out, exp, report)?.is_some())
}

/// [`write_results`], saying what became of the table: `None` when refused, otherwise
/// "new baseline written" or how many numbers matched the baseline.
fn write_results_told(root: &Path, out: &Path, exp: &Experiment, report: &runner::RunReport) -> Result<Option<String>> {
    let _s = probelab::pipeline::profile::span("write");
    let stored = probelab::regression::check::store(out, root, exp, report)?;
    let ok = probelab::regression::check::print_stored(exp, out, &stored, report.rows.len());
    let told = match &stored {
        probelab::regression::check::Stored::New => "no baseline yet: new baseline written".to_string(),
        probelab::regression::check::Stored::Unchanged(c) => {
            format!("{} numbers compared, nothing moved; baseline left unchanged", c.comparison.numbers)
        }
        probelab::regression::check::Stored::Refused(c) => format!("FAILED ({} moved)", c.moved()),
    };
    if ok {
        let dir = out.join(&exp.name);
        // A table that stood within tolerance is the one kept: summarise its numbers.
        let rows = match stored {
            probelab::regression::check::Stored::Unchanged(_) => {
                probelab::regression::check::rows_as_stored(&dir, &report.rows)?
            }
            _ => report.rows.clone(),
        };
        if let Some(baseline) = &exp.summary {
            probelab::pipeline::summary::write(&dir, baseline.as_deref(), &rows)?;
            noteln!("wrote {}", dir.join("summary.csv").display());
        }
    }
    Ok(ok.then_some(told))
}

/// `probelab fit`: every fit of `list` on `map` (about the surface normal `normal`, x,y,z, if
/// given) as JSON or CSV, everything checked before anything is printed.
fn fit_command(search: &SearchPath, map: &str, list: &str, normal: Option<&str>, format: &str) -> Result<String> {
    if format != "json" && format != "csv" {
        bail!("--format '{format}': expected json or csv");
    }
    let surface = match normal {
        None => probelab::api::Surface::Sphere,
        Some(text) => probelab::api::Surface::Normal(parse_normal(text)?),
    };
    let named = encoders::build_list(list)?;
    if surface == probelab::api::Surface::Sphere {
        if let Some(e) = named.iter().find(|e| e.encoder.needs_surface_normal()) {
            bail!(
                "--encoders: {}; pass --normal x,y,z (the surface normal N)",
                probelab::encoders::encoder::surface_normal_refusal(&e.name)
            );
        }
    }
    let map = probelab::api::Map::load_on(search, map)?;
    let light = map.lighting(surface)?;
    let mut fits = Vec::new();
    for e in &named {
        let fit = light.fit(&e.name, "")?;
        let stored = fit.stored();
        if !stored.is_finite() {
            bail!("encoder '{}' on {}: a stored value is not finite", e.name, light.describe());
        }
        fits.push((fit, stored));
    }
    let (w, h) = map.size();
    let n = light.normal();
    let domain = if n.is_some() { "hemisphere" } else { "sphere" };
    if format == "json" {
        let fits: Vec<serde_json::Value> = fits
            .iter()
            .map(|(f, s)| {
                serde_json::json!({
                    "encoder": f.id(),
                    "stored_scalars": f.stored_scalars(),
                    "basis": s.basis,
                    "entries": s.entries,
                })
            })
            .collect();
        let doc = serde_json::json!({
            "map": map.name(),
            "size": [w, h],
            "domain": domain,
            "normal": n.map(|n| n.to_array()),
            "fitted_on": light.describe(),
            "units": "E/pi is irradiance over pi; directions are world-space unit vectors, +Y up \
                      (docs/conventions.md section 1); SH follow section 2",
            "fits": fits,
        });
        return Ok(serde_json::to_string_pretty(&doc)? + "\n");
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["map", "domain", "normal", "encoder", "entry", "role", "unit", "kind", "v0", "v1", "v2", "basis"])?;
    let normal_cell = n.map(|n| format!("{} {} {}", n.x, n.y, n.z)).unwrap_or_default();
    for (f, s) in &fits {
        for e in &s.entries {
            let mut c: Vec<String> = e.value.components().iter().map(|v| format!("{v}")).collect();
            c.resize(3, String::new());
            let role = match e.role {
                probelab::api::Role::Stored => "stored",
                probelab::api::Role::Derived => "derived",
            };
            w.write_record([
                map.name(),
                domain,
                &normal_cell,
                f.id(),
                &e.name,
                role,
                e.unit.label(),
                e.value.kind(),
                &c[0],
                &c[1],
                &c[2],
                &s.basis,
            ])?;
        }
    }
    Ok(String::from_utf8(w.into_inner().context("writing CSV")?)?)
}

/// A surface normal `x,y,z`: three finite numbers, not all zero.
fn parse_normal(text: &str) -> Result<glam::DVec3> {
    let bad = || anyhow::anyhow!("--normal '{text}': expected x,y,z, three finite numbers not all zero (e.g. 0,1,0)");
    let v: Vec<f64> = text.split(',').map(|p| p.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| bad())?;
    let [x, y, z] = v[..] else {
        return Err(bad());
    };
    let n = glam::DVec3::new(x, y, z);
    if !n.is_finite() || n.length_squared() == 0.0 {
        return Err(bad());
    }
    Ok(n)
}

/// The experiment `probelab eval` runs.
fn eval_experiment(
    maps: Vec<String>,
    list: &str,
    domain: &str,
    metric: &str,
    resolution: &str,
    polar_nodes: usize,
) -> Result<Experiment> {
    let res = probelab::pipeline::experiment::parse_resolution(resolution).context("--resolution")?;
    let metric = Metric::parse(metric)?;
    let (kind, orientations, effects) = if domain == "sphere" {
        (DomainKind::Sphere, vec![], vec![])
    } else if let Some(axis) = domain.strip_prefix("hemisphere:") {
        parse_axis(axis).with_context(|| format!("--domain {domain}"))?;
        (DomainKind::Hemisphere, probelab::reference::domain::expand_orientations(axis)?, vec![Effect::Hemisphere])
    } else {
        bail!("--domain '{domain}': expected sphere or hemisphere:AXIS (AXIS one of +x, -x, +y, -y, +z, -z)");
    };
    if kind == DomainKind::Hemisphere && metric == Metric::Probulator {
        bail!("--metric probulator scores the whole sphere; use --domain sphere");
    }
    if !(1..=16).contains(&polar_nodes) {
        bail!("--polar-nodes {polar_nodes}: expected 1..=16");
    }
    let encoders = encoders::build_list(list)?;
    if kind == DomainKind::Sphere {
        if let Some(e) = encoders.iter().find(|e| e.encoder.needs_surface_normal()) {
            bail!(
                "--encoders: {}; pass --domain hemisphere:AXIS (AXIS one of +x, -x, +y, -y, +z, -z), or run an \
                 experiment with domain = \"hemisphere\"",
                probelab::encoders::encoder::surface_normal_refusal(&e.name)
            );
        }
    }
    Ok(Experiment {
        name: "eval".into(),
        description: String::new(),
        source: None,
        maps,
        encoders,
        metrics: vec![metric],
        domain: kind,
        orientations,
        effects,
        resolution: res,
        polar_nodes,
        ci: false,
        summary: None,
        sheets: None,
    })
}
