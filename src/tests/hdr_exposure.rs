//! Radiance `EXPOSURE=` on the loaded map (`envmap::load`): the header's exposures multiply, the
//! pixels are divided by their product as Radiance does, and an exposure of 1 changes nothing.
//! A bad exposure is refused through the binary (`tests/map_headers.rs`).

use crate::envmap::load::load;
use std::fs;
use std::path::Path;

/// A Radiance file of 8x4 texels, each (1, 2, 3) but texel 0, which is (0.5, 0.25, 4): values
/// RGBE stores exactly. `header` lines go after the signature line.
fn hdr_with(path: &Path, header: &str) {
    use image::codecs::hdr::HdrEncoder;
    let px: Vec<image::Rgb<f32>> =
        (0..32).map(|k| image::Rgb(if k == 0 { [0.5, 0.25, 4.0] } else { [1.0, 2.0, 3.0] })).collect();
    let mut bytes = Vec::new();
    HdrEncoder::new(&mut bytes).encode(&px, 8, 4).unwrap();
    let at = bytes.iter().position(|&b| b == b'\n').unwrap() + 1;
    bytes.splice(at..at, header.bytes());
    fs::write(path, bytes).unwrap();
}

#[test]
fn hdr_exposure_divides_the_pixels_as_radiance_does() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain.hdr");
    hdr_with(&plain, "");
    let map = load(&plain).unwrap();
    assert_eq!((map.exposure, map.texel(0, 0), map.texel(1, 0)), (1.0, [0.5, 0.25, 4.0], [1.0, 2.0, 3.0]));
    // Three EXPOSURE lines: 2 × 4 × 0.5 = 4, so every value is a quarter of what the file holds.
    let exposed = dir.path().join("exposed.hdr");
    hdr_with(&exposed, "EXPOSURE=2\nEXPOSURE=   4.0\nEXPOSURE=0.5\n");
    let map = load(&exposed).unwrap();
    assert_eq!(map.exposure, 4.0);
    assert_eq!(map.texel(0, 0), [0.125, 0.0625, 1.0]);
    assert_eq!(map.texel(5, 3), [0.25, 0.5, 0.75]);
    // A written exposure of 1 (as the peer tool's probes carry) changes nothing.
    let one = dir.path().join("one.hdr");
    hdr_with(&one, "EXPOSURE=          1.0000000000000\n");
    assert_eq!(load(&one).unwrap().texels(), load(&plain).unwrap().texels());
}
