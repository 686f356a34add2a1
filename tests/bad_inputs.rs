//! The bad-input corpus: `tests/bad_inputs/` holds one small file per kind of bad map,
//! written by [`generate`] below. Every one must make the `probelab` binary exit with code 2,
//! print an error naming the file and the fault, never panic, write no partial output, and
//! leave existing results byte-identical. A few kinds cannot live in git (a FIFO, a symlink
//! loop, an unreadable file) and are made in a temporary folder when the test runs.
//!
//! Regenerate the committed corpus with
//! `PROBELAB_REGEN_BAD_INPUTS=1 cargo test --test bad_inputs corpus_is_current`.
//!
//! Experiment files get the same treatment: unknown encoder, unknown effect, missing map,
//! malformed TOML, each pointing at the line.

mod common;

use common::harness::{map_from_fn, repo, snapshot, Scratch};
use exr::prelude::*;
use probelab::Map;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

fn corpus_dir() -> PathBuf {
    repo().join("tests").join("bad_inputs")
}

/// A small valid map.
fn good_map(w: usize) -> Map {
    map_from_fn("good", w, w / 2, |i, j| [0.25 + i as f32 * 0.5, 1.0 + j as f32, 0.5])
}

/// Writes `map` as the library writes an EXR ([`Map::write_exr`]).
fn write_exr(path: &Path, map: &Map) -> probelab::Result<()> {
    map.write_exr(path)
}

/// Writes an uncompressed scanline EXR with arbitrary f32 channels (no checks on values).
fn write_channels(path: &Path, w: usize, h: usize, channels: &[(&str, Vec<f32>)]) {
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> =
        channels.iter().map(|(name, v)| AnyChannel::new(*name, FlatSamples::F32(v.clone()))).collect();
    let layer = Layer::new((w, h), LayerAttributes::default(), Encoding::UNCOMPRESSED, AnyChannels::sort(list));
    Image::from_layer(layer).write().to_file(path).unwrap();
}

/// Writes an 8×4 RGB f32 EXR whose texel 5 (x = 5, y = 0) channel G is `v`.
fn write_with_texel(path: &Path, v: f32) {
    let mut g = vec![1.0f32; 32];
    g[5] = v;
    write_channels(path, 8, 4, &[("R", vec![1.0; 32]), ("G", g), ("B", vec![1.0; 32])]);
}

/// Rewrites the dataWindow (xmin, ymin, xmax, ymax) of an EXR file.
fn patch_data_window(path: &Path, window: [i32; 4]) {
    patch_window(path, b"dataWindow\0box2i\0", window)
}

/// Rewrites the window attribute `key` (name, type and their nulls) of an EXR file.
fn patch_window(path: &Path, key: &[u8], window: [i32; 4]) {
    let mut bytes = fs::read(path).unwrap();
    let at = bytes.windows(key.len()).position(|w| w == key).expect("dataWindow") + key.len() + 4;
    for (k, v) in window.iter().enumerate() {
        bytes[at + 4 * k..at + 4 * k + 4].copy_from_slice(&v.to_le_bytes());
    }
    fs::write(path, bytes).unwrap();
}

/// The offset table of a single-part OpenEXR file: its byte position and entry count. The table
/// follows the header's terminating null byte, and its first entry points just past it.
fn offset_table(bytes: &[u8]) -> (usize, usize) {
    let mut at = 8; // magic number and version
    while bytes[at] != 0 {
        let name_end = at + bytes[at..].iter().position(|&b| b == 0).unwrap();
        let type_end = name_end + 1 + bytes[name_end + 1..].iter().position(|&b| b == 0).unwrap();
        let size = i32::from_le_bytes(bytes[type_end + 1..type_end + 5].try_into().unwrap()) as usize;
        at = type_end + 5 + size;
    }
    let table = at + 1;
    let first = u64::from_le_bytes(bytes[table..table + 8].try_into().unwrap()) as usize;
    (table, (first - table) / 8)
}

/// Entry `k` of the offset table.
fn offset(bytes: &[u8], k: usize) -> usize {
    let (table, _) = offset_table(bytes);
    u64::from_le_bytes(bytes[table + 8 * k..table + 8 * k + 8].try_into().unwrap()) as usize
}

