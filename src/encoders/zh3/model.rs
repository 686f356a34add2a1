//! The ZH3 itself (ZH3 talk; FORMULAS §5): L0, L1 and a zonal coefficient k about each
//! channel's axis, its SH3 expansion, and the three ways to get k — hallucinated from L1 by a
//! curve, stored (the least-squares zonal fit of L2), or with the L1 solved.

use crate::encoders::zh3::solve::{
    self as zh3_solve, band2, zonal_fit, zonal_fit_at, Curve, SolverSettings, Target, Zonal,
};
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use glam::DVec3;

/// Where the zonal axis of each channel comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AxisRule {
    /// Each channel's own L1.
    Channel,
    /// One axis from the L1 weighted by these channel weights.
    Shared(Rgb),
}

impl AxisRule {
    /// The unit axis of each channel for L1 vectors `l1`, or None where the (weighted) L1 is 0.
    pub fn axes(&self, l1: &[DVec3; 3]) -> [Option<DVec3>; 3] {
        let unit = |v: DVec3| {
            let n = v.length();
            (n > 0.0 && n.is_finite()).then(|| v / n)
        };
        match self {
            AxisRule::Channel => std::array::from_fn(|c| unit(l1[c])),
            AxisRule::Shared(w) => [unit((0..3).map(|c| l1[c] * w[c]).sum()); 3],
        }
    }
}

/// A ZH3 in irradiance units (E/π): L0, the L1 vectors (xyz per channel), the axes and the
/// zonal coefficients k (L₂ₘ ≈ k·Y₂ₘ(a)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Zh3 {
    /// Band 0 (E/π), per channel.
    pub l0: Rgb,
    /// Per channel, the band-1 coefficients as a world xyz vector (−L₁,₁, −L₁,₋₁, L₁,₀), as
    /// `Sh9::l1_vector` gives them.
    pub l1: [DVec3; 3],
    /// Per channel, the zonal axis a; None when the channel has no usable L1 (no band-2 term then).
    pub axes: [Option<DVec3>; 3],
    /// Per channel, the zonal coefficient k: band 2 is k·Y₂ₘ(a).
    pub k: Rgb,
}

impl Zh3 {
    /// Expands to an irradiance SH3.
    pub fn to_sh(self) -> Sh9 {
        let mut s = Sh9::ZERO;
        s[0] = self.l0;
        for c in 0..3 {
            let v = self.l1[c];
            s[1][c] = -v.y;
            s[2][c] = v.z;
            s[3][c] = -v.x;
            if let Some(a) = self.axes[c] {
                let y = band2(a);
                for m in 0..5 {
                    s[4 + m][c] = self.k[c] * y[m];
                }
            }
        }
        s
    }

    /// The radiance ratio r_c = |L1_c·a_c|/L₀₀,c of each channel (0 without axis or light).
    pub fn ratios(&self) -> Rgb {
        Rgb::from_array(std::array::from_fn(|c| match self.axes[c] {
            Some(a) if self.l0[c] > 0.0 => 1.5 * self.l1[c].dot(a).abs() / self.l0[c],
            _ => 0.0,
        }))
    }
}

/// L1 vectors of an irradiance SH.
fn l1_vectors(irr: &Sh9) -> [DVec3; 3] {
    std::array::from_fn(|c| irr.l1_vector(c))
}

/// Hallucinated ZH3 from an irradiance SH (only L0 and L1 are read).
pub fn hallucinate(irr: &Sh9, rule: AxisRule, curve: Curve) -> Zh3 {
    finish_hallucinated(irr[0], l1_vectors(irr), rule, curve)
}

/// A hallucinated ZH3 of these L0 and L1: the axes by `rule`, k by `curve`.
pub(super) fn finish_hallucinated(l0: Rgb, l1: [DVec3; 3], rule: AxisRule, curve: Curve) -> Zh3 {
    let axes = rule.axes(&l1);
    let k = Rgb::from_array(std::array::from_fn(|c| match axes[c] {
        Some(a) => zh3_solve::hallucinated_k(l0[c], l1[c], a, curve),
        None => 0.0,
    }));
    Zh3 { l0, l1, axes, k }
}

