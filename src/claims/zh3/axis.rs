//! Claims Z1–Z4, on the zonal axis: ZH3 represents zonal lights exactly (Z1); per-channel
//! axes can fringe colour where one shared axis does not (Z2, measured as a chroma error);
//! solving for the axis can beat the L1 axis when the L2 energy lies elsewhere (Z3); and the
//! axis weights must match the error weights (Z4).

use super::cases::{cap, enc, exact, fit, scene, scene_case, values, weights_value, Case};
use super::{mean, pct, reduction, yes, Finding};
use crate::encoders::encoder::Encoder;
use crate::math::colour::{Rgb, REC709};
use crate::math::sh::{delta_light, Sh9};
use crate::pipeline::runner::score_values;
use crate::reference::domain::OutputGrid;
use crate::reference::lighting::Light;
use crate::reference::metrics::Metric;
use crate::reference::scenes::Scene;
use anyhow::Result;
use glam::DVec3;
use std::f64::consts::PI;
use std::fmt::Write as _;

/// The four stored ZH3 encoders.
const STORED: [&str; 4] = ["zh3_stored_channel", "zh3_stored_shared", "zh3_solved_channel", "zh3_solved_shared"];

/// Z1: zonal lights are represented exactly by stored ZH3.
pub(super) fn z1(grid: &OutputGrid) -> Result<(Finding, String)> {
    let a = DVec3::new(0.35, 0.8, -0.49).normalize();
    let deg = PI / 180.0;
    let lights: Vec<(&str, Scene)> = vec![
        ("directional (delta) light, coloured", scene("delta", vec![])),
        ("cone light 5 deg", scene("cone5", vec![cap(a, 5.0 * deg, Rgb::new(200.0, 150.0, 100.0))])),
        ("cone light 30 deg", scene("cone30", vec![cap(-a, 30.0 * deg, Rgb::new(2.0, 3.0, 4.0))])),
        ("sphere light 60 deg over a constant sky", {
            scene("sphere60", vec![cap(a, 60.0 * deg, Rgb::ONE), Light::Ambient(Rgb::splat(0.2))])
        }),
    ];
    let mut worst_field = 0.0f64;
    let mut worst_rmse = 0.0f64;
    let mut table = String::from(
        "| light | encoder | max abs(ZH3 − SH3) / peak | RMSE ZH3 | RMSE SH3 | abs difference |\n|---|---|---|---|---|---|\n",
    );
    let sh2 = enc("sh2", &[])?;
    for (label, s) in &lights {
        // The delta light has no map or closed-form irradiance in `scenes`; its SH3 is the
        // reference there (the claim is ZH3 = SH3).
        let (sh, reference): (Sh9, Vec<Rgb>) = if s.id == "delta" {
            let sh = delta_light(a, Rgb::new(3.0, 2.0, 1.0));
            let r = grid.normals.iter().map(|&n| sh.convolve_cosine().eval(n)).collect();
            (sh, r)
        } else {
            (s.sh(), grid.normals.iter().map(|&n| s.irradiance(n)).collect())
        };
        let case = Case { name: s.id.clone(), sh, reference };
        let f2 = fit(sh2.as_ref(), &case.sh);
        let v2 = values(f2.as_ref(), grid);
        let peak = v2.iter().map(|v| v.max_element()).fold(0.0, f64::max);
        let e2 = score_values(sh2.as_ref(), &v2, grid, &case.reference, Metric::Exact).rmse;
        for id in STORED {
            let e = enc(id, &[])?;
            let f = fit(e.as_ref(), &case.sh);
            let v = values(f.as_ref(), grid);
            let field = v.iter().zip(&v2).map(|(x, y)| (*x - *y).abs().max_element()).fold(0.0, f64::max) / peak;
            let ez = score_values(e.as_ref(), &v, grid, &case.reference, Metric::Exact).rmse;
            worst_field = worst_field.max(field);
            worst_rmse = worst_rmse.max((ez - e2).abs());
            let _ = writeln!(table, "| {label} | {id} | {field:.2e} | {ez:.6e} | {e2:.6e} | {:.1e} |", (ez - e2).abs());
        }
    }
    let holds = worst_field <= 1e-6 && worst_rmse <= 1e-6;
    Ok((
        Finding {
            id: "Z1",
            claim: "ZH3 represents every zonal light (directional, point, cone, sphere) exactly: the same irradiance as SH3",
            paper_figure: "exact (same accuracy as SH3)".into(),
            our_figure: format!(
                "max abs(ZH3 − SH3)/peak = {worst_field:.1e}; max abs(RMSE_ZH3 − RMSE_SH3) = {worst_rmse:.1e} (E/π)"
            ),
            holds: yes(holds),
            notes: "4 zonal lights (delta, 5° and 30° cones, 60° sphere light over a constant; closed-form SH and \
                    irradiance; a point light at a distance is the delta light) × the 4 stored ZH3 encoders; \
                    tolerance 1e-6"
                .into(),
        },
        format!("Closed-form SH and irradiance, sphere, solid-angle weighted, 256x128 normals.\n\n{table}"),
    ))
}

