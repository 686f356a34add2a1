//! The colours for a fixed direction d (FORMULAS §7, §8): least squares over the domain,
//! `Free` as a two-variable NNLS, `IrradZ` with I(N) = I_z fixed; and the objective in θ that
//! the direction search minimises, with the θ-independent parts computed once.

use super::super::lune::{Angle, Clamped, Y_INT};
use super::super::model::Basis;
use crate::math::colour::Rgb;

use super::spec::*;
use super::target::*;

/// The colours and error for one direction.
#[derive(Clone, Copy, Debug)]
pub struct Colour {
    /// The ambient colour C_a (E/π).
    pub c_a: Rgb,
    /// The directional colour C_d (E/π).
    pub c_d: Rgb,
    /// Σ_c weight_c·(‖model − q‖² − ‖q‖²) over the domain.
    pub objective: f64,
}

/// Solves the colours at tilt `t` (module docs).
#[cfg(test)]
pub fn colours_at(spec: &FitSpec, domain: &FitDomain, target: &dyn FitTarget, i_z: Rgb, t: Angle) -> Colour {
    let md = &domain.moments;
    let mc = domain.lune(t);
    let (s, c) = (t.sin, t.cos);
    let fd1 = s * mc.get(1, 0, 0) + c * mc.get(0, 0, 1);
    let fdz = s * mc.get(1, 0, 1) + c * mc.get(0, 0, 2);
    let gdd = s * s * mc.get(2, 0, 0) + 2.0 * s * c * mc.get(1, 0, 1) + c * c * mc.get(0, 0, 2);
    let plain = target.plain();
    let (gaa, gad, ba) = match spec.basis {
        Basis::Ahd => (md.get(0, 0, 0), fd1, plain[0]),
        Basis::Hhd => (
            0.25 * (md.get(0, 0, 0) + 2.0 * md.get(0, 0, 1) + md.get(0, 0, 2)),
            0.5 * (fd1 + fdz),
            0.5 * (plain[0] + plain[1]),
        ),
    };
    let bd = target.clamped(t, &mc);
    let mut out = Colour { c_a: Rgb::ZERO, c_d: Rgb::ZERO, objective: 0.0 };
    for ch in 0..3 {
        let (ca, cd, j) = match spec.colours {
            Colours::Free => nnls2(gaa, gad, gdd, ba[ch], bd[ch]),
            Colours::IrradZ => irradz(gaa, gad, gdd, ba[ch], bd[ch], i_z[ch], c),
        };
        out.c_a[ch] = ca;
        out.c_d[ch] = cd;
        out.objective += spec.weights[ch] * j;
    }
    out
}

/// The pair (`lune::CLAMPED_PAIRS`) of each monomial of [`EVEN_Y`]: x^a y^b z^c times
/// max(0, n·d) integrates over the lune to Y(a + c + 1, b)·g_i with
/// CLAMPED_PAIRS[i] = ((a + 1, c), (a, c + 1)) (1 and y² share one).
pub(super) const PAIR_OF: [usize; 7] = [0, 1, 2, 3, 0, 4, 5];

/// [`colours_at`] for the quadratic target as a function of the tilt θ alone, with everything
/// independent of θ hoisted out: G_aa and ∫ f_a·q (the domain and the target's plain products),
/// the target's coefficients folded with the moments' Y factors into six RGB weights k_i
/// (∫ max(0, n·d)·q = Σ_i k_i·g_i(θ) with the lune's clamped-cosine integrals g_i of
/// `lune::Clamped`; G_dd and ∫ max(0, n·d)·(1, z) are g's too), and 1/I_z. One θ then costs
/// a sin/cos (`Angle::tilt`), the six g's (a few flops each), six RGB multiply-adds and the
/// three channels' colour solves at once, with one division per solve shared by the
/// channels. Equal to [`colours_at`] to rounding (tested).
#[derive(Clone, Copy, Debug)]
pub struct ThetaObjective {
    gram: Gram,
    basis: Basis,
    colours: Colours,
    weights: Rgb,
    i_z: Rgb,
    /// 1/I_z where I_z > 0, else 0 (those channels are zero, [`irradz`]).
    inv_i_z: Rgb,
    /// The IrradZ objective at w = 1 (pure ambient), I_z²·G_aa − 2 I_z·b_a: d plays no part.
    j_ambient: Rgb,
    gaa: f64,
    ba: Rgb,
    k: [Rgb; 6],
}

