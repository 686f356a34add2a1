//! Scores two encoders against the exact reference on a committed CC0 map, with the public API
//! only (docs/library.md):
//!
//! ```text
//! cargo run --release --example compare [ENCODER_A] [ENCODER_B] [MAP]
//! ```
//!
//! The encoders default to `sh1` and `zh3_solved_shared`, the map to `blender_city_256x128`.
//! Each is scored on the whole sphere (or, if either needs a surface normal, on the hemisphere
//! about N = +Y) over a 128×64 lat-long grid of normals, solid-angle weighted: the `exact`
//! metric of the result tables. One line per encoder:
//! `ENCODER rmse=… rel_rmse=… stored_scalars=…`.

use probelab::{needs_surface_normal, DVec3, Map, Surface};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let a = args.first().map_or("sh1", String::as_str);
    let b = args.get(1).map_or("zh3_solved_shared", String::as_str);
    let map_name = args.get(2).map_or("blender_city_256x128", String::as_str);

    let map = Map::load(map_name, env!("CARGO_MANIFEST_DIR"))?;
    let surface =
        if needs_surface_normal(a)? || needs_surface_normal(b)? { Surface::Normal(DVec3::Y) } else { Surface::Sphere };
    let light = map.lighting(surface)?;
    println!("on {}", light.describe());
    for id in [a, b] {
        let fit = light.fit(id, "")?;
        let s = light.score(&fit, (128, 64))?;
        println!("{id} rmse={} rel_rmse={} stored_scalars={}", s.rmse, s.rel_rmse, fit.stored_scalars());
    }
    Ok(())
}
