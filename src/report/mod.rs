//! The report: comparison sheets, charts and `results/REPORT.md`, generated from the result
//! CSVs and the maps — never written by hand. `probelab report` runs it; `probelab reproduce`
//! runs it last.
//!
//! Per experiment (`experiments/*.toml`, in file order), then per other folder of `results/`:
//! - the table (`table.csv`) as a map × encoder rmse pivot, a timing summary when `*_ns`
//!   columns exist, and the whole table;
//! - charts: rmse bars, error against `fit_ns` (when that column exists), one convergence
//!   chart per knob of every sweep CSV (any CSV with `knob`, `value`, `rmse` columns), the blending chart of every blending CSV (`t`, `method`, E/π at N);
//! - comparison sheets (`sheet_<map>.png`), drawn when every map of the experiment is on the
//!   search path; otherwise the committed sheets are kept and linked, and the page reads the
//!   same (what this machine lacked is returned in [`Generated`], for the command to print);
//! - other pictures and files found in the folder (e.g. a blending strip) are linked, so work
//!   added later appears without changes here.
//!
//! Then the claims (`*/claims.csv`) and how the run was made (commit, date, settings, map
//! checksums). Every chart is written as PNG and, beside it, as SVG (same stem). Everything is written
//! atomically; stale `sheet_*`/`chart_*` PNGs and SVGs are removed.
//!
//! Files: `sheet` (comparison sheets of an experiment), `strip` (the lightmap study's blending
//! strips, drawn from the claims layer's data), `charts` (plotters charts), `markdown` (tables
//! and links), `csvfile` (CSV read by column name), `tone` (exposure, Reinhard, sRGB, the error
//! colour scale), `number` (number formatting), `text` (font and labels), `canvas` (pixel
//! painting), `png` (PNG encoding and atomic writing).
//!
//! What this layer may use: the layer table of ARCHITECTURE.md (checked by
//! `tests/architecture.rs`).

pub mod canvas;
pub mod charts;
pub mod csvfile;
mod front;
pub mod glyphs;
pub mod markdown;
pub mod number;
pub mod papers;
pub mod png;
pub mod sheet;
pub mod strip;
pub mod text;
pub mod tone;

use crate::encoders::encoder::Family;
use crate::envmap::search::SearchPath;
use crate::io::progress::Progress;
use crate::pipeline::experiment::{list_experiments, Experiment};
use anyhow::{bail, Context, Result};
use charts::Outcome;
use csvfile::CsvTable;
use front::{other_results, paper_sections, Page};
pub use front::{CLAIMS_CSV, PAGE, PROVENANCE_PAGE};
use markdown::{anchor, href};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Where the report reads and writes.
pub struct Options<'a> {
    /// Repository root (holds `experiments/`).
    pub root: &'a Path,
    /// The results folder (`REPORT.md` is written here).
    pub out: &'a Path,
    /// Where the experiments' maps are looked up (for the sheets and the maps' checksums).
    pub search: &'a SearchPath,
    /// The comparison sheets' scale (`report --scale`, 1..=[`sheet::MAX_SCALE`]): every measure
    /// of a sheet times this; 1 is the standard sheet. Charts do not depend on it.
    pub sheet_scale: u32,
}

/// What a report run produced. The pages written depend only on the committed files (results,
/// experiments, provenance), never on which maps this machine has: what it lacked is here.
pub struct Generated {
    /// The path of the `REPORT.md` written.
    pub report: PathBuf,
    /// The number of PNG pictures drawn: comparison sheets and charts (their SVGs not counted).
    pub pictures: usize,
    /// Experiments whose sheets were not redrawn (maps missing).
    pub kept: Vec<String>,
    /// The experiments' maps not found on the search path.
    pub missing: Vec<String>,
    /// Maps found in another file than the one their tables record (a sentence each).
    pub mismatches: Vec<String>,
}

/// A file name made of `[A-Za-z0-9._-]`.
pub fn file_safe(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') { c } else { '_' }).collect()
}

/// One map file as found now (what the sheets are drawn from; compared with the records).
#[derive(Clone, Debug)]
struct MapUse {
    file: String,
    sha256: String,
}

/// A report section: an experiment, or another folder of results.
struct Section {
    name: String,
    exp: Option<Experiment>,
    source_text: Option<String>,
    source_file: Option<PathBuf>,
}

