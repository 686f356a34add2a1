//! `check`: experiments re-run and every number compared with its baseline.
//!
//! A baseline is `results/<experiment>/table.csv` with its `provenance.toml`. `check` compares
//! every number with the baseline ([`crate::regression::baseline::compare`], tolerances from
//! `tolerances.toml`) and finds every moved number, added or removed row or column, changed map
//! checksum, and missing map ([`Finding`]). Baselines change only through `bless`
//! (`regression::bless`); `run`/`reproduce` keep off a moved one (`regression::guard`).

use crate::envmap::load::sha256_hex;
use crate::envmap::search::SearchPath;
use crate::pipeline::experiment::{list_experiments, Experiment};
use crate::pipeline::runner::{self, MapInfo, RunReport};
use crate::pipeline::settings::RunSettings;
use crate::regression::baseline::{self, Comparison, Table, TABLE};
pub use crate::regression::finding::Finding;
use crate::regression::missing::MissingMaps;
use crate::regression::provenance::{self, MapRecord, Provenance};
use crate::regression::tolerance::{EncoderClass, Tolerance, Tolerances};
use anyhow::{bail, Result};
use std::path::{Path, PathBuf};

/// The outcome of checking one experiment.
#[derive(Clone, Debug)]
pub struct ExperimentCheck {
    /// The experiment's name.
    pub experiment: String,
    /// The baseline folder.
    pub dir: PathBuf,
    /// Everything found, failures and notes, in the order they were found.
    pub findings: Vec<Finding>,
    /// The cell-by-cell comparison of the tables (empty when there was nothing to compare).
    pub comparison: Comparison,
    /// The baseline's provenance, when it could be read.
    pub baseline: Option<Provenance>,
    /// How many maps the experiment names.
    pub maps: usize,
    /// The baseline's rows of maps missing here (not compared).
    pub unchecked_rows: usize,
}

impl ExperimentCheck {
    /// True when nothing fails.
    pub fn passed(&self) -> bool {
        !self.findings.iter().any(Finding::fails)
    }

    /// The moved numbers.
    pub fn moved(&self) -> usize {
        self.count(|f| matches!(f, Finding::Change(baseline::Change::Moved { .. })))
    }

    /// How many findings `which` picks.
    pub fn count(&self, which: impl Fn(&Finding) -> bool) -> usize {
        self.findings.iter().filter(|f| which(f)).count()
    }

    /// Maps not on this machine (their rows were not compared).
    pub fn unchecked_maps(&self) -> usize {
        self.unchecked_map_names().len()
    }

    /// The names of those maps, in the findings' order.
    pub fn unchecked_map_names(&self) -> Vec<&str> {
        self.findings
            .iter()
            .filter_map(|f| match f {
                Finding::MapMissing { map, .. } => Some(map.as_str()),
                _ => None,
            })
            .collect()
    }
}

/// Which experiments a check takes when none is named.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Selection {
    /// Those with `ci = true` (the others are listed as left out).
    Ci,
    /// Every experiment.
    All,
}

/// What a map missing from this machine does to a check.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapPolicy {
    /// Its rows are not compared, and it is said once at the end (not a failure).
    AllowMissing,
    /// It fails the check (`--require-all-maps`).
    RequireAll,
}

/// The file-stem name a map entry gets in tables (entries may be paths).
fn map_table_name(entry: &str) -> String {
    Path::new(entry).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| entry.to_string())
}

