//! The geometry of a W×H lat-long grid, independent of any texel values (FORMULAS §1): edges
//! and centres of its rows and columns, the exact solid angle of a texel, the direction of a
//! texel's centre and the texel containing a direction.
//!
//! Orientation (`../shared/envmaps/SOURCES.md`): pixel centre u = (i+½)/W, v = (j+½)/H;
//! azimuth θ = 2π(u − ½), polar angle φ = πv measured from +Y;
//! direction = (sin φ sin θ, cos φ, −sin φ cos θ). Row 0 is the zenith (+Y).

use crate::math::convention::direction;
use glam::DVec3;
use std::f64::consts::PI;

/// The geometry of a W×H lat-long grid (independent of any texel values): used for maps and
/// for output grids of normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LatLong {
    /// Number of columns (azimuth steps).
    pub width: usize,
    /// Number of rows (polar steps, zenith to nadir).
    pub height: usize,
}

impl LatLong {
    /// A grid of `width` × `height` texels; the sizes are not checked.
    pub fn new(width: usize, height: usize) -> Self {
        Self { width, height }
    }
    /// Azimuth width of one texel, 2π/W.
    pub fn dtheta(&self) -> f64 {
        2.0 * PI / self.width as f64
    }
    /// Polar angle of the top edge of row j (φ_j = πj/H); `j = H` gives the bottom edge π.
    pub fn phi_edge(&self, j: usize) -> f64 {
        PI * j as f64 / self.height as f64
    }
    /// Azimuth of the left edge of column i: θ = 2π(i/W − ½).
    pub fn theta_edge(&self, i: usize) -> f64 {
        2.0 * PI * (i as f64 / self.width as f64 - 0.5)
    }
    /// Polar angle of the centre of row j.
    pub fn phi_centre(&self, j: usize) -> f64 {
        PI * (j as f64 + 0.5) / self.height as f64
    }
    /// Azimuth of the centre of column i.
    pub fn theta_centre(&self, i: usize) -> f64 {
        2.0 * PI * ((i as f64 + 0.5) / self.width as f64 - 0.5)
    }
    /// Exact solid angle of a texel of row j: (2π/W)(cos φ₀ − cos φ₁).
    pub fn solid_angle(&self, j: usize) -> f64 {
        self.dtheta() * (self.phi_edge(j).cos() - self.phi_edge(j + 1).cos())
    }
    /// Direction of the centre of texel (i, j) (FORMULAS §1).
    pub fn direction(&self, i: usize, j: usize) -> DVec3 {
        direction(self.theta_centre(i), self.phi_centre(j))
    }
    /// The texel (i, j) whose cell contains direction `d` (its nearest texel, as the peer tool
    /// reads a map: `Image::sampleNearest` of `cartesianToLatLongTexcoord`): u = θ/2π + ½,
    /// v = φ/π, (⌊uW⌋, ⌊vH⌋) clamped to the grid.
    pub fn texel_at(&self, d: DVec3) -> (usize, usize) {
        let (theta, phi) = crate::math::convention::angles(d);
        let u = theta / (2.0 * PI) + 0.5;
        let v = phi / PI;
        let i = ((u * self.width as f64).floor().max(0.0) as usize).min(self.width - 1);
        let j = ((v * self.height as f64).floor().max(0.0) as usize).min(self.height - 1);
        (i, j)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solid_angles_sum_to_4pi() {
        for (w, h) in [(2, 1), (8, 4), (256, 128), (1000, 500), (1024, 512)] {
            let g = LatLong::new(w, h);
            let total: f64 = (0..h).map(|j| g.solid_angle(j) * w as f64).sum();
            assert!((total - 4.0 * PI).abs() < 1e-12, "{w}x{h}: {total}");
        }
    }

    #[test]
    fn orientation_matches_sources_md() {
        let g = LatLong::new(256, 128);
        // Row 0 is +Y, last row -Y.
        assert!(g.direction(10, 0).y > 0.999);
        assert!(g.direction(10, 127).y < -0.999);
        // u = 0.5 is -Z, u = 0.75 is +X, u = 0.25 is -X.
        let eq = 64; // near the equator: phi = pi*64.5/128
        assert!(g.direction(128, eq).dot(DVec3::NEG_Z) > 0.99);
        assert!(g.direction(192, eq).dot(DVec3::X) > 0.99);
        assert!(g.direction(64, eq).dot(DVec3::NEG_X) > 0.99);
    }

    /// Every texel centre maps back to its texel, and so do points just inside its corners.
    #[test]
    fn texel_at_inverts_the_cell() {
        let g = LatLong::new(16, 8);
        for j in 0..8 {
            for i in 0..16 {
                assert_eq!(g.texel_at(g.direction(i, j)), (i, j));
                for (fi, fj) in [(0.01, 0.01), (0.99, 0.99), (0.01, 0.99), (0.99, 0.01)] {
                    let t = g.theta_edge(i) + fi * g.dtheta();
                    let p = g.phi_edge(j) + fj * PI / 8.0;
                    assert_eq!(g.texel_at(direction(t, p)), (i, j), "({i},{j}) at ({fi},{fj})");
                }
            }
        }
        assert_eq!(g.texel_at(DVec3::Y).1, 0);
        assert_eq!(g.texel_at(DVec3::NEG_Y).1, 7);
    }
}
