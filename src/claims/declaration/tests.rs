//! The declarations' parser and loader: what each key accepts and refuses.

use super::paper::SAYS_MAX;
use super::parse::parse;
use super::*;
use anyhow::Result;
use std::path::Path;

fn paper(claim: &str) -> Result<Paper> {
    let text = format!(
        "title='T'\nauthors='A'\nvenue='V'\norder=1\n[map_sets]\npaper=['m1']\n[[claim]]\nid='X1'\nsays='s'\n\
         paper_figure='p'\ncriterion='c'\nkind='measured'\nfixed='before data'\ndiffers='d'\nquote='the paper states 0.5'\nthreshold_from='paper: 0.5'\n{claim}"
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
        assert!(e.starts_with("t.toml:19: key 'table':") && e.contains("not a plain name"), "{table}: {e}");
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
             criterion='c'\nkind='anchor'\nfixed='after data: the band was set on our maps'\ndiffers='d'\nquote='q'\nthreshold_from='none'\n{check}"
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
             criterion='c'\nkind='measured'\nfixed='before data'\ndiffers='d'\nquote='the paper states 0.5'\nthreshold_from='paper: 0.5'\n{base}test='every_at_most'\nbound=1"
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
         criterion='c'\nkind='measured'\nfixed='before data'\ndiffers='d'\nquote='the paper states 0.5'\nthreshold_from='paper: 0.5'\n{base}test='every_at_most'\nbound=1"
    );
    assert!(format!("{:#}", parse("t", &text, Path::new("t.toml")).unwrap_err()).contains("'says' has"));
}

#[test]
fn measurement_maps_keep_their_order_and_are_checked() {
    let with = |maps: &str| {
        let text = format!(
            "title='T'\nauthors='A'\nvenue='V'\norder=1\n[measurements]\n{maps}\n[[claim]]\nid='X1'\nsays='s'\n\
             paper_figure='p'\ncriterion='c'\nkind='measured'\nfixed='before data'\ndiffers='d'\nquote='the paper states 0.5'\nthreshold_from='paper: 0.5'\n\
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

/// A claim of `kind` with the given quote, threshold_from and primary check keys.
fn quoted(kind: &str, quote: &str, from: &str, test: &str) -> Result<Paper> {
    let text = format!(
        "title='T'\nauthors='A'\nvenue='V'\norder=1\n[[claim]]\nid='X1'\nsays='s'\npaper_figure='p'\ncriterion='c'\n\
         kind='{kind}'\nfixed='before data'\ndiffers='d'\nquote='{quote}'\nthreshold_from='{from}'\n\
         [[claim.check]]\nname='n'\ntable='exp'\nencoder='a'\nbaseline='b'\n{test}\nrole='primary'\n"
    );
    parse("t", &text, Path::new("t.toml"))
}

/// The threshold rule: a number decides only when the paper states it in the quoted words; a
/// word decides only its direction (a ratio against 1); rounding is for identities, none for
/// anchors.
#[test]
fn a_threshold_comes_from_the_paper_or_is_a_direction() {
    let q = "ZH3 is a clear improvement in every case; it more than halves the error";
    // "clear" is a word: ratio < 1 is its direction; 0.9 is a threshold the paper never states.
    assert!(quoted("measured", q, "direction", "test='ratio_every'").is_ok());
    let e = format!("{:#}", quoted("measured", q, "direction", "test='ratio_every'\nbelow=0.9").unwrap_err());
    assert!(e.contains("not a direction"), "{e}");
    // A quoted word without a number cannot carry a threshold.
    let e = format!(
        "{:#}",
        quoted("measured", q, "paper: clear improvement", "test='ratio_every'\nbelow=0.9").unwrap_err()
    );
    assert!(e.contains("states no number"), "{e}");
    // "more than halves" states 0.5, in the quote's own words.
    assert!(quoted("measured", q, "paper: more than halves", "test='ratio_every'\nbelow=0.5").is_ok());
    let e = format!("{:#}", quoted("measured", q, "paper: at most half", "test='ratio_every'\nbelow=0.5").unwrap_err());
    assert!(e.contains("does not contain"), "{e}");
    // A direction of a median is a band with one end at 1; a sign allows a rounding floor.
    let hedge = "it usually helps";
    assert!(quoted("measured", hedge, "direction", "test='ratio_stat'\nstatistic='median'\nmax=1").is_ok());
    assert!(quoted("measured", hedge, "direction", "test='ratio_stat'\nstatistic='median'\nmax=0.8").is_err());
    // Rounding is an identity's; an anchor has none, and only an anchor.
    assert!(quoted("measured", "q", "rounding", "test='ratio_every'").is_err());
    assert!(quoted("identity", "q", "rounding", "test='equal'").is_ok());
    assert!(quoted("anchor", "q", "none", "test='ratio_summary'").is_ok());
    assert!(quoted("anchor", "q", "direction", "test='ratio_summary'").is_err());
    assert!(quoted("measured", "q", "none", "test='ratio_every'").is_err());
    assert!(quoted("measured", "q", "from our data", "test='ratio_every'").is_err());
}

/// The quantifier rule: "For example" makes an example; "in every case" needs every case; a
/// hedge is decided by the per-map median. Identities are exempt.
#[test]
fn the_sentences_quantifier_sets_the_population_rule() {
    let every = "test='ratio_every'";
    let median = "test='ratio_stat'\nstatistic='median'\nmax=1";
    let example = "For example, if blue has a high weight, this is very obvious visually";
    let e = format!("{:#}", quoted("measured", example, "direction", every).unwrap_err());
    assert!(e.contains("is an example"), "{e}");
    assert!(quoted("example", example, "direction", median).is_ok());
    let all = "a clear improvement over linear SH in every case";
    assert!(quoted("measured", all, "direction", every).is_ok());
    let e = format!("{:#}", quoted("measured", all, "direction", median).unwrap_err());
    assert!(e.contains("every case"), "{e}");
    for hedge in ["a shared axis usually produces better results", "Tends to over-brighten", "most of the leak is gone"]
    {
        let e = format!("{:#}", quoted("measured", hedge, "direction", every).unwrap_err());
        assert!(e.contains("hedges"), "{hedge}: {e}");
        assert!(quoted("measured", hedge, "direction", median).is_ok(), "{hedge}");
    }
    // A derivation holds in every case, whatever the sentence's wording.
    assert!(quoted("identity", "to give an example, it should be scaled by ¼", "rounding", "test='equal'").is_ok());
}

/// A declared map set may not name a constructed scene: scenes are judged apart.
#[test]
fn a_map_set_never_names_a_constructed_scene() {
    let text = "title='T'\nauthors='A'\nvenue='V'\norder=1\n[map_sets]\npaper=['m1','gen_tilted_light']\n";
    let e = format!("{:#}", parse("t", text, Path::new("t.toml")).unwrap_err());
    assert!(e.contains("constructed scene"), "{e}");
}
