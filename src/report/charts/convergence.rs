//! A sweep with more series than a legend can tell apart (every map × encoder × normal of a
//! solver's iteration count, say) drawn per encoder: at each value of the knob, the median and
//! the worst (largest) RMSE over the encoder's series, against the value and against the
//! median time at that value. Where each encoder's curves flatten is where it has converged;
//! the levels stay in the table's unit.

use super::draw::Outcome;
use super::lines::{panels, Line, Panels, Series, MAX_LEGEND};
use super::rows::Measure;
use crate::math::stats::median;
use crate::report::style::style_of;
use anyhow::Result;

/// One encoder's summary: at each knob value (ascending), the median time over its series
/// (if any has one), the median RMSE and the worst RMSE.
struct Summary {
    group: String,
    series: usize,
    points: Vec<(f64, Option<f64>, f64, f64)>,
}

/// The summaries of `lines`, by group in first-seen order.
fn summarise(lines: &[Line]) -> Vec<Summary> {
    let mut groups: Vec<&str> = Vec::new();
    for l in lines {
        if !groups.contains(&l.group.as_str()) {
            groups.push(&l.group);
        }
    }
    let mut out = Vec::new();
    for g in groups {
        let members: Vec<&Line> = lines.iter().filter(|l| l.group == g).collect();
        let mut values: Vec<f64> = members.iter().flat_map(|l| &l.points).map(|p| p.0).collect();
        values.sort_by(f64::total_cmp);
        values.dedup();
        let points = values
            .into_iter()
            .filter_map(|v| {
                let at: Vec<&(f64, f64, Option<f64>)> =
                    members.iter().flat_map(|l| &l.points).filter(|p| p.0 == v).collect();
                let rmse: Vec<f64> = at.iter().map(|p| p.1).collect();
                let worst = rmse.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let times: Vec<f64> = at.iter().filter_map(|p| p.2).collect();
                Some((v, median(&times), median(&rmse)?, worst))
            })
            .collect();
        out.push(Summary { group: g.to_string(), series: members.len(), points });
    }
    out
}

/// The convergence charts of one knob: [`MAX_LEGEND`]` / 2` encoders a chart (a median and a
/// worst line each), named `KNOB`, then `KNOB_part2`, … when there are more.
pub fn convergence_charts(
    knob: &str,
    lines: &[Line],
    p: &Panels,
    measure: &Measure,
    unplotted: &str,
) -> Result<Vec<(String, Outcome)>> {
    let summaries = summarise(lines);
    let mut out = Vec::new();
    for (part, chunk) in summaries.chunks(MAX_LEGEND / 2).enumerate() {
        let mut by_value = Vec::new();
        let mut by_time = Vec::new();
        for s in chunk {
            for (dashed, what) in [(false, format!("median of {}", s.series)), (true, "worst".to_string())] {
                let y = |p: &(f64, Option<f64>, f64, f64)| if dashed { p.3 } else { p.2 };
                let label = format!("{}: {what}", s.group);
                let style = style_of(&s.group);
                by_value.push(Series {
                    label: label.clone(),
                    style,
                    dashed,
                    points: s.points.iter().map(|p| (p.0, y(p))).collect(),
                });
                let timed: Vec<(f64, f64)> = s.points.iter().filter_map(|p| p.1.map(|t| (t, y(p)))).collect();
                if !timed.is_empty() {
                    by_time.push(Series { label, style, dashed, points: timed });
                }
            }
        }
        let mut o = panels(p, (&by_value, &by_time))?;
        if let Outcome::Drawn { caption, .. } = &mut o {
            *caption = caption_of(knob, lines.len(), measure, unplotted);
        }
        let name = if part == 0 { knob.to_string() } else { format!("{knob}_part{}", part + 1) };
        out.push((name, o));
    }
    Ok(out)
}

/// The caption of a convergence chart.
fn caption_of(knob: &str, series: usize, measure: &Measure, unplotted: &str) -> String {
    format!(
        "convergence sweep of `{knob}` over {series} series (map / encoder / domain; more than the \
         {MAX_LEGEND} a legend tells apart): per encoder, the median (solid) and the worst (dashed) RMSE \
         over its series at each value, against the value (a W×H value at W) and against the median \
         time_ns there. {}. Every series is in the CSV{unplotted}",
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

    /// Three series of one encoder: at value 1 the median RMSE is 2 and the worst 12; at 5
    /// only one series has a point; the median time is that of the series at the value.
    #[test]
    fn each_value_gets_the_median_and_worst_of_the_encoders_series() {
        let lines = [
            line("e", "a", &[(1.0, 2.0), (10.0, 1.0)]),
            line("e", "b", &[(1.0, 12.0), (10.0, 2.0)]),
            line("e", "c", &[(1.0, 1.0), (5.0, 0.75), (10.0, 0.5)]),
            line("f", "d", &[(1.0, 7.0)]),
        ];
        let s = summarise(&lines);
        assert_eq!(s.len(), 2);
        assert_eq!((s[0].group.as_str(), s[0].series), ("e", 3));
        assert_eq!(
            s[0].points,
            vec![(1.0, Some(10.0), 2.0, 12.0), (5.0, Some(50.0), 0.75, 0.75), (10.0, Some(100.0), 1.0, 2.0)]
        );
        assert_eq!(s[1].points, vec![(1.0, Some(10.0), 7.0, 7.0)]);
        assert_eq!(median(&[3.0, 1.0, 2.0, 10.0]), Some(2.5));
        assert_eq!(median(&[]), None);
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
        let p = Panels {
            title: "k: RMSE against k".into(),
            x_value: "k".into(),
            x_time: "fit time, ns".into(),
            y: measure.quantity(),
            scale: Default::default(),
        };
        let charts = convergence_charts("k", &lines, &p, &measure, "").unwrap();
        let names: Vec<&str> = charts.iter().map(|c| c.0.as_str()).collect();
        assert_eq!(names, ["k", "k_part2"]);
        let Outcome::Drawn { text, caption, .. } = &charts[0].1 else { panic!("not drawn") };
        let legend: Vec<&str> = text.iter().map(|t| t.text.as_str()).filter(|t| t.starts_with("enc")).collect();
        assert_eq!(legend.len(), MAX_LEGEND, "{legend:?}");
        assert!(legend.contains(&"enc0: median of 3") && legend.contains(&"enc3: worst"), "{legend:?}");
        assert!(caption.contains("over 15 series") && caption.contains("median (solid)"), "{caption}");
    }
}
