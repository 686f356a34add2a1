//! The charts' unit tests: ticks, the Pareto front, label placement, legends, every chart as
//! pixels and as a well-formed SVG with the full names.

use super::super::csvfile::CsvTable;
use super::super::text::text_width;
use super::axes::*;
use super::blending::*;
use super::cost::*;
use super::dots::*;
use super::draw::*;
use super::lines::*;
use super::rows::*;
use super::sweeps::*;
use crate::report::style::style_of;
use std::path::Path;

fn csv(s: &str) -> CsvTable {
    CsvTable::parse(Path::new("t.csv"), s.as_bytes()).unwrap()
}

#[test]
fn tick_labels_are_short() {
    assert_eq!(tick(0.01), "0.01");
    assert_eq!(tick(1.0), "1");
    assert_eq!(tick(2.5), "2.5");
    assert_eq!(tick(1e-6), "1e-6");
    assert_eq!(tick(1e5), "1e5");
}

#[test]
fn pareto_front_by_hand() {
    // (time, error): b dominates d; a is fastest; c is the most accurate.
    let p = [(1.0, 5.0), (2.0, 3.0), (10.0, 1.0), (3.0, 4.0), (20.0, 1.0)];
    assert_eq!(pareto_front(&p), vec![0, 1, 2]);
    assert_eq!(pareto_front(&[]), Vec::<usize>::new());
}

#[test]
fn pareto_front_of_a_constructed_storage_set() {
    // (stored scalars, error), as an encoder landscape would give, worked by hand:
    //  0 (3, 0.9)   cheapest: on the front
    //  1 (12, 0.5)  dominated by 2 (same cost, lower error)
    //  2 (12, 0.3)  on: nothing at ≤ 12 scalars is below 0.3
    //  3 (12, 0.3)  equal to 2: both on (neither is strictly better)
    //  4 (15, 0.35) dominated by 2 (cheaper and more accurate)
    //  5 (15, 0.2)  on
    //  6 (27, 0.2)  dominated by 5 (same error, cheaper)
    //  7 (27, 0.05) on
    //  8 (75, 0.06) dominated by 7
    // Expected front by cost: 0, 2, 3, 5, 7 (1 is dominated by 2).
    let p = [
        (3.0, 0.9),
        (12.0, 0.5),
        (12.0, 0.3),
        (12.0, 0.3),
        (15.0, 0.35),
        (15.0, 0.2),
        (27.0, 0.2),
        (27.0, 0.05),
        (75.0, 0.06),
    ];
    assert_eq!(pareto_front(&p), vec![0, 2, 3, 5, 7]);
    // Brute force agrees: a point is on the front iff no other dominates it.
    let dominated = |i: usize| {
        p.iter().enumerate().any(|(j, q)| j != i && q.0 <= p[i].0 && q.1 <= p[i].1 && (q.0 < p[i].0 || q.1 < p[i].1))
    };
    let brute: Vec<usize> = (0..p.len()).filter(|&i| !dominated(i)).collect();
    assert_eq!(brute, vec![0, 2, 3, 5, 7]);
}

fn no_per_point(_: &str) -> usize {
    0
}

