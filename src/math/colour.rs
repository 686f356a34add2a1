//! Colour: linear RGB and its Rec.709 luminance (FORMULAS §4), and its CIE 1931 xy
//! chromaticity with the chroma error both the claims (Z2) and the comparison sheets use.
//!
//! `Rgb` is a named alias of `DVec3`, not a newtype: colours and SH coefficients go through
//! the same vector arithmetic (sums, scalings, `dot`, `max_element`, `map`) as directions, and a
//! newtype would have to re-export all of it. The name documents intent at every signature; a
//! direction is always a `DVec3` and a colour always an `Rgb` (docs/decisions.md).

use glam::DVec3;

/// Linear RGB value (radiance, or irradiance as E/π). Components are R, G, B.
pub type Rgb = DVec3;

/// Rec.709 luminance weights (FORMULAS §4): L(c) = REC709 · c.
pub const REC709: Rgb = Rgb::new(0.2126, 0.7152, 0.0722);

/// Rec.709 luminance of a linear RGB value: REC709 · c.
pub fn luminance(c: Rgb) -> f64 {
    c.dot(REC709)
}

/// The standard Rec.709/sRGB (D65) RGB → CIE XYZ matrix, by rows (X, Y, Z) (IEC 61966-2-1).
const RGB_TO_XYZ: [Rgb; 3] = [
    Rgb::new(0.4124564, 0.3575761, 0.1804375),
    Rgb::new(0.2126729, 0.7151522, 0.0721750),
    Rgb::new(0.0193339, 0.1191920, 0.9503041),
];

/// The D65 white point's CIE 1931 xy chromaticity, which black is given.
pub const D65_XY: (f64, f64) = (0.3127, 0.3290);

/// CIE 1931 xy chromaticity of a displayed linear Rec.709 colour (clamped at 0, as displayed),
/// through the standard Rec.709/sRGB (D65) RGB → XYZ matrix; black is the D65 white point.
pub fn cie_xy(e: Rgb) -> (f64, f64) {
    let c = e.max(Rgb::ZERO);
    let [x, y, z] = RGB_TO_XYZ.map(|row| row.dot(c));
    let s = x + y + z;
    if s > 0.0 {
        (x / s, y / s)
    } else {
        D65_XY
    }
}

/// The CIE luminance Y of a linear Rec.709 colour, clamped at 0: the middle row of the RGB →
/// XYZ matrix, so the chroma error weights by the same Y its chromaticities are taken with.
/// Those are the Rec.709 weights to seven digits; [`REC709`] rounds them to four (and would
/// move claim Z2's published figures).
pub fn cie_y(e: Rgb) -> f64 {
    RGB_TO_XYZ[1].dot(e).max(0.0)
}

/// The CIE 1931 xy distance between the displayed chromaticities ([`cie_xy`]) of a test and a
/// reference colour: the chroma error of one normal (one pixel of a sheet).
pub fn xy_distance(test: Rgb, reference: Rgb) -> f64 {
    xy_distance_squared(test, reference).sqrt()
}

/// The square of [`xy_distance`], summed as the claims always have (so their figures keep
/// every bit).
fn xy_distance_squared(test: Rgb, reference: Rgb) -> f64 {
    let ((tx, ty), (rx, ry)) = (cie_xy(test), cie_xy(reference));
    (tx - rx).powi(2) + (ty - ry).powi(2)
}

