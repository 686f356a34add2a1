//! Reading lat-long environment maps from OpenEXR and Radiance RGBE (`.hdr`) files, and
//! writing small maps as OpenEXR.
//!
//! [`load`] identifies the format from the first bytes of the file (the extension is not
//! trusted), reads and checks the header before any pixel is decoded (size limits, aspect,
//! channels, sample types, single part, no deep data), then decodes the pixels, refusing an
//! OpenEXR file whose chunks do not store every pixel exactly once (a duplicated, missing or
//! misplaced chunk is never read as default-filled pixels), and checks every texel through
//! [`EnvMap::new`]. Every failure is a [`LoadError`] whose message
//! starts with the file path and says what is wrong; a decoder panic on malformed data is
//! caught and reported as an error too.
//!
//! [`write_exr`] writes a single-part scanline f32 RGB EXR with ZIP compression, and
//! [`write_exr_half`] the same with half channels (the format of the shared maps), each
//! atomically (temporary file in the same directory, then rename).

use super::header::{self, HeaderError};
use super::{EnvMap, MapError, Texel};
use exr::prelude::{
    read, Blocks, ChannelDescription, Compression, Encoding, Image, Layer, LayerAttributes, LineOrder, MetaData,
    ReadChannels, ReadLayers, ReadSpecificChannel, SampleType, SpecificChannels, Text, Vec2, WritableImage,
};
use image::codecs::hdr::HdrDecoder;
use image::{ImageDecoder, ImageError};
use sha2::{Digest, Sha256};
use std::any::Any;
use std::cell::Cell;
use std::fs::{self, File};
use std::io::{self, BufReader, BufWriter, Read, Seek, SeekFrom};
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Once};

pub use super::header::{MAX_HEIGHT, MAX_WIDTH};

/// The four bytes every OpenEXR file starts with.
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
/// The two bytes every Radiance RGBE file starts with (`#?RADIANCE` or `#?RGBE`).
const HDR_SIGNATURE: [u8; 2] = *b"#?";
/// What the "unknown format" error says is supported.
const SUPPORTED: &str = "supported formats: OpenEXR (.exr, starts with bytes 76 2f 31 01) and \
                         Radiance RGBE (.hdr, starts with '#?')";

