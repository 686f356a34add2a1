//! The catalogue of hard cases that `encoder_hard_cases.rs` runs every encoder on: named
//! scenes built analytically (ambient, delta and cap lights, visible under the surface's
//! effects; `reference::lighting`, with the surfaces of `common.rs`), each saying what trouble
//! it brings (a division by d_z, L00 or |L1|, a discriminant's square root, a zero vector).

use super::common::*;
use crate::math::colour::Rgb;
use glam::DVec3;
use std::f64::consts::PI;

/// A named hard case.
pub(super) struct Case {
    pub(super) name: String,
    /// What the case probes, for the failure message.
    pub(super) why: &'static str,
    pub(super) lighting: Lighting,
    pub(super) surface: Option<Surface>,
    /// A non-physical edit of the SH after it is computed (rounding beyond a bound).
    pub(super) tweak: Option<fn(&mut Input)>,
    /// No usable direction: the pure-ambient fallback bound (4) applies.
    pub(super) degenerate: bool,
}

pub(super) const UP: DVec3 = DVec3::Y;

pub(super) fn case(name: &str, why: &'static str, lights: Vec<Light>, surface: Option<Surface>) -> Case {
    Case { name: name.into(), why, lighting: Lighting(lights), surface, tweak: None, degenerate: false }
}

pub(super) fn degenerate(mut c: Case) -> Case {
    c.degenerate = true;
    c
}

/// A delta light along d whose E/π facing it is `facing`.
pub(super) fn delta(d: DVec3, facing: Rgb) -> Light {
    Light::Delta { dir: d.normalize(), facing }
}

/// A direction at `deg` degrees from +Y, towards +X.
pub(super) fn from_up(deg: f64) -> DVec3 {
    let t = deg.to_radians();
    DVec3::new(t.sin(), t.cos(), 0.0)
}

/// Sun and sky of the generated `gen_sun_sky` scene (a 5° cap at 40° elevation).
pub(super) fn sun_sky() -> Vec<Light> {
    vec![
        Light::Ambient(Rgb::new(0.2, 0.25, 0.3)),
        Light::Cap { axis: dir(40.0, 30.0), half_angle: 5f64.to_radians(), radiance: Rgb::new(2000.0, 1800.0, 1500.0) },
    ]
}

pub(super) fn scale_lights(lights: Vec<Light>, k: f64) -> Vec<Light> {
    Lighting(lights).scaled(k).0
}

/// Multiplies the L1 band of probe and visible SH by 1 + 8ε: a single delta light then has a
/// hallucination ratio r = |L1|/L00 a few ulps above its physical maximum √3, as rounding in
/// real data produces.
pub(super) fn l1_past_sqrt3(i: &mut Input) {
    for sh in [&mut i.probe_sh, &mut i.visible_sh] {
        for k in 1..4 {
            sh.0[k] *= 1.0 + 8.0 * f64::EPSILON;
        }
    }
}

/// A surface with the hemisphere effect about +Y.
pub(super) fn hemi() -> Option<Surface> {
    Some(Surface::hemisphere(UP))
}

/// A direction off every axis.
pub(super) fn oblique_dir() -> DVec3 {
    DVec3::new(0.3, 0.8, -0.52).normalize()
}