#[test]
fn cost_charts_read_any_encoder_set() {
    // Encoders with made-up names: costs by column name, bytes only where `diagnostics`
    // has them, eval time per encoder the median of its rows; y the geometric mean over the
    // maps of the RMSE relative to the baseline p.
    let t = csv("map,encoder,metric,rmse,stored_scalars,diagnostics,fit_ns,eval_ns\n\
         a,p,exact,0.5,12,,10,4\nb,p,exact,0.7,12,,10,6\na,q,exact,0.2,27,,20,9\nb,q,exact,0.2,27,,20,9\n\
         a,r,exact,0.6,12,bytes=13;x=1,30,3\nb,r,exact,0.6,12,bytes=13;x=1,30,3\n\
         a,s,exact,0.3,27,bytes=28,30,3\nb,s,exact,0.3,27,bytes=28,30,3\n");
    let cx = CostContext { per_point: &no_per_point, baseline: &["p"] };
    let (pts, names, base) = cost_points(&t, Cost::StoredScalars, &cx).unwrap();
    assert_eq!(names, ["p", "q", "r", "s"]);
    assert_eq!(base, "p");
    // By hand: q = sqrt(0.2/0.5 · 0.2/0.7), r = sqrt(0.6/0.5 · 0.6/0.7), s = sqrt(0.3/0.5 · 0.3/0.7).
    let want = [
        (12.0, 1.0),
        (27.0, (0.4f64 * 0.2 / 0.7).sqrt()),
        (12.0, (1.2f64 * 0.6 / 0.7).sqrt()),
        (27.0, (0.6f64 * 0.3 / 0.7).sqrt()),
    ];
    for (p, w) in pts.iter().zip(want) {
        assert!(p.0 == w.0 && (p.1 - w.1).abs() < 1e-12, "{p:?} {w:?}");
    }
    assert_eq!(pareto_front(&pts), vec![0, 1]);
    let (pts, names, _) = cost_points(&t, Cost::Bytes, &cx).unwrap();
    assert_eq!(names, ["r", "s"]);
    assert_eq!((pts[0].0, pts[1].0), (13.0, 28.0));
    // Eval: p's median of {4, 6} is the upper middle (6); r and s share 3 ns, s is better.
    let (pts, _, _) = cost_points(&t, Cost::EvalNs, &cx).unwrap();
    assert_eq!(pts[0], (6.0, 1.0));
    assert_eq!(pareto_front(&pts), vec![3, 1]);
    for c in Cost::ALL {
        match error_vs_cost(&t, c, "x", &cx).unwrap() {
            Outcome::Drawn { caption, .. } => {
                assert!(caption.contains("Pareto front") && caption.contains("`p`"), "{caption}")
            }
            Outcome::Skipped(s) => panic!("{c:?}: {s}"),
        }
    }
    match error_vs_cost(&t, Cost::Bytes, "x", &cx).unwrap() {
        Outcome::Drawn { caption, .. } => assert!(caption.contains("2 encoder(s) without this cost"), "{caption}"),
        Outcome::Skipped(s) => panic!("{s}"),
    }
    // What an encoder keeps per shaded point is added to what it stores per probe.
    let q_cone = |n: &str| if n == "q" { 4 } else { 0 };
    let with_cone = CostContext { per_point: &q_cone, baseline: &["p"] };
    let (pts, _, _) = cost_points(&t, Cost::StoredScalars, &with_cone).unwrap();
    assert_eq!(pts[1].0, 31.0);
    let plain = csv("map,encoder,metric,rmse,stored_scalars,diagnostics\na,p,exact,0.5,12,\n");
    assert!(
        matches!(error_vs_cost(&plain, Cost::Bytes, "x", &cx).unwrap(), Outcome::Skipped(s) if s.contains("quantised"))
    );
    assert!(
        matches!(error_vs_cost(&plain, Cost::EvalNs, "x", &cx).unwrap(), Outcome::Skipped(s) if s.contains("eval_ns"))
    );
}

/// Every encoder storing the same: the chart is not drawn and says why.
#[test]
fn a_constant_cost_chart_is_not_drawn() {
    let t = csv("map,encoder,metric,rmse,stored_scalars\na,p,exact,0.5,27\na,q,exact,0.2,27\na,r,exact,0.3,27\n");
    let cx = CostContext { per_point: &no_per_point, baseline: &["p"] };
    match error_vs_cost(&t, Cost::StoredScalars, "x", &cx).unwrap() {
        Outcome::Skipped(why) => assert!(why.contains("the same") && why.contains("27"), "{why}"),
        Outcome::Drawn { .. } => panic!("a chart of one x drawn"),
    }
    // With per-point storage the costs differ again, and the chart is drawn.
    let cone = |n: &str| if n == "q" { 4 } else { 0 };
    let cx = CostContext { per_point: &cone, baseline: &["p"] };
    assert!(matches!(error_vs_cost(&t, Cost::StoredScalars, "x", &cx).unwrap(), Outcome::Drawn { .. }));
}

