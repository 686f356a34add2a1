//! The pixels of an OpenEXR layer, chunk by chunk: the compressed chunks are read where the
//! offset tables point, a batch at a time, decompressed and converted to texels on the run's
//! threads (each under [`guarded`], so a decoder panic on malformed data is an error, never an
//! abort), and placed through [`Coverage`], which refuses a pixel stored twice or never. One
//! batch is placed (and its rows added to the pixel sha256) while the next is decompressed, so
//! both cores work through the whole decode. At most two batches of [`BATCH_PER_THREAD`] chunks
//! a thread are alive at once: a ZIP chunk holds 16 lines, about 4.5 MB of texels and half bits
//! at 16k, so some 20 MB on 2 threads.

use super::coverage::Coverage;
use super::error::LoadError;
use super::guard::guarded;
use crate::envmap::identity::{half_bits, stored_half_bits, PixelStream};
use crate::envmap::map::Texel;
use crate::io::progress::Progress;
use exr::block::chunk::Chunk;
use exr::block::UncompressedBlock;
use exr::meta::attribute::SampleType;
use exr::meta::MetaData;
use exr::prelude::f16;
use rayon::prelude::*;
use std::io::{Read, Seek};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

const FORMAT: &str = "OpenEXR";

/// Chunks decompressed per thread in one batch.
const BATCH_PER_THREAD: usize = 1;

/// Where the pixels go: the layer's size, its R, G, B channel indices, whether to form the
/// pixel sha256 while decoding (only when the texels are final as decoded: no colour to
/// convert), and a progress bar (one step a row) for large maps.
pub(super) struct Target<'a> {
    pub width: usize,
    pub height: usize,
    pub rgb: [usize; 3],
    pub hash: bool,
    pub progress: Option<&'a Progress>,
}

/// One decompressed chunk's texels: its top-left pixel, its width, its row-major texels and,
/// when hashing, their half bits as the pixel sha256 adds them.
struct Block {
    x0: usize,
    y0: usize,
    width: usize,
    texels: Vec<Texel>,
    halves: Vec<u8>,
}

/// The pixel sha256 formed while decoding: the digest and the next row it expects. It is given
/// up (the caller hashes the finished map instead) at the first chunk that is not the next
/// full-width rows, as in a file whose lines are stored bottom-up or in tiles.
struct InOrder {
    digest: PixelStream,
    next_row: usize,
}

/// Reads every chunk of the file's one layer at its full resolution and returns the row-major
/// texels, and their pixel sha256 when `target.hash` and the chunks came top-down in whole
/// rows. `hit_eof` is the reader's flag that it ran off the end (an error then reads as
/// truncation).
pub(super) fn decode(
    path: &Path,
    reader: impl Read + Seek,
    len: u64,
    hit_eof: &AtomicBool,
    target: &Target,
) -> Result<(Vec<Texel>, Option<String>), LoadError> {
    let fail = |e| exr_error(path, len, hit_eof.load(Ordering::Relaxed), e);
    // Chunks are read where the offset tables point, as other readers read them, so a
    // duplicated or wrong offset shows as a pixel stored twice or never; only the largest
    // resolution level is read.
    let mut chunks = guarded(path, FORMAT, || {
        exr::block::read(reader, false)
            .and_then(|r| r.filter_chunks(false, |_, _, block| block.level.x() == 0 && block.level.y() == 0))
            .map_err(fail)
    })?;
    let meta: MetaData = exr::block::reader::ChunksReader::meta_data(&chunks).clone();
    let batch = BATCH_PER_THREAD * rayon::current_num_threads().max(1);
    let mut coverage = Coverage::new(target.width, target.height);
    let mut stream =
        target.hash.then(|| InOrder { digest: PixelStream::new(target.width, target.height), next_row: 0 });
    let mut ready: Vec<Block> = Vec::new();
    loop {
        let read =
            guarded(path, FORMAT, || chunks.by_ref().take(batch).collect::<Result<Vec<Chunk>, _>>().map_err(fail));
        let (compressed, read) = match read {
            Ok(c) => (c, Ok(())),
            Err(e) => (Vec::new(), Err(e)),
        };
        let last = compressed.is_empty();
        let placing = std::mem::take(&mut ready);
        let ((), blocks) = rayon::join(
            || place_all(placing, target, &mut coverage, &mut stream),
            || {
                compressed
                    .into_par_iter()
                    .map(|c| guarded(path, FORMAT, || to_block(path, &meta, c, target, &fail)))
                    .collect::<Result<Vec<Block>, LoadError>>()
            },
        );
        read?;
        ready = blocks?;
        if last {
            break;
        }
    }
    let texels = coverage.finish().map_err(|detail| LoadError::CorruptChunks { path: path.to_path_buf(), detail })?;
    let sha = stream.filter(|s| s.next_row == target.height).map(|s| s.digest.finish());
    Ok((texels, sha))
}

