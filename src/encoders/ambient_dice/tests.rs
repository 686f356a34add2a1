//! The ambient dice's unit tests: the icosahedron, face location and barycentrics, the three
//! bases (constants, frames, SRBF partition of unity), the fit against its grid, degenerate
//! and scaled inputs.

use super::design::*;
use super::encoder::*;
use super::geometry::*;
use super::variant::*;
use crate::encoders::encoder::{Encoder, FitInput, Fitted};
use crate::math::colour::Rgb;
use crate::math::sh::constant;
use crate::math::sh::Sh9;
use crate::math::test_rng::Rng;
use crate::reference::radiance::latlong_normals;
use glam::DVec3;
use nalgebra::{DMatrix, DVector};

/// The icosahedron: 12 unit vertices, each with 5 neighbours at cos 1/√5; 20 faces, each
/// vertex in 5; antipodal pairs (the peer's list holds each vertex's opposite).
#[test]
fn the_dice_is_an_icosahedron() {
    let g = geometry();
    assert_eq!(g.faces.len(), 20);
    for (i, v) in g.vertices.iter().enumerate() {
        assert!((v.length() - 1.0).abs() < 1e-15);
        let near = g.vertices.iter().filter(|w| (w.dot(*v) - 1.0 / 5f64.sqrt()).abs() < 1e-12).count();
        assert_eq!(near, 5, "vertex {i}");
        assert_eq!(g.faces.iter().filter(|f| f.vertices.contains(&i)).count(), 5);
        assert!(g.vertices.iter().any(|w| (*w + *v).length() < 1e-15));
        let (t, s) = g.frames[i];
        assert!(t.dot(*v).abs() < 1e-15 && (t.cross(s) - *v).length() < 1e-15);
    }
}

/// The face found for a direction is the one whose barycentrics are all ≥ 0 (independent
/// criterion: n inside the cone of the face's vertices), and n = Σ b_i v_i; Σ b_i = 1 at a
/// vertex and (1 + 2/√5)^(−1/2)·3 = 1.258 at a face centre.
#[test]
fn barycentrics_locate_and_reconstruct() {
    let g = geometry();
    let mut rng = Rng::new(3);
    for _ in 0..2000 {
        let n = rng.unit();
        let (face, b) = g.locate(n);
        let back: DVec3 = (0..3).map(|i| g.vertices[face.vertices[i]] * b[i]).sum();
        assert!((back - n).length() < 1e-14, "{n}");
        for f in &g.faces {
            let raw = f.dual.map(|r| r.dot(n));
            if raw.iter().all(|&x| x > 1e-12) {
                assert_eq!(f.vertices, face.vertices, "{n}");
            }
        }
    }
    let (_, b) = g.locate(g.vertices[4]);
    assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    let f = &g.faces[7];
    let (_, b) = g.locate(f.centre);
    let want = 3.0 / (3.0 + 6.0 / 5f64.sqrt()).sqrt();
    assert!((b.iter().sum::<f64>() - want).abs() < 1e-14, "{b:?}");
}

/// D = (√5 − 1)/3 equals the peer's factor: its table gives 0.3504874 for the edge point of
/// face {0, 4, 8} next to vertex 4 towards vertex 0, whose tangent in the peer is +X
/// (`triDerivativeTangentFactors[0][2]`).
#[test]
fn edge_factor_is_the_peers() {
    let g = geometry();
    let d = (5f64.sqrt() - 1.0) / 3.0;
    assert!(((g.vertices[0] - g.vertices[4]).dot(DVec3::X) * d - 0.350_487_4).abs() < 1e-7);
    // And 0.2981424 for vertex 8 towards 0 along the peer's tangent (0.8506508, 0, −0.5257311).
    let t8 = DVec3::new(0.850_650_8, 0.0, -0.525_731_1);
    assert!(((g.vertices[0] - g.vertices[8]).dot(t8) * d - 0.298_142_4).abs() < 1e-7);
}