/// A cluster of points as the ZH3 table's time chart has (eight encoders within 40 px, one
/// at the right edge): every box is inside the plot and no two overlap (checked pairwise from
/// the returned layout), and the right-edge label went left of its point.
#[test]
fn labels_never_overlap_or_leave_the_plot() {
    let plot = (70, 40, 800, 500);
    let pts = [
        (290, 215),
        (295, 232),
        (300, 245),
        (305, 240),
        (310, 250),
        (288, 262),
        (292, 268),
        (297, 230),
        (760, 250),
        (680, 283),
        (720, 290),
        (150, 245),
        (190, 365),
        (200, 195),
    ];
    let widths: Vec<u32> = (0..pts.len()).map(|i| 100 + 10 * i as u32).collect();
    let dots: Vec<_> = pts.iter().map(|&(x, y)| (x - 6, y - 6, x + 6, y + 6)).collect();
    let boxes = place_labels(&pts, &widths, 14, plot, &dots);
    for (i, b) in boxes.iter().enumerate() {
        assert!(b.0 >= plot.0 && b.1 >= plot.1 && b.2 <= plot.2 && b.3 <= plot.3, "label {i} {b:?} leaves the plot");
        assert_eq!((b.2 - b.0) as u32, widths[i], "label {i} shortened");
        for (j, c) in boxes.iter().enumerate().skip(i + 1) {
            let overlap = b.0 < c.2 && c.0 < b.2 && b.1 < c.3 && c.1 < b.3;
            assert!(!overlap, "labels {i} {b:?} and {j} {c:?} overlap");
        }
        for (j, d) in dots.iter().enumerate() {
            let over = b.0 < d.2 && d.0 < b.2 && b.1 < d.3 && d.1 < b.3;
            assert!(!over, "label {i} {b:?} covers point {j} {d:?}");
        }
    }
    assert!(boxes[8].2 <= pts[8].0, "the label of the right-edge point is left of it: {:?}", boxes[8]);
}

#[test]
fn dots_average_cases_and_read_columns_by_name() {
    let t = csv("rmse,encoder,map,metric\n0.5,sh1,a,exact\n0.25,sh1,a,exact\n9,sh1,a,probulator\n0.1,sh2,a,exact\n");
    let (rows, m) = metric_rows(&t);
    assert_eq!(m.as_deref(), Some("exact"));
    let (_, encs, mean, k) = mean_rmse(&t, &rows).unwrap();
    assert_eq!(encs, vec!["sh1", "sh2"]);
    assert_eq!(mean[0][0], Some(0.375));
    assert_eq!(k, 2);
    assert!(
        matches!(rmse_dots(&t, "x", &[]).unwrap(), Outcome::Drawn { caption, .. } if caption.contains("mean over the 2"))
    );
}

#[test]
fn blend_csv_of_the_lightmap_study() {
    // Luminance at N per method, the reference in its own column, sets by `pair`.
    let b = csv("pair,method,t,rmse,luma_at_normal,reference_luma_at_normal\np,ahd,0,0,1,1\np,ahd,0.5,0.1,1.5,1.1\n\
         p,ahd,1,0,1.2,1.2\np,sh2,0,0,1,1\np,sh2,0.5,0.05,1.1,1.1\np,sh2,1,0,1.2,1.2\n");
    let charts = blend_charts(&b).unwrap();
    assert_eq!(charts.len(), 1);
    assert_eq!(charts[0].0, "p");
    match &charts[0].1 {
        Outcome::Drawn { caption, .. } => {
            assert!(caption.contains("ahd: overshoot 0.300"), "{caption}");
            assert!(caption.contains("sh2: overshoot 0") && caption.contains("reference: overshoot 0"), "{caption}");
        }
        Outcome::Skipped(w) => panic!("{w}"),
    }
    assert!(blend_charts(&csv("t,method\n0,a\n")).unwrap_err().to_string().contains("irradiance_at_n_r"));
}

#[test]
fn knob_values_and_sweeps_without_a_label_column() {
    assert_eq!(knob_value("12"), Some(12.0));
    assert_eq!(knob_value("256x128"), Some(256.0));
    assert_eq!(knob_value("full"), None);
    assert_eq!(knob_value("NaN"), None);
    // The committed sweep format: series by map / encoder, W×H values, a `full` row.
    let s = csv("sweep,knob,value,map,encoder,rmse,time_ns\nr,res,32x16,m,sh1,0.2,10\nr,res,64x32,m,sh1,0.1,40\n\
         r,res,full,m,sh1,0.05,90\nr,res,32x16,m,reference,0.01,5\n");
    assert!(is_sweep(&s) && !is_sweep(&csv("knob,rmse\na,1\n")));
    let charts = sweep_charts(&s).unwrap();
    assert_eq!(charts.len(), 1);
    match &charts[0].1 {
        Outcome::Drawn { caption, .. } => {
            assert!(caption.contains("1 row(s) with a non-numeric value"), "{caption}")
        }
        Outcome::Skipped(w) => panic!("{w}"),
    }
}

