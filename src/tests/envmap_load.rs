//! Tests of `envmap::load`: round trips, accepted encodings, and every rejection,
//! each triggered by a file generated in a temporary folder; and the shared maps load.

use super::repository::{repo, shared_envmaps, PAPER_PROBES};
use crate::envmap::header::{MAX_HEIGHT, MAX_WIDTH};
use crate::envmap::load::{load, write_exr, LoadError};
use crate::envmap::EnvMap;
use exr::math::RoundingMode;
use exr::prelude::*;
use std::fs;
use std::path::{Path, PathBuf};

/// A small map with varied values: zero, subnormal, tiny, ordinary and huge.
fn sample_map(w: usize, h: usize) -> EnvMap {
    EnvMap::from_fn("sample", w, h, |i, j| {
        let k = (j * w + i) as f32;
        [k * 0.37 + 0.001, 1.0e-40 * (i as f32), 3.0e4 / (1.0 + k) + f32::EPSILON * k]
    })
    .unwrap()
}

/// Writes an uncompressed scanline EXR with arbitrary f32 channels (no checks on values).
fn write_f32_channels(path: &Path, w: usize, h: usize, channels: &[(&str, Vec<f32>)]) {
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> =
        channels.iter().map(|(name, v)| AnyChannel::new(*name, FlatSamples::F32(v.clone()))).collect();
    let layer = Layer::new((w, h), LayerAttributes::default(), Encoding::UNCOMPRESSED, AnyChannels::sort(list));
    Image::from_layer(layer).write().to_file(path).unwrap();
}

/// Writes an RGB f32 EXR from texels without validating them (for NaN/Inf/negatives).
fn write_rgb_unchecked(path: &Path, w: usize, h: usize, texels: &[[f32; 3]]) {
    let ch = |c: usize| texels.iter().map(|t| t[c]).collect::<Vec<_>>();
    write_f32_channels(path, w, h, &[("R", ch(0)), ("G", ch(1)), ("B", ch(2))]);
}

/// Loads `path`, expecting an error whose message starts with the path and contains
/// every keyword (case-insensitive). Returns the message.
fn expect_error(path: &Path, keywords: &[&str]) -> String {
    let err = match load(path) {
        Ok(m) => panic!("{} loaded as {}x{} but should fail", path.display(), m.width(), m.height()),
        Err(e) => e,
    };
    let msg = err.to_string();
    assert!(msg.starts_with(&path.display().to_string()), "message does not start with the path: {msg}");
    let lower = msg.to_lowercase();
    for k in keywords {
        assert!(lower.contains(&k.to_lowercase()), "message lacks '{k}': {msg}");
    }
    msg
}

fn tmp() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

/// Byte offset of the 16-byte value of the `dataWindow` box2i attribute in an EXR header.
fn data_window_offset(bytes: &[u8]) -> usize {
    let key = b"dataWindow\0box2i\0";
    let at = bytes.windows(key.len()).position(|w| w == key).expect("no dataWindow attribute");
    let size_at = at + key.len();
    assert_eq!(&bytes[size_at..size_at + 4], &16i32.to_le_bytes());
    size_at + 4
}

/// Rewrites the dataWindow of the EXR at `path` to (xmin, ymin, xmax, ymax).
fn patch_data_window(path: &Path, window: [i32; 4]) {
    let mut bytes = fs::read(path).unwrap();
    let off = data_window_offset(&bytes);
    for (k, v) in window.iter().enumerate() {
        bytes[off + 4 * k..off + 4 * k + 4].copy_from_slice(&v.to_le_bytes());
    }
    fs::write(path, bytes).unwrap();
}