/// Files of `dir` (names only), sorted.
fn files(dir: &Path) -> Vec<String> {
    let Ok(rd) = std::fs::read_dir(dir) else { return vec![] };
    let mut v: Vec<String> = rd
        .filter_map(|e| e.ok())
        .filter(|e| e.file_type().map(|t| t.is_file()).unwrap_or(false))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    v.sort();
    v
}

/// The report's sections: every experiment of `root/experiments/`, then every other folder of
/// `out` that holds a CSV or a picture, by name.
fn sections(root: &Path, out: &Path) -> Result<Vec<Section>> {
    let mut sections = Vec::new();
    for path in list_experiments(&root.join("experiments"))? {
        let exp = Experiment::load(&path)?;
        let text = std::fs::read_to_string(&path).with_context(|| format!("{}: cannot read", path.display()))?;
        sections.push(Section {
            name: exp.name.clone(),
            exp: Some(exp),
            source_text: Some(text),
            source_file: Some(path),
        });
    }
    if let Ok(rd) = std::fs::read_dir(out) {
        let mut extra: Vec<String> = rd
            .filter_map(|e| e.ok())
            .filter(|e| e.file_type().map(|t| t.is_dir()).unwrap_or(false))
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| !n.starts_with('.') && !sections.iter().any(|s| s.name == *n))
            .filter(|n| files(&out.join(n)).iter().any(|f| f.ends_with(".csv") || f.ends_with(".png")))
            .collect();
        extra.sort();
        for name in extra {
            sections.push(Section { name, exp: None, source_text: None, source_file: None });
        }
    }
    Ok(sections)
}

/// Writes the report; see the module doc.
pub fn generate(opts: &Options) -> Result<Generated> {
    let out = opts.out;
    std::fs::create_dir_all(out).with_context(|| format!("{}: cannot create folder", out.display()))?;
    let sections = sections(opts.root, out)?;
    let maps = map_uses(opts, &sections);
    let (sheet_pictures, drawn_sheets) = draw_sheets(opts, &sections, &maps)?;
    let (pages, page_pictures, kept) = write_pages(opts, &sections, &drawn_sheets)?;
    // Every table's provenance.toml, read once for REPORT.md's opening and PROVENANCE.md.
    let records = run_records(&sections, out)?;
    let named = named_maps(&sections);
    let doc = report_md(opts, &records, named.len(), &pages)?;
    let report = out.join("REPORT.md");
    crate::io::atomic::write(&report, doc.as_bytes())?;
    crate::io::atomic::write(&out.join(PROVENANCE_PAGE), provenance(&sections, &records, &named).as_bytes())?;
    let missing = maps.iter().filter(|(_, u)| u.is_none()).map(|(m, _)| m.clone()).collect();
    Ok(Generated {
        report,
        pictures: sheet_pictures + page_pictures,
        kept,
        missing,
        mismatches: mismatches(&maps, &records),
    })
}

/// Every map the experiments name, with the experiments that name it (committed data only).
fn named_maps(sections: &[Section]) -> BTreeMap<String, Vec<String>> {
    let mut named: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for s in sections {
        for m in s.exp.iter().flat_map(|e| &e.maps) {
            named.entry(m.clone()).or_default().push(s.name.clone());
        }
    }
    named
}

/// The maps found here in another file than the one a table was computed from, one sentence
/// each (the file's sha256 differs; `check` says whether the pixels are the same).
fn mismatches(maps: &BTreeMap<String, Option<MapUse>>, records: &[RunRecord]) -> Vec<String> {
    let mut out = Vec::new();
    for (section, pr) in records {
        for r in &pr.maps {
            if let Some(Some(u)) = maps.get(&r.name) {
                if u.sha256 != r.sha256 {
                    out.push(format!(
                        "{section}: its table used a map {} with another file sha256 than {}",
                        r.name, u.file
                    ));
                }
            }
        }
    }
    out
}

/// Every map an experiment names, resolved on the search path and checksummed (`None` when it
/// is not found).
fn map_uses(opts: &Options, sections: &[Section]) -> BTreeMap<String, Option<MapUse>> {
    let mut maps: BTreeMap<String, Option<MapUse>> = BTreeMap::new();
    for m in sections.iter().flat_map(|s| s.exp.iter().flat_map(|e| &e.maps)) {
        maps.entry(m.clone()).or_insert_with(|| map_use(opts.search, m).ok());
    }
    maps
}

