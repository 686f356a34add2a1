//! The declarations' parser and loader: what each key accepts and refuses.

use super::paper::SAYS_MAX;
use super::parse::parse;
use super::*;
use anyhow::Result;
use std::path::Path;

fn paper(claim: &str) -> Result<Paper> {
    let text = format!(
        "title='T'\nauthors='A'\nvenue='V'\norder=1\n[map_sets]\npaper=['m1']\n[[claim]]\nid='X1'\nsays='s'\n\
         paper_figure='p'\ncriterion='c'\nkind='measured'\nfixed='before data'\ndiffers='d'\n{claim}"
    );
    parse("t", &text, Path::new("t.toml"))
}

fn err(claim: &str) -> String {
    format!("{:#}", paper(claim).unwrap_err())
}

/// A table name leaves no folder: `measure:../../x`, `../x`, a hidden name are refused
/// with the file, the line and the key.
#[test]
fn table_names_stay_in_their_folder() {
    for table in ["measure:../../x", "../x", "measure:.hidden", "a/b", "measure:"] {
        let e = err(&format!(
            "[[claim.check]]\nname='n'\ntable='{table}'\nencoder='a'\ntest='every_at_most'\nbound=1\nrole='primary'"
        ));
        assert!(e.starts_with("t.toml:17: key 'table':") && e.contains("not a plain name"), "{table}: {e}");
    }
}

#[test]
fn a_valid_claim_parses_with_defaults() {
    let p =
        paper("[[claim.check]]\nname='n'\ntable='exp'\nencoder='a'\nbaseline='b'\ntest='ratio_every'\nrole='primary'")
            .unwrap();
    let k = &p.claims[0].checks[0];
    assert_eq!(k.test, Test::RatioEvery { below: 1.0, per_map: false });
    assert!(k.primary && !k.beside);
    assert_eq!(p.claims[0].kind, Kind::Measured);
    assert_eq!(p.claims[0].primary().name, "n");
    assert_eq!(k.column, "rmse");
    assert_eq!(k.on, vec!["all".to_string()]);
    assert_eq!(k.source, Source::Experiment("exp".into()));
    let m = paper(
        "[[claim.check]]\nname='n'\ntable='measure:z'\nencoder='a'\ntest='every_at_most'\nbound=1\nrole='primary'",
    )
    .unwrap();
    assert_eq!(m.claims[0].checks[0].source.path(), Path::new("claims/measures/z.csv"));
}

