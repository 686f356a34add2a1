//! Fig. 2 of the 2018 brief ("Directional Lightmap Encoding Insights", §2), exactly: a 1-D
//! strip of two texels on a surface with normal N = z. The left texel is a directional light
//! of unit intensity whose highlight direction is tilted by α towards the left,
//! d_L = (−sin α, 0, cos α), C_a = 0, C_d = 1; the right texel has zero intensity pointing to
//! the right, d_R = (sin α, 0, cos α), C_a = 0, C_d = 0. The stored parameters are blended
//! along t ∈ [0, 1] and the irradiance at N (E/π, "irradiance in local Z") is plotted. The
//! figure states no tilt, so α is swept.
//!
//! With s = sin α, c = cos α and u = 1 − t (closed forms derived here):
//!
//! - **IrradZ** stores (C_a, d_xy, I_z); I_z = I(N) is blended linearly: I(N) = u·c.
//! - **AHD, tangent-xy lerp** (texture filtering of the stored d_xy; d_z = √(1 − |d_xy|²)):
//!   d_x = −s(2u − 1), so I(N) = u·√(1 − s²(2u − 1)²). d/dt at t = 0 is −c + 2s²/c, positive
//!   iff tan α > 1/√2, i.e. α > 35.26°. The maximum is at
//!   u* = (3s + √(9s² + 8c²))/(8s) (the root of 8s²u² − 6s²u − c² = 0) when u* < 1.
//! - **AHD, renormalised lerp** (d = normalise((1 − t)d_L + t d_R)): d_z = c/√(c² + s²(2u − 1)²),
//!   I(N) = u·c/√(c² + s²(2u − 1)²). d/dt at t = 0 is c(2s² − 1), positive iff α > 45°; the
//!   maximum is at u* = 1/(2s²) with value 1/(2s).
//! - **AHD, luminance-weighted direction** (the brief's "normalized and (luminance) weighted
//!   average direction"): the right texel has zero luminance, so d stays d_L and I(N) = u·c,
//!   linear like IrradZ.
//!
//! At t = ½ both AHD rules give d = z and I(N) = ½ while IrradZ gives c/2: the ratio is 1/cos α.

use std::f64::consts::FRAC_1_SQRT_2;

/// How blended AHD parameters give a direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// Stored tangent-space xy, filtered linearly; d_z = √(1 − x² − y²).
    TangentXy,
    /// The two directions lerped and renormalised.
    Renormalised,
    /// The directions weighted by their colours' luminance, summed and renormalised.
    LuminanceWeighted,
}

impl Rule {
    /// Every rule, in the order of the measures' rows.
    pub const ALL: [Rule; 3] = [Rule::TangentXy, Rule::Renormalised, Rule::LuminanceWeighted];

    /// The rule's snake-case name (`tangent_xy`, …); the measures' encoder is `ahd_<name>`.
    pub fn name(self) -> &'static str {
        match self {
            Rule::TangentXy => "tangent_xy",
            Rule::Renormalised => "renormalised",
            Rule::LuminanceWeighted => "luminance_weighted",
        }
    }
}

/// AHD's irradiance at N at blend weight t (closed form, module doc).
pub fn ahd_at_normal(alpha: f64, rule: Rule, t: f64) -> f64 {
    let (s, c) = alpha.sin_cos();
    let u = 1.0 - t;
    let x = s * (2.0 * u - 1.0);
    match rule {
        Rule::TangentXy => u * (1.0 - x * x).max(0.0).sqrt(),
        Rule::Renormalised => u * c / (c * c + x * x).sqrt(),
        Rule::LuminanceWeighted => u * c,
    }
}

/// IrradZ's irradiance at N: I_z blended linearly.
pub fn irradz_at_normal(alpha: f64, t: f64) -> f64 {
    (1.0 - t) * alpha.cos()
}

/// The tilt above which AHD's I(N) rises from the left endpoint (radians): atan(1/√2) for
/// tangent-xy, 45° for renormalised; none (π/2) for the luminance-weighted rule.
pub fn overshoot_threshold(rule: Rule) -> f64 {
    match rule {
        Rule::TangentXy => FRAC_1_SQRT_2.atan(),
        Rule::Renormalised => std::f64::consts::FRAC_PI_4,
        Rule::LuminanceWeighted => std::f64::consts::FRAC_PI_2,
    }
}

