//! Map headers that would make a decoder allocate more than the file holds, windows that are
//! not the lat-long sphere, Radiance `EXPOSURE=`, and which files `maps` considers. Every file
//! is made in a temporary folder; every refusal goes through the binary (`probelab eval FILE`):
//! exit 2, an error naming the file and the limit or rule, nothing on stdout.

mod common;

use common::harness::{map_from_fn, probelab, repo};
use common::hdr_files::hdr_with;
use std::fs;
use std::path::Path;
use std::process::Output;

/// An 8x4 map of ones written as EXR at `path`.
fn small_exr(path: &Path) {
    map_from_fn("m", 8, 4, |_, _| [1.0, 1.0, 1.0]).write_exr(path).unwrap();
}

/// `bytes` with `attributes` inserted at the start of the header (after magic and version).
fn with_attributes(bytes: &[u8], attributes: &[u8]) -> Vec<u8> {
    [&bytes[..8], attributes, &bytes[8..]].concat()
}

/// One OpenEXR attribute: name, type, size, value.
fn attribute(name: &str, kind: &str, value: &[u8]) -> Vec<u8> {
    let size = i32::try_from(value.len()).unwrap().to_le_bytes();
    [name.as_bytes(), b"\0", kind.as_bytes(), b"\0", &size, value].concat()
}

/// Rewrites the window attribute `key` (`dataWindow` or `displayWindow`) of the EXR at `path`.
fn patch_window(path: &Path, key: &str, window: [i32; 4]) {
    let mut bytes = fs::read(path).unwrap();
    let tag = format!("{key}\0box2i\0");
    let at = bytes.windows(tag.len()).position(|w| w == tag.as_bytes()).unwrap() + tag.len() + 4;
    for (k, v) in window.iter().enumerate() {
        bytes[at + 4 * k..at + 4 * k + 4].copy_from_slice(&v.to_le_bytes());
    }
    fs::write(path, bytes).unwrap();
}

/// `probelab eval FILE` must refuse: exit 2, the file named, every one of `words` said.
fn refused(path: &Path, words: &[&str]) -> String {
    let out: Output = probelab().args(["eval", path.to_str().unwrap(), "--encoders", "sh1"]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{}: {err}", path.display());
    assert!(err.contains(&path.display().to_string()), "the error does not name the file: {err}");
    for w in words {
        assert!(err.contains(w), "the error lacks '{w}': {err}");
    }
    assert!(out.stdout.is_empty());
    err
}

#[test]
fn an_exr_header_longer_than_4_mib_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.exr");
    small_exr(&good);
    let bytes = fs::read(&good).unwrap();
    // One attribute declaring 5 MiB: refused from its size field.
    let one = dir.path().join("one_big_attribute.exr");
    fs::write(&one, with_attributes(&bytes, &attribute("comments", "string", &vec![b'x'; 5 << 20]))).unwrap();
    refused(&one, &["OpenEXR header is longer than the limit of 4194304 bytes", "attribute 'comments'"]);
    // Fifty of 100 KiB: refused when their sum passes the limit.
    let many: Vec<u8> =
        (0..50).flat_map(|k| attribute(&format!("note{k}"), "string", &vec![b'y'; 100 << 10])).collect();
    let sum = dir.path().join("many_attributes.exr");
    fs::write(&sum, with_attributes(&bytes, &many)).unwrap();
    refused(&sum, &["OpenEXR header is longer than the limit of 4194304 bytes"]);
}

#[test]
fn a_million_attributes_are_refused_at_the_1025th() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.exr");
    small_exr(&good);
    let bytes = fs::read(&good).unwrap();
    let million: Vec<u8> =
        (0..1_000_000).flat_map(|k| attribute(&format!("a{k}"), "int", &7i32.to_le_bytes())).collect();
    let path = dir.path().join("million.exr");
    fs::write(&path, with_attributes(&bytes, &million)).unwrap();
    refused(&path, &["more than the limit of 1024 attributes"]);
    // A thousand (with the file's own, within 1024) are read on, to the map.
    let ok = dir.path().join("thousand.exr");
    let mut attributes = exr::prelude::LayerAttributes::default();
    for k in 0..1000 {
        attributes.other.insert(format!("a{k}").as_str().into(), exr::prelude::AttributeValue::I32(7));
    }
    let channels = exr::prelude::SpecificChannels::rgb(|_: exr::prelude::Vec2<usize>| (1.0f32, 1.0f32, 1.0f32));
    let layer = exr::prelude::Layer::new((8, 4), attributes, exr::prelude::Encoding::UNCOMPRESSED, channels);
    use exr::prelude::WritableImage;
    exr::prelude::Image::from_layer(layer).write().to_file(&ok).unwrap();
    if let Err(e) = probelab::Map::load(ok.to_str().unwrap(), repo()) {
        panic!("{e:#}");
    }
}

