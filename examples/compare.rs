//! Scores two encoders against the exact reference on a committed CC0 map, with the public API
//! only (docs/library.md):
//!
//! ```text
//! cargo run --release --example compare [ENCODER_A] [ENCODER_B] [MAP]
//! ```
//!
//! The encoders default to `sh1` and `zh3_solved_shared`, the map to `blender_city_256x128`.
//! Each is scored on the whole sphere (or, if either needs a surface normal, on the hemisphere
//! about N = +Y) over the default 256×128 lat-long grid of normals (`probelab eval`'s, so the
//! numbers are the command line's), solid-angle weighted: the `exact` metric of the result
//! tables. It prints what it scored on (map, domain, grid), then one line per encoder:
//! `ENCODER rmse=… rel_rmse=… stored_scalars=…`.

use probelab::{needs_surface_normal, DVec3, Map, Surface, DEFAULT_RESOLUTION};

fn main() -> probelab::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let a = args.first().map_or("sh1", String::as_str);
    let b = args.get(1).map_or("zh3_solved_shared", String::as_str);
    let map_name = args.get(2).map_or("blender_city_256x128", String::as_str);

    let map = Map::load(map_name, env!("CARGO_MANIFEST_DIR"))?;
    let surface =
        if needs_surface_normal(a)? || needs_surface_normal(b)? { Surface::Normal(DVec3::Y) } else { Surface::Sphere };
    let light = map.lighting(surface)?;
    let (w, h) = DEFAULT_RESOLUTION;
    println!("on {}", light.describe());
    println!("scored over {w}x{h} normals (probelab eval's default grid), solid-angle weighted, in E/pi");
    for id in [a, b] {
        let fit = light.fit(id, "")?;
        let s = light.score(&fit, DEFAULT_RESOLUTION)?;
        println!("{id} rmse={} rel_rmse={} stored_scalars={}", s.rmse, s.rel_rmse, fit.stored_scalars());
    }
    Ok(())
}
