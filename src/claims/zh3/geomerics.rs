//! Claim Z5 (ZH3 talk): the Geomerics L1 reconstruction is non-negative and keeps the DC term
//! but not the linear moment, so it over-brightens the side facing away from the light.
//! Measured for both variants: ours, normalised (FORMULAS §6), and the peer tool's
//! (`geomerics_peer`, R0 = L00, biased by 2/√π for a constant environment) — what shipped and
//! what the talk compares — with SH L1, which keeps the linear moment exactly, for scale.

use super::cases::{enc, exact, fit, values, Case};
use crate::claims::measure::Measure;
use crate::math::colour::Rgb;
use crate::reference::domain::OutputGrid;
use anyhow::Result;
use glam::DVec3;

/// Z5, per map and encoder (geomerics, geomerics_peer, sh1): the smallest value over the
/// sphere, the DC (mean) error relative to the reference mean, the linear moment's length
/// relative to the reference's, the mean error on the dark side (normals facing away from the
/// reference's linear moment) relative to the reference mean, and the RMSE. Moments are of the
/// luminance (mean of RGB), solid-angle weighted on the 256x128 normals. Measure `geomerics`.
pub(super) fn z5(grid: &OutputGrid, cases: &[Case]) -> Result<Measure> {
    let mut m = Measure::new(
        "geomerics",
        "Z5: geomerics (normalised), geomerics_peer (the peer tool's, R0 = L00) and sh1; min_value = smallest \
         E/π over the sphere; dc_rel_err_abs = |mean − reference mean| / reference mean; moment_ratio = \
         |linear moment| / reference's (sh1 shows the quadrature floor); dark_side_bias = mean error over normals \
         facing away from the reference's linear moment / reference mean (> 0: too bright); rmse exact metric \
         (sphere, solid-angle, 256x128 normals, exact reference, E/π)",
        &["map", "encoder", "min_value", "dc_rel_err_abs", "moment_ratio", "dark_side_bias", "rmse"],
    );
    let wsum: f64 = grid.weights.iter().sum();
    let lum = |e: Rgb| e.element_sum() / 3.0;
    let mean_of = |f: &[Rgb]| f.iter().zip(&grid.weights).map(|(x, w)| lum(*x) * w).sum::<f64>() / wsum;
    let moment_of = |f: &[Rgb]| -> DVec3 {
        f.iter().zip(&grid.normals).zip(&grid.weights).map(|((x, n), w)| *n * (lum(*x) * w)).sum::<DVec3>() / wsum
    };
    for case in cases {
        let mr = mean_of(&case.reference);
        let lr = moment_of(&case.reference);
        let d = lr.normalize_or_zero();
        for id in ["geomerics", "geomerics_peer", "sh1"] {
            let e = enc(id, &[])?;
            let v = values(fit(e.as_ref(), &case.sh).as_ref(), grid);
            let min = v.iter().map(|x| x.min_element()).fold(f64::INFINITY, f64::min);
            let dc = ((mean_of(&v) - mr) / mr).abs();
            let ratio = moment_of(&v).length() / lr.length();
            let (mut se, mut sw) = (0.0, 0.0);
            for ((x, r), (n, w)) in v.iter().zip(&case.reference).zip(grid.normals.iter().zip(&grid.weights)) {
                if n.dot(d) < 0.0 {
                    se += (lum(*x) - lum(*r)) * w;
                    sw += w;
                }
            }
            let dark = if sw > 0.0 { se / sw / mr } else { 0.0 };
            let rmse = exact(e.as_ref(), case, grid).rmse;
            m.row(vec![
                case.name.clone().into(),
                id.into(),
                min.into(),
                dc.into(),
                ratio.into(),
                dark.into(),
                rmse.into(),
            ]);
        }
    }
    Ok(m)
}
