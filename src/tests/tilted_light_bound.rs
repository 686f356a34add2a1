//! The H2 bound of the lightmap paper's claims (`experiments/lightmap_claims.toml`, H2 on the
//! generated scenes): the bound of `scenes::TiltedLight` against quadrature of the closed
//! forms, and the bound the H2 declaration uses (FORMULAS §8, HHD from linear SH).

use crate::claims::declaration::{load_papers, Test};
use crate::encoders::lightmap::hhd_from_linear_sh;
use crate::math::cap::Cap;
use crate::math::colour::Rgb;
use crate::reference::domain::Domain;
use crate::reference::lighting::{Light, Lighting};
use crate::reference::metrics::score;
use crate::reference::scenes::{generated, TILTED_LIGHT};
use std::path::Path;

/// hhd_from_sh1 on gen_tilted_light's closed forms, seen from a floor: the visible linear SH is
/// the hemisphere light of the ambient plus the whole cap (it lies above the horizon), and the
/// reference is A·H(n) plus the cap's form factor. Its rmse over a fine hemisphere grid is
/// below the derived bound and close to it (the bound is not loose); for a delta light of the
/// same E/π the HHD is exact, so the whole error is the cap's size.
#[test]
fn tilted_light_bound_holds_against_quadrature() {
    let t = &TILTED_LIGHT;
    let (a, n) = (t.axis(), glam::DVec3::Y);
    let sigma = t.radius_deg.to_radians();
    assert!(t.tilt_deg + t.radius_deg < 90.0, "the light must lie above the floor's horizon");
    let scene = generated().into_iter().find(|s| s.id == "gen_tilted_light").expect("gen_tilted_light");
    assert_eq!(
        scene.lighting,
        Lighting(vec![Light::Ambient(t.ambient), Light::Cap { axis: a, half_angle: sigma, radiance: t.radiance() }])
    );
    let floor = [Cap::hemisphere(n)];
    let visible = scene.lighting.visible(&floor);
    let model = hhd_from_linear_sh(&visible.sh(), n);
    let grid = Domain::Hemisphere { normal: n }.output_grid((4096, 2048));
    let reference: Vec<Rgb> = grid.normals.iter().map(|&w| visible.irradiance(w)).collect();
    let test: Vec<Rgb> = grid.normals.iter().map(|&w| model.irradiance(w)).collect();
    let rmse = score(&reference, &test, &grid.weights, false).rmse;
    let bound = t.hhd_rmse_bound();
    assert!(rmse <= bound && rmse >= 0.85 * bound, "rmse {rmse:e} vs bound {bound:e}");
    // The same light as a delta (E/π I facing it): the HHD is exact.
    let delta = Lighting(vec![Light::Ambient(t.ambient), Light::Delta { dir: a, facing: t.facing }]).visible(&floor);
    let m = hhd_from_linear_sh(&delta.sh(), n);
    let worst =
        grid.normals.iter().map(|&w| (m.irradiance(w) - delta.irradiance(w)).abs().max_element()).fold(0.0, f64::max);
    assert!(worst < 1e-12, "{worst:e}");
}

/// The H2 bound declared in experiments/claims/hemi.toml is the derived one, rounded up to two
/// significant digits.
#[test]
fn h2_claim_uses_the_derived_bound() {
    let papers = load_papers(&Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments")).unwrap();
    let h2 = papers.iter().flat_map(|p| &p.claims).find(|c| c.id == "H2").expect("claim H2");
    let k = h2.checks.iter().find(|k| k.encoder == "hhd_from_sh1" && !k.test.needs_baseline()).expect("HHD bound");
    let Test::EveryAtMost { bound } = k.test else { panic!("H2's HHD check is not every_at_most: {:?}", k.test) };
    let derived = TILTED_LIGHT.hhd_rmse_bound();
    let unit = 10f64.powf(derived.log10().floor() - 1.0);
    let want = (derived / unit).ceil() * unit;
    assert!((bound - want).abs() < 1e-6 * want, "H2 bound {bound:e}, derived {derived:e} (rounded up: {want:e})");
    assert_eq!(k.maps.as_deref(), Some(&["gen_tilted_light".to_string()][..]));
}