/// Why a map file could not be loaded. Every message starts with the file path.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be opened, inspected or read (missing, permission denied, ...).
    #[error("{}: cannot {action}: {cause}", .path.display())]
    Io {
        /// The map file being loaded.
        path: PathBuf,
        /// What was being attempted, as a verb phrase ("read file", "seek in file", ...).
        action: &'static str,
        /// The operating system's error.
        cause: io::Error,
    },
    /// The path names a directory.
    #[error("{}: is a directory, not an image file", .path.display())]
    IsDirectory {
        /// The map file being loaded.
        path: PathBuf,
    },
    /// The path names something other than a regular file (FIFO, socket, device).
    #[error("{}: is not a regular file", .path.display())]
    NotAFile {
        /// The map file being loaded.
        path: PathBuf,
    },
    /// The file has no bytes at all.
    #[error("{}: file is empty (0 bytes)", .path.display())]
    Empty {
        /// The map file being loaded.
        path: PathBuf,
    },
    /// The first bytes match neither the OpenEXR magic number nor the Radiance signature.
    #[error("{}: unrecognised file format: bad magic number (first bytes: {found}){note}; {SUPPORTED}", .path.display())]
    UnknownFormat {
        /// The map file being loaded.
        path: PathBuf,
        /// The first bytes of the file, as space-separated hex.
        found: String,
        /// A remark on the name or length that makes the mismatch clearer (may be empty; starts
        /// with ", " otherwise).
        note: String,
    },
    /// The decoder ran off the end of the file: the file is cut short, or a length or
    /// offset in it points past the end.
    #[error("{}: file is truncated (or a length field in it is corrupt): the data ends at {len} bytes where the {format} decoder expected more ({detail})", .path.display())]
    Truncated {
        /// The map file being loaded.
        path: PathBuf,
        /// The decoder that ran out of data ("OpenEXR" or "Radiance HDR").
        format: &'static str,
        /// The file's length in bytes.
        len: u64,
        /// The decoder's own error message.
        detail: String,
    },
    /// The header claims a size above [`MAX_WIDTH`] x [`MAX_HEIGHT`]; nothing was decoded.
    #[error("{}: header claims an image of {width}x{height} pixels, above the limit of {MAX_WIDTH}x{MAX_HEIGHT}; refusing to decode it", .path.display())]
    TooLarge {
        /// The map file being loaded.
        path: PathBuf,
        /// Width the header claims, in pixels.
        width: usize,
        /// Height the header claims, in pixels.
        height: usize,
    },
    /// The header breaks a limit or rule checked before decoding ([`super::header`]).
    #[error("{}: {cause}", .path.display())]
    Header {
        /// The map file being loaded.
        path: PathBuf,
        /// The limit or rule, and how the header breaks it.
        cause: HeaderError,
    },
    /// The header claims a zero width or height.
    #[error("{}: image has zero size ({width}x{height})", .path.display())]
    ZeroSize {
        /// The map file being loaded.
        path: PathBuf,
        /// Width the header claims, in pixels.
        width: usize,
        /// Height the header claims, in pixels.
        height: usize,
    },
    /// The pixels do not form a valid map: wrong aspect, NaN, infinite or negative texels.
    #[error("{}: {cause}", .path.display())]
    Map {
        /// The map file being loaded.
        path: PathBuf,
        /// What is wrong with the pixels or the size.
        cause: MapError,
    },
    /// The OpenEXR file holds more than one part.
    #[error("{}: multi-part OpenEXR file with {parts} parts ({names}); only single-part files are supported", .path.display())]
    MultiPart {
        /// The map file being loaded.
        path: PathBuf,
        /// How many parts the file holds.
        parts: usize,
        /// The parts' layer names, quoted and comma-separated (unnamed parts by index).
        names: String,
    },
    /// The OpenEXR file holds deep data.
    #[error("{}: OpenEXR file contains deep data, which is not supported (need a flat RGB image)", .path.display())]
    Deep {
        /// The map file being loaded.
        path: PathBuf,
    },
    /// Some of the R, G, B channels are missing.
    #[error("{}: missing channel(s) {missing}; the file has channels: {present} (need R, G, B, or one layer's LAYER.R, LAYER.G, LAYER.B)", .path.display())]
    MissingChannel {
        /// The map file being loaded.
        path: PathBuf,
        /// The missing channel names, comma-separated, from the most complete candidate set.
        missing: String,
        /// Every channel name the file has, comma-separated ("(none)" if it has none).
        present: String,
    },
    /// Several layers of one part each have a full set of R, G, B channels.
    #[error("{}: ambiguous RGB channels: layers {layers} each have R, G and B, and there are no unprefixed R, G, B channels", .path.display())]
    AmbiguousChannels {
        /// The map file being loaded.
        path: PathBuf,
        /// The layer names that each have R, G and B, quoted and comma-separated.
        layers: String,
    },
    /// A colour channel holds unsigned integers.
    #[error("{}: channel {channel} holds 32-bit unsigned integer samples; only half and float channels are supported", .path.display())]
    IntegerChannel {
        /// The map file being loaded.
        path: PathBuf,
        /// Name of the integer channel.
        channel: String,
    },
    /// A colour channel is subsampled.
    #[error("{}: channel {channel} is subsampled ({x}x{y}); only full-resolution channels are supported", .path.display())]
    Subsampled {
        /// The map file being loaded.
        path: PathBuf,
        /// Name of the subsampled channel.
        channel: String,
        /// Horizontal sampling rate (1 is full resolution).
        x: usize,
        /// Vertical sampling rate (1 is full resolution).
        y: usize,
    },
    /// The OpenEXR chunks do not store every pixel exactly once (a duplicated, missing or
    /// misplaced scanline block or tile).
    #[error("{}: corrupt OpenEXR chunk layout: {detail}; every scanline block and tile must be stored exactly once", .path.display())]
    CorruptChunks {
        /// The map file being loaded.
        path: PathBuf,
        /// Which chunk is duplicated, missing or misplaced.
        detail: String,
    },
    /// The OpenEXR decoder rejected the file.
    #[error("{}: invalid or unsupported OpenEXR data: {message}", .path.display())]
    Exr {
        /// The map file being loaded.
        path: PathBuf,
        /// The decoder's error message.
        message: String,
    },
    /// The Radiance HDR decoder rejected the file.
    #[error("{}: invalid Radiance HDR data: {message}", .path.display())]
    Hdr {
        /// The map file being loaded.
        path: PathBuf,
        /// The decoder's error message.
        message: String,
    },
    /// A decoder panicked; the panic was caught.
    #[error("{}: {format} decoder failed on malformed data (it panicked: {message})", .path.display())]
    DecoderPanic {
        /// The map file being loaded.
        path: PathBuf,
        /// The decoder that panicked ("OpenEXR" or "Radiance HDR").
        format: &'static str,
        /// The panic's message ("no message" if it carried none).
        message: String,
    },
}

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