/// Draws the comparison sheets of every experiment whose maps are all found, removing its
/// stale ones: the number of sheets drawn and, per experiment drawn, its sheets' file names.
fn draw_sheets(
    opts: &Options,
    sections: &[Section],
    maps: &BTreeMap<String, Option<MapUse>>,
) -> Result<(usize, BTreeMap<String, Vec<String>>)> {
    let drawable: Vec<&Section> = sections
        .iter()
        .filter(|s| s.exp.as_ref().is_some_and(|e| e.maps.iter().all(|m| maps.get(m).is_some_and(|u| u.is_some()))))
        .collect();
    let total: usize = drawable.iter().map(|s| s.exp.as_ref().map_or(0, |e| e.sheet_maps().len())).sum();
    let progress = Progress::new(total as u64, "sheets");
    let mut pictures = 0;
    let mut drawn_sheets: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for s in &drawable {
        // Cannot fail: `drawable` holds only the sections that have an experiment.
        let exp = s.exp.as_ref().expect("drawable sections are experiments");
        let dir = opts.out.join(&s.name);
        progress.message(s.name.clone());
        let names = experiment_sheets(opts, exp, &dir, &progress)?;
        pictures += names.len();
        remove_stale(&dir, "sheet_", &names)?;
        drawn_sheets.insert(s.name.clone(), names);
    }
    progress.finish();
    Ok((pictures, drawn_sheets))
}

/// Draws and writes the sheets of one experiment into `dir`, with the figures of its
/// `table.csv` when there is one; their file names, in the experiment's map order.
fn experiment_sheets(opts: &Options, exp: &Experiment, dir: &Path, progress: &Progress) -> Result<Vec<String>> {
    let table_path = dir.join("table.csv");
    let table = if table_path.is_file() { Some(CsvTable::read(&table_path)?) } else { None };
    // The sheets of one experiment are independent files: drawn in parallel (each one's
    // pixels do not depend on the thread count), named in the experiment's map order.
    exp.sheet_maps()
        .par_iter()
        .map(|m| -> Result<String> {
            let map = {
                let _s = crate::io::profile::span("report: decode");
                opts.search.load(m)?
            };
            let (sheet, _) = sheet::experiment_sheet(exp, &map, table.as_ref(), opts.sheet_scale)?;
            let name = format!("sheet_{}.png", file_safe(m));
            let image = {
                let _s = crate::io::profile::span("report: draw");
                sheet.draw()?
            };
            png::write_png(&dir.join(&name), &image)?;
            progress.log(format!("wrote {}", dir.join(&name).display()));
            progress.inc();
            Ok(name)
        })
        .collect::<Result<Vec<String>>>()
}

/// Writes every section's page (`results/<name>/README.md`, when its folder exists): the
/// pages for REPORT.md, the number of charts drawn, and the sections whose sheets were kept.
fn write_pages(
    opts: &Options,
    sections: &[Section],
    drawn_sheets: &BTreeMap<String, Vec<String>>,
) -> Result<(Vec<Page>, usize, Vec<String>)> {
    let out = opts.out;
    let mut pages: Vec<Page> = Vec::new();
    let mut pictures = 0;
    let mut kept = Vec::new();
    for s in sections {
        let dir = out.join(&s.name);
        let (md, n) = section(s, &dir, out, opts.root, drawn_sheets.get(&s.name), &mut kept)?;
        pictures += n;
        let has_page = dir.is_dir();
        if has_page {
            crate::io::atomic::write(&dir.join(PAGE), md.as_bytes())?;
        }
        pages.push(Page { name: s.name.clone(), description: s.exp.as_ref().map(|e| e.description.clone()), has_page });
    }
    Ok((pages, pictures, kept))
}

/// REPORT.md's text: the opening, the claims at a glance, one section per paper and the other
/// results. Reads the claims declarations (`experiments/claims/`), the paper sections' plans
/// ([`papers::PLAN_FILE`]) and the engine's CLAIMS.csv.
fn report_md(opts: &Options, records: &[RunRecord], named: usize, pages: &[Page]) -> Result<String> {
    let out = opts.out;
    let decl_dir = opts.root.join("experiments").join(crate::claims::declaration::DIR);
    let papers = if decl_dir.is_dir() {
        crate::claims::declaration::load_papers(&opts.root.join("experiments"))?
    } else {
        Vec::new()
    };
    // The paper sections' plans; none when the file is absent (a section per declared paper only).
    let plan_file = opts.root.join("experiments").join(papers::PLAN_FILE);
    let plans = match std::fs::read_to_string(&plan_file) {
        Ok(text) => papers::parse_plans(&text, &plan_file)?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Vec::new(),
        Err(e) => bail!("{}: cannot read: {e}", plan_file.display()),
    };
    let claims_csv = out.join(CLAIMS_CSV);
    let claims = if claims_csv.is_file() { Some(CsvTable::read(&claims_csv)?) } else { None };
    let mut doc = opening(records, named, &papers, &plans);
    doc.push_str(&papers::at_a_glance(&papers, claims.as_ref())?);
    doc.push_str(&paper_sections(out, &papers, &plans, pages)?);
    let planned: Vec<&str> = plans.iter().flat_map(|p| p.pages.iter().map(String::as_str)).collect();
    doc.push_str(&other_results(pages, &planned));
    Ok(doc)
}

