//! Claims Z6–Z8, the error on the five paper probes under both metrics: hallucination models
//! against SH L1 (Z6), stored against hallucinated ZH3 (Z7), and ZH3 between L1 and SH3 per
//! map (Z8).

use super::cases::{enc, exact, probulator, Case};
use super::{mean, pct, reduction, yes, Finding};
use crate::encoders::encoder::Encoder;
use crate::reference::domain::OutputGrid;
use crate::reference::metrics::Scores;
use anyhow::Result;
use std::fmt::Write as _;

/// Per encoder, per map: relative RMSE reductions (exact, probulator), and the table.
type Reductions = (Vec<Vec<f64>>, Vec<Vec<f64>>, String);

/// Relative RMSE reductions of `ids` against `base` per map, exact and probulator metrics.
fn reductions(grid: &OutputGrid, cases: &[Case], base: &str, ids: &[&str]) -> Result<Reductions> {
    let b = enc(base, &[])?;
    let es: Vec<Box<dyn Encoder>> = ids.iter().map(|id| enc(id, &[])).collect::<Result<_>>()?;
    let mut ex = vec![Vec::new(); ids.len()];
    let mut pr = vec![Vec::new(); ids.len()];
    let mut table = format!("| map | metric | {base} |");
    for id in ids {
        let _ = write!(table, " {id} |");
    }
    table += "\n|---|---|---|";
    table += &"---|".repeat(ids.len());
    table += "\n";
    for case in cases {
        for (metric, f) in
            [("exact", exact as fn(&dyn Encoder, &Case, &OutputGrid) -> Scores), ("probulator", probulator)]
        {
            let rb = f(b.as_ref(), case, grid).rmse;
            let _ = write!(table, "| {} | {metric} | {rb:.5} |", case.name);
            for (i, e) in es.iter().enumerate() {
                let r = f(e.as_ref(), case, grid).rmse;
                let red = reduction(rb, r);
                let dest = if metric == "exact" { &mut ex } else { &mut pr };
                dest[i].push(red);
                let _ = write!(table, " {r:.5} ({}) |", pct(-red));
            }
            table += "\n";
        }
    }
    Ok((ex, pr, table))
}

/// Z6: hallucination models against L1 SH.
pub(super) fn z6(grid: &OutputGrid, cases: &[Case]) -> Result<(Finding, String)> {
    let ids = ["zh3_hallucinate_ambdir", "zh3_hallucinate_sphere", "zh3_hallucinate"];
    let (ex, pr, table) = reductions(grid, cases, "sh1", &ids)?;
    let m: Vec<f64> = ex.iter().map(|v| mean(v)).collect();
    let p: Vec<f64> = pr.iter().map(|v| mean(v)).collect();
    let curve_best = m[2] >= m[0] && m[2] >= m[1];
    let both_reduce = m[2] > 0.0 && m[0] > 0.0;
    let sphere_zero = m[1].abs() < 0.05;
    let holds = if curve_best && both_reduce && sphere_zero {
        "yes".to_string()
    } else if curve_best && both_reduce {
        "partly: curve best and ambdir helps, but the sphere-light model is not ~0%".to_string()
    } else {
        "no".to_string()
    };
    Ok((
        Finding {
            id: "Z6",
            claim: "Hallucination against L1 SH: ambient+directional ~17% lower RMSE, sphere light ~0%, quadratic curve fit 23% (prod)",
            paper_figure: "17% / 0% / 23% lower RMSE than SH L1 (production set, ~3M probes)".into(),
            our_figure: format!(
                "mean over 5 probes, exact: {} / {} / {}; probulator: {} / {} / {}",
                pct(m[0]),
                pct(m[1]),
                pct(m[2]),
                pct(p[0]),
                pct(p[1]),
                pct(p[2])
            ),
            holds,
            notes: "reductions (positive = lower RMSE than sh1) for ambdir / sphere / curve, Rec.709 shared axis; the paper's \
                    percentages are production anchors (about 3M game probes; ours are five HDR photographs); holds if curve and ambdir both reduce the error, the curve \
                    most, and the sphere model within ±5% of sh1"
                .into(),
        },
        format!("RMSE and change against sh1, both metrics (exact: sphere, solid-angle; probulator: per-pixel, clamped; 256x128).\n\n{table}"),
    ))
}

