//! The claims as data: one declaration file per paper, `experiments/claims/<paper>.toml`,
//! parsed and validated here. Every claim of the papers (`CLAIMS.md` of the paper texts) is
//! declared once, with the paper's statement and figure, the criterion fixed before the run,
//! the evidence it is judged on and the rule its checks roll up by. Judging is
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
//! | `paper_figure`    | string | the paper's own figure for it, as text |
//! | `criterion`       | string | when it counts as holding, in words that mirror the paper's, and why any band was chosen |
//! | `rollup`          | string | `all` (default): holds if every required check passes on every set it is judged on; fails if none passes on any set; otherwise partly (naming what failed). `any`: holds if some required check passes on every set. |
//! | `[[claim.check]]` | tables | the sub-checks (at least one) |
//!
//! | key (`[[claim.check]]`) | type | meaning |
//! |-------------------------|------|---------|
//! | `name`      | string | what the check shows, in a phrase |
//! | `table`     | string | the evidence: an experiment name (its `results/<name>/table.csv`) or `measure:<name>` (`results/claims/measures/<name>.csv`, written by a claims measurement) |
//! | `where`     | table  | only rows whose text columns equal these values (a value may be a list of allowed values) |
//! | `encoder`   | string | the rows judged (the `encoder` column) |
//! | `baseline`  | string | for ratio tests: the rows compared with, matched on the key columns (`map`, `domain`, `effects`, `metric`, `case` where present) |
//! | `column`    | string | the numeric column judged (default `rmse`) |
//! | `test`      | string | `ratio_every` (every matched ratio < `below`), `ratio_some` (at least one ratio < `below`), `ratio_stat` (the ratio statistic in [`min`, `max`]), `every_at_most` / `every_at_least` (every value against `bound`), `equal` (every pair agrees within `tolerance` relative to max(\|a\|, \|b\|), or within `abs_tolerance`) |
//! | `below`     | number | the ratio threshold of `ratio_every`/`ratio_some` (default 1) |
//! | `statistic` | string | `ratio_stat`: `ratio_of_means` (Σa / Σb) or `median_ratio` (median of the per-row ratios) |
//! | `min`, `max`| number | `ratio_stat`: the band (either may be omitted) |
//! | `bound`     | number | `every_at_most` / `every_at_least` |
//! | `tolerance`, `abs_tolerance` | number | `equal` (defaults 1e-9, 1e-12) |
//! | `floor`     | number | ratio tests: rows whose baseline value is below this are excluded and counted (default 0: only an exactly zero baseline) |
//! | `on`        | list   | the map sets judged: `all` and/or names of `[map_sets]` (default `["all"]`; a set absent from the table makes the check untestable on it) |
//! | `maps`      | list   | only rows of these maps (within every set) |
//! | `role`      | string | `required` (default) or `anchor`: shown, never counted (a production percentage of the paper) |

use anyhow::{bail, Context, Result};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The folder under `experiments/` that holds the declarations.
pub const DIR: &str = "claims";

/// The longest `says` phrase (the report's at-a-glance table keeps cells short).
pub const SAYS_MAX: usize = 110;

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
    /// When the claim counts as holding, in words fixed before the run (`criterion`).
    pub criterion: String,
    /// How the checks roll up into the claim's verdict (`rollup`, default `all`).
    pub rollup: Rollup,
    /// The sub-checks, at least one of them required (`[[claim.check]]`).
    pub checks: Vec<CheckDecl>,
}

/// How a claim's checks roll up into its one verdict.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rollup {
    /// `all`: holds if every required check passes on every set judged; fails if none passes
    /// on any set; otherwise partly.
    All,
    /// `any`: holds if some required check passes on every set judged.
    Any,
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
    /// `ratio_every`: every matched encoder/baseline ratio is below the threshold.
    RatioEvery {
        /// The ratio threshold (`below`, default 1).
        below: f64,
    },
    /// `ratio_some`: at least one matched encoder/baseline ratio is below the threshold.
    RatioSome {
        /// The ratio threshold (`below`, default 1).
        below: f64,
    },
    /// `ratio_stat`: a ratio statistic over the matched rows lies in [`min`, `max`].
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
        !matches!(self, Test::EveryAtMost { .. } | Test::EveryAtLeast { .. })
    }
}

