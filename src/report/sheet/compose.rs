//! The comparison sheet of an experiment on one map: its representative case, every encoder
//! fitted as the runner fits it, the reference and encoders at the discs' normals, the tone and
//! error scale, the rows and the header lines.

use super::super::csvfile::CsvTable;
use super::super::number::{percent, sig};
use super::super::tone::{range_of, row_percentile, ErrorScale, ErrorScope, Tone, SCALE_PERCENTILE};
use super::chroma::{Chroma, CHROMA_FLOOR};
use super::figures::{figures_from_table, RowFigures, SheetScores};
use super::layout::{DISC, MAX_SCALE, THUMB_W};
use super::render::{Sheet, SheetRow};
use super::thumbnail::latlong_thumbnail;
use crate::encoders::encoder::Fitted;
use crate::envmap::EnvMap;
use crate::io::profile;
use crate::math::colour::{luminance, xy_distance, Rgb};
use crate::pipeline::experiment::Experiment;
use crate::pipeline::reuse::ReferenceCache;
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
/// reference at each disc is kept in and read from `cache` (so the sheets of a workflow that
/// draw the same case of a map at the same size compute it once), and timed on the cache's
/// profile (`--profile`), as is the encoders' evaluation.
pub fn experiment_sheet(
    exp: &Experiment,
    map: &EnvMap,
    table: Option<&CsvTable>,
    scale: u32,
    cache: &ReferenceCache,
) -> Result<(Sheet, SheetScores)> {
    ensure!((1..=MAX_SCALE).contains(&scale), "sheet scale {scale}: must be 1 to {MAX_SCALE}");
    let data = MapData::new(map);
    let all = cases(exp);
    let ci = representative_case(&all);
    let case = &all[ci];
    let cd = CaseData::new(&data, case, exp.polar_nodes).reusing(cache);
    let timed_on = cache.profile();
    let input = cd.fit_input();
    let fitted: Vec<Box<dyn Fitted>> = exp.encoders.iter().map(|e| e.encoder.fit(&input)).collect();
    let names: Vec<String> = exp.encoders.iter().map(|e| e.name.clone()).collect();

    let metric = shown_metric(exp);
    let (figures, source) = match table.and_then(|t| figures_from_table(t, &map.name, case, &names, metric.name())) {
        Some(f) => (f, "table.csv"),
        None => (computed_figures(exp, case, &cd, &fitted, metric), "computed"),
    };

    let views = case_views(case);
    let discs: Vec<Disc> = views.iter().map(|v| Disc::new(v, (scale * DISC) as usize)).collect();
    let reference: Vec<Vec<Rgb>> =
        discs.iter().map(|d| cd.reference_many_as(&d.normals, "report: reference (sheets)")).collect();
    let values: Vec<Vec<Vec<Rgb>>> = {
        let _s = profile::span(timed_on, "report: encoder eval (sheets)");
        fitted.iter().map(|f| discs.iter().map(|d| evaluate(f.as_ref(), &d.normals)).collect()).collect()
    };
    let tone = sheet_tone(&reference);
    let rows: Vec<SheetRow> = exp
        .encoders
        .iter()
        .zip(values)
        .zip(&figures)
        .map(|((e, values), f)| sheet_row(e.name.clone(), e.encoder.storage(&input), values, f, metric))
        .collect();
    // This sheet's own range; `draw_sheets` gives every sheet of an experiment the range of all.
    let floor = 0.01 * tone_mean(&reference);
    let mut error = ErrorScale { floor, range: 1.0, scope: ErrorScope::Sheet };
    error.range = range_of(row_percentiles(&reference, &rows, &error));

    let described = Described { reference: cd.reference.describe(), source, metric };
    let lines = header_lines(exp, case, all.len(), &described, &tone, &error);
    let mut sheet = Sheet {
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
        chroma: Chroma::NotDrawn { largest: 0.0 },
        rows,
    };
    sheet.chroma = chroma_of(&[&sheet], ErrorScope::Sheet);
    let scores = SheetScores {
        case_label: case.domain_label.clone(),
        figures: names.into_iter().zip(figures).collect(),
        source,
    };
    Ok((sheet, scores))
}