/// The legend is in its own column right of the panels, so it cannot cover data: every
/// entry's box starts right of the panels and stays inside the image, no two overlap, and
/// the pixels right of the panels in a series' colour all lie inside the legend boxes (the
/// data, which fills the panels' upper right corner here, is drawn left of them).
#[test]
fn legends_are_beside_the_data() {
    let s = csv(
        "knob,value,rmse,time_ns,label\nk,1,0.001,10,a_long_series_name_one\nk,100,0.5,1000,a_long_series_name_one\n\
         k,1,0.002,10,two\nk,100,0.4,1000,two\n",
    );
    let charts = sweep_charts(&s).unwrap();
    let Outcome::Drawn { image, .. } = &charts[0].1 else { panic!("not drawn") };
    let series: Vec<Series> = ["a_long_series_name_one", "two"]
        .iter()
        .map(|l| Series { label: l.to_string(), style: style_of(l), dashed: false, points: vec![] })
        .collect();
    let boxes = legend_boxes(&series, 1200);
    for (i, b) in boxes.iter().enumerate() {
        assert!(b.0 >= 1200 && b.2 <= image.width() as i32 && b.3 <= image.height() as i32, "entry {i} {b:?}");
        for c in &boxes[i + 1..] {
            assert!(!(b.0 < c.2 && c.0 < b.2 && b.1 < c.3 && c.1 < b.3), "entries overlap: {b:?} {c:?}");
        }
    }
    let c0 = style_of("a_long_series_name_one").rgb;
    let c0 = (c0[0], c0[1], c0[2]);
    let (mut inside, mut outside, mut left) = (0, 0, 0);
    for (x, y, p) in image.enumerate_pixels() {
        if p.0 != [c0.0, c0.1, c0.2] {
            continue;
        }
        let (x, y) = (x as i32, y as i32);
        if x < 1200 {
            left += 1;
        } else if boxes.iter().any(|b| x >= b.0 && x < b.2 && y >= b.1 && y < b.3) {
            inside += 1;
        } else {
            outside += 1;
        }
    }
    assert!(
        left > 0 && inside > 0 && outside == 0,
        "series colour: {left} in panels, {inside} in legend, {outside} elsewhere"
    );
}

/// Same CSV, same bytes: drawing a sweep twice gives identical images (series in file
/// order, legend and labels from measured widths; nothing depends on hashing or threads).
#[test]
fn sweep_charts_are_deterministic() {
    let text = "knob,value,rmse,time_ns,label\nk,32,0.1,100,b\nk,64,0.02,400,b\nk,32,0.2,90,a\nk,64,0.05,300,a\n";
    let draw = || match sweep_charts(&csv(text)).unwrap().remove(0).1 {
        Outcome::Drawn { image, .. } => image.into_raw(),
        Outcome::Skipped(w) => panic!("{w}"),
    };
    assert!(draw() == draw());
}

