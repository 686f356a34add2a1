//! Regression on the numbers: `probelab check`, `probelab bless`, and the guard that keeps
//! `run`/`reproduce` from overwriting a baseline whose numbers moved.
//!
//! A baseline is `results/<experiment>/table.csv` with its `provenance.toml`. Baselines change
//! only through `bless`:
//! - `check` re-runs experiments and compares every number with the baseline
//!   ([`crate::regression::baseline::compare`], tolerances from `tolerances.toml`), reports every moved
//!   number, added or removed row or column, changed map checksum, and missing map; exit 1 if
//!   anything is reported, 0 if nothing moved.
//! - `bless` re-runs, prints the same report, and rewrites the baselines that differ (all of
//!   an experiment's files, atomically: [`crate::io::atomic::write_set`]).
//! - `run`/`reproduce` write a table freely when none exists yet; when one exists they leave
//!   it untouched if nothing moved, and refuse (exit 1, printing the report) if something did.

use crate::envmap::load::sha256_hex;
use crate::envmap::search::SearchPath;
use crate::pipeline::experiment::{list_experiments, Experiment};
use crate::pipeline::runner::{self, RunReport};
use crate::regression::baseline::{self, Comparison, Table, TABLE};
use crate::regression::missing::MissingMaps;
use crate::regression::provenance::{self, MapRecord, Provenance};
use crate::regression::tolerance::{EncoderClass, Tolerance, Tolerances};
use anyhow::{bail, Result};
use std::fmt;
use std::path::{Path, PathBuf};

/// A problem found when checking one experiment against its baseline.
#[derive(Clone, Debug)]
pub enum Finding {
    /// No `table.csv` in the baseline folder.
    NoBaseline,
    /// A table but no (readable) provenance: map checksums cannot be verified.
    NoProvenance(String),
    /// The table's sha256 is not the one its provenance records (edited by hand, merged, or
    /// an interrupted bless).
    TableEdited {
        /// The table sha256 the provenance records.
        recorded: String,
        /// The sha256 of the table file as it is.
        actual: String,
    },
    /// A map of the experiment is not on this machine's search path (`why`: what was looked
    /// for and passed over, and how to get it when it is a known map).
    MapMissing {
        /// The map's name.
        map: String,
        /// What was looked for and passed over, and how to get the map when it is known.
        why: String,
        /// Whether missing maps were allowed for this check (then not a failure).
        allowed: bool,
    },
    /// A map read from another file than the baseline's, with the same pixels
    /// ([`same_map`]): its rows are compared. A note, never a failure.
    MapSamePixels {
        /// The map's name.
        map: String,
        /// The file it was read from now ("(no file)" for a generated map).
        file: String,
        /// The pixel sha256 both files share.
        pixel_sha256: String,
    },
    /// A map's file differs from the one the baseline was computed from; its rows are not
    /// compared.
    MapChanged {
        /// The map's name.
        map: String,
        /// The baseline's file: size and start of its sha256.
        old: String,
        /// The file read now: size and start of its sha256.
        new: String,
    },
    /// The table has rows of a map the provenance does not list; they are not compared.
    MapUnrecorded {
        /// The map's name.
        map: String,
    },
    /// A difference in the table.
    Change(baseline::Change),
}

impl Finding {
    /// Whether this finding fails the check.
    pub fn fails(&self) -> bool {
        !matches!(self, Finding::MapMissing { allowed: true, .. } | Finding::MapSamePixels { .. })
    }
}