/// Places decompressed blocks in order and adds their rows to the pixel sha256 while they
/// come top-down in whole rows.
fn place_all(blocks: Vec<Block>, target: &Target, coverage: &mut Coverage, stream: &mut Option<InOrder>) {
    for block in blocks {
        let rows = block.texels.len() / block.width.max(1);
        if let Some(s) =
            stream.as_mut().filter(|s| block.x0 == 0 && block.width == target.width && block.y0 == s.next_row)
        {
            s.digest.update(&block.halves);
            s.next_row += rows;
        } else {
            *stream = None;
        }
        for (r, run) in block.texels.chunks(block.width.max(1)).enumerate() {
            coverage.put(block.x0, block.y0 + r, run);
            if let Some(p) = target.progress {
                p.inc();
            }
        }
    }
}

/// Decompresses one chunk and gathers its R, G, B samples into texels (and, when hashing,
/// their half bits); a chunk of another resolution level, which the chunk filter already
/// leaves out, gives an empty block.
fn to_block(
    path: &Path,
    meta: &MetaData,
    chunk: Chunk,
    target: &Target,
    fail: &(dyn Fn(exr::error::Error) -> LoadError + Sync),
) -> Result<Block, LoadError> {
    let block = UncompressedBlock::decompress_chunk(chunk, meta, false).map_err(fail)?;
    let (x0, y0) = (block.index.pixel_position.x(), block.index.pixel_position.y());
    if block.index.level.x() != 0 || block.index.level.y() != 0 {
        return Ok(Block { x0, y0, width: 0, texels: Vec::new(), halves: Vec::new() });
    }
    let header = &meta.headers[block.index.layer];
    let (bw, bh) = (block.index.pixel_size.width(), block.index.pixel_size.height());
    let mut out = Block { x0, y0, width: bw, texels: vec![[0.0; 3]; bw * bh], halves: Vec::new() };
    if target.hash {
        out.halves = vec![0; 6 * bw * bh];
    }
    let mut halves = Vec::new();
    let mut floats = Vec::new();
    for line in block.lines(&header.channels) {
        let Some(k) = target.rgb.iter().position(|&c| c == line.location.channel) else { continue };
        let (lx, ly, n) = (line.location.position.x(), line.location.position.y(), line.location.sample_count);
        let row = ly.checked_sub(y0).filter(|&r| r < bh && lx == x0 && n == bw).ok_or_else(|| LoadError::Exr {
            path: path.to_path_buf(),
            message: format!("a chunk's line at (x={lx}, y={ly}) of {n} samples lies outside its block"),
        })?;
        let texels = &mut out.texels[row * bw..(row + 1) * bw];
        let row_bits = out.halves.get_mut(6 * row * bw..6 * (row + 1) * bw).unwrap_or_default().chunks_exact_mut(6);
        let put = |b: &mut [u8], v: u16| b[2 * k..2 * k + 2].copy_from_slice(&v.to_le_bytes());
        let bad = |e: exr::error::Error| LoadError::Exr { path: path.to_path_buf(), message: e.to_string() };
        match header.channels.list[line.location.channel].sample_type {
            SampleType::F16 => {
                halves.resize(n, f16::ZERO);
                line.read_samples_into_slice(&mut halves).map_err(bad)?;
                texels.iter_mut().zip(&halves).for_each(|(t, h)| t[k] = h.to_f32());
                row_bits.zip(&halves).for_each(|(b, &h)| put(b, stored_half_bits(h)));
            }
            _ => {
                floats.resize(n, 0.0f32);
                line.read_samples_into_slice(&mut floats).map_err(bad)?;
                texels.iter_mut().zip(&floats).for_each(|(t, &v)| t[k] = v);
                row_bits.zip(&floats).for_each(|(b, &v)| put(b, half_bits(v)));
            }
        }
    }
    Ok(out)
}

