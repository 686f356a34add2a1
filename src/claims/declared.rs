//! Declared claims, judged: each [`ClaimSpec`] an experiment file declares (`[[claims]]`,
//! validated by [`crate::pipeline::claim_spec`]) is checked on the table's rows — `ratio` (the
//! encoder's column over its baseline's on matched rows), `equal` (two encoders agree to a
//! relative tolerance), `at_most` / `at_least` (the column against an absolute bound) — and
//! written as `claims.csv` and `CLAIMS.md` beside `table.csv`. Rows are visited in table order,
//! so the files are deterministic.

use crate::pipeline::claim_spec::{Check, ClaimSpec};
use crate::pipeline::summary::{distinct, match_key, mean_worst, median, ratio};
use crate::pipeline::table::{num, Row};
use anyhow::Result;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

/// A pair of matched values (encoder, baseline) with the row they describe.
struct Pair<'a> {
    row: &'a Row,
    a: f64,
    b: f64,
}

/// Matched (encoder, baseline) values of the claim's column on every row of its encoder (in
/// table order) that passes its filters and has a baseline row.
fn pairs<'a>(rows: &'a [Row], c: &ClaimSpec) -> Vec<Pair<'a>> {
    let base: HashMap<_, &Row> = rows.iter().filter(|r| r.encoder == c.baseline).map(|r| (match_key(r), r)).collect();
    rows.iter()
        .filter(|r| c.selects(r))
        .filter_map(|r| {
            let b = base.get(&match_key(r))?;
            Some(Pair { row: r, a: c.column.get(r)?, b: c.column.get(b)? })
        })
        .collect()
}

/// The outcome of one claim: our figure, whether it holds (`yes`, `no`, `partly (k/n rows)`,
/// `not measured`) and the number of rows it was judged on.
pub struct Outcome {
    pub figure: String,
    pub holds: String,
    pub rows: usize,
}

/// Counts of failing rows by a label, largest first (ties in first-appearance order).
fn fail_counts<'a>(fails: &[&'a Row], label: impl Fn(&'a Row) -> &'a str) -> Vec<(&'a str, usize)> {
    let mut v: Vec<(&str, usize)> = Vec::new();
    for r in fails {
        let l = label(r);
        match v.iter_mut().find(|e| e.0 == l) {
            Some(e) => e.1 += 1,
            None => v.push((l, 1)),
        }
    }
    v.sort_by_key(|e| std::cmp::Reverse(e.1));
    v
}

fn top(v: &[(&str, usize)], n: usize) -> String {
    let mut s: Vec<String> = v.iter().take(n).map(|(l, c)| format!("{l} ({c})")).collect();
    if v.len() > n {
        s.push(format!("+{} more", v.len() - n));
    }
    s.join(", ")
}

/// Judges one declared claim on a table's rows.
pub fn check(c: &ClaimSpec, rows: &[Row]) -> Outcome {
    match c.check {
        Check::AtMost { bound } => check_bound(c, rows, bound, true),
        Check::AtLeast { bound } => check_bound(c, rows, bound, false),
        Check::Ratio { .. } | Check::Equal { .. } => check_pairs(c, rows),
    }
}