/// Chromaticity of a displayed colour: max(E, 0)/Σ max(E, 0); black is grey (⅓, ⅓, ⅓).
fn chroma(e: Rgb) -> Rgb {
    let c = e.max(Rgb::ZERO);
    let s = c.element_sum();
    if s > 0.0 {
        c / s
    } else {
        Rgb::splat(1.0 / 3.0)
    }
}

/// The chroma error (our definition for claim Z2): solid-angle RMS over the sphere of the
/// Euclidean distance between the chromaticities rgb/(r+g+b) of the test (clamped at 0, as
/// displayed) and of the reference.
fn chroma_error(test: &[Rgb], reference: &[Rgb], w: &[f64]) -> f64 {
    let (mut s, mut ws) = (0.0, 0.0);
    for ((t, r), &wi) in test.iter().zip(reference).zip(w) {
        s += wi * (chroma(*t) - chroma(*r)).length_squared();
        ws += wi;
    }
    (s / ws).sqrt()
}

/// The same, with each normal weighted by its solid angle times the reference luminance (mean
/// of RGB): chroma errors where the surface is lit, which is where fringing shows.
fn chroma_error_lit(test: &[Rgb], reference: &[Rgb], w: &[f64]) -> f64 {
    let lw: Vec<f64> = reference.iter().zip(w).map(|(r, w)| w * (r.element_sum() / 3.0).max(0.0)).collect();
    chroma_error(test, reference, &lw)
}

/// A scene with two coloured lights 90° apart, whose channels have different L1 axes.
fn two_colour_scene() -> Scene {
    scene(
        "constructed_two_colours",
        vec![
            cap(DVec3::X, 0.3, Rgb::new(8.0, 5.0, 1.0)),
            cap(DVec3::Y, 0.3, Rgb::new(1.0, 3.0, 9.0)),
            Light::Ambient(Rgb::splat(0.05)),
        ],
    )
}

/// Z2: colour fringing of per-channel axes, measured as a chroma error.
pub(super) fn z2(grid: &OutputGrid, cases: &[Case]) -> Result<(Finding, String)> {
    let pairs = [
        ("stored", "zh3_stored_channel", "zh3_stored_shared"),
        ("solved", "zh3_solved_channel", "zh3_solved_shared"),
        ("hallucinated", "zh3_hallucinate_channel", "zh3_hallucinate"),
    ];
    let constructed = scene_case(&two_colour_scene(), grid);
    let mut table = String::from(
        "| case | pair | chroma err channel | chroma err shared | lit chroma err channel | lit chroma err shared | RMSE channel | RMSE shared |\n|---|---|---|---|---|---|---|---|\n",
    );
    let sh2 = enc("sh2", &[])?;
    let sh1 = enc("sh1", &[])?;
    let mut ref_rows = String::from("| case | chroma err sh1 | chroma err sh2 |\n|---|---|---|\n");
    let (mut shared_better, mut total, mut rmse_up, mut lit_better) = (0, 0, 0, 0);
    let mut ch_all = Vec::new();
    let mut sh_all = Vec::new();
    for case in cases.iter().chain(std::iter::once(&constructed)) {
        let ce =
            |e: &dyn Encoder| chroma_error(&values(fit(e, &case.sh).as_ref(), grid), &case.reference, &grid.weights);
        let cl = |e: &dyn Encoder| {
            chroma_error_lit(&values(fit(e, &case.sh).as_ref(), grid), &case.reference, &grid.weights)
        };
        let _ = writeln!(ref_rows, "| {} | {:.4} | {:.4} |", case.name, ce(sh1.as_ref()), ce(sh2.as_ref()));
        for (label, ch, shd) in pairs {
            let (ec, es) = (enc(ch, &[])?, enc(shd, &[])?);
            let (cc, cs) = (ce(ec.as_ref()), ce(es.as_ref()));
            let (lc, ls) = (cl(ec.as_ref()), cl(es.as_ref()));
            let (rc, rs) = (exact(ec.as_ref(), case, grid).rmse, exact(es.as_ref(), case, grid).rmse);
            total += 1;
            shared_better += (cs < cc) as usize;
            lit_better += (ls < lc) as usize;
            rmse_up += (rs > rc) as usize;
            ch_all.push(cc);
            sh_all.push(cs);
            let _ = writeln!(
                table,
                "| {} | {label} | {cc:.4} | {cs:.4} | {lc:.4} | {ls:.4} | {rc:.5} | {rs:.5} |",
                case.name
            );
        }
    }
    let holds = shared_better * 4 >= total * 3;
    Ok((
        Finding {
            id: "Z2",
            claim: "Per-channel zonal axes can fringe colour; one shared axis removes the fringing, and RMSE may go up or down",
            paper_figure: "qualitative (images)".into(),
            our_figure: format!(
                "shared axis has the lower chroma error in {shared_better}/{total} (map, variant) pairs ({lit_better}/{total} \
                 luminance-weighted); mean chroma error channel {:.4} vs shared {:.4}; shared RMSE higher in {rmse_up}/{total}",
                mean(&ch_all),
                mean(&sh_all)
            ),
            holds: yes(holds),
            notes: "chroma error = solid-angle RMS over the sphere of |χ(test) − χ(ref)|, χ = max(E,0)/Σmax(E,0) \
                    (black = grey); five probes + a constructed two-colour scene (warm light +x, blue light +y); \
                    variants stored/solved/hallucinated; holds if shared is better in ≥ 3/4 of pairs"
                .into(),
        },
        format!("{table}\nFor scale, the chroma error of SH L1 and L2:\n\n{ref_rows}"),
    ))
}