impl ThetaObjective {
    /// The objective of `spec` on `domain` for `target` (with I_z, the irradiance at N, for
    /// the IrradZ colours), its θ-independent parts computed once.
    pub fn new(spec: &FitSpec, domain: &FitDomain, target: &QuadraticTarget, i_z: Rgb) -> Self {
        let md = domain.moments;
        let plain = target.plain;
        let (gaa, ba) = match spec.basis {
            Basis::Ahd => (md.get(0, 0, 0), plain[0]),
            Basis::Hhd => {
                (0.25 * (md.get(0, 0, 0) + 2.0 * md.get(0, 0, 1) + md.get(0, 0, 2)), 0.5 * (plain[0] + plain[1]))
            }
        };
        let mut k = [Rgb::ZERO; 6];
        for (j, i) in EVEN_Y.into_iter().zip(PAIR_OF) {
            let (a, b, c) = MONO[j];
            k[i] += target.coef[j] * Y_INT[a + c + 1][b];
        }
        let inv_i_z = match spec.colours {
            Colours::IrradZ => Rgb::select(i_z.cmpgt(Rgb::ZERO), Rgb::ONE / i_z, Rgb::ZERO),
            Colours::Free => Rgb::ZERO,
        };
        ThetaObjective {
            gram: domain.gram,
            basis: spec.basis,
            colours: spec.colours,
            weights: spec.weights,
            i_z,
            inv_i_z,
            j_ambient: i_z * i_z * gaa - i_z * ba * 2.0,
            gaa,
            ba,
            k,
        }
    }

    /// The objective alone at tilt θ (what the search compares; the colours' arithmetic is
    /// left out by inlining).
    #[inline]
    pub fn objective(&self, theta: f64) -> f64 {
        self.at(theta).objective
    }

    /// The colours and objective at tilt θ (the same quantities as [`colours_at`]).
    #[inline]
    pub fn at(&self, theta: f64) -> Colour {
        let t = Angle::tilt(theta);
        let (s, c) = (t.sin, t.cos);
        let g = match self.gram {
            Gram::Hemisphere => Clamped::hemisphere_lune(t),
            Gram::Sphere => Clamped::sphere_half(t),
        }
        .0;
        // ∫ max(0, n·d) = Y(1, 0)·g₀, ∫ z·max(0, n·d) = Y(2, 0)·g₂ and G_dd = ∫ max(0, n·d)² =
        // Y(2, 0)·(sin θ·g₁ + cos θ·g₂).
        let fd1 = Y_INT[1][0] * g[0];
        let fdz = Y_INT[2][0] * g[2];
        let gdd = Y_INT[2][0] * (s * g[1] + c * g[2]);
        let gad = match self.basis {
            Basis::Ahd => fd1,
            Basis::Hhd => 0.5 * (fd1 + fdz),
        };
        let mut bd = Rgb::ZERO;
        for (k, g) in self.k.iter().zip(g) {
            bd += *k * g;
        }
        let (c_a, c_d, j) = match self.colours {
            Colours::Free => nnls2_rgb(self.gaa, gad, gdd, self.ba, bd),
            Colours::IrradZ => self.irradz_rgb(gad, gdd, bd, c),
        };
        Colour { c_a, c_d, objective: self.weights.dot(j) }
    }

    /// [`irradz`] for three channels sharing the Gram and d_z, with its terms multiplied through
    /// by d_z² so that the weight w needs one division (by d_z²·u·u, shared by the channels) and
    /// 1/d_z² runs alongside it: d_z²·u·u = G_aa d_z² − 2 G_ad d_z + G_dd, d_z²·u·g = G_ad d_z − G_dd,
    /// d_z²·u·q = d_z (b_a d_z − b_d). Channels with I_z ≤ 0 are zero.
    #[inline]
    fn irradz_rgb(&self, gad: f64, gdd: f64, bd: Rgb, dz: f64) -> (Rgb, Rgb, Rgb) {
        let (gaa, ba, i_z, inv_i_z) = (self.gaa, self.ba, self.i_z, self.inv_i_z);
        if dz <= 0.0 {
            return (Rgb::ZERO, Rgb::ZERO, Rgb::ZERO);
        }
        let dz2 = dz * dz;
        let inv_dz2 = 1.0 / dz2;
        let uu = gaa * dz2 - 2.0 * gad * dz + gdd;
        let ug = gad * dz - gdd;
        let uq = (ba * dz - bd) * dz;
        let w = if uu > 1e-300 * dz2 {
            ((uq * inv_i_z - Rgb::splat(ug)) * (1.0 / uu)).clamp(Rgb::ZERO, Rgb::ONE)
        } else {
            Rgb::splat(0.5)
        };
        // J about w = 1 (pure ambient, C_d = 0): with v = 1 − w, I = I_z·(f_a − v·u) and
        // J = I_z²·G_aa − 2 I_z·b_a + I_z²·(v²·u·u − 2v·f_a·u) + 2 I_z·v·u·q, d_z²·f_a·u =
        // G_aa d_z² − G_ad d_z. At v = 0 J is the precomputed constant exactly, so that a search
        // over such a plateau (d plays no part) sees exact ties, as with the NNLS's ambient-only
        // fallback, not rounding noise.
        let v = Rgb::ONE - w;
        let fu = gaa * dz2 - gad * dz;
        let j = self.j_ambient + (i_z * i_z * (v * v * uu - v * (2.0 * fu)) + i_z * v * uq * 2.0) * inv_dz2;
        let on = i_z.cmpgt(Rgb::ZERO);
        (
            Rgb::select(on, w * i_z, Rgb::ZERO),
            Rgb::select(on, v * i_z * (dz * inv_dz2), Rgb::ZERO),
            Rgb::select(on, j, Rgb::ZERO),
        )
    }
}