/// The first lines of REPORT.md: what probelab is and how this run was made.
fn opening(
    records: &[RunRecord],
    named: usize,
    papers: &[crate::claims::declaration::Paper],
    plans: &[papers::PaperPlan],
) -> String {
    let mut commits: Vec<String> = Vec::new();
    let mut dates: Vec<String> = Vec::new();
    let mut dirty = 0;
    let tables = records.len();
    for (_, pr) in records {
        let c: String = pr.git_commit.chars().take(12).collect();
        if !commits.contains(&c) {
            commits.push(c);
        }
        dates.push(pr.date.clone());
        dirty += usize::from(pr.git_dirty == Some(true));
    }
    dates.sort();
    dates.dedup();
    let mut md = String::from("# probelab: three papers on compact lighting, reproduced\n\n");
    md.push_str(
        "probelab measures compact lighting encodings (SH, ZH3, Geomerics, AHD/HHD lightmaps, probe occlusion) \
         against an exact reference on HDR environment maps, and judges the claims of three papers on those \
         measurements. This report is generated by `probelab report` from the CSVs under `results/`; do not edit \
         it by hand.\n\n",
    );
    let _ = writeln!(
        md,
        "**How this run was made.** {tables} tables, computed at commit{} {}{} on {} (UTC), each recorded in its \
         `provenance.toml`. Reference: the exact irradiance of each map taken as piecewise-constant radiance over its \
         texel cells (Gauss–Legendre in the polar angle; each table's `reference` column says which grid and nodes). \
         Every figure is **E/π** (a white Lambertian surface's exit radiance: a constant environment of radiance 1 \
         gives 1); each table states its domain, weighting and output resolution. Maps: {named} named in the \
         experiments; each is listed with the sha256 of the file its tables were computed from in \
         [{PROVENANCE_PAGE}]({PROVENANCE_PAGE}) with every experiment's settings.{}\n",
        if commits.len() == 1 { "" } else { "s" },
        commits.iter().map(|c| format!("`{c}`")).collect::<Vec<_>>().join(", "),
        if dirty > 0 { format!(" ({dirty} with uncommitted changes)") } else { String::new() },
        match (dates.first(), dates.last()) {
            (Some(a), Some(b)) if a != b => format!("{a} to {b}"),
            (Some(a), _) => a.clone(),
            _ => "-".into(),
        },
        if papers.is_empty() {
            format!(
                " No claims declarations (`experiments/{}/`) in this checkout: the papers' sections use the \
                 titles of `experiments/{}`.",
                crate::claims::declaration::DIR,
                papers::PLAN_FILE
            )
        } else {
            String::new()
        }
    );
    let mut toc = vec!["[Reproduction at a glance](#reproduction-at-a-glance)".to_string()];
    for (title, _) in papers::section_titles(papers, plans) {
        toc.push(format!("[{title}](#{})", anchor(&title)));
    }
    toc.push("[Other results](#other-results)".into());
    let _ = writeln!(md, "Contents: {}\n", toc.join(" · "));
    md
}

fn map_use(search: &SearchPath, name: &str) -> Result<MapUse> {
    let map = search.load(name)?;
    let path = map.path.clone().unwrap_or_default();
    Ok(MapUse {
        file: path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default(),
        sha256: map.sha256.clone().unwrap_or_default(),
    })
}

/// Removes `prefix*.png` and `prefix*.svg` files of `dir` that are not in `keep`.
fn remove_stale(dir: &Path, prefix: &str, keep: &[String]) -> Result<()> {
    for f in files(dir) {
        if f.starts_with(prefix) && (f.ends_with(".png") || f.ends_with(".svg")) && !keep.contains(&f) {
            let p = dir.join(&f);
            std::fs::remove_file(&p).with_context(|| format!("{}: cannot remove stale picture", p.display()))?;
        }
    }
    Ok(())
}