/// The constructed scene of Z3: two equal lights along ±x (strong L2 about x, no L1 along x)
/// and a weak light along +y (the L1 points along y).
fn z3_scene() -> Scene {
    scene(
        "constructed_l2_off_axis",
        vec![
            cap(DVec3::X, 0.15, Rgb::splat(20.0)),
            cap(DVec3::NEG_X, 0.15, Rgb::splat(20.0)),
            cap(DVec3::Y, 0.15, Rgb::splat(4.0)),
            Light::Ambient(Rgb::splat(0.1)),
        ],
    )
}

/// Z3: a case where the solved axis beats the L1 axis dramatically.
pub(super) fn z3(grid: &OutputGrid, cases: &[Case]) -> Result<(Finding, String)> {
    let c = scene_case(&z3_scene(), grid);
    let ids = ["sh1", "zh3_stored_shared", "zh3_solved_shared", "sh2"];
    let mut r = Vec::new();
    let mut table =
        String::from("| case | sh1 | zh3_stored_shared (L1 axis) | zh3_solved_shared | sh2 |\n|---|---|---|---|---|\n");
    for case in std::iter::once(&c).chain(cases.iter()) {
        let e: Vec<f64> =
            ids.iter().map(|id| Ok(exact(enc(id, &[])?.as_ref(), case, grid).rmse)).collect::<Result<_>>()?;
        let _ = writeln!(table, "| {} | {:.5} | {:.5} | {:.5} | {:.5} |", case.name, e[0], e[1], e[2], e[3]);
        r.push(e);
    }
    let ratio = r[0][2] / r[0][1];
    let maps_gain: Vec<f64> = r[1..].iter().map(|e| reduction(e[1], e[2])).collect();
    Ok((
        Finding {
            id: "Z3",
            claim: "Solving for the zonal axis can give dramatically lower error than the L1 axis when the L2 energy lies in another direction",
            paper_figure: "qualitative (\"dramatically better\", one example)".into(),
            our_figure: format!(
                "constructed scene: RMSE solved/L1-axis = {ratio:.3} ({:.4} vs {:.4}; SH3 {:.4}); five probes: mean {} (range {} to {})",
                r[0][2],
                r[0][1],
                r[0][3],
                pct(-mean(&maps_gain)),
                pct(-maps_gain.iter().cloned().fold(f64::NEG_INFINITY, f64::max)),
                pct(-maps_gain.iter().cloned().fold(f64::INFINITY, f64::min))
            ),
            holds: yes(ratio < 0.5),
            notes: "CONSTRUCTED scene: two equal 8.6° lights along ±x (radiance 20) and a weaker one along +y (4), sky 0.1; \
                    closed-form reference; holds if the solved RMSE is below half the L1-axis RMSE; on the real probes the gain \
                    is small"
                .into(),
        },
        format!("Exact metric (sphere, solid-angle, 256x128). Constructed scene first.\n\n{table}"),
    ))
}

