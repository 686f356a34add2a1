//! `probelab fit`: fits encoders to one map and prints each fit's stored coefficients (names,
//! units, roles and basis) and what it was fitted on, as JSON or CSV; everything is checked
//! before anything is printed. Nothing is written and no lock is taken.

use super::context::Env;
use anyhow::{bail, Context, Result};
use probelab::api::{Fit, Lighting, Map, Role, Stored, Surface};
use probelab::encoders;
use probelab::io::output;

/// `probelab fit`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Map name (on the search path) or file path.
    map: String,
    /// Comma-separated encoder ids (see `probelab encoders`).
    #[arg(long)]
    encoders: String,
    /// The surface normal N as x,y,z (world space, +Y up; normalised): fit to the light above
    /// its horizon, about N. Without it the fit is a probe's, on the whole sphere.
    #[arg(long)]
    normal: Option<String>,
    /// `json` or `csv` (one row per stored or derived value).
    #[arg(long, default_value = "json")]
    format: String,
}

pub fn run(a: Args, env: &Env) -> Result<i32> {
    if a.format != "json" && a.format != "csv" {
        bail!("--format '{}': expected json or csv", a.format);
    }
    let surface = match &a.normal {
        None => Surface::Sphere,
        Some(text) => Surface::Normal(parse_normal(text)?),
    };
    let named = encoders::build_list(&a.encoders)?;
    if surface == Surface::Sphere {
        if let Some(e) = named.iter().find(|e| e.encoder.needs_surface_normal()) {
            bail!(
                "--encoders: {}; pass --normal x,y,z (the surface normal N)",
                probelab::encoders::encoder::surface_normal_refusal(&e.name)
            );
        }
    }
    let map = Map::load_on(&env.search, &a.map)?;
    let light = map.lighting(surface)?;
    let mut fits = Vec::new();
    for e in &named {
        let fit = light.fit(&e.name, "")?;
        let stored = fit.stored();
        if !stored.is_finite() {
            bail!("encoder '{}' on {}: a stored value is not finite", e.name, light.describe());
        }
        fits.push((fit, stored));
    }
    let text = if a.format == "json" { to_json(&map, &light, &fits)? } else { to_csv(&map, &light, &fits)? };
    output::write(text.as_bytes())?;
    Ok(0)
}

/// `sphere`, or `hemisphere` when the light is seen from a surface normal.
fn domain_of(light: &Lighting) -> &'static str {
    if light.normal().is_some() {
        "hemisphere"
    } else {
        "sphere"
    }
}

/// The fits as one JSON document: the map, domain, normal, what they were fitted on, units,
/// and each fit's stored entries.
fn to_json(map: &Map, light: &Lighting, fits: &[(Fit, Stored)]) -> Result<String> {
    let fits: Vec<serde_json::Value> = fits
        .iter()
        .map(|(f, s)| {
            serde_json::json!({
                "encoder": f.id(),
                "stored_scalars": f.stored_scalars(),
                "basis": s.basis,
                "entries": s.entries,
            })
        })
        .collect();
    let (w, h) = map.size();
    let doc = serde_json::json!({
        "map": map.name(),
        "size": [w, h],
        "domain": domain_of(light),
        "normal": light.normal().map(|n| n.to_array()),
        "fitted_on": light.describe(),
        "units": "E/pi is irradiance over pi; directions are world-space unit vectors, +Y up \
                  (docs/conventions.md section 1); SH follow section 2",
        "fits": fits,
    });
    Ok(serde_json::to_string_pretty(&doc)? + "\n")
}

/// The fits as CSV: one row per stored or derived entry, its value's components in v0..v2.
fn to_csv(map: &Map, light: &Lighting, fits: &[(Fit, Stored)]) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["map", "domain", "normal", "encoder", "entry", "role", "unit", "kind", "v0", "v1", "v2", "basis"])?;
    let normal_cell = light.normal().map(|n| format!("{} {} {}", n.x, n.y, n.z)).unwrap_or_default();
    for (f, s) in fits {
        for e in &s.entries {
            let mut c: Vec<String> = e.value.components().iter().map(|v| format!("{v}")).collect();
            c.resize(3, String::new());
            let role = match e.role {
                Role::Stored => "stored",
                Role::Derived => "derived",
            };
            w.write_record([
                map.name(),
                domain_of(light),
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

/// A surface normal `x,y,z`: three finite numbers, not all zero.
fn parse_normal(text: &str) -> Result<glam::DVec3> {
    let bad = || anyhow::anyhow!("--normal '{text}': expected x,y,z, three finite numbers not all zero (e.g. 0,1,0)");
    let v: Vec<f64> = text.split(',').map(|p| p.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| bad())?;
    let [x, y, z] = v[..] else {
        return Err(bad());
    };
    let n = glam::DVec3::new(x, y, z);
    if !n.is_finite() || n.length_squared() == 0.0 {
        return Err(bad());
    }
    Ok(n)
}