/// The Bézier basis interpolates: at vertex i it is 1 on f_i and 0 on every other
/// coefficient (value and derivatives alike).
#[test]
fn bezier_interpolates_the_vertex_values() {
    let g = geometry();
    for (i, &v) in g.vertices.iter().enumerate() {
        let (ids, w) = g.bezier(v);
        for k in 0..3 {
            let want = if ids[k] == i { [1.0, 0.0, 0.0] } else { [0.0; 3] };
            for s in 0..3 {
                assert!((w[k][s] - want[s]).abs() < 1e-14, "vertex {i}: {w:?}");
            }
        }
    }
}

/// The Bézier dice is continuous across edges: on a shared edge both faces give the same
/// weights to the same coefficients (the opposite vertex gets 0).
#[test]
fn bezier_is_continuous_across_edges() {
    let g = geometry();
    let mut rng = Rng::new(9);
    let coeffs: Vec<f64> = (0..36).map(|_| rng.next()).collect();
    let value = |f: &Face, n: DVec3| {
        let b = f.dual.map(|r| r.dot(n).max(0.0));
        let w = bezier_weights(f, b);
        (0..3)
            .flat_map(|i| (0..3).map(move |s| (i, s)))
            .map(|(i, s)| coeffs[3 * f.vertices[i] + s] * w[i][s])
            .sum::<f64>()
    };
    let mut edges = 0;
    for (a, fa) in g.faces.iter().enumerate() {
        for fb in &g.faces[a + 1..] {
            let shared: Vec<usize> = fa.vertices.iter().copied().filter(|v| fb.vertices.contains(v)).collect();
            if shared.len() != 2 {
                continue;
            }
            edges += 1;
            for t in [0.1, 0.37, 0.5, 0.9] {
                let n = (g.vertices[shared[0]] * (1.0 - t) + g.vertices[shared[1]] * t).normalize();
                let (x, y) = (value(fa, n), value(fb, n));
                assert!((x - y).abs() < 1e-13, "edge {shared:?} at {t}: {x} vs {y}");
            }
        }
    }
    assert_eq!(edges, 30);
}

/// The SRBF lobes are a partition of unity (module docs: Σ(n·a)² = 2 and Σ(n·a)⁴ = 6/5 over
/// the six vertex axes, a spherical 5-design).
#[test]
fn srbf_lobes_sum_to_one() {
    let g = geometry();
    let mut rng = Rng::new(5);
    for _ in 0..1000 {
        let n = rng.unit();
        let axes = &g.vertices[..];
        let s2: f64 = axes.iter().map(|a| a.dot(n).powi(2)).sum::<f64>() / 2.0;
        let s4: f64 = axes.iter().map(|a| a.dot(n).powi(4)).sum::<f64>() / 2.0;
        assert!((s2 - 2.0).abs() < 1e-13 && (s4 - 1.2).abs() < 1e-13, "{s2} {s4}");
        assert!((g.srbf(n).iter().sum::<f64>() - 1.0).abs() < 1e-14);
    }
}

/// The normal matrices of all three bases, both weightings, are positive definite (the
/// Cholesky factorisation succeeds).
#[test]
fn normal_matrices_factor() {
    for v in [Variant::Bezier, Variant::BezierYCoCg, Variant::Srbf] {
        for pixel in [false, true] {
            let d = Design::get(v, pixel);
            assert_eq!(d.normal.l().nrows(), v.unknowns());
        }
    }
}

/// A target in the span is reproduced exactly: random coefficients' E/π on the grid, fitted,
/// give the same function at random normals (to rounding), for all three variants and
/// both weightings.
#[test]
fn functions_in_the_span_are_reproduced() {
    let mut rng = Rng::new(11);
    let normals = latlong_normals(FIT_GRID.0, FIT_GRID.1);
    for variant in [Variant::Bezier, Variant::BezierYCoCg, Variant::Srbf] {
        let m = variant.functions();
        let coeffs: Vec<Rgb> = (0..m)
            .map(|j| {
                let c = Rgb::new(rng.next(), rng.next(), rng.next());
                // Y/Co/Cg stores Y in x, then (Co, Cg, 0).
                match variant {
                    Variant::BezierYCoCg if j < 36 => Rgb::new(c.x, 0.0, 0.0),
                    Variant::BezierYCoCg => Rgb::new(c.x, c.y, 0.0),
                    _ => c,
                }
            })
            .collect();
        let truth = DiceFit { variant, coeffs };
        let target: Vec<Rgb> = normals.iter().map(|&n| truth.irradiance(n)).collect();
        for pixel in [false, true] {
            let fit = AmbientDiceEncoder::new(variant, pixel).fit_target(&target);
            for _ in 0..200 {
                let n = rng.unit();
                let (a, b) = (fit.irradiance(n), truth.irradiance(n));
                assert!((a - b).abs().max_element() < 1e-10, "{variant:?} pixel={pixel} at {n}: {a} vs {b}");
            }
        }
    }
}

