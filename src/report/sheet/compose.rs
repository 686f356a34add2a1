//! The comparison sheet of an experiment on one map: its representative case, every encoder
//! fitted as the runner fits it, the reference and encoders at the discs' normals, the tone and
//! error scale, the rows and the header lines.

use super::super::csvfile::CsvTable;
use super::super::number::{percent, sig};
use super::super::tone::{experiment_error_range, nice_ceil, ErrorScale, ErrorScope, Tone};
use super::figures::{figures_from_table, RowFigures, SheetScores};
use super::layout::{DISC, MAX_SCALE, THUMB_W};
use super::render::{Sheet, SheetRow};
use super::thumbnail::latlong_thumbnail;
use crate::encoders::encoder::Fitted;
use crate::envmap::EnvMap;
use crate::io::profile::{self, Profile};
use crate::math::colour::{luminance, Rgb};
use crate::pipeline::experiment::Experiment;
use crate::pipeline::runner::{cases, evaluate, score_fit, Case, CaseData, MapData};
use crate::reference::domain::Domain;
use crate::reference::metrics::Metric;
use crate::reference::view::{Disc, View};
use anyhow::{ensure, Result};
use glam::DVec3;

/// The case drawn for an experiment: the one whose surface normal is nearest +Y (the first
/// such), or the single sphere case.
pub fn representative_case(all: &[Case]) -> usize {
    let mut best = 0;
    let mut best_dot = f64::NEG_INFINITY;
    for (i, c) in all.iter().enumerate() {
        let d = c.normal.map(|n| n.dot(DVec3::Y)).unwrap_or(1.0);
        if d > best_dot + 1e-12 {
            best = i;
            best_dot = d;
        }
    }
    best
}

/// The comparison sheet of an experiment on one map: its representative case, every encoder
/// of the experiment through the trait, fitted from the case's [`CaseData`] exactly as the
/// runner fits it. The figures under each row are the table's when `table` has them (the
/// runner's rows), else scored here by the runner's [`score_fit`] (the `exact` metric over the
/// case's output grid).
/// The reference on the discs is evaluated exactly at every pixel's normal. (Interpolating
/// it from the reference's fast lat-long path was tried: near the terminator of a small bright
/// source the bilinear error reached 2.7% of the local value at 256x128 and 0.66% at 512x256,
/// visible on the error spheres; so it is not done.)
/// At `scale` N the discs are [`DISC`]·N pixels across, each pixel's normal evaluated, and
/// the thumbnail is filtered at [`THUMB_W`]·N; the figures do not depend on the scale. The
/// reference and the encoders' evaluation are timed on `timed_on` (`--profile`), if given.
pub fn experiment_sheet(
    exp: &Experiment,
    map: &EnvMap,
    table: Option<&CsvTable>,
    scale: u32,
    timed_on: Option<&Profile>,
) -> Result<(Sheet, SheetScores)> {
    ensure!((1..=MAX_SCALE).contains(&scale), "sheet scale {scale}: must be 1 to {MAX_SCALE}");
    let data = MapData::new(map);
    let all = cases(exp);
    let ci = representative_case(&all);
    let case = &all[ci];
    let cd = CaseData::new(&data, case, exp.polar_nodes);
    let input = cd.fit_input();
    let fitted: Vec<Box<dyn Fitted>> = exp.encoders.iter().map(|e| e.encoder.fit(&input)).collect();
    let names: Vec<String> = exp.encoders.iter().map(|e| e.name.clone()).collect();

    let (figures, source) = match table.and_then(|t| figures_from_table(t, &map.name, case, &names)) {
        Some(f) => (f, "table.csv"),
        None => (computed_figures(exp, case, &cd, &fitted), "computed"),
    };

    let views = case_views(case);
    let discs: Vec<Disc> = views.iter().map(|v| Disc::new(v, (scale * DISC) as usize)).collect();
    let reference: Vec<Vec<Rgb>> = {
        let _s = profile::span(timed_on, "report: reference (sheets)");
        discs.iter().map(|d| cd.reference_many(&d.normals)).collect()
    };
    let values: Vec<Vec<Vec<Rgb>>> = {
        let _s = profile::span(timed_on, "report: encoder eval (sheets)");
        fitted.iter().map(|f| discs.iter().map(|d| evaluate(f.as_ref(), &d.normals)).collect()).collect()
    };
    let (tone, error) = sheet_scales(&reference, &figures, table.and_then(experiment_error_range));

    let rows: Vec<SheetRow> = exp
        .encoders
        .iter()
        .zip(values)
        .zip(&figures)
        .map(|((e, values), f)| sheet_row(e.name.clone(), e.encoder.storage(&input), values, f))
        .collect();

    let lines = header_lines(exp, case, all.len(), &cd.reference.describe(), source, &tone, &error);
    let sheet = Sheet {
        title: format!("{} - {}", exp.name, map.name),
        lines,
        thumbnail: Some(latlong_thumbnail(map, scale * THUMB_W)),
        thumbnail_caption: format!(
            "input map {}x{} (lat-long, +Y up, centre -Z; own exposure)",
            map.width(),
            map.height()
        ),
        views,
        discs,
        reference,
        scale,
        tone,
        error,
        rows,
    };
    let scores = SheetScores {
        case_label: case.domain_label.clone(),
        figures: names.into_iter().zip(figures).collect(),
        source,
    };
    Ok((sheet, scores))
}

