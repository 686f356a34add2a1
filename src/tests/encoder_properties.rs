//! Properties of every registered encoder (and every encoder configuration declared in
//! `experiments/*.toml`) on random non-negative lighting: mixtures of delta lights, uniform
//! caps and coloured ambient, as closed-form SH (`reference::lighting`, with the
//! surfaces of `common.rs`) and, for the error ordering, as small maps through the exact
//! pipeline.
//!
//! - outputs are finite;
//! - scale covariance, rotation covariance and non-negativity for the encoders that promise
//!   them (`Encoder::is_scale_covariant`, `is_rotation_covariant`, `promises_non_negative`);
//! - with the exact sphere metric and no clamping, rmse(sh2) ≤ rmse(sh1) ≤ rmse(sh0): each is
//!   the orthogonal projection of the true irradiance onto a growing space; likewise every
//!   encoder that promises `sphere_error_at_most_sh() == Some(l)` is no worse than SH L_l.
//!
//! Case count: `PROPTEST_CASES` (default 24 per property, to keep CI fast). For a long run:
//! `PROPTEST_CASES=5000 cargo test --release --lib tests::encoder_properties`. Failing cases
//! proptest found are replayed from `encoder_properties.proptest-regressions` beside this file.

use super::common::*;
use crate::encoders::encoder::Encoder;
use crate::encoders::sh::ShEncoder;
use crate::envmap::moments::RowMoments;
use crate::envmap::LatLong;
use crate::math::colour::Rgb;
use crate::reference::domain::Domain;
use crate::reference::exact::Reference;
use crate::reference::projection::project;
use crate::reference::scenes::Scene;
use glam::{DQuat, DVec3};
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use std::f64::consts::PI;

/// The case count, and the failures proptest saves kept beside this file
/// (`encoder_properties.proptest-regressions`): under `src/` proptest's default would put them
/// in a `proptest-regressions/` folder at the package root.
fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(24);
    let beside = FileFailurePersistence::WithSource("proptest-regressions");
    ProptestConfig { cases, failure_persistence: Some(Box::new(beside)), ..ProptestConfig::default() }
}