#[test]
fn bad_declarations_name_the_claim_and_key() {
    let base = "[[claim.check]]\nname='n'\ntable='exp'\nencoder='a'\nrole='primary'\n";
    assert!(err("").contains("no [[claim.check]]"));
    assert!(err(&format!("{base}test='ratio_every'")).contains("needs 'baseline'"));
    assert!(err(&format!("{base}baseline='b'\ntest='nope'")).contains("test 'nope'"));
    assert!(err(&format!("{base}baseline='b'\ntest='ratio_stat'\nmin=0.5")).contains("needs 'statistic'"));
    assert!(err(&format!("{base}baseline='b'\ntest='ratio_stat'\nstatistic='ratio_of_means'\nmin=1"))
        .contains("a ratio of pooled means is not offered"));
    assert!(
        err(&format!("{base}baseline='b'\ntest='ratio_stat'\nstatistic='median'")).contains("needs 'min' and/or 'max'")
    );
    assert!(err(&format!("{base}test='every_at_most'")).contains("needs 'bound'"));
    assert!(err(&format!("{base}test='every_at_most'\nbound=nan")).contains("finite"));
    assert!(err(&format!("{base}test='every_at_most'\nbound=1\nbelow=2")).contains("'below' is not used"));
    assert!(err(&format!("{base}baseline='b'\ntest='ratio_every'\non=['elsewhere']")).contains("map set 'elsewhere'"));
    let ctx = "[[claim.check]]\nname='n'\ntable='exp'\nencoder='a'\nbaseline='b'\n";
    assert!(err(&format!("{ctx}test='ratio_every'\nrole='maybe'")).contains("role 'maybe'"));
    assert!(err(&format!("{ctx}test='ratio_every'")).contains("0 checks have role = \"primary\""));
    assert!(err(&format!("{base}baseline='b'\ntest='ratio_every'\n{base}baseline='b'\ntest='ratio_some'"))
        .contains("2 checks have role = \"primary\""));
    assert!(err(&format!("{base}baseline='b'\ntest='ratio_every'\nbeside=true")).contains("'beside' is for a context"));
    assert!(err(&format!("{base}test='every_at_most'\nbound=1\nper_map=true")).contains("'per_map' is not used"));
    // The kind decides what the primary may be.
    assert!(err(&format!("{base}baseline='b'\ntest='ratio_summary'")).contains("needs a criterion"));
    let anchor = |check: &str| {
        let text = format!(
            "title='T'\nauthors='A'\nvenue='V'\norder=1\n[[claim]]\nid='X1'\nsays='s'\npaper_figure='p'\n\
             criterion='c'\nkind='anchor'\nfixed='after data: the band was set on our maps'\ndiffers='d'\n{check}"
        );
        parse("t", &text, Path::new("t.toml"))
    };
    assert!(anchor(&format!("{base}baseline='b'\ntest='ratio_summary'")).is_ok());
    assert!(format!("{:#}", anchor(&format!("{base}baseline='b'\ntest='ratio_every'")).unwrap_err())
        .contains("not comparable"));
    for (key, bad, says) in [
        ("kind", "kind='guess'", "kind 'guess'"),
        ("fixed", "fixed='later'", "fixed 'later'"),
        ("fixed", "fixed='after data: '", "fixed 'after data: '"),
        ("differs", "differs=' '", "'differs' is empty"),
    ] {
        let text = format!(
            "title='T'\nauthors='A'\nvenue='V'\norder=1\n[[claim]]\nid='X1'\nsays='s'\npaper_figure='p'\n\
             criterion='c'\nkind='measured'\nfixed='before data'\ndiffers='d'\n{base}test='every_at_most'\nbound=1"
        );
        let line = text.lines().find(|l| l.starts_with(&format!("{key}="))).unwrap().to_string();
        let e = format!("{:#}", parse("t", &text.replace(&line, bad), Path::new("t.toml")).unwrap_err());
        assert!(e.contains(says), "{e}");
    }
    assert!(err(&format!("{base}baseline='b'\ntest='ratio_every'\nbogus=1")).contains("bogus"));
    assert!(err(&format!("{base}baseline='b'\ntest='ratio_every'\nfloor=-1")).contains("'floor' must be ≥ 0"));
    assert!(paper(&format!("says2='x'\n{base}")).is_err());
    let long = "x".repeat(SAYS_MAX + 1);
    let text = format!(
        "title='T'\nauthors='A'\nvenue='V'\norder=1\n[[claim]]\nid='X1'\nsays='{long}'\npaper_figure='p'\n\
         criterion='c'\nkind='measured'\nfixed='before data'\ndiffers='d'\n{base}test='every_at_most'\nbound=1"
    );
    assert!(format!("{:#}", parse("t", &text, Path::new("t.toml")).unwrap_err()).contains("'says' has"));
}

#[test]
fn measurement_maps_keep_their_order_and_are_checked() {
    let with = |maps: &str| {
        let text = format!(
            "title='T'\nauthors='A'\nvenue='V'\norder=1\n[measurements]\n{maps}\n[[claim]]\nid='X1'\nsays='s'\n\
             paper_figure='p'\ncriterion='c'\nkind='measured'\nfixed='before data'\ndiffers='d'\n\
             [[claim.check]]\nname='n'\ntable='e'\nencoder='a'\ntest='every_at_most'\nbound=1\nrole='primary'"
        );
        parse("t", &text, Path::new("t.toml"))
    };
    assert_eq!(with("maps = ['m2', 'm1', 'm3']").unwrap().measurement_maps, ["m2", "m1", "m3"]);
    assert!(paper("[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\ntest='every_at_most'\nbound=1\nrole='primary'")
        .unwrap()
        .measurement_maps
        .is_empty());
    assert!(format!("{:#}", with("maps = []").unwrap_err()).contains("names no map"));
    assert!(format!("{:#}", with("maps = ['m1', 'm2', 'm1']").unwrap_err()).contains("'m1' appears twice"));
    assert!(with("maps = ['m1']\nsets = 2").is_err());
}

/// A check's name is written whole into the verdicts, so it is bounded like `says`: at most
/// [`SAYS_MAX`] characters, else refused with the name cut.
#[test]
fn check_names_are_bounded() {
    let check = |name: &str| {
        format!(
            "[[claim.check]]\nname='{name}'\ntable='exp'\nencoder='a'\ntest='every_at_most'\nbound=1\nrole='primary'"
        )
    };
    assert!(paper(&check(&"n".repeat(SAYS_MAX))).is_ok());
    let e = err(&check(&"n".repeat(SAYS_MAX + 1)));
    assert!(e.contains(&format!("'name' has {} characters (at most {SAYS_MAX})", SAYS_MAX + 1)), "{e}");
    assert!(!e.contains(&"n".repeat(41)), "the name is echoed cut: {e}");
}