/// A decoded map: width, height and row-major texels.
type Decoded = (usize, usize, Vec<Texel>);

/// The file formats [`load`] understands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Exr,
    Hdr,
}

/// Loads a lat-long map from an OpenEXR or Radiance RGBE file.
///
/// The format is taken from the file's first bytes. The map is named after the file stem
/// and remembers `path`. Fails with a [`LoadError`] naming the file if it cannot be read,
/// is not a supported format, is malformed or truncated, claims a size above
/// [`MAX_WIDTH`] x [`MAX_HEIGHT`], is not 2:1, lacks R, G, B channels, or has a NaN,
/// infinite or negative texel. Never panics on bad input.
pub fn load(path: &Path) -> Result<EnvMap, LoadError> {
    let io_err = |action, cause| LoadError::Io { path: path.to_path_buf(), action, cause };
    let meta = fs::metadata(path).map_err(|e| io_err("read file metadata", e))?;
    if meta.is_dir() {
        return Err(LoadError::IsDirectory { path: path.to_path_buf() });
    }
    if !meta.is_file() {
        return Err(LoadError::NotAFile { path: path.to_path_buf() });
    }
    if meta.len() == 0 {
        return Err(LoadError::Empty { path: path.to_path_buf() });
    }
    // The file is decoded as it is read, never held whole (a 16k map's file can be as large as
    // the map itself), while a second reader hashes it on another thread (the map's identity in
    // provenance).
    let open = || File::open(path).map_err(|e| io_err("open file", e));
    let mut file = open()?;
    let mut head = Vec::with_capacity(4);
    (&mut file).take(4).read_to_end(&mut head).map_err(|e| io_err("read file", e))?;
    let format = detect(path, &head)?;
    let hashed = open()?;
    let (decoded, digest) = std::thread::scope(|s| {
        let hasher = s.spawn(move || sha256_hex_of(hashed));
        let decoded = match format {
            Format::Exr => read_exr(path, &mut file, meta.len()).map(|d| (d, 1.0)),
            Format::Hdr => read_hdr(path, &mut file, meta.len()),
        };
        (decoded, hasher.join().unwrap_or_else(|_| Err(io::Error::other("the hashing thread failed"))))
    });
    let ((width, height, texels), exposure) = decoded?;
    let digest = digest.map_err(|e| io_err("read file", e))?;
    let name = path.file_stem().unwrap_or(path.as_os_str()).to_string_lossy().into_owned();
    let mut map =
        EnvMap::new(name, width, height, texels).map_err(|cause| LoadError::Map { path: path.to_path_buf(), cause })?;
    map.path = Some(path.to_path_buf());
    map.sha256 = Some(digest);
    map.exposure = exposure;
    Ok(map)
}

/// A map file's width and height, from its header alone (no pixel is decoded; a 16k map's size
/// is known in a millisecond), checked as [`load`] checks them. For run-time estimates
/// (`pipeline::estimate`); [`load`] still validates everything else.
pub fn dimensions(path: &Path) -> Result<(usize, usize), LoadError> {
    let io_err = |action, cause| LoadError::Io { path: path.to_path_buf(), action, cause };
    let meta = fs::metadata(path).map_err(|e| io_err("read file metadata", e))?;
    if !meta.is_file() {
        return Err(LoadError::NotAFile { path: path.to_path_buf() });
    }
    let (mut file, len) = (File::open(path).map_err(|e| io_err("open file", e))?, meta.len());
    let mut head = Vec::with_capacity(4);
    (&mut file).take(4).read_to_end(&mut head).map_err(|e| io_err("read file", e))?;
    let (reader, hit_eof) = watched(path, &mut file)?;
    match detect(path, &head)? {
        Format::Exr => guarded(path, "OpenEXR", || {
            let meta = MetaData::read_from_buffered(reader, false)
                .map_err(|e| exr_error(path, len, hit_eof.load(Ordering::Relaxed), e))?;
            check_exr_header(path, &meta).map(|(w, h, _)| (w, h))
        }),
        Format::Hdr => guarded(path, "Radiance HDR", || {
            let decoder = HdrDecoder::new_nonstrict(reader)
                .map_err(|e| hdr_error(path, len, hit_eof.load(Ordering::Relaxed), e))?;
            let (w, h) = decoder.dimensions();
            check_size(path, w as usize, h as usize).map(|_| (w as usize, h as usize))
        }),
    }
}

