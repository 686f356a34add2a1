//! `Fitted::stored` over every registered encoder, fitted through the public API on a committed
//! CC0 map: the stored scalars number exactly `Encoder::stored_scalars` (the count the tables'
//! `stored_scalars` column and the cost charts use), every value is finite, and the stored form
//! is well formed (a basis, unique names, unit directions).
//!
//! Each encoder is fitted where it is defined: on the sphere unless it needs a surface normal,
//! and about a tilted surface normal N in every case (an occlusion operator or lightmap texel
//! has its per-N payload there). The count is per probe or texel for every encoder: what is
//! shared by all probes (the SG lobes, the ambient dice's vertices and frames) and what is
//! recomputed per normal (an occlusion operator's payload, a zonal axis, decoded colours) is
//! listed as derived and not counted.

use probelab::{encoder_ids, DVec3, Fit, Map, Role, Surface, Unit, Value};
use std::collections::HashSet;

fn map() -> Map {
    Map::load("blender_city_256x128", env!("CARGO_MANIFEST_DIR")).expect("the committed CC0 map")
}

fn check(fit: &Fit, label: &str) {
    let s = fit.stored();
    assert_eq!(
        s.scalar_count(),
        fit.stored_scalars(),
        "{label}: stored() holds {} stored scalars, stored_scalars() says {}",
        s.scalar_count(),
        fit.stored_scalars()
    );
    assert!(s.is_finite(), "{label}: a value is not finite: {s:?}");
    assert!(!s.basis.is_empty(), "{label}: no basis");
    assert!(s.entries.iter().any(|e| e.role == Role::Stored), "{label}: nothing stored");
    let mut names = HashSet::new();
    for e in &s.entries {
        assert!(names.insert(e.name.clone()), "{label}: entry '{}' twice", e.name);
        if e.unit == Unit::Direction {
            let Value::Vector(v) = e.value else { panic!("{label}: direction '{}' is not a vector", e.name) };
            assert!((v.length() - 1.0).abs() < 1e-9, "{label}: direction '{}' = {v} is not unit", e.name);
        }
    }
}

#[test]
fn every_registered_encoder_stores_what_it_counts() {
    let map = map();
    let sphere = map.lighting(Surface::Sphere).unwrap();
    let surface = map.lighting(Surface::Normal(DVec3::new(0.3, 0.8, -0.5))).unwrap();
    let ids = encoder_ids();
    assert!(ids.len() >= 50, "the registry lost encoders: {ids:?}");
    for id in ids {
        let on_surface = surface.fit(id, "").unwrap();
        check(&on_surface, &format!("{id} about N"));
        if on_surface.needs_surface_normal() {
            // Refused on the sphere, with the reason.
            let e = sphere.fit(id, "").err().expect("refused on the sphere").to_string();
            assert!(e.contains("needs a surface normal"), "{id}: {e}");
        } else {
            check(&sphere.fit(id, "").unwrap(), &format!("{id} on the sphere"));
        }
    }
}

/// The settings that change the stored layout keep the count too: the three texel storages,
/// the quantised ZH3s, SH output bands of the occlusion operators, a wrapped encoder.
#[test]
fn settings_that_change_the_layout_keep_the_count() {
    let map = map();
    let surface = map.lighting(Surface::Normal(DVec3::new(-0.2, 0.9, 0.4))).unwrap();
    let cases = [
        ("hhd_linear_hemi", "storage = 'irradz_luma'", 6),
        ("hhd_linear_hemi", "storage = 'raw'", 8),
        ("ahd_linear_hemi", "storage = 'irradz_rgb'", 8),
        ("hhd_from_sh1", "storage = 'irradz_luma'", 6),
        ("hhd_from_sh1", "", 12),
        ("zh3_stored_shared", "quantise = 'ratio8'", 15),
        ("zh3_hallucinate", "quantise = 'ratio8'", 12),
        ("probe_hemi_full", "output_bands = 1", 27),
        ("with_self_bounce", "inner = 'hhd_search_hemi'", 8),
        ("with_self_bounce", "inner = 'zh3_stored_shared'", 15),
    ];
    for (id, settings, want) in cases {
        let fit = surface.fit(id, settings).unwrap_or_else(|e| panic!("{id} {settings}: {e:#}"));
        assert_eq!(fit.stored_scalars(), want, "{id} {settings}");
        check(&fit, &format!("{id} [{settings}]"));
    }
}
