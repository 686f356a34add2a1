//! The SG fits of the peer tool (kayru/Probulator, `ExperimentSG.h`, `SGFitLeastSquares.cpp`),
//! over a set of radiance samples (unit direction, RGB radiance) taken uniformly on the sphere:
//!
//! - **naive** (`ExperimentSGNaive`): μ_k = f·(1/N)·Σ_i L_i·G_k(ω_i), f = 4λ²/((1 − e^{−2λ})K)
//!   ([`super::lobes::naive_normalisation`]), a scaled projection;
//! - **least squares** (`sgFitLeastSquares`): μ minimises Σ_i |L_i − Σ_k μ_k G_k(ω_i)|² per
//!   channel; the peer solves it by Eigen's Jacobi SVD of the N×K sample matrix A, we by the
//!   normal equations (AᵀA)μ = Aᵀb with AᵀA's pseudo-inverse (the same minimiser; AᵀA is
//!   K×K and fixed for a fixed sample set, see [`Design`]);
//! - **non-negative least squares** (`sgFitNNLeastSquares`, Eigen's `NNLS`): the same with
//!   μ ≥ 0, by Lawson and Hanson's active-set algorithm ("Solving Least Squares Problems",
//!   1974, ch. 23) on the normal equations;
//! - **running average** (`ExperimentSGRunningAverage`; T. Roughton, "Spherical Gaussians
//!   encoding", torust.me, 2018): a progressive least-squares estimate updated once per sample
//!   in the sample order, optionally clamped at 0 after every update.

use crate::encoders::sg::lobes::{naive_normalisation, Lobe};
use crate::math::colour::Rgb;
use glam::DVec3;
use nalgebra::{DMatrix, DVector};

/// The sample matrix of a lobe set on a set of sample directions, and what the least-squares
/// fits need of it: A (N×K, A_ik = G_k(ω_i)), the Gram matrix AᵀA and its pseudo-inverse. It
/// depends on the directions only, never on the radiance, so one design serves every map that
/// is sampled at the same directions.
#[derive(Clone, Debug)]
pub struct Design {
    lobes: Vec<Lobe>,
    directions: Vec<DVec3>,
    /// A, row-major: sample i's K lobe weights at `weights[i*K..(i+1)*K]`.
    weights: Vec<f64>,
    gram: DMatrix<f64>,
    gram_pinv: DMatrix<f64>,
}

/// Singular values of AᵀA below this fraction of the largest are treated as zero in the
/// pseudo-inverse (a rank-deficient design then gets the minimum-norm solution, as the peer's
/// SVD solve does). The peer's 12-lobe design is far from it (condition number about 3e3).
const PINV_RCOND: f64 = 1e-12;

impl Design {
    /// The design of `lobes` at unit sample `directions`.
    pub fn new(lobes: &[Lobe], directions: &[DVec3]) -> Self {
        let k = lobes.len();
        let mut weights = Vec::with_capacity(directions.len() * k);
        for &d in directions {
            weights.extend(lobes.iter().map(|l| l.weight(d)));
        }
        let mut gram = DMatrix::<f64>::zeros(k, k);
        for row in weights.chunks_exact(k.max(1)) {
            for a in 0..k {
                for b in a..k {
                    gram[(a, b)] += row[a] * row[b];
                }
            }
        }
        for a in 0..k {
            for b in 0..a {
                gram[(a, b)] = gram[(b, a)];
            }
        }
        let svd = gram.clone().svd(true, true);
        let smax = svd.singular_values.iter().copied().fold(0.0, f64::max);
        let gram_pinv = svd.pseudo_inverse(smax * PINV_RCOND).unwrap_or_else(|_| DMatrix::zeros(k, k));
        Design { lobes: lobes.to_vec(), directions: directions.to_vec(), weights, gram, gram_pinv }
    }

    /// The lobes of the design, in order.
    pub fn lobes(&self) -> &[Lobe] {
        &self.lobes
    }

