//! Painting pixels of the pictures: the paper and cell backgrounds, filled rectangles, and a
//! lit disc ([`Disc`]) blended over its background by each pixel's coverage.

use crate::reference::view::Disc;
use image::RgbImage;

/// Background of a picture.
pub const PAPER: [u8; 3] = [255, 255, 255];
/// Background of a sphere's cell.
pub const CELL: [u8; 3] = [214, 214, 214];

/// Fills the rectangle (x0, y0, w, h) with `c`, clipped to the image.
pub fn fill(img: &mut RgbImage, x0: u32, y0: u32, w: u32, h: u32, c: [u8; 3]) {
    for y in y0..(y0 + h).min(img.height()) {
        for x in x0..(x0 + w).min(img.width()) {
            img.put_pixel(x, y, image::Rgb(c));
        }
    }
}

/// Paints a disc at (x0, y0): pixel colour `colour(normal index)` blended over `bg` by coverage.
pub fn paint_disc(img: &mut RgbImage, x0: u32, y0: u32, disc: &Disc, bg: [u8; 3], colour: impl Fn(usize) -> [u8; 3]) {
    for py in 0..disc.d {
        for px in 0..disc.d {
            let k = py * disc.d + px;
            let Some(i) = disc.index[k] else { continue };
            let a = disc.coverage[k] as f64;
            let c = colour(i);
            let mixed = [0, 1, 2].map(|j| (c[j] as f64 * a + bg[j] as f64 * (1.0 - a)).round() as u8);
            let (x, y) = (x0 + px as u32, y0 + py as u32);
            if x < img.width() && y < img.height() {
                img.put_pixel(x, y, image::Rgb(mixed));
            }
        }
    }
}