/// The SVG beside a chart's PNG: the same stem, `.svg`.
fn svg_name(png: &str) -> String {
    format!("{}.svg", png.strip_suffix(".png").unwrap_or(png))
}

/// The charts of one section: their Markdown and the files drawn.
struct ChartsOut<'a> {
    dir: &'a Path,
    md: String,
    made: Vec<String>,
}

impl ChartsOut<'_> {
    /// Writes a drawn chart as `file` (PNG) and beside it as the same stem `.svg` (both
    /// atomically), and links it (captioned, with its source CSV `from`, and its SVG); a
    /// skipped one is stated as `skip_label: why`, or left out when `skip_label` is None.
    fn put(&mut self, file: String, o: Outcome, alt: &str, from: Option<&str>, skip_label: Option<&str>) -> Result<()> {
        match o {
            Outcome::Drawn { image, svg, caption, .. } => {
                png::write_png(&self.dir.join(&file), &image)?;
                let svg_file = svg_name(&file);
                crate::io::atomic::write(&self.dir.join(&svg_file), svg.as_bytes())?;
                let from = from.map(|f| format!(" (from [{f}]({}))", href(f))).unwrap_or_default();
                let _ =
                    writeln!(self.md, "![{alt}]({})\n\n*{caption}{from}* ([SVG]({}))\n", href(&file), href(&svg_file));
                self.made.push(file);
                self.made.push(svg_file);
            }
            Outcome::Skipped(why) => {
                if let Some(label) = skip_label {
                    let _ = writeln!(self.md, "{label}: {why}.\n");
                }
            }
        }
        Ok(())
    }
}

/// A result folder's page (`results/<name>/README.md`, links relative to that folder) and
/// the number of charts drawn.
fn section(
    s: &Section,
    dir: &Path,
    out: &Path,
    root: &Path,
    sheets: Option<&Vec<String>>,
    kept: &mut Vec<String>,
) -> Result<(String, usize)> {
    let mut md = String::new();
    page_header(&mut md, s, out, root);
    let all = files(dir);
    let mut drawn = ChartsOut { dir, md: String::new(), made: Vec::new() };

    // The table.
    table_part(&mut md, &mut drawn, s, dir, &all)?;
    // Sweeps and blending.
    csv_charts(&mut drawn, dir, &all)?;
    if dir.is_dir() {
        remove_stale(dir, "chart_", &drawn.made)?;
    }
    if !drawn.md.is_empty() {
        let _ = writeln!(md, "## Charts\n\n{}", drawn.md);
    }

    // Sheets: drawn now, or kept from the committed run.
    let now = files(dir);
    sheets_part(&mut md, s, &now, sheets, kept);

    // Claims, other pictures and files.
    other_files(&mut md, dir, &now, &drawn.made)?;
    Ok((md, drawn.made.iter().filter(|f| f.ends_with(".png")).count()))
}

/// The page's title, its note, the experiment's description and its settings (linked when the
/// output is this repository's `results/`).
fn page_header(md: &mut String, s: &Section, out: &Path, root: &Path) {
    let _ = writeln!(
        md,
        "# {}\n\nGenerated by `probelab report`; do not edit. Back to [the report](../REPORT.md). Every figure is E/π, \
         scored against the exact cell-integrated reference; each table states its domain, weighting and resolution.\n",
        s.name
    );
    if let Some(exp) = &s.exp {
        if !exp.description.is_empty() {
            let _ = writeln!(md, "{}\n", exp.description);
        }
        if let (Some(text), Some(file)) = (&s.source_text, &s.source_file) {
            let fname = file.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
            let same_repo = out.parent().and_then(|p| p.canonicalize().ok()) == root.canonicalize().ok();
            let label = if same_repo {
                format!("<a href=\"{}\">experiments/{fname}</a>", href(&format!("../../experiments/{fname}")))
            } else {
                format!("`experiments/{fname}`")
            };
            let _ = writeln!(
                md,
                "<details><summary>Settings: {label}</summary>\n\n```toml\n{}\n```\n\n</details>\n",
                text.trim_end()
            );
        }
    }
}

