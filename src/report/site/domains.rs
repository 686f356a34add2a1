//! The output grids the site shows: the sphere, the hemisphere about +Y (a floor) with every
//! encoder, and the hemispheres about [`SURFACE_NORMALS`] (a ceiling and the walls) with the
//! encoders defined about a surface normal (lightmaps and occlusion operators) and those the page
//! evaluates itself; each on a [`SITE_RESOLUTION`] lat-long grid of normals: the grids of
//! `probelab eval --resolution 24x12 --domain …` (`reference::domain::Domain::output_grid`),
//! so the page's RMSE over a grid is the one `eval` prints for it. A coarse grid, and the other
//! normals only for the encoders whose picture they change, keep the whole site under 10 MB
//! with every committed map (docs/report.md, docs/decisions.md).

use crate::pipeline::runner::Case;
use crate::reference::domain::{frame_to, OutputGrid};
use glam::DVec3;

/// The lat-long resolution (W, H) of every grid the site ships; a hemisphere keeps the upper
/// H/2 rows in its frame.
pub(super) const SITE_RESOLUTION: (usize, usize) = (24, 12);

/// The hemispheres besides the floor's, as `eval --domain` spells them with their normals: the
/// ceiling and four walls, so the six axes the lightmap experiments declare are all shown.
pub(super) const SURFACE_NORMALS: [(&str, DVec3); 5] = [
    ("hemisphere:-y", DVec3::NEG_Y),
    ("hemisphere:+x", DVec3::X),
    ("hemisphere:-x", DVec3::NEG_X),
    ("hemisphere:+z", DVec3::Z),
    ("hemisphere:-z", DVec3::NEG_Z),
];

/// Which encoders a domain shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Shows {
    /// Every encoder defined on the domain (on the sphere, those that need no surface normal).
    Every,
    /// The encoders defined about a surface normal, and those the page evaluates itself.
    SurfaceAndPage,
}

/// One domain the site shows.
#[derive(Clone, Debug)]
pub(super) struct SiteDomain {
    /// `sphere` or `hemisphere:±x|±y|±z`: `eval --domain`'s spelling.
    pub(super) label: &'static str,
    /// The surface normal N of a hemisphere.
    pub(super) normal: Option<DVec3>,
    /// Which encoders it shows.
    pub(super) shows: Shows,
}

/// The domains, in the page's order: the sphere, the floor, then [`SURFACE_NORMALS`].
pub(super) fn site_domains() -> Vec<SiteDomain> {
    let mut v = vec![
        SiteDomain { label: "sphere", normal: None, shows: Shows::Every },
        SiteDomain { label: "hemisphere:+y", normal: Some(DVec3::Y), shows: Shows::Every },
    ];
    v.extend(SURFACE_NORMALS.iter().map(|&(label, n)| SiteDomain {
        label,
        normal: Some(n),
        shows: Shows::SurfaceAndPage,
    }));
    v
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
