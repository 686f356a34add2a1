//! The claims under regression: `probelab claims` (and `reproduce`, `check`, `bless`) run the
//! claims measurements and judge every declared claim. The measurement tables
//! (`results/claims/measures/*.csv`) are baselines like any `table.csv`: a fresh one is compared
//! with the committed one (numbers within `tolerances.toml`, text exactly) and written only when
//! none exists or nothing moved, or by `bless`. The verdicts (`results/CLAIMS.csv`) are judged on
//! the evidence as it stands in `results/`, and `check` fails if a verdict differs from the
//! committed one.
//!
//! The measurements need every map they name (the ZH3 talk's declared `[measurements] maps`,
//! [`crate::claims::zh3::maps`], and the lightmap study's). Without them the committed
//! measurement tables are judged as they stand, and the command says so; nothing is rewritten
//! from partial data.

use crate::claims::declaration::{load_papers, Paper};
use crate::claims::lightmap::strip::BlendStrip;
use crate::claims::measure::Measure;
use crate::claims::verdicts;
use crate::envmap::search::SearchPath;
use crate::regression::baseline::{compare, Change, Table};
use crate::regression::tolerance::Tolerances;
use anyhow::Result;
use std::path::Path;

/// The fresh measurements and the blending strips (as data), or why they were not taken (a
/// map is missing, or the declarations `papers` name none for the ZH3 measurements).
pub fn measure(
    search: &SearchPath,
    experiments: &Path,
    papers: &[Paper],
) -> std::result::Result<(Vec<Measure>, Vec<BlendStrip>), String> {
    let maps = crate::claims::zh3::maps(papers).map_err(|e| format!("{e:#}"))?;
    let missing: Vec<&str> = maps
        .iter()
        .map(String::as_str)
        .filter(|m| matches!(search.open(m), Err(crate::envmap::search::OpenError::NotFound(_))))
        .collect();
    if !missing.is_empty() {
        return Err(format!("map(s) not on the search path: {}", missing.join(", ")));
    }
    let (mut all, _) = crate::claims::zh3::measure(search, maps).map_err(|e| format!("{e:#}"))?;
    let study = crate::claims::lightmap::measure(search, experiments).map_err(|e| format!("{e:#}"))?;
    all.extend(study.measures);
    Ok((all, study.strips))
}

/// One measurement against its committed table: the changes (empty: nothing moved, or no
/// committed table yet — `None`).
fn compare_measure(results: &Path, m: &Measure, tolerances: &Tolerances) -> Result<Option<Vec<Change>>> {
    let path = results.join(m.rel_path());
    if !path.exists() {
        return Ok(None);
    }
    let old = Table::read(&path)?;
    let new = Table::parse(&m.to_csv()?, Path::new(&m.rel_path()))?;
    let c = compare(&old, &new, &|_| false, &|_, col| tolerances.get(col, None));
    Ok(Some(c.changes))
}

/// What a claims run writes, and so what fails it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClaimsMode {
    /// `check`: nothing written; a measurement moved or a verdict changed fails.
    Check,
    /// `claims`, `reproduce`: measurements new or unmoved written, verdicts and evidence pages
    /// written; a measurement moved fails (and is not written).
    Write,
    /// `bless`: every measurement written, verdicts and evidence pages written.
    Bless,
}

/// The outcome of a claims run.
pub struct ClaimsRun {
    /// What the run was asked to write.
    pub mode: ClaimsMode,
    /// Measurement tables written (relative to results).
    pub written: Vec<String>,
    /// Measurements whose numbers moved (not written unless blessed), with the changes.
    pub moved: Vec<(String, Vec<Change>)>,
    /// Why the measurements were not taken, if they were not.
    pub skipped: Option<String>,
    /// The verdicts that differ from the committed CLAIMS.csv: (id, old, new).
    pub verdicts_changed: Vec<(String, String, String)>,
    /// The blending strips of the lightmap study, for the report layer to draw (empty when
    /// the measurements were not taken).
    pub strips: Vec<BlendStrip>,
    /// Every claim as judged, in the declarations' order.
    pub verdicts: Vec<Judged>,
}

