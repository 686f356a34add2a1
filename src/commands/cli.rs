//! The global options (`Cli`), the commands (`Command`) and the dispatch (`main_with`): the
//! process-wide setup the binary owns (the `--jobs` thread pool, the progress bars, the
//! `--profile` profile), the one `ops::Env` every command is given, and the exit code.

use super::{
    bless, check, claims, encoders, eval, fit, fit_hallucination, gen_envmaps, maps, merge, probes, report, reproduce,
    run, sweep, terminal, view,
};
use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use probelab::ops::{Env, Profile, RunSettings, SearchPath};
use std::path::PathBuf;

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
    /// Run work estimated above 30 minutes on this machine (refused without it, with the
    /// estimate and what drives it).
    #[arg(long, global = true)]
    pub allow_long: bool,
    /// The command to run.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands (docs/commands.md).
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run experiment files and write results/<name>/table.csv (a table that exists is a
    /// baseline: left unchanged if nothing moved, refused if something did; see `bless`).
    Run(run::Args),
    /// Run every experiment in experiments/ on the maps found; an experiment missing some maps is
    /// checked against its baseline on the others, one missing all of them is skipped and listed.
    Reproduce(reproduce::Args),
    /// Draw the comparison sheets and charts and write results/REPORT.md from the result CSVs.
    Report(report::Args),
    /// Print the path of the results viewer (results/site/index.html, written by `report`) and
    /// open it where a desktop browser exists.
    View(view::Args),
    /// Score encoders on maps and print CSV to stdout.
    Eval(eval::Args),
    /// Fit encoders to one map and print each fit's stored coefficients (names, units, basis)
    /// and what it was fitted on.
    Fit(fit::Args),
    /// Write the analytic scenes into envmaps/ as f32 EXR.
    GenEnvmaps(gen_envmaps::Args),
    /// Re-run experiments and compare every number with its baseline in results/ (exit 1 if
    /// anything moved).
    Check(check::Args),
    /// Re-run experiments and rewrite the baselines that differ, printing the differences.
    Bless(bless::Args),
    /// Fit the ZH3 hallucination curve f/L00 = c1 r + c2 r² (+ c3 r³) to maps and/or a probe
    /// file, and print it next to SH L1 and the paper's curve.
    FitHallucination(fit_hallucination::Args),
    /// Run the claims measurements and judge every claim of experiments/claims/*.toml: writes
    /// results/CLAIMS.csv, results/claims/<paper>.md and results/claims/measures/*.csv (a
    /// measurement whose numbers moved is not rewritten; `bless claims` does that).
    Claims(claims::Args),
    /// List the encoders.
    Encoders,
    /// Show the map search path, the maps it finds and the known maps it lacks (with where to
    /// get them); `maps import` makes 256x128 maps.
    Maps(maps::Args),
    /// Score encoders over a probe set (a file, or --synth N), in chunks and optionally sharded.
    Probes(probes::Args),
    /// Merge shard statistics written by `probes --out`.
    Merge(merge::Args),
    /// Vary one accuracy knob and record error against time (experiments/sweeps/*.toml).
    Sweep(sweep::Args),
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
    terminal::install_progress();
    let started = std::time::Instant::now();
    let profile = cli.profile.then(Profile::new);
    let env = Env {
        search: SearchPath::from_env(cli.root.join("envmaps")),
        root: cli.root,
        allow_long: cli.allow_long,
        notes: &terminal::Stderr,
        settings: RunSettings { timing: !cli.no_timing, profile: profile.as_ref(), cancel: None },
    };
    let done = match cli.command {
        Command::Run(a) => run::run(a, &env),
        Command::Reproduce(a) => reproduce::run(a, &env),
        Command::Report(a) => report::run(a, &env),
        Command::View(a) => view::run(a, &env),
        Command::Eval(a) => eval::run(a, &env),
        Command::Fit(a) => fit::run(a, &env),
        Command::GenEnvmaps(a) => gen_envmaps::run(a, &env),
        Command::Check(a) => check::run(a, &env),
        Command::Bless(a) => bless::run(a, &env),
        Command::FitHallucination(a) => fit_hallucination::run(a, &env),
        Command::Claims(a) => claims::run(a, &env),
        Command::Encoders => encoders::run(),
        Command::Maps(a) => maps::run(a, &env),
        Command::Probes(a) => probes::run(a, &env),
        Command::Merge(a) => merge::run(a, &env),
        Command::Sweep(a) => sweep::run(a, &env),
    };
    if let Some(p) = &profile {
        terminal::note(&p.report(started.elapsed().as_secs_f64()));
    }
    done
}