/// Z4: axis weights must match error weights.
pub(super) fn z4(grid: &OutputGrid, cases: &[Case]) -> Result<(Finding, String)> {
    let rec = REC709.to_array();
    let blue_heavy = [0.1, 0.1, 0.8];
    let matched =
        enc("zh3_solved_shared", &[("axis_weights", weights_value(rec)), ("error_weights", weights_value(rec))])?;
    let mismatched = enc(
        "zh3_solved_shared",
        &[("axis_weights", weights_value(blue_heavy)), ("error_weights", weights_value(rec))],
    )?;
    let constructed = scene_case(&two_colour_scene(), grid);
    // The Z3 geometry in colour: white lights along ±x carry the L2, a blue light along +y the L1.
    let off_axis = scene_case(
        &scene(
            "constructed_l2_off_axis_blue",
            vec![
                cap(DVec3::X, 0.15, Rgb::splat(20.0)),
                cap(DVec3::NEG_X, 0.15, Rgb::splat(20.0)),
                cap(DVec3::Y, 0.15, Rgb::new(0.5, 1.0, 8.0)),
                Light::Ambient(Rgb::splat(0.1)),
            ],
        ),
        grid,
    );
    let mut table = String::from(
        "| case | matched R/G/B RMSE | mismatched R/G/B RMSE | blue ratio | red+green ratio |\n|---|---|---|---|---|\n",
    );
    let (mut blue_up, mut pushed, mut total) = (0, 0, 0);
    let mut blue_ratios = Vec::new();
    let mut rg_ratios = Vec::new();
    for case in [&off_axis, &constructed].into_iter().chain(cases.iter()) {
        let m = exact(matched.as_ref(), case, grid).rmse_rgb;
        let x = exact(mismatched.as_ref(), case, grid).rmse_rgb;
        let b = x[2] / m[2];
        let rg = (x[0] + x[1]) / (m[0] + m[1]);
        total += 1;
        blue_up += (b > 1.0 + 1e-9) as usize;
        pushed += (b > rg) as usize;
        blue_ratios.push(b);
        rg_ratios.push(rg);
        let _ = writeln!(
            table,
            "| {} | {:.5} / {:.5} / {:.5} | {:.5} / {:.5} / {:.5} | {b:.3} | {rg:.3} |",
            case.name, m[0], m[1], m[2], x[0], x[1], x[2]
        );
    }
    let holds = if blue_up * 4 >= total * 3 && pushed * 4 >= total * 3 {
        "yes".to_string()
    } else if pushed * 2 > total || blue_up * 2 > total {
        format!("partly: blue error up in {blue_up}/{total}, error moved towards blue in {pushed}/{total}")
    } else {
        "no".to_string()
    };
    Ok((
        Finding {
            id: "Z4",
            claim: "The axis weights must match the error weights; otherwise the solver pushes error into the channel with the low weight",
            paper_figure: "qualitative (\"very obvious visually\")".into(),
            our_figure: format!(
                "axis weights (0.1, 0.1, 0.8) with Rec.709 error weights vs both Rec.709: blue RMSE up in {blue_up}/{total} cases, \
                 blue ratio above the red+green ratio in {pushed}/{total}; off-axis scene: blue ×{:.2}, red+green ×{:.2}; \
                 mean over the 5 probes: blue ×{:.3}, red+green ×{:.3}",
                blue_ratios[0],
                rg_ratios[0],
                mean(&blue_ratios[2..]),
                mean(&rg_ratios[2..])
            ),
            holds,
            notes: "zh3_solved_shared; blue has a high axis weight and a low (0.0722) error weight; CONSTRUCTED scenes (the Z3 \
                    geometry with a blue L1 light; the two-colour scene) + five probes; ratio = mismatched/matched RMSE per \
                    channel; holds if blue error rises, and rises more than red+green, in at least 3/4 of the cases (partly: in \
                    most of them). The mismatched solve \
                    can rotate the axis by moving only the cheap blue L1, so it can also lower every channel's error"
                .into(),
        },
        format!("Exact metric per channel (sphere, solid-angle, 256x128).\n\n{table}"),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chroma_of_black_and_grey() {
        assert_eq!(chroma(Rgb::ZERO), Rgb::splat(1.0 / 3.0));
        assert_eq!(chroma(Rgb::new(2.0, 2.0, 2.0)), Rgb::splat(1.0 / 3.0));
        assert_eq!(chroma(Rgb::new(-1.0, 1.0, 0.0)), Rgb::new(0.0, 1.0, 0.0));
        let e = chroma_error(&[Rgb::new(1.0, 0.0, 0.0)], &[Rgb::new(0.0, 1.0, 0.0)], &[1.0]);
        assert!((e - 2f64.sqrt()).abs() < 1e-15);
    }
}