/// Checks that `svg` is well-formed XML (every tag closed in order, attribute values
/// quoted, only the five predefined entities) and returns its root's `width`/`height`
/// and the text of every `<text>` element, unescaped.
fn parse_svg(svg: &str) -> ((u32, u32), Vec<String>) {
    let unescape = |t: &str| -> String {
        let mut out = String::new();
        let mut rest = t;
        while let Some(i) = rest.find('&') {
            out.push_str(&rest[..i]);
            let j = rest[i..].find(';').unwrap_or_else(|| panic!("unterminated entity in {t:?}"));
            out.push(match &rest[i..i + j + 1] {
                "&amp;" => '&',
                "&lt;" => '<',
                "&gt;" => '>',
                "&quot;" => '"',
                "&apos;" => '\'',
                e => panic!("unknown entity {e}"),
            });
            rest = &rest[i + j + 1..];
        }
        out + rest
    };
    let mut stack: Vec<String> = Vec::new();
    let (mut size, mut texts) = (None, Vec::new());
    let mut rest = svg.trim_start();
    if rest.starts_with("<?xml") {
        rest = &rest[rest.find("?>").expect("xml declaration closed") + 2..];
    }
    while let Some(lt) = rest.find('<') {
        let content = &rest[..lt];
        assert!(!content.contains('>'), "stray '>' in {content:?}");
        if stack.last().is_some_and(|t| t == "text") {
            // plotters writes the text on its own line; SVG's default whitespace handling
            // drops the newlines around it.
            texts.push(unescape(content.trim()));
        } else {
            let _ = unescape(content);
        }
        let gt = rest[lt..].find('>').expect("tag closed") + lt;
        let tag = &rest[lt + 1..gt];
        rest = &rest[gt + 1..];
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(stack.pop().as_deref(), Some(name.trim()), "closing tag out of order");
            continue;
        }
        let self_closing = tag.ends_with('/');
        let tag = tag.trim_end_matches('/');
        let name = tag.split_whitespace().next().expect("tag name").to_string();
        // Attributes: name="value" pairs, values without '<' or a bare '&'.
        let mut attrs = tag[name.len()..].trim();
        let mut found = Vec::new();
        while !attrs.is_empty() {
            let eq = attrs.find("=\"").unwrap_or_else(|| panic!("attribute without =\"…\" in <{tag}>"));
            let key = attrs[..eq].trim().to_string();
            let end = attrs[eq + 2..].find('"').expect("attribute value closed") + eq + 2;
            let value = &attrs[eq + 2..end];
            assert!(!value.contains('<'), "'<' in attribute {key}");
            found.push((key, unescape(value)));
            attrs = attrs[end + 1..].trim_start();
        }
        if name == "svg" && stack.is_empty() {
            let get = |k: &str| found.iter().find(|a| a.0 == k).map(|a| a.1.parse::<u32>().unwrap());
            size = Some((get("width").expect("width"), get("height").expect("height")));
        }
        if !self_closing {
            stack.push(name);
        }
    }
    assert!(stack.is_empty(), "unclosed tags {stack:?}");
    assert!(rest.trim().is_empty(), "text after the root element");
    (size.expect("an <svg> root"), texts)
}

#[test]
fn svg_checker_refuses_broken_documents() {
    let ok = r#"<svg width="3" height="2" viewBox="0 0 3 2"><text x="1">a &amp; b</text><rect x="0"/></svg>"#;
    assert_eq!(parse_svg(ok), ((3, 2), vec!["a & b".to_string()]));
    assert_eq!(parse_svg("<svg width=\"1\" height=\"1\"><text>\nx\n</text></svg>").1, ["x"]);
    for bad in [
        r#"<svg width="3" height="2"><text>a</svg>"#,
        r#"<svg width="3" height="2"><text>a & b</text></svg>"#,
        r#"<svg width="3" height="2"><g></text></g></svg>"#,
        r#"<svg width="3" height=2></svg>"#,
    ] {
        assert!(std::panic::catch_unwind(|| parse_svg(bad)).is_err(), "accepted {bad}");
    }
}

