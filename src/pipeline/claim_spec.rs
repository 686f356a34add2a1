//! A declared claim: the `[[claims]]` tables of an experiment file and their validation into a
//! [`ClaimSpec`] against the experiment's encoders and maps. Only the declaration lives here, in
//! the pipeline layer beside the experiment file that carries it; judging a claim on a table's
//! rows (and writing `claims.csv` and `CLAIMS.md`) is the claims layer's
//! ([`crate::claims::declared`]).
//!
//! | key (`[[claims]]`)     | type   | meaning |
//! |------------------------|--------|---------|
//! | `id`                   | string | claim id (e.g. `H8.hlsh`) |
//! | `claim`, `paper`       | string | the claim and the paper's figure for it, as text |
//! | `check`                | string | `ratio` (encoder / baseline on matched rows), `equal` (two encoders agree), `at_most` / `at_least` (the encoder's column against an absolute `bound`) |
//! | `encoder`, `baseline`  | string | the encoder names compared (`equal`: `encoder` vs `baseline`); `at_most`/`at_least` take no `baseline` |
//! | `column`               | string | `rmse` (default), `rel_rmse`, `max_abs_err`, `at_normal_abs_err` |
//! | `threshold`            | number | `ratio`: a row passes if ratio < threshold (default 1) |
//! | `statistic`            | string | `ratio`: `every` (default; holds yes/partly/no by rows) or `mean` (mean ratio < threshold) |
//! | `tolerance`            | number | `equal`: largest difference allowed relative to max(\|a\|, \|b\|, reference RMS) (default 1e-9) |
//! | `abs_tolerance`        | number | `equal`: a difference this small passes regardless (default 1e-12; for errors at rounding level) |
//! | `bound`                | number | `at_most`: a row passes if column ≤ bound; `at_least`: if column ≥ bound (required, finite, ≥ 0) |
//! | `effects`              | string | only rows with exactly this effects label |
//! | `maps`                 | \[string\] | only rows of these maps (each one of the experiment's `maps`, by name or file stem) |
//! | `note`                 | string | shown under the claims table |

use crate::pipeline::table::Row;
use anyhow::{bail, Result};
use serde::Deserialize;
use std::path::Path;

/// `[[claims]]` as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClaimFile {
    pub id: String,
    pub claim: String,
    #[serde(default)]
    pub paper: String,
    pub check: String,
    pub encoder: String,
    pub baseline: Option<String>,
    pub column: Option<String>,
    pub threshold: Option<f64>,
    pub statistic: Option<String>,
    pub tolerance: Option<f64>,
    pub abs_tolerance: Option<f64>,
    pub bound: Option<f64>,
    pub effects: Option<String>,
    pub maps: Option<Vec<String>>,
    pub note: Option<String>,
}

/// A numeric column of the table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Column {
    Rmse,
    RelRmse,
    MaxAbsErr,
    AtNormalAbsErr,
}

impl Column {
    /// The column a `column` key names.
    pub fn parse(s: &str) -> Result<Self> {
        Ok(match s {
            "rmse" => Column::Rmse,
            "rel_rmse" => Column::RelRmse,
            "max_abs_err" => Column::MaxAbsErr,
            "at_normal_abs_err" => Column::AtNormalAbsErr,
            _ => bail!("column '{s}': expected rmse, rel_rmse, max_abs_err or at_normal_abs_err"),
        })
    }
    /// The name of the column, as written in experiment files and in `table.csv`.
    pub fn name(&self) -> &'static str {
        match self {
            Column::Rmse => "rmse",
            Column::RelRmse => "rel_rmse",
            Column::MaxAbsErr => "max_abs_err",
            Column::AtNormalAbsErr => "at_normal_abs_err",
        }
    }
    /// The column's value on a row (`None` where the row has none).
    pub fn get(&self, r: &Row) -> Option<f64> {
        match self {
            Column::Rmse => Some(r.scores.rmse),
            Column::RelRmse => Some(r.scores.rel_rmse),
            Column::MaxAbsErr => Some(r.scores.max_abs),
            Column::AtNormalAbsErr => r.at_normal_abs_err,
        }
    }
}

/// How a claim is checked.
#[derive(Clone, Debug, PartialEq)]
pub enum Check {
    /// ratio = column(encoder) / column(baseline) per matched row; passes where < threshold.
    Ratio { threshold: f64, every: bool },
    /// column(encoder) and column(baseline) agree on every row: |a − b| ≤ tolerance ·
    /// max(|a|, |b|, RMS of the reference), or |a − b| ≤ abs_tolerance.
    Equal { tolerance: f64, abs_tolerance: f64 },
    /// column(encoder) ≤ bound on every matched row (no baseline).
    AtMost { bound: f64 },
    /// column(encoder) ≥ bound on every matched row (no baseline).
    AtLeast { bound: f64 },
}

