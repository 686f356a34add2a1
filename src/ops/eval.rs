//! `probelab eval`: the experiment its options describe (the encoders, the domain, the
//! metric, the output resolution, the reference's polar nodes), run on maps found by name on
//! the search path or on one map in memory, as the rows of the result table
//! (`docs/tables.md`), and the two documents it prints: the CSV table and the JSON document
//! (`docs/json.md`, `probelab.eval/1`). Nothing is written and no lock is taken.

use super::context::Env;
use super::json::{self, MapEntry};
use super::source::Texels;
use crate::encoders;
use crate::pipeline::experiment::{parse_resolution, DomainKind, Effect, Experiment};
use crate::pipeline::reuse::ReferenceCache;
use crate::pipeline::runner;
use crate::pipeline::table::{self, Row};
use crate::reference::domain::{expand_orientations, parse_axis, Orientation};
use crate::reference::metrics::Metric;
use anyhow::{bail, Context, Result};

pub use crate::pipeline::table::{COLUMNS, NUMERIC_COLUMNS, TIMING_COLUMNS};
pub use crate::reference::exact::DEFAULT_POLAR_NODES;

/// The maps `eval` scores.
#[derive(Clone, Debug, PartialEq)]
pub enum EvalMaps {
    /// Names (on the search path) or file paths (`probelab eval MAPS…`).
    Named(Vec<String>),
    /// One map in memory, named by its texels' name in the rows.
    Texels(Texels),
}

/// The options of `probelab eval`: the maps, and the settings as text (the command line's
/// values).
#[derive(Clone, Debug, PartialEq)]
pub struct EvalOptions {
    /// The maps scored.
    pub maps: EvalMaps,
    /// Comma-separated encoder ids (`--encoders`).
    pub encoders: String,
    /// `sphere`, or `hemisphere:AXIS` with AXIS one of +x -x +y -y +z -z (`--domain`).
    pub domain: String,
    /// `exact` or `probulator` (`--metric`).
    pub metric: String,
    /// The output lat-long grid `WxH` (`--resolution`).
    pub resolution: String,
    /// Gauss–Legendre nodes per row piece of the reference (`--polar-nodes`).
    pub polar_nodes: usize,
}

impl Default for EvalOptions {
    /// The command line's defaults, on no maps.
    fn default() -> Self {
        EvalOptions {
            maps: EvalMaps::Named(Vec::new()),
            encoders: encoders::DEFAULT_IDS.into(),
            domain: "sphere".into(),
            metric: "exact".into(),
            resolution: "256x128".into(),
            polar_nodes: DEFAULT_POLAR_NODES,
        }
    }
}

/// What `probelab eval` computed: the rows of its table and the maps they were scored on.
pub struct Evaluated {
    /// The rows, in table order (`docs/tables.md`).
    pub rows: Vec<Row>,
    /// Each map read, with its identity.
    pub maps: Vec<MapEntry>,
}

impl Evaluated {
    /// The CSV table `eval` prints (`docs/tables.md`).
    pub fn to_csv(&self) -> Result<Vec<u8>> {
        table::to_csv(&self.rows)
    }

    /// The JSON document `eval --format json` prints (`docs/json.md`, `probelab.eval/1`).
    pub fn to_json(&self) -> Result<String> {
        json::text(&json::eval_document(&self.maps, &self.rows)?)
    }
}

/// `probelab eval`. Maps by name: every option is checked, then work estimated above the bound
/// is refused unless `env.allow_long` (`Env::refuse_long_experiments`), then every map is found
/// on `env.search` (one not found is an error naming it, why, and the folders searched) and
/// scored. A map in memory: its texels are checked first, then the options, and it is scored
/// with the same experiment. Either fails with [`crate::pipeline::settings::Cancelled`] when
/// `env.settings.cancel` was set while it ran.
pub fn eval(env: &Env, o: &EvalOptions) -> Result<Evaluated> {
    match &o.maps {
        EvalMaps::Named(maps) => {
            let exp = experiment(maps.clone(), o)?;
            env.refuse_long_experiments(std::slice::from_ref(&exp))?;
            let report = runner::run(&exp, &env.search, &env.settings, &ReferenceCache::new(env.settings.profile))?;
            if !report.missing.is_empty() {
                bail!("map(s) not found: {}", env.search.missing_maps(&report.missing, &report.missing_why));
            }
            Ok(Evaluated { rows: report.rows, maps: report.maps.iter().map(MapEntry::from_info).collect() })
        }
        EvalMaps::Texels(texels) => {
            let map = texels.open()?;
            env.settings.check_cancelled()?;
            let exp = experiment(vec![map.name().to_string()], o)?;
            let rows = runner::run_map(&exp, map.env_map(), &env.settings);
            env.settings.check_cancelled()?;
            Ok(Evaluated { rows, maps: vec![MapEntry::from_map(&texels.name, map.env_map())] })
        }
    }
}

/// The experiment `probelab eval` runs on `maps`. Every option is checked before any map is
/// read.
fn experiment(maps: Vec<String>, o: &EvalOptions) -> Result<Experiment> {
    let res = parse_resolution(&o.resolution).context("--resolution")?;
    let metric = Metric::parse(&o.metric)?;
    let (kind, orientations, effects) = domain(&o.domain)?;
    if kind == DomainKind::Hemisphere && metric == Metric::Probulator {
        bail!("--metric probulator scores the whole sphere; use --domain sphere");
    }
    if !(1..=16).contains(&o.polar_nodes) {
        bail!("--polar-nodes {}: expected 1..=16", o.polar_nodes);
    }
    let encoders = encoders::build_list(&o.encoders)?;
    if kind == DomainKind::Sphere {
        if let Some(e) = encoders.iter().find(|e| e.encoder.needs_surface_normal()) {
            bail!(
                "--encoders: {}; pass --domain hemisphere:AXIS (AXIS one of +x, -x, +y, -y, +z, -z), or run an \
                 experiment with domain = \"hemisphere\"",
                crate::encoders::encoder::surface_normal_refusal(&e.name)
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
        polar_nodes: o.polar_nodes,
        ci: false,
        summary: None,
        sheets: None,
    })
}

/// The domain's kind, orientations and effects: `sphere` or `hemisphere:AXIS`.
fn domain(domain: &str) -> Result<(DomainKind, Vec<Orientation>, Vec<Effect>)> {
    if domain == "sphere" {
        return Ok((DomainKind::Sphere, vec![], vec![]));
    }
    let Some(axis) = domain.strip_prefix("hemisphere:") else {
        bail!(
            "--domain '{}': expected sphere or hemisphere:AXIS (AXIS one of +x, -x, +y, -y, +z, -z)",
            crate::math::echo::value(domain)
        );
    };
    parse_axis(axis).with_context(|| format!("--domain {}", crate::math::echo::value(domain)))?;
    Ok((DomainKind::Hemisphere, expand_orientations(axis)?, vec![Effect::Hemisphere]))
}