/// A uniformly distributed unit vector.
fn unit() -> impl Strategy<Value = DVec3> {
    (-1.0f64..=1.0, 0.0f64..std::f64::consts::TAU).prop_map(|(z, phi)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

/// A non-negative colour; a channel is zero one time in five.
fn colour(max: f64) -> impl Strategy<Value = Rgb> {
    let ch = prop_oneof![1 => Just(0.0), 4 => 0.0..max];
    (ch.clone(), ch.clone(), ch).prop_map(|(r, g, b)| Rgb::new(r, g, b))
}

fn delta() -> impl Strategy<Value = Light> {
    // Radiant intensity e up to 10: E/π facing it e/π.
    (unit(), colour(10.0)).prop_map(|(dir, e)| Light::Delta { dir, facing: e / PI })
}

fn cap() -> impl Strategy<Value = Light> {
    (unit(), 0.02f64..1.2, colour(20.0)).prop_map(|(axis, half_angle, radiance)| Light::Cap {
        axis,
        half_angle,
        radiance,
    })
}

/// Lighting for a probe: 1 to 5 of any kind.
fn probe_lighting() -> impl Strategy<Value = Lighting> {
    prop::collection::vec(prop_oneof![2 => delta(), 2 => cap(), 1 => colour(1.0).prop_map(Light::Ambient)], 1..6)
        .prop_map(Lighting)
}

/// Lighting for a surface (deltas and ambient, whose visible part has a closed form under any
/// nested masks), with a surface: the hemisphere effect about a random normal, a bare normal,
/// or the hemisphere plus a cone tilted up to 30° with cos α in [0.5, 0.99] (nested in the
/// hemisphere, since 30° + acos(0.5) = 90°).
fn surface_input() -> impl Strategy<Value = (Lighting, Surface)> {
    let lights = prop::collection::vec(prop_oneof![3 => delta(), 1 => colour(1.0).prop_map(Light::Ambient)], 1..6)
        .prop_map(Lighting);
    let surface = (unit(), unit(), 0u8..3, 0.0f64..30.0, 0.5f64..0.99).prop_map(|(n, t, kind, tilt, cos)| match kind {
        0 => Surface::hemisphere(n),
        1 => Surface::bare(n),
        _ => {
            let tangent = (t - n * t.dot(n)).try_normalize().unwrap_or_else(|| n.any_orthonormal_vector());
            let c = (n * tilt.to_radians().cos() + tangent * tilt.to_radians().sin()).normalize();
            Surface { normal: n, hemisphere: true, cone: Some((c, cos)) }
        }
    });
    (lights, surface)
}

fn any_input() -> impl Strategy<Value = Input> {
    prop_oneof![
        probe_lighting().prop_map(|l| Input::new(&l, None)),
        surface_input().prop_map(|(l, s)| Input::new(&l, Some(&s))),
    ]
}

fn rotation() -> impl Strategy<Value = DQuat> {
    (unit(), 0.0f64..std::f64::consts::TAU).prop_map(|(axis, angle)| DQuat::from_axis_angle(axis, angle))
}

/// Sample normals: a 32×16 lat-long grid over the sphere.
fn normals() -> Vec<DVec3> {
    Domain::Sphere.output_grid((32, 16)).normals
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn outputs_are_finite(input in any_input()) {
        for (id, e) in all_encoders() {
            let f = e.fit(&input.fit_input());
            for n in normals() {
                let v = f.irradiance(n);
                prop_assert!(v.is_finite(), "{id}: {v} at {n}");
            }
            for (k, v) in f.diagnostics() {
                prop_assert!(v.is_finite(), "{id}: diagnostic {k} = {v}");
            }
        }
    }

    #[test]
    fn scale_covariance(input in any_input(), log_k in -20.0f64..20.0) {
        let k = 10f64.powf(log_k);
        let scaled = input.scaled(k);
        for (id, e) in all_encoders().into_iter().filter(|(_, e)| e.is_scale_covariant()) {
            let (f, fk) = (e.fit(&input.fit_input()), e.fit(&scaled.fit_input()));
            let base: Vec<Rgb> = normals().iter().map(|&n| f.irradiance(n)).collect();
            let m = max_abs(&base);
            for (n, v) in normals().into_iter().zip(&base) {
                let d = (fk.irradiance(n) / k - *v).abs().max_element();
                prop_assert!(d <= 1e-7 * m, "{id}: k = {k:e}, |fit(kx)/k - fit(x)| = {d:e} at {n} (max {m:e})");
            }
        }
    }

    /// Rotating the lights (so the SH rotates), the normal and the cone by R: the fit of the
    /// rotated input at R n equals the fit at n.
    #[test]
    fn rotation_covariance(input in any_input(), q in rotation()) {
        let rotated = Input::new(&input.probe.rotated(q), input.surface.as_ref().map(|s| s.rotated(q)).as_ref());
        for (id, e) in all_encoders().into_iter().filter(|(_, e)| e.is_rotation_covariant()) {
            let (f, fr) = (e.fit(&input.fit_input()), e.fit(&rotated.fit_input()));
            let base: Vec<Rgb> = normals().iter().map(|&n| f.irradiance(n)).collect();
            let m = max_abs(&base).max(1e-300);
            for (n, v) in normals().into_iter().zip(&base) {
                let d = (fr.irradiance(q * n) - *v).abs().max_element();
                prop_assert!(d <= 1e-7 * m, "{id}: rotated fit differs by {d:e} at {n} (max {m:e})");
            }
        }
    }

    #[test]
    fn non_negative_where_promised(input in any_input()) {
        for (id, e) in all_encoders().into_iter().filter(|(_, e)| e.promises_non_negative()) {
            let f = e.fit(&input.fit_input());
            for n in Domain::Sphere.output_grid((64, 32)).normals {
                let v = f.irradiance(n);
                prop_assert!(v.min_element() >= 0.0, "{id}: {v} at {n}");
            }
        }
    }
}

/// A scene of caps and ambient as a map, for the exact pipeline; a delta light becomes a small
/// cap of the same E/π facing it (radiance facing/sin²α).
fn scene_of(lights: &[Light]) -> Scene {
    let lights = lights
        .iter()
        .map(|l| match l {
            Light::Delta { dir, facing } => {
                let half_angle = 0.1f64;
                Light::Cap { axis: *dir, half_angle, radiance: *facing / half_angle.sin().powi(2) }
            }
            l => l.clone(),
        })
        .collect();
    Scene { id: "random".into(), description: String::new(), lighting: Lighting(lights) }
}

proptest! {
    #![proptest_config(config())]

    /// Through the exact pipeline (exact SH projection of a 64×32 map, exact cell-integrated
    /// reference, solid-angle weights, no clamping, 128×64 output grid): each SH order is the
    /// orthogonal projection of the true irradiance onto a space containing the previous one, so
    /// rmse(sh2) ≤ rmse(sh1) ≤ rmse(sh0); and each encoder promising `Some(l)` is no worse than
    /// SH L_l. Slack: the grid's quadrature error enters only the cross term (see
    /// `encoder_hard_cases.rs`, `least_squares_on_a_grid_tolerance`): 1e-5 relative.
    #[test]
    fn sh_errors_shrink_with_order(lighting in probe_lighting()) {
        let map = scene_of(&lighting.0).map(64);
        let sh = project(&map);
        let moments = RowMoments::new(&map);
        let reference = Reference::new(&moments, vec![], 2);
        let grid = Domain::Sphere.output_grid((128, 64));
        let truth = reference.irradiance_latlong(LatLong::new(128, 64));
        let scale = max_abs(&truth).max(1e-300);
        let err = |e: &dyn Encoder| {
            let f = e.fit(&crate::encoders::encoder::FitInput::sphere(&sh));
            rmse_scaled(&truth, &eval(f.as_ref(), &grid), &grid, scale)
        };
        let by_order: Vec<f64> = (0..3).map(|l| err(&ShEncoder::new(l))).collect();
        prop_assert!(by_order[2] <= by_order[1] * (1.0 + 1e-5) + 1e-12, "{by_order:?}");
        prop_assert!(by_order[1] <= by_order[0] * (1.0 + 1e-5) + 1e-12, "{by_order:?}");
        for (id, e) in all_encoders() {
            if let Some(l) = e.sphere_error_at_most_sh() {
                let mine = err(e.as_ref());
                prop_assert!(mine <= by_order[l.min(2)] * (1.0 + 1e-5) + 1e-12, "{id}: {mine} vs SH L{l} {}", by_order[l.min(2)]);
            }
        }
    }
}

/// The ordering property is not vacuous: on a typical random scene the gaps are far above the
/// slack (a broken band scale would flip them).
#[test]
fn sh_error_gaps_are_large_on_a_sun_and_sky() {
    let lights = vec![
        Light::Ambient(Rgb::new(0.2, 0.3, 0.4)),
        Light::Cap { axis: DVec3::new(0.3, 0.8, 0.5).normalize(), half_angle: 0.2, radiance: Rgb::splat(30.0) },
    ];
    let map = scene_of(&lights).map(64);
    let sh = project(&map);
    let moments = RowMoments::new(&map);
    let truth = Reference::new(&moments, vec![], 2).irradiance_latlong(LatLong::new(128, 64));
    let grid = Domain::Sphere.output_grid((128, 64));
    let e: Vec<f64> = (0..3)
        .map(|l| {
            let f = ShEncoder::new(l).fit(&crate::encoders::encoder::FitInput::sphere(&sh));
            rmse_scaled(&truth, &eval(f.as_ref(), &grid), &grid, 1.0)
        })
        .collect();
    assert!(e[1] < 0.6 * e[0] && e[2] < 0.6 * e[1], "{e:?}");
}
