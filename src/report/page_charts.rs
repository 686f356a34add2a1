//! A page's results table and charts: each chart written as PNG and, beside it, SVG and linked
//! ([`ChartsOut`]); the table part (pivot, timing, the whole table, rmse dots or heatmap, cost charts,
//! ratios to the baseline); the charts of the folder's sweep and blending CSVs.

use super::charts::{self, Outcome};
use super::csvfile::CsvTable;
use super::folders::Section;
use super::markdown::{self, href};
use super::names::file_safe;
use super::png;
use super::ratios::ratio_pivot;
use anyhow::Result;
use std::fmt::Write as _;
use std::path::Path;

/// The SVG beside a chart's PNG: the same stem, `.svg`.
pub(super) fn svg_name(png: &str) -> String {
    format!("{}.svg", png.strip_suffix(".png").unwrap_or(png))
}

/// The charts of one section: their Markdown and the files drawn.
pub(super) struct ChartsOut<'a> {
    pub(super) dir: &'a Path,
    pub(super) md: String,
    pub(super) made: Vec<String>,
}

impl ChartsOut<'_> {
    /// Writes a drawn chart as `file` (PNG) and beside it as the same stem `.svg` (both
    /// atomically), and links it (captioned, with its source CSV `from`, and its SVG); a
    /// skipped one is stated as `skip_label: why`, or left out when `skip_label` is None.
    pub(super) fn put(
        &mut self,
        file: String,
        o: Outcome,
        alt: &str,
        from: Option<&str>,
        skip_label: Option<&str>,
    ) -> Result<()> {
        match o {
            Outcome::Drawn { image, svg, caption, .. } => {
                png::write_png(&self.dir.join(&file), &image)?;
                let svg_file = svg_name(&file);
                crate::io::atomic::write(&self.dir.join(&svg_file), svg.as_bytes())?;
                let from = from.map(|f| format!(" (from [{f}]({}))", href(f))).unwrap_or_default();
                let _ =
                    writeln!(self.md, "![{alt}]({})\n\n*{caption}{from}* ([SVG]({}))\n", href(&file), href(&svg_file));
                self.made.push(file);
                self.made.push(svg_file);
            }
            Outcome::Skipped(why) => {
                if let Some(label) = skip_label {
                    let _ = writeln!(self.md, "{label}: {why}.\n");
                }
            }
        }
        Ok(())
    }
}

/// The results table (pivot, timing, the whole table), the rmse chart and the cost charts, the
/// ratios against the baseline; or a note that the experiment has not run.
pub(super) fn table_part(
    md: &mut String,
    drawn: &mut ChartsOut,
    s: &Section,
    dir: &Path,
    all: &[String],
) -> Result<()> {
    if all.iter().any(|f| f == "table.csv") {
        let t = CsvTable::read(&dir.join("table.csv"))?;
        let link = "table.csv".to_string();
        let _ = writeln!(md, "## Results\n\nFrom [table.csv]({}) ({} rows).\n", href(&link), t.rows.len());
        if let Some(p) = markdown::pivot(&t)? {
            md.push_str(&p);
        }
        if let Some(p) = markdown::timing_summary(&t)? {
            md.push_str(&p);
        }
        let _ = writeln!(
            md,
            "<details><summary>The whole table</summary>\n\n{}\n</details>\n",
            markdown::full_table(&t, &link)
        );
        let baseline = baselines(s);
        let baseline: Vec<&str> = baseline.iter().map(String::as_str).collect();
        drawn.put(
            "chart_rmse.png".into(),
            charts::rmse_dots(&t, &format!("{}: RMSE per encoder and map", s.name), &baseline)?,
            "rmse per encoder and map",
            None,
            Some("RMSE per encoder and map"),
        )?;
        if all.iter().any(|f| f == "summary.csv") {
            if let Some(p) = ratio_pivot(&CsvTable::read(&dir.join("summary.csv"))?)? {
                let _ = writeln!(
                    md,
                    "**Against the baseline** (from [summary.csv](summary.csv), per orientation and map there): {p}"
                );
            }
        }
        let per_point = |name: &str| per_point_scalars(s, name);
        let cx = charts::CostContext { per_point: &per_point, baseline: &baseline };
        for cost in charts::Cost::ALL {
            drawn.put(
                cost.file().into(),
                charts::error_vs_cost(&t, cost, &format!("{}: error against {}", s.name, cost.what()), &cx)?,
                &format!("Error against {}", cost.what()),
                None,
                Some(format!("Error against {}", cost.what()).as_str()),
            )?;
        }
    } else if s.exp.is_some() {
        let _ = writeln!(md, "No `table.csv` here yet (run `probelab run experiments/{}.toml`).\n", s.name);
    }
    Ok(())
}

/// The baselines a section's charts compare against, in order of preference: the experiment's
/// `[summary] baseline`, then the program's ([`crate::encoders::BASELINE`]).
fn baselines(s: &Section) -> Vec<String> {
    let declared = s.exp.as_ref().and_then(|e| e.summary.clone().flatten());
    declared.into_iter().chain([crate::encoders::BASELINE.to_string()]).collect()
}

/// The scalars the encoder `name` of a section's experiment keeps per shaded point beside its
/// probe (a cone, an AO term): its `Encoder::scalars_per_point` for a fit on the experiment's
/// domain and cone. 0 for an encoder with nothing per point, or outside an experiment.
pub(super) fn per_point_scalars(s: &Section, name: &str) -> usize {
    use crate::pipeline::experiment::{DomainKind, Effect};
    let Some(exp) = &s.exp else { return 0 };
    let Some(n) = exp.encoders.iter().find(|n| n.name == name) else { return 0 };
    let sh = crate::math::sh::Sh9::ZERO;
    let cone = exp.effects.iter().find_map(|e| match e {
        Effect::Cone { cos_alpha, .. } => Some((glam::DVec3::Y, cos_alpha.first().copied().unwrap_or(0.0))),
        _ => None,
    });
    let input = crate::encoders::FitInput {
        probe_sh: &sh,
        visible_sh: &sh,
        surface_normal: (exp.domain == DomainKind::Hemisphere).then_some(glam::DVec3::Y),
        cone,
        exact_at_normal: None,
        surface_albedo: None,
        radiance: None,
    };
    n.encoder.scalars_per_point(&input)
}

/// The charts of the folder's sweep and blending CSVs.
pub(super) fn csv_charts(drawn: &mut ChartsOut, dir: &Path, all: &[String]) -> Result<()> {
    for f in all.iter().filter(|f| f.ends_with(".csv")) {
        let stem = f.trim_end_matches(".csv");
        let t = CsvTable::read(&dir.join(f))?;
        if charts::is_sweep(&t) {
            for (knob, o) in charts::sweep_charts(&t)? {
                let file = format!("chart_{}_{}.png", file_safe(stem), file_safe(&knob));
                drawn.put(file, o, &format!("sweep {knob}"), Some(f), Some(f))?;
            }
        } else if charts::is_blend(&t) {
            for (set, o) in charts::blend_charts(&t)? {
                let file = if set.is_empty() {
                    format!("chart_{}.png", file_safe(stem))
                } else {
                    format!("chart_{}_{}.png", file_safe(stem), file_safe(&set))
                };
                drawn.put(file, o, "blending", Some(f), None)?;
            }
        }
    }
    Ok(())
}