/// Lower-case hex sha256 of `bytes`: a map file's identity ([`EnvMap::sha256`]), and a result
/// table's (`regression::provenance`).
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// Lower-case hex sha256 of everything `reader` yields, read in 1 MiB pieces (a probe file's
/// identity, `pipeline::probeset`, without holding the file in memory).
pub fn sha256_hex_of(mut reader: impl Read) -> io::Result<String> {
    let mut h = Sha256::new();
    let mut buf = vec![0u8; 1 << 20];
    loop {
        match reader.read(&mut buf) {
            Ok(0) => return Ok(hex(&h.finalize())),
            Ok(n) => h.update(&buf[..n]),
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
}

fn hex(digest: &[u8]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// Writes `map` to `path` as a single-part scanline OpenEXR with f32 R, G, B channels and
/// ZIP compression (16 lines per block), so that [`load`] reads it back bit-exactly.
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
/// stored (`SOURCES.md`), so that [`load`] reads back exactly the halves the map's pixel sha256
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

/// Identifies the format from the first (up to four) bytes of a file.
fn detect(path: &Path, head: &[u8]) -> Result<Format, LoadError> {
    if head.starts_with(&EXR_MAGIC) {
        return Ok(Format::Exr);
    }
    if head.starts_with(&HDR_SIGNATURE) {
        return Ok(Format::Hdr);
    }
    let found = head.iter().map(|b| format!("{b:02x}")).collect::<Vec<_>>().join(" ");
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    let note = match ext.as_deref() {
        _ if head.len() < EXR_MAGIC.len() => {
            format!(", only {} byte(s) long", head.len())
        }
        Some("exr") => ", although the name ends in .exr".to_string(),
        Some("hdr") | Some("pic") => ", although the name ends in .hdr".to_string(),
        _ => String::new(),
    };
    Err(LoadError::UnknownFormat { path: path.to_path_buf(), found, note })
}

/// Checks a size read from a header before any pixel memory is allocated: not zero, at
/// most [`MAX_WIDTH`] x [`MAX_HEIGHT`], and 2:1.
fn check_size(path: &Path, width: usize, height: usize) -> Result<(), LoadError> {
    let path = path.to_path_buf();
    if width == 0 || height == 0 {
        return Err(LoadError::ZeroSize { path, width, height });
    }
    if width > MAX_WIDTH || height > MAX_HEIGHT {
        return Err(LoadError::TooLarge { path, width, height });
    }
    if width != 2 * height {
        return Err(LoadError::Map { path, cause: MapError::Aspect { width, height } });
    }
    Ok(())
}

/// A reader that records whether anyone tried to read past the end of the data, so that a
/// decoder error can be reported as truncation.
struct EofWatch<R> {
    inner: R,
    hit_eof: Arc<AtomicBool>,
}

impl<R: Read> Read for EofWatch<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        if n == 0 && !buf.is_empty() {
            self.hit_eof.store(true, Ordering::Relaxed);
        }
        Ok(n)
    }
}

impl<R: Seek> Seek for EofWatch<R> {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        self.inner.seek(pos)
    }
}

/// Rewinds `file` and wraps it in a buffered [`EofWatch`]; returns the reader and its flag.
fn watched<'f, R: Read + Seek>(
    path: &Path,
    file: &'f mut R,
) -> Result<(BufReader<EofWatch<&'f mut R>>, Arc<AtomicBool>), LoadError> {
    file.seek(SeekFrom::Start(0)).map_err(|cause| LoadError::Io {
        path: path.to_path_buf(),
        action: "seek in file",
        cause,
    })?;
    let flag = Arc::new(AtomicBool::new(false));
    Ok((BufReader::new(EofWatch { inner: file, hit_eof: flag.clone() }), flag))
}