#[test]
fn write_then_load_is_bit_exact() {
    let dir = tmp();
    let path = dir.path().join("round_trip.exr");
    let map = sample_map(64, 32);
    write_exr(&path, &map).unwrap();
    let back = load(&path).unwrap();
    assert_eq!((back.width(), back.height()), (64, 32));
    assert_eq!(back.name, "round_trip");
    assert_eq!(back.path.as_deref(), Some(path.as_path()));
    for (a, b) in map.texels().iter().zip(back.texels()) {
        for c in 0..3 {
            assert_eq!(a[c].to_bits(), b[c].to_bits());
        }
    }
    // The written file is single-part scanline f32 RGB with ZIP compression, and no
    // temporary file is left behind.
    let meta = MetaData::read_from_file(&path, false).unwrap();
    assert_eq!(meta.headers.len(), 1);
    let h = &meta.headers[0];
    assert_eq!(h.compression, Compression::ZIP16);
    assert!(!h.blocks.has_tiles());
    let names: Vec<String> = h.channels.list.iter().map(|c| c.name.to_string()).collect();
    assert_eq!(names, ["B", "G", "R"]);
    assert!(h.channels.list.iter().all(|c| c.sample_type == SampleType::F32));
    let entries: Vec<_> = fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(entries.len(), 1);
    // Overwriting an existing file works.
    write_exr(&path, &map.scaled(2.0)).unwrap();
    assert_eq!(load(&path).unwrap().texel(3, 2)[0], map.texel(3, 2)[0] * 2.0);
}

#[test]
fn write_into_missing_folder_fails_with_path() {
    let dir = tmp();
    let path = dir.path().join("no_such_folder").join("m.exr");
    let msg = write_exr(&path, &sample_map(4, 2)).unwrap_err().to_string();
    assert!(msg.starts_with(&path.display().to_string()), "{msg}");
}

#[test]
fn half_rgba_tiled_mipmapped_loads() {
    let dir = tmp();
    let (w, h) = (40, 20);
    let value = |x: usize, y: usize| {
        (
            f16::from_f32(x as f32 * 0.5),
            f16::from_f32(y as f32 * 0.25),
            f16::from_f32(1.0 / (1.0 + (x + y) as f32)),
            f16::from_f32(0.5), // alpha, ignored
        )
    };
    for (name, mip) in [("tiled", false), ("mip", true)] {
        let path = dir.path().join(format!("{name}.exr"));
        let encoding = Encoding {
            compression: Compression::ZIP16,
            blocks: Blocks::Tiles(Vec2(16, 8)),
            line_order: LineOrder::Increasing,
        };
        if !mip {
            let layer = Layer::new(
                (w, h),
                LayerAttributes::default(),
                encoding,
                SpecificChannels::rgba(|p: Vec2<usize>| value(p.x(), p.y())),
            );
            Image::from_layer(layer).write().to_file(&path).unwrap();
        } else {
            // Write mip levels with AnyChannels: level 0 holds the values above.
            let sizes: Vec<(usize, usize)> = std::iter::successors(Some((w, h)), |&(a, b)| {
                (a > 1 || b > 1).then(|| ((a / 2).max(1), (b / 2).max(1)))
            })
            .collect();
            let chan = |name: &str, pick: fn((f16, f16, f16, f16)) -> f16| {
                let levels: Vec<FlatSamples> = sizes
                    .iter()
                    .map(|&(lw, lh)| FlatSamples::F16((0..lw * lh).map(|k| pick(value(k % lw, k / lw))).collect()))
                    .collect();
                AnyChannel::new(name, Levels::Mip { rounding_mode: RoundingMode::Down, level_data: levels })
            };
            let list: SmallVec<[_; 4]> =
                [chan("R", |v| v.0), chan("G", |v| v.1), chan("B", |v| v.2), chan("A", |v| v.3)].into_iter().collect();
            let layer = Layer::new((w, h), LayerAttributes::default(), encoding, AnyChannels::sort(list));
            Image::from_layer(layer).write().to_file(&path).unwrap();
        }
        let map = load(&path).unwrap();
        assert_eq!((map.width(), map.height()), (w, h));
        for y in 0..h {
            for x in 0..w {
                let (r, g, b, _) = value(x, y);
                assert_eq!(map.texel(x, y), [r.to_f32(), g.to_f32(), b.to_f32()], "{name} {x},{y}");
            }
        }
    }
}

