//! RGB primaries and white points, and the conversion of linear RGB stated in other primaries
//! to Rec.709 (ITU-R BT.709, white D65), the space every map is read in.
//!
//! The standard construction (SMPTE RP 177): the matrix to CIE XYZ has the primaries'
//! chromaticities (x, y, 1 − x − y) as columns, each scaled so that RGB = (1, 1, 1) gives the
//! white point's XYZ at Y = 1 (the scales are positive exactly when the white lies inside the
//! primaries' triangle; ACES AP0's blue has y < 0, so a primary's XYZ is not taken at Y = 1). A white point other than D65 is adapted to D65 with the Bradford
//! transform (von Kries scaling in the Bradford cone space), as OpenEXR's ACES files and the
//! published ACES matrices do. The conversion is M = XYZ→Rec.709 · Bradford(white → D65) ·
//! RGB→XYZ.

use glam::{DMat3, DVec3};

/// The chromaticities (CIE 1931 x, y) of three primaries and a white point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chromaticities {
    /// Red, green, blue primaries: (x, y) each.
    pub primaries: [[f64; 2]; 3],
    /// The white point: (x, y).
    pub white: [f64; 2],
}

/// Rec.709 (and sRGB): its primaries and the D65 white point.
pub const REC709: Chromaticities =
    Chromaticities { primaries: [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]], white: [0.3127, 0.3290] };

/// How close each coordinate must be to Rec.709's to be taken as Rec.709 (files store them as
/// f32, and some writers round them to four decimals).
const SAME: f64 = 1e-4;

/// The Bradford cone-response matrix (rows).
const BRADFORD: DMat3 = DMat3::from_cols(
    DVec3::new(0.8951, -0.7502, 0.0389),
    DVec3::new(0.2664, 1.7135, -0.0685),
    DVec3::new(-0.1614, 0.0367, 1.0296),
);

/// XYZ at Y = 1 of chromaticity (x, y), y > 0.
fn xyz(c: [f64; 2]) -> DVec3 {
    DVec3::new(c[0] / c[1], 1.0, (1.0 - c[0] - c[1]) / c[1])
}

impl Chromaticities {
    /// Whether these are Rec.709's primaries and white, to 1e-4 in every coordinate.
    pub fn is_rec709(&self) -> bool {
        let a = self.primaries.iter().chain([&self.white]).flatten();
        let b = REC709.primaries.iter().chain([&REC709.white]).flatten();
        a.zip(b).all(|(a, b)| (a - b).abs() <= SAME)
    }

    /// The matrix from linear RGB in these primaries to CIE XYZ (white at Y = 1), or why there
    /// is none (a y of 0, a non-finite coordinate, collinear primaries).
    fn to_xyz(&self) -> Result<DMat3, String> {
        let mut all = self.primaries.iter().chain([&self.white]).flatten();
        if all.any(|v| !v.is_finite()) || self.white[1] <= 0.0 {
            return Err("a chromaticity is not finite, or the white point has y <= 0".into());
        }
        let xyz1 = |c: [f64; 2]| DVec3::new(c[0], c[1], 1.0 - c[0] - c[1]);
        let m = DMat3::from_cols(xyz1(self.primaries[0]), xyz1(self.primaries[1]), xyz1(self.primaries[2]));
        let det = m.determinant();
        if !det.is_finite() || det.abs() < 1e-9 {
            return Err("the primaries are collinear: they span no colour space".into());
        }
        let s = m.inverse() * xyz(self.white);
        if !s.is_finite() || s.min_element() <= 0.0 {
            return Err("the white point lies outside the primaries' triangle".into());
        }
        Ok(m * DMat3::from_diagonal(s))
    }

    /// The matrix taking linear RGB in these primaries to linear Rec.709 RGB (white adapted to
    /// D65 with the Bradford transform; the module doc), or why there is none.
    pub fn to_rec709(&self) -> Result<DMat3, String> {
        let (src, dst) = (BRADFORD * xyz(self.white), BRADFORD * xyz(REC709.white));
        let adapt = BRADFORD.inverse() * DMat3::from_diagonal(dst / src) * BRADFORD;
        let m = REC709.to_xyz()?.inverse() * adapt * self.to_xyz()?;
        if !m.is_finite() {
            return Err("the conversion is not finite".into());
        }
        Ok(m)
    }

    /// The chromaticities as text: `R(x,y) G(x,y) B(x,y) white(x,y)`.
    pub fn describe(&self) -> String {
        let [r, g, b] = self.primaries;
        // Files store chromaticities as f32: shown to five decimals (0.7347, not 0.734700024…).
        let r5 = |v: f64| (v * 1e5).round() / 1e5;
        let p = |c: [f64; 2]| format!("({},{})", r5(c[0]), r5(c[1]));
        format!("R{} G{} B{} white{}", p(r), p(g), p(b), p(self.white))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ACES AP0 (SMPTE ST 2065-1: R(0.7347,0.2653) G(0,1) B(0.0001,-0.077), white
    /// (0.32168,0.33767)) to Rec.709 with Bradford adaptation: the published ACES2065-1 →
    /// linear sRGB/Rec.709 matrix, as renderers' colour-space tables print it to six decimals.
    #[test]
    fn aces_ap0_to_rec709_is_the_published_matrix() {
        let ap0 =
            Chromaticities { primaries: [[0.7347, 0.2653], [0.0, 1.0], [0.0001, -0.077]], white: [0.32168, 0.33767] };
        let published =
            [[2.521686, -1.134130, -0.387556], [-0.276479, 1.372719, -0.096240], [-0.015378, -0.152975, 1.168353]];
        let m = ap0.to_rec709().unwrap();
        for (i, row) in published.iter().enumerate() {
            for (j, want) in row.iter().enumerate() {
                let got = m.col(j)[i];
                assert!((got - want).abs() < 1e-6, "[{i}][{j}] = {got}, published {want}");
            }
        }
        assert!(!ap0.is_rec709());
    }

    /// Rec.709 to itself is the identity; white stays white in any primaries.
    #[test]
    fn rec709_is_the_identity_and_white_stays_white() {
        let m = REC709.to_rec709().unwrap();
        assert!((m - DMat3::IDENTITY).to_cols_array().iter().all(|v| v.abs() < 1e-12));
        assert!(REC709.is_rec709());
        let p3 = Chromaticities { primaries: [[0.68, 0.32], [0.265, 0.69], [0.15, 0.06]], white: [0.3127, 0.3290] };
        let w = p3.to_rec709().unwrap() * DVec3::ONE;
        assert!((w - DVec3::ONE).abs().max_element() < 1e-12, "{w}");
    }

    #[test]
    fn degenerate_chromaticities_have_no_matrix() {
        let flat = Chromaticities { primaries: [[0.3, 0.3], [0.4, 0.4], [0.5, 0.5]], white: [0.3127, 0.3290] };
        assert!(flat.to_rec709().unwrap_err().contains("collinear"));
        let zero = Chromaticities { white: [0.3127, 0.0], ..REC709 };
        assert!(zero.to_rec709().unwrap_err().contains("y <= 0"));
        let out = Chromaticities { white: [0.7, 0.25], ..REC709 };
        assert!(out.to_rec709().unwrap_err().contains("outside"));
    }
}
