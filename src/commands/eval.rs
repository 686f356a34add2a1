//! `probelab eval`: scores encoders on maps, once, and prints the table (CSV or JSON) on
//! stdout; nothing is written and no lock is taken. Exit 2 when a map is not found.

use super::context::{describe_search, Env};
use anyhow::{bail, Context, Result};
use probelab::encoders;
use probelab::io::output;
use probelab::pipeline::experiment::{DomainKind, Effect, Experiment};
use probelab::pipeline::{runner, table};
use probelab::reference::domain::{parse_axis, Orientation};
use probelab::reference::metrics::Metric;

/// `probelab eval`.
#[derive(clap::Args, Debug)]
pub struct Args {
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
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    let json = a.format == "json";
    let exp = experiment(a)?;
    let report = runner::run(&exp, &env.search)?;
    if !report.missing.is_empty() {
        let why: Vec<String> =
            report.missing.iter().zip(&report.missing_why).map(|(m, w)| format!("{m} ({w})")).collect();
        bail!("map(s) not found: {}\nSearched: {}", why.join(", "), describe_search(&env.search));
    }
    output::write(&if json { table::to_json(&report.rows)? } else { table::to_csv(&report.rows)? })?;
    Ok(0)
}

/// The domain's kind, orientations and effects: `sphere` or `hemisphere:AXIS`.
fn domain(domain: &str) -> Result<(DomainKind, Vec<Orientation>, Vec<Effect>)> {
    if domain == "sphere" {
        return Ok((DomainKind::Sphere, vec![], vec![]));
    }
    let Some(axis) = domain.strip_prefix("hemisphere:") else {
        bail!("--domain '{domain}': expected sphere or hemisphere:AXIS (AXIS one of +x, -x, +y, -y, +z, -z)");
    };
    parse_axis(axis).with_context(|| format!("--domain {domain}"))?;
    Ok((DomainKind::Hemisphere, probelab::reference::domain::expand_orientations(axis)?, vec![Effect::Hemisphere]))
}

/// The experiment `probelab eval` runs.
fn experiment(a: Args) -> Result<Experiment> {
    let res = probelab::pipeline::experiment::parse_resolution(&a.resolution).context("--resolution")?;
    let metric = Metric::parse(&a.metric)?;
    let (kind, orientations, effects) = domain(&a.domain)?;
    if kind == DomainKind::Hemisphere && metric == Metric::Probulator {
        bail!("--metric probulator scores the whole sphere; use --domain sphere");
    }
    if !(1..=16).contains(&a.polar_nodes) {
        bail!("--polar-nodes {}: expected 1..=16", a.polar_nodes);
    }
    let encoders = encoders::build_list(&a.encoders)?;
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
        maps: a.maps,
        encoders,
        metrics: vec![metric],
        domain: kind,
        orientations,
        effects,
        resolution: res,
        polar_nodes: a.polar_nodes,
        ci: false,
        summary: None,
        sheets: None,
    })
}