/// `ratio` and `equal`: the claim's encoder against its baseline on matched rows.
fn check_pairs(c: &ClaimSpec, rows: &[Row]) -> Outcome {
    let p = pairs(rows, c);
    if p.is_empty() {
        return Outcome {
            figure: format!("no rows of '{}' matched to '{}'", c.encoder, c.baseline),
            holds: "not measured".into(),
            rows: 0,
        };
    }
    let col = c.column.name();
    match c.check {
        Check::Equal { tolerance, abs_tolerance } => {
            // The worst relative difference among rows above the absolute floor.
            let (mut worst_rel, mut worst_abs, mut failing) = (None::<(f64, usize)>, 0.0f64, 0);
            for (i, q) in p.iter().enumerate() {
                let r = q.row;
                let ref_rms = if r.scores.rel_rmse > 0.0 { r.scores.rmse / r.scores.rel_rmse } else { 0.0 };
                let scale = q.a.abs().max(q.b.abs()).max(ref_rms);
                let d = (q.a - q.b).abs();
                worst_abs = worst_abs.max(d);
                if d <= abs_tolerance {
                    continue;
                }
                let rel = if scale > 0.0 { d / scale } else { f64::MAX };
                if worst_rel.is_none_or(|w| rel > w.0) {
                    worst_rel = Some((rel, i));
                }
                if rel > tolerance {
                    failing += 1;
                }
            }
            let rel_text = match worst_rel {
                Some((rel, i)) => {
                    let r = p[i].row;
                    format!(
                        "largest difference {} relative to max(|a|, |b|, reference RMS) (at {} {} {})",
                        num(rel),
                        r.map,
                        r.domain,
                        r.effects
                    )
                }
                None => "every difference is below the absolute floor".to_string(),
            };
            Outcome {
                figure: format!(
                    "{col}: {rel_text}, largest absolute {}, over {} rows; tolerance {} (absolute floor {}){}",
                    num(worst_abs),
                    p.len(),
                    num(tolerance),
                    num(abs_tolerance),
                    if failing > 0 { format!("; {failing} row(s) outside") } else { String::new() }
                ),
                holds: if failing == 0 { "yes".into() } else { "no".into() },
                rows: p.len(),
            }
        }
        // Not reached through `check`, which sends these to `check_bound`.
        Check::AtMost { .. } | Check::AtLeast { .. } => check(c, rows),
        Check::Ratio { threshold, every } => {
            let mut v = Vec::new();
            let mut fails: Vec<&Row> = Vec::new();
            let mut undefined = 0;
            for q in &p {
                match ratio(q.a, q.b) {
                    Some(x) => {
                        v.push(x);
                        if x >= threshold {
                            fails.push(q.row);
                        }
                    }
                    None => {
                        undefined += 1;
                        fails.push(q.row);
                    }
                }
            }
            let (mean, worst, wi) = if v.is_empty() { (0.0, 0.0, 0) } else { mean_worst(&v) };
            let worst_row = p.iter().filter(|q| ratio(q.a, q.b).is_some()).nth(wi).map(|q| q.row);
            let pass = p.len() - fails.len();
            let mut figure = format!(
                "{col} ratio {} / {}: mean {}, median {}, worst {}{}; < {} in {}/{} rows",
                c.encoder,
                c.baseline,
                fmt3(mean),
                fmt3(if v.is_empty() { 0.0 } else { median(&v) }),
                fmt3(worst),
                worst_row.map(|r| format!(" ({} {} {})", r.map, r.domain, r.effects)).unwrap_or_default(),
                fmt3(threshold),
                pass,
                p.len()
            );
            if undefined > 0 {
                figure += &format!(" ({undefined} with a zero baseline counted as failing)");
            }
            if !fails.is_empty() && pass > 0 {
                figure += &format!(
                    "; fails at orientations {}; maps {}",
                    top(&fail_counts(&fails, |r| r.domain.as_str()), 6),
                    top(&fail_counts(&fails, |r| r.map.as_str()), 6)
                );
                if c.effects.is_none() && distinct(p.iter().map(|q| q.row.effects.as_str())).len() > 1 {
                    figure += &format!("; effects {}", top(&fail_counts(&fails, |r| r.effects.as_str()), 6));
                }
            }
            let holds = if every {
                if fails.is_empty() {
                    "yes".to_string()
                } else if pass == 0 {
                    "no".to_string()
                } else {
                    format!("partly ({pass}/{} rows)", p.len())
                }
            } else if mean < threshold && undefined == 0 {
                "yes".to_string()
            } else {
                "no".to_string()
            };
            Outcome { figure, holds, rows: p.len() }
        }
    }
}