/// The metric a sheet prints: `exact` when the experiment scores it, else its first metric
/// (the parity experiment scores only the peer's), so the figures are its table's own.
fn shown_metric(exp: &Experiment) -> Metric {
    if exp.metrics.contains(&Metric::Exact) {
        Metric::Exact
    } else {
        exp.metrics.first().copied().unwrap_or(Metric::Exact)
    }
}

/// Every encoder's figures scored here, as the runner scores them: `metric` over the case's
/// domain at the experiment's resolution, through the runner's own step ([`score_fit`]).
fn computed_figures(
    exp: &Experiment,
    case: &Case,
    cd: &CaseData,
    fitted: &[Box<dyn Fitted>],
    metric: Metric,
) -> Vec<RowFigures> {
    let grid = case.domain.output_grid(exp.resolution);
    let ref_grid = cd.reference_on(&grid);
    exp.encoders
        .iter()
        .zip(fitted)
        .map(|(e, f)| RowFigures::from(&score_fit(e.encoder.as_ref(), f.as_ref(), &grid, &ref_grid, metric)))
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

/// The mean Rec.709 luminance of the reference drawn (over every disc pixel).
fn tone_mean(reference: &[Vec<Rgb>]) -> f64 {
    let n = reference.iter().map(Vec::len).sum::<usize>().max(1);
    (reference.iter().flatten().map(|c| luminance(*c)).sum::<f64>() / n as f64).max(0.0)
}

/// The sheet's tone, from the mean luminance and the brightest channel of the reference drawn.
fn sheet_tone(reference: &[Vec<Rgb>]) -> Tone {
    let max_val = reference.iter().flatten().map(|c| c.max_element()).fold(0.0, f64::max);
    Tone::from_reference(tone_mean(reference), max_val)
}

/// Per row, the [`row_percentile`] of |relative error| over the pixels of its error spheres
/// (every view's disc), under `scale`'s floor: what the error range is the median of.
fn row_percentiles(reference: &[Vec<Rgb>], rows: &[SheetRow], scale: &ErrorScale) -> Vec<f64> {
    rows.iter()
        .map(|r| {
            let views = r.values.iter().zip(reference);
            row_percentile(
                views
                    .flat_map(|(vals, refs)| vals.iter().zip(refs).map(|(v, r)| scale.relative(*r, *v).abs() as f32))
                    .collect(),
            )
        })
        .collect()
}

/// An encoder's row: its name, storage note, values at the discs and the figures printed under
/// its spheres.
fn sheet_row(name: String, note: String, values: Vec<Vec<Rgb>>, f: &RowFigures, metric: Metric) -> SheetRow {
    SheetRow {
        name,
        note,
        values,
        under_lit: if f.neg_frac > 0.0 { format!("negative on {}", percent(f.neg_frac)) } else { String::new() },
        under_err: [
            format!("RMSE {} E/π ({}, {})", sig(f.rmse, 3), metric.name(), metric.weighting()),
            format!("relative RMSE {}", percent(f.rel_rmse)),
        ],
    }
}

/// What a sheet's header says of its figures: the reference's description, where the figures
/// come from ("table.csv" or "computed") and their metric.
struct Described {
    reference: String,
    source: &'static str,
    metric: Metric,
}

/// The sheet's header lines: the description, the case drawn (of `n_cases`), the reference,
/// where the figures come from and their metric, the tone and the error scale.
fn header_lines(
    exp: &Experiment,
    case: &Case,
    n_cases: usize,
    d: &Described,
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
    lines.push(format!("E/π; reference: {}, at every pixel's normal", d.reference));
    lines.push(format!(
        "figures: {} metric, {} weighted over {} at {}x{} ({})",
        d.metric.name(),
        d.metric.weighting(),
        if matches!(case.domain, Domain::Sphere) { "the sphere" } else { "the hemisphere about N" },
        res_w,
        res_h,
        if d.source == "table.csv" { "from table.csv" } else { "computed as the runner does" }
    ));
    lines.push(format!("every sphere: {}", tone.describe()));
    lines.push(error_scale_line(error));
    lines.push("(Y = Rec.709 luminance; the denominator is held at >= 1% of the reference's mean Y)".into());
    lines
}

/// The header line that states the error scale and where its range comes from.
fn error_scale_line(error: &ErrorScale) -> String {
    let p = format!("{:.0}th percentile of a row's |relative error| pixels", SCALE_PERCENTILE * 100.0);
    let whose = match error.scope {
        ErrorScope::Experiment => "the same on every sheet of this experiment: over all its sheets' rows",
        ErrorScope::Sheet => "this sheet's own: over its rows",
    };
    format!(
        "error scale ±{}, {whose}, the median of the {p}, rounded up to 1-2-5; the share beyond it (saturated) is \
         under each row",
        percent(error.range)
    )
}

/// Gives every sheet of an experiment one error scale, and one chroma decision and scale
/// ([`share_chroma`]): the median over the rows of all its
/// sheets of each row's high percentile of |relative error| ([`range_of`]), each under its own
/// sheet's floor; the header line says so.
pub fn share_error_scale<'a>(sheets: impl Iterator<Item = &'a mut Sheet>) {
    let mut sheets: Vec<&mut Sheet> = sheets.collect();
    share_chroma(&mut sheets);
    let all: Vec<f64> = sheets.iter().flat_map(|s| row_percentiles(&s.reference, &s.rows, &s.error)).collect();
    let range = range_of(all);
    for s in sheets {
        let old = error_scale_line(&s.error);
        s.error = ErrorScale { range, scope: ErrorScope::Experiment, ..s.error };
        let new = error_scale_line(&s.error);
        for l in s.lines.iter_mut().filter(|l| **l == old) {
            l.clone_from(&new);
        }
    }
}

