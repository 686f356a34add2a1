//! The `WxH` form of an output grid's resolution on the command line.

use anyhow::{bail, Context, Result};

/// Parses "WxH" with W = 2H.
pub fn parse_resolution(s: &str) -> Result<(usize, usize)> {
    let expected =
        || format!("resolution '{s}': expected WxH with W = 2H, e.g. 256x128", s = crate::math::echo::value(s));
    let (w, h) = s.split_once('x').with_context(expected)?;
    let (w, h): (usize, usize) = match (w.parse(), h.parse()) {
        (Ok(w), Ok(h)) => (w, h),
        _ => bail!(expected()),
    };
    if w != 2 * h || !(2..=4096).contains(&h) {
        bail!("resolution '{s}': expected W = 2H with 2 <= H <= 4096", s = crate::math::echo::value(s));
    }
    Ok((w, h))
}