/// Every encoder's figures scored here, as the runner scores them: the exact metric over the
/// case's domain at the experiment's resolution, through the runner's own step ([`score_fit`]).
fn computed_figures(exp: &Experiment, case: &Case, cd: &CaseData, fitted: &[Box<dyn Fitted>]) -> Vec<RowFigures> {
    let grid = case.domain.output_grid(exp.resolution);
    let ref_grid = cd.reference_on(&grid);
    exp.encoders
        .iter()
        .zip(fitted)
        .map(|(e, f)| RowFigures::from(&score_fit(e.encoder.as_ref(), f.as_ref(), &grid, &ref_grid, Metric::Exact)))
        .collect()
}

/// The views a case is drawn in: a hemisphere as a disc looking down its N (captioned with the
/// orientation of its domain label), the sphere front and top.
fn case_views(case: &Case) -> Vec<View> {
    match &case.domain {
        Domain::Hemisphere { normal } => {
            let label = case.domain_label.split(':').nth(1).unwrap_or("N").to_string();
            vec![View::down(*normal, &label)]
        }
        Domain::Sphere => vec![View::front(), View::top()],
    }
}

/// The sheet's tone (from the mean luminance and the brightest channel of the reference drawn)
/// and its error scale: the floor at 1% of that mean, the range the experiment's
/// (`experiment_range`, from its table) or else the median of this sheet's rows' finite
/// rel_rmse, rounded up to a 1-2-5 step.
fn sheet_scales(reference: &[Vec<Rgb>], figures: &[RowFigures], experiment_range: Option<f64>) -> (Tone, ErrorScale) {
    let drawn: Vec<Rgb> = reference.iter().flatten().copied().collect();
    let mean_lum = drawn.iter().map(|c| luminance(*c)).sum::<f64>() / drawn.len().max(1) as f64;
    let max_val = drawn.iter().map(|c| c.max_element()).fold(0.0, f64::max);
    let tone = Tone::from_reference(mean_lum, max_val);
    let floor = 0.01 * mean_lum.max(0.0);
    if let Some(range) = experiment_range {
        return (tone, ErrorScale { floor, range, scope: ErrorScope::Experiment });
    }
    let mut rel: Vec<f64> = figures.iter().map(|f| f.rel_rmse).filter(|v| v.is_finite()).collect();
    rel.sort_by(f64::total_cmp);
    let median = if rel.is_empty() { 0.0 } else { rel[(rel.len() - 1) / 2] };
    (tone, ErrorScale { floor, range: nice_ceil(median), scope: ErrorScope::Sheet })
}

/// An encoder's row: its name, storage note, values at the discs and the figures printed under
/// its spheres.
fn sheet_row(name: String, note: String, values: Vec<Vec<Rgb>>, f: &RowFigures) -> SheetRow {
    SheetRow {
        name,
        note,
        values,
        under_lit: if f.neg_frac > 0.0 { format!("negative on {}", percent(f.neg_frac)) } else { String::new() },
        under_err: [
            format!("RMSE {} E/π (exact, solid-angle)", sig(f.rmse, 3)),
            format!("relative RMSE {}", percent(f.rel_rmse)),
        ],
    }
}

/// The sheet's header lines: the description, the case drawn (of `n_cases`), the reference
/// (`reference`, its description), where the figures come from, the tone and the error scale.
fn header_lines(
    exp: &Experiment,
    case: &Case,
    n_cases: usize,
    reference: &str,
    source: &str,
    tone: &Tone,
    error: &ErrorScale,
) -> Vec<String> {
    let (res_w, res_h) = match case.domain {
        Domain::Sphere => exp.resolution,
        Domain::Hemisphere { .. } => (exp.resolution.0, exp.resolution.1 / 2),
    };
    let mut lines = vec![];
    if !exp.description.is_empty() {
        lines.push(exp.description.clone());
    }
    lines.push(format!(
        "case: {} (effects: {}){}",
        case.domain_label,
        case.effects_label,
        if n_cases > 1 {
            format!("; drawn: the case nearest N = +Y, 1 of {n_cases} in the table")
        } else {
            String::new()
        }
    ));
    lines.push(format!("E/π; reference: {reference}, at every pixel's normal"));
    lines.push(format!(
        "figures: exact metric, solid-angle weighted over {} at {}x{} ({})",
        if matches!(case.domain, Domain::Sphere) { "the sphere" } else { "the hemisphere about N" },
        res_w,
        res_h,
        if source == "table.csv" { "from table.csv" } else { "computed as the runner does" }
    ));
    lines.push(format!("every sphere: {}", tone.describe()));
    lines.push(match error.scope {
        ErrorScope::Experiment => format!(
            "error scale ±{}, the same on every sheet of this experiment: median rel_rmse of table.csv",
            percent(error.range)
        ),
        ErrorScope::Sheet => {
            format!(
                "error scale ±{}, this sheet's own (no table.csv): median rel_rmse of its rows",
                percent(error.range)
            )
        }
    });
    lines.push("(Y = Rec.709 luminance; the denominator is held at >= 1% of the reference's mean Y)".into());
    lines
}