/// Constant light: the SRBF dice is exact (a partition of unity). The Bézier basis does not
/// contain the constant: with every value 1 and every derivative 0 it is 1 at the vertices,
/// 2b³(1 + 3/√5) = 0.951 at an edge's midpoint (b = (2 + 2/√5)^(−1/2)) and
/// b³(3 + 18/√5 + 12a0 + 12(a1 + a2)/√5) = 0.938 at a face's centre (b = (3 + 6/√5)^(−1/2)),
/// closed forms of the definition; so the least-squares fit of a constant misses by a few
/// per cent (measured: 4.1% at worst, 1.65% RMS; the Y/Co/Cg variant on grey 1.68% RMS). The
/// linear basis of Co and Cg misses a coloured constant by far more (measured: 28.7% at
/// worst, 9.0% RMS on (0.5, 1, 2)). Errors relative, per channel, on a 256×128 grid.
#[test]
fn constant_light() {
    let g = geometry();
    let ones = DiceFit {
        variant: Variant::Bezier,
        coeffs: (0..36).map(|j| Rgb::splat(if j % 3 == 0 { 1.0 } else { 0.0 })).collect(),
    };
    let s5 = 5f64.sqrt();
    let b = 1.0 / (2.0 + 2.0 / s5).sqrt();
    let mid = (g.vertices[0] + g.vertices[4]).normalize();
    assert!((ones.irradiance(mid).x - 2.0 * b.powi(3) * (1.0 + 3.0 / s5)).abs() < 1e-14);
    let b = 1.0 / (3.0 + 6.0 / s5).sqrt();
    let (a0, a1, a2) = ((s5 - 5.0) / 40.0, (11.0 * s5 - 15.0) / 40.0, s5 / 10.0);
    let want = b.powi(3) * (3.0 + 18.0 / s5 + 12.0 * a0 + 12.0 * (a1 + a2) / s5);
    assert!((ones.irradiance(g.faces[3].centre).x - want).abs() < 1e-14, "{want}");
    assert!((want - 0.938).abs() < 5e-4, "{want}");

    let normals = latlong_normals(256, 128);
    let grid = crate::reference::domain::Domain::Sphere.output_grid((256, 128));
    // (variant, constant, worst and RMS relative error at most); a grey and a coloured one.
    let (grey, colour) = (Rgb::splat(0.7), Rgb::new(0.5, 1.0, 2.0));
    for (variant, a, worst_at_most, rms_at_most) in [
        (Variant::Srbf, colour, 1e-12, 1e-12),
        (Variant::Bezier, colour, 0.042, 0.017),
        (Variant::BezierYCoCg, grey, 0.042, 0.017),
        (Variant::BezierYCoCg, colour, 0.29, 0.091),
    ] {
        let f = AmbientDiceEncoder::new(variant, false).fit(&FitInput::sphere(&constant(a)));
        let rel: Vec<f64> = normals.iter().map(|&n| ((f.irradiance(n) - a) / a).abs().max_element()).collect();
        let worst = rel.iter().copied().fold(0.0, f64::max);
        let rms =
            (rel.iter().zip(&grid.weights).map(|(r, w)| r * r * w).sum::<f64>() / (4.0 * std::f64::consts::PI)).sqrt();
        assert!(
            worst < worst_at_most && rms < rms_at_most,
            "{variant:?}: the constant {a} is fitted to {worst:e} at worst, {rms:e} RMS"
        );
    }
}