/// Compares a fresh run with the baseline in `dir`. Maps missing from this machine are
/// findings (failing under [`MapPolicy::RequireAll`]), and their rows are not compared.
pub fn compare_with_baseline(
    dir: &Path,
    exp: &Experiment,
    report: &RunReport,
    tolerances: &Tolerances,
    policy: MapPolicy,
) -> Result<ExperimentCheck> {
    let mut findings = Vec::new();
    let fresh_bytes = crate::pipeline::table::to_csv(&report.rows)?;
    // The fresh table is not on disk: errors name the file it would be compared with.
    let fresh_origin = PathBuf::from(format!("{} (this run's table, not written)", dir.join(TABLE).display()));
    let fresh = Table::parse(&fresh_bytes, &fresh_origin)?;
    let mut skip: Vec<String> = Vec::new();
    for (k, m) in report.missing.iter().enumerate() {
        let why = report.missing_why.get(k).cloned().unwrap_or_else(|| "not on the search path".into());
        findings.push(Finding::MapMissing { map: m.clone(), why, allowed: policy == MapPolicy::AllowMissing });
        skip.push(m.clone());
        skip.push(map_table_name(m));
    }
    let mut check = ExperimentCheck {
        experiment: exp.name.clone(),
        dir: dir.to_path_buf(),
        findings,
        comparison: Comparison::default(),
        baseline: None,
        maps: exp.maps.len(),
        unchecked_rows: 0,
    };
    let table_path = dir.join(TABLE);
    if !table_path.exists() {
        check.findings.push(Finding::NoBaseline);
        return Ok(check);
    }
    let old_bytes =
        std::fs::read(&table_path).map_err(|e| anyhow::anyhow!("{}: cannot read: {e}", table_path.display()))?;
    let old = Table::parse(&old_bytes, &table_path)?;
    check.unchecked_rows = crate::regression::missing::rows_of(&old, &report.missing);
    check.baseline = read_provenance(dir, &mut check.findings);
    if let Some(p) = &check.baseline {
        let actual = sha256_hex(&old_bytes);
        if p.table_sha256 != actual {
            check.findings.push(Finding::TableEdited { recorded: p.table_sha256.clone(), actual });
        }
        map_findings(p, &old, &report.maps, &mut check.findings, &mut skip);
    }
    // Tolerances are looked up by the row's encoder name → the configured encoder's kind and
    // class; rows of encoders the experiment no longer has are only ever added or removed.
    let tolerance = |key: &baseline::RowKey, column: &str| -> Tolerance {
        let class = exp
            .encoders
            .iter()
            .find(|e| e.name == key.encoder)
            .map(|e| EncoderClass { kind: e.encoder.id(), iterative: e.encoder.is_iterative() });
        tolerances.get(column, class)
    };
    check.comparison = baseline::compare(&old, &fresh, &|m| skip.iter().any(|s| s == m), &tolerance);
    check.findings.extend(check.comparison.changes.iter().cloned().map(Finding::Change));
    Ok(check)
}

/// The baseline's provenance in `dir`, or `None` with the finding that says why not.
fn read_provenance(dir: &Path, findings: &mut Vec<Finding>) -> Option<Provenance> {
    let prov_path = dir.join(provenance::FILE_NAME);
    if !prov_path.exists() {
        findings.push(Finding::NoProvenance(format!("{} does not exist", prov_path.display())));
        return None;
    }
    match Provenance::read(&prov_path) {
        Ok(p) => Some(p),
        Err(e) => {
            findings.push(Finding::NoProvenance(format!("{e:#}")));
            None
        }
    }
}

/// The maps read now against the ones the provenance `p` records: a changed or unrecorded
/// map is a finding and its rows are skipped; the same pixels from another file is a note.
fn map_findings(p: &Provenance, old: &Table, maps: &[MapInfo], findings: &mut Vec<Finding>, skip: &mut Vec<String>) {
    let old_maps: Vec<String> = old.keys().into_iter().map(|k| k.map).collect();
    for m in maps {
        match p.map(&m.name) {
            Some(r) if r.sha256 == m.sha256 && (r.width, r.height) == (m.width, m.height) => {}
            Some(r) if same_map(r, m) => findings.push(Finding::MapSamePixels {
                map: m.name.clone(),
                file: m.path.as_ref().map(|p| p.display().to_string()).unwrap_or_else(|| "(no file)".into()),
                pixel_sha256: m.pixel_sha256.clone(),
            }),
            Some(r) => {
                findings.push(Finding::MapChanged {
                    map: m.name.clone(),
                    old: format!("{}x{} sha256 {}", r.width, r.height, &r.sha256[..r.sha256.len().min(12)]),
                    new: format!("{}x{} sha256 {}", m.width, m.height, &m.sha256[..m.sha256.len().min(12)]),
                });
                skip.push(m.name.clone());
            }
            None if old_maps.contains(&m.name) => {
                findings.push(Finding::MapUnrecorded { map: m.name.clone() });
                skip.push(m.name.clone());
            }
            None => {}
        }
    }
}