    /// The sample directions, in their order.
    pub fn directions(&self) -> &[DVec3] {
        &self.directions
    }

    /// The number of sample directions.
    pub fn samples(&self) -> usize {
        self.weights.len() / self.lobes.len().max(1)
    }

    /// The K lobe weights of sample i.
    pub fn row(&self, i: usize) -> &[f64] {
        let k = self.lobes.len();
        &self.weights[i * k..(i + 1) * k]
    }

    /// The Gram matrix AᵀA.
    #[cfg(test)]
    pub fn gram(&self) -> &DMatrix<f64> {
        &self.gram
    }

    /// Aᵀb for each channel: Σ_i G_k(ω_i)·L_i, in sample order.
    pub fn project(&self, values: &[Rgb]) -> Vec<Rgb> {
        let k = self.lobes.len();
        let mut h = vec![Rgb::ZERO; k];
        for (i, &v) in values.iter().enumerate().take(self.samples()) {
            for (hk, &w) in h.iter_mut().zip(self.row(i)) {
                *hk += w * v;
            }
        }
        h
    }
}

/// The naive fit: μ_k = f·Σ_i L_i·(G_k(ω_i)/N), f = [`naive_normalisation`], summed in sample
/// order as the peer does.
pub fn naive(design: &Design, values: &[Rgb]) -> Vec<Rgb> {
    let k = design.lobes.len();
    let n = design.samples();
    let mut mu = vec![Rgb::ZERO; k];
    if n == 0 {
        return mu;
    }
    let f: Vec<f64> = design.lobes.iter().map(|l| naive_normalisation(l.sharpness, k)).collect();
    for (i, &v) in values.iter().enumerate().take(n) {
        for ((m, &w), &fk) in mu.iter_mut().zip(design.row(i)).zip(&f) {
            *m += v * fk * (w / n as f64);
        }
    }
    mu
}

/// The least-squares amplitudes, per channel: (AᵀA)⁺·Aᵀb.
pub fn least_squares(design: &Design, values: &[Rgb]) -> Vec<Rgb> {
    let h = design.project(values);
    let k = h.len();
    (0..k).map(|a| (0..k).map(|b| design.gram_pinv[(a, b)] * h[b]).sum()).collect()
}

/// What a non-negative fit did: the amplitudes and the Lawson–Hanson iterations (outer
/// iterations summed over the channels).
#[derive(Clone, Debug)]
pub struct NnlsFit {
    /// The fitted amplitude of each lobe.
    pub amplitudes: Vec<Rgb>,
    /// Lawson–Hanson outer iterations, summed over the three channels.
    pub iterations: usize,
}

/// The non-negative least-squares amplitudes, per channel (Lawson–Hanson on the normal
/// equations; see [`nnls`]).
pub fn non_negative_least_squares(design: &Design, values: &[Rgb]) -> NnlsFit {
    let h = design.project(values);
    let k = h.len();
    let mut amplitudes = vec![Rgb::ZERO; k];
    let mut iterations = 0;
    for c in 0..3 {
        let hc: Vec<f64> = h.iter().map(|v| v[c]).collect();
        let (x, it) = nnls(&design.gram, &hc);
        iterations += it;
        for (a, xa) in amplitudes.iter_mut().zip(x) {
            a[c] = xa;
        }
    }
    NnlsFit { amplitudes, iterations }
}

