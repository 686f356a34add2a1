//! The fit of one bake (module docs of `fit`): the input scaled to order one by a power of two,
//! the degenerate fallbacks, the θ search and, for `Search2d`, alternating azimuth and tilt
//! searches; the colours scaled back.

use super::super::lune::Angle;
use super::super::model::{Basis, Model};
use crate::encoders::encoder::FitInput;
use crate::math::colour::Rgb;
use crate::math::sh::{k, Sh9};
use glam::DVec3;

use super::least_squares::*;
use super::search::*;
use super::spec::*;
use super::target::*;

/// The result of a fit.
#[derive(Clone, Copy, Debug)]
pub struct FitResult {
    /// The fitted model, in world space.
    pub model: Model,
    /// Tilt of d from N (radians).
    pub theta: f64,
    /// Golden-section iterations and objective evaluations (0 for linear fits).
    pub iterations: usize,
    /// Objective evaluations of the direction search (0 for linear fits).
    pub evaluations: usize,
    /// True when the pure-ambient fallback was used.
    pub fallback: bool,
}

/// Multiplication by 2^e exactly, in two steps so that 2^e itself need not be representable
/// (the two factors computed once, not per scalar).
#[derive(Clone, Copy)]
pub(super) struct Pow2(f64, f64);

impl Pow2 {
    fn new(e: i32) -> Self {
        let h = e / 2;
        Pow2(2f64.powi(h), 2f64.powi(e - h))
    }
    #[inline]
    fn times(self, c: Rgb) -> Rgb {
        c * self.0 * self.1
    }
}

/// Fits `spec` to a bake (module docs).
pub fn fit(spec: &FitSpec, input: &FitInput) -> FitResult {
    let normal = input.surface_normal.and_then(|n| n.try_normalize()).filter(|n| n.is_finite());
    let i_z_exact = if spec.exact_i_z { input.exact_at_normal.filter(|v| v.is_finite()) } else { None };
    // Scale to order one by a power of two.
    let mut big = input.visible_sh.0.iter().map(|c| c.abs().max_element()).fold(0.0, f64::max);
    if let Some(v) = i_z_exact {
        big = big.max(v.abs().max_element());
    }
    let up = normal.unwrap_or(DVec3::Z);
    let result = |model: Model, theta, iterations, evaluations, fallback| FitResult {
        model,
        theta,
        iterations,
        evaluations,
        fallback,
    };
    if big == 0.0 || !big.is_finite() || !input.visible_sh.is_finite() {
        return result(Model::black(spec.basis, up), 0.0, 0, 0, false);
    }
    let e = -(big.log2().floor() as i32);
    let (scale, unscale) = (Pow2::new(e), Pow2::new(-e));
    let sh = Sh9(std::array::from_fn(|i| scale.times(input.visible_sh[i]))).convolve_cosine();
    let unscale = |c: Rgb| unscale.times(c);
    let l1 = sh.l1_vector_weighted(spec.direction_weights);
    let usable = l1.length() > 1e-9;
    let (n, gram, search) = match normal {
        Some(n) => (n, spec.gram, true),
        None if usable => (l1.normalize(), Gram::Sphere, false),
        None => {
            let c_a = (sh[0] * k::Y00).max(Rgb::ZERO);
            let m = Model { basis: Basis::Ahd, normal: DVec3::Z, c_a: unscale(c_a), c_d: Rgb::ZERO, d: DVec3::Z };
            return result(m, 0.0, 0, 0, true);
        }
    };
    let frame = Frame::new(n, if usable { l1 } else { DVec3::ZERO });
    let theta_lin = if usable {
        let t = frame.to_tangent(l1);
        (t.x * t.x + t.y * t.y).sqrt().atan2(t.z)
    } else {
        0.0
    };
    let domain = FitDomain::new(gram);
    let target = QuadraticTarget::new(&sh, &frame, domain.moments);
    let i_z = match i_z_exact {
        Some(v) => scale.times(v),
        None => sh.eval(n),
    }
    .max(Rgb::ZERO);
    let spec_here = if search { *spec } else { FitSpec { direction: Direction::Linear, ..*spec } };
    let theta_lin = if search { theta_lin } else { 0.0 };
    let objective = ThetaObjective::new(&spec_here, &domain, &target, i_z);
    let mut s = solve_by(&spec_here, theta_lin, |th| objective.objective(th), |th| objective.at(th));
    let mut frame = frame;
    if let (true, Direction::Search2d { iterations, tolerance, rounds }) = (search, spec.direction) {
        (frame, s) = search_azimuth(spec, (&domain, &sh, i_z), (frame, s), (iterations, tolerance, rounds));
    }
    let d = frame.direction(Angle::new(s.theta));
    let model = Model {
        basis: spec.basis,
        normal: n,
        c_a: unscale(s.colour.c_a.max(Rgb::ZERO)),
        c_d: unscale(s.colour.c_d.max(Rgb::ZERO)),
        d,
    };
    result(model, s.theta, s.iterations, s.evaluations, false)
}

/// `Search2d` after the first θ search: rounds of an azimuth search at the current θ, then θ
/// again at the new azimuth, while the azimuth improves; the frame turned and the solution,
/// with the iterations and evaluations of every search counted.
fn search_azimuth(
    spec: &FitSpec,
    (domain, sh, i_z): (&FitDomain, &Sh9, Rgb),
    (mut frame, mut s): (Frame, Solved),
    (iterations, tolerance, rounds): (usize, f64, usize),
) -> (Frame, Solved) {
    let (mut iters, mut evals) = (s.iterations, s.evaluations);
    for _ in 0..rounds {
        // φ: golden section over ±90° about the current azimuth at the current θ.
        let theta = s.theta;
        let at = |p: f64| {
            let f = frame.turned(p);
            ThetaObjective::new(spec, domain, &QuadraticTarget::new(sh, &f, domain.moments), i_z).objective(theta)
        };
        let half = std::f64::consts::FRAC_PI_2;
        let (p, fp, k) = golden_section(-half, half, iterations, tolerance, at);
        evals += 2 + k;
        iters += k;
        if fp >= s.colour.objective {
            break;
        }
        // θ again at the new azimuth.
        let turned = frame.turned(p);
        let t2 = ThetaObjective::new(spec, domain, &QuadraticTarget::new(sh, &turned, domain.moments), i_z);
        let s2 = solve_by(spec, s.theta, |th| t2.objective(th), |th| t2.at(th));
        iters += s2.iterations;
        evals += s2.evaluations;
        // (t2 at the old θ repeats the φ search's winner.)
        let better =
            if s2.colour.objective <= fp { s2 } else { Solved { theta: s.theta, colour: t2.at(s.theta), ..s2 } };
        frame = turned;
        s = better;
    }
    s.iterations = iters;
    s.evaluations = evals;
    (frame, s)
}