/// The results table (pivot, timing, the whole table), the rmse bars and the cost charts, the
/// ratios against the baseline; or a note that the experiment has not run.
fn table_part(md: &mut String, drawn: &mut ChartsOut, s: &Section, dir: &Path, all: &[String]) -> Result<()> {
    if all.iter().any(|f| f == "table.csv") {
        let t = CsvTable::read(&dir.join("table.csv"))?;
        let link = "table.csv".to_string();
        let _ = writeln!(md, "## Results\n\nFrom [table.csv]({}) ({} rows).\n", href(&link), t.rows.len());
        if let Some(p) = markdown::pivot(&t)? {
            md.push_str(&p);
        }
        if let Some(p) = markdown::timing_summary(&t)? {
            md.push_str(&p);
        }
        let _ = writeln!(
            md,
            "<details><summary>The whole table</summary>\n\n{}\n</details>\n",
            markdown::full_table(&t, &link)
        );
        drawn.put(
            "chart_rmse.png".into(),
            charts::rmse_bars(&t, &format!("{}: RMSE per encoder and map", s.name), &|name| encoder_family(s, name))?,
            "rmse bars",
            None,
            Some("rmse bars"),
        )?;
        if all.iter().any(|f| f == "summary.csv") {
            if let Some(p) = papers::ratio_pivot(&CsvTable::read(&dir.join("summary.csv"))?)? {
                let _ = writeln!(
                    md,
                    "**Against the baseline** (from [summary.csv](summary.csv), per orientation and map there): {p}"
                );
            }
        }
        for cost in charts::Cost::ALL {
            drawn.put(
                cost.file().into(),
                charts::error_vs_cost(&t, cost, &format!("{}: error against {}", s.name, cost.what()))?,
                &format!("Error against {}", cost.what()),
                None,
                Some(format!("Error against {}", cost.what()).as_str()),
            )?;
        }
    } else if s.exp.is_some() {
        let _ = writeln!(md, "No `table.csv` here yet (run `probelab run experiments/{}.toml`).\n", s.name);
    }
    Ok(())
}

/// The family an encoder of a section's table declares: the experiment's encoder of that name,
/// else the registered kind of that id, else [`Family::Other`].
fn encoder_family(s: &Section, name: &str) -> Family {
    let named = s.exp.as_ref().and_then(|e| e.encoders.iter().find(|n| n.name == name));
    named.map(|n| n.encoder.family()).or_else(|| crate::encoders::family_of(name)).unwrap_or(Family::Other)
}

/// The charts of the folder's sweep and blending CSVs.
fn csv_charts(drawn: &mut ChartsOut, dir: &Path, all: &[String]) -> Result<()> {
    for f in all.iter().filter(|f| f.ends_with(".csv")) {
        let stem = f.trim_end_matches(".csv");
        let t = CsvTable::read(&dir.join(f))?;
        if charts::is_sweep(&t) {
            for (knob, o) in charts::sweep_charts(&t)? {
                let file = format!("chart_{}_{}.png", file_safe(stem), file_safe(&knob));
                drawn.put(file, o, &format!("sweep {knob}"), Some(f), Some(f))?;
            }
        } else if charts::is_blend(&t) {
            for (set, o) in charts::blend_charts(&t)? {
                let file = if set.is_empty() {
                    format!("chart_{}.png", file_safe(stem))
                } else {
                    format!("chart_{}_{}.png", file_safe(stem), file_safe(&set))
                };
                drawn.put(file, o, "blending", Some(f), None)?;
            }
        }
    }
    Ok(())
}

/// The comparison sheets, in the experiment's map order, with the note when they were not
/// (re)drawn in this run (the section is then `kept`).
fn sheets_part(md: &mut String, s: &Section, now: &[String], sheets: Option<&Vec<String>>, kept: &mut Vec<String>) {
    let mut sheet_files: Vec<String> =
        now.iter().filter(|f| f.starts_with("sheet_") && f.ends_with(".png")).cloned().collect();
    if let Some(exp) = &s.exp {
        // In the experiment's map order, then any others.
        let pos = |f: &String| exp.maps.iter().position(|m| format!("sheet_{}.png", file_safe(m)) == *f);
        sheet_files.sort_by_key(|f| (pos(f).unwrap_or(usize::MAX), f.clone()));
    }
    if let Some(exp) = &s.exp {
        // Sheets not redrawn here are the committed ones, and the page says nothing of this
        // machine: the command reports the experiments `kept`.
        if sheets.is_none() {
            kept.push(s.name.clone());
        }
        let note = if sheet_files.is_empty() {
            "None yet: they are drawn when every map of the experiment is on the map search path.\n\n"
        } else {
            ""
        };
        let hemi = !exp.orientations.is_empty();
        let _ = writeln!(
            md,
            "## Comparison sheets\n\n{note}One sheet per map: a row per encoder; in each row the reference, the encoder \
             and its signed relative error (blue darker, red brighter than the reference), {}. All spheres of a sheet \
             share one exposure and tone curve (stated on the sheet); the rmse under each error sphere is the table's \
             `exact` figure for the case drawn.\n",
            if hemi {
                "for the case whose surface normal N is nearest +Y (the hemisphere about N drawn as a disc looking \
                 down N; a sphere domain is drawn front and top)"
            } else {
                "each as two views of the sphere of normals: front (viewer on +Z, +Y up) and top (viewer on +Y, -Z up)"
            }
        );
        for f in &sheet_files {
            let map = f.trim_start_matches("sheet_").trim_end_matches(".png");
            let _ = writeln!(md, "![{} on {map}]({})\n", s.name, href(f));
        }
    }
}

