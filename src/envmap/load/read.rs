//! Opening a map file: [`load`] (the format from the first bytes, the decoding, the file's
//! sha256 read beside it, every texel checked) and [`dimensions`] (the size from the header
//! alone).

use super::error::LoadError;
use super::exr::{check_exr_header, read_exr};
use super::exr_blocks::exr_error;
use super::format::{detect, Format};
use super::guard::guarded;
use super::hash::sha256_hex_of;
use super::hdr::{hdr_error, read_hdr};
use super::size::check_size;
use super::watch::watched;
use crate::envmap::header;
use crate::envmap::map::EnvMap;
use exr::prelude::MetaData;
use image::codecs::hdr::HdrDecoder;
use image::ImageDecoder;
use std::fs::{self, File};
use std::io::{self, Read};
use std::path::Path;
use std::sync::atomic::Ordering;

/// Loads a lat-long map from an OpenEXR or Radiance RGBE file.
///
/// The format is taken from the file's first bytes. The map is named after the file stem
/// and remembers `path`. Fails with a [`LoadError`] naming the file if it cannot be read,
/// is not a supported format, is malformed or truncated, claims a size above
/// [`MAX_WIDTH`] x [`MAX_HEIGHT`], is not 2:1, lacks R, G, B channels (or names one twice),
/// has a pixel aspect other than 1, or has a NaN, infinite, negative or too large texel.
/// Exposure, colour correction and primaries other than Rec.709 are applied
/// ([`super::colour`]). Never panics on bad input.
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
            Format::Exr => read_exr(path, &mut file, meta.len()),
            Format::Hdr => read_hdr(path, &mut file, meta.len()).map(|(d, s)| (d, s, None)),
        };
        (decoded, hasher.join().unwrap_or_else(|_| Err(io::Error::other("the hashing thread failed"))))
    });
    let ((width, height, mut texels), stated, pixels) = decoded?;
    let colour = super::colour::apply(path, width, &mut texels, &stated)?;
    let digest = digest.map_err(|e| io_err("read file", e))?;
    let name = path.file_stem().unwrap_or(path.as_os_str()).to_string_lossy().into_owned();
    let mut map =
        EnvMap::new(name, width, height, texels).map_err(|cause| LoadError::Map { path: path.to_path_buf(), cause })?;
    map.path = Some(path.to_path_buf());
    map.sha256 = Some(digest);
    map.exposure = stated.exposure;
    // A pixel sha256 formed while decoding names the texels as decoded: kept only when the
    // colour left them as they were.
    map.pixel_sha256 = pixels.filter(|_| colour.is_empty() && stated.exposure == 1.0);
    map.colour = colour;
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
    let format = detect(path, &head)?;
    // The same header pre-read as `load`'s, before any decoder parses (and allocates for) the
    // header: 100,000 attributes once took 80 MB here before being refused.
    let (mut reader, _) = watched(path, &mut file)?;
    let header_error = |cause| LoadError::Header { path: path.to_path_buf(), cause };
    match format {
        Format::Exr => header::exr(&mut reader, len).map(|_| ()),
        Format::Hdr => header::hdr(&mut reader).map(|_| ()),
    }
    .map_err(header_error)?;
    let (reader, hit_eof) = watched(path, &mut file)?;
    match format {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::envmap::load::write_exr;
    use sha2::{Digest, Sha256};

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
}
