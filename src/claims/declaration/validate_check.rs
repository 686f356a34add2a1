//! Validating one `[[claim.check]]`: its table, its test and the keys that test uses (any other
//! is refused), its row filter, map sets and role.

use super::check::{CheckDecl, Source, Statistic, Test};
use super::file::CheckFile;
use super::paper::SAYS_MAX;
use crate::math::echo::value as echo;
use anyhow::{bail, Result};
use std::collections::BTreeMap;

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
    pub(super) fn validate(self, id: &str, sets: &BTreeMap<String, Vec<String>>) -> Result<CheckDecl> {
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
            // Both read only the ratios themselves: no bound, statistic or tolerance.
            "ratio_summary" | "ratio_either" => {
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
                Ok(if self.test == "ratio_summary" { Test::RatioSummary } else { Test::RatioEither })
            }
            "every_at_most" | "every_at_least" | "every_equal" | "median_at_least" => self.bound_test(at),
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
                "claim {at}: test '{t}' (expected ratio_every, ratio_some, ratio_either, ratio_stat, ratio_summary, every_at_most, every_at_least, every_equal, median_at_least or equal)",
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

    /// `every_at_most` / `every_at_least` / `every_equal` / `median_at_least`: the `bound`; no
    /// baseline.
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
            "median_at_least" => Test::MedianAtLeast { bound },
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

/// Refuses an empty `on` and a map set that is neither `all`, `scenes` nor one of `sets`.
fn check_on(on: &[String], sets: &BTreeMap<String, Vec<String>>, at: &str) -> Result<()> {
    if on.is_empty() {
        bail!("claim {at}: on = [] judges nothing");
    }
    for s in on {
        if s != "all" && s != crate::claims::population::SCENES && !sets.contains_key(s) {
            bail!("claim {at}: on names map set '{s}', which [map_sets] does not declare", s = echo(&s.to_string()));
        }
    }
    Ok(())
}
