//! The exported coefficients round-trip: each encoder's `stored()` entries are evaluated here by
//! an implementation of its reconstruction written from the formulas (docs/conventions.md, the
//! papers; the module docs cite which), never by the encoder's own evaluation, and must match
//! the encoder's `irradiance(n)` at 600 normals over the whole sphere, to 1e-9 of the largest
//! value. So what `probelab fit` prints is enough to rebuild what probelab scores.
//!
//! Fitted through the public API on committed CC0 maps (envmaps/), on the sphere and, for the
//! lightmap and H-basis encoders, about a tilted surface normal N.

use probelab::{DVec3, Fit, Lighting, Map, Rgb, Stored, Surface};
use std::f64::consts::PI;

const MAPS: [&str; 2] = ["blender_city_256x128", "gen_two_lights"];

/// The surface normal of the lightmap cases (normalised by the test, as by the library).
fn surface_normal() -> DVec3 {
    DVec3::new(0.35, 0.8, -0.45).normalize()
}

/// 600 unit normals on a golden-angle spiral.
fn normals() -> Vec<DVec3> {
    let n = 600;
    let golden = PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - (2 * i + 1) as f64 / n as f64;
            let r = (1.0 - y * y).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), y, r * phi.sin())
        })
        .collect()
}

/// The nine real SH of docs/conventions.md §2 (Condon–Shortley phase), written from the table.
fn sh9(n: DVec3) -> [f64; 9] {
    let (x, y, z) = (n.x, n.y, n.z);
    let c0 = 0.5 * (1.0 / PI).sqrt();
    let c1 = (3.0 / (4.0 * PI)).sqrt();
    let c2 = 0.5 * (15.0 / PI).sqrt();
    let c20 = 0.25 * (5.0 / PI).sqrt();
    let c22 = 0.25 * (15.0 / PI).sqrt();
    [
        c0,
        -c1 * y,
        c1 * z,
        -c1 * x,
        c2 * x * y,
        -c2 * y * z,
        c20 * (3.0 * z * z - 1.0),
        -c2 * x * z,
        c22 * (x * x - y * y),
    ]
}

/// The §2 names of the first `count` SH coefficients.
const SH_NAMES: [&str; 9] = ["L0_0", "L1_-1", "L1_0", "L1_1", "L2_-2", "L2_-1", "L2_0", "L2_1", "L2_2"];

fn rgb(s: &Stored, name: &str) -> Rgb {
    s.rgb_of(name).unwrap_or_else(|| panic!("no RGB entry '{name}' in {s:?}"))
}
fn scalar(s: &Stored, name: &str) -> f64 {
    s.scalar_of(name).unwrap_or_else(|| panic!("no scalar entry '{name}' in {s:?}"))
}
fn vector(s: &Stored, name: &str) -> DVec3 {
    s.vector_of(name).unwrap_or_else(|| panic!("no vector entry '{name}' in {s:?}"))
}

/// The fit's E/π against `ours` at every normal, to 1e-9 of the largest |E/π|.
fn assert_round_trip(label: &str, fit: &Fit, ours: impl Fn(DVec3) -> Rgb) {
    let ns = normals();
    let scale = ns.iter().map(|&n| fit.irradiance(n).abs().max_element()).fold(0.0, f64::max);
    assert!(scale > 0.0 && scale.is_finite(), "{label}: the fit is black or not finite");
    for n in ns {
        let (a, b) = (fit.irradiance(n), ours(n));
        let d = (a - b).abs().max_element();
        assert!(d <= 1e-9 * scale, "{label} at {n}: encoder {a}, from the stored coefficients {b} (scale {scale})");
    }
}

fn fit(light: &Lighting, id: &str, settings: &str) -> Fit {
    light.fit(id, settings).unwrap_or_else(|e| panic!("{id}: {e:#}"))
}

/// L1 per channel as a vector, (−L1_1, −L1_-1, L1_0) (docs/conventions.md §4).
fn l1_vectors(s: &Stored) -> [DVec3; 3] {
    let (m1, z, p1) = (rgb(s, "L1_-1"), rgb(s, "L1_0"), rgb(s, "L1_1"));
    std::array::from_fn(|c| DVec3::new(-p1[c], -m1[c], z[c]))
}