/// Lawson and Hanson's NNLS (1974, ch. 23, algorithm NNLS) for min |Ax − b|² subject to x ≥ 0,
/// given the normal equations G = AᵀA (symmetric positive semi-definite) and h = Aᵀb. Returns
/// x and the outer iterations taken.
///
/// The dual w = h − Gx drives the active set: the index of the largest positive w joins the
/// passive set P, the unconstrained solution on P is taken, and while it has a non-positive
/// entry the step back towards the previous feasible x stops at the first zero and that index
/// leaves P. It stops when no w_j (j ∉ P) exceeds the tolerance 1e-12·max|h| (scale-free), or
/// after 3K outer iterations (K = the number of unknowns, fixed by the lobe set, never by
/// input), with the feasible x reached so far.
pub fn nnls(g: &DMatrix<f64>, h: &[f64]) -> (Vec<f64>, usize) {
    let k = h.len();
    let mut x = vec![0.0; k];
    let hmax = h.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if hmax == 0.0 || !hmax.is_finite() {
        return (x, 0);
    }
    let tol = 1e-12 * hmax;
    let mut passive = vec![false; k];
    let dual =
        |x: &[f64]| -> Vec<f64> { (0..k).map(|a| h[a] - (0..k).map(|b| g[(a, b)] * x[b]).sum::<f64>()).collect() };
    let max_outer = 3 * k;
    let mut outer = 0;
    while outer < max_outer {
        let w = dual(&x);
        let Some(t) = (0..k).filter(|&j| !passive[j] && w[j] > tol).max_by(|&a, &b| w[a].total_cmp(&w[b])) else {
            break;
        };
        outer += 1;
        passive[t] = true;
        let mut added_survived = true;
        for inner in 0..=k {
            let s = solve_passive(g, h, &passive);
            if (0..k).all(|j| !passive[j] || s[j] > 0.0) {
                x = s;
                break;
            }
            // Step from x towards s until the first passive entry reaches 0.
            let mut alpha = 1.0f64;
            for j in 0..k {
                if passive[j] && s[j] <= 0.0 && x[j] - s[j] > 0.0 {
                    let a = x[j] / (x[j] - s[j]);
                    if a < alpha {
                        alpha = a;
                    }
                }
            }
            for j in 0..k {
                if passive[j] {
                    x[j] += alpha * (s[j] - x[j]);
                }
            }
            for j in 0..k {
                if passive[j] && x[j] <= 0.0 {
                    passive[j] = false;
                    x[j] = 0.0;
                    if j == t && inner == 0 {
                        added_survived = false;
                    }
                }
            }
            if inner == k {
                // Cannot happen in exact arithmetic (each pass removes an index); keep x.
                break;
            }
        }
        if !added_survived {
            // The entering index's w was positive only by rounding (its solution on P was
            // not positive): x is optimal to the tolerance.
            break;
        }
    }
    (x, outer)
}

/// The least-squares solution restricted to the passive set (zero elsewhere): G_PP s_P = h_P
/// by Cholesky, or the pseudo-inverse if G_PP is numerically singular.
fn solve_passive(g: &DMatrix<f64>, h: &[f64], passive: &[bool]) -> Vec<f64> {
    let idx: Vec<usize> = (0..h.len()).filter(|&j| passive[j]).collect();
    let m = idx.len();
    let sub = DMatrix::from_fn(m, m, |a, b| g[(idx[a], idx[b])]);
    let rhs = DVector::from_iterator(m, idx.iter().map(|&j| h[j]));
    let sol = match sub.clone().cholesky() {
        Some(ch) => ch.solve(&rhs),
        None => {
            let svd = sub.svd(true, true);
            let smax = svd.singular_values.iter().copied().fold(0.0, f64::max);
            svd.solve(&rhs, smax * PINV_RCOND).unwrap_or_else(|_| DVector::zeros(m))
        }
    };
    let mut s = vec![0.0; h.len()];
    for (a, &j) in idx.iter().enumerate() {
        s[j] = if sol[a].is_finite() { sol[a] } else { 0.0 };
    }
    s
}

