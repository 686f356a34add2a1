//! Parity with the peer tool (Probulator) on the five paper probes: `experiments/probulator_parity.toml`
//! run in a scratch repository, compared with the peer's figures in `../shared/reference/PEER.md`
//! (its reconstructions scored with its metric against our exact reference, so they carry no
//! Monte Carlo noise of the metric itself). Needs the shared maps.
//!
//! Tolerances, and why:
//! - SH (`sh3`, `sh4`, the windowed L2 as the peer): within 1%. Both sides project the same
//!   texels (the peer by texel-centre midpoint, ours by exact cell integrals, which is what the
//!   existing sh1/sh2 parity shows to be ≤ 0.14%) and apply the same band scales.
//! - The ambient cube: the peer fits its Monte Carlo irradiance image, ours the exact E/π, so the
//!   figures are not expected to be equal. With the peer's objective (equal weight per pixel,
//!   `weights = "pixel"`) ours must be no worse than the peer's + 0.1% (rounding of the
//!   five-digit figures); the projection reads exact E/π at the axes where the peer reads its
//!   noisy image at the nearest pixel, so it may differ either way by the image's noise: within
//!   3% (PEER.md: the noise is 1–3% of the map mean).
//! - The ambient dice (`ambient_dice`, `_ycocg`, `_srbf`): the peer fits its Monte Carlo image by
//!   least squares with solid-angle weights; ours fits the exact E/π with the same weights. In
//!   the fit's own weighting ours can only be better (the fitted noise is orthogonal to the
//!   residual), but the figures are per pixel, a weighting neither fit minimises, where the
//!   noise that survives the peer's fit can move its figure either way. That noise is about
//!   σ·√(p/N) per pixel (σ ≈ 2% of the map mean, p = 12–36 functions, N = 32,768 pixels): 0.3–3%
//!   of these figures, and far less in practice. Allowance: ours ≤ the peer's + 1% (measured: at
//!   most +0.10%, `ambient_dice_srbf` on uffizi; every other figure is lower, by up to 21%). The
//!   same fits with per-pixel weights (`*_pixel`), the metric's own weighting, must be no worse
//!   than the peer's + 0.1% (rounding), like the ambient cube.
//! - The H-basis has no encoder here to compare: the peer's H4/H6 figures are a clamped radiance
//!   reconstruction over world +Z. A second test rebuilds them from the peer's definition
//!   (within 0.1%), which pins down how we read its source and its unnormalised H1.

mod common;

use common::harness::{parse_csv, Scratch};
use common::shared_maps::{shared_envmaps, PAPER_PROBES};

/// PEER.md's figures: (our id, [ennis, grace, pisa, uffizi, wells]).
const PEER: &[(&str, [f64; 5])] = &[
    ("sh3", [0.09407, 0.01300, 0.00500, 0.03719, 0.00606]),
    ("sh4", [0.02980, 0.00540, 0.00128, 0.01069, 0.00175]),
    ("sh2_windowed_peer", [0.65375, 0.01300, 0.00500, 0.26135, 0.00606]),
    ("ambient_cube_pixel", [0.39747, 0.04403, 0.03406, 0.18195, 0.04795]),
    ("ambient_cube_proj", [0.46505, 0.05207, 0.03793, 0.22130, 0.05480]),
    ("ambient_dice", AD),
    ("ambient_dice_pixel", AD),
    ("ambient_dice_ycocg", AD_YCOCG),
    ("ambient_dice_ycocg_pixel", AD_YCOCG),
    ("ambient_dice_srbf", AD_RBF),
    ("ambient_dice_srbf_pixel", AD_RBF),
];
/// PEER.md's AD, ADYCoCg and ADRBF.
const AD: [f64; 5] = [0.03996, 0.00781, 0.00386, 0.02022, 0.00634];
const AD_YCOCG: [f64; 5] = [0.04162, 0.00985, 0.00547, 0.02078, 0.00756];
const AD_RBF: [f64; 5] = [0.10649, 0.01489, 0.00447, 0.05708, 0.00764];

