//! The lightmap fits' unit tests: closed-form moments against quadrature, the colour solves,
//! the golden-section search, degenerate and scaled inputs.

use super::super::lune::{Angle, Moments};
use super::super::model::Basis;
use super::least_squares::*;
use super::search::*;
use super::spec::*;
use super::target::*;
use crate::math::colour::Rgb;
use crate::math::test_rng::Rng;
use crate::reference::domain::Domain as Out;
use glam::DVec3;

fn spec(basis: Basis, gram: Gram, colours: Colours) -> FitSpec {
    FitSpec {
        basis,
        gram,
        colours,
        direction: Direction::Linear,
        max_tilt: 89f64.to_radians(),
        weights: Rgb::splat(1.0 / 3.0),
        direction_weights: crate::math::colour::REC709,
        exact_i_z: true,
    }
}

/// The tangent-space quadratic is the SH irradiance, at random points.
#[test]
fn quadratic_target_is_the_sh() {
    let mut r = Rng::new(31);
    for _ in 0..20 {
        let (e, n, t) = (r.sh(), r.unit(), r.unit());
        let f = Frame::new(n, t);
        let q = QuadraticTarget::new(&e, &f, &Moments::hemisphere());
        for _ in 0..5 {
            let w = r.unit();
            assert!((q.eval(f.to_tangent(w)) - e.eval(w)).abs().max_element() < 1e-13);
        }
    }
}

/// The closed-form inner products against brute force: colours solved from Gram entries
/// and target products summed over a fine output grid (512×256, solid-angle weights) with
/// the same solver; agreement to the grid's quadrature error.
#[test]
fn colours_match_brute_force_least_squares() {
    let mut r = Rng::new(77);
    for case in 0..6 {
        let n = r.unit();
        let e = r.sh();
        let f = Frame::new(n, r.unit());
        let theta = [0.0, 0.4, 1.2][case % 3];
        let t = Angle::new(theta);
        let d = f.direction(t);
        for gram in [Gram::Hemisphere, Gram::Sphere] {
            let grid = match gram {
                Gram::Hemisphere => Out::Hemisphere { normal: n }.output_grid((1024, 512)),
                Gram::Sphere => Out::Sphere.output_grid((1024, 512)),
            };
            for basis in [Basis::Ahd, Basis::Hhd] {
                let fa = |w: DVec3| match basis {
                    Basis::Ahd => 1.0,
                    Basis::Hhd => 0.5 * (1.0 + w.dot(n)),
                };
                let (mut gaa, mut gad, mut gdd, mut ba, mut bd) = (0.0, 0.0, 0.0, Rgb::ZERO, Rgb::ZERO);
                for (w, wt) in grid.normals.iter().zip(&grid.weights) {
                    let (a, c, q) = (fa(*w), w.dot(d).max(0.0), e.eval(*w));
                    gaa += wt * a * a;
                    gad += wt * a * c;
                    gdd += wt * c * c;
                    ba += q * (wt * a);
                    bd += q * (wt * c);
                }
                let i_z = e.eval(n).abs();
                for colours in [Colours::Free, Colours::IrradZ] {
                    let sp = spec(basis, gram, colours);
                    let dom = FitDomain::new(gram);
                    let target = QuadraticTarget::new(&e, &f, dom.moments);
                    let got = colours_at(&sp, &dom, &target, i_z, t);
                    for ch in 0..3 {
                        let (ca, cd, _) = match colours {
                            Colours::Free => nnls2(gaa, gad, gdd, ba[ch], bd[ch]),
                            Colours::IrradZ => irradz(gaa, gad, gdd, ba[ch], bd[ch], i_z[ch], t.cos),
                        };
                        let scale = 1.0 + ca.abs() + cd.abs();
                        assert!(
                            (got.c_a[ch] - ca).abs() < 2e-3 * scale && (got.c_d[ch] - cd).abs() < 2e-3 * scale,
                            "{gram:?} {basis:?} {colours:?} θ={theta}: ({}, {}) vs brute ({ca}, {cd})",
                            got.c_a[ch],
                            got.c_d[ch]
                        );
                    }
                }
            }
        }
    }
}