/// Every chart is also an SVG: well-formed, the same width and height as its PNG, with a
/// `<text>` element holding each encoder's (or series') full name — long ones and names
/// with XML's special characters included.
#[test]
fn every_chart_is_also_an_svg_with_the_full_names() {
    let names = ["zh3_hallucinate_sun_sky_windowed_long_name", "sh<2>&co", "hlsh"];
    let mut table = String::from("map,encoder,metric,rmse,stored_scalars,fit_ns,eval_ns\n");
    for (k, n) in names.iter().enumerate() {
        let n = format!("\"{n}\"");
        table += &format!("m1,{n},exact,{},{},{},{}\n", 0.1 / (k + 1) as f64, 9 * (k + 1), 10 * (k + 1), 3 + k);
        table += &format!("m2,{n},exact,{},{},{},{}\n", 0.2 / (k + 1) as f64, 9 * (k + 1), 10 * (k + 1), 3 + k);
    }
    let t = csv(&table);
    let mut drawn = vec![("dots".to_string(), rmse_dots(&t, "dots", &[]).unwrap())];
    let cx = CostContext { per_point: &no_per_point, baseline: &[] };
    for c in [Cost::StoredScalars, Cost::EvalNs, Cost::FitNs] {
        drawn.push((format!("{c:?}"), error_vs_cost(&t, c, "cost", &cx).unwrap()));
    }
    let mut sweep = String::from("knob,value,rmse,time_ns,label\n");
    let mut blend = String::from("t,method,irradiance_at_n_r,irradiance_at_n_g,irradiance_at_n_b,rmse\n");
    for n in names {
        sweep += &format!("k,1,0.5,10,\"{n}\"\nk,10,0.05,100,\"{n}\"\n");
        blend += &format!("0,\"{n}\",1,1,1,0\n0.5,\"{n}\",1.3,1.3,1.3,0.1\n1,\"{n}\",1.2,1.2,1.2,0\n");
    }
    drawn.extend(sweep_charts(&csv(&sweep)).unwrap());
    drawn.extend(blend_charts(&csv(&blend)).unwrap());
    assert_eq!(drawn.len(), 6);
    for (what, o) in drawn {
        let Outcome::Drawn { image, svg, .. } = o else { panic!("{what}: not drawn") };
        let (size, texts) = parse_svg(&svg);
        assert_eq!(size, image.dimensions(), "{what}: SVG size");
        for n in names {
            assert!(texts.iter().any(|t| t == n), "{what}: no <text> with the full name {n:?}: {texts:?}");
        }
    }
}

#[test]
fn sweep_and_blend_formats() {
    let s = csv("knob,value,rmse,time_ns,label\nref_res,32,0.1,100,grace\nref_res,64,0.02,400,grace\n\
         ref_res,128,0.004,1600,grace\niters,1,0.5,,hhd\niters,2,0.2,,hhd\n");
    let charts = sweep_charts(&s).unwrap();
    assert_eq!(charts.len(), 2);
    // The panels (1200 px for two, 640 for one) plus the legend column for "grace" / "hhd".
    let lw = |l: &str| text_width(l, super::super::text::BODY, false) + 48;
    assert!(matches!(&charts[0].1, Outcome::Drawn { image, .. } if image.width() == 1200 + lw("grace")));
    assert!(matches!(&charts[1].1, Outcome::Drawn { image, .. } if image.width() == 640 + lw("hhd")));
    assert!(sweep_charts(&csv("knob,value\na,1\n")).unwrap_err().to_string().contains("missing column"));
    let b = csv(
        "t,method,irradiance_at_n_r,irradiance_at_n_g,irradiance_at_n_b,rmse\n0,ahd,1,1,1,0\n0.5,ahd,1.5,1.5,1.5,0.1\n\
         1,ahd,1.2,1.2,1.2,0\n0,reference,1,1,1,\n0.5,reference,1.1,1.1,1.1,\n1,reference,1.2,1.2,1.2,\n",
    );
    let charts = blend_charts(&b).unwrap();
    match &charts[0].1 {
        Outcome::Drawn { caption, .. } => {
            assert!(caption.contains("ahd: overshoot 0.300") && caption.contains("reference: overshoot 0"), "{caption}")
        }
        Outcome::Skipped(s) => panic!("{s}"),
    }
}