impl Finding {
    /// A short machine-readable name of the finding's kind (`check --format json`).
    pub fn kind(&self) -> &'static str {
        match self {
            Finding::NoBaseline => "no_baseline",
            Finding::NoProvenance(_) => "no_provenance",
            Finding::TableEdited { .. } => "table_edited",
            Finding::MapMissing { .. } => "map_missing",
            Finding::MapSamePixels { .. } => "map_same_pixels",
            Finding::MapChanged { .. } => "map_changed",
            Finding::MapUnrecorded { .. } => "map_unrecorded",
            Finding::Change(baseline::Change::Moved { .. }) => "moved",
            Finding::Change(baseline::Change::Text { .. }) => "text_changed",
            Finding::Change(baseline::Change::RowAdded(_)) => "row_added",
            Finding::Change(baseline::Change::RowRemoved(_)) => "row_removed",
            Finding::Change(baseline::Change::ColumnAdded(_)) => "column_added",
            Finding::Change(baseline::Change::ColumnRemoved(_)) => "column_removed",
        }
    }
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Finding::NoBaseline => write!(f, "no baseline {TABLE}: nothing to compare with"),
            Finding::NoProvenance(why) => {
                write!(f, "no usable {}: {why}; map checksums cannot be verified", provenance::FILE_NAME)
            }
            Finding::TableEdited { recorded, actual } => write!(
                f,
                "{TABLE} is not the table {} vouches for (sha256 {} recorded, {} found): edited outside \
                 `probelab bless`, or a bless was interrupted",
                provenance::FILE_NAME,
                &recorded[..recorded.len().min(12)],
                &actual[..actual.len().min(12)]
            ),
            // Why it is missing, and how to get it, is said once for every experiment
            // (`regression::missing`), not in each experiment's report.
            Finding::MapMissing { map, allowed: false, .. } => {
                write!(f, "map {map} not found on this machine: its rows were not checked (--require-all-maps)")
            }
            Finding::MapMissing { map, allowed: true, .. } => {
                write!(f, "map {map} not found on this machine: its rows were not checked")
            }
            Finding::MapSamePixels { map, file, pixel_sha256 } => write!(
                f,
                "map {map} read from {file}, not the baseline's file but the same pixels (pixel sha256 {}): its rows \
                 were compared",
                &pixel_sha256[..pixel_sha256.len().min(12)]
            ),
            Finding::MapChanged { map, old, new } => {
                write!(
                    f,
                    "map {map} is not the file the baseline used ({old} then, {new} now): its rows were not compared"
                )
            }
            Finding::MapUnrecorded { map } => write!(
                f,
                "map {map} has rows in the baseline but no checksum in {}: its rows were not compared",
                provenance::FILE_NAME
            ),
            Finding::Change(c) => write!(f, "{c}"),
        }
    }
}

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
        self.findings.iter().filter(|f| matches!(f, Finding::Change(baseline::Change::Moved { .. }))).count()
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

    /// The outcome as JSON (`check --format json`): the counts of [`report`](Self::report)
    /// as numbers, the baseline's date and commit, and each finding as its kind, whether it
    /// fails, and the sentence `report` prints.
    pub fn to_json(&self) -> serde_json::Value {
        let c = &self.comparison;
        let findings: Vec<serde_json::Value> = self
            .findings
            .iter()
            .map(|f| serde_json::json!({ "kind": f.kind(), "fails": f.fails(), "text": f.to_string() }))
            .collect();
        let unchecked = self.unchecked_map_names();
        serde_json::json!({
            "experiment": self.experiment,
            "passed": self.passed(),
            "baseline_dir": self.dir.display().to_string(),
            "baseline_date": self.baseline.as_ref().map(|p| p.date.clone()),
            "baseline_commit": self.baseline.as_ref().map(|p| p.git_commit.clone()),
            "maps": self.maps,
            "unchecked_maps": unchecked,
            "rows": c.rows,
            "numbers": c.numbers,
            "within_tolerance": c.within,
            "ignored": c.ignored,
            "moved": self.moved(),
            "findings": findings,
        })
    }

    /// The report: one line per finding, each starting with the experiment's name, then a
    /// verdict line. `check` and `bless` print exactly this.
    pub fn report(&self) -> String {
        let mut s = String::new();
        // A map missing where that is allowed is in the verdict line, not a line of its own.
        for f in self.findings.iter().filter(|f| !matches!(f, Finding::MapMissing { allowed: true, .. })) {
            s += &format!("{}: {f}\n", self.experiment);
        }
        let c = &self.comparison;
        let from = match &self.baseline {
            Some(p) => format!(
                "baseline of {} from {}{}",
                p.date,
                &p.git_commit[..p.git_commit.len().min(12)],
                if p.git_dirty == Some(true) { " (uncommitted changes)" } else { "" }
            ),
            None => "baseline".to_string(),
        };
        let counts = format!(
            "{} rows, {} numbers compared with the {from} in {}; {} within tolerance, {} ignored",
            c.rows,
            c.numbers,
            self.dir.display(),
            c.within,
            c.ignored
        );
        let unchecked = self.unchecked_maps();
        if self.passed() && unchecked >= self.maps {
            s += &format!("{}: skipped: none of its {} map(s) is on this machine\n", self.experiment, self.maps);
        } else if self.passed() && unchecked > 0 {
            s += &format!(
                "{}: ok on the maps here ({} of {}; {} row(s) of the {unchecked} missing not checked) ({counts})\n",
                self.experiment,
                self.maps - unchecked,
                self.maps,
                self.unchecked_rows
            );
        } else if self.passed() {
            s += &format!("{}: ok, nothing moved ({counts})\n", self.experiment);
        } else {
            let mut parts = Vec::new();
            let count = |p: &dyn Fn(&Finding) -> bool| self.findings.iter().filter(|f| p(f)).count();
            use baseline::Change as C;
            for (n, what) in [
                (self.moved(), "number(s) moved"),
                (count(&|f| matches!(f, Finding::Change(C::Text { .. }))), "text cell(s) changed"),
                (count(&|f| matches!(f, Finding::Change(C::RowAdded(_)))), "row(s) added"),
                (count(&|f| matches!(f, Finding::Change(C::RowRemoved(_)))), "row(s) removed"),
                (
                    count(&|f| matches!(f, Finding::Change(C::ColumnAdded(_) | C::ColumnRemoved(_)))),
                    "column(s) added or removed",
                ),
                (
                    count(&|f| {
                        matches!(
                            f,
                            Finding::MapChanged { .. } | Finding::MapUnrecorded { .. } | Finding::MapMissing { .. }
                        ) && f.fails()
                    }),
                    "map(s) changed, unrecorded or missing",
                ),
                (
                    count(&|f| {
                        matches!(f, Finding::NoBaseline | Finding::NoProvenance(_) | Finding::TableEdited { .. })
                    }),
                    "baseline problem(s)",
                ),
            ] {
                if n > 0 {
                    parts.push(format!("{n} {what}"));
                }
            }
            s += &format!("{}: FAILED: {} ({counts})\n", self.experiment, parts.join(", "));
        }
        s
    }
}

