//! Fits one encoder to a committed CC0 map and prints its stored coefficients, with the public
//! API only (docs/library.md):
//!
//! ```text
//! cargo run --release --example fit_map [MAP] [ENCODER] [SETTINGS]
//! ```
//!
//! MAP defaults to `blender_city_256x128` (in envmaps/), ENCODER to `zh3_solved_shared`,
//! SETTINGS (the encoder's TOML keys) to none. An encoder that needs a surface normal is fitted
//! about N = +Y.

use probelab::{needs_surface_normal, DVec3, Map, Role, Surface};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let map_name = args.first().map_or("blender_city_256x128", String::as_str);
    let id = args.get(1).map_or("zh3_solved_shared", String::as_str);
    let settings = args.get(2).map_or("", String::as_str);

    let map = Map::load(map_name, env!("CARGO_MANIFEST_DIR"))?;
    let surface = if needs_surface_normal(id)? { Surface::Normal(DVec3::Y) } else { Surface::Sphere };
    let light = map.lighting(surface)?;
    let fit = light.fit(id, settings)?;
    let stored = fit.stored();

    println!("{id} fitted on {}", light.describe());
    println!("basis: {}", stored.basis);
    println!("stored scalars: {}", stored.scalar_count());
    for e in &stored.entries {
        let role = if e.role == Role::Stored { "stored" } else { "derived" };
        let values: Vec<String> = e.value.components().iter().map(|v| format!("{v:.6}")).collect();
        println!("  {role:7} {:14} {:9} {}", e.name, e.unit.label(), values.join(" "));
    }
    let n = light.normal().unwrap_or(DVec3::Y);
    println!("E/pi at {n}: fit {}, exact {}", fit.irradiance(n), light.reference(&[n])[0]);
    Ok(())
}
