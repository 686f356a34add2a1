//! The claims as data: one declaration file per paper, `experiments/claims/<paper>.toml`,
//! parsed and validated here. Every claim of the papers (`CLAIMS.md` of the paper texts) is
//! declared once, with the paper's statement and figure, its evidence kind (which decides the
//! verdict words it may get), the criterion and when it was fixed, the one primary check that
//! decides the verdict and the context checks shown under it. Judging is
//! [`crate::claims::judge`]; nothing in Rust writes a verdict.
//!
//! | key (top level)  | type   | meaning |
//! |------------------|--------|---------|
//! | `title`, `authors`, `venue` | string | the paper, as cited in the report |
//! | `order`          | integer | the paper's place in the report (ZH3 talk 1, hemispherical talk 2, 2018 brief 3) |
//! | `[map_sets]`     | table of string lists | named map sets a check may be judged on besides `all` (e.g. `paper` = the five paper probes) |
//! | `[measurements]` | table  | optional: `maps` = the maps the paper's claims measurements run on, in the order of their tables' rows (non-empty, each once) |
//! | `[[claim]]`      | tables | the claims, in report order |
//!
//! | key (`[[claim]]`) | type | meaning |
//! |-------------------|------|---------|
//! | `id`              | string | the claim id of CLAIMS.md (`Z6`, `H3`, `D1`) |
//! | `says`            | string | what the paper says, in a phrase (≤ 110 characters) |
//! | `statement`       | string | the claim in full (optional; defaults to `says`) |
//! | `paper_figure`    | string | the paper's own figure for it, as text (≤ 110 characters, like `says`: the report never cuts a cell) |
//! | `kind`            | string | the evidence kind ([`Kind`]): `identity` (true by derivation or construction: `holds (identity)` or `fails`), `measured` (a general statement over maps or scenes: `holds`, `partly`, `fails`), `example` (stated for one case: `reproduced` or `not reproduced`), `anchor` (the paper's figure comes from a population we do not have: `not comparable`) |
//! | `criterion`       | string | when it counts as holding, in words that mirror the paper's, and why any band was chosen; for an `anchor`, why it is not comparable |
//! | `fixed`           | string | when the criterion was fixed: `before data`, or `after data: <reason>` |
//! | `differs`         | string | why our figure and the paper's may differ (population, metric, maps, resolution), for the page's "What we found" |
//! | `[[claim.check]]` | tables | the checks: exactly one with `role = "primary"`, which alone decides the verdict; the others are context, shown under it |
//!
//! | key (`[[claim.check]]`) | type | meaning |
//! |-------------------------|------|---------|
//! | `name`      | string | what the check shows, in a phrase |
//! | `table`     | string | the evidence: an experiment name (its `results/<name>/table.csv`) or `measure:<name>` (`results/claims/measures/<name>.csv`, written by a claims measurement) |
//! | `where`     | table  | only rows whose text columns equal these values (a value may be a list of allowed values) |
//! | `encoder`   | string | the rows judged (the `encoder` column) |
//! | `baseline`  | string | for ratio tests: the rows compared with, matched on the key columns (`map`, `domain`, `effects`, `metric`, `case` where present) |
//! | `column`    | string | the numeric column judged (default `rmse`) |
//! | `test`      | string | `ratio_every` (every matched ratio < `below`), `ratio_some` (at least one ratio < `below`), `ratio_stat` (the statistic of the per-map ratios in [`min`, `max`]), `ratio_summary` (the per-map ratios summarised, no criterion: an anchor's figure or context), `every_at_most` / `every_at_least` (every value against `bound`), `every_equal` (every value exactly `bound`), `equal` (every pair agrees within `tolerance` relative to max(\|a\|, \|b\|), or within `abs_tolerance`) |
//! | `below`     | number | the ratio threshold of `ratio_every`/`ratio_some` (default 1) |
//! | `per_map`   | bool   | `ratio_every`/`ratio_some`: judge each map's ratio (the geometric mean of its rows' ratios) instead of each row (default false) |
//! | `statistic` | string | `ratio_stat`: `median` or `geomean` of the per-map ratios (a map's ratio: the geometric mean of its rows' ratios). Never a ratio of pooled means. |
//! | `min`, `max`| number | `ratio_stat`: the band (either may be omitted) |
//! | `bound`     | number | `every_at_most` / `every_at_least` / `every_equal` |
//! | `tolerance`, `abs_tolerance` | number | `equal` (defaults 1e-9, 1e-12) |
//! | `floor`     | number | ratio tests: rows whose baseline value is below this are excluded and counted (default 0: only an exactly zero baseline) |
//! | `on`        | list   | the map sets judged: `all` and/or names of `[map_sets]` (default `["all"]`; a set absent from the table makes the check untestable on it) |
//! | `maps`      | list   | only rows of these maps (within every set) |
//! | `role`      | string | `primary` (exactly one per claim: decides the verdict) or `context` (default: shown under it, never changes it) |
//! | `beside`    | bool   | a context check whose headline stands beside the verdict in `CLAIMS.csv` and the report (e.g. a cost the verdict does not count; default false) |