/// The file-stem name a map entry gets in tables (entries may be paths).
fn map_table_name(entry: &str) -> String {
    Path::new(entry).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| entry.to_string())
}

/// Compares a fresh run with the baseline in `dir`. Maps missing from this machine are
/// findings (failing unless `allow_missing`), and their rows are not compared.
pub fn compare_with_baseline(
    dir: &Path,
    exp: &Experiment,
    report: &RunReport,
    tolerances: &Tolerances,
    allow_missing: bool,
) -> Result<ExperimentCheck> {
    let mut findings = Vec::new();
    let fresh_bytes = crate::pipeline::table::to_csv(&report.rows)?;
    let fresh = Table::parse(&fresh_bytes, Path::new("(fresh table)"))?;
    let mut skip: Vec<String> = Vec::new();
    for (k, m) in report.missing.iter().enumerate() {
        let why = report.missing_why.get(k).cloned().unwrap_or_else(|| "not on the search path".into());
        findings.push(Finding::MapMissing { map: m.clone(), why, allowed: allow_missing });
        skip.push(m.clone());
        skip.push(map_table_name(m));
    }
    let table_path = dir.join(TABLE);
    if !table_path.exists() {
        findings.push(Finding::NoBaseline);
        return Ok(ExperimentCheck {
            experiment: exp.name.clone(),
            dir: dir.to_path_buf(),
            findings,
            comparison: Comparison::default(),
            baseline: None,
            maps: exp.maps.len(),
            unchecked_rows: 0,
        });
    }
    let old_bytes =
        std::fs::read(&table_path).map_err(|e| anyhow::anyhow!("{}: cannot read: {e}", table_path.display()))?;
    let old = Table::parse(&old_bytes, &table_path)?;
    let unchecked_rows = crate::regression::missing::rows_of(&old, &report.missing);
    let prov_path = dir.join(provenance::FILE_NAME);
    let prov = if prov_path.exists() {
        match Provenance::read(&prov_path) {
            Ok(p) => Some(p),
            Err(e) => {
                findings.push(Finding::NoProvenance(format!("{e:#}")));
                None
            }
        }
    } else {
        findings.push(Finding::NoProvenance(format!("{} does not exist", prov_path.display())));
        None
    };
    if let Some(p) = &prov {
        let actual = sha256_hex(&old_bytes);
        if p.table_sha256 != actual {
            findings.push(Finding::TableEdited { recorded: p.table_sha256.clone(), actual });
        }
        let old_maps: Vec<String> = old.keys().into_iter().map(|k| k.map).collect();
        for m in &report.maps {
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
    let comparison = baseline::compare(&old, &fresh, &|m| skip.iter().any(|s| s == m), &tolerance);
    findings.extend(comparison.changes.iter().cloned().map(Finding::Change));
    Ok(ExperimentCheck {
        experiment: exp.name.clone(),
        dir: dir.to_path_buf(),
        findings,
        comparison,
        baseline: prov,
        maps: exp.maps.len(),
        unchecked_rows,
    })
}

/// The identity rule of `check` (docs/maps.md): a map whose file is not the one the baseline
/// recorded is the same map when it has the same size and the same pixels
/// ([`crate::envmap::identity`]): the pixel sha256 the provenance records, or, for a provenance
/// written before pixel sha256s were recorded, a known map's
/// ([`crate::envmap::known`]) whose known files include the recorded one.
pub fn same_map(recorded: &MapRecord, fresh: &crate::pipeline::runner::MapInfo) -> bool {
    if (recorded.width, recorded.height) != (fresh.width, fresh.height) || fresh.pixel_sha256.is_empty() {
        return false;
    }
    if let Some(p) = &recorded.pixel_sha256 {
        return *p == fresh.pixel_sha256;
    }
    crate::envmap::known::by_pixels(&fresh.pixel_sha256).is_some_and(|k| k.has_file(&recorded.sha256))
}

/// What `reproduce` did with an experiment run on only some of its maps.
pub struct PartialCheck {
    /// False when a number moved (or the baseline is unusable): `reproduce` then fails.
    pub passed: bool,
    /// One line for the closing summary: maps found of maps named, the missing ones, and how
    /// many numbers were compared.
    pub text: String,
    /// What the command shows as it goes: the comparison's report and what became of the
    /// baseline (empty or newline-terminated lines).
    pub notes: String,
    /// The baseline's rows of the maps missing (not compared).
    pub unchecked_rows: usize,
}

/// `reproduce` on an experiment some of whose maps are not on the search path: the rows of
/// the maps found are compared with the committed baseline in `<out>/<name>/` (the missing
/// maps' rows are not, [`compare_with_baseline`] with `allow_missing`); nothing is written,
/// since a baseline holds every map. Without a baseline there is nothing to compare with, and
/// nothing is written either (a note, not a failure).
/// The tolerances are read from `root` only when there is a baseline to compare with.
pub fn check_partial(out: &Path, root: &Path, exp: &Experiment, report: &RunReport) -> Result<PartialCheck> {
    let dir = out.join(&exp.name);
    let found = exp.maps.len() - report.missing.len();
    let head = format!("{}: {found} of {} maps (missing: {})", exp.name, exp.maps.len(), report.missing.join(", "));
    if !dir.join(TABLE).exists() {
        return Ok(PartialCheck {
            passed: true,
            text: format!("{head}; no baseline to compare with, nothing written"),
            notes: format!("{}: no baseline, and a run missing maps writes none\n", dir.join(TABLE).display()),
            unchecked_rows: 0,
        });
    }
    let c = compare_with_baseline(&dir, exp, report, &Tolerances::load(root)?, true)?;
    let numbers = c.comparison.numbers;
    Ok(if c.passed() {
        PartialCheck {
            passed: true,
            text: format!("{head}; {numbers} numbers compared, nothing moved; baseline left unchanged"),
            notes: c.report(),
            unchecked_rows: c.unchecked_rows,
        }
    } else {
        PartialCheck {
            passed: false,
            text: format!("{head}; {numbers} numbers compared, FAILED ({} moved); baseline left unchanged", c.moved()),
            notes: format!("{}{}", c.report(), not_overwritten(&dir)),
            unchecked_rows: c.unchecked_rows,
        }
    })
}

/// The files of an experiment's baseline, in the order [`crate::io::atomic::write_set`] renames them:
/// the table, then the provenance that vouches for it.
pub fn baseline_files(exp: &Experiment, report: &RunReport, root: &Path) -> Result<Vec<(String, Vec<u8>)>> {
    let table = crate::pipeline::table::to_csv(&report.rows)?;
    let prov = Provenance::new(exp, report, &table, root).to_toml()?;
    Ok(vec![(TABLE.to_string(), table), (provenance::FILE_NAME.to_string(), prov.into_bytes())])
}

/// What `run`/`reproduce` did with an experiment's table.
pub enum Stored {
    /// No baseline existed: table and provenance written.
    New,
    /// A baseline exists and nothing moved: left untouched.
    Unchanged(ExperimentCheck),
    /// A baseline exists and something moved: nothing written.
    Refused(ExperimentCheck),
}

/// The overwrite guard of `run`/`reproduce`: writes `<out>/<name>/` when it holds no table;
/// otherwise compares and writes nothing (see [`Stored`]). The run must have found every map.
pub fn store(out: &Path, root: &Path, exp: &Experiment, report: &RunReport) -> Result<Stored> {
    let dir = out.join(&exp.name);
    if !dir.join(TABLE).exists() {
        crate::io::atomic::write_set(&dir, &baseline_files(exp, report, root)?)?;
        return Ok(Stored::New);
    }
    let c = compare_with_baseline(&dir, exp, report, &Tolerances::load(root)?, false)?;
    Ok(if c.passed() { Stored::Unchanged(c) } else { Stored::Refused(c) })
}

/// The fresh rows with their scores replaced by the stored table's (`<dir>/table.csv`), for a
/// run whose table stood within tolerance: what the run writes next to the table (summaries,
/// claims) is then derived from the table actually kept, and does not drift in the last digits
/// when code changes move numbers below tolerance. Rows the table lacks, and cells that are
/// empty or not numbers, keep their fresh values.
pub fn rows_as_stored(dir: &Path, rows: &[crate::pipeline::table::Row]) -> Result<Vec<crate::pipeline::table::Row>> {
    let stored = Table::read(&dir.join(TABLE))?;
    let fresh = Table::parse(&crate::pipeline::table::to_csv(rows)?, &dir.join(TABLE))?;
    let index: std::collections::HashMap<_, usize> =
        stored.keys().into_iter().enumerate().map(|(i, k)| (k, i)).collect();
    let col = |name: &str| stored.columns.iter().position(|c| c == name);
    let cols =
        ["rmse_r", "rmse_g", "rmse_b", "rmse", "rel_rmse", "neg_frac", "max_abs_err", "at_normal_abs_err"].map(col);
    let mut out = rows.to_vec();
    for (row, key) in out.iter_mut().zip(fresh.keys()) {
        let Some(&i) = index.get(&key) else { continue };
        let cell = |c: Option<usize>| c.and_then(|c| stored.rows[i].get(c)).and_then(|v| v.parse::<f64>().ok());
        let s = &mut row.scores;
        let [r, g, b] = &mut s.rmse_rgb;
        let targets: [&mut f64; 7] = [r, g, b, &mut s.rmse, &mut s.rel_rmse, &mut s.neg_frac, &mut s.max_abs];
        for (t, c) in targets.into_iter().zip(cols) {
            if let Some(v) = cell(c) {
                *t = v;
            }
        }
        if row.at_normal_abs_err.is_some() {
            if let Some(v) = cell(cols[7]) {
                row.at_normal_abs_err = Some(v);
            }
        }
    }
    Ok(out)
}

/// The line that says a moved baseline was left as it was.
fn not_overwritten(dir: &Path) -> String {
    format!("{}: NOT overwritten: the baseline changes only through `probelab bless`\n", dir.join(TABLE).display())
}

impl Stored {
    /// Whether the table stands (written new, or unchanged); false when refused.
    pub fn stands(&self) -> bool {
        !matches!(self, Stored::Refused(_))
    }

    /// What became of the table of `exp` under `out` (`rows` rows), as lines for the command
    /// to show: written, matched, or the differences and the refusal.
    pub fn notes(&self, exp: &Experiment, out: &Path, rows: usize) -> String {
        let dir = out.join(&exp.name);
        match self {
            Stored::New => {
                format!(
                    "wrote {} ({rows} rows) and {} (new baseline)\n",
                    dir.join(TABLE).display(),
                    provenance::FILE_NAME
                )
            }
            Stored::Unchanged(c) => format!(
                "{}: matches the baseline ({} numbers compared); left unchanged\n",
                dir.join(TABLE).display(),
                c.comparison.numbers
            ),
            Stored::Refused(c) => format!("{}{}", c.report(), not_overwritten(&dir)),
        }
    }

    /// One phrase for a closing summary: a new baseline, the numbers that matched, or how many
    /// moved.
    pub fn summary(&self) -> String {
        match self {
            Stored::New => "no baseline yet: new baseline written".to_string(),
            Stored::Unchanged(c) => {
                format!("{} numbers compared, nothing moved; baseline left unchanged", c.comparison.numbers)
            }
            Stored::Refused(c) => format!("FAILED ({} moved)", c.moved()),
        }
    }
}

/// The advice after `run`/`reproduce` refused to overwrite the baselines of `refused`; `None`
/// when nothing was refused.
pub fn refusal_advice(refused: &[String]) -> Option<String> {
    (!refused.is_empty()).then(|| {
        format!(
            "{} experiment(s) differ from their baselines and were not written: {}.\n\
             Review the differences above; if they are intended, run `probelab bless {}` and quote its \
             output in the commit message.\n",
            refused.len(),
            refused.join(", "),
            refused.join(" ")
        )
    })
}

/// The experiments named, or by default every experiment in `<root>/experiments/` (only those
/// with `ci = true` when `ci_only`). Returns them and the names left out for `ci = false`.
pub fn select(root: &Path, names: &[String], ci_only: bool) -> Result<(Vec<Experiment>, Vec<String>)> {
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
        if ci_only && !e.ci {
            left.push(e.name);
        } else {
            chosen.push(e);
        }
    }
    Ok((chosen, left))
}

/// What [`check_experiments`] found: the closing lines `check` prints, and the whole as JSON.
pub struct CheckSummary {
    /// The closing lines: the experiments left out for `ci = false`, the verdict line, and the
    /// one line of what could not be checked for want of maps (each experiment's own report
    /// went to the `checked` callback as it came).
    pub text: String,
    /// For stderr: each missing map once, with the one fix ([`MissingMaps::notes`]).
    pub notes: String,
    /// `{ "passed", "experiments": [ExperimentCheck::to_json…], "not_checked": […],
    /// "numbers", "moved", "unchecked_maps", "missing_maps": […], "skipped_experiments",
    /// "unchecked_rows", "seconds" }`.
    pub json: serde_json::Value,
    /// Every map the experiments read, with its identity, in the order read.
    pub maps: Vec<crate::pipeline::runner::MapInfo>,
}

/// `probelab check`: checks the selected experiments against their baselines; the exit code
/// is 0 when nothing moved in any of them, 1 otherwise. A map not on this machine leaves its
/// rows unchecked and is said once at the end, unless `!allow_missing` (then it fails the
/// check). Each experiment's check is handed to `checked`, with the seconds it took, as soon as
/// it is known (so a long check can show its progress); an error from `checked` stops the check.
pub fn check_experiments(
    root: &Path,
    search: &SearchPath,
    out: &Path,
    names: &[String],
    (all, allow_missing): (bool, bool),
    checked: &mut dyn FnMut(&ExperimentCheck, f64) -> Result<()>,
) -> Result<(i32, CheckSummary)> {
    let (exps, left) = select(root, names, !all)?;
    let tolerances = Tolerances::load(root)?;
    if exps.is_empty() {
        bail!("no experiments to check in {}", root.join("experiments").display());
    }
    let start = std::time::Instant::now();
    let mut failed = Vec::new();
    let mut checks = Vec::new();
    let mut missing = MissingMaps::default();
    let (mut numbers, mut moved, mut unchecked, mut maps_only) = (0, 0, 0, true);
    let mut maps = Vec::new();
    for exp in &exps {
        let t = std::time::Instant::now();
        let report = runner::run(exp, search)?;
        let c = compare_with_baseline(&out.join(&exp.name), exp, &report, &tolerances, allow_missing)?;
        checked(&c, t.elapsed().as_secs_f64())?;
        maps.extend(report.maps);
        numbers += c.comparison.numbers;
        moved += c.moved();
        unchecked += c.unchecked_maps();
        missing.add(exp.maps.len(), &report.missing, &report.missing_why, c.unchecked_rows);
        if !c.passed() {
            failed.push(exp.name.clone());
            maps_only &= c.findings.iter().filter(|f| f.fails()).all(|f| matches!(f, Finding::MapMissing { .. }));
        }
        checks.push(c.to_json());
    }
    let elapsed = start.elapsed().as_secs_f64();
    let mut text = String::new();
    if !left.is_empty() {
        text += &format!("not checked (ci = false): {}; `probelab check --all` includes them\n", left.join(", "));
    }
    text += &verdict(exps.len(), &failed, (numbers, moved), maps_only, elapsed);
    if let Some(line) = missing.line("checked") {
        text += &format!("{line}\n");
    }
    let json = serde_json::json!({
        "passed": failed.is_empty(),
        "experiments": checks,
        "not_checked": left,
        "numbers": numbers,
        "moved": moved,
        "unchecked_maps": unchecked,
        "missing_maps": missing.names(),
        "skipped_experiments": missing.skipped(),
        "unchecked_rows": missing.rows(),
        "seconds": (elapsed * 10.0).round() / 10.0,
    });
    let code = i32::from(!failed.is_empty());
    Ok((code, CheckSummary { text, notes: missing.notes(search), json, maps }))
}

/// `check`'s verdict line: ok, or the experiments that failed and what to do (`bless` when
/// numbers moved; the maps when only maps were missing, under `--require-all-maps`).
fn verdict(n: usize, failed: &[String], (numbers, moved): (usize, usize), maps_only: bool, elapsed: f64) -> String {
    if failed.is_empty() {
        return format!("check: ok: {n} experiment(s), {numbers} numbers compared, nothing moved ({elapsed:.1} s)\n");
    }
    let advice = if maps_only {
        "Only maps are missing: put them on the map search path (see the maps listed on stderr).".to_string()
    } else {
        format!("If intended, run `probelab bless {}` and quote its output in the commit message.", failed.join(" "))
    };
    format!(
        "check: FAILED: {} of {n} experiment(s) differ from their baselines ({}); {moved} number(s) moved. {advice} \
         ({elapsed:.1} s)\n",
        failed.len(),
        failed.join(", ")
    )
}

/// `probelab bless`: re-runs the experiments (by default all of them), hands each comparison
/// to `compared` (the same report as `check`'s), and rewrites the baselines that differ (all
/// of them with `force`, which refreshes the provenance and ignored columns such as timings).
/// Every experiment is run and compared before anything is written, so `compared` (which
/// prints) can stop the command only before its first write. A named experiment whose maps
/// are missing is an error (nothing is written); by default such experiments are skipped and
/// listed. Returns the exit code and the lines saying what was written, for the caller to
/// print after its own last write.
pub fn bless(
    root: &Path,
    search: &SearchPath,
    out: &Path,
    (names, force): (&[String], bool),
    compared: &mut dyn FnMut(&ExperimentCheck) -> Result<()>,
) -> Result<(i32, String)> {
    let (exps, _) = select(root, names, false)?;
    let tolerances = Tolerances::load(root)?;
    let mut staged = Vec::new();
    let mut skipped = Vec::new();
    for exp in &exps {
        let report = runner::run(exp, search)?;
        if !report.missing.is_empty() {
            if !names.is_empty() {
                bail!(
                    "{}: map(s) not found: {}; nothing blessed (a baseline needs every map)",
                    exp.name,
                    report.missing.join(", ")
                );
            }
            skipped.push(format!("{} (missing {})", exp.name, report.missing.join(", ")));
            continue;
        }
        let c = compare_with_baseline(&out.join(&exp.name), exp, &report, &tolerances, false)?;
        compared(&c)?;
        let files = if c.passed() && !force { None } else { Some(baseline_files(exp, &report, root)?) };
        staged.push((exp.name.clone(), c.passed(), files));
    }
    // Every write, then every line: a stdout that fails (a closed pipe) can stop the command
    // before its first write (above) or after its last, never between two baselines.
    let mut lines = Vec::new();
    for (name, passed, files) in staged {
        let dir = out.join(&name);
        match files {
            None => lines.push(format!("bless {name}: nothing moved; {} left unchanged", dir.display())),
            Some(files) => {
                crate::io::atomic::write_set(&dir, &files)?;
                let list: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
                let why = if passed { " (nothing moved; rewritten because of --force)" } else { "" };
                lines.push(format!("bless {name}: wrote {} in {}{why}", list.join(", "), dir.display()));
            }
        }
    }
    if !skipped.is_empty() {
        lines.push(format!("not blessed, maps not found on this machine: {}", skipped.join("; ")));
    }
    Ok((0, lines.iter().map(|l| format!("{l}\n")).collect()))
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
        let (ci, left) = select(d.path(), &[], true).unwrap();
        assert_eq!((names(&ci), left), (vec!["a".to_string()], vec!["slow_one".to_string()]));
        let (all, left) = select(d.path(), &[], false).unwrap();
        assert_eq!((names(&all), left.len()), (vec!["a".to_string(), "slow_one".to_string()], 0));
        // By file stem, by name, by path; an explicit ci = false experiment is selected.
        let by = |n: &str| names(&select(d.path(), &[n.to_string()], true).unwrap().0);
        assert_eq!(by("b"), ["slow_one"]);
        assert_eq!(by("slow_one"), ["slow_one"]);
        assert_eq!(by(d.path().join("experiments/a.toml").to_str().unwrap()), ["a"]);
        let e = format!("{:#}", select(d.path(), &["nope".to_string()], true).err().unwrap());
        assert!(e.contains("experiment 'nope'") && e.contains("known: a, b"), "{e}");
    }

    /// A table that stood is what the summaries are computed from: the fresh rows' scores are
    /// replaced cell by cell (round-trip text, so exactly), unknown rows and empty cells kept.
    #[test]
    fn rows_as_stored_takes_the_kept_tables_numbers() {
        use crate::pipeline::table::Row;
        use crate::reference::metrics::Scores;
        let row = |map: &str, rmse: f64, at_n: Option<f64>| Row {
            map: map.into(),
            encoder: "sh1".into(),
            domain: "sphere".into(),
            metric: "exact".into(),
            scores: Scores { rmse_rgb: [rmse; 3], rmse, rel_rmse: 2.0 * rmse, neg_frac: 0.0, max_abs: 3.0 * rmse },
            stored_scalars: 12,
            orientation_set: String::new(),
            effects: String::new(),
            weighting: "solid_angle".into(),
            resolution: "8x4".into(),
            units: "E/pi".into(),
            reference: "exact".into(),
            diagnostics: String::new(),
            at_normal_abs_err: at_n,
            fit_ns: None,
            eval_ns: None,
        };
        let d = tempfile::tempdir().unwrap();
        let kept = vec![row("a", 0.1, Some(1e-3)), row("b", 0.2, None)];
        crate::pipeline::table::write_csv(&d.path().join(TABLE), &kept).unwrap();
        let nudged = |r: &Row| {
            let mut r = r.clone();
            r.scores.rmse *= 1.0 + 1e-13;
            r.scores.max_abs *= 1.0 + 1e-13;
            r.at_normal_abs_err = r.at_normal_abs_err.map(|v| v * 1.5);
            r
        };
        let fresh = vec![nudged(&kept[0]), nudged(&kept[1]), row("new", 0.3, None)];
        assert_ne!(fresh[0], kept[0]);
        let got = rows_as_stored(d.path(), &fresh).unwrap();
        assert_eq!(got[0], kept[0]);
        assert_eq!(got[1], kept[1]);
        assert_eq!(got[2], fresh[2]);
    }

    #[test]
    fn allowed_missing_maps_are_counted_in_the_verdict_and_fail_only_when_required() {
        let c = ExperimentCheck {
            experiment: "x".into(),
            dir: PathBuf::from("results/x"),
            findings: vec![Finding::MapMissing { map: "m".into(), why: "gone".into(), allowed: true }],
            comparison: Comparison::default(),
            baseline: None,
            maps: 3,
            unchecked_rows: 7,
        };
        assert!(c.passed());
        assert!(
            c.report().contains("x: ok on the maps here (2 of 3; 7 row(s) of the 1 missing not checked)"),
            "{}",
            c.report()
        );
        // Which map, and why, is said once for the whole check, not in each experiment's report.
        assert!(!c.report().contains("map m"), "{}", c.report());
        let strict = ExperimentCheck {
            findings: vec![Finding::MapMissing { map: "m".into(), why: "gone".into(), allowed: false }],
            ..c
        };
        assert!(!strict.passed());
        assert!(strict.report().contains("x: FAILED: 1 map(s) changed, unrecorded or missing"), "{}", strict.report());
        assert!(strict.report().contains("x: map m not found on this machine: its rows were not checked"));
    }
}
