//! `probelab fit`'s document: the encoders checked against the surface before any map is
//! read, every fit's stored coefficients checked finite before anything is returned, and the
//! JSON document (`docs/commands.md`, `probelab fit`; the stored form is `docs/library.md`).

use super::json::{self, MapEntry};
use crate::api::{Fit, Lighting, Map, Stored, Surface};
use crate::encoders;
use anyhow::{bail, Result};

/// The encoder ids of the comma-separated `list` (`--encoders`), refused if one is unknown,
/// listed twice, or needs a surface normal while `surface` is the sphere.
pub fn encoder_ids(list: &str, surface: Surface) -> Result<Vec<String>> {
    let named = encoders::build_list(list)?;
    if surface == Surface::Sphere {
        if let Some(e) = named.iter().find(|e| e.encoder.needs_surface_normal()) {
            bail!(
                "--encoders: {}; pass --normal x,y,z (the surface normal N)",
                crate::encoders::encoder::surface_normal_refusal(&e.name)
            );
        }
    }
    Ok(named.into_iter().map(|e| e.name).collect())
}

/// Fits every encoder of `ids` (defaults) to `light`, with its stored coefficients; a stored
/// value that is not finite is an error naming the encoder and the light.
pub fn fit_all(light: &Lighting, ids: &[String]) -> Result<Vec<(Fit, Stored)>> {
    let mut fits = Vec::new();
    for id in ids {
        let fit = light.fit(id, "")?;
        let stored = fit.stored();
        if !stored.is_finite() {
            bail!("encoder '{id}' on {}: a stored value is not finite", light.describe());
        }
        fits.push((fit, stored));
    }
    Ok(fits)
}

/// `sphere`, or `hemisphere` when the light is seen from a surface normal.
pub fn domain_of(light: &Lighting) -> &'static str {
    if light.normal().is_some() {
        "hemisphere"
    } else {
        "sphere"
    }
}

/// The fits as one JSON document (`docs/json.md`, `probelab.fit/1`): the map (asked for as
/// `given`) with its identity, domain, normal, what they were fitted on, units, and each
/// fit's stored entries and diagnostics.
pub fn to_json(given: &str, map: &Map, light: &Lighting, fits: &[(Fit, Stored)]) -> Result<String> {
    let fits: Vec<serde_json::Value> = fits
        .iter()
        .map(|(f, s)| {
            serde_json::json!({
                "encoder": f.id(),
                "stored_scalars": f.stored_scalars(),
                "basis": s.basis,
                "entries": s.entries,
                "diagnostics": json::diagnostics_of(&f.diagnostics()),
            })
        })
        .collect();
    let doc = serde_json::json!({
        "schema": json::FIT,
        "maps": json::maps(&[MapEntry::from_map(given, map.env_map())]),
        "domain": domain_of(light),
        "normal": light.normal().map(|n| n.to_array()),
        "fitted_on": light.describe(),
        "units": "E/pi is irradiance over pi; directions are world-space unit vectors, +Y up \
                  (docs/conventions.md section 1); SH follow section 2",
        "fits": fits,
    });
    json::text(&doc)
}
