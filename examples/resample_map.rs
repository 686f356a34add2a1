//! Writes a map resampled to another size, as the size benchmarks make their maps
//! (benches/README.md):
//!
//! ```text
//! cargo run --release --example resample_map -- SOURCE.exr WIDTHxHEIGHT OUT.exr
//! ```
//!
//! Smaller targets are averaged down (as the shared maps were made), larger ones take the
//! nearest texel ([`probelab::Map::resized`]). The output is a half-float ZIP OpenEXR, the
//! format of most published HDRIs ([`probelab::Map::write_exr_half`]). Prints `wrote OUT (WxH)`.

use anyhow::{bail, Context};
use probelab::Map;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [src, size, out] = args.as_slice() else {
        bail!("usage: resample_map SOURCE.exr WIDTHxHEIGHT OUT.exr");
    };
    let (w, h) = size
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<usize>().ok()?, h.parse::<usize>().ok()?)))
        .context("WIDTHxHEIGHT: two whole numbers, e.g. 4096x2048")?;
    let map = Map::load(src, ".")?;
    let resized = map.resized(w, h)?;
    drop(map);
    resized.write_exr_half(out)?;
    println!("wrote {out} ({w}x{h})");
    Ok(())
}
