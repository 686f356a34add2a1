//! The zonal term about an axis a (ZH3 talk; FORMULAS §5): the band-2 basis Y₂(a) and its
//! Jacobian, the stored least-squares coefficient k = (4π/5)·Y₂(a)·T₂, and the hallucinated
//! coefficient from the radiance ratio and a hallucination curve.

use crate::math::sh::k as shk;
use glam::DVec3;
use std::f64::consts::PI;

/// 4π/5: the least-squares zonal coefficient is k = (4π/5)·Y₂(a)·L₂ since |Y₂(a)|² = 5/(4π).
pub const FOUR_PI_OVER_5: f64 = 4.0 * PI / 5.0;

/// The tetrahedron axes of the multi-start, (±1, ±1, ±1)/√3 with an even number of minus
/// signs (FORMULAS §5).
pub fn tetrahedron_axes() -> [DVec3; 4] {
    let s = 1.0 / 3f64.sqrt();
    [DVec3::new(s, s, s), DVec3::new(s, -s, -s), DVec3::new(-s, s, -s), DVec3::new(-s, -s, s)]
}

/// The five band-2 basis functions at unit direction `a` (FORMULAS §2, indices 4..8) and their
/// derivatives with respect to the components of `a` (as polynomials in x, y, z).
#[inline]
pub fn band2_with_jacobian(a: DVec3) -> ([f64; 5], [[f64; 3]; 5]) {
    let (x, y, z) = (a.x, a.y, a.z);
    let (b, c0, c2) = (shk::Y2_XY, shk::Y20, shk::Y22);
    let y2 = [b * x * y, -b * y * z, c0 * (3.0 * z * z - 1.0), -b * x * z, c2 * (x * x - y * y)];
    let j = [
        [b * y, b * x, 0.0],
        [0.0, -b * z, -b * y],
        [0.0, 0.0, 6.0 * c0 * z],
        [-b * z, 0.0, -b * x],
        [2.0 * c2 * x, -2.0 * c2 * y, 0.0],
    ];
    (y2, j)
}

/// The band-2 basis at `a`.
#[inline]
pub fn band2(a: DVec3) -> [f64; 5] {
    band2_with_jacobian(a).0
}

/// The least-squares zonal coefficient of the L2 band `l2` about the unit axis `a`:
/// k = (4π/5)·Σ_m Y₂ₘ(a)·L₂ₘ, so that L₂ₘ ≈ k·Y₂ₘ(a) (FORMULAS §5).
pub fn zonal_fit(a: DVec3, l2: &[f64; 5]) -> f64 {
    zonal_fit_at(&band2(a), l2)
}

/// [`zonal_fit`] with the band-2 basis `y` = Y₂(a) of the axis already at hand.
#[inline]
pub fn zonal_fit_at(y: &[f64; 5], l2: &[f64; 5]) -> f64 {
    FOUR_PI_OVER_5 * (0..5).map(|m| y[m] * l2[m]).sum::<f64>()
}

/// The hallucination curve f/L₀₀ = g(r) of the radiance ratio r = |L1·a|/L₀₀ (FORMULAS §5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Curve {
    /// g(r) = c₁r + c₂r² + c₃r³ (the paper's curve fit is c = (0.08, 0.6, 0)).
    Poly([f64; 3]),
    /// Ambient plus one delta light: g(r) = √(5/3)·r.
    AmbientDirectional,
    /// A uniform sphere light: g(r) = (2√5/3)r² − √(5/3)r for r ≥ √3/2, and 0 below, where the
    /// model has no sphere light (the two pieces meet at 0).
    SphereLight,
}

impl Curve {
    /// The paper's curve fit, 0.08r + 0.6r².
    pub const PAPER: Curve = Curve::Poly([0.08, 0.6, 0.0]);

    /// g(r) and g′(r).
    #[inline]
    pub fn eval(&self, r: f64) -> (f64, f64) {
        match *self {
            Curve::Poly([c1, c2, c3]) => (r * (c1 + r * (c2 + r * c3)), c1 + r * (2.0 * c2 + 3.0 * c3 * r)),
            Curve::AmbientDirectional => {
                let s = (5.0f64 / 3.0).sqrt();
                (s * r, s)
            }
            Curve::SphereLight => {
                if r < 0.5 * 3f64.sqrt() {
                    (0.0, 0.0)
                } else {
                    let (a, b) = (2.0 * 5f64.sqrt() / 3.0, (5.0f64 / 3.0).sqrt());
                    (a * r * r - b * r, 2.0 * a * r - b)
                }
            }
        }
    }
}

/// How the zonal coefficient k follows from the axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Zonal {
    /// The least-squares fit of the target's L2 band about the axis (stored ZH3).
    Stored,
    /// The hallucination curve of the ratio (hallucinated ZH3; nothing extra stored).
    Hallucinated(Curve),
}

/// √(4π/5)·¼: k_irr = √(4π/5)·f_irr and f_irr = ¼·f_rad.
pub(super) const K_HALLUCINATE: f64 = 0.25 * 1.585_330_919_042_404_4; // √(4π/5)

/// Radiance ratio from irradiance L1: the band scale 2/3 is undone.
pub(super) const RATIO_SCALE: f64 = 1.5;

/// The hallucinated zonal coefficient k (irradiance) of a channel with irradiance L0 `l0` and
/// irradiance L1 vector `v` about unit axis `a`: r = 1.5·|v·a|/L0 (the radiance ratio),
/// f_rad = L0·g(r), k = √(4π/5)·¼·f_rad (FORMULAS §5). 0 when L0 ≤ 0.
#[inline]
pub fn hallucinated_k(l0: f64, v: DVec3, a: DVec3, curve: Curve) -> f64 {
    if l0.is_nan() || l0 <= 0.0 {
        return 0.0;
    }
    let r = RATIO_SCALE * v.dot(a).abs() / l0;
    K_HALLUCINATE * l0 * curve.eval(r).0
}
