//! An experiment that does not declare an effect never pays for it: the runner computes no
//! masked SH projection and builds no capped reference, and the visible SH it hands the
//! encoders is the probe SH itself. One test in its own binary, so the process-wide
//! counters see no other work.

use probelab::envmap::EnvMap;
use probelab::pipeline::experiment::{Experiment, ExperimentFile};
use probelab::pipeline::runner::{cases, run_map, CaseData, MapData};
use probelab::reference::exact::capped_reference_count;
use probelab::reference::projection::masked_projection_count;

fn experiment(extra: &str) -> Experiment {
    // hlsh needs a surface normal, so the sphere (no `domain`) scores sh2 alone.
    let encoders = if extra.is_empty() { "['sh2']" } else { "['sh2', 'hlsh']" };
    let text = format!("maps = ['t']\nencoders = {encoders}\nresolution = [16, 8]\n{extra}");
    let file: ExperimentFile = toml::from_str(&text).unwrap();
    Experiment::from_file(file, "t").unwrap()
}

/// (masked projections, capped references) that running `exp` on `map` costs.
fn cost(exp: &Experiment, map: &EnvMap) -> (usize, usize) {
    let (p0, r0) = (masked_projection_count(), capped_reference_count());
    let rows = run_map(exp, map);
    assert!(!rows.is_empty());
    (masked_projection_count() - p0, capped_reference_count() - r0)
}

#[test]
fn undeclared_effects_cost_nothing() {
    let map = EnvMap::from_fn("t", 32, 16, |i, j| [(i % 5) as f32 + 0.5, j as f32 * 0.1, 1.0]).unwrap();
    // The timing pass (a separate pass after scoring) prepares each case again; count only the
    // scoring pass here.
    probelab::pipeline::timing::set_enabled(false);

    // Hemisphere domain over six walls/floors/ceilings, no effect: nothing masked.
    let none = experiment("domain = 'hemisphere'\norientations = ['axes6']");
    assert_eq!(cost(&none, &map), (0, 0));
    let data = MapData::new(&map);
    for case in cases(&none) {
        let cd = CaseData::new(&data, &case, none.polar_nodes);
        assert!(cd.reference.caps().is_empty());
        // Bit-identical: the masked projection of no caps would differ in rounding.
        assert_eq!(cd.inputs.visible_sh, data.probe_sh);
    }
    // The sphere: nothing masked either.
    assert_eq!(cost(&experiment(""), &map), (0, 0));

    // Declared: one masked projection and one capped reference per case.
    let hemi = experiment("domain = 'hemisphere'\norientations = ['axes6']\neffects = ['hemisphere']");
    assert_eq!(cost(&hemi, &map), (6, 6));
    let cone = experiment(
        "domain = 'hemisphere'\norientations = ['up']\neffects = [{ kind = 'cone', cos_alpha = [0.0, 0.5], tilt_deg = [0, 30] }]",
    );
    assert_eq!(cost(&cone, &map), (4, 4));
    let data = MapData::new(&map);
    for case in cases(&hemi) {
        let cd = CaseData::new(&data, &case, hemi.polar_nodes);
        assert_eq!(cd.reference.caps().len(), 1);
        assert_ne!(cd.inputs.visible_sh, data.probe_sh);
    }
}
