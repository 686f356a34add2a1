//! The site's index: the maps that have data, the domains with their grids (normals, solid-angle
//! weights, frame), every encoder's colour and marker (the one style table, `report::style`),
//! the families in legend order, and the diverging colour map of the sheets (`report::tone`).

use super::domains::{site_domains, Shows, SITE_RESOLUTION};
use super::encode::f32_base64;
use crate::encoders::Family;
use crate::report::style::style_of;
use crate::report::tone::diverging;
use serde_json::{json, Value};

/// The index for `maps` (names, in order, each with a data file) and `encoders` (every encoder
/// name any map shows).
pub(super) fn index_data(maps: &[String], encoders: &[String]) -> Value {
    let domains: Vec<Value> = site_domains()
        .iter()
        .map(|d| {
            let g = d.grid();
            json!({
                "label": d.label,
                "normal": d.normal.map(|n| n.to_array()),
                "every_encoder": d.shows == Shows::Every,
                "frame": d.frame(),
                "resolution": [g.resolution.0, g.resolution.1],
                "normals": f32_base64(g.normals.iter().flat_map(|n| n.to_array())),
                "weights": g.weights,
            })
        })
        .collect();
    let styles: serde_json::Map<String, Value> = encoders
        .iter()
        .map(|e| {
            let s = style_of(e);
            (e.clone(), json!({ "colour": s.hex(), "marker": s.marker.name(), "family": s.family.label() }))
        })
        .collect();
    // The diverging map is linear between its nine classes at v = −1, −0.75, …, 1.
    let knots: Vec<[u8; 3]> = (0..=8).map(|k| diverging(-1.0 + k as f64 / 4.0)).collect();
    json!({
        "maps": maps,
        "resolution": [SITE_RESOLUTION.0, SITE_RESOLUTION.1],
        "domains": domains,
        "families": Family::ALL.iter().map(|f| f.label()).collect::<Vec<_>>(),
        "styles": styles,
        "diverging": knots,
    })
}
