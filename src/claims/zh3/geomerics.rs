//! Claim Z5: the normalised Geomerics reconstruction (FORMULAS §6) is non-negative and keeps
//! the DC term but not the linear moment, so it over-brightens the side facing away from the
//! light.

use super::cases::{enc, exact, fit, values, Case};
use super::{mean, pct, yes, Finding};
use crate::math::colour::Rgb;
use crate::reference::domain::OutputGrid;
use anyhow::Result;
use glam::DVec3;
use std::fmt::Write as _;

/// Z5: Geomerics is non-negative and keeps DC but not the linear moment, so it over-brightens.
pub(super) fn z5(grid: &OutputGrid, cases: &[Case]) -> Result<(Finding, String)> {
    let g = enc("geomerics", &[])?;
    let sh1 = enc("sh1", &[])?;
    let mut table = String::from(
        "| map | min value | DC rel. error | linear moment geo/ref | dark-side mean error / ref mean | RMSE geomerics | RMSE sh1 |\n|---|---|---|---|---|---|---|\n",
    );
    let wsum: f64 = grid.weights.iter().sum();
    let (mut nonneg, mut dc_ok, mut moment_low, mut bright) = (true, true, 0, 0);
    let mut sh1_dev = 0.0f64;
    let mut moments = Vec::new();
    let mut darks = Vec::new();
    for case in cases {
        let v = values(fit(g.as_ref(), &case.sh).as_ref(), grid);
        let lum = |e: Rgb| e.element_sum() / 3.0;
        let min = v.iter().map(|x| x.min_element()).fold(f64::INFINITY, f64::min);
        let mean_of = |f: &[Rgb]| f.iter().zip(&grid.weights).map(|(x, w)| lum(*x) * w).sum::<f64>() / wsum;
        let moment_of = |f: &[Rgb]| -> DVec3 {
            f.iter().zip(&grid.normals).zip(&grid.weights).map(|((x, n), w)| *n * (lum(*x) * w)).sum::<DVec3>() / wsum
        };
        let (mg, mr) = (mean_of(&v), mean_of(&case.reference));
        let dc = (mg - mr) / mr;
        let (lg, lr) = (moment_of(&v), moment_of(&case.reference));
        let ratio = lg.length() / lr.length();
        // SH L1 keeps the linear moment exactly; its measured ratio shows the quadrature error.
        let v1 = values(fit(sh1.as_ref(), &case.sh).as_ref(), grid);
        let r1 = moment_of(&v1).length() / lr.length();
        sh1_dev = sh1_dev.max((r1 - 1.0).abs());
        // The side facing away from the light: n·(linear moment) < 0.
        let d = lr.normalize_or_zero();
        let (mut se, mut sw) = (0.0, 0.0);
        for ((x, r), (n, w)) in v.iter().zip(&case.reference).zip(grid.normals.iter().zip(&grid.weights)) {
            if n.dot(d) < 0.0 {
                se += (lum(*x) - lum(*r)) * w;
                sw += w;
            }
        }
        let dark = se / sw / mr;
        nonneg &= min >= 0.0;
        dc_ok &= dc.abs() < 1e-3;
        moment_low += (ratio < 1.0 - 10.0 * (r1 - 1.0).abs().max(1e-6)) as usize;
        bright += (dark > 0.0) as usize;
        moments.push(ratio);
        darks.push(dark);
        let (eg, e1) = (exact(g.as_ref(), case, grid).rmse, exact(sh1.as_ref(), case, grid).rmse);
        let _ = writeln!(
            table,
            "| {} | {min:.4} | {dc:.1e} | {ratio:.4} (sh1 {r1:.4}) | {} | {eg:.5} | {e1:.5} |",
            case.name,
            pct(dark)
        );
    }
    let peer = enc("geomerics_peer", &[])?;
    let constant = fit(peer.as_ref(), &crate::math::sh::constant(Rgb::ONE)).irradiance(DVec3::Y).x;
    let ours = fit(g.as_ref(), &crate::math::sh::constant(Rgb::ONE)).irradiance(DVec3::Y).x;
    let holds = nonneg && dc_ok && moment_low == cases.len() && bright * 2 > cases.len();
    Ok((
        Finding {
            id: "Z5",
            claim: "Geomerics is non-negative and keeps the DC term but not the linear moment, so it over-brightens",
            paper_figure: "qualitative".into(),
            our_figure: format!(
                "non-negative on all 5 probes: {}; DC kept to < 1e-3: {}; linear moment geo/ref {:.3}–{:.3} (sh1 within {sh1_dev:.0e}), \
                 reduced on {moment_low}/5; dark side too bright on {bright}/5 (mean {})",
                yes(nonneg),
                yes(dc_ok),
                moments.iter().cloned().fold(f64::INFINITY, f64::min),
                moments.iter().cloned().fold(0.0, f64::max),
                pct(mean(&darks))
            ),
            holds: yes(holds),
            notes: format!(
                "normalised geomerics (FORMULAS §6): constant environment gives {ours}; the peer's variant gives {constant:.4} \
                 (2/√π); moments of the luminance (mean of RGB) over the sphere; dark side = normals facing away from the \
                 reference's linear moment"
            ),
        },
        format!("Exact reference, sphere, solid-angle weights, 256x128 normals.\n\n{table}"),
    ))
}