thread_local! {
    /// Set while this thread runs a [`guarded`] decoder step.
    static IN_GUARDED: Cell<bool> = const { Cell::new(false) };
}

/// Runs a decoder step, turning a panic into [`LoadError::DecoderPanic`]. The panic is
/// caught, so it must not print either: the first call installs a panic hook that stays quiet
/// on a thread inside a guarded step and defers to the previous hook everywhere else (the
/// decoders run on the calling thread).
fn guarded<T>(path: &Path, format: &'static str, f: impl FnOnce() -> Result<T, LoadError>) -> Result<T, LoadError> {
    static QUIET_HOOK: Once = Once::new();
    QUIET_HOOK.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if !IN_GUARDED.with(Cell::get) {
                previous(info);
            }
        }));
    });
    let was = IN_GUARDED.with(|g| g.replace(true));
    let result = panic::catch_unwind(AssertUnwindSafe(f));
    IN_GUARDED.with(|g| g.set(was));
    result.unwrap_or_else(|payload| {
        Err(LoadError::DecoderPanic { path: path.to_path_buf(), format, message: panic_message(payload.as_ref()) })
    })
}

/// The text of a panic payload, if it has one.
fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "no message".to_string()
    }
}

/// Converts an `exr` error into a [`LoadError`]; `hit_eof` says the decoder ran off the
/// end of the file.
fn exr_error(path: &Path, len: u64, hit_eof: bool, e: exr::error::Error) -> LoadError {
    let path = path.to_path_buf();
    if hit_eof {
        return LoadError::Truncated { path, format: "OpenEXR", len, detail: e.to_string() };
    }
    match e {
        exr::error::Error::Io(cause) => LoadError::Io { path, action: "read file", cause },
        e => LoadError::Exr { path, message: e.to_string() },
    }
}

/// Converts an `image` error from the HDR decoder into a [`LoadError`].
fn hdr_error(path: &Path, len: u64, hit_eof: bool, e: ImageError) -> LoadError {
    let path = path.to_path_buf();
    let eof = matches!(&e, ImageError::IoError(io) if io.kind() == io::ErrorKind::UnexpectedEof);
    if hit_eof || eof {
        return LoadError::Truncated { path, format: "Radiance HDR", len, detail: e.to_string() };
    }
    match e {
        ImageError::IoError(cause) => LoadError::Io { path, action: "read file", cause },
        e => LoadError::Hdr { path, message: e.to_string() },
    }
}

/// Reads an OpenEXR file: header first (validated by [`check_exr_header`]), then the
/// pixels of the selected R, G, B channels as f32. Returns width, height and row-major
/// texels (row 0 at the top of the data window).
fn read_exr(path: &Path, file: &mut (impl Read + Seek), len: u64) -> Result<Decoded, LoadError> {
    const FORMAT: &str = "OpenEXR";
    let (mut reader, _) = watched(path, file)?;
    header::exr(&mut reader, len).map_err(|cause| LoadError::Header { path: path.to_path_buf(), cause })?;
    let (reader, hit_eof) = watched(path, file)?;
    let meta = guarded(path, FORMAT, || {
        MetaData::read_from_buffered(reader, false)
            .map_err(|e| exr_error(path, len, hit_eof.load(Ordering::Relaxed), e))
    })?;
    let (width, height, [r, g, b]) = check_exr_header(path, &meta)?;
    let progress = (width >= super::PROGRESS_WIDTH)
        .then(|| Arc::new(crate::io::progress::Progress::new(height as u64, &format!("decoding {}", path.display()))));

    let (reader, hit_eof) = watched(path, file)?;
    let image = guarded(path, FORMAT, || {
        read()
            .no_deep_data()
            .largest_resolution_level()
            .specific_channels()
            .required(r)
            .required(g)
            .required(b)
            .collect_pixels(
                |size: Vec2<usize>, _: &(ChannelDescription, ChannelDescription, ChannelDescription)| {
                    Coverage::new(size.width(), size.height())
                },
                move |c: &mut Coverage, pos: Vec2<usize>, (r, g, b): (f32, f32, f32)| {
                    if let (0, Some(p)) = (pos.x(), &progress) {
                        p.inc();
                    }
                    c.set(pos.x(), pos.y(), [r, g, b])
                },
            )
            .first_valid_layer()
            .all_attributes()
            .non_parallel()
            .from_buffered(reader)
            .map_err(|e| exr_error(path, len, hit_eof.load(Ordering::Relaxed), e))
    })?;
    let layer = image.layer_data;
    if (layer.size.width(), layer.size.height()) != (width, height) {
        return Err(LoadError::Exr {
            path: path.to_path_buf(),
            message: format!(
                "decoded {}x{} pixels but the header says {width}x{height}",
                layer.size.width(),
                layer.size.height()
            ),
        });
    }
    let texels = layer
        .channel_data
        .pixels
        .finish()
        .map_err(|detail| LoadError::CorruptChunks { path: path.to_path_buf(), detail })?;
    Ok((width, height, texels))
}

