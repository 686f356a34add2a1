//! H7's tables, Fig. 2 of the 2018 brief in closed form ([`crate::claims::lightmap::fig2`]):
//! `fig2` (per tilt α and rule, the peak of I(N) along t and its overshoot beyond both
//! endpoints) and `fig2_curve` (I(N) along t), IrradZ beside the AHD rules.

use crate::claims::lightmap::fig2;
use crate::claims::measure::Measure;

/// The tilts' case label in `fig2` and `fig2_curve`: `alpha_45` for α = 45°.
fn alpha_case(alpha_deg: f64) -> String {
    format!("alpha_{alpha_deg}")
}

/// The `encoder` of a Fig. 2 rule: the blended AHD under that direction rule.
fn rule_encoder(rule: fig2::Rule) -> String {
    format!("ahd_{}", rule.name())
}

/// H7, Fig. 2 of the 2018 brief (§2) in closed form: `fig2` (per tilt and reconstruction, the
/// peak of I(N) along t and its overshoot beyond both endpoints) and `fig2_curve`.
pub fn fig2_measures() -> (Measure, Measure) {
    (fig2_table(), fig2_curve())
}

/// `fig2`: per tilt and reconstruction, the peak of I(N) along t and its overshoot beyond both
/// endpoints.
fn fig2_table() -> Measure {
    let mut m = Measure::new(
        "fig2",
        "claim H7, Fig. 2 of the 2018 brief in closed form: two texels (C_d = 1 with d tilted by alpha from N, and 0), \
         blended along t; I(N) is E/pi at the normal (closed form, src/claims/lightmap/fig2.rs). encoder = the blended \
         AHD under a direction rule, or irradz (I_z blended); overshoot = max over t of I(N) minus the larger endpoint \
         (E/pi; 0 when I(N) never exceeds both endpoints); overshoot_rel = overshoot / cos(alpha) (the left endpoint); \
         threshold_deg = the tilt above which the rule overshoots (90: never); at_half_over_irradz = I(N) at t = 1/2 over \
         IrradZ's",
        &[
            "case",
            "encoder",
            "alpha_deg",
            "threshold_deg",
            "t_peak",
            "peak",
            "endpoint",
            "overshoot",
            "overshoot_rel",
            "at_half_over_irradz",
            "units",
        ],
    );
    for s in fig2::summary() {
        let c = s.alpha_deg.to_radians().cos();
        m.row(vec![
            alpha_case(s.alpha_deg).into(),
            rule_encoder(s.rule).into(),
            s.alpha_deg.into(),
            s.threshold_deg.into(),
            s.t_peak.into(),
            s.peak.into(),
            c.into(),
            s.overshoot.into(),
            (s.overshoot / c).into(),
            s.ratio_half.into(),
            "E/pi (closed form)".into(),
        ]);
    }
    // IrradZ blends I_z = I(N) linearly: its peak is the left endpoint, cos α.
    for &a in &fig2::ALPHAS_DEG {
        let alpha = a.to_radians();
        let ends = fig2::irradz_at_normal(alpha, 0.0).max(fig2::irradz_at_normal(alpha, 1.0));
        let peak = (0..=100).map(|i| fig2::irradz_at_normal(alpha, i as f64 / 100.0)).fold(f64::MIN, f64::max);
        m.row(vec![
            alpha_case(a).into(),
            "irradz".into(),
            a.into(),
            90.0.into(),
            0.0.into(),
            peak.into(),
            alpha.cos().into(),
            (peak - ends).into(),
            ((peak - ends) / alpha.cos()).into(),
            1.0.into(),
            "E/pi (closed form)".into(),
        ]);
    }
    m
}

/// `fig2_curve`: I(N) along the blend weight t, per tilt and reconstruction.
fn fig2_curve() -> Measure {
    let mut curve = Measure::new(
        "fig2_curve",
        "claim H7, Fig. 2 of the 2018 brief in closed form: E/pi at the normal along the blend weight t, per tilt (case) \
         and reconstruction (encoder: the blended AHD under a direction rule, or irradz)",
        &["case", "encoder", "alpha_deg", "t", "irradiance_at_normal", "units"],
    );
    let mut irradz_rows = Vec::new();
    for p in fig2::points() {
        curve.row(vec![
            alpha_case(p.alpha_deg).into(),
            rule_encoder(p.rule).into(),
            p.alpha_deg.into(),
            p.t.into(),
            p.ahd.into(),
            "E/pi (closed form)".into(),
        ]);
        if p.rule == fig2::Rule::ALL[0] {
            irradz_rows.push((p.alpha_deg, p.t, p.irradz));
        }
    }
    for (a, t, v) in irradz_rows {
        curve.row(vec![
            alpha_case(a).into(),
            "irradz".into(),
            a.into(),
            t.into(),
            v.into(),
            "E/pi (closed form)".into(),
        ]);
    }
    curve
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::claims::measure::Cell;

    fn num(m: &Measure, row: &[Cell], col: &str) -> f64 {
        match &row[m.columns.iter().position(|c| c == col).unwrap()] {
            Cell::Num(x) => *x,
            c => panic!("{col}: {c:?}"),
        }
    }

    fn row<'a>(m: &'a Measure, case: &str, encoder: &str) -> &'a [Cell] {
        m.rows.iter().find(|r| r[0] == Cell::from(case) && r[1] == Cell::from(encoder)).unwrap()
    }

    /// Fig. 2's measured overshoots against the closed forms derived independently: the
    /// tangent-xy rule overshoots for tan α > 1/√2 (35.26°), the renormalised rule for
    /// α > 45°, peaking at 1/(2 sin α); IrradZ and the luminance-weighted rule never; at t = ½
    /// AHD/IrradZ = 1/cos α.
    #[test]
    fn fig2_overshoots_against_closed_forms() {
        let (m, curve) = fig2_measures();
        m.to_csv().unwrap();
        curve.to_csv().unwrap();
        assert_eq!(m.rows.len(), 4 * fig2::ALPHAS_DEG.len());
        assert_eq!(curve.rows.len(), 4 * 21 * fig2::ALPHAS_DEG.len());
        let th = num(&m, row(&m, "alpha_60", "ahd_tangent_xy"), "threshold_deg");
        assert!((th - (1.0 / 2f64.sqrt()).atan().to_degrees()).abs() < 1e-12 && (th - 35.26).abs() < 0.01);
        assert_eq!(num(&m, row(&m, "alpha_60", "ahd_renormalised"), "threshold_deg"), 45.0);
        for &a in &fig2::ALPHAS_DEG {
            let case = format!("alpha_{a}");
            let over = |e: &str| num(&m, row(&m, &case, e), "overshoot");
            assert_eq!(over("irradz"), 0.0, "{a}");
            assert_eq!(over("ahd_luminance_weighted"), 0.0, "{a}");
            assert_eq!(over("ahd_tangent_xy") > 0.0, a > 35.27, "{a}");
            assert_eq!(over("ahd_renormalised") > 0.0, a > 45.0, "{a}");
            let r = a.to_radians();
            if a > 45.0 {
                assert!((over("ahd_renormalised") - (0.5 / r.sin() - r.cos())).abs() < 1e-12, "{a}");
            }
            let half = num(&m, row(&m, &case, "ahd_tangent_xy"), "at_half_over_irradz");
            assert!((half - 1.0 / r.cos()).abs() < 1e-12 * half);
        }
    }
}
