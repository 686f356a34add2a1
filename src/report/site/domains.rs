//! The output grids the site shows: the sphere and the hemisphere about +Y (a floor), on a
//! [`SITE_RESOLUTION`] lat-long grid of normals: the grids of
//! `probelab eval --resolution 24x12 --domain …` (`reference::domain::Domain::output_grid`),
//! so the page's RMSE over a grid is the one `eval` prints for it. Two domains on a coarse grid
//! keep the whole site under 10 MB with every committed map (docs/report.md).

use crate::pipeline::runner::Case;
use crate::reference::domain::{frame_to, OutputGrid};
use glam::DVec3;

/// The lat-long resolution (W, H) of every grid the site ships; a hemisphere keeps the upper
/// H/2 rows in its frame.
pub(super) const SITE_RESOLUTION: (usize, usize) = (24, 12);

/// One domain the site shows.
#[derive(Clone, Debug)]
pub(super) struct SiteDomain {
    /// `sphere` or `hemisphere:+y`: `eval --domain`'s spelling.
    pub(super) label: &'static str,
    /// The surface normal N of a hemisphere.
    pub(super) normal: Option<DVec3>,
}

/// The domains, in the page's order.
pub(super) fn site_domains() -> Vec<SiteDomain> {
    vec![
        SiteDomain { label: "sphere", normal: None },
        SiteDomain { label: "hemisphere:+y", normal: Some(DVec3::Y) },
    ]
}

impl SiteDomain {
    /// The case `eval --domain` scores: the whole sphere, or the light above N's horizon.
    pub(super) fn case(&self) -> Case {
        match self.normal {
            None => Case::sphere(),
            Some(n) => Case::hemisphere(n, self.label.to_string()),
        }
    }

    /// The output grid at [`SITE_RESOLUTION`].
    pub(super) fn grid(&self) -> OutputGrid {
        self.case().domain.output_grid(SITE_RESOLUTION)
    }

    /// The rotation from the grid's frame (pole +Y) to the world, row-major 3×3: the identity
    /// for the sphere.
    pub(super) fn frame(&self) -> [f64; 9] {
        let m = glam::DMat3::from_quat(frame_to(self.normal.unwrap_or(DVec3::Y)));
        // The transpose's columns are the rows of m.
        m.transpose().to_cols_array()
    }
}