/// Every chart the report draws from the committed results — the rmse chart and the four cost
/// charts of every `table.csv`, the charts of every sweep and blending CSV — keeps every text
/// inside its canvas, no text over another, and no label over a data point.
#[test]
fn committed_charts_keep_labels_apart_and_on_the_canvas() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("results");
    let mut checked = 0;
    let mut dirs: Vec<_> = std::fs::read_dir(&root).unwrap().filter_map(|e| e.ok()).map(|e| e.path()).collect();
    dirs.push(root.join("claims").join("measures"));
    dirs.sort();
    for dir in dirs.iter().filter(|d| d.is_dir()) {
        let mut files: Vec<_> = std::fs::read_dir(dir).unwrap().filter_map(|e| e.ok()).map(|e| e.path()).collect();
        files.sort();
        for f in files.iter().filter(|f| f.extension().is_some_and(|x| x == "csv")) {
            let t = CsvTable::read(f).unwrap();
            let what = f.display().to_string();
            let mut drawn: Vec<(String, Outcome)> = Vec::new();
            if f.file_name().is_some_and(|n| n == "table.csv") {
                let base = [crate::encoders::BASELINE];
                drawn.push(("dots".into(), rmse_dots(&t, "a title: RMSE per encoder and map", &base).unwrap()));
                let cx = CostContext { per_point: &no_per_point, baseline: &base };
                for c in Cost::ALL {
                    let o = error_vs_cost(&t, c, "a title: error against a cost", &cx).unwrap();
                    drawn.push((format!("{c:?}"), o));
                }
            } else if is_sweep(&t) {
                drawn.extend(sweep_charts(&t).unwrap());
            } else if is_blend(&t) {
                drawn.extend(blend_charts(&t).unwrap());
            }
            for (name, o) in drawn {
                let Outcome::Drawn { image, text, marks, .. } = o else { continue };
                assert_layout(&format!("{what} {name}"), image.dimensions(), &text, &marks);
                checked += 1;
            }
        }
    }
    assert!(checked >= 20, "only {checked} charts checked");
}

/// No text box leaves the canvas, overlaps another or covers a mark.
fn assert_layout(what: &str, (w, h): (u32, u32), text: &[TextBox], marks: &[(i32, i32, i32, i32)]) {
    let text: Vec<&TextBox> = text.iter().filter(|t| !t.text.trim().is_empty()).collect();
    let hit = |a: (i32, i32, i32, i32), b: (i32, i32, i32, i32)| a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3;
    for (i, t) in text.iter().enumerate() {
        let r = t.rect;
        assert!(
            r.0 >= 0 && r.1 >= 0 && r.2 <= w as i32 && r.3 <= h as i32,
            "{what}: '{}' {r:?} leaves {w}x{h}",
            t.text
        );
        for u in &text[i + 1..] {
            assert!(!hit(r, u.rect), "{what}: '{}' {r:?} overlaps '{}' {:?}", t.text, u.text, u.rect);
        }
        for m in marks {
            assert!(!hit(r, *m), "{what}: '{}' {r:?} covers the point {m:?}", t.text);
        }
    }
}

/// Log axes fitted to the data: the ZH3 table's 12 to 27 stored scalars get at least five
/// ticks inside the bounds (12, 15, 20, 25, 30 from the finest step set), the landscape's 3 to
/// 110 the 1-2-5 steps, and the bounds hug the data (no decade of empty axis).
#[test]
fn log_axes_fit_the_data_with_enough_ticks() {
    let (lo, hi) = fitted([12.0, 16.0, 27.0].into_iter()).unwrap();
    assert!(lo > 10.0 && lo < 12.0 && hi > 27.0 && hi < 32.0, "{lo}..{hi}");
    assert_eq!(log_ticks(lo, hi, 5), vec![12.0, 15.0, 20.0, 25.0, 30.0]);
    let (lo, hi) = fitted([3.0, 110.0].into_iter()).unwrap();
    assert!(lo > 2.0 && hi < 200.0, "{lo}..{hi}");
    assert_eq!(log_ticks(lo, hi, 5), vec![5.0, 10.0, 20.0, 50.0, 100.0]);
}

/// A log axis never spans more than 1e-30 to 1e30, whatever it is handed (an rmse of 1e300
/// once made a chart hang): values beyond are clipped to the bounds.
#[test]
fn log_axes_never_leave_the_drawable_range() {
    for values in [vec![1.0, 1e300], vec![1e-300, 1.0], vec![f64::MAX, f64::MIN_POSITIVE]] {
        for (lo, hi) in [fitted(values.iter().copied()).unwrap()] {
            assert!(lo >= 1e-36 && hi <= 1e36 && lo < hi, "{values:?}: {lo}..{hi}");
        }
    }
}

