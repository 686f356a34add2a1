//! Fitting the ZH3 hallucination curve to your own probes (ZH3 talk, "hallucinating ZH3
//! coefficients": the curve 0.08r + 0.6r² "is for our lighting data ... you can find a better fit
//! for your own data sets"; FORMULAS §5). `probelab fit-hallucination` drives it.
//!
//! **Samples.** One per probe and channel, from radiance SH: the zonal axis a (Rec.709-weighted
//! L1 by default, as `zh3_hallucinate`), the ratio r = |L1·a|/L₀₀, and the best zonal
//! coefficient about a, f* = √(4π/5)·Y₂(a)·L₂ (the stored ZH3 value, FORMULAS §5).
//!
//! **Error measure.** For a hallucinated f the squared error of the irradiance against SH3,
//! integrated over the sphere, is (1/16)·(|L₂|² − f*² + (f − f*)²) (band scale ¼; orthonormal
//! basis). The RMSE printed is √(Σ err / (4π·samples)): a sphere RMSE of E/π against SH3, pooled
//! over probes and channels. It leaves out bands ≥ 3, which no L1/ZH3 encoding represents.
//!
//! **Fit.** Minimising the pooled error is weighted least squares of y = f*/L₀₀ on
//! (r, r²[, r³]) with weights L₀₀², without an intercept (a constant environment, r = 0, has no
//! zonal term).
//!
//! **Probe files**: the one probe format of `probelab probes` (`--input`, `--save`):
//! coefficient-major L2 radiance SH, CSV or raw f32 (`pipeline::probeset::format`), so a set
//! saved by `probes --save` is fitted as it is.

use crate::encoders::encoder::named_weights;
use crate::encoders::zh3::solve::{band2, l2_band};
use crate::encoders::zh3::AxisRule;
use crate::math::sh::Sh9;
use anyhow::{bail, Result};
use nalgebra::{DMatrix, DVector};
use std::f64::consts::PI;

/// One channel of one probe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// L₀₀ of the channel (radiance).
    pub l00: f64,
    /// r = |L1·a|/L₀₀.
    pub ratio: f64,
    /// f*: the least-squares zonal coefficient about a (radiance, coefficient of the rotated Y₂₀).
    pub f_best: f64,
    /// |L₂|² of the channel (radiance).
    pub l2_sq: f64,
}

/// The samples of a set of radiance SH probes; channels with L₀₀ ≤ 0 or no axis are skipped
/// (their count is returned).
pub fn samples(probes: &[Sh9], rule: AxisRule) -> (Vec<Sample>, usize) {
    let mut out = Vec::new();
    let mut skipped = 0;
    for sh in probes {
        let l1: [glam::DVec3; 3] = std::array::from_fn(|c| sh.l1_vector(c));
        let axes = rule.axes(&l1);
        for c in 0..3 {
            let l00 = sh[0][c];
            let (Some(a), true) = (axes[c], l00 > 0.0) else {
                skipped += 1;
                continue;
            };
            let l2 = l2_band(sh, c);
            let y = band2(a);
            let f_best = (4.0 * PI / 5.0).sqrt() * (0..5).map(|m| y[m] * l2[m]).sum::<f64>();
            out.push(Sample { l00, ratio: l1[c].dot(a).abs() / l00, f_best, l2_sq: l2.iter().map(|x| x * x).sum() });
        }
    }
    (out, skipped)
}

/// A curve f/L₀₀ = c₁r + c₂r² + c₃r³.
pub type Coeffs = [f64; 3];

/// The paper's curve.
pub const PAPER: Coeffs = [0.08, 0.6, 0.0];

fn g(c: &Coeffs, r: f64) -> f64 {
    r * (c[0] + r * (c[1] + r * c[2]))
}

/// Pooled sphere RMSE of E/π against SH3 when each sample's f is `f(sample)`.
pub fn rmse(samples: &[Sample], f: impl Fn(&Sample) -> f64) -> f64 {
    if samples.is_empty() {
        return 0.0;
    }
    let se: f64 = samples
        .iter()
        .map(|s| {
            let fv = f(s);
            ((s.l2_sq - s.f_best * s.f_best).max(0.0) + (fv - s.f_best).powi(2)) / 16.0
        })
        .sum();
    (se / (4.0 * PI * samples.len() as f64)).sqrt()
}

