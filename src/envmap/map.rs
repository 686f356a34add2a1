//! The map: [`EnvMap`], a lat-long grid of linear RGB texels, checked on construction (2:1,
//! every value finite, non-negative and at most [`MAX_TEXEL`]), and [`MapError`], what
//! construction refuses.
//! Orientation and geometry: [`super::latlong`] (FORMULAS §1).

use super::latlong::LatLong;
use rayon::prelude::*;
use std::path::PathBuf;

/// Linear RGB radiance of one texel, as stored (f32 keeps 1024×512 maps at 6 MiB).
pub type Texel = [f32; 3];

/// The largest texel value a map may hold: 1e24. Every number a table holds (an error, a
/// coefficient, a mean) is the map's radiance times a factor the encoders keep small (the
/// hard-case sanity bound: an rmse at most twice the RMS irradiance), and a table's numbers
/// lie within ±1e30 (`pipeline::table_cells::MAX_CELL`); 1e24 leaves a factor of a million
/// between them. Real radiance, even the sun's in absolute units, is below 1e10. A map of
/// 3e38 texels once ran, wrote a baseline with rmse 3.47e31, and every later check refused it.
pub const MAX_TEXEL: f32 = 1e24;

/// A lat-long environment map of linear RGB radiance.
#[derive(Clone, Debug)]
pub struct EnvMap {
    /// Name used in tables: the file stem (e.g. `grace_256x128`) or a generated scene's id.
    pub name: String,
    /// Where it was read from, if from a file.
    pub path: Option<PathBuf>,
    /// The sha256 (hex) of the file it was read from, if from a file.
    pub sha256: Option<String>,
    /// Its pixel sha256 (`identity`), when opened through the search path, or when formed
    /// while an OpenEXR file was decoded (`envmap::load`).
    pub pixel_sha256: Option<String>,
    /// The product of the `EXPOSURE=` values of the Radiance file it was read from, which the
    /// file's pixel values were divided by to give radiance (Radiance's rule); 1 for any other
    /// map.
    pub exposure: f64,
    /// What was done to the file's colour beyond the exposure, for provenance: a Radiance
    /// `COLORCORR=` undone, primaries other than Rec.709 converted (`envmap::load`); empty
    /// when nothing was.
    pub colour: String,
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
    /// Some texel values are NaN, infinite, negative or above [`MAX_TEXEL`].
    #[error("{count} texel value(s) are {kind} (first at pixel x={x}, y={y}, channel {channel})")]
    BadTexels {
        /// Which kind of bad value: "NaN", "infinite", "negative" or "above the bound 1e24 …"
        /// (the first kind found, in that order).
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
    /// every value is finite, non-negative and at most [`MAX_TEXEL`].
    pub fn new(name: impl Into<String>, width: usize, height: usize, texels: Vec<Texel>) -> Result<Self, MapError> {
        if height == 0 || width != 2 * height {
            return Err(MapError::Aspect { width, height });
        }
        if texels.len() != width * height {
            return Err(MapError::Count { width, height, got: texels.len() });
        }
        // The common case in one parallel pass: every value in [0, MAX_TEXEL] (NaN fails both
        // comparisons). Only a map that fails it is searched kind by kind for the message.
        let fine = |v: f32| (0.0..=MAX_TEXEL).contains(&v);
        if texels.par_chunks(1 << 16).all(|c| c.iter().all(|t| t.iter().all(|&v| fine(v)))) {
            return Ok(Self::checked(name.into(), width, height, texels));
        }
        for (kind, bad) in [
            ("NaN", (|v: f32| v.is_nan()) as fn(f32) -> bool),
            ("infinite", |v: f32| v.is_infinite()),
            ("negative", |v: f32| v < 0.0),
            (
                "above the bound 1e24 (a map's texels are at most 1e24, so that every table's numbers stay within ±1e30)",
                |v: f32| v > MAX_TEXEL,
            ),
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
        Ok(Self::checked(name.into(), width, height, texels))
    }

    /// A map from texels already checked by [`EnvMap::new`].
    fn checked(name: String, width: usize, height: usize, texels: Vec<Texel>) -> Self {
        Self {
            name,
            path: None,
            sha256: None,
            pixel_sha256: None,
            exposure: 1.0,
            colour: String::new(),
            width,
            height,
            texels,
        }
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

#[cfg(test)]
mod tests {
    use super::*;

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

    /// The bound holds at 1e24 exactly (as f32) and refuses the next f32 up, and 3e38 (below
    /// f32::MAX: the value that once wrote an unreadable baseline), naming the texel.
    #[test]
    fn texels_above_the_bound_are_refused_with_their_pixel() {
        let at = 1e24f32;
        assert!(EnvMap::new("a", 4, 2, vec![[at; 3]; 8]).is_ok());
        for big in [f32::from_bits(at.to_bits() + 1), 3e38] {
            let mut t = vec![[1.0f32; 3]; 8];
            t[6][2] = big;
            let e = EnvMap::new("a", 4, 2, t).unwrap_err().to_string();
            assert!(e.contains("above the bound 1e24") && e.contains("x=2, y=1, channel B"), "{e}");
        }
    }
}
