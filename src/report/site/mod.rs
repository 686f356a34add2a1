//! The results viewer: a static site in `results/site/` (open `index.html` from disk, no server,
//! no network) written by the report run through [`write_site`]. Data ship as script files
//! (`window.PROBELAB_… = …`), never fetched, so the pages open from `file://`.
//!
//! Files: `domains` (the output grids the site shows: the domains, their normals and weights),
//! `map_data` (one map's data: thumbnail, reference grids, every encoder's stored
//! coefficients and, where the page cannot evaluate it, its values on the grid), `evaluable`
//! (which stored forms the page evaluates itself), `encode` (float arrays as base64 and the
//! script wrapper), `index_data` (the maps, encoder styles, families, grids and colour maps),
//! `claims_data` (the claims view), `claims_evidence` (each claim's figure and explorer
//! preset, from its declaration), `landscape_data` (the cost landscape), `assets` (the pages,
//! script and style sheet, compiled in), `write` (the run: compute, keep what a missing map
//! cannot recompute, rewrite only what changed).

mod assets;
mod claims_data;
mod claims_evidence;
mod domains;
mod encode;
mod evaluable;
mod index_data;
mod landscape_data;
mod map_data;
mod write;

pub(super) use write::write_site;