/// Least-squares curve of degree 2 or 3 through the origin (weights L₀₀²). Returns None if the
/// normal equations are singular (fewer distinct ratios than coefficients).
pub fn fit(samples: &[Sample], degree: usize) -> Option<Coeffs> {
    assert!(degree == 2 || degree == 3);
    // Rows L₀₀·(r, r², r³) against L₀₀·y = f*.
    let a = DMatrix::from_fn(samples.len(), degree, |i, j| samples[i].l00 * samples[i].ratio.powi(j as i32 + 1));
    let b = DVector::from_iterator(samples.len(), samples.iter().map(|s| s.f_best));
    let ata = a.transpose() * &a;
    let atb = a.transpose() * b;
    let x = ata.cholesky()?.solve(&atb);
    let mut c = [0.0; 3];
    for (o, v) in c.iter_mut().zip(x.iter()) {
        *o = *v;
    }
    c.iter().all(|v| v.is_finite()).then_some(c)
}

/// One line of the report.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveRow {
    /// What the row scores (e.g. "fitted quadratic", "sh1 (no zonal term)").
    pub name: String,
    /// The curve's coefficients (c₁, c₂, c₃); None for rows that are not a curve of r.
    pub coeffs: Option<Coeffs>,
    /// Pooled sphere RMSE of E/π against SH3 over all samples (module doc).
    pub rmse: f64,
}

/// The full report of a fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Number of probes read.
    pub probes: usize,
    /// Number of channel samples used.
    pub samples: usize,
    /// Number of channels skipped (L₀₀ ≤ 0 or no axis).
    pub skipped: usize,
    /// Label of the axis rule (`--axis`).
    pub axis: String,
    /// One row per scored curve, in report order.
    pub rows: Vec<CurveRow>,
}

/// Fits the quadratic (and the cubic if asked) and scores them next to SH L1 (no zonal term),
/// the paper's curve and the stored coefficient (the bound any curve of r can reach).
pub fn report(probes: &[Sh9], rule: AxisRule, axis_label: &str, cubic: bool) -> Result<Report> {
    let (s, skipped) = samples(probes, rule);
    if s.len() < 3 {
        bail!(
            "fit-hallucination: {} usable channel sample(s); need at least 3 (probes with light and an L1 direction)",
            s.len()
        );
    }
    let curve_row = |name: &str, c: Coeffs| CurveRow {
        name: name.into(),
        coeffs: Some(c),
        rmse: rmse(&s, |x| x.l00 * g(&c, x.ratio)),
    };
    let mut rows = vec![
        CurveRow { name: "sh1 (no zonal term)".into(), coeffs: None, rmse: rmse(&s, |_| 0.0) },
        curve_row("paper 0.08r + 0.6r^2", PAPER),
    ];
    let Some(q) = fit(&s, 2) else { bail!("fit-hallucination: the quadratic fit is singular (all ratios equal?)") };
    rows.push(curve_row("fitted quadratic", q));
    if cubic {
        let Some(c3) = fit(&s, 3) else { bail!("fit-hallucination: the cubic fit is singular") };
        rows.push(curve_row("fitted cubic", c3));
    }
    rows.push(CurveRow { name: "stored ZH3 (f = f*, bound)".into(), coeffs: None, rmse: rmse(&s, |x| x.f_best) });
    Ok(Report { probes: probes.len(), samples: s.len(), skipped, axis: axis_label.into(), rows })
}

/// Parses the `--axis` option: `rec709`, `equal`, or `channel`.
pub fn parse_axis(s: &str) -> Result<AxisRule> {
    match s {
        "channel" => Ok(AxisRule::Channel),
        _ => Ok(AxisRule::Shared(named_weights(s).map_err(|_| {
            anyhow::anyhow!("--axis '{}': expected rec709, equal or channel", crate::math::echo::value(s))
        })?)),
    }
}

