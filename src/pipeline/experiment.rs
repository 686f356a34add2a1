//! Experiment files: TOML in `experiments/` declaring maps, encoders, domain, effects and
//! metrics. An experiment is data; the runner (`runner.rs`) is the only code that executes it.
//!
//! | key            | type                      | default        | meaning |
//! |----------------|---------------------------|----------------|---------|
//! | `name`         | string                    | file stem      | results go to `results/<name>/` |
//! | `description`  | string                    | ""             | shown in the report |
//! | `maps`         | list of strings                  | required       | map names on the search path, or file paths |
//! | `encoders`     | list of strings or tables         | required       | `"sh2"` or `{ kind = "…", name = "…", <settings> }` |
//! | `metrics`      | list of strings                  | `["exact"]`    | `exact`, `probulator` |
//! | `domain`       | string                    | `"sphere"`     | `sphere` or `hemisphere` (n′ over the hemisphere about each N) |
//! | `orientations` | list of strings                  | `[]`           | surface normals N: `+x` … `-z`, `up`, `axes6`, `fibonacciN` |
//! | `effects`      | list of strings or tables         | `[]`           | `"hemisphere"`, `{ kind = "cone", cos_alpha = [..], tilt_deg = [..] }`, `{ kind = "self_bounce", albedo = [..] }` (needs `hemisphere`) |
//! | `resolution`   | [W, H]                    | `[256, 128]`   | output lat-long grid of normals for the `exact` metric |
//! | `polar_nodes`  | integer                   | 2              | Gauss–Legendre nodes per row piece of the reference |
//! | `ci`           | bool                      | true           | whether the CI check re-runs it |
//! | `summary`      | table                     | none           | `summary.csv` per orientation/map/set, ratios to `baseline` (`summary.rs`) |
//! | `sheets`       | list of strings           | every map      | the maps that get a comparison sheet in the report (each one of `maps`) |
//!
//! Unknown keys are errors that name the key and the line.

use crate::encoders::{self, NamedEncoder};
use crate::reference::domain::{expand_orientations, Orientation};
use crate::reference::exact::DEFAULT_POLAR_NODES;
use crate::reference::metrics::Metric;
use anyhow::{bail, Context, Result};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The most cases (surface normals × effect parameter combinations) one experiment may declare.
pub const MAX_CASES: usize = 1 << 20;

/// An encoder entry: a kind, or a table with a kind and settings.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
pub enum EncoderEntry {
    /// An encoder kind with its default settings, e.g. `"sh2"`.
    Kind(String),
    /// `{ kind = "…", name = "…", <settings> }`: a kind, an optional name and its settings.
    Table(toml::Table),
}

/// An effect entry.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
pub enum EffectEntry {
    /// An effect by name: `"hemisphere"` (the others need parameters).
    Name(String),
    /// `{ kind = "…", <parameters> }`: `hemisphere`, `cone` or `self_bounce` with its keys.
    Table(toml::Table),
}

/// The file as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentFile {
    /// The results folder's name (`name`); the file stem when absent.
    pub name: Option<String>,
    /// Shown in the report (`description`, default empty).
    #[serde(default)]
    pub description: String,
    /// Map names on the search path, or file paths (`maps`).
    pub maps: Vec<String>,
    /// The encoders compared (`encoders`).
    pub encoders: Vec<EncoderEntry>,
    /// Metric names (`metrics`); empty means `["exact"]`.
    #[serde(default)]
    pub metrics: Vec<String>,
    /// `sphere` or `hemisphere` (`domain`); absent means the sphere.
    #[serde(default)]
    pub domain: Option<String>,
    /// Surface normals N as written (`orientations`): `+x` … `-z`, `up`, `axes6`, `fibonacciN`.
    #[serde(default)]
    pub orientations: Vec<String>,
    /// The visibility effects (`effects`).
    #[serde(default)]
    pub effects: Vec<EffectEntry>,
    /// The `exact` metric's output lat-long grid of normals, [W, H] in pixels (`resolution`;
    /// default [256, 128]).
    pub resolution: Option<[usize; 2]>,
    /// Gauss–Legendre nodes per row piece of the reference (`polar_nodes`; default 2).
    pub polar_nodes: Option<usize>,
    /// Whether the CI check re-runs it (`ci`; default true).
    pub ci: Option<bool>,
    /// The per-orientation summary and its baseline (`[summary]`), if declared.
    pub summary: Option<crate::pipeline::summary::SummaryFile>,
    /// The maps that get a comparison sheet in the report (default: every map).
    pub sheets: Option<Vec<String>>,
}