/// The chroma error of claim Z2 and of the sheets' chroma discs, a documented standard metric:
/// the RMS of the CIE 1931 xy distance ([`xy_distance`]) between test and reference, each
/// normal weighted by `w` (its solid angle, or 1 per pixel) times the reference's luminance Y
/// ([`cie_y`]), so that what is lit counts and dark regions (whose chromaticity is noise) do
/// not; 0 where nothing is lit.
pub fn xy_error(test: &[Rgb], reference: &[Rgb], w: &[f64]) -> f64 {
    let (mut s, mut ws) = (0.0, 0.0);
    for ((t, r), &wi) in test.iter().zip(reference).zip(w) {
        let wl = wi * cie_y(*r);
        s += wl * xy_distance_squared(*t, *r);
        ws += wl;
    }
    if ws > 0.0 {
        (s / ws).sqrt()
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Rec.709 primaries and white have their standard CIE 1931 xy chromaticities (ITU-R
    /// BT.709: red (0.64, 0.33), green (0.30, 0.60), blue (0.15, 0.06), D65 (0.3127, 0.3290)),
    /// to the 4 digits the standard gives.
    #[test]
    fn cie_xy_of_the_rec709_primaries() {
        let near = |(x, y): (f64, f64), (ex, ey): (f64, f64)| (x - ex).abs() < 1e-4 && (y - ey).abs() < 1e-4;
        assert!(near(cie_xy(Rgb::new(1.0, 0.0, 0.0)), (0.64, 0.33)));
        assert!(near(cie_xy(Rgb::new(0.0, 2.0, 0.0)), (0.30, 0.60)));
        assert!(near(cie_xy(Rgb::new(0.0, 0.0, 0.5)), (0.15, 0.06)));
        assert!(near(cie_xy(Rgb::splat(3.0)), D65_XY));
        assert_eq!(cie_xy(Rgb::ZERO), D65_XY);
    }

    /// Grey against grey of any level is 0 (both sit at the matrix's white); the red and green primaries are
    /// √((0.64 − 0.30)² + (0.33 − 0.60)²) = √(0.34² + 0.27²) = 0.4342 apart whatever their
    /// levels; a negative channel is clamped, as displayed.
    #[test]
    fn xy_distance_of_greys_and_of_two_primaries() {
        assert!(xy_distance(Rgb::splat(0.2), Rgb::splat(7.0)) < 1e-15);
        // Black is D65 as the standard rounds it (four decimals): within 1e-4 of a grey.
        assert!(xy_distance(Rgb::ZERO, Rgb::splat(1.0)) < 1e-4);
        let rg = (0.34f64.powi(2) + 0.27f64.powi(2)).sqrt();
        assert!((xy_distance(Rgb::new(3.0, 0.0, 0.0), Rgb::new(0.0, 0.5, 0.0)) - rg).abs() < 2e-4);
        assert_eq!(xy_distance(Rgb::new(1.0, -1.0, 0.0), Rgb::new(1.0, 0.0, 0.0)), 0.0);
    }

    /// xy_error weights by the reference's luminance: a wrong colour where the reference is
    /// black counts for nothing; red shown where green is lit counts the red–green distance
    /// 0.4342 in full.
    #[test]
    fn xy_error_counts_what_is_lit() {
        let (r, g) = (Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 1.0, 0.0));
        let e = xy_error(&[r, r], &[g, Rgb::ZERO], &[1.0, 1.0]);
        assert!((e - (0.34f64.powi(2) + 0.27f64.powi(2)).sqrt()).abs() < 2e-4, "{e}");
        assert_eq!(xy_error(&[r], &[Rgb::ZERO], &[1.0]), 0.0);
        assert_eq!(xy_error(&[g * 5.0], &[g], &[1.0]), 0.0);
    }

    /// The weights sum to one, so a grey's luminance is its value, and they are the
    /// ITU-R BT.709 primaries' Y row (0.2126, 0.7152, 0.0722).
    #[test]
    fn grey_keeps_its_value_and_primaries_weigh_as_bt709() {
        assert!((REC709.x + REC709.y + REC709.z - 1.0).abs() < 1e-15);
        assert_eq!(luminance(Rgb::splat(0.5)), 0.5);
        assert_eq!(luminance(Rgb::X), 0.2126);
        assert_eq!(luminance(Rgb::Y), 0.7152);
        assert_eq!(luminance(Rgb::Z), 0.0722);
    }
}