/// The report as text.
pub fn format_report(r: &Report) -> String {
    let mut s = format!(
        "hallucination curve fit: {} probe(s), {} channel sample(s) ({} skipped: no light or no L1), zonal axis {}\n\
         error: sphere RMSE of E/pi against SH3 (bands 0-2), pooled over probes and channels\n\n",
        r.probes, r.samples, r.skipped, r.axis
    );
    let sh1 = r.rows[0].rmse;
    let paper = r.rows[1].rmse;
    let pct = |x: f64, base: f64| if base > 0.0 { format!("{:+.1}%", 100.0 * (x / base - 1.0)) } else { "-".into() };
    s += &format!(
        "{:28} {:>10} {:>10} {:>10} {:>12} {:>9} {:>9}\n",
        "curve", "c1", "c2", "c3", "rmse", "vs sh1", "vs paper"
    );
    for row in &r.rows {
        let (c1, c2, c3) = match row.coeffs {
            Some(c) => (format!("{:.5}", c[0]), format!("{:.5}", c[1]), format!("{:.5}", c[2])),
            None => ("-".into(), "-".into(), "-".into()),
        };
        s += &format!(
            "{:28} {:>10} {:>10} {:>10} {:>12.6e} {:>9} {:>9}\n",
            row.name,
            c1,
            c2,
            c3,
            row.rmse,
            pct(row.rmse, sh1),
            pct(row.rmse, paper)
        );
    }
    if let Some(q) = r.rows.iter().find(|x| x.name == "fitted quadratic").and_then(|x| x.coeffs) {
        s += &format!(
            "\nencoder settings: {{ kind = \"zh3_hallucinate\", curve_c1 = {:.5}, curve_c2 = {:.5} }}\n",
            q[0], q[1]
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::colour::Rgb;
    use crate::math::sh::{constant, delta_light};
    use crate::reference::lighting::Light;
    use glam::DVec3;

    /// Samples generated exactly on a known curve are fitted back to it, and the fitted curve
    /// then has the error of the stored coefficient.
    #[test]
    fn recovers_a_known_curve() {
        // Caps of varying size over a constant: r and f* follow the sphere-light relation
        // f*/L₀₀ = (√5/2)c(1+c) only without the constant, so build y directly instead.
        let want = [0.2, 0.45, 0.0];
        let s: Vec<Sample> = (1..40)
            .map(|i| {
                let r = i as f64 * 0.04;
                let l00 = 1.0 + (i % 7) as f64;
                Sample { l00, ratio: r, f_best: l00 * g(&want, r), l2_sq: (l00 * g(&want, r)).powi(2) + 0.1 }
            })
            .collect();
        let q = fit(&s, 2).unwrap();
        assert!((q[0] - want[0]).abs() < 1e-12 && (q[1] - want[1]).abs() < 1e-12, "{q:?}");
        let e_fit = rmse(&s, |x| x.l00 * g(&q, x.ratio));
        let e_best = rmse(&s, |x| x.f_best);
        assert!((e_fit - e_best).abs() < 1e-12);
        assert!(rmse(&s, |_| 0.0) > e_fit);
    }

    /// The error measure against an independent computation: for a cap the hallucinated SH3
    /// (from the zonal coefficient f about the cap axis) differs from the true SH3 only in band
    /// 2, so the squared error is (1/16)·|L₂ − k·Y₂(a)|² with k = √(4π/5)·f.
    #[test]
    fn error_measure_matches_coefficient_space() {
        let axis = DVec3::new(0.2, 0.9, 0.1).normalize();
        let sh = Light::Cap { axis, half_angle: 0.5, radiance: Rgb::ONE }.sh() + constant(Rgb::splat(0.1));
        let (s, _) = samples(&[sh], AxisRule::Channel);
        let f = 0.3;
        let k = (4.0 * PI / 5.0).sqrt() * f;
        let y = band2(axis);
        let direct: f64 = (0..5).map(|m| (sh[4 + m].x - k * y[m]).powi(2)).sum::<f64>() / 16.0;
        let got = rmse(&s[..1], |_| f);
        assert!((got - (direct / (4.0 * PI)).sqrt()).abs() < 1e-14, "{got}");
        // A delta light has r = √3.
        let (d, _) = samples(&[delta_light(axis, Rgb::ONE)], AxisRule::Channel);
        assert!((d[0].ratio - 3f64.sqrt()).abs() < 1e-14);
    }
}