/// The identity rule of `check` (docs/maps.md): a map whose file is not the one the baseline
/// recorded is the same map when it has the same size and the same pixels
/// ([`crate::envmap::identity`]): the pixel sha256 the provenance records, or, for a provenance
/// written before pixel sha256s were recorded, a known map's
/// ([`crate::envmap::known`]) whose known files include the recorded one.
pub fn same_map(recorded: &MapRecord, fresh: &MapInfo) -> bool {
    if (recorded.width, recorded.height) != (fresh.width, fresh.height) || fresh.pixel_sha256.is_empty() {
        return false;
    }
    if let Some(p) = &recorded.pixel_sha256 {
        return *p == fresh.pixel_sha256;
    }
    crate::envmap::known::by_pixels(&fresh.pixel_sha256).is_some_and(|k| k.has_file(&recorded.sha256))
}

/// The experiments named, or by default every experiment in `<root>/experiments/` (only those
/// with `ci = true` under [`Selection::Ci`]). Returns them and the names left out for
/// `ci = false`.
pub fn select(root: &Path, names: &[String], selection: Selection) -> Result<(Vec<Experiment>, Vec<String>)> {
    if !names.is_empty() {
        let exps = names
            .iter()
            .map(|n| Experiment::load(&crate::pipeline::experiment::resolve(root, n)?))
            .collect::<Result<_>>()?;
        return Ok((exps, vec![]));
    }
    let (mut chosen, mut left) = (Vec::new(), Vec::new());
    for f in list_experiments(&root.join("experiments"))? {
        let e = Experiment::load(&f)?;
        if selection == Selection::Ci && !e.ci {
            left.push(e.name);
        } else {
            chosen.push(e);
        }
    }
    Ok((chosen, left))
}

/// What [`check_experiments`] found, for the caller to decide and to render.
pub struct Checked {
    /// Each experiment's check, in order.
    pub experiments: Vec<ExperimentCheck>,
    /// The experiments left out for `ci = false`.
    pub left_out: Vec<String>,
    /// The experiments that failed.
    pub failed: Vec<String>,
    /// Numbers compared, over every experiment.
    pub numbers: usize,
    /// Numbers moved, over every experiment.
    pub moved: usize,
    /// Maps not on this machine, counted per experiment.
    pub unchecked_maps: usize,
    /// True when every failure is a missing map (under [`MapPolicy::RequireAll`]).
    pub maps_only: bool,
    /// The maps not found, each once, and what went unchecked for want of them.
    pub missing: MissingMaps,
    /// Every map the experiments read, with its identity, in the order read.
    pub maps: Vec<MapInfo>,
    /// The seconds the whole check took.
    pub seconds: f64,
}

impl Checked {
    /// True when no experiment failed.
    pub fn passed(&self) -> bool {
        self.failed.is_empty()
    }
}

/// The experiments a check takes and how it treats missing maps.
pub struct CheckRequest<'a> {
    /// Experiment names or files (empty: the default selection).
    pub names: &'a [String],
    /// The default selection.
    pub selection: Selection,
    /// What a missing map does.
    pub policy: MapPolicy,
    /// How the experiments are run (the timing pass, the profile).
    pub settings: RunSettings<'a>,
}