/// The catalogue, grouped by the kind of trouble.
pub(super) fn cases() -> Vec<Case> {
    [
        black_cases(),
        constant_cases(),
        horizon_cases(),
        cancelling_lights_cases(),
        per_channel_cases(),
        extreme_scale_cases(),
        hallucination_ratio_cases(),
        singular_fit_cases(),
        underflow_cases(),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// Black light: 0/0 in every ratio, with and without a surface and a cone.
pub(super) fn black_cases() -> Vec<Case> {
    vec![
        degenerate(case("all_black", "zero everywhere: 0/0 in every ratio", vec![], None)),
        degenerate(case("all_black@hemisphere", "zero with a surface: I_z = 0", vec![], hemi())),
        degenerate(case(
            "all_black@cone",
            "zero under a cone: an empty visible set",
            vec![],
            Some(Surface { normal: UP, hemisphere: true, cone: Some((UP, 0.5)) }),
        )),
    ]
}

/// Constant light: no direction at all, and the hemisphere light whose HHD discriminant is 0.
pub(super) fn constant_cases() -> Vec<Case> {
    vec![
        degenerate(case(
            "constant",
            "no direction at all: L1 = L2 = 0, r = 0",
            vec![Light::Ambient(Rgb::new(0.5, 1.0, 2.0))],
            None,
        )),
        case(
            "constant@hemisphere",
            "the hemisphere light (1 + n.N)/2: HHD's discriminant is exactly 0",
            vec![Light::Ambient(Rgb::new(0.5, 1.0, 2.0))],
            hemi(),
        ),
    ]
}

/// One light along N, grazing, exactly at the horizon and below it.
pub(super) fn horizon_cases() -> Vec<Case> {
    let one = Rgb::ONE;
    vec![
        case("delta_along_n@hemisphere", "one light along N: d = N", vec![delta(UP, one)], hemi()),
        case("delta_89.9deg@hemisphere", "a grazing light: d_z = 0.0017", vec![delta(from_up(89.9), one)], hemi()),
        case(
            "delta_horizon@hemisphere",
            "a light exactly at the horizon (counted visible): d_z = 0, I_z = 0",
            vec![delta(DVec3::X, one)],
            hemi(),
        ),
        case(
            "delta_below@hemisphere",
            "a light 10 deg below the horizon: nothing visible, the probe is lit",
            vec![delta(from_up(100.0), one)],
            hemi(),
        ),
    ]
}

/// Lights that cancel: L1 = 0 (and L2 = 0), the axis undefined.
pub(super) fn cancelling_lights_cases() -> Vec<Case> {
    let one = Rgb::ONE;
    vec![
        degenerate(case(
            "two_opposite",
            "two equal opposite lights: L1 = 0, the zonal axis is undefined; every BFGS start is stationary",
            vec![delta(DVec3::X, one), delta(DVec3::NEG_X, one)],
            None,
        )),
        case(
            "two_opposite@bare_x",
            "L1 = 0 with a surface normal along one light (no effect declared): IrradZ with no direction",
            vec![delta(DVec3::X, one), delta(DVec3::NEG_X, one)],
            Some(Surface::bare(DVec3::X)),
        ),
        degenerate(case(
            "octahedron",
            "six equal lights on the axes: L1 = 0 and L2 = 0",
            [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z]
                .into_iter()
                .map(|d| delta(d, one))
                .collect(),
            None,
        )),
    ]
}

/// Channels that disagree: per-channel axes, a channel that is zero everywhere.
pub(super) fn per_channel_cases() -> Vec<Case> {
    vec![
        case(
            "rgb_directions",
            "R, G, B lit from three orthogonal directions: per-channel axes disagree",
            vec![
                delta(DVec3::X, Rgb::new(1.0, 0.0, 0.0)),
                delta(DVec3::Y, Rgb::new(0.0, 1.0, 0.0)),
                delta(DVec3::NEG_Z, Rgb::new(0.0, 0.0, 1.0)),
            ],
            None,
        ),
        case(
            "rgb_directions@hemisphere",
            "R, G, B from three directions, all visible above a tilted surface",
            vec![
                delta(DVec3::X, Rgb::new(1.0, 0.0, 0.0)),
                delta(DVec3::Y, Rgb::new(0.0, 1.0, 0.0)),
                delta(DVec3::NEG_Z, Rgb::new(0.0, 0.0, 1.0)),
            ],
            Some(Surface::hemisphere(DVec3::new(1.0, 1.0, -1.0))),
        ),
        case(
            "one_channel_zero",
            "green is zero everywhere: 0/0 in that channel only",
            vec![Light::Ambient(Rgb::new(0.3, 0.0, 0.2)), delta(dir(40.0, 10.0), Rgb::new(5.0, 0.0, 2.0) / PI)],
            None,
        ),
        case(
            "one_channel_zero@hemisphere",
            "green is zero everywhere, with a surface",
            vec![Light::Ambient(Rgb::new(0.3, 0.0, 0.2)), delta(dir(40.0, 10.0), Rgb::new(5.0, 0.0, 2.0) / PI)],
            hemi(),
        ),
    ]
}

/// Extreme scales: the whole scene at 1e-30 and 1e+30, a sun 1e6 times the sky.
pub(super) fn extreme_scale_cases() -> Vec<Case> {
    vec![
        case("scale_1e-30", "sun and sky scaled by 1e-30: squares reach 1e-60", scale_lights(sun_sky(), 1e-30), None),
        case(
            "scale_1e-30@hemisphere",
            "sun and sky scaled by 1e-30, with a surface",
            scale_lights(sun_sky(), 1e-30),
            hemi(),
        ),
        case("scale_1e+30", "sun and sky scaled by 1e+30: squares reach 1e+60", scale_lights(sun_sky(), 1e30), None),
        case(
            "scale_1e+30@hemisphere",
            "sun and sky scaled by 1e+30, with a surface",
            scale_lights(sun_sky(), 1e30),
            hemi(),
        ),
        case(
            "sun_radiance_1e6",
            "a 0.265 deg sun of radiance 1e6 times the sky's",
            vec![
                Light::Ambient(Rgb::ONE),
                Light::Cap { axis: dir(30.0, 60.0), half_angle: 0.265f64.to_radians(), radiance: Rgb::splat(1e6) },
            ],
            None,
        ),
        case(
            "sun_irradiance_1e6",
            "a sun whose irradiance is 1e6 times the sky's",
            vec![Light::Ambient(Rgb::ONE), delta(dir(30.0, 60.0), Rgb::splat(1e6))],
            None,
        ),
        case(
            "sun_irradiance_1e6@hemisphere",
            "a sun 1e6 times the sky, with a surface",
            vec![Light::Ambient(Rgb::ONE), delta(dir(30.0, 60.0), Rgb::splat(1e6))],
            hemi(),
        ),
    ]
}

/// The hallucination ratio r = |L1|/L00 at its physical maximum and near 0.
pub(super) fn hallucination_ratio_cases() -> Vec<Case> {
    let oblique = oblique_dir();
    vec![
        case(
            "ratio_r_sqrt3",
            "a single delta light: hallucination ratio r = sqrt(3), the physical maximum; ZH3 exact at the start",
            vec![delta(oblique, Rgb::new(PI, 2.0, 1.0) / PI)],
            None,
        ),
        case(
            "ratio_r_to_0",
            "ambient plus a 1e-9 light: r ~ 1e-10",
            vec![Light::Ambient(Rgb::ONE), delta(oblique, Rgb::splat(1e-9 / PI))],
            None,
        ),
    ]
}

/// Fits near a singularity: d_z = 0, a negative discriminant, a near-zero cone Gram, a zero gradient at the start.
pub(super) fn singular_fit_cases() -> Vec<Case> {
    let one = Rgb::ONE;
    let oblique = oblique_dir();
    vec![
        case(
            "irradz_dz_zero@hemisphere",
            "sky plus a light exactly at the horizon: C_d = (I_z - C_a)/d_z with d_z = 0",
            vec![Light::Ambient(Rgb::splat(0.5)), delta(DVec3::X, Rgb::splat(2.0))],
            hemi(),
        ),
        case(
            "irradz_dz_1e-12@hemisphere",
            "sky plus a light 1e-12 above the horizon: d_z = 1e-12",
            vec![
                Light::Ambient(Rgb::splat(0.5)),
                delta(DVec3::new((1.0f64 - 1e-24).sqrt(), 1e-12, 0.0), Rgb::splat(2.0)),
            ],
            hemi(),
        ),
        // HHD from linear SH (FORMULAS §8), with b_c = (2/√π)L00, b = (2/√π)(L1 vector)/√3 and I_z
        // the exact irradiance at N: for ambient c over the whole sphere plus a light along N
        // of E/π s facing it, b_c = 4c + s, |b| = s, I_z = c + s, so the discriminant
        // (2b_c − I_z)² − 3(b_c² − |b|²) = c² − 10cs + s² = −8 for c = s = 1.
        case(
            "hhd_negative_discriminant@bare",
            "light from below the horizon, no hemisphere effect: hhd_from_sh1's discriminant is -8",
            vec![Light::Ambient(Rgb::ONE), delta(UP, one)],
            Some(Surface::bare(UP)),
        ),
        case(
            "cone_cos_1e-12@cone",
            "a cone of cos(alpha) = 1 - 1e-12 with a light at its centre: the cone Gram is nearly zero",
            vec![Light::Ambient(Rgb::ONE), delta(UP, one)],
            Some(Surface { normal: UP, hemisphere: true, cone: Some((UP, 1.0 - 1e-12)) }),
        ),
        case(
            "cone_cos_1e-6@cone",
            "a tilted cone of cos(alpha) = 1 - 1e-6 under plain sky",
            vec![Light::Ambient(Rgb::splat(0.5))],
            Some(Surface { normal: UP, hemisphere: true, cone: Some((from_up(30.0), 1.0 - 1e-6)) }),
        ),
        case(
            "bfgs_start_at_minimum",
            "ambient plus one cap light: zonal, so the given L1 is already the optimal axis (gradient 0)",
            vec![
                Light::Ambient(Rgb::splat(0.1)),
                Light::Cap { axis: oblique, half_angle: 20f64.to_radians(), radiance: Rgb::new(3.0, 2.0, 1.0) },
            ],
            None,
        ),
    ]
}

/// Squares that underflow, and rounding that pushes r past its bound.
pub(super) fn underflow_cases() -> Vec<Case> {
    let one = Rgb::ONE;
    let oblique = oblique_dir();
    let mut past = case(
        "ratio_r_past_sqrt3",
        "a single delta light with L1 8 ulps too long: r a hair above sqrt(3)",
        vec![delta(oblique, one)],
        None,
    );
    past.tweak = Some(l1_past_sqrt3);
    vec![
        degenerate(case(
            "l1_1e-300",
            "ambient plus an L1 band of 1e-300: |L1|^2 underflows to 0",
            vec![Light::Ambient(Rgb::ONE), delta(oblique, Rgb::splat(1e-300 / PI))],
            None,
        )),
        degenerate(case(
            "tiny_light_1e-300",
            "a lone 1e-300 light: L00 and |L1| ~ 1e-301, their squares 0",
            vec![delta(oblique, Rgb::splat(1e-300 / PI))],
            None,
        )),
        past,
    ]
}