/// The experiment's own claims, other pictures, and links to the folder's other files.
fn other_files(md: &mut String, dir: &Path, now: &[String], made: &[String]) -> Result<()> {
    if now.iter().any(|f| f == "claims.csv") {
        let t = CsvTable::read(&dir.join("claims.csv"))?;
        let _ = writeln!(
            md,
            "## Claims checked here\n\nFrom [claims.csv](claims.csv) (this experiment's own checks; the one verdict per \
             claim is in the report's at-a-glance table).\n\n{}",
            markdown::claims_table(&t)?
        );
    }
    let other_png: Vec<&String> =
        now.iter().filter(|f| f.ends_with(".png") && !f.starts_with("sheet_") && !f.starts_with("chart_")).collect();
    if !other_png.is_empty() {
        md.push_str("## Other pictures\n\n");
        for f in other_png {
            let _ = writeln!(md, "![{f}]({})\n", href(f));
        }
    }
    let other: Vec<&String> = now.iter().filter(|f| !f.ends_with(".png") && *f != PAGE && !made.contains(f)).collect();
    if !other.is_empty() {
        let links: Vec<String> = other.iter().map(|f| format!("[{f}]({})", href(f))).collect();
        let _ = writeln!(md, "Files: {}\n", links.join(" · "));
    }
    Ok(())
}

/// A section's recorded run: the section's name and its folder's `provenance.toml`.
type RunRecord = (String, crate::regression::provenance::Provenance);

/// The `provenance.toml` of every section that has one, in section order, each read once.
fn run_records(sections: &[Section], out: &Path) -> Result<Vec<RunRecord>> {
    let mut records = Vec::new();
    for s in sections {
        let p = out.join(&s.name).join(crate::regression::provenance::FILE_NAME);
        if !p.is_file() {
            continue;
        }
        records.push((s.name.clone(), crate::regression::provenance::Provenance::read(&p)?));
    }
    Ok(records)
}

/// PROVENANCE.md: how each table was computed, the settings of every experiment and the maps.
/// Everything comes from the committed files (each table's provenance.toml, the experiments),
/// not from the clock, the checkout or the maps this machine has, so the same results give the
/// same page.
fn provenance(sections: &[Section], records: &[RunRecord], named: &BTreeMap<String, Vec<String>>) -> String {
    let mut md = String::from(
        "# How this run was made\n\nGenerated by `probelab report`; do not edit. Back to [the report](REPORT.md).\n\n",
    );
    runs_part(&mut md, records);
    settings_part(&mut md, sections);
    maps_part(&mut md, named, records);
    md
}

/// The runs table (per table: commit, date, version, table checksum) and the pictures' version.
fn runs_part(md: &mut String, records: &[RunRecord]) {
    md.push_str(
        "Each table was computed by the run its `provenance.toml` records (`probelab run`, `reproduce` or `bless`); \
         the report was drawn from those tables.\n\n",
    );
    let mut rows = Vec::new();
    for (name, pr) in records {
        let short = |c: &str| if c.len() > 12 { c[..12].to_string() } else { c.to_string() };
        rows.push(vec![
            name.clone(),
            format!(
                "`{}`{}",
                short(&pr.git_commit),
                if pr.git_dirty == Some(true) { " (with uncommitted changes)" } else { "" }
            ),
            pr.date.clone(),
            format!("probelab {}", pr.probelab_version),
            format!("`{}`", short(&pr.table_sha256)),
        ]);
    }
    if !rows.is_empty() {
        let headers: Vec<String> =
            ["experiment", "commit", "date (UTC)", "version", "table sha256"].iter().map(|s| s.to_string()).collect();
        md.push_str(&markdown::table_with(&headers, &rows, markdown::text_cell));
        md.push('\n');
    }
    let _ = writeln!(
        md,
        "Pictures: probelab {}; a comparison sheet is drawn when every map of its experiment is on the map \
         search path, and otherwise kept as committed.\n",
        env!("CARGO_PKG_VERSION")
    );
}

