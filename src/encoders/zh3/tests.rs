//! ZH3's unit tests: zonal lights exact when stored, the shader's hallucination, ratios,
//! degenerate inputs, stored scalars, quantised and serialised forms, the registry's encoder.

use super::model::*;
use super::serialise::*;
use super::*;
use crate::encoders::build;
use crate::encoders::encoder::{Encoder, FitInput, Fitted};
use crate::encoders::quantise;
use crate::encoders::zh3::build::KINDS;
use crate::encoders::zh3::model::finish_hallucinated;
use crate::encoders::zh3::solve::Curve;
use crate::math::colour::Rgb;
use crate::math::sh::Sh9;
use crate::math::sh::{basis, constant, delta_light};
use crate::reference::lighting::Light;
use glam::DVec3;
use std::f64::consts::PI;

fn fit(id: &str, sh: &Sh9) -> Box<dyn Fitted> {
    build(id, None, toml::Table::new()).unwrap().encoder.fit(&FitInput::sphere(sh))
}

const ALL: &[&str] = &[
    "zh3_hallucinate",
    "zh3_hallucinate_channel",
    "zh3_hallucinate_ambdir",
    "zh3_hallucinate_sphere",
    "zh3_stored_channel",
    "zh3_stored_shared",
    "zh3_solved_channel",
    "zh3_solved_shared",
    "zh3_hallucinate_solved",
];
const STORED: &[&str] = &["zh3_stored_channel", "zh3_stored_shared", "zh3_solved_channel", "zh3_solved_shared"];

/// Claim Z1: for zonal lights (delta, caps of several sizes, a cap over a constant, coloured)
/// every stored ZH3 reproduces SH3 irradiance: max |ZH3 − SH3| ≤ 1e-6 of the peak, so their
/// errors against any reference agree to 1e-6.
#[test]
fn stored_zh3_is_exact_for_zonal_lights() {
    let axis = DVec3::new(0.3, 0.7, -0.648).normalize();
    let lights: Vec<Sh9> = vec![
        delta_light(axis, Rgb::new(3.0, 2.0, 1.0)),
        Light::Cap { axis, half_angle: 0.1, radiance: Rgb::new(50.0, 40.0, 30.0) }.sh(),
        Light::Cap { axis: -axis, half_angle: 0.6, radiance: Rgb::new(1.0, 2.0, 3.0) }.sh(),
        Light::Cap { axis, half_angle: 1.3, radiance: Rgb::ONE }.sh() + constant(Rgb::splat(0.2)),
    ];
    let pts = crate::reference::domain::fibonacci_sphere(2000);
    for sh in &lights {
        let sh3 = sh.convolve_cosine();
        let peak = pts.iter().map(|&n| sh3.eval(n).max_element()).fold(0.0, f64::max);
        for id in STORED {
            let f = fit(id, sh);
            let d = pts.iter().map(|&n| (f.irradiance(n) - sh3.eval(n)).abs().max_element()).fold(0.0, f64::max);
            assert!(d <= 1e-6 * peak, "{id}: {d} vs peak {peak}");
        }
    }
}

/// The hallucination formula, written out from the talk's shader code on radiance SH:
/// E/π = SH L1 irradiance + ¼·L₀₀(0.08r + 0.6r²)·√(5/16π)·(3(a·n)² − 1), a from the
/// Rec.709-weighted L1, r = |L1_c·a|/L₀₀,c per channel.
#[test]
fn hallucination_matches_the_shader_formula() {
    let sh = delta_light(DVec3::new(0.1, 0.9, 0.3).normalize(), Rgb::new(1.0, 3.0, 0.5))
        + delta_light(DVec3::new(-0.8, 0.1, 0.2).normalize(), Rgb::new(4.0, 1.0, 2.0))
        + constant(Rgb::new(0.3, 0.2, 0.1));
    let lum = crate::math::colour::REC709;
    let l1 = |c: usize| DVec3::new(-sh[3][c], -sh[1][c], sh[2][c]);
    let axis = (l1(0) * lum.x + l1(1) * lum.y + l1(2) * lum.z).normalize();
    let f = fit("zh3_hallucinate", &sh);
    for n in crate::reference::domain::fibonacci_sphere(50) {
        let y = basis(n);
        let fz = axis.dot(n);
        let zh = (5.0 / (16.0 * PI)).sqrt() * (3.0 * fz * fz - 1.0);
        for c in 0..3 {
            let ratio = l1(c).dot(axis).abs() / sh[0][c];
            let zonal = sh[0][c] * (0.08 * ratio + 0.6 * ratio * ratio);
            let base = sh[0][c] * y[0] + (2.0 / 3.0) * (1..4).map(|i| sh[i][c] * y[i]).sum::<f64>();
            let want = base + 0.25 * zonal * zh;
            assert!((f.irradiance(n)[c] - want).abs() < 1e-13, "{n} {c}");
        }
    }
}

