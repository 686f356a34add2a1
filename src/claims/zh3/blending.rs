//! Claim Z9: blending two probes whose L1 axes are perpendicular. The blend's own zonal
//! coefficient about its axis is ¼ of an endpoint's for two delta lights (P₂(cos 45°));
//! interpolating stored ZH3 coefficients keeps the endpoint's, while hallucinated ZH3 shrinks
//! naturally. The candidates are SH, not encoder fits, so they are scored with
//! [`crate::reference::metrics::score`] directly on their evaluated values.

use super::cases::{cap, scene};
use super::{yes, Finding};
use crate::encoders::zh3::solve::{band2, zonal_fit, Curve};
use crate::encoders::zh3::{hallucinate, stored, AxisRule};
use crate::math::colour::{Rgb, REC709};
use crate::math::sh::{delta_light, Sh9};
use crate::reference::domain::OutputGrid;
use crate::reference::lighting::Light;
use crate::reference::metrics::score;
use anyhow::Result;
use glam::DVec3;
use std::fmt::Write as _;

/// Z9: blending two probes whose L1 axes are perpendicular.
pub(super) fn z9(grid: &OutputGrid) -> Result<(Finding, String)> {
    let mk = |axis: DVec3| scene("p", vec![cap(axis, 0.2, Rgb::splat(10.0)), Light::Ambient(Rgb::splat(0.1))]);
    let (a, b) = (mk(DVec3::X), mk(DVec3::Y));
    let blend = scene("blend", a.lighting.0.iter().chain(&b.lighting.0).cloned().collect());
    let half = |s: Sh9| s * 0.5;
    let (sa, sb) = (a.sh().convolve_cosine(), b.sh().convolve_cosine());
    let sh_blend = half(sa + sb); // irradiance SH3 of the blend (exact SH3 interpolation)
    let reference: Vec<Rgb> = grid.normals.iter().map(|&n| blend.irradiance(n) * 0.5).collect();
    let rule = AxisRule::Shared(Rgb::splat(1.0 / 3.0));
    let (za, zb) = (stored(&sa, rule), stored(&sb, rule));
    // (a) blend the stored ZH3 coefficients: L0, L1 and k averaged, axis from the blended L1.
    let mut zc = za;
    zc.l0 = (za.l0 + zb.l0) * 0.5;
    for c in 0..3 {
        zc.l1[c] = (za.l1[c] + zb.l1[c]) * 0.5;
    }
    zc.axes = rule.axes(&zc.l1);
    zc.k = (za.k + zb.k) * 0.5;
    let coeff_blend = zc.to_sh();
    // (b) expand each to SH3, blend: exact for these zonal probes.
    let sh3_blend = half(za.to_sh() + zb.to_sh());
    // (c) hallucinate from the blended L1.
    let hall = hallucinate(&sh_blend, AxisRule::Shared(REC709), Curve::PAPER);
    let hall_a = hallucinate(&sa, AxisRule::Shared(REC709), Curve::PAPER);
    // The zonal coefficient the blend should have: the least-squares fit of its L2 about its axis.
    let axis = zc.axes[0].expect("blended L1 is non-zero");
    let k_true = zonal_fit(axis, &crate::encoders::zh3::solve::l2_band(&sh_blend, 0));
    let k_end = za.k.x;
    let r = |k: f64| k / k_end;
    let rms = |s: &Sh9| {
        let v: Vec<Rgb> = grid.normals.iter().map(|&n| s.eval(n)).collect();
        score(&reference, &v, &grid.weights, false).rmse
    };
    let sh1_blend = sh_blend.truncate(1);
    let rows = [
        ("blend stored ZH3 coefficients", r(zc.k.x), rms(&coeff_blend)),
        (
            "blend expanded SH3",
            r(zonal_fit(axis, &crate::encoders::zh3::solve::l2_band(&sh3_blend, 0))),
            rms(&sh3_blend),
        ),
        ("hallucinate from blended L1", hall.k.x / hall_a.k.x, rms(&hall.to_sh())),
        ("SH L1 of the blend", 0.0, rms(&sh1_blend)),
    ];
    let mut table = String::from("| method | zonal coefficient / endpoint's | RMSE vs exact blend |\n|---|---|---|\n");
    for (m, k, e) in rows {
        let _ = writeln!(table, "| {m} | {k:.4} | {e:.5} |");
    }
    let _ = writeln!(
        table,
        "\nThe blend's own zonal coefficient about its axis / the endpoint's: {:.4} (¼ for two delta lights).",
        r(k_true)
    );
    let holds = (rows[0].1 - 1.0).abs() < 1e-9
        && (rows[1].1 - r(k_true)).abs() < 1e-9
        && rows[2].1 < 1.0
        && rows[0].2 > rows[1].2;
    // Check, for the record, that a delta light pair gives exactly ¼.
    let da = delta_light(DVec3::X, Rgb::ONE);
    let db = delta_light(DVec3::Y, Rgb::ONE);
    let ax = (DVec3::X + DVec3::Y).normalize();
    let k_delta = zonal_fit(ax, &crate::encoders::zh3::solve::l2_band(&half(da + db), 0))
        / zonal_fit(DVec3::X, &crate::encoders::zh3::solve::l2_band(&da, 0));
    let _ = band2(ax);
    Ok((
        Finding {
            id: "Z9",
            claim: "Averaging two linear SH with perpendicular axes should scale the ZH3 coefficient by ¼; interpolating stored ZH3 coefficients does not; hallucinated ZH3 shrinks naturally",
            paper_figure: "¼ (two perpendicular axes)".into(),
            our_figure: format!(
                "zonal coefficient of the 50% blend / endpoint: stored-coefficient blend {:.3}, expanded-SH3 blend {:.3} (the blend's own; two delta lights: {k_delta:.4}), \
                 hallucinated from blended L1 {:.3}; RMSE vs exact blend {:.4} / {:.4} / {:.4}",
                rows[0].1, rows[1].1, rows[2].1, rows[0].2, rows[1].2, rows[2].2
            ),
            holds: yes(holds),
            notes: "CONSTRUCTED probes: a 11.5° light (radiance 10) along +x resp. +y over sky 0.1, blended 50/50; reference = closed-form \
                    irradiance of the blended lighting; stored ZH3 with the equal-weight shared axis"
                .into(),
        },
        format!("Closed-form reference, sphere, solid-angle weights, 256x128 normals.\n\n{table}"),
    ))
}