#[test]
fn offset_data_window_loads_relative_to_its_origin() {
    let dir = tmp();
    let path = dir.path().join("offset.exr");
    let layer = Layer::new(
        (8, 4),
        LayerAttributes::default().with_position(Vec2(-3, 7)),
        Encoding::SMALL_LOSSLESS,
        SpecificChannels::rgb(|p: Vec2<usize>| (p.x() as f32, p.y() as f32, 0.5f32)),
    );
    Image::from_layer(layer).write().to_file(&path).unwrap();
    let map = load(&path).unwrap();
    assert_eq!((map.width(), map.height()), (8, 4));
    assert_eq!(map.texel(5, 2), [5.0, 2.0, 0.5]);
}

#[test]
fn layer_prefixed_channels_load_when_unambiguous() {
    let dir = tmp();
    let (w, h) = (4, 2);
    let v = |k: f32| (0..w * h).map(|i| i as f32 + k).collect::<Vec<_>>();
    let path = dir.path().join("prefixed.exr");
    write_f32_channels(&path, w, h, &[("rgba.R", v(0.0)), ("rgba.G", v(0.1)), ("rgba.B", v(0.2)), ("rgba.A", v(9.0))]);
    let map = load(&path).unwrap();
    assert_eq!(map.texel(3, 1), [7.0, 7.1, 7.2]);

    // Unprefixed R, G, B take precedence over a layer's.
    let path = dir.path().join("both.exr");
    write_f32_channels(
        &path,
        w,
        h,
        &[("R", v(1.0)), ("G", v(1.0)), ("B", v(1.0)), ("d.R", v(5.0)), ("d.G", v(5.0)), ("d.B", v(5.0))],
    );
    assert_eq!(load(&path).unwrap().texel(0, 0), [1.0; 3]);

    // Two complete layers and no unprefixed set: ambiguous.
    let path = dir.path().join("two_layers.exr");
    write_f32_channels(
        &path,
        w,
        h,
        &[("a.R", v(1.0)), ("a.G", v(1.0)), ("a.B", v(1.0)), ("b.R", v(5.0)), ("b.G", v(5.0)), ("b.B", v(5.0))],
    );
    expect_error(&path, &["two_layers.exr", "ambiguous", "'a'", "'b'"]);

    // An incomplete layer: the missing channel is named with its prefix.
    let path = dir.path().join("incomplete.exr");
    write_f32_channels(&path, w, h, &[("rgba.R", v(0.0)), ("rgba.G", v(0.0)), ("Z", v(0.0))]);
    expect_error(&path, &["incomplete.exr", "missing channel(s) rgba.B", "has channels: Z, rgba.G, rgba.R"]);
}

#[test]
fn rejects_missing_channels_naming_them() {
    let dir = tmp();
    let path = dir.path().join("xyz.exr");
    let z = vec![0.5f32; 8];
    write_f32_channels(&path, 4, 2, &[("X", z.clone()), ("Y", z.clone()), ("Z", z.clone())]);
    expect_error(&path, &["xyz.exr", "missing channel(s) R, G, B", "has channels: X, Y, Z"]);

    let path = dir.path().join("r_only.exr");
    write_f32_channels(&path, 4, 2, &[("R", z.clone()), ("Y", z)]);
    expect_error(&path, &["r_only.exr", "missing channel(s) G, B", "R, Y"]);
}

#[test]
fn rejects_u32_channels() {
    let dir = tmp();
    let path = dir.path().join("ints.exr");
    let f = |name: &str| AnyChannel::new(name, FlatSamples::U32(vec![1u32; 8]));
    let list: SmallVec<[_; 4]> = [f("R"), f("G"), f("B")].into_iter().collect();
    let layer = Layer::new((4, 2), LayerAttributes::default(), Encoding::UNCOMPRESSED, AnyChannels::sort(list));
    Image::from_layer(layer).write().to_file(&path).unwrap();
    expect_error(&path, &["ints.exr", "unsigned integer", "channel R"]);
}