/// Per row of `sheet`, its lit pixels' xy distances (every view's disc), as f32.
fn lit_distances(sheet: &Sheet, row: &SheetRow) -> Vec<f32> {
    row.values
        .iter()
        .zip(&sheet.reference)
        .flat_map(|(vals, refs)| vals.iter().zip(refs))
        .filter(|(_, r)| luminance(**r) >= sheet.error.floor)
        .map(|(v, r)| xy_distance(*v, *r) as f32)
        .collect()
}

/// The chroma discs of sheets drawn with one scale (`scope`): drawn when some row of some sheet
/// exceeds [`CHROMA_FLOOR`] on a lit pixel, R the median of each row's high percentile
/// ([`range_of`]) over the rows whose percentile exceeds the floor, so the grey scenes of an
/// experiment, where every encoding keeps the colour, do not shrink the scale of those in colour.
pub fn chroma_of(sheets: &[&Sheet], scope: ErrorScope) -> Chroma {
    let per_row: Vec<Vec<f32>> = sheets.iter().flat_map(|s| s.rows.iter().map(|r| lit_distances(s, r))).collect();
    let largest = per_row.iter().flatten().copied().filter(|d| d.is_finite()).fold(0.0f32, f32::max) as f64;
    if largest <= CHROMA_FLOOR {
        return Chroma::NotDrawn { largest };
    }
    let coloured: Vec<f64> = per_row.into_iter().map(row_percentile).filter(|p| *p > CHROMA_FLOOR).collect();
    // Every row's percentile at or under the floor while some pixel exceeds it: the floor's scale.
    let range = if coloured.is_empty() { CHROMA_FLOOR } else { range_of(coloured) };
    Chroma::Drawn { range, scope }
}

/// Gives every sheet of an experiment one chroma decision and scale ([`chroma_of`] over all).
pub fn share_chroma(sheets: &mut [&mut Sheet]) {
    let chroma = chroma_of(&sheets.iter().map(|s| &**s).collect::<Vec<_>>(), ErrorScope::Experiment);
    for s in sheets.iter_mut() {
        s.chroma = chroma;
    }
}