/// The running average (`ExperimentSGRunningAverage`), over the samples in the given order.
/// For sample i (weight 1, so the blend factor is 1/i) and lobe k, with w_k = G_k(ω_i):
///
/// - the lobe's running mean of w_k² (its Monte Carlo estimate of ∫G_k²dω/4π) is updated, and
///   floored at 0.75 × the exact (1 − e^{−4λ})/(4λ) ("to avoid noise");
/// - the target is (L_i − Σ_{j≠k} μ_j w_j)·w_k / that integral, with the other lobes'
///   estimate taken before this sample's updates;
/// - μ_k += (target − μ_k)/i, then clamped at 0 if `non_negative`.
///
/// Lobes with w_k = 0 are skipped, as the peer does. Sample order matters.
pub fn running_average(design: &Design, values: &[Rgb], non_negative: bool) -> Vec<Rgb> {
    let k = design.lobes.len();
    let mut mu = vec![Rgb::ZERO; k];
    let mut mc_integral = vec![0.0f64; k];
    let exact_integral: Vec<f64> = design
        .lobes
        .iter()
        .map(|l| {
            let lambda = l.sharpness;
            if lambda < 1e-8 {
                1.0
            } else {
                -(-4.0 * lambda).exp_m1() / (4.0 * lambda)
            }
        })
        .collect();
    let mut total_weight = 0.0f64;
    for (i, &value) in values.iter().enumerate().take(design.samples()) {
        let w = design.row(i);
        total_weight += 1.0;
        let blend = 1.0 / total_weight;
        let estimate: Rgb = mu.iter().zip(w).map(|(&m, &wk)| m * wk).sum();
        for j in 0..k {
            let wk = w[j];
            if wk == 0.0 {
                continue;
            }
            mc_integral[j] += (wk * wk - mc_integral[j]) * blend;
            let integral = mc_integral[j].max(0.75 * exact_integral[j]);
            let others = estimate - mu[j] * wk;
            let target = (value - others) * wk / integral;
            let m = mu[j];
            mu[j] = m + (target - m) * blend;
            if non_negative {
                mu[j] = mu[j].max(Rgb::ZERO);
            }
        }
    }
    mu
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::encoders::sg::lobes::{radiance, vogel_lobes};
    use crate::math::test_rng::Rng;
    use std::f64::consts::PI;

    /// A uniform spherical Fibonacci set of n directions (any well-spread set serves the
    /// algebraic tests).
    fn fibonacci(n: usize) -> Vec<DVec3> {
        let ga = PI * (3.0 - 5f64.sqrt());
        (0..n)
            .map(|i| {
                let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
                let r = (1.0 - z * z).sqrt();
                let (s, c) = (ga * i as f64).sin_cos();
                DVec3::new(r * c, r * s, z)
            })
            .collect()
    }

    fn lobes12() -> Vec<Lobe> {
        vogel_lobes(12, 6.0)
    }

    #[test]
    fn least_squares_recovers_a_radiance_in_the_span() {
        // Radiance made of the lobes themselves (with negative amplitudes too) is fitted exactly.
        let lobes = lobes12();
        let dirs = fibonacci(4000);
        let design = Design::new(&lobes, &dirs);
        let mut rng = Rng::new(3);
        let truth: Vec<Rgb> = (0..12).map(|_| Rgb::new(rng.next(), rng.next(), rng.next()) * 3.0).collect();
        let values: Vec<Rgb> = dirs.iter().map(|&d| radiance(&lobes, &truth, d)).collect();
        let mu = least_squares(&design, &values);
        for (a, b) in mu.iter().zip(&truth) {
            assert!((*a - *b).abs().max_element() < 1e-9, "{a} vs {b}");
        }
    }

    #[test]
    fn least_squares_residual_is_orthogonal_to_every_lobe() {
        // The defining property of the minimiser: Aᵀ(b − Aμ) = 0, checked sample by sample.
        let mut lobes = lobes12();
        lobes.push(Lobe { axis: DVec3::Z, sharpness: 0.0 });
        let dirs = fibonacci(3000);
        let design = Design::new(&lobes, &dirs);
        let values: Vec<Rgb> =
            dirs.iter().map(|d| Rgb::new(d.x.max(0.0).powi(8) * 40.0, 1.0 + d.y, (3.0 * d.z).exp())).collect();
        let mu = least_squares(&design, &values);
        let scale = values.iter().map(|v| v.abs().max_element()).fold(0.0, f64::max) * dirs.len() as f64;
        for (k, lobe) in lobes.iter().enumerate() {
            let r: Rgb = dirs.iter().zip(&values).map(|(&d, &v)| (v - radiance(&lobes, &mu, d)) * lobe.weight(d)).sum();
            assert!(r.abs().max_element() < 1e-10 * scale, "lobe {k}: {r}");
        }
    }

    #[test]
    fn the_peer_design_is_well_conditioned() {
        let mut lobes = lobes12();
        let dirs = fibonacci(20000);
        let cond = |d: &Design| {
            let s = d.gram().clone().symmetric_eigenvalues();
            s.max() / s.min()
        };
        let c12 = cond(&Design::new(&lobes, &dirs));
        lobes.push(Lobe { axis: DVec3::Z, sharpness: 0.0 });
        let c13 = cond(&Design::new(&lobes, &dirs));
        assert!(c12 < 1e5 && c13 < 1e6, "condition numbers {c12:e}, {c13:e}");
    }

    /// NNLS by brute force: the best of the unconstrained solutions on every subset that are
    /// feasible (the optimum is one of them, with the rest at 0).
    fn nnls_brute(g: &DMatrix<f64>, h: &[f64]) -> Vec<f64> {
        let k = h.len();
        let objective = |x: &[f64]| {
            // ½xᵀGx − hᵀx: |Ax − b|² up to a constant.
            let mut o = 0.0;
            for a in 0..k {
                o -= h[a] * x[a];
                for b in 0..k {
                    o += 0.5 * x[a] * g[(a, b)] * x[b];
                }
            }
            o
        };
        let mut best = vec![0.0; k];
        let mut best_o = 0.0;
        for mask in 1u32..(1 << k) {
            let passive: Vec<bool> = (0..k).map(|j| mask & (1 << j) != 0).collect();
            let s = solve_passive(g, h, &passive);
            if s.iter().all(|&v| v >= 0.0) {
                let o = objective(&s);
                if o < best_o {
                    best_o = o;
                    best = s;
                }
            }
        }
        best
    }

    #[test]
    fn nnls_matches_brute_force_on_small_designs() {
        // Six lobes (64 subsets), radiance with strong negative parts so that some amplitudes
        // are held at zero.
        let lobes = vogel_lobes(6, 3.0);
        let dirs = fibonacci(2000);
        let design = Design::new(&lobes, &dirs);
        let mut rng = Rng::new(11);
        let mut held = 0;
        for trial in 0..20 {
            let truth: Vec<f64> = (0..6).map(|_| 2.0 * rng.next()).collect();
            let bump = rng.unit();
            let values: Vec<Rgb> = dirs
                .iter()
                .map(|&d| {
                    let v: f64 = lobes.iter().zip(&truth).map(|(l, t)| t * l.weight(d)).sum::<f64>()
                        + (4.0 * (bump.dot(d) - 1.0)).exp();
                    Rgb::splat(v)
                })
                .collect();
            let h: Vec<f64> = design.project(&values).iter().map(|v| v.x).collect();
            let (x, _) = nnls(design.gram(), &h);
            let b = nnls_brute(design.gram(), &h);
            held += x.iter().filter(|&&v| v == 0.0).count();
            for (a, e) in x.iter().zip(&b) {
                assert!((a - e).abs() < 1e-9 * (1.0 + e.abs()), "trial {trial}: {x:?} vs {b:?}");
            }
        }
        assert!(held > 5, "the trials should exercise the constraint ({held} zeros)");
    }

    #[test]
    fn nnls_meets_the_kkt_conditions_on_the_peer_design() {
        // x ≥ 0; w = h − Gx ≤ tol where x = 0; |w| small where x > 0.
        let lobes = lobes12();
        let dirs = fibonacci(5000);
        let design = Design::new(&lobes, &dirs);
        let mut rng = Rng::new(5);
        for _ in 0..10 {
            let a = rng.unit();
            let b = rng.unit();
            let values: Vec<Rgb> = dirs
                .iter()
                .map(|&d| {
                    Rgb::new((20.0 * (a.dot(d) - 1.0)).exp() * 50.0, 0.2 + d.y.max(0.0), (b.dot(d)).max(0.0).powi(30))
                })
                .collect();
            let fit = non_negative_least_squares(&design, &values);
            let h = design.project(&values);
            for c in 0..3 {
                let x: Vec<f64> = fit.amplitudes.iter().map(|v| v[c]).collect();
                let hc: Vec<f64> = h.iter().map(|v| v[c]).collect();
                let hmax = hc.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for j in 0..12 {
                    let w = hc[j] - (0..12).map(|k| design.gram()[(j, k)] * x[k]).sum::<f64>();
                    assert!(x[j] >= 0.0);
                    if x[j] == 0.0 {
                        assert!(w <= 1e-10 * hmax, "inactive {j}: w = {w}");
                    } else {
                        assert!(w.abs() <= 1e-10 * hmax, "active {j}: w = {w}");
                    }
                }
            }
            assert!(fit.iterations <= 3 * 3 * 12);
        }
    }

    #[test]
    fn nnls_equals_least_squares_when_that_is_non_negative_and_is_zero_on_black() {
        let lobes = lobes12();
        let dirs = fibonacci(3000);
        let design = Design::new(&lobes, &dirs);
        let truth: Vec<Rgb> = (0..12).map(|k| Rgb::new(1.0 + k as f64, 0.5, 2.0)).collect();
        let values: Vec<Rgb> = dirs.iter().map(|&d| radiance(&lobes, &truth, d)).collect();
        let ls = least_squares(&design, &values);
        let nn = non_negative_least_squares(&design, &values);
        for (a, b) in nn.amplitudes.iter().zip(&ls) {
            assert!((*a - *b).abs().max_element() < 1e-9);
        }
        let black = vec![Rgb::ZERO; dirs.len()];
        let z = non_negative_least_squares(&design, &black);
        assert!(z.amplitudes.iter().all(|v| *v == Rgb::ZERO) && z.iterations == 0);
    }

    #[test]
    fn naive_projects_a_constant_to_about_itself() {
        // μ_k = c·f·mean(G_k) → c·2λ/K = c for λ = K/2, to the sample set's quadrature error.
        let lobes = lobes12();
        let dirs = fibonacci(20000);
        let design = Design::new(&lobes, &dirs);
        let values = vec![Rgb::new(1.0, 2.0, 0.5); dirs.len()];
        for m in naive(&design, &values) {
            assert!((m - Rgb::new(1.0, 2.0, 0.5)).abs().max_element() < 1e-3, "{m}");
        }
    }

    #[test]
    fn running_average_first_steps_by_hand() {
        // One lobe: after sample 1, μ = L₁w₁/max(w₁², 0.75·I); after sample 2, the mean of the
        // two targets with the running w² mean, each with the other lobes' part (none) removed
        // and the lobe's own estimate excluded.
        let lobe = Lobe { axis: DVec3::Z, sharpness: 2.0 };
        let dirs = [DVec3::new(0.6, 0.0, 0.8), DVec3::new(0.0, -0.8, 0.6)];
        let design = Design::new(&[lobe], &dirs);
        let values = [Rgb::new(1.0, -2.0, 3.0), Rgb::new(0.5, 4.0, -1.0)];
        let exact = (1.0 - (-8.0f64).exp()) / 8.0;
        let (w1, w2) = (lobe.weight(dirs[0]), lobe.weight(dirs[1]));
        let i1 = (w1 * w1).max(0.75 * exact);
        let mu1 = values[0] * w1 / i1;
        let m2 = 0.5 * (w1 * w1 + w2 * w2);
        let i2 = m2.max(0.75 * exact);
        let t2 = values[1] * w2 / i2;
        let mu2 = mu1 + (t2 - mu1) * 0.5;
        let got = running_average(&design, &values, false);
        assert!((got[0] - mu2).abs().max_element() < 1e-14, "{} vs {mu2}", got[0]);
        // Non-negative: the clamp applies after every update.
        let mu1n = mu1.max(Rgb::ZERO);
        let mu2n = (mu1n + (t2 - mu1n) * 0.5).max(Rgb::ZERO);
        let got = running_average(&design, &values, true);
        assert!((got[0] - mu2n).abs().max_element() < 1e-14, "{} vs {mu2n}", got[0]);
    }

    #[test]
    fn running_average_with_two_lobes_uses_the_other_lobe_estimate_before_the_sample() {
        let lobes = [Lobe { axis: DVec3::Z, sharpness: 1.0 }, Lobe { axis: DVec3::X, sharpness: 1.0 }];
        let dirs = [DVec3::new(0.6, 0.0, 0.8), DVec3::new(0.8, 0.0, 0.6)];
        let design = Design::new(&lobes, &dirs);
        let values = [Rgb::ONE, Rgb::splat(2.0)];
        let exact = (1.0 - (-4.0f64).exp()) / 4.0;
        let w = |s: usize, k: usize| lobes[k].weight(dirs[s]);
        // Sample 1: both lobes start at 0, so each target is L·w/I.
        let mu_a = values[0] * w(0, 0) / (w(0, 0) * w(0, 0)).max(0.75 * exact);
        let mu_b = values[0] * w(0, 1) / (w(0, 1) * w(0, 1)).max(0.75 * exact);
        // Sample 2: the estimate is taken once, before either lobe moves.
        let est = mu_a * w(1, 0) + mu_b * w(1, 1);
        let ia = (0.5 * (w(0, 0).powi(2) + w(1, 0).powi(2))).max(0.75 * exact);
        let ib = (0.5 * (w(0, 1).powi(2) + w(1, 1).powi(2))).max(0.75 * exact);
        let ta = (values[1] - (est - mu_a * w(1, 0))) * w(1, 0) / ia;
        let tb = (values[1] - (est - mu_b * w(1, 1))) * w(1, 1) / ib;
        let got = running_average(&design, &values, false);
        assert!((got[0] - (mu_a + (ta - mu_a) * 0.5)).abs().max_element() < 1e-14);
        assert!((got[1] - (mu_b + (tb - mu_b) * 0.5)).abs().max_element() < 1e-14);
    }

    #[test]
    fn running_average_approaches_least_squares_on_a_radiance_in_the_span() {
        // On radiance made of the lobes the single pass gets close (not exactly: it is one
        // pass of a progressive estimate), far closer than the naive projection.
        let lobes = lobes12();
        // The running average needs an order that covers the sphere evenly as it goes (the
        // peer's Halton order does); the Fibonacci set sweeps from pole to pole, so shuffle it.
        let mut dirs = fibonacci(20000);
        let mut rng = Rng::new(9);
        for i in (1..dirs.len()).rev() {
            let j = ((rng.uniform01() * (i + 1) as f64) as usize).min(i);
            dirs.swap(i, j);
        }
        let design = Design::new(&lobes, &dirs);
        let truth: Vec<Rgb> = (0..12).map(|k| Rgb::splat(1.0 + (k % 3) as f64)).collect();
        let values: Vec<Rgb> = dirs.iter().map(|&d| radiance(&lobes, &truth, d)).collect();
        let res = |mu: &[Rgb]| -> f64 {
            (dirs.iter().zip(&values).map(|(&d, &v)| (v - radiance(&lobes, mu, d)).length_squared()).sum::<f64>()
                / dirs.len() as f64)
                .sqrt()
        };
        let ra = res(&running_average(&design, &values, false));
        let nv = res(&naive(&design, &values));
        let norm = res(&vec![Rgb::ZERO; 12]);
        // Measured: 1.3% of the radiance RMS, a tenth of the naive projection's residual.
        assert!(ra < 0.05 * norm && ra < 0.2 * nv, "ra {ra}, naive {nv}, |truth| {norm}");
    }
}