/// Converts an `exr` error into a [`LoadError`]; `hit_eof` says the decoder ran off the
/// end of the file.
pub(super) fn exr_error(path: &Path, len: u64, hit_eof: bool, e: exr::error::Error) -> LoadError {
    let path = path.to_path_buf();
    if hit_eof {
        return LoadError::Truncated { path, format: "OpenEXR", len, detail: e.to_string() };
    }
    match e {
        exr::error::Error::Io(cause) => LoadError::Io { path, action: "read file", cause },
        e => LoadError::Exr { path, message: e.to_string() },
    }
}

#[cfg(test)]
mod tests {
    use crate::envmap::identity::half_bits;
    use crate::envmap::load::{load, write_exr, write_exr_half};
    use crate::envmap::EnvMap;
    use exr::prelude::*;
    use sha2::{Digest, Sha256};

    /// The pixel sha256 as the identity rule defines it, formed here byte by byte.
    fn by_hand(map: &EnvMap) -> String {
        let mut bytes = Vec::new();
        bytes.extend((map.width() as u32).to_le_bytes());
        bytes.extend((map.height() as u32).to_le_bytes());
        for t in map.texels() {
            t.iter().for_each(|&v| bytes.extend(half_bits(v).to_le_bytes()));
        }
        Sha256::digest(&bytes).iter().map(|b| format!("{b:02x}")).collect()
    }

    /// 160x80 with values from 0 to 6e4 and some −0: ten ZIP chunks of 16 lines, so several
    /// batches are placed while the next decompresses.
    fn sample() -> EnvMap {
        EnvMap::from_fn("s", 160, 80, |i, j| {
            [(i * j) as f32 * 4.7, if i % 3 == 0 { -0.0 } else { 0.01 * j as f32 }, 6e4 / (1.0 + i as f32)]
        })
        .unwrap()
    }

    /// Half and float files stored top-down give the pixel sha256 while decoding, the one the
    /// identity rule defines; a tiled file gives none (the caller hashes the map).
    #[test]
    fn the_pixel_sha256_is_formed_while_decoding_top_down_files() {
        let dir = tempfile::tempdir().unwrap();
        let map = sample();
        for (name, half) in [("f32.exr", false), ("f16.exr", true)] {
            let path = dir.path().join(name);
            if half { write_exr_half(&path, &map) } else { write_exr(&path, &map) }.unwrap();
            let back = load(&path).unwrap();
            assert_eq!(back.pixel_sha256.as_deref(), Some(by_hand(&back).as_str()), "{name}");
        }
        let path = dir.path().join("tiled.exr");
        let encoding = Encoding {
            compression: Compression::ZIP16,
            blocks: Blocks::Tiles(Vec2(16, 8)),
            line_order: LineOrder::Increasing,
        };
        let layer = Layer::new(
            (map.width(), map.height()),
            LayerAttributes::default(),
            encoding,
            SpecificChannels::rgb(|p: Vec2<usize>| {
                let t = map.texel(p.x(), p.y());
                (t[0], t[1], t[2])
            }),
        );
        Image::from_layer(layer).write().to_file(&path).unwrap();
        let back = load(&path).unwrap();
        assert_eq!(back.texels(), map.texels());
        assert_eq!(back.pixel_sha256, None);
    }
}
