//! A small Radiance `.hdr` test file with header lines of the test's choosing. Plain code,
//! shared by the binary's tests (`tests/map_headers.rs`) and the crate's
//! (`src/tests/hdr_exposure.rs`, which includes this file by path).

use std::fs;
use std::path::Path;

/// A Radiance file of 8x4 texels, each (1, 2, 3) but texel 0, which is (0.5, 0.25, 4): values
/// RGBE stores exactly. `header` lines go after the signature line.
pub fn hdr_with(path: &Path, header: &str) {
    use image::codecs::hdr::HdrEncoder;
    let px: Vec<image::Rgb<f32>> =
        (0..32).map(|k| image::Rgb(if k == 0 { [0.5, 0.25, 4.0] } else { [1.0, 2.0, 3.0] })).collect();
    let mut bytes = Vec::new();
    HdrEncoder::new(&mut bytes).encode(&px, 8, 4).unwrap();
    let at = bytes.iter().position(|&b| b == b'\n').unwrap() + 1;
    bytes.splice(at..at, header.bytes());
    fs::write(path, bytes).unwrap();
}
