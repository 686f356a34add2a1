//! One map's data for the explorer: its thumbnail, each encoder's stored-form sentence once
//! (`bases`), and per site domain the exact reference on
//! the grid and every encoder the committed tables show for the map, each with its stored
//! entries where the page evaluates it, else ([`PageForm::Grid`]) its E/π on the grid (as
//! steps from the reference).
//! Everything is E/π (FORMULAS §1); the grids are those of [`super::domains`].

use super::domains::{site_domains, Shows, SiteDomain};
use super::encode::{base64, f32_base64, i16_difference_base64, sig7};
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
    let mut bases = serde_json::Map::new();
    for d in site_domains() {
        let mut value = domain_data(&data, &d, encoders);
        share_bases(&mut value, &mut bases);
        domains.insert(d.label.to_string(), value);
    }
    Ok(json!({
        "name": map.name,
        "sha256": map.sha256,
        "size": [map.width(), map.height()],
        "thumbnail": format!("data:image/png;base64,{}", base64(&thumb)),
        "domains": domains,
        "bases": bases,
    }))
}

/// Moves each row's `basis` (the stored form's sentence, the same for an encoder on every
/// domain) into `bases`, keyed by encoder name, once per map; a row whose sentence differs from
/// the one kept keeps its own.
fn share_bases(domain: &mut Value, bases: &mut serde_json::Map<String, Value>) {
    let Some(rows) = domain.get_mut("encoders").and_then(Value::as_array_mut) else { return };
    for row in rows {
        let (Some(name), Some(basis)) = (row["name"].as_str().map(str::to_string), row.get("basis").cloned()) else {
            continue;
        };
        let kept = bases.entry(name).or_insert_with(|| basis.clone());
        if *kept == basis {
            row.as_object_mut().map(|o| o.remove("basis"));
        }
    }
}

/// One domain: the reference on its grid and every encoder it shows ([`SiteDomain::shows`]; on
/// the sphere, those that need no surface normal). A page-evaluated encoding ships its stored
/// entries; a grid encoding ships its values instead, as int16 steps from the reference
/// ([`i16_difference_base64`]; its stored form is `probelab fit --format json`'s, and the page
/// has no use for it).
fn domain_data(data: &MapData, d: &SiteDomain, encoders: &[&NamedEncoder]) -> Value {
    let case = d.case();
    let cd = CaseData::new(data, &case, DEFAULT_POLAR_NODES);
    let grid = d.grid();
    let reference = cd.reference_on(&grid);
    let reference_flat: Vec<f64> = reference.iter().flat_map(|v| v.to_array()).collect();
    let input = cd.fit_input();
    let rows: Vec<Value> = encoders
        .iter()
        .filter(|e| d.normal.is_some() || !e.encoder.needs_surface_normal())
        .filter_map(|e| {
            let fit = e.encoder.fit(&input);
            let stored = fit.stored();
            let form = page_form(&stored);
            if d.shows == Shows::SurfaceAndPage && !e.encoder.needs_surface_normal() && form != PageForm::ShIrradiance {
                return None;
            }
            let mut row = json!({
                "name": e.name,
                "family": e.encoder.family().label(),
                "stored_scalars": e.encoder.stored_scalars(),
                "storage": e.encoder.storage(&input),
                "form": form.name(),
                "basis": stored.basis,
            });
            if form == PageForm::Grid {
                let values: Vec<f64> =
                    evaluate(fit.as_ref(), &grid.normals).iter().flat_map(|v| v.to_array()).collect();
                let (coded, scale) = i16_difference_base64(&values, &reference_flat);
                row["differences"] = Value::String(coded);
                row["scale"] = json!(scale);
            } else {
                let entries: Vec<Value> = stored
                    .entries
                    .iter()
                    .map(|s| {
                        json!([
                            s.name,
                            s.unit.label(),
                            s.role.to_string(),
                            s.value.components().into_iter().map(sig7).collect::<Vec<_>>()
                        ])
                    })
                    .collect();
                row["entries"] = Value::Array(entries);
            }
            Some(row)
        })
        .collect();
    json!({
        "reference": f32_base64(reference_flat.iter().copied()),
        "encoders": rows,
    })
}
