//! A sweep with more series than a legend can tell apart (every map × encoder × normal of a
//! solver's iteration count, say) drawn as what a sweep is for: how fast each encoder
//! converges. Each series is divided by its own RMSE at the knob's largest value, so every
//! series ends at 1; per encoder the median and the worst (largest) of these ratios over its
//! series are drawn against the value, and against the median time at that value.

use super::draw::Outcome;
use super::lines::{panels, Line, Series, MAX_LEGEND};
use super::rows::Measure;
use anyhow::Result;

/// One encoder's summary: at each knob value (ascending), the median time over its series
/// (if any has one), the median ratio and the worst ratio.
struct Summary {
    group: String,
    series: usize,
    points: Vec<(f64, Option<f64>, f64, f64)>,
}

/// The median of `v` (sorted here); `None` when empty.
fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) })
}

/// The summaries of `lines`, by group in first-seen order, and how many series could not be
/// scaled (their RMSE at their largest value is 0).
fn summarise(lines: &[Line]) -> (Vec<Summary>, usize) {
    let mut groups: Vec<&str> = Vec::new();
    for l in lines {
        if !groups.contains(&l.group.as_str()) {
            groups.push(&l.group);
        }
    }
    let mut unscaled = 0;
    let mut out = Vec::new();
    for g in groups {
        let mut scaled: Vec<Vec<(f64, f64, Option<f64>)>> = Vec::new();
        for l in lines.iter().filter(|l| l.group == g) {
            match l.points.last() {
                Some(last) if last.1 > 0.0 => scaled.push(l.points.iter().map(|p| (p.0, p.1 / last.1, p.2)).collect()),
                Some(_) => unscaled += 1,
                None => {}
            }
        }
        let mut values: Vec<f64> = scaled.iter().flatten().map(|p| p.0).collect();
        values.sort_by(f64::total_cmp);
        values.dedup();
        let points = values
            .into_iter()
            .filter_map(|v| {
                let at: Vec<&(f64, f64, Option<f64>)> = scaled.iter().flatten().filter(|p| p.0 == v).collect();
                let mut ratios: Vec<f64> = at.iter().map(|p| p.1).collect();
                let worst = ratios.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let mut times: Vec<f64> = at.iter().filter_map(|p| p.2).collect();
                Some((v, median(&mut times), median(&mut ratios)?, worst))
            })
            .collect();
        out.push(Summary { group: g.to_string(), series: scaled.len(), points });
    }
    (out, unscaled)
}

/// The convergence charts of one knob: [`MAX_LEGEND`]` / 2` encoders a chart (a median and a
/// worst line each), named `KNOB`, then `KNOB_part2`, … when there are more.
pub fn convergence_charts(
    knob: &str,
    lines: &[Line],
    measure: &Measure,
    unplotted: &str,
) -> Result<Vec<(String, Outcome)>> {
    let (summaries, unscaled) = summarise(lines);
    let mut out = Vec::new();
    for (part, chunk) in summaries.chunks(MAX_LEGEND / 2).enumerate() {
        let mut by_value = Vec::new();
        let mut by_time = Vec::new();
        for (k, s) in chunk.iter().enumerate() {
            for (dashed, what) in [(false, format!("median of {}", s.series)), (true, "worst".to_string())] {
                let y = |p: &(f64, Option<f64>, f64, f64)| if dashed { p.3 } else { p.2 };
                let label = format!("{}: {what}", s.group);
                by_value.push(Series {
                    label: label.clone(),
                    colour: k,
                    dashed,
                    points: s.points.iter().map(|p| (p.0, y(p))).collect(),
                });
                let timed: Vec<(f64, f64)> = s.points.iter().filter_map(|p| p.1.map(|t| (t, y(p)))).collect();
                if !timed.is_empty() {
                    by_time.push(Series { label, colour: k, dashed, points: timed });
                }
            }
        }
        let largest = lines.iter().filter_map(|l| l.points.last()).map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
        let axis = format!("RMSE ÷ RMSE at the series' largest {knob}");
        let mut o = panels(knob, "RMSE ratio", (&by_value, &by_time), &axis, false)?;
        if let Outcome::Drawn { caption, .. } = &mut o {
            *caption = caption_of(knob, lines.len(), largest, measure, unscaled, unplotted);
        }
        let name = if part == 0 { knob.to_string() } else { format!("{knob}_part{}", part + 1) };
        out.push((name, o));
    }
    Ok(out)
}