/// SH irradiance from its E/π coefficients: E/π = Σ c_i Y_i (§2–3).
fn sh_irradiance(s: &Stored, count: usize) -> impl Fn(DVec3) -> Rgb + '_ {
    let c: Vec<Rgb> = SH_NAMES[..count].iter().map(|name| rgb(s, name)).collect();
    move |n| {
        let y = sh9(n);
        c.iter().zip(y).map(|(c, y)| *c * y).sum()
    }
}

#[test]
fn sh_coefficients_round_trip() {
    for m in MAPS {
        let map = Map::load(m, env!("CARGO_MANIFEST_DIR")).unwrap();
        let light = map.lighting(Surface::Sphere).unwrap();
        for (id, count) in [("sh0", 1), ("sh1", 4), ("sh2", 9), ("sh2_q28", 9), ("sh1_q13", 4), ("sh2_windowed", 9)] {
            let f = fit(&light, id, "");
            let s = f.stored();
            assert!(s.get(SH_NAMES.get(count).copied().unwrap_or("L3_-3")).is_none(), "{id} stores too many bands");
            assert_round_trip(&format!("{m} {id}"), &f, sh_irradiance(&s, count));
        }
        // The probe operators store the radiance probe: E/π = Σ Â_l L_lm Y_lm with Â = 1, 2/3, 1/4.
        let f = fit(&light, "probe_unoccluded", "");
        let s = f.stored();
        let c: Vec<Rgb> = SH_NAMES.iter().map(|name| rgb(&s, name)).collect();
        let band_scale = [1.0, 2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 0.25, 0.25, 0.25, 0.25, 0.25];
        assert_round_trip(&format!("{m} probe_unoccluded"), &f, |n| {
            let y = sh9(n);
            (0..9).map(|i| c[i] * (band_scale[i] * y[i])).sum()
        });
    }
}

/// ZH3 (docs/conventions.md §5): E/π = L0·Y0 + Σ L1_m·Y1m + k·Σ_m Y2m(a)·Y2m(n), and
/// Σ_m Y2m(a)·Y2m(n) = (5/4π)·P2(a·n) = (5/8π)(3(a·n)² − 1) (the addition theorem).
fn zh3_irradiance(s: &Stored, axis: DVec3, k: Rgb) -> impl Fn(DVec3) -> Rgb + '_ {
    let linear = sh_irradiance(s, 4);
    move |n| {
        let t = axis.dot(n);
        linear(n) + k * (5.0 / (8.0 * PI) * (3.0 * t * t - 1.0))
    }
}

/// The shared axis of channel weights `w`: normalize(Σ w_c L1_c) (§4–5).
fn shared_axis(s: &Stored, w: Rgb) -> DVec3 {
    let v = l1_vectors(s);
    (v[0] * w.x + v[1] * w.y + v[2] * w.z).normalize()
}

#[test]
fn stored_and_solved_zh3_round_trip() {
    for m in MAPS {
        let map = Map::load(m, env!("CARGO_MANIFEST_DIR")).unwrap();
        let light = map.lighting(Surface::Sphere).unwrap();
        // The acceptance case first: the solved L1 is stored, the axis is its equal-weight direction.
        for id in ["zh3_solved_shared", "zh3_stored_shared"] {
            let f = fit(&light, id, "");
            let s = f.stored();
            let a = shared_axis(&s, Rgb::ONE);
            assert!((vector(&s, "zonal_axis") - a).length() < 1e-12, "{m} {id}: exported axis");
            assert_round_trip(&format!("{m} {id}"), &f, zh3_irradiance(&s, a, rgb(&s, "k")));
        }
        // The stored k is the least-squares zonal fit of sh2's band 2 about the axis (§5):
        // k = (4π/5) Σ_m Y2m(a) L2m, with L2m of sh2's E/π coefficients.
        let zh3 = fit(&light, "zh3_stored_shared", "").stored();
        let sh2 = fit(&light, "sh2", "").stored();
        let a = shared_axis(&zh3, Rgb::ONE);
        let y = sh9(a);
        let k: Rgb = (4..9).map(|i| rgb(&sh2, SH_NAMES[i]) * (4.0 * PI / 5.0 * y[i])).sum();
        assert!((k - rgb(&zh3, "k")).abs().max_element() < 1e-12, "{m}: k {} vs {k}", rgb(&zh3, "k"));
    }
}

