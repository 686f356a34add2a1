//! ZH3 end to end: `fit-hallucination` fits the hallucination curve to a probe file. (The ZH3
//! claims are judged by the claims engine: tests/claims.rs.)

mod common;

use common::harness::run;
use probelab::{DVec3, Map, Rgb, Role, Surface, Unit, Value};
use std::f64::consts::{PI, TAU};

/// The nine real SH basis functions at unit direction `d` (FORMULAS §2 of docs/conventions.md,
/// +Y up, indices as in its table).
fn sh_basis(d: DVec3) -> [f64; 9] {
    let (x, y, z) = (d.x, d.y, d.z);
    let (y00, y1, y2_xy, y20, y22) = (
        0.282_094_791_773_878_14,
        0.488_602_511_902_919_9,
        1.092_548_430_592_079_2,
        0.315_391_565_252_520_05,
        0.546_274_215_296_039_6,
    );
    [
        y00,
        -y1 * y,
        y1 * z,
        -y1 * x,
        y2_xy * x * y,
        -y2_xy * y * z,
        y20 * (3.0 * z * z - 1.0),
        -y2_xy * x * z,
        y22 * (x * x - y * y),
    ]
}

/// The L2 radiance SH, in closed form, of a cap of half-angle `half` about `axis` with radiance
/// `radiance`, over a constant environment of radiance `ambient`: the cap is zonal, its band l
/// coefficients ∫_{t>cos α} Y_l0 scaled by √(4π/(2l+1))·Y_lm(axis); the constant is L₀₀ = c·√(4π).
fn cap_over_constant(axis: DVec3, half: f64, radiance: Rgb, ambient: Rgb) -> [Rgb; 9] {
    let (c, y) = (half.cos(), sh_basis(axis));
    let s2 = 1.0 - c * c;
    let zonal = [
        TAU * (1.0 - c) * 0.5 * (1.0 / PI).sqrt(),
        PI * (3.0 / (4.0 * PI)).sqrt() * s2,
        (5.0 / (4.0 * PI)).sqrt() * PI * c * s2,
    ];
    let band = |i: usize| [0, 1, 1, 1, 2, 2, 2, 2, 2][i];
    let constant = |i: usize| if i == 0 { ambient * (4.0 * PI).sqrt() } else { Rgb::ZERO };
    std::array::from_fn(|i| {
        let l = band(i);
        radiance * (zonal[l] * (4.0 * PI / (2 * l + 1) as f64).sqrt() * y[i]) + constant(i)
    })
}

/// A map's L2 radiance SH (its exact projection), as `probe_unoccluded` stores it: the stored
/// entries of its fit on the whole sphere, in coefficient order.
fn radiance_sh(map: &Map) -> Vec<Rgb> {
    let fit = map.lighting(Surface::Sphere).unwrap().fit("probe_unoccluded", "").unwrap();
    let stored = fit.stored();
    let sh: Vec<Rgb> = stored
        .entries
        .iter()
        .filter(|e| e.role == Role::Stored)
        .map(|e| match (e.unit, &e.value) {
            (Unit::Radiance, Value::Rgb(v)) => *v,
            _ => panic!("probe_unoccluded stores radiance SH as RGB values: {e:?}"),
        })
        .collect();
    assert_eq!(sh.len(), 9, "the L2 radiance SH");
    sh
}

/// A probe file of cap lights over a constant: the fit runs, prints its coefficients and beats
/// SH L1; a malformed file is refused with the file, the line and exit code 2.
#[test]
fn fit_hallucination_from_a_probe_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("probes.csv");
    let mut text = String::from("# caps of several sizes and colours\n");
    for (i, half) in [0.1f64, 0.3, 0.6, 0.9, 1.2].iter().enumerate() {
        let axis = DVec3::new(1.0, i as f64, 0.5).normalize();
        let sh = cap_over_constant(axis, *half, Rgb::new(3.0, 2.0, 1.0), Rgb::splat(0.05 * i as f64));
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
        let sh = radiance_sh(&Map::load(m, repo()).unwrap());
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