/// Z7: stored against hallucinated ZH3.
pub(super) fn z7(grid: &OutputGrid, cases: &[Case]) -> Result<(Finding, String)> {
    let ids = ["zh3_stored_shared", "zh3_solved_shared", "zh3_hallucinate_solved"];
    let (ex, pr, table) = reductions(grid, cases, "zh3_hallucinate", &ids)?;
    let m: Vec<f64> = ex.iter().map(|v| mean(v)).collect();
    let p: Vec<f64> = pr.iter().map(|v| mean(v)).collect();
    Ok((
        Finding {
            id: "Z7",
            claim: "Stored ZH3 has about 27% lower error than hallucinated ZH3 (prod)",
            paper_figure: "~27% lower (production set)".into(),
            our_figure: format!(
                "mean over 5 probes against zh3_hallucinate, exact: stored shared {}, solved shared {}; probulator: {}, {}",
                pct(m[0]),
                pct(m[1]),
                pct(p[0]),
                pct(p[1])
            ),
            holds: yes(m[1] > 0.0 && m[0] > 0.0),
            notes: format!(
                "positive = stored has lower RMSE; also the hallucinated solve (L1 solved for its hallucinated ZH3): exact {}; \
                 holds if stored beats hallucinated on average (the 27% is a production anchor)",
                pct(m[2])
            ),
        },
        format!("RMSE and change against zh3_hallucinate.\n\n{table}"),
    ))
}

/// Z8: ZH3 on the five probes.
pub(super) fn z8(grid: &OutputGrid, cases: &[Case]) -> Result<(Finding, String)> {
    let ids = ["sh1", "zh3_hallucinate", "zh3_hallucinate_channel", "zh3_stored_shared", "zh3_solved_shared", "sh2"];
    let es: Vec<Box<dyn Encoder>> = ids.iter().map(|id| enc(id, &[])).collect::<Result<_>>()?;
    let mut table = String::from("| map | metric |");
    for id in ids {
        let _ = write!(table, " {id} |");
    }
    table += " gap closed (solved shared) |\n|---|---|";
    table += &"---|".repeat(ids.len() + 1);
    table += "\n";
    let mut all_better = true;
    let mut gap = std::collections::BTreeMap::new();
    let mut wells = (0.0, 0.0, 0.0);
    for case in cases {
        for (metric, f) in
            [("exact", exact as fn(&dyn Encoder, &Case, &OutputGrid) -> Scores), ("probulator", probulator)]
        {
            let r: Vec<f64> = es.iter().map(|e| f(e.as_ref(), case, grid).rmse).collect();
            let g = (r[0] - r[4]) / (r[0] - r[5]);
            if metric == "exact" {
                all_better &= r[1] < r[0] && r[3] < r[0] && r[4] < r[0];
            }
            gap.insert((case.name.clone(), metric), g);
            if case.name == "wells_probulator" && metric == "probulator" {
                wells = (r[2], r[3], r[4]);
            }
            let _ = write!(table, "| {} | {metric} |", case.name);
            for x in &r {
                let _ = write!(table, " {x:.5} |");
            }
            let _ = writeln!(table, " {g:.2} |");
        }
    }
    let g = |m: &str, metric: &'static str| gap.get(&(m.to_string(), metric)).copied().unwrap_or(f64::NAN);
    let close = g("grace_256x128", "probulator") >= 0.75 && g("ennis_256x128", "probulator") >= 0.75;
    let wells_beats = wells.0 < wells.1;
    let holds = all_better && close && wells_beats;
    Ok((
        Finding {
            id: "Z8",
            claim: "ZH3 clearly improves on L1 on every map and comes close to SH3 on Grace and Ennis; hallucination with a per-channel axis can beat the stored shared-axis solve (as on Wells)",
            paper_figure: "figure of RMSE per map (Probulator)".into(),
            our_figure: format!(
                "ZH3 (hallucinated, stored, solved) below sh1 on every map: {}; share of the sh1→sh2 gap closed by the solved shared axis \
                 (probulator): grace {:.2}, ennis {:.2} (exact {:.2}, {:.2}); wells (probulator): hallucinate_channel {:.5} vs stored shared {:.5} vs solved shared {:.5}",
                yes(all_better),
                g("grace_256x128", "probulator"),
                g("ennis_256x128", "probulator"),
                g("grace_256x128", "exact"),
                g("ennis_256x128", "exact"),
                wells.0,
                wells.1,
                wells.2
            ),
            holds: if holds { "yes".into() } else { format!("partly: improves {}, close {}, wells {}", yes(all_better), yes(close), yes(wells_beats)) },
            notes: "\"close to SH3\" read as closing at least 75% of the sh1→sh2 RMSE gap; our probulator metric uses the exact \
                    reference (the paper's used Monte Carlo)"
                .into(),
        },
        format!("RMSE per map and metric (exact: sphere, solid-angle; probulator: per-pixel, clamped; 256x128).\n\n{table}"),
    ))
}
