//! An experiment file as written: the TOML keys, deserialised before validation
//! ([`super::validate`]).

use serde::Deserialize;

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
