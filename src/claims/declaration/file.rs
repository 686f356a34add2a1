//! A declaration file as written: the TOML keys, deserialised before validation.

use serde::Deserialize;
use std::collections::BTreeMap;

/// A declaration file: the paper and its claims.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PaperFile {
    pub(super) title: String,
    pub(super) authors: String,
    pub(super) venue: String,
    pub(super) order: i64,
    #[serde(default)]
    pub(super) map_sets: BTreeMap<String, Vec<String>>,
    pub(super) measurements: Option<MeasurementsFile>,
    #[serde(default)]
    pub(super) claim: Vec<ClaimFile>,
}

/// `[measurements]`: the maps the claims measurements run on.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeasurementsFile {
    pub(super) maps: Vec<String>,
}

/// One `[[claim]]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ClaimFile {
    pub(super) id: String,
    pub(super) says: String,
    pub(super) statement: Option<String>,
    pub(super) paper_figure: String,
    pub(super) criterion: String,
    pub(super) quote: String,
    pub(super) threshold_from: String,
    pub(super) kind: String,
    pub(super) fixed: String,
    pub(super) differs: String,
    pub(super) figure: Option<FigureField>,
    #[serde(default)]
    pub(super) check: Vec<CheckFile>,
}

/// `figure`: one figure of ours, or a list of them, beside the claim's paragraph.
#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum FigureField {
    /// `figure = { image, caption }`.
    One(FigureFile),
    /// `figure = [{ image, caption }, …]`.
    Many(Vec<FigureFile>),
}

/// One figure: a committed image under `results/`, its caption, and the sheet `claims` draws
/// as that image, if any.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FigureFile {
    pub(super) image: String,
    pub(super) caption: String,
    pub(super) sheet: Option<SheetFile>,
}

/// `sheet = { experiment, map, encoders }`: the comparison sheet of one experiment on one map,
/// cut down to these encoders.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SheetFile {
    pub(super) experiment: String,
    pub(super) map: String,
    pub(super) encoders: Vec<String>,
}

/// One `[[claim.check]]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CheckFile {
    pub(super) name: String,
    pub(super) table: String,
    #[serde(rename = "where", default)]
    pub(super) filter: BTreeMap<String, toml::Value>,
    pub(super) encoder: String,
    pub(super) baseline: Option<String>,
    pub(super) column: Option<String>,
    pub(super) test: String,
    pub(super) below: Option<f64>,
    pub(super) per_map: Option<bool>,
    pub(super) statistic: Option<String>,
    pub(super) min: Option<f64>,
    pub(super) max: Option<f64>,
    pub(super) bound: Option<f64>,
    pub(super) tolerance: Option<f64>,
    pub(super) abs_tolerance: Option<f64>,
    pub(super) floor: Option<f64>,
    pub(super) on: Option<Vec<String>>,
    pub(super) maps: Option<Vec<String>>,
    pub(super) role: Option<String>,
    pub(super) beside: Option<bool>,
}
