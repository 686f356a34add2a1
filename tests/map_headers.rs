//! Map headers that would make a decoder allocate more than the file holds, windows that are
//! not the lat-long sphere, Radiance `EXPOSURE=`, `COLORCORR=`, `PRIMARIES=`, `PIXASPECT=` and
//! line ends, EXR chromaticities, pixel aspect and channel names, and which files `maps`
//! considers. Every file
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

/// An 8x4 EXR map of one colour, with its image attributes (chromaticities, pixel aspect) set
/// by `attributes`.
fn exr_with(path: &Path, rgb: (f32, f32, f32), attributes: impl FnOnce(&mut exr::prelude::ImageAttributes)) {
    use exr::prelude::WritableImage;
    let channels = exr::prelude::SpecificChannels::rgb(move |_: exr::prelude::Vec2<usize>| rgb);
    let layer = exr::prelude::Layer::new(
        (8, 4),
        exr::prelude::LayerAttributes::default(),
        exr::prelude::Encoding::UNCOMPRESSED,
        channels,
    );
    let mut image = exr::prelude::Image::from_layer(layer);
    attributes(&mut image.attributes);
    image.write().to_file(path).unwrap();
}

/// ACES AP0 (SMPTE ST 2065-1) as an EXR `chromaticities` attribute.
fn ap0() -> exr::prelude::attribute::Chromaticities {
    use exr::prelude::Vec2;
    exr::prelude::attribute::Chromaticities {
        red: Vec2(0.7347, 0.2653),
        green: Vec2(0.0, 1.0),
        blue: Vec2(0.0001, -0.077),
        white: Vec2(0.32168, 0.33767),
    }
}

/// An EXR in ACES AP0 primaries once gave the numbers of Rec.709. It is converted: the texels
/// are the published AP0 → Rec.709 (Bradford) matrix times the file's values (products worked
/// out by hand below), the conversion is recorded in the table's provenance, and a colour
/// outside Rec.709's gamut is refused naming its pixel. A pixel aspect other than 1 is refused.
#[test]
fn exr_primaries_are_converted_to_rec709_and_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("aces.exr");
    exr_with(&path, (0.2, 0.3, 0.4), |a| a.chromaticities = Some(ap0()));
    let map = probelab::Map::load(path.to_str().unwrap(), repo()).unwrap();
    // The published matrix (six decimals) [2.521686 -1.134130 -0.387556; -0.276479 1.372719
    // -0.096240; -0.015378 -0.152975 1.168353] x (0.2, 0.3, 0.4):
    let want = [0.0090758, 0.3180239, 0.4183731];
    for (got, want) in map.texels()[0].iter().zip(want) {
        assert!((f64::from(*got) - want).abs() < 2e-6, "{:?} against {want:?}", map.texels()[0]);
    }
    // Recorded in provenance.
    let exp = dir.path().join("aces_run.toml");
    fs::write(&exp, format!("maps = [{:?}]\nencoders = [\"sh1\"]\n", path.to_str().unwrap())).unwrap();
    let root = dir.path().to_str().unwrap();
    let out = probelab().args(["--no-timing", "--root", root, "run", exp.to_str().unwrap()]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let prov = fs::read_to_string(dir.path().join("results/aces_run/provenance.toml")).unwrap();
    assert!(
        prov.contains("colour = \"converted from primaries R(0.7347,0.2653) G(0,1) B(0.0001,-0.077) white(0.32168,0.33767) to Rec.709"),
        "{prov}"
    );
    // Pure AP0 red has a negative green in Rec.709: refused, not clipped.
    let red = dir.path().join("aces_red.exr");
    exr_with(&red, (1.0, 0.0, 0.0), |a| a.chromaticities = Some(ap0()));
    refused(&red, &["not Rec.709", "pixel x=0, y=0 is outside Rec.709's gamut", "G = -2.76"]);
    // Rec.709 chromaticities change nothing.
    let same = dir.path().join("rec709.exr");
    let rec709 = exr::prelude::attribute::Chromaticities {
        red: exr::prelude::Vec2(0.64, 0.33),
        green: exr::prelude::Vec2(0.30, 0.60),
        blue: exr::prelude::Vec2(0.15, 0.06),
        white: exr::prelude::Vec2(0.3127, 0.3290),
    };
    exr_with(&same, (0.2, 0.3, 0.4), |a| a.chromaticities = Some(rec709));
    let map = probelab::Map::load(same.to_str().unwrap(), repo()).unwrap();
    assert_eq!(map.texels()[0], [0.2, 0.3, 0.4]);
    let wide = dir.path().join("wide_pixels.exr");
    exr_with(&wide, (0.2, 0.3, 0.4), |a| a.pixel_aspect = 2.0);
    refused(&wide, &["pixel aspect ratio 2", "square in angle"]);
}