/// `at_most` (`upper`) or `at_least`: the claim's column of its encoder against `bound` on
/// every selected row; a NaN fails either way.
fn check_bound(c: &ClaimSpec, rows: &[Row], bound: f64, upper: bool) -> Outcome {
    let v: Vec<(&Row, f64)> =
        rows.iter().filter(|r| c.selects(r)).filter_map(|r| Some((r, c.column.get(r)?))).collect();
    if v.is_empty() {
        return Outcome {
            figure: format!("no rows of '{}' with a {} value", c.encoder, c.column.name()),
            holds: "not measured".into(),
            rows: 0,
        };
    }
    let passes = |x: f64| if upper { x <= bound } else { x >= bound };
    let fails: Vec<&Row> = v.iter().filter(|(_, x)| !passes(*x)).map(|(r, _)| *r).collect();
    // The extreme towards failing: the largest value for at_most, the smallest for at_least
    // (a NaN is the most failing of all).
    let worse = |x: f64, y: f64| x.is_nan() || (!y.is_nan() && if upper { x > y } else { x < y });
    let (mut worst, mut best) = (v[0], v[0]);
    for &q in &v[1..] {
        if worse(q.1, worst.1) {
            worst = q;
        }
        if worse(best.1, q.1) {
            best = q;
        }
    }
    let at = |r: &Row| format!("{} {} {}", r.map, r.domain, r.effects);
    let (hi, lo) = if upper { ("largest", "smallest") } else { ("smallest", "largest") };
    let pass = v.len() - fails.len();
    let mut figure = format!(
        "{} of {}: {hi} {} ({}), {lo} {}; {} {} in {}/{} rows",
        c.column.name(),
        c.encoder,
        fmt3(worst.1),
        at(worst.0),
        fmt3(best.1),
        if upper { "<=" } else { ">=" },
        num(bound),
        pass,
        v.len()
    );
    if !fails.is_empty() && pass > 0 {
        figure += &format!(
            "; fails at orientations {}; maps {}",
            top(&fail_counts(&fails, |r| r.domain.as_str()), 6),
            top(&fail_counts(&fails, |r| r.map.as_str()), 6)
        );
    }
    let holds = if fails.is_empty() {
        "yes".to_string()
    } else if pass == 0 {
        "no".to_string()
    } else {
        format!("partly ({pass}/{} rows)", v.len())
    };
    Outcome { figure, holds, rows: v.len() }
}

/// Three significant digits.
fn fmt3(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return num(x);
    }
    let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    if digits > 6 {
        format!("{x:.2e}")
    } else {
        format!("{x:.digits$}")
    }
}

/// `claims.csv`.
pub fn claims_csv(experiment: &str, claims: &[ClaimSpec], outcomes: &[Outcome]) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["id", "claim", "paper_figure", "our_figure", "holds", "check", "experiment", "rows"])?;
    for (c, o) in claims.iter().zip(outcomes) {
        let mut check = match c.check {
            Check::Ratio { threshold, every } => {
                format!("ratio {} < {} ({})", c.column.name(), num(threshold), if every { "every row" } else { "mean" })
            }
            Check::Equal { tolerance, abs_tolerance } => {
                format!("equal {} (rel. tol. {}, abs. {})", c.column.name(), num(tolerance), num(abs_tolerance))
            }
            Check::AtMost { bound } => format!("{} <= {} (every row)", c.column.name(), num(bound)),
            Check::AtLeast { bound } => format!("{} >= {} (every row)", c.column.name(), num(bound)),
        };
        if let Some(e) = &c.effects {
            check += &format!("; effects {e}");
        }
        if let Some(m) = &c.maps {
            check += &format!("; maps {}", m.join(", "));
        }
        w.write_record([
            c.id.as_str(),
            &c.claim,
            &c.paper,
            &o.figure,
            &o.holds,
            &check,
            experiment,
            &o.rows.to_string(),
        ])?;
    }
    w.into_inner().map_err(|e| anyhow::anyhow!("csv: {e}"))
}