/// An axis of less than a decade still gets five labels: 1-2-5 steps within it (0.05 to 0.07
/// has no 1-2-5 decade value inside but 0.05, 0.055, 0.06, 0.065, 0.07 by step 0.005).
#[test]
fn an_axis_under_a_decade_gets_five_labels() {
    assert_eq!(log_ticks(0.05, 0.07, 5), vec![0.05, 0.055, 0.06, 0.065, 0.07]);
    assert_eq!(tick(0.055), "0.055");
    assert_eq!(linear_ticks(0.0, 1.0, 5), vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
    for (lo, hi) in [(0.31, 0.52), (1.1, 1.9), (120.0, 700.0), (3e-5, 9e-5)] {
        let t = log_ticks(lo, hi, 5);
        assert!(t.len() >= 5 && t.iter().all(|v| *v >= lo && *v <= hi), "{lo}..{hi}: {t:?}");
        let labels: Vec<String> = t.iter().map(|v| tick(*v)).collect();
        let mut unique = labels.clone();
        unique.dedup();
        assert_eq!(unique, labels, "two ticks share a label");
    }
}

/// On a crowded axis every decade keeps its label and a minor one goes: 0.1 to 10 with the
/// 1-2-5 ticks on 90 px, where 0.2 would touch 0.1 and 5 would touch 10.
#[test]
fn decade_labels_survive_a_collision() {
    let ticks = log_ticks(0.1, 10.0, 5);
    assert_eq!(ticks, vec![0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0]);
    let at = |v: f64| 20 + ((v.log10() + 1.0) / 2.0 * 90.0).round() as i32;
    let (_, _, text) = canvas!(200, 60, |root| { grid(root, (20, 5, 110, 30), &ticks, at, true) }).unwrap();
    let shown: Vec<&str> = text.iter().map(|t| t.text.as_str()).collect();
    for decade in ["0.1", "1", "10"] {
        assert!(shown.contains(&decade), "decade {decade} dropped: {shown:?}");
    }
    assert!(!shown.contains(&"0.2") && shown.len() < ticks.len(), "no minor label dropped: {shown:?}");
    assert_layout("crowded axis", (200, 60), &text, &[]);
}

/// A row exact to rounding is drawn at the axis floor, its value in the caption, and does
/// not stretch the axis: the ticks stay within the other rows' decade.
#[test]
fn exact_rows_sit_at_the_floor_and_are_named() {
    let t = csv("map,encoder,metric,rmse,rel_rmse\na,sh1,exact,0.2,0.1\na,sh2,exact,0.05,0.025\n\
         a,sh3,exact,2e-12,1e-12\nb,sh1,exact,0.3,0.1\nb,sh2,exact,0.06,0.02\nb,sh3,exact,4e-12,1.3e-12\n");
    let Outcome::Drawn { caption, text, .. } = rmse_dots(&t, "x", &[]).unwrap() else { panic!("not drawn") };
    assert!(caption.contains("2 exact row(s)") && caption.contains("sh3 on a 2e-12"), "{caption}");
    let ticks: Vec<f64> = text.iter().filter_map(|t| t.text.parse::<f64>().ok()).collect();
    assert!(!ticks.is_empty() && ticks.iter().all(|v| *v > 0.01 && *v < 1.0), "{ticks:?}");
}

/// Many maps × many encoders become a heatmap of ratios to the named baseline: a cell reads
/// the ratio (2 where the encoder's RMSE is twice sh1's), the baseline row its own RMSE.
#[test]
fn many_maps_and_encoders_become_a_heatmap_of_ratios() {
    let encs: Vec<&str> = crate::encoders::REGISTRY.iter().map(|k| k.id).take(12).collect();
    let base = crate::encoders::BASELINE;
    let mut s = String::from("map,encoder,metric,rmse\n");
    for m in 0..30 {
        for (k, e) in encs.iter().enumerate() {
            let v = if *e == base {
                0.2
            } else if k == 0 {
                0.4
            } else {
                0.1 + k as f64 * 0.01
            };
            s += &format!("map{m},{e},exact,{v}\n");
        }
    }
    let Outcome::Drawn { caption, text, image, .. } = rmse_dots(&csv(&s), "x", &[base]).unwrap() else { panic!() };
    assert!(caption.contains(&format!("as a ratio to `{base}`")), "{caption}");
    let cells: Vec<&str> = text.iter().map(|t| t.text.as_str()).collect();
    assert!(cells.contains(&"2") && cells.contains(&"0.2"), "{:?}", &cells[..40]);
    assert!(image.height() <= MAX_HEIGHT, "{}", image.height());
    assert_layout("heatmap", image.dimensions(), &text, &[]);
}