#[test]
fn rejects_bad_aspect() {
    let dir = tmp();
    for (w, h) in [(3, 1), (1, 1), (4, 4), (2, 3)] {
        let path = dir.path().join(format!("m{w}x{h}.exr"));
        write_rgb_unchecked(&path, w, h, &vec![[1.0; 3]; w * h]);
        expect_error(&path, &[&format!("m{w}x{h}.exr"), &format!("size {w}x{h}"), "2:1"]);
    }
}

#[test]
fn rejects_nan_inf_negative_with_first_pixel() {
    let dir = tmp();
    for (label, value, kind) in [
        ("nan", f32::NAN, "NaN"),
        ("inf", f32::INFINITY, "infinite"),
        ("neginf", f32::NEG_INFINITY, "infinite"),
        ("negative", -0.5, "negative"),
    ] {
        let path = dir.path().join(format!("{label}.exr"));
        let mut t = vec![[1.0f32; 3]; 8];
        t[5][1] = value; // x=1, y=1, G
        t[7][2] = value;
        write_rgb_unchecked(&path, 4, 2, &t);
        expect_error(&path, &[&format!("{label}.exr"), &format!("2 texel value(s) are {kind}"), "x=1, y=1, channel G"]);
    }
}

#[test]
fn rejects_truncated_files() {
    let dir = tmp();
    let good = dir.path().join("good.exr");
    write_exr(&good, &sample_map(64, 32)).unwrap();
    let bytes = fs::read(&good).unwrap();
    let header_end = data_window_offset(&bytes) + 16;
    for cut in [8, 20, header_end, bytes.len() / 2, bytes.len() - 100, bytes.len() - 1] {
        let path = dir.path().join(format!("cut{cut}.exr"));
        fs::write(&path, &bytes[..cut]).unwrap();
        expect_error(&path, &[&format!("cut{cut}.exr"), "truncated"]);
    }
    // Too short to hold a magic number.
    let path = dir.path().join("cut3.exr");
    fs::write(&path, &bytes[..3]).unwrap();
    expect_error(&path, &["cut3.exr", "magic", "3 byte(s)", "supported formats"]);
}

#[test]
fn rejects_bad_magic_and_unknown_formats() {
    let dir = tmp();
    let good = dir.path().join("good.exr");
    write_exr(&good, &sample_map(8, 4)).unwrap();
    let mut bytes = fs::read(&good).unwrap();
    bytes[0] ^= 0xff;
    let path = dir.path().join("flipped.exr");
    fs::write(&path, &bytes).unwrap();
    expect_error(&path, &["flipped.exr", "bad magic", "89 2f 31 01", "ends in .exr", "OpenEXR", "Radiance"]);

    let path = dir.path().join("notes.txt");
    fs::write(&path, b"hello world").unwrap();
    expect_error(&path, &["notes.txt", "unrecognised file format", "supported formats"]);

    // Content decides, not the extension: a valid EXR named .hdr loads.
    let path = dir.path().join("actually_exr.hdr");
    fs::copy(&good, &path).unwrap();
    assert_eq!(load(&path).unwrap().width(), 8);
}

#[test]
fn rejects_empty_file_directory_and_missing_file() {
    let dir = tmp();
    let path = dir.path().join("empty.exr");
    fs::write(&path, b"").unwrap();
    expect_error(&path, &["empty.exr", "empty"]);

    let path = dir.path().join("folder.exr");
    fs::create_dir(&path).unwrap();
    expect_error(&path, &["folder.exr", "directory"]);

    let path = dir.path().join("absent.exr");
    expect_error(&path, &["absent.exr", "cannot", "no such file"]);
}