#[test]
fn a_radiance_header_longer_than_64_kib_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("long.hdr");
    let mut text = b"#?RADIANCE\n".to_vec();
    for k in 0..7000 {
        text.extend(format!("# comment line {k}\n").bytes());
    }
    text.extend(b"FORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n");
    text.extend([128u8, 128, 128, 129].repeat(32));
    assert!(text.len() > 65536);
    fs::write(&path, text).unwrap();
    refused(&path, &["Radiance HDR header is longer than the limit of 65536 bytes"]);
}

#[test]
fn inverted_windows_hold_no_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let x = dir.path().join("inverted_x.exr");
    small_exr(&x);
    patch_window(&x, "dataWindow", [7, 0, 0, 3]);
    let err = refused(&x, &["data window (7,0)-(0,3) is inverted (x max < x min): it holds no pixel"]);
    assert!(!err.contains("truncated"), "{err}");
    let y = dir.path().join("inverted_y.exr");
    small_exr(&y);
    patch_window(&y, "displayWindow", [0, 3, 7, 0]);
    refused(&y, &["display window (0,3)-(7,0) is inverted (y max < y min): it holds no pixel"]);
}

#[test]
fn a_data_window_other_than_the_display_window_is_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let part = dir.path().join("part_of_the_sphere.exr");
    small_exr(&part);
    patch_window(&part, "displayWindow", [0, 0, 15, 7]);
    refused(&part, &["data window (0,0)-(7,3) differs from display window (0,0)-(15,7)"]);
    // Shifted by one texel: the same size, not the same sphere.
    let shifted = dir.path().join("shifted.exr");
    small_exr(&shifted);
    patch_window(&shifted, "displayWindow", [1, 0, 8, 3]);
    refused(&shifted, &["data window (0,0)-(7,3) differs from display window (1,0)-(8,3)"]);
    // Too large is said before the windows are compared.
    let huge = dir.path().join("huge.exr");
    small_exr(&huge);
    patch_window(&huge, "dataWindow", [0, 0, 99_999, 49_999]);
    let err = refused(&huge, &["100000x50000", "above the limit of 16384x8192"]);
    assert!(!err.contains("differs"), "{err}");
}

#[test]
fn a_map_larger_than_the_memory_limit_is_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.exr");
    small_exr(&path);
    // 8x4 texels at 13 bytes: 416 bytes.
    let out = probelab().args(["eval", path.to_str().unwrap()]).env("PROBELAB_MAP_MEMORY", "415").output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("m.exr: a 8x4 map needs 416 bytes") && err.contains("PROBELAB_MAP_MEMORY"), "{err}");
    let out = probelab().args(["eval", path.to_str().unwrap()]).env("PROBELAB_MAP_MEMORY", "416").output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// A bad `EXPOSURE=` is refused through the binary; what a good one does to the pixels is
/// checked on the loaded map (`src/tests/hdr_exposure.rs`).
#[test]
fn bad_hdr_exposures_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for bad in ["0", "-2", "nan", "inf", "1e300\nEXPOSURE=1e300"] {
        let path = dir.path().join("bad_exposure.hdr");
        hdr_with(&path, &format!("EXPOSURE={bad}\n"));
        refused(&path, &["EXPOSURE=", "expected a positive finite number"]);
    }
}

#[test]
fn maps_considers_regular_files_with_either_extension_in_any_case() {
    let dir = tempfile::tempdir().unwrap();
    let maps = dir.path().join("maps");
    fs::create_dir(&maps).unwrap();
    let big = map_from_fn("up", 512, 256, |i, j| [1.0 + (i % 7) as f32, 0.5 + (j % 3) as f32, 0.25]);
    big.write_exr(maps.join("UPPER.EXR")).unwrap();
    fs::create_dir(maps.join("folder.exr")).unwrap();
    #[cfg(unix)]
    {
        let fifo = std::ffi::CString::new(maps.join("x.exr").to_str().unwrap()).unwrap();
        // SAFETY: `fifo` is a NUL-terminated path that outlives the call.
        assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o600) }, 0);
    }
    let out = probelab().args(["maps"]).env("PROBELAB_ENVMAPS", &maps).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("  UPPER.EXR\n"), "{text}");
    assert!(!text.contains("folder.exr") && !text.contains("x.exr"), "{text}");

    let out_dir = dir.path().join("out");
    let out = probelab()
        .args(["maps", "import", maps.to_str().unwrap(), "--out", out_dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out_dir.join("UPPER_256x128.exr").is_file());
    let names: Vec<_> = fs::read_dir(&out_dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 1, "{names:?}");

    // The FIFO itself, named as a map, is refused without opening it.
    #[cfg(unix)]
    refused(&maps.join("x.exr"), &["is not a regular file"]);
}