/// One claim as judged: its verdict and the evidence tables it read.
pub struct Judged {
    /// The claim's id (`Z1`, `H3`, …).
    pub id: String,
    /// Its verdict word (CLAIMS.csv's `verdict`).
    pub verdict: String,
    /// The evidence files its checks read, relative to the results folder, each once.
    pub evidence: Vec<String>,
}

impl ClaimsRun {
    /// No measurement moved and, under [`ClaimsMode::Check`], no verdict changed.
    pub fn passed(&self) -> bool {
        self.moved.is_empty() && (self.mode != ClaimsMode::Check || self.verdicts_changed.is_empty())
    }
}

/// The committed verdicts, by id.
fn committed_verdicts(results: &Path) -> Vec<(String, String)> {
    let Ok(t) = Table::read(&results.join(verdicts::CSV)) else { return Vec::new() };
    let (Some(i), Some(v)) = (t.columns.iter().position(|c| c == "id"), t.columns.iter().position(|c| c == "verdict"))
    else {
        return Vec::new();
    };
    t.rows.iter().map(|r| (r[i].clone(), r[v].clone())).collect()
}

/// Each claim's verdict with the evidence files its declaration reads.
fn judged(papers: &[Paper], outcomes: &[(String, crate::claims::judge::ClaimOutcome)]) -> Vec<Judged> {
    let declared = |id: &str| papers.iter().flat_map(|p| &p.claims).find(|c| c.id == id);
    outcomes
        .iter()
        .map(|(_, o)| {
            let mut evidence: Vec<String> = Vec::new();
            for check in declared(&o.id).map(|c| c.checks.as_slice()).unwrap_or_default() {
                let path = check.source.path().to_string_lossy().replace('\\', "/");
                if !evidence.contains(&path) {
                    evidence.push(path);
                }
            }
            Judged { id: o.id.clone(), verdict: o.verdict.word().to_string(), evidence }
        })
        .collect()
}

/// Runs the measurements (when their maps are here), writes those that are new or unmoved
/// (all of them under [`ClaimsMode::Bless`]), then judges every claim and, unless
/// [`ClaimsMode::Check`], writes CLAIMS.csv and the evidence pages.
pub fn run(root: &Path, search: &SearchPath, results: &Path, mode: ClaimsMode) -> Result<ClaimsRun> {
    let papers: Vec<Paper> = load_papers(&root.join("experiments"))?;
    let mut run = ClaimsRun {
        mode,
        written: vec![],
        moved: vec![],
        skipped: None,
        verdicts_changed: vec![],
        strips: vec![],
        verdicts: vec![],
    };
    let (bless, write_verdicts) = (mode == ClaimsMode::Bless, mode != ClaimsMode::Check);
    if papers.is_empty() {
        run.skipped = Some("no claims declared in experiments/claims/".into());
        return Ok(run);
    }
    let tolerances = Tolerances::load(root)?;
    match measure(search, &root.join("experiments"), &papers) {
        Err(why) => run.skipped = Some(why),
        Ok((ms, strips)) => {
            run.strips = strips;
            let mut keep = Vec::new();
            for m in ms {
                match compare_measure(results, &m, &tolerances)? {
                    Some(ch) if !ch.is_empty() && !bless => run.moved.push((m.name.clone(), ch)),
                    _ => keep.push(m),
                }
            }
            if write_verdicts {
                run.written = crate::claims::measure::write_all(results, &keep)?;
            }
        }
    }
    let outcomes = verdicts::judge_all(results, &papers);
    let old = committed_verdicts(results);
    run.verdicts = judged(&papers, &outcomes);
    for (_, o) in &outcomes {
        let new = o.verdict.word().to_string();
        let before = old.iter().find(|(id, _)| id == &o.id).map(|(_, v)| v.clone()).unwrap_or_else(|| "-".into());
        if before != new {
            run.verdicts_changed.push((o.id.clone(), before, new));
        }
    }
    if write_verdicts {
        run.written.extend(verdicts::write(results, &papers, &outcomes)?);
    }
    Ok(run)
}