/// Stored ZH3 of an irradiance SH: axes from its L1, k the least-squares zonal fit.
pub fn stored(irr: &Sh9, rule: AxisRule) -> Zh3 {
    finish_stored(irr, l1_vectors(irr), rule)
}

fn finish_stored(irr: &Sh9, l1: [DVec3; 3], rule: AxisRule) -> Zh3 {
    let axes = rule.axes(&l1);
    let k = Rgb::from_array(std::array::from_fn(|c| match axes[c] {
        Some(a) => zonal_fit(a, &zh3_solve::l2_band(irr, c)),
        None => 0.0,
    }));
    Zh3 { l0: irr[0], l1, axes, k }
}

/// ∫ over the sphere of |E_zh3(n) − E_r(n)|² dω summed over RGB, against `irr`, of the
/// closed-form ZH3 of `irr` (k hallucinated by a curve, or stored: [`hallucinate`], [`stored`]):
/// [`crate::encoders::encoder::sh3_sq_error`] of its [`Zh3::to_sh`], bit for bit, without
/// building the ZH3 or its SH3 (the batch form probe sets score through).
///
/// The same operations in the same order as [`Zh3::to_sh`] then that sum: bands 0 and 1 of the
/// expansion are the reference's own (L0 copied, L1 negated twice), so their differences are
/// `r − r`, exactly 0 (NaN where `irr` is not finite, as there); band 2 is k·Y₂(a) per channel,
/// 0 without axis. A shared axis's Y₂(a) is taken once for the three channels.
pub fn closed_form_sq_error(irr: &Sh9, rule: AxisRule, zonal: Zonal) -> f64 {
    let l1 = l1_vectors(irr);
    let axes = rule.axes(&l1);
    let shared = match (rule, axes[0]) {
        (AxisRule::Shared(_), Some(a)) => band2(a),
        _ => [0.0; 5],
    };
    let mut band = [[0.0; 3]; 5];
    for c in 0..3 {
        let Some(a) = axes[c] else { continue };
        let y = if matches!(rule, AxisRule::Shared(_)) { shared } else { band2(a) };
        let l2 = zh3_solve::l2_band(irr, c);
        let k = match zonal {
            Zonal::Hallucinated(curve) => zh3_solve::hallucinated_k(irr[0][c], l1[c], a, curve),
            Zonal::Stored => zonal_fit_at(&y, &l2),
        };
        for m in 0..5 {
            band[m][c] = k * y[m];
        }
    }
    let mut se = 0.0;
    for i in 0..4 {
        se += (irr[i] - irr[i]).length_squared();
    }
    for m in 0..5 {
        se += (Rgb::from_array(band[m]) - irr[4 + m]).length_squared();
    }
    se
}

/// The solve's result: the ZH3 and the summed statistics of its solves.
pub struct Solved {
    /// The solved ZH3.
    pub zh3: Zh3,
    /// Statistics of its solves, summed over the channels solved.
    pub stats: zh3_solve::SolveStats,
}

/// Solved-axis ZH3 of an irradiance SH (FORMULAS §5). With `AxisRule::Channel` each channel
/// is solved on its own (3 variables); with `Shared` the three channels are solved together
/// (9 variables) with the axis weights of the rule and `err_w` in the objective.
pub fn solved(irr: &Sh9, rule: AxisRule, err_w: Rgb, zonal: Zonal, settings: &SolverSettings) -> Solved {
    let target = match rule {
        AxisRule::Channel => Target::per_channel(irr, zonal),
        AxisRule::Shared(w) => Target::shared(irr, w, err_w, zonal),
    };
    let s = zh3_solve::solve(&target, settings);
    let (l1, stats) = (s.l1, s.stats);
    let zh3 = match zonal {
        Zonal::Stored => finish_stored(irr, l1, rule),
        Zonal::Hallucinated(curve) => finish_hallucinated(irr[0], l1, rule, curve),
    };
    Solved { zh3, stats }
}
