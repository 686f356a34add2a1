//! Radiance `EXPOSURE=` on the loaded map (`envmap::load`): the header's exposures multiply, the
//! pixels are divided by their product as Radiance does, and an exposure of 1 changes nothing.
//! A bad exposure is refused through the binary (`tests/map_headers.rs`).

#[path = "../../tests/common/hdr_files.rs"]
mod hdr_files;

use crate::envmap::load::load;
use hdr_files::hdr_with;

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