#[test]
fn hallucinated_zh3_round_trips() {
    let rec709 = Rgb::new(0.2126, 0.7152, 0.0722);
    for m in MAPS {
        let map = Map::load(m, env!("CARGO_MANIFEST_DIR")).unwrap();
        let light = map.lighting(Surface::Sphere).unwrap();
        let f = fit(&light, "zh3_hallucinate", "");
        let s = f.stored();
        assert_eq!(s.scalar_count(), 12, "hallucinated k is not stored");
        let a = shared_axis(&s, rec709);
        let (l0, l1) = (rgb(&s, "L0_0"), l1_vectors(&s));
        // The paper's curve on the radiance ratio r = |L1_rad·a|/L00 = 1.5|L1·a|/L0 (§5):
        // f_rad = L00·(0.08r + 0.6r²), k = √(4π/5)·f_irr, f_irr = f_rad/4.
        let k = Rgb::from_array(std::array::from_fn(|c| {
            if l0[c] <= 0.0 {
                return 0.0;
            }
            let r = 1.5 * l1[c].dot(a).abs() / l0[c];
            (4.0 * PI / 5.0).sqrt() * 0.25 * l0[c] * (0.08 * r + 0.6 * r * r)
        }));
        assert!((k - rgb(&s, "k")).abs().max_element() < 1e-12, "{m}: derived k {} vs {k}", rgb(&s, "k"));
        assert_round_trip(&format!("{m} zh3_hallucinate"), &f, zh3_irradiance(&s, a, k));
    }
}

#[test]
fn geomerics_round_trips() {
    for m in MAPS {
        let map = Map::load(m, env!("CARGO_MANIFEST_DIR")).unwrap();
        let light = map.lighting(Surface::Sphere).unwrap();
        let f = fit(&light, "geomerics", "");
        let s = f.stored();
        let (r0, rx, ry, rz) = (rgb(&s, "R0"), rgb(&s, "R1_x"), rgb(&s, "R1_y"), rgb(&s, "R1_z"));
        // §6 from the SH: R0 = Y00·L00 (= the E/π band-0 coefficient times Y00), and
        // R1 = (−L1_1, −L1_-1, L1_0)_radiance/√(12π), the radiance L1 being 1.5 × E/π's.
        let sh1 = fit(&light, "sh1", "").stored();
        let y00 = 0.5 * (1.0 / PI).sqrt();
        assert!((r0 - rgb(&sh1, "L0_0") * y00).abs().max_element() < 1e-12);
        let v = l1_vectors(&sh1);
        for c in 0..3 {
            let want = v[c] * (1.5 / (12.0 * PI).sqrt());
            assert!((DVec3::new(rx[c], ry[c], rz[c]) - want).length() < 1e-12, "{m} R1 channel {c}");
        }
        assert_round_trip(&format!("{m} geomerics"), &f, |n| {
            Rgb::from_array(std::array::from_fn(|c| {
                let (r0, r1) = (r0[c], DVec3::new(rx[c], ry[c], rz[c]));
                if r0 <= 0.0 {
                    return 0.0;
                }
                let len = r1.length();
                if len == 0.0 {
                    return r0;
                }
                let rho = len / r0;
                let q = (0.5 * (1.0 + r1.dot(n) / len)).clamp(0.0, 1.0);
                let (p, a) = (1.0 + 2.0 * rho, (1.0 - rho) / (1.0 + rho));
                r0 * (a + (1.0 - a) * (p + 1.0) * q.powf(p))
            }))
        });
    }
}

