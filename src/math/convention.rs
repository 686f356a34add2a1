//! The direction convention (FORMULAS §1, `../shared/envmaps/SOURCES.md`): azimuth θ and
//! polar angle φ measured from +Y, direction = (sin φ sin θ, cos φ, −sin φ cos θ). +Y is up.
//! Nothing else in the crate knows which way is up.

use glam::DVec3;

/// The unit direction of azimuth θ and polar angle φ (FORMULAS §1):
/// (sin φ sin θ, cos φ, −sin φ cos θ).
pub fn direction(theta: f64, phi: f64) -> DVec3 {
    direction_of(theta.sin_cos(), phi.sin_cos())
}

/// [`direction`] from the sines and cosines of θ and φ, (sin θ, cos θ) and (sin φ, cos φ): for
/// a grid of directions, whose rows and columns share them.
#[inline]
pub fn direction_of((st, ct): (f64, f64), (sp, cp): (f64, f64)) -> DVec3 {
    DVec3::new(sp * st, cp, -sp * ct)
}

/// The (θ, φ) of a unit direction, inverse of [`direction`]; θ in [−π, π], φ in [0, π].
pub fn angles(d: DVec3) -> (f64, f64) {
    let phi = d.y.clamp(-1.0, 1.0).acos();
    let theta = d.x.atan2(-d.z);
    (theta, phi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_inverts_direction() {
        for &(t, p) in &[(0.3, 0.2), (-2.9, 1.5), (3.0, 3.0), (-0.1, 0.7)] {
            let (t2, p2) = angles(direction(t, p));
            assert!((t - t2).abs() < 1e-12 && (p - p2).abs() < 1e-12);
        }
    }
}
