//! Fits one encoder to a committed CC0 map and prints its stored coefficients, with the public
//! API only (docs/library.md):
//!
//! ```text
//! cargo run --release --example fit_map [MAP] [ENCODER] [SETTINGS]
//! ```
//!
//! MAP defaults to `blender_city_256x128` (in envmaps/), ENCODER to `zh3_solved_shared`,
//! SETTINGS (the encoder's TOML keys) to none (the encoder's defaults). An encoder that needs
//! a surface normal is fitted about N = +Y. The first line says what was fitted, on what, and
//! with which settings.

use probelab::{needs_surface_normal, DVec3, Map, Role, Surface};

fn main() -> probelab::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let map_name = args.first().map_or("blender_city_256x128", String::as_str);
    let id = args.get(1).map_or("zh3_solved_shared", String::as_str);
    let settings = args.get(2).map_or("", String::as_str);

    let map = Map::load(map_name, env!("CARGO_MANIFEST_DIR"))?;
    let surface = if needs_surface_normal(id)? { Surface::Normal(DVec3::Y) } else { Surface::Sphere };
    let light = map.lighting(surface)?;
    let fit = light.fit(id, settings)?;
    let stored = fit.stored();

    let shown = if settings.trim().is_empty() { "the encoder's defaults" } else { settings };
    println!("{id} fitted on {}, settings: {shown}", light.describe());
    println!("basis: {}", stored.basis);
    println!("stored scalars: {}", stored.scalar_count());
    for e in &stored.entries {
        println!("  {:7} {:14} {:9} {:.6}", e.role, e.name, e.unit, e.value);
    }
    let stored_values = stored.entries.iter().filter(|e| e.role == Role::Stored).count();
    println!("({stored_values} stored entries; the derived ones are recomputed at decode time)");
    let n = light.normal().unwrap_or(DVec3::Y);
    println!("E/pi at {n}: fit {}, exact {}", fit.irradiance(n), light.reference(&[n])[0]);
    Ok(())
}
