//! `probelab report` end to end: on a scratch repository with small
//! generated maps, every link of REPORT.md resolves, the pictures exist with the sizes their
//! layout gives, charts appear for the CSV formats the report reads and are skipped (with a
//! reason) where a column is absent; and the committed results/REPORT.md has no broken link.

mod common;

use common::harness::{repo, stderr_ok, Run, Scratch};
use probelab::report::markdown::{anchor, local_links};
use probelab::report::sheet::{CELL_W, COLHEAD_H, HEADER_H, LABEL_W, MARGIN, MIN_W, ROW_H, VIEW_GAP};
use std::path::Path;
use std::process::Output;

/// `probelab --root ROOT ARGS` as in CI (`CI=1`).
fn probelab(root: &Scratch, args: &[&str]) -> Output {
    root.probelab().args(args).env("CI", "1").run()
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

fn png_size(p: &Path) -> (u32, u32) {
    image::image_dimensions(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn write(p: &Path, s: &str) {
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(p, s).unwrap();
}

#[test]
fn report_on_a_scratch_repository() {
    let scratch = Scratch::new();
    let root = scratch.path();
    let rs = root.to_str().unwrap();
    stderr_ok(&probelab(&scratch, &["gen-envmaps", "--width", "32"]));
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
        &scratch,
        &["--no-timing", "run", &format!("{rs}/experiments/a_sphere.toml"), &format!("{rs}/experiments/b_floor.toml")],
    ));
    let res = root.join("results");
    assert!(res.join("a_sphere/provenance.toml").is_file(), "run records the maps' checksums");

    // Timings filled into one table's (empty, under --no-timing) `fit_ns` column, read by name.
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
    let png = probelab::report::png::png_bytes(&image::RgbImage::new(2, 2)).unwrap();
    std::fs::write(res.join("a_sphere/sheet_old_map.png"), &png).unwrap();
    std::fs::write(res.join("a_sphere/blend_strip.png"), &png).unwrap();

    let log = stderr_ok(&probelab(&scratch, &["report"]));
    assert!(log.contains("REPORT.md"), "{log}");
    let report = res.join("REPORT.md");
    let md = std::fs::read_to_string(&report).unwrap();
    let links = check_links(&report);

    // Sheets: one per map, sizes from the layout (3 rows × 2 views; 2 rows × 1 view).
    let h = |rows: u32| HEADER_H + COLHEAD_H + rows * ROW_H + MARGIN;
    let w2 = 2 * MARGIN + LABEL_W + 6 * CELL_W + VIEW_GAP;
    let w1 = (2 * MARGIN + LABEL_W + 3 * CELL_W).max(MIN_W);
    assert_eq!(png_size(&res.join("a_sphere/sheet_gen_sun_sky.png")), (w2, h(3)));
    assert_eq!(png_size(&res.join("a_sphere/sheet_gen_constant.png")), (w2, h(3)));
    assert_eq!(png_size(&res.join("b_floor/sheet_gen_hemisphere.png")), (w1, h(2)));
    assert!(!res.join("a_sphere/sheet_old_map.png").exists(), "stale sheet removed");
    for f in [
        "a_sphere/sheet_gen_sun_sky.png",
        "b_floor/sheet_gen_hemisphere.png",
        "a_sphere/chart_rmse.png",
        "b_floor/chart_time.png",
        "a_sphere/chart_sweep_reference_polar_nodes.png",
        "a_sphere/chart_blend.png",
        "a_sphere/blend_strip.png",
        "timing_only/chart_sweep_res.png",
        "a_sphere/claims.csv",
        "../experiments/a_sphere.toml",
    ] {
        assert!(links.iter().any(|l| l == f), "REPORT.md links {f}; links: {links:?}");
    }
    assert!(!res.join("a_sphere/chart_time.png").exists());
    assert!(md.contains("no fit times"), "the missing timings are stated");
    assert!(md.contains("Pareto front: "), "the time chart names its front");
    assert!(md.contains("## Claims") && md.contains("| X1 | sh2 beats sh1 | yes | 0.47 vs 1.9 | **yes** |"));
    assert!(md.contains("## c_missing") && md.contains("Not drawn: not every map"), "missing maps are stated");
    assert!(md.contains("## timing_only"), "result folders without an experiment file get a section");
    assert!(md.contains("mean / worst over the 6 cases"), "the floor experiment's six orientations are summarised");
    assert!(md.contains("ahd: overshoot 0.200"), "blend overshoot in the caption");
    for m in ["gen_sun_sky", "gen_constant", "gen_hemisphere"] {
        assert!(md.contains(&format!("| {m} | `{m}.exr` in")), "checksum row for {m}");
    }
    assert!(md.contains("| not_on_this_machine | not found on this machine |"));

    // Pictures are deterministic: a second report draws the same bytes.
    let before = std::fs::read(res.join("a_sphere/sheet_gen_sun_sky.png")).unwrap();
    let chart = std::fs::read(res.join("a_sphere/chart_rmse.png")).unwrap();
    stderr_ok(&probelab(&scratch, &["--jobs", "1", "report"]));
    assert_eq!(before, std::fs::read(res.join("a_sphere/sheet_gen_sun_sky.png")).unwrap());
    assert_eq!(chart, std::fs::read(res.join("a_sphere/chart_rmse.png")).unwrap());

    // A claims file without its columns is refused with the file named, exit 2.
    write(&res.join("a_sphere/claims.csv"), "id,claim\nX1,x\n");
    let out = probelab(&scratch, &["report"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("claims.csv") && err.contains("paper_figure"), "{err}");
}

/// The committed report: every picture and file it links exists (what `reproduce` must leave).
#[test]
fn committed_report_links_resolve() {
    let report = repo().join("results/REPORT.md");
    assert!(report.is_file(), "results/REPORT.md is missing: run `probelab reproduce` (or `probelab report`)");
    let links = check_links(&report);
    assert!(links.iter().any(|l| l.ends_with(".png")), "the report shows pictures");
}
