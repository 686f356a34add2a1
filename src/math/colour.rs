//! Colour: linear RGB and its Rec.709 luminance (FORMULAS §4).
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

#[cfg(test)]
mod tests {
    use super::*;

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