/// A visibility effect applied to the radiance before it reaches the surface.
#[derive(Clone, Debug, PartialEq)]
pub enum Effect {
    /// Only light with ω·N > 0 counts.
    Hemisphere,
    /// Only light inside the cone of cos α about C counts, C being N tilted by `tilt_deg`
    /// towards the tangent of N's frame (the image of +X under the rotation taking +Y to N).
    Cone {
        /// The cone's half-angle cosines cos α, each in [-1, 1); one case per value.
        cos_alpha: Vec<f64>,
        /// The tilts of C from N, in degrees; one case per value (default `[0]`).
        tilt_deg: Vec<f64>,
    },
    /// Self-bounce (hemispherical-lighting talk): the surface below the horizon is an infinite
    /// Lambertian plane of albedo ρ lit by the exact I_z, so it reflects the uniform radiance
    /// ρ·I_z (E/π units) from every direction below the horizon, and the reference gains
    /// ρ·I_z·(1 − H(n′)), H(n′) = (1 + n′·N)/2 (`runner::CaseData`). One case per albedo;
    /// needs the `hemisphere` effect.
    SelfBounce {
        /// The plane's albedos ρ, each in [0, 1].
        albedo: Vec<f64>,
    },
}

/// The domain of output normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DomainKind {
    /// Every normal of the sphere.
    Sphere,
    /// The normals n′ of the hemisphere about each surface normal N.
    Hemisphere,
}

/// A validated experiment.
pub struct Experiment {
    /// The name: results go to `results/<name>/` (letters, digits, `_`, `-`).
    pub name: String,
    /// Shown in the report; may be empty.
    pub description: String,
    /// The file it was read from (`None` when built from a parsed file).
    pub source: Option<PathBuf>,
    /// The map names, each once, in the file's order.
    pub maps: Vec<String>,
    /// The encoders, built through the registry, with distinct names.
    pub encoders: Vec<NamedEncoder>,
    /// The metrics scored, in the file's order (`exact` when it names none).
    pub metrics: Vec<Metric>,
    /// The domain of output normals.
    pub domain: DomainKind,
    /// The surface normals N, expanded from the file's orientation names.
    pub orientations: Vec<Orientation>,
    /// The visibility effects, in the file's order.
    pub effects: Vec<Effect>,
    /// The `exact` metric's output grid (W, H) in pixels, W = 2H.
    pub resolution: (usize, usize),
    /// Gauss–Legendre nodes per row piece of the reference (1..=16).
    pub polar_nodes: usize,
    /// Whether the CI check re-runs it.
    pub ci: bool,
    /// `Some(baseline)` when a per-orientation summary is declared.
    pub summary: Option<Option<String>>,
    /// The maps that get a comparison sheet in the report (`sheets = [...]`; `None`: every
    /// map). Each is one of `maps`.
    pub sheets: Option<Vec<String>>,
}

impl Experiment {
    /// The maps that get a comparison sheet, in the experiment's map order.
    pub fn sheet_maps(&self) -> Vec<String> {
        match &self.sheets {
            None => self.maps.clone(),
            Some(s) => self.maps.iter().filter(|m| s.contains(m)).cloned().collect(),
        }
    }