/// The texel's highlight direction (irradz.rs, 2018 brief): d = d_x·t1 + d_y·t2 + d_z·N with
/// d_z = √(1 − d_x² − d_y²), (t1, t2) glam's `any_orthonormal_pair` of N.
fn texel_direction(s: &Stored, n: DVec3) -> DVec3 {
    let (t1, t2) = n.any_orthonormal_pair();
    let (mut x, mut y) = (scalar(s, "d_x"), scalar(s, "d_y"));
    let r2 = x * x + y * y;
    if r2 > 1.0 {
        (x, y) = (x / r2.sqrt(), y / r2.sqrt());
    }
    t1 * x + t2 * y + n * (1.0 - x * x - y * y).max(0.0).sqrt()
}

#[test]
fn ahd_and_hhd_texels_round_trip() {
    let nn = surface_normal();
    let min_dz = 89.9f64.to_radians().cos();
    for m in MAPS {
        let map = Map::load(m, env!("CARGO_MANIFEST_DIR")).unwrap();
        let light = map.lighting(Surface::Normal(nn)).unwrap();
        // AHD, raw storage: C_a, C_d, d_xy (§7): E/π = C_a + C_d·max(0, n·d).
        for id in ["ahd_linear_hemi", "ahd_search_hemi"] {
            let f = fit(&light, id, "");
            let s = f.stored();
            let (ca, cd, d) = (rgb(&s, "C_a"), rgb(&s, "C_d"), texel_direction(&s, nn));
            assert_round_trip(&format!("{m} {id}"), &f, |n| ca + cd * n.dot(d).max(0.0));
        }
        // HHD in IrradZ form (§7–8): C_a, I_z, d_xy; C_d = max(0, (I_z − C_a)/d_z), and
        // E/π = C_a·(1 + n·N)/2 + C_d·max(0, n·d). The luminance-ratio layout stores
        // L(C_a)/L(I_z) instead of C_a: C_a = ratio·I_z.
        for (id, settings) in [
            ("hhd_linear_hemi", ""),
            ("hhd_search_hemi", ""),
            ("hhd_linear_sphere", "storage = 'irradz_luma'"),
            ("ahd_irradz_2018", ""),
        ] {
            let f = fit(&light, id, settings);
            let s = f.stored();
            let iz = rgb(&s, "I_z");
            let ca = match s.rgb_of("C_a") {
                Some(ca) => ca,
                None => iz * scalar(&s, "ratio"),
            };
            let d = texel_direction(&s, nn);
            let cd = ((iz - ca) / d.dot(nn).max(min_dz)).max(Rgb::ZERO);
            let hhd = id.starts_with("hhd");
            let label = format!("{m} {id} [{settings}]");
            assert_round_trip(&label, &f, |n| {
                let ambient = if hhd { 0.5 * (1.0 + n.dot(nn)) } else { 1.0 };
                ca * ambient + cd * n.dot(d).max(0.0)
            });
            // I_z is the value at N.
            let at_n = f.irradiance(nn);
            assert!((at_n - iz).abs().max_element() <= 1e-9 * iz.abs().max_element().max(1e-300), "{label}: I_z");
        }
    }
}

#[test]
fn ambient_cube_round_trips() {
    for m in MAPS {
        let map = Map::load(m, env!("CARGO_MANIFEST_DIR")).unwrap();
        let light = map.lighting(Surface::Sphere).unwrap();
        for id in ["ambient_cube", "ambient_cube_proj"] {
            let f = fit(&light, id, "");
            let s = f.stored();
            let c: Vec<Rgb> = ["C_-x", "C_+x", "C_-y", "C_+y", "C_-z", "C_+z"].iter().map(|k| rgb(&s, k)).collect();
            // McTaggart 2004: E/π = Σ_axes n_a² · C(the face n_a points to).
            assert_round_trip(&format!("{m} {id}"), &f, |n| {
                let pick = |v: f64, neg: Rgb, pos: Rgb| if v >= 0.0 { pos } else { neg } * (v * v);
                pick(n.x, c[0], c[1]) + pick(n.y, c[2], c[3]) + pick(n.z, c[4], c[5])
            });
        }
    }
}

