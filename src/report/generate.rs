//! The report run: the folders, the maps, the sheets, every folder's page, then REPORT.md
//! (opening, claims at a glance, paper sections, other results) and PROVENANCE.md.

use super::csvfile::CsvTable;
use super::draw_sheets::draw_sheets;
use super::folders::sections;
use super::glance::at_a_glance;
use super::maps::{map_uses, mismatches, named_maps};
use super::names::{CLAIMS_CSV, PROVENANCE_PAGE};
use super::opening::opening;
use super::options::{Generated, Options};
use super::page::{write_pages, Page};
use super::paper_sections::{other_results, paper_sections};
use super::plans::{parse_plans, PLAN_FILE};
use super::provenance_page::{provenance, run_records, RunRecord};
use anyhow::{bail, Context, Result};

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
    let site = super::site::write_site(opts, &sections, &maps)?;
    let missing = maps.iter().filter(|(_, u)| u.is_none()).map(|(m, _)| m.clone()).collect();
    Ok(Generated {
        report,
        pictures: sheet_pictures + page_pictures,
        kept,
        missing,
        mismatches: mismatches(&maps, &records),
        site_rewritten: site.rewritten,
    })
}

/// REPORT.md's text: the opening, the claims at a glance, one section per paper and the other
/// results. Reads the claims declarations (`experiments/claims/`), the paper sections' plans
/// ([`PLAN_FILE`]) and the engine's CLAIMS.csv.
pub(super) fn report_md(opts: &Options, records: &[RunRecord], named: usize, pages: &[Page]) -> Result<String> {
    let out = opts.out;
    let decl_dir = opts.root.join("experiments").join(crate::claims::declaration::DIR);
    let papers = if decl_dir.is_dir() {
        crate::claims::declaration::load_papers(&opts.root.join("experiments"))?
    } else {
        Vec::new()
    };
    // The paper sections' plans; none when the file is absent (a section per declared paper only).
    let plan_file = opts.root.join("experiments").join(PLAN_FILE);
    let plans = match std::fs::read_to_string(&plan_file) {
        Ok(text) => parse_plans(&text, &plan_file)?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Vec::new(),
        Err(e) => bail!("{}: cannot read: {e}", plan_file.display()),
    };
    let claims_csv = out.join(CLAIMS_CSV);
    let claims = if claims_csv.is_file() { Some(CsvTable::read(&claims_csv)?) } else { None };
    let mut doc = opening(records, named, &papers, &plans);
    doc.push_str(&at_a_glance(&papers, claims.as_ref())?);
    doc.push_str(&paper_sections(out, &papers, &plans, pages)?);
    let planned: Vec<&str> = plans.iter().flat_map(|p| p.pages.iter().map(String::as_str)).collect();
    doc.push_str(&other_results(pages, &planned));
    Ok(doc)
}