    /// Reads and validates an experiment file; errors name the file and the line (see
    /// [`Experiment::parse`]).
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("{}: cannot read experiment file", path.display()))?;
        Self::parse(&text, path)
    }

    /// Parses and validates the text of an experiment file read from `path` (which names it in
    /// errors and gives the default name). Every error starts with `path:LINE:` when the line
    /// is known: from TOML's own span for syntax and type errors, otherwise the line where the
    /// offending value or key is written ([`find_line`]); the line itself is quoted after the
    /// message. Never panics, whatever the text.
    pub fn parse(text: &str, path: &Path) -> Result<Self> {
        let file: ExperimentFile = parse_toml(text, path)?;
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("experiment").to_string();
        let mut exp = Self::from_file(file, &stem).map_err(|e| match find_line(text, &e) {
            Some(l) => anyhow::anyhow!("{}:{l}: {:#}{}", path.display(), e, quote_line(text, l)),
            None => anyhow::anyhow!("{}: {:#}", path.display(), e),
        })?;
        exp.source = Some(path.to_path_buf());
        Ok(exp)
    }

    /// The lines of the experiment's source file where each of `values` is written as a string
    /// (e.g. map names), for errors found after loading, such as maps that are not on the
    /// search path. The file is read once and indexed, so this is linear in its size and the
    /// number of values (300,000 missing maps once took minutes: a read and a scan per map).
    pub fn source_lines(&self, values: &[String]) -> Vec<Option<usize>> {
        let Some(text) = self.source.as_ref().and_then(|p| std::fs::read_to_string(p).ok()) else {
            return vec![None; values.len()];
        };
        let literals = string_literal_lines(&text);
        values.iter().map(|v| literals.get(v.as_str()).copied().or_else(|| find_key(&text, v))).collect()
    }

    /// Validates a parsed file; `default_name` is the name when the file gives none. The
    /// checks run in the order of the file's keys, so the first error is the one reported.
    pub fn from_file(f: ExperimentFile, default_name: &str) -> Result<Self> {
        let name = check_name(f.name.unwrap_or_else(|| default_name.to_string()))?;
        check_maps(&f.maps)?;
        let built = build_encoders(f.encoders)?;
        let metrics = if f.metrics.is_empty() {
            vec![Metric::Exact]
        } else {
            f.metrics.iter().map(|m| Metric::parse(m).context("metrics")).collect::<Result<_>>()?
        };
        let domain = match f.domain.as_deref().unwrap_or("sphere") {
            "sphere" => DomainKind::Sphere,
            "hemisphere" => DomainKind::Hemisphere,
            d => bail!("domain '{d}': expected sphere or hemisphere", d = crate::math::echo::value(d)),
        };
        check_surface_encoders(domain, &built)?;
        let mut orientations = Vec::new();
        for o in &f.orientations {
            orientations.extend(expand_orientations(o).context("orientations")?);
        }
        let mut effects = Vec::new();
        for e in f.effects {
            effects.push(parse_effect(e)?);
        }
        check_cases(orientations.len(), &effects)?;
        check_normals(domain, &orientations, &effects, &metrics)?;
        let resolution = f.resolution.map(|[w, h]| (w, h)).unwrap_or((256, 128));
        if resolution.0 != 2 * resolution.1 || resolution.1 < 2 || resolution.1 > 4096 {
            bail!("resolution {:?}: expected [2H, H] with 2 <= H <= 4096", resolution);
        }
        let polar_nodes = f.polar_nodes.unwrap_or(DEFAULT_POLAR_NODES);
        if !(1..=16).contains(&polar_nodes) {
            bail!("polar_nodes {polar_nodes}: expected 1..=16");
        }
        let names: Vec<String> = built.iter().map(|e| e.name.clone()).collect();
        let summary = f.summary.map(|s| crate::pipeline::summary::summary_baseline(s, &names)).transpose()?;
        if let Some(sheets) = &f.sheets {
            check_sheets(sheets, &f.maps)?;
        }
        Ok(Experiment {
            name,
            description: f.description,
            source: None,
            maps: f.maps,
            encoders: built,
            metrics,
            domain,
            orientations,
            effects,
            resolution,
            polar_nodes,
            ci: f.ci.unwrap_or(true),
            summary,
            sheets: f.sheets,
        })
    }
}

/// The experiment's name, if it can name a folder under `results/`.
fn check_name(name: String) -> Result<String> {
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
        bail!(
            "name '{name}': use letters, digits, '_' or '-' (it names a folder under results/)",
            name = crate::math::echo::value(&name.to_string())
        );
    }
    Ok(name)
}

/// Refuses an empty map list and a map listed twice.
fn check_maps(maps: &[String]) -> Result<()> {
    if maps.is_empty() {
        bail!("maps: list at least one map");
    }
    let mut seen = std::collections::HashSet::new();
    if let Some(m) = maps.iter().find(|m| !seen.insert(m.as_str())) {
        bail!("maps: '{m}' appears twice", m = crate::math::echo::value(&m.to_string()));
    }
    Ok(())
}

/// Builds the `encoders` entries through the registry, in order; refuses an empty list and two
/// encoders of one name.
fn build_encoders(entries: Vec<EncoderEntry>) -> Result<Vec<NamedEncoder>> {
    if entries.is_empty() {
        bail!("encoders: list at least one encoder (valid: {})", encoders::known_ids());
    }
    let built = entries.into_iter().map(build_encoder).collect::<Result<Vec<_>>>()?;
    for (i, e) in built.iter().enumerate() {
        if built[..i].iter().any(|o| o.name == e.name) {
            bail!("encoders: '{}' appears twice; give variants distinct names with name = \"…\"", e.name);
        }
    }
    Ok(built)
}

/// One `encoders` entry: a kind with its default settings, or a table of `kind`, an optional
/// `name` and the encoder's settings.
fn build_encoder(e: EncoderEntry) -> Result<NamedEncoder> {
    match e {
        EncoderEntry::Kind(k) => encoders::build(&k, None, toml::Table::new()),
        EncoderEntry::Table(mut t) => {
            let kind = match t.remove("kind") {
                Some(toml::Value::String(k)) => k,
                _ => bail!("encoders: a table entry needs kind = \"<encoder>\" (valid: {})", encoders::known_ids()),
            };
            let name = match t.remove("name") {
                Some(toml::Value::String(n)) => Some(n),
                None => None,
                Some(v) => bail!("encoders: name must be a string, got {v}"),
            };
            encoders::build(&kind, name.as_deref(), t)
        }
    }
}

