//! The exact reference against the closed forms of the generated scenes, to 1e-4 relative.
//! The scenes' maps hold exact cell averages, so what remains is the sub-texel placement of
//! light, which falls with resolution; the test checks both the level and the convergence.

use crate::envmap::moments::RowMoments;
use crate::math::cap::Cap;
use crate::math::colour::Rgb;
use crate::reference::domain::fibonacci_sphere;
use crate::reference::exact::{Reference, DEFAULT_POLAR_NODES};
use crate::reference::scenes::generated;
use glam::DVec3;

/// Worst error over 200 Fibonacci normals, relative to the RMS of the closed form.
fn worst_relative(width: usize, scene: &crate::reference::scenes::Scene) -> f64 {
    let map = scene.map(width);
    let rm = RowMoments::new(&map);
    let r = Reference::new(&rm, vec![], DEFAULT_POLAR_NODES);
    let normals = fibonacci_sphere(200);
    let cf: Vec<Rgb> = normals.iter().map(|&n| scene.irradiance(n)).collect();
    let rms = (cf.iter().map(|e| e.length_squared()).sum::<f64>() / (3.0 * cf.len() as f64)).sqrt();
    let got = r.irradiance_many(&normals);
    got.iter().zip(&cf).map(|(g, c)| (*g - *c).abs().max_element() / rms).fold(0.0, f64::max)
}

#[test]
fn reference_matches_closed_forms_to_1e4() {
    for s in generated() {
        let e512 = worst_relative(1024, &s);
        assert!(e512 < 1e-4, "{}: {e512:e}", s.id);
    }
}

/// Under the hemisphere effect about N, a constant environment gives the hemisphere light
/// H(n) = (1 + n·N)/2 (FORMULAS §8), for N off every grid axis too.
#[test]
fn hemisphere_effect_on_constant_gives_hemisphere_light() {
    let map = crate::envmap::EnvMap::from_fn("c", 512, 256, |_, _| [1.0; 3]).unwrap();
    let rm = RowMoments::new(&map);
    for big_n in [DVec3::Y, DVec3::X, DVec3::new(0.3, -0.5, 0.81).normalize()] {
        let r = Reference::new(&rm, vec![Cap::hemisphere(big_n)], DEFAULT_POLAR_NODES);
        for n in fibonacci_sphere(50) {
            let want = 0.5 * (1.0 + n.dot(big_n));
            let got = r.irradiance(n);
            assert!((got - Rgb::splat(want)).abs().max_element() < 1e-5, "N {big_n} n {n}: {got} vs {want}");
        }
    }
}