/// A validated claim: what `[[claims]]` declares, ready to be judged on a table's rows
/// ([`crate::claims::declared::check`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ClaimSpec {
    pub id: String,
    pub claim: String,
    pub paper: String,
    pub check: Check,
    pub encoder: String,
    /// The encoder compared with (`ratio`, `equal`); empty for `at_most`/`at_least`.
    pub baseline: String,
    pub column: Column,
    pub effects: Option<String>,
    /// Only rows of these maps (table names: file stems); `None`: every map.
    pub maps: Option<Vec<String>>,
    pub note: Option<String>,
}

/// The name a map entry of an experiment gets in tables: its file stem (entries may be paths).
fn table_map_name(entry: &str) -> String {
    Path::new(entry).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| entry.to_string())
}

impl ClaimSpec {
    /// Validates a claim against the experiment's encoder names and map entries.
    pub fn from_file(f: ClaimFile, encoders: &[String], maps: &[String]) -> Result<Self> {
        let bounded = matches!(f.check.as_str(), "at_most" | "at_least");
        let baseline = match (&f.baseline, bounded) {
            (Some(_), true) => {
                bail!(
                    "claims: '{}': 'baseline' is not used by check = \"{}\" (it compares with 'bound')",
                    f.id,
                    f.check
                )
            }
            (None, true) => String::new(),
            (Some(b), false) => b.clone(),
            (None, false) => bail!("claims: '{}': check = \"{}\" needs 'baseline'", f.id, f.check),
        };
        for e in std::iter::once(&f.encoder).chain((!bounded).then_some(&baseline)) {
            if !encoders.contains(e) {
                bail!("claims: '{}' names encoder '{e}', which the experiment does not list", f.id);
            }
        }
        if !bounded && f.bound.is_some() {
            bail!("claims: '{}': 'bound' is for check = \"at_most\" or \"at_least\"", f.id);
        }
        let maps_filter = match f.maps {
            None => None,
            Some(list) => {
                if list.is_empty() {
                    bail!("claims: '{}': maps = [] matches no row; list at least one map or drop the key", f.id);
                }
                let mut names = Vec::new();
                for m in &list {
                    let name = table_map_name(m);
                    if !maps.iter().any(|e| e == m || table_map_name(e) == name) {
                        bail!("claims: '{}': maps names '{m}', which is not one of the experiment's maps", f.id);
                    }
                    if !names.contains(&name) {
                        names.push(name);
                    }
                }
                Some(names)
            }
        };
        let column = Column::parse(f.column.as_deref().unwrap_or("rmse"))?;
        let check = match f.check.as_str() {
            "at_most" | "at_least" => {
                if f.threshold.is_some() || f.statistic.is_some() || f.tolerance.is_some() || f.abs_tolerance.is_some()
                {
                    bail!(
                        "claims: '{}': check = \"{}\" takes 'bound' only ('threshold', 'statistic', 'tolerance' and \
                         'abs_tolerance' are for ratio/equal)",
                        f.id,
                        f.check
                    );
                }
                let Some(bound) = f.bound else {
                    bail!("claims: '{}': check = \"{}\" needs 'bound' (a number)", f.id, f.check)
                };
                if !(bound.is_finite() && bound >= 0.0) {
                    bail!("claims: '{}': bound must be a finite non-negative number, got {bound}", f.id);
                }
                if f.check == "at_most" {
                    Check::AtMost { bound }
                } else {
                    Check::AtLeast { bound }
                }
            }
            "ratio" => {
                if f.tolerance.is_some() || f.abs_tolerance.is_some() {
                    bail!("claims: '{}': 'tolerance'/'abs_tolerance' are for check = \"equal\"", f.id);
                }
                let threshold = f.threshold.unwrap_or(1.0);
                if !(threshold.is_finite() && threshold > 0.0) {
                    bail!("claims: '{}': threshold must be a positive number", f.id);
                }
                let every = match f.statistic.as_deref().unwrap_or("every") {
                    "every" => true,
                    "mean" => false,
                    s => bail!("claims: '{}': statistic '{s}' (expected every or mean)", f.id),
                };
                Check::Ratio { threshold, every }
            }
            "equal" => {
                if f.threshold.is_some() || f.statistic.is_some() {
                    bail!("claims: '{}': 'threshold'/'statistic' are for check = \"ratio\"", f.id);
                }
                let tolerance = f.tolerance.unwrap_or(1e-9);
                let abs_tolerance = f.abs_tolerance.unwrap_or(1e-12);
                if !(tolerance.is_finite() && tolerance >= 0.0 && abs_tolerance.is_finite() && abs_tolerance >= 0.0) {
                    bail!("claims: '{}': tolerance and abs_tolerance must be non-negative numbers", f.id);
                }
                Check::Equal { tolerance, abs_tolerance }
            }
            c => bail!("claims: '{}': check '{c}' (expected ratio, equal, at_most or at_least)", f.id),
        };
        Ok(ClaimSpec {
            id: f.id,
            claim: f.claim,
            paper: f.paper,
            check,
            encoder: f.encoder,
            baseline,
            column,
            effects: f.effects,
            maps: maps_filter,
            note: f.note,
        })
    }
}