/// The pixels of an OpenEXR layer as the decoder delivers them, with a record of which were
/// delivered: every pixel must come exactly once. The `exr` crate reads whatever chunk each
/// offset-table entry points at and places it by the y (or tile) coordinate stored in the chunk,
/// and leaves pixels no chunk covered at their initial value; so a duplicated or corrupt
/// offset, or a chunk whose coordinate was changed, would otherwise read as black rows.
struct Coverage {
    width: usize,
    texels: Vec<Texel>,
    /// One bit per pixel: delivered at least once.
    seen: Vec<u64>,
    /// The first pixel delivered twice.
    twice: Option<(usize, usize)>,
    /// The first pixel delivered outside the layer, and how many were.
    outside: Option<(usize, usize)>,
}

impl Coverage {
    fn new(width: usize, height: usize) -> Self {
        let n = width * height;
        Coverage { width, texels: vec![[0.0; 3]; n], seen: vec![0; n.div_ceil(64)], twice: None, outside: None }
    }

    fn set(&mut self, x: usize, y: usize, t: Texel) {
        let k = y.checked_mul(self.width).and_then(|k| k.checked_add(x)).filter(|_| x < self.width);
        let Some(slot) = k.and_then(|k| self.texels.get_mut(k).map(|s| (k, s))) else {
            self.outside.get_or_insert((x, y));
            return;
        };
        let (k, s) = slot;
        *s = t;
        let (word, bit) = (k / 64, 1u64 << (k % 64));
        if self.seen[word] & bit != 0 {
            self.twice.get_or_insert((x, y));
        }
        self.seen[word] |= bit;
    }

    /// The texels, if every pixel was delivered exactly once; else what went wrong.
    fn finish(self) -> Result<Vec<Texel>, String> {
        if let Some((x, y)) = self.twice {
            return Err(format!(
                "pixel (x={x}, y={y}) is stored twice (a duplicated chunk: two offset-table entries point at \
                 one chunk, or a chunk's coordinate is corrupt)"
            ));
        }
        if let Some((x, y)) = self.outside {
            return Err(format!("a chunk holds pixel (x={x}, y={y}), outside the data window"));
        }
        let ones: u64 = self.seen.iter().map(|w| w.count_ones() as u64).sum();
        let missing = self.texels.len() as u64 - ones;
        if missing > 0 {
            let k = (0..self.texels.len()).find(|&k| self.seen[k / 64] & (1 << (k % 64)) == 0).unwrap_or(0);
            let (x, y) = (k % self.width.max(1), k / self.width.max(1));
            return Err(format!(
                "{missing} pixel(s) are in no chunk, the first at (x={x}, y={y}) (a chunk is missing or \
                 its offset or coordinate is corrupt)"
            ));
        }
        Ok(self.texels)
    }
}