/// The settings table: one row per experiment.
fn settings_part(md: &mut String, sections: &[Section]) {
    md.push_str("## Settings\n\nEach experiment file is echoed in full on its page.\n\n");
    let rows: Vec<Vec<String>> =
        sections.iter().filter_map(|s| s.exp.as_ref().map(|e| settings_row(&s.name, e))).collect();
    let headers: Vec<String> =
        ["experiment", "maps", "encoders", "metrics", "domain", "orientations", "effects", "resolution", "polar nodes"]
            .iter()
            .map(|s| s.to_string())
            .collect();
    md.push_str(&markdown::table_with(&headers, &rows, markdown::text_cell));
    md.push('\n');
}

/// An experiment's row of the settings table: its orientation sets and effect labels each
/// once, in first-use order.
fn settings_row(name: &str, e: &Experiment) -> Vec<String> {
    let mut orient: Vec<String> = Vec::new();
    for o in &e.orientations {
        if !orient.contains(&o.set) {
            orient.push(o.set.clone());
        }
    }
    let mut labels: Vec<String> = Vec::new();
    for c in crate::pipeline::runner::cases(e) {
        if !labels.contains(&c.effects_label) {
            labels.push(c.effects_label);
        }
    }
    vec![
        name.to_string(),
        e.maps.len().to_string(),
        e.encoders.iter().map(|n| n.name.clone()).collect::<Vec<_>>().join(", "),
        e.metrics.iter().map(|m| m.name()).collect::<Vec<_>>().join(", "),
        format!("{:?}", e.domain).to_lowercase(),
        if orient.is_empty() { "-".into() } else { orient.join(", ") },
        labels.join(", "),
        format!("{}x{}", e.resolution.0, e.resolution.1),
        e.polar_nodes.to_string(),
    ]
}

/// What the runs recorded of a map: its file, size and sha256.
type RecordedMap = (String, String, String);

/// The maps table: every map the experiments name, as the first table that records it
/// (section order) recorded it, with the experiments that name it; and a warning naming the
/// tables computed from a file with another checksum than that one.
fn maps_part(md: &mut String, named: &BTreeMap<String, Vec<String>>, records: &[RunRecord]) {
    md.push_str(
        "## Maps\n\nSHA-256 of the file each table was computed from, as its `provenance.toml` records it. \
         `probelab maps` lists the known maps missing on a machine and where to get them (docs/maps.md).\n\n",
    );
    let mut recorded: BTreeMap<String, RecordedMap> = BTreeMap::new();
    let mut mismatches = Vec::new();
    for (section, pr) in records {
        for r in &pr.maps {
            let first = recorded.entry(r.name.clone()).or_insert_with(|| {
                (
                    r.file.clone(),
                    crate::regression::provenance::size_and_exposure(r.width, r.height, r.exposure),
                    r.sha256.clone(),
                )
            });
            if first.2 != r.sha256 {
                mismatches.push(format!("`{section}`: its table used a map `{}` with another checksum", r.name));
            }
        }
    }
    let rows: Vec<Vec<String>> = named.iter().map(|(name, by)| map_row(name, by, recorded.get(name))).collect();
    let headers: Vec<String> = ["map", "file", "size", "sha256", "used by"].iter().map(|s| s.to_string()).collect();
    md.push_str(&markdown::table_with(&headers, &rows, markdown::text_cell));
    if !mismatches.is_empty() {
        let _ = writeln!(md, "\n**Warning:** {}.", mismatches.join("; "));
    }
    md.push('\n');
}

/// A map's row of the maps table: as recorded, else that no table records it.
fn map_row(name: &str, used_by: &[String], recorded: Option<&RecordedMap>) -> Vec<String> {
    match recorded {
        Some((file, size, sha)) => {
            vec![name.to_string(), format!("`{file}`"), size.clone(), format!("`{sha}`"), used_by.join(", ")]
        }
        None => vec![name.to_string(), "no table records it yet".into(), "-".into(), "-".into(), used_by.join(", ")],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names_are_safe() {
        assert_eq!(file_safe("a b/c.png"), "a_b_c.png");
    }
}
