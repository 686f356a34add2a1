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
mod latlong;
pub mod load;
mod map;
pub mod moments;
pub mod resample;
pub mod search;

pub use latlong::LatLong;
#[cfg(test)]
pub(crate) use map::MAX_TEXEL;
pub use map::{EnvMap, Texel};

/// Maps at least this many texels wide show progress while they are decoded and while the
/// exact reference runs over them.
pub const PROGRESS_WIDTH: usize = 4096;