/// r ∈ [0, √3], r = √3 for one delta light (every channel, any axis rule); r = 0 for a
/// constant.
#[test]
fn ratio_range() {
    let d = DVec3::new(-0.2, 0.4, 0.89).normalize();
    let irr = delta_light(d, Rgb::new(1.0, 2.0, 0.5)).convolve_cosine();
    for rule in [AxisRule::Channel, AxisRule::Shared(crate::math::colour::REC709)] {
        let r = hallucinate(&irr, rule, Curve::PAPER).ratios();
        assert!((r - Rgb::splat(3f64.sqrt())).abs().max_element() < 1e-14, "{r}");
    }
    // Random non-negative lights stay inside.
    let mut s = 7u64;
    let mut rnd = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..200 {
        let mut sh = constant(Rgb::splat(rnd() * 0.01));
        for _ in 0..3 {
            let dir = DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
            sh = sh + delta_light(dir, Rgb::new(rnd(), rnd(), rnd()));
        }
        let r = hallucinate(&sh.convolve_cosine(), AxisRule::Channel, Curve::PAPER).ratios();
        assert!(r.min_element() >= 0.0 && r.max_element() <= 3f64.sqrt() + 1e-12, "{r}");
    }
    assert_eq!(hallucinate(&constant(Rgb::ONE).convolve_cosine(), AxisRule::Channel, Curve::PAPER).ratios(), Rgb::ZERO);
}

/// No L1: every variant falls back to SH L1 (k = 0) without NaN; a black probe gives 0.
#[test]
fn degenerate_inputs() {
    let mut sh = constant(Rgb::new(1.0, 0.5, 0.0));
    sh[6] = Rgb::splat(0.3);
    for id in ALL {
        let f = fit(id, &sh);
        let e = f.irradiance(DVec3::new(0.0, 0.6, 0.8));
        assert!((e - Rgb::new(1.0, 0.5, 0.0)).abs().max_element() < 1e-12, "{id}: {e}");
        assert!(f.diagnostics().iter().all(|(_, v)| v.is_finite()), "{id}");
        assert_eq!(fit(id, &Sh9::ZERO).irradiance(DVec3::X), Rgb::ZERO, "{id}");
    }
}

#[test]
fn stored_scalar_counts_and_keys() {
    for id in ALL {
        let e = build(id, None, toml::Table::new()).unwrap();
        let want =
            if id.contains("stored") || *id == "zh3_solved_channel" || *id == "zh3_solved_shared" { 15 } else { 12 };
        assert_eq!(e.encoder.stored_scalars(), want, "{id}");
    }
    let mut t = toml::Table::new();
    t.insert("error_weights".into(), toml::Value::String("rec709".into()));
    let e = format!("{:#}", build("zh3_stored_shared", None, t).err().unwrap());
    assert!(e.contains("error_weights"), "{e}");
    let mut t = toml::Table::new();
    t.insert("axis_weights".into(), toml::Value::Array(vec![1.into(), 0.into(), (-1).into()]));
    assert!(build("zh3_solved_shared", None, t).is_err());
}

/// Quantised stored ZH3 stays within a few byte steps of the unquantised one, and reports
/// 16 bytes (13 when hallucinated).
#[test]
fn quantised_zh3() {
    let sh = Light::Cap { axis: DVec3::Y, half_angle: 0.4, radiance: Rgb::new(5.0, 4.0, 3.0) }.sh()
        + constant(Rgb::splat(0.5));
    let mut t = toml::Table::new();
    t.insert("quantise".into(), toml::Value::String("ratio8".into()));
    let q = build("zh3_stored_shared", None, t.clone()).unwrap().encoder.fit(&FitInput::sphere(&sh));
    let f = fit("zh3_stored_shared", &sh);
    let peak = f.irradiance(DVec3::Y).max_element();
    for n in crate::reference::domain::fibonacci_sphere(100) {
        assert!((q.irradiance(n) - f.irradiance(n)).abs().max_element() < 0.02 * peak);
    }
    assert!(q.diagnostics().contains(&("bytes", 16.0)));
    let h = build("zh3_hallucinate", None, t).unwrap().encoder.fit(&FitInput::sphere(&sh));
    assert!(h.diagnostics().contains(&("bytes", 13.0)));
}

/// The quantisation as specified scalar by scalar (DC through RGB9E5; each radiance L1
/// component and f/L₀₀ through a ratio byte to the decoded DC), independently of the byte
/// layout.
fn per_scalar(z: &Zh3, rule: AxisRule, store_k: bool, curve: Curve) -> Zh3 {
    let dc = quantise::rgb9e5_decode(quantise::rgb9e5_encode(z.l0));
    let b1 = quantise::bound_l1();
    let l1: [DVec3; 3] = std::array::from_fn(|c| {
        let v = (z.l1[c] * 1.5).to_array();
        DVec3::from_array(v.map(|x| quantise::ratio8_decode(quantise::ratio8_encode(x, dc[c], b1), dc[c], b1))) / 1.5
    });
    if !store_k {
        return finish_hallucinated(dc, l1, rule, curve);
    }
    let f_of_k = 4.0 * (5.0 / (4.0 * std::f64::consts::PI)).sqrt();
    let bz = quantise::bound_zh3();
    let k = Rgb::from_array(std::array::from_fn(|c| {
        quantise::ratio8_decode(quantise::ratio8_encode(z.k[c] * f_of_k, dc[c], bz), dc[c], bz) / f_of_k
    }));
    Zh3 { l0: dc, l1, axes: rule.axes(&l1), k }
}

