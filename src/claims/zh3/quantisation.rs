//! Claim Z10: ratio-based quantisation stores L1 in 13 bytes, ZH3 in 16 and L2 in 28
//! (`encoders::quantise`), and the error quantisation adds, relative to each encoding's own
//! error against the reference.

use super::cases::{enc, fit, values, Case};
use super::{yes, Finding};
use crate::encoders::encoder::Encoder;
use crate::pipeline::runner::score_values;
use crate::reference::domain::OutputGrid;
use crate::reference::metrics::{score, Metric};
use anyhow::Result;
use std::fmt::Write as _;

/// Z10: ratio quantisation to 13 / 16 / 28 bytes.
pub(super) fn z10(grid: &OutputGrid, cases: &[Case]) -> Result<(Finding, String)> {
    let q = toml::Value::String("ratio8".into());
    type Pair = (&'static str, Box<dyn Encoder>, Box<dyn Encoder>, usize);
    let pairs: Vec<Pair> = vec![
        ("sh1", enc("sh1", &[])?, enc("sh1_q13", &[])?, 13),
        (
            "zh3_solved_shared",
            enc("zh3_solved_shared", &[])?,
            enc("zh3_solved_shared", &[("quantise", q.clone())])?,
            16,
        ),
        ("zh3_hallucinate", enc("zh3_hallucinate", &[])?, enc("zh3_hallucinate", &[("quantise", q)])?, 13),
        ("sh2", enc("sh2", &[])?, enc("sh2_q28", &[])?, 28),
    ];
    let mut table = String::from(
        "| map | encoder | bytes | RMSE | RMSE quantised | quantisation error (RMS of the difference) | / RMSE |\n|---|---|---|---|---|---|---|\n",
    );
    let mut worst = vec![0.0f64; pairs.len()];
    for case in cases {
        for (i, (name, e, eq, bytes)) in pairs.iter().enumerate() {
            let v = values(fit(e.as_ref(), &case.sh).as_ref(), grid);
            let vq = values(fit(eq.as_ref(), &case.sh).as_ref(), grid);
            let r = score_values(e.as_ref(), &v, grid, &case.reference, Metric::Exact).rmse;
            let rq = score_values(eq.as_ref(), &vq, grid, &case.reference, Metric::Exact).rmse;
            // What quantisation adds: the RMS of quantised − unquantised, the unquantised
            // values standing in for the reference.
            let dq = score(&v, &vq, &grid.weights, false).rmse;
            worst[i] = worst[i].max(dq / r);
            let _ =
                writeln!(table, "| {} | {name} | {bytes} | {r:.5} | {rq:.5} | {dq:.2e} | {:.3} |", case.name, dq / r);
        }
    }
    // The claim is about sizes, which the layout reaches by construction; the added error is
    // reported next to it.
    let holds = true;
    Ok((
        Finding {
            id: "Z10",
            claim: "Ratio-based quantisation stores L1 in 13 bytes, ZH3 in 16 and L2 in 28",
            paper_figure: "13 / 16 / 28 bytes".into(),
            our_figure: format!(
                "13 / 16 / 28 bytes (DC RGB9E5 + one signed byte per ratio); quantisation error / encoding RMSE, worst of 5 probes: sh1 {:.3}, zh3 solved {:.3}, zh3 hallucinated {:.3}, sh2 {:.3}",
                worst[0], worst[1], worst[2], worst[3]
            ),
            holds: yes(holds),
            notes: "layout derived (the talk gives sizes only; see src/encoders/quantise.rs); ratio bounds of non-negative radiance \
                    (√3 for L1, √15/2 and √5 for L2, √5 for f/L00); the sizes hold by construction; the figure gives the error \
                    quantisation adds, relative to each encoding's own error against the reference"
                .into(),
        },
        format!("Exact metric (sphere, solid-angle, 256x128). Quantisation error = RMS over the sphere of (quantised − unquantised) E/π.\n\n{table}"),
    ))
}