#[test]
#[cfg_attr(
    not(shared_maps),
    ignore = "needs the paper probes (not CC0, not in the repository): set PROBELAB_ENVMAPS to a folder holding them, see envmaps/README.md"
)]
fn the_peer_encodings_match_peer_md() {
    let env = shared_envmaps(&PAPER_PROBES);
    let s = Scratch::new();
    s.copy_from_repo("experiments/probulator_parity.toml");
    let out = s
        .probelab()
        .args(["--no-timing", "run", "experiments/probulator_parity.toml"])
        .env("PROBELAB_ENVMAPS", env)
        .output()
        .expect("run probelab");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let table = std::fs::read_to_string(s.path().join("results/probulator_parity/table.csv")).unwrap();
    let rows = parse_csv(&table);
    let mut failures = Vec::new();
    for (id, figures) in PEER {
        for (map, peer) in PAPER_PROBES.iter().zip(figures) {
            let r =
                rows.iter().find(|r| r["encoder"] == *id && r["map"] == *map).unwrap_or_else(|| panic!("{id} {map}"));
            assert_eq!(r["weighting"], "per-pixel");
            let ours: f64 = r["rmse"].parse().unwrap();
            let rel = ours / peer - 1.0;
            eprintln!("{id:20} {map:18} ours {ours:.5} peer {peer:.5} {:+.3}%", 100.0 * rel);
            let ok = match *id {
                "ambient_cube_pixel"
                | "ambient_dice_pixel"
                | "ambient_dice_ycocg_pixel"
                | "ambient_dice_srbf_pixel" => rel <= 1e-3,
                "ambient_dice" | "ambient_dice_ycocg" | "ambient_dice_srbf" => rel <= 0.01,
                "ambient_cube_proj" => rel.abs() <= 0.03,
                _ => rel.abs() <= 0.01,
            };
            if !ok {
                failures.push(format!("{id} on {map}: ours {ours} vs peer {peer}"));
            }
        }
    }
    // sh3 adds nothing to irradiance: it equals sh2 on every map.
    for map in PAPER_PROBES {
        let get = |id: &str| rows.iter().find(|r| r["encoder"] == id && r["map"] == map).unwrap()["rmse"].clone();
        assert_eq!(get("sh3"), get("sh2"), "{map}");
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The peer's H-basis figures (H4, H6), reproduced from its definition to confirm how we read
/// its source. This is no encoder of ours: the peer's figure is the clamped *radiance*
/// reconstruction over the world +Z hemisphere, scored as if it were irradiance (PEER.md);
/// `hbasis4`/`hbasis6` are irradiance encodings over the hemisphere about N. As the peer
/// (`HBasis.h`, `ExperimentHBasis.h`): its 20,000 Halton radiance samples (nearest texel) are
/// projected with weight 4π/N onto H1 = 1/(2√π), H2 = √(3/2π)·y′, H3 = √(3/2π)(2z − 1),
/// H4 = √(3/2π)·x′, H5 = √(15/2π)·x′y′, H6 = ½√(15/2π)(x′² − y′²), x′ = −x, y′ = −y, all zero
/// for z < 0; the reconstruction is clamped at 0 and is 0 below +Z; the peer metric against
/// our exact E/π at 256×128. Within 0.1% of PEER.md (measured: all ten to the five digits
/// given; samples in f64 here, f32 there). With the normalised H1 = 1/√(2π) instead the
/// figures move by 0.04–6.3% (uffizi H6), so they carry the peer's H1, whose square integrates
/// to ½ over the hemisphere: a slip that halves the constant term.
#[test]
#[cfg_attr(
    not(shared_maps),
    ignore = "needs the paper probes (not CC0, not in the repository): set PROBELAB_ENVMAPS to a folder holding them, see envmaps/README.md"
)]
fn the_peers_hbasis_figures_are_a_clamped_radiance_reconstruction() {
    use glam::DVec3;
    use probelab::envmap::moments::RowMoments;
    use probelab::envmap::search::SearchPath;
    use probelab::envmap::LatLong;
    use probelab::math::colour::Rgb;
    use probelab::reference::exact::{Reference, DEFAULT_POLAR_NODES};
    use probelab::reference::metrics::score;
    use probelab::reference::radiance::{MapLight, RadianceSource};
    use std::f64::consts::PI;

    const H4: [f64; 5] = [1.64600, 0.29816, 0.18197, 1.03221, 0.16338];
    const H6: [f64; 5] = [1.64735, 0.29002, 0.18392, 1.13015, 0.19034];
    let env = shared_envmaps(&PAPER_PROBES);
    let search = SearchPath::new(std::env::split_paths(&env).collect());
    let peer_basis = |d: DVec3, h1: f64| -> [f64; 6] {
        if d.z < 0.0 {
            return [0.0; 6];
        }
        let (x, y, z) = (-d.x, -d.y, d.z);
        let (c3, c15) = ((3.0 / (2.0 * PI)).sqrt(), (15.0 / (2.0 * PI)).sqrt());
        [h1, -c3 * y, c3 * (2.0 * z - 1.0), -c3 * x, c15 * x * y, 0.5 * c15 * (x * x - y * y)]
    };
    let (mut fails, mut normalised_miss) = (Vec::new(), 0.0f64);
    for (m, name) in PAPER_PROBES.iter().enumerate() {
        let map = search.load(name).unwrap();
        let rm = RowMoments::new(&map);
        let grid = LatLong::new(256, 128);
        let reference = Reference::new(&rm, vec![], DEFAULT_POLAR_NODES).irradiance_latlong(grid);
        let light = MapLight::new(&map, &rm, vec![], DEFAULT_POLAR_NODES);
        let samples = light.samples();
        let normals: Vec<DVec3> = (0..grid.height)
            .flat_map(|j| (0..grid.width).map(move |i| (i, j)))
            .map(|(i, j)| grid.direction(i, j))
            .collect();
        for (count, figures) in [(4, H4), (6, H6)] {
            let rmse = |h1: f64| {
                let mut c = [Rgb::ZERO; 6];
                for s in samples {
                    let h = peer_basis(s.direction, h1);
                    for k in 0..count {
                        c[k] += s.radiance * (h[k] * 4.0 * PI / samples.len() as f64);
                    }
                }
                let test: Vec<Rgb> = normals
                    .iter()
                    .map(|&n| {
                        let h = peer_basis(n, h1);
                        (0..count).fold(Rgb::ZERO, |a, k| a + c[k] * h[k]).max(Rgb::ZERO)
                    })
                    .collect();
                score(&reference, &test, &vec![1.0; test.len()], true).rmse
            };
            let (peer_h1, normalised_h1) = (rmse(0.5 / PI.sqrt()), rmse(1.0 / (2.0 * PI).sqrt()));
            let rel = peer_h1 / figures[m] - 1.0;
            eprintln!(
                "H{count} {name}: as the peer {peer_h1:.5} (PEER.md {:.5}, {:+.2}%), with a normalised H1 {normalised_h1:.5}",
                figures[m],
                100.0 * rel
            );
            if rel.abs() > 1e-3 {
                fails.push(format!("H{count} on {name}: {peer_h1} vs PEER.md {}", figures[m]));
            }
            normalised_miss = normalised_miss.max((normalised_h1 / figures[m] - 1.0).abs());
        }
    }
    assert!(fails.is_empty(), "{}", fails.join("\n"));
    assert!(normalised_miss > 0.05, "a normalised H1 also gives the peer's figures (at most {normalised_miss} off)");
}