/// The serialised form is the scalar-by-scalar quantisation bit for bit, is 16 bytes with
/// a stored coefficient and 13 without, starts with SH L1's 13 bytes, and decodes
/// idempotently.
#[test]
fn serialised_zh3_round_trip() {
    let mut rng = crate::math::test_rng::Rng::new(11);
    for i in 0..200 {
        let mut sh = constant(Rgb::splat(0.2 * rng.uniform01()));
        for _ in 0..2 {
            sh = sh + delta_light(rng.unit(), Rgb::new(rng.uniform01(), rng.uniform01(), 1.0));
        }
        let irr = sh.convolve_cosine();
        for (rule, store_k) in
            [(AxisRule::Shared(Rgb::ONE / 3.0), true), (AxisRule::Shared(crate::math::colour::REC709), false)]
        {
            let z = if store_k { stored(&irr, rule) } else { hallucinate(&irr, rule, Curve::PAPER) };
            let bytes = encode_zh3(&z, store_k);
            assert_eq!(bytes.len(), if store_k { 16 } else { 13 });
            let mut rad = Sh9::ZERO;
            rad[0] = irr[0];
            for j in 1..4 {
                rad[j] = irr[j] * 1.5;
            }
            assert_eq!(bytes[..13], quantise::encode_sh(&rad, 1), "{i}: the first 13 bytes are SH L1's");
            let d = decode_zh3(&bytes, rule, Curve::PAPER).unwrap();
            assert_eq!(d, per_scalar(&z, rule, store_k, Curve::PAPER), "{i}");
            assert_eq!(decode_zh3(&encode_zh3(&d, store_k), rule, Curve::PAPER).unwrap(), d, "{i}");
        }
    }
    for n in [0, 12, 14, 15, 17, 28] {
        let e = decode_zh3(&vec![0u8; n], AxisRule::Channel, Curve::PAPER).unwrap_err().to_string();
        assert!(e.contains(&format!("{n} bytes")) && e.contains("13") && e.contains("16"), "{e}");
    }
}

/// `configured` gives the registry's encoder (the same fit), and refuses other kinds.
#[test]
fn configured_is_the_registered_encoder() {
    let sh = Light::Cap { axis: DVec3::X, half_angle: 0.3, radiance: Rgb::new(2.0, 3.0, 4.0) }.sh();
    for (kind, _) in KINDS {
        let c = configured(kind, toml::Table::new()).unwrap();
        assert_eq!(c.id(), kind);
        let f = fit(kind, &sh);
        assert_eq!(c.fit(&FitInput::sphere(&sh)).sh3(), f.sh3(), "{kind}");
    }
    let e = configured("sh1", toml::Table::new()).err().unwrap().to_string();
    assert!(e.contains("'sh1' is not a ZH3 encoder"), "{e}");
    let mut t = toml::Table::new();
    t.insert("quantise".into(), toml::Value::String("bits".into()));
    assert!(format!("{:#}", configured("zh3_hallucinate", t).err().unwrap()).contains("key 'quantise'"));
}

/// The talk's two ZH3 storage formats as their own ids: `zh3_q16` is `zh3_solved_shared`
/// quantised and `zh3_hallucinate_q13` is `zh3_hallucinate` quantised, value for value; they
/// store the talk's 16 and 13 bytes (its "storage" paragraph), write exactly that many, and
/// refuse a `quantise` key.
#[test]
fn storage_formats_are_their_quantised_kinds() {
    let sh =
        Light::Cap { axis: DVec3::new(0.3, 0.8, -0.5).normalize(), half_angle: 0.3, radiance: Rgb::new(6.0, 4.0, 2.0) }
            .sh()
            + constant(Rgb::new(0.4, 0.5, 0.6));
    let mut t = toml::Table::new();
    t.insert("quantise".into(), toml::Value::String("ratio8".into()));
    for (id, kind, bytes) in [("zh3_q16", "zh3_solved_shared", 16), ("zh3_hallucinate_q13", "zh3_hallucinate", 13)] {
        let e = build(id, None, toml::Table::new()).unwrap().encoder;
        assert_eq!(e.stored_bytes(), bytes, "{id}");
        let f = e.fit(&FitInput::sphere(&sh));
        assert!(f.diagnostics().contains(&("bytes", bytes as f64)), "{id} writes {bytes} bytes");
        let g = build(kind, None, t.clone()).unwrap().encoder.fit(&FitInput::sphere(&sh));
        for n in crate::reference::domain::fibonacci_sphere(50) {
            assert_eq!(f.irradiance(n), g.irradiance(n), "{id} is {kind} quantised");
        }
        assert!(build(id, None, t.clone()).is_err(), "{id} takes no quantise key");
    }
    let plain = build("zh3_solved_shared", None, toml::Table::new()).unwrap().encoder;
    assert_eq!(plain.stored_bytes(), 2 * 15, "unquantised: half floats");
}