/// Validates OpenEXR meta data before any pixel is read: no deep data, one part, a size
/// accepted by [`check_size`], and R, G, B channels (see [`select_rgb`]) holding
/// full-resolution half or float samples. Returns the size and the three channel names.
fn check_exr_header(path: &Path, meta: &MetaData) -> Result<(usize, usize, [Text; 3]), LoadError> {
    let p = || path.to_path_buf();
    if meta.requirements.has_deep_data || meta.headers.iter().any(|h| h.deep) {
        return Err(LoadError::Deep { path: p() });
    }
    let header = match meta.headers.as_slice() {
        [h] => h,
        [] => return Err(LoadError::Exr { path: p(), message: "the file has no header".into() }),
        hs => {
            let names = hs
                .iter()
                .enumerate()
                .map(|(i, h)| match &h.own_attributes.layer_name {
                    Some(n) => format!("'{n}'"),
                    None => format!("part {i} unnamed"),
                })
                .collect::<Vec<_>>()
                .join(", ");
            return Err(LoadError::MultiPart { path: p(), parts: hs.len(), names });
        }
    };
    let (width, height) = (header.layer_size.width(), header.layer_size.height());
    check_size(path, width, height)?;
    let list = &header.channels.list;
    let chosen = select_rgb(path, list)?;
    for &i in &chosen {
        let c = &list[i];
        if c.sample_type == SampleType::U32 {
            return Err(LoadError::IntegerChannel { path: p(), channel: c.name.to_string() });
        }
        if (c.sampling.x(), c.sampling.y()) != (1, 1) {
            return Err(LoadError::Subsampled {
                path: p(),
                channel: c.name.to_string(),
                x: c.sampling.x(),
                y: c.sampling.y(),
            });
        }
    }
    let [r, g, b] = chosen.map(|i| list[i].name.clone());
    Ok((width, height, [r, g, b]))
}

/// Picks the indices of the red, green and blue channels: the unprefixed `R`, `G`, `B` if
/// all three exist, otherwise `L.R`, `L.G`, `L.B` of the one layer `L` that has all three.
/// Several such layers is an ambiguity error; none is a missing-channel error naming what
/// is missing from the most complete candidate set and every channel the file has.
fn select_rgb(path: &Path, list: &[ChannelDescription]) -> Result<[usize; 3], LoadError> {
    let names: Vec<String> = list.iter().map(|c| c.name.to_string()).collect();
    let find = |prefix: &str, c: char| {
        let full = if prefix.is_empty() { c.to_string() } else { format!("{prefix}.{c}") };
        names.iter().position(|n| *n == full)
    };
    let full_set = |prefix: &str| match (find(prefix, 'R'), find(prefix, 'G'), find(prefix, 'B')) {
        (Some(r), Some(g), Some(b)) => Some([r, g, b]),
        _ => None,
    };
    if let Some(set) = full_set("") {
        return Ok(set);
    }
    // Layer prefixes that have at least one of R, G, B, in channel-list order.
    let mut prefixes: Vec<&str> = Vec::new();
    for n in &names {
        let prefix = n.strip_suffix(".R").or(n.strip_suffix(".G")).or(n.strip_suffix(".B"));
        if let Some(p) = prefix {
            if !prefixes.contains(&p) {
                prefixes.push(p);
            }
        }
    }
    let complete: Vec<&str> = prefixes.iter().copied().filter(|p| full_set(p).is_some()).collect();
    match complete.as_slice() {
        [only] => {
            if let Some(set) = full_set(only) {
                return Ok(set);
            }
        }
        [] => {}
        several => {
            let layers = several.iter().map(|p| format!("'{p}'")).collect::<Vec<_>>().join(", ");
            return Err(LoadError::AmbiguousChannels { path: path.to_path_buf(), layers });
        }
    }
    // Report against the candidate set with the most channels present (unprefixed on ties).
    let present_count = |p: &str| ['R', 'G', 'B'].iter().filter(|&&c| find(p, c).is_some()).count();
    let mut best = "";
    for p in &prefixes {
        if present_count(p) > present_count(best) {
            best = p;
        }
    }
    let missing = ['R', 'G', 'B']
        .iter()
        .filter(|&&c| find(best, c).is_none())
        .map(|&c| if best.is_empty() { c.to_string() } else { format!("{best}.{c}") })
        .collect::<Vec<_>>()
        .join(", ");
    let present = if names.is_empty() { "(none)".to_string() } else { names.join(", ") };
    Err(LoadError::MissingChannel { path: path.to_path_buf(), missing, present })
}

