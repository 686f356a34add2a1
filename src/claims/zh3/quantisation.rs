//! Claim Z10 (ZH3 talk, "storage"): ratio-based quantisation stores L1 in 13 bytes, ZH3 in 16
//! and L2 in 28. Measured as the table `quantised_sizes` from the real encoded form: each
//! encoding's unquantised fit is serialised (`quantise::encode_sh`, `Zh3Encoder::encode`), the
//! bytes are counted and decoded, and the decoded coefficients are compared with what the
//! quantised encoder evaluates; beside them, the RMSE with and without quantisation against
//! the exact reference, and the error quantisation adds.

use super::cases::{fit, values, Case};
use crate::claims::measure::Measure;
use crate::encoders::encoder::{Encoder, FitInput, Fitted};
use crate::encoders::quantise::{self, BYTES_L1, BYTES_L2, BYTES_ZH3};
use crate::encoders::zh3;
use crate::math::sh::Sh9;
use crate::pipeline::runner::score_values;
use crate::reference::domain::OutputGrid;
use crate::reference::metrics::{score, Metric};
use anyhow::{Context, Result};

/// The largest |a − b| over the coefficients and channels of two irradiance SH3.
fn max_abs(a: &Sh9, b: &Sh9) -> f64 {
    (0..9).map(|i| (a[i] - b[i]).abs().max_element()).fold(0.0, f64::max)
}

/// One encoding measured on one case: the unquantised and quantised fits, the stored bytes
/// of the unquantised fit, and those bytes decoded (irradiance SH3, E/π).
struct Encoded {
    plain: Box<dyn Fitted>,
    quantised: Box<dyn Fitted>,
    bytes: Vec<u8>,
    decoded: Sh9,
}

/// SH L1 (`sh1` → `sh1_q13`) or L2 (`sh2` → `sh2_q28`).
fn sh(band: usize, case: &Case) -> Result<Encoded> {
    let (plain, quantised) = if band == 1 { ("sh1", "sh1_q13") } else { ("sh2", "sh2_q28") };
    let e = crate::encoders::build(plain, None, toml::Table::new())?.encoder;
    let q = crate::encoders::build(quantised, None, toml::Table::new())?.encoder;
    let bytes = quantise::encode_sh(&case.sh, band);
    let decoded = quantise::decode_sh(&bytes).with_context(|| format!("Z10: {quantised} on {}", case.name))?;
    Ok(Encoded {
        plain: fit(e.as_ref(), &case.sh),
        quantised: fit(q.as_ref(), &case.sh),
        bytes,
        decoded: decoded.convolve_cosine(),
    })
}

/// A ZH3 encoder kind, unquantised and with `quantise = "ratio8"`.
fn zh3_kind(kind: &str, case: &Case) -> Result<Encoded> {
    let e = zh3::configured(kind, toml::Table::new())?;
    let mut t = toml::Table::new();
    t.insert("quantise".into(), toml::Value::String("ratio8".into()));
    let q = zh3::configured(kind, t)?;
    let plain = e.fit_zh3(&case.sh);
    let bytes = q.encode(&plain.zh3);
    let decoded = q.decode(&bytes).with_context(|| format!("Z10: {kind} on {}", case.name))?.to_sh();
    Ok(Encoded { plain: Box::new(plain), quantised: q.fit(&FitInput::sphere(&case.sh)), bytes, decoded })
}

