//! A claim's check as declared: its evidence table, the rows it judges, its criterion
//! ([`Test`]) and its role (primary or context).

use std::path::{Path, PathBuf};

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
    /// `median_at_least`: the median over maps of each map's median value is at least the
    /// bound (the direction on most maps, a hedge's population rule); the count of maps at or
    /// beyond the bound is shown.
    MedianAtLeast {
        /// The bound, in the judged column's units (`bound`).
        bound: f64,
    },
    /// `ratio_either`: some per-map ratio is below 1 and some is above 1 (either one wins
    /// somewhere); no threshold beyond the direction.
    RatioEither,
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
        !matches!(
            self,
            Test::EveryAtMost { .. } | Test::EveryAtLeast { .. } | Test::EveryEqual { .. } | Test::MedianAtLeast { .. }
        )
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
