//! ZH3 end to end: `fit-hallucination` fits the hallucination curve to a probe file. (The ZH3
//! claims are judged by the claims engine: tests/claims.rs.)

mod common;

use common::harness::run;

/// A probe file of cap lights over a constant: the fit runs, prints its coefficients and beats
/// SH L1; a malformed file is refused with the file, the line and exit code 2.
#[test]
fn fit_hallucination_from_a_probe_file() {
    use glam::DVec3;
    use probelab::math::colour::Rgb;
    use probelab::math::sh::constant;
    use probelab::reference::lighting::Light;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("probes.csv");
    let mut text = String::from("# caps of several sizes and colours\n");
    for (i, half) in [0.1f64, 0.3, 0.6, 0.9, 1.2].iter().enumerate() {
        let axis = DVec3::new(1.0, i as f64, 0.5).normalize();
        let sh = Light::Cap { axis, half_angle: *half, radiance: Rgb::new(3.0, 2.0, 1.0) }.sh()
            + constant(Rgb::splat(0.05 * i as f64));
        // Coefficient-major, as `probes --save` writes: c0.r c0.g c0.b c1.r … c8.b.
        let nums: Vec<String> =
            (0..9).flat_map(|k| (0..3).map(move |c| (k, c))).map(|(k, c)| sh[k][c].to_string()).collect();
        text += &nums.join(",");
        text += "\n";
    }
    std::fs::write(&path, &text).unwrap();
    let out = run(&["fit-hallucination", "--probes", path.to_str().unwrap(), "--cubic"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let s = String::from_utf8(out.stdout).unwrap();
    assert!(s.contains("fitted quadratic") && s.contains("fitted cubic") && s.contains("curve_c1"), "{s}");
    assert!(s.contains("15 channel sample(s)"), "{s}");

    std::fs::write(&path, "1,2,3\n").unwrap();
    let out = run(&["fit-hallucination", "--probes", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("probes.csv:1") && err.contains("27"), "{err}");

    let out = run(&["fit-hallucination"]);
    assert_eq!(out.status.code(), Some(2));
}

/// One probe format: the probes of two committed CC0 maps, written coefficient-major as
/// `probes --save` writes them (c0.r c0.g c0.b c1.r … c8.b, shortest round-trip decimals), fit
/// exactly as the maps themselves do; and the same file re-saved by `probes --save` as raw f32
/// is read too. A channel-major reader would see other probes and print another fit.
#[test]
fn fit_hallucination_reads_the_probe_format_probes_writes() {
    use common::harness::{repo, stdout_ok};
    let maps = ["blender_city_256x128", "pmndrs_forest_256x128"];
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("maps.csv");
    let mut text = String::from("# the two maps' L2 radiance SH, coefficient-major\n");
    for m in maps {
        let map = probelab::envmap::load::load(&repo().join("envmaps").join(format!("{m}.exr"))).unwrap();
        let sh = probelab::reference::projection::project(&map);
        let nums: Vec<String> =
            (0..9).flat_map(|k| (0..3).map(move |c| (k, c))).map(|(k, c)| format!("{:?}", sh[k][c])).collect();
        text += &nums.join(",");
        text += "\n";
    }
    std::fs::write(&csv, &text).unwrap();
    let from_maps = stdout_ok(&run(&["fit-hallucination", maps[0], maps[1]]));
    let from_file = stdout_ok(&run(&["fit-hallucination", "--probes", csv.to_str().unwrap()]));
    let body = |s: &str| s.lines().filter(|l| !l.starts_with("maps:")).collect::<Vec<_>>().join("\n");
    assert!(from_maps.contains("2 probe(s)"), "{from_maps}");
    assert_eq!(body(&from_maps), body(&from_file), "the file's probes are the maps' probes");

    // `probes --save` writes the set it reads; fit-hallucination reads what it wrote.
    let save = |to: &std::path::Path| {
        stdout_ok(&run(&[
            "probes",
            "--input",
            csv.to_str().unwrap(),
            "--encoders",
            "sh1",
            "--save",
            to.to_str().unwrap(),
        ]))
    };
    let f32 = dir.path().join("maps.f32");
    save(&f32);
    let from_f32 = stdout_ok(&run(&["fit-hallucination", "--probes", f32.to_str().unwrap()]));
    assert!(from_f32.contains("2 probe(s), 6 channel sample(s)"), "{from_f32}");
    let resaved = dir.path().join("again.csv");
    save(&resaved);
    let from_resaved = stdout_ok(&run(&["fit-hallucination", "--probes", resaved.to_str().unwrap()]));
    assert_eq!(body(&from_resaved), body(&from_file), "probes --save (CSV) keeps every digit");
    let out = run(&["fit-hallucination", "--probes", csv.to_str().unwrap(), "--format", "f64"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown probe file format 'f64'"));
}
