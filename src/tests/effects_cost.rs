//! An experiment that does not declare an effect never pays for it: the runner computes no
//! masked SH projection and builds no capped reference, and the visible SH it hands the
//! encoders is the probe SH itself. What a run computed is read from its own profile: a case
//! under caps is set up in the phase `CAPPED_CASE_SETUP` (one masked projection, one capped
//! reference), any other in "case setup".

use crate::envmap::EnvMap;
use crate::io::profile::Profile;
use crate::pipeline::experiment::{Experiment, ExperimentFile};
use crate::pipeline::runner::{cases, run_map, CaseData, MapData, CAPPED_CASE_SETUP};
use crate::pipeline::settings::RunSettings;

fn experiment(extra: &str) -> Experiment {
    // hlsh needs a surface normal, so the sphere (no `domain`) scores sh2 alone.
    let encoders = if extra.is_empty() { "['sh2']" } else { "['sh2', 'hlsh']" };
    let text = format!("maps = ['t']\nencoders = {encoders}\nresolution = [16, 8]\n{extra}");
    let file: ExperimentFile = toml::from_str(&text).unwrap();
    Experiment::from_file(file, "t").unwrap()
}

/// (cases set up under caps, cases set up without) when running `exp` on `map`. The timing
/// pass (a separate pass after scoring) prepares each case again: only the scoring pass counts.
fn cost(exp: &Experiment, map: &EnvMap) -> (u64, u64) {
    let profile = Profile::new();
    let settings = RunSettings { timing: false, profile: Some(&profile), cancel: None };
    let rows = run_map(exp, map, &settings);
    assert!(!rows.is_empty());
    (profile.calls(CAPPED_CASE_SETUP), profile.calls("case setup"))
}

#[test]
fn undeclared_effects_cost_nothing() {
    let map = EnvMap::from_fn("t", 32, 16, |i, j| [(i % 5) as f32 + 0.5, j as f32 * 0.1, 1.0]).unwrap();

    // Hemisphere domain over six walls/floors/ceilings, no effect: nothing masked.
    let none = experiment("domain = 'hemisphere'\norientations = ['axes6']");
    assert_eq!(cost(&none, &map), (0, 6));
    let data = MapData::new(&map);
    for case in cases(&none) {
        let cd = CaseData::new(&data, &case, none.polar_nodes);
        assert!(cd.reference.caps().is_empty());
        // Bit-identical: the masked projection of no caps would differ in rounding.
        assert_eq!(cd.inputs.visible_sh, data.probe_sh);
    }
    // The sphere: nothing masked either.
    assert_eq!(cost(&experiment(""), &map), (0, 1));

    // Declared: one masked projection and one capped reference per case.
    let hemi = experiment("domain = 'hemisphere'\norientations = ['axes6']\neffects = ['hemisphere']");
    assert_eq!(cost(&hemi, &map), (6, 0));
    let cone = experiment(
        "domain = 'hemisphere'\norientations = ['up']\neffects = [{ kind = 'cone', cos_alpha = [0.0, 0.5], tilt_deg = [0, 30] }]",
    );
    assert_eq!(cost(&cone, &map), (4, 0));
    let data = MapData::new(&map);
    for case in cases(&hemi) {
        let cd = CaseData::new(&data, &case, hemi.polar_nodes);
        assert_eq!(cd.reference.caps().len(), 1);
        assert_ne!(cd.inputs.visible_sh, data.probe_sh);
    }
}
