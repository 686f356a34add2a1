//! The three dice variants (`ambient_dice`, `ambient_dice_ycocg`, `ambient_dice_srbf`): the
//! scalar basis functions each fits and their non-zero values at a normal.

use super::geometry::{bezier_weights, Geometry};
use glam::DVec3;

/// A dice variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// `ambient_dice`: the Bézier basis in every channel.
    Bezier,
    /// `ambient_dice_ycocg`: Y in the Bézier basis, Co and Cg in the linear basis.
    BezierYCoCg,
    /// `ambient_dice_srbf`: the cosine SRBF lobes in every channel.
    Srbf,
}

impl Variant {
    pub(super) fn id(self) -> &'static str {
        match self {
            Variant::Bezier => "ambient_dice",
            Variant::BezierYCoCg => "ambient_dice_ycocg",
            Variant::Srbf => "ambient_dice_srbf",
        }
    }

    /// The scalar basis functions whose moments a fit takes: 36 Bézier, 36 + 12 (Bézier then
    /// linear) or 12 SRBF.
    pub(super) fn functions(self) -> usize {
        match self {
            Variant::Bezier => 36,
            Variant::BezierYCoCg => 48,
            Variant::Srbf => 12,
        }
    }

    /// The unknowns of the normal equations: per channel (36, 12), or joint for Y/Co/Cg
    /// (36 + 12 + 12).
    pub(super) fn unknowns(self) -> usize {
        match self {
            Variant::Bezier => 36,
            Variant::BezierYCoCg => 60,
            Variant::Srbf => 12,
        }
    }

    /// The non-zero scalar basis values at `n`, as (index, value).
    pub(super) fn row(self, g: &Geometry, n: DVec3, out: &mut Vec<(u16, f64)>) {
        match self {
            Variant::Bezier | Variant::BezierYCoCg => {
                let (face, b) = g.locate(n);
                let w = bezier_weights(face, b);
                for (i, &v) in face.vertices.iter().enumerate() {
                    for (slot, &x) in w[i].iter().enumerate() {
                        out.push(((3 * v + slot) as u16, x));
                    }
                }
                if self == Variant::BezierYCoCg {
                    for (i, &v) in face.vertices.iter().enumerate() {
                        out.push(((36 + v) as u16, b[i]));
                    }
                }
            }
            Variant::Srbf => {
                for (i, &x) in g.srbf(n).iter().enumerate() {
                    if x != 0.0 {
                        out.push((i as u16, x));
                    }
                }
            }
        }
    }
}
