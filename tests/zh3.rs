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
        let nums: Vec<String> =
            (0..3).flat_map(|c| (0..9).map(move |k| (c, k))).map(|(c, k)| sh[k][c].to_string()).collect();
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
