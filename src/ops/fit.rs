//! `probelab fit`: the encoders checked against the surface before any map is read, every
//! fit's stored coefficients checked finite before anything is returned, and the two
//! documents it prints: JSON (`docs/json.md`, `probelab.fit/1`; the stored form is
//! `docs/library.md`) and CSV, one row per stored or derived value (`docs/commands.md`,
//! `probelab fit`). Nothing is written and no lock is taken.

use super::context::Env;
use super::json::{self, MapEntry};
use super::source::MapSource;
use crate::api::{DVec3, Fit, Lighting, Role, Stored, Surface};
use crate::encoders;
use anyhow::{bail, Context, Result};

/// The options of `probelab fit`.
#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// The map fitted.
    pub map: MapSource,
    /// Comma-separated encoder ids (`--encoders`).
    pub encoders: String,
    /// The whole sphere (a probe's fit), or the light above a surface's horizon (`--normal`).
    pub surface: Surface,
}

/// What `probelab fit` computed: every fit with its stored coefficients, and what they were
/// fitted on.
pub struct Fitted {
    /// The map read, with its identity.
    pub map: MapEntry,
    /// The surface normal N the light was seen from; `None` on the sphere.
    pub normal: Option<DVec3>,
    /// What the fits were fitted on, for a reader (`api::Lighting::describe`).
    pub fitted_on: String,
    /// Each encoder's fit and its stored coefficients, in the order asked for.
    pub fits: Vec<(Fit, Stored)>,
}

/// `probelab fit`: the encoders checked ([`encoder_ids`]), then the map opened on `env.search`,
/// then every encoder fitted to its light.
pub fn fit(env: &Env, o: &FitOptions) -> Result<Fitted> {
    let ids = encoder_ids(&o.encoders, o.surface)?;
    let map = o.map.open(&env.search)?;
    let light = map.lighting(o.surface)?;
    let fits = fit_all(&light, &ids)?;
    Ok(Fitted {
        map: MapEntry::from_map(o.map.given(), map.env_map()),
        normal: light.normal(),
        fitted_on: light.describe(),
        fits,
    })
}

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
fn fit_all(light: &Lighting, ids: &[String]) -> Result<Vec<(Fit, Stored)>> {
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

impl Fitted {
    /// `sphere`, or `hemisphere` when the light is seen from a surface normal.
    pub fn domain(&self) -> &'static str {
        if self.normal.is_some() {
            "hemisphere"
        } else {
            "sphere"
        }
    }

    /// The fits as one JSON document (`docs/json.md`, `probelab.fit/1`): the map (as asked
    /// for) with its identity, domain, normal, what they were fitted on, units, and each fit's
    /// stored entries and diagnostics.
    pub fn to_json(&self) -> Result<String> {
        let fits: Vec<serde_json::Value> = self
            .fits
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
            "maps": json::maps(std::slice::from_ref(&self.map)),
            "domain": self.domain(),
            "normal": self.normal.map(|n| n.to_array()),
            "fitted_on": self.fitted_on,
            "units": "E/pi is irradiance over pi; directions are world-space unit vectors, +Y up \
                      (docs/conventions.md section 1); SH follow section 2",
            "fits": fits,
        });
        json::text(&doc)
    }

    /// The fits as CSV: one row per stored or derived entry, its value's components in v0..v2.
    pub fn to_csv(&self) -> Result<String> {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record([
            "map", "domain", "normal", "encoder", "entry", "role", "unit", "kind", "v0", "v1", "v2", "basis",
        ])?;
        let normal_cell = self.normal.map(|n| format!("{} {} {}", n.x, n.y, n.z)).unwrap_or_default();
        for (f, s) in &self.fits {
            for e in &s.entries {
                let mut c: Vec<String> = e.value.components().iter().map(|v| format!("{v}")).collect();
                c.resize(3, String::new());
                let role = match e.role {
                    Role::Stored => "stored",
                    Role::Derived => "derived",
                };
                w.write_record([
                    &self.map.name,
                    self.domain(),
                    &normal_cell,
                    f.id(),
                    &e.name,
                    role,
                    e.unit.label(),
                    e.value.kind(),
                    &c[0],
                    &c[1],
                    &c[2],
                    &s.basis,
                ])?;
            }
        }
        Ok(String::from_utf8(w.into_inner().context("writing CSV")?)?)
    }
}

/// A surface normal given as text `x,y,z` (the command line's `--normal`): three finite numbers,
/// checked by `api::unit_normal`; an error echoes the text as given.
pub fn parse_normal(text: &str) -> Result<DVec3> {
    let shown = crate::math::echo::value(text);
    let bad = || anyhow::anyhow!("--normal '{shown}': expected x,y,z, three finite numbers (e.g. 0,1,0)");
    let v: Vec<f64> = text.split(',').map(|p| p.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| bad())?;
    let [x, y, z] = v[..] else {
        return Err(bad());
    };
    crate::api::unit_normal(DVec3::new(x, y, z)).with_context(|| format!("--normal '{shown}'"))
}
