//! Claim Z9 (ZH3 talk, "blending"): blending two probes whose L1 axes are perpendicular. The
//! blend's own zonal coefficient about its axis is ¼ of an endpoint's (P₂(cos 45°) = ¼: the
//! two zonal lobes, each at 45° from the blended axis); interpolating stored ZH3 coefficients
//! keeps the endpoint's, while hallucinated ZH3 shrinks naturally. Measured as the table
//! `zh3_blend`. The candidates are SH, not encoder fits, so they are scored with
//! [`crate::reference::metrics::score`] directly on their evaluated values.

use super::cases::{cap, scene};
use crate::claims::measure::{Cell, Measure};
use crate::encoders::zh3::solve::{l2_band, zonal_fit, Curve};
use crate::encoders::zh3::{hallucinate, stored, AxisRule};
use crate::math::colour::{Rgb, REC709};
use crate::math::sh::{delta_light, Sh9};
use crate::reference::domain::OutputGrid;
use crate::reference::lighting::Light;
use crate::reference::metrics::score;
use anyhow::{Context, Result};
use glam::DVec3;

/// P₂(cos 45°) = (3·½ − 1)/2 = ¼: the scale of a zonal coefficient seen from an axis 45° away.
pub(super) const P2_COS_45: f64 = 0.25;

/// The case of two 11.5° cap lights (radiance 10) along +x and +y over a sky of 0.1.
const CAPS: &str = "caps_x_y";
/// The case of two white delta lights along +x and +y.
const DELTAS: &str = "deltas_x_y";

/// The empty table `zh3_blend`, its columns and what they hold.
fn blend_table() -> Measure {
    Measure::new(
        "zh3_blend",
        "claim Z9, blending two probes with perpendicular L1 axes 50/50: zonal_scale = the blend's zonal coefficient \
         (red channel) about its axis / an endpoint's; rmse = E/pi RMSE of the blended encoding against the exact \
         irradiance of the blended lighting (closed form), sphere, solid-angle weighted, 256x128 lat-long normals \
         (empty where not scored)",
        &[
            "case",
            "encoder",
            "zonal_scale",
            "rmse",
            "metric",
            "domain",
            "weighting",
            "resolution",
            "reference",
            "units",
        ],
    )
}

/// A row of `zh3_blend`: the case, the method, its zonal scale and RMSE (none where not
/// scored), the exact metric's context and the reference.
fn context(m: &mut Measure, case: &str, encoder: &str, scale: f64, rmse: Option<f64>, reference: &str) {
    m.row(vec![
        case.into(),
        encoder.into(),
        scale.into(),
        rmse.map_or(Cell::from(""), Cell::from),
        "exact".into(),
        "sphere".into(),
        "solid_angle".into(),
        "256x128".into(),
        reference.into(),
        "E/pi".into(),
    ])
}