/// Where AHD's I(N) peaks along t, and the peak (closed form, module doc). t = 0 (the left
/// endpoint) when there is no overshoot.
pub fn ahd_peak(alpha: f64, rule: Rule) -> (f64, f64) {
    let (s, c) = alpha.sin_cos();
    let u = match rule {
        Rule::TangentXy if s > 0.0 => ((3.0 * s + (9.0 * s * s + 8.0 * c * c).sqrt()) / (8.0 * s)).min(1.0),
        Rule::Renormalised if 2.0 * s * s > 1.0 => 1.0 / (2.0 * s * s),
        _ => 1.0,
    };
    let t = 1.0 - u;
    (t, ahd_at_normal(alpha, rule, t))
}

/// One point of the Fig. 2 curves, AHD under one rule and IrradZ at one tilt and t (the
/// `fig2_curve` measure's rows).
#[derive(Clone, Debug)]
pub struct Fig2Point {
    /// The tilt α of the left texel's direction from N, degrees.
    pub alpha_deg: f64,
    /// How the blended AHD parameters give a direction.
    pub rule: Rule,
    /// The blend weight, 0 (left texel) to 1 (right texel).
    pub t: f64,
    /// AHD's I(N) under `rule` at t, E/π ([`ahd_at_normal`]).
    pub ahd: f64,
    /// IrradZ's I(N) at t, E/π ([`irradz_at_normal`]); the same for every rule.
    pub irradz: f64,
}

/// One tilt and rule of the Fig. 2 summary: a row of the `fig2` measure.
#[derive(Clone, Debug)]
pub struct Fig2Summary {
    /// The tilt α of the left texel's direction from N, degrees.
    pub alpha_deg: f64,
    /// How the blended AHD parameters give a direction.
    pub rule: Rule,
    /// The tilt above which `rule` overshoots, degrees ([`overshoot_threshold`]; 90: never).
    pub threshold_deg: f64,
    /// The blend weight t where AHD's I(N) peaks (0 when it does not overshoot).
    pub t_peak: f64,
    /// AHD's I(N) at `t_peak`, E/π.
    pub peak: f64,
    /// Peak minus the larger endpoint (cos α at t = 0), E/π; 0 when there is no overshoot.
    pub overshoot: f64,
    /// The ratio AHD / IrradZ at t = ½ (1/cos α for both tangent rules).
    pub ratio_half: f64,
}

/// The tilts swept (degrees).
pub const ALPHAS_DEG: [f64; 7] = [15.0, 30.0, 35.0, 45.0, 60.0, 75.0, 85.0];

/// The Fig. 2 curves (the `fig2_curve` measure): every tilt × rule at t = 0, 0.05, …, 1.
pub fn points() -> Vec<Fig2Point> {
    let mut out = Vec::new();
    for &a in &ALPHAS_DEG {
        for rule in Rule::ALL {
            for i in 0..=20 {
                let t = i as f64 / 20.0;
                let alpha = a.to_radians();
                out.push(Fig2Point {
                    alpha_deg: a,
                    rule,
                    t,
                    ahd: ahd_at_normal(alpha, rule, t),
                    irradz: irradz_at_normal(alpha, t),
                });
            }
        }
    }
    out
}