/// Reads a Radiance RGBE file: its header first ([`header::hdr`]: size limits, `EXPOSURE=`),
/// then the pixels with the `image` crate, whose buffer is allocated only after the size was
/// checked. Returns width, height, row-major texels (row 0 at the top) divided by the product
/// of the `EXPOSURE=` values as Radiance defines them, and that product.
fn read_hdr(path: &Path, file: &mut (impl Read + Seek), len: u64) -> Result<(Decoded, f64), LoadError> {
    let (mut reader, _) = watched(path, file)?;
    let head = header::hdr(&mut reader).map_err(|cause| LoadError::Header { path: path.to_path_buf(), cause })?;
    let (reader, hit_eof) = watched(path, file)?;
    let eof = || hit_eof.load(Ordering::Relaxed);
    let exposure = head.exposure;
    guarded(path, "Radiance HDR", || {
        // Non-strict: `detect` has already seen the "#?" signature, and this also accepts
        // "#?RGBE" files, which the strict mode (requiring "#?RADIANCE") refuses.
        let decoder = HdrDecoder::new_nonstrict(reader).map_err(|e| hdr_error(path, len, eof(), e))?;
        let (w, h) = decoder.dimensions();
        let (width, height) = (w as usize, h as usize);
        check_size(path, width, height)?;
        let bytes = usize::try_from(decoder.total_bytes()).map_err(|_| LoadError::TooLarge {
            path: path.to_path_buf(),
            width,
            height,
        })?;
        let mut buf = vec![0u8; bytes];
        decoder.read_image(&mut buf).map_err(|e| hdr_error(path, len, eof(), e))?;
        let scale = |v: f32| if exposure == 1.0 { v } else { (f64::from(v) / exposure) as f32 };
        let texels = buf
            .chunks_exact(12)
            .map(|px| {
                let f = |k: usize| scale(f32::from_ne_bytes([px[k], px[k + 1], px[k + 2], px[k + 3]]));
                [f(0), f(4), f(8)]
            })
            .collect();
        Ok(((width, height, texels), exposure))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A loaded map carries the sha256 of its file's bytes (the provenance identity), and a
    /// map built in memory carries none. The digest of the written file is taken here
    /// independently of the loader's single read.
    #[test]
    fn loaded_map_carries_its_file_digest() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("two.exr");
        let map = EnvMap::new("two", 4, 2, (0..8).map(|i| [i as f32, 0.5, 2.0]).collect()).unwrap();
        assert_eq!(map.sha256, None);
        write_exr(&path, &map).unwrap();
        let want: String = Sha256::digest(std::fs::read(&path).unwrap()).iter().map(|b| format!("{b:02x}")).collect();
        let back = load(&path).unwrap();
        assert_eq!(back.sha256.as_deref(), Some(want.as_str()));
        assert_eq!(want.len(), 64);
    }

    #[test]
    fn guarded_turns_a_panic_into_an_error() {
        let path = Path::new("maps/x.exr");
        let r: Result<(), LoadError> = guarded(path, "OpenEXR", || panic!("index out of bounds"));
        let msg = r.unwrap_err().to_string();
        assert_eq!(msg, "maps/x.exr: OpenEXR decoder failed on malformed data (it panicked: index out of bounds)");
        let r = guarded(path, "OpenEXR", || Ok(7));
        assert_eq!(r.unwrap(), 7);
    }

    #[test]
    fn detect_uses_content_not_extension() {
        let p = Path::new("a.hdr");
        assert_eq!(detect(p, &EXR_MAGIC).unwrap(), Format::Exr);
        assert_eq!(detect(Path::new("a.exr"), b"#?RA").unwrap(), Format::Hdr);
        let msg = detect(Path::new("a.exr"), b"\x89PNG").unwrap_err().to_string();
        assert!(msg.starts_with("a.exr: unrecognised file format: bad magic number"), "{msg}");
        assert!(msg.contains("89 50 4e 47") && msg.contains("ends in .exr"), "{msg}");
    }

    #[test]
    fn check_size_order_of_checks() {
        let p = Path::new("m.exr");
        assert!(matches!(check_size(p, 0, 0), Err(LoadError::ZeroSize { .. })));
        assert!(matches!(check_size(p, 32768, 16384), Err(LoadError::TooLarge { .. })));
        assert!(matches!(check_size(p, 1, 1), Err(LoadError::Map { .. })));
        assert!(check_size(p, MAX_WIDTH, MAX_HEIGHT).is_ok());
        assert!(check_size(p, 2, 1).is_ok());
    }
}
