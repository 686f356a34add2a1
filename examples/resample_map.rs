//! Writes a map resampled to another size, as the size benchmarks make their maps
//! (benches/README.md):
//!
//! ```text
//! cargo run --release --example resample_map -- SOURCE.exr WIDTHxHEIGHT OUT.exr
//! ```
//!
//! Smaller targets are averaged down (`envmap::resample::downsample`, as the shared maps were
//! made), larger ones take the nearest texel (`envmap::resample::nearest`). The output is a
//! half-float ZIP OpenEXR, the format of most published HDRIs. Prints `wrote OUT (WxH)`.

use anyhow::{bail, Context};
use probelab::envmap::{load, resample};
use std::path::Path;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [src, size, out] = args.as_slice() else {
        bail!("usage: resample_map SOURCE.exr WIDTHxHEIGHT OUT.exr");
    };
    let (w, h) = size
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<usize>().ok()?, h.parse::<usize>().ok()?)))
        .context("WIDTHxHEIGHT: two whole numbers, e.g. 4096x2048")?;
    let map = load::load(Path::new(src))?;
    let resized = resample::resized(&map, w, h).map_err(anyhow::Error::msg)?;
    drop(map);
    load::write_exr_half(Path::new(out), &resized)?;
    println!("wrote {out} ({w}x{h})");
    Ok(())
}