/// Root reads a mode-000 file anyway, so this needs another user.
#[cfg(unix)]
#[test]
#[cfg_attr(mode_000_readable, ignore = "this user (root) can read a mode-000 file: run the tests as another user")]
fn rejects_unreadable_file() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tmp();
    let path = dir.path().join("secret.exr");
    write_exr(&path, &sample_map(8, 4)).unwrap();
    fs::set_permissions(&path, fs::Permissions::from_mode(0o000)).unwrap();
    assert!(fs::File::open(&path).is_err(), "this process reads a mode-000 file, but the build script could not");
    expect_error(&path, &["secret.exr", "permission denied"]);
    fs::set_permissions(&path, fs::Permissions::from_mode(0o600)).unwrap();
}

#[test]
fn rejects_multi_part_files() {
    let dir = tmp();
    let path = dir.path().join("two_parts.exr");
    let layer = |name: &str, v: f32| {
        Layer::new(
            (8, 4),
            LayerAttributes::named(name),
            Encoding::FAST_LOSSLESS,
            SpecificChannels::rgb(move |_: Vec2<usize>| (v, v, v)),
        )
    };
    let image = Image::empty(ImageAttributes::new(IntegerBounds::from_dimensions((8, 4))))
        .with_layer(layer("left", 1.0))
        .with_layer(layer("right", 2.0));
    image.write().to_file(&path).unwrap();
    expect_error(&path, &["two_parts.exr", "multi-part", "2 parts", "'left'", "'right'"]);
}

#[test]
fn rejects_absurd_header_size_without_allocating() {
    let dir = tmp();
    let good = dir.path().join("good.exr");
    write_exr(&good, &sample_map(8, 4)).unwrap();
    let bytes = fs::read(&good).unwrap();
    let cases: [(&str, [i32; 4], &[&str]); 4] = [
        ("huge", [0, 0, 999_999_999, 999_999_999], &["1000000000x1000000000", "above the limit", "refusing"]),
        ("wide", [0, 0, 32767, 16383], &["32768x16384", "limit"]),
        ("tall", [0, 0, 15, 8192], &["16x8193", "limit"]),
        ("negative_origin", [-500_000_000, -500_000_000, 499_999_999, 499_999_999], &["1000000000x1000000000"]),
    ];
    for (label, window, keywords) in cases {
        let path = dir.path().join(format!("{label}.exr"));
        fs::write(&path, &bytes).unwrap();
        patch_data_window(&path, window);
        let mut k = vec![format!("{label}.exr")];
        k.extend(keywords.iter().map(|s| s.to_string()));
        let k: Vec<&str> = k.iter().map(|s| s.as_str()).collect();
        let msg = expect_error(&path, &k);
        assert!(msg.contains(&format!("{MAX_WIDTH}x{MAX_HEIGHT}")), "{msg}");
    }
    // (A zero-size window cannot be expressed: the exr crate orders min and max. The zero
    // size check is exercised through a Radiance header below.)
}

#[test]
fn rejects_deep_flag() {
    // Set the "non-image (deep) parts" bit (bit 11 of the version field) of a valid file.
    let dir = tmp();
    let path = dir.path().join("deep.exr");
    write_exr(&path, &sample_map(8, 4)).unwrap();
    let mut bytes = fs::read(&path).unwrap();
    bytes[5] |= 0x08;
    fs::write(&path, bytes).unwrap();
    expect_error(&path, &["deep.exr", "deep"]);
}