/// The caption of a convergence chart.
fn caption_of(knob: &str, series: usize, largest: f64, measure: &Measure, unscaled: usize, unplotted: &str) -> String {
    let left_out = if unscaled > 0 {
        format!("; {unscaled} series with an RMSE of 0 at their largest value are left out")
    } else {
        String::new()
    };
    format!(
        "convergence sweep of `{knob}` over {series} series (map / encoder / domain; more than the \
         {MAX_LEGEND} a legend tells apart): each series' RMSE divided by its RMSE at its largest `{knob}` \
         (up to {largest}), so every series ends at 1; per encoder the median (solid) and the worst \
         (dashed) ratio, against the value (a W×H value at W) and against the median time_ns. {}. Every \
         series is in the CSV{left_out}{unplotted}",
        measure.caption(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(group: &str, label: &str, points: &[(f64, f64)]) -> Line {
        Line {
            label: label.into(),
            group: group.into(),
            points: points.iter().map(|p| (p.0, p.1, Some(p.0 * 10.0))).collect(),
        }
    }

    /// Three series ending at 1, 2 and 0.5 that start at 2, 6 and 2 times that: at the first
    /// value the median ratio is 2 and the worst 6; at the last every ratio is 1. A series
    /// ending at 0 cannot be scaled and is counted.
    #[test]
    fn each_series_is_scaled_by_its_own_last_value() {
        let lines = [
            line("e", "a", &[(1.0, 2.0), (10.0, 1.0)]),
            line("e", "b", &[(1.0, 12.0), (10.0, 2.0)]),
            line("e", "c", &[(1.0, 1.0), (5.0, 0.75), (10.0, 0.5)]),
            line("e", "d", &[(1.0, 1.0), (10.0, 0.0)]),
        ];
        let (s, unscaled) = summarise(&lines);
        assert_eq!(unscaled, 1);
        assert_eq!(s.len(), 1);
        assert_eq!(s[0].series, 3);
        assert_eq!(
            s[0].points,
            vec![(1.0, Some(10.0), 2.0, 6.0), (5.0, Some(50.0), 1.5, 1.5), (10.0, Some(100.0), 1.0, 1.0)]
        );
        assert_eq!(median(&mut [3.0, 1.0, 2.0, 10.0]), Some(2.5));
        assert_eq!(median(&mut []), None);
    }

    /// Five encoders of three series each: four encoders (eight legend entries) on the first
    /// chart and the fifth on `KNOB_part2`, each entry a median or a worst line.
    #[test]
    fn more_groups_than_a_legend_holds_are_split() {
        let mut lines = Vec::new();
        for g in 0..5 {
            for m in 0..3 {
                lines.push(line(&format!("enc{g}"), &format!("m{m} / enc{g}"), &[(1.0, 2.0 + m as f64), (4.0, 1.0)]));
            }
        }
        let measure =
            Measure { unit: "E/π".into(), metric: None, reference: None, weighting: None, resolution: vec![] };
        let charts = convergence_charts("k", &lines, &measure, "").unwrap();
        let names: Vec<&str> = charts.iter().map(|c| c.0.as_str()).collect();
        assert_eq!(names, ["k", "k_part2"]);
        let Outcome::Drawn { text, caption, .. } = &charts[0].1 else { panic!("not drawn") };
        let legend: Vec<&str> = text.iter().map(|t| t.text.as_str()).filter(|t| t.starts_with("enc")).collect();
        assert_eq!(legend.len(), MAX_LEGEND, "{legend:?}");
        assert!(legend.contains(&"enc0: median of 3") && legend.contains(&"enc3: worst"), "{legend:?}");
        assert!(caption.contains("over 15 series") && caption.contains("median (solid)"), "{caption}");
    }
}
