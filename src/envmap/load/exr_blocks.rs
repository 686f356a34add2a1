//! The pixels of an OpenEXR layer, chunk by chunk: the compressed chunks are read where the
//! offset tables point, a batch at a time, decompressed on the run's threads (each under [`guarded`], so a
//! decoder panic on malformed data is an error, never an abort), and placed through
//! [`Coverage`], which refuses a pixel stored twice or never. At most one batch of compressed
//! and decompressed chunks is alive at once: [`BATCH_PER_THREAD`] chunks a thread, a few MB at
//! 16k (a ZIP chunk holds 16 lines).

use super::coverage::Coverage;
use super::error::LoadError;
use super::guard::guarded;
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
const BATCH_PER_THREAD: usize = 4;

/// Where the pixels go: the layer's size, its R, G, B channel indices, and a progress bar (one
/// step a row) for large maps.
pub(super) struct Target<'a> {
    pub width: usize,
    pub height: usize,
    pub rgb: [usize; 3],
    pub progress: Option<&'a Progress>,
}

/// Reads every chunk of the file's one layer at its full resolution and returns the row-major
/// texels. `hit_eof` is the reader's flag that it ran off the end (an error then reads as
/// truncation).
pub(super) fn decode(
    path: &Path,
    reader: impl Read + Seek,
    len: u64,
    hit_eof: &AtomicBool,
    target: &Target,
) -> Result<Vec<Texel>, LoadError> {
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
    loop {
        let compressed =
            guarded(path, FORMAT, || chunks.by_ref().take(batch).collect::<Result<Vec<Chunk>, _>>().map_err(fail))?;
        if compressed.is_empty() {
            break;
        }
        let blocks: Vec<Result<UncompressedBlock, LoadError>> = compressed
            .into_par_iter()
            .map(|c| guarded(path, FORMAT, || UncompressedBlock::decompress_chunk(c, &meta, false).map_err(fail)))
            .collect();
        for block in blocks {
            place(path, &meta, &block?, target, &mut coverage)?;
        }
    }
    coverage.finish().map_err(|detail| LoadError::CorruptChunks { path: path.to_path_buf(), detail })
}

/// Puts one decompressed block's R, G, B samples into `coverage` (a block of another
/// resolution level, which the chunk filter already leaves out, is skipped).
fn place(
    path: &Path,
    meta: &MetaData,
    block: &UncompressedBlock,
    target: &Target,
    coverage: &mut Coverage,
) -> Result<(), LoadError> {
    if block.index.level.x() != 0 || block.index.level.y() != 0 {
        return Ok(());
    }
    let header = &meta.headers[block.index.layer];
    let (x0, y0) = (block.index.pixel_position.x(), block.index.pixel_position.y());
    let (bw, bh) = (block.index.pixel_size.width(), block.index.pixel_size.height());
    let mut rgb: Vec<Texel> = vec![[0.0; 3]; bw * bh];
    let mut halves = Vec::new();
    for line in block.lines(&header.channels) {
        let Some(k) = target.rgb.iter().position(|&c| c == line.location.channel) else { continue };
        let (lx, ly, n) = (line.location.position.x(), line.location.position.y(), line.location.sample_count);
        let row = ly.checked_sub(y0).filter(|&r| r < bh && lx == x0 && n == bw).ok_or_else(|| LoadError::Exr {
            path: path.to_path_buf(),
            message: format!("a chunk's line at (x={lx}, y={ly}) of {n} samples lies outside its block"),
        })?;
        let out = &mut rgb[row * bw..(row + 1) * bw];
        let bad = |e: exr::error::Error| LoadError::Exr { path: path.to_path_buf(), message: e.to_string() };
        match header.channels.list[line.location.channel].sample_type {
            SampleType::F16 => {
                halves.resize(n, f16::ZERO);
                line.read_samples_into_slice(&mut halves).map_err(bad)?;
                out.iter_mut().zip(&halves).for_each(|(t, h)| t[k] = h.to_f32());
            }
            _ => {
                let mut floats = vec![0.0f32; n];
                line.read_samples_into_slice(&mut floats).map_err(bad)?;
                out.iter_mut().zip(&floats).for_each(|(t, &v)| t[k] = v);
            }
        }
    }
    for (r, texels) in rgb.chunks(bw.max(1)).enumerate() {
        for (i, &t) in texels.iter().enumerate() {
            coverage.set(x0 + i, y0 + r, t);
        }
        if let Some(p) = target.progress {
            p.inc();
        }
    }
    Ok(())
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
