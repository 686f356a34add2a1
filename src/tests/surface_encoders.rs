//! Where the encoders defined only about a surface normal are declared: every committed
//! experiment and sweep loads, and each such encoder is in a hemisphere experiment and in no
//! sphere one (`Encoder::needs_surface_normal`; the loader refuses it on the sphere).

/// Every registered encoder that needs a surface normal (H-basis, AHD/HHD, the occlusion
/// operators) is in some committed hemisphere experiment and in no sphere one: every committed
/// experiment and sweep loads (the loader refuses a surface encoder on the sphere), and the
/// sphere landscape lists none of them. Needs no maps.
#[test]
fn surface_encoders_are_in_hemisphere_experiments_only() {
    use crate::pipeline::experiment::DomainKind;
    use crate::pipeline::experiment::Experiment;
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
            crate::pipeline::sweep::Sweep::load(f).unwrap_or_else(|e| panic!("{e:#}")).exp
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
    for k in crate::encoders::REGISTRY {
        let e = crate::encoders::build(k.id, None, toml::Table::new()).unwrap();
        if e.encoder.needs_surface_normal() {
            needing += 1;
            assert!(on_hemisphere.contains(k.id), "{} is in no committed hemisphere experiment", k.id);
        }
    }
    // H4, H6, 5 AHD, 5 HHD, 8 occlusion operators (all but probe_unoccluded).
    assert_eq!(needing, 2 + 5 + 5 + 8);
}