/// The peak and overshoot per tilt and rule.
pub fn summary() -> Vec<Fig2Summary> {
    let mut out = Vec::new();
    for &a in &ALPHAS_DEG {
        let alpha = a.to_radians();
        for rule in Rule::ALL {
            let (t_peak, peak) = ahd_peak(alpha, rule);
            let ends = ahd_at_normal(alpha, rule, 0.0).max(ahd_at_normal(alpha, rule, 1.0));
            out.push(Fig2Summary {
                alpha_deg: a,
                rule,
                threshold_deg: overshoot_threshold(rule).to_degrees(),
                t_peak,
                peak,
                overshoot: (peak - ends).max(0.0),
                ratio_half: ahd_at_normal(alpha, rule, 0.5) / irradz_at_normal(alpha, 0.5),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::encoders::lightmap::{Basis, Model, Storage, Texel};
    use crate::math::colour::Rgb;
    use glam::DVec3;

    /// The two texels of the figure as models on a surface with an arbitrary N, "left" being
    /// −t₁ of the texel storage's own tangent frame.
    fn texels(alpha: f64, n: DVec3) -> (Model, Model) {
        let (t1, _) = crate::encoders::lightmap::irradz::tangent_frame(n);
        let (s, c) = alpha.sin_cos();
        let left = Model { basis: Basis::Ahd, normal: n, c_a: Rgb::ZERO, c_d: Rgb::ONE, d: n * c - t1 * s };
        let right = Model { basis: Basis::Ahd, normal: n, c_a: Rgb::ZERO, c_d: Rgb::ZERO, d: n * c + t1 * s };
        (left, right)
    }

    /// The closed forms are what the stored texels do: blending `raw` texels (stored
    /// tangent xy) is the tangent-xy rule, and blending `irradz_rgb` texels keeps I(N) linear.
    #[test]
    fn closed_forms_match_blended_texels() {
        let n = DVec3::new(0.2, 0.9, -0.3).normalize();
        for &a in &ALPHAS_DEG {
            let alpha = a.to_radians();
            let (l, r) = texels(alpha, n);
            for i in 0..=20 {
                let t = i as f64 / 20.0;
                let raw = Texel::lerp(&Texel::encode(&l, Storage::Raw), &Texel::encode(&r, Storage::Raw), t).decode();
                let want = ahd_at_normal(alpha, Rule::TangentXy, t);
                assert!((raw.i_z() - Rgb::splat(want)).abs().max_element() < 1e-12, "{a} {t}");
                let iz = Texel::lerp(&Texel::encode(&l, Storage::IrradzRgb), &Texel::encode(&r, Storage::IrradzRgb), t);
                let want = irradz_at_normal(alpha, t);
                assert!((iz.decode().i_z() - Rgb::splat(want)).abs().max_element() < 1e-12, "{a} {t}");
                // Renormalised: the model with the lerped colours and the renormalised direction.
                let d = (l.d * (1.0 - t) + r.d * t).normalize();
                let m = Model { c_d: l.c_d * (1.0 - t) + r.c_d * t, d, ..l };
                let want = ahd_at_normal(alpha, Rule::Renormalised, t);
                assert!((m.i_z() - Rgb::splat(want)).abs().max_element() < 1e-12);
            }
        }
    }

    /// The peaks are maxima (no sampled t beats them, the derivative vanishes there), the
    /// thresholds are where the slope at t = 0 changes sign, and t = ½ gives 1/cos α.
    #[test]
    fn peaks_thresholds_and_the_midpoint() {
        for rule in [Rule::TangentXy, Rule::Renormalised] {
            let th = overshoot_threshold(rule);
            for alpha in [th - 1e-3, th + 1e-3] {
                let slope = (ahd_at_normal(alpha, rule, 1e-6) - ahd_at_normal(alpha, rule, 0.0)) / 1e-6;
                assert_eq!(slope > 0.0, alpha > th, "{rule:?} {alpha}");
            }
            for deg in 1..90 {
                let alpha = (deg as f64).to_radians();
                let (tp, peak) = ahd_peak(alpha, rule);
                // A 1e-4 sampling of t (it misses a sharp peak near 90° by ~½ f″ h², < 1e-5).
                let best = (0..=10000).map(|i| ahd_at_normal(alpha, rule, i as f64 / 1e4)).fold(0.0, f64::max);
                assert!(peak >= best - 1e-12 && peak - best < 1e-5, "{rule:?} {deg}: {peak} vs {best}");
                if tp > 0.0 {
                    let h = 1e-5;
                    let d = ahd_at_normal(alpha, rule, tp + h) - ahd_at_normal(alpha, rule, tp - h);
                    assert!(d.abs() < 1e-8, "{rule:?} {deg}: slope {d}");
                }
                assert_eq!(tp > 0.0, alpha > th);
                let half = ahd_at_normal(alpha, rule, 0.5) / irradz_at_normal(alpha, 0.5);
                assert!((half - 1.0 / alpha.cos()).abs() < 1e-12 * half);
            }
        }
        // The renormalised peak is 1/(2 sin α).
        let a = 60f64.to_radians();
        assert!((ahd_peak(a, Rule::Renormalised).1 - 0.5 / a.sin()).abs() < 1e-15);
        // The thresholds: tan α = 1/√2 (35.26°) and 45°.
        assert!((overshoot_threshold(Rule::TangentXy).tan() - FRAC_1_SQRT_2).abs() < 1e-15);
        assert!((overshoot_threshold(Rule::TangentXy).to_degrees() - 35.264_389_682_754_654).abs() < 1e-12);
        // IrradZ and the luminance-weighted rule are linear: never above the left endpoint.
        for &a in &ALPHAS_DEG {
            let alpha = a.to_radians();
            for i in 0..=20 {
                let t = i as f64 / 20.0;
                assert!(irradz_at_normal(alpha, t) <= alpha.cos() + 1e-15);
                assert_eq!(ahd_at_normal(alpha, Rule::LuminanceWeighted, t), irradz_at_normal(alpha, t));
            }
        }
    }
}