/// An 8×4 map of ones, uncompressed: one scanline per chunk, so 4 chunks.
fn write_ones(path: &Path) {
    let v = vec![1.0f32; 32];
    write_channels(path, 8, 4, &[("R", v.clone()), ("G", v.clone()), ("B", v)]);
}

/// Applies `edit` to the bytes of the file at `path`.
fn patch(path: &Path, edit: impl FnOnce(&mut Vec<u8>)) {
    let mut b = fs::read(path).unwrap();
    edit(&mut b);
    fs::write(path, b).unwrap();
}

fn write_hdr(path: &Path, w: usize, h: usize) {
    use image::codecs::hdr::HdrEncoder;
    let px: Vec<image::Rgb<f32>> = (0..w * h).map(|k| image::Rgb([(k % 5) as f32, 0.5, 1.0])).collect();
    HdrEncoder::new(fs::File::create(path).unwrap()).encode(&px, w, h).unwrap();
}

/// One kind of bad map: its file name in the corpus, how it is made, and the words (lower
/// case) the error must contain besides the file name.
struct Kind {
    file: &'static str,
    make: fn(&Path),
    fault: &'static [&'static str],
}

/// The committed corpus. Every entry is written by `make` into the corpus folder.
fn kinds() -> Vec<Kind> {
    [
        truncated_exr_kinds(),
        size_kinds(),
        texel_value_kinds(),
        channel_kinds(),
        exr_feature_kinds(),
        huge_header_kinds(),
        header_rule_kinds(),
        radiance_header_kinds(),
        chunk_layout_kinds(),
        not_a_map_kinds(),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// EXR files cut short: in the pixels, in the header.
fn truncated_exr_kinds() -> Vec<Kind> {
    vec![
        Kind {
            file: "truncated_pixels.exr",
            make: |p| {
                write_exr(p, &good_map(16)).unwrap();
                let b = fs::read(p).unwrap();
                fs::write(p, &b[..b.len() * 2 / 3]).unwrap();
            },
            fault: &["truncated"],
        },
        Kind {
            file: "truncated_header.exr",
            make: |p| {
                write_exr(p, &good_map(16)).unwrap();
                let b = fs::read(p).unwrap();
                fs::write(p, &b[..40]).unwrap();
            },
            fault: &["truncated"],
        },
    ]
}

/// Sizes that are not a 2:1 lat-long map: zero width, one texel, other aspects.
fn size_kinds() -> Vec<Kind> {
    vec![
        // A data window with x_max = x_min − 1 (zero width). The exr crate would read the box
        // with its corners ordered (as 2×4); the header is read first and refuses it.
        Kind {
            file: "zero_width_window.exr",
            make: |p| {
                write_exr(p, &good_map(8)).unwrap();
                patch_data_window(p, [0, 0, -1, 3]);
            },
            fault: &["data window (0,0)-(-1,3) is inverted (x max < x min): it holds no pixel"],
        },
        Kind {
            file: "zero_width.hdr",
            make: |p| fs::write(p, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 0\n").unwrap(),
            fault: &["zero size (0x4)"],
        },
        Kind {
            file: "one_by_one.exr",
            make: |p| write_channels(p, 1, 1, &[("R", vec![1.0]), ("G", vec![1.0]), ("B", vec![1.0])]),
            fault: &["size 1x1", "2:1"],
        },
        Kind {
            file: "aspect_3x1.exr",
            make: |p| {
                let v = vec![1.0f32; 3];
                write_channels(p, 3, 1, &[("R", v.clone()), ("G", v.clone()), ("B", v)])
            },
            fault: &["size 3x1", "2:1"],
        },
        Kind { file: "aspect_square.hdr", make: |p| write_hdr(p, 8, 8), fault: &["size 8x8", "2:1"] },
    ]
}

/// A texel that is not a finite non-negative radiance, named by its place and channel.
fn texel_value_kinds() -> Vec<Kind> {
    vec![
        Kind { file: "nan_texel.exr", make: |p| write_with_texel(p, f32::NAN), fault: &["nan", "x=5, y=0, channel g"] },
        Kind {
            file: "inf_texel.exr",
            make: |p| write_with_texel(p, f32::INFINITY),
            fault: &["infinite", "x=5, y=0, channel g"],
        },
        Kind {
            file: "negative_texel.exr",
            make: |p| write_with_texel(p, -0.25),
            fault: &["negative", "x=5, y=0, channel g"],
        },
    ]
}

/// Channel sets without exactly one R, G, B of floats.
fn channel_kinds() -> Vec<Kind> {
    vec![
        Kind {
            file: "channels_xyz.exr",
            make: |p| {
                let v = vec![0.5f32; 32];
                write_channels(p, 8, 4, &[("X", v.clone()), ("Y", v.clone()), ("Z", v)])
            },
            fault: &["missing channel(s) r, g, b", "x, y, z"],
        },
        Kind {
            file: "channels_lowercase.exr",
            make: |p| {
                let v = vec![0.5f32; 32];
                write_channels(p, 8, 4, &[("r", v.clone()), ("g", v.clone()), ("b", v)])
            },
            fault: &["missing channel(s) r, g, b"],
        },
        Kind {
            file: "channels_red_only.exr",
            make: |p| write_channels(p, 8, 4, &[("R", vec![0.5; 32])]),
            fault: &["missing channel(s) g, b"],
        },
        Kind {
            file: "channels_two_layers.exr",
            make: |p| {
                let v = vec![0.5f32; 32];
                let names = ["a.R", "a.G", "a.B", "b.R", "b.G", "b.B"];
                let ch: Vec<(&str, Vec<f32>)> = names.iter().map(|n| (*n, v.clone())).collect();
                write_channels(p, 8, 4, &ch)
            },
            fault: &["ambiguous"],
        },
        Kind {
            file: "channels_u32.exr",
            make: |p| {
                let f = |name: &str| AnyChannel::new(name, FlatSamples::U32(vec![1u32; 32]));
                let list: SmallVec<[_; 4]> = [f("R"), f("G"), f("B")].into_iter().collect();
                let layer =
                    Layer::new((8, 4), LayerAttributes::default(), Encoding::UNCOMPRESSED, AnyChannels::sort(list));
                Image::from_layer(layer).write().to_file(p).unwrap();
            },
            fault: &["unsigned integer"],
        },
    ]
}

/// OpenEXR features the loader does not read: deep data, several parts.
fn exr_feature_kinds() -> Vec<Kind> {
    vec![
        Kind {
            file: "deep.exr",
            make: |p| {
                // The "non-image (deep) parts" bit of the version field of a valid file.
                write_exr(p, &good_map(8)).unwrap();
                let mut b = fs::read(p).unwrap();
                b[5] |= 0x08;
                fs::write(p, b).unwrap();
            },
            fault: &["deep data"],
        },
        Kind {
            file: "multi_part.exr",
            make: |p| {
                let layer = |name: &str, v: f32| {
                    Layer::new(
                        (8, 4),
                        LayerAttributes::named(name),
                        Encoding::UNCOMPRESSED,
                        SpecificChannels::rgb(move |_: Vec2<usize>| (v, v, v)),
                    )
                };
                Image::empty(ImageAttributes::new(IntegerBounds::from_dimensions((8, 4))))
                    .with_layer(layer("left", 1.0))
                    .with_layer(layer("right", 2.0))
                    .write()
                    .to_file(p)
                    .unwrap();
            },
            fault: &["multi-part", "2 parts"],
        },
    ]
}

/// Headers claiming sizes too large to allocate: refused before reading pixels.
fn huge_header_kinds() -> Vec<Kind> {
    vec![
        Kind {
            file: "header_1e9_by_1e9.exr",
            make: |p| {
                write_exr(p, &good_map(8)).unwrap();
                patch_data_window(p, [0, 0, 999_999_999, 999_999_999]);
            },
            fault: &["1000000000x1000000000", "refusing"],
        },
        Kind {
            file: "header_2e8_by_1e8.hdr",
            make: |p| fs::write(p, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000000 +X 200000000\n").unwrap(),
            fault: &["200000000x100000000", "refusing"],
        },
    ]
}

/// Radiance files with a corrupt or missing size line, or cut short.
fn radiance_header_kinds() -> Vec<Kind> {
    vec![
        Kind {
            file: "corrupt_size_line.hdr",
            make: |p| fs::write(p, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y eight +X 16\n").unwrap(),
            fault: &["invalid radiance hdr"],
        },
        Kind {
            file: "corrupt_orientation.hdr",
            make: |p| fs::write(p, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+Y 8 +X 16\n").unwrap(),
            fault: &["radiance", "orientation"],
        },
        Kind {
            file: "truncated.hdr",
            make: |p| {
                write_hdr(p, 32, 16);
                let b = fs::read(p).unwrap();
                fs::write(p, &b[..b.len() / 2]).unwrap();
            },
            fault: &["truncated"],
        },
        Kind {
            file: "header_only.hdr",
            make: |p| fs::write(p, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n").unwrap(),
            fault: &["radiance hdr"],
        },
    ]
}

/// Headers that break a rule the header pre-read holds them to (`envmap::header`): windows,
/// attribute sizes, the offset table against the file's length, EXPOSURE values.
fn header_rule_kinds() -> Vec<Kind> {
    vec![
        Kind {
            file: "window_mismatch.exr",
            make: |p| {
                write_exr(p, &good_map(8)).unwrap();
                patch_window(p, b"displayWindow\0box2i\0", [0, 0, 15, 7]);
            },
            fault: &["data window (0,0)-(7,3) differs from display window (0,0)-(15,7)"],
        },
        Kind {
            file: "display_window_inverted.exr",
            make: |p| {
                write_exr(p, &good_map(8)).unwrap();
                patch_window(p, b"displayWindow\0box2i\0", [0, 3, 7, 0]);
            },
            fault: &["display window (0,3)-(7,0) is inverted (y max < y min): it holds no pixel"],
        },
        Kind {
            file: "attribute_negative_size.exr",
            make: |p| {
                write_ones(p);
                patch(p, |b| {
                    let key = b"compression\0compression\0";
                    let at = b.windows(key.len()).position(|w| w == key).unwrap() + key.len();
                    b[at..at + 4].copy_from_slice(&(-5i32).to_le_bytes());
                });
            },
            fault: &["attribute 'compression'", "declares -5 bytes, a negative size"],
        },
        Kind {
            file: "offset_table_cut.exr",
            make: |p| {
                write_ones(p);
                patch(p, |b| {
                    let (table, _) = offset_table(b);
                    b.truncate(table + 16);
                });
            },
            fault: &["truncated", "offset table (4 entries"],
        },
        Kind {
            file: "exposure_zero.hdr",
            make: |p| {
                write_hdr(p, 8, 4);
                patch(p, |b| {
                    let at = b.iter().position(|&c| c == b'\n').unwrap() + 1;
                    b.splice(at..at, b"EXPOSURE=0\n".iter().copied());
                });
            },
            fault: &["line 2: exposure=0: expected a positive finite number"],
        },
    ]
}

/// OpenEXR files whose offset table or chunk headers are edited after writing.
fn chunk_layout_kinds() -> Vec<Kind> {
    vec![
        // Chunk coverage: chunks that do not store every scanline exactly once. The exr crate
        // places a chunk by the y in it and leaves uncovered rows black; each is refused.
        Kind {
            file: "chunk_offset_duplicated.exr",
            make: |p| {
                write_ones(p);
                patch(p, |b| {
                    let (table, _) = offset_table(b);
                    let first = b[table..table + 8].to_vec();
                    b[table + 8..table + 16].copy_from_slice(&first);
                });
            },
            fault: &["corrupt openexr chunk layout", "stored twice", "exactly once"],
        },
        Kind {
            file: "chunk_y_duplicated.exr",
            make: |p| {
                write_ones(p);
                patch(p, |b| {
                    let at = offset(b, 1);
                    b[at..at + 4].copy_from_slice(&0i32.to_le_bytes());
                });
            },
            fault: &["corrupt openexr chunk layout", "(x=0, y=0) is stored twice"],
        },
        Kind {
            file: "chunk_y_outside.exr",
            make: |p| {
                write_ones(p);
                patch(p, |b| {
                    let at = offset(b, 3);
                    b[at..at + 4].copy_from_slice(&9i32.to_le_bytes());
                });
            },
            fault: &["openexr"],
        },
        Kind {
            file: "chunk_offset_to_nowhere.exr",
            make: |p| {
                write_ones(p);
                patch(p, |b| {
                    let (table, n) = offset_table(b);
                    let k = table + 8 * (n - 1);
                    let past_the_end = (b.len() as u64 + 1000).to_le_bytes();
                    b[k..k + 8].copy_from_slice(&past_the_end);
                });
            },
            fault: &["openexr"],
        },
        Kind {
            file: "tile_duplicated.exr",
            make: |p| {
                let layer = Layer::new(
                    (16, 8),
                    LayerAttributes::default(),
                    Encoding {
                        compression: Compression::Uncompressed,
                        blocks: Blocks::Tiles(Vec2(8, 4)),
                        line_order: LineOrder::Increasing,
                    },
                    SpecificChannels::rgb(|_: Vec2<usize>| (1.0f32, 1.0f32, 1.0f32)),
                );
                Image::from_layer(layer).write().to_file(p).unwrap();
                patch(p, |b| {
                    let (table, n) = offset_table(b);
                    assert_eq!(n, 4, "a 16x8 image in 8x4 tiles");
                    let first = b[table..table + 8].to_vec();
                    b[table + 24..table + 32].copy_from_slice(&first);
                });
            },
            fault: &["corrupt openexr chunk layout", "stored twice"],
        },
    ]
}

/// Files that are no map at all: empty, text, PNG, a bad magic number, a folder.
fn not_a_map_kinds() -> Vec<Kind> {
    vec![
        Kind { file: "empty.exr", make: |p| fs::write(p, b"").unwrap(), fault: &["empty (0 bytes)"] },
        Kind {
            file: "not_an_image.exr",
            make: |p| fs::write(p, b"maps = ['grace']\n").unwrap(),
            fault: &["unrecognised file format", "ends in .exr"],
        },
        Kind {
            file: "png_image.png",
            make: |p| {
                image::RgbImage::from_fn(8, 4, |x, y| image::Rgb([x as u8 * 30, y as u8 * 60, 7])).save(p).unwrap()
            },
            fault: &["unrecognised file format", "89 50 4e 47"],
        },
        Kind {
            file: "bad_magic.exr",
            make: |p| {
                write_exr(p, &good_map(8)).unwrap();
                let mut b = fs::read(p).unwrap();
                b[0] ^= 0xff;
                fs::write(p, b).unwrap();
            },
            fault: &["bad magic"],
        },
        Kind {
            file: "directory.exr",
            make: |p| {
                fs::create_dir_all(p).unwrap();
                fs::write(p.join("README.md"), "A folder named like a map: the loader must refuse it.\n").unwrap();
            },
            fault: &["is a directory"],
        },
    ]
}

/// A fuzz seed: its file name and how it is made.
type Seed = (&'static str, fn(&Path));

/// Small valid maps: the fuzz seeds of the map loader (`fuzz/seeds/map_loader/`), one per
/// encoding the loader accepts, so mutations start from every decoder path.
fn seeds() -> Vec<Seed> {
    vec![
        ("zip_f32_8x4.exr", |p| write_exr(p, &good_map(8)).unwrap()),
        ("plain_f32_8x4.exr", |p| {
            let m = good_map(8);
            let ch = |c: usize| m.texels().iter().map(|t| t[c]).collect::<Vec<_>>();
            write_channels(p, 8, 4, &[("R", ch(0)), ("G", ch(1)), ("B", ch(2))])
        }),
        ("rle_tiled_half_rgba_16x8.exr", |p| {
            let layer = Layer::new(
                (16, 8),
                LayerAttributes::default(),
                Encoding {
                    compression: Compression::RLE,
                    blocks: Blocks::Tiles(Vec2(8, 4)),
                    line_order: LineOrder::Increasing,
                },
                SpecificChannels::rgba(|q: Vec2<usize>| {
                    (f16::from_f32(q.x() as f32), f16::from_f32(q.y() as f32), f16::ONE, f16::ONE)
                }),
            );
            Image::from_layer(layer).write().to_file(p).unwrap();
        }),
        ("piz_layer_8x4.exr", |p| {
            let v = |k: f32| (0..32).map(|i| i as f32 * 0.1 + k).collect::<Vec<_>>();
            let list: SmallVec<[AnyChannel<FlatSamples>; 4]> =
                [("diffuse.R", v(0.0)), ("diffuse.G", v(1.0)), ("diffuse.B", v(2.0))]
                    .into_iter()
                    .map(|(n, d)| AnyChannel::new(n, FlatSamples::F32(d)))
                    .collect();
            let enc = Encoding { compression: Compression::PIZ, ..Encoding::UNCOMPRESSED };
            Image::from_layer(Layer::new((8, 4), LayerAttributes::default(), enc, AnyChannels::sort(list)))
                .write()
                .to_file(p)
                .unwrap();
        }),
        ("rle_16x8.hdr", |p| write_hdr(p, 16, 8)),
        ("flat_4x2.hdr", |p| write_hdr(p, 4, 2)),
    ]
}

fn seed_dir() -> PathBuf {
    repo().join("fuzz").join("seeds").join("map_loader")
}

/// Writes the whole corpus into `dir` (created if needed).
fn generate(dir: &Path) {
    fs::create_dir_all(dir).unwrap();
    for k in kinds() {
        let p = dir.join(k.file);
        if p.is_dir() {
            fs::remove_dir_all(&p).unwrap();
        } else if p.exists() {
            fs::remove_file(&p).unwrap();
        }
        (k.make)(&p);
    }
}

#[test]
fn fuzz_seeds_are_current_and_load() {
    if std::env::var_os("PROBELAB_REGEN_BAD_INPUTS").is_some() {
        fs::create_dir_all(seed_dir()).unwrap();
        for (name, make) in seeds() {
            make(&seed_dir().join(name));
        }
    }
    let fresh = tempfile::tempdir().unwrap();
    for (name, make) in seeds() {
        make(&fresh.path().join(name));
        let committed = fs::read(seed_dir().join(name)).unwrap_or_default();
        assert!(committed == fs::read(fresh.path().join(name)).unwrap(), "fuzz seed {name} is stale");
        let seed = seed_dir().join(name);
        Map::load(seed.to_str().unwrap(), repo()).unwrap_or_else(|e| panic!("seed {name}: {e:#}"));
    }
}

#[test]
fn corpus_is_current() {
    if std::env::var_os("PROBELAB_REGEN_BAD_INPUTS").is_some() {
        generate(&corpus_dir());
        println!("regenerated {}", corpus_dir().display());
    }
    let fresh = tempfile::tempdir().unwrap();
    generate(fresh.path());
    let (want, have) = (snapshot(fresh.path()), snapshot(&corpus_dir()));
    assert!(want.len() >= 20, "at least 20 kinds");
    for (name, bytes) in &want {
        let committed = have.get(name).unwrap_or_else(|| {
            panic!("{} is missing: run PROBELAB_REGEN_BAD_INPUTS=1 cargo test --test bad_inputs", name.display())
        });
        assert!(committed == bytes, "{} differs from its generator", name.display());
    }
    for name in have.keys() {
        assert!(want.contains_key(name), "{} is not made by the generator", name.display());
    }
}

/// A scratch repository: envmaps/good.exr, results/ with an existing table, and an empty
/// experiments/ folder.
fn scratch_root() -> Scratch {
    let root = Scratch::new();
    fs::create_dir_all(root.path().join("envmaps")).unwrap();
    write_exr(&root.path().join("envmaps/good.exr"), &good_map(16)).unwrap();
    root.write("results/old/table.csv", "map,encoder\nold,sh1\n");
    root.write("results/good_and_bad/table.csv", "map,encoder\nprevious,sh2\n");
    fs::create_dir_all(root.path().join("experiments")).unwrap();
    root
}

/// Checks a failed run: exit code 2, one `error:` naming `file` and every fault word, no panic
/// and nothing on stdout.
fn assert_clean_failure(out: &Output, file: &str, fault: &[&str], what: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{what}: exit status {:?}; stderr: {err}", out.status);
    assert!(err.starts_with("error: "), "{what}: {err}");
    assert!(!err.contains("panicked at") && !err.contains("RUST_BACKTRACE"), "{what}: a panic: {err}");
    assert!(err.contains(file), "{what}: the error does not name {file}: {err}");
    let lower = err.to_lowercase();
    for w in fault {
        assert!(lower.contains(w), "{what}: the error lacks '{w}': {err}");
    }
    assert!(out.stdout.is_empty(), "{what}: partial output on stdout: {}", String::from_utf8_lossy(&out.stdout));
}

/// Runs `probelab eval <bad>` and `probelab run <experiment naming a good map, then the bad
/// one>`; both must fail cleanly and leave results/ byte-identical.
fn check_bad_map(root: &Scratch, bad: &Path, fault: &[&str]) {
    let name = bad.file_name().unwrap().to_str().unwrap();
    let before = root.snapshot("results");
    let out = root.run(&["eval", bad.to_str().unwrap(), "--encoders", "sh1"]);
    assert_clean_failure(&out, name, fault, &format!("eval {name}"));
    let exp = root.path().join("experiments/good_and_bad.toml");
    let text = format!("maps = ['good', '{}']\nencoders = ['sh1', 'sh2']\nresolution = [16, 8]\n", bad.display());
    fs::write(&exp, text).unwrap();
    let out = root.run(&["run", exp.to_str().unwrap()]);
    assert_clean_failure(&out, name, fault, &format!("run with {name}"));
    assert!(root.snapshot("results") == before, "run with {name}: results/ changed");
    fs::remove_file(&exp).unwrap();
}

#[test]
fn every_bad_map_fails_cleanly() {
    let root = scratch_root();
    let kinds = kinds();
    for k in &kinds {
        check_bad_map(&root, &corpus_dir().join(k.file), k.fault);
    }
    println!("{} committed kinds refused cleanly", kinds.len());
}

/// Kinds that cannot be committed: made in a temporary folder.
#[cfg(unix)]
#[test]
fn special_files_fail_cleanly() {
    let root = scratch_root();
    let tmp = tempfile::tempdir().unwrap();

    // A path through a regular file ("empty.exr/inside.exr"): ENOTDIR.
    let through = corpus_dir().join("empty.exr").join("inside.exr");
    check_bad_map(&root, &through, &["cannot read file metadata", "not a directory"]);

    // A FIFO: refused before anything opens it (opening would block).
    let fifo = tmp.path().join("fifo.exr");
    let c_path = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: `c_path` is a NUL-terminated path that outlives the call.
    assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0, "mkfifo: {}", std::io::Error::last_os_error());
    check_bad_map(&root, &fifo, &["not a regular file"]);

    // A symlink loop.
    let (a, b) = (tmp.path().join("loop_a.exr"), tmp.path().join("loop_b.exr"));
    std::os::unix::fs::symlink(&b, &a).unwrap();
    std::os::unix::fs::symlink(&a, &b).unwrap();
    check_bad_map(&root, &a, &["symbolic links"]);

    // A dangling symlink names a file that does not exist.
    let dangling = tmp.path().join("dangling.exr");
    std::os::unix::fs::symlink(tmp.path().join("gone.exr"), &dangling).unwrap();
    check_bad_map(&root, &dangling, &["not found"]);
}

/// An unreadable file (mode 000), made in a temporary folder. Root reads it anyway, so this
/// needs another user.
#[cfg(unix)]
#[test]
#[cfg_attr(mode_000_readable, ignore = "this user (root) can read a mode-000 file: run the tests as another user")]
fn unreadable_file_fails_cleanly() {
    use std::os::unix::fs::PermissionsExt;
    let root = scratch_root();
    let tmp = tempfile::tempdir().unwrap();
    let secret = tmp.path().join("unreadable.exr");
    write_exr(&secret, &good_map(8)).unwrap();
    fs::set_permissions(&secret, fs::Permissions::from_mode(0o000)).unwrap();
    assert!(fs::File::open(&secret).is_err(), "this process reads a mode-000 file, but the build script could not");
    check_bad_map(&root, &secret, &["permission denied"]);
}

/// Experiment files: each error names the file and the line, exit code 2, nothing written.
#[test]
fn bad_experiment_files_point_at_the_line() {
    let root = scratch_root();
    let cases: &[(&str, &str, usize, &[&str])] = &[
        (
            "unknown_encoder",
            "description = 'sh1 and friends'\nmaps = ['good']\nencoders = ['sh1',\n  'sh9']\n",
            4,
            &["unknown encoder 'sh9'", "valid encoders: sh0, sh1, sh2"],
        ),
        (
            "unknown_effect",
            "maps = ['good']\nencoders = ['sh1']\norientations = ['up']\neffects = ['fog']\n",
            4,
            &["unknown effect 'fog'", "valid: hemisphere, cone"],
        ),
        (
            "unknown_effect_kind",
            "maps = ['good']\nencoders = ['sh1']\norientations = ['up']\n\neffects = [{ kind = 'smoke' }]\n",
            5,
            &["unknown effect kind 'smoke'"],
        ),
        ("missing_map", "maps = ['good',\n  'no_such_map']\nencoders = ['sh1']\n", 2, &["map 'no_such_map' not found"]),
        ("malformed", "maps = ['good']\nencoders = ['sh1'\nmetrics = ['exact']\n", 3, &[]),
        ("unknown_key", "maps = ['good']\nencoders = ['sh1']\n\ncolour = 'red'\n", 4, &["unknown field `colour`"]),
        (
            "encoder_setting",
            "maps = ['good']\nencoders = [\n  'sh2',\n  { kind = 'sh1', name = 'x', band = 3 },\n]\n",
            4,
            &["unknown key(s) 'band'"],
        ),
        ("bad_value", "maps = ['good']\nencoders = ['sh1']\nresolution = [16, 'eight']\n", 3, &[]),
        ("nan_tilt", "maps = ['good']\nencoders = ['sh1']\norientations = ['up']\neffects = [{ kind = 'cone', cos_alpha = 0.5, tilt_deg = nan }]\n", 4, &["tilt_deg must be finite"]),
    ];
    for (name, text, line, words) in cases {
        let before = root.snapshot("results");
        let file = format!("{name}.toml");
        let p = root.path().join("experiments").join(&file);
        fs::write(&p, text).unwrap();
        let out = root.run(&["run", p.to_str().unwrap()]);
        let mut fault = vec![format!("{file}:{line}:")];
        fault.extend(words.iter().map(|w| w.to_lowercase()));
        let fault: Vec<&str> = fault.iter().map(|s| s.as_str()).collect();
        assert_clean_failure(&out, &file, &fault, name);
        assert!(root.snapshot("results") == before, "{name}: results/ changed");
        // `reproduce` meets the same file (it is in experiments/) and fails the same way
        // before running anything, except that an experiment with a map missing is run on the
        // maps found (documented: a fresh clone lacks the shared probes) and says so.
        let out = root.run(&["reproduce"]);
        let mut after = root.snapshot("results");
        if *name == "missing_map" {
            assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
            // One of its two maps is here: it runs on that one; with no baseline to compare
            // with, nothing is written (a baseline holds every map) and it says so.
            let said = String::from_utf8_lossy(&out.stdout);
            assert!(
                said.contains("missing_map: 1 of 2 maps (missing: no_such_map)")
                    && said.contains("no baseline to compare with, nothing written"),
                "{said}"
            );
            // A successful reproduce ends by writing the report (which lists the skipped
            // experiment); it writes no table.
            let md = after.remove(Path::new("REPORT.md")).expect("reproduce writes REPORT.md");
            assert!(
                String::from_utf8_lossy(&md).contains("missing_map: no results yet"),
                "the report lists the skipped experiment"
            );
            fs::remove_file(root.path().join("results/REPORT.md")).unwrap();
            // The report's other pages (PROVENANCE.md, a README.md per result folder, the
            // results viewer's site).
            let pages: Vec<PathBuf> = after
                .keys()
                .filter(|k| {
                    k.starts_with("site") || k.file_name().is_some_and(|n| n == "README.md" || n == "PROVENANCE.md")
                })
                .cloned()
                .collect();
            for k in pages {
                after.remove(&k);
                fs::remove_file(root.path().join("results").join(&k)).unwrap();
            }
        } else {
            assert_clean_failure(&out, &file, &fault, &format!("reproduce with {name}"));
        }
        assert!(after == before, "reproduce with {name}: results/ changed");
        fs::remove_file(&p).unwrap();
    }
}

/// A header claiming 10⁹ × 10⁹ pixels is refused before any pixel memory is reserved: the
/// binary gives the same clean error with its address space capped at 128 MiB (on the machine
/// this was written on, scoring even gen_constant under that cap fails for lack of memory, so
/// the cap is tight).
#[cfg(unix)]
#[test]
fn huge_headers_are_refused_in_128_mib() {
    for file in ["header_1e9_by_1e9.exr", "header_2e8_by_1e8.hdr"] {
        let path = corpus_dir().join(file);
        let out = std::process::Command::new("sh")
            .arg("-c")
            .arg("ulimit -v 131072 && exec \"$0\" eval \"$1\" --encoders sh1")
            .arg(env!("CARGO_BIN_EXE_probelab"))
            .arg(&path)
            .env_remove("PROBELAB_ENVMAPS")
            .output()
            .unwrap();
        assert_clean_failure(&out, file, &["refusing"], &format!("{file} under ulimit -v"));
    }
}