/// Markdown-safe cell text.
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// `CLAIMS.md`: what the figures are, the claims table, then for each ratio claim its
/// breakdown by effects and orientation set, by orientation (sets of up to 8), and by map.
pub fn claims_md(
    name: &str,
    description: &str,
    rows: &[Row],
    claims: &[ClaimSpec],
    outcomes: &[Outcome],
) -> Result<String> {
    let mut s = String::new();
    writeln!(s, "# Claims checked by `{name}`\n")?;
    writeln!(s, "Generated by `probelab run experiments/{name}.toml`; do not edit. {description}\n")?;
    let list = |f: fn(&Row) -> &str| distinct(rows.iter().map(f)).join(", ");
    writeln!(
        s,
        "Every figure is an error of E/π (units `{}`), weighting `{}`, output grid `{}`, reference `{}`, \
         effects `{}`, domains `{}` (orientation sets `{}`), on maps {}.\n",
        list(|r| &r.units),
        list(|r| &r.weighting),
        list(|r| &r.resolution),
        list(|r| &r.reference),
        list(|r| &r.effects),
        if distinct(rows.iter().map(|r| r.domain.as_str())).len() > 8 {
            format!("{} distinct", distinct(rows.iter().map(|r| r.domain.as_str())).len())
        } else {
            list(|r| &r.domain)
        },
        list(|r| &r.orientation_set),
        list(|r| &r.map)
    )?;
    writeln!(s, "| id | claim | paper figure | our figure | holds |")?;
    writeln!(s, "|---|---|---|---|---|")?;
    for (c, o) in claims.iter().zip(outcomes) {
        writeln!(s, "| {} | {} | {} | {} | {} |", c.id, cell(&c.claim), cell(&c.paper), cell(&o.figure), o.holds)?;
    }
    for c in claims.iter().filter(|c| c.note.is_some()) {
        writeln!(s, "\n- **{}**: {}", c.id, c.note.as_deref().unwrap_or_default())?;
    }
    for c in claims {
        let Check::Ratio { threshold, .. } = c.check else { continue };
        let p = pairs(rows, c);
        if p.is_empty() {
            continue;
        }
        writeln!(
            s,
            "\n## {}: {} ratio {} / {} (passes below {})\n",
            c.id,
            c.column.name(),
            c.encoder,
            c.baseline,
            fmt3(threshold)
        )?;
        let table = |s: &mut String, title: &str, sel: &dyn Fn(&Row) -> String| -> Result<()> {
            let labels: Vec<String> = {
                let mut v: Vec<String> = Vec::new();
                for q in &p {
                    let l = sel(q.row);
                    if !v.contains(&l) {
                        v.push(l);
                    }
                }
                v
            };
            writeln!(
                s,
                "| {title} | rows | mean ratio | median | worst ratio | worst at | below {} |",
                fmt3(threshold)
            )?;
            writeln!(s, "|---|---|---|---|---|---|---|")?;
            for l in labels {
                let sub: Vec<(f64, &Row)> =
                    p.iter().filter(|q| sel(q.row) == l).filter_map(|q| ratio(q.a, q.b).map(|x| (x, q.row))).collect();
                if sub.is_empty() {
                    continue;
                }
                let v: Vec<f64> = sub.iter().map(|x| x.0).collect();
                let (m, wv, wi) = mean_worst(&v);
                let below = v.iter().filter(|&&x| x < threshold).count();
                let wr = sub[wi].1;
                writeln!(
                    s,
                    "| {} | {} | {} | {} | {} | {} {} | {}/{} |",
                    cell(&l),
                    v.len(),
                    fmt3(m),
                    fmt3(median(&v)),
                    fmt3(wv),
                    wr.map,
                    wr.domain,
                    below,
                    v.len()
                )?;
            }
            writeln!(s)?;
            Ok(())
        };
        table(&mut s, "effects, orientation set", &|r| format!("{}, {}", r.effects, r.orientation_set))?;
        let small_sets: Vec<&str> = distinct(p.iter().map(|q| q.row.orientation_set.as_str()))
            .into_iter()
            .filter(|set| {
                distinct(p.iter().filter(|q| q.row.orientation_set == *set).map(|q| q.row.domain.as_str())).len() <= 8
            })
            .collect();
        if !small_sets.is_empty() {
            let sets = small_sets.clone();
            table(&mut s, "orientation (sets of up to 8)", &move |r| {
                if sets.contains(&r.orientation_set.as_str()) {
                    format!("{} ({})", r.domain, r.orientation_set)
                } else {
                    "other sets".into()
                }
            })?;
        }
        table(&mut s, "map", &|r| r.map.clone())?;
    }
    Ok(s)
}

