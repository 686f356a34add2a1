//! The input map's lat-long thumbnail on a sheet: box-filtered, with its own exposure.

use super::super::tone::Tone;
use crate::envmap::EnvMap;
use crate::math::colour::{luminance, Rgb};
use image::RgbImage;

/// A lat-long thumbnail of a map (box-filtered to `w`×`w/2`), with its own exposure (mean
/// luminance → 0.5, Reinhard with white at the 99th-percentile texel).
pub fn latlong_thumbnail(map: &EnvMap, w: u32) -> RgbImage {
    let h = w / 2;
    let (mw, mh) = (map.width(), map.height());
    let box_of = |o: u32, n: u32, m: usize| {
        let a = (o as usize * m) / n as usize;
        let b = (((o as usize + 1) * m) / n as usize).max(a + 1).min(m);
        (a.min(m - 1), b)
    };
    let mut px = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        let (j0, j1) = box_of(y, h, mh);
        for x in 0..w {
            let (i0, i1) = box_of(x, w, mw);
            let mut acc = Rgb::ZERO;
            for j in j0..j1 {
                for i in i0..i1 {
                    let t = map.texel(i, j);
                    acc += Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64);
                }
            }
            px.push(acc / ((j1 - j0) * (i1 - i0)) as f64);
        }
    }
    let mut lum: Vec<f64> = px.iter().map(|&c| luminance(c)).collect();
    let mean = lum.iter().sum::<f64>() / lum.len() as f64;
    lum.sort_by(f64::total_cmp);
    let p99 = lum[((lum.len() - 1) as f64 * 0.99) as usize];
    let exposure = if mean > 0.0 { 0.5 / mean } else { 1.0 };
    let tone = Tone { exposure, white: (p99 * exposure).max(1.0) };
    RgbImage::from_fn(w, h, |x, y| image::Rgb(tone.map(px[(y * w + x) as usize])))
}
