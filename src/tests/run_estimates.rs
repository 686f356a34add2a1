//! Everything committed is estimated under the bound of long runs
//! (`pipeline::estimate::BOUND_S`, 30 minutes): each experiment, each sweep, and `reproduce` as
//! a whole, so nothing needs `--allow-long`. The refusals themselves run through the binary
//! (`tests/long_runs.rs`). docs/robustness.md, "Long runs".

use super::repository::repo;
use crate::envmap::search::SearchPath;
use crate::pipeline::estimate::{self, Estimate, BOUND_S};
use crate::pipeline::experiment::{list_experiments, Experiment};
use crate::pipeline::sweep::Sweep;

/// The size assumed for a map the search path does not find here that is not a known map
/// (`envmaps/known.toml` gives the size of those, the paper probes without
/// `PROBELAB_ENVMAPS` among them): at least as large as any map the committed files name.
const UNFOUND: (usize, usize) = (2048, 1024);

/// The committed search path: the repository's maps, then `PROBELAB_ENVMAPS`.
fn search() -> SearchPath {
    SearchPath::from_env(repo().join("envmaps"))
}

/// Each map's size from its header, else its known size, else [`UNFOUND`].
fn sizes(maps: &[String], search: &SearchPath) -> Vec<(usize, usize)> {
    maps.iter()
        .map(|m| {
            let known = || crate::envmap::known::by_name(m).map(|k| (k.width, k.height));
            search
                .resolve(m)
                .ok()
                .and_then(|p| crate::envmap::load::dimensions(&p).ok())
                .or_else(known)
                .unwrap_or(UNFOUND)
        })
        .collect()
}

/// Every committed experiment, every sweep, and `reproduce` (all the experiments together) are
/// estimated under the bound: none needs `--allow-long`.
#[test]
fn every_committed_run_is_estimated_under_the_bound() {
    let search = search();
    let mut parts = Vec::new();
    for path in list_experiments(&repo().join("experiments")).unwrap() {
        let exp = Experiment::load(&path).unwrap();
        let e = estimate::experiment_on(&exp, &sizes(&exp.maps, &search));
        assert!(!e.is_long(), "{}: {e}", path.display());
        parts.push(e);
    }
    let all = Estimate::total(&parts);
    assert!(all.seconds < BOUND_S, "reproduce: {all}");
    for path in list_experiments(&repo().join("experiments").join("sweeps")).unwrap() {
        let sweep = Sweep::load(&path).unwrap();
        let e = estimate::sweep_on(&sweep, &sizes(&sweep.exp.maps, &search));
        assert!(!e.is_long(), "{}: {e}", path.display());
    }
}