/// `probelab check`: checks the selected experiments against their baselines. A map not on
/// this machine leaves its rows unchecked, unless [`MapPolicy::RequireAll`] (then it fails the
/// check). Each experiment's check is handed to `checked`, with the seconds it took, as soon as
/// it is known (so a long check can show its progress); an error from `checked` stops the check.
pub fn check_experiments(
    root: &Path,
    search: &SearchPath,
    out: &Path,
    request: &CheckRequest,
    checked: &mut dyn FnMut(&ExperimentCheck, f64) -> Result<()>,
) -> Result<Checked> {
    let (exps, left_out) = select(root, request.names, request.selection)?;
    let tolerances = Tolerances::load(root)?;
    if exps.is_empty() {
        bail!("no experiments to check in {}", root.join("experiments").display());
    }
    let start = std::time::Instant::now();
    let mut all = Checked {
        experiments: Vec::new(),
        left_out,
        failed: Vec::new(),
        numbers: 0,
        moved: 0,
        unchecked_maps: 0,
        maps_only: true,
        missing: MissingMaps::default(),
        maps: Vec::new(),
        seconds: 0.0,
    };
    // The experiments' cases that are the same on a map share one reference.
    let cache = crate::pipeline::reuse::ReferenceCache::new(request.settings.profile);
    for exp in &exps {
        let t = std::time::Instant::now();
        let report = runner::run(exp, search, &request.settings, &cache)?;
        let c = compare_with_baseline(&out.join(&exp.name), exp, &report, &tolerances, request.policy)?;
        checked(&c, t.elapsed().as_secs_f64())?;
        all.maps.extend(report.maps);
        all.numbers += c.comparison.numbers;
        all.moved += c.moved();
        all.unchecked_maps += c.unchecked_maps();
        all.missing.add(exp.maps.len(), &report.missing, &report.missing_why, c.unchecked_rows);
        if !c.passed() {
            all.failed.push(exp.name.clone());
            all.maps_only &= c.findings.iter().filter(|f| f.fails()).all(|f| matches!(f, Finding::MapMissing { .. }));
        }
        all.experiments.push(c);
    }
    all.seconds = start.elapsed().as_secs_f64();
    Ok(all)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn root_with(files: &[(&str, &str)]) -> tempfile::TempDir {
        let d = tempfile::tempdir().unwrap();
        std::fs::create_dir(d.path().join("experiments")).unwrap();
        for (n, t) in files {
            std::fs::write(d.path().join("experiments").join(n), t).unwrap();
        }
        d
    }

    #[test]
    fn default_selection_honours_ci_and_names_resolve() {
        let d = root_with(&[
            ("a.toml", "maps = ['m']\nencoders = ['sh1']\n"),
            ("b.toml", "name = 'slow_one'\nmaps = ['m']\nencoders = ['sh1']\nci = false\n"),
        ]);
        let names = |v: &[Experiment]| v.iter().map(|e| e.name.clone()).collect::<Vec<_>>();
        let (ci, left) = select(d.path(), &[], Selection::Ci).unwrap();
        assert_eq!((names(&ci), left), (vec!["a".to_string()], vec!["slow_one".to_string()]));
        let (all, left) = select(d.path(), &[], Selection::All).unwrap();
        assert_eq!((names(&all), left.len()), (vec!["a".to_string(), "slow_one".to_string()], 0));
        // By file stem, by name, by path; an explicit ci = false experiment is selected.
        let by = |n: &str| names(&select(d.path(), &[n.to_string()], Selection::Ci).unwrap().0);
        assert_eq!(by("b"), ["slow_one"]);
        assert_eq!(by("slow_one"), ["slow_one"]);
        assert_eq!(by(d.path().join("experiments/a.toml").to_str().unwrap()), ["a"]);
        let e = format!("{:#}", select(d.path(), &["nope".to_string()], Selection::Ci).err().unwrap());
        assert!(e.contains("experiment 'nope'") && e.contains("known: a, b"), "{e}");
    }
}
