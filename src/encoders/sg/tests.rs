//! The SG encoders' unit tests.

use super::encoder::*;
use super::variant::*;
use super::*;
use crate::encoders::encoder::{Encoder, Fitted};
use crate::math::colour::Rgb;
use crate::math::halton::{peer_sphere_directions, PEER_SAMPLE_COUNT};
use crate::reference::radiance::RadianceSample;
use glam::DVec3;

fn samples_of(f: impl Fn(DVec3) -> Rgb) -> Vec<RadianceSample> {
    peer_sphere_directions(PEER_SAMPLE_COUNT)
        .into_iter()
        .map(|d| RadianceSample { direction: d, radiance: f(d) })
        .collect()
}

const ALL: [Variant; 6] = [
    Variant::Naive,
    Variant::LeastSquares,
    Variant::LeastSquaresAmbient,
    Variant::NonNegativeLeastSquares,
    Variant::RunningAverage,
    Variant::NonNegativeRunningAverage,
];

#[test]
fn stored_scalars_are_the_lobes_rgb() {
    for v in ALL {
        let want = if v == Variant::LeastSquaresAmbient { 39 } else { 36 };
        assert_eq!(SphericalGaussians { variant: v }.stored_scalars(), want, "{v:?}");
    }
}

#[test]
fn ls_ambient_reproduces_a_constant_and_the_others_come_close() {
    // A constant c: the ambient lobe takes it exactly (E/π = c); the 12 lobes alone
    // approximate it (the naive projection gives amplitudes ≈ c, whose sum over the lobes
    // is not flat), all within 15%.
    let c = Rgb::new(0.5, 1.0, 2.0);
    let samples = samples_of(|_| c);
    for v in ALL {
        let fit = SphericalGaussians { variant: v }.fit_samples(&samples);
        for n in [DVec3::X, DVec3::Y, DVec3::NEG_Z, DVec3::new(0.3, -0.5, 0.81).normalize()] {
            let e = fit.irradiance(n);
            let rel = ((e - c) / c).abs().max_element();
            if v == Variant::LeastSquaresAmbient {
                assert!(rel < 1e-9, "{v:?} at {n}: {e}");
            } else {
                assert!(rel < 0.15, "{v:?} at {n}: {e} vs {c}");
            }
        }
    }
}

#[test]
fn other_sample_directions_get_their_own_design() {
    // The same radiance sampled at a different set of directions fits through a fresh
    // design: a lobe-shaped radiance is recovered by least squares either way.
    let lobes = peer_lobes(false);
    let truth: Vec<Rgb> = (0..12).map(|k| Rgb::splat(k as f64 * 0.1)).collect();
    let f = |d: DVec3| lobes::radiance(&lobes, &truth, d);
    let enc = SphericalGaussians { variant: Variant::LeastSquares };
    let peer = enc.fit_samples(&samples_of(f));
    let other: Vec<RadianceSample> = peer_sphere_directions(5000)
        .into_iter()
        .map(|d| DVec3::new(d.y, d.z, d.x))
        .map(|d| RadianceSample { direction: d, radiance: f(d) })
        .collect();
    let own = enc.fit_samples(&other);
    for ((a, b), t) in peer.amplitudes().iter().zip(own.amplitudes()).zip(&truth) {
        assert!((*a - *t).abs().max_element() < 1e-9 && (*b - *t).abs().max_element() < 1e-9);
    }
}