/// Radiance's `COLORCORR=` is applied as `EXPOSURE=` is, per channel (the pixel values are
/// divided by the products); `PRIMARIES=` other than Rec.709 are converted (AP0 makes the
/// file's colours leave Rec.709's gamut: refused at pixel 0,0); `PIXASPECT=` must be 1; CR LF
/// line ends are refused as a text-mode copy.
#[test]
fn radiance_colour_variables_and_line_ends() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cc.hdr");
    hdr_with(&path, "EXPOSURE=2\nCOLORCORR=2 4 0.5\nCOLORCORR=1 2 1\n");
    let map = probelab::Map::load(path.to_str().unwrap(), repo()).unwrap();
    // Divided by 2·2, 2·8, 2·0.5: texel 0 is (0.5, 0.25, 4), the others (1, 2, 3).
    assert_eq!(map.texels()[0], [0.125, 0.015625, 4.0]);
    assert_eq!(map.texels()[1], [0.25, 0.125, 3.0]);
    for bad in ["COLORCORR=1 1\n", "COLORCORR=1 0 1\n", "COLORCORR=1 nan 1\n", "PRIMARIES=0.64 0.33\n"] {
        hdr_with(&path, bad);
        refused(&path, &["Radiance header line 2:", "expected"]);
    }
    hdr_with(&path, "PRIMARIES=0.640 0.330 0.300 0.600 0.150 0.060 0.3127 0.3290\n");
    let map = probelab::Map::load(path.to_str().unwrap(), repo()).unwrap();
    assert_eq!(map.texels()[1], [1.0, 2.0, 3.0]);
    hdr_with(&path, "PRIMARIES=0.7347 0.2653 0 1 0.0001 -0.077 0.32168 0.33767\n");
    refused(&path, &["not Rec.709", "pixel x=0, y=0 is outside Rec.709's gamut"]);
    hdr_with(&path, "PIXASPECT=1.0\n");
    assert!(probelab::Map::load(path.to_str().unwrap(), repo()).is_ok());
    hdr_with(&path, "PIXASPECT=0.5\n");
    refused(&path, &["Radiance header line 2: PIXASPECT=0.5", "square in angle"]);
    hdr_with(&path, "");
    let bytes = fs::read(&path).unwrap();
    let at = bytes.iter().position(|&b| b == b'\n').unwrap();
    fs::write(&path, [&bytes[..at], b"\r", &bytes[at..]].concat()).unwrap();
    refused(&path, &["Radiance header line 1 ends in CR LF", "converted as text"]);
}

/// Two channels named R: the first used to win. Refused, naming the channel. An EXR with the
/// multi-part bit set on a single-part file was reported as truncated; it is now said so.
#[test]
fn ambiguous_channels_and_a_stray_multipart_bit_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("two_r.exr");
    {
        use exr::prelude::*;
        let channel = |name: &str| AnyChannel::new(name, FlatSamples::F32(vec![1.0; 32]));
        let list = SmallVec::from_vec(vec![channel("B"), channel("G"), channel("R"), channel("S")]);
        let layer = Layer::new((8, 4), LayerAttributes::default(), Encoding::UNCOMPRESSED, AnyChannels::sort(list));
        Image::from_layer(layer).write().to_file(&path).unwrap();
    }
    let mut bytes = fs::read(&path).unwrap();
    let at = bytes.windows(3).position(|w| w == b"\0S\0").unwrap() + 1;
    bytes[at] = b'R';
    fs::write(&path, bytes).unwrap();
    refused(&path, &["channel 'R' appears 2 times", "ambiguous"]);

    let flagged = dir.path().join("flagged.exr");
    small_exr(&flagged);
    let mut bytes = fs::read(&flagged).unwrap();
    bytes[5] |= 0x10;
    fs::write(&flagged, bytes).unwrap();
    refused(&flagged, &["multi-part bit (0x1000) is set", "lacks the attributes every part"]);
}

/// 100,000 attributes (2 MB) were refused only after the run-time estimate's header parse had
/// taken 80 MB. The header is now read under its limits first, by every path: `eval` and `run`
/// refuse the file with their address space capped at 48 MiB (the earlier parse failed to
/// allocate there and aborted).
#[cfg(unix)]
#[test]
fn a_hundred_thousand_attributes_are_refused_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.exr");
    small_exr(&good);
    let many: Vec<u8> = (0..100_000).flat_map(|k| attribute(&format!("a{k}"), "int", &7i32.to_le_bytes())).collect();
    let path = dir.path().join("attrs.exr");
    fs::write(&path, with_attributes(&fs::read(&good).unwrap(), &many)).unwrap();
    let exp = dir.path().join("attrs_run.toml");
    fs::write(&exp, format!("maps = [{:?}]\nencoders = [\"sh1\"]\n", path.to_str().unwrap())).unwrap();
    let root = dir.path().to_str().unwrap();
    for args in
        [vec!["eval", path.to_str().unwrap(), "--encoders", "sh1"], vec!["--root", root, "run", exp.to_str().unwrap()]]
    {
        let out = std::process::Command::new("sh")
            .arg("-c")
            .arg("ulimit -v 49152 && exec \"$@\"")
            .arg("sh")
            .arg(env!("CARGO_BIN_EXE_probelab"))
            .args(&args)
            .env_remove("PROBELAB_ENVMAPS")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains("more than the limit of 1024 attributes"), "{args:?}: {err}");
    }
}
