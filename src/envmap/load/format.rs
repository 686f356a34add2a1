//! The file formats the loader understands, told apart by the file's first bytes (the
//! extension is not trusted), and what decoding one gives.

use super::error::LoadError;
use crate::envmap::map::Texel;
use std::path::Path;

/// The four bytes every OpenEXR file starts with.
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
/// The two bytes every Radiance RGBE file starts with (`#?RADIANCE` or `#?RGBE`).
const HDR_SIGNATURE: [u8; 2] = *b"#?";

/// A decoded map: width, height and row-major texels.
pub(super) type Decoded = (usize, usize, Vec<Texel>);

/// The file formats [`super::load`] understands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Format {
    Exr,
    Hdr,
}

/// Identifies the format from the first (up to four) bytes of a file.
pub(super) fn detect(path: &Path, head: &[u8]) -> Result<Format, LoadError> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detect_uses_content_not_extension() {
        let p = Path::new("a.hdr");
        assert_eq!(detect(p, &EXR_MAGIC).unwrap(), Format::Exr);
        assert_eq!(detect(Path::new("a.exr"), b"#?RA").unwrap(), Format::Hdr);
        let msg = detect(Path::new("a.exr"), b"\x89PNG").unwrap_err().to_string();
        assert!(msg.starts_with("a.exr: unrecognised file format: bad magic number"), "{msg}");
        assert!(msg.contains("89 50 4e 47") && msg.contains("ends in .exr"), "{msg}");
    }
}
