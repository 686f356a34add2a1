//! `probelab report` end to end: on a scratch repository with small
//! generated maps, REPORT.md opens with what probelab is, how the run was made and the
//! reproduction at a glance (from a fixture CLAIMS.csv and fixture declarations, every cell
//! within the length limit), then one section per paper; per-experiment detail sits in
//! `results/<name>/README.md`; every link of every page resolves, the pictures exist with the
//! sizes their layout gives, charts appear for the CSV formats the report reads and are
//! skipped (with a reason) where a column is absent, and no page holds an absolute path. The
//! committed results/ has no broken link and no absolute machine path.

mod common;

use common::harness::{repo, stderr_ok, Run, Scratch};
use std::path::Path;
use std::process::Output;

/// `probelab --root ROOT ARGS` as in CI (`CI=1`).
fn probelab(root: &Scratch, args: &[&str]) -> Output {
    root.probelab().args(args).env("CI", "1").run()
}

/// The local link targets of a report page: Markdown links and HTML `src`/`href` attributes,
/// without their `#fragment`, percent-escapes of space and brackets undone. The test's own
/// reading of the pages, apart from the report's.
fn local_links(md: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (open, close) in [("](", ')'), ("src=\"", '"'), ("href=\"", '"')] {
        let mut rest = md;
        while let Some(i) = rest.find(open) {
            rest = &rest[i + open.len()..];
            if let Some(j) = rest.find(close) {
                out.push(rest[..j].to_string());
            }
        }
    }
    out.into_iter()
        .filter(|l| !l.starts_with('#') && !l.contains("://") && !l.starts_with("mailto:"))
        .map(|l| l.split('#').next().unwrap_or("").replace("%20", " ").replace("%28", "(").replace("%29", ")"))
        .collect()
}

/// A heading's anchor as GitHub makes it: lower case, spaces to `-`, other punctuation dropped.
fn anchor(heading: &str) -> String {
    let keep = |c: char| c.is_alphanumeric() || c == '-' || c == '_';
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| if c == ' ' { Some('-') } else { keep(c).then_some(c) })
        .collect()
}

/// Every local link of a Markdown file resolves to a file, and every `#anchor` to a heading.
fn check_links(report: &Path) -> Vec<String> {
    let md = std::fs::read_to_string(report).unwrap();
    let base = report.parent().unwrap();
    let links = local_links(&md);
    for l in &links {
        assert!(base.join(l).is_file(), "{}: broken link '{l}'", report.display());
    }
    let headings: Vec<String> =
        md.lines().filter(|l| l.starts_with('#')).map(|l| anchor(l.trim_start_matches('#'))).collect();
    let mut rest = md.as_str();
    while let Some(i) = rest.find("](#") {
        rest = &rest[i + 3..];
        let a = &rest[..rest.find(')').unwrap()];
        assert!(headings.iter().any(|h| h == a), "{}: anchor #{a} has no heading", report.display());
    }
    links
}

/// `a/b/../c` → `a/c` (links of a page, made relative to the results folder).
fn normalise(p: &str) -> String {
    let mut out: Vec<&str> = Vec::new();
    for part in p.split('/') {
        match part {
            ".." if out.last().is_some_and(|l| *l != "..") => {
                out.pop();
            }
            "." | "" => {}
            _ => out.push(part),
        }
    }
    out.join("/")
}

/// The links of REPORT.md, PROVENANCE.md and every `<folder>/README.md` of `res`, each checked,
/// relative to `res`.
fn check_all_links(res: &Path) -> Vec<String> {
    let mut links = check_links(&res.join("REPORT.md"));
    links.extend(check_links(&res.join("PROVENANCE.md")));
    for e in std::fs::read_dir(res).unwrap() {
        let page = e.unwrap().path().join("README.md");
        if page.is_file() {
            let name = page.parent().unwrap().file_name().unwrap().to_string_lossy().into_owned();
            links.extend(check_links(&page).into_iter().map(|l| normalise(&format!("{name}/{l}"))));
        }
    }
    links
}

