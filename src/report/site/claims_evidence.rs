//! Each claim's evidence for the claims view, read from its declaration
//! (`experiments/claims/*.toml`, through `claims::declaration`), never written here: its figure
//! (the declared `figure`, else the sheet of the primary check's experiment for the claim's
//! first map that has one) and its explorer preset (the maps its checks name, the encoders they
//! judge and compare with, the domain that shows them all).

use super::domains::site_domains;
use crate::claims::declaration::{ClaimDecl, Paper, Source};
use crate::encoders::NamedEncoder;
use crate::report::names::file_safe;
use serde_json::{json, Value};
use std::collections::BTreeMap;

/// What the claims view needs besides CLAIMS.csv: per claim id, the paper's sentence (`quote`),
/// its figure and its preset.
pub(super) fn claims_evidence(
    papers: &[Paper],
    shown: &BTreeMap<String, Vec<&NamedEncoder>>,
    experiment_maps: &BTreeMap<String, Vec<String>>,
    listed: &[String],
    exists: &dyn Fn(&str) -> bool,
) -> Value {
    let mut by_id = serde_json::Map::new();
    for paper in papers {
        for claim in &paper.claims {
            let maps = claim_maps(paper, claim, experiment_maps, listed);
            let preset = preset(claim, &maps, shown);
            let figure = figure(claim, &maps, exists);
            by_id.insert(claim.id.clone(), json!({ "quote": claim.quote, "figure": figure, "preset": preset }));
        }
    }
    Value::Object(by_id)
}

/// The checks, the primary first.
fn checks_in_order(claim: &ClaimDecl) -> impl Iterator<Item = &crate::claims::declaration::CheckDecl> {
    claim.checks.iter().filter(|k| k.primary).chain(claim.checks.iter().filter(|k| !k.primary))
}

/// The maps the claim's checks name, the primary's first: a check's `maps`, else its named map
/// sets, else (for the set `all`) its experiment's maps or the paper's measurement maps; only
/// maps the site lists, each once.
fn claim_maps(
    paper: &Paper,
    claim: &ClaimDecl,
    experiment_maps: &BTreeMap<String, Vec<String>>,
    listed: &[String],
) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for k in checks_in_order(claim) {
        let mut named: Vec<String> = k.maps.clone().unwrap_or_default();
        if named.is_empty() {
            for set in &k.on {
                match paper.map_sets.get(set) {
                    Some(maps) => named.extend(maps.iter().cloned()),
                    None if set == "all" => named.extend(match &k.source {
                        Source::Experiment(n) => experiment_maps.get(n).cloned().unwrap_or_default(),
                        Source::Measure(_) => paper.measurement_maps.clone(),
                    }),
                    None => {}
                }
            }
        }
        for m in named {
            if listed.contains(&m) && !out.contains(&m) {
                out.push(m);
            }
        }
    }
    out
}

/// The explorer preset: the claim's maps, the encoders its checks judge and compare with that
/// the first map shows, and the first site domain that shows them all (the sphere unless one
/// needs a surface normal). None without a map or an encoder the site shows.
fn preset(claim: &ClaimDecl, maps: &[String], shown: &BTreeMap<String, Vec<&NamedEncoder>>) -> Value {
    let Some(first) = maps.first() else { return Value::Null };
    let on_map = shown.get(first).map(Vec::as_slice).unwrap_or_default();
    let mut encoders: Vec<&NamedEncoder> = Vec::new();
    for k in checks_in_order(claim) {
        for name in std::iter::once(&k.encoder).chain(k.baseline.iter()) {
            if let Some(e) = on_map.iter().find(|e| e.name == *name) {
                if !encoders.iter().any(|x| x.name == e.name) {
                    encoders.push(e);
                }
            }
        }
    }
    if encoders.is_empty() {
        return Value::Null;
    }
    let surface = encoders.iter().any(|e| e.encoder.needs_surface_normal());
    let domain = site_domains().into_iter().find(|d| d.normal.is_some() == surface).map_or("sphere", |d| d.label);
    json!({
        "maps": maps,
        "encoders": encoders.iter().map(|e| e.name.as_str()).collect::<Vec<_>>(),
        "domain": domain,
    })
}

/// The claim's figure under the results folder: the declared one, else the sheet
/// (`<experiment>/sheet_<map>.png`, or its first page) of the first check on an experiment table for the first of
/// the claim's maps that has one (`exists`: whether a path under the results folder is a file);
/// None when neither exists.
fn figure(claim: &ClaimDecl, maps: &[String], exists: &dyn Fn(&str) -> bool) -> Value {
    if let Some(f) = claim.figures.first() {
        return json!({ "image": f.image, "caption": f.caption });
    }
    for k in checks_in_order(claim) {
        let Source::Experiment(exp) = &k.source else { continue };
        for m in maps {
            // A long sheet is split into pages (`sheet_<map>_p1.png`, …): the first page.
            let whole = format!("{exp}/sheet_{}.png", file_safe(m));
            let first_page = format!("{exp}/sheet_{}_p1.png", file_safe(m));
            if let Some(image) = [whole, first_page].into_iter().find(|i| exists(i)) {
                let caption =
                    format!("the comparison sheet of {exp} for {m}: the reference, each encoding and its signed error");
                return json!({ "image": image, "caption": caption });
            }
        }
    }
    Value::Null
}