/// A ratio statistic over matched rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Statistic {
    /// Σ encoder / Σ baseline.
    RatioOfMeans,
    /// The median of the per-row ratios.
    MedianRatio,
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
    /// Whether the check is an anchor (`role = "anchor"`): shown, never counted.
    pub anchor: bool,
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
    rollup: Option<String>,
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
}

/// A finite number, or the key's error.
fn finite(id: &str, key: &str, v: f64) -> Result<f64> {
    if !v.is_finite() {
        bail!("claim {id}: '{key}' must be a finite number, got {v}");
    }
    Ok(v)
}

/// A non-negative finite number, or the key's error (`at` names the claim and check).
fn non_negative(at: &str, key: &str, v: f64) -> Result<f64> {
    let v = finite(at, key, v)?;
    if v < 0.0 {
        bail!("claim {at}: '{key}' must be ≥ 0, got {v}");
    }
    Ok(v)
}

impl CheckFile {
    /// The validated check of claim `id`; `sets` are the paper's named map sets. The keys are
    /// checked in a fixed order (table, test and its keys, baseline, where, on, maps, role,
    /// floor), so the first error is the one reported.
    fn validate(self, id: &str, sets: &BTreeMap<String, Vec<String>>) -> Result<CheckDecl> {
        let at = format!("{id}, check '{}'", self.name);
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
        let anchor = match self.role.as_deref().unwrap_or("required") {
            "required" => false,
            "anchor" => true,
            r => bail!("claim {at}: role '{r}' (expected required or anchor)"),
        };
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
            anchor,
        })
    }

    /// The evidence named by `table`: an experiment, or `measure:<name>`.
    fn source(&self, at: &str) -> Result<Source> {
        Ok(match self.table.strip_prefix("measure:") {
            Some(m) if !m.is_empty() => Source::Measure(m.to_string()),
            Some(_) => bail!("claim {at}: table 'measure:' names no measurement"),
            None if self.table.is_empty() || self.table.contains(['/', '\\']) => {
                bail!("claim {at}: table '{}' must be an experiment name or measure:<name>", self.table)
            }
            None => Source::Experiment(self.table.clone()),
        })
    }

    /// Refuses the first of `keys` (name, whether present) that is present: a key the test
    /// does not use.
    fn unused(&self, at: &str, keys: &[(&str, bool)]) -> Result<()> {
        for (k, present) in keys {
            if *present {
                bail!("claim {at}: '{k}' is not used by test = \"{}\"", self.test);
            }
        }
        Ok(())
    }

    /// The criterion named by `test`, from the keys it uses; any other test key is an error.
    fn parse_test(&self, at: &str) -> Result<Test> {
        match self.test.as_str() {
            "ratio_every" | "ratio_some" => self.ratio_test(at),
            "ratio_stat" => self.ratio_stat_test(at),
            "every_at_most" | "every_at_least" => self.bound_test(at),
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
                "claim {at}: test '{t}' (expected ratio_every, ratio_some, ratio_stat, every_at_most, every_at_least or equal)"
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
        Ok(if self.test == "ratio_every" { Test::RatioEvery { below } } else { Test::RatioSome { below } })
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
            Some("ratio_of_means") => Statistic::RatioOfMeans,
            Some("median_ratio") => Statistic::MedianRatio,
            Some(s) => bail!("claim {at}: statistic '{s}' (expected ratio_of_means or median_ratio)"),
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

    /// `every_at_most` / `every_at_least`: the `bound`; no baseline.
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
        Ok(if self.test == "every_at_most" { Test::EveryAtMost { bound } } else { Test::EveryAtLeast { bound } })
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
                    other => bail!("claim {at}: where.{k}: expected strings, got {other}"),
                })
                .collect::<Result<_>>()?,
            other => bail!("claim {at}: where.{k}: expected a string or a list of strings, got {other}"),
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
            bail!("claim {at}: on names map set '{s}', which [map_sets] does not declare");
        }
    }
    Ok(())
}