/// Writes `claims.csv` and `CLAIMS.md` into `dir` when the experiment declares claims; returns
/// the names of the files written (none without claims).
pub fn write(dir: &Path, name: &str, description: &str, claims: &[ClaimSpec], rows: &[Row]) -> Result<Vec<String>> {
    if claims.is_empty() {
        return Ok(Vec::new());
    }
    let outcomes: Vec<Outcome> = claims.iter().map(|c| check(c, rows)).collect();
    crate::pipeline::atomic::write(&dir.join("claims.csv"), &claims_csv(name, claims, &outcomes)?)?;
    crate::pipeline::atomic::write(
        &dir.join("CLAIMS.md"),
        claims_md(name, description, rows, claims, &outcomes)?.as_bytes(),
    )?;
    Ok(vec!["claims.csv".to_string(), "CLAIMS.md".to_string()])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::claim_spec::fixtures::{bounded, claim, maps};
    use crate::pipeline::claim_spec::ClaimFile;
    use crate::pipeline::summary::fixtures::rows;

    #[test]
    fn ratio_claims_count_rows_and_name_failures() {
        let o = check(&claim("ratio", ""), &rows());
        // Ratios: 0.5, 1.5, 0.25, 0/0 = 1 (a tie fails "< 1").
        assert_eq!(o.rows, 4);
        assert_eq!(o.holds, "partly (2/4 rows)");
        assert!(o.figure.contains("mean 0.812, median 0.750, worst 1.50 (m1 hemisphere:+y"), "{}", o.figure);
        assert!(o.figure.contains("fails at orientations hemisphere:+y (2)"), "{}", o.figure);
        let mean = check(&claim("ratio", "statistic='mean'\nthreshold=0.9"), &rows());
        assert_eq!(mean.holds, "yes");
        let all = check(&claim("ratio", "threshold=2"), &rows());
        assert_eq!(all.holds, "yes");
    }

    #[test]
    fn equal_claims_use_relative_tolerance() {
        assert_eq!(check(&claim("equal", ""), &rows()).holds, "no");
        // A copy of op under another name, off by 1e-13 relative: equal at 1e-12, not at 1e-14.
        let mut t = rows();
        t.extend(rows().into_iter().filter(|x| x.encoder == "op").map(|mut x| {
            x.encoder = "dup".into();
            x.scores.rmse *= 1.0 + 1e-13;
            x
        }));
        let enc = ["op".to_string(), "dup".to_string()];
        let c = |tol: &str| {
            let f: ClaimFile = toml::from_str(&format!(
                "id='e'\nclaim='x'\ncheck='equal'\nencoder='op'\nbaseline='dup'\ntolerance={tol}\nabs_tolerance=1e-15"
            ))
            .unwrap();
            ClaimSpec::from_file(f, &enc, &maps()).unwrap()
        };
        let o = check(&c("1e-12"), &t);
        assert_eq!((o.holds.as_str(), o.rows), ("yes", 4), "{}", o.figure);
        assert_eq!(check(&c("1e-14"), &t).holds, "no");
        // Differences below the absolute floor pass whatever their relative size (errors at
        // rounding level): op = 1e-16 vs dup = 2e-16.
        let tiny: Vec<Row> = t
            .iter()
            .cloned()
            .map(|mut x| {
                x.scores.rmse = if x.encoder == "dup" { 2e-16 } else { 1e-16 };
                x.scores.rel_rmse = 1.0;
                x
            })
            .collect();
        assert_eq!(check(&c("1e-14"), &tiny).holds, "yes");
    }

    #[test]
    fn bound_claims_compare_each_row_with_the_bound() {
        // op's rmse: 1.0, 1.5 (m1), 1.0, 0.0 (m2).
        let o = check(&bounded("at_most", "bound=1.5"), &rows());
        assert_eq!((o.holds.as_str(), o.rows), ("yes", 4), "{}", o.figure);
        assert!(
            o.figure.contains("rmse of op: largest 1.50 (m1 hemisphere:+y hemisphere), smallest 0"),
            "{}",
            o.figure
        );
        assert!(o.figure.contains("<= 1.5 in 4/4 rows"), "{}", o.figure);
        // Just below the largest value: that row fails.
        let o = check(&bounded("at_most", "bound=1.4999999"), &rows());
        assert_eq!(o.holds, "partly (3/4 rows)", "{}", o.figure);
        assert!(o.figure.contains("fails at orientations hemisphere:+y (1); maps m1 (1)"), "{}", o.figure);
        assert_eq!(check(&bounded("at_most", "bound=0"), &rows()).holds, "partly (1/4 rows)");
        // at_least: the zero row fails a positive bound and passes bound 0; the smallest value is named.
        let o = check(&bounded("at_least", "bound=1"), &rows());
        assert_eq!(o.holds, "partly (3/4 rows)", "{}", o.figure);
        assert!(o.figure.contains("smallest 0 (m2 hemisphere:+y hemisphere), largest 1.50"), "{}", o.figure);
        assert_eq!(check(&bounded("at_least", "bound=0"), &rows()).holds, "yes");
        assert_eq!(check(&bounded("at_least", "bound=2"), &rows()).holds, "no");
        // Another column.
        let mut t = rows();
        t[1].at_normal_abs_err = Some(3e-13);
        let o = check(&bounded("at_most", "bound=1e-12\ncolumn='at_normal_abs_err'\nmaps=['m1']"), &t);
        assert_eq!(o.holds, "partly (1/2 rows)", "{}", o.figure);
        // A NaN fails both checks.
        let mut t = rows();
        t[1].scores.rmse = f64::NAN;
        assert_eq!(check(&bounded("at_most", "bound=10"), &t).holds, "partly (3/4 rows)");
        assert_eq!(check(&bounded("at_least", "bound=0"), &t).holds, "partly (3/4 rows)");
    }

    #[test]
    fn maps_filter_selects_rows_by_table_name() {
        // m2 is listed as a path; rows name it by its stem. On m2 the ratios are 0.25 and the
        // 0/0 tie (1), so all pass below 1.01; on m1 they are 0.5 and 1.5.
        let on = |m: &str, thr: &str| check(&claim("ratio", &format!("maps=['{m}']\nthreshold={thr}")), &rows());
        let o = on("m2", "1.01");
        assert_eq!((o.holds.as_str(), o.rows), ("yes", 2), "{}", o.figure);
        let o = on("m1", "1");
        assert_eq!((o.holds.as_str(), o.rows), ("partly (1/2 rows)", 2), "{}", o.figure);
        // By its path as written in the experiment, too.
        assert_eq!(on("dir/m2.exr", "1.01").rows, 2);
        let o = check(&bounded("at_most", "bound=1\nmaps=['m2']"), &rows());
        assert_eq!((o.holds.as_str(), o.rows), ("yes", 2), "{}", o.figure);
        let c = claim("ratio", "maps=['m2']");
        let csv = String::from_utf8(claims_csv("e", std::slice::from_ref(&c), &[check(&c, &rows())]).unwrap()).unwrap();
        assert!(csv.contains("ratio rmse < 1 (every row); maps m2"), "{csv}");
        // CLAIMS.md breaks the claim down over the selected map only.
        let md = claims_md("e", "", &rows(), std::slice::from_ref(&c), &[check(&c, &rows())]).unwrap();
        let breakdown = &md[md.find("## c:").unwrap()..];
        assert!(breakdown.contains("| m2 |") && !breakdown.contains("| m1 |"), "{md}");
    }
}
