//! `check` catches a changed band scale (`regression::check::compare_with_baseline`): sh1 with
//! band 1 scaled by a rounded Â₁, run through the runner on the committed generated_scenes
//! experiment, moves exactly the numbers it should against the committed baseline. `check`
//! through the binary is `tests/regression.rs`.

use super::repository::repo;
use crate::encoders::encoder::{Encoder, FitInput, Fitted};
use crate::encoders::NamedEncoder;
use crate::envmap::search::SearchPath;
use crate::math::sh::band_of;
use crate::pipeline::experiment::Experiment;
use crate::regression::check::{compare_with_baseline, Finding};
use crate::regression::tolerance::Tolerances;

/// A deliberately broken variant of sh1: band 1 scaled by 0.6667 instead of Â₁ = 2/3 (a
/// rounded constant, 5e-5 relative). Everything else as `sh1` (FORMULAS §3).
struct BrokenSh1;

impl Encoder for BrokenSh1 {
    fn id(&self) -> &str {
        "sh1"
    }
    fn stored_scalars(&self) -> usize {
        12
    }
    fn fit(&self, input: &FitInput) -> Box<dyn Fitted> {
        let mut sh = input.visible_sh.truncate(1);
        for i in 0..9 {
            sh[i] *= [1.0, 0.6667, 0.25][band_of(i)];
        }
        Box::new(crate::encoders::sh::ShIrradiance(sh, 1))
    }
}

/// `check` catches the broken band scale against the committed generated_scenes baseline: it
/// reports moved numbers for sh1 on every scene with a linear (band 1) component, and nothing
/// else — not for sh0 or sh2, and not for the constant scene, whose band 1 is zero.
#[test]
fn check_catches_a_changed_band_scale() {
    let mut exp = Experiment::load(&repo().join("experiments/generated_scenes.toml")).unwrap();
    let i = exp.encoders.iter().position(|e| e.name == "sh1").expect("generated_scenes has sh1");
    exp.encoders[i] = NamedEncoder { name: "sh1".into(), encoder: Box::new(BrokenSh1) };
    let search = SearchPath::new(vec![repo().join("envmaps")]);
    let report = crate::pipeline::runner::run(
        &exp,
        &search,
        &Default::default(),
        &crate::pipeline::reuse::ReferenceCache::new(None),
    )
    .unwrap();
    let tolerances = Tolerances::load(&repo()).unwrap();
    let c = compare_with_baseline(
        &repo().join("results/generated_scenes"),
        &exp,
        &report,
        &tolerances,
        crate::regression::check::MapPolicy::RequireAll,
    )
    .unwrap();
    let report_text = crate::ops::check::text::experiment(&c);
    assert!(!c.passed());
    let mut maps = std::collections::BTreeSet::new();
    for f in &c.findings {
        match f {
            Finding::Change(crate::regression::baseline::Change::Moved { key, .. }) if key.encoder == "sh1" => {
                maps.insert(key.map.clone());
            }
            other => panic!("unexpected finding: {other}"),
        }
    }
    let want: std::collections::BTreeSet<String> =
        ["gen_hemisphere", "gen_sun_sky", "gen_two_lights", "gen_cone", "gen_sky_sun"].map(String::from).into();
    assert_eq!(maps, want);
    assert!(
        report_text.contains("generated_scenes: moved    gen_sun_sky  sh1  sphere  exact  rmse  "),
        "{report_text}"
    );
}