/// Refuses a `self_bounce` effect without the hemisphere effect or listed twice, and more than
/// [`MAX_CASES`] cases (the `n_orientations` normals, at least one, times every effect's
/// parameter combinations).
fn check_cases(n_orientations: usize, effects: &[Effect]) -> Result<()> {
    let variants = effects.iter().try_fold(n_orientations.max(1), |n: usize, e| match e {
        Effect::Hemisphere => Some(n),
        Effect::Cone { cos_alpha, tilt_deg } => n.checked_mul(cos_alpha.len())?.checked_mul(tilt_deg.len()),
        Effect::SelfBounce { albedo } => n.checked_mul(albedo.len()),
    });
    if effects.iter().any(|e| matches!(e, Effect::SelfBounce { .. })) {
        if !effects.contains(&Effect::Hemisphere) {
            bail!(
                "effects: 'self_bounce' needs the hemisphere effect (the bounce is the light of the surface \
                 below the horizon); add \"hemisphere\" to effects"
            );
        }
        if effects.iter().filter(|e| matches!(e, Effect::SelfBounce { .. })).count() > 1 {
            bail!("effects: 'self_bounce' appears twice; list every albedo in one entry");
        }
    }
    match variants {
        Some(n) if n <= MAX_CASES => Ok(()),
        _ => bail!(
            "orientations: the orientations and effect parameters make more than {MAX_CASES} cases (one per \
             normal and parameter combination); split the experiment"
        ),
    }
}

/// Surface normals are given exactly when something uses them (a hemisphere domain or an
/// effect); the `probulator` metric, which scores the whole sphere, only on the sphere domain.
fn check_normals(
    domain: DomainKind,
    orientations: &[Orientation],
    effects: &[Effect],
    metrics: &[Metric],
) -> Result<()> {
    let needs_normal = domain == DomainKind::Hemisphere || !effects.is_empty();
    if needs_normal && orientations.is_empty() {
        bail!("orientations: a hemisphere domain or an effect needs surface normals (e.g. orientations = [\"up\"])");
    }
    if !needs_normal && !orientations.is_empty() {
        bail!("orientations: only a hemisphere domain or an effect uses surface normals; remove them or set domain = \"hemisphere\"");
    }
    if domain == DomainKind::Hemisphere && metrics.contains(&Metric::Probulator) {
        bail!("metrics: 'probulator' scores the whole sphere at 256x128; it cannot be used with a hemisphere domain");
    }
    Ok(())
}

/// Refuses a `sheets` entry that is not one of the experiment's maps, or listed twice.
fn check_sheets(sheets: &[String], maps: &[String]) -> Result<()> {
    if let Some(m) = sheets.iter().find(|m| !maps.contains(m)) {
        bail!("sheets: '{m}' is not one of the experiment's maps", m = crate::math::echo::value(&m.to_string()));
    }
    let mut seen = std::collections::HashSet::new();
    if let Some(m) = sheets.iter().find(|m| !seen.insert(m.as_str())) {
        bail!("sheets: '{m}' appears twice", m = crate::math::echo::value(&m.to_string()));
    }
    Ok(())
}

/// Refuses an encoder defined only on the hemisphere about a surface normal
/// ([`crate::encoders::encoder::Encoder::needs_surface_normal`]) unless the domain
/// is `hemisphere`: on the sphere there is no N, and it must not be scored where it is not
/// defined. The error names the encoder (and, through [`Experiment::parse`], the file and line).
pub fn check_surface_encoders(domain: DomainKind, encoders: &[NamedEncoder]) -> Result<()> {
    if domain == DomainKind::Hemisphere {
        return Ok(());
    }
    if let Some(e) = encoders.iter().find(|e| e.encoder.needs_surface_normal()) {
        bail!(
            "encoders: {}; this experiment's domain is the sphere: use domain = \"hemisphere\" with orientations \
             (and the hemisphere effect), or remove it",
            crate::encoders::encoder::surface_normal_refusal(&e.name)
        );
    }
    Ok(())
}

