//! The report: comparison sheets, charts and `results/REPORT.md`, generated from the result
//! CSVs and the maps — never written by hand. `probelab report` runs it; `probelab reproduce`
//! runs it last.
//!
//! Per experiment (`experiments/*.toml`, in file order), then per other folder of `results/`:
//! - the table (`table.csv`) as a map × encoder rmse pivot, a timing summary when `*_ns`
//!   columns exist, and the whole table;
//! - charts: rmse per encoder and map (dots or a heatmap), error against costs and `fit_ns` (when that column exists), one convergence
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
//! Files: `generate` (the run, REPORT.md put together), `options` (what the report is asked and
//! returns), `folders` (the result folders covered, their files, stale pictures), `maps` (the
//! experiments' maps as found and as recorded), `draw_sheets` (every experiment's sheets
//! written), `page` and `page_charts` (a result folder's page, its table and charts),
//! REPORT.md's parts: `opening`, `glance` (the claims at a glance), `paper_sections` (one per
//! paper, then the other results), `plans` (which folders and figures each paper section shows),
//! `ratios` (ratios to the baseline), `budgets` (the landscape by storage budget);
//! `provenance_page` (PROVENANCE.md), `names` (the pages' and files' names); `style` (the one
//! colour and marker of each encoder id, which every chart and the HTML viewer use); and the
//! pictures: `sheet` (comparison sheets of an
//! experiment), `strip` (the lightmap study's blending strips, drawn from the claims layer's
//! data), `claim_figures` (the claims pages' cut-down sheets and blending charts), `charts` (plotters charts), `markdown` (tables and links), `csvfile` (CSV read by
//! column name), `tone` (exposure, Reinhard, sRGB, the error colour scale), `number` (number
//! formatting), `text` (font and labels), `canvas` (pixel painting), `png` (PNG encoding and
//! atomic writing); `site` (the results viewer, `results/site/`).
//!
//! What this layer may use: the layer table of ARCHITECTURE.md (checked by
//! `tests/architecture.rs`).

mod budgets;
pub mod canvas;
pub mod charts;
pub mod claim_figures;
pub mod csvfile;
mod draw_sheets;
mod folders;
mod generate;
mod glance;
pub mod glyphs;
mod maps;
pub mod markdown;
mod names;
pub mod number;
mod opening;
mod options;
mod page;
mod page_charts;
mod paper_sections;
pub mod plans;
pub mod png;
mod provenance_page;
mod ratios;
pub mod sheet;
mod site;
pub mod strip;
pub(crate) mod style;
pub mod text;
pub mod tone;

pub use generate::generate;
pub use options::{Generated, Options};