/// [`nnls2`] for three channels sharing the Gram: one reciprocal of the determinant, and the
/// per-channel fallbacks only when some channel's unconstrained solution is infeasible.
#[inline]
pub(super) fn nnls2_rgb(gaa: f64, gad: f64, gdd: f64, ba: Rgb, bd: Rgb) -> (Rgb, Rgb, Rgb) {
    let det = gaa * gdd - gad * gad;
    if det > 1e-12 * gaa * gdd {
        let inv = 1.0 / det;
        let a = (ba * gdd - bd * gad) * inv;
        let d = (bd * gaa - ba * gad) * inv;
        if a.cmpge(Rgb::ZERO).all() && d.cmpge(Rgb::ZERO).all() {
            let j = a * a * gaa + a * d * (2.0 * gad) + d * d * gdd - ba * a * 2.0 - bd * d * 2.0;
            return (a, d, j);
        }
    }
    let mut out = (Rgb::ZERO, Rgb::ZERO, Rgb::ZERO);
    for ch in 0..3 {
        (out.0[ch], out.1[ch], out.2[ch]) = nnls2(gaa, gad, gdd, ba[ch], bd[ch]);
    }
    out
}

/// min over ca, cd ≥ 0 of J = gaa ca² + 2 gad ca cd + gdd cd² − 2 ba ca − 2 bd cd.
pub(super) fn nnls2(gaa: f64, gad: f64, gdd: f64, ba: f64, bd: f64) -> (f64, f64, f64) {
    let j = |a: f64, d: f64| gaa * a * a + 2.0 * gad * a * d + gdd * d * d - 2.0 * ba * a - 2.0 * bd * d;
    let det = gaa * gdd - gad * gad;
    if det > 1e-12 * gaa * gdd {
        let (a, d) = ((gdd * ba - gad * bd) / det, (gaa * bd - gad * ba) / det);
        if a >= 0.0 && d >= 0.0 {
            return (a, d, j(a, d));
        }
    }
    let a = if gaa > 0.0 { (ba / gaa).max(0.0) } else { 0.0 };
    let d = if gdd > 0.0 { (bd / gdd).max(0.0) } else { 0.0 };
    let (ja, jd) = (j(a, 0.0), j(0.0, d));
    if ja <= jd {
        (a, 0.0, ja)
    } else {
        (0.0, d, jd)
    }
}

/// The IrradZ line I = I_z·(g + w·u), g = f_d/d_z, u = f_a − g, w ∈ [0, 1].
#[cfg(test)]
pub(super) fn irradz(gaa: f64, gad: f64, gdd: f64, ba: f64, bd: f64, i_z: f64, dz: f64) -> (f64, f64, f64) {
    if i_z <= 0.0 || dz <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    let inv = 1.0 / dz;
    let gg = gdd * inv * inv;
    let ug = gad * inv - gg;
    let uu = gaa - 2.0 * gad * inv + gg;
    let (uq, gq) = (ba - bd * inv, bd * inv);
    let w = if uu > 1e-300 { ((uq - i_z * ug) / (i_z * uu)).clamp(0.0, 1.0) } else { 0.5 };
    // w = 1: J without d, exactly (see `irradz_rgb`).
    let j = if w == 1.0 {
        i_z * i_z * gaa - 2.0 * i_z * ba
    } else {
        i_z * i_z * (gg + 2.0 * w * ug + w * w * uu) - 2.0 * i_z * (gq + w * uq)
    };
    (w * i_z, (1.0 - w) * i_z * inv, j)
}