/// Without a radiance source the target is the E/π of the visible SH, fitted in closed form
/// from the nine coefficients: the same fit as from that light's E/π grid, to rounding.
#[test]
fn the_sh_path_equals_the_grid_path() {
    let mut rng = Rng::new(21);
    for variant in [Variant::Bezier, Variant::BezierYCoCg, Variant::Srbf] {
        for pixel in [false, true] {
            let e = AmbientDiceEncoder::new(variant, pixel);
            let sh = rng.sh();
            let light = crate::reference::radiance::ShLight::new(&sh);
            let grid = e.fit(&FitInput { radiance: Some(&light), ..FitInput::sphere(&sh) });
            let closed = e.fit(&FitInput::sphere(&sh));
            for _ in 0..100 {
                let n = rng.unit();
                let (a, b) = (grid.irradiance(n), closed.irradiance(n));
                assert!((a - b).abs().max_element() < 1e-12, "{variant:?} {pixel}: {a} vs {b}");
            }
        }
    }
    let e = AmbientDiceEncoder::new(Variant::Bezier, false);
    assert_eq!(e.fit(&FitInput::sphere(&Sh9::ZERO)).irradiance(DVec3::X), Rgb::ZERO);
}

/// Black in, black out; a non-finite target gives black; k·target gives k·fit.
#[test]
fn degenerate_and_scaled_targets() {
    let n = latlong_normals(FIT_GRID.0, FIT_GRID.1).len();
    let mut rng = Rng::new(4);
    let target: Vec<Rgb> = (0..n).map(|_| Rgb::new(rng.uniform01(), rng.uniform01(), rng.uniform01())).collect();
    for variant in [Variant::Bezier, Variant::BezierYCoCg, Variant::Srbf] {
        let e = AmbientDiceEncoder::new(variant, false);
        let d = rng.unit();
        assert_eq!(e.fit_target(&vec![Rgb::ZERO; n]).irradiance(d), Rgb::ZERO);
        let mut bad = target.clone();
        bad[17] = Rgb::new(f64::NAN, 0.0, 0.0);
        assert_eq!(e.fit_target(&bad).irradiance(d), Rgb::ZERO);
        let one = e.fit_target(&target).irradiance(d);
        let scaled: Vec<Rgb> = target.iter().map(|v| *v * 1e-300).collect();
        let tiny = e.fit_target(&scaled).irradiance(d) / 1e-300;
        assert!((tiny - one).abs().max_element() < 1e-12 * one.abs().max_element(), "{variant:?}");
    }
}

/// The fitted E/π does not depend on the tangent frames: the same least-squares problem
/// with every frame turned by 0.7 rad gives the same function (a small grid, solved here
/// with nalgebra's SVD, independently of [`Design`]).
#[test]
fn tangent_frames_do_not_matter() {
    let normals = latlong_normals(32, 16);
    let target = |n: DVec3| (3.0 * n.x).sin() + n.y * n.z + 0.5;
    let fit = |g: &Geometry| {
        let rows: Vec<Vec<(u16, f64)>> = normals
            .iter()
            .map(|&n| {
                let mut r = Vec::new();
                Variant::Bezier.row(g, n, &mut r);
                r
            })
            .collect();
        let mut a = DMatrix::<f64>::zeros(normals.len(), 36);
        for (p, r) in rows.iter().enumerate() {
            for &(j, x) in r {
                a[(p, j as usize)] = x;
            }
        }
        let b = DVector::from_iterator(normals.len(), normals.iter().map(|&n| target(n)));
        let x = a.svd(true, true).solve(&b, 1e-12).unwrap();
        move |g: &Geometry, n: DVec3| {
            let mut r = Vec::new();
            Variant::Bezier.row(g, n, &mut r);
            r.iter().map(|&(j, w)| x[j as usize] * w).sum::<f64>()
        }
    };
    let (g0, g1) = (Geometry::new(0.0), Geometry::new(0.7));
    let (f0, f1) = (fit(&g0), fit(&g1));
    let mut rng = Rng::new(8);
    for _ in 0..200 {
        let n = rng.unit();
        assert!((f0(&g0, n) - f1(&g1, n)).abs() < 1e-9, "{n}");
    }
}