use crate::math::echo::value as echo;
use anyhow::{bail, Context, Result};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The folder under `experiments/` that holds the declarations.
pub const DIR: &str = "claims";

/// The longest `says` and `paper_figure` phrases (the report's at-a-glance table never cuts a
/// cell, so its cells are short at the source).
pub const SAYS_MAX: usize = 110;

/// What kind of evidence a claim is, which decides the verdict words it may get.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// True by derivation or construction, checked numerically to rounding (by an independent
    /// path where one exists): `holds (identity)` or `fails`.
    Identity,
    /// A general statement over maps or scenes: `holds`, `partly` or `fails`, decided by the
    /// primary check.
    Measured,
    /// Stated for one case (usually the paper's figure): `reproduced` or `not reproduced`, on
    /// the paper's case or the closest we have; the rate over all maps is context.
    Example,
    /// The paper's figure comes from a population we do not have (a production set): `not
    /// comparable`; our figure stands beside theirs, with the reason. It never holds or fails.
    Anchor,
}

impl Kind {
    /// Every kind, in the order the docs list them.
    pub const ALL: [Kind; 4] = [Kind::Identity, Kind::Measured, Kind::Example, Kind::Anchor];

    /// The key's value (`identity`, `measured`, `example`, `anchor`).
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Identity => "identity",
            Kind::Measured => "measured",
            Kind::Example => "example",
            Kind::Anchor => "anchor",
        }
    }

    /// The verdict words a claim of this kind may get when its evidence is there
    /// (`untestable` is the one word any kind gets when it is not).
    pub fn verdict_words(self) -> &'static [&'static str] {
        match self {
            Kind::Identity => &["holds (identity)", "fails"],
            Kind::Measured => &["holds", "partly", "fails"],
            Kind::Example => &["reproduced", "not reproduced"],
            Kind::Anchor => &["not comparable"],
        }
    }

    /// The kind named `s`, if any.
    pub fn parse(s: &str) -> Option<Kind> {
        Kind::ALL.into_iter().find(|k| k.as_str() == s)
    }
}

/// The word of a claim whose evidence is missing, for any kind.
pub const UNTESTABLE: &str = "untestable";

/// A paper and its claims.
#[derive(Clone, Debug)]
pub struct Paper {
    /// The file stem (`zh3`, `hemi`, `brief2018`).
    pub key: String,
    /// The paper's title, as cited in the report (`title`).
    pub title: String,
    /// The paper's authors, as cited in the report (`authors`).
    pub authors: String,
    /// Where the paper appeared, as cited in the report (`venue`).
    pub venue: String,
    /// The paper's place in the report, smallest first (`order`).
    pub order: i64,
    /// Named map sets (besides `all`).
    pub map_sets: BTreeMap<String, Vec<String>>,
    /// The maps the paper's claims measurements run on, in order (`[measurements] maps`; empty
    /// when the file declares none).
    pub measurement_maps: Vec<String>,
    /// The paper's claims, in report order (`[[claim]]`).
    pub claims: Vec<ClaimDecl>,
}

