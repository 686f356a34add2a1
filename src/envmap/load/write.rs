//! Writing a map as a single-part scanline OpenEXR with ZIP compression, f32 or half channels,
//! atomically (a temporary file beside the target, then rename).

use crate::envmap::map::EnvMap;
use exr::prelude::{
    Blocks, Compression, Encoding, Image, Layer, LayerAttributes, LineOrder, SpecificChannels, Text, Vec2,
    WritableImage,
};
use std::fs::File;
use std::io::{self, BufWriter};
use std::path::{Path, PathBuf};

/// Why [`write_exr`] failed. Every message starts with the file path.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// Creating, writing, syncing or renaming a file failed.
    #[error("{}: cannot {action}: {cause}", .path.display())]
    Io {
        /// The file being written (the target, or the temporary file beside it for steps that write
        /// it).
        path: PathBuf,
        /// What was being attempted, as a verb phrase ("sync the temporary file", ...).
        action: &'static str,
        /// The operating system's error.
        cause: io::Error,
    },
    /// The OpenEXR encoder failed.
    #[error("{}: OpenEXR encoding failed: {message}", .path.display())]
    Encode {
        /// The target file.
        path: PathBuf,
        /// The encoder's error message.
        message: String,
    },
}

/// Writes `map` to `path` as a single-part scanline OpenEXR with f32 R, G, B channels and
/// ZIP compression (16 lines per block), so that [`super::load`] reads it back bit-exactly.
///
/// The data goes to a temporary file in the same directory, which is synced and then
/// renamed over `path`, so readers never see a partial file. On failure the temporary
/// file is removed.
pub fn write_exr(path: &Path, map: &EnvMap) -> Result<(), WriteError> {
    write_atomically(path, |tmp_path, file| {
        write_exr_to(
            path,
            tmp_path,
            file,
            |pos: Vec2<usize>| {
                let [r, g, b] = map.texel(pos.x(), pos.y());
                (r, g, b)
            },
            map,
        )
    })
}

/// Writes `map` to `path` like [`write_exr`], with half-float R, G, B channels: each texel
/// rounded to the nearest half ([`crate::envmap::identity::to_half`]), as the shared maps are
/// stored (`SOURCES.md`), so that [`super::load`] reads back exactly the halves the map's pixel sha256
/// names. The caller checks the values fit in a half (`identity::halved`).
pub fn write_exr_half(path: &Path, map: &EnvMap) -> Result<(), WriteError> {
    use exr::prelude::f16;
    let h = |v: f32| f16::from_bits(crate::envmap::identity::half_bits(v));
    write_atomically(path, |tmp_path, file| {
        write_exr_to(
            path,
            tmp_path,
            file,
            |pos: Vec2<usize>| {
                let [r, g, b] = map.texel(pos.x(), pos.y());
                (h(r), h(g), h(b))
            },
            map,
        )
    })
}

/// Runs `write` on a new temporary file beside `path` (the one atomic writer,
/// [`crate::io::atomic::Staged`]), then moves it over `path`; on failure the temporary file is
/// removed.
fn write_atomically(
    path: &Path,
    write: impl FnOnce(&Path, &mut File) -> Result<(), WriteError>,
) -> Result<(), WriteError> {
    let mut staged = crate::io::atomic::Staged::beside(path).map_err(|cause| WriteError::Io {
        path: path.to_path_buf(),
        action: "create a temporary file next to it",
        cause,
    })?;
    let tmp_path = staged.tmp_path().to_path_buf();
    write(&tmp_path, staged.file())?;
    staged.commit().map_err(|cause| WriteError::Io {
        path: path.to_path_buf(),
        action: "sync the temporary file and rename it onto the target",
        cause,
    })
}

/// Encodes the pixels `pixel` gives for each position of `map`'s grid into the already
/// created temporary file `file` (at `tmp_path`) and flushes it; the commit syncs it. An
/// encoding error names the final `path`, a failed flush the temporary file.
fn write_exr_to<S: exr::prelude::IntoSample + Sync>(
    path: &Path,
    tmp_path: &Path,
    file: &mut File,
    pixel: impl Fn(Vec2<usize>) -> (S, S, S) + Sync,
    map: &EnvMap,
) -> Result<(), WriteError> {
    let channels = SpecificChannels::rgb(pixel);
    let encoding =
        Encoding { compression: Compression::ZIP16, blocks: Blocks::ScanLines, line_order: LineOrder::Increasing };
    let attributes = LayerAttributes { software_name: Some(Text::from("probelab")), ..LayerAttributes::default() };
    let layer = Layer::new((map.width(), map.height()), attributes, encoding, channels);
    let mut writer = BufWriter::new(file);
    Image::from_layer(layer)
        .write()
        .non_parallel()
        .to_buffered(&mut writer)
        .map_err(|e| WriteError::Encode { path: path.to_path_buf(), message: e.to_string() })?;
    let io_err = |action, cause| WriteError::Io { path: tmp_path.to_path_buf(), action, cause };
    writer.into_inner().map_err(|e| io_err("flush the temporary file", e.into_error()))?;
    Ok(())
}
