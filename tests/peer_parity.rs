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
//!   reconstruction over world +Z. A test inside the crate (`src/tests/peer_hbasis.rs`) rebuilds
//!   them from the peer's definition (within 0.1%), which pins down how we read its source and
//!   its unnormalised H1.

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