/// Every registered encoder that needs a surface normal (H-basis, AHD/HHD, the occlusion
/// operators) is in some committed hemisphere experiment and in no sphere one: every committed
/// experiment and sweep loads (the loader refuses a surface encoder on the sphere), and the
/// sphere landscape lists none of them. Needs no maps.
#[test]
fn surface_encoders_are_in_hemisphere_experiments_only() {
    use probelab::pipeline::experiment::DomainKind;
    use probelab::pipeline::experiment::Experiment;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let mut files: Vec<std::path::PathBuf> = Vec::new();
    for d in [dir.clone(), dir.join("sweeps")] {
        for f in std::fs::read_dir(&d).unwrap() {
            let f = f.unwrap().path();
            if f.extension().is_some_and(|x| x == "toml") {
                files.push(f);
            }
        }
    }
    let mut on_hemisphere = std::collections::BTreeSet::new();
    for f in &files {
        let e = if f.parent().unwrap().ends_with("sweeps") {
            probelab::pipeline::sweep::Sweep::load(f).unwrap_or_else(|e| panic!("{e:#}")).exp
        } else {
            Experiment::load(f).unwrap_or_else(|e| panic!("{e:#}"))
        };
        for n in &e.encoders {
            if e.domain == DomainKind::Hemisphere {
                on_hemisphere.insert(n.encoder.id().to_string());
            } else {
                assert!(!n.encoder.needs_surface_normal(), "{}: {} on the sphere", f.display(), n.name);
            }
        }
    }
    let mut needing = 0;
    for k in probelab::encoders::REGISTRY {
        let e = probelab::encoders::build(k.id, None, toml::Table::new()).unwrap();
        if e.encoder.needs_surface_normal() {
            needing += 1;
            assert!(on_hemisphere.contains(k.id), "{} is in no committed hemisphere experiment", k.id);
        }
    }
    // H4, H6, 5 AHD, 5 HHD, 8 occlusion operators (all but probe_unoccluded).
    assert_eq!(needing, 2 + 5 + 5 + 8);
}