/// One declared claim.
#[derive(Clone, Debug)]
pub struct ClaimDecl {
    /// The claim id of CLAIMS.md, unique within the paper (`id`, e.g. `Z6`).
    pub id: String,
    /// What the paper says, in a phrase of at most [`SAYS_MAX`] characters (`says`).
    pub says: String,
    /// The claim in full (`statement`; `says` when not given).
    pub statement: String,
    /// The paper's own figure for the claim, as text (`paper_figure`).
    pub paper_figure: String,
    /// When the claim counts as holding, in words that mirror the paper's (`criterion`).
    pub criterion: String,
    /// The evidence kind (`kind`), which decides the verdict words.
    pub kind: Kind,
    /// When the criterion was fixed (`fixed`): `before data` or `after data: <reason>`.
    pub fixed: String,
    /// Why our figure and the paper's may differ (`differs`).
    pub differs: String,
    /// The checks (`[[claim.check]]`): exactly one primary, the others context.
    pub checks: Vec<CheckDecl>,
}

impl ClaimDecl {
    /// The primary check: the one that decides the verdict.
    pub fn primary(&self) -> &CheckDecl {
        // Cannot fail: `parse` refuses a claim without exactly one primary check.
        self.checks.iter().find(|k| k.primary).expect("validated: one primary check")
    }
}

/// Where a check's rows come from.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// `results/<name>/table.csv`.
    Experiment(String),
    /// `results/claims/measures/<name>.csv`.
    Measure(String),
}

impl Source {
    /// The evidence file, relative to the results folder.
    pub fn path(&self) -> PathBuf {
        match self {
            Source::Experiment(n) => Path::new(n).join("table.csv"),
            Source::Measure(n) => Path::new("claims").join("measures").join(format!("{n}.csv")),
        }
    }
    /// As written in the declaration.
    pub fn label(&self) -> String {
        match self {
            Source::Experiment(n) => n.clone(),
            Source::Measure(n) => format!("measure:{n}"),
        }
    }
}

/// The criterion of a check.
#[derive(Clone, Debug, PartialEq)]
pub enum Test {
    /// `ratio_every`: every matched encoder/baseline ratio (per row, or per map) is below the
    /// threshold.
    RatioEvery {
        /// The ratio threshold (`below`, default 1).
        below: f64,
        /// Judge each map's ratio instead of each row's (`per_map`).
        per_map: bool,
    },
    /// `ratio_some`: at least one matched encoder/baseline ratio (per row, or per map) is
    /// below the threshold.
    RatioSome {
        /// The ratio threshold (`below`, default 1).
        below: f64,
        /// Judge each map's ratio instead of each row's (`per_map`).
        per_map: bool,
    },
    /// `ratio_summary`: the per-map ratios summarised (median, geometric mean, range); no
    /// criterion, so it neither passes nor fails.
    RatioSummary,
    /// `ratio_stat`: a statistic of the per-map ratios lies in [`min`, `max`].
    RatioStat {
        /// The statistic computed (`statistic`).
        statistic: Statistic,
        /// The band's lower end (`min`), if any.
        min: Option<f64>,
        /// The band's upper end (`max`), if any.
        max: Option<f64>,
    },
    /// `every_at_most`: every value is at most the bound.
    EveryAtMost {
        /// The bound, in the judged column's units (`bound`).
        bound: f64,
    },
    /// `every_at_least`: every value is at least the bound.
    EveryAtLeast {
        /// The bound, in the judged column's units (`bound`).
        bound: f64,
    },
    /// `every_equal`: every value is exactly the bound (a count, a size in bytes).
    EveryEqual {
        /// The value every row must have (`bound`).
        value: f64,
    },
    /// `equal`: every value agrees with its baseline's within the tolerances.
    Equal {
        /// The largest difference relative to max(|a|, |b|) (`tolerance`, default 1e-9).
        tolerance: f64,
        /// Differences up to this count as none (`abs_tolerance`, default 1e-12).
        abs_tolerance: f64,
    },
}