fn parse_effect(e: EffectEntry) -> Result<Effect> {
    let floats = |t: &toml::Table, key: &str| -> Result<Vec<f64>> {
        match t.get(key) {
            None => bail!("effects: cone needs '{key}'"),
            Some(toml::Value::Float(f)) => Ok(vec![*f]),
            Some(toml::Value::Integer(i)) => Ok(vec![*i as f64]),
            Some(toml::Value::Array(a)) => a
                .iter()
                .map(|v| match v {
                    toml::Value::Float(f) => Ok(*f),
                    toml::Value::Integer(i) => Ok(*i as f64),
                    _ => bail!("effects: '{key}' must hold numbers"),
                })
                .collect(),
            Some(v) => bail!(
                "effects: '{key}' must be a number or a list, got {v}",
                v = crate::math::echo::value(&v.to_string())
            ),
        }
    };
    match e {
        EffectEntry::Name(n) if n == "hemisphere" => Ok(Effect::Hemisphere),
        EffectEntry::Name(n) if n == "self_bounce" => {
            bail!("effects: 'self_bounce' needs an albedo: {{ kind = \"self_bounce\", albedo = [0.2, 0.5, 0.8] }}")
        }
        EffectEntry::Name(n) => bail!(
            "effects: unknown effect '{n}' (valid: hemisphere, cone, self_bounce)",
            n = crate::math::echo::value(&n.to_string())
        ),
        EffectEntry::Table(t) => match t.get("kind").and_then(|v| v.as_str()) {
            Some("hemisphere") if t.len() == 1 => Ok(Effect::Hemisphere),
            Some("cone") => {
                if let Some(k) = t.keys().find(|k| !["kind", "cos_alpha", "tilt_deg"].contains(&k.as_str())) {
                    bail!(
                        "effects: cone has unknown key '{k}' (valid: cos_alpha, tilt_deg)",
                        k = crate::math::echo::value(&k.to_string())
                    );
                }
                let cos_alpha = floats(&t, "cos_alpha")?;
                if cos_alpha.iter().any(|c| !(-1.0..1.0).contains(c)) {
                    bail!("effects: cone cos_alpha must lie in [-1, 1)");
                }
                let tilt_deg = if t.contains_key("tilt_deg") { floats(&t, "tilt_deg")? } else { vec![0.0] };
                if tilt_deg.iter().any(|t| !t.is_finite()) {
                    bail!("effects: cone tilt_deg must be finite");
                }
                if cos_alpha.is_empty() || tilt_deg.is_empty() {
                    bail!("effects: cone cos_alpha and tilt_deg need at least one value each");
                }
                Ok(Effect::Cone { cos_alpha, tilt_deg })
            }
            Some("self_bounce") => {
                if let Some(k) = t.keys().find(|k| !["kind", "albedo"].contains(&k.as_str())) {
                    bail!(
                        "effects: self_bounce has unknown key '{k}' (valid: albedo)",
                        k = crate::math::echo::value(&k.to_string())
                    );
                }
                if !t.contains_key("albedo") {
                    bail!("effects: 'self_bounce' needs 'albedo' (a number or a list, each in [0, 1])");
                }
                let albedo = floats(&t, "albedo")?;
                if albedo.is_empty() {
                    bail!("effects: self_bounce 'albedo' needs at least one value");
                }
                if let Some(a) = albedo.iter().find(|a| !(0.0..=1.0).contains(*a)) {
                    bail!("effects: self_bounce 'albedo' {a} must lie in [0, 1]");
                }
                Ok(Effect::SelfBounce { albedo })
            }
            Some(k) => bail!(
                "effects: unknown effect kind '{k}' (valid: hemisphere, cone, self_bounce)",
                k = crate::math::echo::value(k)
            ),
            None => bail!("effects: a table entry needs kind = \"hemisphere\", \"cone\" or \"self_bounce\""),
        },
    }
}

/// The line of an error in the source text. The message's quoted words ('…') are tried from
/// the last (the most specific: "encoder 'sh1': unknown key(s) 'bogus'" points at `bogus`) to
/// the first, each looked up as a string literal ("w" or 'w') or as a key (`w =`). Failing
/// that, a message starting with a key ("maps: …", "resolution (…)") points at its line.
pub fn find_line(text: &str, e: &anyhow::Error) -> Option<usize> {
    let msg = format!("{e:#}");
    let quoted: Vec<&str> = msg.split('\'').skip(1).step_by(2).filter(|q| !q.is_empty()).collect();
    if let Some(l) = quoted.iter().rev().find_map(|q| find_value_or_key(text, q)) {
        return Some(l);
    }
    let key: String = msg.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
    if key.is_empty() {
        return None;
    }
    find_key(text, &key)
}

