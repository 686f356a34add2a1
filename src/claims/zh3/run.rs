//! Every ZH3 measurement, run in order (Z1–Z5, blending, quantisation) on the cases of the
//! declared maps the search path has, with progress.

use crate::claims::measure::Measure;
use crate::claims::zh3::axis;
use crate::claims::zh3::blending;
use crate::claims::zh3::cases;
use crate::claims::zh3::geomerics;
use crate::claims::zh3::quantisation;
use crate::envmap::search::SearchPath;
use anyhow::Result;

/// The maps a measurement ran on: (name, sha256 and reference description).
pub type MapsUsed = Vec<(String, String)>;

/// Runs every ZH3 measurement on those of `maps` (in order; see [`maps`]) that the search path
/// has; returns the tables and the maps used.
pub fn measure(search: &SearchPath, maps: &[String]) -> Result<(Vec<Measure>, MapsUsed)> {
    let progress = crate::io::progress::Progress::new(8, "claims: ZH3 measurements");
    let grid = cases::grid();
    let (cases, maps) = cases::probes(search, &grid, maps)?;
    progress.inc();
    type Step<'a> = (&'static str, Box<dyn Fn() -> Result<Measure> + 'a>);
    let steps: Vec<Step> = vec![
        ("Z3", Box::new(|| axis::z3(&grid, &cases))),
        ("Z4", Box::new(|| axis::z4(&grid, &cases))),
        ("Z5", Box::new(|| geomerics::z5(&grid, &cases))),
        ("blending", Box::new(|| blending::zh3_blend(&grid))),
        ("quantisation", Box::new(|| quantisation::quantised_sizes(&grid, &cases))),
    ];
    progress.message("Z1");
    let mut out = vec![axis::z1(&grid)?];
    progress.inc();
    progress.message("Z2");
    let (chroma, ordered) = axis::z2(&grid, &cases)?;
    out.extend([chroma, ordered]);
    progress.inc();
    for (what, step) in steps {
        progress.message(what);
        out.push(step()?);
        progress.inc();
    }
    Ok((out, maps))
}
