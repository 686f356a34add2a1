//! Why a map file could not be loaded: [`LoadError`], one variant per fault, every message
//! starting with the file path.

use crate::envmap::header::{HeaderError, MAX_HEIGHT, MAX_WIDTH};
use crate::envmap::map::MapError;
use std::io;
use std::path::PathBuf;

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
    /// The file's primaries cannot be converted to Rec.709, or a pixel falls outside its gamut.
    #[error("{}: its colour primaries {primaries} (not Rec.709) cannot be converted: {why}", .path.display())]
    Primaries {
        /// The map file being loaded.
        path: PathBuf,
        /// The chromaticities the file states.
        primaries: String,
        /// Why not.
        why: String,
    },
    /// Two channels of the file have one name.
    #[error("{}: channel '{channel}' appears {count} times in the channel list; which one is meant is ambiguous, so the file is refused", .path.display())]
    DuplicateChannel {
        /// The map file being loaded.
        path: PathBuf,
        /// The channel's name (cut to 40 characters).
        channel: String,
        /// How many channels have that name.
        count: usize,
    },
    /// The pixel aspect ratio is not 1.
    #[error("{}: pixel aspect ratio {aspect}: a lat-long map's texels are square in angle (width = 2 x height); a pixel aspect other than 1 would stretch the sphere, so the map is refused", .path.display())]
    PixelAspect {
        /// The map file being loaded.
        path: PathBuf,
        /// The file's pixel aspect ratio.
        aspect: f32,
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