#[test]
fn corrupted_files_never_panic() {
    // Deterministic byte corruption of valid files (ZIP scanline f32 EXR, RLE tiled half
    // EXR, run-length Radiance HDR): every outcome must be Ok or an error naming the file;
    // a decoder panic must come back as an error. PROBELAB_FUZZ_ROUNDS sets the number of
    // rounds per file (default 600).
    let rounds: usize = std::env::var("PROBELAB_FUZZ_ROUNDS").ok().and_then(|v| v.parse().ok()).unwrap_or(600);
    let dir = tmp();
    let zip = dir.path().join("zip.exr");
    write_exr(&zip, &sample_map(32, 16)).unwrap();
    let tiled = dir.path().join("tiled.exr");
    let layer = Layer::new(
        (32, 16),
        LayerAttributes::default(),
        Encoding::FAST_LOSSLESS,
        SpecificChannels::rgba(|p: Vec2<usize>| {
            (f16::from_f32(p.x() as f32), f16::from_f32(p.y() as f32), f16::ONE, f16::ONE)
        }),
    );
    Image::from_layer(layer).write().to_file(&tiled).unwrap();
    let hdr = dir.path().join("rle.hdr");
    let px: Vec<image::Rgb<f32>> = (0..32 * 16).map(|k| image::Rgb([(k % 13) as f32, 0.5, (k / 32) as f32])).collect();
    image::codecs::hdr::HdrEncoder::new(fs::File::create(&hdr).unwrap()).encode(&px, 32, 16).unwrap();

    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for source in [zip, tiled, hdr] {
        let bytes = fs::read(&source).unwrap();
        let path = dir.path().join(format!("fuzz_{}", source.file_name().unwrap().to_str().unwrap()));
        let (mut ok, mut failed, mut panicked) = (0, 0, 0);
        for round in 0..rounds {
            let mut b = bytes.clone();
            let flips = 1 + (next() % 4) as usize;
            for _ in 0..flips {
                // Half the rounds hit the header, where the structure lives.
                let limit = if round % 2 == 0 { 400.min(b.len()) } else { b.len() };
                let at = (next() as usize) % limit;
                b[at] = next() as u8;
            }
            if round % 5 == 4 {
                b.truncate((next() as usize) % b.len());
            }
            fs::write(&path, &b).unwrap();
            match load(&path) {
                Ok(m) => {
                    assert!(m.texels().iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
                    ok += 1
                }
                Err(e) => {
                    assert!(e.to_string().starts_with(&path.display().to_string()), "{e}");
                    if matches!(e, LoadError::DecoderPanic { .. }) {
                        panicked += 1;
                    }
                    failed += 1;
                }
            }
        }
        let said = format!("{}: {ok} loaded, {failed} rejected ({panicked} decoder panics caught)", path.display());
        assert_eq!(ok + failed, rounds, "{said}");
    }
}

#[test]
fn hdr_loads_and_corrupt_hdr_is_rejected() {
    use image::codecs::hdr::HdrEncoder;
    use image::Rgb;
    let dir = tmp();
    let (w, h) = (16, 8);
    let px: Vec<Rgb<f32>> =
        (0..w * h).map(|k| Rgb([0.25 * (k % 7) as f32, 2.0f32.powi((k % 5) as i32), 1.0])).collect();
    let path = dir.path().join("probe.hdr");
    HdrEncoder::new(fs::File::create(&path).unwrap()).encode(&px, w, h).unwrap();
    let map = load(&path).unwrap();
    assert_eq!((map.width(), map.height(), map.name.as_str()), (16, 8, "probe"));
    for (k, p) in px.iter().enumerate() {
        let t = map.texels()[k];
        for c in 0..3 {
            assert!((t[c] - p.0[c]).abs() <= 0.01 * p.0[c], "texel {k}: {t:?} vs {:?}", p.0);
        }
    }
    let good = fs::read(&path).unwrap();

    let bad = dir.path().join("bad_dims.hdr");
    fs::write(&bad, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y eight +X 16\n").unwrap();
    expect_error(&bad, &["bad_dims.hdr", "invalid Radiance HDR"]);

    let bad = dir.path().join("flipped.hdr");
    fs::write(&bad, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+Y 8 +X 16\n").unwrap();
    expect_error(&bad, &["flipped.hdr", "Radiance", "orientation"]);

    let bad = dir.path().join("short.hdr");
    fs::write(&bad, &good[..good.len() / 2]).unwrap();
    expect_error(&bad, &["short.hdr", "truncated"]);

    let bad = dir.path().join("header_only.hdr");
    fs::write(&bad, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n").unwrap();
    expect_error(&bad, &["header_only.hdr"]);

    let bad = dir.path().join("huge.hdr");
    fs::write(&bad, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000000 +X 200000000\n").unwrap();
    expect_error(&bad, &["huge.hdr", "200000000x100000000", "refusing"]);

    let bad = dir.path().join("zero.hdr");
    fs::write(&bad, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 0 +X 0\n").unwrap();
    expect_error(&bad, &["zero.hdr", "zero size (0x0)"]);

    let bad = dir.path().join("square.hdr");
    HdrEncoder::new(fs::File::create(&bad).unwrap()).encode(&[Rgb([1.0f32; 3]); 16], 4, 4).unwrap();
    expect_error(&bad, &["square.hdr", "2:1"]);
}

#[test]
fn errors_are_typed() {
    let dir = tmp();
    let path = dir.path().join("folder.exr");
    fs::create_dir(&path).unwrap();
    assert!(matches!(load(&path), Err(LoadError::IsDirectory { .. })));
}

/// Every real map of the shared folders (`*_256x128`, `wells_probulator`) loads as a finite,
/// non-negative 2:1 map, the paper probes among them, at their sizes.
#[test]
#[cfg_attr(
    not(shared_maps),
    ignore = "needs the paper probes (not CC0, not in the repository): set PROBELAB_ENVMAPS to a folder holding them, see envmaps/README.md"
)]
fn shared_probes_load() {
    let value = shared_envmaps(&PAPER_PROBES);
    let mut loaded = Vec::new();
    for dir in std::env::split_paths(&value).filter(|p| !p.as_os_str().is_empty()) {
        let Ok(entries) = fs::read_dir(&dir) else {
            panic!("PROBELAB_ENVMAPS names {}, which is not a readable folder", dir.display());
        };
        let mut files: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                let n = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
                n.ends_with("_256x128.exr") || n == "wells_probulator.exr"
            })
            .collect();
        files.sort();
        for f in files {
            let map = load(&f).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(map.width(), 2 * map.height(), "{}", f.display());
            assert!(map.texels().iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
            if map.name == "grace_256x128" || map.name == "wells_probulator" {
                assert_eq!((map.width(), map.height()), (256, 128), "{}", f.display());
            }
            loaded.push(map.name);
        }
    }
    for p in PAPER_PROBES {
        assert!(loaded.iter().any(|m| m == p), "{p} was not among the maps loaded: {loaded:?}");
    }
}

/// The CC0 maps committed in `envmaps/` (what a fresh clone has): each loads as a finite,
/// non-negative 256x128 map, `envmaps/README.md` credits exactly these files with each one's
/// sha256, and none of the paper probes (not CC0) is among them.
#[test]
fn committed_cc0_maps_load_and_match_their_readme() {
    let dir = repo().join("envmaps");
    let readme = fs::read_to_string(dir.join("README.md")).expect("envmaps/README.md");
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "exr" || e == "hdr"))
        .filter(|p| !p.file_name().unwrap().to_string_lossy().starts_with("gen_"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 14, "the 14 CC0 maps: {files:?}");
    for f in &files {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        for probe in ["ennis", "grace", "pisa", "uffizi", "wells"] {
            assert!(!name.starts_with(probe), "{name}: the paper probes are not CC0 and stay outside the repository");
        }
        let map = load(f).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((map.width(), map.height()), (256, 128), "{name}");
        assert!(map.texels().iter().flatten().all(|v| v.is_finite() && *v >= 0.0), "{name}");
        let sha = crate::envmap::load::sha256_hex(&fs::read(f).unwrap());
        let row = readme
            .lines()
            .find(|l| l.starts_with(&format!("| `{name}` |")))
            .unwrap_or_else(|| panic!("envmaps/README.md has no row for {name}"));
        assert!(row.contains(&format!("`{sha}`")), "{name}: README's sha256 is not the file's ({sha}): {row}");
        assert!(row.contains("Poly Haven"), "{name}: its row credits no source: {row}");
    }
    let rows = readme.lines().filter(|l| l.starts_with("| `") && l.contains("_256x128.exr` |")).count();
    assert_eq!(rows, files.len(), "README rows for files that are not here");
}