/// The first line holding `w` as a string literal, else as a key.
fn find_value_or_key(text: &str, w: &str) -> Option<usize> {
    // A value cut for the message (`math::echo`): its start, without the closing quote.
    if let Some(start) = w.strip_suffix('…') {
        let opened = [format!("\"{start}"), format!("'{start}")];
        return text.lines().position(|l| opened.iter().any(|q| l.contains(q.as_str()))).map(|i| i + 1);
    }
    let literal = [format!("\"{w}\""), format!("'{w}'")];
    text.lines()
        .position(|l| literal.iter().any(|q| l.contains(q.as_str())))
        .map(|i| i + 1)
        .or_else(|| find_key(text, w))
}

/// The first line of every string literal ("…" or '…', without escapes) in `text`.
fn string_literal_lines(text: &str) -> std::collections::HashMap<&str, usize> {
    let mut out = std::collections::HashMap::new();
    for (i, line) in text.lines().enumerate() {
        let mut rest = line;
        while let Some(start) = rest.find(['"', '\'']) {
            let quote = rest[start..].chars().next().unwrap_or('"');
            let after = &rest[start + 1..];
            let Some(len) = after.find(quote) else { break };
            out.entry(&after[..len]).or_insert(i + 1);
            rest = &after[len + 1..];
        }
    }
    out
}

/// The first line where `key` is assigned (`key =`, at the start of a line or inside an
/// inline table after `{` or `,`).
fn find_key(text: &str, key: &str) -> Option<usize> {
    text.lines()
        .position(|l| {
            l.match_indices(key).any(|(i, _)| {
                let before = l[..i].trim_end();
                let after = l[i + key.len()..].trim_start();
                (before.is_empty() || before.ends_with('{') || before.ends_with(',')) && after.starts_with('=')
            })
        })
        .map(|i| i + 1)
}

/// The deepest nesting a TOML file may have: tables (headers and dotted keys), arrays and
/// inline tables together. Deeper files are refused with their line before the parser sees them
/// (whose own limit would end in "recursion limit", or a deep stack).
pub const MAX_TOML_DEPTH: usize = 32;

/// Parses the TOML `text` of the file at `path` (an experiment, sweep, claims or report-plan
/// file): refused with `FILE:LINE:` when it nests deeper than [`MAX_TOML_DEPTH`]; a syntax or
/// type error reads `FILE:LINE:COL: message` and quotes the line (cut to 120 characters).
pub fn parse_toml<T: serde::de::DeserializeOwned>(text: &str, path: &Path) -> Result<T> {
    if let Some(line) = too_deep(text) {
        bail!(
            "{}:{line}: nested deeper than {MAX_TOML_DEPTH} levels (tables, dotted keys, arrays and inline tables \
             together); refusing to read it{}",
            path.display(),
            quote_line(text, line)
        );
    }
    toml::from_str(text).map_err(|e| {
        let at = e.span().map(|s| line_col(text, s.start));
        let msg = crate::math::echo::quoted_values(e.message().trim_end());
        match at {
            Some((line, col)) => anyhow::anyhow!("{}:{line}:{col}: {msg}{}", path.display(), quote_line(text, line)),
            None => anyhow::anyhow!("{}: {msg}", path.display()),
        }
    })
}

/// The first line where `text` nests deeper than [`MAX_TOML_DEPTH`], counting the current
/// table's header segments, open arrays and inline tables, and a key's dotted segments. Strings
/// and comments are skipped; a scan, never a parse, so it cannot itself recurse.
fn too_deep(text: &str) -> Option<usize> {
    let b = text.as_bytes();
    let (mut line, mut i) = (1usize, 0usize);
    let mut open: Vec<u8> = Vec::new(); // the open brackets: b'[' (array or header) or b'{'
    let (mut table, mut dots, mut in_key, mut header) = (0usize, 0usize, true, false);
    while i < b.len() {
        let c = b[i];
        match c {
            b'\n' => {
                line += 1;
                if open.is_empty() {
                    (dots, in_key) = (0, true);
                }
            }
            b'#' => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'"' | b'\'' => {
                i = skip_string(b, i, &mut line);
                continue;
            }
            b'[' if open.is_empty() && in_key => (header, dots, table) = (true, 0, 0),
            b'[' | b'{' => (dots, in_key) = (0, c == b'{'),
            b'.' if in_key || header => dots += 1,
            b'=' => in_key = false,
            b',' => in_key = open.last() == Some(&b'{'),
            _ => {}
        }
        if c == b'[' || c == b'{' {
            open.push(c);
        } else if c == b']' || c == b'}' {
            open.pop();
            if header && open.is_empty() && b.get(i + 1) != Some(&b']') {
                (header, table, in_key) = (false, dots + 1, true);
            }
        }
        let key = if in_key || header { dots + 1 } else { 0 };
        if table + open.len() + key > MAX_TOML_DEPTH {
            return Some(line);
        }
        i += 1;
    }
    None
}