/// Text files under `dir` (recursively) that contain an absolute path: `needle` (the scratch
/// root), or a Unix home/work/temp folder or a drive letter.
fn absolute_paths(dir: &Path, needle: Option<&str>) -> Vec<String> {
    let mut bad = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
                continue;
            }
            let ext = p.extension().map(|x| x.to_string_lossy().into_owned()).unwrap_or_default();
            if !["md", "csv", "toml", "txt"].contains(&ext.as_str()) {
                continue;
            }
            let text = std::fs::read_to_string(&p).unwrap_or_default();
            let hit = needle.is_some_and(|n| text.contains(n))
                || ["/home/", "/work/", "/tmp/", "/Users/", "/root/", "C:\\"].iter().any(|m| text.contains(m));
            if hit {
                bad.push(p.display().to_string());
            }
        }
    }
    bad
}

fn png_size(p: &Path) -> (u32, u32) {
    image::image_dimensions(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn write(p: &Path, s: &str) {
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(p, s).unwrap();
}

/// The scratch repository end to end, in one chained sequence: its results folder grows and
/// changes step by step (a first report, the claims fixtures, a refused verdict, reports at
/// other scales, a refused claims file), each step reading what the earlier ones left.
#[test]
fn report_on_a_scratch_repository() {
    let scratch = Scratch::new();
    let root = scratch.path();
    let rs = root.to_str().unwrap();
    run_two_experiments(&scratch);
    let res = root.join("results");
    assert!(res.join("a_sphere/provenance.toml").is_file(), "run records the maps' checksums");
    fill_in_timings(&res);
    add_other_result_files(root, &res);

    let log = stderr_ok(&probelab(&scratch, &["report"]));
    assert!(log.contains("REPORT.md"), "{log}");
    let md = std::fs::read_to_string(res.join("REPORT.md")).unwrap();
    let links = check_all_links(&res);
    opening_then_papers_in_order(&md);
    sheets_have_their_layout_sizes(&res);
    pages_link_pictures_and_files(&res, &links);
    charts_are_also_svg(&res, &links);
    experiment_pages_explain_what_is_missing(&res, &md);
    provenance_page_lists_every_map(&res);
    assert_eq!(absolute_paths(&res, Some(rs)), Vec::<String>::new(), "no absolute path in results/");

    claims_at_a_glance_in_paper_order(&scratch, &res);
    unknown_verdict_is_refused(&scratch, &res);
    let chart = pictures_are_deterministic(&scratch, &res);
    sheet_scale_multiplies_sheets_only(&scratch, &res, &chart);
    claims_file_without_its_columns_is_refused(&scratch, &res);
}

/// Generated maps, the paper plans, two experiments run (and a third that has no map here).
fn run_two_experiments(scratch: &Scratch) {
    let root = scratch.path();
    let rs = root.to_str().unwrap();
    stderr_ok(&probelab(scratch, &["gen-envmaps", "--width", "32"]));
    // The paper sections' plans, without the claims declarations: the sections take the plans'
    // titles.
    scratch.copy_from_repo("experiments/report/papers.toml");
    write(
        &root.join("experiments/a_sphere.toml"),
        "description = \"sphere\"\nmaps = [\"gen_sun_sky\", \"gen_constant\"]\nencoders = [\"sh0\", \"sh1\", \"sh2\"]\n\
         resolution = [32, 16]\n",
    );
    write(
        &root.join("experiments/b_floor.toml"),
        "maps = [\"gen_hemisphere\"]\nencoders = [\"sh1\", \"sh2\"]\ndomain = \"hemisphere\"\n\
         orientations = [\"axes6\"]\neffects = [\"hemisphere\"]\nresolution = [16, 8]\n",
    );
    write(&root.join("experiments/c_missing.toml"), "maps = [\"not_on_this_machine\"]\nencoders = [\"sh1\"]\n");
    // No timing pass: a_sphere's table then has no `fit_ns` column (b_floor's is added below).
    stderr_ok(&probelab(
        scratch,
        &["--no-timing", "run", &format!("{rs}/experiments/a_sphere.toml"), &format!("{rs}/experiments/b_floor.toml")],
    ));
}

/// Timings filled into one table's (empty, under --no-timing) `fit_ns` column, read by name.
fn fill_in_timings(res: &Path) {
    let t = std::fs::read_to_string(res.join("b_floor/table.csv")).unwrap();
    let mut r = csv::Reader::from_reader(t.as_bytes());
    let head = r.headers().unwrap().clone();
    let fc = head.iter().position(|h| h == "fit_ns").expect("fit_ns column");
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(&head).unwrap();
    for (i, rec) in r.records().enumerate() {
        let mut rec: Vec<String> = rec.unwrap().iter().map(String::from).collect();
        rec[fc] = (100 * (i % 2 + 1)).to_string();
        w.write_record(&rec).unwrap();
    }
    write(&res.join("b_floor/table.csv"), &String::from_utf8(w.into_inner().unwrap()).unwrap());
}

/// Result files the report reads besides the tables: a sweep, a blend, claims, a folder with no
/// experiment, a file that is no picture, and stale pictures.
fn add_other_result_files(root: &Path, res: &Path) {
    write(
        &res.join("a_sphere/sweep_reference.csv"),
        "knob,value,rmse,time_ns,label\npolar_nodes,1,1e-3,100,gen_sun_sky\npolar_nodes,2,1e-6,200,gen_sun_sky\n\
         polar_nodes,4,1e-9,400,gen_sun_sky\n",
    );
    write(
        &res.join("a_sphere/blend.csv"),
        "t,method,irradiance_at_n_r,irradiance_at_n_g,irradiance_at_n_b,rmse\n0,ahd,1,1,1,0\n0.5,ahd,1.4,1.4,1.4,0.1\n\
         1,ahd,1.2,1.2,1.2,0\n0,reference,1,1,1,0\n0.5,reference,1.1,1.1,1.1,0\n1,reference,1.2,1.2,1.2,0\n",
    );
    write(
        &res.join("a_sphere/claims.csv"),
        "id,claim,paper_figure,our_figure,holds,notes\nX1,sh2 beats sh1,yes,0.47 vs 1.9,yes,on gen_sun_sky\n",
    );
    write(&res.join("timing_only/sweep.csv"), "knob,value,rmse,time_ns,label\nres,32,0.1,,m\nres,64,0.05,,m\n");
    std::fs::copy(root.join("envmaps/gen_constant.exr"), res.join("a_sphere/not_a_picture.exr")).unwrap();
    // A stale sheet of a map the experiment no longer lists is removed; another picture (as
    // a blending strip would be) is linked.
    let mut png = Vec::new();
    image::RgbImage::new(2, 2).write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).unwrap();
    std::fs::write(res.join("a_sphere/sheet_old_map.png"), &png).unwrap();
    std::fs::write(res.join("a_sphere/blend_strip.png"), &png).unwrap();
    std::fs::write(res.join("a_sphere/chart_old_knob.svg"), "<svg/>").unwrap();
}

/// The opening: what probelab is, how the run was made, then the claims at a glance — with
/// no CLAIMS.csv, one line says so — then the papers, in their order.
fn opening_then_papers_in_order(md: &str) {
    assert!(md.starts_with("# probelab"), "{md}");
    let how = md.find("**How this run was made.**").expect("how the run was made");
    let glance = md.find("## Reproduction at a glance").expect("at a glance");
    assert!(how < glance, "{md}");
    assert!(md.contains("`results/CLAIMS.csv` is not there yet"), "{md}");
    assert!(md.contains("E/π") && md.contains("sha256") && md.contains("Reference: the exact irradiance"), "{md}");
    let zh3 = md.find("## ZH3").expect("the ZH3 section");
    let hemi = md.find("## Hemispherical Lighting Insights").expect("the hemispherical section");
    let brief = md.find("## Directional Lightmap Encoding Insights").expect("the 2018 brief's section");
    assert!(glance < zh3 && zh3 < hemi && hemi < brief, "papers in order");
    assert!(!md.contains("No `table.csv`") && !md.contains("yet (run"), "no folder is said to lack a table");
}

/// Sheets: one per map, the same size within an experiment; 3 rows × 2 views are wider and
/// taller than 2 rows × 1 view. (The exact sizes from the layout's measures are the unit test
/// `report::sheet::tests::sheet_size_follows_rows_and_views`.)
fn sheets_have_their_layout_sizes(res: &Path) {
    let (w2, h3) = png_size(&res.join("a_sphere/sheet_gen_sun_sky.png"));
    assert_eq!(png_size(&res.join("a_sphere/sheet_gen_constant.png")), (w2, h3));
    let (w1, h2) = png_size(&res.join("b_floor/sheet_gen_hemisphere.png"));
    assert!(w2 > w1 && h3 > h2, "3 rows x 2 views {w2}x{h3} against 2 rows x 1 view {w1}x{h2}");
    assert!(!res.join("a_sphere/sheet_old_map.png").exists(), "stale sheet removed");
}

/// The pages link every page, picture, chart, claims file and experiment file.
fn pages_link_pictures_and_files(res: &Path, links: &[String]) {
    for f in [
        "a_sphere/README.md",
        "b_floor/README.md",
        "timing_only/README.md",
        "PROVENANCE.md",
        "a_sphere/sheet_gen_sun_sky.png",
        "b_floor/sheet_gen_hemisphere.png",
        "a_sphere/chart_rmse.png",
        "a_sphere/chart_cost_scalars.png",
        "b_floor/chart_cost_scalars.png",
        "b_floor/chart_time.png",
        "a_sphere/chart_sweep_reference_polar_nodes.png",
        "a_sphere/chart_blend.png",
        "a_sphere/blend_strip.png",
        "timing_only/chart_sweep_res.png",
        "a_sphere/claims.csv",
        "../experiments/a_sphere.toml",
    ] {
        assert!(links.iter().any(|l| l == f), "a page links {f}; links: {links:?}");
    }
    assert!(!res.join("a_sphere/chart_time.png").exists());
}

/// Every chart is also written as SVG beside its PNG (same stem, same size) and linked;
/// a stale chart SVG is removed, and no SVG is listed among the folder's other files.
fn charts_are_also_svg(res: &Path, links: &[String]) {
    for png in [
        "a_sphere/chart_rmse.png",
        "a_sphere/chart_cost_scalars.png",
        "b_floor/chart_cost_scalars.png",
        "b_floor/chart_time.png",
        "a_sphere/chart_sweep_reference_polar_nodes.png",
        "a_sphere/chart_blend.png",
        "timing_only/chart_sweep_res.png",
    ] {
        let svg = png.replace(".png", ".svg");
        let text = std::fs::read_to_string(res.join(&svg)).unwrap_or_else(|e| panic!("{svg}: {e}"));
        let (w, h) = png_size(&res.join(png));
        assert!(text.contains(&format!("<svg width=\"{w}\" height=\"{h}\"")), "{svg}: not {w}x{h}");
        assert!(text.trim_end().ends_with("</svg>"), "{svg}: not closed");
        assert!(links.contains(&svg), "a page links {svg}");
    }
    assert!(!res.join("a_sphere/chart_old_knob.svg").exists(), "stale chart SVG removed");
    let a_page = page(res, "a_sphere");
    let files_line = a_page.lines().find(|l| l.starts_with("Files:")).unwrap_or("");
    assert!(!files_line.contains(".svg"), "SVGs are not listed as other files: {files_line}");
}

/// The experiment pages state what is missing (timings, quantised encoders, results, an
/// experiment file) and caption what they show.
fn experiment_pages_explain_what_is_missing(res: &Path, md: &str) {
    let a = page(res, "a_sphere");
    assert!(a.contains("no fit times") || a.contains("--no-timing"), "the missing timings are stated");
    assert!(a.contains("Pareto front (lower cost and lower error both better): "), "cost charts name their front");
    assert!(a.contains("no encoder of this table is quantised"), "the bytes chart says why it is not drawn");
    assert!(a.contains("## Claims checked here") && a.contains("| X1 | sh2 beats sh1 | yes | 0.47 vs 1.9 | **yes** |"));
    assert!(md.contains("c_missing: no results yet"), "an experiment without results is listed, not paged");
    assert!(
        md.contains("[timing_only](timing_only/README.md)"),
        "result folders without an experiment file get a page"
    );
    assert!(!page(res, "timing_only").contains("table.csv"), "no 'no table' line for a folder that never has one");
    assert!(page(res, "b_floor").contains("mean / worst over the 6 cases"), "the floor experiment's six orientations");
    assert!(a.contains("ahd: overshoot 0.200"), "blend overshoot in the caption");
}

/// PROVENANCE.md has a row per map the experiments name, with the file and checksum its table
/// recorded, and says which map no table records; nothing of this machine (no search path).
fn provenance_page_lists_every_map(res: &Path) {
    let prov = std::fs::read_to_string(res.join("PROVENANCE.md")).unwrap();
    for m in ["gen_sun_sky", "gen_constant", "gen_hemisphere"] {
        assert!(prov.contains(&format!("| {m} | `{m}.exr` | ")), "checksum row for {m}");
    }
    assert!(prov.contains("| not_on_this_machine | no table records it yet | - | - | c_missing |"), "{prov}");
    assert!(!prov.contains("search path of this report") && !prov.contains("not found on this machine"), "{prov}");
}

/// Claims: fixture declarations (two papers, out of file order) and a fixture CLAIMS.csv.
fn claims_at_a_glance_in_paper_order(scratch: &Scratch, res: &Path) {
    let root = scratch.path();
    const KIND: &str = "kind = \"measured\"\nfixed = \"before data\"\ndiffers = \"d\"\nquote = \"q 0.5\"\nthreshold_from = \"paper: 0.5\"\n";
    write(
        &root.join("experiments/claims/zz_first.toml"),
        &("title = \"Paper One\"\nauthors = \"A. Author\"\nvenue = \"Conf 1\"\norder = 1\n\
         [[claim]]\nid = \"P1\"\nsays = \"sh2 beats sh1\"\npaper_figure = \"yes\"\ncriterion = \"every map\"\n{K}\
         [[claim.check]]\nname = \"c\"\ntable = \"a_sphere\"\nencoder = \"sh2\"\nbaseline = \"sh1\"\ntest = \"ratio_every\"\n{P}\
         [[claim]]\nid = \"P2\"\nsays = \"never judged\"\npaper_figure = \"-\"\ncriterion = \"-\"\n{K}\
         [[claim.check]]\nname = \"c\"\ntable = \"a_sphere\"\nencoder = \"sh2\"\ntest = \"every_at_most\"\nbound = 1\n{P}"
        )
        .replace("{K}", KIND)
        .replace("{P}", "role = \"primary\"\n"),
    );
    write(
        &root.join("experiments/claims/aa_second.toml"),
        "title = \"Paper Two\"\nauthors = \"B. Author\"\nvenue = \"Conf 2\"\norder = 2\n\
         [[claim]]\nid = \"Q1\"\nsays = \"the second paper's claim\"\npaper_figure = \"27%\"\ncriterion = \"-\"\n\
         kind = \"anchor\"\nfixed = \"after data: a production figure\"\ndiffers = \"d\"\nquote = \"q\"\nthreshold_from = \"none\"\n\
         [[claim.check]]\nname = \"c\"\ntable = \"a_sphere\"\nencoder = \"sh2\"\nbaseline = \"sh1\"\n\
         test = \"ratio_summary\"\nrole = \"primary\"\n",
    );
    let long = "x ".repeat(200);
    write(
        &res.join("CLAIMS.csv"),
        &format!(
            "id,kind,verdict,paper_figure,our_figure,criterion,maps,detail\n\
             Q1,anchor,not comparable,27%,\"{long}\",c,all,claims/aa_second.md#q1\n\
             P1,measured,holds,yes,0.47 vs 1.9,c,all,claims/zz_first.md#p1\n"
        ),
    );
    write(&res.join("claims/aa_second.md"), "# Paper Two\n\n<a id=\"q1\"></a>\n");
    write(&res.join("claims/zz_first.md"), "# Paper One\n\n<a id=\"p1\"></a>\n");
    stderr_ok(&probelab(scratch, &["report"]));
    let md = std::fs::read_to_string(res.join("REPORT.md")).unwrap();
    check_all_links(res);
    let rows: Vec<&str> = md.lines().filter(|l| l.starts_with("| [") || l.starts_with("| P2")).collect();
    assert_eq!(rows.len(), 3, "{md}");
    // Paper order (by `order`, not file name), then declaration order; a declared claim without
    // a row is shown as not judged.
    assert!(
        rows[0]
            .starts_with("| [P1](claims/zz_first.md#p1) | measured | sh2 beats sh1 | yes | 0.47 vs 1.9 | **holds** |"),
        "{}",
        rows[0]
    );
    assert!(rows[1].starts_with("| P2 | - | never judged | - | - | not judged"), "{}", rows[1]);
    assert!(
        rows[2].starts_with("| [Q1](claims/aa_second.md#q1) | anchor | the second paper's claim | 27% |"),
        "{}",
        rows[2]
    );
    // No cell is ever cut: the long figure stands whole.
    assert!(rows[2].contains(long.trim()) && !rows[2].contains('…'), "the long figure is cut: {}", rows[2]);
    assert!(rows[2].contains("**not comparable**"), "{}", rows[2]);
    assert!(md.contains("2 claims judged: 1 holds, 1 not comparable."), "{md}");
    assert!(md.find("## Paper One").unwrap() < md.find("## Paper Two").unwrap(), "sections in paper order");
    assert!(md.contains("A. Author. Conf 1. Claims P1, P2"), "{md}");
}

/// A verdict word its kind does not allow is refused with the file and claim named, exit 2.
fn unknown_verdict_is_refused(scratch: &Scratch, res: &Path) {
    let head = "id,kind,verdict,paper_figure,our_figure,criterion,maps,detail\n";
    write(&res.join("CLAIMS.csv"), &format!("{head}P1,measured,yes,a,b,c,d,e\n"));
    let out = probelab(scratch, &["report"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("CLAIMS.csv") && err.contains("P1") && err.contains("holds, partly"), "{err}");
    // A word of another kind is refused too: an anchor never holds.
    write(&res.join("CLAIMS.csv"), &format!("{head}P1,anchor,holds,a,b,c,d,e\n"));
    let out = probelab(scratch, &["report"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("an anchor claim may get (not comparable"), "{err}");
    std::fs::remove_file(res.join("CLAIMS.csv")).unwrap();
}

/// Pictures are deterministic: a second report draws the same bytes. Returns the rmse chart.
fn pictures_are_deterministic(scratch: &Scratch, res: &Path) -> Vec<u8> {
    let before = std::fs::read(res.join("a_sphere/sheet_gen_sun_sky.png")).unwrap();
    let chart = std::fs::read(res.join("a_sphere/chart_rmse.png")).unwrap();
    stderr_ok(&probelab(scratch, &["--jobs", "1", "report"]));
    assert_eq!(before, std::fs::read(res.join("a_sphere/sheet_gen_sun_sky.png")).unwrap());
    assert_eq!(chart, std::fs::read(res.join("a_sphere/chart_rmse.png")).unwrap());
    chart
}

/// `--scale 1` is the default sheet, byte for byte; `--scale 2` draws every sheet exactly
/// twice as wide and tall and leaves the charts (`chart`: the rmse chart) as they were; then back
/// to the default.
fn sheet_scale_multiplies_sheets_only(scratch: &Scratch, res: &Path, chart: &[u8]) {
    let sheets =
        ["a_sphere/sheet_gen_sun_sky.png", "a_sphere/sheet_gen_constant.png", "b_floor/sheet_gen_hemisphere.png"];
    let default: Vec<Vec<u8>> = sheets.iter().map(|s| std::fs::read(res.join(s)).unwrap()).collect();
    let sizes: Vec<(u32, u32)> = sheets.iter().map(|s| png_size(&res.join(s))).collect();
    stderr_ok(&probelab(scratch, &["report", "--scale", "1"]));
    for (s, bytes) in sheets.iter().zip(&default) {
        assert!(std::fs::read(res.join(s)).unwrap() == *bytes, "{s} at --scale 1 differs from the default");
    }
    stderr_ok(&probelab(scratch, &["report", "--scale", "2"]));
    for (s, (w, h)) in sheets.iter().zip(&sizes) {
        assert_eq!(png_size(&res.join(s)), (2 * w, 2 * h), "{s} at --scale 2");
    }
    assert_eq!(chart, std::fs::read(res.join("a_sphere/chart_rmse.png")).unwrap(), "charts do not scale");
    stderr_ok(&probelab(scratch, &["report"]));
    assert!(std::fs::read(res.join(sheets[0])).unwrap() == default[0]);
}

/// A claims file without its columns is refused with the file named, exit 2.
fn claims_file_without_its_columns_is_refused(scratch: &Scratch, res: &Path) {
    write(&res.join("a_sphere/claims.csv"), "id,claim\nX1,x\n");
    let out = probelab(scratch, &["report"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("claims.csv") && err.contains("paper_figure"), "{err}");
}

/// A result folder's page.
fn page(res: &Path, name: &str) -> String {
    std::fs::read_to_string(res.join(name).join("README.md")).unwrap()
}

/// The committed report: every picture and file its pages link exists (what `reproduce` must
/// leave), and nothing under results/ holds an absolute machine path.
#[test]
fn committed_report_links_resolve() {
    let res = repo().join("results");
    assert!(
        res.join("REPORT.md").is_file(),
        "results/REPORT.md is missing: run `probelab reproduce` (or `probelab report`)"
    );
    let links = check_all_links(&res);
    assert!(links.iter().any(|l| l.ends_with(".png")), "the report shows pictures");
    assert_eq!(absolute_paths(&res, None), Vec::<String>::new(), "absolute paths in results/");
}