/// The hoisted objective equals the general per-θ solve (`colours_at` with libm sin/cos
/// and the full lune moments) to rounding, for both Grams, bases and colour rules, on
/// random targets (including negative-lobed ones, where the NNLS falls back per channel,
/// and I_z ≤ 0 channels) and tilts across [0, 89°].
#[test]
fn theta_objective_equals_colours_at() {
    let mut r = Rng::new(909);
    let mut fallbacks = 0;
    for case in 0..40 {
        let (e, n) = (r.sh(), r.unit());
        let f = Frame::new(n, r.unit());
        let mut i_z = e.eval(n).abs();
        if case % 5 == 0 {
            i_z[case % 3] = 0.0;
        }
        for gram in [Gram::Hemisphere, Gram::Sphere] {
            let dom = FitDomain::new(gram);
            let target = QuadraticTarget::new(&e, &f, dom.moments);
            for basis in [Basis::Ahd, Basis::Hhd] {
                for colours in [Colours::Free, Colours::IrradZ] {
                    let sp = FitSpec { weights: Rgb::new(0.2, 0.5, 0.3), ..spec(basis, gram, colours) };
                    let obj = ThetaObjective::new(&sp, &dom, &target, i_z);
                    for th in [0.0, 0.01, 0.3, std::f64::consts::FRAC_PI_4, 1.1, 1.55] {
                        let (got, want) = (obj.at(th), colours_at(&sp, &dom, &target, i_z, Angle::new(th)));
                        let scale = 1.0 + want.c_a.abs().max_element() + want.c_d.abs().max_element();
                        let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * scale;
                        for ch in 0..3 {
                            assert!(
                                close(got.c_a[ch], want.c_a[ch]) && close(got.c_d[ch], want.c_d[ch]),
                                "{gram:?} {basis:?} {colours:?} θ={th}: {got:?} vs {want:?}"
                            );
                        }
                        assert!(
                            (got.objective - want.objective).abs() <= 1e-12 * (1.0 + want.objective.abs()),
                            "{gram:?} {basis:?} {colours:?} θ={th}: J {} vs {}",
                            got.objective,
                            want.objective
                        );
                        if colours == Colours::Free && (want.c_a.min_element() == 0.0 || want.c_d.min_element() == 0.0)
                        {
                            fallbacks += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(fallbacks > 0, "the cases exercise the NNLS fallback");
}

/// The golden section at the encoders' defaults (30 steps, 1e-6 rad) converges to within
/// 1e-6 rad of the objective's minimum found by brute force: a scan of 2000 points over
/// [0, 89°], then 20001 points over the two grid cells about the best one (steps of
/// 8e-8 rad). Scenes: ambient plus one to three directional lights of random directions
/// and colours, seen by random normals, for both Grams, bases and colour rules (the
/// path `fit` takes: frame at the L1 azimuth, `ThetaObjective`, `solve_by`). Only objectives
/// with one minimum on the coarse grid are compared (a golden section finds a local one);
/// the test requires most cases to qualify.
/// A tolerance below one ulp (and a huge step count) once looped forever,
/// the bracket no longer shrinking. The search now stops when the bracket stops shrinking:
/// from [0, 1.55] that is about 80 steps (0.618^k · 1.55 < 2^-52 for k ≥ 78), and never
/// more than the cap.
#[test]
fn golden_section_stops_when_the_bracket_stops_shrinking() {
    let mut evals = 0usize;
    let (x, _, iters) = golden_section(0.0, 1.55, usize::MAX, 1e-300, |t| {
        evals += 1;
        (t - 0.3).powi(2)
    });
    assert!(iters < MAX_GOLDEN_STEPS, "{iters} steps");
    assert!((70..=90).contains(&iters), "{iters} steps: one ulp is reached near 80");
    assert_eq!(evals, iters + 2);
    assert!((x - 0.3).abs() < 1e-7, "{x}");
    // A bracket that cannot shrink at all (one ulp wide) ends at once.
    let one = 1.0f64;
    let (_, _, k) = golden_section(one, one.next_up(), usize::MAX, 0.0, |t| t);
    assert!(k <= 2, "{k}");
}

#[test]
fn golden_section_converges_to_the_scanned_minimum() {
    let mut r = Rng::new(2026);
    let max_tilt = 89f64.to_radians();
    let (mut compared, mut total) = (0, 0);
    for case in 0..12 {
        let mut rad = crate::math::sh::constant(Rgb::new(0.2, 0.3, 0.4) * (1.0 + r.next()));
        for _ in 0..1 + case % 3 {
            let e = Rgb::new(r.next().abs(), r.next().abs(), r.next().abs()) * 4.0;
            rad = rad + crate::math::sh::delta_light(r.unit(), e);
        }
        let sh = rad.convolve_cosine();
        let n = r.unit();
        let l1 = sh.l1_vector_weighted(crate::math::colour::REC709);
        let frame = Frame::new(n, l1);
        let tl = frame.to_tangent(l1);
        let theta_lin = (tl.x * tl.x + tl.y * tl.y).sqrt().atan2(tl.z);
        let i_z = sh.eval(n).max(Rgb::ZERO);
        for gram in [Gram::Hemisphere, Gram::Sphere] {
            let dom = FitDomain::new(gram);
            let target = QuadraticTarget::new(&sh, &frame, dom.moments);
            for basis in [Basis::Ahd, Basis::Hhd] {
                for colours in [Colours::Free, Colours::IrradZ] {
                    let sp = FitSpec {
                        direction: Direction::Search { iterations: 30, tolerance: 1e-6 },
                        ..spec(basis, gram, colours)
                    };
                    let obj = ThetaObjective::new(&sp, &dom, &target, i_z);
                    let got = solve_by(&sp, theta_lin, |th| obj.objective(th), |th| obj.at(th)).theta;
                    total += 1;
                    let m = 2000;
                    let grid: Vec<f64> = (0..=m).map(|k| obj.objective(max_tilt * k as f64 / m as f64)).collect();
                    // One strict minimum: non-increasing before it and non-decreasing after
                    // (to rounding noise, which flat plateaus show), strictly below its
                    // neighbours (so that θ is defined).
                    let k = (0..=m).min_by(|&a, &b| grid[a].total_cmp(&grid[b])).unwrap();
                    let tol = 1e-11 * (1.0 + grid[k].abs());
                    let unimodal = (0..k).all(|i| grid[i + 1] <= grid[i] + tol)
                        && (k..m).all(|i| grid[i + 1] >= grid[i] - tol)
                        && (k == 0 || grid[k - 1] > grid[k] + tol)
                        && (k == m || grid[k + 1] > grid[k] + tol);
                    if !unimodal {
                        continue;
                    }
                    compared += 1;
                    let (lo, hi) =
                        (max_tilt * k.saturating_sub(1) as f64 / m as f64, max_tilt * (k + 1).min(m) as f64 / m as f64);
                    let fine = 20_000;
                    let best = (0..=fine)
                        .map(|i| lo + (hi - lo) * i as f64 / fine as f64)
                        .min_by(|&a, &b| obj.objective(a).total_cmp(&obj.objective(b)))
                        .unwrap();
                    assert!(
                        (got - best).abs() <= 1e-6,
                        "case {case} {gram:?} {basis:?} {colours:?}: golden θ = {got}, scanned minimum at {best} \
                         (J {} vs {})",
                        obj.objective(got),
                        obj.objective(best)
                    );
                }
            }
        }
    }
    assert!(compared * 4 >= total * 3, "only {compared} of {total} objectives had one minimum");
}

/// The pair table: EVEN_Y[k] = x^a y^b z^c goes with (A(a + 1, c), A(a, c + 1)).
#[test]
fn pairs_match_the_monomials() {
    for (j, i) in EVEN_Y.into_iter().zip(PAIR_OF) {
        let (a, _, c) = MONO[j];
        assert_eq!(
            crate::encoders::lightmap::lune::CLAMPED_PAIRS[i],
            ((a + 1, c), (a, c + 1)),
            "monomial {:?}",
            MONO[j]
        );
    }
}

/// The two-variable NNLS is the minimum over the feasible quadrant (grid search check).
#[test]
fn nnls2_is_the_constrained_minimum() {
    let mut r = Rng::new(5);
    for _ in 0..50 {
        let (a, b, c) = (r.next() * 2.0, r.next() * 2.0, r.next());
        let (gaa, gad, gdd) = (a * a + 0.1, a * b + 0.3 * c, b * b + c * c + 0.1);
        let (ba, bd) = (r.next(), r.next());
        let (_, _, j) = nnls2(gaa, gad, gdd, ba, bd);
        let jf = |x: f64, y: f64| gaa * x * x + 2.0 * gad * x * y + gdd * y * y - 2.0 * ba * x - 2.0 * bd * y;
        for i in 0..60 {
            for k in 0..60 {
                assert!(jf(i as f64 * 0.05, k as f64 * 0.05) >= j - 1e-12);
            }
        }
    }
}

/// The IrradZ line keeps I(N) = I_z for every w, and the 2018 brief's minimum-norm point
/// I_z/(d_z² + 1)·(1, d_z) lies on it (AHD).
#[test]
fn irradz_keeps_i_z() {
    let mut r = Rng::new(6);
    for _ in 0..50 {
        let dz = 0.05 + 0.9 * r.next().abs();
        let i_z = r.next().abs() + 0.1;
        let (ca, cd, _) = irradz(1.0 + r.next().abs(), 0.3, 0.5, r.next(), r.next(), i_z, dz);
        assert!((ca + cd * dz - i_z).abs() < 1e-12);
        let (ma, md) = (i_z / (dz * dz + 1.0), i_z * dz / (dz * dz + 1.0));
        assert!((ma + md * dz - i_z).abs() < 1e-12);
    }
}
