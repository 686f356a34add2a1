//! Reading a Radiance RGBE (`.hdr`) map: its header first (size limits, line ends, `EXPOSURE=`,
//! `COLORCORR=`, `PRIMARIES=`, `PIXASPECT=`), then the pixels as the file stores them; what
//! the header states about colour is applied by [`super::colour`].

use super::colour::Stated;
use super::error::LoadError;
use super::format::Decoded;
use super::guard::guarded;
use super::size::check_size;
use super::watch::watched;
use crate::envmap::header;
use image::codecs::hdr::HdrDecoder;
use image::{ImageDecoder, ImageError};
use std::io::{self, Read, Seek};
use std::path::Path;
use std::sync::atomic::Ordering;

/// Reads a Radiance RGBE file: its header first ([`header::hdr`]), then the pixels with the
/// `image` crate, whose buffer is allocated only after the size was checked. Returns width,
/// height, row-major texels (row 0 at the top) as stored, and what the header states about
/// their colour (exposure, colour correction, primaries).
pub(super) fn read_hdr(path: &Path, file: &mut (impl Read + Seek), len: u64) -> Result<(Decoded, Stated), LoadError> {
    let (mut reader, _) = watched(path, file)?;
    let head = header::hdr(&mut reader).map_err(|cause| LoadError::Header { path: path.to_path_buf(), cause })?;
    let (reader, hit_eof) = watched(path, file)?;
    let eof = || hit_eof.load(Ordering::Relaxed);
    let stated = Stated { exposure: head.exposure, colorcorr: head.colorcorr, primaries: head.primaries };
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
        let texels = buf
            .chunks_exact(12)
            .map(|px| {
                let f = |k: usize| f32::from_ne_bytes([px[k], px[k + 1], px[k + 2], px[k + 3]]);
                [f(0), f(4), f(8)]
            })
            .collect();
        Ok(((width, height, texels), stated))
    })
}

/// Converts an `image` error from the HDR decoder into a [`LoadError`].
pub(super) fn hdr_error(path: &Path, len: u64, hit_eof: bool, e: ImageError) -> LoadError {
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