/// Z9 as the table `zh3_blend`: per case and method, the zonal coefficient of the 50% blend
/// over an endpoint's (`zonal_scale`), and the RMSE of the method's blend against the exact
/// blend. The row `p2_cos_45` holds the expected ¼ of each case.
pub(super) fn zh3_blend(grid: &OutputGrid) -> Result<Measure> {
    let mut m = blend_table();
    let mk = |axis: DVec3| scene("p", vec![cap(axis, 0.2, Rgb::splat(10.0)), Light::Ambient(Rgb::splat(0.1))]);
    let (a, b) = (mk(DVec3::X), mk(DVec3::Y));
    let blend = scene("blend", a.lighting.0.iter().chain(&b.lighting.0).cloned().collect());
    let half = |s: Sh9| s * 0.5;
    let (sa, sb) = (a.sh().convolve_cosine(), b.sh().convolve_cosine());
    let sh_blend = half(sa + sb); // irradiance SH3 of the blend (exact SH3 interpolation)
    let reference: Vec<Rgb> = grid.normals.iter().map(|&n| blend.irradiance(n) * 0.5).collect();
    let rule = AxisRule::Shared(Rgb::splat(1.0 / 3.0));
    let (za, zb) = (stored(&sa, rule), stored(&sb, rule));
    // Blend the stored ZH3 coefficients: L0, L1 and k averaged, the axis from the blended L1.
    let mut zc = za;
    zc.l0 = (za.l0 + zb.l0) * 0.5;
    for c in 0..3 {
        zc.l1[c] = (za.l1[c] + zb.l1[c]) * 0.5;
    }
    zc.axes = rule.axes(&zc.l1);
    zc.k = (za.k + zb.k) * 0.5;
    // Expand each to SH3, then blend: exact for these zonal probes.
    let sh3_blend = half(za.to_sh() + zb.to_sh());
    // Hallucinate from the blended L1.
    let hall = hallucinate(&sh_blend, AxisRule::Shared(REC709), Curve::PAPER);
    let hall_a = hallucinate(&sa, AxisRule::Shared(REC709), Curve::PAPER);
    let axis = zc.axes[0].context("Z9: the blended L1 is zero")?;
    let k_end = za.k.x;
    let rms = |s: &Sh9| {
        let v: Vec<Rgb> = grid.normals.iter().map(|&n| s.eval(n)).collect();
        score(&reference, &v, &grid.weights, false).rmse
    };
    let closed = "closed-form irradiance of the blended lighting";
    context(&mut m, CAPS, "zh3_stored_coefficients_blended", zc.k.x / k_end, Some(rms(&zc.to_sh())), closed);
    context(
        &mut m,
        CAPS,
        "sh3_blended",
        zonal_fit(axis, &l2_band(&sh3_blend, 0)) / k_end,
        Some(rms(&sh3_blend)),
        closed,
    );
    context(&mut m, CAPS, "zh3_hallucinated_from_blended_l1", hall.k.x / hall_a.k.x, Some(rms(&hall.to_sh())), closed);
    context(&mut m, CAPS, "sh1_blended", 0.0, Some(rms(&sh_blend.truncate(1))), closed);
    context(&mut m, CAPS, "p2_cos_45", P2_COS_45, None, "P2(cos 45 deg), closed form");
    // Two delta lights: the blend's own zonal coefficient about (x + y)/√2 over one light's.
    let (da, db) = (delta_light(DVec3::X, Rgb::ONE), delta_light(DVec3::Y, Rgb::ONE));
    let ax = (DVec3::X + DVec3::Y).normalize();
    let k_delta = zonal_fit(ax, &l2_band(&half(da + db), 0)) / zonal_fit(DVec3::X, &l2_band(&da, 0));
    context(&mut m, DELTAS, "sh3_blended", k_delta, None, "SH3 of the delta lights (closed form)");
    context(&mut m, DELTAS, "p2_cos_45", P2_COS_45, None, "P2(cos 45 deg), closed form");
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(m: &Measure, case: &str, encoder: &str, col: &str) -> Option<f64> {
        let i = m.columns.iter().position(|c| c == col).unwrap();
        let r = m.rows.iter().find(|r| r[0] == Cell::from(case) && r[1] == Cell::from(encoder)).unwrap();
        match &r[i] {
            Cell::Num(x) => Some(*x),
            Cell::Text(_) => None,
        }
    }

    /// P₂(cos 45°) = ¼ (Legendre P₂(x) = (3x² − 1)/2 at x² = ½); the blend's own scale is ¼ for
    /// delta lights and for the equal caps (a zonal fit of two equal zonal lobes at 45° from
    /// the axis is P₂(cos 45°) times either); blending stored coefficients keeps 1;
    /// hallucinated ZH3 shrinks; the stored blend is further from the exact blend than SH3's.
    #[test]
    fn blend_scales_against_closed_forms() {
        assert_eq!(P2_COS_45, (3.0 * 0.5 - 1.0) / 2.0);
        let m = zh3_blend(&super::super::cases::grid()).unwrap();
        m.to_csv().unwrap();
        assert!((value(&m, DELTAS, "sh3_blended", "zonal_scale").unwrap() - 0.25).abs() < 1e-12);
        assert!((value(&m, CAPS, "sh3_blended", "zonal_scale").unwrap() - 0.25).abs() < 1e-12);
        assert!((value(&m, CAPS, "zh3_stored_coefficients_blended", "zonal_scale").unwrap() - 1.0).abs() < 1e-12);
        let h = value(&m, CAPS, "zh3_hallucinated_from_blended_l1", "zonal_scale").unwrap();
        assert!(h > 0.0 && h < 1.0, "{h}");
        let rmse = |e| value(&m, CAPS, e, "rmse").unwrap();
        assert!(rmse("zh3_stored_coefficients_blended") > rmse("sh3_blended"));
        assert_eq!(value(&m, CAPS, "p2_cos_45", "rmse"), None);
    }
}
