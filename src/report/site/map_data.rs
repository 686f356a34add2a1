//! One map's data for the explorer: its thumbnail, and per site domain the exact reference on
//! the grid and every encoder the committed tables show for the map, each with its stored
//! form and, where the page cannot evaluate it ([`PageForm::Grid`]), its E/π on the grid.
//! Everything is E/π (FORMULAS §1); the grids are those of [`super::domains`].

use super::domains::{site_domains, SiteDomain};
use super::encode::{base64, f32_base64, sig7};
use super::evaluable::{page_form, PageForm};
use crate::encoders::NamedEncoder;
use crate::envmap::EnvMap;
use crate::pipeline::runner::{evaluate, CaseData, MapData};
use crate::reference::exact::DEFAULT_POLAR_NODES;
use anyhow::Result;
use serde_json::{json, Value};

/// The thumbnail's width in pixels (its height is half): small enough for every map to ship one.
pub(super) const THUMB_WIDTH: u32 = 96;

/// The explorer's data for `map` and the encoders the tables show for it (in table order).
pub(super) fn map_data(map: &EnvMap, encoders: &[&NamedEncoder]) -> Result<Value> {
    let thumb = crate::report::png::png_bytes(&crate::report::sheet::latlong_thumbnail(map, THUMB_WIDTH))?;
    let data = MapData::new(map);
    let mut domains = serde_json::Map::new();
    for d in site_domains() {
        domains.insert(d.label.to_string(), domain_data(&data, &d, encoders));
    }
    Ok(json!({
        "name": map.name,
        "sha256": map.sha256,
        "size": [map.width(), map.height()],
        "thumbnail": format!("data:image/png;base64,{}", base64(&thumb)),
        "domains": domains,
    }))
}

/// One domain: the reference on its grid and every encoder defined there (on the sphere, those
/// that need no surface normal).
fn domain_data(data: &MapData, d: &SiteDomain, encoders: &[&NamedEncoder]) -> Value {
    let case = d.case();
    let cd = CaseData::new(data, &case, DEFAULT_POLAR_NODES);
    let grid = d.grid();
    let reference = cd.reference_on(&grid);
    let input = cd.fit_input();
    let rows: Vec<Value> = encoders
        .iter()
        .filter(|e| d.normal.is_some() || !e.encoder.needs_surface_normal())
        .map(|e| {
            let fit = e.encoder.fit(&input);
            let stored = fit.stored();
            let form = page_form(&stored);
            let entries: Vec<Value> = stored
                .entries
                .iter()
                .map(|s| json!([s.name, s.unit.label(), s.role.to_string(), s.value.components().into_iter().map(sig7).collect::<Vec<_>>()]))
                .collect();
            let mut row = json!({
                "name": e.name,
                "family": e.encoder.family().label(),
                "stored_scalars": e.encoder.stored_scalars(),
                "storage": e.encoder.storage(&input),
                "form": form.name(),
                "basis": stored.basis,
                "entries": entries,
            });
            if form == PageForm::Grid {
                let values = evaluate(fit.as_ref(), &grid.normals);
                row["values"] = Value::String(f32_base64(values.iter().flat_map(|v| v.to_array())));
            }
            row
        })
        .collect();
    json!({
        "reference": f32_base64(reference.iter().flat_map(|v| v.to_array())),
        "encoders": rows,
    })
}