#[test]
fn hbasis_round_trips() {
    let nn = surface_normal();
    // N's frame (hbasis.rs; Habel & Wimmer 2010): t = the image of +X under the rotation taking
    // +Y to N, s = N × t.
    let t = (glam::DQuat::from_rotation_arc(DVec3::Y, nn) * DVec3::X).normalize();
    let sv = nn.cross(t);
    for m in MAPS {
        let map = Map::load(m, env!("CARGO_MANIFEST_DIR")).unwrap();
        let light = map.lighting(Surface::Normal(nn)).unwrap();
        for (id, count) in [("hbasis4", 4), ("hbasis6", 6)] {
            let f = fit(&light, id, "");
            let s = f.stored();
            let c: Vec<Rgb> = (1..=count).map(|k| rgb(&s, &format!("H{k}"))).collect();
            assert_round_trip(&format!("{m} {id}"), &f, |n| {
                let (x, y, z) = (n.dot(t), n.dot(sv), n.dot(nn));
                let (a, b, d) = (1.0 / (2.0 * PI).sqrt(), (3.0 / (2.0 * PI)).sqrt(), (15.0 / (2.0 * PI)).sqrt());
                let h = [a, b * y, b * (2.0 * z - 1.0), b * x, d * x * y, 0.5 * d * (x * x - y * y)];
                c.iter().zip(h).map(|(c, h)| *c * h).sum()
            });
        }
    }
}

#[test]
fn hlsh_payload_and_srbf_dice_round_trip() {
    let nn = surface_normal();
    for m in MAPS {
        let map = Map::load(m, env!("CARGO_MANIFEST_DIR")).unwrap();
        // HLSH: the probe is stored; the per-N payload is linear, E/π = dc + grad·n.
        let light = map.lighting(Surface::Normal(nn)).unwrap();
        let f = fit(&light, "hlsh", "");
        let s = f.stored();
        assert_eq!(s.scalar_count(), 27, "the probe is what is stored");
        let (dc, gx, gy, gz) =
            (rgb(&s, "payload_dc"), rgb(&s, "payload_grad_x"), rgb(&s, "payload_grad_y"), rgb(&s, "payload_grad_z"));
        assert_round_trip(&format!("{m} hlsh"), &f, |n| dc + gx * n.x + gy * n.y + gz * n.z);

        // The ambient dice's SRBF lobes: E/π = Σ w_i (0.7·c²/2 + 0.3·5c⁴/6), c = max(0, n·v_i),
        // with v_i the normalised cyclic permutations of (±1, ±1/φ, 0).
        let light = map.lighting(Surface::Sphere).unwrap();
        let f = fit(&light, "ambient_dice_srbf", "");
        let s = f.stored();
        let k = (5f64.sqrt() - 1.0) / 2.0;
        let v: Vec<DVec3> = (0..12).map(|i| vector(&s, &format!("vertex_{i}"))).collect();
        for (i, p) in v.iter().enumerate() {
            let mut a = p.to_array().map(f64::abs);
            a.sort_by(f64::total_cmp);
            let want = [0.0, k, 1.0].map(|x| x / (1.0 + k * k).sqrt());
            assert!((0..3).all(|j| (a[j] - want[j]).abs() < 1e-12), "vertex {i} = {p}");
            assert!(v[..i].iter().all(|q| (*q - *p).length() > 0.5), "vertex {i} repeats");
        }
        let w: Vec<Rgb> = (0..12).map(|i| rgb(&s, &format!("w_{i}"))).collect();
        assert_round_trip(&format!("{m} ambient_dice_srbf"), &f, |n| {
            w.iter()
                .zip(&v)
                .map(|(w, p)| {
                    let c = n.dot(*p).max(0.0);
                    *w * (0.7 * c * c / 2.0 + 0.3 * 5.0 * c.powi(4) / 6.0)
                })
                .sum()
        });
    }
}
