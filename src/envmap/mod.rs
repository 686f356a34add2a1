//! Lat-long environment maps: the texel grid, its directions and exact solid angles.
//!
//! Orientation (FORMULAS §1, `../shared/envmaps/SOURCES.md`): pixel centre u = (i+½)/W,
//! v = (j+½)/H; azimuth θ = 2π(u − ½), polar angle φ = πv measured from +Y;
//! direction = (sin φ sin θ, cos φ, −sin φ cos θ). Row 0 is the zenith (+Y).
//!
//! A map is read as piecewise-constant radiance over its texel cells. Everything that
//! integrates a map (the SH projection, the exact reference) integrates those cells, not
//! point samples at their centres.

pub mod header;
pub mod identity;
pub mod import;
pub mod known;
pub mod load;
pub mod moments;
pub mod resample;
pub mod search;

/// Maps at least this many texels wide show progress while they are decoded and while the
/// exact reference runs over them.
pub const PROGRESS_WIDTH: usize = 4096;

use crate::math::convention::direction;
use glam::DVec3;
use std::f64::consts::PI;
use std::path::PathBuf;

/// Linear RGB radiance of one texel, as stored (f32 keeps 1024×512 maps at 6 MiB).
pub type Texel = [f32; 3];

/// A lat-long environment map of linear RGB radiance.
#[derive(Clone, Debug)]
pub struct EnvMap {
    /// Name used in tables: the file stem (e.g. `grace_256x128`) or a generated scene's id.
    pub name: String,
    /// Where it was read from, if from a file.
    pub path: Option<PathBuf>,
    /// The sha256 (hex) of the file it was read from, if from a file.
    pub sha256: Option<String>,
    /// Its pixel sha256 (`identity`), when opened through the search path.
    pub pixel_sha256: Option<String>,
    /// The product of the `EXPOSURE=` values of the Radiance file it was read from, which the
    /// file's pixel values were divided by to give radiance (Radiance's rule); 1 for any other
    /// map.
    pub exposure: f64,
    width: usize,
    height: usize,
    texels: Vec<Texel>,
}

/// Errors of map construction that do not involve a file (the loader wraps them with the path).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MapError {
    /// The size is not a 2:1 lat-long grid (width ≠ 2 × height, or height 0).
    #[error("size {width}x{height} is not a 2:1 lat-long map (width must be 2 x height, height >= 1)")]
    Aspect {
        /// Width in texels.
        width: usize,
        /// Height in texels.
        height: usize,
    },
    /// The number of texels given differs from width × height.
    #[error("texel count {got} does not match {width}x{height}")]
    Count {
        /// Width in texels.
        width: usize,
        /// Height in texels.
        height: usize,
        /// Number of texels given.
        got: usize,
    },
    /// Some texel values are NaN, infinite or negative.
    #[error("{count} texel value(s) are {kind} (first at pixel x={x}, y={y}, channel {channel})")]
    BadTexels {
        /// Which kind of bad value: "NaN", "infinite" or "negative" (the first kind found, in that
        /// order).
        kind: &'static str,
        /// How many channel values are of that kind.
        count: usize,
        /// Column of the first such texel.
        x: usize,
        /// Row of the first such texel (row 0 at the zenith).
        y: usize,
        /// Channel of the first such value: 'R', 'G' or 'B'.
        channel: char,
    },
}

impl EnvMap {
    /// Builds a map from row-major texels (row 0 = zenith), checking the 2:1 aspect and that
    /// every value is finite and non-negative.
    pub fn new(name: impl Into<String>, width: usize, height: usize, texels: Vec<Texel>) -> Result<Self, MapError> {
        if height == 0 || width != 2 * height {
            return Err(MapError::Aspect { width, height });
        }
        if texels.len() != width * height {
            return Err(MapError::Count { width, height, got: texels.len() });
        }
        for (kind, bad) in [
            ("NaN", (|v: f32| v.is_nan()) as fn(f32) -> bool),
            ("infinite", |v: f32| v.is_infinite()),
            ("negative", |v: f32| v < 0.0),
        ] {
            let mut first = None;
            let mut count = 0usize;
            for (i, t) in texels.iter().enumerate() {
                for (c, &v) in t.iter().enumerate() {
                    if bad(v) {
                        count += 1;
                        first.get_or_insert((i, c));
                    }
                }
            }
            if let Some((i, c)) = first {
                return Err(MapError::BadTexels {
                    kind,
                    count,
                    x: i % width,
                    y: i / width,
                    channel: ['R', 'G', 'B'][c],
                });
            }
        }
        Ok(Self {
            name: name.into(),
            path: None,
            sha256: None,
            pixel_sha256: None,
            exposure: 1.0,
            width,
            height,
            texels,
        })
    }

    /// Builds a map by evaluating `f(i, j)` for every texel (row j, column i).
    pub fn from_fn(
        name: impl Into<String>,
        width: usize,
        height: usize,
        mut f: impl FnMut(usize, usize) -> Texel,
    ) -> Result<Self, MapError> {
        let mut texels = Vec::with_capacity(width * height);
        for j in 0..height {
            for i in 0..width {
                texels.push(f(i, j));
            }
        }
        Self::new(name, width, height, texels)
    }

    /// Width of the map in texels (twice the height).
    pub fn width(&self) -> usize {
        self.width
    }
    /// Height of the map in texels (rows from zenith to nadir).
    pub fn height(&self) -> usize {
        self.height
    }
    /// Row-major texels, row 0 at the zenith.
    pub fn texels(&self) -> &[Texel] {
        &self.texels
    }
    /// The texel in row `j`, column `i`.
    pub fn texel(&self, i: usize, j: usize) -> Texel {
        self.texels[j * self.width + i]
    }
    /// One row of texels.
    pub fn row(&self, j: usize) -> &[Texel] {
        &self.texels[j * self.width..(j + 1) * self.width]
    }
    /// The same map scaled by `k` (k ≥ 0 and finite).
    pub fn scaled(&self, k: f32) -> Self {
        let mut m = self.clone();
        for t in &mut m.texels {
            for v in t.iter_mut() {
                *v *= k;
            }
        }
        m
    }

    /// The grid geometry of this map.
    pub fn grid(&self) -> LatLong {
        LatLong::new(self.width, self.height)
    }
}

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

    #[test]
    fn rejects_bad_aspect_and_values() {
        assert_eq!(EnvMap::new("a", 3, 2, vec![[0.0; 3]; 6]).unwrap_err(), MapError::Aspect { width: 3, height: 2 });
        let mut t = vec![[1.0f32; 3]; 8];
        t[5][1] = f32::NAN;
        t[6][2] = f32::NAN;
        match EnvMap::new("a", 4, 2, t).unwrap_err() {
            MapError::BadTexels { kind, count, x, y, channel } => {
                assert_eq!((kind, count, x, y, channel), ("NaN", 2, 1, 1, 'G'))
            }
            e => panic!("{e}"),
        }
        let mut t = vec![[1.0f32; 3]; 8];
        t[0][0] = -1.0;
        assert!(matches!(EnvMap::new("a", 4, 2, t), Err(MapError::BadTexels { kind: "negative", .. })));
    }
}
