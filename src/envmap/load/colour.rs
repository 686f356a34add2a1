//! What a file says about its colour, applied after decoding: Radiance's `EXPOSURE=` and
//! `COLORCORR=` (the file's pixel values are the radiance times their products, per channel
//! for `COLORCORR`), and primaries other than Rec.709 (a Radiance `PRIMARIES=` line, an
//! OpenEXR `chromaticities` attribute), converted to Rec.709 ([`crate::math::primaries`]).

use super::error::LoadError;
use crate::envmap::map::Texel;
use crate::math::primaries::Chromaticities;
use glam::DVec3;
use std::path::Path;

/// What a file states about its colour (the defaults: nothing to undo, Rec.709).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Stated {
    /// The product of the `EXPOSURE=` values (1 without any, and for OpenEXR).
    pub exposure: f64,
    /// The per-channel product of the `COLORCORR=` values (1, 1, 1 without any).
    pub colorcorr: [f64; 3],
    /// The primaries the file states, when it states any.
    pub primaries: Option<Chromaticities>,
}

impl Default for Stated {
    fn default() -> Self {
        Stated { exposure: 1.0, colorcorr: [1.0; 3], primaries: None }
    }
}

/// Undoes the exposure and colour correction (dividing each channel by exposure × its
/// COLORCORR product) and converts other primaries to Rec.709, in place. Returns what was done
/// beyond the exposure, for the map's provenance (empty when nothing). A texel that the
/// conversion makes negative lies outside Rec.709's gamut: it is refused, naming the pixel,
/// since clipping it would change the light silently.
pub(super) fn apply(path: &Path, width: usize, texels: &mut [Texel], stated: &Stated) -> Result<String, LoadError> {
    let divisor = stated.colorcorr.map(|c| stated.exposure * c);
    if divisor != [1.0; 3] {
        for t in texels.iter_mut() {
            for (v, d) in t.iter_mut().zip(divisor) {
                *v = (f64::from(*v) / d) as f32;
            }
        }
    }
    let mut done = Vec::new();
    if stated.colorcorr != [1.0; 3] {
        let [r, g, b] = stated.colorcorr;
        done.push(format!("COLORCORR={r} {g} {b} (the file's pixel values divided by it per channel)"));
    }
    let Some(from) = stated.primaries.filter(|p| !p.is_rec709()) else { return Ok(done.join("; ")) };
    let bad = |why: String| LoadError::Primaries { path: path.to_path_buf(), primaries: from.describe(), why };
    let m = from.to_rec709().map_err(bad)?;
    for (i, t) in texels.iter_mut().enumerate() {
        let c = m * DVec3::new(f64::from(t[0]), f64::from(t[1]), f64::from(t[2]));
        // Rounding may leave a hair below zero where the light is in gamut.
        let floor = -1e-6 * c.abs().max_element();
        if let Some(k) = (0..3).find(|&k| c[k] < floor) {
            let channel = ['R', 'G', 'B'][k];
            let why = format!(
                "pixel x={}, y={} is outside Rec.709's gamut once converted ({channel} = {:e}); \
                 probelab does not clip light: convert the map to Rec.709 with the gamut mapping of your choice",
                i % width,
                i / width,
                c[k]
            );
            return Err(bad(why));
        }
        *t = c.max(DVec3::ZERO).as_vec3().to_array();
    }
    done.push(format!("converted from primaries {} to Rec.709 (D65, Bradford adaptation)", from.describe()));
    Ok(done.join("; "))
}