impl Test {
    /// Whether the test compares the encoder with a baseline.
    pub fn needs_baseline(&self) -> bool {
        !matches!(self, Test::EveryAtMost { .. } | Test::EveryAtLeast { .. } | Test::EveryEqual { .. })
    }
}

/// A statistic of the per-map ratios (a map's ratio: the geometric mean of its rows' ratios).
/// Never a ratio of pooled means, which one map with large errors dominates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Statistic {
    /// The median of the per-map ratios (`median`).
    Median,
    /// The geometric mean of the per-map ratios (`geomean`).
    GeoMean,
}

impl Statistic {
    /// The statistic named in words, as every figure names it.
    pub fn words(self) -> &'static str {
        match self {
            Statistic::Median => "median of per-map ratios",
            Statistic::GeoMean => "geometric mean of per-map ratios",
        }
    }
}

/// One sub-check.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckDecl {
    /// What the check shows, in a phrase (`name`).
    pub name: String,
    /// The evidence table (`table`: an experiment name or `measure:<name>`).
    pub source: Source,
    /// Only rows whose text column equals one of the values (`where`), as (column, values).
    pub filter: Vec<(String, Vec<String>)>,
    /// The rows judged: their `encoder` column's value (`encoder`).
    pub encoder: String,
    /// The rows compared with in baseline tests, matched on the key columns (`baseline`).
    pub baseline: Option<String>,
    /// The numeric column judged (`column`, default `rmse`).
    pub column: String,
    /// The criterion (`test` with its keys).
    pub test: Test,
    /// Ratio tests leave out and count rows whose baseline value is at or below this (`floor`,
    /// default 0).
    pub floor: f64,
    /// The map sets judged: `all` or names of `[map_sets]` (`on`, default `["all"]`).
    pub on: Vec<String>,
    /// Only rows of these maps, within every set (`maps`); `None`: every map.
    pub maps: Option<Vec<String>>,
    /// Whether the check is the claim's primary one (`role = "primary"`): it alone decides
    /// the verdict; the others are context.
    pub primary: bool,
    /// A context check whose headline stands beside the verdict (`beside`).
    pub beside: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PaperFile {
    title: String,
    authors: String,
    venue: String,
    order: i64,
    #[serde(default)]
    map_sets: BTreeMap<String, Vec<String>>,
    measurements: Option<MeasurementsFile>,
    #[serde(default)]
    claim: Vec<ClaimFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeasurementsFile {
    maps: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ClaimFile {
    id: String,
    says: String,
    statement: Option<String>,
    paper_figure: String,
    criterion: String,
    kind: String,
    fixed: String,
    differs: String,
    #[serde(default)]
    check: Vec<CheckFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CheckFile {
    name: String,
    table: String,
    #[serde(rename = "where", default)]
    filter: BTreeMap<String, toml::Value>,
    encoder: String,
    baseline: Option<String>,
    column: Option<String>,
    test: String,
    below: Option<f64>,
    per_map: Option<bool>,
    statistic: Option<String>,
    min: Option<f64>,
    max: Option<f64>,
    bound: Option<f64>,
    tolerance: Option<f64>,
    abs_tolerance: Option<f64>,
    floor: Option<f64>,
    on: Option<Vec<String>>,
    maps: Option<Vec<String>>,
    role: Option<String>,
    beside: Option<bool>,
}

/// A finite number, or the key's error.
fn finite(id: &str, key: &str, v: f64) -> Result<f64> {
    if !v.is_finite() {
        bail!("claim {id}: '{key}' must be a finite number, got {v}", v = echo(&v.to_string()));
    }
    Ok(v)
}

/// A non-negative finite number, or the key's error (`at` names the claim and check).
fn non_negative(at: &str, key: &str, v: f64) -> Result<f64> {
    let v = finite(at, key, v)?;
    if v < 0.0 {
        bail!("claim {at}: '{key}' must be ≥ 0, got {v}", v = echo(&v.to_string()));
    }
    Ok(v)
}

impl CheckFile {
    /// The validated check of claim `id`; `sets` are the paper's named map sets. The keys are
    /// checked in a fixed order (table, test and its keys, baseline, where, on, maps, role,
    /// floor), so the first error is the one reported.
    fn validate(self, id: &str, sets: &BTreeMap<String, Vec<String>>) -> Result<CheckDecl> {
        let at = format!("{}, check '{}'", echo(id), echo(&self.name));
        if self.name.chars().count() > SAYS_MAX {
            bail!("claim {at}: 'name' has {} characters (at most {SAYS_MAX})", self.name.chars().count());
        }
        let source = self.source(&at)?;
        let test = self.parse_test(&at)?;
        if test.needs_baseline() && self.baseline.is_none() {
            bail!("claim {at}: test = \"{}\" needs 'baseline'", self.test);
        }
        let filter = row_filter(self.filter, &at)?;
        let on = self.on.unwrap_or_else(|| vec!["all".to_string()]);
        check_on(&on, sets, &at)?;
        if self.maps.as_ref().is_some_and(|m| m.is_empty()) {
            bail!("claim {at}: maps = [] matches no row");
        }
        let primary = match self.role.as_deref().unwrap_or("context") {
            "primary" => true,
            "context" => false,
            r => bail!("claim {at}: role '{r}' (expected primary or context)", r = echo(r)),
        };
        let beside = self.beside.unwrap_or(false);
        if beside && primary {
            bail!("claim {at}: 'beside' is for a context check (the primary's figure is the claim's own)");
        }
        if self.per_map.is_some() && !matches!(self.test.as_str(), "ratio_every" | "ratio_some") {
            bail!("claim {at}: 'per_map' is not used by test = \"{}\"", self.test);
        }
        Ok(CheckDecl {
            name: self.name,
            source,
            filter,
            encoder: self.encoder,
            baseline: self.baseline,
            column: self.column.unwrap_or_else(|| "rmse".into()),
            test,
            floor: non_negative(&at, "floor", self.floor.unwrap_or(0.0))?,
            on,
            maps: self.maps,
            primary,
            beside,
        })
    }

    /// The evidence named by `table`: an experiment, or `measure:<name>`.
    fn source(&self, at: &str) -> Result<Source> {
        let name = self.table.strip_prefix("measure:").unwrap_or(&self.table);
        // The name is joined under results/ or results/claims/measures/: it must stay there.
        if let Err(e) = crate::io::name::check(name) {
            bail!("claim {at}: key 'table': {e} (an experiment name or measure:<name>)");
        }
        Ok(match self.table.strip_prefix("measure:") {
            Some(m) => Source::Measure(m.to_string()),
            None => Source::Experiment(self.table.clone()),
        })
    }

    /// Refuses the first of `keys` (name, whether present) that is present: a key the test
    /// does not use.
    fn unused(&self, at: &str, keys: &[(&str, bool)]) -> Result<()> {
        for (k, present) in keys {
            if *present {
                bail!("claim {at}: '{k}' is not used by test = \"{}\"", self.test, k = echo(k));
            }
        }
        Ok(())
    }

    /// The criterion named by `test`, from the keys it uses; any other test key is an error.
    fn parse_test(&self, at: &str) -> Result<Test> {
        match self.test.as_str() {
            "ratio_every" | "ratio_some" => self.ratio_test(at),
            "ratio_stat" => self.ratio_stat_test(at),
            "ratio_summary" => {
                self.unused(
                    at,
                    &[
                        ("below", self.below.is_some()),
                        ("statistic", self.statistic.is_some()),
                        ("min", self.min.is_some()),
                        ("max", self.max.is_some()),
                        ("bound", self.bound.is_some()),
                        ("tolerance", self.tolerance.is_some()),
                        ("abs_tolerance", self.abs_tolerance.is_some()),
                    ],
                )?;
                Ok(Test::RatioSummary)
            }
            "every_at_most" | "every_at_least" | "every_equal" => self.bound_test(at),
            "equal" => {
                self.unused(
                    at,
                    &[
                        ("below", self.below.is_some()),
                        ("statistic", self.statistic.is_some()),
                        ("min", self.min.is_some()),
                        ("max", self.max.is_some()),
                        ("bound", self.bound.is_some()),
                        ("floor", self.floor.is_some()),
                    ],
                )?;
                Ok(Test::Equal {
                    tolerance: non_negative(at, "tolerance", self.tolerance.unwrap_or(1e-9))?,
                    abs_tolerance: non_negative(at, "abs_tolerance", self.abs_tolerance.unwrap_or(1e-12))?,
                })
            }
            t => bail!(
                "claim {at}: test '{t}' (expected ratio_every, ratio_some, ratio_stat, ratio_summary, every_at_most, every_at_least, every_equal or equal)",
                t = echo(t)
            ),
        }
    }

    /// `ratio_every` / `ratio_some`: the threshold `below` (default 1).
    fn ratio_test(&self, at: &str) -> Result<Test> {
        self.unused(
            at,
            &[
                ("statistic", self.statistic.is_some()),
                ("min", self.min.is_some()),
                ("max", self.max.is_some()),
                ("bound", self.bound.is_some()),
                ("tolerance", self.tolerance.is_some()),
                ("abs_tolerance", self.abs_tolerance.is_some()),
            ],
        )?;
        let below = non_negative(at, "below", self.below.unwrap_or(1.0))?;
        let per_map = self.per_map.unwrap_or(false);
        Ok(if self.test == "ratio_every" {
            Test::RatioEvery { below, per_map }
        } else {
            Test::RatioSome { below, per_map }
        })
    }

    /// `ratio_stat`: the `statistic` and its band [`min`, `max`] (at least one of them).
    fn ratio_stat_test(&self, at: &str) -> Result<Test> {
        self.unused(
            at,
            &[
                ("below", self.below.is_some()),
                ("bound", self.bound.is_some()),
                ("tolerance", self.tolerance.is_some()),
                ("abs_tolerance", self.abs_tolerance.is_some()),
            ],
        )?;
        let statistic = match self.statistic.as_deref() {
            Some("median") => Statistic::Median,
            Some("geomean") => Statistic::GeoMean,
            Some(s) => bail!(
                "claim {at}: statistic '{s}' (expected median or geomean of the per-map ratios; a ratio of pooled \
                 means is not offered: one map with large errors dominates it)",
                s = echo(s)
            ),
            None => bail!("claim {at}: test = \"ratio_stat\" needs 'statistic'"),
        };
        let min = self.min.map(|v| non_negative(at, "min", v)).transpose()?;
        let max = self.max.map(|v| non_negative(at, "max", v)).transpose()?;
        if min.is_none() && max.is_none() {
            bail!("claim {at}: test = \"ratio_stat\" needs 'min' and/or 'max'");
        }
        if let (Some(a), Some(b)) = (min, max) {
            if a > b {
                bail!("claim {at}: min {a} > max {b}");
            }
        }
        Ok(Test::RatioStat { statistic, min, max })
    }

    /// `every_at_most` / `every_at_least` / `every_equal`: the `bound`; no baseline.
    fn bound_test(&self, at: &str) -> Result<Test> {
        self.unused(
            at,
            &[
                ("below", self.below.is_some()),
                ("statistic", self.statistic.is_some()),
                ("min", self.min.is_some()),
                ("max", self.max.is_some()),
                ("tolerance", self.tolerance.is_some()),
                ("abs_tolerance", self.abs_tolerance.is_some()),
                ("baseline", self.baseline.is_some()),
                ("floor", self.floor.is_some()),
            ],
        )?;
        let Some(b) = self.bound else { bail!("claim {at}: test = \"{}\" needs 'bound'", self.test) };
        let bound = finite(at, "bound", b)?;
        Ok(match self.test.as_str() {
            "every_at_most" => Test::EveryAtMost { bound },
            "every_at_least" => Test::EveryAtLeast { bound },
            _ => Test::EveryEqual { value: bound },
        })
    }
}

/// The `where` table as (column, allowed values): a string, or a list of strings.
fn row_filter(filter: BTreeMap<String, toml::Value>, at: &str) -> Result<Vec<(String, Vec<String>)>> {
    let mut out = Vec::new();
    for (k, v) in filter {
        let values = match v {
            toml::Value::String(s) => vec![s],
            toml::Value::Array(a) => a
                .into_iter()
                .map(|x| match x {
                    toml::Value::String(s) => Ok(s),
                    other => {
                        bail!("claim {at}: where.{}: expected strings, got {}", echo(&k), echo(&other.to_string()))
                    }
                })
                .collect::<Result<_>>()?,
            other => bail!(
                "claim {at}: where.{}: expected a string or a list of strings, got {}",
                echo(&k),
                echo(&other.to_string())
            ),
        };
        out.push((k, values));
    }
    Ok(out)
}

/// Refuses an empty `on` and a map set that is neither `all` nor one of `sets`.
fn check_on(on: &[String], sets: &BTreeMap<String, Vec<String>>, at: &str) -> Result<()> {
    if on.is_empty() {
        bail!("claim {at}: on = [] judges nothing");
    }
    for s in on {
        if s != "all" && !sets.contains_key(s) {
            bail!("claim {at}: on names map set '{s}', which [map_sets] does not declare", s = echo(&s.to_string()));
        }
    }
    Ok(())
}

/// Refuses a `fixed` that is neither `before data` nor `after data: <reason>`.
fn check_fixed(fixed: &str) -> Result<()> {
    match fixed.strip_prefix("after data:") {
        _ if fixed == "before data" => Ok(()),
        Some(reason) if !reason.trim().is_empty() => Ok(()),
        _ => bail!("fixed '{fixed}' (expected \"before data\" or \"after data: <reason>\")", fixed = echo(fixed)),
    }
}

/// Refuses a claim without exactly one primary check, and a primary whose test does not fit
/// the kind: an anchor's primary only summarises (`ratio_summary`: it never holds or fails);
/// every other kind's primary has a criterion.
fn check_primary(kind: Kind, checks: &[CheckDecl]) -> Result<()> {
    let primaries: Vec<&CheckDecl> = checks.iter().filter(|k| k.primary).collect();
    let [p] = primaries.as_slice() else {
        bail!("{} checks have role = \"primary\" (exactly one decides the verdict)", primaries.len())
    };
    let summary = matches!(p.test, Test::RatioSummary);
    if kind == Kind::Anchor && !summary {
        bail!(
            "an anchor's primary check is test = \"ratio_summary\": an anchor is not comparable, never held or failed"
        );
    }
    if kind != Kind::Anchor && summary {
        bail!(
            "the primary check of a{} {} claim needs a criterion (ratio_summary has none)",
            if kind == Kind::Identity { "n" } else { "" },
            kind.as_str()
        );
    }
    Ok(())
}

/// Refuses a `table` whose name is not a plain identifier (`io::name`), as `FILE:LINE: key
/// 'table': …` at the first line of `text` that sets `table` to it.
fn table_name(table: &str, text: &str, origin: &Path) -> Result<()> {
    let Err(e) = crate::io::name::check(table.strip_prefix("measure:").unwrap_or(table)) else {
        return Ok(());
    };
    let line = text.lines().position(|l| {
        let l = l.trim_start();
        l.strip_prefix("table").is_some_and(|rest| {
            rest.trim_start().starts_with('=')
                && toml::from_str::<toml::Table>(l).ok().and_then(|t| t.get("table")?.as_str().map(|v| v == table))
                    == Some(true)
        })
    });
    match line {
        Some(n) => bail!("{}:{}: key 'table': {e}", origin.display(), n + 1),
        None => bail!("{}: key 'table': {e}", origin.display()),
    }
}

/// Parses one declaration file's text; `key` is its stem, `origin` names it in errors.
pub fn parse(key: &str, text: &str, origin: &Path) -> Result<Paper> {
    let f: PaperFile = crate::pipeline::experiment::parse_toml(text, origin)
        .map_err(|e| anyhow::anyhow!("{e:#} (not a claims declaration)"))?;
    let declared = f.measurements.is_some();
    let measurement_maps = f.measurements.map(|m| m.maps).unwrap_or_default();
    if declared && measurement_maps.is_empty() {
        bail!("{}: [measurements] maps = [] names no map", origin.display());
    }
    if let Some(m) = measurement_maps.iter().enumerate().find(|(i, m)| measurement_maps[..*i].contains(m)) {
        bail!("{}: [measurements] maps: '{}' appears twice", origin.display(), echo(m.1));
    }
    let mut claims = Vec::new();
    for c in f.claim {
        let id = c.id.clone();
        let shown = echo(&id);
        let at = || format!("{}: claim {shown}", origin.display());
        if id.is_empty() || claims.iter().any(|d: &ClaimDecl| d.id == id) {
            bail!("{}: claim id '{shown}' is empty or declared twice", origin.display());
        }
        if c.says.chars().count() > SAYS_MAX {
            bail!("{}: 'says' has {} characters (at most {SAYS_MAX})", at(), c.says.chars().count());
        }
        if c.paper_figure.chars().count() > SAYS_MAX {
            bail!("{}: 'paper_figure' has {} characters (at most {SAYS_MAX})", at(), c.paper_figure.chars().count());
        }
        let Some(kind) = Kind::parse(&c.kind) else {
            bail!("{}: kind '{}' (expected identity, measured, example or anchor)", at(), echo(&c.kind))
        };
        check_fixed(&c.fixed).with_context(at)?;
        if c.differs.trim().is_empty() {
            bail!("{}: 'differs' is empty: say why our figure and the paper's may differ", at());
        }
        if c.check.is_empty() {
            bail!("{}: no [[claim.check]]: a claim is judged by its primary check", at());
        }
        for k in &c.check {
            table_name(&k.table, text, origin)?;
        }
        let checks = c.check.into_iter().map(|k| k.validate(&id, &f.map_sets)).collect::<Result<Vec<_>>>();
        let checks = checks.with_context(at)?;
        check_primary(kind, &checks).with_context(at)?;
        claims.push(ClaimDecl {
            statement: c.statement.unwrap_or_else(|| c.says.clone()),
            id,
            says: c.says,
            paper_figure: c.paper_figure,
            criterion: c.criterion,
            kind,
            fixed: c.fixed,
            differs: c.differs,
            checks,
        });
    }
    Ok(Paper {
        key: key.to_string(),
        title: f.title,
        authors: f.authors,
        venue: f.venue,
        order: f.order,
        map_sets: f.map_sets,
        measurement_maps,
        claims,
    })
}

/// Every declaration file in `experiments_dir/claims/`, in report order (by `order`, then
/// key). Claim ids are unique across papers. A repository without the folder declares no
/// claims.
pub fn load_papers(experiments_dir: &Path) -> Result<Vec<Paper>> {
    let dir = experiments_dir.join(DIR);
    if !dir.exists() {
        return Ok(Vec::new());
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .with_context(|| format!("{}: cannot list the claims declarations", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    let mut papers = Vec::new();
    for p in files {
        let text = std::fs::read_to_string(&p).with_context(|| format!("{}: cannot read", p.display()))?;
        let key = p.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        // The stem names results/claims/<key>.md: a plain identifier.
        if let Err(e) = crate::io::name::check(&key) {
            bail!("{}: the claims file's name {e}", p.display());
        }
        papers.push(parse(&key, &text, &p)?);
    }
    let mut seen: Vec<&str> = Vec::new();
    for p in &papers {
        for c in &p.claims {
            if seen.contains(&c.id.as_str()) {
                bail!("claim id '{}' is declared by two papers", echo(&c.id));
            }
            seen.push(&c.id);
        }
    }
    papers.sort_by(|a, b| a.order.cmp(&b.order).then(a.key.cmp(&b.key)));
    Ok(papers)
}

#[cfg(test)]
mod tests;
