//! PNG encoding of the pictures, and writing them atomically
//! ([`crate::io::atomic::write`]).

use anyhow::Result;
use image::RgbImage;
use std::path::Path;

/// PNG bytes of an image (default deflate level: within 0.5% of the best level in size at two
/// thirds of the report's time; deterministic).
pub fn png_bytes(img: &RgbImage) -> Result<Vec<u8>> {
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    use image::ImageEncoder;
    let mut out = Vec::new();
    PngEncoder::new_with_quality(&mut out, CompressionType::Default, FilterType::Adaptive).write_image(
        img.as_raw(),
        img.width(),
        img.height(),
        image::ExtendedColorType::Rgb8,
    )?;
    Ok(out)
}

/// Writes an image as PNG, atomically.
pub fn write_png(path: &Path, img: &RgbImage) -> Result<()> {
    crate::io::atomic::write(path, &png_bytes(img)?)
}