/// Z10 as the table `quantised_sizes`: per map and encoding, the serialised length, the round
/// trip, and the RMSE with and without quantisation.
pub(super) fn quantised_sizes(grid: &OutputGrid, cases: &[Case]) -> Result<Measure> {
    let mut m = Measure::new(
        "quantised_sizes",
        "claim Z10, ratio quantisation (FORMULAS §11; src/encoders/quantise.rs): bytes = length of the serialised \
         unquantised fit; paper_bytes = the talk's size; roundtrip_max_abs = max |decoded bytes - the coefficients the \
         quantised encoder evaluates| over the irradiance SH3 (E/pi, 0 when the encoder evaluates its bytes); rmse, \
         rmse_quantised = E/pi RMSE against the exact cell-integrated reference (2 GL nodes per row piece), sphere, \
         solid-angle weighted, 256x128 lat-long normals; added_rmse = rmse_quantised - rmse; quantisation_rmse = RMS of \
         (quantised - unquantised) E/pi; quantisation_over_rmse = quantisation_rmse / rmse",
        &[
            "map",
            "encoder",
            "quantised_encoder",
            "bytes",
            "paper_bytes",
            "bytes_minus_paper",
            "roundtrip_max_abs",
            "rmse",
            "rmse_quantised",
            "added_rmse",
            "quantisation_rmse",
            "quantisation_over_rmse",
            "metric",
            "domain",
            "weighting",
            "resolution",
            "reference",
            "units",
        ],
    );
    type Measured = fn(&Case) -> Result<Encoded>;
    let encodings: [(&str, &str, usize, Measured); 4] = [
        ("sh1", "sh1_q13", BYTES_L1, |c| sh(1, c)),
        ("zh3_hallucinate", "zh3_hallucinate(quantise=ratio8)", BYTES_L1, |c| zh3_kind("zh3_hallucinate", c)),
        ("zh3_solved_shared", "zh3_solved_shared(quantise=ratio8)", BYTES_ZH3, |c| zh3_kind("zh3_solved_shared", c)),
        ("sh2", "sh2_q28", BYTES_L2, |c| sh(2, c)),
    ];
    // Scoring needs an encoder only for the probulator clamp; the exact metric never clamps.
    let scorer = crate::encoders::build("sh2", None, toml::Table::new())?.encoder;
    for case in cases {
        for (name, quantised, paper, measure) in encodings {
            let x = measure(case)?;
            let used = x.quantised.sh3().context("Z10: a quantised encoder evaluates an SH3")?;
            let (v, vq) = (values(x.plain.as_ref(), grid), values(x.quantised.as_ref(), grid));
            let r = score_values(scorer.as_ref(), &v, grid, &case.reference, Metric::Exact).rmse;
            let rq = score_values(scorer.as_ref(), &vq, grid, &case.reference, Metric::Exact).rmse;
            // What quantisation adds: the RMS of quantised − unquantised.
            let dq = score(&v, &vq, &grid.weights, false).rmse;
            m.row(vec![
                case.name.as_str().into(),
                name.into(),
                quantised.into(),
                x.bytes.len().into(),
                paper.into(),
                (x.bytes.len() as f64 - paper as f64).into(),
                max_abs(&x.decoded, &used).into(),
                r.into(),
                rq.into(),
                (rq - r).into(),
                dq.into(),
                (dq / r).into(),
                "exact".into(),
                "sphere".into(),
                "solid_angle".into(),
                "256x128".into(),
                "exact cell-integrated (2 GL nodes per row piece)".into(),
                "E/pi".into(),
            ]);
        }
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::claims::measure::Cell;
    use crate::math::colour::Rgb;
    use crate::reference::lighting::{Light, Lighting};
    use glam::DVec3;

    /// On a constructed scene (a cap over a sky, closed-form SH and irradiance): the byte
    /// counts are the talk's 13 / 13 / 16 / 28, the bytes decode to exactly what each quantised
    /// encoder evaluates, and quantisation adds a small error.
    #[test]
    fn sizes_and_round_trips_on_a_scene() {
        let grid = crate::reference::domain::Domain::Sphere.output_grid((64, 32));
        let l = Lighting(vec![
            Light::Cap {
                axis: DVec3::new(0.3, 0.9, 0.2).normalize(),
                half_angle: 0.3,
                radiance: Rgb::new(8.0, 6.0, 4.0),
            },
            Light::Ambient(Rgb::new(0.2, 0.3, 0.4)),
        ]);
        let case = Case {
            name: "scene".into(),
            sh: l.sh(),
            reference: grid.normals.iter().map(|&n| l.irradiance(n)).collect(),
        };
        let m = quantised_sizes(&grid, &[case]).unwrap();
        m.to_csv().unwrap();
        let col = |name: &str| m.columns.iter().position(|c| c == name).unwrap();
        let num = |r: &Vec<Cell>, name: &str| match &r[col(name)] {
            Cell::Num(x) => *x,
            c => panic!("{c:?}"),
        };
        // SH rows: each stored scalar is off by at most half a step — DC by max(DC)/512
        // (RGB9E5), a ratio byte by bound·DC/254 — so the E/π difference, Σ Âᵢ·eᵢ·Yᵢ with
        // Â = 1, 2/3, ¼, has a sphere RMS of at most √(Σ_c Σᵢ (Âᵢ eᵢ,c)² / 4π / 3) (Yᵢ
        // orthonormal); 2% margin for the grid's quadrature and the decoded DC.
        let sh_bound = |band: usize| {
            let dc = l.sh()[0];
            let mut sum = 0.0;
            for c in 0..3 {
                sum += (dc.max_element() / 512.0).powi(2);
                for i in 1..if band == 2 { 9 } else { 4 } {
                    let (a, b) =
                        if i < 4 { (2.0 / 3.0, quantise::bound_l1()) } else { (0.25, quantise::bounds_l2()[i - 4]) };
                    sum += (a * b * dc[c] / 254.0).powi(2);
                }
            }
            (sum / (4.0 * std::f64::consts::PI) / 3.0).sqrt() * 1.02
        };
        assert!(num(&m.rows[0], "quantisation_rmse") <= sh_bound(1), "{}", sh_bound(1));
        assert!(num(&m.rows[3], "quantisation_rmse") <= sh_bound(2), "{}", sh_bound(2));
        let bytes: Vec<f64> = m.rows.iter().map(|r| num(r, "bytes")).collect();
        assert_eq!(bytes, [13.0, 13.0, 16.0, 28.0]);
        for r in &m.rows {
            assert_eq!(num(r, "roundtrip_max_abs"), 0.0, "{r:?}");
            assert_eq!(num(r, "bytes_minus_paper"), 0.0);
            let (q, rmse) = (num(r, "quantisation_rmse"), num(r, "rmse"));
            // Quantisation moves the values, and by the triangle inequality no more than the
            // two errors against the reference together.
            assert!(q > 0.0 && q <= rmse + num(r, "rmse_quantised"), "{r:?}");
            assert!((num(r, "added_rmse") - (num(r, "rmse_quantised") - rmse)).abs() == 0.0);
        }
    }
}
