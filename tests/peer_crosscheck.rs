//! Agreement with the peer tool (Probulator) on grace_256x128 under `--metric probulator`: its
//! published errors, measured against its Monte Carlo reference, are matched by ours within a
//! few percent. Needs the shared maps.

mod common;

use common::harness::{parse_csv, probelab, stdout_ok, Run};
use common::shared_maps::shared_envmaps;

/// `probelab eval grace_256x128 --metric probulator` for `encoders`, with the shared maps.
fn eval_on_grace(encoders: &str) -> Vec<std::collections::HashMap<String, String>> {
    let env = shared_envmaps(&["grace_256x128"]);
    let out = probelab()
        .args(["eval", "grace_256x128", "--encoders", encoders, "--metric", "probulator"])
        .env("PROBELAB_ENVMAPS", env)
        .run();
    parse_csv(&stdout_ok(&out))
}

/// The peer reports sh1 = 0.08238 and sh2 = 0.01324; ours within 3%.
#[test]
#[cfg_attr(
    not(shared_maps),
    ignore = "needs the paper probes (not CC0, not in the repository): set PROBELAB_ENVMAPS to a folder holding them, see envmaps/README.md"
)]
fn sh_agrees_with_the_peer_on_grace() {
    let rows = eval_on_grace("sh1,sh2");
    assert_eq!(rows.len(), 2);
    for (r, peer) in rows.iter().zip([0.08238, 0.01324]) {
        let ours: f64 = r["rmse"].parse().unwrap();
        let rel = (ours - peer).abs() / peer;
        eprintln!("{}: ours {ours:.5}, peer {peer}, {:.2}%", r["encoder"], 100.0 * rel);
        assert!(rel < 0.03, "{}: {ours} vs {peer}", r["encoder"]);
        assert_eq!(r["weighting"], "per-pixel");
    }
}

/// The peer reports 0.04191 (zh3_hallucinate) and 0.01395 (zh3_solved_shared); ours within 4%.
#[test]
#[cfg_attr(
    not(shared_maps),
    ignore = "needs the paper probes (not CC0, not in the repository): set PROBELAB_ENVMAPS to a folder holding them, see envmaps/README.md"
)]
fn zh3_agrees_with_the_peer_on_grace() {
    let rows = eval_on_grace("zh3_hallucinate,zh3_solved_shared");
    assert_eq!(rows.len(), 2);
    for (row, peer) in rows.iter().zip([0.04191, 0.01395]) {
        let rmse: f64 = row["rmse"].parse().unwrap();
        assert!((rmse / peer - 1.0).abs() < 0.04, "{}: {rmse} vs peer {peer}", row["encoder"]);
        assert_eq!(row["weighting"], "per-pixel");
    }
    assert!(rows[1]["diagnostics"].contains("iters="), "{}", rows[1]["diagnostics"]);
}