impl ClaimSpec {
    /// Whether a row of the claim's encoder passes its effects and maps filters.
    pub fn selects(&self, r: &Row) -> bool {
        r.encoder == self.encoder
            && self.effects.as_deref().is_none_or(|e| r.effects == e)
            && self.maps.as_ref().is_none_or(|m| m.contains(&r.map))
    }
}

/// Claims the summary and claims tests share, declared over the encoders `op` and `base` and
/// the maps of [`maps`].
#[cfg(test)]
pub(crate) mod fixtures {
    use super::*;

    /// The experiment's map entries: one by name, one by path (its table name is `m2`).
    pub fn maps() -> Vec<String> {
        vec!["m1".into(), "dir/m2.exr".into()]
    }

    /// A claim of `op` against `base`.
    pub fn claim(check: &str, extra: &str) -> ClaimSpec {
        let f: ClaimFile =
            toml::from_str(&format!("id='c'\nclaim='x'\ncheck='{check}'\nencoder='op'\nbaseline='base'\n{extra}"))
                .unwrap();
        ClaimSpec::from_file(f, &["op".into(), "base".into()], &maps()).unwrap()
    }

    /// A claim without a baseline (`at_most`/`at_least`).
    pub fn bounded(check: &str, extra: &str) -> ClaimSpec {
        let f: ClaimFile =
            toml::from_str(&format!("id='b'\nclaim='x'\ncheck='{check}'\nencoder='op'\n{extra}")).unwrap();
        ClaimSpec::from_file(f, &["op".into(), "base".into()], &maps()).unwrap()
    }
}

#[cfg(test)]
mod tests {
    use super::fixtures::{bounded, maps};
    use super::*;

    #[test]
    fn bad_claims_are_rejected_with_the_key() {
        let enc = ["op".to_string(), "base".to_string()];
        let parse = |s: &str| -> String {
            let f: ClaimFile =
                toml::from_str(&format!("id='c'\nclaim='x'\nencoder='op'\nbaseline='base'\n{s}")).unwrap();
            format!("{:#}", ClaimSpec::from_file(f, &enc, &maps()).err().unwrap())
        };
        assert!(parse("check='nope'").contains("check 'nope'"));
        assert!(parse("check='ratio'\ncolumn='speed'").contains("column 'speed'"));
        assert!(parse("check='ratio'\nstatistic='median'").contains("statistic 'median'"));
        assert!(parse("check='equal'\nthreshold=1").contains("threshold"));
        assert!(parse("check='ratio'\nbound=1").contains("'bound' is for check"));
        assert!(parse("check='at_most'\nbound=1").contains("'baseline' is not used"));
        assert!(parse("check='ratio'\nmaps=['m3']").contains("maps names 'm3'"));
        assert!(parse("check='ratio'\nmaps=[]").contains("maps = [] matches no row"));
        let parse_nb = |s: &str| -> String {
            let f: ClaimFile = toml::from_str(&format!("id='c'\nclaim='x'\nencoder='op'\n{s}")).unwrap();
            format!("{:#}", ClaimSpec::from_file(f, &enc, &maps()).err().unwrap())
        };
        assert!(parse_nb("check='ratio'").contains("needs 'baseline'"));
        assert!(parse_nb("check='at_most'").contains("needs 'bound'"));
        assert!(parse_nb("check='at_least'\nbound=-1").contains("bound must be"));
        assert!(parse_nb("check='at_most'\nbound=nan").contains("bound must be"));
        assert!(parse_nb("check='at_most'\nbound=1\nthreshold=2").contains("takes 'bound' only"));
        // A map is matched by its entry or its table name (file stem).
        assert_eq!(bounded("at_most", "bound=1\nmaps=['m2', 'dir/m2.exr']").maps, Some(vec!["m2".to_string()]));
        let f: ClaimFile = toml::from_str("id='c'\nclaim='x'\ncheck='ratio'\nencoder='zz'\nbaseline='base'").unwrap();
        assert!(format!("{:#}", ClaimSpec::from_file(f, &enc, &maps()).err().unwrap()).contains("encoder 'zz'"));
        assert!(toml::from_str::<ClaimFile>("id='c'\nclaim='x'\ncheck='ratio'\nencoder='a'\nbaseline='b'\nbogus=1")
            .is_err());
    }
}