/// The index just past the string that starts at `b[i]` (basic or literal, one line or
/// multi-line), counting the lines it spans into `line`.
fn skip_string(b: &[u8], i: usize, line: &mut usize) -> usize {
    let q = b[i];
    let multi = b[i..].starts_with(&[q, q, q]);
    let mut j = if multi { i + 3 } else { i + 1 };
    while j < b.len() {
        match b[j] {
            b'\\' if q == b'"' => j += 1,
            b'\n' if !multi => return j,
            b'\n' => *line += 1,
            c if c == q && (!multi || b[j..].starts_with(&[q, q, q])) => return j + if multi { 3 } else { 1 },
            _ => {}
        }
        j += 1;
    }
    j
}

/// 1-based line and column of byte offset `at`.
fn line_col(text: &str, at: usize) -> (usize, usize) {
    let mut at = at.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// The source line `line` (1-based), quoted for an error message.
fn quote_line(text: &str, line: usize) -> String {
    match text.lines().nth(line.wrapping_sub(1)) {
        Some(l) if !l.trim().is_empty() => format!("\n  {line} | {}", crate::math::echo::line(l.trim_end())),
        _ => String::new(),
    }
}

/// What a command that needs the experiments says where there are none.
pub const NOT_A_CHECKOUT: &str = "run inside a probelab checkout or pass `--root`";

/// Every `*.toml` in a folder, sorted by name. A folder that is not there is an error saying
/// where to run ([`NOT_A_CHECKOUT`]).
pub fn list_experiments(dir: &Path) -> Result<Vec<PathBuf>> {
    if !dir.is_dir() {
        bail!("{}: no experiments folder here: {NOT_A_CHECKOUT}", dir.display());
    }
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("{}: cannot list experiments", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    out.sort();
    Ok(out)
}

/// Finds an experiment file by path, by file stem in `<root>/experiments/` (`run
/// sh_baseline` is `experiments/sh_baseline.toml`), or by its `name`. An unknown name is an
/// error naming the nearest experiment ([`crate::math::nearest`]) and every one there; outside
/// a checkout it says where to run.
pub fn resolve(root: &Path, name: &str) -> Result<PathBuf> {
    let p = Path::new(name);
    if p.is_file() {
        return Ok(p.to_path_buf());
    }
    let dir = root.join("experiments");
    if !dir.is_dir() {
        bail!("experiment '{name}': no such file, and no experiments folder at {}: {NOT_A_CHECKOUT}", dir.display());
    }
    let by_stem = dir.join(format!("{name}.toml"));
    if by_stem.is_file() {
        return Ok(by_stem);
    }
    let all = list_experiments(&dir)?;
    let mut names = Vec::new();
    for f in &all {
        if let Ok(e) = Experiment::load(f) {
            if e.name == name {
                return Ok(f.clone());
            }
            names.push(e.name);
        }
    }
    let known: Vec<String> =
        all.iter().filter_map(|f| f.file_stem().map(|s| s.to_string_lossy().into_owned())).collect();
    let stem = p.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| name.to_string());
    let hint = match crate::math::nearest::nearest(&stem, known.iter().chain(&names)) {
        Some(n) => format!("; did you mean '{n}'?"),
        None => String::new(),
    };
    bail!(
        "experiment '{name}': no such file, and no experiment of that name in {}{hint} (known: {})",
        dir.display(),
        known.join(", ")
    )
}

/// Parses "WxH" with W = 2H.
pub fn parse_resolution(s: &str) -> Result<(usize, usize)> {
    let expected =
        || format!("resolution '{s}': expected WxH with W = 2H, e.g. 256x128", s = crate::math::echo::value(s));
    let (w, h) = s.split_once('x').with_context(expected)?;
    let (w, h): (usize, usize) = match (w.parse(), h.parse()) {
        (Ok(w), Ok(h)) => (w, h),
        _ => bail!(expected()),
    };
    if w != 2 * h || !(2..=4096).contains(&h) {
        bail!("resolution '{s}': expected W = 2H with 2 <= H <= 4096", s = crate::math::echo::value(s));
    }
    Ok((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(s: &str) -> Result<Experiment> {
        Experiment::from_file(toml::from_str(s)?, "t")
    }

    #[test]
    fn minimal_file_gets_defaults() {
        let e = parse("maps = ['a']\nencoders = ['sh1', 'sh2']").unwrap();
        assert_eq!(e.name, "t");
        assert_eq!(e.metrics, vec![Metric::Exact]);
        assert_eq!(e.resolution, (256, 128));
        assert_eq!(e.encoders.len(), 2);
    }

    #[test]
    fn errors_are_specific() {
        let e = |s: &str| format!("{:#}", parse(s).err().unwrap());
        assert!(e("maps=['a']\nencoders=['shx']").contains("valid encoders"));
        assert!(e("maps=['a']\nencoders=['sh1']\nbogus=1").contains("bogus"));
        assert!(e("maps=['a']\nencoders=['sh1']\neffects=['fog']").contains("unknown effect 'fog'"));
        assert!(e("maps=['a']\nencoders=['sh1']\ndomain='hemisphere'").contains("orientations"));
        assert!(e("maps=['a']\nencoders=['sh1','sh1']").contains("twice"));
        assert!(e("maps=['a']\nencoders=['sh1']\nmetrics=['l1']").contains("unknown metric"));
    }

    #[test]
    fn load_reports_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.toml");
        std::fs::write(&p, "maps = ['a']\nencoders = ['sh1',\n  'nope']\n").unwrap();
        let msg = format!("{:#}", Experiment::load(&p).err().unwrap());
        assert!(msg.contains("x.toml:3: ") && msg.contains("nope") && msg.contains("3 |   'nope']"), "{msg}");
        std::fs::write(&p, "maps = ['a'\nencoders = 3\n").unwrap();
        let msg = format!("{:#}", Experiment::load(&p).err().unwrap());
        assert!(msg.contains("x.toml:2:"), "{msg}");
    }

    /// Each validation error points at the line that causes it (not at an earlier line that
    /// merely contains the same word).
    #[test]
    fn errors_point_at_the_offending_line() {
        let line = |text: &str| {
            let e = Experiment::parse(text, Path::new("e.toml")).err().expect("must fail");
            let msg = format!("{e:#}");
            let l = msg.strip_prefix("e.toml:").and_then(|r| r.split(':').next()).and_then(|n| n.parse().ok());
            (l.unwrap_or(0usize), msg)
        };
        let cases: &[(&str, usize)] = &[
            // The description mentions sh: the literal 'sh' on line 3 is the culprit.
            ("description = 'sh and sh1'\nmaps = ['a']\nencoders = ['sh1', 'sh']\n", 3),
            ("maps = ['a']\nencoders = ['sh1']\neffects = ['hemisphere',\n 'fog']\norientations = ['up']\n", 4),
            ("maps = ['a']\nencoders = ['sh1']\norientations = ['up']\neffects = [{ kind = 'cone', cos_alpha = 0.5, bogus = 1 }]\n", 4),
            ("maps = ['a']\nencoders = [\n  { kind = 'sh1', bogus = 2 },\n]\n", 3),
            ("maps = ['a']\nencoders = [{ kind = 'zz9' }]\n", 2),
            ("maps = []\nencoders = ['sh1']\n", 1),
            ("maps = ['a']\nencoders = ['sh1']\nmetrics = ['exact', 'l2']\n", 3),
            ("maps = ['a']\n\nencoders = ['sh1']\nwhat = 1\n", 4),
            ("maps = ['a']\nencoders = ['sh1'\n", 2),
            ("maps = ['a']\nencoders = ['sh1']\nresolution = [100, 10]\n", 3),
            // An encoder defined only about a surface normal, on the sphere.
            ("maps = ['a']\nencoders = ['sh1',\n  'hbasis4']\n", 3),
        ];
        for (text, want) in cases {
            let (got, msg) = line(text);
            assert_eq!(got, *want, "{msg}");
        }
    }

    /// The H-basis needs N: refused on the sphere (and on a sphere with effects about N), with
    /// the encoder's name and what to do; accepted on the hemisphere domain.
    #[test]
    fn surface_encoders_need_the_hemisphere_domain() {
        let e = |s: &str| format!("{:#}", parse(s).err().expect("must fail"));
        let msg = e("maps = ['a']\nencoders = [{ kind = 'hbasis6', name = 'h6' }]\n");
        assert!(msg.contains("'h6' needs a surface normal N: it is defined only on the hemisphere"), "{msg}");
        assert!(msg.contains("domain = \"hemisphere\""), "{msg}");
        let msg = e("maps = ['a']\nencoders = ['hbasis4']\norientations = ['up']\neffects = ['hemisphere']\n");
        assert!(msg.contains("'hbasis4'"), "{msg}");
        let ok = parse("maps = ['a']\nencoders = ['hbasis4']\ndomain = 'hemisphere'\norientations = ['up']\n");
        assert!(ok.is_ok());
    }

    #[test]
    fn line_col_handles_multibyte_text() {
        assert_eq!(line_col("a\nbé c", 5), (2, 3));
        assert_eq!(line_col("é", 1), (1, 1));
        assert_eq!(line_col("", 10), (1, 1));
    }
}