/// Parses one declaration file's text; `key` is its stem, `origin` names it in errors.
pub fn parse(key: &str, text: &str, origin: &Path) -> Result<Paper> {
    let f: PaperFile =
        toml::from_str(text).with_context(|| format!("{}: not a claims declaration", origin.display()))?;
    let declared = f.measurements.is_some();
    let measurement_maps = f.measurements.map(|m| m.maps).unwrap_or_default();
    if declared && measurement_maps.is_empty() {
        bail!("{}: [measurements] maps = [] names no map", origin.display());
    }
    if let Some(m) = measurement_maps.iter().enumerate().find(|(i, m)| measurement_maps[..*i].contains(m)) {
        bail!("{}: [measurements] maps: '{}' appears twice", origin.display(), m.1);
    }
    let mut claims = Vec::new();
    for c in f.claim {
        let id = c.id.clone();
        let at = || format!("{}: claim {id}", origin.display());
        if id.is_empty() || claims.iter().any(|d: &ClaimDecl| d.id == id) {
            bail!("{}: claim id '{id}' is empty or declared twice", origin.display());
        }
        if c.says.chars().count() > SAYS_MAX {
            bail!("{}: 'says' has {} characters (at most {SAYS_MAX})", at(), c.says.chars().count());
        }
        let rollup = match c.rollup.as_deref().unwrap_or("all") {
            "all" => Rollup::All,
            "any" => Rollup::Any,
            r => bail!("{}: rollup '{r}' (expected all or any)", at()),
        };
        if c.check.is_empty() {
            bail!("{}: no [[claim.check]]: a claim is judged by at least one check", at());
        }
        let checks = c.check.into_iter().map(|k| k.validate(&id, &f.map_sets)).collect::<Result<Vec<_>>>();
        let checks = checks.with_context(at)?;
        if checks.iter().all(|k| k.anchor) {
            bail!("{}: every check is an anchor; at least one must be required", at());
        }
        claims.push(ClaimDecl {
            statement: c.statement.unwrap_or_else(|| c.says.clone()),
            id,
            says: c.says,
            paper_figure: c.paper_figure,
            criterion: c.criterion,
            rollup,
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
        papers.push(parse(&key, &text, &p)?);
    }
    let mut seen: Vec<&str> = Vec::new();
    for p in &papers {
        for c in &p.claims {
            if seen.contains(&c.id.as_str()) {
                bail!("claim id '{}' is declared by two papers", c.id);
            }
            seen.push(&c.id);
        }
    }
    papers.sort_by(|a, b| a.order.cmp(&b.order).then(a.key.cmp(&b.key)));
    Ok(papers)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper(claim: &str) -> Result<Paper> {
        let text = format!(
            "title='T'\nauthors='A'\nvenue='V'\norder=1\n[map_sets]\npaper=['m1']\n[[claim]]\nid='X1'\nsays='s'\n\
             paper_figure='p'\ncriterion='c'\n{claim}"
        );
        parse("t", &text, Path::new("t.toml"))
    }

    fn err(claim: &str) -> String {
        format!("{:#}", paper(claim).unwrap_err())
    }

    #[test]
    fn a_valid_claim_parses_with_defaults() {
        let p = paper("[[claim.check]]\nname='n'\ntable='exp'\nencoder='a'\nbaseline='b'\ntest='ratio_every'").unwrap();
        let k = &p.claims[0].checks[0];
        assert_eq!(k.test, Test::RatioEvery { below: 1.0 });
        assert_eq!(k.column, "rmse");
        assert_eq!(k.on, vec!["all".to_string()]);
        assert_eq!(k.source, Source::Experiment("exp".into()));
        assert_eq!(p.claims[0].rollup, Rollup::All);
        let m =
            paper("[[claim.check]]\nname='n'\ntable='measure:z'\nencoder='a'\ntest='every_at_most'\nbound=1").unwrap();
        assert_eq!(m.claims[0].checks[0].source.path(), Path::new("claims/measures/z.csv"));
    }

    #[test]
    fn bad_declarations_name_the_claim_and_key() {
        let base = "[[claim.check]]\nname='n'\ntable='exp'\nencoder='a'\n";
        assert!(err("").contains("no [[claim.check]]"));
        assert!(err(&format!("{base}test='ratio_every'")).contains("needs 'baseline'"));
        assert!(err(&format!("{base}baseline='b'\ntest='nope'")).contains("test 'nope'"));
        assert!(err(&format!("{base}baseline='b'\ntest='ratio_stat'\nmin=0.5")).contains("needs 'statistic'"));
        assert!(err(&format!("{base}baseline='b'\ntest='ratio_stat'\nstatistic='mean'\nmin=1"))
            .contains("statistic 'mean'"));
        assert!(err(&format!("{base}baseline='b'\ntest='ratio_stat'\nstatistic='median_ratio'"))
            .contains("needs 'min' and/or 'max'"));
        assert!(err(&format!("{base}test='every_at_most'")).contains("needs 'bound'"));
        assert!(err(&format!("{base}test='every_at_most'\nbound=nan")).contains("finite"));
        assert!(err(&format!("{base}test='every_at_most'\nbound=1\nbelow=2")).contains("'below' is not used"));
        assert!(
            err(&format!("{base}baseline='b'\ntest='ratio_every'\non=['elsewhere']")).contains("map set 'elsewhere'")
        );
        assert!(err(&format!("{base}baseline='b'\ntest='ratio_every'\nrole='maybe'")).contains("role 'maybe'"));
        assert!(
            err(&format!("{base}baseline='b'\ntest='ratio_every'\nrole='anchor'")).contains("every check is an anchor")
        );
        assert!(err(&format!("{base}baseline='b'\ntest='ratio_every'\nbogus=1")).contains("bogus"));
        assert!(err(&format!("{base}baseline='b'\ntest='ratio_every'\nfloor=-1")).contains("'floor' must be ≥ 0"));
        assert!(paper(&format!("says2='x'\n{base}")).is_err());
        let long = "x".repeat(SAYS_MAX + 1);
        let text = format!(
            "title='T'\nauthors='A'\nvenue='V'\norder=1\n[[claim]]\nid='X1'\nsays='{long}'\npaper_figure='p'\n\
             criterion='c'\n{base}test='every_at_most'\nbound=1"
        );
        assert!(format!("{:#}", parse("t", &text, Path::new("t.toml")).unwrap_err()).contains("'says' has"));
    }

    #[test]
    fn measurement_maps_keep_their_order_and_are_checked() {
        let with = |maps: &str| {
            let text = format!(
                "title='T'\nauthors='A'\nvenue='V'\norder=1\n[measurements]\n{maps}\n[[claim]]\nid='X1'\nsays='s'\n\
                 paper_figure='p'\ncriterion='c'\n[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\n\
                 test='every_at_most'\nbound=1"
            );
            parse("t", &text, Path::new("t.toml"))
        };
        assert_eq!(with("maps = ['m2', 'm1', 'm3']").unwrap().measurement_maps, ["m2", "m1", "m3"]);
        assert!(paper("[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\ntest='every_at_most'\nbound=1")
            .unwrap()
            .measurement_maps
            .is_empty());
        assert!(format!("{:#}", with("maps = []").unwrap_err()).contains("names no map"));
        assert!(format!("{:#}", with("maps = ['m1', 'm2', 'm1']").unwrap_err()).contains("'m1' appears twice"));
        assert!(with("maps = ['m1']\nsets = 2").is_err());
    }
}
